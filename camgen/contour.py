"""The one shared value of camgen: a closed counter-clockwise chain of exact segments.

A :class:`Contour` is a closed, planar, counter-clockwise curve in the cam frame (origin on
the rotation axis), in millimetres.  It is a chain of two kinds of segment:

* :class:`Arc`, an exact circular arc (centre, radius, start angle, signed sweep);
* :class:`Spline`, a parametric piecewise cubic or quintic ``x(t), y(t)`` (C2 inside the
  segment when built by interpolation or quintic Hermite fit; C1 when it is a refitted offset).

Every check and export in camgen works through the operations defined here, so they work for
every cam.  Nothing in this module imports another camgen module except :mod:`camgen.errors`.

Parameterisation: a contour with ``n`` segments has the global parameter ``t`` in ``[0, n)``;
``floor(t)`` is the segment index and ``t - floor(t)`` the local parameter ``u`` in ``[0, 1)``.

Conventions: lengths in mm, angles in rad, curvature in 1/mm, positive where the curve turns
left (convex parts of a counter-clockwise contour).  The outward normal is the unit tangent
rotated by -90 deg.
"""
from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Iterable, Union

import numpy as np

from camgen.errors import CornerError, GeometryError, ParameterError, require_positive
from camgen.geometry import (
    angle_in_sweep,
    cross,
    outward_normal,
    signed_curvature,
    unit_vectors,
    wrap_pi,
)

TWO_PI = 2.0 * math.pi

#: Default chord tolerance of :meth:`Contour.flatten`, mm.
DEFAULT_CHORD_TOL = 1e-3
#: Gap allowed between the end of one segment and the start of the next, mm.
DEFAULT_CLOSURE_TOL = 1e-7
#: Relative slack (of a piece's parameter length) within which a root of a piece's polynomial
#: just outside the piece, by rounding, still counts as on its end (knot).
ROOT_TOL = 1e-9


def _as_array(values: object) -> np.ndarray:
    return np.asarray(values, dtype=float)


_unit = unit_vectors
_wrap_pi = wrap_pi
_angle_in_sweep = angle_in_sweep


