"""The motion and cam-form axes: an entry registered from outside camgen gets every output.

A toy motion (a full-turn harmonic rise and return, a displacement law) registered here is
realised by the plate form for a translating roller, and a toy form (the polar cam of a radial
knife: radius = base + lift) registered here realises the motion programs camgen has.  Each is
checked against closed forms through the files camgen writes, read back independently.
"""
from __future__ import annotations

import io
import json
import math

import numpy as np
import pytest

#: Every per-cam format and the report (STEP and the FEA meshes need the step and fea extras,
#: which the test extra installs).
ALL_FORMATS = ["dxf", "points", "lift", "follower", "stl", "stl_ascii", "3mf", "obj", "ply", "vtu", "msh", "inp", "step", "ngc",
               "html"]


class HarmonicTurn:
    """s = h (1 - cos theta) + q sin theta over the turn (mm): smooth everywhere, no break, and not
    symmetric about cam angle 0 (a mirrored convention shows).  Closed forms: s' = h sin + q cos,
    s'' = h cos - q sin, s''' = -h sin - q cos; each peak is A = sqrt(h^2 + q^2), and s spans
    h - A to h + A."""

    breaks = np.zeros(0)
    break_continuity = np.zeros(0, dtype=int)

    def __init__(self, h: float, q: float) -> None:
        self.h, self.q = h, q
        amplitude = math.hypot(h, q)
        self.s_bounds = (h - amplitude, h + amplitude)
        self.stroke = 2 * amplitude

    def __call__(self, theta):
        theta = np.asarray(theta, dtype=float)
        c, s = np.cos(theta), np.sin(theta)
        h, q = self.h, self.q
        return h * (1 - c) + q * s, h * s + q * c, h * c - q * s, -h * s - q * c

    def peak_values(self):
        from camgen.synthesis.laws import Peaks

        a, delta = math.hypot(self.h, self.q), math.atan2(self.q, self.h)
        turn = 2 * math.pi
        return Peaks(a, (math.pi / 2 - delta) % turn, a, -delta % turn, a, (1.5 * math.pi - delta) % turn,
                     infinite_acceleration=False, infinite_jerk=False)


def _toy_motion():
    from camgen.motions import LawReading, Motion
    from camgen.schema import REQUIRED, Key, Length

    def read_law(where, parsed, follower, base_dir=None):
        return LawReading(HarmonicTurn(parsed["lift"] / 2, parsed["lift"] / 6), {"lift_mm": parsed["lift"]})

    return Motion("harmonic_turn", "a harmonic rise and return over the turn",
                  (Key("lift_mm", Length(), "Lift.", ("profile",), default=REQUIRED),), read_law=read_law)


def _run(scene_table):
    """The files of a run, in memory (name -> text or bytes)."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene(scene_table, "toy")
    return execute(scene, plan_run(scene)).files


def _table(text):
    """The numbers of a CSV file written header-first (camgen's tables)."""
    return np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, ndmin=2)


