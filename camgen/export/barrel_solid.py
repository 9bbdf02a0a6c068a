"""The surface mesh of a barrel (cylindrical) cam: the cylinder less the bore, less the groove.

The body is ``{R_bore <= r <= R_o, 0 <= z <= length}`` less the groove ``{R_i < r <= R_o,
z_lower(r, phi) < z < z_upper(r, phi)}`` (cam frame of :mod:`camgen.synthesis.barrel`: z along
the axis, r, phi polar about it; the walls those of :class:`BarrelGroove`).  The mesh is built
as a structured grid, every vertex on the exact surface it samples:

* the two walls on one (r, psi) grid: rows ``R_i = r_0 < ... < r_M = R_o``, columns
  ``0 = psi_0 < ... < psi_{N-1} < 2 pi`` (periodic; the cam angle ``theta = -sigma psi``, so that
  the polar angle grows with ``psi``), vertex the exact contact point at radius r for that cam
  angle (:meth:`BarrelGroove.wall`, in closed form for a translating roller: no inverse solve);
  a row whose polar angle does not grow (the section folds: undercut) is refused;
* the floor (the root cylinder ``r = R_i``) between the walls' root rows, the rim (``r = R_o``)
  from a ring at ``z = 0`` to the lower wall's rim row and from the upper wall's to a ring at
  ``z = length``, joined by angle (:func:`zipper`); the bore (``r = R_bore``) from end to end and
  the two end faces (annuli, or discs without a bore), two triangles per step of the rings.

How the steps follow from the chord tolerance ``tol`` (``output.chord_tol_mm``):

* Columns: every point of a triangle whose vertices lie on a circle of radius R within an arc
  of angle ``a`` is within ``R (1 - cos(a / 2))`` of the circle's cylinder.  The floor and rim bands
  join two rows of vertices merged by angle (:func:`zipper`), whose triangles span at most two
  steps, one of each row: so every circle (the rim and bore rings, the walls' root and rim rows)
  is sampled at steps of at most ``acos(1 - tol / R)`` (half the chord step), and the bands, bore
  and end faces are within ``tol`` of their cylinders and planes.
* The walls are then measured, not estimated: at the midpoint of every edge of every wall
  triangle (its sides and diagonal) the point of the mesh is taken back to cylindrical
  coordinates (r, phi, z) and compared with the exact wall there, ``|z - z_wall(r, phi)|``
  (:func:`axial_deviation`: the axial distance, which the distance to the surface never exceeds
  and which is what moves the follower).  For a surface that is
  quadratic over a triangle the deviation is the sum of the edge-midpoint deviations times
  hat functions ``4 l_i l_j``, whose sum is at most 4/3 (Ciarlet, The Finite Element Method for
  Elliptic Problems, sec. 3.1, the quadratic Lagrange triangle): a column or row is halved until
  every midpoint is within :data:`MIDPOINT_FRACTION` ``* tol``, which leaves the whole wall
  within ``tol`` with a margin for the higher-order terms.  A wall edge at a wall meeting a
  cylinder (the rows ``R_i`` and ``R_o``) is shared by the cylinder's triangles, so they meet
  exactly.

The result is handed to manifold3d, whose status says it is a closed, consistently oriented
2-manifold of one piece, genus 1 with a bore (0 without); :attr:`CamSolid.volume` is manifold3d's.
The size is bounded before the work: a grid whose mesh would make a file of a requested mesh
format larger than :data:`camgen.export.solid.MAX_FILE_BYTES` (:data:`BYTES_PER_TRIANGLE`) is
refused before its walls are evaluated, naming ``output.chord_tol_mm``.  Where the body cannot be made (the groove reaches an end face or the
bore) a :class:`GeometryError` names the cam (the pipeline reports it as a failed check).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError

if TYPE_CHECKING:
    from camgen.export.solid import CamSolid

__all__ = ["BYTES_PER_TRIANGLE", "MAX_REFINEMENTS", "MIDPOINT_FRACTION", "NEWTON_ITERATIONS", "NEWTON_STEP", "NEWTON_TOL", "axial_deviation", "barrel_solid", "band", "closed_body", "half_chord_step", "triangle_cap", "wall_grid", "zipper"]

#: Largest deviation of a wall triangle's edge midpoint from the exact wall, as a fraction of the
#: chord tolerance: a quadratic surface's deviation over the triangle is at most 4/3 of its largest
#: midpoint deviation (module notes), so 1/2 leaves the whole triangle within 2/3 of ``tol`` plus
#: higher-order terms.
MIDPOINT_FRACTION = 0.5
#: Most times a row or column of the wall grid is halved before the tolerance is declared out of
#: reach (each halving at least doubles the resolution where it is needed: 2^24 is far below
#: any float's reach of a smooth wall).
MAX_REFINEMENTS = 24
#: Bytes per triangle of each mesh format, at most: binary STL exactly 50 (and an 84-byte head);
#: measured on the barrel template at 1e-2 and 1e-3 mm: ASCII STL 288, 3MF 18-20 (deflated),
#: OBJ 37-40, PLY 19; with a margin.
BYTES_PER_TRIANGLE = {"stl": 50, "stl_ascii": 300, "3mf": 40, "obj": 60, "ply": 30}
#: Newton's method for the cam angle of a wall point (:func:`axial_deviation`): iterations, the forward
#: difference (rad) and the largest polar-angle residual accepted (rad: 1e-12 rad moves a point
#: on a 1 m radius by 1e-9 mm).
NEWTON_ITERATIONS = 6
NEWTON_STEP = 1e-7
NEWTON_TOL = 1e-12


def triangle_cap(formats: tuple[str, ...] | None) -> int:
    """Most triangles a mesh may have for ``formats`` (None: every mesh format)."""
    from camgen.export.solid import MAX_FILE_BYTES

    sizes = [BYTES_PER_TRIANGLE[f] for f in (formats or ()) if f in BYTES_PER_TRIANGLE] or list(BYTES_PER_TRIANGLE.values())
    return MAX_FILE_BYTES // max(sizes)


def _wall_points(groove: Any, side: int, r: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (M + 1, N, 3) of wall ``side`` on rows ``r`` (M + 1, mm) and columns ``psi`` (N,
    rad; the cam angle ``theta = -sigma psi``, so that the polar angle grows with ``psi``), and
    their polar angles (M + 1, N)."""
    rr, pp = np.meshgrid(r, psi, indexing="ij")
    phi, z = groove.wall(side, rr, -groove.layout.sigma * pp)
    phi, z = np.asarray(phi, dtype=np.float64), np.asarray(z, dtype=np.float64)
    return np.stack([rr * np.cos(phi), rr * np.sin(phi), z], axis=-1), phi


