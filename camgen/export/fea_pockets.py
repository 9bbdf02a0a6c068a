"""FEA volume meshes of a body with pockets: the outline extruded by the thickness, minus bore and
keyway, minus each pocket (:class:`camgen.kinds.base.Pocket`) from the top face down its depth.

The section's loops (the profile polygon, the hole polygon, every pocket wall's polygon, each at
the chord tolerance and sized as in :mod:`camgen.export.fea`) do not cross; each loop's *face* is
the region inside it and outside the loops directly inside it (found by containment: the
smallest loop around a loop's first vertex is its parent).  Each face is material from z = 0 up
to its *top*: the thickness (the face inside the profile, an island inside a pocket's inner
wall), a pocket's floor (``thickness - depth``: the face inside the pocket's ``walls[0]``, whose
children must be exactly its other walls) or 0 (the hole; a pocket through the body).  Between a
loop's face and its parent's the material's side face runs from the lower top to the higher: the
loop's *strip* (a wall's strip is the pocket's wall, floor to top face).  Nothing names a form.

* Wedges: gmsh meshes the faces of the section (one plane surface per face with material, the
  walls their shared edges, so every triangle lies inside or outside each pocket); the triangles
  are extruded through the layers of :func:`camgen.export.fea.layer_levels` (a layer boundary at
  every floor) and a triangle's wedges stop at its face's top.  Nodes are shared between
  neighbouring wedges (one node per triangle vertex and level; nodes of no wedge are dropped).
* Tetrahedra: the same body in gmsh's built-in kernel, face by face: each strip one plane
  quadrilateral per polygon edge, each level's horizontal faces one plane surface per connected
  region; gmsh meshes the surfaces and then the volume (HXT), sizes graded as in
  :mod:`camgen.export.fea`.

Node sets: PROFILE (the profile's strip), BORE (the hole's), BOTTOM (z = 0), TOP (z = thickness),
one per wall named by its layer (the wall's strip: floor to top face) and one per pocket floor
(``<POCKET>_FLOOR``, e.g. GROOVE_FLOOR; none for a pocket through the body).  The mesh's volume
(the sum of its elements') must equal the polygons' (:func:`camgen.export.pocket_solid.pocketed_volume`)
within :data:`camgen.export.solid.VOLUME_RTOL`, or the mesh is refused: a wall crossing another,
the bore or the outline cannot pass.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np

from camgen.errors import ExportError, GeometryError

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.contour import Contour
    from camgen.export.fea import Section, VolumeMesh
    from camgen.kinds.base import Pocket

__all__ = ["PART_SETS", "Arrangement", "arrangement", "body_volume_mesh", "floor_set_name", "pocket_volume_mesh"]

#: Node-set names of the part (a wall's layer or a floor's set may not take them).
PART_SETS = ("NALL", "CAM", "PROFILE", "BORE", "BOTTOM", "TOP")


def floor_set_name(pocket: "Pocket") -> str:
    """The node set of ``pocket``'s floor: its name in capitals and ``_FLOOR`` (GROOVE_FLOOR)."""
    return f"{pocket.name.upper()}_FLOOR"


