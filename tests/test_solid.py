"""Extruded solids and surface mesh files, read back by trimesh, lib3mf and admesh (the FEA
volume meshes: test_fea.py)."""
from __future__ import annotations

import math
import re
import subprocess

import numpy as np
import pytest

from camgen.body import BodySpec
from camgen.errors import GeometryError
from camgen.export.solid import cam_solid, mesh_bytes
from cams import BODIES, radial_error
from helpers import require_tool


def _shapely_section(contour, body, tol):
    from shapely import affinity
    from shapely.geometry import Polygon, box

    outer = Polygon(contour.flatten(tol))
    r = body.bore_diameter / 2
    n = max(8, math.ceil(2 * math.pi / (2 * math.acos(1 - tol / r))))
    a = 2 * math.pi * np.arange(n) / n
    hole = Polygon(np.stack([r * np.cos(a), r * np.sin(a)], 1))
    key = box(0, -body.keyway_width / 2, r + body.keyway_depth, body.keyway_width / 2)
    key = affinity.rotate(key, body.keyway_angle, origin=(0, 0), use_radians=True)
    return outer.difference(hole.union(key))


@pytest.mark.parametrize("name", ["stride", "height", "steering"])
def test_solid_is_watertight_genus_one_with_the_right_volume(name, contours):
    import trimesh
    contour, body, tol = contours[name], BODIES[name], 1e-3
    solid = cam_solid(contour, body, tol)
    mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume
    assert mesh.euler_number == 0 and solid.genus == 1  # one hole through the body
    section = _shapely_section(contour, body, tol)  # independent 2-D boolean (GEOS)
    assert solid.volume == pytest.approx(section.area * body.thickness, rel=1e-9)
    assert mesh.volume == pytest.approx(solid.volume, rel=1e-12)
    # against the exact profile area: the chords cut off at most perimeter x chord_tol
    r, h = body.bore_diameter / 2, body.keyway_width / 2
    # keyway area outside the bore: strip |y| <= h, 0 <= x <= r + depth, minus the disc part
    keyway = 2 * h * (r + body.keyway_depth) - (h * math.sqrt(r * r - h * h) + r * r * math.asin(h / r))
    exact = (contour.area - math.pi * r * r - keyway) * body.thickness
    assert abs(solid.volume - exact) <= (contour.length + math.pi * body.bore_diameter + 4 * body.keyway_depth) * tol * body.thickness


@pytest.mark.parametrize("fmt", ["stl", "stl_ascii", "3mf", "obj", "ply"])
def test_surface_mesh_formats_read_back(fmt, contours, tmp_path):
    import trimesh

    contour, body = contours["stride"], BODIES["stride"]
    solid = cam_solid(contour, body, 1e-3)
    data = mesh_bytes(solid, fmt, "stride")
    assert data == mesh_bytes(solid, fmt, "stride")  # deterministic
    path = tmp_path / f"cam.{'stl' if fmt == 'stl_ascii' else fmt}"
    path.write_bytes(data)
    mesh = trimesh.load(path, force="mesh")
    assert mesh.is_watertight and mesh.is_winding_consistent
    rel = 1e-6 if fmt in ("stl", "ply", "3mf") else 1e-9  # float32 in binary STL/PLY, 3MF text precision
    assert mesh.volume == pytest.approx(solid.volume, rel=rel)
    if fmt == "3mf":
        assert mesh.units in ("millimeter", "millimeters", "mm")