def test_a_law_motion_registered_from_outside_is_realised_as_a_plate_cam_with_every_output():
    """One module and one line (here: register) add a motion; the plate form and its followers take
    it unchanged.  Translating radial roller, base 40 mm, roller 10 mm, h = 6 mm, q = 2 mm: the roller's
    centre at cam angle theta is (R + s) (cos(pi/2 - theta), sin(pi/2 - theta)) in the cam frame (the
    cam turns counter-clockwise, the follower moves along +y: README's conventions) with
    R = 50 mm; the profile touches that circle of 10 mm and never enters it."""
    from camgen.motions import register, unregister

    register(_toy_motion())
    try:
        cam = {"kind": "harmonic_turn", "lift_mm": 12.0, "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 60.0,
               "thickness_mm": 8.0}
        files = _run({"output": {"formats": ALL_FORMATS}, "cams": {"h": cam}})
    finally:
        unregister("harmonic_turn")
    report = json.loads(files["report.json"])
    assert report["status"] == "pass", [c for c in report["cams"]["h"]["checks"] if c["status"] == "fail"]
    expected = {"h.dxf", "h_points.csv", "h_lift.csv", "h_follower.csv", "h.stl", "h_ascii.stl", "h.3mf", "h.obj", "h.ply", "h.vtu",
                "h.msh", "h.inp", "h.step", "h.ngc", "report.html", "report.json"}
    assert expected <= set(files)
    points = _table(files["h_points.csv"])
    theta = np.linspace(0, 2 * math.pi, 721)
    def lift(angle):
        return 6.0 * (1 - np.cos(angle)) + 2.0 * np.sin(angle)

    reach = 50.0 + lift(theta)
    centres = reach[:, None] * np.stack([np.cos(math.pi / 2 - theta), np.sin(math.pi / 2 - theta)], axis=1)
    gaps = np.linalg.norm(points[None, :, :] - centres[:, None, :], axis=2).min(axis=1) - 10.0
    chord = report["chord_tol_mm"]
    assert gaps.min() > -1e-6 and gaps.max() < 2 * chord + 0.01  # touches (to the points' spacing), never cuts
    # the follower table at 60 rev/min: the lift is the closed form at each cam angle
    rows = _table(files["h_follower.csv"])  # cam_angle_deg, time_s, lift_mm, ...
    assert np.allclose(rows[:, 2], lift(np.radians(rows[:, 0])), atol=1e-6)
    # peak pressure angle of a radial roller on this law: max atan(s' / (R + s)), by brute force
    fine = np.linspace(0, 2 * math.pi, 200001)
    alpha = np.degrees(np.max(np.abs(np.arctan2(6.0 * np.sin(fine) + 2.0 * np.cos(fine), 50.0 + lift(fine)))))
    pressure = next(c for c in report["cams"]["h"]["checks"] if c["name"] == "pressure_angle")
    assert pressure["value"] == pytest.approx(alpha, abs=1e-3)


def _toy_form():
    """The polar cam of a radial knife: radius R + s(phi) at polar angle phi, a periodic cubic
    spline through 720 samples (within ~1e-6 mm of the closed form for the laws used here)."""
    from camgen.checks import Follower
    from camgen.contour import Contour, Spline
    from camgen.forms import CamForm
    from camgen.kinds.base import BuiltCam, CamSpec, body_keys, check_keys, read_body, read_checks
    from camgen.schema import REQUIRED, Key, Length

    def read(where, name, parsed, motion, base_dir=None):
        from camgen.synthesis.followers import FollowerSpec

        knife = FollowerSpec(kind="knife", base_radius=parsed["base_radius"])
        law = motion.read_law(where, parsed, knife, base_dir).law
        return CamSpec(name, motion.name, (law, parsed["base_radius"]), read_body(where, parsed), read_checks(parsed),
                       Follower("roller", roller_radius=1.0))

    def build(spec, stages):
        law, base = spec.params
        phi = np.linspace(0.0, 2 * math.pi, 721)
        radius = base + law(phi)[0]
        points = radius[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
        points[-1] = points[0]
        contour = Contour([Spline.interpolate(phi, points)])
        return BuiltCam(spec.name, spec.kind, contour, {"base_radius_mm": base}, spec.body, spec.follower)

    keys = (Key("base_radius_mm", Length(), "Radius at zero lift.", ("profile",), default=REQUIRED),) + body_keys() + check_keys()
    return CamForm("polar", "the polar cam of a radial knife", lambda: keys, read=read, build=build)


def test_a_form_registered_from_outside_realises_every_law_motion_with_every_output():
    """One module and one line add a form; the motion program (camgen's own) is realised by it
    with no change anywhere else.  Cycloidal rise of 10 mm over 120 deg, dwell, return: every
    point of the profile lies at the polar radius 30 + s(phi) (Norton, eq. 8.6: s = h (x - sin(2 pi
    x) / (2 pi)), x = phi / beta)."""
    from camgen.forms import register, unregister
    from camgen.kinds import forms_of

    register(_toy_form())
    try:
        assert "polar" in forms_of("motion_law") and "polar" in forms_of("lift_table")
        assert "polar" not in forms_of("three_arc")  # a design of its own names its forms
        segments = [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 10.0}, {"law": "dwell", "span_deg": 60.0},
                    {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -10.0}, {"law": "dwell", "span_deg": 60.0}]
        cam = {"kind": "motion_law", "form": "polar", "segments": segments, "base_radius_mm": 30.0, "thickness_mm": 6.0}
        files = _run({"output": {"formats": [f for f in ALL_FORMATS if f != "follower"]}, "cams": {"p": cam}})
    finally:
        unregister("polar")
    assert {"p.dxf", "p_points.csv", "p_lift.csv", "p.stl", "p.3mf", "p.obj", "p.ply", "p.vtu", "p.msh", "p.inp", "p.step", "p.ngc",
            "report.html"} <= set(files)
    points = _table(files["p_points.csv"])
    phi = np.mod(np.arctan2(points[:, 1], points[:, 0]), 2 * math.pi)
    beta = 2 * math.pi / 3
    x = np.clip(phi / beta, 0, 1)
    rise = 10.0 * (x - np.sin(2 * math.pi * x) / (2 * math.pi))
    y = np.clip((phi - math.pi) / beta, 0, 1)
    fall = 10.0 * (y - np.sin(2 * math.pi * y) / (2 * math.pi))
    expected = 30.0 + np.where(phi < math.pi, rise, 10.0 - fall)
    assert np.max(np.abs(np.hypot(points[:, 0], points[:, 1]) - expected)) < 1e-4


