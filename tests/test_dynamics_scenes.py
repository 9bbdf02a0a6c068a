"""Cam-follower dynamics at scene level: the keys, the numbers in the report against closed
forms, ``camgen check`` failing on jump and contact stress, the yoke's two contacts, refusals.

Every expected number is computed here in SI units from the motion laws written out (cycloidal,
simple harmonic), Newton's law for the follower, Norton's pressure angle of an offset roller
(Design of Machinery, ch. 8), Norton's radius of curvature of a flat-faced follower's cam
(Rb + s + s''), the two-cylinder Hertz formula (Rothbart, Cam Design Handbook, eq. 9.11), the
arc radii of paper 000's three-arc cam, and the moment of the contact force about the cam axis
and the pivot (an independent route to the torque the power balance gives).
"""
from __future__ import annotations

import copy
import json
import math
import re

import numpy as np
import pytest

from camgen.cli import main
from helpers import scene_toml

D = math.radians
TWO_PI = 2.0 * math.pi
G = 9.80665  # m/s^2, standard gravity


def _omega(rpm: float) -> float:
    return rpm * TWO_PI / 60.0


def rise_return(theta: np.ndarray, law: str, h: float, rise: float, dwell: float, ret: float):
    """s, s', s'' per rad of rise ``h`` over ``rise``, dwell, return over ``ret``, dwell (written out).

    cycloidal: s = h (u - sin(2 pi u) / 2 pi); simple harmonic: s = h/2 (1 - cos(pi u))."""
    theta = np.mod(theta, TWO_PI)
    s, v, a = (np.zeros_like(theta) for _ in range(3))

    def segment(u, beta):
        if law == "cycloidal":
            w = TWO_PI * u
            return h * (u - np.sin(w) / TWO_PI), h / beta * (1 - np.cos(w)), TWO_PI * h / beta**2 * np.sin(w)
        return h / 2 * (1 - np.cos(math.pi * u)), math.pi * h / (2 * beta) * np.sin(math.pi * u), \
            math.pi**2 * h / (2 * beta**2) * np.cos(math.pi * u)

    up = theta < rise
    s[up], v[up], a[up] = segment(theta[up] / rise, rise)
    top = (theta >= rise) & (theta < rise + dwell)
    s[top] = h
    down = (theta >= rise + dwell) & (theta < rise + dwell + ret)
    sd, vd, ad = segment((theta[down] - rise - dwell) / ret, ret)
    s[down], v[down], a[down] = h - sd, -vd, -ad
    return s, v, a


def program(law: str, h: float, rise: float, dwell: float, ret: float, key: str = "lift_mm") -> list[dict]:
    rest = 360.0 - rise - dwell - ret
    return [{"law": law, "span_deg": rise, key: h}, {"law": "dwell", "span_deg": dwell},
            {"law": law, "span_deg": ret, key: -h}, {"law": "dwell", "span_deg": rest}]


def plate(**changes) -> dict:
    """A translating roller cam (cycloidal 20 mm over 120 deg, dwell 60, back over 120, dwell 60) with a follower train."""
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 300.0, "thickness_mm": 10.0,
           "segments": program("cycloidal", 20.0, 120.0, 60.0, 120.0), "mass_kg": 0.6, "spring_rate_n_per_mm": 2.0,
           "spring_preload_n": 35.0}
    cam.update(changes)
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {k: v for k, v in cam.items() if v is not None}}}


def oscillating(**changes) -> dict:
    """An oscillating roller (pivot (90, 50), arm 80 mm, cycloidal swing of 15 deg) with an arm train."""
    scene = plate(follower_motion="oscillating", pivot_x_mm=90.0, pivot_y_mm=50.0, arm_length_mm=80.0, roller_radius_mm=8.0,
                  segments=program("cycloidal", 15.0, 100.0, 60.0, 120.0, "swing_deg"), mass_kg=None, spring_rate_n_per_mm=None,
                  spring_preload_n=None, inertia_kg_m2=2e-3, spring_rate_n_mm_per_rad=5000.0, spring_preload_n_mm=3000.0)
    scene["cams"]["c"].update(changes)
    scene["cams"]["c"] = {k: v for k, v in scene["cams"]["c"].items() if v is not None}
    return scene


def oscillating_flat(**changes) -> dict:
    return oscillating(follower="flat", roller_radius_mm=None, arm_length_mm=None, base_radius_mm=45.0, pivot_x_mm=100.0,
                       pivot_y_mm=60.0, face_offset_mm=10.0, swing_turn="cw", segments=program("cycloidal", 10.0, 120.0, 60.0, 120.0,
                                                                                               "swing_deg"), **changes)


YOKE = {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0, "thickness_mm": 20.0, "rpm": 30.0, "mass_kg": 20.0}


def run(scene: dict, tmp_path=None, formats=None):
    """(the built cam, report.json as a dict, the files) of ``scene`` run by the pipeline in memory."""
    from pathlib import Path

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = copy.deepcopy(scene)
    if formats is not None:
        scene["output"] = {"formats": list(formats)}
    parsed = parse_scene(scene, "s", base_dir=Path(tmp_path) if tmp_path is not None else None)
    result = execute(parsed, plan_run(parsed))
    return result.cams[0], json.loads(result.files["report.json"]), result.files


def check_exit(scene: dict, tmp_path, capsys) -> tuple[int, str, str]:
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    code = main(["check", str(path)])
    out = capsys.readouterr()
    return code, out.out, out.err


# --------------------------------------------------------------------------------------------
# The numbers against closed forms
# --------------------------------------------------------------------------------------------
def test_contact_force_is_m_a_plus_k_s_plus_preload_plus_c_v_plus_weight_point_by_point():
    """Offset roller (e = 8 mm, Rp = 50 mm, ccw cam): along the motion the cam pushes with
    m a + k s + F0 + c v + m g (the follower moves up, gravity down); along the normal with
    that over cos(alpha), Norton's tan(alpha) = (s' - e) / (sqrt(Rp^2 - e^2) + s)."""
    m, k, f0, c, e, rpm = 0.6, 2.0, 35.0, 15.0, 8.0, 300.0  # kg, N/mm, N, N*s/m, mm, rpm
    cam, report, _ = run(plate(damping_n_s_per_m=c, follower_offset_mm=e))
    res = cam.dynamics.result
    w = _omega(rpm)
    s, v, a = rise_return(res.theta, "cycloidal", 20.0, D(120), D(60), D(120))  # mm, mm/rad, mm/rad^2
    axial = m * a * w**2 / 1000 + k * 1000 * s / 1000 + f0 + c * v * w / 1000 + m * G  # N
    scale = np.max(np.abs(axial))
    assert np.max(np.abs(res.follower_force - axial)) <= 1e-10 * scale
    alpha = np.arctan((v - e) / (math.sqrt(50.0**2 - e**2) + s))
    assert np.max(np.abs(res.contact_force - axial / np.cos(alpha))) <= 1e-9 * scale
    assert np.max(np.abs(res.pressure_angle - alpha)) <= 1e-12
    figures = report["cams"]["c"]["figures"]["dynamics"]
    assert figures["min_contact_force_N"] == pytest.approx(np.min(axial / np.cos(alpha)), rel=1e-10)
    assert figures["max_contact_force_N"] == pytest.approx(np.max(axial / np.cos(alpha)), rel=1e-10)
    # the shaft's power is the follower force times the follower velocity
    power = axial * v * w / 1000
    assert np.max(np.abs(res.power - power)) <= 1e-9 * np.max(np.abs(power))
    assert figures["power_peak_W"] == pytest.approx(np.max(np.abs(power)), rel=1e-9)


