"""The files of a body with pockets (issue 23, item 1: groove cams; a slot): DXF wall layers,
point lists, surface meshes, STEP, and the formats such a body does not have.

The bodies are built here (a rim circle, a bore, a groove between two circles, concentric and
eccentric, whose areas are closed forms pi r^2; a groove between the offsets of a spline pitch
curve, whose areas come from an independent dense shoelace; a single-loop slot, blind and
through), and read back by independent programs: ezdxf and GDAL (DXF), admesh, PrusaSlicer and
OpenSCAD (STL), trimesh and meshio (3MF, OBJ, PLY), OpenCASCADE (STEP).
"""
from __future__ import annotations

import io
import json
import math
import re
import shutil
import subprocess

import numpy as np
import pytest

from camgen.body import BodySpec
from camgen.contour import Arc, Contour, Spline
from camgen.errors import ParameterError
from camgen.kinds.base import Pocket, Wall
from helpers import require_tool, shoelace
from test_dxf import GDAL_STEP_DEG, Chain, exact_chain, exact_samples, gdal_chain, gdal_layers, hole_area, read_dxf
from test_solid import admesh_clean

RIM = 50.0  # the plate's rim radius, mm
THICKNESS = 12.0
DEPTH = 5.0
HALF = 5.0  # half the groove's width
BODY = BodySpec(thickness=THICKNESS, bore_diameter=16.0, keyway_width=4.0, keyway_depth=2.5, keyway_angle=math.radians(30.0), min_wall=1.0)


def circle(centre, radius) -> Contour:
    return Contour([Arc(centre, radius, 0.0, 2.0 * math.pi)])


def circle_groove(centre, pitch_radius) -> Pocket:
    """A groove between two circles about ``centre``: radii pitch +- HALF."""
    walls = (Wall("GROOVE_OUTER", circle(centre, pitch_radius + HALF)), Wall("GROOVE_INNER", circle(centre, pitch_radius - HALF)))
    return Pocket("groove", walls, DEPTH, 2 * HALF, circle(centre, pitch_radius), 0.1)


