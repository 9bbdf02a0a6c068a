"""Cam-follower dynamics against closed forms, a textbook example, energy and a time-domain ODE.

Every expected number is computed here in SI units (m, kg, N, s) from the motion laws written
out in time, independently of camgen's per-radian millimetre arithmetic.
"""
from __future__ import annotations

import math
from itertools import pairwise

import numpy as np
import pytest

from camgen import dynamics as dy
from camgen.errors import GeometryError, ParameterError
from camgen.kinds.dynamics import dynamics_checks
from camgen.synthesis.laws import MotionProgram
from camgen.synthesis.laws import Segment as MotionSegment

D = math.radians
N_SAMPLES = 3600
THETA = 2 * math.pi * np.arange(N_SAMPLES) / N_SAMPLES
LBF = 4.4482216152605  # N
INCH = 25.4  # mm
PSI = 6.894757293168361e-3  # MPa


def _checks(kin, train, rpm, material=None, *, jump_margin=0.0, torque_limit=None):
    """The checks of the dynamics at ``rpm`` (camgen.kinds.dynamics turns the physics' results into checks)."""
    res = dy.analyse(kin, train, rpm, material, jump_margin=jump_margin)
    return dynamics_checks(res, kin, material, torque_limit)


def _program(law: str, rise: float, h_mm: float, dwell: float, ret: float) -> MotionProgram:
    return MotionProgram([MotionSegment(law, rise, h_mm), MotionSegment("dwell", dwell, 0.0),
                          MotionSegment(law, ret, -h_mm), MotionSegment("dwell", 2 * math.pi - rise - dwell - ret, 0.0)])


def _kin(program: MotionProgram, theta=THETA, phi=None, rho=40.0, radius=10.0, **extra) -> dy.Kinematics:
    s, ds, d2s, _ = program(theta)
    phi = np.zeros_like(theta) if phi is None else phi
    return dy.Kinematics(theta, s, ds, d2s, phi, np.full_like(theta, rho), radius, **extra)


