"""Groove (track) cams ridden on their exported walls, their undercut thresholds and crossovers.

The walls of a groove are the envelopes of a roller of radius ``w = r + c / 2`` on both sides of
the pitch curve.  Each cam is made by the pipeline from a scene (form ``groove``: every roller of
tests/test_disk_cams.py, both rotations, the program of every law and a lift table), written as
camgen writes it, and read back by ezdxf and scipy (the DXF's GROOVE_INNER and GROOVE_OUTER
layers, exact B-splines) and pandas (the point list).  The required roller centre comes from
the conventions (plane geometry, tests/test_followers.py), not from camgen:

* the inner wall is ridden by the independent simulator (tests/ride.py) with a roller of radius
  w: the roller centre it finds is the required one within 1e-6 mm (1e-6 rad);
* the outer wall: the distance from the required roller centre to the nearest point of the wall
  (found over the whole wall, then polished by Newton steps on the read-back splines) is w: the
  roller touches it and nowhere crosses it; the error in the follower's position is that
  distance error over the lever (tests/test_disk_cams.lever), within 1e-6 mm (1e-6 rad).

A roller of radius r in the groove then has exactly c of play: c / 2 to each wall.
"""
from __future__ import annotations

import functools
import io
import math
from pathlib import Path

import numpy as np
import pytest

import ride
from helpers import scene_toml
from test_disk_cams import (
    CHORD_TOL,
    EXACT_TOL,
    FOLLOWERS,
    ROTATIONS,
    _tables_dir,
    bspline_contour,
    follower_spec,
    lever,
    polygon_translating_roller,
    required_law,
    segments_toml,
    the_law,
)
from test_followers import rest_arm_angle

TWO_PI = 2.0 * math.pi
CLEARANCE = 0.05  # mm, the scenes' groove_clearance_mm
ROLLERS = ("roller", "roller_offset", "osc_roller")
CASES = [(name, rotation, law) for name in ROLLERS for rotation in ROTATIONS for law in ("every_law", "lift_table")]


def cam_name(name: str, rotation: str, law: str) -> str:
    return f"groove_{law}_{name}_{rotation}"


@functools.lru_cache(maxsize=None)
def exported() -> dict[str, str]:
    """Every groove cam of the matrix as `camgen run` writes it: file name -> text."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    cams = {}
    for name, rotation, law in CASES:
        table = {**FOLLOWERS[name], "rotation": rotation, "form": "groove", "groove_clearance_mm": CLEARANCE}
        if law == "lift_table":
            table.update(kind="lift_table", lift_table_csv=f"{name}.csv")
        else:
            table.update(kind="motion_law", segments=segments_toml(name))
        cams[cam_name(name, rotation, law)] = table
    data = {"output": {"formats": ["dxf", "points"], "chord_tol_mm": CHORD_TOL, "dxf_splines": "bspline"}, "cams": cams}
    scene = parse_scene(data, "groove", base_dir=Path(_tables_dir()))
    result = execute(scene, plan_run(scene))
    failed = [(cam, check.name) for cam, check in result.failed_checks() if check.blocks_manufacture]
    assert not failed, failed
    return {name: text for name, text in result.files.items() if isinstance(text, str)}


def centre_in_cam_frame(f, law, theta: np.ndarray) -> np.ndarray:
    """The required roller centre (cam frame, (n, 2) mm) at cam angles theta: on the line x = e at
    height sqrt(Rp^2 - e^2) + s, or at the arm's end at g = rest + tau s (tests/test_followers)."""
    s = law(theta)[0]
    if f.motion == "translating":
        centre = np.stack([np.full_like(s, f.offset), math.sqrt(f.prime_radius**2 - f.offset**2) + s], axis=-1)
    else:
        g = rest_arm_angle(f) + f.tau * s
        centre = np.asarray(f.pivot) + f.arm_length * np.stack([np.cos(g), np.sin(g)], axis=-1)
    return ride._rot1(-f.sigma * theta, centre)  # the fixed frame turned back by the cam's rotation