def axial_deviation(groove: Any, side: int, points: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """``|z - z_wall(r, phi)|`` (mm) of ``points`` (..., 3) against wall ``side`` at their own
    radius and polar angle: the cam angle whose contact at radius ``r`` lies at ``phi`` is solved
    by Newton's method from ``theta = -sigma psi`` (``psi`` (...): the parameters' midpoint, close
    to it), the derivative by a forward difference of :data:`NEWTON_STEP` rad."""
    sigma = groove.layout.sigma
    r = np.hypot(points[..., 0], points[..., 1])
    target = np.arctan2(points[..., 1], points[..., 0])
    theta = -sigma * np.asarray(psi, dtype=np.float64)
    residual = np.full(r.shape, np.inf)
    for _ in range(NEWTON_ITERATIONS):
        phi, _ = groove.wall(side, r, theta)
        ahead, _ = groove.wall(side, r, theta + NEWTON_STEP)
        residual = (phi - target + math.pi) % (2.0 * math.pi) - math.pi
        theta = theta - residual * NEWTON_STEP / (ahead - phi)
    phi, z = groove.wall(side, r, theta)
    residual = (np.asarray(phi) - target + math.pi) % (2.0 * math.pi) - math.pi
    if not np.all(np.abs(residual) <= NEWTON_TOL):
        return np.full(r.shape, np.inf)  # not converged: the caller refines until it does (or gives up)
    return np.abs(points[..., 2] - z)


def _deviations(groove: Any, side: int, r: np.ndarray, psi: np.ndarray, grid: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Axial deviation (mm) of the wall mesh ``grid`` (M + 1, N, 3; columns periodic) from the exact
    wall at its edge midpoints (:func:`axial_deviation`): along psi (M + 1, N), along r (M, N) and on the
    cells' diagonals (M, N)."""
    psi_next = np.append(psi[1:], psi[0] + 2.0 * math.pi)
    psi_mid = np.broadcast_to(0.5 * (psi + psi_next), grid.shape[:2])
    nxt = np.roll(grid, -1, axis=1)
    return (axial_deviation(groove, side, 0.5 * (grid + nxt), psi_mid),
            axial_deviation(groove, side, 0.5 * (grid[:-1] + grid[1:]), np.broadcast_to(psi, (len(r) - 1, len(psi)))),
            axial_deviation(groove, side, 0.5 * (grid[:-1] + nxt[1:]), psi_mid[:-1]))


def _halve(values: np.ndarray, marked: np.ndarray, periodic: float | None) -> np.ndarray:
    """``values`` (sorted) with the midpoint of every marked interval inserted (interval k from
    ``values[k]`` to the next; ``periodic``: the period closing the last interval, else None)."""
    nxt = np.append(values[1:], values[0] + periodic) if periodic is not None else values[1:]
    return np.sort(np.concatenate([values, 0.5 * (values[: len(nxt)] + nxt)[marked[: len(nxt)]]]))


def wall_grid(groove: Any, tol: float, max_triangles: int, cam: str = "cam") -> tuple[np.ndarray, np.ndarray, list[np.ndarray], list[np.ndarray]]:
    """The rows ``r`` (M + 1), columns ``psi`` (N) and both walls' vertices (M + 1, N, 3) and polar
    angles (M + 1, N), upper then lower, each wall's edge midpoints within :data:`MIDPOINT_FRACTION`
    ``* tol`` of the exact wall (module notes).  GeometryError where that needs more than
    ``max_triangles`` triangles, or where a wall's section folds (its polar angle does not grow
    along a row: undercut)."""
    rim, root = float(groove.rim_radius), float(groove.root_radius)
    count = max(16, math.ceil(2.0 * math.pi / half_chord_step(rim, tol)))
    psi = 2.0 * math.pi * np.arange(count) / count
    r = np.linspace(root, rim, 3)
    limit = MIDPOINT_FRACTION * tol
    for _ in range(MAX_REFINEMENTS):
        if _triangle_count(len(r), len(psi), len(psi)) > max_triangles:
            break
        walls = [_wall_points(groove, side, r, psi) for side in (1, -1)]
        cols = np.zeros(len(psi), dtype=bool)
        rows = np.zeros(len(r) - 1, dtype=bool)
        for side, (grid, phi) in zip((1, -1), walls):
            along_psi, along_r, diagonal = _deviations(groove, side, r, psi, grid)
            if not (np.all(np.isfinite(grid)) and np.all(np.isfinite(along_psi)) and np.all(np.isfinite(along_r))
                    and np.all(np.isfinite(diagonal))):
                raise GeometryError(f"cam '{cam}': the groove walls are not defined everywhere between the root and the rim")
            cols |= np.any(along_psi > limit, axis=0) | np.any(diagonal > limit, axis=0)
            rows |= np.any(along_r > limit, axis=1) | np.any(diagonal > limit, axis=1)
            for row, radius in ((0, root), (-1, rim)):  # the rows the floor and rim bands join (module notes)
                cols |= _turn(phi[row]) > half_chord_step(radius, tol)
        if not cols.any() and not rows.any():
            for which, (_, phi) in zip(("upper", "lower"), walls):
                turn = np.diff(np.concatenate([phi, phi[:, :1] + 2.0 * math.pi], axis=1), axis=1)
                if not np.all(turn > 0.0):
                    i, j = np.unravel_index(int(np.argmin(turn)), turn.shape)
                    raise GeometryError(f"cam '{cam}': the {which} wall folds at radius {r[i]:.4g} mm, cam angle "
                                        f"{math.degrees(-groove.layout.sigma * psi[j]) % 360.0:.2f} deg (undercut): it cannot be meshed")
            return r, psi, [w[0] for w in walls], [w[1] for w in walls]
        psi = _halve(psi, cols, 2.0 * math.pi)
        r = _halve(r, rows, None)
    raise GeometryError(f"cam '{cam}': the barrel's mesh at output.chord_tol_mm = {tol:g} needs more than {max_triangles} triangles "
                        "(the mesh files' size cap): use a larger output.chord_tol_mm")


def half_chord_step(radius: float, tol: float) -> float:
    """The largest angle step (rad) of a circle of ``radius`` mm joined to another by angle:
    ``acos(1 - tol / radius)``, half the chord step of sag ``tol`` (module notes)."""
    return math.acos(max(-1.0, 1.0 - tol / radius))


def _turn(phi: np.ndarray) -> np.ndarray:
    """Steps (rad) between consecutive polar angles of a closed row (the last to the first + 2 pi)."""
    return np.diff(np.append(phi, phi[0] + 2.0 * math.pi))


def _triangle_count(rows: int, columns: int, ring: int) -> int:
    """Triangles of the mesh on ``rows`` wall rows, ``columns`` wall columns and ``ring`` vertices
    on each rim and bore circle: two walls, the floor, two rim bands, the bore and two end faces."""
    return 4 * columns * (rows - 1) + 2 * columns + 2 * (columns + ring) + 2 * ring + 4 * ring


def band(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Two triangles per column between vertex rows ``first`` and ``second`` (ids (N,), columns
    periodic, polar angle increasing): they face ``e_phi x (second - first)``."""
    a, b = first, np.roll(first, -1)
    c, d = np.roll(second, -1), second
    return np.concatenate([np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)])


def zipper(first: np.ndarray, first_angle: np.ndarray, second: np.ndarray, second_angle: np.ndarray) -> np.ndarray:
    """Triangles between two closed rows of vertices (ids ``first`` (n,) and ``second`` (m,), polar
    angles increasing over one turn, rad): merged by angle, each triangle advances one row by one
    vertex (n + m triangles).  They face ``e_phi x (second - first)``, as :func:`band`'s.

    Where two chains in the (angle, height) plane never meet (one always above the other) the
    merge gives a triangulation of the band between them: each diagonal joins two vertices with
    no other vertex between their angles."""
    n, m = len(first), len(second)
    start = int(np.argmin(np.abs((second_angle - first_angle[0] + math.pi) % (2.0 * math.pi) - math.pi)))
    second, second_angle = np.roll(second, -start), np.roll(second_angle, -start)
    a = np.unwrap(np.append(first_angle, first_angle[0] + 2.0 * math.pi))
    b = np.unwrap(np.append(second_angle, second_angle[0] + 2.0 * math.pi))
    b += 2.0 * math.pi * np.round((a[0] - b[0]) / (2.0 * math.pi))
    events = np.concatenate([a[1:], b[1:]])
    which = np.concatenate([np.zeros(n, dtype=bool), np.ones(m, dtype=bool)])  # True: the second row advances
    order = np.lexsort((which, events))
    which = which[order]
    i = np.concatenate([[0], np.cumsum(~which)[:-1]])  # vertex of the first row before each event
    j = np.concatenate([[0], np.cumsum(which)[:-1]])
    fi, fi1 = first[i % n], first[(i + 1) % n]
    sj, sj1 = second[j % m], second[(j + 1) % m]
    return np.where(which[:, None], np.stack([fi, sj1, sj], axis=1), np.stack([fi, fi1, sj], axis=1))


def barrel_solid(groove: Any, chord_tol: float, cam: str = "cam", formats: tuple[str, ...] | None = None) -> "CamSolid":
    """The :class:`~camgen.export.solid.CamSolid` of the barrel cam of ``groove``
    (:class:`camgen.synthesis.barrel.BarrelGroove`): every surface within ``chord_tol`` mm of the
    exact one (module notes), validated by manifold3d.  ``formats``: the mesh formats to be written
    (the size cap, :data:`BYTES_PER_TRIANGLE`; None: every one)."""
    rim, root, length, bore = (float(groove.rim_radius), float(groove.root_radius), float(groove.length), float(groove.bore_radius))
    if not 0.0 <= bore < root < rim:
        raise GeometryError(f"cam '{cam}': the barrel needs 0 <= bore radius < root radius < rim radius (bore {bore:g} mm, root "
                            f"{root:g} mm, rim {rim:g} mm)")
    r, psi, (upper, lower), (phi_up, phi_lo) = wall_grid(groove, chord_tol, triangle_cap(formats), cam)
    low, high = float(np.min(lower[..., 2])), float(np.max(upper[..., 2]))
    if not (low > 0.0 and high < length):
        raise GeometryError(f"cam '{cam}': the groove runs from z = {low:.4g} mm to z = {high:.4g} mm, through an end face of the "
                            f"cylinder (length {length:g} mm)")
    rows, n = upper.shape[:2]
    # the rings of the rim and the bore: steps of half the rim's chord step (module notes)
    ring_count = max(16, math.ceil(2.0 * math.pi / half_chord_step(rim, chord_tol)))
    ring_angle = 2.0 * math.pi * np.arange(ring_count) / ring_count
    c, s = np.cos(ring_angle), np.sin(ring_angle)

    def ring(radius: float, z: float) -> np.ndarray:
        return np.column_stack([radius * c, radius * s, np.full(ring_count, z)])

    blocks = [upper.reshape(-1, 3), lower.reshape(-1, 3), ring(rim, 0.0), ring(rim, length)]
    up = np.arange(rows * n).reshape(rows, n)
    lo = up + rows * n
    rim0 = 2 * rows * n + np.arange(ring_count)
    rim1 = rim0 + ring_count
    faces = [band(up[i], up[i + 1]) for i in range(rows - 1)]  # facing -z: material above the upper wall
    faces += [band(lo[i + 1], lo[i]) for i in range(rows - 1)]  # facing +z
    faces += [zipper(lo[0], phi_lo[0], up[0], phi_up[0]),  # the floor, facing +r
              zipper(rim0, ring_angle, lo[-1], phi_lo[-1]), zipper(up[-1], phi_up[-1], rim1, ring_angle)]  # the rim bands
    return closed_body(blocks, faces, rim0, rim1, ring, bore, length, rim, f"cam '{cam}': the barrel", "the walls cross", chord_tol)


def closed_body(blocks: list[np.ndarray], faces: list[np.ndarray], outer0: np.ndarray, outer1: np.ndarray, ring: Any, bore: float,
                length: float, rim: float, what: str, crossing: str, chord_tol: float) -> "CamSolid":
    """A barrel body's mesh closed and checked: ``blocks`` of vertices (mm) and ``faces`` so far,
    whose outer rings at z = 0 and z = length are the vertex indices ``outer0``, ``outer1``; the
    bore (radius ``bore`` mm, 0: none, then a fan to the axis closes each end face) and the end
    faces added (``ring(radius, z)``: a ring's vertices on the outer rings' angles).  manifold3d
    must find one closed 2-manifold of genus 1 with a bore (0 without); else a
    :class:`GeometryError` saying ``what`` cannot be meshed at ``chord_tol`` and why (``crossing``)."""
    import manifold3d

    from camgen.export.solid import CamSolid

    ring_count = outer0.size
    if bore > 0.0:
        blocks = blocks + [ring(bore, 0.0), ring(bore, length)]
        bore0 = outer0 + 2 * ring_count
        bore1 = bore0 + ring_count
        faces = faces + [band(bore1, bore0), band(bore0, outer0), band(outer1, bore1)]  # bore (facing -r), bottom (-z), top (+z)
    else:
        blocks = blocks + [np.array([[0.0, 0.0, 0.0], [0.0, 0.0, length]])]
        centre = outer1[-1] + 1
        faces = faces + [np.column_stack([np.full(ring_count, centre), np.roll(outer0, -1), outer0]),
                         np.column_stack([np.full(ring_count, centre + 1), outer1, np.roll(outer1, -1)])]
    vertices = np.concatenate(blocks)
    triangles = np.concatenate(faces).astype(np.int64)
    if not np.all(np.isfinite(vertices)):
        raise GeometryError(f"{what}'s surfaces are not finite everywhere")
    solid = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=vertices, tri_verts=triangles.astype(np.uint64)))
    status = solid.status()
    genus = int(solid.genus()) if status == manifold3d.Error.NoError else -1
    pieces = len(solid.decompose()) if status == manifold3d.Error.NoError else 0
    if status != manifold3d.Error.NoError or pieces != 1 or genus != (1 if bore > 0.0 else 0):
        why = f"manifold3d: {status}" if status != manifold3d.Error.NoError else f"{pieces} bodies of genus {genus}"
        raise GeometryError(f"{what} cannot be meshed at chord_tol_mm = {chord_tol:g} ({why}): {crossing}")
    return CamSolid(vertices, triangles, float(solid.volume()), math.pi * (rim * rim - bore * bore), genus, "barrel")
