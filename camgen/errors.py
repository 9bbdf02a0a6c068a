"""Errors camgen raises for user mistakes.

Every user-facing failure is a :class:`CamgenError` subclass whose message names the
parameter (or segment, or file), the offending value and what would be valid.  The CLI
prints the message on one line and exits with status 2.
"""
from __future__ import annotations

import math

__all__ = [
    "CamgenError", "CornerError", "ExportError", "FitToleranceError", "GeometryError", "MAX_QUOTED", "ParameterError",
    "SceneError", "UndercutError", "ceil_significant", "floor_significant", "quoted", "require_finite",
    "require_positive", "shortened",
]

#: Longest text a message quotes from a value or a name given by the user, characters (a
#: longer one keeps its first and last characters and says its full length), so every error
#: line stays short; long enough for a file path followed by ", line 12".
MAX_QUOTED = 120
#: Characters kept from the end of a shortened text (a path's file name, a row's line number).
_TAIL = 36
#: Integers of more bits than this are quoted by their number of digits (about 60 digits).
_MAX_INT_BITS = 200
#: Items of a list or table quoted before "... (N items)".
_MAX_ITEMS = 8


def _digits(number: int) -> int:
    """Decimal digits of ``|number|`` without converting it to text (``str`` refuses integers of
    more than 4300 digits, and is quadratic before that)."""
    n = abs(number)
    if n == 0:
        return 1
    digits = math.floor((n.bit_length() - 1) * math.log10(2.0)) + 1  # a lower bound: 2**(b-1) <= n
    while n >= 10**digits:
        digits += 1
    return digits


def _cut(text: str, length: int, limit: int) -> str:
    """``text`` (a repr) cut to about ``limit`` characters, its head and tail kept, with the
    quoted value's full ``length``."""
    if len(text) <= limit:
        return text
    tail = min(_TAIL, limit // 3)
    return f"{text[: limit - tail - 3]}...{text[len(text) - tail:]} ({length} characters)"


def quoted(value: object, limit: int = MAX_QUOTED) -> str:
    """``repr(value)`` of at most about ``limit`` characters, for error messages.

    A longer string keeps its first and last characters and says its length (``'xxx...xxx'
    (1000000 characters)``); an integer of more than about 60 digits is ``<4817-digit integer>``; a list
    or table shows its first items and its length (``[1.0, 1.0, ... (100001 items)]``).  Whatever
    the value, the text is at most ``limit`` + 40 characters.
    """
    if isinstance(value, bool) or value is None or isinstance(value, float):
        return repr(value)
    if isinstance(value, int):
        if value.bit_length() > _MAX_INT_BITS:
            return f"<{_digits(value)}-digit {'negative ' if value < 0 else ''}integer>"
        return repr(value)
    if isinstance(value, str):
        from camgen.textfile import display_path

        value = display_path(value)  # a file name an ASCII locale decoded to surrogates: as the user typed it
        if len(value) <= limit:
            return repr(value)
        tail = min(_TAIL, limit // 3)
        return _cut(repr(value[:limit] + value[-tail:]), len(value), limit)
    if isinstance(value, (list, tuple, dict)):
        items = list(value.items()) if isinstance(value, dict) else list(value[: _MAX_ITEMS + 1])
        open_, close = ("{", "}") if isinstance(value, dict) else ("(", ")") if isinstance(value, tuple) else ("[", "]")
        if limit < 12 and value:  # deep inside a nested value: its length only (bounded recursion)
            return f"{open_}...{close} ({len(value)} items)"
        parts: list[str] = []
        used = 0
        for item in items[:_MAX_ITEMS]:
            part = (f"{quoted(item[0], limit // 4)}: {quoted(item[1], limit // 4)}" if isinstance(value, dict)
                    else quoted(item, limit // 4))
            if used + len(part) > limit:
                break
            parts.append(part)
            used += len(part) + 2
        if len(parts) < len(value):
            return f"{open_}{', '.join(parts + ['...'])}{close} ({len(value)} items)"
        return f"{open_}{', '.join(parts)}{',' if isinstance(value, tuple) and len(value) == 1 else ''}{close}"
    try:
        text = repr(value)
    except Exception:  # a value whose repr fails is still named by its type
        return f"<{type(value).__name__}>"
    return _cut(text, len(text), limit)


def shortened(text: str, limit: int = MAX_QUOTED) -> str:
    """``text`` (a key or file name, shown as it is) cut to about ``limit`` characters, its head
    and tail kept and its length said."""
    return _cut(text, len(text), limit)


class CamgenError(Exception):
    """Base class of every error camgen raises on purpose."""


class ParameterError(CamgenError, ValueError):
    """A parameter is missing, of the wrong type, not finite, or outside its valid range.

    The message quotes the value shortened (:func:`quoted`) and the name cut (:func:`shortened`):
    ``value`` and ``name`` keep them whole."""

    def __init__(self, name: str, value: object, valid: str, why: str = "") -> None:
        self.name = name
        self.value = value
        self.valid = valid
        self.why = why
        text = f"parameter '{shortened(str(name))}' = {quoted(value)} is invalid: valid range is {valid}"
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


def floor_significant(x: float, digits: int) -> float:
    """``x`` > 0 rounded down to ``digits`` significant digits, so that a largest value quoted in
    an error message with that many digits is itself accepted (0.0102345 -> 0.0102 for 3)."""
    scale = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return float(f"{math.floor(x / scale * (1 + 1e-12)) * scale:.{digits}g}")