def test_a_form_that_does_not_realise_the_motion_is_refused_naming_the_key_and_the_forms():
    """Every registered form a motion is not realised by is refused, naming cams.c.form, the value
    and the forms that do realise it (one line, before anything is computed)."""
    from camgen.errors import ParameterError
    from camgen.forms import form_names
    from camgen.kinds import forms_of, kind_names
    from camgen.scene import parse_scene

    refused = 0
    for motion in kind_names():
        for form in sorted(set(form_names()) - set(forms_of(motion))):
            with pytest.raises(ParameterError) as caught:
                parse_scene({"cams": {"c": {"kind": motion, "form": form}}}, "t")
            assert caught.value.name == "cams.c.form" and caught.value.value == form
            assert all(f in str(caught.value) for f in forms_of(motion)), str(caught.value)
            refused += 1
    assert refused >= 2  # trajectory (plate only), three_arc (constant_breadth only); the laws take both


def test_three_arc_places_an_oscillating_pivot_as_every_follower_does():
    """pivot_x_mm / pivot_y_mm (the disk cams' keys) place a three-arc cam's oscillating roller; the old
    polar keys are refused naming the new ones.  The pivot at (0, 350) is the one at distance 350,
    polar angle 90 deg: the pressure angle is the same as computed from the polar form by hand
    (checks.Follower with pivot_distance, pivot_angle)."""
    from camgen.checks import Follower, evaluate_cam
    from camgen.errors import SceneError
    from camgen.scene import parse_scene
    from camgen.synthesis.three_arc import three_arc_cam

    base = {"kind": "three_arc", "a_mm": 100.0, "b_mm": 100.0, "c_mm": 35.0, "follower": "roller", "roller_radius_mm": 10.0,
            "follower_motion": "oscillating", "arm_length_mm": 330.0}
    with pytest.raises(SceneError, match="pivot_distance_mm.*did you mean pivot_x_mm, pivot_y_mm"):
        parse_scene({"cams": {"c": {**base, "pivot_distance_mm": 350.0, "pivot_angle_deg": 90.0}}}, "t")
    files = _run({"output": {"formats": ["dxf"]}, "cams": {"c": {**base, "pivot_x_mm": 0.0, "pivot_y_mm": 350.0}}})
    report = json.loads(files["report.json"])
    got = next(c for c in report["cams"]["c"]["checks"] if c["name"] == "pressure_angle")
    by_hand = evaluate_cam(three_arc_cam(100.0, 100.0, 35.0), Follower("roller", "oscillating", roller_radius=10.0,
                           pivot_distance=350.0, pivot_angle=math.pi / 2, arm_length=330.0), 0.0)
    want = next(c for c in by_hand.checks if c.name == "pressure_angle")
    assert got["value"] == pytest.approx(math.degrees(want.value) if want.unit == "rad" else want.value, rel=1e-9)