def spline_pitch(samples: int = 400) -> Contour:
    """r = 30 + 3 cos 2 phi + 1.5 sin 3 phi: a periodic cubic spline through ``samples`` points."""
    phi = np.linspace(0.0, 2 * math.pi, samples + 1)
    r = 30.0 + 3.0 * np.cos(2 * phi) + 1.5 * np.sin(3 * phi)
    points = r[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    points[-1] = points[0]
    return Contour([Spline.interpolate(phi, points)])


def spline_groove() -> Pocket:
    pitch = spline_pitch()
    walls = (Wall("GROOVE_OUTER", pitch.offset(HALF)), Wall("GROOVE_INNER", pitch.offset(-HALF)))
    return Pocket("groove", walls, DEPTH, 2 * HALF, pitch, 0.1)


def slot(depth: float) -> Pocket:
    """A single closed loop (a slot), not about the axis."""
    return Pocket("slot", (Wall("SLOT", circle((30.0, -12.0), 6.0)),), depth)


def dense_area(contour: Contour, per_segment: int = 400_000) -> float:
    """The area inside ``contour`` by the shoelace of a dense sampling (independent of Contour.area's
    Green's theorem; the chords cut off at most perimeter x sagitta: ~1e-9 mm^2 here)."""
    t = np.concatenate([i + np.arange(per_segment) / per_segment for i in range(contour.n_segments)])
    return shoelace(contour.evaluate(t))


def wall_area(contour: Contour) -> float:
    """Closed form pi r^2 for a circle, else the dense shoelace."""
    seg = contour.segments[0]
    if contour.n_segments == 1 and isinstance(seg, Arc):
        return math.pi * seg.radius**2
    return dense_area(contour)


def pocket_area(pocket: Pocket) -> float:
    return wall_area(pocket.walls[0].contour) - sum(wall_area(w.contour) for w in pocket.walls[1:])


CASES = {
    "concentric": (circle_groove((0.0, 0.0), 30.0),),
    "eccentric": (circle_groove((3.0, 1.0), 30.0),),
    "spline": (spline_groove(),),
    "slot": (slot(4.0),),
    "through_slot": (slot(THICKNESS),),
    "groove_and_slot": (circle_groove((0.0, 0.0), 20.0), slot(3.0)),  # the slot 1.3 mm outside the groove
}
RIM_CONTOUR = circle((0.0, 0.0), RIM)


def exact_volume(pockets) -> float:
    """pi R^2 T - hole area T - sum of pocket area x depth (closed forms)."""
    return (math.pi * RIM**2 - hole_area(BODY)) * THICKNESS - sum(pocket_area(p) * p.depth for p in pockets)


def volume_bound(pockets, tol: float) -> float:
    """How far the flattened body may be from the exact one: every chord lies within ``tol`` of
    its curve, so each side face sweeps at most its loop's length x tol x its height."""
    hole_perimeter = math.pi * BODY.bore_diameter + 2 * (BODY.keyway_depth + BODY.keyway_width)
    walls = sum(w.contour.length * p.depth for p in pockets for w in p.walls)
    return tol * ((2 * math.pi * RIM + hole_perimeter) * THICKNESS + walls)


# --------------------------------------------------------------------------------------------
# DXF: each wall on its own layer, drawn as PROFILE is
# --------------------------------------------------------------------------------------------
def layer_read_back(doc, layer: str, per_span: int = 2048):
    """A layer read back by ezdxf (tests/test_dxf.py's reader, 2000 points an arc): (Chain of its
    CIRCLEs, ARCs, LINEs and SPLINEs (as polylines of ``per_span`` chords a knot span), points on
    them, entity types)."""
    from test_dxf import dxf_layer

    return dxf_layer(doc, layer, per_span, arc_points=2000)


def assert_layer_is_the_curve(contour, doc, layer: str, tol: float) -> list[str]:
    """``layer`` lies within ``tol`` of ``contour`` and covers it (both ways); its entity types."""
    _, points, kinds = layer_read_back(doc, layer, per_span=64)  # points on the file's curves
    chain, _, _ = layer_read_back(doc, layer)  # the file's curves: chords of 1/2048 knot span
    exact = exact_chain(contour, per_piece=1024)  # chords of 1/1024 piece: sagitta < 2e-9 mm here
    assert np.max(exact.distance(points)) <= tol + 2e-9, f"{layer}: a point of the file is off the curve"
    assert np.max(chain.distance(exact_samples(contour))) <= tol, f"{layer}: a point of the curve is off the file"
    return kinds


def gdal_round_trip(contour, path, layer: str, tol: float) -> None:
    """GDAL (pyogrio) reads ``layer``: its vertices on the curve, the curve within ``tol`` plus
    GDAL's own arc chords (0.05 deg steps) of its polylines."""
    lines = gdal_layers(path)[layer]
    assert np.max(exact_chain(contour).distance(np.concatenate(lines))) <= tol + 1e-9
    sag = contour.size * (1.0 - math.cos(math.radians(GDAL_STEP_DEG) / 2))
    assert np.max(gdal_chain(lines).distance(exact_samples(contour))) <= tol + sag


@pytest.mark.parametrize("case", ["concentric", "eccentric", "spline", "groove_and_slot"])
@pytest.mark.parametrize("mode", ["biarc", "bspline"])
def test_dxf_draws_each_wall_on_its_layer_within_the_tolerance(case, mode, tmp_path):
    """ezdxf (and GDAL, for the biarcs) read each wall's layer back within the tolerance of the
    exact wall, both ways (every point of the file near the wall, every point of the wall near
    the file); circles come back as CIRCLEs of their radius and centre; the layers are the
    part's and the walls'; each pocket's depth is in the header."""
    from camgen.export.dxf import DxfOptions, contour_to_dxf

    pockets = CASES[case]
    tol = 1e-3
    options = DxfOptions(splines=mode, chord_tol=tol)
    text = contour_to_dxf(RIM_CONTOUR, BODY, None, options, None, pockets)
    path = tmp_path / "cam.dxf"
    path.write_text(text)
    doc = read_dxf(text)
    walls = [w for p in pockets for w in p.walls]
    assert {layer.dxf.name for layer in doc.layers} - {"Defpoints"} == {"0", "PROFILE", "BORE", "KEYWAY"} | {w.layer for w in walls}
    stated = tol if mode == "biarc" else options.bspline_tol + 1e-9  # + the polyline through each SPLINE span (2048 chords)
    for wall in walls + [Wall("PROFILE", RIM_CONTOUR)]:
        kinds = assert_layer_is_the_curve(wall.contour, doc, wall.layer, stated)
        seg = wall.contour.segments[0]
        if isinstance(seg, Arc):  # the exact circle
            chain, _, _ = layer_read_back(doc, wall.layer)
            assert kinds == ["CIRCLE"] and np.array_equal(chain.arcs[0, :3], [*seg.center, seg.radius])
        else:
            assert set(kinds) <= ({"ARC", "LINE"} if mode == "biarc" else {"SPLINE"})
        if mode == "biarc":
            gdal_round_trip(wall.contour, path, wall.layer, tol)
    for pocket in pockets:
        assert doc.header.custom_vars.get(f"camgen_pocket_{pocket.name}_depth_mm") == repr(pocket.depth)


def test_dxf_of_a_plate_cam_has_no_wall_layer(contours):
    """No pockets: the drawing is the one it was (the golden test holds the bytes of every
    template; here the call with an empty pocket list is the call without it)."""
    from camgen.export.dxf import DxfOptions, contour_to_dxf

    from cams import BODIES

    contour, body = contours["stride"], BODIES["stride"]
    assert contour_to_dxf(contour, body, None, DxfOptions(), None, ()) == contour_to_dxf(contour, body, None, DxfOptions(), None)


def test_dxf_extents_hold_the_walls():
    """$EXTMIN/$EXTMAX hold a wall reaching past the rim (bounds of what is drawn, not of the outline)."""
    from camgen.export.dxf import DxfOptions, contour_to_dxf

    small_rim = circle((0.0, 0.0), 20.0)
    wide = (Pocket("slot", (Wall("SLOT", circle((30.0, 0.0), 5.0)),), 2.0),)
    doc = read_dxf(contour_to_dxf(small_rim, BODY, None, DxfOptions(), None, wide))
    assert doc.header["$EXTMAX"][0] == pytest.approx(35.0, abs=1e-12) and doc.header["$EXTMIN"][0] == pytest.approx(-20.0, abs=1e-12)


def test_a_wall_on_a_part_layer_is_refused():
    from camgen.errors import ExportError
    from camgen.export.dxf import DxfOptions, contour_to_dxf

    clash = (Pocket("slot", (Wall("BORE", circle((30.0, 0.0), 5.0)),), 2.0),)
    with pytest.raises(ExportError, match="BORE"):
        contour_to_dxf(RIM_CONTOUR, BODY, None, DxfOptions(), None, clash)


# --------------------------------------------------------------------------------------------
# Point list: a wall column, each loop closed and counter-clockwise within the chord tolerance
# --------------------------------------------------------------------------------------------
def read_points(text: str) -> dict[str, np.ndarray]:
    """The point list read with the csv module: loops by wall, in the file's order."""
    import csv

    rows = list(csv.reader(io.StringIO(text)))
    assert rows[0] == ["x_mm", "y_mm", "wall"]
    loops: dict[str, list] = {}
    for x, y, wall in rows[1:]:
        loops.setdefault(wall, []).append((float(x), float(y)))
    return {wall: np.array(points) for wall, points in loops.items()}


@pytest.mark.parametrize("case", ["eccentric", "spline", "groove_and_slot"])
def test_point_list_has_each_wall_closed_counter_clockwise_within_the_chord_tolerance(case):
    """PROFILE first, then each wall in the pockets' order; each loop's vertices on its exact
    curve (to the 9 decimals written), its chords within chord_tol of it and covering it (every
    point of the exact wall within chord_tol of the polygon, the closing chord included),
    counter-clockwise (positive shoelace area); no wall's rows run into another's."""
    from camgen.export.points import points_csv

    pockets = CASES[case]
    tol = 1e-3
    loops = read_points(points_csv(RIM_CONTOUR, tol, pockets))
    walls = [w for p in pockets for w in p.walls]
    assert list(loops) == ["PROFILE"] + [w.layer for w in walls]
    for contour, loop in [(RIM_CONTOUR, loops["PROFILE"])] + [(w.contour, loops[w.layer]) for w in walls]:
        assert shoelace(loop) > 0
        exact = exact_chain(contour)
        assert np.max(exact.distance(loop)) <= 1e-9
        polygon = Chain(segments=np.concatenate([loop, np.roll(loop, -1, axis=0)], axis=1))
        assert np.max(polygon.distance(exact_samples(contour))) <= tol + 1e-9
        assert abs(shoelace(loop) - wall_area(contour)) <= tol * contour.length  # the whole loop, once


def test_point_list_and_its_metadata_of_a_plate_cam_are_unchanged(contours):
    """No pockets: two columns, as before (the golden test holds the templates' bytes)."""
    from camgen.export.points import points_csv, points_metadata

    text = points_csv(contours["stride"], 1e-3, ())
    assert text.startswith("x_mm,y_mm\n") and text == points_csv(contours["stride"], 1e-3)
    assert points_metadata(1e-3, ()) == points_metadata(1e-3) and set(points_metadata(1e-3)["columns"]) == {"x_mm", "y_mm"}


def test_point_list_metadata_names_the_wall_column_and_the_walls():
    from camgen.export.points import points_metadata

    meta = points_metadata(1e-3, CASES["groove_and_slot"])
    assert list(meta["columns"]) == ["x_mm", "y_mm", "wall"]
    assert meta["walls"] == ["PROFILE", "GROOVE_OUTER", "GROOVE_INNER", "SLOT"]
    assert meta["pockets"] == [{"name": "groove", "depth_mm": DEPTH, "walls": ["GROOVE_OUTER", "GROOVE_INNER"]},
                               {"name": "slot", "depth_mm": 3.0, "walls": ["SLOT"]}]
    assert meta["chord_tol_mm"] == 1e-3


# --------------------------------------------------------------------------------------------
# Surface meshes: the real body
# --------------------------------------------------------------------------------------------
def _solid(case, tol=1e-3):
    from camgen.export.pocket_solid import pocket_solid

    return pocket_solid(RIM_CONTOUR, BODY, CASES[case], tol, case)


@pytest.mark.parametrize("case", list(CASES))
def test_body_with_pockets_is_watertight_with_the_closed_form_volume(case):
    """trimesh finds the mesh closed, consistently wound, a volume; its volume is pi R^2 T - hole
    x T - pocket area x depth within the chord bound (the bound far below any pocket's volume,
    so a pocket missing or of the wrong depth fails); the genus is the bore's hole plus a through
    slot's; every vertex lies on an exact curve (outline, bore/keyway, a wall) at its height: the
    floor of each pocket at thickness - depth."""
    import trimesh

    pockets = CASES[case]
    tol = 1e-3
    solid = _solid(case, tol)
    mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume and mesh.body_count == 1
    through = sum(1 for p in pockets if p.depth >= THICKNESS)
    assert solid.genus == 1 + through and mesh.euler_number == 2 - 2 * (1 + through)
    bound = volume_bound(pockets, tol)
    assert bound < 0.02 * min(pocket_area(p) * p.depth for p in pockets)
    assert abs(solid.volume - exact_volume(pockets)) <= bound
    assert mesh.volume == pytest.approx(solid.volume, rel=1e-12)
    # heights: 0, each blind pocket's floor, the top
    floors = {THICKNESS - p.depth for p in pockets if p.depth < THICKNESS}
    assert set(np.unique(solid.vertices[:, 2])) == {0.0, THICKNESS} | floors
    for p in pockets:
        chains = [exact_chain(w.contour) for w in p.walls]
        at_floor = solid.vertices[solid.vertices[:, 2] == THICKNESS - p.depth][:, :2] if p.depth < THICKNESS else None
        if at_floor is not None:
            assert len(at_floor) and np.max(np.min([c.distance(at_floor) for c in chains], axis=0)) <= 1e-9
    on_rim = np.abs(np.hypot(solid.vertices[:, 0], solid.vertices[:, 1]) - RIM) <= 1e-9
    assert on_rim.sum() == 2 * len(RIM_CONTOUR.flatten(tol))
    # every vertex within the chord tolerance of an exact curve: the rim, a wall, the bore circle or
    # the keyway's sides (its cuts of the bore polygon lie on the polygon's chords)
    xy = solid.vertices[:, :2]
    rho = np.hypot(xy[:, 0], xy[:, 1])
    ka = BODY.keyway_angle
    along, across = xy @ [math.cos(ka), math.sin(ka)], xy @ [-math.sin(ka), math.cos(ka)]
    reach, half = BODY.bore_diameter / 2 + BODY.keyway_depth, BODY.keyway_width / 2
    keyway = np.minimum(np.where((along >= 0) & (along <= reach), np.abs(np.abs(across) - half), np.inf),
                        np.where(np.abs(across) <= half, np.abs(along - reach), np.inf))
    walls = np.min([exact_chain(w.contour, per_piece=256).distance(xy) for p in pockets for w in p.walls], axis=0)
    nearest = np.min([np.abs(rho - RIM), np.abs(rho - BODY.bore_diameter / 2), keyway, walls], axis=0)
    assert np.max(nearest) <= tol


def first_hit_from_above(vertices: np.ndarray, triangles: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """Height of the highest face over each point ``xy`` (m, 2): the first a ray cast straight
    down meets (barycentric coordinates of the point in each face's projection; NaN: none)."""
    tri = vertices[triangles]  # (t, 3, 3)
    a, b, c = tri[:, 0, :2], tri[:, 1, :2], tri[:, 2, :2]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    keep = np.abs(det) > 1e-12  # vertical faces are never met first
    a, b, c, det, z = a[keep], b[keep], c[keep], det[keep], tri[keep, :, 2]
    out = np.full(len(xy), np.nan)
    for i, p in enumerate(xy):
        u = ((b[:, 0] - p[0]) * (c[:, 1] - p[1]) - (b[:, 1] - p[1]) * (c[:, 0] - p[0])) / det
        v = ((c[:, 0] - p[0]) * (a[:, 1] - p[1]) - (c[:, 1] - p[1]) * (a[:, 0] - p[0])) / det
        w = 1.0 - u - v
        inside = (u >= -1e-12) & (v >= -1e-12) & (w >= -1e-12)
        if inside.any():
            out[i] = np.max(u[inside] * z[inside, 0] + v[inside] * z[inside, 1] + w[inside] * z[inside, 2])
    return out


@pytest.mark.parametrize("case", ["eccentric", "spline"])
def test_pocket_floor_and_walls_are_where_the_pocket_is(case):
    """Rays cast down onto the mesh: inside the groove (by shapely, on the exact walls sampled
    densely) the first face met is the floor at thickness - depth; beside it the top face."""
    import shapely
    from shapely.geometry import Polygon

    pockets = CASES[case]
    solid = _solid(case)
    wall = [Polygon(w.contour.evaluate(np.linspace(0, w.contour.n_segments, 20001)[:-1])) for w in pockets[0].walls]
    region = wall[0].difference(wall[1])
    rng = np.random.default_rng(7)
    xy = rng.uniform(-45, 45, size=(300, 2))
    xy = xy[(np.hypot(*xy.T) > 12) & (np.hypot(*xy.T) < RIM - 1)]  # off the bore and keyway, inside the rim
    inside = shapely.contains_xy(region.buffer(-0.01), xy[:, 0], xy[:, 1])
    outside = ~shapely.contains_xy(region.buffer(0.01), xy[:, 0], xy[:, 1])
    top = first_hit_from_above(solid.vertices, solid.triangles, xy)
    assert inside.sum() > 20 and outside.sum() > 20
    assert np.allclose(top[inside], THICKNESS - DEPTH, atol=1e-9)
    assert np.allclose(top[outside], THICKNESS, atol=1e-9)


def _stl(case, tmp_path, fmt="stl"):
    from camgen.export.solid import mesh_bytes

    solid = _solid(case)
    path = tmp_path / ("cam.stl" if fmt in ("stl", "stl_ascii") else f"cam.{fmt}")
    path.write_bytes(mesh_bytes(solid, fmt, case))
    return solid, path


@pytest.mark.parametrize("case", ["eccentric", "spline", "through_slot"])
def test_stl_passes_admesh(case, tmp_path):
    """admesh reads the binary STL: nothing to repair, no disconnected facet, every facet, the volume (float32
    summation bound as in test_solid)."""
    admesh = require_tool("admesh")
    solid, path = _stl(case, tmp_path)
    out = admesh_clean(admesh, path)
    assert re.search(r"Number of facets\s*:\s*(\d+)", out).group(1) == str(len(solid.triangles))
    rel = max(1e-6, len(solid.triangles) * 2.0**-24)
    assert float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1)) == pytest.approx(exact_volume(CASES[case]), rel=rel)


