"""Conjugate cam pairs (form ``conjugate``): the follower ridden on both exported cams, the checks
of both cams against closed forms, the undercut thresholds against a root search, the scene.

Every pair is made by the pipeline from a scene, written as camgen writes it and read back:

* **the ride**: one rigid follower carries both rollers.  Roller A is ridden on cam A's DXF (exact
  B-splines read back by ezdxf, turned into piecewise cubics by scipy: tests/test_disk_cams.py's
  reader) by the independent simulator tests/ride.py, and on cam A's points CSV as a polygon;
  its position must be the law's within 1e-6 mm (translating) or 1e-6 rad (oscillating).  Roller
  B is where the rigid follower puts it (translating: ``roller_b_distance_mm`` below roller A on
  the stem; oscillating: arm A's angle + ``arm_b_angle_deg``); the gap between roller B and cam B
  (the distance from its centre to cam B's curve, found here by Newton steps on the read-back
  curve or by the nearest edge of the point polygon, less its radius) must be the stated
  ``-conjugate_preload_mm`` within 1e-6 mm at every cam angle, and roller B ridden alone on cam B
  (as a roller of the envelope radius, roller_b_radius_mm - preload) must find the same follower
  position within 1e-6 mm (rad).  The points are written at ``chord_tol_mm`` 5e-7 so that the
  polygon's chords keep within 1e-6 mm.
* **the checks**: the pressure angle of both cams against the closed forms (Norton's formula for
  roller A; for every roller the angle between the normal through the instant centre of cam and
  follower (Kennedy's theorem) and the roller centre's direction of motion).
* **undercut thresholds**: for a centred translating pair (the pitch curves polar curves
  ``r(theta)``, radius of curvature ``(r^2 + r'^2)^(3/2) / (r^2 + 2 r'^2 - r r'')``, any calculus
  text), the roller radius at which cam A undercuts and the roller distance at which cam B does,
  found by scipy's brentq; the scene 1e-6 relative on the safe side passes, on the other side it
  fails with the undercut check named.
"""
from __future__ import annotations

import functools
import math
import types
from pathlib import Path

import numpy as np
import pytest

import ride
from camgen.synthesis.followers import FollowerSpec
from camgen.synthesis.laws import MotionProgram, Segment
from camgen.synthesis.lift_table import LiftTable
from test_disk_cams import bspline_contour, csv_points, polygon_oscillating_roller, polygon_translating_roller
from test_followers import rest_arm_angle

D = math.radians
TWO_PI = 2.0 * math.pi
TOL = 1e-6  # mm or rad: the ride, the gap
POINTS_CHORD = 5e-7  # mm: the points CSV's chord tolerance
LIFT, SWING = 20.0, 12.0  # mm, deg


def segments(key: str, size: float) -> list[dict]:
    return [{"law": "cycloidal", "span_deg": 120.0, key: size}, {"law": "dwell", "span_deg": 60.0},
            {"law": "poly345", "span_deg": 120.0, key: -size}, {"law": "dwell", "span_deg": 60.0}]


def program(unit: str, size: float) -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(120), size), Segment("dwell", D(60), 0.0), Segment("poly345", D(120), -size),
                          Segment("dwell", D(60), 0.0)], unit=unit)


TABLE_ANGLES = np.arange(0.0, 360.0, 4.0)
TABLE_LIFT = 15.0 * (1 - np.cos(np.radians(TABLE_ANGLES))) / 2 + 1.5 * np.sin(np.radians(2 * TABLE_ANGLES)) * (1 - np.cos(np.radians(TABLE_ANGLES))) / 2

