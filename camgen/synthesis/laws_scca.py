"""Piecewise accelerations of the trapezoidal law, the SCCA family and the skewed (asymmetric)
modified sine and modified trapezoid, before they are integrated into laws.

Each function here returns an :class:`AccelerationPlan`: the edges of the law's pieces on the
normalised segment ``tau in [0, 1]``, the acceleration on each piece as a polynomial plus sines in
the piece's own variable ``u = tau - lo`` (any amplitude: :mod:`camgen.synthesis.laws` integrates
it in closed form from rest and scales it to ``S(1) = 1``), and which derivative jumps at each
inner edge.  The plans hold only the shapes; :mod:`camgen.synthesis.laws` builds the laws (this
module imports nothing of it, so the law catalogue can take it without an import cycle).

=============================  =============================================================  ==========================
law                            acceleration (rise; each shape scaled to S(1) = 1)              source
=============================  =============================================================  ==========================
trapezoidal                    linear ramps 0 -> +A over [0, r], +A -> -A over                 Norton, Design of
                               [1/2 - r, 1/2 + r], -A -> 0 over [1 - r, 1] (r = 1/8:            Machinery, ch. 8
                               :data:`TRAPEZOID_RAMP`), constant +A / -A between                (trapezoidal accel.)
scca  (b, c, d; b + c + d = 1) sine ramp ``sin(pi u / b)`` over [0, b/2], constant over         Norton, Design of
                               c/2, cosine ``cos(pi u / d)`` over d through the middle,         Machinery, 2nd ed.,
                               constant over c/2, ``-cos(pi u / b)`` over the last b/2          sec. 8.3, eqs. 8.21-8.24
asymmetric_modified_sine,      the symmetric law's positive half stretched over               Rothbart, Cam Design
asymmetric_modified_trapezoid  [0, f] and its negative half over [f, 1] (``f``:                Handbook (2004), sec. 3,
                               ``accel_fraction``), the negative pulse scaled by               "skewed modified
                               ``f / (1 - f)`` so the rise ends at rest                       trapezoidal curve",
                                                                                              Fig. 3.7, eqs. 3.10-3.13
=============================  =============================================================  ==========================

Notes:

* **SCCA** (sine-constant-cosine acceleration; Norton sec. 8.3): its members include constant
  acceleration (b = 0, c = 1, d = 0), the modified trapezoid (1/4, 1/2, 1/4), simple harmonic
  (0, 0, 1), the modified sine (1/4, 0, 3/4) and the cycloid (1/2, 0, 1/2).  Zones of zero width are
  left out.  Every zone ends with zero jerk, so at an inner edge the acceleration and the jerk are
  continuous and only the 4th derivative steps; except where the constant +A meets the constant
  -A (d = 0) or the two sine ramps meet (b = 1): the acceleration jumps there.  Where the first
  ramp meets the middle cosine directly (c = 0) with b = d the two are the same sine (no break).
* **Skewed laws** (Rothbart, eqs. 3.10-3.13): the peak velocity is the symmetric law's, the
  positive peak acceleration the symmetric one's times ``1 / (2 f)``, the negative one's times
  ``1 / (2 (1 - f))``, and the follower is at ``f`` of the lift at the transition ``tau = f``.
  Stretching the halves differently makes the jerk step at the transition (``f != 1/2``): the
  jerk there is ``-2 pi A+ / f`` on the left and ``-2 pi A- / (1 - f)`` on the right (modified
  trapezoid; the modified sine's likewise with its own end ramps).  ``f = 1/2`` is the symmetric law.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from camgen.errors import ParameterError, require_finite

__all__ = [
    "ACCEL_FRACTION_RANGE", "AccelerationPlan", "PieceAcceleration", "SCCA_SUM_TOL", "TRAPEZOID_RAMP", "asymmetric_modified_sine_plan",
    "accel_fraction_value", "asymmetric_modified_trapezoid_plan", "scca_parameters", "scca_plan", "trapezoidal_plan",
]

#: Fraction of the span over which the trapezoidal law's acceleration ramps linearly (each of the
#: two end ramps; the middle ramp from +A to -A takes twice it).
TRAPEZOID_RAMP = 1.0 / 8.0
#: How far b + c + d of an SCCA law may be from 1 (absolute; the law uses c = 1 - b - d).
SCCA_SUM_TOL = 1e-9
#: The range of ``accel_fraction`` (fraction of the span in the positive acceleration pulse) of the
#: skewed laws: beyond it one pulse's peak acceleration exceeds 10 times the symmetric law's.
ACCEL_FRACTION_RANGE = (0.05, 0.95)

#: One piece's acceleration: polynomial coefficients in u (lowest power first) and sine terms
#: (omega, a, b) meaning ``a sin(omega u) + b cos(omega u)``.
PieceAcceleration = tuple[tuple[float, ...], tuple[tuple[float, float, float], ...]]


@dataclass(frozen=True)
class AccelerationPlan:
    """A law's acceleration piece by piece (any amplitude).

    Attributes
    ----------
    edges : tuple of float
        The pieces' ends in tau, ``0 = edges[0] < .. < edges[-1] = 1``.
    accel : tuple
        Per piece ``(poly, trig)`` in the piece's variable ``u = tau - edges[k]`` (:data:`PieceAcceleration`).
    breaks : tuple of (tau, order)
        The inner edges where some derivative jumps and the lowest order that does (2: acceleration,
        3: jerk, 4: only beyond the jerk); an inner edge not listed is analytic.
    """

    edges: tuple[float, ...]
    accel: tuple[PieceAcceleration, ...]
    breaks: tuple[tuple[float, int], ...]


def trapezoidal_plan(ramp: float = TRAPEZOID_RAMP) -> AccelerationPlan:
    """Trapezoidal acceleration (Norton, Design of Machinery, ch. 8): linear ramps of acceleration
    over ``ramp`` at each end and ``2 ramp`` through the middle, constant between.  The jerk is a
    square wave: it steps at every edge."""
    r = ramp
    edges = (0.0, r, 0.5 - r, 0.5 + r, 1.0 - r, 1.0)
    slope = 1.0 / r
    accel: tuple[PieceAcceleration, ...] = (((0.0, slope), ()), ((1.0,), ()), ((1.0, -slope), ()), ((-1.0,), ()),
                                            ((-1.0, slope), ()))
    return AccelerationPlan(edges, accel, tuple((t, 3) for t in edges[1:-1]))


def scca_parameters(value: object) -> tuple[float, float, float]:
    """(b, c, d) of an SCCA law from ``value``: three numbers in [0, 1] adding up to 1 within
    :data:`SCCA_SUM_TOL`; a fraction below :data:`SCCA_SUM_TOL` counts as 0 and ``c`` is returned
    as ``1 - b - d``.

    Raises
    ------
    ParameterError
        Naming ``scca``, if ``value`` is not three such numbers.
    """
    valid = "[b, c, d]: three fractions of the span, each 0 <= x <= 1, b + c + d = 1"
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or len(value) != 3:
        raise ParameterError("scca", value, valid)
    b, c, d = (require_finite("scca", x) for x in value)
    if min(b, c, d) < 0.0 or max(b, c, d) > 1.0:
        raise ParameterError("scca", value, valid)
    if abs(b + c + d - 1.0) > SCCA_SUM_TOL:
        raise ParameterError("scca", value, valid, f"they add up to {b + c + d:.12g} (tolerance {SCCA_SUM_TOL:g})")
    b, d = (0.0 if x < SCCA_SUM_TOL else x for x in (b, d))
    c = 1.0 - b - d
    return b, (0.0 if c < SCCA_SUM_TOL else c), d


def scca_plan(b: float, c: float, d: float) -> AccelerationPlan:
    """The SCCA family (Norton, Design of Machinery, 2nd ed., sec. 8.3, eqs. 8.21-8.24): zones
    1..5 of widths b/2, c/2, d, c/2, b/2 (zero-width zones left out; the last edge is 1); see the
    module notes for the breaks.  Takes (b, c, d) as :func:`scca_parameters` gives them."""
    pi = math.pi
    widths = (b / 2, c / 2, d, c / 2, b / 2)
    shapes: tuple[PieceAcceleration, ...] = (
        ((0.0,), ((pi / b, 1.0, 0.0),)) if b > 0 else ((0.0,), ()),
        ((1.0,), ()),
        ((0.0,), ((pi / d, 0.0, 1.0),)) if d > 0 else ((0.0,), ()),
        ((-1.0,), ()),
        ((0.0,), ((pi / b, 0.0, -1.0),)) if b > 0 else ((0.0,), ()),
    )
    zones = [k for k in range(5) if widths[k] > 0.0]
    edges = [0.0]
    for k in zones:
        edges.append(edges[-1] + widths[k])
    edges[-1] = 1.0
    breaks = []
    for i, (left, right) in enumerate(zip(zones[:-1], zones[1:])):
        at = edges[i + 1]
        if (left, right) in ((1, 3), (0, 4)):  # +A meets -A: the acceleration jumps
            breaks.append((at, 2))
        elif (left, right) in ((0, 2), (2, 4)) and b == d:  # the same sine on both sides
            continue
        else:  # every zone ends with the jerk 0: only the 4th derivative steps
            breaks.append((at, 4))
    return AccelerationPlan(tuple(edges), tuple(shapes[k] for k in zones), tuple(breaks))


def accel_fraction_value(value: object) -> float:
    """``value`` as the skewed laws' ``accel_fraction``, in :data:`ACCEL_FRACTION_RANGE`.

    Raises
    ------
    ParameterError
        Naming ``accel_fraction``, if ``value`` is not a number in the range.
    """
    f = require_finite("accel_fraction", value)
    lo, hi = ACCEL_FRACTION_RANGE
    if not lo <= f <= hi:
        raise ParameterError("accel_fraction", value, f"{lo:g} <= accel_fraction <= {hi:g} (fraction of the span in the "
                             "positive acceleration pulse; 0.5: the symmetric law)")
    return f


def _skewed(f: float, positive: Sequence[tuple[float, PieceAcceleration]], negative: Sequence[tuple[float, PieceAcceleration]],
            inner: Sequence[int]) -> AccelerationPlan:
    """The plan of a symmetric law's halves stretched over [0, f] and [f, 1] (Rothbart, Fig. 3.7).

    ``positive`` / ``negative``: each half's pieces as (width as a fraction of the half, acceleration
    of the unit-width half in u / half-width); ``inner``: the break order at the half's inner edges.
    """
    g = 1.0 - f
    k = f / g  # the negative pulse's amplitude: equal areas, so the rise ends at rest
    edges = [0.0]
    accel: list[PieceAcceleration] = []
    breaks: list[tuple[float, int]] = []
    for half, (width, amp, pieces) in enumerate(((f, 1.0, positive), (g, k, negative))):
        start = edges[-1]
        at = start
        for i, (frac, (poly, trig)) in enumerate(pieces):
            # u / width is the half's own variable: a coefficient of (u/width)^j scales by width^-j
            accel.append((tuple(amp * c / width**j for j, c in enumerate(poly)),
                          tuple((om / width, amp * a, amp * bb) for om, a, bb in trig)))
            at = start + sum(p for p, _ in pieces[: i + 1]) * width
            edges.append(at)
            if i < len(pieces) - 1:
                breaks.append((at, inner[i]))
        if half == 0 and f != 0.5:  # the transition: the jerk steps unless the halves are equal
            breaks.append((at, 3))
    edges[-1] = 1.0
    return AccelerationPlan(tuple(edges), tuple(accel), tuple(breaks))


def asymmetric_modified_trapezoid_plan(accel_fraction: object) -> AccelerationPlan:
    """The skewed modified trapezoid (Rothbart, Cam Design Handbook, sec. 3, Fig. 3.7): the modified
    trapezoid's positive pulse (quarter sine over 1/4 of it, constant over 1/2, quarter sine down)
    over the fraction ``accel_fraction`` of the span, its negative pulse over the rest."""
    f = accel_fraction_value(accel_fraction)
    w = 2.0 * math.pi  # a quarter sine over a quarter of a unit-width half
    positive = ((0.25, ((0.0,), ((w, 1.0, 0.0),))), (0.5, ((1.0,), ())), (0.25, ((0.0,), ((w, 0.0, 1.0),))))
    negative = ((0.25, ((0.0,), ((w, -1.0, 0.0),))), (0.5, ((-1.0,), ())), (0.25, ((0.0,), ((w, 0.0, -1.0),))))
    return _skewed(f, positive, negative, (4, 4))


def asymmetric_modified_sine_plan(accel_fraction: object) -> AccelerationPlan:
    """The skewed modified sine (Rothbart's skewing, sec. 3, applied to the modified sine): the
    positive pulse (quarter sine of period 1 over 1/4 of it, then a quarter of the cosine of period
    3 over 3/4) over ``accel_fraction`` of the span, the mirrored negative pulse over the rest."""
    f = accel_fraction_value(accel_fraction)
    w1, w3 = 2.0 * math.pi, 2.0 * math.pi / 3.0
    positive = ((0.25, ((0.0,), ((w1, 1.0, 0.0),))), (0.75, ((0.0,), ((w3, 0.0, 1.0),))))
    negative = ((0.75, ((0.0,), ((w3, -1.0, 0.0),))), (0.25, ((0.0,), ((w1, 0.0, -1.0),))))
    return _skewed(f, positive, negative, (4,))
