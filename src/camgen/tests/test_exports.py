"""Exports for machining, each read back by an independent tool."""
from __future__ import annotations

import io
import math
import re
import subprocess

import numpy as np
import pytest

import camgen
from camgen.errors import GeometryError, ParameterError
from camgen.export.dxf import DxfOptions, contour_to_dxf
from camgen.export.gcode import MachiningSpec, gcode_program
from camgen.export.points import base_radius, lift_csv
from camgen.export.solid import SolidSpec, cam_solid, mesh_bytes
from camgen.tests.helpers import distance_to_arcs, require_tool, rs274_toolpath

STRIDE = (220.0, 160.0, 25.0)
HEIGHT = (220.0, 220.0, 10.0)
BODIES = {
    "stride": SolidSpec(thickness=20.0, bore_diameter=20.0, keyway_width=6.0, keyway_depth=2.8, min_wall=3.0),
    "height": SolidSpec(thickness=20.0, bore_diameter=8.0, keyway_width=2.0, keyway_depth=1.0, min_wall=3.0),
    "steering": SolidSpec(thickness=8.0, bore_diameter=8.0, keyway_width=2.0, keyway_depth=1.0, min_wall=3.0),
}


@pytest.fixture(scope="module")
def steering():
    from camgen.mechanisms import tricycle as tc
    from camgen.synthesis.trajectory import trajectory_from_expression

    return tc.tricycle_cam(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0))


@pytest.fixture(scope="module")
def contours(steering):
    return {"stride": camgen.three_arc_cam(*STRIDE), "height": camgen.three_arc_cam(*HEIGHT), "steering": steering.profile}


def radial_error(contour, points):
    """|r - polar radius of the contour| at the points' polar angles (>= their normal distance)."""
    ang = np.arctan2(points[:, 1], points[:, 0])
    return np.abs(np.hypot(points[:, 0], points[:, 1]) - contour.polar_radius(ang))


# --- DXF --------------------------------------------------------------------------------------------
def _read_dxf(text):
    import ezdxf

    doc = ezdxf.read(io.StringIO(text))
    assert not doc.audit().has_errors
    assert doc.dxfversion == "AC1024" and doc.header["$INSUNITS"] == 4
    return doc


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_dxf_entities_match_the_contour_by_ezdxf(name, contours, steering):
    contour = contours[name]
    pitch = steering.pitch if name == "steering" else None
    doc = _read_dxf(contour_to_dxf(contour, BODIES[name], pitch))
    msp = doc.modelspace()
    profile = [e for e in msp if e.dxf.layer == "PROFILE"]
    assert len(profile) == contour.n_segments
    for entity, seg in zip(profile, contour.segments):
        if entity.dxftype() == "ARC":
            assert entity.dxf.radius == pytest.approx(seg.radius, abs=1e-9)
        else:
            assert entity.dxftype() == "SPLINE" and entity.dxf.degree == 3
            knots = np.array(entity.knots)
            assert np.all(knots[:4] == knots[0]) and np.all(knots[-4:] == knots[-1])  # clamped
            pts = np.array(list(entity.construction_tool().points(np.linspace(knots[0], knots[-1], 5001))))[:, :2]
            assert np.max(radial_error(contour, pts)) <= 1e-6
    bore = [e for e in msp if e.dxf.layer == "BORE"]
    assert bore and bore[0].dxf.radius == pytest.approx(BODIES[name].bore_diameter / 2)
    assert len([e for e in msp if e.dxf.layer == "KEYWAY"]) == 1
    assert len([e for e in msp if e.dxf.layer == "CENTER"]) == 2
    assert bool([e for e in msp if e.dxf.layer == "PITCH"]) == (pitch is not None)


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_dxf_read_by_gdal_within_1e6(name, contours, tmp_path):
    import pyogrio
    import shapely
    contour = contours[name]
    path = tmp_path / "cam.dxf"
    path.write_text(contour_to_dxf(contour, BODIES[name]))
    pyogrio.set_gdal_config_options({"OGR_ARC_STEPSIZE": "0.5"})  # GDAL samples arcs every 0.5 deg
    meta, _, wkb, fields = pyogrio.raw.read(path)
    layer = fields[list(meta["fields"]).index("Layer")]
    lines = shapely.from_wkb(wkb)[layer == "PROFILE"]
    pts = np.concatenate([shapely.get_coordinates(g) for g in lines])
    assert len(pts) > 100
    if name == "stride":
        assert np.max(distance_to_arcs(pts, contour.segments)) <= 1e-6
    else:
        assert np.max(radial_error(contour, pts)) <= 1e-6
    # the PROFILE pieces go all the way round: their total length is the contour's perimeter
    assert sum(g.length for g in lines) == pytest.approx(contour.length, rel=1e-4)


