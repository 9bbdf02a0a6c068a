"""Cutting simulation of a G-code program, independent of the code that wrote it.

The program is run through LinuxCNC's interpreter (``rs274 -g``); the tool-centre path is
rebuilt from its canonical calls (``STRAIGHT_TRAVERSE``, ``STRAIGHT_FEED``, ``ARC_FEED``: with
cutter compensation rs274 prints the compensated path) and compared with the exact profile:

* **no gouge**: every tool-centre position of every feed move below Z 0 stays outside the part
  at a distance >= r from the exact profile;
* **nothing proud**: every point of the exact profile lies within r of the tool path of every
  pass (each Z level below 0);
* **rapids and depth**: no traverse below Z 0 near the part, no Z below the stock bottom minus
  the breakthrough, and the last pass at exactly that depth.

Exactness.  The profile is flattened with chords within ``PROFILE_TOL`` (1e-7 mm) of the curve
(vertices on the curve, spacing ``s``).  For a point ``q`` whose nearest vertex is ``d_v`` away,
the distance to the chord polygon is >= ``sqrt(d_v^2 - s^2 / 4)`` (``|q - p(t)|^2`` has second
derivative 2 along a chord), so the distance to the curve is >= that minus ``PROFILE_TOL``.
Along a tool move sampled every ``step`` mm the squared distance to any fixed point has second
derivative <= ``2 (1 + D / rho)`` (``rho`` the radius of the move, ``D`` the distance), so between
two samples the distance cannot fall below ``sqrt(min(f0^2, f1^2) - (1 + D / rho) step^2 / 4)``.
The lower bounds used for the gouge test are therefore rigorous; the proud test uses the
distance to the nearest tool-path sample, an upper bound that is at most ``step^2 / (8 r)`` too
large.  rs274 prints 4 decimals: every rebuilt point is within 7.1e-5 mm of the interpreter's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from helpers import arc_sweep, rs274_canon

#: Chord tolerance of the exact profile's flattening, mm.
PROFILE_TOL = 1e-7
#: Spacing of the samples along every tool move, mm.
SAMPLE_STEP = 0.02
#: Largest gouge and largest proud material accepted by the tests, mm.
CUT_TOL = 1e-3


@dataclass
class PassReport:
    """One pass (a chain of feed moves below Z 0): worst gouge and worst proud material, mm."""

    z: float
    gouge: float  # r - smallest distance tool centre -> profile (> 0: the tool cut into the part)
    proud: float  # largest distance profile -> tool path - r (> 0: material left standing)
    outside: bool  # the tool centre is outside the part
    moves: int


@dataclass
class CutReport:
    """The whole program: its passes and the checks that are not per pass."""

    status: int
    message: str
    passes: list[PassReport] = field(default_factory=list)
    deepest: float = 0.0
    rapid_clearance: float = math.inf  # smallest clearance (distance - r) of traverses below Z 0
    canon: list[dict] = field(default_factory=list)

    @property
    def gouge(self) -> float:
        return max(p.gouge for p in self.passes)

    @property
    def proud(self) -> float:
        return max(p.proud for p in self.passes)

    @property
    def z_levels(self) -> list[float]:
        return [p.z for p in self.passes]


class ExactProfile:
    """The exact profile as a dense chord polygon with rigorous distance lower bounds."""

    def __init__(self, contour, tol: float = PROFILE_TOL) -> None:
        from scipy.spatial import cKDTree

        self.vertices = contour.flatten(tol)
        closed = np.vstack([self.vertices, self.vertices[:1]])
        self.spacing = float(np.max(np.hypot(*np.diff(closed, axis=0).T)))
        self.tol = tol
        self.tree = cKDTree(self.vertices)

    def distance_lower_bound(self, points: np.ndarray, beyond: float = np.inf) -> np.ndarray:
        """Rigorous lower bound (n,) of the distance from points (n, 2) to the exact profile, mm
        (inf for points farther than ``beyond`` from every vertex: a faster search)."""
        d_v, _ = self.tree.query(points, distance_upper_bound=beyond)
        return np.sqrt(np.maximum(d_v * d_v - self.spacing**2 / 4.0, 0.0)) - self.tol

    def contains_many(self, points: np.ndarray) -> np.ndarray:
        """Points (n, 2) inside the chord polygon (shapely's vectorised test)."""
        import shapely
        from shapely.geometry import Polygon

        polygon = Polygon(self.vertices)
        shapely.prepare(polygon)
        return shapely.contains_xy(polygon, points[:, 0], points[:, 1])

    def contains(self, point: np.ndarray) -> bool:
        """Even-odd test of one point (2,) against the chord polygon."""
        a = self.vertices
        b = np.roll(a, -1, axis=0)
        x, y = point
        crosses = (a[:, 1] > y) != (b[:, 1] > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
        return bool(np.count_nonzero(crosses & (xc > x)) % 2)


def sample_moves(chain: list[dict], step: float = SAMPLE_STEP, with_z: bool = False) -> tuple[np.ndarray, ...]:
    """Samples of canonical feed moves, ends included, at most ``step`` apart along each move.

    Returns the XY points (n, 2), the index of the move of each point (n,), and per move the
    slack (m,) of the squared-distance bound between two neighbouring samples (module docstring):
    ``(1 + (D + h) / rho) h^2 / 4`` with ``h`` the sample spacing, ``rho`` the smallest radius of
    the move (inf for a line) and ``D`` = 1 mm plus the largest distance of interest, added by the
    caller.  Arcs with a start/end radius mismatch run as spirals, as LinuxCNC runs them.
    ``with_z``: also the Z of every sample (n,), linear along each move as LinuxCNC runs lines
    with Z and helical arcs.
    """
    m = len(chain)
    start = np.array([mv["start"][:2] for mv in chain])
    end = np.array([mv["end"][:2] for mv in chain])
    is_arc = np.array([mv["kind"] == "arc" for mv in chain])
    centre = np.array([mv.get("centre", np.zeros(2)) for mv in chain])
    sweep = np.array([arc_sweep(mv["start"], mv["end"], mv["centre"], mv["turn"]) if mv["kind"] == "arc" else 0.0 for mv in chain])
    r0 = np.hypot(*(start - centre).T)
    r1 = np.hypot(*(end - centre).T)
    length = np.where(is_arc, np.maximum(r0, r1) * np.abs(sweep) + np.abs(r1 - r0), np.hypot(*(end - start).T))
    count = np.maximum(2, np.ceil(length / step).astype(int) + 1)
    move = np.repeat(np.arange(m), count)
    first = np.repeat(np.cumsum(count) - count, count)
    w = (np.arange(count.sum()) - first) / (count[move] - 1)
    a0 = np.arctan2(start[:, 1] - centre[:, 1], start[:, 0] - centre[:, 0])
    ang = a0[move] + sweep[move] * w
    radius = r0[move] + (r1 - r0)[move] * w
    on_arc = centre[move] + radius[:, None] * np.stack([np.cos(ang), np.sin(ang)], axis=1)
    on_line = start[move] + w[:, None] * (end - start)[move]
    points = np.where(is_arc[move][:, None], on_arc, on_line)
    h = length / (count - 1)
    rho = np.where(is_arc, np.minimum(r0, r1), np.inf)
    if with_z:
        z0 = np.array([mv["start"][2] for mv in chain])
        z1 = np.array([mv["end"][2] for mv in chain])
        return points, move, h, rho, z0[move] + (z1 - z0)[move] * w
    return points, move, h, rho


def _passes(canon: list[dict]) -> list[list[dict]]:
    """Chains of consecutive feed moves that reach below Z 0."""
    out: list[list[dict]] = []
    chain: list[dict] = []
    for move in canon:
        cutting = move["kind"] != "traverse" and min(move["start"][2], move["end"][2]) < 0.0
        if cutting:
            chain.append(move)
        elif chain:
            out.append(chain)
            chain = []
    if chain:
        out.append(chain)
    return out


def _check_pass(chain: list[dict], profile: ExactProfile, radius: float, step: float) -> tuple[float, float, bool]:
    """(gouge, proud, outside) of one pass."""
    from scipy.spatial import cKDTree

    pts, move, h, rho = sample_moves(chain, step)
    reach = radius + 1.0  # distances beyond this are not needed
    f = profile.distance_lower_bound(pts, reach)
    same = move[:-1] == move[1:]  # neighbouring samples of one move
    slack = ((1.0 + (reach + h) / rho) * h * h / 4.0)[move[:-1]]
    pair = np.minimum(f[:-1], f[1:])
    low = np.where(pair > 0, np.sqrt(np.maximum(pair * pair - slack, 0.0)), pair)
    low = float(min(np.min(low[same], initial=np.inf), np.min(f)))
    inside = profile.contains_many(pts)
    if inside.any():  # the tool centre entered the part: the gouge is r + its depth inside
        low = min(low, -float(np.max(profile.tree.query(pts[inside])[0])))
    gouge = radius - low
    d_s, _ = cKDTree(pts).query(profile.vertices, distance_upper_bound=reach)
    proud = float(np.max(d_s)) - radius
    outside = not profile.contains(pts[len(pts) // 2])
    return gouge, proud, outside


def simulate(program: str, contour, tool_radius: float, workdir, step: float = SAMPLE_STEP,
             profile: ExactProfile | None = None, tool_table: str | None = None) -> CutReport:
    """Run ``program`` through rs274 (with ``tool_table``, if given) and cut ``contour`` (the exact profile) with it."""
    status, message, canon = rs274_canon(program, workdir, tool_table)
    report = CutReport(status, message, canon=canon)
    if status != 0:
        return report
    profile = profile or ExactProfile(contour)
    cache: dict[bytes, tuple[float, float, bool]] = {}
    for chain in _passes(canon):
        xy = [np.concatenate([m["start"][:2], m["end"][:2], m.get("centre", np.zeros(2)), [m.get("turn", 0)]]) for m in chain]
        key = np.round(np.concatenate(xy), 6).tobytes()
        if key not in cache:  # passes with the same XY moves cut the same way
            cache[key] = _check_pass(chain, profile, tool_radius, step)
        z = min(min(m["start"][2], m["end"][2]) for m in chain)
        report.passes.append(PassReport(z, *cache[key], moves=len(chain)))
    report.deepest = min(min(m["start"][2], m["end"][2]) for m in canon)
    for move in canon:
        if move["kind"] == "traverse" and min(move["start"][2], move["end"][2]) < 0.0:
            pts = sample_moves([move], step)[0]
            report.rapid_clearance = min(report.rapid_clearance, float(np.min(profile.distance_lower_bound(pts))) - tool_radius)
    return report


def part_left(contour, chain_xy: np.ndarray, tool_radius: float, margin: float = 20.0):
    """Coarse cross-check with shapely: stock (the profile's box + ``margin``) minus the tool disc
    swept along the polyline ``chain_xy`` (n, 2); the piece that holds the profile's centroid."""
    from shapely.geometry import LineString, Point, Polygon, box

    poly = Polygon(contour.flatten(1e-3))
    xmin, ymin, xmax, ymax = poly.bounds
    stock = box(xmin - margin, ymin - margin, xmax + margin, ymax + margin)
    left = stock.difference(LineString(chain_xy).buffer(tool_radius, quad_segs=64))
    inside = poly.representative_point()
    pieces = getattr(left, "geoms", [left])
    return next(p for p in pieces if p.contains(Point(inside))), poly


# ---------------------------------------------------------------------------------------------
# pockets (a groove cam's groove): cut into the top face from inside, down to a floor
# ---------------------------------------------------------------------------------------------
@dataclass
class PocketCut:
    """The moves of a program that cut inside the outline (a pocket), judged against its walls.

    ``gouge``: per wall, r - the least distance (rigorous lower bound) of any cutting tool-centre
    position from the wall (> 0: the tool cut into the wall); ``proud``: per wall, the largest
    distance from a point of the wall to the tool-centre path at the floor, minus r (> 0: wall
    material left standing at the floor, hence everywhere above it); ``between``: every cutting
    tool-centre position lies inside the outer wall and outside the others; ``levels``: per chain
    (a level: a feed down, the ramp, then its loops) the Z of its first sideways move's start
    (where the ramp begins) and its lowest Z; ``deepest``:
    the lowest Z of any cutting move; ``floor``: tool-centre samples (n, 2) at that Z.
    """

    gouge: dict[str, float]
    proud: dict[str, float]
    between: bool
    levels: list[tuple[float, float]]
    deepest: float
    floor: np.ndarray

    def island(self, points: np.ndarray, radius: float) -> float:
        """Largest distance of ``points`` (n, 2) of the floor from the tool-centre path at the
        floor, minus r (> 0: material left standing there: an island)."""
        from scipy.spatial import cKDTree

        return float(np.max(cKDTree(self.floor).query(points)[0])) - radius


@dataclass
class GrooveCutReport:
    """A program for a part with pockets: the outline's passes (as :func:`simulate` judges them)
    and the pocket's cut; ``order``: "pocket" / "outline" for each cutting chain, in program order."""

    outline: CutReport
    pocket: PocketCut | None
    order: list[str]


def _least_distance(pts: np.ndarray, move: np.ndarray, h: np.ndarray, rho: np.ndarray, profile: ExactProfile, reach: float) -> float:
    """Rigorous lower bound of the distance from the tool-centre moves sampled at ``pts`` to the
    exact ``profile`` (the bound of :func:`_check_pass`, between neighbouring samples too)."""
    f = profile.distance_lower_bound(pts, reach)
    same = move[:-1] == move[1:]
    slack = ((1.0 + (reach + h) / rho) * h * h / 4.0)[move[:-1]]
    pair = np.minimum(f[:-1], f[1:])
    low = np.where(pair > 0, np.sqrt(np.maximum(pair * pair - slack, 0.0)), pair)
    return float(min(np.min(low[same], initial=np.inf), np.min(f)))


def simulate_pockets(program: str, outline, walls: dict, tool_radius: float, workdir, step: float = SAMPLE_STEP,
                     tool_table: str | None = None) -> GrooveCutReport:
    """Run ``program`` through rs274 and cut a part whose outline is ``outline`` (a contour) and
    whose pocket lies inside ``walls[first]`` and outside the other walls (``{layer: contour or
    any object with flatten(tol)}``, the outer wall first).  Cutting chains whose tool centre
    starts inside the outline are the pocket's; the others are the outline's.  ``tool_table``: as
    for :func:`simulate`."""
    from scipy.spatial import cKDTree

    status, message, canon = rs274_canon(program, workdir, tool_table)
    report = CutReport(status, message, canon=canon)
    if status != 0:
        return GrooveCutReport(report, None, [])
    part = ExactProfile(outline)
    chains = _passes(canon)
    inside = [part.contains(np.asarray(chain[0]["end"][:2])) for chain in chains]
    order = ["pocket" if i else "outline" for i in inside]
    cache: dict[bytes, tuple[float, float, bool]] = {}
    for chain in (c for c, i in zip(chains, inside) if not i):
        xy = [np.concatenate([m["start"][:2], m["end"][:2], m.get("centre", np.zeros(2)), [m.get("turn", 0)]]) for m in chain]
        key = np.round(np.concatenate(xy), 6).tobytes()
        if key not in cache:  # passes with the same XY moves cut the same way
            cache[key] = _check_pass(chain, part, tool_radius, step)
        z = min(min(m["start"][2], m["end"][2]) for m in chain)
        report.passes.append(PassReport(z, *cache[key], moves=len(chain)))
    outline_moves = [m for c, i in zip(chains, inside) if not i for m in c]
    report.deepest = min((min(m["start"][2], m["end"][2]) for m in outline_moves), default=0.0)
    for move in canon:
        if move["kind"] == "traverse" and min(move["start"][2], move["end"][2]) < 0.0:
            pts = sample_moves([move], step)[0]
            report.rapid_clearance = min(report.rapid_clearance, float(np.min(part.distance_lower_bound(pts))) - tool_radius)
    pocket_chains = [c for c, i in zip(chains, inside) if i]
    if not pocket_chains:
        return GrooveCutReport(report, None, order)
    profiles = {layer: ExactProfile(wall) for layer, wall in walls.items()}
    samples = [sample_moves(chain, step, with_z=True) for chain in pocket_chains]
    reach = tool_radius + 1.0
    least: dict[bytes, list[float]] = {}  # levels with the same XY moves come as close to the walls
    for pts, mv, h, rho, _ in samples:
        key = np.round(pts, 6).tobytes()
        if key not in least:  # (computed once per key: setdefault would compute it for every level, then drop it)
            least[key] = [_least_distance(pts, mv, h, rho, prof, reach) for prof in profiles.values()]
    gouge = {layer: tool_radius - min(v[k] for v in least.values()) for k, layer in enumerate(profiles)}
    pts = np.concatenate([s[0] for s in samples])
    z = np.concatenate([s[4] for s in samples])
    cutting = z < 0.0
    first, *others = profiles.values()
    between = bool(np.all(first.contains_many(pts[cutting])) and not any(np.any(p.contains_many(pts[cutting])) for p in others))
    deepest = float(np.min(z))
    floor = pts[np.abs(z - deepest) < 1e-6]
    tree = cKDTree(floor)
    proud = {layer: float(np.max(tree.query(prof.vertices)[0])) - tool_radius for layer, prof in profiles.items()}
    levels = []
    for chain in pocket_chains:
        sideways = [m for m in chain if np.hypot(*(m["end"][:2] - m["start"][:2])) > 0.0]  # after the feed down
        first = sideways[0] if sideways else chain[0]  # a drill's peck moves only down
        levels.append((float(first["start"][2]), float(min(min(m["start"][2], m["end"][2]) for m in chain))))
    return GrooveCutReport(report, PocketCut(gouge, proud, between, levels, deepest, floor), order)
