"""Biarcs: a parametric curve replaced by G1-continuous circular arcs within a tolerance.

Every CAM program and CNC control reads arcs (DXF ``ARC``, G-code ``G2/G3``); few read
B-splines well.  A biarc joins two points with given tangents by two circular arcs that meet
with a common tangent.  :func:`fit_biarcs` builds the equal-tangent-length biarc on every
interval of the curve's parameter, checks its distance to the curve and splits the interval in
two where it is too far, all intervals of a level at once (vectorised); it returns arrays
(:class:`Biarcs`).  :func:`camgen.contour.arcspline.spline_to_biarcs` turns them into a contour's
:class:`~camgen.contour.Arc` segments.

Tolerance: the distance from the curve to the biarc is measured at ``CHECK_SAMPLES`` points of
the curve per interval and must be <= ``(1 - SAMPLING_MARGIN) tol``: the deviation is smooth
between samples and its true maximum exceeds the sampled one by well under that margin (0.3 %
measured on a concave spline), so the whole curve stays within ``tol``.  The fitted arcs pass
exactly through the interval ends with the curve's tangent there (G1 everywhere).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from camgen.errors import GeometryError, require_positive
from camgen.geometry import angle_in_sweep

__all__ = ["CHECK_SAMPLES", "MAX_LEVELS", "SAMPLING_MARGIN", "STRAIGHT", "Biarcs", "arc_through", "fit_biarcs"]

CHECK_SAMPLES = 33
SAMPLING_MARGIN = 0.05
#: Most halvings of an interval before the fit gives up.
MAX_LEVELS = 30
#: |sagitta / chord| below which an arc is treated as a straight line.
STRAIGHT = 1e-12


class Curve(Protocol):
    """A parametric planar curve on ``breaks[0] <= t <= breaks[-1]`` (:class:`camgen.contour.Spline`)."""

    breaks: np.ndarray

    def derivatives(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """P, dP/dt, d2P/dt2 (each (n, 2)) at ``t`` (n,)."""
        ...

    def eval_t(self, t: np.ndarray, order: int = 0) -> np.ndarray:
        """d^order P / dt^order (n, 2) at ``t`` (n,)."""
        ...


@dataclass(frozen=True)
class Biarcs:
    """The biarcs of a curve, one per parameter interval in order along it (K intervals): each
    runs from ``start`` with unit tangent ``start_tangent`` to ``junction``, then on to ``end``
    arriving with unit tangent ``end_tangent`` (all (K, 2), mm)."""

    start: np.ndarray
    start_tangent: np.ndarray
    junction: np.ndarray
    end: np.ndarray
    end_tangent: np.ndarray


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def arc_through(p: np.ndarray, tangent: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Arc from ``p`` with unit tangent ``tangent`` to ``q``: centre (n, 2), signed curvature (n,), sweep (n,)."""
    chord = q - p
    left = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1)
    # curvature of the circle tangent to `tangent` at p through q: 2 (left . chord) / |chord|^2
    kappa = 2.0 * np.einsum("ij,ij->i", left, chord) / np.einsum("ij,ij->i", chord, chord)
    with np.errstate(divide="ignore", invalid="ignore"):
        centre = p + left / kappa[:, None]
        a0 = np.arctan2(p[:, 1] - centre[:, 1], p[:, 0] - centre[:, 0])
        a1 = np.arctan2(q[:, 1] - centre[:, 1], q[:, 0] - centre[:, 0])
        sweep = np.where(kappa > 0, np.mod(a1 - a0, 2 * math.pi), -np.mod(a0 - a1, 2 * math.pi))
    return centre, kappa, sweep


