"""The one shared value of camgen: :class:`Contour`, a closed counter-clockwise chain of exact
segments (:class:`~camgen.contour.Arc`, :class:`~camgen.contour.Spline`), and :class:`Joint`,
the continuity where one segment meets the next (see :mod:`camgen.contour` for the conventions).
"""
from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Iterable, Union

import numpy as np

from camgen.contour.arc import Arc
from camgen.contour.ends import spline_end_values
from camgen.contour.spline import Spline, bounding_box_of, flatten_params_of
from camgen.contour.spline_joints import spline_joint_values
from camgen.contour.tables import SegmentTables, StarTable
from camgen.errors import CornerError, GeometryError, require_positive
from camgen.geometry import cross, unit_vectors, wrap_pi

__all__ = ["DEFAULT_CHORD_TOL", "DEFAULT_CLOSURE_TOL", "Contour", "Joint", "Segment"]

TWO_PI = 2.0 * math.pi

#: Default chord tolerance of :meth:`Contour.flatten`, mm.
DEFAULT_CHORD_TOL = 1e-3
#: Gap allowed between the end of one segment and the start of the next, mm.
DEFAULT_CLOSURE_TOL = 1e-7

Segment = Union[Arc, Spline]


def _as_array(values: object) -> np.ndarray:
    return np.asarray(values, dtype=float)


_unit = unit_vectors
_wrap_pi = wrap_pi


@dataclass(frozen=True)
class Joint:
    """Continuity where segment ``index`` ends and the next one starts.

    ``gap_mm`` is the distance between the two ends, ``tangent_jump_rad`` the angle between the
    two unit tangents, ``curvature_jump_per_mm`` the jump of signed curvature (1/mm), and
    ``continuity`` the highest of ``"G2"``, ``"G1"``, ``"G0"`` that holds, or ``"none"``.
    """

    index: int
    point: tuple[float, float]
    gap_mm: float
    tangent_jump_rad: float
    curvature_jump_per_mm: float
    continuity: str


