"""The surface mesh of a body with pockets: the outline extruded by the thickness, minus bore and
keyway, minus each pocket from the top face down its depth.

Every vertex is a vertex of a flattened polygon (the outline, the hole, a pocket wall, each at
the chord tolerance: :meth:`camgen.contour.Contour.flatten`, :func:`camgen.export.solid.bore_polygon`)
at one of the body's heights (0, each pocket's floor ``thickness - depth``, the thickness), with
the polygon's own coordinates: no boolean moves a vertex.  The faces:

* the bottom cap (z = 0, facing -z): outline minus hole;
* the top cap (z = thickness): outline minus hole minus every pocket;
* each pocket's floor (facing +z): inside ``walls[0]``, outside the other walls;
* the side walls, two triangles per polygon edge: the outline and the hole from 0 to the
  thickness, each pocket wall from its floor to the thickness.

Each cap is triangulated by manifold3d (``manifold3d.triangulate``: the caps' loops, each
oriented so that the material lies on its left, index the vertices as given); every loop is
oriented that way for the side walls too, so each side quad faces out of the material.  A pocket
as deep as the body (a through slot) has no floor and its walls join the bottom cap and run
from 0.  The result is handed to manifold3d, whose status says it is a closed, consistently
oriented 2-manifold; its volume must equal the polygons' (shoelace) areas times their heights
within :data:`camgen.export.solid.VOLUME_RTOL`.  Loops that cross or overlap (a wall through the
bore, the outline or another pocket) are refused before: the area manifold3d's polygon clipping
finds for each cap must be the sum of its loops' signed areas (:func:`_require_nested`).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

from camgen.errors import GeometryError

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.contour import Contour
    from camgen.export.solid import CamSolid
    from camgen.kinds.base import Pocket

__all__ = ["CLIPPER_SNAP", "pocket_solid", "pocketed_volume"]


def _shoelace(loop: np.ndarray) -> float:
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def pocketed_volume(outer: np.ndarray, hole: np.ndarray | None, walls: Sequence[Sequence[np.ndarray]], depths: Sequence[float],
                    thickness: float) -> float:
    """Volume (mm^3) of the prism over ``outer`` minus ``hole`` (counter-clockwise polygons, mm)
    of height ``thickness``, minus each pocket (its walls' polygons, counter-clockwise: inside the
    first, outside the others) times its depth: the shoelace areas."""
    section = _shoelace(outer) - (_shoelace(hole) if hole is not None else 0.0)
    pockets = sum(depth * (_shoelace(loops[0]) - sum(_shoelace(loop) for loop in loops[1:])) for loops, depth in zip(walls, depths))
    return section * thickness - pockets


#: How far (mm) manifold3d's cross-section (Clipper2, 8 decimals) may move a vertex: the areas
#: compared by :func:`_require_nested` may differ by this times the loops' length (twice, for margin).
CLIPPER_SNAP = 1e-8


def _require_nested(loops: list[np.ndarray], what: str, cam: str, chord_tol: float) -> None:
    """Refuse ``loops`` (material on their left) that cross or overlap: their region's area, by
    manifold3d's polygon clipping (points of positive winding number), must be the sum of their
    signed (shoelace) areas, which it is exactly when every point is inside at most one more
    counter-clockwise loop than clockwise ones (nested loops); a wall across the bore, the
    outline or another pocket's wall makes them differ by the overlap."""
    from manifold3d import CrossSection, FillRule

    signed = sum(_shoelace(loop) for loop in loops)
    clipped = float(CrossSection(loops, FillRule.Positive).area())
    length = sum(float(np.sum(np.hypot(*(np.roll(loop, -1, axis=0) - loop).T))) for loop in loops)
    if not abs(clipped - signed) <= 2.0 * CLIPPER_SNAP * length:
        raise GeometryError(f"cam '{cam}': at chord_tol_mm = {chord_tol:g} the loops of {what} cross or overlap (the region's area "
                            f"{clipped:.9g} mm^2, its loops' signed areas {signed:.9g} mm^2): a pocket wall meets the bore, the outline "
                            "or another wall")


class _Mesh:
    """Vertices placed level by level: each loop at a height gets a block of consecutive ids."""

    def __init__(self) -> None:
        self.blocks: list[np.ndarray] = []
        self.count = 0
        self.faces: list[np.ndarray] = []

    def place(self, loop: np.ndarray, z: float) -> np.ndarray:
        """Ids of ``loop``'s vertices at height ``z`` (a new block)."""
        self.blocks.append(np.column_stack([loop, np.full(len(loop), z)]))
        ids = self.count + np.arange(len(loop))
        self.count += len(loop)
        return ids

    def cap(self, loops: list[np.ndarray], ids: list[np.ndarray], up: bool) -> None:
        """Triangles of the region the ``loops`` (material on their left) bound, facing +z
        (``up``) or -z; ``ids``: the loops' vertex ids at the cap's height."""
        import manifold3d

        local = np.asarray(manifold3d.triangulate(loops), dtype=np.int64).reshape(-1, 3)
        tris = np.concatenate(ids)[local]
        self.faces.append(tris if up else tris[:, ::-1])

    def side(self, low: np.ndarray, high: np.ndarray) -> None:
        """Two triangles per edge between a loop's ids at its lower and upper height (material
        on the loop's left: the quads face out)."""
        a, b = low, np.roll(low, -1)
        c, d = np.roll(high, -1), high
        self.faces.append(np.concatenate([np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)]))