def nearest_distance(contour, points: np.ndarray) -> np.ndarray:
    """The distance (mm) from each point to the nearest point of ``contour``: the nearest vertex
    of a dense polygon, then Newton steps on (Q(t) - p) . Q'(t) = 0 on the contour itself."""
    t_poly = contour.flatten_params(2e-3)
    poly = contour.evaluate(t_poly)
    t = np.empty(len(points))
    for sl in ride._chunks(len(points), len(poly)):
        d = np.hypot(points[sl, None, 0] - poly[None, :, 0], points[sl, None, 1] - poly[None, :, 1])
        t[sl] = t_poly[np.argmin(d, axis=1)]
    for _ in range(ride.NEWTON_STEPS):
        q, d1, d2 = ride.contour_derivatives(contour, t)
        rel = q - points
        g = np.sum(rel * d1, axis=1)
        step = g / (np.sum(d1 * d1, axis=1) + np.sum(rel * d2, axis=1))
        t = t - step
        if np.max(np.abs(step)) < ride.NEWTON_TOL:
            break
    q = ride.contour_derivatives(contour, t)[0]
    return np.hypot(*(q - points).T)


def angles(law, count: int) -> np.ndarray:
    brk = np.asarray(law.breaks)
    return np.concatenate([np.linspace(0.0, TWO_PI, count, endpoint=False) + math.radians(0.137), brk + 1e-4, brk - 1e-4])


def wall_follower(f):
    """The roller of radius w = r + c / 2 on the same pitch curve (prime radius base + r)."""
    import dataclasses

    return dataclasses.replace(f, roller_radius=f.roller_radius + CLEARANCE / 2, base_radius=f.base_radius - CLEARANCE / 2)


@pytest.mark.parametrize("name, rotation, law", CASES)
def test_the_roller_rides_both_exported_walls(name, rotation, law):
    """<= 1e-6 mm (rad): the inner wall ridden, the outer wall at w from the required centre."""
    f = follower_spec(name, rotation)
    motion = the_law(name, law)
    text = exported()[f"{cam_name(name, rotation, law)}.dxf"]
    inner, outer = bspline_contour(text, "GROOVE_INNER"), bspline_contour(text, "GROOVE_OUTER")
    theta = angles(motion, 720)
    fw = wall_follower(f)
    w = fw.roller_radius
    if f.motion == "translating":
        got = ride.translating_roller(inner, theta, f.offset, w, f.sigma)
        required = math.sqrt(f.prime_radius**2 - f.offset**2) + motion(theta)[0]
    else:
        got = ride.oscillating_roller(inner, theta, f.pivot, f.arm_length, w, rest_arm_angle(f), f.tau, f.sigma)
        required = rest_arm_angle(f) + f.tau * motion(theta)[0]
    assert np.max(np.abs(ride._wrap(got - required))) <= EXACT_TOL
    distance = nearest_distance(outer, centre_in_cam_frame(f, motion, theta))
    assert np.max(np.abs(distance - w) / lever(f, motion, theta)) <= EXACT_TOL
    # and the inner wall is at w too (the ride above found the highest touching centre: no deeper crossing)
    assert np.max(np.abs(nearest_distance(inner, centre_in_cam_frame(f, motion, theta)) - w)) <= EXACT_TOL


@pytest.mark.parametrize("name, rotation, law", [c for c in CASES if c[2] == "every_law"])
def test_the_point_list_holds_both_walls_within_the_chord_tolerance(name, rotation, law):
    """The point list's GROOVE_INNER and GROOVE_OUTER polygons: the roller centre at w from each
    within chord_tol_mm (a polygon within the tolerance of the curve)."""
    import pandas

    f = follower_spec(name, rotation)
    motion = required_law(name)
    frame = pandas.read_csv(io.StringIO(exported()[f"{cam_name(name, rotation, law)}_points.csv"]))
    assert list(frame.columns) == ["x_mm", "y_mm", "wall"]
    assert set(frame["wall"]) == {"PROFILE", "GROOVE_INNER", "GROOVE_OUTER"}
    theta = angles(motion, 360)
    centre = centre_in_cam_frame(f, motion, theta)
    w = f.roller_radius + CLEARANCE / 2
    for layer in ("GROOVE_INNER", "GROOVE_OUTER"):
        pts = frame.loc[frame["wall"] == layer, ["x_mm", "y_mm"]].to_numpy()
        error = np.abs(ride.polygon_distance(pts, centre) - w)
        assert np.max(error) <= CHORD_TOL * 1.01, layer
        assert np.max(error) > 0.05 * CHORD_TOL  # the tolerance is used: the chords are felt
    if f.motion == "translating":  # the inner polygon ridden by the simulator, as a plate cam's is
        pts = frame.loc[frame["wall"] == "GROOVE_INNER", ["x_mm", "y_mm"]].to_numpy()
        got = polygon_translating_roller(pts, theta, f.offset, w, f.sigma)
        bound = CHORD_TOL / lever(f, motion, theta) * 1.01 + 1e-9
        assert np.all(np.abs(got - (math.sqrt(f.prime_radius**2 - f.offset**2) + motion(theta)[0])) <= bound)


