"""Several cams on one shaft ([mechanisms.machine], issue 25 item 1): the combined torque against
each cam run alone, the flywheel against hand-integrated torque curves, the speed it leaves
against an integration of the shaft's equation of motion, the timing diagram against the motion
law written out, refusals naming the key.

Sources: the energy method for the flywheel (Norton, Design of Machinery, ch. 11:
I = dE / (Cs w^2)); the cycloidal law s = h (u - sin(2 pi u) / (2 pi)) (Norton ch. 8); the shaft's
equation of motion I phi'' = T_motor - T_load(phi) integrated by scipy's DOP853.
"""
from __future__ import annotations

import copy
import json
import math
import tomllib

import numpy as np
import pytest

from camgen.cli import main

TWO_PI = 2.0 * math.pi


def toml_value(v) -> str:
    """``v`` as TOML text (tables inline): the scenes here nest tables in lists, which
    helpers.scene_toml does not write."""
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    return json.dumps(v) if isinstance(v, str) else repr(v)


def scene_toml(scene: dict) -> str:
    return "".join(f"{k} = {toml_value(v)}\n" for k, v in scene.items())


def template() -> dict:
    from camgen.scene import template_path

    with open(template_path("packaging_machine"), "rb") as f:
        return tomllib.load(f)


def compute(scene: dict):
    from camgen.pipeline import compute as run, plan_run
    from camgen.scene import parse_scene

    parsed = parse_scene(scene, "machine_test")
    return run(parsed, plan_run(parsed, None))


def machine_report(scene: dict) -> dict:
    return compute(scene).jobs["machine"].report


def alone(scene: dict, name: str):
    """The dynamics result of cam ``name`` run in a scene of its own (no machine)."""
    single = {"output": {"formats": ["dxf"]}, "machining": dict(scene["machining"]), "cams": {name: copy.deepcopy(scene["cams"][name])}}
    cam = next(c for c in compute(single).cams if c.name == name)
    return cam.dynamics_stage.outcome.result


# --------------------------------------------------------------------------------------------
# The combined torque
# --------------------------------------------------------------------------------------------
def test_combined_torque_is_the_sum_of_each_cam_alone_shifted_by_its_phase():
    """Each cam run alone gives its torque on its own grid; read here at cam angle = machine
    angle + phase (scipy's linear interpolation on the periodically extended samples) and summed,
    it is the machine's torque within 1e-9 of its peak."""
    from scipy.interpolate import interp1d

    scene = template()
    report = machine_report(scene)
    phi = np.radians(np.asarray(report["curves"]["machine_angle_deg"]))
    assert phi.size == report["samples"]
    expected = np.zeros_like(phi)
    for entry in scene["mechanisms"]["machine"]["cams"]:
        result = alone(scene, entry["name"])
        theta = np.concatenate((result.theta - TWO_PI, result.theta, result.theta + TWO_PI))
        torque = np.tile(result.torque, 3)
        expected += interp1d(theta, torque)(np.mod(phi + math.radians(entry["phase_deg"]), TWO_PI))
    combined = np.asarray(report["curves"]["torque_Nm"])
    scale = np.max(np.abs(expected))
    assert scale > 1.0  # a real torque (N*m) from the three cams' dynamics
    assert np.max(np.abs(combined - expected)) <= 1e-9 * scale
    assert report["torque_peak_Nm"] == pytest.approx(scale, rel=1e-9)
    assert report["torque_rms_Nm"] == pytest.approx(math.sqrt(np.mean(expected**2)), rel=1e-9)
    omega = report["rpm"] * TWO_PI / 60.0
    assert report["power_peak_W"] == pytest.approx(scale * omega, rel=1e-9)


def test_a_cams_friction_torque_is_in_the_machines_torque():
    """With friction keys on the knife (a guide and a roller pin), the machine sums the knife's
    camshaft torque with friction (its own run's, tests/test_friction.py checks it) and the
    others' frictionless torques, each at its phase, and names the knife among the cams with
    friction; without the friction the sum is lower by the knife's friction torque."""
    from scipy.interpolate import interp1d

    scene = template()
    scene["cams"]["knife"].update(guide_length_mm=40.0, guide_overhang_mm=20.0, roller_pin_radius_mm=3.0)
    report = machine_report(scene)
    assert report["cams_with_friction"] == ["knife"]
    phi = np.radians(np.asarray(report["curves"]["machine_angle_deg"]))
    expected = np.zeros_like(phi)
    for entry in scene["mechanisms"]["machine"]["cams"]:
        single = {"output": {"formats": ["dxf"]}, "machining": dict(scene["machining"]),
                  "cams": {entry["name"]: copy.deepcopy(scene["cams"][entry["name"]])}}
        outcome = next(c for c in compute(single).cams if c.name == entry["name"]).dynamics_stage.outcome
        life = outcome.friction_life
        torque = life.friction.total_torque if life is not None else outcome.result.torque
        assert (life is not None) == (entry["name"] == "knife")
        theta = outcome.result.theta
        expected += interp1d(np.concatenate((theta - TWO_PI, theta, theta + TWO_PI)), np.tile(torque, 3))(
            np.mod(phi + math.radians(entry["phase_deg"]), TWO_PI))
    combined = np.asarray(report["curves"]["torque_Nm"])
    assert np.max(np.abs(combined - expected)) <= 1e-9 * np.max(np.abs(expected))
    frictionless = np.asarray(machine_report(template())["curves"]["torque_Nm"])
    assert np.mean(combined) > np.mean(frictionless)  # friction takes energy every turn: the mean torque rises


