"""Linear-time triangulation of a cam's cross-section: profile polygon minus bore and keyway.

The region lies between two loops that are both *star-shaped about the rotation axis*: the
flattened profile (every cam camgen makes: a polar lift table needs every ray from the axis to
meet the profile once) and the hole (bore polygon plus keyway rectangle: each is convex and
holds the axis, so their union is star-shaped about it).  What the fill relies on, and checks:

1. the profile polygon's polar angles increase strictly, by steps in (0, pi), once around the
   axis (winding number 1): a simple polygon, star-shaped about the axis (:func:`star_angles`);
2. a circle about the axis separates the two loops: every hole vertex is closer to the axis
   than every profile vertex.

Construction (every step O(N) numpy; the loops run over rings, about 20 to 60 of them):

* rings of *radial copies*: each ring holds copies of some of the previous ring's vertices, on
  the same rays from the axis, one log-polar step closer to a circle about the axis: the
  profile's rings move inwards to a circle of radius ``rho_p``, the hole's outwards to one of
  ``rho_q < rho_p`` (the free annulus between hole and profile split in the middle, in log
  radius).  The step of a vertex is :data:`RING_ASPECT` times the angular spacing of its rays
  (log-polar cells of that aspect); a vertex that reaches its circle stays there and is shared
  by the later rings.  Each ring keeps the first ray of every bin of ``2 pi / SEAM_SEGMENTS``
  and every :data:`DECIMATION`-th ray inside a crowded bin, so a fine ring is thinned
  DECIMATION to one per ring until its rays are about SEAM_SEGMENTS to the turn: the interior
  vertices add up to about N / (DECIMATION - 1) plus a constant.
* between two rings, the run of edges of the outer ring between two kept rays fans to the two
  copies, and the inner ring's edge takes a vertex of the run as apex (the middle one, else
  the second or the last but one).  A run of one edge (a quad with two radial sides) is always
  valid: a point on the segment from the axis to a vertex lies strictly on the axis's side of
  both edges at that vertex.  Longer runs are checked triangle by triangle; a run that stays
  bad keeps all its rays (quads) instead.  Triangles with a shared vertex twice are dropped:
  their edges cancel, the band's boundary is unchanged.
* between the two circles the two rings are merged by polar angle (a zipper); both are convex
  and close together, the zipper is valid when the ratio of the radii beats the angular steps.
* without a hole the profile's rings end on a circle of half the profile's smallest radius,
  then rings of halving counts and a fan from the axis.

Every triangle's signed area is then checked positive (twice its area over its longest edge
squared above :data:`MIN_SINE`).  The triangles' boundary is the two loops by construction (every inner edge is
shared by two triangles in opposite directions), so positive triangles cover every point of the
section exactly once (the count of triangles over a point is the winding number of the
boundary about it): a valid triangulation.  :func:`fill_section` returns None when an
assumption fails; the caller then falls back to manifold3d's own triangulation.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = [
    "CENTRE_SEGMENTS", "DECIMATION", "LAST_STEP", "MAX_RINGS", "MIN_SINE", "RING_ASPECT", "SEAM_SEGMENTS",
    "fill_section", "star_angles",
]

TWO_PI = 2.0 * math.pi
#: About one ray in DECIMATION is kept from one ring to the next while the rings are finer than
#: the seam circles: the interior vertices add up to about N / (DECIMATION - 1).
DECIMATION = 6
#: Segments of the two seam circles (at most; fewer when the loops are coarser).
SEAM_SEGMENTS = 48
#: Radial step of a ring over its angular step (1: about square log-polar cells).
RING_ASPECT = 1.5
#: Smallest 2 area / longest edge^2 of a triangle (its height over its longest edge, in units
#: of that edge) accepted as non-degenerate.
MIN_SINE = 1e-12
#: A vertex this close to its circle (log radius) goes onto it: closer, its copy could round to it.
LAST_STEP = 1e-9
#: Fewest segments of the innermost ring before the fan from the axis (no hole).
CENTRE_SEGMENTS = 8


def star_angles(loop: np.ndarray, tol: float = 1e-9) -> np.ndarray | None:
    """Unwrapped polar angles (n,) of a loop (n, 2) that is star-shaped about the origin and
    counter-clockwise: strictly increasing by steps in (0, pi), ``2 pi`` once around (within
    ``tol`` rad); None otherwise (a vertex on the origin, a step backwards or a half turn)."""
    loop = np.asarray(loop, dtype=float)
    if len(loop) < 3 or np.any(np.hypot(loop[:, 0], loop[:, 1]) == 0.0):
        return None
    ang = np.arctan2(loop[:, 1], loop[:, 0])
    step = np.mod(np.diff(ang, append=ang[:1]), TWO_PI)
    if not (np.all(step > 0.0) and np.all(step < math.pi) and abs(float(step.sum()) - TWO_PI) <= tol):
        return None
    # exact sign test of consecutive vertices (cross > 0: counter-clockwise about the origin)
    nxt = np.roll(loop, -1, axis=0)
    if np.any(loop[:, 0] * nxt[:, 1] - loop[:, 1] * nxt[:, 0] <= 0.0):
        return None
    return ang[0] + np.concatenate([[0.0], np.cumsum(step[:-1])])


def _positive(points: np.ndarray, tris: np.ndarray) -> np.ndarray:
    """True for triangles (t, 3) that run counter-clockwise, 2 area / longest edge^2 > MIN_SINE."""
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    ab, ac, bc = b - a, c - a, c - b
    twice = ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]
    longest = np.maximum(np.maximum(np.einsum("ij,ij->i", ab, ab), np.einsum("ij,ij->i", ac, ac)), np.einsum("ij,ij->i", bc, bc))
    return twice > MIN_SINE * longest


def _select(theta: np.ndarray, width: float, fan: int) -> np.ndarray:
    """Rays kept (sorted indices, 0 first): the first of every bin of ``width`` rad, every
    ``fan``-th inside a crowded bin (a dense ring is thinned ``fan`` to one per ring) and both
    ends of every edge wider than a bin."""
    bins = np.floor((theta - theta[0]) / width).astype(np.int64)
    first = np.diff(bins, prepend=-1) > 0
    index = np.arange(theta.size)
    start = np.maximum.accumulate(np.where(first, index, 0))
    gap = np.diff(np.append(theta, theta[0] + TWO_PI))
    wide = gap > width  # both ends of an edge wider than a bin stay: no run reaches across it
    return np.flatnonzero(first | ((index - start) % fan == 0) | wide | np.roll(wide, 1))


class _Ring:
    """A ring of radial copies: global vertex ids (m,), unwrapped angles (m,), unit rays (m, 2),
    positions (m, 2) and log radii (m,); ``done`` marks the vertices on the final circle."""

    def __init__(self, ids: np.ndarray, theta: np.ndarray, rays: np.ndarray, points: np.ndarray, done: np.ndarray, log_r: np.ndarray | None = None) -> None:
        self.ids, self.theta, self.rays, self.points, self.done = ids, theta, rays, points, done
        self.log_r = np.log(np.hypot(points[:, 0], points[:, 1])) if log_r is None else log_r


def _band_triangles(m: int, keep: np.ndarray, mid: np.ndarray, inward: bool) -> tuple[np.ndarray, np.ndarray]:
    """Triangles between a ring A of ``m`` vertices (local indices 0..m-1) and the ring B of the
    copies of A's vertices ``keep`` (local indices m..m+k-1); the run (index into keep) of each.

    The run of A's edges from ``keep[j]`` to ``keep[j + 1]`` fans to B's vertex j up to A's
    vertex ``mid[j]`` and to B's vertex j + 1 after it; B's edge j takes ``mid[j]`` as apex.
    ``inward``: B lies inside A (the profile's rings), else outside (the hole's)."""
    k = keep.size
    width = np.diff(np.append(keep, m))
    edge = np.arange(m)
    run = np.repeat(np.arange(k), width)
    apex = m + np.where(edge < mid[run], run, (run + 1) % k)
    j = np.arange(k)
    if inward:
        edge_tris = np.stack([edge, (edge + 1) % m, apex], axis=1)
        run_tris = np.stack([m + (j + 1) % k, m + j, mid % m], axis=1)
    else:
        edge_tris = np.stack([(edge + 1) % m, edge, apex], axis=1)
        run_tris = np.stack([m + j, m + (j + 1) % k, mid % m], axis=1)
    return np.concatenate([edge_tris, run_tris]), np.concatenate([run, j])


def _spacing(theta: np.ndarray) -> np.ndarray:
    """Mean of the two angular gaps at each vertex of a ring (rad)."""
    gaps = np.diff(np.append(theta, theta[0] + TWO_PI))
    return 0.5 * (gaps + np.roll(gaps, 1))


def _band(ring: _Ring, keep: np.ndarray, rho: float, inward: bool, first_id: int) -> tuple[_Ring, np.ndarray, np.ndarray] | None:
    """The next ring and the band of triangles between it and ``ring``.

    The next ring holds copies of ``ring``'s rays ``keep``, one log-polar step (RING_ASPECT
    times the angular spacing) closer to the circle of radius ``rho`` and stopping on it
    (``rho`` 0: no circle); a vertex already on the circle is shared, not copied.  Triangles
    with a shared vertex twice are degenerate and dropped (their edges cancel: the boundary of
    the band is unchanged).  A run with a bad triangle tries its other middle vertices, then
    keeps all its rays (quads with radial sides: always valid).

    Returns the next ring, the triangles (global ids) and the new vertices (in id order); None
    if a triangle is still bad.
    """
    m = len(ring.ids)
    target = math.log(rho) if rho > 0 else -math.inf
    log_new = np.full(m, np.nan)  # log radius of each ray's copy, fixed once chosen

    def place(rays: np.ndarray, spacing: np.ndarray) -> None:
        step = RING_ASPECT * spacing
        left = np.abs(ring.log_r[rays] - target)
        # onto the circle when close: no sliver of a last step, and none the radius would not show
        arrive = left <= 1.5 * step + LAST_STEP
        log_new[rays] = np.where(arrive, target, ring.log_r[rays] - step if inward else ring.log_r[rays] + step)

    spacing_a = _spacing(ring.theta)
    place(keep, 0.5 * (spacing_a[keep] + _spacing(ring.theta[keep])))
    for attempt in range(2):
        new = log_new[keep]
        done = ring.done[keep]
        fresh = ~done
        ids = ring.ids[keep].copy()
        ids[fresh] = first_id + np.arange(int(fresh.sum()))
        radius = np.where(new == target, rho, np.exp(new))
        points = np.where(done[:, None], ring.points[keep], radius[:, None] * ring.rays[keep])
        stacked = np.concatenate([ring.points, points])
        width = np.diff(np.append(keep, m))
        mid = keep + width // 2
        bad = np.ones(keep.size, bool)
        for offset in (None, 1, -1):  # the middle vertex, then the second and the last but one
            if offset is not None:
                mid = np.where(bad, keep + np.clip(offset % width, 1, None) * (width > 1), mid)
            local, run = _band_triangles(m, keep, mid, inward)
            glob = np.concatenate([ring.ids, ids])[local]
            real = (glob[:, 0] != glob[:, 1]) & (glob[:, 1] != glob[:, 2]) & (glob[:, 2] != glob[:, 0])
            ok = _positive(stacked, local[real])
            bad = np.bincount(run[real][~ok], minlength=keep.size) > 0
            if not bad.any():
                nxt = _Ring(ids, ring.theta[keep], ring.rays[keep], points, done | (new == target), new)
                return nxt, glob[real], points[fresh]
        if attempt:
            return None
        # every ray of a bad run (quads); the copies kept so far stay where they are
        added = np.setdiff1d(np.flatnonzero(np.repeat(bad, width)), keep)
        place(added, spacing_a[added])
        keep = np.union1d(keep, added)
    return None


#: Most rings a band may take (a guard: log-polar steps reach the circle in far fewer).
MAX_RINGS = 10000


def _march(ring: _Ring, rho: float, inward: bool, first_id: int, seam_step: float) -> tuple[_Ring, list[np.ndarray], list[np.ndarray]] | None:
    """Rings from a loop to the circle of radius ``rho``: the last ring, the new vertices (one
    array per ring, in id order) and the bands' triangles."""
    points: list[np.ndarray] = []
    tris: list[np.ndarray] = []
    for _ in range(MAX_RINGS):
        if ring.done.all():
            return ring, points, tris
        keep = _select(ring.theta, seam_step, DECIMATION)
        result = _band(ring, keep, rho, inward, first_id)
        if result is None:
            return None
        ring, band, new = result
        first_id += len(new)
        points.append(new)
        tris.append(band)
    return None