def test_jump_speed_of_a_harmonic_program_and_camgen_check_fails_above_it(tmp_path, capsys):
    """Harmonic rise 10 mm over 150 deg, dwell 30, return over 120 deg: the return starts with
    the deceleration pi^2 h w^2 / (2 beta^2) at the top of the stroke, where spring, preload and
    weight press with k h + F0 + m g; the contact force reaches 0 at
    w^2 = 2 beta^2 (k h + F0 + m g) / (pi^2 m h)."""
    m, k, f0, h, beta = 0.8, 1.5, 20.0, 0.010, D(120)  # kg, N/mm, N, m, rad
    omega = math.sqrt(2 * beta**2 * (k * 1000 * h + f0 + m * G) / (math.pi**2 * m * h))
    jump = omega * 60 / TWO_PI
    segments = program("simple_harmonic", 10.0, 150.0, 30.0, 120.0)
    scene = plate(segments=segments, mass_kg=m, spring_rate_n_per_mm=k, spring_preload_n=f0)
    for factor, code in ((0.97, 0), (1.03, 1)):
        scene["cams"]["c"]["rpm"] = round(factor * jump, 3)
        cam, report, _ = run(scene)
        figures = report["cams"]["c"]["figures"]["dynamics"]
        assert figures["jump_rpm"] == pytest.approx(jump, rel=1e-9)
        status, out, err = check_exit(scene, tmp_path, capsys)
        assert status == code, (factor, err)
        jump_row = next(line for line in out.splitlines() if line.split()[1:2] == ["jump"])
        assert ("FAIL" in jump_row) == (code == 1)
        if code:
            assert "camgen: check failed: cams.c: jump" in err and "no manufacturing file" not in err
            # the follower leaves the cam where the return starts and lands before mid-return
            start, end = figures["jump_ranges_deg"][:2]
            assert start == pytest.approx(180.0, abs=1e-6) and 180.0 < end < 240.0
            assert cam.manufacturable  # a jump withholds no file
        else:
            assert figures["jump_ranges_deg"] == []


def test_hertz_stress_of_a_flat_face_against_norton_and_rothbart(tmp_path, capsys):
    """Translating flat face: the cam's radius at the contact is Rb + s + s'' (Norton ch. 8);
    the face is flat, so p = sqrt(F / (pi b rho K)), K = (1 - nu_c^2)/E_c + (1 - nu_f^2)/E_f
    (Rothbart eq. 9.11 with an infinite follower radius); b defaults to the cam's thickness."""
    m, k, f0, base, thick, rpm = 0.5, 1.0, 30.0, 60.0, 12.0, 400.0
    scene = plate(follower="flat", roller_radius_mm=None, base_radius_mm=base, thickness_mm=thick, rpm=rpm, mass_kg=m,
                  spring_rate_n_per_mm=k, spring_preload_n=f0, cam_modulus_gpa=210.0, cam_poisson=0.3, follower_modulus_gpa=200.0,
                  follower_poisson=0.29)
    cam, report, _ = run(scene)
    res = cam.dynamics.result
    s, _, a = rise_return(res.theta, "cycloidal", 20.0, D(120), D(60), D(120))
    force = m * a * _omega(rpm) ** 2 / 1000 + k * s + f0 + m * G  # N, pressure angle 0
    compliance = (1 - 0.3**2) / 210e3 + (1 - 0.29**2) / 200e3  # 1/MPa
    stress = np.sqrt(force / (math.pi * thick * (base + s + a) * compliance))
    assert np.max(np.abs(res.hertz_stress - stress)) <= 1e-9 * np.max(stress)
    figures = report["cams"]["c"]["figures"]["dynamics"]
    assert figures["hertz_stress_peak_MPa"] == pytest.approx(np.max(stress), rel=1e-9)
    assert figures["contact_width_mm"] == thick
    assert figures["hertz_stress_peak_deg"] == pytest.approx(math.degrees(res.theta[np.argmax(stress)]), abs=1e-6)
    for factor, code in ((1.001, 0), (0.999, 1)):
        scene["cams"]["c"]["allowable_contact_stress_mpa"] = factor * float(np.max(stress))
        status, out, err = check_exit(scene, tmp_path, capsys)
        assert status == code, err
        row = next(line for line in out.splitlines() if line.split()[1:2] == ["hertz_stress"])
        assert ("FAIL" in row) == (code == 1) and ("hertz_stress" in err) == (code == 1)


def test_torque_integrates_to_zero_per_turn_and_damping_dissipates_c_v_squared():
    """Without damping spring, weight and inertia are conservative: the shaft's work per turn is
    0.  With damping c it is c int v^2 dt = 1.5 c h^2 (w / beta_rise + w / beta_return) for
    cycloidal motion (int_0^1 (1 - cos 2 pi u)^2 du = 1.5)."""
    rpm, c, h = 300.0, 25.0, 0.020
    report = run(plate())[1]
    figures = report["cams"]["c"]["figures"]["dynamics"]
    assert abs(figures["energy_per_turn_J"]) <= 1e-10 * figures["torque_peak_Nm"] * TWO_PI
    assert abs(figures["mean_power_W"]) <= 1e-10 * figures["power_peak_W"]
    damped = run(plate(damping_n_s_per_m=c))[1]["cams"]["c"]["figures"]["dynamics"]
    w = _omega(rpm)
    dissipated = 1.5 * c * h**2 * (w / D(120) + w / D(120))
    assert damped["energy_per_turn_J"] == pytest.approx(dissipated, rel=1e-6)
    assert damped["mean_power_W"] == pytest.approx(dissipated * w / TWO_PI, rel=1e-6)


def test_oscillating_arm_torque_is_i_alpha_plus_spring_plus_damping():
    """Arm of inertia I, torsional spring k_t with preload T0, damping c_t, no weight: the cam
    must supply I psi'' w^2 + k_t psi + T0 + c_t psi' w about the pivot (psi the cycloidal swing)."""
    inertia, k_t, t0, c_t, rpm = 2e-3, 5000.0, 3000.0, 0.04, 300.0  # kg*m^2, N*mm/rad, N*mm, N*m*s/rad
    cam, report, _ = run(oscillating(gravity=False, damping_n_m_s_per_rad=c_t))
    res = cam.dynamics.result
    w = _omega(rpm)
    psi, dpsi, d2psi = rise_return(res.theta, "cycloidal", D(15), D(100), D(60), D(120))
    torque = inertia * d2psi * w**2 + k_t / 1000 * psi + t0 / 1000 + c_t * dpsi * w  # N*m
    assert np.max(np.abs(res.generalised_force / 1000 - torque)) <= 1e-10 * np.max(np.abs(torque))
    assert report["cams"]["c"]["figures"]["dynamics"]["spring_preload_Nmm"] == t0


@pytest.mark.parametrize("case", ["translating roller", "translating knife", "translating flat", "oscillating roller",
                                  "oscillating flat", "cw oscillating roller"])
