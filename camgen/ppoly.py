"""Piecewise polynomials and periodic interpolating splines of odd degree, in numpy.

:class:`PiecewisePolynomial` holds breaks ``x`` (p + 1,) and coefficients ``c`` (k + 1, p) or
(k + 1, p, d), highest power first, in powers of ``(t - x[i])`` on piece ``i`` (scipy's ``PPoly``
layout): evaluation, derivatives, and the real roots of every piece.

:func:`periodic_spline` interpolates ``y`` at the breaks by the periodic spline of odd degree
``k = 2 m - 1`` (3: C2, 5: C4).  It is solved in Hermite form: the unknowns are the derivatives
1 .. m-1 at every break; on each piece the polynomial follows from the derivatives 0 .. m-1 at
its two ends (a constant (k+1) x (k+1) Hermite matrix in the piece's local variable
``u = (t - x[i]) / h[i]``), and continuity of the derivatives m .. 2m-2 at every break gives a
cyclic block-tridiagonal system with (m-1) x (m-1) blocks (:mod:`camgen.linsolve`).  The spline
is the unique periodic interpolating spline with knots at the data (de Boor, *A Practical Guide
to Splines*, ch. XII), so it equals scipy's ``make_interp_spline(..., bc_type="periodic")``.
"""
from __future__ import annotations

import math

import numpy as np

from camgen.errors import ParameterError
from camgen.linsolve import solve_block_tridiagonal


class PiecewisePolynomial:
    """A piecewise polynomial: breaks ``x`` (p + 1,), coefficients ``c`` (k + 1, p[, d]) highest
    power first, ``P(t) = sum_r c[r, i] (t - x[i]) ** (k - r)`` on ``x[i] <= t < x[i+1]``.
    Outside ``[x[0], x[-1]]`` the end pieces are extended."""

    def __init__(self, x: np.ndarray, c: np.ndarray) -> None:
        self.x = np.asarray(x, dtype=float)
        self.c = np.asarray(c, dtype=float)
        if self.x.ndim != 1 or self.c.shape[1] != self.x.size - 1:
            raise ParameterError("coefficients", f"shape {self.c.shape}", f"(order, {self.x.size - 1}, ...) for {self.x.size} breaks")

    @property
    def degree(self) -> int:
        return self.c.shape[0] - 1

    def derivative(self, n: int = 1) -> "PiecewisePolynomial":
        """The ``n``-th derivative (a constant 0 piece beyond the degree)."""
        c = self.c
        for _ in range(n):
            k = c.shape[0] - 1
            if k == 0:
                return PiecewisePolynomial(self.x, np.zeros_like(c))
            powers = np.arange(k, 0, -1, dtype=float).reshape((k,) + (1,) * (c.ndim - 1))
            c = c[:-1] * powers
        return PiecewisePolynomial(self.x, c)

    def piece(self, t: np.ndarray) -> np.ndarray:
        """Index of the piece holding each ``t`` (the right-hand piece at a break)."""
        return np.clip(np.searchsorted(self.x, t, side="right") - 1, 0, self.x.size - 2)

    def __call__(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        flat = t.ravel()
        i = self.piece(flat)
        h = flat - self.x[i]
        if self.c.ndim == 3:
            h = h[:, None]
        value = self.c[0, i].copy()
        for row in self.c[1:]:
            value = value * h + row[i]
        return value.reshape(t.shape + self.c.shape[2:])

    def roots(self) -> np.ndarray:
        """Sorted real roots inside the pieces (``x[i] <= t <= x[i+1]``; a scalar polynomial):
        eigenvalues of the companion matrices of all pieces at once; a root shared by two
        pieces at a break is listed once."""
        if self.c.ndim != 1 + 1:
            raise ParameterError("roots", f"coefficients of shape {self.c.shape}", "a scalar piecewise polynomial")
        c = self.c
        # drop leading zero coefficients piece by piece: scale by the leading coefficient where nonzero
        k = c.shape[0] - 1
        if k < 1:
            return np.empty(0)
        h = np.diff(self.x)
        found = []
        lead = c[0]
        full = np.abs(lead) > 1e-14 * np.max(np.abs(c), axis=0)
        if k >= 1 and np.any(full):
            idx = np.flatnonzero(full)
            comp = np.zeros((idx.size, k, k))
            comp[:, 0, :] = -c[1:, idx].T / lead[idx, None]
            if k > 1:
                comp[:, np.arange(1, k), np.arange(k - 1)] = 1.0
            eig = np.linalg.eigvals(comp)
            real = np.abs(eig.imag) <= 1e-9 * np.maximum(1.0, np.abs(eig.real))
            r = eig.real
            inside = real & (r >= -1e-12 * h[idx, None]) & (r <= h[idx, None] * (1 + 1e-12))
            rows, cols = np.nonzero(inside)
            found.append(self.x[idx[rows]] + np.clip(r[rows, cols], 0.0, h[idx[rows]]))
        for i in np.flatnonzero(~full):  # lower-degree pieces (rare): drop the zero lead
            lower = PiecewisePolynomial(self.x[i:i + 2], c[1:, i:i + 1])
            found.append(lower.roots())
        if not found:
            return np.empty(0)
        roots = np.sort(np.concatenate(found))
        if roots.size:
            keep = np.concatenate([[True], np.diff(roots) > 1e-12 * max(1.0, float(np.max(np.abs(self.x))))])
            roots = roots[keep]
        return roots


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
    y : array (n + 1,)
        Values, ``y[-1] == y[0]`` (the last value closes the period).
    degree : int
        3 (C2) or 5 (C4).

    Returns
    -------
    PiecewisePolynomial
        ``n`` pieces of the given degree.
    """
    if degree not in (3, 5):
        raise ParameterError("degree", degree, "3 or 5")
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
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
    yv = y[:-1]
    rhs = -(lower_full[:, :, 0] * np.roll(yv, 1)[:, None] + diag_full[:, :, 0] * yv[:, None] + upper_full[:, :, 0] * np.roll(yv, -1)[:, None])
    w = solve_block_tridiagonal(lower_full[:, :, 1:], diag_full[:, :, 1:], upper_full[:, :, 1:], rhs, cyclic=True)
    z = np.concatenate([yv[:, None], w / hbar[:, None] ** j[None, 1:]], axis=1)  # (n, m): derivatives 0 .. m-1
    z_next = np.roll(z, -1, axis=0)
    data = np.concatenate([z * h[:, None] ** j, z_next * h[:, None] ** j], axis=1)  # scaled Hermite data
    cu = data @ hinv.T  # (n, k + 1): coefficients of u^r
    c = cu / h[:, None] ** np.arange(degree + 1)[None, :]  # powers of (t - x[i])
    return PiecewisePolynomial(x, c[:, ::-1].T)
