"""Arc splines: a contour's spline segments replaced by G1-continuous biarcs within a tolerance
(the fit itself: :mod:`camgen.numerics.biarc`); straight pieces become linear splines."""
from __future__ import annotations

import math

import numpy as np

from camgen.contour.arc import Arc
from camgen.contour.contour import Contour
from camgen.contour.spline import Spline
from camgen.numerics.biarc import STRAIGHT, arc_through, fit_biarcs

__all__ = ["spline_to_biarcs", "to_arc_spline"]


def spline_to_biarcs(spline: Spline, tol: float) -> list[Arc | Spline]:
    """Replace ``spline`` by biarcs within ``tol`` mm (straight pieces become linear splines)."""
    biarcs = fit_biarcs(spline, tol)
    out: list[Arc | Spline] = []
    for a, ta, j, b, tb in zip(biarcs.start, biarcs.start_tangent, biarcs.junction, biarcs.end, biarcs.end_tangent):
        out.append(_segment(a, ta, j))
        out.append(_segment_end(j, b, tb))
    return out


def _segment(p: np.ndarray, tangent: np.ndarray, q: np.ndarray) -> Arc | Spline:
    """Arc from p (tangent given) to q, or a straight piece where it is flat."""
    centre, kappa, sweep = arc_through(p[None], tangent[None], q[None])
    if not np.isfinite(kappa[0]) or abs(kappa[0]) * np.linalg.norm(q - p) < STRAIGHT:
        return _line(p, q)
    start = math.atan2(p[1] - centre[0, 1], p[0] - centre[0, 0])
    return Arc((centre[0, 0], centre[0, 1]), 1.0 / abs(kappa[0]), start, float(sweep[0]))


def _segment_end(p: np.ndarray, q: np.ndarray, tangent_at_q: np.ndarray) -> Arc | Spline:
    """Arc from p to q whose tangent at q is given."""
    centre, kappa, sweep = arc_through(q[None], -tangent_at_q[None], p[None])
    if not np.isfinite(kappa[0]) or abs(kappa[0]) * np.linalg.norm(q - p) < STRAIGHT:
        return _line(p, q)
    start = math.atan2(p[1] - centre[0, 1], p[0] - centre[0, 0])
    return Arc((centre[0, 0], centre[0, 1]), 1.0 / abs(kappa[0]), start, float(-sweep[0]))


def _line(p: np.ndarray, q: np.ndarray) -> Spline:
    coeffs = np.zeros((4, 1, 2))
    coeffs[2, 0] = q - p
    coeffs[3, 0] = p
    return Spline(np.array([0.0, 1.0]), coeffs)


def to_arc_spline(contour: Contour, tol: float) -> Contour:
    """``contour`` with every spline segment replaced by biarcs within ``tol`` mm (arcs kept)."""
    segments: list[Arc | Spline] = []
    for seg in contour.segments:
        if isinstance(seg, Arc):
            segments.append(seg)
        else:
            segments.extend(spline_to_biarcs(seg, tol))
    return Contour(segments, closure_tol=1e-6)