def test_shaft_torque_is_the_moment_of_the_contact_force_about_the_cam_axis(case):
    """Two routes to the camshaft torque: the power balance T w = Q v the stage uses, and the
    moment of the contact force F n (n the common normal, from the cam into the follower) at the
    contact point X about the cam axis, in the direction of rotation: T = sigma (X x F n)_z.
    For an arm, the same force's moment about the pivot is the generalised force Q (positive swing
    direction).  X, n from the follower geometry (the roller centre, the face normal, the knife's
    path tangent); the weight included."""
    scene = {
        "translating roller": plate(follower_offset_mm=6.0),
        "translating knife": plate(follower="knife", roller_radius_mm=None, follower_offset_mm=-5.0),
        "translating flat": plate(follower="flat", roller_radius_mm=None, base_radius_mm=60.0),
        "oscillating roller": oscillating(mass_kg=0.3, cg_distance_mm=35.0),
        "oscillating flat": oscillating_flat(mass_kg=0.3, cg_distance_mm=20.0),
        "cw oscillating roller": oscillating(mass_kg=0.3, cg_distance_mm=35.0, rotation="cw", swing_turn="cw", pivot_x_mm=-90.0),
    }[case]
    cam, _, _ = run(scene)
    res, f, k = cam.dynamics.result, cam.built.spec_follower, cam.built.envelope.data
    theta = k.theta
    c, s = np.cos(f.sigma * theta), np.sin(f.sigma * theta)

    def to_fixed(p: np.ndarray) -> np.ndarray:  # cam frame -> fixed frame at cam angle theta
        return np.stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]], axis=-1)

    if f.kind == "roller":
        x = to_fixed(k.contact_point)
        n = (k.follower_point - x) / f.roller_radius  # towards the roller centre
    elif f.kind == "flat":
        x = k.follower_point
        angle = np.full_like(theta, math.pi / 2) if f.motion == "translating" else k.arm_angle
        n = np.stack([np.cos(angle), np.sin(angle)], axis=-1)  # the face normal, away from the cam
    else:  # knife: the normal of the tip's path seen from the cam, pointing away from the axis
        x = k.follower_point
        tangent = to_fixed(k.pitch_d1)
        n = np.stack([-tangent[:, 1], tangent[:, 0]], axis=-1) / np.hypot(tangent[:, 0], tangent[:, 1])[:, None]
        n *= np.sign(np.sum(n * x, axis=1))[:, None]
    force = res.contact_force[:, None] * n
    moment = f.sigma * (x[:, 0] * force[:, 1] - x[:, 1] * force[:, 0]) / 1000  # N*m
    assert np.max(np.abs(res.torque - moment)) <= 1e-9 * res.torque_peak
    if f.motion == "oscillating":
        arm = x - np.asarray(f.pivot)
        about_pivot = f.tau * (arm[:, 0] * force[:, 1] - arm[:, 1] * force[:, 0])  # N*mm
        assert np.max(np.abs(res.generalised_force - about_pivot)) <= 1e-9 * np.max(np.abs(about_pivot))


@pytest.mark.parametrize("follower", ["roller", "flat"])
def test_an_arms_weight_is_balanced_about_the_pivot(follower):
    """The arm's weight W = m g (cos gamma, sin gamma) at its centre of mass r (r_g along the arm
    towards the roller; a flat face's arm: r_g perpendicular to the face from the pivot towards the
    cam, -w) turns it by (r x W)_z; the cam balances it with -tau (r x W)_z along the swing."""
    m, r_g, gamma = 0.3, 35.0, D(-60.0)
    make = oscillating if follower == "roller" else oscillating_flat
    with_weight = run(make(mass_kg=m, cg_distance_mm=r_g, gravity_deg=-60.0))[0]
    without = run(make(mass_kg=m, cg_distance_mm=r_g, gravity=False))[0].dynamics.result
    f, k = with_weight.built.spec_follower, with_weight.built.envelope.data
    if follower == "roller":  # along the arm, from the pivot to the roller centre
        arm = k.follower_point - np.asarray(f.pivot)
        r = r_g * arm / np.hypot(arm[:, 0], arm[:, 1])[:, None]
    else:  # towards the cam: the face normal w points away from it
        r = -r_g * np.stack([np.cos(k.arm_angle), np.sin(k.arm_angle)], axis=-1)
    weight = m * G * np.array([math.cos(gamma), math.sin(gamma)])  # N
    moment = r[:, 0] * weight[1] - r[:, 1] * weight[0]  # N*mm
    added = with_weight.dynamics.result.generalised_force - without.generalised_force
    assert np.max(np.abs(added + f.tau * moment)) <= 1e-9 * m * G * r_g


def test_weight_and_load_table_add_their_forces_along_the_motion(tmp_path):
    """The weight m g acts along the motion by cos(gravity - motion direction); a load table
    (0 deg: 10 N, 180 deg: 30 N) is interpolated linearly and periodically: 20 N at 90 and 270
    deg, 15 N at 315 deg."""
    base = run(plate(gravity=False))[0].dynamics.result
    theta = np.degrees(base.theta)
    for gravity, along in ((-90.0, 1.0), (90.0, -1.0), (-30.0, 0.5)):
        res = run(plate(gravity_deg=gravity))[0].dynamics.result
        assert np.max(np.abs(res.follower_force - base.follower_force - along * 0.6 * G)) <= 1e-9
    (tmp_path / "load.csv").write_text("# load on the follower\ncam_angle_deg, load_n\n0, 10\n180, 30\n")
    res = run(plate(gravity=False, external_load_csv="load.csv"), tmp_path)[0].dynamics.result
    for angle, load in ((0.0, 10.0), (90.0, 20.0), (180.0, 30.0), (270.0, 20.0), (315.0, 15.0)):
        i = int(np.argmin(np.abs(theta - angle)))
        assert theta[i] == pytest.approx(angle, abs=1e-6)
        assert res.follower_force[i] - base.follower_force[i] == pytest.approx(load, abs=1e-9)
    constant = run(plate(gravity=False, external_load_n=12.5))[0].dynamics.result
    assert np.max(np.abs(constant.follower_force - base.follower_force - 12.5)) <= 1e-9


def test_spring_lengths_set_the_preload_and_the_margin_needs_the_stated_spring():
    """rate x (free - installed) is the preload; the stated smallest preload, used as the
    preload, brings the smallest contact force to the margin (linear in the preload)."""
    a = run(plate(spring_preload_n=None, spring_free_length_mm=70.0, spring_installed_length_mm=52.5))[1]
    b = run(plate(spring_preload_n=35.0))[1]
    assert a["cams"]["c"]["figures"]["dynamics"] == b["cams"]["c"]["figures"]["dynamics"]
    scene = plate(rpm=600.0, jump_margin_n=15.0)
    figures = run(scene)[1]["cams"]["c"]["figures"]["dynamics"]
    assert figures["min_contact_force_N"] < 15.0
    fixed = run(plate(rpm=600.0, jump_margin_n=15.0, spring_preload_n=figures["min_preload_N"]))[1]
    assert fixed["cams"]["c"]["figures"]["dynamics"]["min_contact_force_N"] == pytest.approx(15.0, rel=1e-9)
    above = run(plate(rpm=600.0, jump_margin_n=15.0, spring_preload_n=figures["min_preload_N"] + 1e-6))[1]
    assert {c["name"]: c["status"] for c in above["cams"]["c"]["checks"]}["jump"] == "pass"
    stiffer = run(plate(rpm=600.0, jump_margin_n=15.0, spring_rate_n_per_mm=figures["min_spring_rate_N_per_mm"]))[1]
    assert stiffer["cams"]["c"]["figures"]["dynamics"]["min_contact_force_N"] >= 15.0 * (1 - 1e-9)


def _spring_need(margin: float, rpm: float, m: float, k: float, f0: float, d0: float | None = None):
    """For plate()'s roller (cycloidal 20 mm, centred, Rp = 50 mm, gravity down the motion):
    the contact force is (m a w^2 + k s + F0 + m g) / cos(alpha), tan(alpha) = s' / (Rp + s)
    (Norton ch. 8).  Returns the least preload F0 (rate k), the least rate (preload F0) and, with
    free - installed = d0 (preload = k d0), the least rate with those lengths, for a force >=
    ``margin`` at every cam angle (every 0.002 deg, written out)."""
    theta = np.radians(np.arange(0.0, 360.0, 0.002))
    s, v, a = rise_return(theta, "cycloidal", 20.0, D(120), D(60), D(120))
    w = _omega(rpm)
    need = margin * np.cos(np.arctan(v / (50.0 + s)))  # what the force along the motion must reach
    inertia = m * a * w**2 / 1000 + m * G
    least_preload = float(np.max(need - inertia - k * s))
    lifted = s > 1e-9
    least_rate = float(np.max((need - inertia - f0)[lifted] / s[lifted]))
    with_lengths = None if d0 is None else float(np.max((need - inertia) / (s + d0)))
    return least_preload, least_rate, with_lengths