# --------------------------------------------------------------------------------------------
# Volumes of FEA cells (test_fea.py)
# --------------------------------------------------------------------------------------------
def wedge_volumes(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Signed volumes of 6-node wedges (A, B, C over D, E, F) as the tetrahedra ABCD, BCDE, CDEF
    (det / 6 each): positive when ABC runs counter-clockwise seen from DEF (the Gmsh, Abaqus
    and VTK isoparametric orientation)."""
    p = points[cells]  # (m, 6, 3)

    def tet(a, b, c, d):
        return np.einsum("ij,ij->i", p[:, b] - p[:, a], np.cross(p[:, c] - p[:, a], p[:, d] - p[:, a])) / 6.0

    return tet(0, 1, 2, 3) + tet(1, 2, 3, 4) + tet(2, 3, 4, 5)


def admesh_clean(admesh: str, path) -> str:
    """admesh's report on the STL at ``path`` (it always exits 0 and echoes the 80-byte header's
    raw bytes: decoded leniently), asserting that it had nothing to repair and found one part."""
    out = subprocess.run([admesh, "-e", str(path)], capture_output=True, timeout=60).stdout.decode("utf-8", "replace")
    figures = {k.strip(): v for k, v in re.findall(r"^([A-Za-z ]+?)\s*:\s*(\d+)", out, re.M)}
    for key in ("Degenerate facets", "Edges fixed", "Facets removed", "Facets added", "Facets reversed", "Backwards edges", "Normals fixed"):
        assert int(figures[key]) == 0, (key, out)
    assert re.search(r"Total disconnected facets\s*:\s*0\s+0", out), out
    return out


def test_binary_stl_passes_admesh(contours, tmp_path):
    admesh = require_tool("admesh")
    path = tmp_path / "cam.stl"
    solid = cam_solid(contours["height"], BODIES["height"], 1e-3)
    path.write_bytes(mesh_bytes(solid, "stl"))
    out = admesh_clean(admesh, path)
    assert re.search(r"Number of facets\s*:\s*(\d+)", out).group(1) == str(len(solid.triangles))
    # admesh adds the facets' volumes one by one in float32: recursive summation of n positive
    # terms is within (n - 1) 2^-24 of their sum (Higham, Accuracy and Stability of Numerical
    # Algorithms, 2nd ed., eq. 4.4); the float32 coordinates add about 1e-7 more
    rel = max(1e-6, len(solid.triangles) * 2.0**-24)
    assert float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1)) == pytest.approx(solid.volume, rel=rel)


@pytest.mark.parametrize(
    "body, fragment",
    [
        (BodySpec(bore_diameter=21.0, min_wall=0.5), "breaks through"),
        (BodySpec(bore_diameter=16.0, min_wall=3.0), "wall of only"),
        (BodySpec(bore_diameter=8.0, keyway_width=2.0, keyway_depth=6.0, keyway_angle=0.0, min_wall=0.5), "breaks through"),
    ],
)
def test_bore_or_keyway_breaking_the_wall_is_an_error(body, fragment, contours):
    with pytest.raises(GeometryError, match=fragment):
        cam_solid(contours["height"], body)  # base radius c = 10 mm


def test_wall_is_measured_where_it_is_thinnest(contours):
    from camgen.body import wall_left

    wall, where = wall_left(contours["height"], BodySpec(bore_diameter=8.0))
    # the whole base arc (+-30 deg for b = a) is 10 mm from the axis
    assert wall == pytest.approx(10.0 - 4.0, abs=2e-4) and (where <= 30.01 or where >= 329.99)
    wall, where = wall_left(contours["height"], BodySpec(bore_diameter=8.0, keyway_width=2.0, keyway_depth=5.5, keyway_angle=0.0))
    # thinnest at the keyway's outer corners (9.5, +-1): 10 - hypot(9.5, 1) from the base circle
    assert wall == pytest.approx(10.0 - math.hypot(9.5, 1.0), abs=2e-4) and (where < 15 or where > 345)



# --------------------------------------------------------------------------------------------
# The linear-time section fill (camgen.export.section_fill), against GEOS, trimesh, manifold3d
# --------------------------------------------------------------------------------------------
def _template_cams():
    """(template, cam, contour, body, chord_tol) of every plate cam of every bundled template (a
    barrel cam is no extruded outline: tests/test_barrel_solid.py has its solid)."""
    from camgen.kinds import get_kind
    from camgen.scene import load_template
    from golden.regenerate import TEMPLATES

    out = []
    for name in TEMPLATES:
        scene = load_template(name)
        for spec in scene.cams:
            cam = get_kind(spec.kind, spec.form).build(spec, frozenset())
            if cam.planar:
                out.append((name, spec.name, cam.contour, cam.body, scene.output.chord_tol))
    return out


def _concave_cam():
    """A three-lobed spline cam r = 40 + 8 cos(3 theta): concave between the lobes (radius of
    curvature 25.6 mm there), star-shaped about the axis; bore 20 mm with a 6 x 2.8 keyway
    pointing into a valley."""
    theta = np.linspace(0.0, 2 * math.pi, 97)
    r = 40.0 + 8.0 * np.cos(3.0 * theta)
    from camgen.contour import Contour, Spline

    contour = Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])
    assert not contour.is_convex()
    body = BodySpec(thickness=12.0, bore_diameter=20.0, keyway_width=6.0, keyway_depth=2.8, keyway_angle=math.pi / 3, min_wall=2.0)
    return contour, body


# (a linear cam's plate is not star-shaped about the axis: manifold3d fills it; tests/test_linear_cam.py reads its solid back)
SECTION_CASES = [(t, c) for t, c, *_ in _template_cams() if t != "linear_cam"] + [("concave", "lobes")]


def _section_case(template, cam):
    if template == "concave":
        contour, body = _concave_cam()
        return contour, body, 1e-3
    for t, c, contour, body, tol in _template_cams():
        if (t, c) == (template, cam):
            return contour, body, tol
    raise KeyError(cam)


def _triangle_areas(points, triangles):
    a, b, c = points[triangles[:, 0]], points[triangles[:, 1]], points[triangles[:, 2]]
    return 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])


@pytest.mark.parametrize("template, cam", SECTION_CASES)
def test_ring_fill_solid_is_valid_and_covers_the_section_exactly(template, cam):
    """Every bundled template's cams and a concave cam take the linear-time fill.  trimesh: the
    surface is watertight, consistently wound, a volume with Euler number 0 (bore) or 2 (none);
    manifold3d's genus agrees; the volume is GEOS's section area x thickness (1e-9).  The cap
    triangulation, against GEOS: every triangle counter-clockwise, the areas add up to the
    section's area (1e-9), their union has that area too (no overlaps) and differs from the
    section by nothing (no triangle outside, no gap).  The profile's vertices are the
    flattened polygon's own values."""
    import shapely
    import trimesh
    from shapely.geometry import Polygon

    from camgen.export.solid import bore_polygon, section_triangulation

    contour, body, tol = _section_case(template, cam)
    solid = cam_solid(contour, body, tol)
    assert solid.fill == "rings"
    mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume
    holes = 1 if body.bore_diameter > 0 else 0
    assert mesh.euler_number == 2 - 2 * holes and solid.genus == holes
    outer = contour.flatten(tol)
    hole = bore_polygon(body, tol)
    section = Polygon(outer, [hole[::-1]] if holes else [])
    if holes:
        assert section.area == pytest.approx(_shapely_section(contour, body, tol).area, rel=1e-9)  # our hole = GEOS's boolean
    assert solid.volume == pytest.approx(section.area * body.thickness, rel=1e-9)
    assert mesh.volume == pytest.approx(solid.volume, rel=1e-9)
    assert np.array_equal(solid.vertices[: len(outer), :2], outer) and np.all(solid.vertices[: len(outer), 2] == 0.0)

    points, triangles = section_triangulation(solid)
    areas = _triangle_areas(points, triangles)
    assert np.all(areas > 0)
    assert areas.sum() == pytest.approx(section.area, rel=1e-9)
    union = shapely.union_all(shapely.polygons(points[triangles]))
    assert union.area == pytest.approx(section.area, rel=1e-9)
    assert union.symmetric_difference(section).area <= 1e-9 * section.area


