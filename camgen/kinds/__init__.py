"""The cam-kind registry: one module per kind, one line here.

Adding a kind: write ``camgen/kinds/<kind>.py`` exposing ``KIND`` (a
:class:`~camgen.kinds.base.CamKind`) and add its module to :data:`KIND_MODULES`.  Kinds are
imported when a scene names them (or when the key reference lists them all).
"""
from __future__ import annotations

import importlib

from camgen.kinds.base import CamKind

#: kind name -> module defining ``KIND``
KIND_MODULES: dict[str, str] = {
    "three_arc": "camgen.kinds.three_arc",
    "trajectory": "camgen.kinds.trajectory",
    "motion_law": "camgen.kinds.motion_law",
    "lift_table": "camgen.kinds.lift_table",
}

_EXTRA: dict[str, CamKind] = {}


def register(kind: CamKind) -> None:
    """Register a kind defined outside this package (plug-ins, tests)."""
    _EXTRA[kind.name] = kind


def unregister(name: str) -> None:
    _EXTRA.pop(name, None)


def kind_names() -> list[str]:
    return sorted(set(KIND_MODULES) | set(_EXTRA))


def get_kind(name: str) -> CamKind:
    """The registered kind ``name`` (KeyError if none)."""
    if name in _EXTRA:
        return _EXTRA[name]
    return importlib.import_module(KIND_MODULES[name]).KIND