def _jump_status(scene: dict) -> str:
    return {c["name"]: c["status"] for c in run(scene)[1]["cams"]["c"]["checks"]}["jump"]


def test_the_jump_notes_least_preload_and_rate_are_tried():
    """The note's "preload >= P" and "rate >= K", each quoted to 6 digits, rounded up and tried:
    the scene with P (or K) passes the jump check; just below the closed form's value fails."""
    m, k, f0, rpm, margin = 0.6, 2.0, 35.0, 600.0, 15.0
    scene = plate(rpm=rpm, jump_margin_n=margin)
    note = {c["name"]: c for c in run(scene)[1]["cams"]["c"]["checks"]}["jump"]["note"]
    preload = float(re.search(r"preload >= ([\d.e+-]+) N \(rate 2 N/mm\)", note).group(1))
    rate = float(re.search(r"or rate >= ([\d.e+-]+) N/mm \(preload 35 N\)", note).group(1))
    least_preload, least_rate, _ = _spring_need(margin, rpm, m, k, f0)
    assert least_preload * (1 - 1e-7) <= preload <= least_preload * (1 + 1e-5)
    assert least_rate * (1 - 1e-7) <= rate <= least_rate * (1 + 1e-5)
    assert _jump_status(plate(rpm=rpm, jump_margin_n=margin, spring_preload_n=preload)) == "pass"
    assert _jump_status(plate(rpm=rpm, jump_margin_n=margin, spring_preload_n=least_preload * (1 - 1e-5))) == "fail"
    assert _jump_status(plate(rpm=rpm, jump_margin_n=margin, spring_rate_n_per_mm=rate)) == "pass"
    assert _jump_status(plate(rpm=rpm, jump_margin_n=margin, spring_rate_n_per_mm=least_rate * (1 - 1e-5))) == "fail"
    # the jump speed quoted is rounded down: at it (margin 0) the follower stays on the cam.  Written
    # out: the force along the motion k s + F0 + m g + m a w^2 first reaches 0 where a < 0
    jumps = float(re.search(r"the follower jumps at ([\d.e+-]+) rpm", note).group(1))
    theta = np.radians(np.arange(0.0, 360.0, 0.002))
    s, _, a = rise_return(theta, "cycloidal", 20.0, D(120), D(60), D(120))
    falling = a < 0
    exact = math.sqrt(np.min((k * s + f0 + m * G)[falling] / (m * -a[falling] / 1000))) * 60 / TWO_PI
    assert exact * (1 - 1e-5) <= jumps <= exact * (1 + 1e-9)
    assert _jump_status(plate(rpm=jumps, jump_margin_n=0.0)) == "pass"
    assert _jump_status(plate(rpm=exact * (1 + 1e-5), jump_margin_n=0.0)) == "fail"


def test_a_spring_given_by_its_lengths_is_told_its_installed_length_and_rate():
    """A spring of free length 70 mm installed at 52.5 mm (preload 2 x 17.5 = 35 N) cannot be given
    a preload: the note quotes the longest installed length (free - least preload / rate) and the
    least rate with the lengths kept (the preload then grows with the rate); both tried."""
    m, k, rpm, margin = 0.6, 2.0, 600.0, 15.0
    springy = dict(spring_preload_n=None, spring_free_length_mm=70.0, spring_installed_length_mm=52.5, rpm=rpm, jump_margin_n=margin)
    note = {c["name"]: c for c in run(plate(**springy))[1]["cams"]["c"]["checks"]}["jump"]["note"]
    installed = float(re.search(r"installed length <= ([\d.e+-]+) mm", note).group(1))
    rate = float(re.search(r"or rate >= ([\d.e+-]+) N/mm \(spring lengths given\)", note).group(1))
    least_preload, _, least_rate = _spring_need(margin, rpm, m, k, 35.0, d0=17.5)
    longest = 70.0 - least_preload / k
    assert longest - 1e-4 <= installed <= longest + 1e-9
    assert least_rate * (1 - 1e-7) <= rate <= least_rate * (1 + 1e-5)
    assert _jump_status(plate(**{**springy, "spring_installed_length_mm": installed})) == "pass"
    assert _jump_status(plate(**{**springy, "spring_installed_length_mm": longest + 1e-4})) == "fail"
    assert _jump_status(plate(**{**springy, "spring_rate_n_per_mm": rate})) == "pass"
    assert _jump_status(plate(**{**springy, "spring_rate_n_per_mm": least_rate * (1 - 1e-5)})) == "fail"


# --------------------------------------------------------------------------------------------
# The yoke: form closure, both contacts
# --------------------------------------------------------------------------------------------
def test_yoke_faces_share_the_force_and_both_contacts_are_hertz_checked():
    """Paper 000's three-arc cam (a, b, c = 220, 160, 25 mm): arcs of radii c, a + c, a + c - b,
    2a + c - b in opposite pairs adding up to the breadth 2a + 2c - b.  On an arc of radius r
    about a centre fixed to the cam, the face's distance from the axis is s = C . d + r, so
    s'' = r - s: face 1 carries m (r - s) w^2 where that is positive, face 2 the rest, and each
    face's Hertz stress is that of its own arc (flat face: p = sqrt(F / (pi b r K))).  s is
    measured here by brute force on the profile's points."""
    a, b, c, m, rpm, width = 220.0, 160.0, 25.0, 20.0, 30.0, 20.0
    radii = np.array([c, a + c, a + c - b, 2 * a + c - b])
    breadth = 2 * a + 2 * c - b
    cam, report, _ = run({"output": {"formats": ["dxf"]}, "cams": {"c": dict(YOKE)}})
    res = cam.dynamics.result
    assert res.contact_force_2 is not None and res.hertz_stress_2 is not None
    compliance = 2 * (1 - 0.3**2) / 210e3
    f1, f2 = res.contact_force, res.contact_force_2
    assert np.all(f1 >= 0) and np.all(f2 >= 0) and np.all((f1 == 0) | (f2 == 0))
    # the radius each loaded face touches, from its stress: one of the paper's arcs
    with np.errstate(divide="ignore", invalid="ignore"):
        rho1 = f1 / (math.pi * width * compliance * res.hertz_stress**2)
        rho2 = f2 / (math.pi * width * compliance * res.hertz_stress_2**2)
    on1, on2 = f1 > 1e-6 * np.max(f1), f2 > 1e-6 * np.max(f2)
    near1 = radii[np.argmin(np.abs(rho1[on1, None] - radii), axis=1)]
    near2 = radii[np.argmin(np.abs(rho2[on2, None] - radii), axis=1)]
    assert np.max(np.abs(rho1[on1] / near1 - 1)) <= 1e-9 and np.max(np.abs(rho2[on2] / near2 - 1)) <= 1e-9
    # face 1's arc: its own where it carries, the opposite of face 2's arc where that one does
    r1 = np.full(res.theta.shape, np.nan)
    r1[on1], r1[on2] = near1, breadth - near2
    loaded = on1 | on2
    pts = cam.contour.flatten(1e-4)
    psi = cam.follower.direction - res.theta[loaded]
    s = np.max(pts @ np.stack([np.cos(psi), np.sin(psi)]), axis=0)  # brute-force support, mm
    net = m * (r1[loaded] - s) * _omega(rpm) ** 2 / 1000  # N
    assert np.max(np.abs((f1 - f2)[loaded] - net)) <= 1e-5 * np.max(np.abs(net))
    figures = report["cams"]["c"]["figures"]["dynamics"]
    assert figures["closure"] == "form" and "jump_rpm" not in figures
    assert figures["max_contact_force_1_N"] == pytest.approx(np.max(f1)) and figures["max_contact_force_2_N"] == pytest.approx(np.max(f2))
    checks = {ch["name"]: ch for ch in report["cams"]["c"]["checks"]}
    assert "jump" not in checks and checks["contact_force"]["status"] == "info"
    assert checks["hertz_stress"]["value"] == pytest.approx(max(np.max(res.hertz_stress), np.max(res.hertz_stress_2)), rel=1e-12)
    assert "both contacts" in checks["hertz_stress"]["note"]


