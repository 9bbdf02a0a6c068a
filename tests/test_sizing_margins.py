"""Sizing with margins (issue 26, item 4), against brute-force searches and closed forms written
out here on their own:

* Norton's pressure angle of a centred translating roller, tan(alpha) = |s'| / (Rb + r + s), and
  the radius of curvature of its pitch curve, the polar curve r = Rb + r + s:
  (r^2 + r'^2)^1.5 / (r^2 + 2 r'^2 - r r'') (*Design of Machinery*, ch. 8);
* an oscillating roller's pressure angle and pitch curve from the arm's geometry (the roller
  centre turned into the cam frame, its curvature by central differences);
* the Hertz line-contact stress, p = sqrt(F (1/rho_cam + 1/r) / (pi b K)) (Rothbart, *Cam Design
  Handbook*, eq. 9.11) with the contact force of a spring-loaded translating follower,
  F = (k (s - s_min) + P0 + m g + m s'' w^2) / cos(alpha).

The user's case of the issue: an oscillating roller told "at least 43.935 mm" while 60, 65 and
70 mm all failed and 44-55 mm passed: the pressure angle of an oscillating follower falls, then
rises again as the cam grows towards the pivot; the hint quotes the interval, and both its ends
pass when used (the CLI exits 0) while 1e-3 mm beyond each fails (exit 1).
"""
from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from camgen.cli import main
from camgen.synthesis.followers import FollowerSpec
from camgen.synthesis.laws import MotionProgram
from camgen.synthesis.laws import Segment as MotionSegment
from camgen.synthesis.sizing import (
    ContactStressLimit, DesignLimits, arm_length_intervals, face_width, feasible_intervals, min_base_radius,
    pivot_distance_intervals, roller_radius_intervals,
)
from helpers import scene_toml
from test_followers import rest_arm_angle

D = math.radians
TWO_PI = 2.0 * math.pi
THETA = np.linspace(0.0, TWO_PI, 14400, endpoint=False)  # 0.025 deg


def cli(tmp_path, cam: dict, name: str = "s") -> tuple[int, dict]:
    """Exit status and report.json of ``camgen run`` on a one-cam scene."""
    path = tmp_path / f"{name}.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"c": cam}}), encoding="utf-8")
    out = tmp_path / f"{name}-out"
    status = main(["run", str(path), "-o", str(out)])
    return status, json.loads((out / name / "report.json").read_text(encoding="utf-8"))


def checks(report: dict) -> dict:
    return {c["name"]: c for c in report["cams"]["c"]["checks"]}


# --------------------------------------------------------------------------------------------
# The oscillating case: an interval, both ends used
# --------------------------------------------------------------------------------------------
SWING = [{"law": "cycloidal", "span_deg": 100.0, "swing_deg": 18.0}, {"law": "dwell", "span_deg": 60.0},
         {"law": "poly4567", "span_deg": 120.0, "swing_deg": -18.0}, {"law": "dwell", "span_deg": 80.0}]
PIVOT, ARM, ROLLER, LIMIT = (90.0, 50.0), 80.0, 8.0, 27.0


def rocker(base: float, **more) -> dict:
    """The user's oscillating roller (the bundled template's geometry, no follower train)."""
    return {"kind": "motion_law", "follower": "roller", "follower_motion": "oscillating", "base_radius_mm": base,
            "roller_radius_mm": ROLLER, "pivot_x_mm": PIVOT[0], "pivot_y_mm": PIVOT[1], "arm_length_mm": ARM, "swing_turn": "ccw",
            "rotation": "cw", "pressure_angle_limit_deg": LIMIT, "thickness_mm": 8.0, "segments": SWING, **more}


def _swing_law():
    return MotionProgram([MotionSegment("cycloidal", D(100), D(18)), MotionSegment("dwell", D(60), 0.0),
                          MotionSegment("poly4567", D(120), -D(18)), MotionSegment("dwell", D(80), 0.0)])


