"""Least-squares cubic B-spline fits within a tolerance, with as few knots as the tolerance needs.

Two fits, both returning piecewise cubics (breaks and coefficients in the layout of
:class:`camgen.contour.Spline`) that are **C2 at every break**, so that a B-spline with simple
interior knots holds them exactly (``pieces + 3`` control points):

* :func:`fit_periodic`: a closed curve ``P(t)``, ``t0 <= t < t0 + period``, by a periodic cubic
  spline;
* :func:`fit_clamped`: an open curve on ``[a, b]`` by a clamped cubic spline that keeps the
  curve's point, first and second derivative at both ends exactly (so neighbouring segments
  keep their G1 / G2 joints).

Method: the weighted least-squares (L2) projection onto the spline space of the current knots,
with Gauss-Legendre nodes and weights on every knot interval as the samples (de Boor, *A
Practical Guide to Splines*, ch. XIV).  Unlike interpolation at the knots, whose error is
one-signed where the curve's fourth derivative keeps its sign (a cubic spline through points of
a circle lies inside it), the L2 error is orthogonal to the spline space, constants included:
it changes sign inside every few pieces and its local mean is of higher order.  The distance to
the curve is measured at the probe fractions :data:`PROBES` of every piece; where it exceeds the
tolerance, the knots are redistributed by equidistribution of ``h (err / tol)^(1/4)`` (the
error of a cubic falls as ``h^4``), then bisected where it still does.

The periodic fit is numpy only (the tricycle's synthesis imports no scipy); the clamped fit (an
export step) uses scipy's B-spline design matrix and sparse solver, imported inside it.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camgen.errors import GeometryError, ParameterError, require_positive
from camgen.numerics.polynomial import horner

__all__ = ["Fit", "MAX_PIECES", "PROBES", "RELATIVE_FLOOR", "fit_clamped", "fit_periodic"]

Curve = Callable[[np.ndarray], np.ndarray]

#: Fractions of every piece at which the fit's distance to the curve is measured (its start and
#: the eighths; the tests measure between them too).
PROBES = np.arange(8) / 8.0
#: Gauss-Legendre nodes per knot interval of the least-squares samples.
GAUSS_NODES = 6
#: The redistribution aims at this fraction of the tolerance (margin for the nonlocal error).
TARGET = 0.5
#: Fewest and most pieces of a fit (a periodic fit needs 7: its band of half-width 3 must not wrap).
MIN_PIECES = 4
MIN_PERIODIC_PIECES = 8
MAX_PIECES = 200_000
#: A fit within tolerance is redistributed onto fewer pieces when they would be below this
#: fraction of its pieces.
COARSEN = 0.7
#: Rounds of redistribution (then bisection) before the fit gives up.
MAX_ROUNDS = 24
#: Smallest tolerance relative to the curve's size: below it rounding decides.
RELATIVE_FLOOR = 1e-13


@dataclass(frozen=True)
class Fit:
    """A fitted piecewise cubic: ``breaks`` (K + 1,), ``coeffs`` (4, K, d) highest power first,
    the B-spline ``knots`` and ``controls`` that hold it exactly, and the largest measured
    distance ``error`` (mm) from the curve at the probe points."""

    breaks: np.ndarray
    coeffs: np.ndarray
    knots: np.ndarray
    controls: np.ndarray
    error: float


def _gauss(nodes: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(nodes)
    return 0.5 * (x + 1.0), 0.5 * w


def _samples(breaks: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    h = np.diff(breaks)
    return (breaks[:-1, None] + fractions[None, :] * h[:, None]).ravel()


def _pieces_from_bspline(knots: np.ndarray, controls: np.ndarray, breaks: np.ndarray) -> np.ndarray:
    """PPoly coefficients (4, K, d) of the B-spline on the pieces starting at ``breaks[:-1]``."""
    from scipy.interpolate import BSpline

    bs = BSpline(knots, controls, 3, extrapolate=False)
    left = breaks[:-1]
    return np.stack([bs(left, 3) / 6.0, bs(left, 2) / 2.0, bs(left, 1), bs(left)])


def _cubic_basis(knots: np.ndarray, piece: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The four cubic B-splines nonzero on piece ``i`` at ``t`` (M,): (M, 4), ``N_{i-3} .. N_i``
    (Cox-de Boor recursion, Piegl and Tiller, *The NURBS Book*, A2.2), ``knots[m + 3] = u_m``."""
    i = piece + 3  # position of u_i in knots
    left = [None] + [t - knots[i + 1 - j] for j in (1, 2, 3)]
    right = [None] + [knots[i + j] - t for j in (1, 2, 3)]
    n = [np.ones_like(t)]
    for j in (1, 2, 3):
        saved = np.zeros_like(t)
        new = []
        for r in range(j):
            temp = n[r] / (right[r + 1] + left[j - r])
            new.append(saved + right[r + 1] * temp)
            saved = left[j - r] * temp
        new.append(saved)
        n = new
    return np.stack(n, axis=1)


