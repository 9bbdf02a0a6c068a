"""The motion registry: one module per motion, one line here.

Adding a motion: write ``camgen/motions/<name>.py`` exposing ``MOTION`` (a
:class:`~camgen.motions.base.Motion`) and add its module to :data:`MOTION_MODULES`.  A
displacement law needs nothing else: every cam form and follower take it.  Motions are imported
when a scene names them (or when the key reference lists them all).
"""
from __future__ import annotations

from camgen.motions.base import LawReading, Motion
from camgen.registry import Registry

__all__ = ["MOTION_MODULES", "LawReading", "Motion", "get_motion", "motion_names", "register", "unregister"]

#: motion name (the ``kind`` value in scene files) -> module defining ``MOTION``
MOTION_MODULES: dict[str, str] = {
    "three_arc": "camgen.motions.three_arc",
    "trajectory": "camgen.motions.trajectory",
    "motion_law": "camgen.motions.motion_law",
    "lift_table": "camgen.motions.lift_table",
}

_REGISTRY: Registry[Motion] = Registry(MOTION_MODULES, "MOTION")

#: Register (or remove) an entry defined outside this package (plug-ins, tests).
register = _REGISTRY.register
unregister = _REGISTRY.unregister


def motion_names() -> list[str]:
    return sorted(_REGISTRY.names())


def get_motion(name: str) -> Motion:
    """The registered motion ``name`` (KeyError if none)."""
    return _REGISTRY.get(name)