@pytest.mark.parametrize("tol", [1e-2, 1e-3, 1e-4])
def test_dxf_biarcs_within_tolerance(tol, contours, tmp_path):
    contour = contours["steering"]
    doc = _read_dxf(contour_to_dxf(contour, options=DxfOptions(splines="biarc", biarc_tol=tol)))
    arcs = [e for e in doc.modelspace() if e.dxf.layer == "PROFILE"]
    assert {e.dxftype() for e in arcs} <= {"ARC", "LINE"}
    from types import SimpleNamespace

    segs = [
        SimpleNamespace(center=(e.dxf.center.x, e.dxf.center.y), radius=e.dxf.radius, start_angle=math.radians(e.dxf.start_angle),
                        sweep=math.radians((e.dxf.end_angle - e.dxf.start_angle) % 360))
        for e in arcs if e.dxftype() == "ARC"
    ]
    # every point of the exact profile is within tol of the arcs read back from the file
    samples = contour.evaluate(np.linspace(0, 1, 20000, endpoint=False))
    assert np.max(distance_to_arcs(samples, segs)) <= tol * (1 + 1e-6)
    # and they come back in fewer entities than the spline has pieces when the tolerance allows
    if tol >= 1e-3:
        assert len(arcs) < contour.segments[0].n_pieces


# --- solids ------------------------------------------------------------------------------------------
def _shapely_section(contour, body, tol):
    from shapely.geometry import Polygon, box
    from shapely import affinity

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


@pytest.mark.parametrize("fmt", ["stl", "stl_ascii", "3mf", "obj", "ply", "vtu", "msh", "inp"])
def test_mesh_formats_read_back(fmt, contours, tmp_path):
    contour, body = contours["stride"], BODIES["stride"]
    solid = cam_solid(contour, body, 1e-3)
    data = mesh_bytes(solid, fmt, "stride")
    assert data == mesh_bytes(solid, fmt, "stride")  # deterministic
    suffix = {"stl_ascii": "stl"}.get(fmt, fmt)
    path = tmp_path / f"cam.{suffix}"
    path.write_bytes(data)
    if fmt in ("vtu", "msh", "inp"):
        import meshio

        mesh = meshio.read(path)
        tri = mesh.points[mesh.cells_dict["triangle"]]
        volume = np.sum(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))) / 6
        assert volume == pytest.approx(solid.volume, rel=1e-12)
        return
    import trimesh

    mesh = trimesh.load(path, force="mesh")
    assert mesh.is_watertight and mesh.is_winding_consistent
    rel = 1e-6 if fmt in ("stl", "ply", "3mf") else 1e-9  # float32 in binary STL/PLY, 3MF text precision
    assert mesh.volume == pytest.approx(solid.volume, rel=rel)
    if fmt == "3mf":
        assert mesh.units in ("millimeter", "millimeters", "mm")


def test_binary_stl_passes_admesh(contours, tmp_path):
    admesh = require_tool("admesh")
    path = tmp_path / "cam.stl"
    solid = cam_solid(contours["height"], BODIES["height"], 1e-3)
    path.write_bytes(mesh_bytes(solid, "stl"))
    # admesh always exits 0 and echoes the 80-byte header's raw bytes: decode leniently, parse the figures
    out = subprocess.run([admesh, "-e", str(path)], capture_output=True, timeout=60).stdout.decode("utf-8", "replace")
    figures = {k.strip(): v for k, v in re.findall(r"^([A-Za-z ]+?)\s*:\s*(\d+)", out, re.M)}
    for key in ("Degenerate facets", "Edges fixed", "Facets removed", "Facets added", "Facets reversed", "Backwards edges", "Normals fixed"):
        assert int(figures[key]) == 0, (key, out)
    assert re.search(r"Total disconnected facets\s*:\s*0\s+0", out), out
    assert re.search(r"Number of facets\s*:\s*(\d+)", out).group(1) == str(len(solid.triangles))
    assert float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1)) == pytest.approx(solid.volume, rel=1e-6)