def _shoelace(loop: np.ndarray) -> float:
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _inside(point: np.ndarray, polygon: np.ndarray) -> bool:
    """Whether ``point`` (2,) lies inside the closed ``polygon`` (n, 2): the even-odd crossing
    count of the ray towards +x (Shimrat's algorithm)."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    straddles = (a[:, 1] > point[1]) != (b[:, 1] > point[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (point[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(straddles & (x > point[0])) % 2)


@dataclass(frozen=True)
class Arrangement:
    """The loops of the section and their faces (see the module notes).

    ``polygons``/``sizes``: each loop counter-clockwise (mm) and the element size at its
    vertices; ``names``: PROFILE, BORE or the wall's layer; ``parent``: the loop directly around
    it (-1 for the profile); ``top``: the height (mm) up to which the loop's face is material (0:
    none); ``strip``: (low, high) heights of the loop's side face; ``floor_of``: the pocket whose
    floor each loop's face is (-1: none).
    """

    polygons: tuple[np.ndarray, ...]
    sizes: tuple[np.ndarray, ...]
    names: tuple[str, ...]
    parent: tuple[int, ...]
    top: tuple[float, ...]
    strip: tuple[tuple[float, float], ...]
    floor_of: tuple[int, ...]

    def children(self, i: int) -> list[int]:
        """The loops directly inside loop ``i``."""
        return [j for j, p in enumerate(self.parent) if p == i]


def arrangement(section: "Section", thickness: float, pockets: "Sequence[Pocket]", cam: str = "cam") -> Arrangement:
    """The loops and faces of ``section`` with ``pockets`` (their walls in ``section.walls``, in
    order).  Raises :class:`GeometryError` naming the cam where the walls do not nest as pockets
    must (a wall outside the outline or inside the bore, a loop inside a pocket besides its own
    walls, a pocket through the body around an island)."""
    polygons = [section.outer] + ([section.hole] if section.hole is not None else []) + [w[1] for w in section.walls]
    sizes = [section.outer_sizes] + ([section.hole_sizes] if section.hole is not None else []) + [w[2] for w in section.walls]
    names = ["PROFILE"] + (["BORE"] if section.hole is not None else []) + [w[0] for w in section.walls]
    first_wall = len(polygons) - len(section.walls)
    for i, polygon in enumerate(polygons):
        if _shoelace(polygon) < 0:  # counter-clockwise, each vertex's size with it
            polygons[i], sizes[i] = polygon[::-1], sizes[i][::-1]
    areas = [abs(_shoelace(p)) for p in polygons]
    n = len(polygons)
    parent = [-1] * n
    for i in range(1, n):
        around = [j for j in range(n) if j != i and _inside(polygons[i][0], polygons[j])]
        if 0 not in around:
            raise GeometryError(f"cam '{cam}': the {names[i]} loop lies outside the profile")
        parent[i] = min(around, key=lambda j: areas[j])
    if any(_inside(polygons[0][0], p) for p in polygons[1:]):
        raise GeometryError(f"cam '{cam}': the profile lies inside the {names[1]} loop")
    # each loop's face: material up to the thickness, a pocket's floor or nowhere (0)
    top = [float(thickness)] * n
    floor_of = [-1] * n
    if section.hole is not None:
        top[1] = 0.0
    k = first_wall
    owner: dict[int, tuple[int, list[int]]] = {}
    for p, pocket in enumerate(pockets):
        ids = list(range(k, k + len(pocket.walls)))
        k += len(pocket.walls)
        owner[ids[0]] = (p, ids[1:])
        top[ids[0]] = max(0.0, float(thickness - pocket.depth))
        floor_of[ids[0]] = p
    for i in range(n):
        inner = [j for j in range(n) if parent[j] == i]
        if top[i] == 0.0 and i not in owner and inner:
            raise GeometryError(f"cam '{cam}': the wall {names[inner[0]]} lies inside the bore")
        if i in owner:
            p, islands = owner[i]
            if sorted(inner) != sorted(islands):
                stray = sorted(set(inner) ^ set(islands))
                raise GeometryError(f"cam '{cam}': pocket {pockets[p].name!r} (inside {names[i]}, outside "
                                    f"{', '.join(names[j] for j in islands) or 'no other wall'}) holds or misses the "
                                    f"{', '.join(names[j] for j in stray)} loop: its walls cross the bore, the outline or another wall")
            if top[i] == 0.0 and islands:
                raise GeometryError(f"cam '{cam}': pocket {pockets[p].name!r} goes through the body around "
                                    f"{', '.join(names[j] for j in islands)}: it would cut the body in two")
    strip = []
    for i in range(n):
        outside = top[parent[i]] if parent[i] >= 0 else 0.0
        strip.append((min(top[i], outside), max(top[i], outside)))
        if strip[-1][0] == strip[-1][1]:  # not expected: every loop separates material from a pocket or the outside
            raise GeometryError(f"cam '{cam}': the {names[i]} loop has material of one height on both sides")
    return Arrangement(tuple(polygons), tuple(sizes), tuple(names), tuple(parent), tuple(top), tuple(strip), tuple(floor_of))


def _check_names(pockets: "Sequence[Pocket]", thickness: float) -> None:
    """Refuse pockets whose walls or floors would not make distinct, valid node-set names."""
    from camgen.export.pocket import check_pockets

    check_pockets(pockets, thickness, PART_SETS)
    seen = set(PART_SETS) | {wall.layer.upper() for pocket in pockets for wall in pocket.walls}
    for pocket in pockets:
        name = floor_set_name(pocket)
        if name in seen:
            raise ExportError(f"pocket {pocket.name!r}: its floor's node set {name} is taken by another set")
        seen.add(name)
    for name in seen:
        if not re.fullmatch(r"[A-Z][A-Z0-9_]{0,79}", name):
            raise ExportError(f"node set {name!r} is not a CalculiX/Abaqus name (a letter, then letters, digits or _, 80 at most)")


def _notes(pockets: "Sequence[Pocket]", thickness: float) -> dict[str, str]:
    """The .inp header's words on each pocket set."""
    notes = {}
    for pocket in pockets:
        floor = max(0.0, thickness - pocket.depth)
        for wall in pocket.walls:
            notes[wall.layer] = f"{wall.layer} (wall of pocket '{pocket.name}', z = {floor:g} to {thickness:g})"
        if floor > 0.0:
            notes[floor_set_name(pocket)] = f"{floor_set_name(pocket)} (floor of pocket '{pocket.name}', z = {floor:g})"
    return notes