def test_ring_fill_triangles_are_better_shaped_than_manifolds():
    """Triangle shape (longest edge^2 / (2 area): 1.15 equilateral, large for slivers) of the
    ring fill against manifold3d's triangulation of the same section (the previous mesh):
    the median falls by more than 20x and the 99th percentile by more than 10x for the
    default template's cams."""
    from camgen.export.solid import section_triangulation

    def shape(solid):
        points, triangles = section_triangulation(solid)
        p = points[triangles]
        longest = np.max([np.sum((p[:, i] - p[:, (i + 1) % 3]) ** 2, axis=1) for i in range(3)], axis=0)
        return longest / (2 * _triangle_areas(points, triangles))

    for template, name, contour, body, tol in _template_cams()[:3]:
        rings, old = shape(cam_solid(contour, body, tol)), shape(cam_solid(contour, body, tol, fill="manifold"))
        assert np.median(rings) * 20 < np.median(old), name
        assert np.percentile(rings, 99) * 10 < np.percentile(old, 99), name


def test_ring_fill_vertex_count_is_linear(contours):
    """The fill adds interior vertices in proportion to the outline (about one in three) plus a
    constant, whatever the tolerance: 1e-3 ... 1e-5 mm on the stride cam (856 ... 8539 points)."""
    from camgen.export.solid import bore_polygon

    contour, body = contours["stride"], BODIES["stride"]
    for tol in (1e-3, 1e-4, 1e-5):
        solid = cam_solid(contour, body, tol)
        boundary = len(contour.flatten(tol)) + len(bore_polygon(body, tol))
        interior = len(solid.vertices) // 2 - boundary
        assert solid.fill == "rings" and 0 < interior <= 0.5 * boundary + 3000