@pytest.mark.parametrize(
    "body, fragment",
    [
        (SolidSpec(bore_diameter=21.0, min_wall=0.5), "breaks through"),
        (SolidSpec(bore_diameter=16.0, min_wall=3.0), "wall of only"),
        (SolidSpec(bore_diameter=8.0, keyway_width=2.0, keyway_depth=6.0, keyway_angle=0.0, min_wall=0.5), "breaks through"),
    ],
)
def test_bore_or_keyway_breaking_the_wall_is_an_error(body, fragment, contours):
    with pytest.raises(GeometryError, match=fragment):
        cam_solid(contours["height"], body)  # base radius c = 10 mm


def test_wall_is_measured_where_it_is_thinnest(contours):
    from camgen.export.solid import wall_left

    wall, where = wall_left(contours["height"], SolidSpec(bore_diameter=8.0))
    # the whole base arc (+-30 deg for b = a) is 10 mm from the axis
    assert wall == pytest.approx(10.0 - 4.0, abs=2e-4) and (where <= 30.01 or where >= 329.99)
    wall, where = wall_left(contours["height"], SolidSpec(bore_diameter=8.0, keyway_width=2.0, keyway_depth=5.5, keyway_angle=0.0))
    # thinnest at the keyway's outer corners (9.5, +-1): 10 - hypot(9.5, 1) from the base circle
    assert wall == pytest.approx(10.0 - math.hypot(9.5, 1.0), abs=2e-4) and (where < 15 or where > 345)


# --- G-code ----------------------------------------------------------------------------------------
@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


def _check_program(program, intended, tmp_path, spec):
    status, message, moves = rs274_toolpath(program, tmp_path)
    assert status == 0, message
    depth = -spec.thickness
    cutting = [pts for z, pts in moves if abs(z - depth) < 1e-9]
    assert cutting
    # the lead-in/out lines are not on the contour: drop the first and last move of the pass
    contour_pts = np.concatenate([p[1:] for p in cutting[1:-1]])
    assert np.max(radial_error(intended, contour_pts)) <= 1e-3
    z_levels = sorted({round(z, 6) for z, _ in moves if z < 0})
    assert len(z_levels) == math.ceil(spec.thickness / spec.step_down)
    return contour_pts


@pytest.mark.parametrize("direction", ["climb", "conventional"])
@pytest.mark.usefixtures("needs_rs274")
def test_gcode_three_arc_runs_in_rs274_and_follows_the_offset(direction, contours, tmp_path):
    spec = MachiningSpec(thickness=6.0, step_down=2.5, direction=direction, tool_diameter=8.0)
    program = gcode_program(contours["stride"], spec, "stride")
    assert program.count("G2 ") + program.count("G3 ") == 6 * 3  # exact arcs, 3 passes
    intended = contours["stride"].offset(4.0)
    pts = _check_program(program, intended, tmp_path, spec)
    signed = 0.5 * np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - pts[:, 1] * np.roll(pts[:, 0], -1))
    assert (signed < 0) == (direction == "climb")  # climb: clockwise round the outside


@pytest.mark.parametrize("mode", ["biarcs", "lines"])
@pytest.mark.usefixtures("needs_rs274")
def test_gcode_spline_cam_runs_in_rs274(mode, contours, tmp_path):
    spec = MachiningSpec(thickness=4.0, step_down=2.0, tool_diameter=6.0, spline_mode=mode, chord_tol=5e-4)
    program = gcode_program(contours["steering"], spec, "steering")
    if mode == "biarcs":
        assert "G1 X" in program and program.count("G2 ") > 20
    intended = contours["steering"].offset(3.0, spline_tol=1e-7)
    _check_program(program, intended, tmp_path, spec)


@pytest.mark.parametrize("direction", ["climb", "conventional"])
@pytest.mark.usefixtures("needs_rs274")
def test_gcode_cutter_compensation_done_by_rs274(direction, contours, tmp_path):
    spec = MachiningSpec(thickness=2.0, step_down=2.0, tool_diameter=8.0, cutter_compensation=True, direction=direction)
    program = gcode_program(contours["stride"], spec, "stride")
    assert ("G41.1 D8.0000 G1" in program) == (direction == "climb")
    assert ("G42.1 D8.0000 G1" in program) == (direction != "climb")
    _check_program(program, contours["stride"].offset(4.0), tmp_path, spec)