def test_a_follower_registered_from_outside_rides_every_form_with_every_output():
    """One module and one line add a follower: a mushroom follower (a translating stem ending in a
    circular face of radius 60 mm) is a point contact of that radius; the plate form makes its cam,
    checks, sizes and draws it with no change elsewhere.  The face's centre at cam angle theta is
    (R + s) (cos(pi/2 - theta), sin(pi/2 - theta)) in the cam frame (R = base 30 + 60 mm, the
    cam turning counter-clockwise, the follower along +y); the profile touches that circle of
    60 mm and never enters it (cycloidal rise of 10 mm over 120 deg, dwell, return: Norton, eq. 8.6)."""
    from camgen.followers import FollowerKind, register, unregister
    from camgen.schema import Key, Length

    register(FollowerKind("mushroom", "a mushroom (a stem ending in a circular face)", "point",
                          (Key("face_radius_mm", Length(), "Radius of the mushroom's face.", ("profile", "pitch"), default=50.0),),
                          radius=lambda parsed: parsed["face_radius"], has_radius=True))
    try:
        segments = [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 10.0}, {"law": "dwell", "span_deg": 60.0},
                    {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -10.0}, {"law": "dwell", "span_deg": 60.0}]
        cam = {"kind": "motion_law", "segments": segments, "follower": "mushroom", "face_radius_mm": 60.0, "base_radius_mm": 30.0,
               "rpm": 60.0, "thickness_mm": 6.0}
        files = _run({"output": {"formats": ALL_FORMATS}, "cams": {"m": cam}})
    finally:
        unregister("mushroom")
    report = json.loads(files["report.json"])
    assert report["status"] == "pass", [c for c in report["cams"]["m"]["checks"] if c["status"] == "fail"]
    assert {"m.dxf", "m_points.csv", "m_lift.csv", "m_follower.csv", "m.stl", "m.3mf", "m.vtu", "m.step", "m.ngc", "report.html"} <= set(files)
    assert report["cams"]["m"]["figures"]["follower"]["kind"] == "mushroom"
    points = _table(files["m_points.csv"])
    theta = np.linspace(0, 2 * math.pi, 1441)
    beta = 2 * math.pi / 3
    x, y = np.clip(theta / beta, 0, 1), np.clip((theta - math.pi) / beta, 0, 1)
    lift = np.where(theta < math.pi, 10.0 * (x - np.sin(2 * math.pi * x) / (2 * math.pi)),
                    10.0 - 10.0 * (y - np.sin(2 * math.pi * y) / (2 * math.pi)))
    centres = (90.0 + lift)[:, None] * np.stack([np.cos(math.pi / 2 - theta), np.sin(math.pi / 2 - theta)], axis=1)
    gaps = np.linalg.norm(points[None, :, :] - centres[:, None, :], axis=2).min(axis=1) - 60.0
    assert gaps.min() > -1e-6 and gaps.max() < 0.05  # touches (to the points' spacing), never cuts
    from camgen.errors import SceneError
    from camgen.scene import parse_scene

    with pytest.raises(SceneError, match="face_radius_mm"):  # unregistered again: its key is unknown
        parse_scene({"cams": {"m": cam}}, "t")
