"""Trajectory-driven spline cam and the tricycle of paper 004."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.errors import CamgenError, ParameterError
from camgen.mechanisms import tricycle as tc
from camgen.synthesis.expression import parse_expression
from camgen.synthesis.trajectory import (
    arc_length,
    read_trajectory_csv,
    trajectory_from_expression,
    trajectory_from_table,
)

PAPER_F = "202.4396*sin(pi*x/1000)"  # paper 004, eq. (15)
AMPLITUDE = 202.4396


@pytest.fixture(scope="module")
def traj():
    return trajectory_from_expression(PAPER_F, 2000.0)


@pytest.fixture(scope="module")
def cam(traj):
    return tc.tricycle_cam(traj, n_samples=720)


# --- expressions -------------------------------------------------------------------------------
def test_expression_derivatives_match_closed_form():
    e = parse_expression(PAPER_F)
    x = np.linspace(0, 2000, 101)
    w = math.pi / 1000
    assert np.allclose(e.f(x), AMPLITUDE * np.sin(w * x), rtol=0, atol=1e-12)
    assert np.allclose(e.df(x), AMPLITUDE * w * np.cos(w * x), rtol=0, atol=1e-14)
    assert np.allclose(e.d2f(x), -AMPLITUDE * w * w * np.sin(w * x), rtol=0, atol=1e-16)


@pytest.mark.parametrize("text", ["exp(-x/3)*cos(x)", "sqrt(2 + x**2) / (1 + x)", "log(3 + tan(x/4)) - abs(x - 0.3)", "x**x", "-(+x)**3"])
def test_expression_derivatives_against_finite_differences(text):
    e = parse_expression(text)
    x = np.linspace(0.5, 2.5, 41)
    h = 1e-5
    assert np.allclose(e.df(x), (e.f(x + h) - e.f(x - h)) / (2 * h), rtol=1e-7, atol=1e-8)
    assert np.allclose(e.d2f(x), (e.f(x + h) - 2 * e.f(x) + e.f(x - h)) / h**2, rtol=1e-4, atol=1e-4)


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("__import__('os').system('echo hi')", "system' is not allowed"),
        ("__import__('os')", "call of '__import__'"),
        ("os.system", "'os.system' is not allowed"),
        ("x.real", "'x.real' is not allowed"),
        ("y + 1", "name 'y'"),
        ("x ^ 2", "^ (use ** for powers)"),
        ("lambda: 1", "not allowed"),
        ("sin(x, 2)", "call of 'sin'"),
        ("[x]", "not allowed"),
        ("x +", "syntax error"),
        ("", "non-empty"),
        ("1e999 * x", "finite numbers"),
    ],
)
def test_forbidden_expressions_raise_parameter_error(text, fragment):
    with pytest.raises(ParameterError) as info:
        parse_expression(text)
    assert info.value.name == "expression" and fragment in str(info.value)


# --- arc length, d_AB, device ---------------------------------------------------------------------
def test_arc_length_against_closed_elliptic_form_and_paper(traj):
    from scipy.special import ellipe

    k = AMPLITUDE * math.pi / 1000
    closed = 4000 / math.pi * math.sqrt(1 + k * k) * ellipe(k * k / (1 + k * k))
    length = arc_length(traj).total
    assert length == pytest.approx(closed, rel=1e-12)
    assert round(length, 4) == 2189.0270  # paper 004, text after eq. (15)


def test_arc_length_inverse_is_consistent(traj):
    length = arc_length(traj)
    s = np.linspace(0, length.total, 777)
    x = length.inverse(s)
    from scipy.integrate import quad

    for xi, si in zip(x[::97], s[::97]):
        ref, _ = quad(lambda t: math.sqrt(1 + traj.df(np.array([t]))[0] ** 2), 0, xi, epsabs=1e-12, limit=200)
        assert ref == pytest.approx(si, abs=1e-8)


def test_drive_wheel_diameter_and_the_papers_rounding(cam):
    device = cam.device
    s = cam.synthesis.arc_length
    assert device.drive_wheel_diameter(s) == pytest.approx(s * 20 / (120 * math.pi), rel=1e-15)
    # the paper prints 116.19 mm: that is S * Z1 / (3.14 * Z2), pi rounded to 3.14
    assert round(s * 20 / (120 * 3.14), 2) == 116.19
    assert round(device.drive_wheel_diameter(s), 2) == 116.13
    # with Table 2's Z2 = 20 the wheel would be S / pi across
    assert tc.Tricycle(z_cam=20).drive_wheel_diameter(s) == pytest.approx(s / math.pi)
    assert device.base_radius == 75.5  # r_b = L - r_d, Table 2 row 6


def test_rho_is_equation_14(cam, traj):
    # eq. (14) typed from the paper: rho = 75.5 + 77 * 30 k / (1 + 50 k)
    k = traj.curvature(cam.synthesis.x)
    assert np.allclose(cam.synthesis.rho, 75.5 + 77 * 30 * k / (1 + 50 * k), rtol=0, atol=1e-12)
    # and the curvature is that of the sine path at the arc-length positions
    w = math.pi / 1000
    x = cam.synthesis.x
    k_closed = -AMPLITUDE * w * w * np.sin(w * x) / (1 + (AMPLITUDE * w * np.cos(w * x)) ** 2) ** 1.5
    assert np.allclose(k, k_closed, rtol=0, atol=1e-15)


def test_true_contact_contour_versus_rho(cam):
    # polar radius of the profile by brute force: dense polygon, interpolated in polar angle
    poly = cam.profile.flatten(1e-7)
    ang = np.mod(np.arctan2(poly[:, 1], poly[:, 0]), 2 * math.pi)
    order = np.argsort(ang)
    theta = cam.synthesis.theta
    brute = np.interp(np.mod(-theta, 2 * math.pi), ang[order], np.hypot(*poly[order].T), period=2 * math.pi)
    exact = cam.profile.polar_radius(-theta)
    assert np.max(np.abs(exact - brute)) <= 1e-6
    gap = tc.contact_vs_rho(cam)
    assert gap == pytest.approx(np.max(np.abs(brute - cam.synthesis.rho)), abs=1e-6)
    assert 1e-4 < gap < 0.05  # the paper's polar-radius shortcut is off by microns here, not zero
    # the profile is the rod-centre path moved in by r_d: offsetting it back gives rho + r_d
    back = cam.profile.offset(cam.device.rod_radius)
    assert np.max(np.abs(back.polar_radius(-theta) - cam.synthesis.rho - 1.5)) <= 1e-8


# --- ride simulation -------------------------------------------------------------------------------
def test_ride_against_solve_ivp_dop853(cam, traj):
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    profile, rd, dev = cam.profile, cam.device.rod_radius, cam.device
    n = profile.segments[0].n_pieces

    def rod_centre(t):
        return profile.evaluate(np.array([t / n]))[0] + rd * profile.normal(np.array([t / n]))[0]

    def polar(t):
        p = rod_centre(t)
        return math.atan2(p[1], p[0])

    def q_of_theta(theta):
        phi = (-theta) % (2 * math.pi)
        # find the spline parameter whose rod-centre polar angle is phi (independent root finder)
        t_guess = phi / (2 * math.pi) * n
        lo, hi = t_guess - 3, t_guess + 3
        f = lambda t: math.sin(polar(t) - phi)  # noqa: E731
        return float(np.hypot(*rod_centre(brentq(f, lo, hi, xtol=1e-14))))

    speed = cam.synthesis.arc_length / (2 * math.pi)

    def rhs(theta, state):
        q = q_of_theta(theta)
        k_o = (q - dev.wheelbase) / dev.lever / dev.wheelbase
        k_a = k_o / (1 - dev.half_track * k_o)
        return [speed * math.cos(state[2]), speed * math.sin(state[2]), speed * k_a]

    h0 = math.atan(traj.df(np.array([0.0]))[0])
    sol = solve_ivp(rhs, (0, 2 * math.pi), [0.0, 0.0, h0], method="DOP853", rtol=1e-12, atol=1e-10, dense_output=True)
    ride = tc.simulate_cam(cam)
    ref = sol.sol(ride.theta)
    assert np.max(np.hypot(ride.x - ref[0], ride.y - ref[1])) <= 1e-6
    assert np.max(np.abs(ride.heading - ref[2])) <= 1e-8


def test_ride_error_small_at_n720_and_over_ten_periods(cam, traj):
    one = tc.simulate_cam(cam)
    assert np.max(np.abs(tc.lateral_error(traj, one.x, one.y))) <= 1e-6  # issue #3 target
    assert one.x[-1] == pytest.approx(2000.0, abs=1e-6) and one.theta[-1] == pytest.approx(2 * math.pi)
    ten = tc.simulate_cam(cam, periods=10)
    assert ten.x[-1] == pytest.approx(20000.0, abs=1e-3)
    assert np.max(np.abs(tc.lateral_error(traj, ten.x, ten.y))) <= 1e-3


def _ride_error(traj, n, scheme):
    # offset refit tolerance far below the spline error, so the curvature scheme sets the order
    cam = tc.tricycle_cam(traj, n_samples=n, scheme=scheme, offset_tol=1e-11)
    ride = tc.simulate_cam(cam)
    return float(np.max(np.abs(tc.lateral_error(traj, ride.x, ride.y))))


@pytest.mark.parametrize("scheme, min_order, max_order", [("exact", 3.98, 4.5), ("central", 1.95, 2.1), ("forward", 0.95, 1.05)])
def test_convergence_order_of_ride_error(traj, scheme, min_order, max_order):
    """Ride error against N: exact curvature leaves only the cubic-spline interpolation error,
    O(h^4); eq. (12) central differences are O(h^2), forward differences O(h)."""
    ns = np.array([90, 180, 360, 720])
    errors = np.array([_ride_error(traj, int(n), scheme) for n in ns])
    slope = -np.polyfit(np.log(ns), np.log(errors), 1)[0]
    assert min_order <= slope <= max_order, (scheme, errors, slope)
    local = -np.log2(errors[1:] / errors[:-1])
    assert np.all(local >= min_order - 0.05), (scheme, local)


def test_start_phase_shifts_along_the_design(cam, traj):
    ride = tc.simulate_cam(cam, tc.ErrorModel(start_phase=1.0))
    assert np.max(np.abs(tc.lateral_error(traj, ride.x, ride.y))) <= 1e-6


# --- error types (paper 004, Section 4.2, Figs. 9 and 10) -------------------------------------------
def _end_offset(cam, **kw):
    ride = tc.simulate_cam(cam, tc.ErrorModel(**kw), periods=2)
    x, y, _ = ride.at(np.array([4 * math.pi]))
    return float(y[0])  # design ends at y = 0 after whole periods: > 0 is left, < 0 right


def test_error_type_one_skews_the_path_to_the_side_of_the_offset(cam):
    assert _end_offset(cam, steering_offset=math.radians(0.1)) > 50  # Fig. 9: +0.1 deg -> skewed left
    assert _end_offset(cam, steering_offset=math.radians(-0.1)) < -50


def test_error_type_two_and_its_worm_compensation(cam):
    geom = tc.ride_geometry(cam.profile, 1.5)
    alpha_max = float(np.max(np.abs(np.degrees(np.arctan((geom.rod - 77.0) / 30.0)))))
    up = math.tan(math.radians(alpha_max + 1.7)) / math.tan(math.radians(alpha_max))
    down = math.tan(math.radians(alpha_max - 1.0)) / math.tan(math.radians(alpha_max))
    a = _end_offset(cam, steering_gain=up)  # Fig. 10, trajectory A: amplitude +1.7 deg
    b = _end_offset(cam, steering_gain=up, steering_offset=math.radians(0.1))  # B: + distribution +0.1 deg
    c = _end_offset(cam, steering_gain=down)  # C: amplitude -1 deg
    d = _end_offset(cam, steering_gain=down, steering_offset=math.radians(-0.1))
    assert a < -100 and c > 100  # larger amplitude deviates right, smaller deviates left
    assert abs(b) < abs(a) and abs(d) < abs(c)  # the worm's distribution correction helps


# --- measured tables ------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["A1", "A2"])
def test_measured_table_rows_are_consistent(name):
    table = tc.load_measured_table(name)
    assert table.x.size == 41 and np.all(np.diff(table.x) > 0)
    formula = AMPLITUDE * np.sin(math.pi * table.x / 1000)
    # the column printed as "Actual"/"Adjusted" trajectory is the ideal formula, to its printed digits
    assert np.max(np.abs(table.ideal - formula)) <= 5e-4
    # the error column is measured - ideal, to the printed digits
    assert np.max(np.abs(table.measured - table.ideal - table.error)) <= 5e-4
    # the column printed as "Ideal" is not the formula: the printed labels are swapped
    assert np.max(np.abs(table.measured - formula)) > 50
    assert table.measured[0] == 0 and table.measured[-1] == 0  # one measured period, zero to zero


def test_measured_paths_are_longer_than_the_drive_distance_per_cam_turn(cam):
    """Model-free evidence against the paper's explanation of Table A1: the measured path of
    one period (polyline through the points: a lower bound of its length) is longer than S,
    the distance the drive wheel rolls per cam turn by design.  Steering errors change the
    shape of the path, not its length per cam turn."""
    for name, lower in (("A1", 1.07), ("A2", 1.02)):
        table = tc.load_measured_table(name)
        polyline = float(np.sum(np.hypot(np.diff(table.x), np.diff(table.measured))))
        assert polyline / cam.synthesis.arc_length > lower


def test_fit_recovers_known_error_parameters(cam):
    from camgen.mechanisms.tricycle_fit import fit_error_model, model_y

    truth = np.array([0.15, 0.93, 1.06, 8.0, -1.5])  # delta deg, gain, sigma, phase deg, heading deg
    geom = tc.ride_geometry(cam.profile, cam.device.rod_radius, 4)
    x = np.linspace(0, 2100, 41)
    y = np.concatenate([[0.0], model_y(cam, geom, truth, x[1:])])
    synthetic = tc.MeasuredTable("synthetic", x, y, np.zeros_like(x), np.zeros_like(x))
    fit = fit_error_model(cam, synthetic)
    got = np.array([fit.values[k] for k in ("steering_offset_deg", "steering_gain", "drive_scale", "start_phase_deg", "start_heading_deg")])
    assert np.allclose(got, truth, rtol=0, atol=[1e-4, 1e-5, 1e-5, 1e-3, 1e-3])
    assert fit.residual_rms_mm <= 1e-4


def test_fit_to_measured_tables_and_advice(cam):
    from camgen.mechanisms.tricycle_fit import fit_error_model

    fits = {name: fit_error_model(cam, tc.load_measured_table(name)) for name in ("A1", "A2")}
    for fit in fits.values():
        raw_rms = float(np.sqrt(np.mean(tc.load_measured_table(fit.table).error ** 2)))
        assert fit.residual_rms_mm < raw_rms / 5  # the five-parameter model explains most of the error
        assert all(np.isfinite(v) for v in fit.uncertainty.values())
        # the drive distance per cam turn is significantly longer than designed
        assert fit.values["drive_scale"] - 1 > 5 * fit.uncertainty["drive_scale"]
        advice = fit.advice
        assert advice["worm_knob_deg"] == pytest.approx(-fit.values["steering_offset_deg"] * 50)
        assert advice["indexing_head_change_of_d_mm"] == pytest.approx(30 * (1 - 1 / fit.values["steering_gain"]))
    # the adjustment between A1 and A2 brought the steering gain closer to 1
    assert abs(fits["A2"].values["steering_gain"] - 1) < abs(fits["A1"].values["steering_gain"] - 1)


# --- table input and bad input ----------------------------------------------------------------------
def test_table_trajectory_matches_expression(tmp_path, traj):
    x = np.linspace(0, 2000, 201)
    path = tmp_path / "path.csv"
    path.write_text("# sampled eq. (15)\nx_mm,y_mm\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(x, AMPLITUDE * np.sin(math.pi * x / 1000))))
    table = read_trajectory_csv(str(path))
    assert arc_length(table).total == pytest.approx(arc_length(traj).total, rel=1e-9)
    xs = np.linspace(0, 2000, 333)
    assert np.max(np.abs(table.curvature(xs) - traj.curvature(xs))) <= 1e-8


@pytest.mark.parametrize(
    "make, fragment",
    [
        (lambda: trajectory_from_expression("x", 2000.0), "periodic"),
        (lambda: trajectory_from_expression("sin(x)", 2000.0), "periodic"),
        (lambda: trajectory_from_expression("log(x)", 2000.0), "not finite"),
        (lambda: trajectory_from_expression("sin(pi*x/1000)", -1.0), "period"),
        (lambda: tc.tricycle_cam(trajectory_from_expression("300*sin(pi*x/100)", 200.0)), "1 + D k"),
        (lambda: tc.tricycle_cam(trajectory_from_expression(PAPER_F, 2000.0), n_samples=8), "samples"),
        (lambda: trajectory_from_table(np.arange(10.0), np.arange(10.0)), "periodic"),
    ],
)
def test_bad_trajectories_raise_clear_errors(make, fragment):
    with pytest.raises(CamgenError, match=fragment.replace("(", r"\(").replace("+", r"\+")):
        make()


def test_bad_trajectory_scene_writes_nothing(tmp_path, capsys):
    from camgen.cli import main

    scene = tmp_path / "t.toml"
    scene.write_text('[cams.s]\nkind = "trajectory"\nexpression = "__import__(\'os\')"\nperiod_mm = 2000\n')
    assert main(["run", str(scene), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "cams.s.expression" in err and "__import__" in err
    assert not (tmp_path / "out").exists()
    scene.write_text('[cams.s]\nkind = "trajectory"\nexpression = "sin(pi*x/1000)"\nperiod_mm = 2000\nsamples = 4\n')
    assert main(["run", str(scene), "-o", str(tmp_path / "out")]) == 2
    assert "cams.s.samples" in capsys.readouterr().err


def test_fine_tuning_equations_16_and_17():
    # +-0.01 deg permissible -> e <= 0.02 deg (eq. 16) -> Z3 >= 50 with a 1 deg knob step (eq. 17)
    e = tc.fine_tuning_step(0.01)
    assert e == pytest.approx(0.02)
    assert tc.worm_teeth_for(e) == 50
    assert tc.worm_teeth_for(0.019) == 53 and tc.worm_teeth_for(0.05) == 20
    with pytest.raises(ParameterError, match="step_deg"):
        tc.worm_teeth_for(0.0)


@pytest.mark.parametrize("name", ["A1", "A2"])
def test_one_start_finds_the_multi_start_minimum(name):
    """The default single-start fit and the six-start fit agree within the fit's own 1-sigma
    uncertainty on every parameter (the start phase modulo 360 deg) and in residual."""
    from camgen.mechanisms import tricycle as tc
    from camgen.mechanisms.tricycle_fit import fit_error_model
    from camgen.synthesis.trajectory import trajectory_from_expression

    cam = tc.tricycle_cam(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0))
    table = tc.load_measured_table(name)
    one, every = fit_error_model(cam, table), fit_error_model(cam, table, starts="all")
    for key, value in every.values.items():
        diff = abs(one.values[key] - value)
        if key == "start_phase_deg":
            diff = min(diff, 360.0 - diff)
        assert diff <= every.uncertainty[key], key
    assert one.residual_rms_mm == pytest.approx(every.residual_rms_mm, rel=1e-6)


@pytest.mark.parametrize("name", ["A1", "A2"])
def test_levenberg_marquardt_matches_scipys_least_squares(name):
    """camgen's Levenberg-Marquardt and scipy's MINPACK-based least_squares(method="lm"), from
    the same start on the same residuals, agree within the fit's 1-sigma uncertainty."""
    from scipy.optimize import least_squares

    from camgen.errors import GeometryError
    from camgen.mechanisms import tricycle as tc
    from camgen.mechanisms.tricycle_fit import PARAMETER_SCALE, PARAMETERS, fit_error_model, model_y
    from camgen.synthesis.trajectory import trajectory_from_expression

    cam = tc.tricycle_cam(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0))
    table = tc.load_measured_table(name)
    geom = tc.ride_geometry(cam.profile, cam.device.rod_radius, 4)
    x, y = table.x[1:], table.measured[1:]

    def residual(p):
        try:
            return model_y(cam, geom, p, x) - y
        except GeometryError:
            return np.full(x.shape, 1e3)

    theirs = least_squares(residual, np.array([0.0, 1.0, 1.0, 0.0, 0.0]), x_scale=PARAMETER_SCALE, method="lm", max_nfev=400)
    ours = fit_error_model(cam, table)
    for key, value in zip(PARAMETERS, theirs.x):
        diff = abs(ours.values[key] - value)
        if key == "start_phase_deg":
            diff = min(diff % 360.0, 360.0 - diff % 360.0)
        assert diff <= ours.uncertainty[key], key
    assert ours.residual_rms_mm == pytest.approx(math.sqrt(2 * theirs.cost / x.size), rel=1e-6)