# --------------------------------------------------------------------------------------------
# Undercut thresholds: the polar pitch curve of a centred translating roller, r(theta) = Rp + s
# --------------------------------------------------------------------------------------------
def _harmonic_scene(base: float, lift: float, span: float, rotation: str = "ccw") -> dict:
    return {"output": {"formats": ["dxf"]}, "cams": {"g": {
        "kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0, "base_radius_mm": base,
        "groove_clearance_mm": CLEARANCE, "rotation": rotation, "pressure_angle_limit_deg": 89.0,
        "segments": [{"law": "simple_harmonic", "span_deg": span, "lift_mm": lift}, {"law": "dwell", "span_deg": 180.0 - span},
                     {"law": "simple_harmonic", "span_deg": span, "lift_mm": -lift}, {"law": "dwell", "span_deg": 180.0 - span}]}}}


def _pitch_radius_extremes(base: float, lift: float, span: float) -> tuple[float, float]:
    """(smallest convex radius, smallest |concave radius|) of the polar pitch curve r = Rp + s,
    kappa = (r^2 + 2 r'^2 - r r'') / (r^2 + r'^2)^1.5 (the polar-curve curvature), on a fine grid
    of the program (harmonic s = H (1 - cos(pi x / beta)) / 2), the breaks included."""
    beta = math.radians(span)
    x = np.concatenate([np.linspace(0.0, beta, 200001), [0.0, beta]])
    s = lift * (1 - np.cos(math.pi * x / beta)) / 2
    d1 = lift * math.pi / (2 * beta) * np.sin(math.pi * x / beta)
    d2 = lift * (math.pi / beta) ** 2 / 2 * np.cos(math.pi * x / beta)
    r = base + 10.0 + s
    kappa = (r * r + 2 * d1 * d1 - r * d2) / (r * r + d1 * d1) ** 1.5
    kappa = np.concatenate([kappa, [1 / (base + 10.0), 1 / (base + 10.0 + lift)]])  # the dwells: circles
    convex = float(np.min(1 / kappa[kappa > 0]))
    concave = float(np.min(-1 / kappa[kappa < 0])) if (kappa < 0).any() else math.inf
    return convex, concave


def _undercut_check(base: float, lift: float, span: float):
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene(_harmonic_scene(base, lift, span), "g")
    result = execute(scene, plan_run(scene))
    (cam,) = result.cams
    return next(c for c in cam.checks if c.name == "undercut"), cam


@pytest.mark.parametrize("wall, lift, span", [("inner", 5.0, 90.0), ("outer", 30.0, 60.0)])
def test_undercut_thresholds_match_an_independent_root_search(wall, lift, span):
    """The base radius where the pitch curve's convex (inner wall) or concave (outer wall) radius
    reaches w, found by brentq on the polar-curve curvature: 1e-6 above it passes, 1e-6 below
    fails naming the wall."""
    from scipy.optimize import brentq

    w = 10.0 + CLEARANCE / 2
    index = 0 if wall == "inner" else 1
    threshold = brentq(lambda b: _pitch_radius_extremes(b, lift, span)[index] - w, 0.5, 60.0, xtol=1e-12)
    # the other wall is clear at the threshold (the case tests one wall at a time)
    assert _pitch_radius_extremes(threshold, lift, span)[1 - index] > w * 1.01
    above, cam = _undercut_check(threshold * (1 + 1e-6), lift, span)
    assert above.passed, above.note
    assert cam.pockets and cam.contour is not None
    below, cam = _undercut_check(threshold * (1 - 1e-6), lift, span)
    assert below.passed is False and below.blocks_manufacture
    assert f"{wall} wall (GROOVE_{wall.upper()})" in below.note
    assert not cam.manufacturable