def _time_law(law: str, t: np.ndarray, T: float, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Displacement (m), velocity (m/s), acceleration (m/s^2) of a rise of ``h`` m lasting ``T`` s."""
    if law == "cycloidal":  # s = h (t/T - sin(2 pi t/T) / 2 pi)
        u = 2 * math.pi * t / T
        return h * (t / T - np.sin(u) / (2 * math.pi)), h / T * (1 - np.cos(u)), 2 * math.pi * h / T**2 * np.sin(u)
    u = math.pi * t / T  # harmonic: s = h/2 (1 - cos(pi t/T))
    return h / 2 * (1 - np.cos(u)), math.pi * h / (2 * T) * np.sin(u), math.pi**2 * h / (2 * T**2) * np.cos(u)


def _time_motion(law, theta, omega, h, rise, dwell, ret):
    """The rise-dwell-return-dwell program in SI, as functions of time t = theta / omega."""
    s, v, a = (np.zeros_like(theta) for _ in range(3))
    up = theta < rise
    s[up], v[up], a[up] = _time_law(law, theta[up] / omega, rise / omega, h)
    top = (theta >= rise) & (theta < rise + dwell)
    s[top] = h
    down = (theta >= rise + dwell) & (theta < rise + dwell + ret)
    sd, vd, ad = _time_law(law, (theta[down] - rise - dwell) / omega, ret / omega, h)
    s[down], v[down], a[down] = h - sd, -vd, -ad
    return s, v, a


# --------------------------------------------------------------------------------------------
# Closed forms
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("law", ["cycloidal", "harmonic"])
def test_contact_force_is_m_a_plus_k_s_plus_preload_plus_c_v_point_by_point(law):
    rise, dwell, ret, h_mm = D(100), D(80), D(120), 12.0
    m, k_n_per_mm, f0, c = 0.8, 3.0, 40.0, 25.0  # kg, N/mm, N, N*s/m
    rpm = 300.0
    phi = 0.4 * np.sin(THETA)  # any pressure angle: the normal force is the axial one over cos(phi)
    s_mm, ds, d2s, _ = _program(law, rise, h_mm, dwell, ret)(THETA)
    # the position measured from elsewhere (e.g. from the cam axis): the preload acts at the lowest one
    kin = dy.Kinematics(THETA, s_mm + 37.5, ds, d2s, phi, np.full_like(THETA, 40.0), 10.0)
    train = dy.FollowerTrain(mass=m, spring_rate=k_n_per_mm, preload=f0, damping=c, gravity=0.0)
    res = dy.analyse(kin, train, rpm)
    omega = rpm * 2 * math.pi / 60
    s, v, a = _time_motion(law, THETA, omega, h_mm / 1000, rise, dwell, ret)
    axial = m * a + (k_n_per_mm * 1000) * s + f0 + c * v  # N, SI throughout
    scale = np.max(np.abs(axial))
    assert np.max(np.abs(res.follower_force - axial)) <= 1e-12 * scale
    assert np.max(np.abs(res.contact_force - axial / np.cos(phi))) <= 1e-12 * scale
    assert np.max(np.abs(res.side_force - axial * np.tan(phi))) <= 1e-12 * scale
    assert np.array_equal(res.pressure_angle, phi)
    # camshaft power = contact force along the motion times the follower velocity
    assert np.max(np.abs(res.power - axial * v)) <= 1e-12 * np.max(np.abs(axial * v))


def test_weight_adds_m_g_along_the_motion_and_nothing_across_it():
    program = _program("cycloidal", D(90), 10.0, D(90), D(90))
    kin = _kin(program)  # the follower moves along +y (direction pi/2)
    base = dy.analyse(kin, dy.FollowerTrain(mass=2.0, gravity=0.0), 200.0).follower_force
    for angle, sign in ((-math.pi / 2, 1.0), (math.pi / 2, -1.0), (0.0, 0.0)):
        res = dy.analyse(kin, dy.FollowerTrain(mass=2.0, gravity=9.81, gravity_angle=angle), 200.0)
        assert np.allclose(res.follower_force - base, sign * 2.0 * 9.81, rtol=0, atol=1e-9)


def test_load_table_is_interpolated_periodically():
    kin = _kin(_program("harmonic", D(90), 10.0, D(90), D(90)))
    train = dy.FollowerTrain(load=([0.0, math.pi], [10.0, 30.0]), gravity=0.0)  # massless, no spring: Q = load
    force = dy.analyse(kin, train, 100.0).follower_force
    at = {0.0: 10.0, 90.0: 20.0, 180.0: 30.0, 270.0: 20.0, 315.0: 15.0}  # linear, wrapping from 180 back to 360
    for deg, expected in at.items():
        assert force[round(deg * 10)] == pytest.approx(expected, abs=1e-12)


def test_jump_speed_of_a_harmonic_program_in_closed_form():
    """Harmonic rise h over beta: a = h pi^2 w^2 / (2 beta^2) cos(pi theta/beta); at the top of the
    stroke (s = h, cos = -1) the force m a + k s + F0 is smallest and reaches 0 at
    w^2 = 2 beta^2 (k h + F0) / (pi^2 m h)."""
    rise, ret, h_mm = D(120), D(90), 8.0  # the shorter return decelerates harder: it sets the jump speed
    m, k, f0 = 0.6, 1.5, 15.0  # kg, N/mm, N
    phi = D(25)  # a constant pressure angle: the normal force is the axial one over cos(phi)
    kin = _kin(_program("harmonic", rise, h_mm, D(60), ret), phi=np.full(N_SAMPLES, phi))
    train = dy.FollowerTrain(mass=m, spring_rate=k, preload=f0, gravity=0.0)
    h = h_mm / 1000
    omega = ret * math.sqrt(2 * (k * 1000 * h + f0) / (math.pi**2 * m * h))
    assert dy.jump_speed(kin, train) == pytest.approx(omega * 60 / (2 * math.pi), rel=1e-12)
    margin = 4.0  # N along the normal: reached at the same point when the axial force is margin cos(phi)
    omega_m = ret * math.sqrt(2 * (k * 1000 * h + f0 - margin * math.cos(phi)) / (math.pi**2 * m * h))
    assert dy.jump_speed(kin, train, margin) == pytest.approx(omega_m * 60 / (2 * math.pi), rel=1e-12)
    rpm_jump = omega * 60 / (2 * math.pi)
    below, above = dy.analyse(kin, train, 0.99 * rpm_jump), dy.analyse(kin, train, 1.01 * rpm_jump)
    below_checks, above_checks = _checks(kin, train, 0.99 * rpm_jump), _checks(kin, train, 1.01 * rpm_jump)
    assert below.jump_ranges_deg == [] and below_checks[0].name == "jump" and below_checks[0].status == "pass"
    assert above_checks[0].status == "fail"
    # the follower lifts where the return starts (180 deg: the acceleration jumps there) and lands soon after
    assert len(above.jump_ranges_deg) == 2
    start, end = above.jump_ranges_deg
    assert start == pytest.approx(180.0, abs=1e-9) and 180.0 < end < 200.0
    # a pulling load larger than the preload: the follower is off the cam standing still
    assert dy.jump_speed(kin, dy.FollowerTrain(preload=10.0, load=-20.0, gravity=0.0)) == 0.0
    # no inertia, no damping: the force does not depend on the speed
    assert dy.jump_speed(kin, dy.FollowerTrain(spring_rate=1.0, preload=5.0, gravity=0.0)) == math.inf


def test_minimum_preload_and_rate_in_closed_form():
    """Above the jump speed of the harmonic program the force at the top of the stroke is
    k h + F0 - m w^2 A (A = h pi^2 / (2 beta^2)); holding it at the margin M takes
    F0 >= M - k h + m w^2 A, or (for F0 > M) k >= (M - F0 + m w^2 A) / h."""
    rise, h_mm = D(90), 10.0
    m, k, f0, margin, rpm = 0.5, 2.0, 20.0, 5.0, 1000.0
    kin = _kin(_program("harmonic", rise, h_mm, D(90), rise))
    train = dy.FollowerTrain(mass=m, spring_rate=k, preload=f0, gravity=0.0)
    res = dy.analyse(kin, train, rpm, jump_margin=margin)
    h, omega = h_mm / 1000, rpm * 2 * math.pi / 60
    inertia = m * omega**2 * h * math.pi**2 / (2 * rise**2)
    assert res.min_preload == pytest.approx(margin - k * 1000 * h + inertia, rel=1e-12)
    assert res.min_spring_rate == pytest.approx((margin - f0 + inertia) / h / 1000, rel=1e-12)  # N/mm
    fixed = dy.analyse(kin, dy.FollowerTrain(mass=m, spring_rate=k, preload=res.min_preload, gravity=0.0), rpm)
    assert fixed.min_contact_force == pytest.approx(margin, rel=1e-9)
    # with the preload below the margin no rate helps where the spring is at its lowest (the dwell)
    weak_train = dy.FollowerTrain(mass=m, spring_rate=k, preload=2.0, gravity=0.0)
    weak = dy.analyse(kin, weak_train, rpm, jump_margin=margin)
    assert weak.min_spring_rate is None and "no spring rate alone" in _checks(kin, weak_train, rpm, jump_margin=margin)[0].note


def test_spring_lengths_set_the_preload():
    train = dy.FollowerTrain(spring_rate=2.5, spring_free_length=60.0, spring_installed_length=52.0)
    assert train.spring_preload == pytest.approx(2.5 * 8.0)


def test_oscillating_follower_torques_and_jump_speed_in_closed_form():
    """Arm of inertia I about the pivot, torsional spring k_t with preload T0, damping c_t, arm
    weight m g at distance r_g: the cam must supply I alpha + k_t psi + T0 + c_t psi_dot +
    m g r_g cos(arm angle); the normal force is that torque over (arm cos(phi))."""
    rise, swing = D(100), 0.2  # rad
    inertia, k_t, t0, c_t = 0.004, 3000.0, 500.0, 0.02  # kg*m^2, N*mm/rad, N*mm, N*m*s/rad
    arm, mass, r_g, alpha0 = 60.0, 0.3, 25.0, D(30)  # mm, kg, mm, rad (arm angle at psi = 0)
    program = _program("harmonic", rise, swing, D(60), rise)
    s, ds, d2s, _ = program(THETA)
    phi = 0.3 * np.cos(THETA)
    kin = dy.Kinematics(THETA, s, ds, d2s, phi, np.full_like(THETA, 50.0), 12.0, direction=alpha0 + s + math.pi / 2)
    train = dy.FollowerTrain(motion="oscillating", mass=mass, inertia=inertia, arm_length=arm, cg_distance=r_g,
                             spring_rate=k_t, preload=t0, damping=c_t, gravity=9.81)
    rpm = 400.0
    res = dy.analyse(kin, train, rpm)
    omega = rpm * 2 * math.pi / 60
    _, psi_dot, psi_ddot = _time_motion("harmonic", THETA, omega, swing, rise, D(60), rise)
    psi = s
    # the weight (0, -m g) at r_g (cos a, sin a) from the pivot: its moment (r x F)_z, which the cam must balance
    r = r_g / 1000 * np.stack([np.cos(alpha0 + psi), np.sin(alpha0 + psi)])
    weight_torque = r[0] * (-mass * 9.81) - r[1] * 0.0
    torque = inertia * psi_ddot + k_t / 1000 * psi + t0 / 1000 + c_t * psi_dot - weight_torque  # N*m
    assert np.max(np.abs(res.generalised_force / 1000 - torque)) <= 1e-12 * np.max(np.abs(torque))
    normal = torque / (arm / 1000 * np.cos(phi))
    assert np.max(np.abs(res.contact_force - normal)) <= 1e-12 * np.max(np.abs(normal))
    assert np.max(np.abs(res.torque - torque * psi_dot / omega)) <= 1e-12 * np.max(np.abs(torque * psi_dot / omega))
    # jump speed without weight and damping: I w^2 swing pi^2 / (2 beta^2) = k_t swing + T0
    still = dy.FollowerTrain(motion="oscillating", inertia=inertia, arm_length=arm, spring_rate=k_t, preload=t0, gravity=0.0)
    omega_j = rise * math.sqrt(2 * (k_t / 1000 * swing + t0 / 1000) / (math.pi**2 * inertia * swing))
    assert dy.jump_speed(kin, still) == pytest.approx(omega_j * 60 / (2 * math.pi), rel=1e-12)


# --------------------------------------------------------------------------------------------
# Hertz stress
# --------------------------------------------------------------------------------------------
def test_hertz_stress_matches_rothbart_worked_example():
    """Rothbart, Cam Design Handbook (McGraw-Hill, 2004), ch. 9, p. 259, Example: cam nose radius
    of curvature 1/4 in, roller follower diameter 3/4 in, cam thickness 3/4 in, both steel
    (E = 30e6 psi, nu = 0.3), axial force 132 lb at a pressure angle of 20 deg, i.e. a normal
    force of 140 lb (the book's rounding): sigma_max = 80,800 psi by eq. (9.11)."""
    steel = dy.ContactMaterial(width=0.75 * INCH, cam_modulus=30e6 * PSI / 1000, follower_modulus=30e6 * PSI / 1000)
    sigma = dy.hertz_line_stress(140 * LBF, 0.25 * INCH, 0.375 * INCH, steel)
    assert float(sigma) / PSI == pytest.approx(80_800, rel=1e-3)  # the book gives 3 significant figures
    # the same point through the whole analysis: 132 lb along the motion, 20 deg pressure angle
    n = 36
    theta = 2 * math.pi * np.arange(n) / n
    zero = np.zeros(n)
    kin = dy.Kinematics(theta, zero, zero, zero, np.full(n, D(20)), np.full(n, 0.25 * INCH), 0.375 * INCH)
    res = dy.analyse(kin, dy.FollowerTrain(preload=132 * LBF, gravity=0.0), 1200.0, steel)
    # 132/cos 20 = 140.47 lb, 0.34 % above the book's rounded 140 lb: 0.17 % more stress
    assert np.allclose(res.hertz_stress / PSI, 80_800, rtol=3e-3)


def test_flat_face_and_concave_contact_follow_carvill_formulas():
    """Carvill, Mechanical Engineer's Data Handbook (1993), p. 52, same material: roller on a flat
    surface, contact width w = sqrt(32 F (1-nu^2) r / (pi L E)); roller on a concave surface of
    radius r2, w = sqrt(32 F (1-nu^2) / (pi L E (1/r1 - 1/r2))); stress 4 F / (pi w L)."""
    e_gpa, nu, length, force = 200.0, 0.29, 12.0, 3000.0
    mat = dy.ContactMaterial(width=length, cam_modulus=e_gpa, cam_poisson=nu, follower_modulus=e_gpa, follower_poisson=nu)
    e = e_gpa * 1000
    r, r2 = 15.0, 40.0
    w_flat = math.sqrt(32 * force * (1 - nu**2) * r / (math.pi * length * e))
    # a flat face (infinite radius) on a convex cam of radius r: the same geometry
    assert float(dy.hertz_line_stress(force, r, math.inf, mat)) == pytest.approx(4 * force / (math.pi * w_flat * length), rel=1e-12)
    w_conc = math.sqrt(32 * force * (1 - nu**2) / (math.pi * length * e * (1 / r - 1 / r2)))
    assert float(dy.hertz_line_stress(force, -r2, r, mat)) == pytest.approx(4 * force / (math.pi * w_conc * length), rel=1e-12)
    with pytest.raises(GeometryError, match="at most 15 mm"):
        dy.hertz_line_stress(force, -15.0, 20.0, mat)  # the roller does not fit the hollow
    with pytest.raises(GeometryError, match="must be convex"):
        dy.hertz_line_stress(force, -80.0, math.inf, mat)
    # a contact that has lifted carries no stress
    assert float(dy.hertz_line_stress(-5.0, r, r, mat)) == 0.0


# --------------------------------------------------------------------------------------------
# Energy
# --------------------------------------------------------------------------------------------
def _gauss_turn(program: MotionProgram, nodes: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on every segment of one turn: exact for the smooth
    torque inside each segment."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    starts = np.append(program.starts, 2 * math.pi)
    theta = np.concatenate([a + (b - a) * (x + 1) / 2 for a, b in pairwise(starts)])
    weight = np.concatenate([(b - a) / 2 * w for a, b in pairwise(starts)])
    return theta, weight


@pytest.mark.parametrize("law", ["cycloidal", "poly345"])
def test_work_per_turn_is_zero_without_damping_and_the_dissipation_with_it(law):
    rise, dwell, ret, h_mm = D(110), D(50), D(140), 15.0
    program = _program(law, rise, h_mm, dwell, ret)
    theta, weight = _gauss_turn(program)
    kin = _kin(program, theta=theta, phi=0.2 * np.sin(theta))
    rpm = 600.0
    omega = rpm * 2 * math.pi / 60
    conservative = dy.FollowerTrain(mass=1.2, spring_rate=4.0, preload=30.0, load=12.0, gravity=9.81)
    torque = dy.analyse(kin, conservative, rpm).torque
    assert abs(np.sum(weight * torque)) <= 1e-10 * np.sum(weight * np.abs(torque))
    c = 40.0  # N*s/m
    damped = dy.analyse(kin, dy.FollowerTrain(mass=1.2, spring_rate=4.0, preload=30.0, damping=c, gravity=9.81), rpm)
    # dissipated per turn: c int v^2 dt; cycloidal: int_0^T (h/T)^2 (1 - cos 2 pi t/T)^2 dt = 1.5 h^2 / T
    h = h_mm / 1000
    if law == "cycloidal":
        dissipated = c * 1.5 * h**2 * (omega / rise + omega / ret)
    else:  # 3-4-5: v = (h/T) 30 tau^2 (1 - tau)^2, int_0^1 900 tau^4 (1-tau)^4 dtau = 900/630
        dissipated = c * (900 / 630) * h**2 * (omega / rise + omega / ret)
    assert np.sum(weight * damped.torque) == pytest.approx(dissipated, rel=1e-10)
    # the result's own periodic trapezoid on a uniform grid, to its discretisation error
    uniform = dy.analyse(_kin(program), dy.FollowerTrain(mass=1.2, spring_rate=4.0, preload=30.0, damping=c, gravity=9.81), rpm)
    assert uniform.energy_per_turn == pytest.approx(dissipated, rel=1e-5)
    assert uniform.mean_power == pytest.approx(dissipated * omega / (2 * math.pi), rel=1e-5)


def test_torque_from_power_balance_equals_the_contact_force_lever_on_an_offset_roller():
    """Offset translating roller (axis x = -e, moving along +y, cam counter-clockwise): the roller
    centre is C = (-e, d0 + s); the pitch curve's tangent seen in the fixed frame is
    C' - J C, the contact normal n is perpendicular to it, and the shaft torque is the moment
    (C x F n)_z of the normal force about the cam axis."""
    e, base, roller = 8.0, 30.0, 10.0
    program = _program("cycloidal", D(100), 14.0, D(70), D(110))
    s, ds, _, _ = program(THETA)
    d0 = math.sqrt((base + roller) ** 2 - e**2)
    cx, cy = -e, d0 + s
    tx, ty = ds * 0 + cy, ds + e * 1.0  # C' - J C with C' = (0, s'), J C = (-cy, cx)
    norm = np.hypot(tx, ty)
    nx, ny = -ty / norm, tx / norm  # towards +y: from the cam into the roller
    phi = np.arctan2(-nx, ny)  # angle of n from the motion direction +y
    kin = _kin(program, phi=phi)
    res = dy.analyse(kin, dy.FollowerTrain(mass=0.7, spring_rate=2.0, preload=25.0, damping=15.0, gravity=9.81), 800.0)
    fx, fy = res.contact_force * nx, res.contact_force * ny
    lever_torque = (cx * fy - cy * fx) / 1000  # N*m
    assert np.max(np.abs(res.torque - lever_torque)) <= 1e-12 * np.max(np.abs(lever_torque))
    assert np.max(np.abs(np.abs(res.side_force) - np.abs(fx))) <= 1e-12 * np.max(np.abs(fx))


# --------------------------------------------------------------------------------------------
# Time domain: the follower really leaves the cam above the predicted speed, and only there
# --------------------------------------------------------------------------------------------
#: A follower further than this from the cam surface has left it (m); the penalty contact's
#: own compression stays below 0.6 um here.
SEPARATION_THRESHOLD = 1e-6


def test_solve_ivp_follower_leaves_the_cam_only_above_the_predicted_jump_speed():
    from scipy.integrate import solve_ivp

    rise, h = D(90), 0.010  # m
    m, k, f0 = 0.5, 2000.0, 20.0  # kg, N/m, N
    program = _program("cycloidal", rise, h * 1000, D(90), rise)
    predicted = dy.jump_speed(_kin(program), dy.FollowerTrain(mass=m, spring_rate=k / 1000, preload=f0, gravity=0.0))
    k_contact = 1e8  # N/m: the cam surface as a stiff one-sided spring (contact period 0.44 ms)
    c_contact = 2 * 0.5 * math.sqrt(k_contact * m)  # half-critical damping of the contact

    def surface(t: float, omega: float) -> tuple[float, float]:
        theta = (omega * t) % (2 * math.pi)
        for start, sign, base in ((0.0, 1.0, 0.0), (2 * rise, -1.0, h)):
            if start <= theta < start + rise:
                tau, period = (theta - start) / rise, rise / omega
                return (base + sign * h * (tau - math.sin(2 * math.pi * tau) / (2 * math.pi)),
                        sign * h / period * (1 - math.cos(2 * math.pi * tau)))
        return (h if rise <= theta < 2 * rise else 0.0), 0.0

    separations = {}
    for factor in (0.9, 1.1):
        omega = factor * predicted * 2 * math.pi / 60

        def rhs(t, y, omega=omega):
            x_cam, v_cam = surface(t, omega)
            depth = x_cam - y[0]
            contact = max(k_contact * depth + c_contact * (v_cam - y[1]), 0.0) if depth > 0 else 0.0
            return [y[1], (contact - k * y[0] - f0) / m]

        turn = 2 * math.pi / omega
        sol = solve_ivp(rhs, (0.0, 3 * turn), [-f0 / k_contact, 0.0], method="LSODA", rtol=1e-9, atol=1e-13,
                        max_step=2e-5, dense_output=True)
        assert sol.success
        t = np.linspace(turn, 3 * turn, 40001)  # after the first turn's start-up
        cam = np.array([surface(ti, omega)[0] for ti in t])
        separations[factor] = float(np.max(sol.sol(t)[0] - cam))
    assert separations[0.9] < 0.0  # pressed into the cam throughout
    assert separations[1.1] > 100 * SEPARATION_THRESHOLD  # flies off by about 0.24 mm


# --------------------------------------------------------------------------------------------
# Form closure (yoke, conjugate cams)
# --------------------------------------------------------------------------------------------
def test_yoke_contacts_share_the_net_force_and_are_both_hertz_checked():
    rise, h_mm, m, rpm = D(120), 20.0, 1.5, 500.0
    program = _program("cycloidal", rise, h_mm, D(60), rise)
    rho_1 = 30.0 + 10.0 * np.cos(THETA)
    rho_2 = 45.0 - 5.0 * np.sin(THETA)
    zero = np.zeros_like(THETA)
    s, ds, d2s, _ = program(THETA)
    kin = dy.Kinematics(THETA, s, ds, d2s, zero, rho_1, math.inf, pressure_angle_2=zero, rho_cam_2=rho_2)
    train = dy.FollowerTrain(closure="form", mass=m, gravity=0.0)
    mat = dy.ContactMaterial(width=10.0, allowable_stress=900.0)
    res = dy.analyse(kin, train, rpm, mat)
    checks = dynamics_checks(res, kin, mat, None)
    omega = rpm * 2 * math.pi / 60
    _, _, a = _time_motion("cycloidal", THETA, omega, h_mm / 1000, rise, D(60), rise)
    net = m * a  # N
    assert np.max(np.abs(res.contact_force - np.maximum(net, 0))) <= 1e-12 * np.max(np.abs(net))
    assert np.max(np.abs(res.contact_force_2 - np.maximum(-net, 0))) <= 1e-12 * np.max(np.abs(net))
    names = [c.name for c in checks]
    assert "jump" not in names and names[0] == "contact_force" and res.jump_rpm == math.inf
    # the load passes from one face to the other at mid-rise and mid-return (the acceleration's zeros)
    # each listed angle is the first sample the other face carries
    where = checks[0].where_deg
    assert len(where) == 2 and where[0] == pytest.approx(60.0, abs=0.11) and where[1] == pytest.approx(240.0, abs=0.11)
    first, second = (round(w * 10) for w in where)
    assert res.contact_force[first - 1] > 0 and res.contact_force_2[first] > 0 and res.contact_force[first] == 0
    assert res.contact_force_2[second - 1] > 0 and res.contact_force[second] > 0 and res.contact_force_2[second] == 0
    # flat faces: Carvill's roller-on-flat formula with each face's own cam radius
    k_mat = 2 * (1 - 0.3**2) / 210e3
    for stress, force, rho in ((res.hertz_stress, res.contact_force, rho_1), (res.hertz_stress_2, res.contact_force_2, rho_2)):
        expected = np.sqrt(force / (math.pi * 10.0 * k_mat * rho))
        assert np.max(np.abs(stress - expected)) <= 1e-12 * np.max(expected)
    hertz = next(c for c in checks if c.name == "hertz_stress")
    assert hertz.value == pytest.approx(max(np.max(res.hertz_stress), np.max(res.hertz_stress_2)))


# --------------------------------------------------------------------------------------------
# Checks, figures, validation
# --------------------------------------------------------------------------------------------
def test_torque_peak_rms_and_checks_against_a_constant_load():
    """Massless follower under a constant load L on a harmonic program (rise = return = beta):
    T = L s' peaks at L pi h / (2 beta); its RMS over the turn is L pi h / (2 beta) sqrt(beta / (2 pi))."""
    beta, h_mm, load, rpm = D(90), 10.0, 50.0, 300.0
    kin = _kin(_program("harmonic", beta, h_mm, D(90), beta))
    train = dy.FollowerTrain(load=load, gravity=0.0)
    peak = load * math.pi * h_mm / (2 * beta) / 1000  # N*m
    res = dy.analyse(kin, train, rpm)
    assert res.torque_peak == pytest.approx(peak, rel=1e-12)
    assert res.torque_rms == pytest.approx(peak * math.sqrt(beta / (2 * math.pi)), rel=1e-12)
    assert res.power_peak == pytest.approx(peak * rpm * 2 * math.pi / 60, rel=1e-12)
    torque_check = next(c for c in _checks(kin, train, rpm, torque_limit=1.01 * peak) if c.name == "camshaft_torque")
    assert torque_check.status == "pass" and torque_check.where_deg == [45.0]  # s' peaks at mid-rise
    failing = next(c for c in _checks(kin, train, rpm, torque_limit=0.99 * peak) if c.name == "camshaft_torque")
    assert failing.status == "fail" and failing.where_deg[0] < 45.0 < failing.where_deg[1]
    assert next(c for c in _checks(kin, train, rpm) if c.name == "camshaft_torque").status == "info"
    # Hertz: pass, fail or information against the allowable stress (the peak is at the largest force)
    mat = dy.ContactMaterial(width=8.0)
    stress = float(dy.hertz_line_stress(load, 40.0, 10.0, mat))  # constant force on constant radii
    for allowable, status in ((1.01 * stress, "pass"), (0.99 * stress, "fail"), (None, "info")):
        m = dy.ContactMaterial(width=8.0, allowable_stress=allowable)
        check = next(c for c in _checks(kin, train, rpm, m) if c.name == "hertz_stress")
        assert check.status == status and check.value == pytest.approx(stress, rel=1e-12)
    figures = res.figures()
    assert figures["jump_rpm"] is None  # never: JSON gets no infinity
    assert all(v is None or isinstance(v, list) or math.isfinite(v) for v in figures.values())
    assert set(res.curves()) >= {"cam_angle_deg", "contact_force_N", "torque_Nm", "power_W"}


def test_a_sharp_knife_has_no_finite_contact_stress():
    kin = _kin(_program("harmonic", D(90), 10.0, D(90), D(90)), radius=0.0)
    knife = dy.FollowerTrain(preload=10.0, gravity=0.0)
    material = dy.ContactMaterial(width=5.0, allowable_stress=500)
    res = dy.analyse(kin, knife, 100.0, material)
    check = next(c for c in _checks(kin, knife, 100.0, material) if c.name == "hertz_stress")
    assert res.hertz_stress is None and check.value == "unbounded" and check.status == "info"


@pytest.mark.parametrize("kwargs, name", [
    ({"mass": -1.0}, "mass"),
    ({"motion": "rotary"}, "follower_motion"),
    ({"motion": "oscillating"}, "arm_length"),
    ({"preload": 5.0, "spring_free_length": 50.0, "spring_installed_length": 40.0}, "preload"),
    ({"spring_free_length": 40.0, "spring_installed_length": 50.0}, "spring_installed_length"),
    ({"closure": "form", "spring_rate": 2.0}, "spring_rate"),
    ({"load": ([0.0, 7.0], [1.0, 2.0])}, "load"),
])
def test_bad_train_parameters_are_refused(kwargs, name):
    with pytest.raises(ParameterError) as err:
        dy.FollowerTrain(**kwargs)
    assert err.value.name == name


def test_bad_kinematics_and_speed_are_refused():
    program = _program("harmonic", D(90), 10.0, D(90), D(90))
    with pytest.raises(ParameterError, match="pressure angle"):
        _kin(program, phi=np.full(N_SAMPLES, D(90)))
    with pytest.raises(ParameterError, match="strictly increasing"):
        _kin(program, theta=THETA[::-1].copy())
    with pytest.raises(ParameterError, match="nonzero radius"):
        _kin(program, rho=0.0)
    with pytest.raises(ParameterError, match="rpm"):
        dy.analyse(_kin(program), dy.FollowerTrain(), 0.0)
    with pytest.raises(ParameterError, match="second contact"):
        dy.analyse(_kin(program), dy.FollowerTrain(closure="form"), 100.0)


def test_smallest_force_against_speed_reaches_zero_at_the_jump_speed():
    """min_contact_force is the smallest force of the analysis at each speed: the harmonic
    program's closed-form jump speed (above) is where it reaches 0."""
    rise, ret, h_mm = D(120), D(90), 8.0
    m, k, f0 = 0.6, 1.5, 15.0
    kin = _kin(_program("harmonic", rise, h_mm, D(60), ret), phi=np.full(N_SAMPLES, D(25)))
    train = dy.FollowerTrain(mass=m, spring_rate=k, preload=f0, gravity=0.0)
    h = h_mm / 1000
    jump = ret * math.sqrt(2 * (k * 1000 * h + f0) / (math.pi**2 * m * h)) * 60 / (2 * math.pi)
    rpm = np.array([0.0, 100.0, 0.5 * jump, jump, 1.2 * jump])
    smallest = dy.min_contact_force(kin, train, rpm)
    assert smallest[3] == pytest.approx(0.0, abs=1e-9 * f0)
    assert smallest[0] == pytest.approx(f0 / math.cos(D(25)), rel=1e-12)  # at rest: the preload at the dwell
    for r, value in zip(rpm[1:], smallest[1:]):
        assert value == pytest.approx(dy.analyse(kin, train, float(r)).min_contact_force, rel=1e-12, abs=1e-12)
    with pytest.raises(ParameterError):
        dy.min_contact_force(kin, dy.FollowerTrain(closure="form"), rpm)


def test_a_per_sample_lever_replaces_the_arm_length():
    """An oscillating follower whose pressure angle refers to a point moving along the arm (a flat
    face's contact) gives its distance from the pivot per sample: a constant lever L is an arm of L."""
    program = _program("harmonic", D(90), 0.2, D(90), D(90))
    s, ds, d2s, _ = program(THETA)
    phi = 0.2 * np.cos(THETA)
    args = (THETA, s, ds, d2s, phi, np.full_like(THETA, 40.0), math.inf)
    train = dy.FollowerTrain(motion="oscillating", inertia=2e-3, arm_length=60.0, spring_rate=4000.0, preload=2000.0, gravity=0.0)
    as_arm = dy.analyse(dy.Kinematics(*args), train, 300.0)
    as_lever = dy.analyse(dy.Kinematics(*args, lever=np.full_like(THETA, 60.0)), dy.FollowerTrain(
        motion="oscillating", inertia=2e-3, arm_length=1.0, spring_rate=4000.0, preload=2000.0, gravity=0.0), 300.0)
    assert np.array_equal(as_arm.contact_force, as_lever.contact_force) and as_arm.jump_rpm == as_lever.jump_rpm
    with pytest.raises(ParameterError, match="lever"):
        dy.Kinematics(*args, lever=np.zeros_like(THETA))