_TRANS = {"kind": "motion_law", "form": "conjugate", "segments": segments("lift_mm", LIFT)}
_OSC = {"kind": "motion_law", "form": "conjugate", "follower_motion": "oscillating", "segments": segments("swing_deg", SWING)}
#: the pairs, in scene keys
PAIRS = {
    "t_ccw": {**_TRANS, "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "follower_offset_mm": 6.0, "roller_b_distance_mm": 140.0},
    "t_cw_preload": {**_TRANS, "base_radius_mm": 45.0, "roller_radius_mm": 10.0, "follower_offset_mm": -5.0, "roller_b_radius_mm": 12.0,
                     "roller_b_distance_mm": 150.0, "rotation": "cw", "conjugate_preload_mm": 0.02},
    "t_table_backlash": {"kind": "lift_table", "form": "conjugate", "lift_table_csv": "table.csv", "base_radius_mm": 40.0,
                         "roller_radius_mm": 10.0, "roller_b_distance_mm": 140.0, "conjugate_preload_mm": -0.05},
    "o_ccw": {**_OSC, "base_radius_mm": 40.0, "roller_radius_mm": 8.0, "pivot_x_mm": 110.0, "pivot_y_mm": 40.0, "arm_length_mm": 95.0,
              "arm_b_angle_deg": -70.0},
    "o_cw_backlash": {**_OSC, "base_radius_mm": 40.0, "roller_radius_mm": 8.0, "pivot_x_mm": -100.0, "pivot_y_mm": 50.0,
                      "arm_length_mm": 90.0, "swing_turn": "cw", "rotation": "cw", "arm_b_length_mm": 85.0, "roller_b_radius_mm": 9.0,
                      "arm_b_angle_deg": 80.0, "conjugate_preload_mm": -0.03},
}


@functools.lru_cache(maxsize=None)
def _tables_dir() -> str:
    import tempfile

    folder = tempfile.mkdtemp(prefix="camgen_conjugate_")
    Path(folder, "table.csv").write_text("angle_deg,lift\n" + "".join(f"{a:.1f},{v:.12f}\n" for a, v in zip(TABLE_ANGLES, TABLE_LIFT)))
    return folder


@functools.lru_cache(maxsize=None)
def exported() -> tuple[dict[str, str], object]:
    """Every pair written by the pipeline: file name -> text, and the run's result."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    data = {"output": {"formats": ["dxf", "points"], "chord_tol_mm": POINTS_CHORD, "dxf_splines": "bspline"}, "cams": PAIRS}
    scene = parse_scene(data, "conjugate", base_dir=Path(_tables_dir()))
    result = execute(scene, plan_run(scene))
    failed = [(cam, check.name) for cam, check in result.failed_checks() if check.blocks_manufacture]
    assert not failed, failed
    return {name: data for name, data in result.files.items() if isinstance(data, str)}, result


def law_of(name: str):
    keys = PAIRS[name]
    if keys["kind"] == "lift_table":
        return LiftTable(TABLE_ANGLES, TABLE_LIFT)
    osc = keys.get("follower_motion") == "oscillating"
    return program("rad" if osc else "mm", D(SWING) if osc else LIFT)


def follower_a(name: str) -> FollowerSpec:
    k = PAIRS[name]
    osc = k.get("follower_motion") == "oscillating"
    return FollowerSpec("roller", k["base_radius_mm"], "oscillating" if osc else "translating", k["roller_radius_mm"],
                        k.get("follower_offset_mm", 0.0), (k["pivot_x_mm"], k["pivot_y_mm"]) if osc else None, k.get("arm_length_mm", 0.0),
                        0.0, k.get("swing_turn", "ccw"), k.get("rotation", "ccw"))


def roller_b(name: str) -> tuple[float, float]:
    """Roller B's radius and the radius cam B is the envelope of (mm)."""
    k = PAIRS[name]
    r = k.get("roller_b_radius_mm", k["roller_radius_mm"])
    return r, r - k.get("conjugate_preload_mm", 0.0)


def angles(law, count: int) -> np.ndarray:
    brk = np.asarray(law.breaks)
    return np.concatenate([np.linspace(0.0, TWO_PI, count, endpoint=False) + D(0.137), brk + 1e-4, brk - 1e-4])


def turned(contour):
    """A read-back contour turned by 180 deg about the axis (a frame in which roller B rides on top)."""
    from camgen.contour import Contour, Spline

    return Contour([Spline(seg.breaks, -seg.coeffs) for seg in contour.segments], closure_tol=1e-6)


def centres(name: str, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Roller A's and roller B's centres (fixed frame, (n, 2) mm) the law requires: plane geometry
    of the rigid follower (rest positions: tests/test_followers.py)."""
    f, k, s = follower_a(name), PAIRS[name], law_of(name)(theta)[0]
    if f.motion == "translating":
        e = f.offset
        y = math.sqrt(f.prime_radius**2 - e * e) + s
        return np.stack([np.full_like(y, e), y], axis=1), np.stack([np.full_like(y, e), y - k["roller_b_distance_mm"]], axis=1)
    g = rest_arm_angle(f) + f.tau * s
    gb = g + D(k["arm_b_angle_deg"])
    p = np.asarray(f.pivot)
    lb = k.get("arm_b_length_mm", f.arm_length)
    return (p + f.arm_length * np.stack([np.cos(g), np.sin(g)], axis=1), p + lb * np.stack([np.cos(gb), np.sin(gb)], axis=1))


def to_cam(points: np.ndarray, theta: np.ndarray, sigma: float) -> np.ndarray:
    """Fixed-frame points at cam angles theta in the cam frame: R(-sigma theta) p."""
    return ride._rot1(-sigma * theta, points)


def gap_exact(contour, c: np.ndarray) -> np.ndarray:
    """Distance (mm) from each point c (M, 2) to the contour: the nearest vertex of a dense polygon,
    then Newton steps on (X(t) - c) . X'(t) = 0 with the contour's own derivatives."""
    params = contour.flatten_params(1e-3)
    pts = contour.evaluate(params)
    t = np.empty(len(c))
    for sl in ride._chunks(len(c), len(pts)):
        d = np.hypot(pts[None, :, 0] - c[sl, None, 0], pts[None, :, 1] - c[sl, None, 1])
        t[sl] = params[np.argmin(d, axis=1)]
    for _ in range(40):
        x, d1, d2 = ride.contour_derivatives(contour, t)
        rel = x - c
        g = np.sum(rel * d1, axis=1)
        dg = np.sum(d1 * d1, axis=1) + np.sum(rel * d2, axis=1)
        step = np.clip(g / dg, -0.05, 0.05)
        t = t - step
        if np.max(np.abs(step)) < 1e-15 * contour.n_segments:
            break
    x = ride.contour_derivatives(contour, t)[0]
    return np.hypot(*(x - c).T)


def ride_a(name: str, cam, theta, polygon: bool = False) -> np.ndarray:
    """Roller A's position on cam A: its centre's height (mm) or arm A's angle (rad)."""
    f = follower_a(name)
    if f.motion == "translating":
        if polygon:
            return polygon_translating_roller(cam, theta, f.offset, f.roller_radius, f.sigma)
        return ride.translating_roller(cam, theta, f.offset, f.roller_radius, f.sigma)
    if polygon:
        return polygon_oscillating_roller(cam, theta, f, rest_arm_angle(f), f.sigma)
    return ride.oscillating_roller(cam, theta, f.pivot, f.arm_length, f.roller_radius, rest_arm_angle(f), f.tau, f.sigma)


def ride_b(name: str, cam, theta, polygon: bool = False) -> np.ndarray:
    """Roller B (as the roller cam B is the envelope of) ridden alone on cam B: its centre's height
    (mm, fixed frame) or arm B's angle (rad).  Translating: in the frame turned by 180 deg roller
    B rides on top of the turned cam on the line x = -offset."""
    f, k = follower_a(name), PAIRS[name]
    _, r_env = roller_b(name)
    if f.motion == "translating":
        if polygon:
            return -polygon_translating_roller(-cam, theta, -f.offset, r_env, f.sigma)
        return -ride.translating_roller(turned(cam), theta, -f.offset, r_env, f.sigma)
    lb = k.get("arm_b_length_mm", f.arm_length)
    rest_b = rest_arm_angle(f) + D(k["arm_b_angle_deg"]) + f.tau * float(law_of(name).s_bounds[1])  # arm B at arm A's largest swing
    arm = types.SimpleNamespace(pivot=f.pivot, arm_length=lb, roller_radius=r_env, tau=-f.tau)
    if polygon:
        return polygon_oscillating_roller(cam, theta, arm, rest_b, f.sigma)
    return ride.oscillating_roller(cam, theta, f.pivot, lb, r_env, rest_b, -f.tau, f.sigma)


def required(name: str, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Roller A's and B's positions the law requires: heights (mm) or arm angles (rad)."""
    a, b = centres(name, theta)
    f = follower_a(name)
    if f.motion == "translating":
        return a[:, 1], b[:, 1]
    p = np.asarray(f.pivot)
    return np.arctan2(a[:, 1] - p[1], a[:, 0] - p[0]), np.arctan2(b[:, 1] - p[1], b[:, 0] - p[0])


def error(name: str, got: np.ndarray, want: np.ndarray) -> np.ndarray:
    diff = got - want
    return np.abs(np.remainder(diff + math.pi, TWO_PI) - math.pi) if follower_a(name).motion == "oscillating" else np.abs(diff)


# --------------------------------------------------------------------------------------------
# The ride
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(PAIRS))
def test_follower_rides_both_exported_dxf_cams(name):
    """Both rollers of the one follower on both cams' exact B-spline DXFs: the law within 1e-6 mm
    (rad), and the gap between roller B and cam B the stated -preload within 1e-6 mm."""
    files, _ = exported()
    law, f = law_of(name), follower_a(name)
    theta = angles(law, 720)
    cam_a, cam_b = bspline_contour(files[f"{name}_a.dxf"]), bspline_contour(files[f"{name}_b.dxf"])
    want_a, want_b = required(name, theta)
    assert np.max(error(name, ride_a(name, cam_a, theta), want_a)) <= TOL
    assert np.max(error(name, ride_b(name, cam_b, theta), want_b)) <= TOL
    r_b, _ = roller_b(name)
    gap = gap_exact(cam_b, to_cam(centres(name, theta)[1], theta, f.sigma)) - r_b
    assert np.max(np.abs(gap + PAIRS[name].get("conjugate_preload_mm", 0.0))) <= TOL
    gap_a = gap_exact(cam_a, to_cam(centres(name, theta)[0], theta, f.sigma)) - f.roller_radius  # roller A touches cam A
    assert np.max(np.abs(gap_a)) <= TOL


@pytest.mark.parametrize("name", sorted(PAIRS))
def test_follower_rides_both_point_lists(name):
    """The same on the points CSVs ridden as the polygons they are (chord 5e-7 mm)."""
    files, _ = exported()
    law, f = law_of(name), follower_a(name)
    theta = angles(law, 240)
    pts_a, pts_b = csv_points(files[f"{name}_a_points.csv"]), csv_points(files[f"{name}_b_points.csv"])
    want_a, want_b = required(name, theta)
    assert np.max(error(name, ride_a(name, pts_a, theta, polygon=True), want_a)) <= TOL
    assert np.max(error(name, ride_b(name, pts_b, theta, polygon=True), want_b)) <= TOL
    r_b, _ = roller_b(name)
    gap = ride.polygon_distance(pts_b, to_cam(centres(name, theta)[1], theta, f.sigma)) - r_b
    assert np.max(np.abs(gap + PAIRS[name].get("conjugate_preload_mm", 0.0))) <= TOL


def test_cam_b_is_on_the_other_side_of_the_shaft():
    """Translating: roller B's centre is below the shaft at every cam angle, and the files state the
    preload and the distance between the rollers."""
    _, result = exported()
    theta = angles(law_of("t_ccw"), 360)
    assert np.all(centres("t_ccw", theta)[1][:, 1] < 0)
    cams = {c.name: c for c in result.cams}
    for member in ("a", "b"):
        figures = cams[f"t_cw_preload_{member}"].figures["conjugate"]
        assert figures["preload_mm"] == 0.02 and figures["roller_distance_mm"] == 150.0
        check = [c for c in cams[f"t_cw_preload_{member}"].checks if c.name == "conjugate_preload"][0]
        assert check.value == 0.02 and "150 mm" in check.note


# --------------------------------------------------------------------------------------------
# The checks against closed forms
# --------------------------------------------------------------------------------------------
def kennedy_pressure_angle(name: str, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """|pressure angle| (rad) of roller A and roller B: the common normal passes through the roller
    centre and the instant centre I of cam and follower (Kennedy): (sigma s', 0) for a follower
    moving along y, -q P / (1 - q) on the line to the pivot P for a rocker turning q = sigma tau s'
    times as fast as the cam; the angle is between that normal and the centre's direction of motion."""
    f = follower_a(name)
    ds = law_of(name)(theta)[1]
    a, b = centres(name, theta)
    if f.motion == "translating":
        instant = np.stack([f.sigma * ds, np.zeros_like(ds)], axis=1)
        motion_a = motion_b = np.stack([np.zeros_like(ds), np.ones_like(ds)], axis=1)
    else:
        p = np.asarray(f.pivot)
        q = f.sigma * f.tau * ds
        instant = -q[:, None] * p / (1.0 - q)[:, None]
        motion_a, motion_b = ((c - p)[:, ::-1] * np.array([-1.0, 1.0]) for c in (a, b))
    out = []
    for c, m in ((a, motion_a), (b, motion_b)):
        n = c - instant
        cos = np.abs(np.sum(n * m, axis=1)) / (np.hypot(*n.T) * np.hypot(*m.T))
        out.append(np.arccos(np.minimum(cos, 1.0)))
    return out[0], out[1]


@pytest.mark.parametrize("name", sorted(PAIRS))
def test_pressure_angles_of_both_cams_against_the_closed_forms(name):
    """Both cams' pressure-angle curves (the checks' data) against Kennedy's instant centre, and cam
    A's against Norton's formula tan(alpha) = (s' - sigma e) / (sqrt(Rp^2 - e^2) + s) (Design of
    Machinery, ch. 8); the check's value is the curve's largest |alpha|."""
    _, result = exported()
    f = follower_a(name)
    cams = {c.name: c for c in result.cams}
    for member, index in (("a", 0), ("b", 1)):
        cam = cams[f"{name}_{member}"]
        theta, alpha = cam.evaluation.pressure_angle
        want = kennedy_pressure_angle(name, theta)[index]
        assert np.max(np.abs(np.abs(alpha) - want)) <= 1e-9
        check = [c for c in cam.checks if c.name == "pressure_angle"][0]
        assert abs(check.value - math.degrees(np.max(want))) <= 1e-7
        if member == "a" and f.motion == "translating":
            s, ds = law_of(name)(theta)[:2]
            norton = np.arctan((ds - f.sigma * f.offset) / (math.sqrt(f.prime_radius**2 - f.offset**2) + s))
            assert np.max(np.abs(alpha - norton)) <= 1e-9


# undercut thresholds of a centred translating pair with simple-harmonic rise and return: the
# noses of both cams are where the acceleration jumps (the law's breaks, on the check grid)
THRESHOLD_LIFT = 30.0
THRESHOLD_SPAN = 45.0  # deg: short rises, sharp noses
THRESHOLD_SEGMENTS = [{"law": "simple_harmonic", "span_deg": THRESHOLD_SPAN, "lift_mm": THRESHOLD_LIFT},
                      {"law": "dwell", "span_deg": 180.0 - THRESHOLD_SPAN},
                      {"law": "simple_harmonic", "span_deg": THRESHOLD_SPAN, "lift_mm": -THRESHOLD_LIFT},
                      {"law": "dwell", "span_deg": 180.0 - THRESHOLD_SPAN}]
THRESHOLD_BASE = 15.0


def polar_min_radius(height: float, sign: float) -> float:
    """Smallest convex radius of curvature (mm) of the polar curve r = height + sign s(theta) over
    the harmonic program (s from its own closed form here), by scipy's bounded minimiser on each
    segment from the best of a dense grid."""
    from scipy.optimize import minimize_scalar

    beta, c = D(THRESHOLD_SPAN), THRESHOLD_LIFT

    def s_parts(t):  # s, s', s'' of the program: rise on [0, beta], dwell, return on [pi, pi + beta], dwell
        t = np.asarray(t, dtype=float)
        rise, back = t <= beta, (t >= math.pi) & (t <= math.pi + beta)
        u = np.where(rise, t, np.where(back, t - math.pi, 0.0))
        k = math.pi / beta
        s = np.where(rise, c / 2 * (1 - np.cos(k * u)), np.where(back, c / 2 * (1 + np.cos(k * u)), np.where(t < math.pi, c, 0.0)))
        ds = np.where(rise, c / 2 * k * np.sin(k * u), np.where(back, -c / 2 * k * np.sin(k * u), 0.0))
        d2s = np.where(rise, c / 2 * k * k * np.cos(k * u), np.where(back, -c / 2 * k * k * np.cos(k * u), 0.0))
        return s, ds, d2s

    def rho(t):
        s, ds, d2s = s_parts(t)
        r, r1, r2 = height + sign * s, sign * ds, sign * d2s
        den = r * r + 2 * r1 * r1 - r * r2
        return np.where(den > 0, (r * r + r1 * r1) ** 1.5 / np.where(den > 0, den, 1.0), np.inf)

    best = math.inf
    for lo, hi in ((0.0, beta), (math.pi, math.pi + beta)):
        grid = np.linspace(lo, hi, 2001)
        i = int(np.argmin(rho(grid)))
        found = minimize_scalar(lambda t: float(rho(np.array([t]))[0]), bounds=(grid[max(i - 1, 0)], grid[min(i + 1, 2000)]),
                                method="bounded", options={"xatol": 1e-12})
        best = min(best, float(found.fun), float(rho(grid[[0, -1]]).min()))
    return best


def threshold_cams(roller_mm: float, distance_mm: float):
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene

    cam = {"kind": "motion_law", "form": "conjugate", "base_radius_mm": THRESHOLD_BASE, "roller_radius_mm": roller_mm,
           "roller_b_radius_mm": 8.0, "roller_b_distance_mm": distance_mm, "segments": THRESHOLD_SEGMENTS}
    scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"u": cam}}, "u")
    return {c.name: c for c in compute(scene, plan_run(scene)).cams}


def undercut(cam):
    return [c for c in cam.checks if c.name == "undercut"][0]


def test_undercut_thresholds_of_both_cams_against_a_root_search():
    """Cam A undercuts when its roller radius r reaches the pitch curve's smallest convex radius
    (the pitch curve r = base + r + s itself grows with r): brentq on r; cam B (roller B 8 mm)
    when the roller distance D brings its pitch curve r = D - (base + r_A) - s to a radius of 8 mm:
    brentq on D.  1e-6 relative on the safe side passes, on the other side the undercut check fails."""
    from scipy.optimize import brentq

    r_star = brentq(lambda r: polar_min_radius(THRESHOLD_BASE + r, 1.0) - r, 1.0, 30.0, xtol=1e-13)
    r_a = 10.0
    d_star = brentq(lambda d: polar_min_radius(d - THRESHOLD_BASE - r_a, -1.0) - 8.0, THRESHOLD_BASE + r_a + THRESHOLD_LIFT + 8.5, 400.0,
                    xtol=1e-12)
    far = 200.0  # roller B far from the shaft: cam B nowhere near its undercut
    below_a, above_a = threshold_cams(r_star * (1 - 1e-6), far), threshold_cams(r_star * (1 + 1e-6), far)
    assert undercut(below_a["u_a"]).passed and below_a["u_a"].contour is not None and below_a["u_a"].manufacturable
    assert not undercut(above_a["u_a"]).passed and undercut(above_a["u_a"]).blocks_manufacture and not above_a["u_a"].manufacturable
    assert undercut(above_a["u_b"]).passed
    safe_b, over_b = threshold_cams(r_a, d_star * (1 + 1e-6)), threshold_cams(r_a, d_star * (1 - 1e-6))
    assert undercut(safe_b["u_b"]).passed and safe_b["u_b"].contour is not None and safe_b["u_b"].manufacturable
    assert not undercut(over_b["u_b"]).passed and undercut(over_b["u_a"]).passed
    assert not over_b["u_b"].manufacturable


# --------------------------------------------------------------------------------------------
# The scene
# --------------------------------------------------------------------------------------------
def _refusal(base: str, changes: dict, drop: tuple[str, ...] = ()) -> str:
    from camgen.errors import ParameterError
    from camgen.scene import parse_scene

    cam = {k: v for k, v in {**PAIRS[base], **changes}.items() if k not in drop}
    with pytest.raises(ParameterError) as info:
        parse_scene({"output": {"formats": ["dxf"]}, "cams": {"p": cam}}, "x")
    return str(info.value)


def test_refusals_name_the_key_and_the_valid_range():
    # roller B must pass below the shaft: Y + s_max + sqrt(r^2 - e^2) = sqrt(50^2 - 6^2) + 20 + sqrt(10^2 - 6^2)
    least = math.sqrt(50**2 - 36) + LIFT + 8.0
    text = _refusal("t_ccw", {"roller_b_distance_mm": least - 0.01})
    assert "cams.p.roller_b_distance_mm" in text and f"> {least:.6g} mm" in text
    assert "cams.p.roller_b_distance_mm" in _refusal("t_ccw", {}, drop=("roller_b_distance_mm",))
    assert "cams.p.conjugate_preload_mm" in _refusal("t_ccw", {"conjugate_preload_mm": 10.0})
    # arm B 60 deg counter-clockwise from arm A: both rollers would move away from their cams together
    assert "cams.p.arm_b_angle_deg" in _refusal("o_ccw", {"arm_b_angle_deg": 60.0})
    assert "cams.p.arm_b_angle_deg" in _refusal("o_ccw", {}, drop=("arm_b_angle_deg",))


def test_a_name_clash_is_refused():
    from camgen.errors import ParameterError
    from camgen.scene import parse_scene

    with pytest.raises(ParameterError, match=r"cams\.p\b.*p_b"):
        parse_scene({"output": {"formats": ["dxf"]}, "cams": {"p": PAIRS["t_ccw"], "p_b": PAIRS["o_ccw"]}}, "x")


def test_least_roller_distance_is_the_valid_limit():
    """The least distance quoted is verified by using it: just above it the pair is made."""
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene

    least = math.sqrt(50**2 - 36) + LIFT + 8.0
    cam = {**PAIRS["t_ccw"], "roller_b_distance_mm": least + 1e-3}
    scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"p": cam}}, "x")
    cams = compute(scene, plan_run(scene)).cams
    assert [c.name for c in cams] == ["p_a", "p_b"] and cams[1].figures["base_radius_mm"] > 0


