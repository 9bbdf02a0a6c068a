"""STEP solids, read back by OpenCASCADE."""
from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np
import pytest

from cams import BODIES
from helpers import occt_shape


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
    # OCCT integrates planar faces bounded by circles exactly; B-spline edges of a few spans each
    # (camgen.export.step.EDGE_SPANS) keep its one-rule-per-face integration within 1e-6
    assert step_volume(data) == pytest.approx(exact, rel=1e-9 if name == "stride" else 1e-6)


def test_bspline_form_has_the_fewest_knots_and_is_exact(steering):
    from scipy.interpolate import BSpline

    from camgen.export.dxf import spline_bspline
    from camgen.mechanisms import tricycle as tc

    # the earlier ("cartesian") form has a C2 pitch and a C1 refitted offset; the polar form's are both C2
    cartesian = tc.tricycle_cam(steering.trajectory, form="cartesian")
    for contour, per_piece in ((cartesian.pitch, 1), (cartesian.profile, 2), (steering.pitch, 1), (steering.profile, 1)):
        seg = contour.segments[0]
        knots, controls = spline_bspline(seg)
        assert len(controls) == per_piece * seg.n_pieces + (3 if per_piece == 1 else 2)
        curve = BSpline(knots, controls, 3)  # scipy evaluates the written form independently
        t = np.linspace(seg.breaks[0], seg.breaks[-1], 20001)
        assert np.max(np.abs(curve(t) - seg.eval_t(t))) <= 1e-9


def _step_shape(data: bytes, tmp_path):
    return occt_shape(data, tmp_path / "cam.step")


def _step_vertices_and_centroid(shape) -> tuple[np.ndarray, np.ndarray]:
    from OCP.BRep import BRep_Tool
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_VERTEX
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    pts = []
    explorer = TopExp_Explorer(shape, TopAbs_VERTEX)
    while explorer.More():
        p = BRep_Tool.Pnt_s(TopoDS.Vertex(explorer.Current()))
        pts.append((p.X(), p.Y(), p.Z()))
        explorer.Next()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    c = props.CentreOfMass()
    return np.array(pts), np.array([c.X(), c.Y()])


def _notch(points: np.ndarray, body) -> tuple[float, float]:
    """Direction (rad) and radius (mm) of the keyway's outer corners: the points off the axis by
    more than the bore radius and less than the keyway's corner radius (+1e-3 mm)."""
    r = body.bore_diameter / 2
    corner = math.hypot(r + body.keyway_depth, body.keyway_width / 2)
    radius = np.hypot(points[:, 0], points[:, 1])
    notch = points[(radius > r + 1e-3) & (radius < corner + 1e-3)]
    assert len(notch) >= 2
    mean = notch[:, :2].mean(axis=0)
    return math.atan2(mean[1], mean[0]), float(np.hypot(notch[:, 0], notch[:, 1]).max())


@pytest.mark.parametrize("angle_deg", [90.0, 30.0])
def test_keyway_and_profile_orientation_agree_in_stl_dxf_and_step(angle_deg, contours, tmp_path):
    """The keyway notch lies at the requested keyway_angle in the STL (trimesh), the DXF (ezdxf:
    KEYWAY corners and the gap of the BORE arc) and the STEP (OCP vertices), and the body's
    centroid is where GEOS puts the profile minus bore and keyway (so no writer turns or mirrors
    the profile against the keyway)."""
    import io

    import ezdxf
    import trimesh
    from shapely import affinity
    from shapely.geometry import Polygon, box

    from camgen.export.dxf import contour_to_dxf
    from camgen.export.solid import cam_solid, mesh_bytes
    from camgen.export.step import step_bytes

    contour = contours["stride"]
    body = replace(BODIES["stride"], keyway_angle=math.radians(angle_deg))
    want = math.radians(angle_deg)
    r = body.bore_diameter / 2
    corner = math.hypot(r + body.keyway_depth, body.keyway_width / 2)

    def same_angle(a):
        return abs(math.remainder(a - want, 2 * math.pi)) <= 1e-6

    # independent section: GEOS polygon of the exact profile minus bore and keyway
    outer = Polygon(contour.flatten(1e-5))
    t = np.linspace(0, 2 * math.pi, 20000, endpoint=False)
    key = affinity.rotate(box(0, -body.keyway_width / 2, r + body.keyway_depth, body.keyway_width / 2), angle_deg, origin=(0, 0))
    section = outer.difference(Polygon(np.stack([r * np.cos(t), r * np.sin(t)], 1)).union(key))
    centroid = np.array(section.centroid.coords[0])

    # STL
    (tmp_path / "cam.stl").write_bytes(mesh_bytes(cam_solid(contour, body, 1e-3), "stl"))
    mesh = trimesh.load(tmp_path / "cam.stl", force="mesh")
    walls = np.abs(mesh.face_normals[:, 2]) < 0.5  # the outline: cap triangles have interior vertices
    direction, reach = _notch(mesh.vertices[np.unique(mesh.faces[walls])], body)
    assert same_angle(direction) and reach == pytest.approx(corner, abs=1e-5)
    assert np.allclose(mesh.center_mass[:2], centroid, atol=1e-3)

    # DXF
    doc = ezdxf.read(io.StringIO(contour_to_dxf(contour, body)))
    keyway = [e for e in doc.modelspace() if e.dxf.layer == "KEYWAY"]
    pts = np.array([p[:2] for e in keyway for p in e.get_points("xy")])
    direction, reach = _notch(pts, body)
    assert same_angle(direction) and reach == pytest.approx(corner, abs=1e-12)
    (arc,) = [e for e in doc.modelspace() if e.dxf.layer == "BORE"]
    gap_middle = math.radians((arc.dxf.start_angle + arc.dxf.end_angle) / 2 + 180.0)  # the arc skips the keyway
    assert same_angle(gap_middle) and arc.dxf.radius == r

    # STEP
    shape = _step_shape(step_bytes(contour, body, "stride"), tmp_path)
    vertices, step_centroid = _step_vertices_and_centroid(shape)
    direction, reach = _notch(vertices, body)
    assert same_angle(direction) and reach == pytest.approx(corner, abs=1e-7)
    assert np.allclose(step_centroid, centroid, atol=1e-3)


