"""Follower ``roller``: a roller of radius ``roller_radius_mm`` (a point contact of that radius)."""
from __future__ import annotations

from typing import Any, Mapping

from camgen.followers.base import FollowerKind
from camgen.schema import Key, Length

__all__ = ["FOLLOWER"]


def _radius(parsed: Mapping[str, Any]) -> float:
    radius: float = parsed["roller_radius"]
    return radius


FOLLOWER = FollowerKind(
    name="roller",
    summary="a roller",
    contact="point",
    keys=(Key("roller_radius_mm", Length(), "Roller radius.", ("profile", "pitch"), default=10.0),),
    radius=_radius,
    has_radius=True,
)
