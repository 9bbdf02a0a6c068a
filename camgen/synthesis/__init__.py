"""Cam synthesis: motion laws, follower kinematics and the exact profiles they give, sizing, the
three-arc and trajectory cams, one module each.  The package namespace imports none of them:
import the module you need."""
from __future__ import annotations

__all__: list[str] = []
