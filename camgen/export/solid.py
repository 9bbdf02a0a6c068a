"""Extruded cam solids: profile minus shaft bore and keyway; mesh files.

The profile is flattened at the chord tolerance; the hole is the bore circle's inscribed
polygon at the same chord tolerance united with the keyway rectangle (from the axis out to
``bore radius + depth``; :func:`bore_polygon`).  Before anything the wall left between
bore/keyway and profile is measured; less than ``min_wall`` is a :class:`GeometryError`.

The section between the two loops is triangulated in linear time by
:mod:`camgen.export.section_fill` (rings of interior vertices between profile and bore; it
relies on both loops being star-shaped about the axis and on a circle separating them, and
checks both); the prism over it (bottom cap, top cap, two triangles per outline edge) is handed
to manifold3d, whose status and genus guarantee a closed, consistently oriented 2-manifold.
Where the fill's assumptions fail, manifold3d triangulates the cross-section itself (time about
N^1.9).  The vertex coordinates are the flattened polygons' own values either way: manifold3d's
cross-section (Clipper2, 8 decimals) snaps them to a grid, by up to 5e-9 mm, and :func:`unsnap`
maps each back to the nearest polygon vertex within :data:`MANIFOLD_SNAP`.  Where that cannot
be done safely (a vertex farther than that from every polygon vertex, two vertices of one cap on
one polygon vertex, a cap triangle the move would turn over, or manifold3d rejecting the result)
the solid keeps manifold3d's values and :attr:`CamSolid.snapped` states how far (mm) they lie
from the polygons' (0.0 otherwise).

Surface meshes (the boundary of the solid): binary and ASCII STL with numpy (no trimesh import),
3MF, OBJ and PLY through trimesh.  Mind: STL stores float32 (~1e-5 mm at 300 mm).

FEA volume meshes (VTU, Gmsh MSH 2.2, Abaqus/CalculiX INP) are not made from this solid but by
gmsh from the same polygons: :mod:`camgen.export.fea`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.body import WALL_TOL, BodySpec, wall_left
from camgen.contour import Contour
from camgen.export.tables import format_rows
from camgen.errors import (
    GeometryError,
    ParameterError,
)

__all__ = [
    "BYTES_PER_VERTEX", "CamSolid", "EXTRA_VERTICES", "FILLS", "MANIFOLD_SNAP", "MAX_FILE_BYTES", "MESH_FORMATS",
    "SUFFIX", "VOLUME_RTOL", "bore_polygon", "cam_solid", "check_wall", "cross_section", "mesh_bytes", "section_triangulation",
    "stl_ascii", "stl_binary", "three_mf", "unsnap", "vertex_limit",
]

#: Mesh formats and how they are written.
MESH_FORMATS = {
    "stl": "binary STL (numpy writer)",
    "stl_ascii": "ASCII STL (numpy writer)",
    "3mf": "3MF (camgen writer; units mm)",
    "obj": "Wavefront OBJ (trimesh)",
    "ply": "binary PLY (trimesh)",
}
SUFFIX = {"stl": ".stl", "stl_ascii": "_ascii.stl", "3mf": ".3mf", "obj": ".obj", "ply": ".ply"}


#: Largest surface mesh file (bytes).
MAX_FILE_BYTES = 100_000_000
#: Bytes per outline vertex (profile and hole polygons) of each surface format, at most: the
#: solid has about 5 triangles per outline vertex (two per wall edge, the caps' share with the
#: ring fill's interior vertices); measured 250-380 (STL), 1440-2170 (ASCII STL), 74-125 (3MF),
#: 190-265 (OBJ), 95-145 (PLY) on the templates' cams at 1e-3 and 1e-5 mm, with a margin (the
#: tests compare on the templates and random cams).  The ring fill's seam circles add a
#: constant: a file holds at most ``BYTES_PER_VERTEX * (vertices + EXTRA_VERTICES)`` bytes
#: (measured: at most 100 more vertices' worth on small cams).
BYTES_PER_VERTEX = {"stl": 500, "stl_ascii": 2800, "3mf": 160, "obj": 340, "ply": 180}
EXTRA_VERTICES = 500


def vertex_limit(fmt: str) -> int:
    """Most outline vertices a surface mesh file of format ``fmt`` may have to stay within
    :data:`MAX_FILE_BYTES` (:data:`BYTES_PER_VERTEX`, :data:`EXTRA_VERTICES`)."""
    return max(0, MAX_FILE_BYTES // BYTES_PER_VERTEX[fmt] - EXTRA_VERTICES)


#: Farthest (mm) manifold3d's cross-section may move a polygon vertex for it to be mapped back:
#: Clipper2 keeps 8 decimals, so a rounded point moves by at most sqrt(2)/2 x 1e-8 = 7.1e-9 mm
#: (measured: 5.0e-9 mm on a 255 mm cam).  Polygon vertices closer together than twice this
#: could be confused: the mapping must then be one to one, or it is not made.
MANIFOLD_SNAP = 1e-8

#: How the section is triangulated: "auto" (the linear-time ring fill of
#: :mod:`camgen.export.section_fill`, manifold3d's triangulation where its assumptions fail) or
#: "manifold" (manifold3d's triangulation of the cross-section, O(N^1.9)).
FILLS = ("auto", "manifold")


def bore_polygon(spec: BodySpec, chord_tol: float) -> np.ndarray | None:
    """The hole through the cam (k, 2), mm, counter-clockwise: the bore circle's inscribed
    polygon at ``chord_tol`` (vertex 0 on the +x axis) united with the keyway rectangle
    (:meth:`BodySpec.keyway_corners`); None without a bore.

    Bore vertices inside the keyway are dropped and the two points where the keyway's sides cut
    the polygon are inserted (on the polygon's chords), then the keyway's two outer corners.
    """
    if spec.bore_diameter <= 0:
        return None
    r = spec.bore_diameter / 2
    step = 2.0 * math.acos(max(-1.0, 1.0 - chord_tol / r))
    n = max(8, math.ceil(2.0 * math.pi / step))
    a = 2.0 * math.pi * np.arange(n) / n
    circle = np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
    if spec.keyway_width <= 0:
        return circle
    half = spec.keyway_width / 2
    c, s = math.cos(spec.keyway_angle), math.sin(spec.keyway_angle)
    along = circle @ np.array([c, s])
    across = circle @ np.array([-s, c])
    inside = (along > 0) & (np.abs(across) <= half)
    # rotate the polygon so that it starts at the vertex opposite the keyway: the vertices inside
    # the keyway then form one run in the middle
    first = int(np.argmin(along))
    order = np.roll(np.arange(n), -first)
    circle, along, across, inside = circle[order], along[order], across[order], inside[order]
    ahead = np.flatnonzero(along > 0)
    if inside.any():
        lo, hi = int(np.flatnonzero(inside)[0]), int(np.flatnonzero(inside)[-1])
    else:  # a keyway narrower than a chord: both sides cut the chord that crosses its centre line
        lo = int(ahead[np.flatnonzero(across[ahead] > 0)[0]])
        hi = lo - 1

    def cut(i: int, j: int, level: float) -> np.ndarray:  # point of chord i -> j where across = level
        t = (level - across[i]) / (across[j] - across[i])
        return circle[i] + t * (circle[j] - circle[i])

    corners = spec.keyway_corners()
    notch = np.stack([cut(lo - 1, lo, -half), corners[1], corners[2], cut(hi, hi + 1, half)])
    return np.concatenate([circle[:lo], notch, circle[hi + 1 :]])


def cross_section(contour: Contour, spec: BodySpec, chord_tol: float):
    """manifold3d ``CrossSection`` of the profile minus bore and keyway (:func:`bore_polygon`)."""
    from manifold3d import CrossSection

    loops = [contour.flatten(chord_tol)]
    hole = bore_polygon(spec, chord_tol)
    if hole is not None:
        loops.append(hole[::-1])  # clockwise: a hole
    return CrossSection(loops)


@dataclass(frozen=True)
class CamSolid:
    """A cam body: mesh vertices (n, 3, float64, mm), triangles (m, 3) and the manifold figures.

    The first ``N`` vertices are the flattened profile at z = 0 (the polygon's own values), the
    hole's follow, then the section's interior vertices; the same again at z = thickness (a body
    with pockets: the outline and the hole at both heights, then each pocket's walls at the
    thickness and at the pocket's floor).
    ``fill``: how the section was triangulated ("rings" or "manifold", see :data:`FILLS`;
    "pockets": a body with pockets, :mod:`camgen.export.pocket_solid`, the vertices the polygons' own).
    ``snapped``: how far (mm) a vertex lies from its polygon's value: 0.0 but where manifold3d's
    snapping could not be undone (see the module notes).
    """

    vertices: np.ndarray
    triangles: np.ndarray
    volume: float
    section_area: float
    genus: int
    fill: str = "manifold"
    snapped: float = 0.0


def _shoelace(loop: np.ndarray) -> float:
    x, y = loop[:, 0], loop[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _extrude(points: np.ndarray, triangles: np.ndarray, loops: list[tuple[int, int, bool]], thickness: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (2k, 3) and triangles of the prism over a section triangulation: bottom cap
    (facing -z), top cap, and two triangles per boundary edge.  ``loops``: (first vertex, count,
    counter-clockwise) of each boundary loop, its vertices consecutive in ``points``."""
    k = len(points)
    vertices = np.concatenate([np.column_stack([points, np.zeros(k)]), np.column_stack([points, np.full(k, thickness)])])
    walls = []
    for first, count, ccw in loops:
        a = first + np.arange(count)
        b = first + (np.arange(count) + 1) % count
        if not ccw:  # a hole runs clockwise as the boundary of the section
            a, b = b, a
        walls += [np.stack([a, b, b + k], axis=1), np.stack([a, b + k, a + k], axis=1)]
    faces = np.concatenate([triangles[:, ::-1], triangles + k] + walls)
    return vertices, faces


def check_wall(contour: Contour, spec: BodySpec, chord_tol: float, cam: str = "cam") -> None:
    """Refuse (:class:`GeometryError`) a bore or keyway that leaves less than ``spec.min_wall``
    to the profile, or that the profile flattened at ``chord_tol`` reaches."""
    wall, where = wall_left(contour, spec)
    if wall < spec.min_wall:  # the pipeline reports this as a failed check first; library callers get an error
        what = "breaks through the profile" if wall <= 0 else f"leaves a wall of only {wall:.3f} mm"
        raise GeometryError(f"cam '{cam}': the bore/keyway {what} at cam angle {where:.2f} deg (min_wall_mm = {spec.min_wall:g})")
    if chord_tol > WALL_TOL:  # the meshed polygons: the profile's chords sag inward by up to chord_tol
        mesh_wall, where = wall_left(contour, spec, chord_tol)
        if mesh_wall <= 0.0:
            raise GeometryError(f"cam '{cam}': at chord_tol_mm = {chord_tol:g} the flattened profile reaches the bore/keyway at cam angle "
                                f"{where:.2f} deg (the wall is {wall + WALL_TOL:.3g} mm): use output.chord_tol_mm < {wall + WALL_TOL:.2g} mm "
                                "for the meshes")


def cam_solid(contour: Contour, spec: BodySpec, chord_tol: float = 1e-3, cam: str = "cam", fill: str = "auto") -> CamSolid:
    """Extrude the cam profile (minus bore and keyway) to ``spec.thickness``; checks the wall first
    (:func:`check_wall`).  A body with pockets (a groove, a slot):
    :func:`camgen.export.pocket_solid.pocket_solid`.

    ``fill`` (see :data:`FILLS`): "auto" triangulates the section in linear time
    (:func:`camgen.export.section_fill.fill_section`: rings of interior vertices, well-shaped
    triangles) and hands the solid to manifold3d, whose status and genus guarantee a closed,
    consistently oriented 2-manifold; "manifold" (or "auto" where the profile is not
    star-shaped about the axis or no circle separates bore and profile) extrudes manifold3d's
    own triangulation.
    """
    import manifold3d

    if fill not in FILLS:
        raise ParameterError("fill", fill, f"one of {', '.join(FILLS)}")
    check_wall(contour, spec, chord_tol, cam)
    if fill == "auto":
        solid = _ring_solid(contour, spec, chord_tol)
        if solid is not None:
            return solid
    section = cross_section(contour, spec, chord_tol)
    solid = section.extrude(spec.thickness)
    if solid.status() != manifold3d.Error.NoError:
        raise GeometryError(f"cam '{cam}': the solid could not be built ({solid.status()})")
    mesh = solid.to_mesh64()
    vertices = np.asarray(mesh.vert_properties[:, :3], dtype=np.float64)
    triangles = np.asarray(mesh.tri_verts, dtype=np.int64)
    volume, area, genus = float(solid.volume()), float(section.area()), int(solid.genus())
    outer, hole = contour.flatten(chord_tol), bore_polygon(spec, chord_tol)
    outline = outer if hole is None else np.concatenate([outer, hole])
    exact = unsnap(vertices, triangles, outline)
    if exact is not None:  # the polygons' own values, if manifold3d still finds a 2-manifold of the same genus
        check = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=exact, tri_verts=triangles.astype(np.uint64)))
        if check.status() != manifold3d.Error.NoError or int(check.genus()) != genus:
            exact = None
    expected = 0 if hole is None else 1
    if exact is None:
        from scipy.spatial import cKDTree

        snapped = float(np.max(cKDTree(outline).query(vertices[:, :2])[0]))
        if genus != expected or snapped > MANIFOLD_SNAP:  # not the one body with one hole the polygons describe
            raise GeometryError(f"cam '{cam}': the solid's section is not the one region the profile and bore polygons at chord_tol_mm "
                                f"= {chord_tol:g} describe (genus {genus}, vertices moved {snapped:.3g} mm): use a smaller "
                                "output.chord_tol_mm")
        return CamSolid(vertices, triangles, volume, area, genus, "manifold", snapped)
    area = _shoelace(outer) - (_shoelace(hole) if hole is not None else 0.0)
    return CamSolid(exact, triangles, float(check.volume()), area, genus, "manifold")


def unsnap(vertices: np.ndarray, triangles: np.ndarray, outline: np.ndarray, snap: float = MANIFOLD_SNAP) -> np.ndarray | None:
    """``vertices`` (n, 3) of an extruded section with x, y put back on the polygon vertices
    ``outline`` (k, 2) they were snapped from; None where that cannot be done safely.

    Each vertex takes the x, y of its nearest outline vertex, which must lie within ``snap`` mm
    and be taken by no other vertex at the same height; no triangle of either cap may turn the
    other way (counter-clockwise against clockwise seen from +z) by the move.  z is kept.
    """
    from scipy.spatial import cKDTree

    distance, nearest = cKDTree(outline).query(vertices[:, :2])
    if not len(vertices) or np.max(distance) > snap:
        return None
    _, level = np.unique(vertices[:, 2], return_inverse=True)
    key = level.ravel() * len(outline) + nearest
    if len(np.unique(key)) != len(vertices):
        return None
    exact = np.column_stack([outline[nearest], vertices[:, 2]])

    def turning(points: np.ndarray) -> np.ndarray:
        p = points[triangles]
        u, v = p[:, 1, :2] - p[:, 0, :2], p[:, 2, :2] - p[:, 0, :2]
        return np.sign(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])

    caps = np.all(vertices[triangles, 2] == vertices[triangles[:, :1], 2], axis=1)
    if np.any(turning(vertices)[caps] * turning(exact)[caps] < 0):
        return None
    return exact


#: Largest relative difference between manifold3d's volume of the ring-filled solid and the
#: section's shoelace area times the thickness (the two are the same number up to rounding).
VOLUME_RTOL = 1e-9


def _ring_solid(contour: Contour, spec: BodySpec, chord_tol: float) -> CamSolid | None:
    """The solid over the linear-time section fill, validated by manifold3d; None where the fill
    does not apply (or, defensively, where manifold3d rejects it)."""
    import manifold3d

    from camgen.export.section_fill import fill_section

    outer = contour.flatten(chord_tol)
    hole = bore_polygon(spec, chord_tol)
    filled = fill_section(outer, hole)
    if filled is None:
        return None
    points, triangles = filled
    loops = [(0, len(outer), True)] + ([(len(outer), len(hole), False)] if hole is not None else [])
    vertices, faces = _extrude(points, triangles, loops, spec.thickness)
    solid = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=vertices, tri_verts=faces.astype(np.uint64)))
    area = _shoelace(outer) - (_shoelace(hole) if hole is not None else 0.0)
    volume = float(solid.volume())
    genus = int(solid.genus())
    if solid.status() != manifold3d.Error.NoError or genus != (0 if hole is None else 1) or abs(volume - area * spec.thickness) > VOLUME_RTOL * volume:
        return None
    return CamSolid(vertices, faces, volume, area, genus, "rings")