# --------------------------------------------------------------------------------------------
# Every bundled template: compact exact geometry, OCCT's volume, the stated tolerance
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def template_cams():
    """Every manufacturable cam of every bundled template (synthesis and checks only)."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template, template_names

    cams = []
    for name in template_names():
        for cam in compute(load_template(name), Plan((), frozenset())).cams:
            if cam.manufacturable and cam.built.planar:  # a plate body (a barrel's STEP: tests of export/barrel_step.py)
                cams.append((name, cam))
    return cams


def _exact_volume(contour, body) -> float:
    """area x thickness: the profile's area (Green's theorem, exact for arcs and cubics) less the
    bore circle and the keyway's part outside it (circular segment, closed form)."""
    r, h = body.bore_diameter / 2, body.keyway_width / 2
    area = contour.area - math.pi * r * r
    if h > 0:
        area -= 2 * h * (r + body.keyway_depth) - (h * math.sqrt(r * r - h * h) + r * r * math.asin(h / r))
    return area * body.thickness


def test_occt_volume_of_every_template_step_is_within_1e6(template_cams):
    """Issue "Accuracy and numerical stability", item 2: OCCT's default volume (what FreeCAD
    shows) of every bundled template's STEP within 1e-6 relative of area x thickness (before:
    up to 8.5e-7, and 1e-3 for the motion-law cam of the issue); every spline edge has at most
    EDGE_SPANS knot spans; the header states the tolerance."""
    from camgen.export.step import EDGE_SPANS, step_bytes, step_volume

    assert len(template_cams) >= 12
    for name, cam in template_cams:
        data = step_bytes(cam.contour, cam.body, cam.name)
        exact = _exact_volume(cam.contour, cam.body)
        assert step_volume(data) == pytest.approx(exact, rel=1e-7), (name, cam.name)  # issue: 1e-6; measured <= 6e-9
        text = data.decode("ascii")
        if any(seg.kind == "spline" for seg in cam.contour.segments):
            assert f"FILE_DESCRIPTION(('camgen cam {cam.name}: B-spline edges within 1e-08 mm of the contour')" in text
            for knots in re.findall(r"B_SPLINE_CURVE_WITH_KNOTS\('',3,\(.*?\),\s*\.UNSPECIFIED\.,\s*\.F\.,\s*\.F\.,\s*\(([^)]*)\)", text, re.DOTALL):
                assert len(knots.split(",")) - 1 <= EDGE_SPANS


def _step_bspline_edges(shape, z: float = 0.0):
    """(knots, controls) of the cubic B-spline edges of ``shape`` in the plane ``z`` (each once)."""
    return [(knots, controls) for degree, knots, controls in step_bspline_edges(shape, z) if degree == 3]