def test_crossovers_are_where_the_acceleration_changes_sign():
    """Cycloidal rise and return over 120 deg (s'' = 2 pi H / beta^2 sin(2 pi x / beta)): the
    roller changes walls at the middle of each, 60 and 240 deg."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    data = {"output": {"formats": ["dxf"]}, "cams": {"g": {
        "kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0, "base_radius_mm": 50.0, "rpm": 300.0,
        "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                     {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]}}}
    scene = parse_scene(data, "g")
    (cam,) = execute(scene, plan_run(scene)).cams
    check = next(c for c in cam.checks if c.name == "wall_crossover")
    assert check.value == 2
    assert np.allclose(check.where_deg, [60.0, 240.0], atol=1e-9)
    # at 300 rpm the follower's speed there is the cycloid's peak, 2 H / beta omega (m/s)
    omega = TWO_PI * 300.0 / 60.0
    assert f"{2 * 20.0 / math.radians(120.0) * omega * 1e-3:.6g} m/s" in check.note


def test_the_walls_the_rim_and_the_floor_are_checked(tmp_path):
    """The rim camgen chooses leaves min_wall_mm (the hint used: the check passes); a rim
    radius that leaves less fails, and no manufacturing file is written (exit 1)."""
    import subprocess
    import sys

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    def scene(**extra):
        return {"output": {"formats": ["dxf"]}, "cams": {"g": {
            "kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0, "base_radius_mm": 50.0,
            "thickness_mm": 20.0, "groove_depth_mm": 12.0, "bore_diameter_mm": 20.0, "min_wall_mm": 3.0, **extra,
            "segments": [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 20.0}, {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -20.0}]}}}

    parsed = parse_scene(scene(), "g")
    (cam,) = execute(parsed, plan_run(parsed)).cams
    checks = {c.name: c for c in cam.checks}
    # the outer wall's farthest point: the pitch curve's top (Rp + H = 80 mm) plus w, at the rise's end
    w = 10.0 + 0.05 / 2
    rim = math.ceil((80.0 + w + 3.0) / 0.5) * 0.5
    assert cam.figures["groove"]["rim_radius_mm"] == rim
    assert checks["rim_wall"].passed and abs(checks["rim_wall"].value - (rim - 80.0 - w)) <= 2e-4
    assert checks["groove_floor"].value == 8.0 and checks["groove_floor"].passed
    # bore radius 10 to the inner wall's nearest point: the base circle Rp - w = 50 - 0.025 mm from the axis
    assert abs(checks["wall_thickness"].value - (50.0 - 0.025 - 10.0)) <= 2e-4
    path = tmp_path / "tight.toml"
    path.write_text(scene_toml(scene(rim_radius_mm=80.0 + w + 2.0)), encoding="utf-8")
    run = subprocess.run([sys.executable, "-m", "camgen", "run", str(path), "--out", str(tmp_path / "out")], capture_output=True,
                         text=True)
    assert run.returncode == 1, run.stderr
    assert not (tmp_path / "out" / "tight" / "g.dxf").exists()
    assert "rim_wall" in (tmp_path / "out" / "tight" / "report.json").read_text(encoding="utf-8")


@pytest.mark.parametrize("extra, key", [
    ({"groove_depth_mm": 10.0}, "cams.g.groove_depth_mm"),
    ({"follower": "knife"}, "cams.g.follower"),
    ({"sizing": "base_radius"}, "cams.g.base_radius_mm"),
    ({"groove_clearance_mm": -0.1}, "cams.g.groove_clearance_mm"),
    ({"base_radius_mm": 0.02, "groove_clearance_mm": 0.05}, "cams.g.base_radius_mm"),  # the inner wall's base circle: 0.02 - 0.025
])
def test_bad_groove_input_is_refused_naming_the_key(tmp_path, extra, key):
    import subprocess
    import sys

    table = {"kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0, "base_radius_mm": 50.0,
             "thickness_mm": 10.0, "segments": [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 20.0},
                                                {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -20.0}]}
    table.update(extra)
    path = tmp_path / "bad.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"g": table}}), encoding="utf-8")
    run = subprocess.run([sys.executable, "-m", "camgen", "run", str(path), "--out", str(tmp_path / "out")], capture_output=True,
                         text=True)
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camgen: error:") and key in lines[0], run.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("method", ["base_radius", "base_radius_and_offset"])
def test_sizing_finds_the_least_base_radius_whose_groove_can_be_made(method):
    """The sized groove (harmonic rise 30 mm over 60 deg: its outer wall binds, |concave radius|
    of the pitch curve against w) used as given passes; 0.002 mm smaller fails a check."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    def run(**keys):
        data = _harmonic_scene(40.0, 30.0, 60.0)
        table = data["cams"]["g"]
        table.update(pressure_angle_limit_deg=60.0, **keys)
        if "sizing" in keys:
            del table["base_radius_mm"]
        scene = parse_scene(data, "g")
        (cam,) = execute(scene, plan_run(scene)).cams
        return cam

    sized = run(sizing=method)
    base = sized.figures["sizing"]["base_radius_mm"]
    offset = sized.figures["sizing"].get("offset_mm", 0.0)
    assert next(c for c in sized.checks if c.name == "sizing").value == base
    given = run(base_radius_mm=base, follower_offset_mm=offset)
    assert not [c.name for c in given.checks if c.failed], [c for c in given.checks if c.failed]
    smaller = run(base_radius_mm=base - 0.002, follower_offset_mm=offset)
    assert {c.name for c in smaller.checks if c.failed} & {"undercut", "pressure_angle"}
    # the outer wall binds here: the independent threshold of the centred cam is below the sized one only by the pressure angle
    if method == "base_radius":
        from scipy.optimize import brentq

        threshold = brentq(lambda b: _pitch_radius_extremes(b, 30.0, 60.0)[1] - (10.0 + CLEARANCE / 2), 0.5, 60.0, xtol=1e-12)
        assert base >= threshold