def test_fill_falls_back_to_manifold_where_no_circle_separates_bore_and_profile():
    """A keyway reaching 13.4 mm from the axis, pointing at the lobe of a cam whose base circle
    is 12 mm from the axis (the wall check passes: the base is away from the keyway): no circle
    about the axis separates the hole from the profile, so manifold3d triangulates; the solid
    is still valid with GEOS's volume."""
    import trimesh

    import camgen

    contour = camgen.three_arc_cam(220.0, 160.0, 12.0)  # lobe towards 180 deg, base arc c = 12 mm
    body = BodySpec(thickness=10.0, bore_diameter=16.0, keyway_width=6.0, keyway_depth=5.0, keyway_angle=math.pi, min_wall=2.0)
    solid = cam_solid(contour, body, 1e-3)
    assert solid.fill == "manifold"
    mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
    assert mesh.is_watertight and mesh.is_volume and solid.genus == 1
    assert solid.volume == pytest.approx(_shapely_section(contour, body, 1e-3).area * body.thickness, rel=1e-9)


def test_fill_falls_back_to_manifold_for_a_profile_not_star_shaped_about_the_axis():
    """A disc of radius 10 mm centred 30 mm from the axis: rays from the axis meet it twice or
    never; the fill declines and manifold3d triangulates (area pi 100 mm^2, less at most the
    perimeter x chord tolerance cut off by the chords)."""
    from camgen.contour import Arc, Contour
    from camgen.export.section_fill import fill_section, star_angles

    disc = Contour([Arc((30.0, 0.0), 10.0, 0.0, 2 * math.pi)])
    assert star_angles(disc.flatten(1e-3)) is None and fill_section(disc.flatten(1e-3)) is None
    solid = cam_solid(disc, BodySpec(thickness=5.0), 1e-3)
    assert solid.fill == "manifold" and solid.genus == 0
    assert math.pi * 100 * 5.0 - 2 * math.pi * 10 * 1e-3 * 5.0 <= solid.volume < math.pi * 100 * 5.0
    from camgen.errors import ParameterError

    with pytest.raises(ParameterError, match="fill"):
        cam_solid(disc, BodySpec(thickness=5.0), 1e-3, fill="rings")  # "auto" or "manifold"


def test_star_angles_and_fill_inputs():
    """star_angles: increasing unwrapped polar angles for a star-shaped CCW loop (a square about
    the origin: 45, 135, 225, 315 deg), None for a clockwise loop, a loop around twice, or a
    vertex on the origin.  fill_section keeps both loops' vertices bitwise and declines when the
    hole reaches past the profile's nearest vertex."""
    from camgen.export.section_fill import fill_section, star_angles

    square = np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]])
    assert np.degrees(star_angles(square)) == pytest.approx([45, 135, 225, 315])
    assert star_angles(square[::-1]) is None
    twice = np.array([[math.cos(a), math.sin(a)] for a in np.linspace(0, 4 * math.pi, 9)[:-1] + 0.1])
    assert star_angles(twice) is None
    assert star_angles(np.vstack([square, [[0.0, 0.0]]])) is None
    a = 2 * math.pi * np.arange(200) / 200
    outer = np.stack([50 * np.cos(a), 30 * np.sin(a)], 1)
    hole = np.stack([10 * np.cos(a[::4]), 10 * np.sin(a[::4])], 1)
    points, triangles = fill_section(outer, hole)
    assert np.array_equal(points[:200], outer) and np.array_equal(points[200:250], hole)
    assert _triangle_areas(points, triangles).sum() == pytest.approx(math.pi * (1500 - 100), rel=1e-3)
    assert fill_section(outer, 3.1 * hole) is None  # the hole reaches 31 mm, the profile comes to 30 mm