# --------------------------------------------------------------------------------------------
# Arc
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Arc:
    """An exact circular arc.

    Parameters
    ----------
    center : tuple of float
        Centre (x, y), mm.
    radius : float
        Radius, mm, > 0.
    start_angle : float
        Polar angle of the start point about the centre, rad.
    sweep : float
        Signed sweep, rad: > 0 counter-clockwise about the centre (convex on a CCW contour),
        < 0 clockwise (concave).
    """

    center: tuple[float, float]
    radius: float
    start_angle: float
    sweep: float

    kind = "arc"

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", (float(self.center[0]), float(self.center[1])))
        require_positive("radius", self.radius)
        if not math.isfinite(self.start_angle) or not math.isfinite(self.sweep) or self.sweep == 0:
            raise ParameterError("sweep", self.sweep, "a finite non-zero angle in rad")

    # -- pointwise --------------------------------------------------------------------------
    def angle(self, u: np.ndarray) -> np.ndarray:
        """Polar angle about the centre (rad) at local parameters ``u`` in [0, 1]."""
        return self.start_angle + self.sweep * _as_array(u)

    def point(self, u: np.ndarray) -> np.ndarray:
        """Points (n, 2), mm, at local parameters ``u``."""
        return np.asarray(self.center) + self.radius * _unit(self.angle(u))

    def derivative(self, u: np.ndarray) -> np.ndarray:
        """dP/du (n, 2), mm."""
        a = self.angle(u)
        return self.radius * self.sweep * np.stack([-np.sin(a), np.cos(a)], axis=-1)

    def second_derivative(self, u: np.ndarray) -> np.ndarray:
        """d2P/du2 (n, 2), mm."""
        return -(self.radius * self.sweep**2) * _unit(self.angle(u))

    def curvature(self, u: np.ndarray) -> np.ndarray:
        """Signed curvature (1/mm): +1/r on a counter-clockwise arc, -1/r on a clockwise one."""
        return np.full(np.shape(u), math.copysign(1.0 / self.radius, self.sweep))

    @property
    def start_point(self) -> np.ndarray:
        return self.point(np.array([0.0]))[0]

    @property
    def end_point(self) -> np.ndarray:
        return self.point(np.array([1.0]))[0]

    @property
    def length(self) -> float:
        """Arc length, mm (exact)."""
        return self.radius * abs(self.sweep)

    # -- whole-segment operations ----------------------------------------------------------
    def flatten_params(self, chord_tol: float) -> np.ndarray:
        """Local parameters of a chord polygon with sagitta <= ``chord_tol`` (start included, end excluded).

        The sagitta of a chord spanning the angle ``delta`` is ``r (1 - cos(delta / 2))``, so
        ``delta = 2 acos(1 - chord_tol / r)`` is the widest allowed step.
        """
        ratio = min(chord_tol / self.radius, 2.0)
        max_step = 2.0 * math.acos(1.0 - ratio)
        count = max(1, math.ceil(abs(self.sweep) / max_step - 1e-12))
        return np.arange(count) / count

    def green_area(self) -> float:
        """(1/2) integral of (x dy - y dx) along the arc, mm^2 (exact)."""
        cx, cy = self.center
        r, s = self.radius, self.start_angle
        e = s + self.sweep
        return 0.5 * (r * cx * (math.sin(e) - math.sin(s)) - r * cy * (math.cos(e) - math.cos(s)) + r * r * self.sweep)

    def extreme_points(self) -> np.ndarray:
        """End points and axis-extreme points (k, 2) of the arc: its exact bounding box."""
        axis_angles = np.arange(4) * (math.pi / 2)
        inside = axis_angles[_angle_in_sweep(axis_angles, self.start_angle, self.sweep)]
        pts = [self.start_point[None], self.end_point[None]]
        if inside.size:
            pts.append(np.asarray(self.center) + self.radius * _unit(inside))
        return np.concatenate(pts)

    def offset(self, distance: float, index: int = 0) -> "Arc":
        """The arc offset by ``distance`` along the outward normal of a CCW contour (exact)."""
        new_radius = self.radius + (distance if self.sweep > 0 else -distance)
        if new_radius <= 0.0:
            mid = self.point(np.array([0.5]))[0]
            polar = math.degrees(math.atan2(mid[1], mid[0])) % 360.0
            raise GeometryError(
                f"offset {distance:g} mm of segment {index} (arc of radius {self.radius:g} mm, "
                f"{'concave' if self.sweep < 0 else 'convex'}, around cam angle {polar:.3f} deg) "
                f"would make its radius {new_radius:g} mm <= 0 (undercut): "
                f"use |offset| < {self.radius:g} mm there"
            )
        return Arc(self.center, new_radius, self.start_angle, self.sweep)

    def support_candidates(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Interior support values (M,), contact points (M, 2) and radii of curvature (M,).

        For outward normal angles ``psi`` inside the sweep of a convex arc the contact is
        ``center + r u(psi)`` and ``h = center . u + r``; concave arcs have no interior maxima
        of ``p . u`` (value -inf).
        """
        u = _unit(psi)
        pts = np.asarray(self.center) + self.radius * u
        vals = np.einsum("ij,ij->i", pts, u)
        if self.sweep > 0:
            vals = np.where(_angle_in_sweep(psi, self.start_angle, self.sweep), vals, -np.inf)
        else:
            vals = np.full(psi.shape, -np.inf)
        return vals, pts, np.full(psi.shape, self.radius)

    def ray_hits(self, phi: np.ndarray) -> np.ndarray:
        """Distances (M, 2) along rays from the origin at polar angles ``phi`` to this arc (NaN: no hit)."""
        u = _unit(phi)
        uc = u @ np.asarray(self.center)
        disc = uc * uc - float(np.dot(self.center, self.center)) + self.radius**2
        root = np.sqrt(np.where(disc >= 0, disc, np.nan))
        dist = np.stack([uc - root, uc + root], axis=1)
        pts = dist[..., None] * u[:, None, :] - np.asarray(self.center)
        ang = np.arctan2(pts[..., 1], pts[..., 0])
        on_arc = _angle_in_sweep(ang, self.start_angle, self.sweep) & (dist > 0)
        return np.where(on_arc, dist, np.nan)


# --------------------------------------------------------------------------------------------
# Spline
# --------------------------------------------------------------------------------------------
#: Relative size below which the couplings of parallel cyclic reduction count as eliminated.
PCR_TOL = 1e-17


def solve_tridiagonal(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray, rhs: np.ndarray, cyclic: bool) -> np.ndarray:
    """Solve ``lower[i] x[i-1] + diag[i] x[i] + upper[i] x[i+1] = rhs[i]`` (rhs (n, k)) by parallel
    cyclic reduction, vectorised over the rows (Hockney 1965; each step eliminates the neighbours
    at distance s with the rows i -+ s and doubles s).  ``cyclic``: indices wrap (the periodic
    system); else ``lower[0]`` and ``upper[-1]`` must be 0.

    Needs strict diagonal dominance, ``|lower| + |upper| <= q |diag|`` with q < 1: every step
    squares that ratio (Heller 1976, SIAM J. Numer. Anal. 13, thm. 2.1: the couplings of the
    reduced rows are at most ``q^2`` of their diagonal), so after k steps the couplings are below
    ``q^(2^k)`` of the diagonal and the number of steps to reach :data:`PCR_TOL` is known in
    advance whatever ``n`` (the loop runs over those steps, never over rows; without ``cyclic`` it
    also stops once the distance reaches ``n``: every coupling then points outside the system).
    Cubic-spline moment systems have q = 1/2: 6 steps.
    """
    a, b, c = (np.asarray(v, dtype=float) for v in (lower, diag, upper))
    d = np.asarray(rhs, dtype=float)
    n = b.size
    if not cyclic:
        a, c = a.copy(), c.copy()
        a[0] = c[-1] = 0.0
    ratio = float(np.max((np.abs(a) + np.abs(c)) / np.abs(b)))
    if not ratio < 1.0:
        raise GeometryError(f"tridiagonal system not diagonally dominant (ratio {ratio:.3g}): cannot solve it by cyclic reduction")
    steps = 0 if ratio == 0.0 else max(0, math.ceil(math.log2(math.log(PCR_TOL) / math.log(ratio))))
    if not cyclic:
        return _reduce(a, b, c, d, min(steps, max(0, math.ceil(math.log2(n)))))
    a, b, c, d = a.copy(), b.copy(), c.copy(), d.copy()
    step = 1
    while np.max((np.abs(a) + np.abs(c)) / np.abs(b)) > PCR_TOL:
        below, above = (np.roll(np.arange(n), step), np.roll(np.arange(n), -step))
        alpha = -a / b[below]
        gamma = -c / b[above]
        b, d, a, c = (b + alpha * c[below] + gamma * a[above],
                      d + alpha[:, None] * d[below] + gamma[:, None] * d[above],
                      alpha * a[below], gamma * c[above])
        step *= 2
        if step > 4 * n + 64:  # cannot happen for a dominant system (the ratio squares each step)
            raise GeometryError("cyclic reduction did not converge")
    return d / b[:, None]


def _reduce(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray, steps: int) -> np.ndarray:
    """``steps`` steps of parallel cyclic reduction of the non-cyclic system (``a[0] = c[-1] = 0``),
    then ``d / b``: the rows live between ``pad`` rows of the identity on both sides (no couplings,
    no right-hand side), so the neighbours at distance s are slices, and two sets of buffers
    take turns (no allocation per step)."""
    n, k = d.shape
    pad = min(1 << max(steps - 1, 0), n)
    size = n + 2 * pad
    mid = slice(pad, pad + n)
    # negated couplings A = -a, C = -c: then alpha = A[i] / b[i-s], a'[i] = -alpha a[i-s] = alpha A[i-s], ...
    A, B, C, D = np.zeros((2, size)), np.ones((2, size)), np.zeros((2, size)), np.zeros((2, k, size))  # D: columns as rows
    np.negative(a, out=A[0, mid])
    B[0, mid] = b
    np.negative(c, out=C[0, mid])
    D[0, :, mid] = d.T
    al, ga, tmp, tmpd = np.empty(n), np.empty(n), np.empty(n), np.empty((k, n))
    s = 1
    for j in range(steps):
        o, w = j & 1, 1 - (j & 1)  # old and new buffers
        lo, hi = slice(pad - s, pad - s + n), slice(pad + s, pad + s + n)
        Ao, Bo, Co, Do = A[o], B[o], C[o], D[o]
        np.divide(Ao[mid], Bo[lo], out=al)
        np.divide(Co[mid], Bo[hi], out=ga)
        bn = B[w, mid]  # b - alpha c[i-s] - gamma a[i+s]
        np.multiply(al, Co[lo], out=bn)
        np.multiply(ga, Ao[hi], out=tmp)
        bn += tmp
        np.subtract(Bo[mid], bn, out=bn)
        dn = D[w, :, mid]  # d + alpha d[i-s] + gamma d[i+s]
        np.multiply(al, Do[:, lo], out=dn)
        np.multiply(ga, Do[:, hi], out=tmpd)
        dn += tmpd
        dn += Do[:, mid]
        np.multiply(al, Ao[lo], out=A[w, mid])
        np.multiply(ga, Co[hi], out=C[w, mid])
        s *= 2
    last = steps & 1
    return (D[last, :, mid] / B[last, mid]).T


def _moment_system(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Spans h (n-1,), slopes (n-1, k) and the rhs (n-2, k) of the interior moment equations
    ``h[i-1] M[i-1] + 2 (h[i-1] + h[i]) M[i] + h[i] M[i+1] = 6 (slope[i] - slope[i-1])``
    (de Boor, A Practical Guide to Splines, ch. IV)."""
    h = np.diff(t)
    slope = np.diff(y, axis=0) / h[:, None]
    return h, slope, 6.0 * np.diff(slope, axis=0)


def _periodic_moments(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Second derivatives (n, k) of the periodic C2 cubic spline through ``y`` (``y[-1] == y[0]``)."""
    h, slope, _ = _moment_system(t, y)
    hp = np.roll(h, 1)  # h[i-1], cyclic
    rhs = 6.0 * (slope - np.roll(slope, 1, axis=0))
    m = solve_tridiagonal(hp, 2.0 * (hp + h), h, rhs, cyclic=True)
    return np.vstack([m, m[:1]])


def _clamped_moments(t: np.ndarray, y: np.ndarray, d0: np.ndarray, d1: np.ndarray) -> np.ndarray:
    """Second derivatives (n, k) of the C2 cubic spline through ``y`` with end first derivatives ``d0``, ``d1``."""
    h, slope, inner = _moment_system(t, y)
    lower = np.concatenate([[0.0], h])
    upper = np.concatenate([h, [0.0]])
    diag = 2.0 * np.concatenate([h[:1], h[:-1] + h[1:], h[-1:]])
    rhs = np.vstack([6.0 * (slope[:1] - d0), inner, 6.0 * (d1 - slope[-1:])])
    return solve_tridiagonal(lower, diag, upper, rhs, cyclic=False)


def _cubic_coefficients(t: np.ndarray, y: np.ndarray, moments: np.ndarray) -> np.ndarray:
    """PPoly coefficients (4, n-1, k), highest power first, from the knot moments."""
    h = np.diff(t)[:, None]
    m0, m1 = moments[:-1], moments[1:]
    slope = np.diff(y, axis=0) / h
    return np.stack([(m1 - m0) / (6.0 * h), 0.5 * m0, slope - h * (2.0 * m0 + m1) / 6.0, y[:-1]])


#: Polynomial degrees a :class:`Spline` piece may have.
SPLINE_DEGREES = (3, 5)


def _derivative_factors(degree: int, order: int) -> np.ndarray:
    """Factors (degree + 1 - order,) turning the coefficients (highest power first) of a degree
    ``degree`` polynomial into those of its ``order``-th derivative: ``p!/(p - order)!`` for the
    powers ``p = degree .. order``."""
    powers = np.arange(degree, order - 1, -1, dtype=float)
    out = np.ones_like(powers)
    for j in range(order):
        out *= powers - j
    return out


def _horner(c: np.ndarray, tau: np.ndarray, order: int = 0) -> np.ndarray:
    """``d^order/dtau^order`` of the polynomials with coefficients ``c`` (n, degree + 1, d),
    highest power first, at ``tau`` (n, 1): Horner's rule on the derivative's coefficients."""
    degree = c.shape[1] - 1
    if order > degree:
        return np.zeros((c.shape[0], c.shape[2]))
    f = _derivative_factors(degree, order)
    acc = c[:, 0] * f[0]
    for m in range(1, degree + 1 - order):
        acc = acc * tau + c[:, m] * f[m]
    return acc


@functools.lru_cache(maxsize=None)
def _area_weights(degree: int) -> np.ndarray:
    """The (degree + 1, degree + 1) matrix ``W[i, m] = (m - i) / (i + m)`` for ``i < m`` (0 elsewhere)
    of :func:`piece_green_areas` (read-only; complex, as it multiplies complex coefficients)."""
    i, m = np.triu_indices(degree + 1, 1)
    w = np.zeros((degree + 1, degree + 1), dtype=complex)
    w[i, m] = (m - i) / (i + m)
    w.flags.writeable = False
    return w


def piece_green_areas(q: np.ndarray) -> np.ndarray:
    """``(1/2) integral of (x dy - y dx)`` (mm^2, exact) over every piece of polynomial curves
    given by their scaled coefficients ``q`` (degree + 1, K, ...), complex ``x + i y``, lowest power
    first: piece k is ``sum_i q[i, k] s^i`` for ``s`` in [0, 1] (``q_i = p_i h^i`` of a piece
    ``sum_i p_i tau^i`` on ``[0, h]``); returns (K, ...).

    ``x y' - y x' = sum_{i<m} (m - i) (q_i x q_m) s^(i+m-1)`` integrates to ``sum_{i<m} (m - i) /
    (i + m) (q_i x q_m)``; with ``q_i x q_m = Im(conj(q_i) q_m)`` that is ``Im(sum_i conj(q_i) (W q)_i)``
    (:func:`_area_weights`)."""
    d = q.shape[0] - 1
    wq = _area_weights(d) @ q.reshape(d + 1, -1)
    wq *= np.conj(q).reshape(wq.shape)
    return 0.5 * wq.sum(axis=0).imag.reshape(q.shape[1:])


#: The exponents 0, 1, .. as a column (:func:`piece_green_areas`).
_EXPONENTS = np.arange(max(SPLINE_DEGREES) + 1.0)[:, None]


def _bernstein_max_norm(c: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Upper bound (K,) of ``|P(tau)|`` on ``[0, h]`` of the polynomials with coefficients ``c``
    (degree + 1, K, 2), highest power first: the largest norm of their Bezier control points
    (the curve lies in their convex hull; Farin, *Curves and Surfaces for CAGD*, ch. 4).  Exact for
    degree <= 1 (the control points are the end values)."""
    degree = c.shape[0] - 1
    # power basis in s = tau / h, ascending: a_i = c[degree - i] h^i
    a = np.stack([c[degree - i] * (h ** i)[:, None] for i in range(degree + 1)])
    # Bezier points b_j = sum_{i <= j} C(j, i) / C(degree, i) a_i
    best = np.zeros(h.size)
    for j in range(degree + 1):
        b = sum(math.comb(j, i) / math.comb(degree, i) * a[i] for i in range(j + 1))
        np.maximum(best, np.hypot(b[:, 0], b[:, 1]), out=best)
    return best


def _scaled_ascending(coeffs: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Coefficients (K, degree + 1, 2), lowest power first, of the pieces ``Q(s) = P(h s)`` on
    ``s`` in [0, 1], from ``coeffs`` (degree + 1, K, 2) highest power first in ``tau`` and the
    piece lengths ``h`` (K,)."""
    degree = coeffs.shape[0] - 1
    return np.stack([coeffs[degree - i] * (h ** i)[:, None] for i in range(degree + 1)], axis=1)


def _power_to_bezier(a: np.ndarray) -> np.ndarray:
    """Bezier control values (n, degree + 1, ...) on [0, 1] of the polynomials with ascending power
    coefficients ``a`` (n, degree + 1, ...): ``b_j = sum_{i <= j} C(j, i) / C(degree, i) a_i``
    (Farin, *Curves and Surfaces for CAGD*, ch. 4)."""
    degree = a.shape[1] - 1
    return np.stack([sum(math.comb(j, i) / math.comb(degree, i) * a[:, i] for i in range(j + 1))
                     for j in range(degree + 1)], axis=1)


def _poly_ascending(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Values (n, k) of the polynomials with ascending coefficients ``a`` (n, degree + 1) at ``x`` (n, k) (Horner)."""
    acc = np.broadcast_to(a[:, -1:], x.shape).copy()
    for i in range(a.shape[1] - 2, -1, -1):
        acc *= x
        acc += a[:, i : i + 1]
    return acc


#: Largest number of safeguarded Newton steps of :func:`_sign_change_roots` (each step that
#: would leave the bracket is a bisection; Newton on a monotonic bracket converges in a few).
ROOT_STEPS = 64


def _sign_change_roots(a: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Every point of ``(lo, hi)`` where the polynomial with ascending coefficients ``a`` (n, degree + 1)
    changes sign: (n, degree), sorted, NaN-padded.

    Derivative chain (no eigenvalues, no leading-coefficient division): the sign changes of the
    derivative (found the same way, down to a constant) cut ``[lo, hi]`` into intervals where the
    polynomial is monotonic; each holds one sign change iff its end values differ in sign, and
    Newton steps kept inside the shrinking bracket (a bisection where a step would leave it) find
    it to a few ulps.  A root of even multiplicity (no sign change) is not
    returned: the callers want the extrema of the polynomial's antiderivative, which sit exactly
    at the sign changes.  Identically zero polynomials have none.
    """
    n, degree = a.shape[0], a.shape[1] - 1
    if degree <= 0:
        return np.empty((n, 0))
    crit = np.sort(_sign_change_roots(a[:, 1:] * np.arange(1, degree + 1), lo, hi), axis=1)  # (n, degree - 1)
    bounds = np.concatenate([np.full((n, 1), lo), np.where(np.isnan(crit), hi, crit), np.full((n, 1), hi)], axis=1)
    left, right = bounds[:, :-1], bounds[:, 1:]  # (n, degree) monotonic intervals
    f_left, f_right = _poly_ascending(a, left), _poly_ascending(a, right)
    out = np.full((n, degree), np.nan)
    row, col = np.nonzero(((f_left < 0) & (f_right > 0)) | ((f_left > 0) & (f_right < 0)))
    if row.size:
        coef = a[row]
        slope = coef[:, 1:] * np.arange(1, degree + 1)
        l, r = left[row, col], right[row, col]
        rising = f_left[row, col] < 0
        x = 0.5 * (l + r)
        for _ in range(ROOT_STEPS):
            f = _poly_ascending(coef, x[:, None])[:, 0]
            up = (f < 0) == rising  # x on the left end's side
            l = np.where(up, x, l)
            r = np.where(up, r, x)
            with np.errstate(divide="ignore", invalid="ignore"):
                new = x - f / _poly_ascending(slope, x[:, None])[:, 0]
            tol = 4.0 * np.finfo(float).eps * np.maximum(1.0, np.abs(x))
            step = np.abs(new - x)
            # a Newton step inside the bracket, or one that has converged (x may sit on the bracket's end)
            new = np.where(((new > l) & (new < r)) | (step <= tol), new, 0.5 * (l + r))
            new = np.where(f == 0, x, new)
            moved = np.abs(new - x) > tol
            x = new
            if not np.any(moved):
                break
        out[row, col] = x
    return out


#: Quintic Hermite interpolation on ``s`` in [0, 1] (:func:`quintic_hermite_scaled`): the cubic,
#: quartic and quintic coefficients from what the quadratic Taylor part from ``s = 0`` misses at
#: ``s = 1`` of the value, slope and second derivative, ``(r0, r1, r2)``: ``q_3 = 10 r0 - 4 r1 + r2/2``,
#: ``q_4 = -15 r0 + 7 r1 - r2``, ``q_5 = 6 r0 - 3 r1 + r2/2`` (the 3 x 3 end conditions solved in closed form).
QUINTIC_RESIDUALS = np.array([[10.0, -4.0, 0.5], [-15.0, 7.0, -1.0], [6.0, -3.0, 0.5]])
QUINTIC_RESIDUALS.flags.writeable = False


def quintic_hermite_data(p: np.ndarray, d1: np.ndarray, d2: np.ndarray, h: np.ndarray) -> np.ndarray:
    """The end data ``(p0, delta, v0, v1, a0, a1)`` (6, n - 1, ...) of :func:`quintic_hermite_scaled`
    for the pieces between consecutive rows of ``p``, ``d1``, ``d2`` ((n, ...) each: values, first
    and second derivatives in t) of lengths ``h`` (n - 1,) in t: the derivatives scaled to
    ``s = (t - t_i) / h`` (by ``h`` and ``h^2``); complex when the inputs are."""
    hh = h.reshape(h.shape + (1,) * (p.ndim - 1))
    data = np.empty((6,) + (p.shape[0] - 1,) + p.shape[1:], dtype=np.result_type(p, d1, d2, float))
    data[0] = p[:-1]
    np.subtract(p[1:], p[:-1], out=data[1])
    np.multiply(d1[:-1], hh, out=data[2])
    np.multiply(d1[1:], hh, out=data[3])
    hh = hh * hh
    np.multiply(d2[:-1], hh, out=data[4])
    np.multiply(d2[1:], hh, out=data[5])
    return data


def quintic_hermite_scaled(data: np.ndarray) -> np.ndarray:
    """Power coefficients ``q_0 .. q_5`` (6, ...), lowest first, in ``s`` in [0, 1] of the quintics
    with the end data ``(p0, delta, v0, v1, a0, a1)`` (6, ...) of :func:`quintic_hermite_data`
    (value ``p0`` at 0 and ``p0 + delta`` at 1, slopes, second derivatives): ``q_0 = p0``,
    ``q_1 = v0``, ``q_2 = a0 / 2`` and :data:`QUINTIC_RESIDUALS` times the residuals ``r0 = delta -
    v0 - a0/2``, ``r1 = v1 - v0 - a0``, ``r2 = a1 - a0`` (small differences formed first: the
    coefficients keep the precision of the end data)."""
    q = np.empty_like(data)
    q[0] = data[0]
    q[1] = data[2]
    np.multiply(data[4], 0.5, out=q[2])
    r = np.empty((3,) + data.shape[1:], dtype=data.dtype)
    np.subtract(data[1], data[2], out=r[0])
    r[0] -= q[2]
    np.subtract(data[3], data[2], out=r[1])
    r[1] -= data[4]
    np.subtract(data[5], data[4], out=r[2])
    np.matmul(QUINTIC_RESIDUALS, r.reshape(3, -1), out=q[3:].reshape(3, -1))
    return q


def quintic_hermite_coefficients(t: np.ndarray, p: np.ndarray, d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """Coefficients (6, n - 1, ...), highest power first (in ``t - t[i]``), of the quintics on
    ``[t[i], t[i + 1]]`` that take the values ``p``, first derivatives ``d1`` and second derivatives
    ``d2`` ((n, ...) each) at both ends: :func:`quintic_hermite_scaled` of the end data
    (:func:`quintic_hermite_data`), then ``q_i / h^i``."""
    h = t[1:] - t[:-1]
    return power_coefficients(quintic_hermite_scaled(quintic_hermite_data(p, d1, d2, h)), h)


def power_coefficients(q: np.ndarray, h: np.ndarray) -> np.ndarray:
    """The coefficients (degree + 1, K, ...) in ``tau`` on ``[0, h]``, highest power first (the
    :class:`Spline` convention), of the pieces ``sum_i q[i, k] s^i`` with ``s = tau / h[k]`` (``q``
    lowest power first): ``q_i / h^i``."""
    d = q.shape[0] - 1
    powers = h ** _EXPONENTS[: d + 1]
    return (q / powers.reshape(powers.shape + (1,) * (q.ndim - 2)))[::-1]


class Spline:
    """A parametric piecewise polynomial ``P(t) = (x(t), y(t))`` on ``breaks[0] <= t <= breaks[-1]``,
    every piece of the same degree (3: cubic, 5: quintic; :data:`SPLINE_DEGREES`).

    Parameters
    ----------
    breaks : array (K + 1,)
        Strictly increasing break points of the parameter.
    coeffs : array (degree + 1, K, 2)
        Polynomial coefficients per piece, highest power first (scipy ``PPoly`` convention):
        ``P(t) = sum_m coeffs[m, i] (t - breaks[i]) ** (degree - m)`` on piece ``i``.

    Instances are immutable: the arrays are copied and made read-only.
    """

    kind = "spline"

    def __init__(self, breaks: np.ndarray, coeffs: np.ndarray) -> None:
        breaks = np.array(breaks, dtype=float)
        coeffs = np.array(coeffs, dtype=float)
        if breaks.ndim != 1 or breaks.size < 2 or not (breaks[1:] > breaks[:-1]).all():
            raise ParameterError("breaks", f"array of shape {breaks.shape}", "a strictly increasing 1-D array of >= 2 values")
        if (coeffs.ndim != 3 or coeffs.shape[0] - 1 not in SPLINE_DEGREES or coeffs.shape[1:] != (breaks.size - 1, 2)
                or not np.isfinite(coeffs).all()):
            raise ParameterError("coeffs", f"array of shape {coeffs.shape}",
                                 f"finite values of shape (degree + 1, {breaks.size - 1}, 2), degree one of {SPLINE_DEGREES}")
        breaks.flags.writeable = False
        coeffs.flags.writeable = False
        self.breaks = breaks
        self.coeffs = coeffs
        self.degree = coeffs.shape[0] - 1

    @classmethod
    def _checked_by_caller(cls, breaks: np.ndarray, coeffs: np.ndarray) -> "Spline":
        """A spline of arrays its caller has checked (float ``breaks`` strictly increasing, finite
        float ``coeffs`` of shape (degree + 1, K, 2), possibly a view into a larger block): made
        read-only, neither copied nor checked again (the envelope fit checks all its segments at once)."""
        spline = cls.__new__(cls)
        breaks.flags.writeable = False
        coeffs.flags.writeable = False
        spline.breaks = breaks
        spline.coeffs = coeffs
        spline.degree = coeffs.shape[0] - 1
        return spline

    @functools.cached_property
    def _rows(self) -> np.ndarray:
        """The coefficients as (K, degree + 1, 2), contiguous, for fast gathers of whole pieces."""
        return np.ascontiguousarray(self.coeffs.transpose(1, 0, 2))

    # -- constructors ------------------------------------------------------------------------
    @classmethod
    def interpolate(
        cls,
        t: np.ndarray,
        points: np.ndarray,
        periodic: bool = True,
        end_derivatives: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> "Spline":
        """Cubic spline through ``points`` (n, 2) at parameters ``t`` (n,).

        ``periodic=True`` gives the periodic C2 spline (``points[-1]`` must equal ``points[0]``);
        otherwise the ends are clamped to ``end_derivatives`` (dP/dt at both ends), or use the
        not-a-knot condition when those are not given.
        """
        t = _as_array(t)
        points = _as_array(points)
        if t.ndim != 1 or t.size < 3 or points.shape != (t.size, 2) or not np.all(np.diff(t) > 0):
            raise ParameterError("t", f"{t.size} parameters for points of shape {points.shape}",
                                 "strictly increasing parameters, one per point (n, 2), n >= 3")
        if periodic:
            if not np.allclose(points[0], points[-1], rtol=0, atol=1e-9):
                raise GeometryError("a periodic spline needs its last point equal to its first")
            points = points.copy()
            points[-1] = points[0]
            moments = _periodic_moments(t, points)
        elif end_derivatives is not None:
            moments = _clamped_moments(t, points, *(np.asarray(d, dtype=float) for d in end_derivatives))
        else:
            from scipy.interpolate import CubicSpline  # lazy: scipy.interpolate costs ~0.5 s to import

            spline = CubicSpline(t, points, bc_type="not-a-knot")
            return cls(spline.x, spline.c)
        return cls(t, _cubic_coefficients(t, points, moments))

    @classmethod
    def hermite(cls, t: np.ndarray, points: np.ndarray, derivatives: np.ndarray) -> "Spline":
        """C1 piecewise cubic Hermite interpolant of ``points`` (n, 2) and ``derivatives`` dP/dt (n, 2) at ``t`` (n,)."""
        t, p, m = _as_array(t), _as_array(points), _as_array(derivatives)
        h = np.diff(t)[:, None]
        p0, p1, m0, m1 = p[:-1], p[1:], m[:-1], m[1:]
        c3 = (2.0 * (p0 - p1) + h * (m0 + m1)) / h**3
        c2 = (3.0 * (p1 - p0) - h * (2.0 * m0 + m1)) / h**2
        return cls(t, np.stack([c3, c2, m0, p0]))

    @classmethod
    def hermite5(cls, t: np.ndarray, points: np.ndarray, first: np.ndarray, second: np.ndarray) -> "Spline":
        """C2 piecewise quintic Hermite interpolant of ``points`` (n, 2) and their first and second
        derivatives ``first``, ``second`` (d/dt, d2/dt2, (n, 2) each) at ``t`` (n,): on every piece the
        one quintic with those values at both ends (its error on a piece of length ``h`` is at most
        ``h^6 max|P^(6)| / 46080``: the interpolation remainder ``P^(6)/6! (t - a)^3 (t - b)^3``)."""
        return cls(t, quintic_hermite_coefficients(_as_array(t), _as_array(points), _as_array(first), _as_array(second)))

    # -- pointwise ---------------------------------------------------------------------------
    @property
    def span(self) -> float:
        return float(self.breaks[-1] - self.breaks[0])

    @property
    def n_pieces(self) -> int:
        return self.breaks.size - 1

    def _locate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        idx = np.clip(np.searchsorted(self.breaks, t, side="right") - 1, 0, self.n_pieces - 1)
        return idx, t - self.breaks[idx]

    def eval_t(self, t: np.ndarray, order: int = 0) -> np.ndarray:
        """d^order P / dt^order (n, 2) at spline parameters ``t``."""
        idx, tau = self._locate(_as_array(t))
        return self.eval_piece(idx, tau, order)

    def eval_piece(self, idx: np.ndarray, tau: np.ndarray, order: int = 0) -> np.ndarray:
        """d^order P / dt^order (n, 2) at offsets ``tau`` from the start of pieces ``idx``."""
        if not 0 <= order <= self.degree:
            raise ValueError(f"order must be 0..{self.degree}")
        c = self._rows[idx]  # (n, degree + 1, 2): one contiguous gather
        tau = tau[:, None]
        if self.degree != 3:
            return _horner(c, tau, order)
        if order == 0:
            return ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3]
        if order == 1:
            return (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        if order == 2:
            return 6.0 * c[:, 0] * tau + 2.0 * c[:, 1]
        return 6.0 * c[:, 0]

    def derivatives(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """P, dP/dt and d2P/dt2 (each (n, 2)) at spline parameters ``t``, with one piece lookup."""
        idx, tau = self._locate(_as_array(t))
        c = self._rows[idx]
        tau = tau[:, None]
        if self.degree != 3:
            return _horner(c, tau, 0), _horner(c, tau, 1), _horner(c, tau, 2)
        p = ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3]
        d1 = (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        d2 = 6.0 * c[:, 0] * tau + 2.0 * c[:, 1]
        return p, d1, d2

    def _t(self, u: np.ndarray) -> np.ndarray:
        return self.breaks[0] + _as_array(u) * self.span

    def point(self, u: np.ndarray) -> np.ndarray:
        """Points (n, 2), mm, at local parameters ``u`` in [0, 1]."""
        return self.eval_t(self._t(u))

    def derivative(self, u: np.ndarray) -> np.ndarray:
        return self.eval_t(self._t(u), 1) * self.span

    def second_derivative(self, u: np.ndarray) -> np.ndarray:
        return self.eval_t(self._t(u), 2) * self.span**2

    def curvature(self, u: np.ndarray) -> np.ndarray:
        """Signed curvature, 1/mm."""
        _, d1, d2 = self.derivatives(self._t(u))
        return signed_curvature(d1, d2)

    @property
    def start_point(self) -> np.ndarray:
        return self.coeffs[-1, 0].copy()  # P at tau = 0 of the first piece (what eval_t gives there)

    @property
    def end_point(self) -> np.ndarray:
        (x, y), *rest = self._rows[-1].tolist()  # the last piece at its end, by the arithmetic of eval_piece (Horner)
        tau = float(self.breaks[-1] - self.breaks[-2])
        for cx, cy in rest:
            x = x * tau + cx
            y = y * tau + cy
        return np.array([x, y])

    def _ascending(self) -> np.ndarray:
        """Coefficients (degree + 1, K, 2), lowest power first."""
        return self.coeffs[::-1]

    @property
    def length(self) -> float:
        """Arc length, mm, by 16-point Gauss-Legendre quadrature on every piece (error < 1e-12 relative for smooth pieces)."""
        nodes, weights = np.polynomial.legendre.leggauss(16)
        h = np.diff(self.breaks)
        tau = 0.5 * (nodes[:, None] + 1.0) * h[None, :]  # (16, K)
        d1 = self.eval_piece(np.tile(np.arange(self.n_pieces), 16), tau.ravel(), 1).reshape(16, -1, 2)
        speed = np.hypot(d1[..., 0], d1[..., 1])
        return float(np.sum(weights[:, None] * speed * 0.5 * h[None, :]))

    # -- whole-segment operations -------------------------------------------------------------
    def flatten_params(self, chord_tol: float) -> np.ndarray:
        """Local parameters of a chord polygon within ``chord_tol`` of the curve (end excluded).

        On a piece of parameter length ``h`` the chord deviates from the curve by at most
        ``h^2 / 8 * max |P''|`` (linear-interpolation error bound); ``P''`` is linear on a cubic
        piece, so its largest norm is at one of the piece's ends; on a quintic piece its largest
        norm is bounded by its Bezier control points (:func:`_bernstein_max_norm`).
        """
        h = np.diff(self.breaks)
        c = self.coeffs
        if self.degree == 3:
            acc_start = np.hypot(*(2.0 * c[1]).T)
            acc_end = np.hypot(*(6.0 * c[0] * h[:, None] + 2.0 * c[1]).T)
            max_acc = np.maximum(acc_start, acc_end)
        else:
            second = c[:-2] * _derivative_factors(self.degree, 2)[:, None, None]
            max_acc = _bernstein_max_norm(second, h)
        counts = np.maximum(1, np.ceil(h * np.sqrt(max_acc / (8.0 * chord_tol)) - 1e-12)).astype(int)
        piece = np.repeat(np.arange(self.n_pieces), counts)
        first = np.repeat(np.cumsum(counts) - counts, counts)
        frac = (np.arange(counts.sum()) - first) / counts[piece]
        t = self.breaks[piece] + frac * h[piece]
        return (t - self.breaks[0]) / self.span

    def min_turning(self) -> float:
        """Smallest ``P' x P''`` over the spline (its sign is the sign of the curvature), exact.

        On a cubic piece ``P' x P''`` is the quadratic ``-6 (a x b) t^2 + 6 (c x a) t + 2 (c x b)``
        (``P = a t^3 + b t^2 + c t + d``); its minimum is at an end or at the vertex.  Other
        degrees: :meth:`_min_turning_generic` (degree 6 on a quintic piece).
        """
        if self.degree != 3:
            return self._min_turning_generic()
        a, b, c = self.coeffs[0], self.coeffs[1], self.coeffs[2]

        def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
            return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]

        qa, qb, qc = -6.0 * cross(a, b), 6.0 * cross(c, a), 2.0 * cross(c, b)
        h = np.diff(self.breaks)
        with np.errstate(divide="ignore", invalid="ignore"):
            vertex = np.clip(np.where(qa != 0, -qb / (2.0 * qa), 0.0), 0.0, h)
        values = [qc, (qa * h + qb) * h + qc, (qa * vertex + qb) * vertex + qc]
        return float(np.min(values))

    def _scaled(self) -> np.ndarray:
        """Coefficients (K, degree + 1, 2), lowest power first, of ``Q(s) = P(breaks[i] + h_i s)``, s in [0, 1]."""
        return _scaled_ascending(self.coeffs, np.diff(self.breaks))

    def _roots_in_pieces(self, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Pieces and offsets ``tau`` of the sign changes of the polynomials in ``s`` with ascending
        coefficients ``a`` (K, m) (one per piece) on ``[0, 1]``; one just outside (within
        :data:`ROOT_TOL`, by rounding at a knot) counts as on the end."""
        s = _sign_change_roots(a, -ROOT_TOL, 1.0 + ROOT_TOL)  # (K, m - 1)
        piece, col = np.nonzero(np.isfinite(s))
        h = np.diff(self.breaks)
        return piece, np.clip(s[piece, col], 0.0, 1.0) * h[piece]

    def _min_turning_generic(self) -> float:
        """:meth:`min_turning` for any degree: with ``Q(s) = sum_i q_i s^i`` (``s = tau / h``),
        ``Q' x Q'' = sum_{k<m} k m (m - k) (q_k x q_m) s^(k+m-3)`` (degree ``2 degree - 4``; 6 for a
        quintic); its minimum on a piece is at an end or where its derivative changes sign."""
        q = self._scaled()  # (K, d + 1, 2)
        d = self.degree
        w = np.zeros((self.n_pieces, 2 * d - 3))
        for k in range(1, d + 1):
            for m in range(k + 1, d + 1):
                w[:, k + m - 3] += k * m * (m - k) * (q[:, k, 0] * q[:, m, 1] - q[:, k, 1] * q[:, m, 0])
        piece, tau = self._roots_in_pieces(w[:, 1:] * np.arange(1, w.shape[1]))
        h = np.diff(self.breaks)
        everywhere = np.arange(self.n_pieces)
        idx = np.concatenate([everywhere, everywhere, piece])
        at = np.concatenate([np.zeros(self.n_pieces), h, tau])
        d1, d2 = self.eval_piece(idx, at, 1), self.eval_piece(idx, at, 2)
        return float(np.min(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]))

    def green_area(self) -> float:
        """(1/2) integral of (x dy - y dx) along the spline, mm^2 (exact polynomial integration,
        :func:`piece_green_areas` of the coefficients scaled to each piece)."""
        h = self.breaks[1:] - self.breaks[:-1]
        return float(piece_green_areas(self.coeffs.view(complex)[::-1, :, 0] * h ** _EXPONENTS[: self.degree + 1]).sum())

    def _quadratic_roots(self, qa: np.ndarray, qb: np.ndarray, qc: np.ndarray) -> np.ndarray:
        """Real roots (2, ...) of qa tau^2 + qb tau + qc inside each piece, NaN elsewhere."""
        h = np.diff(self.breaks).reshape((-1,) + (1,) * (qa.ndim - 1))
        with np.errstate(divide="ignore", invalid="ignore"):
            disc = qb * qb - 4.0 * qa * qc
            sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
            # numerically stable pair of roots; linear case where qa is ~0
            q = -0.5 * (qb + np.copysign(sq, qb))
            r1 = np.where(np.abs(qa) > 1e-300, q / qa, -qc / qb)
            r2 = np.where(np.abs(q) > 1e-300, qc / q, np.nan)
        roots = np.stack([r1, r2])
        # a root on a knot may round to just outside [0, h]: accept it within ROOT_TOL of the piece
        slack = ROOT_TOL * h
        inside = (roots >= -slack) & (roots <= h + slack)
        return np.where(inside, np.clip(roots, 0.0, h), np.nan)

    def extreme_points(self) -> np.ndarray:
        """Break points and axis-extreme points (k, 2): the exact bounding box of the spline."""
        if self.degree != 3:
            # x'(s) and y'(s) (degree 4 for a quintic): the extremes are at their sign changes
            q = self._scaled()
            pts = [self.eval_t(self.breaks)]
            for axis in range(2):
                piece, tau = self._roots_in_pieces(q[:, 1:, axis] * np.arange(1, self.degree + 1))
                pts.append(self.eval_piece(piece, tau))
            return np.concatenate(pts)
        c = self.coeffs
        pts = [self.eval_t(self.breaks)]
        for axis in range(2):
            roots = self._quadratic_roots(3 * c[0][:, axis], 2 * c[1][:, axis], c[2][:, axis])
            piece = np.broadcast_to(np.arange(self.n_pieces), roots.shape)
            ok = np.isfinite(roots)
            if ok.any():
                pts.append(self.eval_t(self.breaks[piece[ok]] + roots[ok]))
        return np.concatenate(pts)

    def ray_hits(self, phi: np.ndarray, iterations: int = 60) -> np.ndarray:
        """Distances (M, 1) along rays from the origin at polar angles ``phi`` to this spline (NaN: no hit).

        The piece where ``u x P`` changes sign from - to + (with ``P . u > 0``) holds the hit;
        safeguarded Newton steps refine it to 1e-13 in the parameter.  One hit per ray is
        returned (the first such piece); :meth:`Contour.polar_radius` checks that there is one.
        """
        u = _unit(phi)
        pts = self.eval_t(self.breaks)  # (K + 1, 2)
        if np.allclose(pts[0], pts[-1], rtol=0, atol=1e-9):
            pts[-1] = pts[0]  # a closed spline: its two ends are one break, counted once
        g = np.outer(u[:, 0], pts[:, 1]) - np.outer(u[:, 1], pts[:, 0])  # (M, K + 1) = u x P
        ahead = (u @ pts.T) > 0
        crossing = (g[:, :-1] < 0) & (g[:, 1:] >= 0) & (ahead[:, :-1] | ahead[:, 1:])  # half-open: a break counts once
        count = crossing.sum(axis=1)
        piece = np.argmax(crossing, axis=1)
        lo = self.breaks[piece].copy()
        hi = self.breaks[piece + 1].copy()
        g0, g1 = g[np.arange(phi.size), piece], g[np.arange(phi.size), piece + 1]
        t = lo + (hi - lo) * np.clip(-g0 / np.where(g1 - g0 != 0, g1 - g0, 1.0), 0.0, 1.0)
        for _ in range(iterations):
            p = self.eval_t(t)
            dp = self.eval_t(t, 1)
            gt = u[:, 0] * p[:, 1] - u[:, 1] * p[:, 0]
            dg = u[:, 0] * dp[:, 1] - u[:, 1] * dp[:, 0]
            lo = np.where(gt < 0, t, lo)
            hi = np.where(gt > 0, t, hi)
            new = t - np.where(dg != 0, gt / np.where(dg != 0, dg, 1.0), 0.0)
            new = np.where((new <= lo) | (new >= hi) | ~np.isfinite(new), 0.5 * (lo + hi), new)
            converged = np.max(np.abs(new - t), initial=0.0) <= 1e-13 * max(1.0, self.span)
            t = new
            if converged:
                break
        dist = np.einsum("ij,ij->i", self.eval_t(t), u)
        out = np.where(count >= 1, dist, np.nan)
        if np.any(count > 1):
            out = np.where(count > 1, np.inf, out)  # several crossings: flagged for the caller
        return out[:, None]

    def support_candidates(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Largest interior value of ``P . u(psi)`` (M,) over all pieces, its point (M, 2) and radius of curvature (M,).

        Interior extrema of ``P(t) . u`` are roots of the quadratic ``P'(t) . u = 0`` on each piece
        (cubic pieces; other degrees: :meth:`_support_candidates_generic`).
        """
        if self.degree != 3:
            return self._support_candidates_generic(psi)
        u = _unit(psi)  # (M, 2)
        c = self.coeffs  # (4, K, 2)
        # coefficients of P'(tau).u per (piece, direction): (K, M)
        qa = 3.0 * (c[0] @ u.T)
        qb = 2.0 * (c[1] @ u.T)
        qc = c[2] @ u.T
        roots = self._quadratic_roots(qa, qb, qc)  # (2, K, M)
        tau = np.nan_to_num(roots, nan=0.0)
        vals = np.zeros_like(roots)
        for m in range(4):  # Horner on P(tau) . u
            vals = vals * tau + (c[m] @ u.T)[None]
        vals = np.where(np.isfinite(roots), vals, -np.inf)
        flat = vals.reshape(-1, psi.size)
        best = np.argmax(flat, axis=0)
        best_val = flat[best, np.arange(psi.size)]
        root_idx, piece = np.divmod(best, self.n_pieces)
        t = self.breaks[piece] + tau[root_idx, piece, np.arange(psi.size)]
        d1, d2 = self.eval_t(t, 1), self.eval_t(t, 2)
        with np.errstate(divide="ignore"):
            rho = np.hypot(d1[:, 0], d1[:, 1]) ** 3 / (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
        return best_val, self.eval_t(t), rho

    def _support_candidates_generic(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`support_candidates` for any degree.

        ``f(s) = Q'(s) . u`` (``Q(s) = P(breaks[i] + h s)``) is a polynomial of degree
        ``degree - 1`` whose Bezier control values on [0, 1] are ``B_j . u`` (``B_j`` the control
        points of ``Q'``): where they keep one sign ``f`` has no root on the piece (convex-hull
        property).  Only the (piece, direction) pairs where they change sign (within a slack
        covering the :data:`ROOT_TOL` extension of the piece) are solved, by :func:`_sign_change_roots`.
        """
        u = _unit(psi)  # (M, 2)
        m_dirs = psi.size
        q = self._scaled()  # (K, d + 1, 2)
        d = self.degree
        bez = _power_to_bezier(q[:, 1:] * np.arange(1, d + 1)[None, :, None])  # (K, d, 2): control points of Q'
        # |f| changes by at most |f'| ROOT_TOL <= 2 (d - 1) max|B| ROOT_TOL on the slack
        slack = 2.0 * (d - 1) * ROOT_TOL * np.max(np.hypot(bez[..., 0], bez[..., 1]), axis=1)  # (K,)
        lowest = np.full((self.n_pieces, m_dirs), np.inf)
        highest = np.full((self.n_pieces, m_dirs), -np.inf)
        for j in range(d):
            bj = bez[:, j] @ u.T  # (K, M)
            np.minimum(lowest, bj, out=lowest)
            np.maximum(highest, bj, out=highest)
        piece, direction = np.nonzero((lowest < slack[:, None]) & (highest > -slack[:, None]))
        best_val = np.full(m_dirs, -np.inf)
        best_piece = np.zeros(m_dirs, dtype=int)
        best_tau = np.zeros(m_dirs)
        if piece.size:
            uu = u[direction]
            f = (q[piece, 1:, 0] * uu[:, :1] + q[piece, 1:, 1] * uu[:, 1:]) * np.arange(1, d + 1)  # (n, d)
            s = _sign_change_roots(f, -ROOT_TOL, 1.0 + ROOT_TOL)  # (n, d - 1)
            row, col = np.nonzero(np.isfinite(s))
            if row.size:
                h = np.diff(self.breaks)
                pc = piece[row]
                tau = np.clip(s[row, col], 0.0, 1.0) * h[pc]
                dr = direction[row]
                vals = np.einsum("ij,ij->i", self.eval_piece(pc, tau), u[dr])
                order = np.lexsort((vals, dr))  # by direction, then value: the last of each direction wins
                last = order[np.append(dr[order][1:] != dr[order][:-1], True)]
                best_val[dr[last]] = vals[last]
                best_piece[dr[last]] = pc[last]
                best_tau[dr[last]] = tau[last]
        pts = self.eval_piece(best_piece, best_tau)
        d1, d2 = self.eval_piece(best_piece, best_tau, 1), self.eval_piece(best_piece, best_tau, 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = np.hypot(d1[:, 0], d1[:, 1]) ** 3 / (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
        return best_val, pts, rho

    def offset(self, distance: float, index: int = 0, tol: float = 1e-6) -> "Spline":
        """Offset along the outward normal of a CCW contour, refitted as a piecewise cubic.

        The exact offset ``Q = P + d n`` has tangent ``Q' = P' (1 + d kappa)``; where
        ``1 + d kappa <= 0`` the offset reverses (cusp, undercut) and a :class:`GeometryError`
        names the segment and cam angle (sampled: 4 points per cubic piece, 32 per quintic
        piece).  ``Q`` is only C1 at the breaks of ``P`` (``kappa'``
        jumps there), so the refit is a cubic Hermite interpolant of the exact ``Q`` and ``Q'``
        on a subdivision of every piece (C1, error O(h^4)), refined until its distance to the
        exact offset at the quarter points of every new piece is <= ``tol`` mm.
        """
        # sampled reversal check: 4 points per cubic piece; quintic pieces are ~8x longer, so 32
        per_piece = 4 if self.degree == 3 else 32
        dense_u = np.linspace(0.0, 1.0, per_piece * self.n_pieces + 1)
        kappa = self.curvature(dense_u)
        factor = 1.0 + distance * kappa
        if np.any(factor <= 0.0):
            worst = int(np.argmin(factor))
            p = self.point(dense_u[worst : worst + 1])[0]
            polar = math.degrees(math.atan2(p[1], p[0])) % 360.0
            raise GeometryError(
                f"offset {distance:g} mm of segment {index} (spline) reverses at cam angle {polar:.3f} deg: "
                f"radius of curvature {1.0 / abs(kappa[worst]):.6g} mm <= |offset| (undercut)"
            )

        def exact(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            p, d1, d2 = self.derivatives(t)
            return p + distance * outward_normal(d1), d1 * (1.0 + distance * signed_curvature(d1, d2))[:, None]

        subdiv = 1
        h = np.diff(self.breaks)
        while True:
            frac = np.arange(subdiv) / subdiv
            t = np.append((self.breaks[:-1, None] + frac[None, :] * h[:, None]).ravel(), self.breaks[-1])
            q, dq = exact(t)
            fit = Spline.hermite(t, q, dq)
            probe = (t[:-1, None] + np.array([0.25, 0.5, 0.75])[None, :] * np.diff(t)[:, None]).ravel()
            err = float(np.max(np.hypot(*(fit.eval_t(probe) - exact(probe)[0]).T)))
            if err <= tol:
                return fit
            if subdiv >= 256:
                raise GeometryError(
                    f"offset {distance:g} mm of segment {index} (spline): refit error {err:.3g} mm "
                    f"stays above tol = {tol:g} mm; the offset is too close to a cusp"
                )
            # the Hermite error falls as (piece length)^4: jump to the subdivision that should do
            subdiv = min(256, max(subdiv + 1, math.ceil(1.1 * subdiv * (err / tol) ** 0.25)))


Segment = Union[Arc, Spline]


# --------------------------------------------------------------------------------------------
# Joint report
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Joint:
    """Continuity where segment ``index`` ends and the next one starts.

    ``gap_mm`` is the distance between the two ends, ``tangent_jump_rad`` the angle between the
    two unit tangents, ``curvature_jump_per_mm`` the jump of signed curvature (1/mm), and
    ``continuity`` the highest of ``"G2"``, ``"G1"``, ``"G0"`` that holds, or ``"none"``.
    """

    index: int
    point: tuple[float, float]
    gap_mm: float
    tangent_jump_rad: float
    curvature_jump_per_mm: float
    continuity: str


# --------------------------------------------------------------------------------------------
# Vectorised evaluation over many segments
# --------------------------------------------------------------------------------------------
def _grouped_searchsorted(values: np.ndarray, starts: np.ndarray, groups: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """``np.searchsorted(values[starts[g]:starts[g + 1]], q, side="right")`` for every query
    ``q`` of group ``g`` at once (``values`` sorted within each group, groups in order; ``starts``
    (G + 1,)).  Exact: one stable sort of values and queries together, no arithmetic on them."""
    if starts.size == 2:  # one group: a plain search
        return np.searchsorted(values, queries, side="right")
    value_groups = np.repeat(np.arange(starts.size - 1), np.diff(starts))
    keys_group = np.concatenate([value_groups, groups])
    keys_value = np.concatenate([values, queries])
    is_query = np.concatenate([np.zeros(values.size, np.int8), np.ones(queries.size, np.int8)])
    order = np.lexsort((is_query, keys_value, keys_group))  # by group, value, values before queries
    queries_before = np.cumsum(is_query[order]) - is_query[order]
    rank = np.empty(order.size, np.int64)
    rank[order] = np.arange(order.size)
    at = rank[values.size :]
    return at - queries_before[at] - starts[groups]


class _SegmentTables:
    """Per-segment arrays of a contour: arc parameters, and the pieces of all its splines
    concatenated (rows (P, degree + 1, 2) of the highest degree among them, lower-degree pieces
    with leading zeros; breaks, and where each spline's breaks and pieces start)."""

    def __init__(self, segments: tuple) -> None:
        n = len(segments)
        self.is_arc = np.array([isinstance(seg, Arc) for seg in segments])
        self.center = np.full((n, 2), np.nan)
        self.radius = np.full(n, np.nan)
        self.start = np.full(n, np.nan)
        self.sweep = np.full(n, np.nan)
        self.kappa = np.full(n, np.nan)
        splines = []
        for i, seg in enumerate(segments):
            if isinstance(seg, Arc):
                self.center[i] = seg.center
                self.radius[i], self.start[i], self.sweep[i] = seg.radius, seg.start_angle, seg.sweep
                self.kappa[i] = math.copysign(1.0 / seg.radius, seg.sweep)
            else:
                splines.append((i, seg))
        self.spline_of = np.full(n, -1)  # segment -> spline number
        self.spline_of[[i for i, _ in splines]] = np.arange(len(splines))
        self.splines = [seg for _, seg in splines]
        if splines:
            self.breaks = np.concatenate([seg.breaks for seg in self.splines])
            self.break_start = np.concatenate([[0], np.cumsum([seg.breaks.size for seg in self.splines])])
            self.piece_start = self.break_start[:-1] - np.arange(len(splines))  # K pieces per K + 1 breaks
            self.n_pieces = np.array([seg.n_pieces for seg in self.splines])
            self.degree = max(seg.degree for seg in self.splines)
            self.rows = np.concatenate([np.pad(seg._rows, ((0, 0), (self.degree - seg.degree, 0), (0, 0))) for seg in self.splines])
            self.t0 = np.array([seg.breaks[0] for seg in self.splines])
            self.span = np.array([seg.span for seg in self.splines])

    def arc_values(self, idx: np.ndarray, u: np.ndarray, method: str) -> np.ndarray:
        """Arc.point / derivative / curvature of segments ``idx`` at local parameters ``u``."""
        if method == "curvature":
            return self.kappa[idx]
        angle = self.start[idx] + self.sweep[idx] * u
        if method == "point":
            return self.center[idx] + self.radius[idx][:, None] * _unit(angle)
        return (self.radius[idx] * self.sweep[idx])[:, None] * np.stack([-np.sin(angle), np.cos(angle)], axis=-1)

    def locate(self, spline: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rows (into ``self.rows``) and offsets of spline parameters ``t`` of splines
        ``spline``: Spline._locate for many splines at once."""
        local = _grouped_searchsorted(self.breaks, self.break_start, spline, t) - 1
        local = np.clip(local, 0, self.n_pieces[spline] - 1)
        return self.piece_start[spline] + local, t - self.breaks[self.break_start[spline] + local]

    def spline_values(self, idx: np.ndarray, u: np.ndarray, method: str) -> np.ndarray:
        """Spline.point / derivative / curvature of segments ``idx`` at local parameters ``u``."""
        spline = self.spline_of[idx]
        t = self.t0[spline] + u * self.span[spline]  # Spline._t
        row, tau = self.locate(spline, t)
        c = self.rows[row]
        tau = tau[:, None]
        if self.degree != 3:
            if method == "point":
                return _horner(c, tau, 0)
            d1 = _horner(c, tau, 1)
            if method == "derivative":
                return d1 * self.span[spline][:, None]
            return signed_curvature(d1, _horner(c, tau, 2))
        if method == "point":
            return ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3]
        d1 = (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        if method == "derivative":
            return d1 * self.span[spline][:, None]
        return signed_curvature(d1, 6.0 * c[:, 0] * tau + 2.0 * c[:, 1])


#: Newton steps of the spline ray solve (:class:`_StarTable`); it stops once every step is
#: below 1e-13 of the parameter span.
RAY_ITERATIONS = 60


class _StarTable:
    """Polar angles at the start of every piece of a star-shaped contour (arcs cut into parts
    of at most 45 deg), increasing once around the axis, what each piece is, and the splines'
    break points (aligned with ``tables.breaks``)."""

    def __init__(self, psi: np.ndarray, segment: np.ndarray, piece: np.ndarray, tables: _SegmentTables, ends: np.ndarray) -> None:
        self.psi, self.segment, self.piece, self.tables, self.ends = psi, segment, piece, tables, ends

    @classmethod
    def build(cls, contour: "Contour") -> "_StarTable | None":
        tables = contour._tables()
        segment, piece, points, ends = [], [], [], []
        for i, seg in enumerate(contour.segments):
            if isinstance(seg, Arc):
                # P x P' = r s (r + c . u(a)) along the arc (s: sign of the sweep) keeps its
                # sign iff the polar angle is monotonic there: check its extremes over the sweep
                cx, cy = seg.center
                distance = math.hypot(cx, cy)
                candidates = [seg.start_angle, seg.start_angle + seg.sweep]
                toward = math.atan2(cy, cx)
                for extreme in (toward, toward + math.pi):
                    if angle_in_sweep(np.array([extreme]), seg.start_angle, seg.sweep)[0]:
                        candidates.append(extreme)
                cu = distance * np.cos(np.array(candidates) - toward)
                if not np.all(np.sign(seg.sweep) * (seg.radius + cu) > 0):
                    return None
                parts = max(1, math.ceil(abs(seg.sweep) / (math.pi / 4)))
                segment += [i] * parts
                piece += list(range(parts))
                points.append(seg.point(np.arange(parts) / parts))
            else:
                pts = seg.eval_t(seg.breaks)
                if np.allclose(pts[0], pts[-1], rtol=0, atol=1e-9):
                    pts[-1] = pts[0]  # a closed spline: its two ends are one break
                ends.append(pts)  # aligned with tables.breaks
                segment += [i] * seg.n_pieces
                piece += list(range(seg.n_pieces))
                points.append(pts[:-1])
        points = np.concatenate(points)
        angle = np.arctan2(points[:, 1], points[:, 0])
        step = np.mod(np.diff(angle, append=angle[:1]) + math.pi, TWO_PI) - math.pi
        if not (np.all(step > 0) and abs(float(step.sum()) - TWO_PI) < 1e-9):
            return None
        psi = angle[0] + np.concatenate([[0.0], np.cumsum(step[:-1])])
        return cls(psi, np.array(segment), np.array(piece), tables, np.concatenate(ends) if ends else np.empty((0, 2)))

    def radius(self, phi: np.ndarray) -> np.ndarray:
        """Distance along each ray ``phi`` (M,) to the contour, mm (NaN where a solve failed)."""
        start = self.psi[0]
        k = np.searchsorted(self.psi, start + np.mod(phi - start, TWO_PI), side="right") - 1
        seg = self.segment[k]
        u = _unit(phi)
        out = np.full(phi.size, np.nan)
        arc = self.tables.is_arc[seg]
        if arc.any():
            s = seg[arc]
            c, r, uu = self.tables.center[s], self.tables.radius[s], u[arc]
            uc = uu[:, 0] * c[:, 0] + uu[:, 1] * c[:, 1]
            disc = uc * uc - (c[:, 0] * c[:, 0] + c[:, 1] * c[:, 1]) + r**2
            root = np.sqrt(np.maximum(disc, 0.0))
            # the root where P x P' has the sign of the sweep: far on a convex arc, near on a concave one
            out[arc] = np.where(self.tables.sweep[s] > 0, uc + root, uc - root)
        if not arc.all():
            out[~arc] = self._spline_radius(seg[~arc], self.piece[k[~arc]], u[~arc])
        return out

    def _spline_radius(self, seg: np.ndarray, piece: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Safeguarded Newton on ``g(t) = u x P(t)`` inside the piece each ray meets."""
        tables = self.tables
        spline = tables.spline_of[seg]
        first = tables.break_start[spline] + piece
        lo, hi = tables.breaks[first].copy(), tables.breaks[first + 1].copy()
        row = tables.piece_start[spline] + piece
        c = tables.rows[row]
        p0, p1 = self.ends[first], self.ends[first + 1]
        g0 = u[:, 0] * p0[:, 1] - u[:, 1] * p0[:, 0]
        g1 = u[:, 0] * p1[:, 1] - u[:, 1] * p1[:, 0]
        t = lo + (hi - lo) * np.clip(-g0 / np.where(g1 - g0 != 0, g1 - g0, 1.0), 0.0, 1.0)
        base = lo.copy()
        tol = 1e-13 * np.maximum(1.0, tables.span[spline])
        active = np.arange(t.size)  # rays still iterating
        cubic = tables.degree == 3
        for _ in range(RAY_ITERATIONS):
            a = active
            tau = (t[a] - base[a])[:, None]
            ca, ua = c[a], u[a]
            if cubic:
                p = ((ca[:, 0] * tau + ca[:, 1]) * tau + ca[:, 2]) * tau + ca[:, 3]
                dp = (3.0 * ca[:, 0] * tau + 2.0 * ca[:, 1]) * tau + ca[:, 2]
            else:
                p, dp = _horner(ca, tau, 0), _horner(ca, tau, 1)
            gt = ua[:, 0] * p[:, 1] - ua[:, 1] * p[:, 0]
            dg = ua[:, 0] * dp[:, 1] - ua[:, 1] * dp[:, 0]
            lo[a] = np.where(gt < 0, t[a], lo[a])
            hi[a] = np.where(gt > 0, t[a], hi[a])
            new = t[a] - np.where(dg != 0, gt / np.where(dg != 0, dg, 1.0), 0.0)
            # a Newton step leaving the bracket becomes a bisection (a root on a break stays)
            new = np.where((new < lo[a]) | (new > hi[a]) | ~np.isfinite(new), 0.5 * (lo[a] + hi[a]), new)
            moving = np.abs(new - t[a]) > tol[a]
            t[a] = new
            active = a[moving]
            if not active.size:
                break
        tau = (t - base)[:, None]
        p = ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3] if cubic else _horner(c, tau, 0)
        return np.einsum("ij,ij->i", p, u)


# --------------------------------------------------------------------------------------------
# Contour
# --------------------------------------------------------------------------------------------
class Contour:
    """A closed counter-clockwise chain of :class:`Arc` and :class:`Spline` segments (mm, cam frame).

    Parameters
    ----------
    segments : sequence of Arc or Spline
        In order along the curve; each must start where the previous one ends.
    closure_tol : float
        Largest gap allowed at a joint, mm.

    Raises
    ------
    GeometryError
        If the chain is not closed within ``closure_tol`` or is not counter-clockwise.
    """

    def __init__(self, segments: Iterable[Segment], closure_tol: float = DEFAULT_CLOSURE_TOL) -> None:
        self.segments: tuple[Segment, ...] = tuple(segments)
        if not self.segments:
            raise GeometryError("a contour needs at least one segment")
        for i, seg in enumerate(self.segments):
            nxt = self.segments[(i + 1) % len(self.segments)]
            (ex, ey), (sx, sy) = seg.end_point.tolist(), nxt.start_point.tolist()
            gap = math.hypot(ex - sx, ey - sy)
            if gap > closure_tol:
                raise GeometryError(
                    f"contour is not closed: segment {i} ends {gap:.3g} mm from where segment "
                    f"{(i + 1) % len(self.segments)} starts (closure_tol = {closure_tol:g} mm)"
                )
        area = self.area
        if area <= 0.0:
            raise GeometryError(f"contour must run counter-clockwise (signed area {area:.6g} mm^2 <= 0)")
        self._corners = np.array([seg.start_point for seg in self.segments])  # segment start points (n, 2)
        self._arc_table = self._convex_arc_table()

    @classmethod
    def _checked_by_caller(cls, segments: Sequence[Segment], area: float) -> Contour:
        """A contour whose caller has checked what the constructor checks (each segment starts
        within ``DEFAULT_CLOSURE_TOL`` of where the previous one ends; the signed ``area`` (mm^2,
        Green's theorem) is > 0) for several contours at once (the envelope fit); else use
        ``Contour(segments)``, which raises the message that names the failure."""
        contour = cls.__new__(cls)
        contour.segments = tuple(segments)
        contour.__dict__["area"] = area
        contour._corners = np.array([seg.start_point for seg in contour.segments])
        contour._arc_table = contour._convex_arc_table()
        return contour

    def _convex_arc_table(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """For a G1 chain of convex arcs, the normal-angle ranges tile the circle: start angles
        (sorted, mod 2 pi), centres and radii, for an O(log n) support function."""
        if not all(isinstance(s, Arc) and s.sweep > 0 for s in self.segments):
            return None
        starts = np.array([s.start_angle for s in self.segments]) % TWO_PI
        ends = np.array([s.start_angle + s.sweep for s in self.segments])
        # convex arcs join with a common tangent iff each ends at the normal angle the next starts at
        if np.any(np.abs(_wrap_pi(ends - np.roll(starts, -1))) > 1e-9):
            return None
        order = np.argsort(starts)
        centres = np.array([s.center for s in self.segments])[order]
        radii = np.array([s.radius for s in self.segments])[order]
        return starts[order], centres, radii

    def __repr__(self) -> str:
        kinds = ", ".join(s.kind for s in self.segments)
        return f"Contour({len(self.segments)} segments: {kinds})"

    @property
    def n_segments(self) -> int:
        return len(self.segments)

    # -- pointwise ---------------------------------------------------------------------------
    def _tables(self) -> "_SegmentTables":
        """Per-segment arrays for vectorised evaluation (built once, on first use)."""
        tables = self.__dict__.get("_segment_tables")
        if tables is None:
            tables = self.__dict__["_segment_tables"] = _SegmentTables(self.segments)
        return tables

    def _dispatch(self, t: object, method: str) -> np.ndarray:
        """``method`` ("point", "derivative" or "curvature") of the segments at global
        parameters ``t``: every arc point in one vectorised pass (centres, radii and angles
        gathered per point), every spline point in another (its piece located by one sorted
        search over all spline breaks); the same arithmetic as the segments' own methods."""
        t = _as_array(t)
        shape = t.shape
        flat = np.mod(t.ravel(), self.n_segments)
        idx = np.minimum(np.floor(flat).astype(int), self.n_segments - 1)
        u = flat - idx
        tables = self._tables()
        width = () if method == "curvature" else (2,)
        out = np.empty((flat.size,) + width)
        arc = tables.is_arc[idx]
        if arc.all():
            out[...] = tables.arc_values(idx, u, method)
        elif arc.any():
            out[arc] = tables.arc_values(idx[arc], u[arc], method)
            out[~arc] = tables.spline_values(idx[~arc], u[~arc], method)
        else:
            out[...] = tables.spline_values(idx, u, method)
        return out.reshape(shape + width)

    def evaluate(self, t: object) -> np.ndarray:
        """Points (..., 2), mm, at global parameters ``t`` (see module docstring)."""
        return self._dispatch(t, "point")

    def tangent(self, t: object) -> np.ndarray:
        """Unit tangents (..., 2) in the direction of travel (counter-clockwise)."""
        d = self._dispatch(t, "derivative")
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def normal(self, t: object) -> np.ndarray:
        """Outward unit normals (..., 2): the tangent rotated by -90 deg."""
        tan = self.tangent(t)
        return np.stack([tan[..., 1], -tan[..., 0]], axis=-1)

    def curvature(self, t: object) -> np.ndarray:
        """Signed curvature (...,), 1/mm; > 0 where the contour is convex."""
        return self._dispatch(t, "curvature")

    # -- flattening ---------------------------------------------------------------------------
    def flatten_params(self, chord_tol: float = DEFAULT_CHORD_TOL) -> np.ndarray:
        """Global parameters of the vertices of :meth:`flatten` (start of the contour first)."""
        require_positive("chord_tol", chord_tol)
        parts = [i + seg.flatten_params(chord_tol) for i, seg in enumerate(self.segments)]
        params = np.concatenate(parts)
        if params.size < 3:  # a closed polygon needs 3 vertices
            params = np.linspace(0.0, self.n_segments, 4)[:-1]
        return params

    def flatten(self, chord_tol: float = DEFAULT_CHORD_TOL) -> np.ndarray:
        """Closed polygon (N, 2), mm, first vertex not repeated, counter-clockwise.

        Every vertex lies on the curve and every chord stays within ``chord_tol`` mm of the
        curve between its ends (sagitta formula for arcs, second-derivative bound for splines).
        """
        return self.evaluate(self.flatten_params(chord_tol))

    # -- global measures ----------------------------------------------------------------------
    @functools.cached_property
    def area(self) -> float:
        """Enclosed area, mm^2, by Green's theorem (exact for arcs and polynomial pieces)."""
        return float(sum(seg.green_area() for seg in self.segments))

    @property
    def length(self) -> float:
        """Perimeter, mm (exact for arcs, Gauss-Legendre for splines)."""
        return float(sum(seg.length for seg in self.segments))

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """Exact bounding box ``(xmin, ymin, xmax, ymax)``, mm."""
        pts = np.concatenate([seg.extreme_points() for seg in self.segments])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    @property
    def size(self) -> float:
        """Largest distance of the contour from the rotation axis (bounding-box estimate), mm."""
        xmin, ymin, xmax, ymax = self.bounds
        return float(max(abs(xmin), abs(ymin), abs(xmax), abs(ymax)))

    # -- offset -------------------------------------------------------------------------------
    def offset(self, distance: float, spline_tol: float = 1e-6) -> "Contour":
        """The contour offset by ``distance`` mm along its outward normal (< 0: inward).

        Arcs stay exact arcs with radius ``r + d`` (convex) or ``r - d`` (concave); spline
        segments are refitted within ``spline_tol`` mm.  Raises :class:`GeometryError` naming
        the segment and cam angle where a radius would reach zero (undercut), or the cam angle
        where two distant parts of the offset cross (a neck narrower than twice the offset).
        The global check runs for non-convex contours only: the parallel curve of a convex
        curve whose radii all exceed the offset is simple.
        """
        from camgen.errors import require_finite

        distance = require_finite("offset", distance)
        if distance == 0.0:
            return self
        closure_tol = max(10 * spline_tol, DEFAULT_CLOSURE_TOL)
        # joints between G1 segments stay closed; a corner (G0 joint) opens a gap of |distance| times its turn
        turn = self._joint_turns()
        corner = np.flatnonzero(np.abs(turn) * abs(distance) > closure_tol)
        if corner.size:
            i = int(corner[0])
            p = self.segments[i].end_point
            polar = math.degrees(math.atan2(p[1], p[0])) % 360.0
            kind = "convex: its offset needs an arc about the corner" if turn[i] > 0 else "concave: a round tool cannot reach into it"
            raise CornerError(
                f"offset {distance:g} mm of a contour with a corner: segments {i} and {(i + 1) % self.n_segments} meet at cam angle "
                f"{polar:.3f} deg, the tangent turning by {math.degrees(turn[i]):.3f} deg ({kind}); a disk cam has a corner where "
                "its law's velocity jumps (a knife follower): blend the velocity there (e.g. constant_velocity with blend > 0)")
        new = []
        for i, seg in enumerate(self.segments):
            if isinstance(seg, Arc):
                new.append(seg.offset(distance, index=i))
            else:
                new.append(seg.offset(distance, index=i, tol=spline_tol))
        out = Contour(new, closure_tol=closure_tol)
        if not self.is_convex():
            crossing = out.self_intersection()
            if crossing is not None:
                polar = round(math.degrees(math.atan2(crossing[1], crossing[0])), 3) % 360.0
                raise GeometryError(
                    f"offset {distance:g} mm crosses itself near cam angle {polar:.3f} deg "
                    f"(point ({crossing[0]:.4g}, {crossing[1]:.4g}) mm): a neck of the contour is narrower than twice the offset"
                )
        return out

    def is_convex(self, corner_tol: float = 1e-9) -> bool:
        """True if the contour turns left everywhere: the signed curvature is >= 0 on every
        segment (exact for arcs and cubic or quintic pieces) and no joint is a concave corner
        (the tangent turning right by more than ``corner_tol`` rad where a segment meets the next,
        as at a knife cam's velocity jump)."""
        if not all(seg.sweep > 0 if isinstance(seg, Arc) else seg.min_turning() >= 0 for seg in self.segments):
            return False
        return bool(np.all(self._joint_turns() >= -corner_tol))

    def _joint_turns(self) -> np.ndarray:
        """Signed angles (n,), rad, by which the tangent turns where segment i meets segment i + 1
        (> 0: to the left, a convex corner; ~0 at a G1 joint)."""
        ends = np.array([seg.derivative(np.array([1.0]))[0] for seg in self.segments])  # (n, 2) tangents at the ends
        starts = np.roll(np.array([seg.derivative(np.array([0.0]))[0] for seg in self.segments]), -1, axis=0)  # next starts
        return np.arctan2(ends[:, 0] * starts[:, 1] - ends[:, 1] * starts[:, 0], np.einsum("ij,ij->i", ends, starts))

    def self_intersection(self, chord_tol: float | None = None, block: int = 1 << 22) -> np.ndarray | None:
        """A point (2,) where two non-adjacent chords of the flattened contour cross, else None.

        ``chord_tol`` defaults to 1e-6 of the contour size (at least 1e-6 mm): parts of the
        curve closer than twice that may be reported as crossing.  Of several crossings, the one
        on the lowest-numbered chord (then the lowest-numbered other chord) is returned.  Only
        chords whose x ranges overlap are tested (sweep and prune: sorted by their smallest x),
        ``block`` pairs at a time.
        """
        tol = chord_tol if chord_tol is not None else max(1e-6, 1e-6 * self.size)
        a = self.flatten(tol)
        b = np.roll(a, -1, axis=0)
        n = len(a)
        d = b - a
        lo_x, hi_x = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
        lo_y, hi_y = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
        order = np.argsort(lo_x, kind="stable")
        sorted_lo = lo_x[order]
        # chord order[p] against the chords after it in x order that start within its x range
        stop = np.searchsorted(sorted_lo, hi_x[order], side="right")
        count = np.maximum(stop - np.arange(n) - 1, 0)
        best: tuple[int, int] | None = None
        first = 0
        cumulative = np.cumsum(count)
        while first < n:
            last = int(np.searchsorted(cumulative, (cumulative[first - 1] if first else 0) + block, side="right"))
            last = min(n, max(last, first + 1))
            pos = np.arange(first, last)
            reps = count[first:last]
            p = np.repeat(pos, reps)
            offset = np.arange(int(reps.sum())) - np.repeat(np.cumsum(reps) - reps, reps)
            i, j = order[p], order[p + 1 + offset]
            keep = (lo_y[i] <= hi_y[j]) & (lo_y[j] <= hi_y[i])
            gap = np.abs(i - j)
            keep &= (gap > 1) & (gap < n - 1)
            i, j = np.minimum(i[keep], j[keep]), np.maximum(i[keep], j[keep])
            o1 = cross(d[i], a[j] - a[i])
            o2 = cross(d[i], a[j] + d[j] - a[i])
            o3 = cross(d[j], a[i] - a[j])
            o4 = cross(d[j], a[i] + d[i] - a[j])
            hit = (o1 * o2 < 0) & (o3 * o4 < 0)
            if hit.any():
                k = int(np.lexsort((j[hit], i[hit]))[0])
                pair = (int(i[hit][k]), int(j[hit][k]))
                best = pair if best is None or pair < best else best
            first = last
        if best is None:
            return None
        i, j = best
        o3 = float(cross(d[j], a[i] - a[j]))
        o4 = float(cross(d[j], a[i] + d[i] - a[j]))
        return a[i] + o3 / (o3 - o4) * d[i]

    # -- support function -----------------------------------------------------------------------
    def _support(self, psi: object, chunk: int = 2048) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Support value, contact point and radius of curvature at the contact (0 at a corner)."""
        psi = _as_array(psi)
        shape = psi.shape
        if self._arc_table is not None:  # convex G1 arcs: the arc holding psi in its normal range
            starts, centres, radii = self._arc_table
            k = np.searchsorted(starts, np.mod(psi, TWO_PI), side="right") - 1  # -1 wraps to the last arc
            u = _unit(psi)
            c, r = centres[k], radii[k]
            pts = c + r[..., None] * u
            return c[..., 0] * u[..., 0] + c[..., 1] * u[..., 1] + r, pts, r
        flat = psi.ravel()
        h = np.empty(flat.size)
        pts = np.empty((flat.size, 2))
        rho = np.empty(flat.size)
        corners = self._corners
        for lo in range(0, flat.size, chunk):
            block = flat[lo : lo + chunk]
            best = np.full(block.size, -np.inf)
            best_pt = np.zeros((block.size, 2))
            best_rho = np.zeros(block.size)
            for seg in self.segments:
                vals, cand, cand_rho = seg.support_candidates(block)
                better = vals > best
                best = np.where(better, vals, best)
                best_pt = np.where(better[:, None], cand, best_pt)
                best_rho = np.where(better, cand_rho, best_rho)
            # segment ends win only where clearly better: a corner (G0 joint) of the contour
            cv = corners @ _unit(block).T  # (n, M)
            c_best = np.argmax(cv, axis=0)
            c_val = cv[c_best, np.arange(block.size)]
            better = c_val > best + 1e-12 * (1.0 + np.abs(c_val))
            best = np.where(better, c_val, best)
            best_pt = np.where(better[:, None], corners[c_best], best_pt)
            best_rho = np.where(better, 0.0, best_rho)
            h[lo : lo + chunk] = best
            pts[lo : lo + chunk] = best_pt
            rho[lo : lo + chunk] = best_rho
        return h.reshape(shape), pts.reshape(shape + (2,)), rho.reshape(shape)

    def support_point(self, psi: object) -> tuple[np.ndarray, np.ndarray]:
        """Support function and contact point for outward normal directions ``psi`` (rad).

        Returns
        -------
        h : array (...,)
            ``max over the contour of p . (cos psi, sin psi)``, mm: the distance from the
            rotation axis to a flat face with outward normal ``psi`` touching the cam.
        point : array (..., 2)
            The contact point (for a non-convex contour, a point of the convex hull).
        """
        h, pts, _ = self._support(psi)
        return h, pts

    def support(self, psi: object) -> np.ndarray:
        """Support function ``h(psi)``, mm, for outward normal directions ``psi`` (rad); see :meth:`support_point`."""
        return self._support(psi)[0]

    def support_derivatives(self, psi: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``h``, ``dh/dpsi`` and ``d2h/dpsi2`` of the support function (mm, mm/rad, mm/rad^2).

        ``dh/dpsi = p . u_perp`` (the contact point's coordinate along the face) and
        ``d2h/dpsi2 = rho - h`` with ``rho`` the radius of curvature at the contact (0 at a
        corner).  At a joint where the curvature jumps, ``d2h`` jumps too.
        """
        psi = _as_array(psi)
        h, pts, rho = self._support(psi)
        u_perp = np.stack([-np.sin(psi), np.cos(psi)], axis=-1)
        dh = np.einsum("...i,...i->...", pts, u_perp)
        return h, dh, rho - h

    def polar_radius(self, phi: object, chunk: int = 1 << 22) -> np.ndarray:
        """Distance (mm) from the rotation axis to the contour along polar angles ``phi`` (rad).

        Needs a contour that is star-shaped about the axis (every ray from the origin meets it
        once), as a cam must be for a polar lift table; raises :class:`GeometryError` otherwise.

        O(N log K) time and O(N) memory for N rays and K pieces: the polar angles of the
        segments' ends and of the splines' breaks increase once around the axis (checked once
        per contour; arcs exactly, from the sign of ``P x P'``), so a sorted search finds the
        piece each ray meets; the distance is then the circle's root (arcs) or a safeguarded
        Newton solve of ``u x P(t) = 0`` inside the piece (splines).  A ray through a joint
        meets the piece that starts there.  Contours failing the check take every piece for
        every ray (``chunk`` bounds rays x pieces per block) and raise the error.
        """
        phi = _as_array(phi)
        flat = phi.ravel()
        star = self._star_table()
        if star is not None:
            dist = star.radius(flat)
            if np.all(np.isfinite(dist)) and np.all(dist > 0):
                return dist.reshape(phi.shape)
        pieces = sum(2 if isinstance(seg, Arc) else 1 for seg in self.segments)
        step = max(1, chunk // pieces)
        dist = np.concatenate([self._polar_radius_all_pieces(flat[lo : lo + step]) for lo in range(0, flat.size, step)] or [np.empty(0)])
        return dist.reshape(phi.shape)

    def _star_table(self) -> "_StarTable | None":
        """The polar-angle table of :meth:`polar_radius`, or None if the contour is not
        star-shaped about the axis at the resolution of its breaks (built once)."""
        if "_star" not in self.__dict__:
            self.__dict__["_star"] = _StarTable.build(self)
        return self.__dict__["_star"]

    def _polar_radius_all_pieces(self, flat: np.ndarray) -> np.ndarray:
        """:meth:`polar_radius` by intersecting every ray with every segment (rays x pieces)."""
        hits = np.concatenate([seg.ray_hits(flat) for seg in self.segments], axis=1)
        finite = np.isfinite(hits)
        # a ray through a joint hits both neighbouring segments at the same distance
        dist = np.where(finite, hits, np.inf).min(axis=1)
        far = np.where(finite, hits, -np.inf).max(axis=1)
        missed = np.flatnonzero(~finite.any(axis=1))
        if missed.size:
            # a ray through a joint whose two ends differ by rounding (up to DEFAULT_CLOSURE_TOL) can
            # pass between them: it meets the contour at the joint (a segment's start point)
            u = _unit(flat[missed])
            along = u @ self._corners.T  # (rays, joints)
            across = np.abs(np.outer(u[:, 0], self._corners[:, 1]) - np.outer(u[:, 1], self._corners[:, 0]))
            at_joint = np.where((across <= DEFAULT_CLOSURE_TOL) & (along > 0), along, np.inf).min(axis=1)
            dist[missed] = at_joint
        bad = ~np.isfinite(dist) | (far - dist > 1e-9 * (1.0 + np.abs(dist))) | np.any(np.isposinf(hits), axis=1)
        if np.any(bad):
            where = math.degrees(float(flat[np.argmax(bad)])) % 360.0
            raise GeometryError(f"contour is not star-shaped about the rotation axis: the ray at cam angle {where:.3f} deg does not meet it exactly once")
        return dist

    # -- continuity -----------------------------------------------------------------------------
    def joints(
        self,
        position_tol: float = 1e-9,
        angle_tol: float = 1e-9,
        curvature_tol: float = 1e-9,
    ) -> tuple[Joint, ...]:
        """G0/G1/G2 continuity at every joint (end of segment ``i`` -> start of segment ``i + 1``).

        Tolerances: ``position_tol`` mm, ``angle_tol`` rad, ``curvature_tol`` 1/mm.
        """
        out = []
        n = self.n_segments
        for i, seg in enumerate(self.segments):
            nxt = self.segments[(i + 1) % n]
            end = seg.end_point
            gap = float(np.hypot(*(end - nxt.start_point)))
            t_end = seg.derivative(np.array([1.0]))[0]
            t_start = nxt.derivative(np.array([0.0]))[0]
            cross = t_end[0] * t_start[1] - t_end[1] * t_start[0]
            dot = float(t_end @ t_start)
            angle = abs(math.atan2(cross, dot))
            k_jump = float(nxt.curvature(np.array([0.0]))[0] - seg.curvature(np.array([1.0]))[0])
            if gap > position_tol:
                level = "none"
            elif angle > angle_tol:
                level = "G0"
            elif abs(k_jump) > curvature_tol:
                level = "G1"
            else:
                level = "G2"
            out.append(Joint(i, (float(end[0]), float(end[1])), gap, angle, k_jump, level))
        return tuple(out)

    def continuity(self) -> str:
        """The lowest continuity over all joints (``"G2"``, ``"G1"``, ``"G0"`` or ``"none"``)."""
        order = ["none", "G0", "G1", "G2"]
        return min((j.continuity for j in self.joints()), key=order.index)

