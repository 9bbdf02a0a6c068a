"""Hermite interpolation on pieces: the polynomial of each piece from values and derivatives at
its two ends (no system to solve; each piece on its own).

* cubic (C1): values and first derivatives (:func:`cubic_hermite_coefficients`);
* quintic (C2): values, first and second derivatives (:func:`quintic_hermite_coefficients`,
  built from :func:`quintic_hermite_data` and :func:`quintic_hermite_scaled`, which the
  envelope fit of :mod:`camgen.synthesis.followers` also calls on complex data, x + i y).

Coefficients come out highest power first in ``t - t[i]`` (:class:`~camgen.contour.Spline`'s
layout).  The interpolation remainder of a piece of length ``h`` is at most
``h^4 max|P^(4)| / 384`` (cubic) and ``h^6 max|P^(6)| / 46080`` (quintic): the remainders
``P^(4)/4! (t - a)^2 (t - b)^2`` and ``P^(6)/6! (t - a)^3 (t - b)^3``.
"""
from __future__ import annotations

import numpy as np

from camgen.numerics.polynomial import power_coefficients

__all__ = ["QUINTIC_RESIDUALS", "cubic_hermite_coefficients", "quintic_hermite_coefficients", "quintic_hermite_data",
           "quintic_hermite_scaled"]

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



def cubic_hermite_coefficients(t: np.ndarray, p: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Coefficients (4, n - 1, d), highest power first (in ``t - t[i]``), of the cubics on
    ``[t[i], t[i + 1]]`` that take the values ``p`` and first derivatives ``m`` ((n, d) each) at
    both ends."""
    h = np.diff(t)[:, None]
    p0, p1, m0, m1 = p[:-1], p[1:], m[:-1], m[1:]
    c3 = (2.0 * (p0 - p1) + h * (m0 + m1)) / h**3
    c2 = (3.0 * (p1 - p0) - h * (2.0 * m0 + m1)) / h**2
    return np.stack([c3, c2, m0, p0])
