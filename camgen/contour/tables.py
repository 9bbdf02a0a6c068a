"""Per-contour tables for vectorised queries over many segments: the arcs' parameters and the
splines' pieces side by side (:class:`SegmentTables`, for :meth:`Contour.evaluate` and friends),
and the polar angles of a star-shaped contour's pieces (:class:`StarTable`, for
:meth:`Contour.polar_radius`).  Built once per contour, on first use.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from camgen.contour.arc import Arc
from camgen.geometry import angle_in_sweep, signed_curvature, unit_vectors
from camgen.numerics.polynomial import horner

if TYPE_CHECKING:
    from collections.abc import Sequence

    from camgen.contour.spline import Spline

__all__ = ["RAY_ITERATIONS", "SegmentTables", "StarTable"]

TWO_PI = 2.0 * math.pi
_unit = unit_vectors


def _grouped_searchsorted(values: np.ndarray, starts: np.ndarray, groups: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """``np.searchsorted(values[starts[g]:starts[g + 1]], q, side="right")`` for every query
    ``q`` of group ``g`` at once (``values`` sorted within each group, groups in order; ``starts``
    (G + 1,)).  Exact: one stable sort of values and queries together, no arithmetic on them."""
    if starts.size == 2:  # one group: a plain search
        return np.searchsorted(values, queries, side="right")
    value_groups = np.repeat(np.arange(starts.size - 1), np.diff(starts))
    keys_group = np.concatenate([value_groups, groups])
    keys_value = np.concatenate([values, queries])
    is_query = np.concatenate([np.zeros(values.size, np.int8), np.ones(queries.size, np.int8)])
    order = np.lexsort((is_query, keys_value, keys_group))  # by group, value, values before queries
    queries_before = np.cumsum(is_query[order]) - is_query[order]
    rank = np.empty(order.size, np.int64)
    rank[order] = np.arange(order.size)
    at = rank[values.size :]
    return at - queries_before[at] - starts[groups]


class SegmentTables:
    """Per-segment arrays of a contour: arc parameters, and the pieces of all its splines
    concatenated (rows (P, degree + 1, 2) of the highest degree among them, lower-degree pieces
    with leading zeros; breaks, and where each spline's breaks and pieces start)."""

    def __init__(self, segments: tuple) -> None:
        n = len(segments)
        self.is_arc = np.array([isinstance(seg, Arc) for seg in segments])
        self.center = np.full((n, 2), np.nan)
        self.radius = np.full(n, np.nan)
        self.start = np.full(n, np.nan)
        self.sweep = np.full(n, np.nan)
        self.kappa = np.full(n, np.nan)
        splines = []
        for i, seg in enumerate(segments):
            if isinstance(seg, Arc):
                self.center[i] = seg.center
                self.radius[i], self.start[i], self.sweep[i] = seg.radius, seg.start_angle, seg.sweep
                self.kappa[i] = math.copysign(1.0 / seg.radius, seg.sweep)
            else:
                splines.append((i, seg))
        self.spline_of = np.full(n, -1)  # segment -> spline number
        self.spline_of[[i for i, _ in splines]] = np.arange(len(splines))
        self.splines = [seg for _, seg in splines]
        if splines:
            self.breaks = np.concatenate([seg.breaks for seg in self.splines])
            self.break_start = np.concatenate([[0], np.cumsum([seg.breaks.size for seg in self.splines])])
            self.piece_start = self.break_start[:-1] - np.arange(len(splines))  # K pieces per K + 1 breaks
            self.n_pieces = np.array([seg.n_pieces for seg in self.splines])
            self.degree = max(seg.degree for seg in self.splines)
            self.rows = np.concatenate([seg._rows if seg.degree == self.degree else
                                        np.pad(seg._rows, ((0, 0), (self.degree - seg.degree, 0), (0, 0))) for seg in self.splines])
            self.t0 = np.array([seg.breaks[0] for seg in self.splines])
            self.span = np.array([seg.span for seg in self.splines])

    def arc_values(self, idx: np.ndarray, u: np.ndarray, method: str) -> np.ndarray:
        """Arc.point / derivative / curvature of segments ``idx`` at local parameters ``u``."""
        if method == "curvature":
            return self.kappa[idx]
        angle = self.start[idx] + self.sweep[idx] * u
        if method == "point":
            return self.center[idx] + self.radius[idx][:, None] * _unit(angle)
        return (self.radius[idx] * self.sweep[idx])[:, None] * np.stack([-np.sin(angle), np.cos(angle)], axis=-1)

    def locate(self, spline: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rows (into ``self.rows``) and offsets of spline parameters ``t`` of splines
        ``spline``: Spline._locate for many splines at once."""
        local = _grouped_searchsorted(self.breaks, self.break_start, spline, t) - 1
        local = np.minimum(np.maximum(local, 0), self.n_pieces[spline] - 1)  # np.clip, fewer calls
        return self.piece_start[spline] + local, t - self.breaks[self.break_start[spline] + local]

    def spline_values(self, idx: np.ndarray, u: np.ndarray, method: str) -> np.ndarray:
        """Spline.point / derivative / curvature of segments ``idx`` at local parameters ``u``."""
        spline = self.spline_of[idx]
        t = self.t0[spline] + u * self.span[spline]  # Spline._t
        row, tau = self.locate(spline, t)
        c = self.rows[row]
        tau = tau[:, None]
        if self.degree != 3:
            if method == "point":
                return horner(c, tau, 0)
            d1 = horner(c, tau, 1)
            if method == "derivative":
                return d1 * self.span[spline][:, None]
            return signed_curvature(d1, horner(c, tau, 2))
        if method == "point":
            return ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3]
        d1 = (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        if method == "derivative":
            return d1 * self.span[spline][:, None]
        return signed_curvature(d1, 6.0 * c[:, 0] * tau + 2.0 * c[:, 1])


#: Newton steps of the spline ray solve (:class:`StarTable`); it stops once every step is
#: below 1e-13 of the parameter span.
RAY_ITERATIONS = 60


class StarTable:
    """Polar angles at the start of every piece of a star-shaped contour (arcs cut into parts
    of at most 45 deg), increasing once around the axis, what each piece is, and the splines'
    break points (aligned with ``tables.breaks``)."""

    def __init__(self, psi: np.ndarray, segment: np.ndarray, piece: np.ndarray, tables: SegmentTables, ends: np.ndarray) -> None:
        self.psi, self.segment, self.piece, self.tables, self.ends = psi, segment, piece, tables, ends

    @classmethod
    def build(cls, segments: "Sequence[Arc | Spline]", tables: SegmentTables) -> "StarTable | None":
        """The table of a contour's ``segments`` (with their :class:`SegmentTables`), or None if
        the contour is not star-shaped about the axis at the resolution of its breaks."""
        segment, piece, points, ends = [], [], [], []
        for i, seg in enumerate(segments):
            if isinstance(seg, Arc):
                # P x P' = r s (r + c . u(a)) along the arc (s: sign of the sweep) keeps its
                # sign iff the polar angle is monotonic there: check its extremes over the sweep
                cx, cy = seg.center
                distance = math.hypot(cx, cy)
                candidates = [seg.start_angle, seg.start_angle + seg.sweep]
                toward = math.atan2(cy, cx)
                for extreme in (toward, toward + math.pi):
                    if angle_in_sweep(np.array([extreme]), seg.start_angle, seg.sweep)[0]:
                        candidates.append(extreme)
                cu = distance * np.cos(np.array(candidates) - toward)
                if not np.all(np.sign(seg.sweep) * (seg.radius + cu) > 0):
                    return None
                parts = max(1, math.ceil(abs(seg.sweep) / (math.pi / 4)))
                segment += [i] * parts
                piece += list(range(parts))
                points.append(seg.point(np.arange(parts) / parts))
            else:
                pts = seg.eval_t(seg.breaks)
                if np.allclose(pts[0], pts[-1], rtol=0, atol=1e-9):
                    pts[-1] = pts[0]  # a closed spline: its two ends are one break
                ends.append(pts)  # aligned with tables.breaks
                segment += [i] * seg.n_pieces
                piece += list(range(seg.n_pieces))
                points.append(pts[:-1])
        starts = np.concatenate(points)
        angle = np.arctan2(starts[:, 1], starts[:, 0])
        step = np.mod(np.diff(angle, append=angle[:1]) + math.pi, TWO_PI) - math.pi
        if not (np.all(step > 0) and abs(float(step.sum()) - TWO_PI) < 1e-9):
            return None
        psi = angle[0] + np.concatenate([[0.0], np.cumsum(step[:-1])])
        return cls(psi, np.array(segment), np.array(piece), tables, np.concatenate(ends) if ends else np.empty((0, 2)))

    def radius(self, phi: np.ndarray) -> np.ndarray:
        """Distance along each ray ``phi`` (M,) to the contour, mm (NaN where a solve failed)."""
        start = self.psi[0]
        k = np.searchsorted(self.psi, start + np.mod(phi - start, TWO_PI), side="right") - 1
        seg = self.segment[k]
        u = _unit(phi)
        out = np.full(phi.size, np.nan)
        arc = self.tables.is_arc[seg]
        if arc.any():
            s = seg[arc]
            c, r, uu = self.tables.center[s], self.tables.radius[s], u[arc]
            uc = uu[:, 0] * c[:, 0] + uu[:, 1] * c[:, 1]
            disc = uc * uc - (c[:, 0] * c[:, 0] + c[:, 1] * c[:, 1]) + r**2
            root = np.sqrt(np.maximum(disc, 0.0))
            # the root where P x P' has the sign of the sweep: far on a convex arc, near on a concave one
            out[arc] = np.where(self.tables.sweep[s] > 0, uc + root, uc - root)
        if not arc.all():
            out[~arc] = self._spline_radius(seg[~arc], self.piece[k[~arc]], u[~arc])
        return out

    def _spline_radius(self, seg: np.ndarray, piece: np.ndarray, u: np.ndarray) -> np.ndarray:
        """Safeguarded Newton on ``g(t) = u x P(t)`` inside the piece each ray meets."""
        tables = self.tables
        spline = tables.spline_of[seg]
        first = tables.break_start[spline] + piece
        lo, hi = tables.breaks[first].copy(), tables.breaks[first + 1].copy()
        row = tables.piece_start[spline] + piece
        c = tables.rows[row]
        p0, p1 = self.ends[first], self.ends[first + 1]
        g0 = u[:, 0] * p0[:, 1] - u[:, 1] * p0[:, 0]
        g1 = u[:, 0] * p1[:, 1] - u[:, 1] * p1[:, 0]
        t = lo + (hi - lo) * np.clip(-g0 / np.where(g1 - g0 != 0, g1 - g0, 1.0), 0.0, 1.0)
        base = lo.copy()
        tol = 1e-13 * np.maximum(1.0, tables.span[spline])
        active = np.arange(t.size)  # rays still iterating
        cubic = tables.degree == 3
        for _ in range(RAY_ITERATIONS):
            a = active
            tau = (t[a] - base[a])[:, None]
            ca, ua = c[a], u[a]
            if cubic:
                p = ((ca[:, 0] * tau + ca[:, 1]) * tau + ca[:, 2]) * tau + ca[:, 3]
                dp = (3.0 * ca[:, 0] * tau + 2.0 * ca[:, 1]) * tau + ca[:, 2]
            else:
                p, dp = horner(ca, tau, 0), horner(ca, tau, 1)
            gt = ua[:, 0] * p[:, 1] - ua[:, 1] * p[:, 0]
            dg = ua[:, 0] * dp[:, 1] - ua[:, 1] * dp[:, 0]
            lo[a] = np.where(gt < 0, t[a], lo[a])
            hi[a] = np.where(gt > 0, t[a], hi[a])
            new = t[a] - np.where(dg != 0, gt / np.where(dg != 0, dg, 1.0), 0.0)
            # a Newton step leaving the bracket becomes a bisection (a root on a break stays)
            new = np.where((new < lo[a]) | (new > hi[a]) | ~np.isfinite(new), 0.5 * (lo[a] + hi[a]), new)
            moving = np.abs(new - t[a]) > tol[a]
            t[a] = new
            active = a[moving]
            if not active.size:
                break
        tau = (t - base)[:, None]
        p = ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3] if cubic else horner(c, tau, 0)
        return np.einsum("ij,ij->i", p, u)
