"""Piecewise polynomials of one variable: breaks ``x`` (p + 1,) and coefficients ``c`` (k + 1, p)
or (k + 1, p, d), highest power first, in powers of ``(t - x[i])`` on piece ``i`` (scipy's ``PPoly``
layout): evaluation, derivatives, and the real roots of every piece.

:class:`PiecewisePolynomial` is a function ``y(t)`` (a lift table's displacement, a spline's
coordinates side by side); :class:`camgen.contour.Spline` is the planar *curve* segment of a
contour (always (degree + 1, K, 2), with the geometry a contour needs: tangents, curvature,
offsets, support, ray hits).  Both evaluate with the kernels of :mod:`camgen.numerics.polynomial`.
"""
from __future__ import annotations

import numpy as np

from camgen.errors import ParameterError
from camgen.numerics.polynomial import horner, scaled_ascending
from camgen.numerics.roots import roots_in_pieces

__all__ = ["PiecewisePolynomial"]


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
        return np.minimum(np.maximum(np.searchsorted(self.x, t, side="right") - 1, 0), self.x.size - 2)  # np.clip, fewer calls

    def __call__(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        flat = t.ravel()
        i = self.piece(flat)
        h = flat - self.x[i]
        if self.c.ndim == 3:
            h = h[:, None]
        value = horner(np.moveaxis(self.c[:, i], 0, 1), h)  # the pieces' rows (n, k + 1[, d])
        return value.reshape(t.shape + self.c.shape[2:])

    def roots(self) -> np.ndarray:
        """Sorted points inside the pieces (``x[i] <= t <= x[i+1]``; a scalar polynomial) where the
        polynomial changes sign: its real roots of odd multiplicity, found piece by piece by
        :func:`~camgen.numerics.roots.roots_in_pieces` on the pieces scaled to [0, 1] (a root within
        :data:`~camgen.numerics.roots.ROOT_TOL` of a piece's length outside it, by rounding, counts
        as on its end);
        a root shared by two pieces at a break is listed once.  A root of even multiplicity (the
        polynomial touches zero) is not a sign change and is not listed: the callers want the
        extrema of the antiderivative.

        One root finder for camgen's polynomial pieces (the splines' too); the companion-matrix
        eigenvalues this method used before gave the same roots (to 1 ulp, as close to the true
        roots: one Newton step moves either by < 4.5e-16) on lift tables, in 1.7 against 3.2 ms for
        a 72-row table's construction and four extremes, 380 against 283 ms for 20000 rows
        (measured)."""
        if self.c.ndim != 1 + 1:
            raise ParameterError("roots", f"coefficients of shape {self.c.shape}", "a scalar piecewise polynomial")
        k = self.c.shape[0] - 1
        if k < 1:
            return np.empty(0)
        piece, tau = roots_in_pieces(scaled_ascending(self.c, np.diff(self.x)), np.diff(self.x))
        roots = np.sort(self.x[piece] + tau)
        if roots.size:
            keep = np.concatenate([[True], np.diff(roots) > 1e-12 * max(1.0, float(np.max(np.abs(self.x))))])
            roots = roots[keep]
        return roots
