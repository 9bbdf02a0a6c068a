"""The compliant follower train (camgen/compliant.py, camgen/kinds/compliant.py).

Every expected number comes from elsewhere:

* scipy's ``solve_ivp`` (DOP853, rtol 1e-12) integrating the follower's equation of motion
  written out here, ``M x'' + C x' + c (x' - y') + k (x - y) + K x + P0 = 0``, with the law
  ``y(w t)`` in closed form (cycloidal, written out), started from the periodic state camgen
  finds (it must come back to it after a turn) and from rest over several turns (it converges
  to it);
* the residual vibration of an undamped one-degree system after a cycloidal rise of duration
  ``T`` (natural period ``T_n``, ``rho = T / T_n``), from Duhamel's integral in closed form:
  ``A / h = |sin(pi rho)| / (pi rho |1 - rho^2|)`` (Koster, *Vibrations of cam mechanisms*,
  1974; Norton, *Design of Machinery*, ch. 8), carried to the periodic state by superposition;
* the rigid model's figures (camgen/dynamics.py, tested against Newton's law in
  test_dynamics_scenes.py): a very stiff train gives them.
"""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from camgen import dynamics as dy
from camgen.compliant import TrainCompliance, compliant_response, response_from
from camgen.cli import main
from helpers import scene_toml

TWO_PI = 2.0 * math.pi
RISE, DWELL_START, RETURN = math.radians(90.0), math.radians(200.0), math.radians(100.0)
LIFT = 20.0  # mm


