"""The largest distance of a contour from the rotation axis, exactly, in one pass over its pieces.

The distance ``|P|`` of a polynomial piece is largest at an end of the piece or where
``d|P|^2/ds = 2 P . P'`` changes sign (a polynomial of degree ``2 degree - 1`` in the piece's
parameter ``s``); an arc's is largest at an end or where the ray from the origin through its
centre meets it (``|centre| + radius``).  Only the pieces that can reach beyond the largest end
distance need the root finding: the polynomial ``|P|^2`` (degree ``2 degree``) of a piece lies
within its Bezier control values (Farin, *Curves and Surfaces for CAGD*, ch. 4), so a piece whose
control values stay below the largest end distance squared (within :data:`REACH_REL`) has no
larger point.  The roots are those of :func:`camgen.numerics.roots.grouped_sign_change_roots` (a
few ulps of ``s``), so the maximum is exact to rounding and :data:`REACH_REL` (the distance is
stationary there: an error ``e`` of ``s`` changes it by ``O(e^2)``).  The old estimate, the largest vertex distance of the outline
flattened at a chord tolerance, was up to that tolerance too small.
"""
from __future__ import annotations

import math
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from camgen.contour.arc import Arc
from camgen.contour.spline import Spline
from camgen.numerics.bernstein import bezier_matrix
from camgen.numerics.polynomial import horner_ascending
from camgen.numerics.roots import grouped_sign_change_roots

if TYPE_CHECKING:
    from camgen.contour.contour import Contour

__all__ = ["REACH_REL", "arc_farthest_distance", "farthest_distance", "splines_farthest_distance"]

#: A piece whose ``|P|^2`` has Bezier control values all below ``(1 + 2 REACH_REL)`` times the
#: largest end distance squared cannot reach beyond it by more than ``REACH_REL`` of it (relative):
#: its roots are skipped (a circular dwell about the axis, where ``d|P|^2/ds`` is rounding noise).
REACH_REL = 1e-12


def _in_sweep(angle: float, start: float, sweep: float) -> bool:
    """``angle`` (rad) lies on the arc from ``start`` through the signed ``sweep``."""
    turned = (angle - start) % (2.0 * math.pi) if sweep > 0 else (start - angle) % (2.0 * math.pi)
    return turned <= abs(sweep)


def arc_farthest_distance(arc: Arc) -> float:
    """Largest ``|P|`` (mm) on ``arc``: ``|centre| + radius`` where the arc passes the direction of
    its centre from the origin, else the larger of its end distances."""
    cx, cy = arc.center
    ends = arc.point(np.array([0.0, 1.0]))
    best = float(np.hypot(ends[:, 0], ends[:, 1]).max())
    if (cx != 0.0 or cy != 0.0) and _in_sweep(math.atan2(cy, cx), arc.start_angle, arc.sweep):
        best = max(best, math.hypot(cx, cy) + arc.radius)
    elif cx == 0.0 and cy == 0.0:  # centred on the axis: every point at the radius
        best = max(best, arc.radius)
    return best


@lru_cache(maxsize=None)
def _square_matrix(degree: int) -> np.ndarray:
    """(degree + 1)^2 x (2 degree + 1): the products ``a_i b_j`` (flattened row-major) summed into
    the ascending coefficient of ``s^(i + j)`` (read-only)."""
    m = np.zeros(((degree + 1) ** 2, 2 * degree + 1))
    for i in range(degree + 1):
        for j in range(degree + 1):
            m[i * (degree + 1) + j, i + j] = 1.0
    m.flags.writeable = False
    return m


@lru_cache(maxsize=None)
def _bezier_matrix(degree: int) -> np.ndarray:
    """(degree + 1) x (degree + 1): ascending power coefficients on [0, 1] (as a row) times it are
    the Bezier control values, ``b_j = sum_{i <= j} C(j, i) / C(degree, i) a_i`` (Farin, ch. 4; read-only):
    :func:`camgen.numerics.bernstein.bezier_matrix` transposed, laid out by rows."""
    m = np.ascontiguousarray(bezier_matrix(degree).T)
    m.flags.writeable = False
    return m


def _scaled_pieces(coeffs: np.ndarray, h: np.ndarray) -> np.ndarray:
    """:func:`camgen.numerics.polynomial.scaled_ascending` of plane pieces (``coeffs`` (degree + 1,
    K, 2), highest power first; ``h`` (K,)): the same products ``coeffs[degree - i] h^i`` written
    into one (K, degree + 1, 2) block (no stack of reshaped copies)."""
    degree = coeffs.shape[0] - 1
    q = np.empty((h.size, degree + 1, coeffs.shape[2]))
    for i in range(degree + 1):
        np.multiply(coeffs[degree - i], (h ** i)[:, None], out=q[:, i])
    return q


def splines_farthest_distance(splines: list[Spline], floor: float = 0.0) -> float:
    """Largest ``|P|`` (mm) on ``splines`` (at least ``floor``): every piece's ends, and the sign
    changes of ``d|P|^2/ds`` of the pieces where the Bezier hull of ``|P|^2`` reaches beyond the
    largest end distance by more than :data:`REACH_REL` (all pieces of one degree in one pass)."""
    by_degree: dict[int, list[Spline]] = {}
    for spline in splines:
        by_degree.setdefault(spline.degree, []).append(spline)
    squares = []
    best2 = floor * floor
    for degree, group in by_degree.items():
        # (K, degree + 1, 2): Q(s) on s in [0, 1], ascending, of every piece of this degree in one pass (elementwise:
        # the same values as spline by spline); the piece lengths as np.diff makes them (b[1:] - b[:-1])
        coeffs = group[0].coeffs if len(group) == 1 else np.concatenate([s.coeffs for s in group], axis=1)
        h = np.concatenate([s.breaks[1:] - s.breaks[:-1] for s in group]) if len(group) > 1 else group[0].breaks[1:] - group[0].breaks[:-1]
        q = _scaled_pieces(coeffs, h)
        x, y = q[:, :, 0], q[:, :, 1]  # the products summed over the axes as einsum("kic,kjc->kij") sums them, x x + y y
        outer = (x[:, :, None] * x[:, None, :] + y[:, :, None] * y[:, None, :]).reshape(q.shape[0], -1)
        f = outer @ _square_matrix(degree)  # |Q(s)|^2, ascending (K, 2 degree + 1)
        best2 = max(best2, float(f[:, 0].max()), float(f.sum(axis=1).max()))  # the ends, s = 0 and 1
        squares.append(f)
    for f in squares:
        hull = (f @ _bezier_matrix(f.shape[1] - 1)).max(axis=1)
        pieces = np.flatnonzero(hull > best2 * (1.0 + 2.0 * REACH_REL))
        if not pieces.size:
            continue
        a = f[pieces]
        slope = a[:, 1:] * np.arange(1, a.shape[1])
        s = grouped_sign_change_roots(slope, 0.0, 1.0, np.zeros(pieces.size, dtype=np.intp), 1)
        row, col = np.nonzero(np.isfinite(s))
        if row.size:
            best2 = max(best2, float(horner_ascending(a[row], s[row, col][:, None]).max()))
    return math.sqrt(best2)


def farthest_distance(contour: "Contour") -> float:
    """Largest distance (mm) from the origin (the cam axis) to ``contour``, exact to rounding."""
    splines = [seg for seg in contour.segments if isinstance(seg, Spline)]
    floor = max([arc_farthest_distance(seg) for seg in contour.segments if isinstance(seg, Arc)], default=0.0)
    return splines_farthest_distance(splines, floor) if splines else floor