def pocket_solid(contour: "Contour", spec: "BodySpec", pockets: "Sequence[Pocket]", chord_tol: float, cam: str = "cam") -> "CamSolid":
    """The :class:`~camgen.export.solid.CamSolid` of the body with ``pockets`` (see the module
    notes): vertices on the flattened polygons at ``chord_tol`` mm, validated by manifold3d; the
    bore and keyway checked against the outline first (:func:`camgen.export.solid.check_wall`).

    Raises :class:`GeometryError` naming the cam where the faces do not bound one closed body of
    the polygons' volume (a wall crossing another, the bore or the outline; a through pocket
    that cuts the body in two).
    """
    import manifold3d

    from camgen.export.pocket import check_pockets
    from camgen.export.solid import VOLUME_RTOL, CamSolid, bore_polygon, check_wall

    check_pockets(pockets, spec.thickness)
    check_wall(contour, spec, chord_tol, cam)  # the bore and keyway against the outline
    thickness = spec.thickness
    outer = contour.flatten(chord_tol)
    hole = bore_polygon(spec, chord_tol)
    part = [outer] + ([hole[::-1]] if hole is not None else [])  # material on the left: outline CCW, hole CW
    mesh = _Mesh()
    bottom_loops, bottom = list(part), [mesh.place(loop, 0.0) for loop in part]
    top_loops, top = list(part), [mesh.place(loop, thickness) for loop in part]
    for down, up in zip(bottom, top):
        mesh.side(down, up)
    walls, depths = [], []
    for pocket in pockets:
        loops = [wall.contour.flatten(chord_tol) for wall in pocket.walls]
        walls.append(loops)
        depths.append(float(pocket.depth))
        floor = thickness - pocket.depth
        # the material beside the pocket: outside walls[0] (clockwise), inside the others (counter-clockwise)
        around = [loops[0][::-1]] + loops[1:]
        high = [mesh.place(loop, thickness) for loop in around]
        top_loops += around
        top += high
        if floor > 0.0:
            low = [mesh.place(loop, floor) for loop in around]
            # the floor: inside walls[0], outside the others (the reverse of the loops around it), facing up
            mesh.cap([loops[0]] + [loop[::-1] for loop in loops[1:]], [low[0][::-1]] + [ids[::-1] for ids in low[1:]], up=True)
        else:  # through the body: the walls join the bottom face
            low = [mesh.place(loop, 0.0) for loop in around]
            bottom_loops += around
            bottom += low
        for lo, hi in zip(low, high):
            mesh.side(lo, hi)
    mesh.cap(bottom_loops, bottom, up=False)
    mesh.cap(top_loops, top, up=True)
    floors = [[loops[0]] + [loop[::-1] for loop in loops[1:]] for loops in walls]
    for what, loops in [("the top face", top_loops), ("the bottom face", bottom_loops)] + [
            (f"the floor of pocket {p.name!r}", f) for p, f in zip(pockets, floors)]:
        _require_nested(loops, what, cam, chord_tol)
    vertices = np.concatenate(mesh.blocks)
    triangles = np.concatenate(mesh.faces)
    solid = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=vertices, tri_verts=triangles.astype(np.uint64)))
    expected = pocketed_volume(outer, hole, walls, depths, thickness)
    status = solid.status()
    volume = float(solid.volume()) if status == manifold3d.Error.NoError else float("nan")
    pieces = len(solid.decompose()) if status == manifold3d.Error.NoError else 0
    if status != manifold3d.Error.NoError or pieces != 1 or not abs(volume - expected) <= VOLUME_RTOL * abs(expected):
        why = (f"manifold3d: {status}" if status != manifold3d.Error.NoError else f"{pieces} separate bodies" if pieces != 1
               else f"volume {volume:.9g} mm^3 where its polygons give {expected:.9g} mm^3: a wall crosses another, the bore or the outline")
        raise GeometryError(f"cam '{cam}': the body with its pockets cannot be meshed at chord_tol_mm = {chord_tol:g} ({why})")
    area = _shoelace(outer) - (_shoelace(hole) if hole is not None else 0.0)
    return CamSolid(vertices, triangles, volume, area, int(solid.genus()), "pockets")
