"""Small shared plane-geometry helpers (the ground floor with :mod:`camgen.contour`).

Angles in rad, lengths in mm.  One definition of each: the angle wrap, the "angle inside a
sweep" test (with its one tolerance), unit vectors, the signed curvature of a parametric curve
and the outward normal of a counter-clockwise curve.
"""
from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = ["SWEEP_TOL", "angle_in_sweep", "cross", "outward_normal", "signed_curvature", "unit_vectors", "wrap_pi"]

TWO_PI = 2.0 * math.pi

#: Tolerance (rad) of :func:`angle_in_sweep`: an angle this close outside a sweep's ends counts
#: as inside (keeps full circles and the ends of adjacent arcs closed under rounding).
SWEEP_TOL = 1e-12


def wrap_pi(angle: npt.ArrayLike) -> np.ndarray:
    """Angles wrapped to [-pi, pi) (rad)."""
    return np.mod(np.asarray(angle, dtype=float) + math.pi, TWO_PI) - math.pi


def angle_in_sweep(angle: np.ndarray, start: float | np.ndarray, sweep: float | np.ndarray, tol: float = SWEEP_TOL) -> np.ndarray:
    """True where ``angle`` (rad) lies on the arc of directions from ``start`` over the signed
    ``sweep`` (> 0 counter-clockwise), ends included within ``tol`` rad (arrays broadcast)."""
    start, sweep = np.asarray(start, dtype=float), np.asarray(sweep, dtype=float)
    lo = np.where(sweep >= 0, start, start + sweep)
    rel = np.mod(np.asarray(angle, dtype=float) - lo, TWO_PI)
    return (rel <= np.abs(sweep) + tol) | (rel >= TWO_PI - tol)


def unit_vectors(angle: np.ndarray) -> np.ndarray:
    """Unit vectors (..., 2) at the given angles (rad)."""
    angle = np.asarray(angle, dtype=float)
    out = np.empty(angle.shape + (2,))
    np.cos(angle, out=out[..., 0])
    np.sin(angle, out=out[..., 1])
    return out


def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """z component of the cross product of 2-D vectors (..., 2)."""
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def signed_curvature(d1: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """Signed curvature (1/mm) of a parametric curve from its first and second derivatives
    (..., 2): ``(x' y'' - y' x'') / |P'|^3``, > 0 turning left (do Carmo, 1-5)."""
    speed = np.hypot(d1[..., 0], d1[..., 1])
    return cross(d1, d2) / speed**3


def outward_normal(d1: np.ndarray) -> np.ndarray:
    """Outward unit normals (..., 2) of a counter-clockwise curve from its derivatives: the
    tangent turned by -90 deg."""
    speed = np.hypot(d1[..., 0], d1[..., 1])
    return np.stack([d1[..., 1], -d1[..., 0]], axis=-1) / speed[..., None]
