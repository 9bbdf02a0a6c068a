"""Constant-breadth and constant-diameter cams for any law (form ``constant_breadth``).

What is shown, and where each expected number comes from:

* **The ride** (tests/ride.py, contact geometry only): the upper face (roller) simulated on the
  exported DXF (exact B-splines, read back by ezdxf and turned into piecewise cubics by scipy)
  and on the point list keeps the required lift within 1e-6 mm, and the far face (roller) stays
  in contact: the gap between it and the cam is within 1e-6 mm all turn.  The required lift is
  the law written out here from its textbook formula (Norton, *Design of Machinery*, ch. 8:
  cycloidal, double harmonic) with the second half-turn ``C - s(theta - 180 deg)`` (the rule).
* **The breadth** ``h(psi) + h(psi + pi)`` (the diameter ``r(phi) + r(phi + pi)`` of the pitch
  curve) measured on the exported B-spline DXF in 3600 directions.
* **The three-arc cam** (paper 000, eq. 1 and Fig. 5) through the form equal to its construction
  written out here to 1e-12 mm, and its own yoke law (the arcs' support function ``o . u + r`` in
  closed form) fed to the generic form giving the same profile within the fit tolerance.
* **The undercut threshold** of a yoke: the base radius where ``min (h + h'')`` crosses 0, by
  scipy's brentq on this file's own formula of the law; the design 1e-6 above passes, 1e-6 below
  fails the ``undercut`` check.
* **Refusals**: a whole program that breaks the rule, named by its segment (exit 2, one line).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import ride
from helpers import distance_to_arcs
from test_disk_cams import bspline_contour, csv_points, polygon_translating_roller

TWO_PI = 2.0 * math.pi
D = math.radians
#: ride tolerance (mm): the required motion and the far contact
RIDE_TOL = 1e-6
#: fit tolerance of the exported cams (mm): the smallest allowed, so that the breadth through the
#: DXF is limited by its cubic B-splines (bspline_tol 1e-8 mm), not by the profile (1.2e-10 mm)
FIT_TOL = 1e-10
#: point list chord tolerance (mm): a polygon face or roller ride is off by up to its sagitta on each side
CHORD_TOL = 2e-7


# --------------------------------------------------------------------------------------------
# The laws, written out here (Norton ch. 8), per rad of cam angle
# --------------------------------------------------------------------------------------------
def cycloidal(u):
    return u - np.sin(TWO_PI * u) / TWO_PI


def double_harmonic(u):
    return (1 - np.cos(np.pi * u)) / 2 - (1 - np.cos(TWO_PI * u)) / 8


SHAPES = {"cycloidal": cycloidal, "double_harmonic": double_harmonic}


def half_turn_lift(theta, dwell0: float, rise: float, lift: float, shape: str):
    """s over the first half-turn: dwell ``dwell0`` rad at 0, rise ``lift`` mm over ``rise`` rad, dwell at the top."""
    u = np.clip((theta - dwell0) / rise, 0.0, 1.0)
    return lift * SHAPES[shape](u)


def required_lift(theta, dwell0, rise, lift, shape):
    """The whole turn by the rule s(theta + pi) = C - s(theta), C = s(0) + s(pi) = lift."""
    theta = np.mod(theta, TWO_PI)
    first = half_turn_lift(np.where(theta < math.pi, theta, theta - math.pi), dwell0, rise, lift, shape)
    return np.where(theta < math.pi, first, lift - first)


def half_segments(dwell0_deg, rise_deg, lift, shape):
    return [{"law": "dwell", "span_deg": dwell0_deg}, {"law": shape, "span_deg": rise_deg, "lift_mm": lift},
            {"law": "dwell", "span_deg": 180.0 - dwell0_deg - rise_deg}]


def _run(scene_table, name="cb"):
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene(scene_table, name)
    return execute(scene, plan_run(scene))


# --------------------------------------------------------------------------------------------
# The ride on the exported DXF and point list
# --------------------------------------------------------------------------------------------
#: (follower, rotation, half_turn, shape): the yoke and the two rollers, both rotations, a
#: half-turn program and a whole one, a symmetric law and an asymmetric one (double harmonic: its
#: mirror is not the time-reversed return a program's negative lift makes)
CASES = [("yoke", "ccw", True, "cycloidal"), ("yoke", "cw", True, "double_harmonic"),
         ("roller", "ccw", False, "cycloidal"), ("roller", "cw", True, "double_harmonic")]
DWELL0, RISE, LIFT, BASE, ROLLER = 30.0, 120.0, 20.0, 40.0, 8.0


def _cam_table(follower, rotation, half, shape):
    table = {"kind": "motion_law", "form": "constant_breadth", "follower": follower, "rotation": rotation,
             "base_radius_mm": BASE, "half_turn": half}
    if follower == "roller":
        table["roller_radius_mm"] = ROLLER
    segments = half_segments(DWELL0, RISE, LIFT, shape)
    if not half:  # the whole turn, written out by the rule: dwell, return by the same law, dwell
        segments += [{"law": "dwell", "span_deg": DWELL0}, {"law": shape, "span_deg": RISE, "lift_mm": -LIFT},
                     {"law": "dwell", "span_deg": 180.0 - DWELL0 - RISE}]
    table["segments"] = segments
    return table


@pytest.fixture(scope="module")
def exported():
    cams = {f"c{i}": {**_cam_table(*case), "fit_tol_mm": FIT_TOL} for i, case in enumerate(CASES)}
    result = _run({"output": {"formats": ["dxf", "points"], "dxf_splines": "bspline", "dxf_construction": True,
                              "chord_tol_mm": CHORD_TOL}, "cams": cams})
    files = {name: data for name, data in result.files.items() if isinstance(data, str)}
    return files, [(cam, check.name) for cam, check in result.failed_checks()]


def test_every_check_of_the_exported_cams_passes(exported):
    """Every check passes, and report.json states the size: 2 base + C (yoke), 2 (base + roller) + C."""
    import json

    assert exported[1] == []
    cams = json.loads(exported[0]["report.json"])["cams"]
    for index, (follower, _, _, _) in enumerate(CASES):
        figures = cams[f"c{index}"]["figures"]
        if follower == "yoke":
            assert figures["breadth_mm"] == pytest.approx(2 * BASE + LIFT, abs=1e-12)
        else:
            assert figures["roller_spacing_mm"] == pytest.approx(2 * (BASE + ROLLER) + LIFT, abs=1e-12)
            # a radial translating roller: tan(alpha) = s' / (Rp + s) (Norton ch. 8), s' by central
            # differences of this file's law; the lower roller's is the upper's half a turn later
            _, _, _, shape = CASES[index]
            theta = np.linspace(0.0, TWO_PI, 720001)
            step = 1e-6
            s = required_lift(theta, D(DWELL0), D(RISE), LIFT, shape)
            ds = (required_lift(theta + step, D(DWELL0), D(RISE), LIFT, shape)
                  - required_lift(theta - step, D(DWELL0), D(RISE), LIFT, shape)) / (2 * step)
            alpha = math.degrees(float(np.max(np.abs(np.arctan2(ds, BASE + ROLLER + s)))))
            pressure = next(c for c in cams[f"c{index}"]["checks"] if c["name"] == "pressure_angle")
            assert pressure["value"] == pytest.approx(alpha, abs=1e-4)


def _contact(follower, cam, theta, sigma, polygon=False):
    """Upper follower height (face, or roller centre) touching ``cam`` at ``theta`` from above."""
    if follower == "yoke":
        return ride.translating_flat(cam, theta, sigma)
    if polygon:
        return polygon_translating_roller(cam, theta, 0.0, ROLLER, sigma)
    return ride.translating_roller(cam, theta, 0.0, ROLLER, sigma)


@pytest.mark.parametrize("source", ["dxf", "points"])
@pytest.mark.parametrize("index", range(len(CASES)))
def test_both_faces_or_rollers_ride_the_exported_cam(exported, index, source):
    """The upper face (roller) keeps the required lift within 1e-6 mm and the lower one, a
    breadth (spacing) below it, touches the cam within 1e-6 mm all turn: the lowest point of the
    cam at theta is the highest at theta + 180 deg (the cam turned half a turn more)."""
    follower, rotation, half, shape = CASES[index]
    sigma = 1.0 if rotation == "ccw" else -1.0
    name = f"c{index}"
    files = exported[0]
    cam = bspline_contour(files[f"{name}.dxf"]) if source == "dxf" else csv_points(files[f"{name}_points.csv"])
    theta = np.linspace(0.0, TWO_PI, 1441)[:-1]
    s = required_lift(theta, D(DWELL0), D(RISE), LIFT, shape)
    rest = BASE if follower == "yoke" else BASE + ROLLER
    size = 2 * rest + LIFT  # breadth (spacing): the rule's C = s(0) + s(180) = LIFT
    upper = _contact(follower, cam, theta, sigma, source == "points")
    lower_contact = -_contact(follower, cam, theta + math.pi, sigma, source == "points")
    assert np.max(np.abs(upper - (rest + s))) <= RIDE_TOL
    assert np.max(np.abs((upper - size) - lower_contact)) <= RIDE_TOL


def test_the_exported_breadth_and_diameter_are_constant(exported):
    """The yoke cam's breadth h(psi) + h(psi + pi) on the B-spline DXF (PROFILE) and the roller
    cam's pitch-curve diameter r(phi) + r(phi + pi) on the B-spline DXF (PITCH layer), in 3600
    directions: within 2e-8 mm of the size.  (The DXF's SPLINEs are cubics within bspline_tol =
    1e-8 mm of the quintic profile, each side within that: 1e-9 is not reachable through the file
    (measured: 9.9e-9 mm at fit_tol_mm = 1e-10; the profile itself keeps 1.2e-10 mm, see the next
    test); what is reached is printed.)"""
    import io

    import ezdxf

    from camgen.contour import Contour

    psi = TWO_PI * np.arange(3600) / 3600
    reached = {}
    for index, (follower, _, _, _) in enumerate(CASES):
        text = exported[0][f"c{index}.dxf"]
        if follower == "yoke":
            cam = bspline_contour(text)
            err = np.abs(cam.support(psi) + cam.support(psi + math.pi) - (2 * BASE + LIFT))
        else:
            pitch_text = io.StringIO(text)
            doc = ezdxf.read(pitch_text)
            for e in doc.modelspace():  # the PITCH layer as the PROFILE layer's reader reads it
                if e.dxf.layer == "PITCH":
                    e.dxf.layer = "PROFILE"
                elif e.dxf.layer == "PROFILE":
                    e.dxf.layer = "OLD"
            out = io.StringIO()
            doc.write(out)
            pitch: Contour = bspline_contour(out.getvalue())
            err = np.abs(pitch.polar_radius(psi) + pitch.polar_radius(psi + math.pi) - (2 * (BASE + ROLLER) + LIFT))
        reached[f"c{index}"] = float(err.max())
    print("breadth / diameter error on the DXF (mm):", reached)
    assert max(reached.values()) <= 2e-8, reached


def test_the_breadth_check_measures_the_profile(exported):
    """report.json's constant_breadth check: its value is the profile's measured breadth error,
    at most 2 fit_tol; with fit_tol_mm = 1e-10 the profile itself keeps the breadth within 1e-9 mm
    (measured here on the in-memory profile's support function, not the file)."""
    table = _cam_table("yoke", "ccw", True, "cycloidal")
    table["fit_tol_mm"] = 1e-10
    result = _run({"output": {"formats": ["dxf"]}, "cams": {"y": table}})
    cam = result.cams[0]
    psi = TWO_PI * np.arange(3600) / 3600
    err = np.abs(cam.contour.support(psi) + cam.contour.support(psi + math.pi) - (2 * BASE + LIFT))
    assert err.max() <= 1e-9
    check = next(c for c in cam.checks if c.name == "constant_breadth")
    assert check.passed and check.value == pytest.approx(err.max(), rel=1e-6, abs=1e-15) and check.limit == 2e-10


def test_a_half_turn_lift_table_is_the_whole_table_mirrored(tmp_path):
    """A lift table of rows 0..180 deg with half_turn = true gives the law of the whole table this
    test mirrors itself ((a + 180, C - s), C = s(0) + s(180)), and the rule holds on it."""
    from camgen.scene import parse_scene

    angles = np.arange(0.0, 181.0, 15.0)
    lifts = 12.0 * cycloidal(angles / 180.0)
    (tmp_path / "half.csv").write_text("angle_deg,lift\n" + "".join(f"{a},{float(s)!r}\n" for a, s in zip(angles, lifts)))
    full_a = np.concatenate([angles, angles[1:-1] + 180.0])
    full_s = np.concatenate([lifts, 12.0 - lifts[1:-1]])
    (tmp_path / "full.csv").write_text("angle_deg,lift\n" + "".join(f"{a},{float(s)!r}\n" for a, s in zip(full_a, full_s)))
    common = {"kind": "lift_table", "form": "constant_breadth", "base_radius_mm": 40.0}
    scene = parse_scene({"cams": {"h": {**common, "lift_table_csv": "half.csv", "half_turn": True},
                                  "f": {**common, "lift_table_csv": "full.csv"}}}, "t", base_dir=tmp_path)
    half, full = (c.params.disk.law for c in scene.cams)
    theta = np.linspace(0, TWO_PI, 7201)
    for a, b in zip(half(theta), full(theta)):
        assert np.max(np.abs(a - b)) <= 1e-9 * max(1.0, float(np.max(np.abs(b))))
    s = half(theta)[0]
    assert np.max(np.abs(s + half(theta + math.pi)[0] - 12.0)) <= 1e-9
    # the whole table with one row of the second half 0.01 mm off breaks the rule: refused naming the table
    from camgen.errors import ParameterError

    full_s[len(angles) + 3] += 0.01
    (tmp_path / "off.csv").write_text("angle_deg,lift\n" + "".join(f"{a},{float(s)!r}\n" for a, s in zip(full_a, full_s)))
    with pytest.raises(ParameterError) as caught:
        parse_scene({"cams": {"o": {**common, "lift_table_csv": "off.csv"}}}, "t", base_dir=tmp_path)
    assert caught.value.name == "cams.o.lift_table_csv"


@pytest.mark.parametrize("law", ["cycloidal", "double_harmonic", "simple_harmonic", "modified_trapezoid", "modified_sine",
                                 "modified_cycloidal", "poly345", "poly4567", "constant_velocity", "polynomial"])
def test_every_law_of_a_half_turn_program_completes_by_the_rule(law):
    """A half-turn program of each law (a rise of 15 mm over 100 deg between dwells; constant
    velocity with blends 0.25; a polynomial from rest to rest with a jerk at its ends): the law over
    the whole turn keeps s(theta) + s(theta + 180 deg) = 15 mm and s'(theta) + s'(theta + 180 deg)
    = 0 (this test's own comparison on 7200 angles), and its second half is not the first."""
    from camgen.scene import parse_scene

    rise = {"law": law, "span_deg": 100.0, "lift_mm": 15.0}
    if law == "constant_velocity":
        rise["blend"] = 0.25
    if law == "polynomial":
        rise = {"law": law, "span_deg": 100.0, "start": [0.0, 0.0, 0.0, 0.001], "end": [15.0, 0.0, 0.0, 0.002]}
    table = {"kind": "motion_law", "form": "constant_breadth", "half_turn": True, "base_radius_mm": 60.0,
             "segments": [{"law": "dwell", "span_deg": 20.0}, rise, {"law": "dwell", "span_deg": 60.0}]}
    scene = parse_scene({"cams": {"h": table}}, "t")
    program = scene.cams[0].params.disk.law
    theta = np.linspace(0.0, math.pi, 3600, endpoint=False)
    s0, v0, _, _ = program(theta)
    s1, v1, _, _ = program(theta + math.pi)
    assert np.max(np.abs(s0 + s1 - 15.0)) <= 1e-9 and np.max(np.abs(v0 + v1)) <= 1e-9
    assert np.max(np.abs(s1 - s0)) > 1.0


# --------------------------------------------------------------------------------------------
# The three-arc cam (paper 000)
# --------------------------------------------------------------------------------------------
A, B, C = 220.0, 160.0, 25.0  # the stride-length cam of paper 000


def paper_arcs(a, b, c):
    """The six arcs of paper 000's Fig. 5 written out here: (centre, radius, start, sweep), from
    theta_x = 2 asin(b / 2a) (eq. 1), O' and O'' at distance a, polar angles pi -/+ theta_x / 2."""
    tx = 2 * math.asin(b / (2 * a))
    half, flank = tx / 2, math.pi / 2 - tx / 2
    o, o1, o2 = (0.0, 0.0), (-a * math.cos(half), -a * math.sin(half)), (-a * math.cos(half), a * math.sin(half))
    return [(o, c, -half, tx), (o1, a + c, half, flank), (o2, a + c - b, math.pi / 2, flank), (o, 2 * a + c - b, math.pi - half, tx),
            (o1, a + c - b, math.pi + half, flank), (o2, a + c, 1.5 * math.pi, flank)]


def test_the_three_arc_cam_through_the_form_is_paper_000s_construction():
    """kind = "three_arc", form = "constant_breadth": six arcs, each centre, radius, start and
    sweep equal to the construction written out here to 1e-12 mm (rad)."""
    from camgen.contour import Arc

    result = _run({"output": {"formats": ["dxf"]}, "cams": {"t": {"kind": "three_arc", "form": "constant_breadth", "a_mm": A,
                                                                  "b_mm": B, "c_mm": C}}})
    segments = result.cams[0].contour.segments
    assert len(segments) == 6 and all(isinstance(s, Arc) for s in segments)
    for seg, (centre, radius, start, sweep) in zip(segments, paper_arcs(A, B, C)):
        assert np.max(np.abs(np.asarray(seg.center) - centre)) <= 1e-12
        assert abs(seg.radius - radius) <= 1e-12
        assert abs(math.remainder(seg.start_angle - start, TWO_PI)) <= 1e-12 and abs(seg.sweep - sweep) <= 1e-12


class ThreeArcYokeLaw:
    """The three-arc cam's yoke law in closed form: the upper face (normal psi = pi/2 - theta in
    the cam frame, ccw cam) touches the arc whose normal span holds psi, h(psi) = o . u(psi) + r,
    so s = h - base, s' = -h', s'' = h'', s''' = h' (h' = o . u_perp, h'' = -o . u); the breaks are
    where the face passes from arc to arc (the curvature, so s'', jumps)."""

    def __init__(self, base: float):
        self.base = base
        arcs = paper_arcs(A, B, C)
        self.centres = np.array([a[0] for a in arcs])
        self.radii = np.array([a[1] for a in arcs])
        self.starts = np.array([a[2] for a in arcs])
        self.sweeps = np.array([a[3] for a in arcs])
        self.breaks = np.sort(np.mod(math.pi / 2 - self.starts, TWO_PI))
        self.break_continuity = np.ones(6, dtype=int)
        theta = np.linspace(0, TWO_PI, 20001)
        s, ds, d2s, d3s = self(theta)
        self.s_bounds = (float(s.min()), float(s.max()))
        self.stroke = self.s_bounds[1] - self.s_bounds[0]
        self._peaks = (float(np.abs(ds).max()), float(np.abs(d2s).max()), float(np.abs(d3s).max()))

    def __call__(self, theta):
        theta = np.asarray(theta, dtype=float)
        psi = math.pi / 2 - theta
        rel = np.mod(psi[..., None] - self.starts, TWO_PI)  # the arc whose normal span holds psi (at a break: the next one in theta)
        inside = rel < self.sweeps - 1e-15
        k = np.argmax(inside, axis=-1)
        o, r = self.centres[k], self.radii[k]
        c, sn = np.cos(psi), np.sin(psi)
        h = o[..., 0] * c + o[..., 1] * sn + r
        dh = -o[..., 0] * sn + o[..., 1] * c
        d2h = -(o[..., 0] * c + o[..., 1] * sn)
        return h - self.base, -dh, d2h, dh

    def peak_values(self):
        from camgen.synthesis.laws import Peaks

        v, a, j = self._peaks
        return Peaks(v, 0.0, a, 0.0, j, 0.0)


def test_the_three_arc_yoke_law_through_the_generic_form_gives_the_three_arc_profile():
    """The three-arc cam's own yoke law (closed form above), as a motion registered here, through
    form = "constant_breadth" with a yoke, base radius c: the profile lies on paper 000's arcs
    within the fit tolerance (points at 50 per piece), its breadth is 2a + 2c - b within 2 fit_tol,
    and both faces touch all turn (ride on the profile)."""
    from camgen.motions import LawReading, Motion, register, unregister

    law = ThreeArcYokeLaw(C)

    def read_law(where, parsed, follower, base_dir=None):
        return LawReading(law, {})

    register(Motion("three_arc_yoke_law", "the three-arc cam's yoke law", (), read_law=read_law))
    try:
        result = _run({"output": {"formats": ["dxf"]}, "cams": {"g": {"kind": "three_arc_yoke_law", "form": "constant_breadth",
                                                                      "base_radius_mm": C}}})
    finally:
        unregister("three_arc_yoke_law")
    cam = result.cams[0]
    fit_tol = cam.built.figures["fit_tol_mm"]
    breadth = 2 * A + 2 * C - B
    assert cam.built.figures["breadth_mm"] == pytest.approx(breadth, abs=1e-9)
    pts = np.concatenate([seg.eval_t(np.linspace(seg.breaks[0], seg.breaks[-1], 50 * seg.n_pieces + 1))
                          for seg in cam.contour.segments])
    from camgen.contour import Arc

    arcs = [Arc(o, r, a0, sw) for o, r, a0, sw in paper_arcs(A, B, C)]
    assert np.max(np.abs(distance_to_arcs(pts, arcs))) <= 2 * fit_tol
    psi = TWO_PI * np.arange(3600) / 3600
    assert np.max(np.abs(cam.contour.support(psi) + cam.contour.support(psi + math.pi) - breadth)) <= 2 * fit_tol
    theta = np.linspace(0, TWO_PI, 721)
    upper = ride.translating_flat(cam.contour, theta)
    assert np.max(np.abs(upper - C - law(theta)[0])) <= 1e-6
    assert np.max(np.abs((upper - breadth) + ride.translating_flat(cam.contour, theta + math.pi))) <= 1e-6


# --------------------------------------------------------------------------------------------
# The undercut threshold
# --------------------------------------------------------------------------------------------
HARMONIC = (60.0, 60.0, 10.0)  # dwell, simple-harmonic rise, lift: rho = h + h'' dips below the base radius


def _min_rho_minus_base():
    """min over the turn of s + s'' for the harmonic half-turn and its mirror (s = L (1 - cos pi u) / 2,
    s'' = L (pi / beta)^2 cos(pi u) / 2 on the rise, C - s on the second half), by minimize_scalar on
    each piece and its ends."""
    from scipy.optimize import minimize_scalar

    dwell, rise, lift = D(HARMONIC[0]), D(HARMONIC[1]), HARMONIC[2]
    k2 = (math.pi / rise) ** 2

    def rise_rho(u):
        return lift * (1 - math.cos(math.pi * u)) / 2 + lift * k2 * math.cos(math.pi * u) / 2

    def return_rho(u):  # C - s: s'' negated
        return lift - lift * (1 - math.cos(math.pi * u)) / 2 - lift * k2 * math.cos(math.pi * u) / 2

    values = [0.0, lift]  # the dwells: s + 0
    for f in (rise_rho, return_rho):
        best = minimize_scalar(f, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-12})
        values += [best.fun, f(0.0), f(1.0)]
    del dwell
    return min(values)


