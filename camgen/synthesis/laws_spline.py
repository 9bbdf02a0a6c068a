"""Piecewise-polynomial motion from conditions: Hermite polynomials and interpolating B-splines.

The numbers behind three laws of :mod:`camgen.synthesis.laws` (which wraps them into its pieces;
this module imports nothing of it):

* :func:`hermite_polynomial`: the polynomial of lowest degree meeting, at distinct points
  ``tau`` of ``[0, 1]``, the displacement and optionally its first derivatives
  (Hermite interpolation; Norton, Design of Machinery, ch. 8, "polynomial functions": one
  condition, one coefficient).  Solved exactly in rational arithmetic (the floats converted
  exactly), then rounded once: the confluent Vandermonde system is regular for distinct points
  whenever every point gives its derivatives 0, 1, .. without a gap.  The ``polynomial`` law
  with ``interior`` conditions and the ``velocity_blend`` law take it.
* :func:`interpolating_spline`: the B-spline of odd degree ``k`` through given points with
  ``(k - 1) / 2`` derivatives prescribed at each end (scipy's ``make_interp_spline``, knots at the
  points: C^(k-1) there), returned as its polynomial pieces (``PPoly.from_spline``): the ``bspline``
  law.  scipy is imported only when a spline is built.

Everything here is in normalised units: the abscissa ``tau in [0, 1]`` (the segment's span), the
ordinate in the follower's unit (mm or rad), a derivative ``d^n/dtau^n``.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from camgen.errors import ParameterError

__all__ = ["INTERPOLATION_TOL", "MAX_POLYNOMIAL_DEGREE", "MIN_SPACING", "SPLINE_DEGREES", "Polynomial", "SplinePieces", "hermite_polynomial",
           "interpolating_spline", "polynomial_derivative_at"]

#: Highest degree of a polynomial from conditions (16 conditions): beyond it the power-basis
#: coefficients grow so that evaluating them loses more than ~1e-9 of the lift to rounding.
MAX_POLYNOMIAL_DEGREE = 15
#: Least gap between two positions of a spline's points or a polynomial's conditions (the segment's
#: ends included), as a fraction of the span: closer ones make the system too ill-conditioned to
#: meet (refused before the work, naming the row).
MIN_SPACING = 1e-6
#: A built spline or polynomial must reproduce every prescribed displacement within this fraction of
#: the largest one (at least 1): checked after building, refused otherwise (never a silent miss).
INTERPOLATION_TOL = 1e-9
#: Degrees of the interpolating B-spline: odd, so that the end conditions split evenly
#: (``(k - 1) / 2`` derivatives at each end: v; v, a; v, a, j).
SPLINE_DEGREES = (3, 5, 7)


@dataclass(frozen=True)
class Polynomial:
    """``S(tau) = sum_i coefficients[i] tau^i`` in exact rationals (lowest power first)."""

    coefficients: tuple[Fraction, ...]

    @property
    def degree(self) -> int:
        return len(self.coefficients) - 1

    def floats(self) -> tuple[float, ...]:
        """The coefficients rounded once to floats."""
        return tuple(float(c) for c in self.coefficients)


def polynomial_derivative_at(poly: Polynomial, tau: Fraction, order: int) -> Fraction:
    """``d^order S / dtau^order`` at ``tau``, exactly."""
    return sum((c * math.perm(i, order) * tau ** (i - order) for i, c in enumerate(poly.coefficients) if i >= order),
               Fraction(0))


def hermite_polynomial(conditions: Sequence[tuple[float, Sequence[float]]], name: str = "conditions") -> Polynomial:
    """The polynomial of lowest degree with ``d^k S/dtau^k (tau_j) = values_j[k]``.

    Parameters
    ----------
    conditions : sequence of (tau, values)
        A point ``tau`` and the displacement there followed by as many derivatives as wanted
        (``values[k]`` is the k-th derivative); the points are distinct.
    name : str
        How a refusal names the conditions.

    Returns
    -------
    Polynomial
        Degree ``(number of values) - 1``, exact.

    Raises
    ------
    ParameterError
        Two conditions at one point, a non-finite value, or more than
        ``MAX_POLYNOMIAL_DEGREE + 1`` values.
    """
    rows: list[list[Fraction]] = []
    taus = [float(t) for t, _ in conditions]
    if len(set(taus)) != len(taus):
        raise ParameterError(name, sorted(taus), "conditions at distinct points", "two conditions fall on one point and conflict")
    count = sum(len(v) for _, v in conditions)
    if count > MAX_POLYNOMIAL_DEGREE + 1:
        raise ParameterError(name, f"{count} conditions", f"at most {MAX_POLYNOMIAL_DEGREE + 1} (degree {MAX_POLYNOMIAL_DEGREE})",
                             "a higher-degree power series loses the lift to rounding; split the segment")
    for tau, values in conditions:
        t = Fraction(tau)
        for k, value in enumerate(values):
            if not math.isfinite(value):
                raise ParameterError(name, value, "finite numbers")
            # row of d^k/dtau^k tau^i at t: i!/(i-k)! t^(i-k)
            rows.append([Fraction(math.perm(i, k)) * t ** (i - k) if i >= k else Fraction(0) for i in range(count)]
                        + [Fraction(value)])
    # Gaussian elimination, exact (the confluent Vandermonde matrix is regular for distinct points)
    for col in range(count):
        piv = next((r for r in range(col, count) if rows[r][col] != 0), None)
        if piv is None:  # pragma: no cover - a gapless Hermite system is regular
            raise ParameterError(name, "a singular system", "conditions that fix one polynomial")
        rows[col], rows[piv] = rows[piv], rows[col]
        pivot = rows[col]
        for r in range(count):
            if r != col and rows[r][col] != 0:
                f = rows[r][col] / pivot[col]
                rows[r] = [x - f * y for x, y in zip(rows[r], pivot)]
    poly = Polynomial(tuple(rows[j][count] / rows[j][j] for j in range(count)))
    # the float coefficients must meet the displacements (a near-confluent system blows them up)
    coeffs = [float(c) if abs(c) < 1e300 else math.inf for c in poly.coefficients]
    targets = [(t, values[0]) for t, values in conditions]
    scale = max([1.0] + [abs(v) for _, v in targets])
    if not all(math.isfinite(c) for c in coeffs) or any(
            abs(float(np.polynomial.polynomial.polyval(t, coeffs)) - v) > INTERPOLATION_TOL * scale for t, v in targets):
        raise ParameterError(name, f"{count} conditions", f"conditions a polynomial meets to {INTERPOLATION_TOL:g} of the lift in floating point",
                             "the conditions are too close together for their values: spread them or use fewer")
    return poly


@dataclass(frozen=True)
class SplinePieces:
    """A piecewise polynomial on ``[0, 1]``: piece ``i`` covers ``[edges[i], edges[i + 1]]`` and is
    ``sum_p coefficients[i][p] (tau - edges[i])^p`` (lowest power first).  ``knots``: the interior
    edges, where the ``degree``-th derivative may jump (every lower one is continuous)."""

    edges: tuple[float, ...]
    coefficients: tuple[tuple[float, ...], ...]
    degree: int

    @property
    def knots(self) -> tuple[float, ...]:
        return self.edges[1:-1]


def interpolating_spline(points: Sequence[tuple[float, float]], degree: int, start: Sequence[float], end: Sequence[float]) -> SplinePieces:
    """The B-spline of odd ``degree`` through ``(0, start[0])``, the ``points`` and ``(1, end[0])``
    whose derivatives 1 .. (degree - 1)/2 at the ends are ``start[1:]`` and ``end[1:]``.

    Parameters
    ----------
    points : sequence of (tau, S)
        Interior points, ``0 < tau < 1``, increasing (the caller checks and names them).
    degree : int
        3, 5 or 7 (:data:`SPLINE_DEGREES`).
    start, end : sequence of float
        ``(S, S', ..)`` at ``tau = 0`` and ``tau = 1``: ``1 + (degree - 1)/2`` values each.

    Returns
    -------
    SplinePieces
        One polynomial per knot interval (knots at the points: scipy's ``make_interp_spline`` with
        the derivatives as ``bc_type``; the pieces from ``PPoly.from_spline``).
    """
    if degree not in SPLINE_DEGREES:
        raise ParameterError("degree", degree, "3, 5 or 7 (odd: the end conditions split evenly)")
    m = (degree - 1) // 2
    if len(start) != m + 1 or len(end) != m + 1:
        raise ParameterError("start" if len(start) != m + 1 else "end", list(start if len(start) != m + 1 else end),
                             f"{m + 1} values (s and {m} derivative{'s' if m > 1 else ''}) for degree {degree}")
    if not points:  # no interior point: the one polynomial of that degree meeting both ends (exact; scipy not imported)
        poly = hermite_polynomial([(0.0, tuple(start)), (1.0, tuple(end))], "ends")
        return SplinePieces((0.0, 1.0), (poly.floats(),), degree)
    from scipy.interpolate import PPoly, make_interp_spline

    x = np.array([0.0] + [float(t) for t, _ in points] + [1.0])
    y = np.array([float(start[0])] + [float(s) for _, s in points] + [float(end[0])])
    bc = ([(k + 1, float(start[k + 1])) for k in range(m)], [(k + 1, float(end[k + 1])) for k in range(m)])
    spline = make_interp_spline(x, y, k=degree, bc_type=bc)
    pp = PPoly.from_spline(spline)
    edges, coefficients = [], []
    for i in range(len(pp.x) - 1):
        lo, hi = float(pp.x[i]), float(pp.x[i + 1])
        if hi > lo:  # the repeated end knots give empty intervals
            edges.append(lo)
            coefficients.append(tuple(float(c) for c in pp.c[::-1, i]))  # scipy's highest power first
    edges.append(1.0)
    # the spline must meet its points (a near-confluent system would not, or not finitely)
    scale = max(1.0, float(np.abs(y).max()))
    if not (np.isfinite(pp.c).all() and np.abs(pp(x) - y).max() <= INTERPOLATION_TOL * scale):
        raise ParameterError("points", f"{len(points)} points", f"points the spline meets to {INTERPOLATION_TOL:g} of the lift",
                             "the points are too close together for their lifts: spread them or use fewer")
    return SplinePieces(tuple(edges), tuple(coefficients), degree)