@pytest.mark.parametrize("case", ["eccentric", "spline"])
def test_openscad_imports_and_renders_the_stl(case, tmp_path):
    """OpenSCAD imports the STL and renders it through CGAL (a union with a small cube far from it:
    CGAL takes only a closed polyhedron); its output holds the body's volume and bounding box
    beside the cube."""
    import trimesh

    openscad = require_tool("openscad")
    solid, path = _stl(case, tmp_path)
    (tmp_path / "cam.scad").write_text('union() { import("cam.stl"); translate([100, 100, 0]) cube(1); }\n')
    proc = subprocess.run([openscad, "--render", "-o", "out.stl", "--export-format", "binstl", "cam.scad"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert "WARNING" not in proc.stderr and "ERROR" not in proc.stderr, proc.stderr
    out = trimesh.load(tmp_path / "out.stl", force="mesh")
    assert out.is_watertight and out.body_count == 2
    expected = exact_volume(CASES[case]) + 1.0
    assert abs(out.volume - expected) <= volume_bound(CASES[case], 1e-3) + 1e-6 * expected  # the chord bound, float32 vertices
    body = out.split(only_watertight=True)
    big = max(body, key=lambda m: m.volume)
    assert np.allclose(big.bounds, [[-RIM, -RIM, 0], [RIM, RIM, THICKNESS]], atol=1e-3)


def test_prusa_slicer_reads_the_stl(tmp_path):
    """PrusaSlicer (Debian prusa-slicer 2.5) reads the STL: manifold, one part, the volume (its
    float32 facets: the bound as admesh's), the size."""
    exe = require_tool("prusa-slicer")
    solid, path = _stl("spline", tmp_path)
    proc = subprocess.run([exe, "--loglevel", "1", "--info", str(path)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    info = dict(re.findall(r"^(\w+) = (.+)$", proc.stdout, re.M))
    assert info["manifold"].strip() == "yes" and info["number_of_parts"].strip() == "1"
    assert int(info["number_of_facets"]) == len(solid.triangles)
    rel = max(1e-6, len(solid.triangles) * 2.0**-24)
    assert float(info["volume"]) == pytest.approx(exact_volume(CASES["spline"]), rel=rel)
    assert float(info["size_z"]) == pytest.approx(THICKNESS, abs=1e-5)


@pytest.mark.parametrize("fmt", ["stl_ascii", "3mf", "obj", "ply"])
def test_other_mesh_formats_read_back_by_trimesh_and_meshio(fmt, tmp_path):
    """trimesh reads every format (closed, the volume); meshio reads the OBJ, PLY and ASCII STL
    (its own parsers: the triangle count and the vertices' heights)."""
    import trimesh

    solid, path = _stl("spline", tmp_path, fmt)
    mesh = trimesh.load(path, force="mesh")
    assert mesh.is_watertight and mesh.is_winding_consistent
    rel = 1e-6 if fmt in ("ply", "3mf") else 1e-8
    assert mesh.volume == pytest.approx(solid.volume, rel=rel)
    assert abs(mesh.volume - exact_volume(CASES["spline"])) <= volume_bound(CASES["spline"], 1e-3) + rel * mesh.volume
    if fmt != "3mf":
        import meshio

        read = meshio.read(path)
        assert sum(len(c.data) for c in read.cells if c.type == "triangle") == len(solid.triangles)
        assert set(np.round(read.points[:, 2], 5)) == {0.0, THICKNESS - DEPTH, THICKNESS}


def test_mesh_file_sizes_stay_within_the_cap_counting_the_walls(tmp_path):
    """Each surface file is within BYTES_PER_VERTEX x (outline, hole and wall vertices +
    EXTRA_VERTICES), the bound camgen.planning.check_flat_size applies before meshing."""
    from camgen.export.pocket import wall_flat_count
    from camgen.export.solid import BYTES_PER_VERTEX, EXTRA_VERTICES, bore_polygon, mesh_bytes
    from camgen.planning import _flat_count

    for case in ("spline", "groove_and_slot"):
        for tol in (1e-3, 1e-5):
            solid = _solid(case, tol)
            outline = len(RIM_CONTOUR.flatten(tol)) + len(bore_polygon(BODY, tol))
            walls = sum(len(w.contour.flatten(tol)) for p in CASES[case] for w in p.walls)
            assert wall_flat_count(CASES[case], tol) == walls
            assert _flat_count(RIM_CONTOUR, BODY, tol, CASES[case]) >= outline + walls - 4  # the keyway's corners aside
            for fmt, per in BYTES_PER_VERTEX.items():
                assert len(mesh_bytes(solid, fmt)) <= per * (outline + walls + EXTRA_VERTICES), (case, tol, fmt)


def test_walls_crossing_the_bore_are_a_geometry_error():
    """A groove whose inner wall runs through the bore is no body: a GeometryError naming the cam."""
    from camgen.errors import GeometryError
    from camgen.export.pocket_solid import pocket_solid

    bad = (Pocket("groove", (Wall("GROOVE_OUTER", circle((0.0, 0.0), 20.0)), Wall("GROOVE_INNER", circle((3.0, 0.0), 7.0))), DEPTH),)
    with pytest.raises(GeometryError, match="cam 'bad'.*the top face cross or overlap"):
        pocket_solid(RIM_CONTOUR, BODY, bad, 1e-3, "bad")
    overlapping = (circle_groove((0.0, 0.0), 25.0), slot(3.0))  # the slot reaches into the groove
    with pytest.raises(GeometryError, match="cross or overlap"):
        pocket_solid(RIM_CONTOUR, BODY, overlapping, 1e-3, "bad")


# --------------------------------------------------------------------------------------------
# STEP: the exact body with its pockets
# --------------------------------------------------------------------------------------------
def _occt_shape(data: bytes):
    from OCP.STEPControl import STEPControl_Reader

    reader = STEPControl_Reader()
    assert int(reader.ReadStream("cam.step", io.BytesIO(data))) == 1
    reader.TransferRoots()
    return reader.OneShape()


@pytest.mark.parametrize("case", list(CASES))
def test_step_body_is_valid_with_the_closed_form_volume(case):
    """OpenCASCADE reads the file back: BRepCheck valid, one solid, its volume the closed form
    within 1e-6 relative (arcs exact; spline walls within bspline_tol = 1e-8 mm: 1e-9 relative;
    OCCT's integration adds ~1e-8), far below a pocket's volume; its bounding box the rim's and
    the thickness."""
    pytest.importorskip("OCP")
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    from camgen.export.step import step_bytes, step_volume

    pockets = CASES[case]
    data = step_bytes(RIM_CONTOUR, BODY, case, pockets=pockets)
    shape = _occt_shape(data)
    assert BRepCheck_Analyzer(shape).IsValid()
    solids = TopExp_Explorer(shape, TopAbs_SOLID)
    count = 0
    while solids.More():
        count += 1
        solids.Next()
    assert count == 1
    exact = exact_volume(pockets)
    assert abs(step_volume(data) - exact) <= 1e-6 * exact
    assert 1e-6 * exact < 0.01 * min(pocket_area(p) * p.depth for p in pockets)
    box = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, box, False, False)  # the geometry's box (no tolerance gap)
    lo, hi = box.CornerMin(), box.CornerMax()
    assert lo.Z() == pytest.approx(0.0, abs=1e-6) and hi.Z() == pytest.approx(THICKNESS, abs=1e-6)
    assert hi.X() == pytest.approx(RIM, abs=1e-6)
    splines = any(isinstance(seg, Spline) for p in pockets for w in p.walls for seg in w.contour.segments)
    stated = re.search(rb"FILE_DESCRIPTION\(\('([^']*)'", data).group(1).decode()
    assert stated.endswith("within 1e-08 mm of the contour" if splines else "exact arcs, lines and B-splines"), stated


# --------------------------------------------------------------------------------------------
# Through the run: a toy form with a groove gets its files; the lift table of a slot is refused
# --------------------------------------------------------------------------------------------
def _groove_form():
    """A form registered from the test: the rim circle and a groove between the offsets of the
    polar pitch curve r = 30 + s(phi) (the motion's law), +- HALF."""
    from camgen.checks import Follower
    from camgen.forms import CamForm
    from camgen.kinds.base import BuiltCam, CamSpec, body_keys, check_keys, read_body, read_checks

    def read(where, name, parsed, motion, base_dir=None):
        from camgen.synthesis.followers import FollowerSpec

        law = motion.read_law(where, parsed, FollowerSpec(kind="knife", base_radius=30.0), base_dir).law
        return CamSpec(name, motion.name, law, read_body(where, parsed), read_checks(parsed), Follower("roller", roller_radius=1.0))

    def build(spec, stages):
        phi = np.linspace(0.0, 2 * math.pi, 721)
        radius = 30.0 + spec.params(phi)[0]
        points = radius[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
        points[-1] = points[0]
        pitch = Contour([Spline.interpolate(phi, points)])
        groove = Pocket("groove", (Wall("GROOVE_OUTER", pitch.offset(HALF)), Wall("GROOVE_INNER", pitch.offset(-HALF))), DEPTH,
                        2 * HALF, pitch)
        return BuiltCam(spec.name, spec.kind, RIM_CONTOUR, {}, spec.body, spec.follower, pockets=(groove,))

    return CamForm("toy_groove", "a rim with a groove along a polar pitch curve", lambda: body_keys() + check_keys(), read=read, build=build)


SEGMENTS = [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 6.0}, {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -6.0}]
GROOVE_CAM = {"kind": "motion_law", "form": "toy_groove", "segments": SEGMENTS, "thickness_mm": THICKNESS, "bore_diameter_mm": 16.0}


@pytest.fixture
def groove_form():
    from camgen.forms import register, unregister

    register(_groove_form())
    yield
    unregister("toy_groove")


def test_a_form_with_a_groove_gets_its_files_through_the_run(groove_form):
    """The run writes the DXF with the wall layers, the point list with its wall column and the lift
    table with a column per wall (and report.json says so), the meshes and the STEP of the
    pocketed body (volumes the closed form)."""
    import trimesh

    from camgen.export.step import step_volume
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": ["dxf", "points", "lift", "stl", "3mf", "step"]}, "cams": {"g": GROOVE_CAM}}, "toy")
    files = execute(scene, plan_run(scene)).files
    report = json.loads(files["report.json"])
    meta = report["tables"]["g_points.csv"]
    assert list(meta["columns"]) == ["x_mm", "y_mm", "wall"] and meta["walls"] == ["PROFILE", "GROOVE_OUTER", "GROOVE_INNER"]
    loops = read_points(files["g_points.csv"])
    assert list(loops) == ["PROFILE", "GROOVE_OUTER", "GROOVE_INNER"]
    # the walls are the pitch curve r = 30 + s(phi) offset by +-HALF: each point of a wall is HALF
    # from the pitch curve (the closed-form law, Norton eq. 8.6, sampled densely)
    phi = np.linspace(0, 2 * math.pi, 200001)
    x = np.where(phi < math.pi, phi / math.pi, (phi - math.pi) / math.pi)
    s = 6.0 * (x - np.sin(2 * math.pi * x) / (2 * math.pi))
    s = np.where(phi < math.pi, s, 6.0 - s)
    pitch = Chain(segments=np.concatenate([p := (30 + s)[:, None] * np.stack([np.cos(phi), np.sin(phi)], 1), np.roll(p, -1, 0)], 1))
    for layer in ("GROOVE_OUTER", "GROOVE_INNER"):
        assert np.max(np.abs(pitch.distance(loops[layer], k=4) - HALF)) < 1e-5
    # the lift table: each wall's radius along each ray is a point HALF from the pitch curve
    lift = np.loadtxt(io.StringIO(files["g_lift.csv"]), delimiter=",", skiprows=1)
    assert list(report["tables"]["g_lift.csv"]["columns"])[3:] == ["groove_outer_radius_mm", "groove_inner_radius_mm"]
    ray = np.stack([np.cos(np.radians(lift[:, 0])), np.sin(np.radians(lift[:, 0]))], axis=1)
    for column in (3, 4):
        assert np.max(np.abs(pitch.distance(lift[:, column, None] * ray, k=4) - HALF)) < 1e-5
    # the outer wall beyond the pitch curve along each ray, the inner one inside it (r = 30 + s)
    u = np.mod(np.radians(lift[:, 0]), 2 * math.pi) / math.pi
    rise = 6.0 * (u % 1 - np.sin(2 * math.pi * u) / (2 * math.pi))
    on_pitch = 30.0 + np.where(u < 1, rise, 6.0 - rise)
    assert np.all(lift[:, 3] > on_pitch + HALF / 2) and np.all(lift[:, 4] < on_pitch - HALF / 2)
    doc = read_dxf(files["g.dxf"])
    assert {"GROOVE_OUTER", "GROOVE_INNER"} <= {layer.dxf.name for layer in doc.layers}
    # the area between the offsets +-h of a closed convex curve of length L is 2 h L (Steiner's
    # formula A(d) = A + d L + pi d^2); L of the dense polygon through the closed-form pitch curve
    length = float(np.sum(np.hypot(*(np.roll(p, -1, 0) - p).T)))
    expected = (math.pi * RIM**2 - math.pi * 64.0) * THICKNESS - 2 * HALF * length * DEPTH
    tol = report["chord_tol_mm"]
    bound = tol * (2 * math.pi * (RIM + 8.0) * THICKNESS + 2 * length * DEPTH) + 1e-5 * 2 * HALF * length * DEPTH  # + the toy's spline fit
    mesh = trimesh.load(io.BytesIO(files["g.3mf"]), file_type="3mf", force="mesh")
    assert mesh.is_watertight and abs(mesh.volume - expected) <= bound
    assert abs(step_volume(files["g.step"]) - expected) <= bound


def _slot_form():
    """A rim with a slot beside the axis (no ray from the axis meets it once: no lift column)."""
    from camgen.forms import CamForm
    from camgen.kinds.base import BuiltCam

    form = _groove_form()

    def build(spec, stages):
        return BuiltCam(spec.name, spec.kind, RIM_CONTOUR, {}, spec.body, spec.follower, pockets=(slot(4.0),))

    return CamForm("toy_slot", "a rim with a slot", form.keys, read=form.read, build=build)


@pytest.fixture
def slot_form():
    from camgen.forms import register, unregister

    register(_slot_form())
    yield
    unregister("toy_slot")


def _refused(scene_table, tmp_path, capsys) -> str:
    """Run the scene through the CLI: exit 2, one ``camgen: error:`` line (returned), nothing written."""
    from camgen.cli import main
    from helpers import scene_toml

    scene = tmp_path / "pockets.toml"
    scene.write_text(scene_toml(scene_table))
    out = tmp_path / "out"
    assert main(["run", str(scene), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: error:"), err
    assert not out.exists() or not any(out.rglob("*"))
    return err[0]


def test_lift_table_of_a_slot_beside_the_axis_is_refused_through_the_cli(slot_form, tmp_path, capsys):
    cam = dict(GROOVE_CAM, form="toy_slot")
    line = _refused({"output": {"formats": ["dxf", "lift"]}, "cams": {"s": cam}}, tmp_path, capsys)
    assert "output.formats" in line and "lift" in line and "'s'" in line and "SLOT" in line and "star-shaped" in line


def test_lift_table_has_a_radius_column_per_wall_on_the_closed_form():
    """Eccentric circular walls (centre c, radius r): the ray at polar angle phi meets a circle
    about c at rho = c.u + sqrt(r^2 - (c x u)^2), u = (cos phi, sin phi); the rim at R."""
    from camgen.export.points import lift_csv, lift_metadata

    pockets = CASES["eccentric"]
    text = lift_csv(RIM_CONTOUR, math.radians(0.5), pockets)
    assert text.splitlines()[0] == "polar_angle_deg,radius_mm,lift_mm,groove_outer_radius_mm,groove_inner_radius_mm"
    rows = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1)
    phi = np.radians(rows[:, 0])
    c = np.array([3.0, 1.0])
    along, across = c[0] * np.cos(phi) + c[1] * np.sin(phi), c[0] * np.sin(phi) - c[1] * np.cos(phi)
    assert len(rows) == 720 and np.allclose(rows[:, 1], RIM, atol=1e-9) and np.allclose(rows[:, 2], 0.0, atol=1e-9)
    for column, r in ((3, 30.0 + HALF), (4, 30.0 - HALF)):
        assert np.max(np.abs(rows[:, column] - (along + np.sqrt(r * r - across**2)))) <= 1e-9
    meta = lift_metadata(RIM_CONTOUR, math.radians(0.5), pockets)
    assert list(meta["columns"]) == text.splitlines()[0].split(",")


def test_lift_writer_refuses_a_slot_naming_the_wall():
    """The writer itself (library callers): ParameterError naming output.formats and the walls."""
    from camgen.writers import RunSettings, lift

    class Cam:
        name, pockets, contour = "s", CASES["slot"], RIM_CONTOUR

    class Output:
        lift_step = math.radians(1.0)

    with pytest.raises(ParameterError, match=r"output\.formats.*walls SLOT.*wall SLOT: contour is not star-shaped"):
        lift(Cam(), RunSettings("x", Output(), None), "lift")


# --------------------------------------------------------------------------------------------
# The bundled groove cam (templates/groove_cam.toml)
# --------------------------------------------------------------------------------------------
def _cycloidal_pitch_length(prime: float, lift: float, samples: int = 400_000) -> float:
    """Length (mm) of the pitch curve of a radial translating roller on the template's program:
    polar radius prime + s over the turn, s cycloidal rise of ``lift`` over 120 deg, dwell 60,
    cycloidal return over 120, dwell 60 (Norton eq. 8.6); the dense polygon (its chords fall
    short of the curve by ~1e-9 relative)."""
    theta = 2 * math.pi * np.arange(samples) / samples
    beta = 2 * math.pi / 3
    x = np.clip(theta / beta, 0, 1)
    y = np.clip((theta - math.pi) / beta, 0, 1)
    s = lift * (x - np.sin(2 * math.pi * x) / (2 * math.pi)) - lift * (y - np.sin(2 * math.pi * y) / (2 * math.pi))
    p = (prime + s)[:, None] * np.stack([np.cos(theta), np.sin(theta)], axis=1)
    return float(np.sum(np.hypot(*(np.roll(p, -1, axis=0) - p).T)))


def test_groove_cam_template_files_are_the_pocketed_body(tmp_path):
    """The bundled groove cam: the meshes and the STEP hold the plate of the rim's radius, less bore
    and keyway, less the groove: the area between the offsets +-w of the pitch curve is 2 w L
    (Steiner's formula, the walls simple curves), L from the closed-form law; the DXF's wall
    layers and the point list's walls are the form's walls within the chord tolerance; admesh
    reads the STL; the lift table has a column per wall (the FEA meshes: tests/test_fea_pockets.py)."""
    import trimesh

    from camgen.export.step import step_volume
    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template

    scene = load_template("groove_cam")
    result = execute(scene, plan_run(scene, ["dxf", "points", "lift", "stl", "3mf", "step"]))
    (cam,) = result.cams
    files = result.files
    (groove,) = cam.pockets
    body, tol = cam.body, scene.output.chord_tol
    (rim,) = cam.contour.segments
    assert isinstance(rim, Arc) and rim.center == (0.0, 0.0)
    w = cam.figures["groove"]["wall_offset_mm"]
    assert w == pytest.approx(10.0 + 0.05 / 2, abs=1e-12)  # roller radius + clearance / 2 (the template)
    length = _cycloidal_pitch_length(60.0, 20.0)  # prime radius = base 50 + roller 10
    exact = (math.pi * rim.radius**2 - hole_area(body)) * body.thickness - 2 * w * length * groove.depth
    hole_perimeter = math.pi * body.bore_diameter + 2 * (body.keyway_depth + body.keyway_width)
    bound = tol * ((2 * math.pi * rim.radius + hole_perimeter) * body.thickness + 2 * length * groove.depth) + 1e-7 * exact
    mesh = trimesh.load(io.BytesIO(files["track.3mf"]), file_type="3mf", force="mesh")
    assert mesh.is_watertight and mesh.is_volume and abs(mesh.volume - exact) <= bound
    assert bound < 0.01 * 2 * w * length * groove.depth
    assert abs(step_volume(files["track.step"]) - exact) <= 1e-6 * exact
    doc = read_dxf(files["track.dxf"])
    for wall in groove.walls:
        assert_layer_is_the_curve(wall.contour, doc, wall.layer, tol)
    loops = read_points(files["track_points.csv"])
    assert list(loops) == ["PROFILE", "GROOVE_OUTER", "GROOVE_INNER"]
    lift = np.loadtxt(io.StringIO(files["track_lift.csv"]), delimiter=",", skiprows=1)
    # along a ray the walls are at least the width apart (each wall point is w from the pitch curve,
    # which the ray crosses between them), within the walls' fit tolerance
    assert np.all(lift[:, 3] - lift[:, 4] >= 2 * w - 1e-6)
    path = tmp_path / "track.stl"
    path.write_bytes(files["track.stl"])
    out = admesh_clean(require_tool("admesh"), path)
    assert float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1)) == pytest.approx(exact, rel=max(1e-6, len(mesh.faces) * 2.0**-24))