def _threshold():
    """The base radius at which min (h + h'') = min (Rb + s + s'') crosses 0 (brentq)."""
    from scipy.optimize import brentq

    low = _min_rho_minus_base()
    return brentq(lambda rb: rb + low, 1e-6, 1e3, xtol=1e-14, rtol=1e-15)


@pytest.mark.parametrize("factor, passes", [(1 + 1e-6, True), (1 - 1e-6, False)])
def test_the_yoke_undercut_threshold_is_the_independent_root(factor, passes, tmp_path, capsys):
    """The undercut check's value (the smallest h + h'' over the turn, both faces) is the
    independent Rb + min (s + s'') within 1e-6 of the threshold; 1e-6 above the threshold it
    passes, 1e-6 below it fails: exit 1, named on stderr, no DXF.  (So close to the threshold the
    profile's radius at the rise's end is 3.5e-5 mm, a near-corner: the continuity check reads G0
    there, as for a plate cam; only the undercut check is asserted here.)"""
    from camgen.cli import main
    from helpers import scene_toml

    threshold = _threshold()
    base = threshold * factor
    dwell, rise, lift = HARMONIC
    table = {"kind": "motion_law", "form": "constant_breadth", "half_turn": True, "base_radius_mm": base,
             "segments": [{"law": "dwell", "span_deg": dwell}, {"law": "simple_harmonic", "span_deg": rise, "lift_mm": lift},
                          {"law": "dwell", "span_deg": 180.0 - dwell - rise}]}
    result = _run({"output": {"formats": ["dxf"]}, "cams": {"u": table}})
    undercut = next(c for c in result.cams[0].checks if c.name == "undercut")
    assert undercut.passed is passes
    assert abs(undercut.value - (base + _min_rho_minus_base())) <= 1e-6 * threshold
    path = tmp_path / "u.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"u": table}}))
    status = main(["run", str(path), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert ("camgen: check failed: cams.u: undercut" in err) is not passes
    if not passes:
        assert status == 1 and not list((tmp_path / "out").rglob("*.dxf"))


# --------------------------------------------------------------------------------------------
# Refusals
# --------------------------------------------------------------------------------------------
def _check(tmp_path, capsys, table, formats=("dxf",)):
    from camgen.cli import main
    from helpers import scene_toml

    path = tmp_path / "r.toml"
    path.write_text(scene_toml({"output": {"formats": list(formats)}, "cams": {"r": table}}))
    status = main(["run", str(path), "-o", str(tmp_path / "out")])
    return status, capsys.readouterr().err


def test_a_whole_program_that_breaks_the_rule_is_refused_naming_its_segment(tmp_path, capsys):
    """A double-harmonic rise and return over the whole turn: a program's return is the
    time-reversed rise (Norton's fall), not its mirror C - s, so the return (segments[4]) breaks
    the rule: exit 2, one line naming it, nothing written.  The same program with the cycloidal
    law (symmetric: its time-reversal is its mirror) keeps the rule and runs."""
    bad = _cam_table("yoke", "ccw", False, "double_harmonic")
    status, err = _check(tmp_path, capsys, bad)
    assert status == 2
    assert err.count("\n") == 1 and err.startswith("camgen: error: parameter 'cams.r.segments[4]'"), err
    assert not (tmp_path / "out").exists()
    # the rule broken by a span: the return 10 deg longer, the dwell after it 10 deg shorter
    shifted = _cam_table("yoke", "ccw", False, "cycloidal")
    shifted["segments"][4]["span_deg"] += 10.0
    shifted["segments"][5]["span_deg"] -= 10.0
    status, err = _check(tmp_path, capsys, shifted)
    assert status == 2 and "cams.r.segments[4]" in err and err.count("\n") == 1
    status, err = _check(tmp_path, capsys, _cam_table("yoke", "ccw", False, "cycloidal"))
    assert status == 0, err


@pytest.mark.parametrize("change, key", [
    ({"follower": "flat"}, "cams.r.follower"),
    ({"follower": "knife"}, "cams.r.follower"),
    ({"breadth_mm": 99.0}, "cams.r.breadth_mm"),
    ({"roller_spacing_mm": 120.0}, "cams.r.roller_spacing_mm"),
    ({"base_radius_mm": None}, "cams.r.base_radius_mm"),
    ({"half_turn": False}, "cams.r.segments"),
])
def test_bad_constant_breadth_tables_are_refused_naming_the_key(tmp_path, capsys, change, key):
    """A follower the form does not carry (naming the ones it does), a breadth that disagrees
    with 2 base + C, a spacing for a yoke, no size at all, a half-turn program read as a whole
    turn: one line naming the key."""
    table = _cam_table("yoke", "ccw", True, "cycloidal")
    for k, v in change.items():
        if v is None:
            table.pop(k)
        else:
            table[k] = v
    status, err = _check(tmp_path, capsys, table)
    assert status == 2 and err.count("\n") == 1 and f"'{key}'" in err, err
    if key == "cams.r.follower":
        assert "yoke" in err and "roller" in err
    if key == "cams.r.breadth_mm":
        assert "100" in err  # 2 x 40 + 20


@pytest.mark.parametrize("follower", ["yoke", "roller"])
def test_the_report_draws_and_animates_both_faces_or_rollers(follower):
    """The drawing at cam angle 0 and the animation hold both faces (rollers), the size apart, the
    upper one where the law puts it; the animation moves the follower by the law's lift."""
    table = _cam_table(follower, "ccw", True, "cycloidal")
    if follower == "roller":
        table["roller_radius_mm"] = ROLLER
    result = _run({"output": {"formats": ["html"]}, "cams": {"d": table}})
    ev = result.cams[0].evaluation
    rest = BASE if follower == "yoke" else BASE + ROLLER
    size = 2 * rest + LIFT
    label = "follower face" if follower == "yoke" else "roller"
    for shapes in (ev.follower_drawing, ev.animation.follower):
        parts = [poly for name, poly in shapes if name == label]
        assert len(parts) == 2
        heights = sorted(float(np.mean(poly[:, 1])) for poly in parts)
        assert heights[1] == pytest.approx(rest, abs=1e-9) and heights[1] - heights[0] == pytest.approx(size, abs=1e-9)
    frames = ev.animation.moves
    theta = TWO_PI * np.arange(frames.size) / frames.size
    assert np.max(np.abs(frames - required_lift(theta, D(DWELL0), D(RISE), LIFT, "cycloidal"))) <= 1e-9


def test_breadth_alone_gives_the_base_radius(tmp_path, capsys):
    """breadth_mm = 100 with the 20 mm half-turn rise: base radius (100 - 20) / 2 = 40 mm, the
    same cam as base_radius_mm = 40."""
    table = _cam_table("yoke", "ccw", True, "cycloidal")
    table.pop("base_radius_mm")
    table["breadth_mm"] = 100.0
    result = _run({"output": {"formats": ["dxf"]}, "cams": {"b": table}})
    assert result.cams[0].built.figures["base_radius_mm"] == 40.0


# --------------------------------------------------------------------------------------------
# The body: every plate-cam output
# --------------------------------------------------------------------------------------------
def _stl_volume(data: bytes) -> float:
    """Signed volume of a binary STL (divergence theorem over its triangles), read with numpy."""
    count = int(np.frombuffer(data[80:84], dtype="<u4")[0])
    rows = np.frombuffer(data[84:84 + 50 * count], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    v = rows["v"].astype(float)
    return float(np.sum(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2]))) / 6.0)


