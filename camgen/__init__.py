"""camgen: cam profiles from required motion, checked and exported for machining.

The package namespace is lazy: ``import camgen`` loads nothing heavy (not even numpy);
``camgen.three_arc_cam`` and ``camgen.Contour`` import their modules on first use.
"""
from __future__ import annotations

from camgen.errors import (
    CamgenError,
    ExportError,
    GeometryError,
    ParameterError,
    SceneError,
)

__version__ = "0.1.0"

_LAZY = {
    "Contour": ("camgen.contour", "Contour"),
    "Arc": ("camgen.contour", "Arc"),
    "Spline": ("camgen.contour", "Spline"),
    "three_arc_cam": ("camgen.synthesis.three_arc", "three_arc_cam"),
    "yoke_law": ("camgen.synthesis.three_arc", "yoke_law"),
    "yoke_motion": ("camgen.synthesis.three_arc", "yoke_motion"),
}

__all__ = ["CamgenError", "ExportError", "GeometryError", "ParameterError", "SceneError", "__version__", *_LAZY]


def __getattr__(name: str) -> object:
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        value = getattr(importlib.import_module(module), attr)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'camgen' has no attribute {name!r}")