def test_camgen_check_fails_a_yoke_on_its_second_face_alone(tmp_path, capsys):
    """A yoke moving vertically with gravity pointing up (+y): the weight adds to face 2's load, so
    face 2's stress peaks above face 1's; an allowable stress between the two peaks fails the run
    where face 2 carries the load."""
    yoke = {**YOKE, "follower_direction_deg": 90.0, "gravity_deg": 90.0}
    cam, _, _ = run({"output": {"formats": ["dxf"]}, "cams": {"c": yoke}})
    res = cam.dynamics.result
    peak1, peak2 = float(np.max(res.hertz_stress)), float(np.max(res.hertz_stress_2))
    assert peak2 > 1.01 * peak1
    scene = {"output": {"formats": ["dxf"]}, "cams": {"c": {**yoke, "allowable_contact_stress_mpa": 0.5 * (peak1 + peak2)}}}
    code, _, err = check_exit(scene, tmp_path, capsys)
    assert code == 1 and "camgen: check failed: cams.c: hertz_stress" in err
    check = next(c for c in run(scene)[0].checks if c.name == "hertz_stress")
    theta = np.degrees(res.theta)
    for start, end in zip(check.where_deg[::2], check.where_deg[1::2]):  # face 2 carries the load over each failing range
        inside = (theta >= start) & (theta <= end)
        assert inside.any() and np.all(res.contact_force_2[inside] > 0) and np.all(res.contact_force[inside] == 0)
    scene["cams"]["c"]["allowable_contact_stress_mpa"] = 1.001 * peak2
    assert check_exit(scene, tmp_path, capsys)[0] == 0


# --------------------------------------------------------------------------------------------
# Report
# --------------------------------------------------------------------------------------------
def test_report_json_and_html_carry_the_dynamics():
    import jsonschema

    from camgen.report import REPORT_SCHEMA

    cam, report, files = run(plate(torque_limit_n_m=5.0, allowable_contact_stress_mpa=900.0, jump_margin_n=5.0),
                             formats=["dxf", "html"])
    jsonschema.validate(report, REPORT_SCHEMA)
    figures = report["cams"]["c"]["figures"]["dynamics"]
    res = cam.dynamics.result
    assert figures["jump_rpm"] == pytest.approx(res.jump_rpm) and figures["torque_peak_Nm"] == pytest.approx(res.torque_peak)
    assert {c["name"] for c in report["cams"]["c"]["checks"]} >= {"jump", "hertz_stress", "camshaft_torque"}
    broken = copy.deepcopy(report)
    del broken["cams"]["c"]["figures"]["dynamics"]["jump_rpm"]
    with pytest.raises(jsonschema.ValidationError):  # the dynamics figures' schema is not vacuous
        jsonschema.validate(broken, REPORT_SCHEMA)
    page = files["report.html"]
    assert "<h3>Dynamics at 300 rpm</h3>" in page
    for title in ("contact force at 300 rpm", "pressure angle", "camshaft torque: peak", "shaft power: peak",
                  "Hertz contact stress: peak", "jump margin against speed"):
        assert title in page, title
    # the speed curve reaches the margin at the jump speed (it is the smallest force over the turn)
    speed, smallest = cam.dynamics.speed_rpm, cam.dynamics.speed_min_force
    assert speed[-1] > res.jump_rpm > speed[0] and smallest[0] > 0
    crossing = np.interp(0.0, -smallest, speed)  # decreasing past the jump
    assert crossing == pytest.approx(res.jump_rpm, rel=2e-3)
    assert smallest[int(np.argmin(np.abs(speed - 300.0)))] == pytest.approx(res.min_contact_force, rel=1e-3)
    # report.json stays without plot data; a run without html computes none
    assert run(plate(), formats=["dxf"])[0].dynamics.speed_rpm is None


# --------------------------------------------------------------------------------------------
# Every dynamics figure of report.json against a force balance computed here
# --------------------------------------------------------------------------------------------
REFERENCE_SAMPLES = 72000  # 0.005 deg: the reference's own grid (camgen's check grid is its own)


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _turn(v: np.ndarray, angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]], axis=-1)