def _pieces_from_controls(knots: np.ndarray, controls: np.ndarray, breaks: np.ndarray) -> np.ndarray:
    """PPoly coefficients (4, K, d) of the B-spline (``controls[m + 3]`` of basis ``N_m``,
    ``knots[m + 3] = u_m``, m = -3 ..): value and derivatives at the start of every piece from the
    control points' differences (the derivative of a B-spline is a B-spline of one degree less,
    Piegl and Tiller, eq. 3.3), so that neighbouring pieces agree to rounding (C2)."""
    k = breaks.size - 1
    i = np.arange(k)
    u = [knots[i + 3 + j] for j in range(-2, 4)]  # u[j + 2] = u_{i + j}, j = -2 .. 3
    p = [controls[i + a] for a in range(4)]  # P_{i-3} .. P_i

    def d(a: int, b: int) -> np.ndarray:  # u_{i+a} - u_{i+b}
        return (u[a + 2] - u[b + 2])[:, None]

    q1_3 = 3.0 * (p[1] - p[0]) / d(1, -2)  # Q1_{i-3}
    q1_2 = 3.0 * (p[2] - p[1]) / d(2, -1)  # Q1_{i-2}
    q1_1 = 3.0 * (p[3] - p[2]) / d(3, 0)  # Q1_{i-1}
    q2_3 = 2.0 * (q1_2 - q1_3) / d(1, -1)  # Q2_{i-3}
    q2_2 = 2.0 * (q1_1 - q1_2) / d(2, 0)  # Q2_{i-2}
    third = (q2_2 - q2_3) / d(1, 0)
    first = (q1_3 * d(1, 0) + q1_2 * d(0, -1)) / d(1, -1)
    basis = _cubic_basis(knots, i, breaks[:-1])
    value = np.einsum("ka,akd->kd", basis, np.stack(p))
    return np.stack([third / 6.0, 0.5 * q2_3, first, value])


#: Relative residual at which the conjugate-gradient solve of the normal equations stops, and its
#: largest number of iterations (the Gram matrix of B-splines on quasi-uniform knots is well
#: conditioned: tens of iterations).
CG_TOL = 1e-15
CG_MAX_ITER = 2000