@pytest.mark.parametrize("base, key, value", [("t_ccw", "roller_b_distance_mm", 141.0), ("t_ccw", "roller_b_radius_mm", 9.0),
                                              ("t_ccw", "conjugate_preload_mm", 0.01), ("o_ccw", "arm_b_angle_deg", -75.0),
                                              ("o_ccw", "arm_b_length_mm", 97.0)])
def test_roller_b_keys_change_cam_b_only(base, key, value):
    """Each key of roller B changes cam B's profile (its DXF), and cam A's not at all."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    def files(cam):
        scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"p": cam}}, "x")
        return execute(scene, plan_run(scene)).files

    before, after = files(PAIRS[base]), files({**PAIRS[base], key: value})
    assert before["p_a.dxf"] == after["p_a.dxf"] and before["p_b.dxf"] != after["p_b.dxf"]


# --------------------------------------------------------------------------------------------
# The dynamics of a pair (a form-closed train: roller A pushes the follower along +s, roller B back)
# --------------------------------------------------------------------------------------------
DYN_SPAN = 120.0  # deg: the cycloidal rise and return
DYN_RPM = 300.0
#: A translating pair (offset stem, roller B of its own radius) and an oscillating one (arm B of
#: its own length, a backlash, turning clockwise), both cycloidal both ways, with a load.
DYN_PAIRS = {
    "t": {"kind": "motion_law", "form": "conjugate", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "follower_offset_mm": 6.0,
          "roller_b_radius_mm": 12.0, "roller_b_distance_mm": 140.0, "rpm": DYN_RPM, "mass_kg": 2.0, "external_load_n": 30.0,
          "gravity": True, "contact_width_mm": 8.0,
          "segments": [{"law": "cycloidal", "span_deg": DYN_SPAN, "lift_mm": LIFT}, {"law": "dwell", "span_deg": 60.0},
                       {"law": "cycloidal", "span_deg": DYN_SPAN, "lift_mm": -LIFT}, {"law": "dwell", "span_deg": 60.0}]},
    "o": {"kind": "motion_law", "form": "conjugate", "follower_motion": "oscillating", "base_radius_mm": 40.0, "roller_radius_mm": 8.0,
          "pivot_x_mm": -100.0, "pivot_y_mm": 50.0, "arm_length_mm": 90.0, "swing_turn": "cw", "rotation": "cw", "arm_b_length_mm": 85.0,
          "roller_b_radius_mm": 9.0, "arm_b_angle_deg": 80.0, "conjugate_preload_mm": -0.03, "rpm": DYN_RPM, "inertia_kg_m2": 0.02,
          "external_load_n_mm": 2000.0, "gravity": False,
          "segments": [{"law": "cycloidal", "span_deg": DYN_SPAN, "swing_deg": SWING}, {"law": "dwell", "span_deg": 60.0},
                       {"law": "cycloidal", "span_deg": DYN_SPAN, "swing_deg": -SWING}, {"law": "dwell", "span_deg": 60.0}]},
}


@functools.lru_cache(maxsize=None)
def dynamics_run():
    """Both dynamic pairs through the pipeline (with the report): cam name -> CamResult."""
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": ["dxf", "html"]}, "cams": DYN_PAIRS}, "dyn")
    return {c.name: c for c in compute(scene, plan_run(scene)).cams}


def dyn_law(name: str):
    osc = name == "o"
    size = D(SWING) if osc else LIFT
    return MotionProgram([Segment("cycloidal", D(DYN_SPAN), size), Segment("dwell", D(60), 0.0), Segment("cycloidal", D(DYN_SPAN), -size),
                          Segment("dwell", D(60), 0.0)], unit="rad" if osc else "mm")


def dyn_geometry(name: str, theta: np.ndarray):
    """Plane geometry of the rigid follower (this test's own): per contact (roller A, roller B) its
    centre (fixed frame, mm), the unit normal along which its cam pushes it (through the instant
    centre of cam and follower: Kennedy's theorem) and the unit direction in which the centre moves
    as s grows; and the lever (mm per unit of s: 1, or the arm's length)."""
    k = DYN_PAIRS[name]
    s, ds = dyn_law(name)(theta)[:2]
    sigma = -1.0 if k.get("rotation") == "cw" else 1.0
    if name == "t":
        e = k["follower_offset_mm"]
        y = math.sqrt((k["base_radius_mm"] + k["roller_radius_mm"]) ** 2 - e * e) + s
        a = np.stack([np.full_like(y, e), y], axis=1)
        b = a - np.array([0.0, k["roller_b_distance_mm"]])
        instant = np.stack([sigma * ds, np.zeros_like(ds)], axis=1)
        up = np.stack([np.zeros_like(ds), np.ones_like(ds)], axis=1)
        moves, levers = (up, up), (1.0, 1.0)
    else:
        tau = -1.0 if k["swing_turn"] == "cw" else 1.0
        f = FollowerSpec("roller", k["base_radius_mm"], "oscillating", k["roller_radius_mm"], 0.0, (k["pivot_x_mm"], k["pivot_y_mm"]),
                         k["arm_length_mm"], 0.0, k["swing_turn"], k["rotation"])
        p = np.array([k["pivot_x_mm"], k["pivot_y_mm"]])
        g = rest_arm_angle(f) + tau * s
        gb = g + D(k["arm_b_angle_deg"])
        a = p + k["arm_length_mm"] * np.stack([np.cos(g), np.sin(g)], axis=1)
        b = p + k["arm_b_length_mm"] * np.stack([np.cos(gb), np.sin(gb)], axis=1)
        q = sigma * tau * ds
        instant = -q[:, None] * p / (1.0 - q)[:, None]
        moves = tuple(tau * np.stack([-(c - p)[:, 1], (c - p)[:, 0]], axis=1) / np.hypot(*(c - p).T)[:, None] for c in (a, b))
        levers = (k["arm_length_mm"], k["arm_b_length_mm"])
    out = []
    for c, m, push in ((a, moves[0], 1.0), (b, moves[1], -1.0)):
        n = (c - instant) / np.hypot(*(c - instant).T)[:, None]
        n *= np.sign(push * np.sum(n * m, axis=1))[:, None]  # roller A pushed along +s, roller B along -s
        out.append((c, n, m))
    return out, levers, sigma


def dyn_q(name: str, theta: np.ndarray) -> np.ndarray:
    """The force the cams must supply along +s (N, or N*mm about the pivot): the load and the
    weight plus the inertia m w^2 s'' (I w^2 s'')."""
    k = DYN_PAIRS[name]
    omega = TWO_PI * DYN_RPM / 60.0
    d2s = dyn_law(name)(theta)[2]
    if name == "t":  # kg * mm/s^2 = 1e-3 N; the weight (gravity down, -y) resists the rise (+y)
        return k["mass_kg"] * (omega**2 * d2s * 1e-3 + 9.80665) + k["external_load_n"]
    return k["inertia_kg_m2"] * omega**2 * d2s * 1e3 + k["external_load_n_mm"]  # kg*m^2/s^2 = 1e3 N*mm


@pytest.mark.parametrize("name", sorted(DYN_PAIRS))
def test_pair_crossovers_against_the_closed_form(name):
    """Where the load passes from roller A to roller B and back: q = L + m w^2 s'' changes sign; on
    the cycloidal rise s'' = (2 pi H / beta^2) sin(2 pi x / beta), so at x = beta / (2 pi) (pi +
    asin(L / P)) and beta / (2 pi) (2 pi - asin(L / P)) (P = m w^2 2 pi H / beta^2), on the return
    where sin(2 pi x / beta) = L / P.  The check lists the first angle of the dynamics' grid past each."""
    cam = dynamics_run()[f"{name}_a"]
    k = DYN_PAIRS[name]
    omega, beta = TWO_PI * DYN_RPM / 60.0, D(DYN_SPAN)
    if name == "t":
        peak = k["mass_kg"] * omega**2 * TWO_PI * LIFT / beta**2 * 1e-3
        load = k["external_load_n"] + k["mass_kg"] * 9.80665
    else:
        peak = k["inertia_kg_m2"] * omega**2 * TWO_PI * D(SWING) / beta**2 * 1e3
        load = k["external_load_n_mm"]
    u = math.asin(load / peak)
    expected = np.degrees(sorted([beta / TWO_PI * (math.pi + u), beta / TWO_PI * (TWO_PI - u), math.pi + beta / TWO_PI * u,
                                  math.pi + beta / TWO_PI * (math.pi - u)]))
    check = next(c for c in cam.checks if c.name == "contact_force")
    got = np.sort(np.asarray(check.where_deg, dtype=float))
    grid = np.degrees(cam.dynamics_stage.outcome.kinematics.theta)
    assert got.size == 4, check.note
    at = np.searchsorted(grid, got - 1e-6)  # each listed angle is a grid angle (listed to 1e-6 deg) ...
    assert np.max(np.abs(grid[at] - got)) <= 1e-6
    assert np.all(grid[at - 1] < expected) and np.all(expected <= got + 1e-6), (got, expected)  # ... the first past the crossover
    assert "crosses from one contact to the other" in check.note


@pytest.mark.parametrize("name", sorted(DYN_PAIRS))
def test_pair_contact_forces_and_torque_against_an_independent_computation(name):
    """Each roller's contact force: the force balance along the follower, q, carried by roller A
    where q > 0 and by roller B where q < 0, divided by its lever times the cosine of its pressure
    angle (between its cam's normal through the instant centre and its centre's motion, Kennedy's
    theorem, computed here); the camshaft torque as the moment about the shaft of both contact
    forces (T = sigma (c x F)), not from the power balance camgen uses."""
    cam = dynamics_run()[f"{name}_a"]
    res = cam.dynamics_stage.outcome.result
    theta = res.theta
    (a, b), levers, sigma = dyn_geometry(name, theta)
    q = dyn_q(name, theta)
    cos_a, cos_b = (np.sum(n * m, axis=1) * np.sign(push) for (_, n, m), push in ((a, 1.0), (b, -1.0)))
    f1 = np.maximum(q, 0.0) / (levers[0] * cos_a)
    f2 = np.maximum(-q, 0.0) / (levers[1] * cos_b)
    scale = float(np.max(np.abs(q)) / min(levers))
    assert np.max(np.abs(res.contact_force - f1)) <= 1e-9 * scale
    assert np.max(np.abs(res.contact_force_2 - f2)) <= 1e-9 * scale
    assert np.max(f1) > 0 and np.max(f2) > 0  # both rollers carry the load somewhere
    # the shaft's torque balances the moment of the rollers' reactions on the cams: T = sigma (c x F) about +z
    torque = sigma * sum(c[:, 0] * (f * n[:, 1]) - c[:, 1] * (f * n[:, 0]) for f, (c, n, _) in ((f1, a), (f2, b))) * 1e-3
    assert np.max(np.abs(res.torque - torque)) <= 1e-7 * float(np.max(np.abs(torque)))
    figures = cam.figures["dynamics"]
    assert figures["closure"] == "form" and abs(figures["max_contact_force_2_N"] - float(np.max(f2))) <= 1e-9 * scale


def test_roller_b_contact_stress_is_roller_b_on_cam_b():
    """Hertz stress of contact 2 of a centred translating pair: roller B (its own radius) on cam B,
    whose pitch curve is the polar curve r = D - (base + r_A) - s (radius of curvature (r^2 +
    r'^2)^(3/2) / (r^2 + 2 r'^2 - r r''), profile radius that less roller B's): Rothbart eq. 9.11
    with the force of the independent balance."""
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene

    keys = {**DYN_PAIRS["t"], "follower_offset_mm": 0.0}
    scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"c": keys}}, "c")
    cam = {c.name: c for c in compute(scene, plan_run(scene)).cams}["c_a"]
    res = cam.dynamics_stage.outcome.result
    theta = res.theta
    s, ds, d2s = dyn_law("t")(theta)[:3]
    r = keys["roller_b_distance_mm"] - keys["base_radius_mm"] - keys["roller_radius_mm"] - s
    r1, r2 = -ds, -d2s
    rho_pitch = (r * r + r1 * r1) ** 1.5 / (r * r + 2 * r1 * r1 - r * r2)
    rb = keys["roller_b_radius_mm"]
    rho = rho_pitch - rb
    force = np.maximum(-dyn_q("t", theta), 0.0) * np.hypot(r, ds) / r  # centred: cos(phi) = r / hypot(r, r')
    compliance = 2 * (1 - 0.3**2) / 210e3
    want = np.sqrt(force * (1 / rho + 1 / rb) / (math.pi * keys["contact_width_mm"] * compliance))
    assert np.max(want) > 0
    assert np.max(np.abs(res.hertz_stress_2 - want)) <= 1e-7 * np.max(want)