@pytest.mark.parametrize("follower", ["yoke", "roller"])
def test_the_body_is_a_plate_cams_prism_in_every_format(follower, tmp_path):
    """The cam is a plate cam's prism: the STL's volume (numpy, divergence theorem) and the STEP
    solid's (OpenCASCADE) are the point list's area (shoelace) x thickness - the bore's, within
    the chord tolerance's band round the perimeter; LinuxCNC's rs274 reads the G-code."""
    from helpers import require_tool, rs274_canon, shoelace
    from test_step import _step_shape

    chord, thickness, bore = 1e-3, 8.0, 12.0
    table = {**_cam_table(follower, "ccw", True, "cycloidal"), "thickness_mm": thickness, "bore_diameter_mm": bore}
    result = _run({"output": {"formats": ["points", "stl", "step", "ngc"], "chord_tol_mm": chord},
                   "machining": {"tool_diameter_mm": 6.0}, "cams": {"b": table}})
    assert result.failed_checks() == []
    files = result.files
    points = csv_points(files["b_points.csv"])
    area = abs(shoelace(points)) - math.pi * (bore / 2) ** 2
    band = 2 * chord * float(np.sum(np.hypot(*np.diff(points, axis=0).T))) * thickness
    assert abs(_stl_volume(files["b.stl"]) - area * thickness) <= band
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(_step_shape(files["b.step"].encode() if isinstance(files["b.step"], str) else files["b.step"],
                                             tmp_path), props)
    assert abs(props.Mass() - area * thickness) <= band
    require_tool("rs274")
    status, message, moves = rs274_canon(files["b.ngc"], tmp_path)
    assert status == 0, message
    assert any(m["kind"] == "arc" for m in moves)