def _zipper(outer: _Ring, inner: _Ring) -> np.ndarray:
    """Triangles (global ids) between two rings merged by polar angle (outer ring outside)."""
    p, q = len(outer.ids), len(inner.ids)
    start = outer.theta[0]
    q_theta = start + np.mod(inner.theta - start, TWO_PI)
    order_q = np.argsort(q_theta, kind="stable")
    q_ids, q_theta = inner.ids[order_q], q_theta[order_q]
    # events: outer vertices 1..p-1 and the wrap to vertex 0, inner vertices 0..q-1
    angles = np.concatenate([outer.theta[1:], [start + TWO_PI], q_theta])
    is_outer = np.concatenate([np.ones(p, bool), np.zeros(q, bool)])
    order = np.argsort(angles, kind="stable")
    is_outer = is_outer[order]
    p_now = np.cumsum(is_outer)  # outer index after the event (mod p)
    q_now = np.cumsum(~is_outer) - 1  # inner index after the event (-1: the last one, before the start)
    p_before = np.concatenate([[0], p_now[:-1]])
    q_before = np.concatenate([[-1], q_now[:-1]])
    o_ids = outer.ids
    tri = np.where(
        is_outer[:, None],
        np.stack([o_ids[p_before % p], o_ids[p_now % p], q_ids[q_before % q]], axis=1),
        np.stack([q_ids[q_now % q], q_ids[q_before % q], o_ids[p_before % p]], axis=1),
    )
    return tri