def _solve_periodic_normal(index: np.ndarray, basis: np.ndarray, w: np.ndarray, values: np.ndarray, k: int) -> np.ndarray:
    """Least-squares controls (K, d): the normal equations ``sum w N_a N_b c_b = sum w N_a y`` of
    the periodic basis, a cyclic band of half-width 3, solved by Jacobi-preconditioned conjugate
    gradients (numpy only: the tricycle's synthesis imports no scipy), all columns at once."""
    band = np.zeros((4, k))  # band[d, j] = A[j, j + d mod K]
    for a in range(4):
        for b in range(a, 4):
            np.add.at(band[b - a], index[:, a], w * basis[:, a] * basis[:, b])
    rhs = np.zeros((k, values.shape[1]))
    for a in range(4):
        np.add.at(rhs, index[:, a], (w * basis[:, a])[:, None] * values)

    upper = band[1:, :, None]

    def matvec(x: np.ndarray) -> np.ndarray:
        # A x: the diagonal, x[j + d] above it and (band_d x)[j - d] below it, indices mod K
        xp = np.concatenate([x[-3:], x, x[:3]])
        bx = upper * x[None]
        bxp = np.concatenate([bx[:, -3:], bx, bx[:, :3]], axis=1)
        out = band[0][:, None] * x
        for d in (1, 2, 3):
            out += upper[d - 1] * xp[3 + d : 3 + d + k] + bxp[d - 1, 3 - d : 3 - d + k]
        return out

    diag = band[0][:, None]
    x = rhs / diag
    r = rhs - matvec(x)
    z = r / diag
    p = z.copy()
    rz = np.sum(r * z, axis=0)
    stop = CG_TOL * np.sqrt(np.sum(rhs * rhs, axis=0))
    for _ in range(CG_MAX_ITER):
        if np.all(np.sqrt(np.sum(r * r, axis=0)) <= stop):
            break
        ap = matvec(p)
        alpha = rz / np.where(np.sum(p * ap, axis=0) != 0, np.sum(p * ap, axis=0), 1.0)
        x = x + alpha * p
        r = r - alpha * ap
        z = r / diag
        rz_new = np.sum(r * z, axis=0)
        p = z + (rz_new / np.where(rz != 0, rz, 1.0)) * p
        rz = rz_new
    return x


def _eval(breaks: np.ndarray, coeffs: np.ndarray, t: np.ndarray) -> np.ndarray:
    i = np.clip(np.searchsorted(breaks, t, side="right") - 1, 0, breaks.size - 2)
    tau = (t - breaks[i])[:, None]
    return horner(np.moveaxis(coeffs[:, i], 0, 1), tau)


def _redistribute(breaks: np.ndarray, err: np.ndarray, tol: float, max_pieces: int) -> np.ndarray:
    """New breaks equidistributing ``h (err / (TARGET tol))^(1/4)`` (pieces needed per piece), the
    density changing by at most a factor 2 between neighbours (a quasi-uniform knot sequence)."""
    h = np.diff(breaks)
    need = np.maximum((np.maximum(err, 1e-300) / (TARGET * tol)) ** 0.25, 1e-3)
    density = need / h
    for _ in range(64):  # limit the ratio of neighbouring densities to 2 (a few sweeps suffice)
        smoothed = np.maximum(density, 0.5 * np.maximum(np.roll(density, 1), np.roll(density, -1)))
        if np.array_equal(smoothed, density):
            break
        density = smoothed
    cumulative = np.concatenate([[0.0], np.cumsum(density * h)])
    count = int(min(max_pieces, max(MIN_PIECES, math.ceil(cumulative[-1]))))
    return np.interp(np.linspace(0.0, cumulative[-1], count + 1), cumulative, breaks)


def _bisect(breaks: np.ndarray, bad: np.ndarray) -> np.ndarray:
    mids = 0.5 * (breaks[:-1] + breaks[1:])[bad]
    return np.sort(np.concatenate([breaks, mids]))