@pytest.mark.parametrize("key_name", ["groove_clearance_mm", "groove_depth_mm", "rim_radius_mm", "sizing"])
def test_every_groove_key_changes_what_it_documents(key_name, tmp_path):
    """The walk of tests/test_keys.py over the groove's own keys (the follower's are the plate
    cam's, walked in tests/test_disk_cams.py)."""
    from test_keys import _assert_effect, _changed, run, scene

    from camgen.kinds.groove import groove_keys, roller_keys

    key = next(k for k in groove_keys() + roller_keys() if k.name == key_name)
    base = {"kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 5.0, "base_radius_mm": 40.0,
            "thickness_mm": 12.0, "segments": [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 10.0},
                                               {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -10.0}]}
    if key_name == "sizing":
        alt = {**{k: v for k, v in base.items() if k != "base_radius_mm"}, "sizing": "base_radius"}
    else:
        alt = {**base, key_name: key.example if key.example is not None else _changed(key.default, key)}
    formats = ("dxf", "points", "ngc", "stl")
    machining = {"tool_diameter_mm": 8.0}
    _assert_effect(key, run(scene(base, formats, machining), tmp_path), run(scene(alt, formats, machining), tmp_path))


def test_the_dynamics_find_the_crossovers_an_external_load_moves():
    """A form-closed train: with a mass m, a constant load L against the lift and no gravity the
    cam pushes q = L + m omega^2 s'' along +s; the load crosses from the inner wall (contact 1)
    to the outer where q changes sign: on the cycloidal rise s'' = (2 pi H / beta^2) sin(2 pi x /
    beta), at x = beta / (2 pi) (pi + asin(L / (m omega^2 2 pi H / beta^2))) and (2 pi - asin(...)),
    and on the return where sin(2 pi x / beta) = +L / (...)."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    mass, load, rpm, lift, span = 2.0, 30.0, 300.0, 20.0, 120.0
    data = {"output": {"formats": ["dxf"]}, "cams": {"g": {
        "kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0, "base_radius_mm": 50.0, "rpm": rpm,
        "mass_kg": mass, "external_load_n": load, "gravity": False,
        "segments": [{"law": "cycloidal", "span_deg": span, "lift_mm": lift}, {"law": "dwell", "span_deg": 60.0},
                     {"law": "cycloidal", "span_deg": span, "lift_mm": -lift}, {"law": "dwell", "span_deg": 60.0}]}}}
    scene = parse_scene(data, "g")
    (cam,) = execute(scene, plan_run(scene)).cams
    check = next(c for c in cam.checks if c.name == "contact_force")
    omega, beta = TWO_PI * rpm / 60.0, math.radians(span)
    peak = mass * omega**2 * 2 * math.pi * lift / beta**2 * 1e-3  # N: the largest inertia force
    x = beta / TWO_PI * (math.pi + math.asin(load / peak))
    # the rise: q < 0 where sin(2 pi x / beta) < -L / peak; the return (s'' of the opposite sign): where sin > L / peak
    expected = sorted([math.degrees(x), math.degrees(beta / TWO_PI * (2 * math.pi - math.asin(load / peak))),
                       180.0 + math.degrees(beta / TWO_PI * math.asin(load / peak)),
                       180.0 + math.degrees(beta / TWO_PI * (math.pi - math.asin(load / peak)))])
    got = sorted(check.where_deg)
    assert len(got) == 4, check.note
    assert np.allclose(got, expected, atol=0.11), (got, expected)  # the dynamics grid is 0.1 deg
    assert "crosses from one contact to the other" in check.note


def test_springs_are_refused_on_a_groove(tmp_path):
    import subprocess
    import sys

    table = {"kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0, "base_radius_mm": 50.0,
             "rpm": 100.0, "mass_kg": 1.0, "spring_rate_n_per_mm": 2.0,
             "segments": [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 20.0}, {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -20.0}]}
    path = tmp_path / "spring.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"g": table}}), encoding="utf-8")
    run = subprocess.run([sys.executable, "-m", "camgen", "run", str(path), "--out", str(tmp_path / "out")], capture_output=True,
                         text=True)
    assert run.returncode == 2
    assert "cams.g.spring_rate_n_per_mm" in run.stderr and "groove is form-closed" in run.stderr


@pytest.mark.parametrize("tool, strategy", [(20.05, "one pass along the pitch curve"), (16.0, "two wall passes, slot cleared")])
def test_the_program_cuts_both_exact_walls(tool, strategy, tmp_path):
    """The G-code of a groove cam made by the pipeline (the groove_cam template's design), run
    by rs274 and swept over the stock (tests/cutting.py): both walls within CUT_TOL of the exact
    walls (no gouge, nothing left proud), every cut between them, the rim cut as a plate's
    outline; with a tool as wide as the groove (one pass) and a narrower one (wall passes)."""
    from cutting import CUT_TOL, simulate_pockets
    from helpers import require_tool

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    require_tool("rs274")
    data = {"output": {"formats": ["ngc"]}, "machining": {"tool_diameter_mm": tool, "step_down_mm": 4.0},
            "cams": {"track": {"kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0,
                               "base_radius_mm": 50.0, "groove_depth_mm": 8.0, "thickness_mm": 12.0,
                               "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                                            {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -20.0},
                                            {"law": "dwell", "span_deg": 60.0}]}}}
    scene = parse_scene(data, "g")
    result = execute(scene, plan_run(scene))
    (cam,) = result.cams
    program = result.files["track.ngc"]
    assert strategy in program
    walls = {"GROOVE_OUTER": cam.built.outer_wall, "GROOVE_INNER": cam.built.inner_wall}
    report = simulate_pockets(program, cam.contour, walls, tool / 2, tmp_path)
    assert report.outline.status == 0, report.outline.message
    pocket = report.pocket
    assert pocket is not None and pocket.between
    for layer in walls:
        assert pocket.gouge[layer] <= CUT_TOL and pocket.proud[layer] <= CUT_TOL, (layer, pocket.gouge, pocket.proud)
    assert pocket.deepest == -8.0
    assert report.outline.gouge <= CUT_TOL and report.outline.proud <= CUT_TOL


def test_the_report_names_the_walls_in_the_force_plot():
    """report.html's dynamics plot names a groove's two contacts by its walls (a yoke's are its faces)."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    data = {"output": {"formats": ["html"]}, "cams": {"g": {
        "kind": "motion_law", "form": "groove", "follower": "roller", "roller_radius_mm": 10.0, "base_radius_mm": 50.0, "rpm": 300.0,
        "mass_kg": 2.0, "segments": [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 20.0},
                                     {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -20.0}]}}}
    scene = parse_scene(data, "g")
    page = execute(scene, plan_run(scene)).files["report.html"]
    assert "inner wall (pushes the follower out)" in page and "outer wall (pulls it back)" in page
    assert "the yoke&#x27;s two faces" not in page and "the yoke's two faces" not in page