def _ordered_sets(sets: dict, pockets: "Sequence[Pocket]") -> dict:
    """PROFILE, BORE, BOTTOM, TOP, then each pocket's walls and floor."""
    order = ["PROFILE", "BORE", "BOTTOM", "TOP"]
    for pocket in pockets:
        order += [wall.layer for wall in pocket.walls] + [floor_set_name(pocket)]
    return {name: np.unique(sets[name]) for name in order if name in sets}


def _check_volume(nodes: np.ndarray, cells: np.ndarray, elements: str, section: "Section", arr: Arrangement,
                  pockets: "Sequence[Pocket]", thickness: float, cam: str, chord_tol: float) -> float:
    """The mesh's volume (mm^3), refused unless it is the polygons' within VOLUME_RTOL."""
    from camgen.export.pocket_solid import pocketed_volume
    from camgen.export.solid import VOLUME_RTOL

    p = nodes[cells]
    if elements == "wedge":  # a prism with parallel triangles: base area x height
        a, b, c = p[:, 0, :2], p[:, 1, :2], p[:, 2, :2]
        area = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
        volume = float(np.sum(area * (p[:, 3, 2] - p[:, 0, 2])))
    else:
        volume = float(np.sum(np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))) / 6.0)
    first = 1 + (section.hole is not None)
    walls, k = [], first
    for pocket in pockets:
        walls.append(list(arr.polygons[k : k + len(pocket.walls)]))
        k += len(pocket.walls)
    expected = pocketed_volume(arr.polygons[0], arr.polygons[1] if section.hole is not None else None, walls, [float(p.depth) for p in pockets], thickness)
    if not abs(volume - expected) <= VOLUME_RTOL * abs(expected):
        raise GeometryError(f"cam '{cam}': the FEA mesh of the body with its pockets at chord_tol_mm = {chord_tol:g} has volume "
                            f"{volume:.9g} mm^3 where its polygons give {expected:.9g} mm^3: a wall crosses another, the bore or the outline")
    return volume


