"""The two-mass compliant follower train (camgen/compliant_two.py, issue 25 item 2).

Every expected number comes from elsewhere:

* scipy's ``solve_ivp`` (DOP853, rtol 1e-12) integrating the two masses' equations of motion
  written out here (Newton's law on each mass, the springs and dampers between them), with the
  cycloidal law in closed form (test_compliant.law), started from the periodic state camgen
  finds: it must come back to it after a turn;
* the one-degree model (camgen/compliant.py, itself tested against DOP853 and Koster's closed
  form in test_compliant.py) with the masses as one, in the limit of a stiff follower;
* the two natural frequencies from the closed form of the 2 x 2 eigenproblem
  ``det(K - w^2 M) = 0``: ``m1 m2 w^4 - (m1 K22 + m2 K11) w^2 + det K = 0``, typed here;
* the tool's residual vibration of an undamped train: DOP853 through the dwell, the free
  vibration fitted by least squares with the closed-form frequencies.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen import dynamics as dy
from camgen.cli import main
from camgen.compliant import TrainCompliance, compliant_response
from camgen.compliant_two import FollowerCompliance, two_degree_response, two_degree_states
from helpers import scene_toml
from test_compliant import DWELL_START, LIFT, RISE, RETURN, kinematics, law

TWO_PI = 2.0 * math.pi
#: 0.5 kg in all: 0.3 kg on the cam side (roller, rod end), 0.2 kg tool; spring 2 N/mm, preload 30 N
TRAIN = dy.FollowerTrain(mass=0.5, spring_rate=2.0, preload=30.0, damping=5.0, load=12.0, gravity=dy.STANDARD_GRAVITY,
                         gravity_angle=-math.pi / 2)  # the follower rises along +y (Kinematics.direction), its weight against it
TOOL_MASS = 0.2


def integrate(train: dy.FollowerTrain, k1: float, k2: float, m2_kg: float, zeta: float, spring_at: str, rpm: float,
              state: np.ndarray, theta_out: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """DOP853 of the two masses over one turn from ``state`` = (x1, x2, x1', x2') (mm, mm/s),
    segment by segment of the law; the positions/velocities (4, len(theta_out)) and the end state.

    m1 x1'' = k1 (y - x1) + c1 (y' - x1') + k2 (x2 - x1) + c2 (x2' - x1') - [spring on 1] - W m1/M
    m2 x2'' = k2 (x1 - x2) + c2 (x1' - x2') - [spring on 2] - W m2/M - L
    spring = K (x - 0) + P0 + C x' (q_min = 0), W = M g (the follower moves up, +y)."""
    from scipy.integrate import solve_ivp

    omega = rpm * TWO_PI / 60.0
    big_m = train.mass * 1e-3  # N per mm/s^2
    m2 = m2_kg * 1e-3
    m1 = big_m - m2
    big_c = train.damping * 1e-3
    k_s, preload, load = train.spring_rate, train.spring_preload, 12.0
    weight = train.mass * train.gravity  # N: kg * m/s^2
    c1 = 2.0 * zeta * math.sqrt((k1 + k_s) * big_m)
    c2 = 2.0 * zeta * math.sqrt(k2 * m1 * m2 / big_m)

    def rhs(t, z):
        y, v, _ = law(np.array([omega * t]))
        y, v = y[0], v[0] * omega
        x1, x2, v1, v2 = z
        f1 = k1 * (y - x1) + c1 * (v - v1) + k2 * (x2 - x1) + c2 * (v2 - v1) - weight * m1 / big_m
        f2 = k2 * (x1 - x2) + c2 * (v1 - v2) - weight * m2 / big_m - load
        if spring_at == "tool":
            f2 -= k_s * x2 + preload + big_c * v2
        else:
            f1 -= k_s * x1 + preload + big_c * v1
        return [v1, v2, f1 / m1, f2 / m2]

    cuts = np.array([0.0, RISE, DWELL_START, DWELL_START + RETURN, TWO_PI]) / omega
    z = np.array(state, dtype=float)
    out = np.empty((4, theta_out.size))
    for t0, t1 in zip(cuts[:-1], cuts[1:]):
        sol = solve_ivp(rhs, (t0, t1), z, method="DOP853", rtol=1e-12, atol=1e-13, dense_output=True)
        z = sol.y[:, -1]
        on = (theta_out >= t0 * omega) & (theta_out < t1 * omega)
        out[:, on] = sol.sol(theta_out[on] / omega)
    return out, z


def compliance(k1: float, k2: float, zeta: float, spring_at: str = "tool", m2: float = TOOL_MASS) -> TrainCompliance:
    return TrainCompliance(k1, zeta, None, FollowerCompliance(k2, m2, spring_at))


