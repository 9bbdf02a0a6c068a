"""Interpolating splines with knots at the data, in numpy (no scipy import).

* :func:`periodic_spline`: the periodic interpolating spline of odd degree ``k`` (3: C2, 5: C4)
  through values or points: the unique periodic interpolating spline with knots at the data
  (de Boor, *A Practical Guide to Splines*, ch. XII), so it equals scipy's
  ``make_interp_spline(..., bc_type="periodic")`` (and, for k = 3, ``CubicSpline(...,
  bc_type="periodic")``).

  - k = 3 from its knot moments (second derivatives): a cyclic tridiagonal system (de Boor,
    ch. IV);
  - k = 5 in Hermite form: the unknowns are the derivatives 1 .. m-1 at every break (k = 2 m - 1);
    on each piece the polynomial follows from the derivatives 0 .. m-1 at its two ends (a
    constant (k+1) x (k+1) Hermite matrix in the piece's local variable ``u = (t - x[i]) / h[i]``),
    and continuity of the derivatives m .. 2m-2 at every break gives a cyclic block-tridiagonal
    system with (m-1) x (m-1) blocks.

  The Hermite form covers k = 3 too (1 x 1 blocks: the slopes), but the moments are the better
  cubic: measured on periodic cubics through random points (20 seeds each, 2 columns, against a
  long-double reference), their coefficients are within 5e-16 of the reference where the Hermite
  form's are within 4e-14 (knot spacing varying 300-fold; 8e-16 on even knots), in half the time
  (0.32 against 0.60 ms at 720 knots, 1.35 against 2.8 ms at 5001).
* :func:`clamped_cubic`: the C2 cubic through points with given first derivatives at both ends,
  from its knot moments: a tridiagonal system (de Boor, ch. IV).

Both systems are solved by :mod:`camgen.numerics.tridiagonal`.
"""
from __future__ import annotations

import math

import numpy as np

from camgen.errors import ParameterError
from camgen.numerics.ppoly import PiecewisePolynomial
from camgen.numerics.tridiagonal import solve_block_tridiagonal, solve_tridiagonal

__all__ = ["clamped_cubic", "periodic_spline"]


def _hermite_inverse(m: int) -> np.ndarray:
    """Inverse of the Hermite matrix of degree 2m-1 on u in [0, 1]: rows = derivatives 0..m-1 at 0,
    then at 1; columns = the coefficients of u^0 .. u^(2m-1)."""
    k = 2 * m - 1
    a = np.zeros((2 * m, k + 1))
    for j in range(m):
        a[j, j] = math.factorial(j)
        for r in range(j, k + 1):
            a[m + j, r] = math.factorial(r) / math.factorial(r - j)
    return np.linalg.inv(a)


def _derivative_rows(m: int, at_one: bool) -> np.ndarray:
    """Rows (m-1, 2m) giving the derivatives m .. 2m-2 (in u) at u = 0 or 1 from the Hermite data."""
    k = 2 * m - 1
    e = np.zeros((m - 1, k + 1))
    for row, q in enumerate(range(m, 2 * m - 1)):
        for r in range(q, k + 1):
            e[row, r] = (math.factorial(r) / math.factorial(r - q)) if at_one else (math.factorial(q) if r == q else 0.0)
    return e @ _hermite_inverse(m)


def periodic_spline(x: np.ndarray, y: np.ndarray, degree: int) -> PiecewisePolynomial:
    """The periodic interpolating spline of odd ``degree`` (3 or 5) through ``y`` at ``x``.

    Parameters
    ----------
    x : array (n + 1,)
        Strictly increasing breaks; the period is ``x[-1] - x[0]``.
    y : array (n + 1,) or (n + 1, d)
        Values, or points (one spline per column, one solve for all), ``y[-1] == y[0]`` (the last
        row closes the period).
    degree : int
        3 (C2) or 5 (C4).

    Returns
    -------
    PiecewisePolynomial
        ``n`` pieces of the given degree; coefficients (degree + 1, n) or (degree + 1, n, d).
    """
    if degree not in (3, 5):
        raise ParameterError("degree", degree, "3 or 5")
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    columns = y.reshape(y.shape[0], -1)  # (n + 1, d): a 1-D y is one column
    if degree == 3:
        c = _cubic_coefficients(x, columns, _periodic_moments(x, columns))
        return PiecewisePolynomial(x, c.reshape(c.shape[:2] + y.shape[1:]))
    return _hermite_form(x, y, columns, degree)