def test_concave_cam_stl_passes_admesh(tmp_path):
    admesh = require_tool("admesh")
    contour, body = _concave_cam()
    solid = cam_solid(contour, body, 1e-3)
    assert solid.fill == "rings"
    path = tmp_path / "cam.stl"
    path.write_bytes(mesh_bytes(solid, "stl"))
    out = admesh_clean(admesh, path)
    assert float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1)) == pytest.approx(solid.volume, rel=len(solid.triangles) * 2.0**-24)


def test_ring_fill_of_random_star_shaped_sections():
    """Random star-shaped outlines (Fourier radius functions, even and uneven ray spacing) with
    random bores and keyways: every fill covers GEOS's section exactly (triangle areas and
    their union), with positive triangles; the fill declines only without a free annulus."""
    import shapely
    from shapely.geometry import Polygon

    from camgen.export.section_fill import fill_section
    from camgen.export.solid import bore_polygon

    rng = np.random.default_rng(2024)
    filled = 0
    for _ in range(16):
        n = int(rng.integers(30, 1500))
        theta = np.unique(rng.uniform(0, 2 * math.pi, n)) if rng.random() < 0.5 else 2 * math.pi * np.arange(n) / n
        k = np.arange(1, 9)
        a, b = rng.normal(size=(2, 8)) / k ** rng.uniform(0.5, 2)
        r = 1 + rng.uniform(0.1, 0.5) * (np.cos(np.outer(theta, k)) @ a + np.sin(np.outer(theta, k)) @ b)
        r = np.maximum(r, 0.05) * rng.uniform(10, 300)
        outer = np.stack([r * np.cos(theta), r * np.sin(theta)], 1)
        bore = rng.uniform(0.1, 1.0) * r.min()
        width = rng.uniform(0.1, 0.8) * bore if rng.random() < 0.7 else 0.0
        body = BodySpec(bore_diameter=bore, keyway_width=width, keyway_depth=rng.uniform(0.02, 0.3) * bore if width else 0.0,
                        keyway_angle=rng.uniform(0, 2 * math.pi), min_wall=0.0)
        hole = bore_polygon(body, 10 ** rng.uniform(-5, -2))
        result = fill_section(outer, hole)
        if result is None:
            assert np.hypot(*hole.T).max() >= 0.99 * r.min()
            continue
        filled += 1
        points, triangles = result
        section = Polygon(outer, [hole[::-1]])
        areas = _triangle_areas(points, triangles)
        assert np.all(areas > 0) and areas.sum() == pytest.approx(section.area, rel=1e-9)
        union = shapely.union_all(shapely.polygons(points[triangles]))
        assert union.area == pytest.approx(section.area, rel=1e-9)
        assert union.symmetric_difference(section).area <= 1e-9 * section.area
    assert filled >= 12


def test_3mf_passes_the_reference_readers_strict_mode(contours, tmp_path):
    """lib3mf (the 3MF Consortium's reference implementation) reads camgen's 3MF in strict mode
    without a warning: one manifold, oriented mesh in millimetres whose volume (divergence
    theorem over lib3mf's own triangles) is the solid's."""
    import lib3mf

    solid = cam_solid(contours["stride"], BODIES["stride"], 1e-3)
    path = tmp_path / "cam.3mf"
    path.write_bytes(mesh_bytes(solid, "3mf", "stride"))
    wrapper = lib3mf.get_wrapper()
    model = wrapper.CreateModel()
    reader = model.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromFile(str(path))
    assert reader.GetWarningCount() == 0
    assert model.GetUnit() == lib3mf.ModelUnit.MilliMeter
    objects = model.GetMeshObjects()
    assert objects.MoveNext()
    mesh = objects.GetCurrentMeshObject()
    assert mesh.IsManifoldAndOriented() and mesh.GetName() == "stride"
    vertices = np.array([v.Coordinates[0:3] for v in mesh.GetVertices()], dtype=float)
    triangles = np.array([t.Indices[0:3] for t in mesh.GetTriangleIndices()], dtype=int)
    tri = vertices[triangles]
    volume = np.sum(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))) / 6.0
    assert volume == pytest.approx(solid.volume, rel=1e-7)  # lib3mf holds coordinates as float32
    assert not objects.MoveNext()