@pytest.mark.parametrize("spring_at", ["tool", "cam_side"])
def test_the_periodic_state_comes_back_to_itself_under_dop853(spring_at):
    """From camgen's periodic state at 0 deg, DOP853 of Newton's law on both masses reproduces
    both masses' errors over the turn and comes back to the start, to 1e-6."""
    kin = kinematics()
    rpm, k1, k2, zeta = 60.0, 30.0, 80.0, 0.05  # modes at about 37 and 125 Hz
    z, _ = two_degree_states(kin, TRAIN, compliance(k1, k2, zeta, spring_at), rpm)
    omega = rpm * TWO_PI / 60.0
    start = z[0] + np.array([kin.s[0], kin.s[0], omega * kin.ds[0], omega * kin.ds[0]])
    x, end = integrate(TRAIN, k1, k2, TOOL_MASS, zeta, spring_at, rpm, start, kin.theta)
    for i in (0, 1):
        scale = float(np.max(np.abs(z[:, i])))
        assert np.max(np.abs((x[i] - kin.s) - z[:, i])) <= 1e-6 * scale
        assert abs(end[i] - start[i]) <= 1e-6 * scale
        assert abs(end[2 + i] - start[2 + i]) <= 1e-6 * float(np.max(np.abs(z[:, 2 + i])))
    res = two_degree_response(kin, TRAIN, compliance(k1, k2, zeta, spring_at), rpm)
    c1 = 2.0 * zeta * math.sqrt((k1 + TRAIN.spring_rate) * TRAIN.mass * 1e-3)
    expected = k1 * (kin.s - x[0]) + c1 * (omega * kin.ds - x[2])  # the contact spring and damper
    assert np.max(np.abs(res.contact_force - expected)) <= 1e-6 * float(np.max(np.abs(expected)))
    assert np.max(np.abs(res.error - (x[1] - kin.s))) <= 1e-6 * float(np.max(np.abs(res.error)))


def test_a_stiff_follower_is_the_one_degree_train_of_both_masses():
    """k2 -> infinity: the masses move as one, M = m1 + m2 on k1 with the one-degree damping:
    the contact force and the tool's error are the one-degree model's (tested against DOP853
    and Koster's closed form in test_compliant.py) to 1e-6."""
    kin = kinematics()
    rpm, k1, zeta = 60.0, 30.0, 0.05
    one = compliant_response(kin, TRAIN, TrainCompliance(k1, zeta), rpm)
    two = two_degree_response(kin, TRAIN, compliance(k1, 1e9, zeta), rpm)
    assert np.max(np.abs(two.contact_force - one.contact_force)) <= 1e-6 * float(np.max(np.abs(one.contact_force)))
    assert np.max(np.abs(two.error - one.error)) <= 1e-6 * float(np.max(np.abs(one.error)))
    assert two.natural_frequency == pytest.approx(one.natural_frequency, rel=1e-6)
    assert two.residual == pytest.approx(one.residual, rel=1e-6)


@pytest.mark.parametrize("spring_at", ["tool", "cam_side"])
def test_the_two_natural_frequencies_are_the_closed_form_of_the_2x2_eigenproblem(spring_at):
    k1, k2, big_k = 30.0, 80.0, TRAIN.spring_rate
    m2 = TOOL_MASS * 1e-3
    m1 = TRAIN.mass * 1e-3 - m2
    k11 = k1 + k2 + (big_k if spring_at == "cam_side" else 0.0)
    k22 = k2 + (big_k if spring_at == "tool" else 0.0)
    b = m1 * k22 + m2 * k11
    det = k11 * k22 - k2 * k2
    root = math.sqrt(b * b - 4.0 * m1 * m2 * det)
    expected = [math.sqrt((b - root) / (2.0 * m1 * m2)) / TWO_PI, math.sqrt((b + root) / (2.0 * m1 * m2)) / TWO_PI]
    res = two_degree_response(kinematics(), TRAIN, compliance(k1, k2, 0.05, spring_at), 60.0)
    assert list(res.natural_frequencies) == pytest.approx(expected, rel=1e-9)
    figures = res.figures()
    assert figures["natural_frequencies_Hz"] == pytest.approx(expected, rel=1e-9)
    assert figures["natural_frequency_Hz"] == pytest.approx(expected[0], rel=1e-9)