@pytest.mark.parametrize("key, value", [("spring_rate_n_per_mm", 2.0), ("spring_preload_n", 50.0), ("jump_margin_n", 5.0)])
def test_springs_and_jump_margin_are_refused_on_a_pair(key, value, tmp_path):
    """A conjugate pair is form-closed: a spring or a jump margin is refused naming the key, exit 2, one line."""
    import subprocess
    import sys

    from helpers import scene_toml

    path = tmp_path / "spring.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"p": {**DYN_PAIRS["t"], key: value}}}), encoding="utf-8")
    run = subprocess.run([sys.executable, "-m", "camgen", "run", str(path), "--out", str(tmp_path / "out")], capture_output=True,
                         text=True)
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camgen: error: ")
    assert f"cams.p.{key}" in lines[0] and "conjugate pair is form-closed" in lines[0]
    assert not (tmp_path / "out").exists()


def test_the_pair_dynamics_are_reported_once_on_cam_a():
    """Cam A carries the pair's dynamics (report.json's figures.dynamics, the checks); cam B has
    none of its own and its "dynamics" check names cam A (the torque is not counted twice)."""
    cams = dynamics_run()
    for name in DYN_PAIRS:
        a, b = cams[f"{name}_a"], cams[f"{name}_b"]
        assert "dynamics" in a.figures and "dynamics" not in b.figures
        assert {c.name for c in a.checks} >= {"contact_force", "hertz_stress", "camshaft_torque"}
        assert not {c.name for c in b.checks} & {"contact_force", "hertz_stress", "camshaft_torque"}
        pointer = next(c for c in b.checks if c.name == "dynamics")
        assert pointer.value == f"on {name}_a" and f"{name}_a" in pointer.note
        assert "contact 2 roller B on cam B" in next(c for c in a.checks if c.name == "conjugate_preload").note


