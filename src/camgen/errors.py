"""Errors camgen raises for user mistakes.

Every user-facing failure is a :class:`CamgenError` subclass whose message names the
parameter (or segment, or file), the offending value and what would be valid.  The CLI
prints the message on one line and exits with status 2.
"""
from __future__ import annotations

import math


class CamgenError(Exception):
    """Base class of every error camgen raises on purpose."""


class ParameterError(CamgenError, ValueError):
    """A parameter is missing, of the wrong type, not finite, or outside its valid range."""

    def __init__(self, name: str, value: object, valid: str, why: str = "") -> None:
        self.name = name
        self.value = value
        self.valid = valid
        self.why = why
        text = f"parameter '{name}' = {value!r} is invalid: valid range is {valid}"
        if why:
            text += f" ({why})"
        super().__init__(text)


class GeometryError(CamgenError, ValueError):
    """The parameters are individually valid but the geometry cannot be built or used."""


class FitToleranceError(GeometryError):
    """A spline representation that cannot reach its tolerance with the most pieces allowed.

    Attributes
    ----------
    fit_tol : the tolerance asked for, mm.
    reached : the largest distance reached with ``pieces`` pieces, mm.
    pieces : the pieces of the last attempt.
    """

    def __init__(self, message: str, fit_tol: float = 0.0, reached: float = 0.0, pieces: int = 0) -> None:
        super().__init__(message)
        self.fit_tol, self.reached, self.pieces = fit_tol, reached, pieces


class UndercutError(GeometryError):
    """The follower cannot ride the cam as designed: the profile reverses (roller: the pitch
    curve's radius of curvature is not larger than the roller; flat face: the envelope's radius
    of curvature is not positive).  Carries what the report draws to show where and why.

    Attributes
    ----------
    pitch : the follower-centre path (roller followers), or None.
    curve : (cam angle rad, radius of curvature mm) of the curve whose radius must stay above
        ``limit``, or None.
    limit : that radius' limit, mm (the roller radius, or 0 for a flat face).
    where_deg : cam angles (deg) bounding the undercut regions.
    """

    def __init__(self, message: str, pitch: object = None, curve: object = None, limit: float = 0.0,
                 where_deg: list[float] | None = None) -> None:
        super().__init__(message)
        self.pitch = pitch
        self.curve = curve
        self.limit = limit
        self.where_deg = list(where_deg or [])


class CornerError(GeometryError):
    """An offset of a contour with a corner (a G0 joint): no single offset curve, so no round
    tool follows it exactly (a knife cam's corner where its law's velocity jumps)."""


class SceneError(CamgenError, ValueError):
    """A scene file cannot be read or does not follow the scene schema."""


class ExportError(CamgenError, OSError):
    """An output file could not be written or failed its read-back check."""


def require_finite(name: str, value: object) -> float:
    """Return ``value`` as a float, or raise :class:`ParameterError` if it is not a finite real number."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        try:
            import numpy as np

            if isinstance(value, np.generic) and np.isrealobj(value):
                value = float(value)
            else:
                raise TypeError
        except (TypeError, ImportError):
            raise ParameterError(name, value, "a finite real number") from None
    number = float(value)
    if not math.isfinite(number):
        raise ParameterError(name, value, "a finite real number")
    return number


def require_positive(name: str, value: object, unit: str = "mm") -> float:
    """Return ``value`` as a float if it is finite and > 0, else raise :class:`ParameterError`."""
    number = require_finite(name, value)
    if number <= 0.0:
        raise ParameterError(name, value, f"{name} > 0 {unit}".rstrip())
    return number


def ceil_significant(x: float, digits: int) -> float:
    """``x`` > 0 rounded up to ``digits`` significant digits, so that a least value quoted in an
    error message with that many digits is itself accepted (0.0102345 -> 0.0103 for 3)."""
    scale = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return float(f"{math.ceil(x / scale * (1 - 1e-12)) * scale:.{digits}g}")