def test_gcode_header_dialects_and_errors(contours):
    linux = gcode_program(contours["stride"], MachiningSpec())
    assert "G21 G90 G17 G40 G49 G80 G94" in linux and "G64 P0.0010" in linux and linux.rstrip().endswith("M2")
    grbl = gcode_program(contours["stride"], MachiningSpec(dialect="grbl"))
    assert "G64" not in grbl and "G41" not in grbl and "M3 S8000" in grbl
    with pytest.raises(ParameterError, match="cutter_compensation"):
        MachiningSpec(dialect="grbl", cutter_compensation=True)
    with pytest.raises(ParameterError, match="lead"):
        MachiningSpec(lead=2.0, tool_diameter=6.0)


def test_gcode_refuses_a_tool_that_would_gouge():
    from camgen.contour import Contour, Spline

    theta = np.linspace(0, 2 * math.pi, 49)
    r = 40 + 8 * np.cos(3 * theta)  # concave at 60, 180, 300 deg with radius 25.6 mm
    contour = Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])
    gcode_program(contour, MachiningSpec(tool_diameter=40.0))
    with pytest.raises(GeometryError, match=r"diameter 60 mm would gouge.*cam angle (59|60|179|180|299|300)\.\d+ deg"):
        gcode_program(contour, MachiningSpec(tool_diameter=60.0))


# --- point lists -----------------------------------------------------------------------------------------
def test_lift_table_against_table_1():
    cam = camgen.three_arc_cam(*STRIDE)
    text = lift_csv(cam, math.radians(0.5), "stride", "test")
    assert "units: deg, mm" in text and "base radius 25.000000000 mm" in text
    rows = [line for line in text.splitlines() if not line.startswith("#")]
    assert rows[0] == "cam_angle_deg,radius_mm,lift_mm"
    data = np.loadtxt(rows[1:], delimiter=",")
    assert data.shape == (720, 3)
    _, radius = camgen.yoke_law(*STRIDE, np.radians(data[:, 0]))  # Table 1's radius vector R
    assert np.max(np.abs(data[:, 1] - radius)) <= 2e-9
    assert np.allclose(data[:, 2], data[:, 1] - 25.0, atol=2e-9)
    assert base_radius(camgen.three_arc_cam(*HEIGHT)) == pytest.approx(10.0, abs=1e-12)


# --- STEP (optional extra) ---------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["stride", "steering"])
def test_step_solid_is_exact(name, contours):
    from camgen.export.step import step_bytes, step_volume

    contour, body = contours[name], BODIES[name]
    data = step_bytes(contour, body, name)
    assert data == step_bytes(contour, body, name)  # deterministic
    text = data.decode("ascii")
    assert text.startswith("ISO-10303-21;") and "AUTOMOTIVE_DESIGN" in text and "SI_UNIT(.MILLI.,.METRE.)" in text
    cubic = "B_SPLINE_CURVE_WITH_KNOTS('',3,"  # (degree-1 B-splines are OCCT's parameter-space pcurves)
    if name == "stride":
        assert text.count("CIRCLE(") >= 2 * (6 + 1)  # six arcs and the bore, on both faces
        assert cubic not in text
    else:
        assert cubic in text
    r, h = body.bore_diameter / 2, body.keyway_width / 2
    keyway = 2 * h * (r + body.keyway_depth) - (h * math.sqrt(r * r - h * h) + r * r * math.asin(h / r))
    exact = (contour.area - math.pi * r * r - keyway) * body.thickness
    # OCCT integrates planar faces bounded by circles exactly; on B-spline boundaries its default
    # integration is approximate (shared/research/ecosystem.md section 6)
    assert step_volume(data) == pytest.approx(exact, rel=1e-9 if name == "stride" else 1e-4)


def test_bspline_form_has_the_fewest_knots_and_is_exact(steering):
    from scipy.interpolate import BSpline

    from camgen.export.dxf import spline_bspline

    for contour, per_piece in ((steering.pitch, 1), (steering.profile, 2)):  # C2 pitch, C1 refitted offset
        seg = contour.segments[0]
        knots, controls = spline_bspline(seg)
        assert len(controls) == per_piece * seg.n_pieces + (3 if per_piece == 1 else 2)
        curve = BSpline(knots, controls, 3)  # scipy evaluates the written form independently
        t = np.linspace(seg.breaks[0], seg.breaks[-1], 20001)
        assert np.max(np.abs(curve(t) - seg.eval_t(t))) <= 1e-9
