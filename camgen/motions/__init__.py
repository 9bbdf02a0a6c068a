"""The motion registry: one module per motion, one line here.

Adding a motion: write ``camgen/motions/<name>.py`` exposing ``MOTION`` (a
:class:`~camgen.motions.base.Motion`) and add its module to :data:`MOTION_MODULES`.  A
displacement law needs nothing else: every cam form and follower take it.  Motions are imported
when a scene names them (or when the key reference lists them all).
"""
from __future__ import annotations

import importlib

from camgen.motions.base import LawReading, Motion

__all__ = ["MOTION_MODULES", "LawReading", "Motion", "get_motion", "motion_names", "register", "unregister"]

#: motion name (the ``kind`` value in scene files) -> module defining ``MOTION``
MOTION_MODULES: dict[str, str] = {
    "three_arc": "camgen.motions.three_arc",
    "trajectory": "camgen.motions.trajectory",
    "motion_law": "camgen.motions.motion_law",
    "lift_table": "camgen.motions.lift_table",
}

_EXTRA: dict[str, Motion] = {}


def register(motion: Motion) -> None:
    """Register a motion defined outside this package (plug-ins, tests)."""
    _EXTRA[motion.name] = motion


def unregister(name: str) -> None:
    _EXTRA.pop(name, None)


def motion_names() -> list[str]:
    return sorted(set(MOTION_MODULES) | set(_EXTRA))


def get_motion(name: str) -> Motion:
    """The registered motion ``name`` (KeyError if none)."""
    if name in _EXTRA:
        return _EXTRA[name]
    motion: Motion = importlib.import_module(MOTION_MODULES[name]).MOTION
    return motion