# --------------------------------------------------------------------------------------------
# Wedges
# --------------------------------------------------------------------------------------------
def _face_triangles(arr: Arrangement, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[np.ndarray]]:
    """gmsh's Frontal-Delaunay triangulation of the faces with material: points (k, 2) (the loops'
    vertices first, in order), counter-clockwise triangles (t, 3), each triangle's face (t,) and
    each loop's nodes (indices into points)."""
    from camgen.export.fea import GmshSession, Section, add_polygon_loops, node_table, size_field

    with GmshSession("the section with its pockets") as gmsh:
        geo = gmsh.model.geo
        curve_loops, lines_of = add_polygon_loops(geo, zip(arr.polygons, arr.sizes))
        surfaces = {}
        for i in range(len(arr.polygons)):
            if arr.top[i] > 0.0:
                surfaces[i] = geo.addPlaneSurface([curve_loops[i]] + [curve_loops[j] for j in arr.children(i)])
        geo.synchronize()
        groups = [gmsh.model.addPhysicalGroup(1, lines) for lines in lines_of]
        # the size field only reads the section's h
        size_field(gmsh, Section(arr.polygons[0], None, arr.sizes[0], None, h, 0.0), [t for lines in lines_of for t in lines], [])
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
        gmsh.model.mesh.generate(2)
        coords, lookup = node_table(gmsh)
        triangles, face = [], []
        for i, surface in surfaces.items():
            _, node_tags = gmsh.model.mesh.getElementsByType(2, surface)
            tris = lookup[np.asarray(node_tags, dtype=np.int64).reshape(-1, 3)]
            triangles.append(tris)
            face.append(np.full(len(tris), i, dtype=np.int64))
        loop_nodes = [np.unique(lookup[np.asarray(gmsh.model.mesh.getNodesForPhysicalGroup(1, g)[0], dtype=np.int64)]) for g in groups]
    polygon = np.concatenate(arr.polygons)
    k = len(polygon)
    if len(coords) < k or not np.array_equal(coords[:k, :2], polygon):
        raise GeometryError("gmsh did not keep the section's polygon vertices as its first nodes")
    points = coords[:, :2].copy()
    tris = np.concatenate(triangles)
    p = points[tris]
    twice = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    if np.any(twice == 0):
        raise GeometryError("gmsh's section triangulation has a triangle of no area")
    tris = np.where((twice < 0)[:, None], tris[:, ::-1], tris)
    return points, np.ascontiguousarray(tris), np.concatenate(face), loop_nodes


def _wedges(section: "Section", arr: Arrangement, pockets: "Sequence[Pocket]", thickness: float) -> "VolumeMesh":
    from camgen.export.fea import VolumeMesh, edge_range, layer_levels, triangle_angles

    points, triangles, face, loop_nodes = _face_triangles(arr, section.h)
    least = float(triangle_angles(points, triangles).min())
    levels = layer_levels(thickness, section.h, section.floors)
    layers = len(levels) - 1
    k = len(points)
    top_level = np.searchsorted(levels, np.asarray(arr.top)[face])  # each triangle's wedges stop there
    if not np.array_equal(levels[top_level], np.asarray(arr.top)[face]):
        raise GeometryError("a pocket's floor is not a layer boundary")  # not expected (layer_levels)
    layer, tri = np.nonzero(np.arange(layers)[:, None] < top_level[None, :])
    base = layer[:, None] * k + triangles[tri]
    cells = np.concatenate([base, base + k], axis=1).astype(np.int64)
    nodes = np.concatenate([np.repeat(points[None], layers + 1, axis=0),
                            np.broadcast_to(levels[:, None, None], (layers + 1, k, 1))], axis=2).reshape(-1, 3)
    sets: dict[str, np.ndarray] = {}
    for i, name in enumerate(arr.names):  # each loop's strip: its nodes at the levels from low to high
        lo, hi = (int(np.searchsorted(levels, z)) for z in arr.strip[i])
        sets[name] = ((np.arange(lo, hi + 1) * k)[:, None] + loop_nodes[i][None]).ravel()
    for i, p in enumerate(arr.floor_of):
        if p >= 0 and arr.top[i] > 0.0:
            sets[floor_set_name(pockets[p])] = int(top_level[face == i][0]) * k + np.unique(triangles[face == i])
    used = np.unique(cells)
    sets["BOTTOM"] = used[used < k]
    sets["TOP"] = used[used >= layers * k]
    remap = np.full(len(nodes), -1, dtype=np.int64)
    remap[used] = np.arange(used.size)
    nodes, cells = nodes[used], remap[cells]
    sets = {name: remap[members] for name, members in sets.items()}
    if any(np.any(members < 0) for members in sets.values()):
        raise GeometryError("a node set of the pocketed body holds a node of no wedge")  # not expected
    heights = np.diff(levels)
    shortest, longest = edge_range(points, triangles)
    figures = {"elements": "wedge", "element_count": int(len(cells)), "node_count": int(len(nodes)), "layers": layers,
               "element_size_mm": section.h, "least_triangle_angle_deg": least,
               "shortest_edge_mm": min(shortest, float(heights.min())), "longest_edge_mm": max(longest, float(heights.max())),
               "layer_height_mm": float(heights.min())}
    return VolumeMesh(nodes, cells, "wedge", _ordered_sets(sets, pockets), thickness, layers, section.h, figures,
                      _notes(pockets, thickness))


