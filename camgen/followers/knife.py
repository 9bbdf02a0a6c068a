"""Follower ``knife``: a knife edge (a point contact of radius 0: the profile is its pitch curve)."""
from __future__ import annotations

from camgen.followers.base import FollowerKind

__all__ = ["FOLLOWER"]

FOLLOWER = FollowerKind(name="knife", summary="a knife edge", contact="point")