def _junctions(p0: np.ndarray, t0: np.ndarray, p1: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """Junction points (n, 2) of equal-tangent-length biarcs between (p0, t0) and (p1, t1)."""
    v = p1 - p0
    t = t0 + t1
    vt = np.einsum("ij,ij->i", v, t)
    vv = np.einsum("ij,ij->i", v, v)
    one_minus = 1.0 - np.einsum("ij,ij->i", t0, t1)  # (4 - |t|^2) / 2
    with np.errstate(divide="ignore", invalid="ignore"):
        # d^2 (|t|^2 - 4) - 2 d (v . t) + v . v = 0, positive root
        d = np.where(one_minus > 1e-12, (np.sqrt(vt * vt + 2.0 * one_minus * vv) - vt) / (2.0 * one_minus), vv / (2.0 * vt))
    q0 = p0 + d[:, None] * t0
    q1 = p1 - d[:, None] * t1
    return 0.5 * (q0 + q1)


def _distance_to_arc(points: np.ndarray, start: np.ndarray, centre: np.ndarray, kappa: np.ndarray,
                     sweep: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Distance of points (n, s, 2) to arcs (n,) given by start, centre, curvature, sweep and end."""
    straight = np.abs(kappa) * np.linalg.norm(end - start, axis=-1) < STRAIGHT
    # straight pieces: distance to the segment
    ab = (end - start)[:, None, :]
    w = np.clip(np.einsum("nsi,nsi->ns", points - start[:, None], ab) / np.einsum("nsi,nsi->ns", ab, ab), 0, 1)
    seg_dist = np.linalg.norm(points - start[:, None] - w[..., None] * ab, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = points - centre[:, None]
        radius = 1.0 / np.abs(kappa)
        ang = np.arctan2(rel[..., 1], rel[..., 0])
        a0 = np.arctan2(start[:, 1] - centre[:, 1], start[:, 0] - centre[:, 0])
        inside = angle_in_sweep(ang, a0[:, None], sweep[:, None])
        radial = np.abs(np.linalg.norm(rel, axis=-1) - radius[:, None])
        ends = np.minimum(np.linalg.norm(points - start[:, None], axis=-1), np.linalg.norm(points - end[:, None], axis=-1))
        arc_dist = np.where(inside, radial, ends)
    return np.where(straight[:, None], seg_dist, arc_dist)


def fit_biarcs(curve: Curve, tol: float) -> Biarcs:
    """Biarcs within ``tol`` mm of ``curve`` over its whole parameter range (module notes):
    four intervals to start, each halved where its biarc is too far, all of a level at once.

    Raises :class:`~camgen.errors.GeometryError` when an interval still misses ``tol`` after
    :data:`MAX_LEVELS` halvings."""
    tol = require_positive("biarc_tol", tol)
    edges = np.linspace(curve.breaks[0], curve.breaks[-1], 5)  # start coarse; split where needed
    lo, hi = edges[:-1], edges[1:]
    done_lo, done_hi, done_j = [], [], []
    s = np.linspace(0.0, 1.0, CHECK_SAMPLES)[1:-1]
    for _ in range(MAX_LEVELS):
        p0, d0, _ = curve.derivatives(lo)
        p1, d1, _ = curve.derivatives(hi)
        t0, t1 = _unit(d0), _unit(d1)
        junction = _junctions(p0, t0, p1, t1)
        c1, k1, w1 = arc_through(p0, t0, junction)
        # second arc: from the junction to p1, tangent at p1 is t1: build it backwards from p1
        c2, k2, w2 = arc_through(p1, -t1, junction)
        samples = curve.eval_t((lo[:, None] + s[None, :] * (hi - lo)[:, None]).ravel()).reshape(lo.size, s.size, 2)
        dist = np.minimum(
            _distance_to_arc(samples, p0, c1, k1, w1, junction),
            _distance_to_arc(samples, p1, c2, k2, w2, junction),
        )
        ok = np.all(np.isfinite(junction), axis=1) & (np.max(dist, axis=1) <= (1.0 - SAMPLING_MARGIN) * tol)
        done_lo.append(lo[ok])
        done_hi.append(hi[ok])
        done_j.append(junction[ok])
        if ok.all():
            break
        mid = 0.5 * (lo[~ok] + hi[~ok])
        lo, hi = np.concatenate([lo[~ok], mid]), np.concatenate([mid, hi[~ok]])
    else:
        raise GeometryError(f"biarc fit did not reach tol = {tol:g} mm in {MAX_LEVELS} subdivisions")
    lo, hi, junction = np.concatenate(done_lo), np.concatenate(done_hi), np.concatenate(done_j)
    order = np.argsort(lo)
    lo, hi, junction = lo[order], hi[order], junction[order]
    p0, d0, _ = curve.derivatives(lo)
    p1, d1, _ = curve.derivatives(hi)
    return Biarcs(p0, _unit(d0), junction, p1, _unit(d1))