# --------------------------------------------------------------------------------------------
# Tetrahedra
# --------------------------------------------------------------------------------------------
def _regions(arr: Arrangement, z: float) -> list[tuple[int, list[tuple[int, float]]]]:
    """The horizontal faces of the body at height ``z``: for each connected region, the face it
    starts from and its loops as (loop, height) pairs, the region's outer loop first.  At z = 0
    the bottom (every face with material); above, the faces whose top is ``z``."""
    n = len(arr.polygons)
    member = [arr.top[i] > 0.0 if z == 0.0 else arr.top[i] == z for i in range(n)]
    out = []
    for root in range(n):
        if not member[root] or (arr.parent[root] >= 0 and member[arr.parent[root]]):
            continue
        loops, stack = [(root, z)], [root]
        while stack:
            i = stack.pop()
            for j in arr.children(i):
                if member[j]:
                    stack.append(j)
                else:
                    loops.append((j, z))
        out.append((root, loops))
    return out


def _tetrahedra(section: "Section", arr: Arrangement, pockets: "Sequence[Pocket]", thickness: float) -> "VolumeMesh":
    from camgen.export.fea import GmshSession, VolumeMesh, node_table, size_field, tetra_figures, tidy_tetrahedra

    with GmshSession("the body with its pockets") as gmsh:
        geo = gmsh.model.geo
        rings: dict[tuple[int, float], int] = {}  # (loop, height) -> curve loop
        strips: dict[int, list[int]] = {}  # loop -> its quadrilaterals
        lines_all: list[int] = []
        tag = 1
        for i, (polygon, sizes) in enumerate(zip(arr.polygons, arr.sizes)):
            n = len(polygon)
            lo, hi = arr.strip[i]
            ids = {}
            for z in (lo, hi):
                ids[z] = list(range(tag, tag + n))
                for t, (x, y), size in zip(ids[z], polygon.tolist(), sizes.tolist()):
                    geo.addPoint(x, y, z, size, t)
                tag += n
            edges = {}
            for z in (lo, hi):
                edges[z] = [geo.addLine(ids[z][j], ids[z][(j + 1) % n]) for j in range(n)]
                rings[(i, z)] = geo.addCurveLoop(edges[z])
            up = [geo.addLine(ids[lo][j], ids[hi][j]) for j in range(n)]
            lines_all += edges[lo] + edges[hi] + up
            strips[i] = [geo.addPlaneSurface([geo.addCurveLoop([edges[lo][j], up[(j + 1) % n], -edges[hi][j], -up[j]])])
                         for j in range(n)]
        horizontal: dict[float, list[int]] = {}
        floors: dict[int, int] = {}  # pocket -> its floor's surface
        for z in sorted({0.0} | {t for t in arr.top if t > 0.0}):
            for root, loops in _regions(arr, z):
                if any(key not in rings for key in loops):  # not expected: every loop's strip ends at its faces' tops
                    raise GeometryError("a face of the pocketed body has no edge at its height")
                surface = geo.addPlaneSurface([rings[key] for key in loops])
                horizontal.setdefault(z, []).append(surface)
                if z > 0.0 and arr.floor_of[root] >= 0:
                    floors[arr.floor_of[root]] = surface
        surfaces = [s for faces in strips.values() for s in faces] + [s for faces in horizontal.values() for s in faces]
        volume = geo.addVolume([geo.addSurfaceLoop(surfaces)])
        geo.synchronize()
        groups: dict[str, tuple[int, float | None]] = {name: (gmsh.model.addPhysicalGroup(2, strips[i]), None)
                                                       for i, name in enumerate(arr.names)}
        groups["BOTTOM"] = (gmsh.model.addPhysicalGroup(2, horizontal[0.0]), 0.0)
        groups["TOP"] = (gmsh.model.addPhysicalGroup(2, horizontal[float(thickness)]), float(thickness))
        for p, surface in floors.items():
            groups[floor_set_name(pockets[p])] = (gmsh.model.addPhysicalGroup(2, [surface]), float(thickness - pockets[p].depth))
        gmsh.model.addPhysicalGroup(3, [volume])
        size_field(gmsh, section, lines_all, surfaces)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.Algorithm3D", 10)  # HXT
        gmsh.option.setNumber("Mesh.Optimize", 1)
        gmsh.model.mesh.generate(3)
        coords, lookup = node_table(gmsh)
        _, node_tags = gmsh.model.mesh.getElementsByType(4)  # 4-node tetrahedra
        tets = lookup[np.asarray(node_tags, dtype=np.int64).reshape(-1, 4)]
        sets: dict[str, np.ndarray] = {}
        heights: dict[str, float | None] = {}
        for name, (group, level) in groups.items():
            tags, _ = gmsh.model.mesh.getNodesForPhysicalGroup(2, group)
            sets[name] = np.unique(lookup[np.asarray(tags, dtype=np.int64)])
            heights[name] = level
    for name, level in heights.items():  # the nodes of a horizontal face at its height exactly (gmsh's plane maps round off)
        if level is not None:
            if np.max(np.abs(coords[sets[name], 2] - level), initial=0.0) > 1e-9 * max(1.0, thickness):
                raise GeometryError(f"gmsh put a node of {name} off its plane z = {level:g}")  # not expected
            coords[sets[name], 2] = level
    coords, tets, sets = tidy_tetrahedra(coords, tets, sets)
    figures = tetra_figures(coords, tets, section.h)
    return VolumeMesh(coords, np.ascontiguousarray(tets, dtype=np.int64), "tetra", _ordered_sets(sets, pockets), thickness, 0,
                      section.h, figures, _notes(pockets, thickness))