# --------------------------------------------------------------------------------------------
# Writers
# --------------------------------------------------------------------------------------------
def _facets(vertices: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    tri = vertices[triangles]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    return tri, normal


def stl_binary(solid: CamSolid, name: str = "camgen") -> bytes:
    """Binary STL bytes (float32 coordinates, mm)."""
    tri, normal = _facets(solid.vertices, solid.triangles)
    records = np.zeros(len(tri), dtype=[("normal", "<f4", 3), ("vertices", "<f4", (3, 3)), ("attribute", "<u2")])
    records["normal"] = normal
    records["vertices"] = tri
    header = f"camgen binary STL '{name}', units mm".encode("ascii", "replace")[:80].ljust(80, b" ")
    return header + np.uint32(len(tri)).tobytes() + records.tobytes()


def stl_ascii(solid: CamSolid, name: str = "camgen") -> str:
    """ASCII STL text (coordinates printed with 9 significant digits, mm)."""
    tri, normal = _facets(solid.vertices, solid.triangles)
    rows = np.concatenate([normal, tri.reshape(-1, 9)], axis=1)
    fmt = (
        "  facet normal %.9e %.9e %.9e\n    outer loop\n      vertex %.9e %.9e %.9e\n"
        "      vertex %.9e %.9e %.9e\n      vertex %.9e %.9e %.9e\n    endloop\n  endfacet"
    )
    return f"solid {name}\n{format_rows(rows + 0.0, fmt)}endsolid {name}\n"


def mesh_bytes(solid: CamSolid, fmt: str, name: str = "camgen") -> bytes:
    """File content of ``solid`` in surface mesh format ``fmt`` (see :data:`MESH_FORMATS`; the
    FEA volume meshes: :func:`camgen.export.fea.fea_bytes`)."""
    if fmt == "stl":
        return stl_binary(solid, name)
    if fmt == "stl_ascii":
        return stl_ascii(solid, name).encode("ascii")
    if fmt == "3mf":
        return three_mf(solid, name)
    if fmt in ("obj", "ply"):
        import trimesh

        mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
        mesh.units = "mm"
        data = mesh.export(file_type=fmt)
        data = data.encode("utf-8") if isinstance(data, str) else bytes(data)
        return data
    raise ParameterError("format", fmt, f"one of {sorted(MESH_FORMATS)}")


# --------------------------------------------------------------------------------------------
# The section of a solid
# --------------------------------------------------------------------------------------------
def section_triangulation(solid: CamSolid) -> tuple[np.ndarray, np.ndarray]:
    """The cross-section triangulation of an extruded ``solid``: vertices (k, 2) and
    counter-clockwise triangles (t, 3), from the bottom cap (z = 0) of its mesh."""
    z = solid.vertices[:, 2]
    cap = solid.triangles[np.all(z[solid.triangles] == 0.0, axis=1)]
    if not len(cap):
        raise GeometryError("the solid has no bottom cap at z = 0: not an extrusion from z = 0")
    used, local = np.unique(cap, return_inverse=True)
    triangles = local.reshape(-1, 3)[:, ::-1]  # the cap faces -z: reverse to counter-clockwise seen from +z
    return solid.vertices[used, :2], triangles


_3MF_TYPES = (
    '<?xml version="1.0" encoding="UTF-8"?>\n<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
    '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
    '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>\n'
)
_3MF_RELS = (
    '<?xml version="1.0" encoding="UTF-8"?>\n<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
    '<Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>'
    "</Relationships>\n"
)


def three_mf(solid: CamSolid, name: str = "camgen") -> bytes:
    """3MF package (3MF Core Specification 1.2: a zip of the content types, the relationship and
    the model part) of ``solid``: one mesh object in millimetres, vertices printed with 15
    significant digits, triangles counter-clockwise seen from outside.  Deterministic: fixed
    entry dates and order."""
    import io
    import zipfile
    from xml.sax.saxutils import quoteattr

    vertices = format_rows(solid.vertices + 0.0, '<vertex x="%.15g" y="%.15g" z="%.15g"/>')
    triangles = format_rows(solid.triangles, '<triangle v1="%d" v2="%d" v3="%d"/>')
    model = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<model unit="millimeter" xml:lang="en-US" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">\n'
        f'<metadata name="Title">{quoteattr(name)[1:-1]}</metadata>\n<metadata name="Application">camgen</metadata>\n'
        f'<resources>\n<object id="1" type="model" name={quoteattr(name)}>\n<mesh>\n<vertices>\n{vertices}</vertices>\n'
        f"<triangles>\n{triangles}</triangles>\n</mesh>\n</object>\n</resources>\n"
        '<build>\n<item objectid="1"/>\n</build>\n</model>\n'
    )
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as package:
        for entry, text in (("[Content_Types].xml", _3MF_TYPES), ("_rels/.rels", _3MF_RELS), ("3D/3dmodel.model", model)):
            info = zipfile.ZipInfo(entry, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            package.writestr(info, text.encode("utf-8"))
    return out.getvalue()