class Contour:
    """A closed counter-clockwise chain of :class:`Arc` and :class:`Spline` segments (mm, cam frame).

    Parameters
    ----------
    segments : sequence of Arc or Spline
        In order along the curve; each must start where the previous one ends.
    closure_tol : float
        Largest gap allowed at a joint, mm.

    Raises
    ------
    GeometryError
        If the chain is not closed within ``closure_tol`` or is not counter-clockwise.
    """

    def __init__(self, segments: Iterable[Segment], closure_tol: float = DEFAULT_CLOSURE_TOL) -> None:
        self.segments: tuple[Segment, ...] = tuple(segments)
        if not self.segments:
            raise GeometryError("a contour needs at least one segment")
        for i, seg in enumerate(self.segments):
            nxt = self.segments[(i + 1) % len(self.segments)]
            (ex, ey), (sx, sy) = seg.end_point.tolist(), nxt.start_point.tolist()
            gap = math.hypot(ex - sx, ey - sy)
            if gap > closure_tol:
                raise GeometryError(
                    f"contour is not closed: segment {i} ends {gap:.3g} mm from where segment "
                    f"{(i + 1) % len(self.segments)} starts (closure_tol = {closure_tol:g} mm)"
                )
        area = self.area
        if area <= 0.0:
            raise GeometryError(f"contour must run counter-clockwise (signed area {area:.6g} mm^2 <= 0)")
        self._corners = np.array([seg.start_point for seg in self.segments])  # segment start points (n, 2)
        self._arc_table = self._convex_arc_table()

    @classmethod
    def _checked_by_caller(cls, segments: Sequence[Segment], area: float) -> Contour:
        """A contour whose caller has checked what the constructor checks (each segment starts
        within ``DEFAULT_CLOSURE_TOL`` of where the previous one ends; the signed ``area`` (mm^2,
        Green's theorem) is > 0) for several contours at once (the envelope fit); else use
        ``Contour(segments)``, which raises the message that names the failure."""
        contour = cls.__new__(cls)
        contour.segments = tuple(segments)
        contour.__dict__["area"] = area
        contour._corners = np.array([seg.start_point for seg in contour.segments])
        contour._arc_table = contour._convex_arc_table()
        return contour

    def _convex_arc_table(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """For a G1 chain of convex arcs, the normal-angle ranges tile the circle: start angles
        (sorted, mod 2 pi), centres and radii, for an O(log n) support function."""
        arcs = [s for s in self.segments if isinstance(s, Arc) and s.sweep > 0]
        if len(arcs) != len(self.segments):
            return None
        starts = np.array([s.start_angle for s in arcs]) % TWO_PI
        ends = np.array([s.start_angle + s.sweep for s in arcs])
        # convex arcs join with a common tangent iff each ends at the normal angle the next starts at
        if np.any(np.abs(_wrap_pi(ends - np.roll(starts, -1))) > 1e-9):
            return None
        order = np.argsort(starts)
        centres = np.array([s.center for s in arcs])[order]
        radii = np.array([s.radius for s in arcs])[order]
        return starts[order], centres, radii

    def __repr__(self) -> str:
        kinds = ", ".join(s.kind for s in self.segments)
        return f"Contour({len(self.segments)} segments: {kinds})"

    @property
    def n_segments(self) -> int:
        return len(self.segments)

    # -- pointwise ---------------------------------------------------------------------------
    def _tables(self) -> "SegmentTables":
        """Per-segment arrays for vectorised evaluation (built once, on first use)."""
        tables = self.__dict__.get("_segment_tables")
        if tables is None:
            tables = self.__dict__["_segment_tables"] = SegmentTables(self.segments)
        return tables

    def _dispatch(self, t: object, method: str) -> np.ndarray:
        """``method`` ("point", "derivative" or "curvature") of the segments at global
        parameters ``t``: every arc point in one vectorised pass (centres, radii and angles
        gathered per point), every spline point in another (its piece located by one sorted
        search over all spline breaks); the same arithmetic as the segments' own methods."""
        t = _as_array(t)
        shape = t.shape
        flat = np.mod(t.ravel(), self.n_segments)
        idx = np.minimum(np.floor(flat).astype(int), self.n_segments - 1)
        u = flat - idx
        tables = self._tables()
        width = () if method == "curvature" else (2,)
        out = np.empty((flat.size,) + width)
        arc = tables.is_arc[idx]
        if arc.all():
            out[...] = tables.arc_values(idx, u, method)
        elif arc.any():
            out[arc] = tables.arc_values(idx[arc], u[arc], method)
            out[~arc] = tables.spline_values(idx[~arc], u[~arc], method)
        else:
            out[...] = tables.spline_values(idx, u, method)
        return out.reshape(shape + width)

    def evaluate(self, t: object) -> np.ndarray:
        """Points (..., 2), mm, at global parameters ``t`` (see module docstring)."""
        return self._dispatch(t, "point")

    def tangent(self, t: object) -> np.ndarray:
        """Unit tangents (..., 2) in the direction of travel (counter-clockwise)."""
        d = self._dispatch(t, "derivative")
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def normal(self, t: object) -> np.ndarray:
        """Outward unit normals (..., 2): the tangent rotated by -90 deg."""
        tan = self.tangent(t)
        return np.stack([tan[..., 1], -tan[..., 0]], axis=-1)

    def curvature(self, t: object) -> np.ndarray:
        """Signed curvature (...,), 1/mm; > 0 where the contour is convex."""
        return self._dispatch(t, "curvature")

    # -- flattening ---------------------------------------------------------------------------
    def flatten_params(self, chord_tol: float = DEFAULT_CHORD_TOL) -> np.ndarray:
        """Global parameters of the vertices of :meth:`flatten` (start of the contour first)."""
        require_positive("chord_tol", chord_tol)
        splines = iter(flatten_params_of([seg for seg in self.segments if isinstance(seg, Spline)], chord_tol))
        parts = [i + (next(splines) if isinstance(seg, Spline) else seg.flatten_params(chord_tol)) for i, seg in enumerate(self.segments)]
        params = np.concatenate(parts)
        if params.size < 3:  # a closed polygon needs 3 vertices
            params = np.linspace(0.0, self.n_segments, 4)[:-1]
        return params

    def flatten(self, chord_tol: float = DEFAULT_CHORD_TOL) -> np.ndarray:
        """Closed polygon (N, 2), mm, first vertex not repeated, counter-clockwise.

        Every vertex lies on the curve and every chord stays within ``chord_tol`` mm of the
        curve between its ends (sagitta formula for arcs, second-derivative bound for splines).
        """
        return self.evaluate(self.flatten_params(chord_tol))

    # -- global measures ----------------------------------------------------------------------
    @functools.cached_property
    def area(self) -> float:
        """Enclosed area, mm^2, by Green's theorem (exact for arcs and polynomial pieces)."""
        return float(sum(seg.green_area() for seg in self.segments))

    @property
    def length(self) -> float:
        """Perimeter, mm (exact for arcs, Gauss-Legendre for splines)."""
        return float(sum(seg.length for seg in self.segments))

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """Exact bounding box ``(xmin, ymin, xmax, ymax)``, mm."""
        splines = [seg for seg in self.segments if isinstance(seg, Spline)]
        boxes = [(p.min(axis=0), p.max(axis=0)) for p in (seg.extreme_points() for seg in self.segments if not isinstance(seg, Spline))]
        if splines:
            boxes.append(bounding_box_of(splines))
        lo, hi = np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)
        return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])

    @property
    def size(self) -> float:
        """Largest distance of the contour from the rotation axis (bounding-box estimate), mm."""
        xmin, ymin, xmax, ymax = self.bounds
        return float(max(abs(xmin), abs(ymin), abs(xmax), abs(ymax)))

    # -- offset -------------------------------------------------------------------------------
    def offset(self, distance: float, spline_tol: float = 1e-6) -> "Contour":
        """The contour offset by ``distance`` mm along its outward normal (< 0: inward).

        Arcs stay exact arcs with radius ``r + d`` (convex) or ``r - d`` (concave); spline
        segments are refitted within ``spline_tol`` mm.  Raises :class:`GeometryError` naming
        the segment and cam angle where a radius would reach zero (undercut), or the cam angle
        where two distant parts of the offset cross (a neck narrower than twice the offset).
        The global check runs for non-convex contours only: the parallel curve of a convex
        curve whose radii all exceed the offset is simple.
        """
        from camgen.errors import require_finite

        distance = require_finite("offset", distance)
        if distance == 0.0:
            return self
        closure_tol = max(10 * spline_tol, DEFAULT_CLOSURE_TOL)
        # joints between G1 segments stay closed; a corner (G0 joint) opens a gap of |distance| times its turn
        turn = self._joint_turns()
        corner = np.flatnonzero(np.abs(turn) * abs(distance) > closure_tol)
        if corner.size:
            i = int(corner[0])
            p = self.segments[i].end_point
            polar = math.degrees(math.atan2(p[1], p[0])) % 360.0
            kind = "convex: its offset needs an arc about the corner" if turn[i] > 0 else "concave: a round tool cannot reach into it"
            raise CornerError(
                f"offset {distance:g} mm of a contour with a corner: segments {i} and {(i + 1) % self.n_segments} meet at cam angle "
                f"{polar:.3f} deg, the tangent turning by {math.degrees(turn[i]):.3f} deg ({kind}); a disk cam has a corner where "
                "its law's velocity jumps (a knife follower): blend the velocity there (e.g. constant_velocity with blend > 0)")
        new: list[Segment] = []
        for i, seg in enumerate(self.segments):
            if isinstance(seg, Arc):
                new.append(seg.offset(distance, index=i))
            else:
                new.append(seg.offset(distance, index=i, tol=spline_tol))
        out = Contour(new, closure_tol=closure_tol)
        if not self.is_convex():
            crossing = out.self_intersection()
            if crossing is not None:
                polar = round(math.degrees(math.atan2(crossing[1], crossing[0])), 3) % 360.0
                raise GeometryError(
                    f"offset {distance:g} mm crosses itself near cam angle {polar:.3f} deg "
                    f"(point ({crossing[0]:.4g}, {crossing[1]:.4g}) mm): a neck of the contour is narrower than twice the offset"
                )
        return out

    def is_convex(self, corner_tol: float = 1e-9) -> bool:
        """True if the contour turns left everywhere: the signed curvature is >= 0 on every
        segment (exact for arcs and cubic or quintic pieces) and no joint is a concave corner
        (the tangent turning right by more than ``corner_tol`` rad where a segment meets the next,
        as at a knife cam's velocity jump)."""
        if not all(seg.sweep > 0 if isinstance(seg, Arc) else seg.min_turning() >= 0 for seg in self.segments):
            return False
        return bool(np.all(self._joint_turns() >= -corner_tol))

    def _joint_turns(self) -> np.ndarray:
        """Signed angles (n,), rad, by which the tangent turns where segment i meets segment i + 1
        (> 0: to the left, a convex corner; ~0 at a G1 joint)."""
        ends = np.array([seg.derivative(np.array([1.0]))[0] for seg in self.segments])  # (n, 2) tangents at the ends
        starts = np.roll(np.array([seg.derivative(np.array([0.0]))[0] for seg in self.segments]), -1, axis=0)  # next starts
        return np.arctan2(ends[:, 0] * starts[:, 1] - ends[:, 1] * starts[:, 0], np.einsum("ij,ij->i", ends, starts))

    def self_intersection(self, chord_tol: float | None = None, block: int = 1 << 22) -> np.ndarray | None:
        """A point (2,) where two non-adjacent chords of the flattened contour cross, else None.

        ``chord_tol`` defaults to 1e-6 of the contour size (at least 1e-6 mm): parts of the
        curve closer than twice that may be reported as crossing.  Of several crossings, the one
        on the lowest-numbered chord (then the lowest-numbered other chord) is returned.  Only
        chords whose x ranges overlap are tested (sweep and prune: sorted by their smallest x),
        ``block`` pairs at a time.
        """
        tol = chord_tol if chord_tol is not None else max(1e-6, 1e-6 * self.size)
        a = self.flatten(tol)
        b = np.roll(a, -1, axis=0)
        n = len(a)
        d = b - a
        lo_x, hi_x = np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 0], b[:, 0])
        lo_y, hi_y = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
        order = np.argsort(lo_x, kind="stable")
        sorted_lo = lo_x[order]
        # chord order[p] against the chords after it in x order that start within its x range
        stop = np.searchsorted(sorted_lo, hi_x[order], side="right")
        count = np.maximum(stop - np.arange(n) - 1, 0)
        best: tuple[int, int] | None = None
        first = 0
        cumulative = np.cumsum(count)
        while first < n:
            last = int(np.searchsorted(cumulative, (cumulative[first - 1] if first else 0) + block, side="right"))
            last = min(n, max(last, first + 1))
            pos = np.arange(first, last)
            reps = count[first:last]
            p = np.repeat(pos, reps)
            offset = np.arange(int(reps.sum())) - np.repeat(np.cumsum(reps) - reps, reps)
            i, j = order[p], order[p + 1 + offset]
            keep = (lo_y[i] <= hi_y[j]) & (lo_y[j] <= hi_y[i])
            gap = np.abs(i - j)
            keep &= (gap > 1) & (gap < n - 1)
            i, j = np.minimum(i[keep], j[keep]), np.maximum(i[keep], j[keep])
            o1 = cross(d[i], a[j] - a[i])
            o2 = cross(d[i], a[j] + d[j] - a[i])
            o3 = cross(d[j], a[i] - a[j])
            o4 = cross(d[j], a[i] + d[i] - a[j])
            hit = (o1 * o2 < 0) & (o3 * o4 < 0)
            if hit.any():
                k = int(np.lexsort((j[hit], i[hit]))[0])
                pair = (int(i[hit][k]), int(j[hit][k]))
                best = pair if best is None or pair < best else best
            first = last
        if best is None:
            return None
        first_chord, second_chord = best
        o3_at = float(cross(d[second_chord], a[first_chord] - a[second_chord]))
        o4_at = float(cross(d[second_chord], a[first_chord] + d[first_chord] - a[second_chord]))
        return a[first_chord] + o3_at / (o3_at - o4_at) * d[first_chord]

    # -- support function -----------------------------------------------------------------------
    def _support(self, psi: object, chunk: int = 2048) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Support value, contact point and radius of curvature at the contact (0 at a corner)."""
        psi = _as_array(psi)
        shape = psi.shape
        if self._arc_table is not None:  # convex G1 arcs: the arc holding psi in its normal range
            starts, centres, radii = self._arc_table
            k = np.searchsorted(starts, np.mod(psi, TWO_PI), side="right") - 1  # -1 wraps to the last arc
            u = _unit(psi)
            c, r = centres[k], radii[k]
            pts = c + r[..., None] * u
            return c[..., 0] * u[..., 0] + c[..., 1] * u[..., 1] + r, pts, r
        flat = psi.ravel()
        h = np.empty(flat.size)
        pts = np.empty((flat.size, 2))
        rho = np.empty(flat.size)
        corners = self._corners
        for lo in range(0, flat.size, chunk):
            block = flat[lo : lo + chunk]
            best = np.full(block.size, -np.inf)
            best_pt = np.zeros((block.size, 2))
            best_rho = np.zeros(block.size)
            for seg in self.segments:
                vals, cand, cand_rho = seg.support_candidates(block)
                better = vals > best
                best = np.where(better, vals, best)
                best_pt = np.where(better[:, None], cand, best_pt)
                best_rho = np.where(better, cand_rho, best_rho)
            # segment ends win only where clearly better: a corner (G0 joint) of the contour
            cv = corners @ _unit(block).T  # (n, M)
            c_best = np.argmax(cv, axis=0)
            c_val = cv[c_best, np.arange(block.size)]
            better = c_val > best + 1e-12 * (1.0 + np.abs(c_val))
            best = np.where(better, c_val, best)
            best_pt = np.where(better[:, None], corners[c_best], best_pt)
            best_rho = np.where(better, 0.0, best_rho)
            h[lo : lo + chunk] = best
            pts[lo : lo + chunk] = best_pt
            rho[lo : lo + chunk] = best_rho
        return h.reshape(shape), pts.reshape(shape + (2,)), rho.reshape(shape)

    def support_point(self, psi: object) -> tuple[np.ndarray, np.ndarray]:
        """Support function and contact point for outward normal directions ``psi`` (rad).

        Returns
        -------
        h : array (...,)
            ``max over the contour of p . (cos psi, sin psi)``, mm: the distance from the
            rotation axis to a flat face with outward normal ``psi`` touching the cam.
        point : array (..., 2)
            The contact point (for a non-convex contour, a point of the convex hull).
        """
        h, pts, _ = self._support(psi)
        return h, pts

    def support(self, psi: object) -> np.ndarray:
        """Support function ``h(psi)``, mm, for outward normal directions ``psi`` (rad); see :meth:`support_point`."""
        return self._support(psi)[0]

    def support_derivatives(self, psi: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``h``, ``dh/dpsi`` and ``d2h/dpsi2`` of the support function (mm, mm/rad, mm/rad^2).

        ``dh/dpsi = p . u_perp`` (the contact point's coordinate along the face) and
        ``d2h/dpsi2 = rho - h`` with ``rho`` the radius of curvature at the contact (0 at a
        corner).  At a joint where the curvature jumps, ``d2h`` jumps too.
        """
        psi = _as_array(psi)
        h, pts, rho = self._support(psi)
        u_perp = np.stack([-np.sin(psi), np.cos(psi)], axis=-1)
        dh = np.einsum("...i,...i->...", pts, u_perp)
        return h, dh, rho - h

    def polar_radius(self, phi: object, chunk: int = 1 << 22) -> np.ndarray:
        """Distance (mm) from the rotation axis to the contour along polar angles ``phi`` (rad).

        Needs a contour that is star-shaped about the axis (every ray from the origin meets it
        once), as a cam must be for a polar lift table; raises :class:`GeometryError` otherwise.

        O(N log K) time and O(N) memory for N rays and K pieces: the polar angles of the
        segments' ends and of the splines' breaks increase once around the axis (checked once
        per contour; arcs exactly, from the sign of ``P x P'``), so a sorted search finds the
        piece each ray meets; the distance is then the circle's root (arcs) or a safeguarded
        Newton solve of ``u x P(t) = 0`` inside the piece (splines).  A ray through a joint
        meets the piece that starts there.  Contours failing the check take every piece for
        every ray (``chunk`` bounds rays x pieces per block) and raise the error.
        """
        phi = _as_array(phi)
        flat = phi.ravel()
        star = self._star_table()
        if star is not None:
            dist = star.radius(flat)
            if np.all(np.isfinite(dist)) and np.all(dist > 0):
                return dist.reshape(phi.shape)
        pieces = sum(2 if isinstance(seg, Arc) else 1 for seg in self.segments)
        step = max(1, chunk // pieces)
        dist = np.concatenate([self._polar_radius_all_pieces(flat[lo : lo + step]) for lo in range(0, flat.size, step)] or [np.empty(0)])
        return dist.reshape(phi.shape)

    def _star_table(self) -> "StarTable | None":
        """The polar-angle table of :meth:`polar_radius`, or None if the contour is not
        star-shaped about the axis at the resolution of its breaks (built once)."""
        if "_star" not in self.__dict__:
            self.__dict__["_star"] = StarTable.build(self.segments, self._tables())
        return self.__dict__["_star"]

    def _polar_radius_all_pieces(self, flat: np.ndarray) -> np.ndarray:
        """:meth:`polar_radius` by intersecting every ray with every segment (rays x pieces)."""
        hits = np.concatenate([seg.ray_hits(flat) for seg in self.segments], axis=1)
        finite = np.isfinite(hits)
        # a ray through a joint hits both neighbouring segments at the same distance
        dist = np.where(finite, hits, np.inf).min(axis=1)
        far = np.where(finite, hits, -np.inf).max(axis=1)
        missed = np.flatnonzero(~finite.any(axis=1))
        if missed.size:
            # a ray through a joint whose two ends differ by rounding (up to DEFAULT_CLOSURE_TOL) can
            # pass between them: it meets the contour at the joint (a segment's start point)
            u = _unit(flat[missed])
            along = u @ self._corners.T  # (rays, joints)
            across = np.abs(np.outer(u[:, 0], self._corners[:, 1]) - np.outer(u[:, 1], self._corners[:, 0]))
            at_joint = np.where((across <= DEFAULT_CLOSURE_TOL) & (along > 0), along, np.inf).min(axis=1)
            dist[missed] = at_joint
        bad = ~np.isfinite(dist) | (far - dist > 1e-9 * (1.0 + np.abs(dist))) | np.any(np.isposinf(hits), axis=1)
        if np.any(bad):
            where = math.degrees(float(flat[np.argmax(bad)])) % 360.0
            raise GeometryError(f"contour is not star-shaped about the rotation axis: the ray at cam angle {where:.3f} deg does not meet it exactly once")
        return dist

    # -- continuity -----------------------------------------------------------------------------
    def joints(
        self,
        position_tol: float = 1e-9,
        angle_tol: float = 1e-9,
        curvature_tol: float = 1e-9,
    ) -> tuple[Joint, ...]:
        """G0/G1/G2 continuity at every joint (end of segment ``i`` -> start of segment ``i + 1``).

        Tolerances: ``position_tol`` mm, ``angle_tol`` rad, ``curvature_tol`` 1/mm.
        """
        out = []
        if "_segment_tables" not in self.__dict__ and all(isinstance(seg, Spline) for seg in self.segments):
            values = spline_joint_values(self.segments)  # type: ignore[arg-type]  # (the same values in Python floats)
            if values is not None:
                for i, (point, gap, angle, k_jump) in enumerate(values):
                    level = ("none" if gap > position_tol else "G0" if angle > angle_tol else
                             "G1" if abs(k_jump) > curvature_tol else "G2")
                    out.append(Joint(i, point, gap, angle, k_jump, level))
                return tuple(out)
        n = self.n_segments
        ends = self._all_end_values()  # (tangent, curvature) at u = 0 and u = 1
        for i, seg in enumerate(self.segments):
            nxt = self.segments[(i + 1) % n]
            end = seg.end_point
            gap = float(np.hypot(*(end - nxt.start_point)))
            t_end = ends[i][0][1]
            t_start = ends[(i + 1) % n][0][0]
            cross = t_end[0] * t_start[1] - t_end[1] * t_start[0]
            dot = float(t_end @ t_start)
            angle = abs(math.atan2(cross, dot))
            k_jump = float(ends[(i + 1) % n][1][0] - ends[i][1][1])
            if gap > position_tol:
                level = "none"
            elif angle > angle_tol:
                level = "G0"
            elif abs(k_jump) > curvature_tol:
                level = "G1"
            else:
                level = "G2"
            out.append(Joint(i, (float(end[0]), float(end[1])), gap, angle, k_jump, level))
        return tuple(out)

    def _all_end_values(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """:meth:`_end_values` of every segment: the splines' in one vectorised pass
        (:func:`camgen.contour.ends.spline_end_values`: the same values), the arcs' one at a time.
        (:meth:`joints` takes a contour of splines of one degree without tables from
        :func:`camgen.contour.spline_joints.spline_joint_values` instead.)"""
        tables = self._tables()
        spline = np.flatnonzero(~tables.is_arc)
        ends: list[tuple[np.ndarray, np.ndarray] | None] = [None] * self.n_segments
        if spline.size:
            tangents, curvatures = spline_end_values(tables, spline)
            for m, i in enumerate(spline.tolist()):
                ends[i] = (tangents[m], curvatures[m])
        return [self._end_values(seg) if got is None else got for seg, got in zip(self.segments, ends)]

    @staticmethod
    def _end_values(seg: "Segment") -> tuple[np.ndarray, np.ndarray]:
        """The tangents (2, 2) and curvatures (2,) of ``seg`` at its start and end (u = 0, 1): a
        spline's in one evaluation each (elementwise arithmetic: the values of one evaluation per
        end), an arc's one end at a time (its sine and cosine as before)."""
        if isinstance(seg, Spline):
            both = np.array([0.0, 1.0])
            return seg.derivative(both), seg.curvature(both)
        start, end = np.array([0.0]), np.array([1.0])
        return (np.concatenate([seg.derivative(start), seg.derivative(end)]),
                np.concatenate([seg.curvature(start), seg.curvature(end)]))

    def continuity(self) -> str:
        """The lowest continuity over all joints (``"G2"``, ``"G1"``, ``"G0"`` or ``"none"``)."""
        order = ["none", "G0", "G1", "G2"]
        return min((j.continuity for j in self.joints()), key=order.index)