def pocket_volume_mesh(section: "Section", body: "BodySpec", pockets: "Sequence[Pocket]", elements: str, chord_tol: float,
                       cam: str = "cam") -> "VolumeMesh":
    """The FEA mesh (``elements``: "wedge" or "tetra") of the body of ``section`` (its walls and
    floors those of ``pockets``) less each pocket; see the module notes.  Raises
    :class:`GeometryError` naming the cam where the pockets do not fit the body."""
    thickness = float(body.thickness)
    _check_names(pockets, thickness)
    arr = arrangement(section, thickness, pockets, cam)
    mesh = _wedges(section, arr, pockets, thickness) if elements == "wedge" else _tetrahedra(section, arr, pockets, thickness)
    _check_volume(mesh.nodes, mesh.cells, elements, section, arr, pockets, thickness, cam, chord_tol)
    return mesh


def body_volume_mesh(contour: "Contour", body: "BodySpec", chord_tol: float, element_size: float | None = None,
                     elements: str = "wedge", pockets: "Sequence[Pocket]" = (), cam: str = "cam") -> "VolumeMesh":
    """The FEA mesh of the cam body with ``pockets`` (none: :func:`camgen.export.fea.volume_mesh`,
    the prismatic body), at ``chord_tol`` mm, element size ``element_size`` mm (None: the default)."""
    from camgen.export.fea import FEA_ELEMENTS, section_outline, volume_mesh
    from camgen.errors import ParameterError

    if not pockets:
        return volume_mesh(contour, body, chord_tol, element_size, elements)
    if elements not in FEA_ELEMENTS:
        raise ParameterError("fea_elements", elements, f"one of {', '.join(FEA_ELEMENTS)}")
    return pocket_volume_mesh(section_outline(contour, body, chord_tol, element_size, pockets), body, pockets, elements, chord_tol, cam)
