"""The rib_width_mm that gives an oscillating follower's rib its least width (the rib_thickness
check's hint).

A translating rib's width along the cam axis grows one to one with ``rib_width_mm`` (both faces
move by half of it along z).  An oscillating rib's rollers ride ``rib_width / 2 + w`` along the
arm's normal (:class:`camgen.synthesis.barrel.BarrelRib`): a wider rib lengthens each roller's
effective arm (``hypot(L, o)``) and turns it (``atan2(o, L)``), so its least width along z grows
by about ``cos(psi)`` per mm and not exactly so.  The width that gives ``min_wall`` is solved here
by the secant method on the check's own grid (each step re-evaluates the whole grid), quoted
rounded up to :data:`HINT_DIGITS` significant digits and verified by evaluating the grid at the
quoted width before it is given.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

__all__ = ["HINT_DIGITS", "HINT_STEPS", "HINT_TOL", "rib_width_for", "rib_width_hint"]

#: The secant iteration stops when the least width is within this of min_wall (mm).
HINT_TOL = 1e-9
#: Secant steps before the hint gives up (each evaluates the check's whole grid).
HINT_STEPS = 12
#: Significant digits of the quoted width (rounded up, then verified).
HINT_DIGITS = 6


def _round_up(value: float, digits: int) -> float:
    """``value`` (> 0) rounded up to ``digits`` significant digits."""
    scale = 10.0 ** (digits - 1 - math.floor(math.log10(value)))
    return math.ceil(value * scale - 1e-9) / scale


def rib_width_for(rib: Any, min_wall: float, least: Callable[[Any], float]) -> float | None:
    """The ``rib_width_mm`` (mm) at which ``least(rib with that width)`` (the rib's least width
    along z on the check's grid, mm) reaches ``min_wall`` (mm), rounded up to :data:`HINT_DIGITS`
    significant digits and verified (``least`` there >= ``min_wall``); None when the secant method
    does not get there in :data:`HINT_STEPS` steps or the quoted width fails the verification."""
    width0, gap0 = float(rib.width), least(rib) - min_wall
    width1 = width0 - gap0  # the one-to-one (translating) step, the secant's second point
    if not width1 > 0.0:
        return None
    gap1 = least(replace(rib, width=width1)) - min_wall
    for _ in range(HINT_STEPS):
        if abs(gap1) <= HINT_TOL or gap1 == gap0:
            break
        width0, gap0, width1 = width1, gap1, width1 - gap1 * (width1 - width0) / (gap1 - gap0)
        if not width1 > 0.0:
            return None
        gap1 = least(replace(rib, width=width1)) - min_wall
    quoted = _round_up(width1, HINT_DIGITS)
    for _ in range(2):  # the quoted width verified; one unit in the last digit more if the rounding fell short
        if least(replace(rib, width=quoted)) >= min_wall:
            return quoted
        quoted = _round_up(quoted * (1.0 + 10.0 ** (1 - HINT_DIGITS)), HINT_DIGITS)
    return None


def rib_width_hint(rib: Any, min_wall: float, least: Callable[[Any], float]) -> str:
    """The rib_thickness check's note ending for an oscillating rib thinner than ``min_wall``
    (:func:`rib_width_for`)."""
    width = rib_width_for(rib, min_wall, least)
    if width is None:
        return "; no rib_width_mm found that gives it (a wider rib)"
    return (f"; a rib_width_mm of {width:g} mm gives {min_wall:g} mm (solved on the check's grid and verified: on an oscillating "
            "follower the width does not grow one to one with it)")