def reference_dynamics(keys: dict) -> dict:
    """The force balance of a spring-loaded roller follower (translating with an offset, or an
    oscillating arm) of a cycloidal rise-dwell-return-dwell cam, in SI units, from plane geometry
    and the program written out (rise_return); nothing of camgen's but its conventions.

    * the generalised force along the follower's coordinate q (s mm, or the arm angle psi rad):
      Q = M w^2 q'' + C w q' + K q + P0 + weight (translating N: m, c, k; arm N*mm: I, c_t, k_t and
      the arm's weight m g at r_g along the arm, -tau (r x W)_z) = A + B w + C w^2;
    * the common normal through the roller centre C and the instant centre of cam and follower
      (Kennedy): I = (sigma s', 0) for a follower moving along +y, I = -r P / (1 - r) on the line to
      the pivot P for an arm (r = sigma tau psi' its angular velocity over the cam's); the contact
      force F = Q / (lever cos(alpha)), alpha between that normal and C's velocity;
    * the camshaft torque as the moment of F n at the contact point X = C - r_roller n about the
      cam axis, in the direction of rotation (not the power balance camgen uses);
    * the Hertz stress (Rothbart eq. 9.11) with the profile's radius of curvature: the pitch
      curve's R(-sigma theta) C(theta) from its closed-form derivatives, less the roller radius.
    """
    from camgen.synthesis.followers import FollowerSpec
    from test_followers import rest_arm_angle

    rpm, w = keys["rpm"], _omega(keys["rpm"])
    sigma = 1.0 if keys.get("rotation", "ccw") == "ccw" else -1.0
    roller, base = keys["roller_radius_mm"], keys["base_radius_mm"]
    segs = keys["segments"]
    rise, dwell, ret = D(segs[0]["span_deg"]), D(segs[1]["span_deg"]), D(segs[2]["span_deg"])
    theta = np.arange(REFERENCE_SAMPLES) * (TWO_PI / REFERENCE_SAMPLES)
    g = G if keys.get("gravity", True) else 0.0
    n = theta.size
    zero = np.zeros(n)
    if keys.get("follower_motion", "translating") == "translating":
        e = keys.get("follower_offset_mm", 0.0)
        h = segs[0]["lift_mm"]
        q, dq, d2q = rise_return(theta, "cycloidal", h, rise, dwell, ret)
        m, k, p0, c = keys["mass_kg"], keys["spring_rate_n_per_mm"], keys["spring_preload_n"], keys.get("damping_n_s_per_m", 0.0)
        quad = (k * q + p0 + m * g, c * dq / 1000, m * d2q / 1000)  # N: A, B per rad/s, C per (rad/s)^2
        centre = np.stack([np.full(n, e), math.sqrt((base + roller) ** 2 - e * e) + q], axis=-1)
        d1c, d2c = np.stack([zero, dq], axis=-1), np.stack([zero, d2q], axis=-1)
        instant = np.stack([sigma * dq, zero], axis=-1)
        velocity = np.tile([0.0, 1.0], (n, 1))
        lever = 1.0
    else:
        tau = 1.0 if keys.get("swing_turn", "ccw") == "ccw" else -1.0
        pivot = np.array([keys["pivot_x_mm"], keys["pivot_y_mm"]])
        arm = keys["arm_length_mm"]
        q, dq, d2q = rise_return(theta, "cycloidal", D(segs[0]["swing_deg"]), rise, dwell, ret)
        rest = rest_arm_angle(FollowerSpec("roller", base, motion="oscillating", roller_radius=roller, pivot=tuple(pivot),
                                           arm_length=arm, rotation=keys.get("rotation", "ccw"), lift_turn=keys.get("swing_turn", "ccw")))
        gamma = rest + tau * q
        u = np.stack([np.cos(gamma), np.sin(gamma)], axis=-1)
        ju = np.stack([-u[:, 1], u[:, 0]], axis=-1)
        m, r_g = keys.get("mass_kg", 0.0), keys.get("cg_distance_mm", 0.0)
        gravity = D(keys.get("gravity_deg", -90.0))
        weight = m * g * np.array([math.cos(gravity), math.sin(gravity)])  # N
        weight_moment = -tau * _cross(r_g * u, np.broadcast_to(weight, (n, 2)))  # N*mm, against the swing
        inertia, k_t, t0, c_t = keys["inertia_kg_m2"], keys["spring_rate_n_mm_per_rad"], keys["spring_preload_n_mm"], \
            keys.get("damping_n_m_s_per_rad", 0.0)
        quad = (k_t * q + t0 + weight_moment, c_t * dq * 1000, inertia * d2q * 1000)  # N*mm
        centre = pivot + arm * u
        d1c = arm * tau * dq[:, None] * ju
        d2c = arm * tau * d2q[:, None] * ju - arm * (dq**2)[:, None] * u
        ratio = sigma * tau * dq
        instant = -ratio[:, None] * pivot / (1.0 - ratio)[:, None]
        velocity = tau * ju
        lever = arm
    normal = centre - instant
    normal /= np.hypot(*normal.T)[:, None]
    normal *= np.sign(np.sum(normal * centre, axis=1))[:, None]  # from the cam into the roller
    cos_alpha = np.abs(np.sum(normal * velocity, axis=1))
    a_, b_, c_ = quad
    force = (a_ + b_ * w + c_ * w * w) / (lever * cos_alpha)  # N
    contact = centre - roller * normal
    torque = sigma * _cross(contact, force[:, None] * normal) / 1000  # N*m
    # the pitch curve seen from the cam: P = R(-sigma theta) C, P' = R(C' - sigma J C), P'' = R(C'' - 2 sigma J C' - C)
    jc, jd1 = np.stack([-centre[:, 1], centre[:, 0]], -1), np.stack([-d1c[:, 1], d1c[:, 0]], -1)
    p1, p2 = d1c - sigma * jc, d2c - 2 * sigma * jd1 - centre
    pitch_radius = -sigma * np.hypot(*p1.T) ** 3 / _cross(p1, p2)  # > 0 convex (the curve runs clockwise for sigma = +1)
    width = keys.get("contact_width_mm", keys.get("thickness_mm"))
    compliance = 2 * (1 - 0.3**2) / 210e3  # steel on steel, 1/MPa
    hertz = np.sqrt(force * (1 / (pitch_radius - roller) + 1 / roller) / (math.pi * width * compliance))
    # the jump (the follower leaves the cam): the smallest w > 0 with A + B w + C w^2 = 0, the quadratic formula per angle
    disc = b_ * b_ - 4 * a_ * c_
    with np.errstate(invalid="ignore", divide="ignore"):
        roots = np.stack([(-b_ + sgn * np.sqrt(disc)) / (2 * c_) for sgn in (1.0, -1.0)])
    roots = np.where((disc >= 0) & (roots > 0), roots, np.inf)
    jump = float(np.min(roots)) * 60 / TWO_PI
    # the least preload (and spring rate) that keeps the contact force at the margin at this speed
    margin = keys.get("jump_margin_n", 0.0)
    need = margin * lever * cos_alpha - (b_ * w + c_ * w * w)
    spring = (k * q) if lever == 1.0 else (k_t * q)
    rate_need = need - (a_ - spring)
    lifted = q > 1e-9
    min_rate = None if np.any((rate_need > 0) & ~lifted) else float(np.max(np.where(lifted, rate_need / np.where(lifted, q, 1), 0)))
    return {"theta": theta, "force": force, "torque": torque, "hertz": hertz, "jump_rpm": jump, "omega": w,
            "min_preload": max(0.0, float(np.max(need - (a_ - (p0 if lever == 1.0 else t0))))), "min_rate": min_rate,
            "dissipated": (keys.get("damping_n_s_per_m", 0.0) * 1.5 * (h / 1000) ** 2 if lever == 1.0 else
                           keys.get("damping_n_m_s_per_rad", 0.0) * 1.5 * D(segs[0]["swing_deg"]) ** 2) * w * (1 / rise + 1 / ret)}


DYNAMICS_CASES = {
    "translating roller": plate(follower_offset_mm=8.0, damping_n_s_per_m=20.0, rpm=420.0, jump_margin_n=10.0, torque_limit_n_m=5.0,
                                allowable_contact_stress_mpa=900.0, contact_width_mm=8.0),
    "cw translating roller": plate(follower_offset_mm=-5.0, rotation="cw", damping_n_s_per_m=20.0, jump_margin_n=10.0,
                                   segments=program("cycloidal", 20.0, 150.0, 60.0, 90.0)),  # the return drives the cam: T < 0 peaks
    "oscillating roller": oscillating(mass_kg=0.3, cg_distance_mm=35.0, damping_n_m_s_per_rad=0.05, rpm=360.0, jump_margin_n=5.0,
                                      allowable_contact_stress_mpa=900.0, torque_limit_n_m=5.0),
    "cw oscillating roller": oscillating(mass_kg=0.3, cg_distance_mm=35.0, rotation="cw", swing_turn="cw", pivot_x_mm=-90.0,
                                         damping_n_m_s_per_rad=0.05, gravity_deg=-60.0, jump_margin_n=5.0),
}


