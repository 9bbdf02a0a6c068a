"""STEP solids, read back by OpenCASCADE."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from camgen.tests.cams import BODIES


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
    import os

    from OCP.STEPControl import STEPControl_Reader

    path = tmp_path / "cam.step"
    path.write_bytes(data)
    reader = STEPControl_Reader()
    saved = os.dup(1)  # OCCT prints its statistics on stdout
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
        try:
            assert int(reader.ReadFile(str(path))) == 1  # IFSelect_RetDone
            reader.TransferRoots()
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    return reader.OneShape()


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