def step_bspline_edges(shape, z: float = 0.0) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """(degree, knots, controls (n, 2)) of the B-spline edges of ``shape`` in the plane ``z`` (each
    once), as OCCT reads them."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GeomAbs import GeomAbs_BSplineCurve
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    found = {}
    explorer = TopExp_Explorer(shape, TopAbs_EDGE)
    while explorer.More():
        curve = BRepAdaptor_Curve(TopoDS.Edge(explorer.Current()))
        if curve.GetType() == GeomAbs_BSplineCurve:
            b = curve.BSpline()
            poles = np.array([[b.Pole(i).X(), b.Pole(i).Y(), b.Pole(i).Z()] for i in range(1, b.NbPoles() + 1)])
            if np.allclose(poles[:, 2], z):
                knots = np.repeat([b.Knot(i) for i in range(1, b.NbKnots() + 1)], [b.Multiplicity(i) for i in range(1, b.NbKnots() + 1)])
                found[(b.Degree(), round(knots[0], 12), round(knots[-1], 12))] = (b.Degree(), knots, poles[:, :2])
        explorer.Next()
    return list(found.values())


@pytest.mark.parametrize("template", ["tricycle", "motion_law", "lift_table"])
def test_step_edges_are_within_the_stated_tolerance_both_ways(template, template_cams, tmp_path):
    """The STEP read back by OCCT: its B-spline edges (poles and knots evaluated by scipy) lie
    within 1e-8 mm (the header's tolerance) of the contour, and every point of the contour
    within 1e-8 mm of an edge; together they have fewer control points than the old exact form
    (pieces + 3 per segment) wherever the tolerance allows."""
    from scipy.interpolate import BSpline

    from camgen.contour import Spline
    from camgen.export.step import step_bytes
    from test_dxf import curve_distance

    tol = 1e-8
    for name, cam in template_cams:
        if name != template:
            continue
        edges = _step_bspline_edges(_step_shape(step_bytes(cam.contour, cam.body, cam.name), tmp_path))
        splines = [seg for seg in cam.contour.segments if isinstance(seg, Spline) and seg.n_pieces > 1]
        assert edges and splines
        # an edge is a run of its segment's compact form: same parameter range, same end points
        def owner(knots, controls, splines=splines):
            for i, seg in enumerate(splines):
                inside = seg.breaks[0] - 1e-9 <= knots[0] and knots[-1] <= seg.breaks[-1] + 1e-9
                if inside and np.hypot(*(seg.eval_t(knots[:1])[0] - controls[0])) <= 1e-6:
                    return i
            raise AssertionError("an edge that starts on no spline segment")

        by_segment = {i: [] for i in range(len(splines))}
        for knots, controls in edges:
            by_segment[owner(knots, controls)].append((knots, controls))
        for i, seg in enumerate(splines):
            mine = by_segment[i]
            assert mine
            # every edge point within tol of its segment
            for knots, controls in mine:
                pts = BSpline(knots, controls, 3)(np.linspace(knots[0], knots[-1], 801))
                assert np.max(curve_distance(pts, lambda t, o, seg=seg: seg.eval_t(t, o), seg.breaks[0], seg.breaks[-1])) <= tol * (1 + 1e-6)
            # every point of the segment within tol of its edges
            pts = seg.eval_t(np.linspace(seg.breaks[0], seg.breaks[-1], 4001))
            dist = []
            for knots, controls in mine:
                b = BSpline(knots, controls, 3)
                ders = (b, b.derivative(1), b.derivative(2))
                dist.append(curve_distance(pts, lambda t, o, d=ders: d[o](t), knots[0], knots[-1], seeds=2001))
            assert np.max(np.min(dist, axis=0)) <= tol * (1 + 1e-6)
        if template == "tricycle":
            assert sum(len(c) for _, c in edges) < 0.8 * sum(s.n_pieces + 3 for s in splines)


# --------------------------------------------------------------------------------------------
# Arcs from their circles, shared vertices, OCCT's failures as named errors
# --------------------------------------------------------------------------------------------
def _bitten_disk(d: float = 14.0):
    """A disk of radius 10 with a concave (clockwise) bite between its points at -30 and +30 deg,
    on a circle centred at (d, 0); and its area in closed form: the disk less the big circle's
    segment over the chord and the bite's segment (r^2 / 2 (t - sin t) for a segment of angle t)."""
    from camgen.contour import Arc, Contour

    R, half = 10.0, math.radians(30.0)
    x, y = R * math.cos(half), R * math.sin(half)
    rho = math.hypot(d - x, y)
    phi = math.atan2(y, d - x)  # half the bite's angle at its centre
    contour = Contour([Arc((0.0, 0.0), R, half, 2 * math.pi - 2 * half), Arc((d, 0.0), rho, math.pi + phi, -2 * phi)])

    def segment(r, t):
        return r * r / 2 * (t - math.sin(t))

    return contour, math.pi * R * R - segment(R, 2 * half) - segment(rho, 2 * phi), rho


def test_clockwise_arcs_are_written_on_their_own_circles(tmp_path):
    """A concave arc is a circle of its own radius turning the other way: OCCT's volume of the
    bitten disk is its closed-form area x thickness (a concave arc written the convex way would
    add the bite's lens instead of removing it) and the read-back circles have the radii 10 and rho."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.GeomAbs import GeomAbs_Circle
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    from camgen.body import BodySpec
    from camgen.export.step import step_bytes, step_volume

    contour, area, rho = _bitten_disk()
    body = BodySpec(thickness=3.0, bore_diameter=4.0)
    data = step_bytes(contour, body, "bite")
    shape = _step_shape(data, tmp_path)
    assert BRepCheck_Analyzer(shape).IsValid()
    assert step_volume(data) == pytest.approx((area - math.pi * 4.0) * 3.0, rel=1e-12)
    radii = set()
    explorer = TopExp_Explorer(shape, TopAbs_EDGE)
    while explorer.More():
        curve = BRepAdaptor_Curve(TopoDS.Edge(explorer.Current()))
        if curve.GetType() == GeomAbs_Circle:
            radii.add(round(curve.Circle().Radius(), 12))
        explorer.Next()
    assert radii == {10.0, round(rho, 12), 2.0}


def test_profile_edges_share_their_vertices(contours, tmp_path):
    """The profile wire read back from STEP closes on shared vertices: as many distinct vertices
    at z = 0 on the profile as edges (six arcs of the stride cam; none lost, none doubled)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_VERTEX
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    from camgen.body import BodySpec
    from camgen.export.step import step_bytes

    contour = contours["stride"]
    shape = _step_shape(step_bytes(contour, BodySpec(thickness=5.0), "stride"), tmp_path)
    points = set()
    explorer = TopExp_Explorer(shape, TopAbs_VERTEX)
    while explorer.More():
        p = BRep_Tool.Pnt_s(TopoDS.Vertex(explorer.Current()))
        if abs(p.Z()) < 1e-9:
            points.add((round(p.X(), 6), round(p.Y(), 6)))
        explorer.Next()
    ends = {(round(x, 6), round(y, 6)) for x, y in (seg.start_point for seg in contour.segments)}
    assert len(contour.segments) == 6 and points == ends


def test_occt_failures_are_geometry_errors_naming_the_cam(monkeypatch, tmp_path):
    """A profile shorter than OCCT's confusion distance, and any OCCT exception while building the
    solid, are GeometryErrors naming the cam; in a run that is a failed 'step_export' check that
    withholds the cam's manufacturing files (no traceback, nothing half written)."""
    from OCP.StdFail import StdFail_NotDone

    from camgen.body import BodySpec
    from camgen.contour import Arc, Contour
    from camgen.errors import GeometryError
    from camgen.export import step
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    tiny = Contour([Arc((0.0, 0.0), 1e-9, 0.0, 2 * math.pi)])  # 6.3e-9 mm around
    with pytest.raises(GeometryError, match=r"cam 'tiny'.*below OpenCASCADE's confusion distance 1e-07 mm"):
        step.step_bytes(tiny, BodySpec(), "tiny")

    def fails(*args):
        raise StdFail_NotDone("no result")

    monkeypatch.setattr(step, "_solid", fails)
    with pytest.raises(GeometryError, match=r"cam 'x': OpenCASCADE cannot build the STEP solid \(StdFail_NotDone"):
        step.step_bytes(_bitten_disk()[0], BodySpec(), "x")
    scene = parse_scene({"output": {"formats": ["dxf", "step"]},
                         "cams": {"x": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0}}}, "fail")
    result = execute(scene, plan_run(scene))
    (check,) = [c for c in result.cams[0].checks if c.name == "step_export"]
    assert check.failed and check.blocks_manufacture and "StdFail_NotDone" in check.note
    assert not {"x.dxf", "x.step"} & set(result.files)