@pytest.mark.parametrize("case", DYNAMICS_CASES)
def test_every_dynamics_figure_is_the_independent_force_balance(case):
    """Each number under figures.dynamics of report.json (the run's file, read as JSON) against
    reference_dynamics on its own 0.005 deg grid: the peaks (camgen's are its grid's largest: the
    same to 1e-6), where they are (the reference's value there is the peak), the RMS values and
    the work per turn (the energy the damping dissipates, c w int q'^2 dtheta = 1.5 c h^2 w
    (1/beta_rise + 1/beta_return) for cycloidal motion), the jump speed, the least preload and
    spring rate, and the inputs echoed."""
    scene = DYNAMICS_CASES[case]
    keys = scene["cams"]["c"]
    figures = run(scene)[1]["cams"]["c"]["figures"]["dynamics"]
    ref = reference_dynamics(keys)
    theta, force, torque, hertz, w = ref["theta"], ref["force"], ref["torque"], ref["hertz"], ref["omega"]
    arm = keys.get("follower_motion") == "oscillating"
    unit, rate_unit = ("Nmm", "Nmm_per_rad") if arm else ("N", "N_per_mm")

    def at(deg: float, values: np.ndarray) -> float:  # the reference at a reported cam angle
        return float(np.interp(deg, np.degrees(theta), values, period=360.0))

    def rms(values: np.ndarray) -> float:  # uniform grid over one turn: the mean square
        return float(np.sqrt(np.mean(values**2)))

    assert figures["closure"] == "force" and figures["follower_motion"] == ("oscillating" if arm else "translating")
    assert figures["rpm"] == keys["rpm"] and figures["jump_margin_N"] == keys["jump_margin_n"]
    assert figures[f"spring_preload_{unit}"] == keys["spring_preload_n_mm" if arm else "spring_preload_n"]
    assert figures["min_contact_force_N"] == pytest.approx(float(np.min(force)), rel=1e-6)
    assert figures["max_contact_force_N"] == pytest.approx(float(np.max(force)), rel=1e-6)
    assert at(figures["min_contact_force_deg"], force) == pytest.approx(figures["min_contact_force_N"], rel=1e-5)
    assert at(figures["max_contact_force_deg"], force) == pytest.approx(figures["max_contact_force_N"], rel=1e-5)
    assert figures["torque_peak_Nm"] == pytest.approx(float(np.max(np.abs(torque))), rel=1e-6)
    assert abs(at(figures["torque_peak_deg"], torque)) == pytest.approx(figures["torque_peak_Nm"], rel=1e-5)
    assert figures["torque_rms_Nm"] == pytest.approx(rms(torque), rel=1e-6)
    assert figures["power_peak_W"] == pytest.approx(float(np.max(np.abs(torque))) * w, rel=1e-6)
    assert figures["power_rms_W"] == pytest.approx(rms(torque) * w, rel=1e-6)
    assert figures["energy_per_turn_J"] == pytest.approx(ref["dissipated"], rel=1e-5)
    assert figures["mean_power_W"] == pytest.approx(ref["dissipated"] * w / TWO_PI, rel=1e-5)
    assert figures["jump_rpm"] == pytest.approx(ref["jump_rpm"], rel=1e-6)
    assert keys["rpm"] < figures["jump_rpm"] and figures["jump_ranges_deg"] == []
    assert figures[f"min_preload_{unit}"] == pytest.approx(ref["min_preload"], rel=1e-5, abs=1e-9)
    assert figures[f"min_spring_rate_{rate_unit}"] == pytest.approx(ref["min_rate"], rel=1e-5, abs=1e-9)
    if "allowable_contact_stress_mpa" in keys:
        assert figures["hertz_stress_peak_MPa"] == pytest.approx(float(np.max(hertz)), rel=1e-6)
        assert at(figures["hertz_stress_peak_deg"], hertz) == pytest.approx(figures["hertz_stress_peak_MPa"], rel=1e-5)
        assert figures["allowable_contact_stress_MPa"] == keys["allowable_contact_stress_mpa"]
        assert figures["contact_width_mm"] == keys.get("contact_width_mm", keys["thickness_mm"])
    if "torque_limit_n_m" in keys:
        assert figures["torque_limit_Nm"] == keys["torque_limit_n_m"]


# --------------------------------------------------------------------------------------------
# Refusals
# --------------------------------------------------------------------------------------------
def _three_arc(**changes) -> dict:
    cam = {**YOKE, **changes}
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {k: v for k, v in cam.items() if v is not None}}}


REFUSED = {
    "spring without a mass": (plate(mass_kg=None), "cams.c.mass_kg", "need the follower's mass"),
    "mass without rpm": (plate(rpm=None), "cams.c.rpm", "computed at the cam speed"),
    "arm spring without inertia": (oscillating(inertia_kg_m2=None), "cams.c.inertia_kg_m2", "moment of inertia"),
    "torsional spring on a slider": (plate(spring_rate_n_mm_per_rad=10.0), "cams.c.spring_rate_n_mm_per_rad",
                                     "only with follower_motion = 'oscillating'"),
    "linear spring on an arm": (oscillating(spring_rate_n_per_mm=1.0), "cams.c.spring_rate_n_per_mm",
                                "only with follower_motion = 'translating'"),
    "spring lengths on an arm": (oscillating(spring_free_length_mm=50.0), "cams.c.spring_free_length_mm", "only with follower_motion"),
    "arm weight without its centre": (oscillating(mass_kg=0.3), "cams.c.cg_distance_mm", "centre of mass"),
    "preload and lengths": (plate(spring_free_length_mm=60.0, spring_installed_length_mm=50.0), "cams.c.spring_preload_n",
                            "set the preload"),
    "one spring length": (plate(spring_preload_n=None, spring_free_length_mm=60.0), "cams.c.spring_installed_length_mm",
                          "given together"),
    "installed longer than free": (plate(spring_preload_n=None, spring_free_length_mm=50.0, spring_installed_length_mm=60.0),
                                   "cams.c.spring_installed_length_mm", "<= spring_free_length"),
    "two loads": (plate(external_load_n=5.0, external_load_csv="load.csv"), "cams.c.external_load_csv", "give one external load"),
    "gravity direction without gravity": (plate(gravity=False, gravity_deg=0.0), "cams.c.gravity_deg", "only with gravity"),
    "contact stress of a knife": (plate(follower="knife", roller_radius_mm=None, allowable_contact_stress_mpa=900.0),
                                  "cams.c.allowable_contact_stress_mpa", "knife edge"),
    "spring on a yoke": (_three_arc(spring_rate_n_per_mm=1.0), "cams.c.spring_rate_n_per_mm", "form-closed"),
    "jump margin of a yoke": (_three_arc(jump_margin_n=5.0), "cams.c.jump_margin_n", "cannot jump"),
    "dynamics of a three-arc roller": (_three_arc(follower="roller", roller_radius_mm=10.0), "cams.c.mass_kg", "yoke or a flat face"),
    "yoke without a mass": (_three_arc(mass_kg=None, damping_n_s_per_m=3.0), "cams.c.mass_kg", "damping_n_s_per_m"),
    "load table out of order": (plate(external_load_csv="bad.csv"), "cams.c.external_load_csv", "strictly increasing"),
    "missing load table": (plate(external_load_csv="missing.csv"), "cams.c.external_load_csv", "readable"),
}


@pytest.mark.parametrize("case", REFUSED)
def test_misplaced_or_incomplete_dynamics_keys_are_refused(case, tmp_path, capsys):
    scene, key, why = REFUSED[case]
    (tmp_path / "load.csv").write_text("0, 1\n")
    (tmp_path / "bad.csv").write_text("0, 1\n90, 2\n45, 3\n")
    code, _, err = check_exit(scene, tmp_path, capsys)
    assert code == 2 and err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert f"'{key}'" in err and why in err, err