def test_no_dynamics_when_cam_b_cannot_be_made():
    """Cam B undercut (roller B too close to the shaft): the pair's dynamics are stated as not
    computed on cam A (no forces from a cam that cannot be made), and the run's verdict is the
    undercut's."""
    cams = threshold_cams_dyn()
    assert not undercut(cams["u_b"]).passed
    note = next(c for c in cams["u_a"].checks if c.name == "dynamics")
    assert note.value == "not computed" and "u_b" in note.note


def threshold_cams_dyn():
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene
    from scipy.optimize import brentq

    d_star = brentq(lambda d: polar_min_radius(d - THRESHOLD_BASE - 10.0, -1.0) - 8.0, THRESHOLD_BASE + 10.0 + THRESHOLD_LIFT + 8.5, 400.0,
                    xtol=1e-12)
    cam = {"kind": "motion_law", "form": "conjugate", "base_radius_mm": THRESHOLD_BASE, "roller_radius_mm": 10.0, "roller_b_radius_mm": 8.0,
           "roller_b_distance_mm": d_star * (1 - 1e-3), "segments": THRESHOLD_SEGMENTS, "rpm": 100.0, "mass_kg": 1.0}
    scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"u": cam}}, "u")
    return {c.name: c for c in compute(scene, plan_run(scene)).cams}