def test_a_cam_without_dynamics_adds_no_torque_and_is_named():
    scene = template()
    base = machine_report(scene)
    scene["cams"]["spare"] = {k: v for k, v in scene["cams"]["knife"].items()
                              if k not in ("mass_kg", "spring_rate_n_per_mm", "spring_preload_n", "external_load_n", "contact_width_mm",
                                           "allowable_contact_stress_mpa", "jump_margin_n")}
    scene["mechanisms"]["machine"]["cams"].append({"name": "spare", "phase_deg": 90.0})
    report = machine_report(scene)
    assert report["cams_without_dynamics"] == {"spare": "no dynamics keys"}
    assert report["curves"]["torque_Nm"] == base["curves"]["torque_Nm"]
    assert "spare" in report["curves"]["followers"]  # its follower is still in the timing diagram


# --------------------------------------------------------------------------------------------
# The flywheel (energy method) on hand-integrated torque curves
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("k, swing_per_a", [(2, 1.0), (1, 2.0), (3, 2.0 / 3.0)])
def test_flywheel_inertia_against_a_hand_integrated_torque(k, swing_per_a):
    """T = T0 + A sin(k phi): E(phi) = int_0^phi (T0 - T) = A (cos(k phi) - 1) / k swings by 2 A / k
    (k = 2: A), so I = (2 A / k) / (Cs w^2); the trapezoid rule on n samples integrates cos(k phi)
    to within its relative error (h k)^2 / 12, h = 2 pi / n (the tolerance, with 10 % to spare)."""
    from camgen.machine import flywheel, machine_angles

    t0, a, rpm, cs = 3.0, 5.0, 120.0, 0.04
    phi = machine_angles(3600)
    fw = flywheel(t0 + a * np.sin(k * phi), rpm, cs)
    omega = rpm * TWO_PI / 60.0
    trapezoid = 1.1 * (TWO_PI / phi.size * k) ** 2 / 12.0
    assert fw.energy_swing == pytest.approx(swing_per_a * a, rel=trapezoid)
    assert fw.inertia == pytest.approx(swing_per_a * a / (cs * omega**2), rel=trapezoid)
    assert fw.mean_torque == pytest.approx(t0, rel=1e-12)


def test_a_constant_torque_needs_no_flywheel():
    from camgen.machine import flywheel

    fw = flywheel(np.full(720, 2.5), 100.0, 0.05)
    assert fw.inertia == 0.0 and fw.energy_swing == 0.0 and fw.fluctuation == 0.0


def test_the_speed_the_flywheel_leaves_by_integrating_the_shaft():
    """I phi'' = T_m - T(phi) with the machine's torque (linear between its samples, as the
    flywheel was sized on) and the stated inertia over a turn, started at the speed that makes the
    time-mean speed the machine's: (w_max - w_min) / w_mean within 1 % of the stated Cs."""
    from scipy.integrate import solve_ivp

    scene = template()
    report = machine_report(scene)
    curves = report["curves"]
    phi_k = np.radians(np.asarray(curves["machine_angle_deg"]))
    torque_k = np.asarray(curves["torque_Nm"])
    inertia = report["flywheel"]["inertia_kg_m2"]
    cs = report["speed_fluctuation"]
    t_motor = float(np.mean(torque_k))  # the motor's constant torque: the mean over a turn (trapezoid on the even grid)
    assert report["motor"]["with_flywheel"]["torque_peak_Nm"] == pytest.approx(abs(t_motor), rel=1e-12)

    def shaft(t, y):
        load = np.interp(np.mod(y[0], TWO_PI), phi_k, torque_k, period=TWO_PI)
        return [y[1], (t_motor - load) / inertia]

    def turned(t, y):
        return y[0] - TWO_PI
    turned.terminal = True

    omega = report["rpm"] * TWO_PI / 60.0

    def one_turn(w0: float):
        sol = solve_ivp(shaft, (0.0, 10.0 * TWO_PI / omega), [0.0, w0], method="DOP853", rtol=1e-11, atol=1e-12,
                        events=turned, max_step=TWO_PI / omega / 2000.0)
        assert sol.status == 1  # one turn
        return sol.y[1], TWO_PI / sol.t_events[0][0]  # speeds over the turn, its time-mean speed

    # the speed at phi = 0 that makes the machine run at its speed on average (secant on the time-mean speed)
    w0, w1 = omega, omega * 1.01
    g0, g1 = one_turn(w0)[1] - omega, one_turn(w1)[1] - omega
    for _ in range(6):
        w0, w1, g0 = w1, w1 - g1 * (w1 - w0) / (g1 - g0), g1
        g1 = one_turn(w1)[1] - omega
        if abs(g1) < 1e-9 * omega:
            break
    w, w_mean = one_turn(w1)
    assert w_mean == pytest.approx(omega, rel=1e-8)
    assert (w.max() - w.min()) / w_mean == pytest.approx(cs, rel=0.01)
    assert report["flywheel"]["speed_fluctuation_left"] == pytest.approx(cs, rel=0.01)