# --------------------------------------------------------------------------------------------
# manifold3d's fill: the polygons' own vertices back (export.solid.unsnap)
# --------------------------------------------------------------------------------------------
def _square_prism(offset: np.ndarray):
    """The unit square's prism (z 0 and 1): 8 vertices (its corners moved by ``offset`` (8, 2)),
    12 outward triangles; and the square."""
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    vertices = np.column_stack([np.vstack([square, square]) + offset, np.repeat([0.0, 1.0], 4)])
    caps = [[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]]
    walls = [[i, (i + 1) % 4, (i + 1) % 4 + 4] for i in range(4)] + [[i, (i + 1) % 4 + 4, i + 4] for i in range(4)]
    return vertices, np.array(caps + walls), square


def test_unsnap_puts_vertices_back_or_declines():
    """Vertices moved by 3e-9 mm go back to the square's corners bit for bit (z kept); a vertex
    moved beyond MANIFOLD_SNAP, two vertices of one cap taking the same corner, or a cap triangle
    the move would turn over (its apex 4e-9 mm on either side of its base) are declined."""
    from camgen.export.solid import MANIFOLD_SNAP, unsnap

    rng = np.random.default_rng(1)
    vertices, triangles, square = _square_prism(rng.uniform(-3e-9, 3e-9, (8, 2)))
    exact = unsnap(vertices, triangles, square)
    assert np.array_equal(exact[:, :2], np.vstack([square, square])) and np.array_equal(exact[:, 2], vertices[:, 2])
    far = vertices.copy()
    far[5, 0] += 1.5 * MANIFOLD_SNAP
    assert unsnap(far, triangles, square) is None
    twice = np.vstack([vertices, [1.0, -1e-9, 0.0]])  # a ninth vertex at z = 0 also next to corner 1
    assert unsnap(twice, triangles, square) is None
    twice[8, 2] = 0.5  # at another height: one to one again
    assert unsnap(twice, triangles, square) is not None
    base = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, -4e-9]])
    raw = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 4e-9, 0.0]])
    assert unsnap(raw, np.array([[0, 1, 2]]), base) is None
    assert unsnap(raw, np.array([[0, 1, 2]]), base[[0, 1, 0]] + [[0, 0], [0, 0], [1.0, 4e-9]]) is not None


def test_manifold_fill_states_what_it_could_not_put_back(monkeypatch):
    """Where the mapping is declined the solid keeps manifold3d's vertices and says how far they
    lie from the polygons (> 0, <= MANIFOLD_SNAP: trimesh and scipy measure it independently);
    either way the mesh is a watertight volume of GEOS's section area x thickness."""
    import trimesh
    from scipy.spatial import cKDTree

    import camgen
    from camgen.export import solid as solid_module
    from camgen.export.solid import MANIFOLD_SNAP, bore_polygon

    cam = camgen.three_arc_cam(220.0, 160.0, 25.0)
    body = BodySpec(thickness=5.0, bore_diameter=20.0)
    outline = np.vstack([cam.flatten(1e-3), bore_polygon(body, 1e-3)])
    area = _shapely_section(cam, body, 1e-3).area
    exact = cam_solid(cam, body, 1e-3, fill="manifold")
    monkeypatch.setattr(solid_module, "unsnap", lambda *args, **kw: None)
    snapped = cam_solid(cam, body, 1e-3, fill="manifold")
    off = cKDTree(outline).query(snapped.vertices[:, :2])[0]
    assert exact.snapped == 0.0 and 0.0 < snapped.snapped == np.max(off) <= MANIFOLD_SNAP
    for solid in (exact, snapped):
        mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
        assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume and mesh.euler_number == 0
        assert mesh.volume == pytest.approx(area * body.thickness, rel=1e-9)
    assert exact.volume == pytest.approx(area * body.thickness, rel=1e-12)


THIN_WALL = """
[output]
formats = ["stl", "dxf"]
chord_tol_mm = {tol}
[cams.c]
kind = "three_arc"
a_mm = 60.0
b_mm = 40.0
c_mm = 5.0
thickness_mm = 5.0
bore_diameter_mm = 9.996
min_wall_mm = 0.001
"""