def _refine(fit_on: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]], curve: Curve,
            breaks: np.ndarray, tol: float, max_pieces: int, what: str, coarsen: bool = True) -> Fit:
    """Fit on ``breaks``, measure, redistribute / bisect until within ``tol``; a first fit within
    ``tol`` on far more pieces than its errors call for is redistributed once onto fewer (kept if
    that is within ``tol`` too).  The columns of
    the curve are taken in pairs (several planar curves on shared knots): the distance of a
    piece is the largest over the pairs."""
    best: Fit | None = None
    for round_ in range(MAX_ROUNDS):
        knots, controls, coeffs = fit_on(breaks)
        probe = _samples(breaks, PROBES)
        diff = _eval(breaks, coeffs, probe) - curve(probe)
        diff = diff.reshape(diff.shape[0], -1, 2)
        dist = np.sqrt(np.sum(diff * diff, axis=2)).max(axis=1).reshape(-1, PROBES.size).max(axis=1)
        err = float(dist.max())
        if not np.isfinite(err):
            raise GeometryError(f"{what}: the curve is not finite where it is sampled")
        if err <= tol:
            done = Fit(breaks, coeffs, knots, controls, err)
            fewer = _redistribute(breaks, dist, tol, max_pieces)
            if coarsen and fewer.size < COARSEN * breaks.size:  # far more pieces than the tolerance needs
                try:
                    return _refine(fit_on, curve, fewer, tol, max_pieces, what, coarsen=False)
                except GeometryError:
                    pass
            return done
        if best is None or err < best.error:
            best = Fit(breaks, coeffs, knots, controls, err)
        if breaks.size - 1 >= max_pieces:
            break
        if round_ < MAX_ROUNDS // 2:
            new = _redistribute(breaks, dist, tol, max_pieces)
            if new.size <= breaks.size:  # no progress by redistribution: add pieces where needed
                new = _bisect(breaks, dist > TARGET * tol)
        else:
            new = _bisect(breaks, dist > TARGET * tol)
        breaks = new[: max_pieces + 1] if new.size > max_pieces + 1 else new
    assert best is not None
    raise GeometryError(f"{what}: the cubic spline fit does not reach tol = {tol:g} mm (error {best.error:.3g} mm with "
                        f"{best.breaks.size - 1} pieces): the curve is too close to a cusp; increase the tolerance or "
                        "move the curve away from the cusp (larger radii)")


def _check_tol(tol: float, scale: float, what: str) -> float:
    tol = require_positive("tol", tol, "mm")
    if tol < RELATIVE_FLOOR * max(1.0, scale):
        raise ParameterError("tol", tol, f"tol >= {RELATIVE_FLOOR * max(1.0, scale):.3g} mm for a curve of size {scale:.4g} mm",
                             f"{what}: below that, rounding decides the fit")
    return tol


def fit_periodic(curve: Curve, t0: float, period: float, tol: float, initial_pieces: int = 16,
                 max_pieces: int = MAX_PIECES, what: str = "periodic curve") -> Fit:
    """Periodic C2 cubic spline within ``tol`` mm of the closed curve ``curve``.

    Parameters
    ----------
    curve : callable
        ``curve(t)`` -> points (n, 2 m), mm (``m`` planar curves side by side, fitted on
        shared knots), for parameters ``t`` (n,) in ``[t0, t0 + period)``; periodic:
        ``curve(t0) == curve(t0 + period)`` with matching derivatives.
    t0, period : float
        Start and length of the parameter interval.
    tol : float
        Largest distance (mm) of the fit from each curve at the probe points of every piece.
    initial_pieces : int
        Uniform pieces of the first fit.
    max_pieces : int
        The fit raises :class:`GeometryError` rather than use more pieces.

    Returns
    -------
    Fit
        Breaks ``t0 .. t0 + period``, coefficients (4, K, d), and the periodic B-spline form:
        ``knots`` (K + 7,) (the breaks extended by three on either side, shifted by the period)
        and ``controls`` (K + 3, d) (the last three repeat the first three).
    """
    require_positive("period", period)
    scale = float(np.max(np.abs(curve(np.array([t0, t0 + period / 3, t0 + 2 * period / 3])))))
    tol = _check_tol(tol, scale, what)
    gx, gw = _gauss(GAUSS_NODES)

    def fit_on(breaks: np.ndarray):
        k = breaks.size - 1
        if k < MIN_PERIODIC_PIECES:
            raise ParameterError("pieces", k, f">= {MIN_PERIODIC_PIECES}")
        knots = np.concatenate([breaks[k - 3 : k] - period, breaks, breaks[1:4] + period])  # u_-3 .. u_K+3
        piece = np.repeat(np.arange(k), gx.size)
        t = _samples(breaks, gx)
        w = (np.diff(breaks)[:, None] * gw[None, :]).ravel()
        basis = _cubic_basis(knots, piece, t)  # (M, 4): N_{i-3} .. N_i on piece i
        index = (piece[:, None] + np.arange(-3, 1)[None, :]) % k
        controls = _solve_periodic_normal(index, basis, w, curve(t), k)
        # basis function m (support u_m .. u_m+4) is control m mod K; the B-spline form starts at u_-3
        ordered = np.concatenate([controls[-3:], controls])
        return knots, ordered, _pieces_from_controls(knots, ordered, breaks)

    first = max(MIN_PERIODIC_PIECES, initial_pieces)
    breaks = t0 + period * np.arange(first + 1) / first
    return _refine(fit_on, curve, breaks, tol, max_pieces, what)


