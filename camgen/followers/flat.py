"""Follower ``flat``: a flat face (the profile is the envelope of the face's lines)."""
from __future__ import annotations

from camgen.followers.base import FollowerKind

__all__ = ["FOLLOWER"]

FOLLOWER = FollowerKind(name="flat", summary="a flat face", contact="face")