def law(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cycloidal rise of LIFT over 90 deg, dwell to 200 deg, cycloidal return over 100 deg, dwell
    (s mm, s' mm/rad, s'' mm/rad^2): s = h (u - sin(2 pi u) / (2 pi))."""
    theta = np.mod(np.asarray(theta, dtype=float), TWO_PI)
    s, v, a = (np.zeros_like(theta) for _ in range(3))
    for start, span, sign, base in ((0.0, RISE, 1.0, 0.0), (DWELL_START, RETURN, -1.0, LIFT)):
        on = (theta >= start) & (theta < start + span)
        u = (theta[on] - start) / span
        s[on] = base + sign * LIFT * (u - np.sin(TWO_PI * u) / TWO_PI)
        v[on] = sign * LIFT / span * (1.0 - np.cos(TWO_PI * u))
        a[on] = sign * TWO_PI * LIFT / span**2 * np.sin(TWO_PI * u)
    s[(theta >= RISE) & (theta < DWELL_START)] = LIFT
    return s, v, a


def kinematics(samples: int = 3600, doubled_breaks: bool = False) -> dy.Kinematics:
    """The law's kinematics of a translating flat face on a uniform grid; ``doubled_breaks``: each
    break angle sampled twice, its one-sided values (as camgen's check grid does)."""
    theta = TWO_PI * np.arange(samples) / samples
    s, v, a = law(theta)
    if doubled_breaks:
        at = np.searchsorted(theta, np.array([RISE, DWELL_START, DWELL_START + RETURN]) - 1e-9)  # the grid's break samples
        before = np.nextafter(theta[at], 0.0)  # a sample a rounding before each: the segment ending there
        left = [law(np.array([b - 1e-13]))[i][0] for b in theta[at] for i in range(3)]  # its values (continuous to 1e-13)
        theta = np.insert(theta, at, before)
        s, v, a = (np.insert(arr, at, np.array(left[i::3])) for i, arr in enumerate((s, v, a)))
    zero = np.zeros(theta.size)
    return dy.Kinematics(theta, s, v, a, zero, np.full(theta.size, np.inf), math.inf)


def integrate(train: dy.FollowerTrain, stiffness: float, zeta: float, rpm: float, state: tuple[float, float], turns: int,
              theta_out: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """DOP853 of the follower's equation from ``state`` = (x mm, x' mm/s) at t = 0 over ``turns``
    turns, segment by segment of the law (its jerk jumps at the breaks); returns x and x' at the
    cam angles ``theta_out`` of the last turn and the state at its end."""
    from scipy.integrate import solve_ivp

    omega = rpm * TWO_PI / 60.0
    m = train.mass * 1e-3  # kg -> N per mm/s^2
    big_c = train.damping * 1e-3  # N*s/m -> N per mm/s
    k_s, preload = train.spring_rate, train.spring_preload
    c = 2.0 * zeta * math.sqrt((stiffness + k_s) * m)

    def rhs(t, z):
        y, v, _ = law(np.array([omega * t]))
        x, xd = z
        return [xd, (-big_c * xd - c * (xd - v[0] * omega) - stiffness * (x - y[0]) - k_s * x - preload) / m]

    period = TWO_PI / omega
    cuts = np.array([0.0, RISE, DWELL_START, DWELL_START + RETURN, TWO_PI]) / omega
    z = np.array(state, dtype=float)
    x_out = np.empty((2, theta_out.size))
    for turn in range(turns):
        for t0, t1 in zip(cuts[:-1], cuts[1:]):
            sol = solve_ivp(rhs, (turn * period + t0, turn * period + t1), z, method="DOP853", rtol=1e-12, atol=1e-13,
                            dense_output=True)
            z = sol.y[:, -1]
            if turn == turns - 1:
                on = (theta_out >= t0 * omega) & (theta_out < t1 * omega)
                x_out[:, on] = sol.sol(turn * period + theta_out[on] / omega)
    return x_out[0], x_out[1], z


TRAIN = dy.FollowerTrain(mass=0.5, spring_rate=2.0, preload=30.0, damping=5.0, gravity=0.0)


@pytest.mark.parametrize("doubled", [False, True], ids=["uniform grid", "break angles sampled twice"])
def test_the_periodic_state_comes_back_to_itself_under_dop853(doubled):
    kin = kinematics(doubled_breaks=doubled)
    rpm, stiffness, zeta = 60.0, 30.0, 0.05  # f_n = sqrt(32 N/mm / 0.5 kg) / 2 pi = 40.3 Hz, 40 x the turn
    r, r_dot, _ = response_from(kin, TRAIN, TrainCompliance(stiffness, zeta), rpm)
    omega = rpm * TWO_PI / 60.0
    start = (r[0] + kin.s[0], r_dot[0] + omega * kin.ds[0])
    x, _, end = integrate(TRAIN, stiffness, zeta, rpm, start, 1, kin.theta)
    scale = float(np.max(np.abs(r)))
    assert np.max(np.abs((x - kin.s) - r)) <= 1e-6 * scale
    assert abs(end[0] - start[0]) <= 1e-6 * scale
    assert abs(end[1] - start[1]) <= 1e-6 * float(np.max(np.abs(r_dot)))


def test_from_rest_the_train_converges_to_the_periodic_state():
    kin = kinematics()
    rpm, stiffness, zeta = 60.0, 30.0, 0.2  # the transient decays as exp(-zeta w_n t): e^-50 per turn
    r, _, _ = response_from(kin, TRAIN, TrainCompliance(stiffness, zeta), rpm)
    x, _, _ = integrate(TRAIN, stiffness, zeta, rpm, (0.0, 0.0), 3, kin.theta)
    assert np.max(np.abs((x - kin.s) - r)) <= 1e-6 * float(np.max(np.abs(r)))


def test_the_contact_force_is_the_train_spring_and_damper_force():
    """F = k (y - x) + c (y' - x') from the DOP853 state, against the result's dynamic force."""
    kin = kinematics()
    rpm, stiffness, zeta = 60.0, 30.0, 0.05
    res = compliant_response(kin, TRAIN, TrainCompliance(stiffness, zeta), rpm)
    omega = rpm * TWO_PI / 60.0
    x, x_dot, _ = integrate(TRAIN, stiffness, zeta, rpm, (res.error[0] + kin.s[0], res.error_rate[0] + omega * kin.ds[0]), 1,
                            kin.theta)
    c = 2.0 * zeta * math.sqrt((stiffness + TRAIN.spring_rate) * TRAIN.mass * 1e-3)  # N per mm/s
    expected = stiffness * (kin.s - x) + c * (omega * kin.ds - x_dot)
    assert np.max(np.abs(res.contact_force - expected)) <= 1e-6 * float(np.max(np.abs(res.contact_force)))


def test_residual_vibration_after_a_cycloidal_rise_is_kosters_closed_form():
    """Undamped train, k_s = 0: r'' + w_n^2 r = -y''.  A cycloidal segment of duration T entered at
    rest leaves the free vibration of amplitude (Duhamel, closed form; Koster 1974)
    A = h |sin(pi rho)| / (pi rho |1 - rho^2|), rho = T / T_n.  The return lasts exactly 2 T_n
    (rho = 2: it leaves none), so in the periodic state the rise's vibration D satisfies
    D = D e^(i w_n T_turn) + A_rise: |D| = A_rise / (2 |sin(w_n T_turn / 2)|), in both dwells."""
    rpm = 60.0  # T_turn = 1 s
    ratio = 720.0 / math.degrees(RETURN)  # T_turn / T_n with T_return = 2 T_n: 7.2
    mass = 0.5
    stiffness = (TWO_PI * ratio) ** 2 * mass * 1e-3  # N/mm, w_n = 2 pi 7.2 rad/s
    train = dy.FollowerTrain(mass=mass, spring_rate=0.0, preload=30.0, gravity=0.0)  # the preload: a static deflection only
    res = compliant_response(kinematics(7200), train, TrainCompliance(stiffness, 0.0), rpm)
    rho = RISE / TWO_PI * ratio
    koster = LIFT * abs(math.sin(math.pi * rho)) / (math.pi * rho * abs(1.0 - rho**2))
    expected = koster / (2.0 * abs(math.sin(math.pi * ratio)))
    assert np.degrees(res.theta[res.dwell_start]).round(9).tolist() == [90.0, 300.0]
    assert res.residual == pytest.approx([expected, expected], rel=1e-6)


def test_a_damped_residual_vibration_is_the_free_vibration_the_integrator_finds_in_the_dwell():
    """From the state at the dwell after the rise, DOP853 integrates the follower through the
    dwell; the offset from the static deflection r_eq = -(K h + P0) / (k + K) times e^(zeta w_n t)
    is a cos(w_d t) + b sin(w_d t) (a damped free vibration): its amplitude hypot(a, b), fitted
    by least squares, is the residual camgen reports."""
    from scipy.integrate import solve_ivp

    kin = kinematics()
    rpm, stiffness, zeta = 60.0, 30.0, 0.1
    res = compliant_response(kin, TRAIN, TrainCompliance(stiffness, zeta), rpm)
    omega = rpm * TWO_PI / 60.0
    m, big_k = TRAIN.mass * 1e-3, TRAIN.spring_rate
    c_total = 2.0 * zeta * math.sqrt((stiffness + big_k) * m) + TRAIN.damping * 1e-3
    w_n = math.sqrt((stiffness + big_k) / m)
    zeta_total = c_total / (2.0 * m * w_n)
    w_d = w_n * math.sqrt(1.0 - zeta_total**2)
    i = int(res.dwell_start[0])
    assert math.isclose(math.degrees(kin.theta[i]), 90.0)
    duration = (DWELL_START - RISE) / omega
    t = np.linspace(0.0, duration, 400)
    sol = solve_ivp(lambda _, z: [z[1], (-c_total * z[1] - (stiffness + big_k) * z[0]) / m], (0.0, duration),
                    [res.error[i] + (big_k * LIFT + TRAIN.spring_preload) / (stiffness + big_k), res.error_rate[i]],
                    method="DOP853", rtol=1e-12, atol=1e-15, t_eval=t)  # the offset from r_eq: y is still in the dwell
    basis = np.stack([np.cos(w_d * t), np.sin(w_d * t)], axis=1)
    (a, b), *_ = np.linalg.lstsq(basis, sol.y[0] * np.exp(zeta_total * w_n * t), rcond=None)
    assert res.damping_ratio == pytest.approx(zeta_total, rel=1e-12)
    assert res.residual[0] == pytest.approx(math.hypot(a, b), rel=1e-6)


def test_an_undamped_train_in_resonance_with_the_turn_has_no_periodic_state():
    from camgen.errors import GeometryError

    train = dy.FollowerTrain(mass=0.5, spring_rate=0.0, preload=0.0, gravity=0.0)
    stiffness = (TWO_PI * 12.0) ** 2 * 0.5e-3  # f_n = 12 Hz, the 12th harmonic at 60 rpm
    with pytest.raises(GeometryError, match="resonance"):
        compliant_response(kinematics(), train, TrainCompliance(stiffness, 0.0), 60.0)


@pytest.mark.parametrize("block", [None, 1000], ids=["one block", "blocks of 1000 terms"])
def test_the_acceleration_spectrum_is_the_laws_fourier_series(block, monkeypatch):
    """The cycloidal law's acceleration a(theta) = w^2 s''; its harmonic amplitudes from a
    128-point-per-degree trapezoid of the closed form, independently of the samples camgen used
    (also when its memory cap splits the sum into blocks)."""
    if block is not None:
        monkeypatch.setattr("camgen.compliant.SPECTRUM_CHUNK", block)
    kin = kinematics(3600)
    rpm = 60.0
    res = compliant_response(kin, TRAIN, TrainCompliance(30.0, 0.05), rpm)
    fine = TWO_PI * np.arange(360 * 128) / (360 * 128)
    omega = rpm * TWO_PI / 60.0
    coef = np.fft.rfft(omega**2 * law(fine)[2]) / fine.size
    expected = 2.0 * np.abs(coef[1:res.spectrum.size])
    assert np.max(np.abs(res.spectrum[1:] - expected)) <= 1e-4 * float(np.max(expected))


# --------------------------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------------------------
def plate(**changes) -> dict:
    """A translating roller cam (cycloidal 20 mm over 120 deg, dwell 60, back over 120, dwell 60)."""
    segments = [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 300.0, "thickness_mm": 10.0,
           "segments": segments, "mass_kg": 0.6, "spring_rate_n_per_mm": 2.0, "spring_preload_n": 35.0, "jump_margin_n": 5.0}
    cam.update(changes)
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {k: v for k, v in cam.items() if v is not None}}}


def run(scene: dict):
    import json

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    parsed = parse_scene(copy.deepcopy(scene), "s")
    result = execute(parsed, plan_run(parsed))
    return result.cams[0], json.loads(result.files["report.json"])


def test_a_very_stiff_train_gives_the_rigid_contact_force():
    """k = 1e10 N/mm on a 4-5-6-7 law: the deflection's share of the force (K / k), the damper's
    (2 zeta F' / w_n) and the ringing a jump in a derivative of the law leaves (a jerk jump dJ
    rings with m dJ / w_n: the cycloid's would be 1e-5 of the force here; the 4-5-6-7 law's
    jerk is continuous) all vanish against the rigid force, to 1e-6."""
    segments = [{"law": "poly4567", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                {"law": "poly4567", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]
    cam, report = run(plate(train_stiffness_n_per_mm=1e10, damping_ratio=0.05, segments=segments))
    outcome = cam.dynamics
    rigid = outcome.result.contact_force
    dynamic = outcome.compliant.contact_force
    assert np.max(np.abs(dynamic - rigid)) <= 1e-6 * float(np.max(np.abs(rigid)))
    figures = report["cams"]["c"]["figures"]["dynamics"]
    assert figures["compliant"]["min_dynamic_contact_force_N"] == pytest.approx(figures["min_contact_force_N"], rel=1e-6)
    assert figures["compliant"]["max_dynamic_contact_force_N"] == pytest.approx(figures["max_contact_force_N"], rel=1e-6)
    assert figures["compliant"]["dynamic_amplification"] == pytest.approx(1.0, rel=1e-6)


def test_without_a_stiffness_the_dynamics_are_rigid_as_before():
    (cam_a, a), (_, b) = run(plate()), run(plate(train_stiffness_n_per_mm=200.0))
    assert "compliant" not in a["cams"]["c"]["figures"]["dynamics"] and cam_a.dynamics.compliant is None
    names = {c["name"] for c in b["cams"]["c"]["checks"]} - {c["name"] for c in a["cams"]["c"]["checks"]}
    assert names == {"dynamic_jump", "residual_vibration"}
    rigid = {k: v for k, v in b["cams"]["c"]["figures"]["dynamics"].items() if k != "compliant"}
    assert rigid == a["cams"]["c"]["figures"]["dynamics"]


def test_a_soft_train_jumps_where_the_rigid_one_does_not_and_the_check_fails(tmp_path, capsys):
    """A soft train (f_n 3.4 x the turn at 400 rpm) rings: its least contact force falls below 0
    where the rigid force stays above the margin; ``camgen check`` exits 1 on dynamic_jump."""
    scene = plate(rpm=400.0, train_stiffness_n_per_mm=10.0, damping_ratio=0.02)
    cam, report = run(scene)
    figures = report["cams"]["c"]["figures"]["dynamics"]
    assert figures["min_contact_force_N"] > 5.0
    assert figures["compliant"]["min_dynamic_contact_force_N"] < 0.0 and figures["compliant"]["dynamic_jump_ranges_deg"]
    checks = {c["name"]: c for c in report["cams"]["c"]["checks"]}
    assert checks["jump"]["status"] == "pass" and checks["dynamic_jump"]["status"] == "fail"
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    assert main(["check", str(path)]) == 1


def test_the_residual_vibration_limit_fails_the_check_above_it():
    _, report = run(plate(train_stiffness_n_per_mm=200.0))
    peak = report["cams"]["c"]["figures"]["dynamics"]["compliant"]["residual_vibration_peak_mm"]
    for limit, status in ((peak * 1.001, "pass"), (peak * 0.999, "fail")):
        _, report = run(plate(train_stiffness_n_per_mm=200.0, residual_vibration_limit_mm=limit))
        check = next(c for c in report["cams"]["c"]["checks"] if c["name"] == "residual_vibration")
        assert check["status"] == status


REFUSED = {
    "zero stiffness": (plate(train_stiffness_n_per_mm=0.0), "cams.c.train_stiffness_n_per_mm", "0 < x"),
    "negative stiffness": (plate(train_stiffness_n_per_mm=-5.0), "cams.c.train_stiffness_n_per_mm", "0 < x"),
    "damping ratio 1": (plate(train_stiffness_n_per_mm=100.0, damping_ratio=1.0), "cams.c.damping_ratio", "x < 1"),
    "damping ratio 1.5": (plate(train_stiffness_n_per_mm=100.0, damping_ratio=1.5), "cams.c.damping_ratio", "x < 1"),
    "damping ratio without a stiffness": (plate(damping_ratio=0.1), "cams.c.damping_ratio", "train_stiffness_n_per_mm"),
    "limit without a stiffness": (plate(residual_vibration_limit_mm=0.1), "cams.c.residual_vibration_limit_mm",
                                  "train_stiffness_n_per_mm"),
    "torsional stiffness on a slider": (plate(train_stiffness_n_mm_per_rad=1e6), "cams.c.train_stiffness_n_mm_per_rad",
                                        "oscillating"),
    "stiffness without a mass": (plate(mass_kg=0.0, train_stiffness_n_per_mm=100.0), "cams.c.mass_kg", "mass_kg > 0"),
}


@pytest.mark.parametrize("case", REFUSED)
def test_bad_compliant_input_is_refused_naming_the_key(case, tmp_path, capsys):
    scene, key, why = REFUSED[case]
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    code = main(["check", str(path)])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert f"'{key}'" in err and why in err, err


def test_a_groove_refuses_a_train_stiffness(tmp_path, capsys):
    scene = plate(form="groove", train_stiffness_n_per_mm=100.0, spring_rate_n_per_mm=None, spring_preload_n=None,
                  jump_margin_n=None)
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    code = main(["check", str(path)])
    err = capsys.readouterr().err
    assert code == 2 and "'cams.c.train_stiffness_n_per_mm'" in err and "form-closed" in err, err