def fit_clamped(curve: Curve, a: float, b: float, tol: float, ends: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                np.ndarray, np.ndarray], initial_pieces: int = 4, max_pieces: int = MAX_PIECES, what: str = "curve") -> Fit:
    """Clamped C2 cubic spline within ``tol`` mm of ``curve`` on ``[a, b]``, keeping the end
    conditions ``ends = (P(a), P'(a), P''(a), P(b), P'(b), P''(b))`` (each (d,)) exactly.

    The three first and three last control points follow from the end conditions (de Boor,
    ch. IX: derivatives of a B-spline from its control points); the others are the
    least-squares fit.  Returns the breaks, coefficients (4, K, d), the knots (K + 7,: ends of
    multiplicity 4) and the control points (K + 3, d).
    """
    if not b > a:
        raise ParameterError("interval", (a, b), "a < b")
    p0, d0, s0, p1, d1, s1 = (np.asarray(e, dtype=float) for e in ends)
    scale = float(max(np.max(np.abs(p0)), np.max(np.abs(p1))))
    tol = _check_tol(tol, scale, what)
    gx, gw = _gauss(GAUSS_NODES)

    def fit_on(breaks: np.ndarray):
        from scipy.interpolate import BSpline
        from scipy.sparse import diags_array
        from scipy.sparse.linalg import spsolve

        k = breaks.size - 1
        knots = np.concatenate([[a] * 3, breaks, [b] * 3])
        n = k + 3
        # end controls from P, P', P'' (clamped cubic: knots a,a,a,a,x1,x2 ...)
        u1, u2 = breaks[1] - a, breaks[2] - a
        c0 = p0
        c1 = p0 + d0 * u1 / 3.0
        c2 = c1 + u2 * (s0 * u1 / 6.0 + (c1 - c0) / u1)
        v1, v2 = b - breaks[-2], b - breaks[-3]
        e0 = p1
        e1 = p1 - d1 * v1 / 3.0
        e2 = e1 + v2 * (s1 * v1 / 6.0 - (e0 - e1) / v1)
        fixed_idx = np.array([0, 1, 2, n - 3, n - 2, n - 1])
        fixed = np.stack([c0, c1, c2, e2, e1, e0])
        t = _samples(breaks, gx)
        w = (np.diff(breaks)[:, None] * gw[None, :]).ravel()
        design = BSpline.design_matrix(t, knots, 3).tocsc()
        free = np.setdiff1d(np.arange(n), fixed_idx)
        controls = np.empty((n, p0.size))
        controls[fixed_idx] = fixed
        if free.size:
            dfree = design[:, free]
            resid = curve(t) - design[:, fixed_idx] @ fixed
            normal = (dfree.T @ diags_array(w) @ dfree).tocsc()
            sol = spsolve(normal, dfree.T @ (w[:, None] * resid))
            controls[free] = sol.reshape(free.size, -1)
        return knots, controls, _pieces_from_bspline(knots, controls, breaks)

    breaks = np.linspace(a, b, max(3, initial_pieces) + 1)
    return _refine(fit_on, curve, breaks, tol, max_pieces, what)