def _hermite_form(x: np.ndarray, y: np.ndarray, columns: np.ndarray, degree: int) -> PiecewisePolynomial:
    """:func:`periodic_spline` in Hermite form (module notes) of ``y`` (n + 1, ...) as ``columns`` (n + 1, d)."""
    m = (degree + 1) // 2
    n = x.size - 1
    h = np.diff(x)
    hinv = _hermite_inverse(m)
    g1 = _derivative_rows(m, at_one=True)  # right end of a piece
    g0 = _derivative_rows(m, at_one=False)  # left end of a piece
    hp = np.roll(h, 1)  # the piece before break i (cyclic)
    q = np.arange(m, 2 * m - 1)  # derivative orders of the conditions
    j = np.arange(m)  # Hermite data orders
    # condition q at break i: sum_j G1[q, j] hp^(j-q) z_{i-1}^(j) + G1[q, m+j] hp^(j-q) z_i^(j)
    #                       - G0[q, j] h^(j-q) z_i^(j) - G0[q, m+j] h^(j-q) z_{i+1}^(j) = 0;
    # rows scaled by hbar^q, unknowns w^(j) = z^(j) hbar^j with hbar the mean of hp and h at each break
    hbar = 0.5 * (hp + h)
    hbar_prev, hbar_next = np.roll(hbar, 1), np.roll(hbar, -1)
    row_scale = hbar[:, None, None] ** q[None, :, None]

    def block(g: np.ndarray, cols: slice, span: np.ndarray, unknown_scale: np.ndarray) -> np.ndarray:
        # (n, m-1, m): coefficient of z^(j) -> of w^(j) = z^(j) s^j
        coeff = g[None, :, cols] * span[:, None, None] ** (j[None, None, :] - q[None, :, None])
        return row_scale * coeff / unknown_scale[:, None, None] ** j[None, None, :]

    lower_full = block(g1, slice(0, m), hp, hbar_prev)
    diag_full = block(g1, slice(m, 2 * m), hp, hbar) - block(g0, slice(0, m), h, hbar)
    upper_full = -block(g0, slice(m, 2 * m), h, hbar_next)
    yv = columns[:-1]  # (n, d)
    rhs = -(lower_full[:, :, 0, None] * np.roll(yv, 1, axis=0)[:, None] + diag_full[:, :, 0, None] * yv[:, None]
            + upper_full[:, :, 0, None] * np.roll(yv, -1, axis=0)[:, None])  # (n, m-1, d)
    w = solve_block_tridiagonal(lower_full[:, :, 1:], diag_full[:, :, 1:], upper_full[:, :, 1:], rhs, cyclic=True)
    z = np.concatenate([yv[:, None], w / (hbar[:, None] ** j[None, 1:])[:, :, None]], axis=1)  # (n, m, d): derivatives 0 .. m-1
    z_next = np.roll(z, -1, axis=0)
    scale = (h[:, None] ** j)[:, :, None]
    data = np.concatenate([z * scale, z_next * scale], axis=1)  # (n, 2m, d): scaled Hermite data
    d = yv.shape[1]
    cu = data.transpose(0, 2, 1).reshape(n * d, 2 * m) @ hinv.T  # (n d, k + 1): coefficients of u^r
    c = cu.reshape(n, d, degree + 1) / (h[:, None] ** np.arange(degree + 1)[None, :])[:, None, :]  # powers of (t - x[i])
    c = np.ascontiguousarray(c[:, :, ::-1].transpose(2, 0, 1))  # (k + 1, n, d), highest power first
    return PiecewisePolynomial(x, c.reshape(c.shape[:2] + y.shape[1:]))


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


def _cubic_coefficients(t: np.ndarray, y: np.ndarray, moments: np.ndarray) -> np.ndarray:
    """Coefficients (4, n-1, k), highest power first, from the knot moments."""
    h = np.diff(t)[:, None]
    m0, m1 = moments[:-1], moments[1:]
    slope = np.diff(y, axis=0) / h
    return np.stack([(m1 - m0) / (6.0 * h), 0.5 * m0, slope - h * (2.0 * m0 + m1) / 6.0, y[:-1]])


def clamped_cubic(t: np.ndarray, y: np.ndarray, d0: np.ndarray, d1: np.ndarray) -> np.ndarray:
    """Coefficients (4, n - 1, k), highest power first (in ``t - t[i]``), of the C2 cubic spline
    through ``y`` (n, k) at ``t`` (n,) whose first derivatives at the ends are ``d0`` and ``d1``
    ((k,) each): the knot moments (second derivatives) solve a tridiagonal system (de Boor, ch. IV)."""
    h, slope, inner = _moment_system(t, y)
    lower = np.concatenate([[0.0], h])
    upper = np.concatenate([h, [0.0]])
    diag = 2.0 * np.concatenate([h[:1], h[:-1] + h[1:], h[-1:]])
    rhs = np.vstack([6.0 * (slope[:1] - d0), inner, 6.0 * (d1 - slope[-1:])])
    return _cubic_coefficients(t, y, solve_tridiagonal(lower, diag, upper, rhs, cyclic=False))