def test_joints_within_the_closure_tolerance_close_the_wire(tmp_path):
    """Segments that meet within the contour's closure tolerance but farther apart than OCCT's
    confusion distance (the bite's radius 4e-7 mm too long: gaps of ~4e-7 mm at both joints, as
    refitted offsets have) still give one valid closed solid: its volume is the exact bitten disk's
    area x thickness within the band the longer radius sweeps (4e-7 mm x the bite's length) and the
    slivers at the two joints (4e-7 mm x the disk's radius each), times the thickness."""
    from OCP.BRepCheck import BRepCheck_Analyzer

    from camgen.body import BodySpec
    from camgen.contour import Arc, Contour
    from camgen.export.step import step_bytes, step_volume

    exact, area, rho = _bitten_disk()
    big, bite = exact.segments
    gapped = Contour([big, Arc(bite.center, rho + 4e-7, bite.start_angle, bite.sweep)], closure_tol=1e-6)
    gap = np.hypot(*(gapped.segments[1].start_point - big.end_point))
    assert 3e-7 < gap < 5e-7
    data = step_bytes(gapped, BodySpec(thickness=2.0), "gap")
    assert BRepCheck_Analyzer(_step_shape(data, tmp_path)).IsValid()
    band = 4e-7 * (abs(bite.sweep) * rho + 2 * 10.0)
    assert abs(step_volume(data) - area * 2.0) <= band * 2.0
