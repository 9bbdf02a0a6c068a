"""Kernels on polynomial pieces in the power basis, vectorised over the pieces.

Two layouts, both scipy ``PPoly``'s order of powers where it applies:

* **descending**, in the offset ``tau = t - breaks[i]`` from the start of piece ``i``: ``c[m]``
  multiplies ``tau ** (degree - m)`` (:class:`~camgen.numerics.ppoly.PiecewisePolynomial`,
  :class:`~camgen.contour.Spline`);
* **ascending and scaled**, in ``s = tau / h`` on ``[0, 1]`` (``h`` the piece's length):
  ``q[i] = p_i h^i`` multiplies ``s ** i`` (root finding, Bezier bounds, exact integrals).

Horner's rule evaluates both (no powers formed).
"""
from __future__ import annotations

import functools

import numpy as np

__all__ = ["EXPONENTS", "MAX_DEGREE", "derivative_factors", "exponents", "horner", "horner_ascending", "power_coefficients",
           "scaled_ascending"]

#: Highest degree with cached exponents (:func:`power_coefficients`); higher degrees work too.
MAX_DEGREE = 5
#: The exponents 0, 1, .., MAX_DEGREE as a column.
EXPONENTS = np.arange(MAX_DEGREE + 1.0)[:, None]
EXPONENTS.flags.writeable = False


def exponents(degree: int) -> np.ndarray:
    """The exponents 0 .. ``degree`` as a float column (degree + 1, 1)."""
    return EXPONENTS[: degree + 1] if degree <= MAX_DEGREE else np.arange(degree + 1.0)[:, None]


@functools.lru_cache(maxsize=None)
def derivative_factors(degree: int, order: int) -> np.ndarray:
    """Factors (degree + 1 - order,) turning the coefficients (highest power first) of a degree
    ``degree`` polynomial into those of its ``order``-th derivative: ``p!/(p - order)!`` for the
    powers ``p = degree .. order`` (computed once per degree and order; read-only)."""
    powers = np.arange(degree, order - 1, -1, dtype=float)
    out = np.ones_like(powers)
    for j in range(order):
        out *= powers - j
    out.flags.writeable = False
    return out


def horner(c: np.ndarray, tau: np.ndarray, order: int = 0) -> np.ndarray:
    """``d^order/dtau^order`` of the polynomials with coefficients ``c`` (n, degree + 1, ...),
    highest power first, at ``tau`` (broadcastable to ``c[:, 0]``, e.g. (n, 1) for (n, degree + 1,
    d)): Horner's rule on the derivative's coefficients; (n, ...)."""
    degree = c.shape[1] - 1
    if order > degree:
        return np.zeros(c.shape[:1] + c.shape[2:])
    if order == 0:  # every factor 1: the products by them are exact, left out
        acc = c[:, 0] * 1.0
        for m in range(1, degree + 1):
            acc = acc * tau + c[:, m]
        return acc
    f = derivative_factors(degree, order).tolist()
    acc = c[:, 0] * f[0]
    for m in range(1, degree + 1 - order):
        acc = acc * tau + c[:, m] * f[m]
    return acc


def horner_ascending(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Values (n, k) of the polynomials with ascending coefficients ``a`` (n, degree + 1) at ``x`` (n, k) (Horner)."""
    acc = np.empty(x.shape, dtype=a.dtype)
    acc[...] = a[:, -1:]
    for i in range(a.shape[1] - 2, -1, -1):
        acc *= x
        acc += a[:, i : i + 1]
    return acc


def scaled_ascending(coeffs: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Coefficients (K, degree + 1, ...), lowest power first, of the pieces ``Q(s) = P(h s)`` on
    ``s`` in [0, 1], from ``coeffs`` (degree + 1, K, ...) highest power first in ``tau`` and the
    piece lengths ``h`` (K,)."""
    degree = coeffs.shape[0] - 1
    column = (1,) * (coeffs.ndim - 2)
    return np.stack([coeffs[degree - i] * (h ** i).reshape(h.shape + column) for i in range(degree + 1)], axis=1)


def power_coefficients(q: np.ndarray, h: np.ndarray) -> np.ndarray:
    """The coefficients (degree + 1, K, ...) in ``tau`` on ``[0, h]``, highest power first (the
    :class:`~camgen.contour.Spline` convention), of the pieces ``sum_i q[i, k] s^i`` with
    ``s = tau / h[k]`` (``q`` lowest power first): ``q_i / h^i``."""
    d = q.shape[0] - 1
    powers = h ** exponents(d)
    return (q / powers.reshape(powers.shape + (1,) * (q.ndim - 2)))[::-1]