def rocker_measures(f: FollowerSpec, law, theta: np.ndarray, h: float = 1e-4) -> tuple[float, float]:
    """Largest pressure angle (deg) and smallest convex pitch-curve radius (mm) of an oscillating
    roller, from the arm's geometry: the roller centre C = O + L u(g0 + tau psi) turned into the
    cam frame (the cam turns by sigma theta: C seen from it is C turned by -sigma theta); the
    pitch curve's tangent and curvature by central differences (step ``h`` rad); the pressure
    angle between the pitch normal and C's motion (along J u)."""
    samples = (theta[:, None] + np.array([-h, 0.0, h])[None, :])
    psi = law(samples.ravel())[0].reshape(samples.shape)
    g = rest_arm_angle(f) + f.tau * psi
    px, py = f.pivot
    c = np.stack([px + f.arm_length * np.cos(g), py + f.arm_length * np.sin(g)], -1)  # fixed frame
    t = -f.sigma * samples
    p = np.stack([np.cos(t) * c[..., 0] - np.sin(t) * c[..., 1], np.sin(t) * c[..., 0] + np.cos(t) * c[..., 1]], -1)  # cam frame
    d1 = (p[:, 2] - p[:, 0]) / (2 * h)
    d2 = (p[:, 2] - 2 * p[:, 1] + p[:, 0]) / h**2
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    winding = np.sign(np.sum(p[:, 1, 0] * d1[:, 1] - p[:, 1, 1] * d1[:, 0]))  # the way the pitch curve runs round the axis
    kappa = winding * cross / np.hypot(*d1.T) ** 3  # > 0 convex
    back = f.sigma * theta  # the tangent in the fixed frame
    tangent = np.stack([np.cos(back) * d1[:, 0] - np.sin(back) * d1[:, 1], np.sin(back) * d1[:, 0] + np.cos(back) * d1[:, 1]], -1)
    arm = c[:, 1] - np.array([px, py])
    motion = np.stack([-arm[:, 1], arm[:, 0]], -1) / f.arm_length
    along = np.abs(np.sum(tangent * motion, 1)) / np.hypot(*tangent.T)
    alpha = float(np.degrees(np.max(np.arcsin(np.clip(along, 0.0, 1.0)))))
    convex = np.where(kappa > 0, 1.0 / np.where(kappa > 0, kappa, 1.0), np.inf)
    return alpha, float(convex.min())


def oscillating_ok(bases: np.ndarray, theta: np.ndarray, limit_deg: float = LIMIT) -> np.ndarray:
    """Feasibility of the user's rocker at each base radius (:func:`rocker_measures`): the pressure
    angle within the limit and the pitch curve's convex radius above the roller radius (no undercut)."""
    law, out = _swing_law(), np.zeros(bases.size, dtype=bool)
    for n, base in enumerate(bases):
        f = FollowerSpec("roller", float(base), motion="oscillating", roller_radius=ROLLER, pivot=PIVOT, arm_length=ARM,
                         rotation="cw")
        alpha, convex = rocker_measures(f, law, theta)
        out[n] = alpha <= limit_deg and convex > ROLLER
    return out


def test_the_oscillating_hint_is_the_brute_force_interval_and_its_ends_pass_on_the_cli(tmp_path):
    status, report = cli(tmp_path, rocker(30.0), "at30")
    assert status == 1 and checks(report)["pressure_angle"]["status"] == "fail"
    note = checks(report)["min_base_radius"]["note"]
    low, high = (float(v) for v in re.search(r"set base_radius_mm between ([\d.]+) and ([\d.]+)[ ,]", note).groups())
    assert ", or between" not in note  # one run here
    # brute force over the whole range the pivot allows (|d - L| - r, d - r), every 0.1 mm, cam angles every 0.05 deg
    d = math.hypot(*PIVOT)
    grid = np.arange(math.ceil((abs(d - ARM) - ROLLER) * 10) / 10 + 0.1, d - ROLLER, 0.1)
    ok = oscillating_ok(grid, THETA[::2])
    runs = np.flatnonzero(np.diff(ok.astype(int)))
    assert ok.any() and runs.size == 2, "one run of passing base radii, bounded on both sides"
    first, last = grid[runs[0] + 1], grid[runs[1]]
    assert first - 0.1 - 0.01 <= low <= first + 0.01 and last - 0.01 <= high <= last + 0.1 + 0.01
    assert low < 44.0 and 53.0 < high < 60.0  # as the user's: 44-53 mm pass, 60, 65 and 70 mm fail
    # the ends used: exit 0; 1e-3 mm beyond each: exit 1 (the pressure angle), also by the brute force at fine cam angles
    for base, expected in ((low, 0), (high, 0), (round(low - 1e-3, 6), 1), (round(high + 1e-3, 6), 1), (60.0, 1), (65.0, 1), (70.0, 1),
                           (50.0, 0)):
        status, report = cli(tmp_path, rocker(base), f"b{base}")
        assert status == expected, (base, checks(report)["pressure_angle"])
        if min(abs(base - low), abs(base - high)) > 0.01:  # away from the ends the brute force agrees
            assert oscillating_ok(np.array([base]), THETA)[0] == (expected == 0)
    # and the geometry here is camgen's: the pressure angle the CLI reports at 50 mm
    f = FollowerSpec("roller", 50.0, motion="oscillating", roller_radius=ROLLER, pivot=PIVOT, arm_length=ARM, rotation="cw")
    assert rocker_measures(f, _swing_law(), THETA)[0] == pytest.approx(checks(report)["pressure_angle"]["value"], abs=1e-3)