def _centre(ring: _Ring, first_id: int) -> tuple[list[np.ndarray], list[np.ndarray]] | None:
    """Rings of halving counts inside a circle, then a fan from the axis: new vertices and
    triangles."""
    ring = _Ring(ring.ids, ring.theta, ring.rays, ring.points, np.zeros(len(ring.ids), bool), ring.log_r)
    points, tris = [], []
    while len(ring.ids) > CENTRE_SEGMENTS:
        keep = _select(ring.theta, 0.99 * TWO_PI / (len(ring.ids) // 2), 2)
        if keep.size == len(ring.ids):  # nothing to thin out (a very uneven ring): fan from here
            break
        result = _band(ring, keep, 0.0, True, first_id)
        if result is None:
            return None
        ring, band, new = result
        first_id += len(new)
        points.append(new)
        tris.append(band)
    tris.append(np.stack([np.full(len(ring.ids), first_id), ring.ids, np.roll(ring.ids, -1)], axis=1))
    points.append(np.zeros((1, 2)))
    return points, tris


def fill_section(outer: np.ndarray, hole: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray] | None:
    """Triangulate the region between ``outer`` (N, 2) and ``hole`` (n, 2) (both counter-clockwise
    loops, star-shaped about the origin; ``hole`` None: no hole) in O(N + n).

    Returns
    -------
    points : array (k, 2)
        ``outer``'s vertices (same values, same order), then ``hole``'s, then interior ones, mm.
    triangles : array (t, 3)
        Counter-clockwise triangles, indices into ``points``.

    or None when an assumption of the module docstring fails (use another triangulator then).
    """
    outer = np.asarray(outer, dtype=float)
    theta_o = star_angles(outer)
    if theta_o is None:
        return None
    r_o = np.hypot(outer[:, 0], outer[:, 1])
    seam_step = TWO_PI / SEAM_SEGMENTS
    points = [outer]
    hole_ring: _Ring | None = None  # the hole's loop as the first ring of its band (with a hole)
    if hole is not None:
        hole = np.asarray(hole, dtype=float)
        theta_h = star_angles(hole)
        if theta_h is None:
            return None
        r_h = np.hypot(hole[:, 0], hole[:, 1])
        hole_ring = _Ring(len(outer) + np.arange(len(hole)), theta_h, hole / r_h[:, None], hole, np.zeros(len(hole), bool))
        gap = math.log(float(r_o.min()) / float(r_h.max()))  # log width of the free annulus
        if not gap > 0.0:
            return None
        seam = min(RING_ASPECT * seam_step, gap / 3)  # log gap between the two seam circles
        seam_step = seam / RING_ASPECT
        rho_q = float(r_h.max()) * math.exp((gap - seam) / 2)
        rho_p = rho_q * math.exp(seam)
        points.append(hole)
    else:
        rho_p = 0.5 * float(r_o.min())
    first = sum(len(p) for p in points)
    none = np.zeros(len(outer), bool)
    marched = _march(_Ring(np.arange(len(outer)), theta_o, outer / r_o[:, None], outer, none), rho_p, True, first, seam_step)
    if marched is None:
        return None
    last_o, new, tris = marched
    points += new
    first += sum(len(p) for p in new)
    if hole_ring is not None:
        marched = _march(hole_ring, rho_q, False, first, seam_step)
        if marched is None:
            return None
        last_h, new, tris_h = marched
        points += new
        tris += tris_h
        tris.append(_zipper(last_o, last_h))
    else:
        centre = _centre(last_o, first)
        if centre is None:
            return None
        points += centre[0]
        tris += centre[1]
    all_points = np.concatenate(points)
    all_tris = np.concatenate(tris)
    if not _positive(all_points, all_tris).all():
        return None
    return all_points, all_tris