# --------------------------------------------------------------------------------------------
# The timing diagram
# --------------------------------------------------------------------------------------------
def test_timing_diagram_is_each_law_at_its_phase():
    """The pusher rises 40 mm cycloidally over its first 110 deg; at phase p its displacement at
    machine angle phi is s(phi + p) written out; velocity and acceleration at the machine speed."""
    scene = template()
    scene["mechanisms"]["machine"]["cams"][0]["phase_deg"] = 30.0
    report = machine_report(scene)
    phi = np.radians(np.asarray(report["curves"]["machine_angle_deg"]))
    pusher = report["curves"]["followers"]["pusher"]
    theta = np.mod(phi + math.radians(30.0), TWO_PI)
    beta, h = math.radians(110.0), 40.0
    rise = theta < beta
    u = theta[rise] / beta
    omega = report["rpm"] * TWO_PI / 60.0
    assert np.max(np.abs(np.asarray(pusher["displacement_mm"])[rise] - h * (u - np.sin(TWO_PI * u) / TWO_PI))) < 1e-9
    assert np.max(np.abs(np.asarray(pusher["velocity_mm_per_s"])[rise] - omega * h / beta * (1 - np.cos(TWO_PI * u)))) < 1e-7
    a = omega**2 * TWO_PI * h / beta**2 * np.sin(TWO_PI * u)
    assert np.max(np.abs(np.asarray(pusher["acceleration_mm_per_s2"])[rise] - a)) < 1e-5 * np.max(np.abs(a))
    folder = report["curves"]["followers"]["folder"]
    assert max(folder["displacement_deg"]) == pytest.approx(30.0, abs=1e-9)  # an oscillating follower's swing in deg


def test_the_report_draws_the_machine(tmp_path):
    scene = template()
    path = tmp_path / "pm.toml"
    path.write_text(scene_toml(scene))
    assert main(["run", str(path), "-o", str(tmp_path / "out"), "--only", "html", "--quiet"]) == 0
    page = (tmp_path / "out" / "pm" / "report.html").read_text()
    assert "timing diagram: displacement" in page and "timing diagram: acceleration" in page and "shaft speed the flywheel leaves" in page


# --------------------------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------------------------
def _bad(change) -> dict:
    scene = template()
    change(scene)
    return scene


BAD = [
    (lambda s: s["mechanisms"]["machine"]["cams"][1].update(phase_deg=360.0), "mechanisms.machine.cams[1].phase_deg", "360"),
    (lambda s: s["mechanisms"]["machine"]["cams"][1].update(phase_deg=-1.0), "mechanisms.machine.cams[1].phase_deg", "-1"),
    (lambda s: s["mechanisms"]["machine"]["cams"][2].update(name="pusher"), "mechanisms.machine.cams[2].name", "named once"),
    (lambda s: s["mechanisms"]["machine"]["cams"][2].update(name="hopper"), "mechanisms.machine.cams[2].name", "a cam of this scene"),
    (lambda s: s["cams"]["knife"].update(rpm=100.0), "cams.knife.rpm", "the machine's speed, 120 rev/min"),
    (lambda s: s["mechanisms"]["machine"].update(speed_fluctuation=1.0), "mechanisms.machine.speed_fluctuation", "x < 1"),
    (lambda s: s["mechanisms"]["machine"].update(speed_fluctuation=0.0), "mechanisms.machine.speed_fluctuation", "0 < x"),
]


@pytest.mark.parametrize("change, key, valid", BAD)
def test_bad_machine_input_is_refused_naming_the_key(change, key, valid, tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(scene_toml(_bad(change)))
    out = tmp_path / "out"
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: error: ") and key in err[0] and valid in err[0], err
    assert main(["run", str(path), "-o", str(out), "--quiet"]) == 2
    assert not out.exists() or not any(out.iterdir())


def test_a_motor_limit_fails_the_check():
    scene = template()
    scene["mechanisms"]["machine"]["motor_torque_limit_n_m"] = 0.1  # below the mean shaft torque (0.195 N*m)
    result = compute(scene)
    check = next(c for c in result.cams[0].checks if c.name == "machine_motor_torque")
    mean = float(np.mean(result.jobs["machine"].report["curves"]["torque_Nm"]))  # the motor's torque with the flywheel
    assert check.passed is False and check.value == pytest.approx(abs(mean), rel=1e-12) and check.limit == 0.1