def test_the_tools_residual_vibration_is_the_free_vibration_dop853_finds_in_the_dwell():
    """Undamped (zeta 0, no follower damping): from camgen's state at the dwell after the rise,
    DOP853 integrates the masses through the dwell; the tool's offset from its static deflection
    is a1 cos w1 t + b1 sin w1 t + a2 cos w2 t + b2 sin w2 t with the closed-form frequencies:
    the residual camgen reports is hypot(a1, b1) + hypot(a2, b2)."""
    train = dy.FollowerTrain(mass=0.5, spring_rate=2.0, preload=30.0, gravity=0.0)
    kin = kinematics()
    rpm, k1, k2 = 60.0, 30.0, 80.0
    res = two_degree_response(kin, train, compliance(k1, k2, 0.0), rpm)
    z, _ = two_degree_states(kin, train, compliance(k1, k2, 0.0), rpm)
    i = int(res.dwell_start[0])
    assert math.isclose(math.degrees(kin.theta[i]), 90.0)
    omega = rpm * TWO_PI / 60.0
    start = z[i] + np.array([LIFT, LIFT, 0.0, 0.0])
    duration = (DWELL_START - RISE) / omega
    t = np.linspace(0.0, duration, 2000)
    from scipy.integrate import solve_ivp

    m2 = TOOL_MASS * 1e-3
    m1 = train.mass * 1e-3 - m2

    def rhs(_, s):
        x1, x2, v1, v2 = s
        return [v1, v2, (k1 * (LIFT - x1) + k2 * (x2 - x1)) / m1, (k2 * (x1 - x2) - 2.0 * x2 - 30.0) / m2]

    sol = solve_ivp(rhs, (0.0, duration), start, method="DOP853", rtol=1e-12, atol=1e-13, t_eval=t)
    # static: k1 (h - x1) = k2 (x1 - x2) = K x2 + P0: k1, k2 in series (ke), x2 = (ke h - P0) / (ke + K)
    k_series = 1.0 / (1.0 / k1 + 1.0 / k2)
    x2_static = (k_series * LIFT - 30.0) / (k_series + 2.0)
    k11, k22 = k1 + k2, k2 + 2.0
    b = m1 * k22 + m2 * k11
    root = math.sqrt(b * b - 4.0 * m1 * m2 * (k11 * k22 - k2 * k2))
    w = [math.sqrt((b - root) / (2.0 * m1 * m2)), math.sqrt((b + root) / (2.0 * m1 * m2))]
    basis = np.stack([np.cos(w[0] * t), np.sin(w[0] * t), np.cos(w[1] * t), np.sin(w[1] * t)], axis=1)
    coef, *_ = np.linalg.lstsq(basis, sol.y[1] - x2_static, rcond=None)
    expected = math.hypot(coef[0], coef[1]) + math.hypot(coef[2], coef[3])
    assert res.residual[0] == pytest.approx(expected, rel=1e-6)


# --------------------------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------------------------
from test_compliant import plate, run  # the one-mass train's scene and runner


TWO = {"train_stiffness_n_per_mm": 2000.0, "follower_stiffness_n_per_mm": 500.0, "tool_mass_kg": 0.25}


def test_a_two_mass_scene_reports_both_modes_and_the_tools_response():
    cam, report = run(plate(**TWO))
    figures = report["cams"]["c"]["figures"]["dynamics"]["compliant"]
    res = cam.dynamics.compliant
    assert figures["model"] == "two masses" and figures["tool_mass_kg"] == 0.25 and figures["return_spring_on"] == "tool"
    assert figures["natural_frequencies_Hz"] == list(res.natural_frequencies)
    assert figures["max_dynamic_error_mm"] == pytest.approx(float(np.max(np.abs(res.error))))
    names = {c["name"] for c in report["cams"]["c"]["checks"]}
    assert {"dynamic_jump", "residual_vibration"} <= names
    _, moved = run(plate(**TWO, return_spring_on="cam_side"))
    assert moved["cams"]["c"]["figures"]["dynamics"]["compliant"]["return_spring_on"] == "cam_side"
    assert moved["cams"]["c"]["figures"]["dynamics"]["compliant"]["natural_frequencies_Hz"] != figures["natural_frequencies_Hz"]


