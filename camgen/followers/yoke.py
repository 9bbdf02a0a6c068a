"""Follower ``yoke``: two parallel flat faces a cam of constant breadth fits between (form
closure: no spring, no jump); the constant-breadth form carries it."""
from __future__ import annotations

from camgen.followers.base import FollowerKind

__all__ = ["FOLLOWER"]

FOLLOWER = FollowerKind(name="yoke", summary="a yoke (two parallel flat faces)", contact="faces")