def test_feasible_intervals_finds_every_run_and_brackets_each_end():
    """A predicate with two known runs, [2.25, 3.5] and [5.125, 7.75] (closed), in (0, 10)."""
    tried = []

    def ok(x: float) -> bool:
        tried.append(x)
        return 2.25 <= x <= 3.5 or 5.125 <= x <= 7.75

    runs = feasible_intervals(ok, 0.0, 10.0, tol=1e-6, scan=32)
    assert len(runs) == 2
    for (low, high), (a, b) in zip(runs, [(2.25, 3.5), (5.125, 7.75)]):
        assert ok(low) and ok(high) and a <= low <= a + 1e-6 and b - 1e-6 <= high <= b
    # a stated cap that passes is the run's end
    assert feasible_intervals(lambda x: x >= 4.0, 0.0, 10.0, tol=1e-6, high_is_cap=True)[-1][1] == 10.0


# --------------------------------------------------------------------------------------------
# Rise and return limits
# --------------------------------------------------------------------------------------------
STEEP_RETURN = [{"law": "cycloidal", "span_deg": 150.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                {"law": "cycloidal", "span_deg": 90.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]


def _steep_law():
    return MotionProgram([MotionSegment("cycloidal", D(150), 20.0), MotionSegment("dwell", D(60), 0.0),
                          MotionSegment("cycloidal", D(90), -20.0), MotionSegment("dwell", D(60), 0.0)])


def norton_alpha_deg(base: float, roller: float, theta: np.ndarray = THETA) -> tuple[float, float]:
    """Largest pressure angle (deg) of a centred translating roller on the rise (s' >= 0) and on
    the return (s' < 0): tan(alpha) = |s'| / (Rb + r + s), the cycloid written out."""
    theta = np.mod(theta, TWO_PI)
    rise, ret = theta < D(150), (theta >= D(210)) & (theta < D(300))
    tau = np.where(rise, theta / D(150), (theta - D(210)) / D(90))
    s = np.where(rise, 20.0 * (tau - np.sin(TWO_PI * tau) / TWO_PI), np.where(ret, 20.0 * (1 - tau + np.sin(TWO_PI * tau) / TWO_PI),
                 np.where(theta < D(210), 20.0, 0.0)))
    v = np.where(rise, 20.0 / D(150) * (1 - np.cos(TWO_PI * tau)), np.where(ret, -20.0 / D(90) * (1 - np.cos(TWO_PI * tau)), 0.0))
    alpha = np.degrees(np.arctan(np.abs(v) / (base + roller + s)))
    return float(alpha[~ret].max()), float(alpha[ret].max())


def test_a_steeper_return_passes_with_its_own_looser_limit_and_fails_with_a_tighter_one(tmp_path):
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "segments": STEEP_RETURN}
    rise, ret = norton_alpha_deg(40.0, 10.0)
    assert ret > rise + 5.0  # the return is the steeper
    status, report = cli(tmp_path, {**cam, "pressure_angle_limit_return_deg": 40.0}, "split")
    c = checks(report)
    assert status == 0 and c["pressure_angle"]["status"] == "pass" and c["pressure_angle_return"]["status"] == "pass"
    measured_rise, measured_ret = c["pressure_angle"]["value"], c["pressure_angle_return"]["value"]
    # the checks measure the closed form (on their grid, at most a hair below the true peak)
    assert rise - 2e-4 <= measured_rise <= rise + 1e-9 and ret - 2e-4 <= measured_ret <= ret + 1e-9
    assert c["pressure_angle"]["limit"] == 30.0 and c["pressure_angle_return"]["limit"] == 40.0
    # the single limit that passes the rise fails the cam (the return breaks it)
    status, report = cli(tmp_path, {**cam, "pressure_angle_limit_deg": measured_rise + 1e-6}, "single")
    assert status == 1 and checks(report)["pressure_angle"]["status"] == "fail"
    for name, value in (("return", measured_ret), ("rise", measured_rise)):
        other = {"rise": 40.0, "return": 40.0}
        del other[name]
        keys = {f"pressure_angle_limit_{n}_deg": v for n, v in other.items()}
        check = "pressure_angle" if name == "rise" else "pressure_angle_return"
        status, report = cli(tmp_path, {**cam, **keys, f"pressure_angle_limit_{name}_deg": value + 1e-6}, f"{name}-pass")
        assert status == 0 and checks(report)[check]["status"] == "pass"
        status, report = cli(tmp_path, {**cam, **keys, f"pressure_angle_limit_{name}_deg": value - 1e-6}, f"{name}-fail")
        assert status == 1 and checks(report)[check]["status"] == "fail"
        note = checks(report)["min_base_radius"]["note"]
        least = float(re.search(r"increase base_radius_mm to at least ([\d.]+) ", note).group(1))
        limits = {"rise": 40.0, "return": 40.0, name: value - 1e-6}
        # the hint's base radius meets both limits by Norton's formula, and 0.001 mm less does not
        r_up, r_down = norton_alpha_deg(least, 10.0)
        r_up2, r_down2 = norton_alpha_deg(least - 1e-3, 10.0)
        assert r_up <= limits["rise"] + 1e-6 and r_down <= limits["return"] + 1e-6
        assert r_up2 > limits["rise"] - 1e-4 or r_down2 > limits["return"] - 1e-4


def test_sizing_meets_the_return_limit_against_nortons_bound():
    """Translating roller: the least base radius with a 25 deg rise and 35 deg return limit, by
    brute force over Norton's formula (0.001 mm steps about the answer)."""
    limits = DesignLimits(max_pressure_angle=D(25), max_pressure_angle_return=D(35))
    found = min_base_radius(FollowerSpec("roller", 50.0, roller_radius=10.0), _steep_law(), limits).base_radius

    def ok(base):
        up, down = norton_alpha_deg(base, 10.0)
        return up <= 25.0 and down <= 35.0

    coarse = np.arange(1.0, 100.0, 0.5)
    first = coarse[np.argmax([ok(b) for b in coarse])]
    assert ok(found + 1e-4) and not ok(found - 1e-3)
    assert first - 0.5 <= found <= first
    both = min_base_radius(FollowerSpec("roller", 50.0, roller_radius=10.0), _steep_law(), DesignLimits(max_pressure_angle=D(25)))
    assert both.base_radius > found + 1.0  # the looser return limit is worth it


# --------------------------------------------------------------------------------------------
# Norton's pitch-curvature rule
# --------------------------------------------------------------------------------------------
def pitch_radius(base: float, roller: float, law, theta: np.ndarray = THETA) -> np.ndarray:
    """|radius of curvature| of a centred roller's pitch curve, the polar curve r = Rb + r + s."""
    s, v, a, _ = law(theta)
    r = base + roller + s
    return np.abs((r**2 + v**2) ** 1.5 / (r**2 + 2 * v**2 - r * a))


def test_nortons_rule_at_its_threshold(tmp_path):
    law = _steep_law()
    cam = {"kind": "motion_law", "base_radius_mm": 30.0, "roller_radius_mm": 8.0, "segments": STEEP_RETURN,
           "pressure_angle_limit_deg": 45.0}
    least = float(pitch_radius(30.0, 8.0, law).min())
    status, report = cli(tmp_path, {**cam, "min_pitch_radius_roller_factor": 2.0}, "norton")
    c = checks(report)["pitch_curvature"]
    assert c["value"] == pytest.approx(least, rel=1e-4) and c["value"] >= least * (1 - 1e-4)
    factor = c["value"] / 8.0
    assert 1.0 < factor < 100.0
    status, report = cli(tmp_path, {**cam, "min_pitch_radius_roller_factor": factor * (1 - 1e-9)}, "norton-pass")
    assert status == 0 and checks(report)["pitch_curvature"]["status"] == "pass"
    status, report = cli(tmp_path, {**cam, "min_pitch_radius_roller_factor": factor * (1 + 1e-9)}, "norton-fail")
    assert status == 1 and checks(report)["pitch_curvature"]["status"] == "fail"
    assert "min_base_radius" in checks(report)  # and the hint says which base radius meets it


@pytest.mark.parametrize("factor", [2.0, 3.0])
def test_sizing_with_nortons_rule_against_brute_force(factor):
    law = _steep_law()
    limits = DesignLimits(max_pressure_angle=D(45), min_pitch_radius_factor=factor)
    found = min_base_radius(FollowerSpec("roller", 50.0, roller_radius=8.0), law, limits).base_radius

    def ok(base):
        return pitch_radius(base, 8.0, law).min() >= factor * 8.0 and max(norton_alpha_deg(base, 8.0)) <= 45.0

    assert ok(found + 1e-4) and not ok(found - 1e-3)
    coarse = np.arange(0.5, 80.0, 0.5)
    assert coarse[np.argmax([ok(b) for b in coarse])] - 0.5 <= found


def test_the_largest_roller_is_set_by_nortons_rule():
    """Base radius kept: a larger roller needs a flatter pitch curve; the largest that passes
    against the polar-curve brute force."""
    law = _steep_law()
    limits = DesignLimits(max_pressure_angle=D(45), min_pitch_radius_factor=2.5)
    answer = roller_radius_intervals(FollowerSpec("roller", 40.0, roller_radius=5.0), law, limits)
    assert len(answer.runs) == 1
    low, high = answer.runs[0]

    def ok(r):
        return pitch_radius(40.0, r, law).min() >= 2.5 * r and max(norton_alpha_deg(40.0, r)) <= 45.0

    assert ok(high) and not ok(high + 1e-3) and low < 0.01
    assert "roller_radius between" in answer.text()


# --------------------------------------------------------------------------------------------
# The Hertz stress as a sizing constraint
# --------------------------------------------------------------------------------------------
def _stress_limit(allowable: float):
    from camgen import dynamics as dy

    train = dy.FollowerTrain(mass=0.5, spring_rate=2.0, preload=150.0)
    return ContactStressLimit(train, dy.ContactMaterial(width=10.0, allowable_stress=allowable), 300.0)


def hertz_closed_form(base: float, roller: float, law, theta: np.ndarray = THETA) -> float:
    """Peak Hertz stress (MPa) of a centred translating roller on a spring at 300 rpm: the contact
    force F = (k (s - s_min) + P0 + m g + m s'' w^2 1e-3) / cos(alpha) (N; s'' mm/rad^2), the
    profile's radius rho_pitch - r, steel on steel (E 210 GPa, nu 0.3)."""
    s, v, a, _ = law(theta)
    w = 300.0 * TWO_PI / 60.0
    r = base + roller + s
    alpha = np.arctan(np.abs(v) / r)
    force = (2.0 * (s - s.min()) + 150.0 + 0.5 * 9.80665 + 0.5 * a * w**2 * 1e-3) / np.cos(alpha)
    rho_pitch = (r**2 + v**2) ** 1.5 / (r**2 + 2 * v**2 - r * a)
    rho_cam = rho_pitch - roller
    compliance = 2 * (1 - 0.3**2) / 210e3
    return float(np.max(np.sqrt(np.maximum(force, 0.0) * (1 / rho_cam + 1 / roller) / (math.pi * 10.0 * compliance))))


def test_sizing_meets_the_contact_stress_against_the_closed_form():
    law = _steep_law()
    allowable = hertz_closed_form(60.0, 10.0, law)  # binding: far more base radius than the pressure angle needs
    limits = DesignLimits(max_pressure_angle=D(45), contact_stress=_stress_limit(allowable))
    found = min_base_radius(FollowerSpec("roller", 50.0, roller_radius=10.0), law, limits)
    assert found.measures.max_contact_stress == pytest.approx(hertz_closed_form(found.base_radius, 10.0, law), rel=1e-4)
    assert hertz_closed_form(found.base_radius + 1e-4, 10.0, law) <= allowable * (1 + 1e-6)
    assert hertz_closed_form(found.base_radius - 1e-3, 10.0, law) > allowable
    assert found.base_radius == pytest.approx(60.0, abs=2e-3)
    assert max(norton_alpha_deg(found.base_radius, 10.0)) < 30.0  # the stress binds, not the pressure angle


def test_the_least_roller_meets_the_stress():
    """Base radius kept: a larger roller carries the load at a lower stress; the least roller that
    meets it against the closed form."""
    law = _steep_law()
    allowable = hertz_closed_form(40.0, 10.0, law)
    answer = roller_radius_intervals(FollowerSpec("roller", 40.0, roller_radius=5.0), law,
                                     DesignLimits(max_pressure_angle=D(45), contact_stress=_stress_limit(allowable)))
    low = answer.runs[0][0]
    assert hertz_closed_form(40.0, low, law) <= allowable * (1 + 1e-6) and hertz_closed_form(40.0, low - 1e-3, law) > allowable
    assert low == pytest.approx(10.0, abs=2e-3)


# --------------------------------------------------------------------------------------------
# The oscillating arm and pivot
# --------------------------------------------------------------------------------------------
def test_arm_length_and_pivot_distance_intervals_pass_at_their_ends():
    law = _swing_law()
    f = FollowerSpec("roller", 45.0, motion="oscillating", roller_radius=ROLLER, pivot=PIVOT, arm_length=ARM, rotation="cw")
    limits = DesignLimits(max_pressure_angle=D(LIMIT))
    theta = THETA[::2]
    for answer in (arm_length_intervals(f, law, limits), pivot_distance_intervals(f, law, limits)):
        assert answer.runs
        for low, high in answer.runs:
            for value, passes in ((low, True), (high, True), (low - 1e-3, False), (high + 1e-3, False)):
                assert _rocker_ok(f, law, theta, value, answer.name) == passes, (answer.name, value)


def _rocker_ok(f: FollowerSpec, law, theta: np.ndarray, value: float, name: str) -> bool:
    """The rocker with its arm length or pivot distance (along the pivot's own direction) set to
    ``value``, feasible by :func:`rocker_measures`."""
    from dataclasses import replace

    d = math.hypot(*PIVOT)
    g = replace(f, arm_length=value) if name == "arm_length" else replace(f, pivot=(PIVOT[0] * value / d, PIVOT[1] * value / d))
    alpha, convex = rocker_measures(g, law, theta)
    return alpha <= LIMIT and convex > ROLLER


# --------------------------------------------------------------------------------------------
# The flat face with a margin
# --------------------------------------------------------------------------------------------
def test_the_face_margin_quotes_the_least_half_length_and_it_passes(tmp_path):
    """Centred ccw translating face: the contact is at x = s' (Norton); with a 2 mm clearance the
    face must reach max |s'| + 2."""
    law = _steep_law()
    reach = float(np.max(np.abs(law(THETA)[1])))
    width = face_width(FollowerSpec("flat", 60.0), law, margin=2.0)
    assert width.half_length == pytest.approx(reach + 2.0, abs=1e-6)
    cam = {"kind": "motion_law", "follower": "flat", "base_radius_mm": 60.0, "segments": STEEP_RETURN, "face_margin_mm": 2.0}
    status, report = cli(tmp_path, cam, "face")
    need = checks(report)["face_length"]["value"]
    assert need == pytest.approx(reach + 2.0, abs=1e-6) and "face_margin_mm" in checks(report)["face_length"]["note"]
    status, report = cli(tmp_path, {**cam, "face_half_length_mm": need}, "face-pass")
    assert status == 0 and checks(report)["face_length"]["status"] == "pass"
    status, report = cli(tmp_path, {**cam, "face_half_length_mm": need - 1e-3}, "face-fail")
    assert status == 1 and checks(report)["face_length"]["status"] == "fail"


def test_margin_keys_are_refused_where_they_do_nothing(tmp_path, capsys):
    cam = {"kind": "motion_law", "follower": "flat", "base_radius_mm": 60.0, "segments": STEEP_RETURN,
           "min_pitch_radius_roller_factor": 2.0}
    path = tmp_path / "bad.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"c": cam}}), encoding="utf-8")
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: error:") and "min_pitch_radius_roller_factor" in err[0]


def test_the_scene_sizes_to_the_allowable_contact_stress(tmp_path):
    """sizing = "base_radius" with the dynamics keys and an allowable stress: the base radius it
    builds meets the stress (closed form) and 0.001 mm less does not; the hertz_stress check passes."""
    law = _steep_law()
    allowable = hertz_closed_form(60.0004, 10.0, law)  # the least base radius 60.0004 mm: sizing quotes 60.001
    cam = {"kind": "motion_law", "sizing": "base_radius", "roller_radius_mm": 10.0, "segments": STEEP_RETURN, "rpm": 300.0,
           "mass_kg": 0.5, "spring_rate_n_per_mm": 2.0, "spring_preload_n": 150.0, "contact_width_mm": 10.0,
           "thickness_mm": 10.0, "allowable_contact_stress_mpa": allowable}
    status, report = cli(tmp_path, cam, "stress")
    c = checks(report)
    sized = c["sizing"]["value"]
    assert status == 0 and c["hertz_stress"]["status"] == "pass" and "Hertz contact stress" in c["sizing"]["note"]
    assert sized == 60.001
    assert hertz_closed_form(sized, 10.0, law) <= allowable * (1 + 1e-9) < hertz_closed_form(sized - 1e-3, 10.0, law)