REFUSED = {
    "zero follower stiffness": (plate(**{**TWO, "follower_stiffness_n_per_mm": 0.0}), "cams.c.follower_stiffness_n_per_mm",
                                "0 < x"),
    "zero tool mass": (plate(**{**TWO, "tool_mass_kg": 0.0}), "cams.c.tool_mass_kg", "1e-06 <= x"),
    "tool mass the whole mass": (plate(**{**TWO, "tool_mass_kg": 0.6}), "cams.c.tool_mass_kg", "tool_mass_kg <= mass_kg - 1e-06"),
    "tool mass without a follower stiffness": (plate(**{**TWO, "follower_stiffness_n_per_mm": None}), "cams.c.tool_mass_kg",
                                               "follower_stiffness_n_per_mm"),
    "follower stiffness without a tool mass": (plate(**{**TWO, "tool_mass_kg": None}), "cams.c.follower_stiffness_n_per_mm",
                                               "tool_mass_kg"),
    "two masses without a train stiffness": (plate(**{**TWO, "train_stiffness_n_per_mm": None}),
                                             "cams.c.follower_stiffness_n_per_mm", "train_stiffness_n_per_mm"),
    "spring place without two masses": (plate(train_stiffness_n_per_mm=100.0, return_spring_on="tool"),
                                        "cams.c.return_spring_on", "follower_stiffness_n_per_mm"),
    "spring place unknown": (plate(**TWO, return_spring_on="roller"), "cams.c.return_spring_on", '"cam_side"'),
    "two masses on an arm": (plate(follower_motion="oscillating", pivot_x_mm=120.0, pivot_y_mm=0.0, arm_length_mm=100.0,
                                   mass_kg=None, inertia_kg_m2=0.01, spring_rate_n_per_mm=None, spring_preload_n=None,
                                   train_stiffness_n_mm_per_rad=1e7, follower_stiffness_n_per_mm=500.0),
                             "cams.c.follower_stiffness_n_per_mm", "translating"),
}


@pytest.mark.parametrize("case", REFUSED)
def test_bad_two_mass_input_is_refused_naming_the_key(case, tmp_path, capsys):
    scene, key, why = REFUSED[case]
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    code = main(["check", str(path)])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert f"'{key}'" in err and why in err, err


def test_the_report_marks_both_natural_frequencies_and_plots_both_masses():
    """report.html's compliant panels: both modes named in the spectrum's title (from the closed
    form of the 2 x 2 eigenproblem), the tool's and the cam side's errors, the two-mass model."""
    import json

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = plate(**TWO)
    scene["output"]["formats"] = ["html"]
    parsed = parse_scene(scene, "s")
    done = execute(parsed, plan_run(parsed))
    html = done.files["report.html"]
    m2, big_m = 0.25e-3, 0.6e-3
    m1, k1, k2, big_k = big_m - m2, TWO["train_stiffness_n_per_mm"], TWO["follower_stiffness_n_per_mm"], 2.0
    b = m1 * (k2 + big_k) + m2 * (k1 + k2)
    root = math.sqrt(b * b - 4.0 * m1 * m2 * ((k1 + k2) * (k2 + big_k) - k2 * k2))
    modes = [math.sqrt((b + sign * root) / (2.0 * m1 * m2)) / TWO_PI for sign in (-1.0, 1.0)]
    assert f"natural frequencies {modes[0]:.4g} Hz = harmonic {modes[0] / 5.0:.4g}" in html
    assert f"and {modes[1]:.4g} Hz = harmonic {modes[1] / 5.0:.4g}" in html
    assert "two-mass compliant follower train" in html and "tool mass" in html and "cam-side mass" in html
    figures = json.loads(done.files["report.json"])["cams"]["c"]["figures"]["dynamics"]["compliant"]
    assert figures["natural_frequencies_Hz"] == pytest.approx(modes, rel=1e-9)


def test_the_mode_damping_ratios_are_the_roots_of_the_characteristic_quartic():
    """det(M s^2 + C s + K) = 0 expanded by hand into a quartic in s (the damper across each
    spring, the follower's own damping with the spring on the tool); each complex pair of roots
    s = -zeta w +- i w sqrt(1 - zeta^2) gives zeta = -Re s / |s|, ascending in |s|."""
    k1, k2, zeta, big_k = 30.0, 80.0, 0.08, TRAIN.spring_rate
    big_m = TRAIN.mass * 1e-3
    m2 = TOOL_MASS * 1e-3
    m1 = big_m - m2
    c1 = 2.0 * zeta * math.sqrt((k1 + big_k) * big_m)
    c2 = 2.0 * zeta * math.sqrt(k2 * m1 * m2 / big_m)
    c_f = TRAIN.damping * 1e-3
    p11 = [m1, c1 + c2, k1 + k2]
    p22 = [m2, c2 + c_f, k2 + big_k]
    p12 = [-c2, -k2]
    quartic = np.polysub(np.polymul(p11, p22), np.polymul(p12, p12))
    roots = np.roots(quartic)
    upper = sorted((r for r in roots if r.imag > 0), key=abs)
    expected = [-r.real / abs(r) for r in upper]
    res = two_degree_response(kinematics(), TRAIN, compliance(k1, k2, zeta), 60.0)
    assert list(res.damping_ratios) == pytest.approx(expected, rel=1e-9)
    assert res.damping_ratio == pytest.approx(expected[0], rel=1e-9)