# --------------------------------------------------------------------------------------------
# Every dynamics key changes what it documents (the report), and nothing manufactured
# --------------------------------------------------------------------------------------------
OSC = oscillating(mass_kg=0.3, cg_distance_mm=35.0)
DISK_WALK = {
    # key: (base scene, changed scene)
    "mass_kg": (plate(), plate(mass_kg=0.7)),
    "inertia_kg_m2": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=35.0, inertia_kg_m2=3e-3)),
    "cg_distance_mm": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=45.0)),
    "spring_rate_n_per_mm": (plate(), plate(spring_rate_n_per_mm=2.5)),
    "spring_preload_n": (plate(), plate(spring_preload_n=40.0)),
    "spring_free_length_mm": (plate(spring_preload_n=None, spring_free_length_mm=70.0, spring_installed_length_mm=50.0),
                              plate(spring_preload_n=None, spring_free_length_mm=72.0, spring_installed_length_mm=50.0)),
    "spring_installed_length_mm": (plate(spring_preload_n=None, spring_free_length_mm=70.0, spring_installed_length_mm=50.0),
                                   plate(spring_preload_n=None, spring_free_length_mm=70.0, spring_installed_length_mm=48.0)),
    "spring_rate_n_mm_per_rad": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=35.0, spring_rate_n_mm_per_rad=6000.0)),
    "spring_preload_n_mm": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=35.0, spring_preload_n_mm=3500.0)),
    "damping_n_s_per_m": (plate(), plate(damping_n_s_per_m=10.0)),
    "damping_n_m_s_per_rad": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=35.0, damping_n_m_s_per_rad=0.05)),
    "external_load_n": (plate(), plate(external_load_n=5.0)),
    "external_load_n_mm": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=35.0, external_load_n_mm=500.0)),
    "external_load_csv": (plate(external_load_csv="load.csv"), plate(external_load_csv="load2.csv")),
    "gravity": (plate(), plate(gravity=False)),
    "gravity_deg": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=35.0, gravity_deg=-60.0)),
    "contact_width_mm": (plate(), plate(contact_width_mm=8.0)),
    "cam_modulus_gpa": (plate(), plate(cam_modulus_gpa=200.0)),
    "cam_poisson": (plate(), plate(cam_poisson=0.28)),
    "follower_modulus_gpa": (plate(), plate(follower_modulus_gpa=200.0)),
    "follower_poisson": (plate(), plate(follower_poisson=0.28)),
    "allowable_contact_stress_mpa": (plate(), plate(allowable_contact_stress_mpa=100.0)),
    "jump_margin_n": (plate(), plate(jump_margin_n=5.0)),
    "torque_limit_n_m": (plate(), plate(torque_limit_n_m=0.5)),
    # the compliant train (issue 25 item 2; tests/test_compliant.py)
    "train_stiffness_n_per_mm": (plate(), plate(train_stiffness_n_per_mm=500.0)),
    "train_stiffness_n_mm_per_rad": (OSC, oscillating(mass_kg=0.3, cg_distance_mm=35.0, train_stiffness_n_mm_per_rad=2e7)),
    "damping_ratio": (plate(train_stiffness_n_per_mm=500.0), plate(train_stiffness_n_per_mm=500.0, damping_ratio=0.1)),
    "residual_vibration_limit_mm": (plate(train_stiffness_n_per_mm=500.0),
                                    plate(train_stiffness_n_per_mm=500.0, residual_vibration_limit_mm=0.05)),
    # the two-mass train (camgen/compliant_two.py): its keys given together
    "follower_stiffness_n_per_mm": (plate(train_stiffness_n_per_mm=500.0, follower_stiffness_n_per_mm=800.0, tool_mass_kg=0.1),
                                    plate(train_stiffness_n_per_mm=500.0, follower_stiffness_n_per_mm=900.0, tool_mass_kg=0.1)),
    "tool_mass_kg": (plate(train_stiffness_n_per_mm=500.0, follower_stiffness_n_per_mm=800.0, tool_mass_kg=0.1),
                     plate(train_stiffness_n_per_mm=500.0, follower_stiffness_n_per_mm=800.0, tool_mass_kg=0.15)),
    "return_spring_on": (plate(train_stiffness_n_per_mm=500.0, follower_stiffness_n_per_mm=800.0, tool_mass_kg=0.1),
                         plate(train_stiffness_n_per_mm=500.0, follower_stiffness_n_per_mm=800.0, tool_mass_kg=0.1,
                               return_spring_on="cam_side")),
}
# FATIGUE (issue 25 items 3, 4): the friction and life keys (camgen/kinds/dynamics.py friction_life_keys)
_GUIDE = {"guide_length_mm": 40.0, "guide_overhang_mm": 20.0}
_PIN = {"roller_pin_radius_mm": 3.0}
_BEARING = {"roller_dynamic_load_rating_n": 8000.0}
_SN = {"sn_stress_mpa": 1500.0, "sn_cycles": 1e7, "sn_exponent": 6.6, "contact_design_cycles": 1e8}
_FLAT = {"follower": "flat", "roller_radius_mm": None, "base_radius_mm": 45.0}
DISK_WALK.update({
    "guide_length_mm": (plate(**_GUIDE), plate(**{**_GUIDE, "guide_length_mm": 50.0})),
    "guide_overhang_mm": (plate(**_GUIDE), plate(**{**_GUIDE, "guide_overhang_mm": 25.0})),
    "guide_friction": (plate(**_GUIDE), plate(**_GUIDE, guide_friction=0.2)),
    "contact_friction": (plate(**_FLAT, case_depth_factor=2.0), plate(**_FLAT, contact_friction=0.1)),
    "roller_pin_friction": (plate(**_PIN), plate(**_PIN, roller_pin_friction=0.2)),
    "roller_pin_radius_mm": (plate(**_PIN), plate(roller_pin_radius_mm=4.0)),
    "roller_inertia_kg_mm2": (plate(**_PIN), plate(**_PIN, roller_inertia_kg_mm2=2.0)),
    "roller_dynamic_load_rating_n": (plate(**_BEARING), plate(roller_dynamic_load_rating_n=9000.0)),
    "roller_bearing": (plate(**_BEARING), plate(**_BEARING, roller_bearing="ball")),
    "min_bearing_life_h": (plate(**_BEARING), plate(**_BEARING, min_bearing_life_h=1000.0)),
    "case_depth_factor": (plate(case_depth_factor=2.0), plate(case_depth_factor=3.0)),
    "sn_stress_mpa": (plate(**_SN), plate(**{**_SN, "sn_stress_mpa": 1400.0})),
    "sn_cycles": (plate(**_SN), plate(**{**_SN, "sn_cycles": 2e7})),
    "sn_exponent": (plate(**_SN), plate(**{**_SN, "sn_exponent": 8.0})),
    "contact_design_cycles": (plate(**_SN), plate(**{**_SN, "contact_design_cycles": 2e8})),
})


def test_the_walk_covers_every_dynamics_key():
    from camgen.kinds import get_kind
    from camgen.kinds.dynamics import dynamics_keys

    names = [k.name for k in dynamics_keys()]
    assert set(DISK_WALK) == set(names)
    for kind in ("motion_law", "lift_table"):
        assert {k.name for k in get_kind(kind).keys} >= set(names)
    assert all(k.affects == ("report",) for k in dynamics_keys())


@pytest.mark.parametrize("key", DISK_WALK)
def test_every_dynamics_key_changes_the_report_and_no_file(key, tmp_path):
    (tmp_path / "load.csv").write_text("0, 10\n180, 30\n")
    (tmp_path / "load2.csv").write_text("0, 10\n180, 35\n")
    before, after = DISK_WALK[key]
    (_, a, fa), (_, b, fb) = (run(scene, tmp_path) for scene in (before, after))
    assert a["cams"]["c"]["figures"]["dynamics"] != b["cams"]["c"]["figures"]["dynamics"] or \
        a["cams"]["c"]["checks"] != b["cams"]["c"]["checks"], key
    assert fa["c.dxf"] == fb["c.dxf"]  # a dynamics key changes no manufacturing file


# --------------------------------------------------------------------------------------------
# Templates
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name, motion", [("plate_cam", "translating"), ("oscillating_roller", "oscillating")])
def test_templates_with_a_spring_loaded_follower_pass_their_dynamic_checks(name, motion):
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    cam = compute(load_template(name), Plan((), frozenset(), full_report=False)).cams[0]
    checks = {c.name: c for c in cam.checks}
    assert not any(c.failed for c in cam.checks)
    for check in ("jump", "hertz_stress", "camshaft_torque"):  # every limit given: each is a pass, not information
        assert checks[check].status == "pass", check
    figures = cam.figures["dynamics"]
    assert figures["follower_motion"] == motion and figures["jump_rpm"] > 2 * figures["rpm"]


def test_a_cam_that_cannot_be_made_reports_no_forces():
    """An undercut profile (base radius far too small for a 30 mm rise over 60 deg): the undercut
    fails, and the dynamics say they were not computed rather than report forces on no cam."""
    segments = [{"law": "cycloidal", "span_deg": 60.0, "lift_mm": 30.0}, {"law": "dwell", "span_deg": 120.0},
                {"law": "cycloidal", "span_deg": 60.0, "lift_mm": -30.0}, {"law": "dwell", "span_deg": 120.0}]
    cam, report, _ = run(plate(base_radius_mm=20.0, roller_radius_mm=25.0, segments=segments))
    checks = {c["name"]: c for c in report["cams"]["c"]["checks"]}
    assert checks["undercut"]["status"] == "fail" and cam.contour is None
    assert checks["dynamics"]["status"] == "info" and checks["dynamics"]["value"] == "not computed"
    assert cam.dynamics is None and "dynamics" not in report["cams"]["c"]["figures"] and "jump" not in checks