def test_a_wall_thinner_than_the_mesh_tolerance_is_no_split_solid(tmp_path, capsys):
    """Base circle radius c = 5 mm around a 9.996 mm bore: a 0.002 mm wall passes min_wall_mm,
    but at chord_tol_mm = 0.01 the profile's chords (sagitta up to 0.01 mm) cut into the bore and
    the section falls apart (manifold3d made 4 bodies of it).  That run is a failed solid_export
    check naming output.chord_tol_mm, no file written; at 0.001 the STL is one watertight body
    (trimesh) of volume (area of the section, shapely) x thickness."""
    import json

    import trimesh
    from shapely.geometry import Point, Polygon

    from camgen.cli import main

    for tol in (0.01, 0.001):
        (tmp_path / f"t{tol}.toml").write_text(THIN_WALL.format(tol=tol))
        status = main(["run", str(tmp_path / f"t{tol}.toml"), "-o", str(tmp_path / "out"), "--quiet"])
        folder = tmp_path / "out" / f"t{tol}"
        if tol == 0.01:
            err = capsys.readouterr().err
            assert status == 1 and "camgen: check failed: cams.c: solid_export: " in err and "output.chord_tol_mm < 0.002 mm" in err, err
            checks = {c["name"]: c for c in json.loads((folder / "report.json").read_text())["cams"]["c"]["checks"]}
            assert "output.chord_tol_mm < 0.002" in checks["solid_export"]["note"]
            assert sorted(p.name for p in folder.iterdir()) == ["report.json"]
        else:
            assert status == 0, capsys.readouterr().err
            mesh = trimesh.load(folder / "c.stl")
            assert mesh.is_watertight and len(mesh.split(only_watertight=False)) == 1
            import camgen

            outline = Polygon(camgen.three_arc_cam(60.0, 40.0, 5.0).flatten(0.001))
            section = outline.difference(Point(0.0, 0.0).buffer(9.996 / 2, 4096))
            assert mesh.volume == pytest.approx(section.area * 5.0, rel=1e-5)


def test_manifold_fallback_refuses_a_section_of_the_wrong_genus(monkeypatch):
    """The same cam with the mesh-wall check switched off: the crossing polygons reach manifold3d's
    own triangulation, whose result has genus != 1 (several bodies): a GeometryError, not a file."""
    import camgen
    import camgen.export.solid as solid

    monkeypatch.setattr(solid, "WALL_TOL", 1.0)
    body = BodySpec(thickness=5.0, bore_diameter=9.996, keyway_width=0.0, keyway_depth=0.0, min_wall=0.001)
    with pytest.raises(GeometryError, match=r"not the one region .* \(genus -3"):
        cam_solid(camgen.three_arc_cam(60.0, 40.0, 5.0), body, 0.01)


def test_wall_to_a_keyway_corner_facing_the_middle_of_a_chord(contours):
    """At a coarse tolerance the profile polygon's chords are long (2 mm on the 10 mm base arc at
    0.05 mm): a keyway corner facing the middle of a chord is nearer to it than to both its ends.
    The wall on that polygon against shapely's distance between the polygon and the rectangle."""
    from shapely.geometry import Polygon

    from camgen.body import wall_left

    tol = 0.05
    poly = contours["height"].flatten(tol)
    angle = np.arctan2(poly[:, 1], poly[:, 0])
    on_base = np.flatnonzero(np.abs(np.hypot(poly[:, 0], poly[:, 1]) - 10.0) < 1e-9)
    k = on_base[np.argmin(np.abs(angle[on_base]))]  # a base-arc vertex near angle 0 and the next one
    middle = 0.5 * (angle[k] + angle[k + 1])
    body = BodySpec(bore_diameter=3.0, keyway_width=2.0, keyway_depth=7.0, keyway_angle=0.0)
    corner = body.keyway_corners()[2]  # (reach, +half) at keyway angle 0
    body = BodySpec(bore_diameter=3.0, keyway_width=2.0, keyway_depth=7.0, keyway_angle=float(middle - math.atan2(corner[1], corner[0])))
    wall, _ = wall_left(contours["height"], body, tol)
    expected = Polygon(poly).exterior.distance(Polygon(body.keyway_corners()))
    assert wall + tol == pytest.approx(expected, abs=1e-9)
    ends = np.hypot(*(poly[[k, k + 1]] - body.keyway_corners()[2]).T)
    assert expected < ends.min() - 0.01  # the case this test is for: the chord's middle is nearer than its ends
