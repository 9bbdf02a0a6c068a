"""The trajectory (tricycle steering) cam at its limits, against outside numbers.

* the exact rod undercut of a Gaussian bump: the rod-centre path's curvature in closed form
  (Hermite derivatives of the bump, eq. 13, the polar curvature formula), N -> infinity;
* the steerable radius R > D + d L / r_b (eq. 13 with rho > 0), on both sides;
* the trajectory CSV reader: what a row is, line numbers, the row cap;
* the error-model fit refused where the table does not determine it (tan(alpha) = g Delta r / d
  with Delta r = 0: the gain does nothing);
* the long ride integrated one cam turn at a time, against the one-shot integration; the report's
  ride figures against scipy's DOP853 ride on the exported cam.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.errors import ParameterError

#: Paper 004, Table 2 (d as eq. 14 uses it): D, d, L, r_d (mm).
D, LEVER, L, RD = 50.0, 30.0, 77.0, 1.5
RB = L - RD


# --------------------------------------------------------------------------------------------
# The exact undercut of a Gaussian bump
# --------------------------------------------------------------------------------------------
def gauss_expression(width: float, period: float = 2000.0) -> str:
    """y = A exp(-((x - P/2)/w)^2) with A = 0.005 w^2: peak curvature -2 A / w^2 = -0.01 1/mm."""
    return f"{0.005 * width * width!r}*exp(-((x-{period / 2!r})/{width!r})**2)"


def exact_undercut_factor(width: float, period: float = 2000.0, points: int = 200_001) -> np.ndarray:
    """``1 - r_d kappa`` along the exact rod-centre path of the bump (no samples, no spline), on a
    fine x grid over +-6 w about the bump (outside it the path is straight: kappa = 1 / R_0).

    The n-th derivative of A exp(-u^2), u = (x - P/2)/w, is A (-1)^n H_n(u) exp(-u^2) / w^n
    (physicists' Hermite polynomials); k and its x-derivatives by the chain rule; the rod-centre
    radius R = rho + r_d with rho = d L k / (1 + D k) + r_b (paper 004, eq. 13); the polar angle
    phi = -2 pi s(x) / S (S by adaptive quadrature); the curvature of R(phi) u(phi) is
    (R^2 + 2 R_phi^2 - R R_phiphi) / (R^2 + R_phi^2)^1.5.
    """
    from numpy.polynomial import hermite
    from scipy.integrate import quad

    amplitude = 0.005 * width * width

    def derivatives(x: np.ndarray) -> list[np.ndarray]:
        u = (x - period / 2) / width
        g = np.exp(-u * u)
        return [amplitude * (-1) ** n * hermite.hermval(u, [0] * n + [1]) * g / width**n for n in range(5)]

    x = np.linspace(period / 2 - 6 * width, period / 2 + 6 * width, points)
    _, f1, f2, f3, f4 = derivatives(x)
    q = 1 + f1 * f1
    k = f2 * q**-1.5
    k1 = f3 * q**-1.5 - 3 * f1 * f2**2 * q**-2.5
    k2 = f4 * q**-1.5 - (9 * f1 * f2 * f3 + 3 * f2**3) * q**-2.5 + 15 * f1**2 * f2**3 * q**-3.5
    den = 1 + D * k
    r = LEVER * L * k / den + RB + RD
    r1 = LEVER * L * k1 / den**2
    r2 = LEVER * L * (k2 / den**2 - 2 * D * k1**2 / den**3)
    total = quad(lambda t: math.sqrt(1 + derivatives(np.array([t]))[1][0] ** 2), 0, period, points=[period / 2], limit=500)[0]
    phi1 = -2 * math.pi * np.sqrt(q) / total  # d phi / dx
    phi2 = -2 * math.pi * f1 * f2 / (total * np.sqrt(q))
    rp = r1 / phi1
    rpp = (r2 - rp * phi2) / phi1**2
    kappa = (r * r + 2 * rp * rp - r * rpp) / (r * r + rp * rp) ** 1.5
    return 1 - RD * kappa


def _cam(width: float, samples: int):
    from camgen.pipeline import Plan, compute
    from camgen.scene import parse_scene

    table = {"kind": "trajectory", "expression": gauss_expression(width), "period_mm": 2000.0, "samples": samples}
    return compute(parse_scene({"cams": {"x": table}}, "limits"), Plan((), frozenset())).cams[0]


def test_exact_curvature_formula_matches_a_finite_difference_of_the_exact_radius():
    """The closed form's R_phi, R_phiphi chain (the heart of exact_undercut_factor) against a
    plain curvature of the polyline (R cos phi, R sin phi) by central differences, w = 50 mm."""
    from scipy.integrate import cumulative_trapezoid

    width, period = 50.0, 2000.0
    x = np.linspace(period / 2 - 6 * width, period / 2 + 6 * width, 200_001)
    factor = exact_undercut_factor(width, period, x.size)
    a = 0.005 * width * width
    u = (x - period / 2) / width
    f1 = -2 * u * a * np.exp(-u * u) / width
    f2 = (4 * u * u - 2) * a * np.exp(-u * u) / width**2
    k = f2 / (1 + f1 * f1) ** 1.5
    r = LEVER * L * k / (1 + D * k) + RB + RD
    flat = period - (x[-1] - x[0])  # outside the window the path is straight (to e^-36)
    s = cumulative_trapezoid(np.sqrt(1 + f1 * f1), x, initial=0.0)
    phi = -2 * math.pi * s / (s[-1] + flat)
    px, py = r * np.cos(phi), r * np.sin(phi)
    dx, dy = np.gradient(px, x), np.gradient(py, x)
    ddx, ddy = np.gradient(dx, x), np.gradient(dy, x)
    kappa = -(dx * ddy - dy * ddx) / (dx * dx + dy * dy) ** 1.5  # phi decreases with x: clockwise
    inner = slice(10, -10)
    assert np.max(np.abs((1 - RD * kappa)[inner] - factor[inner])) <= 1e-4


def test_the_polar_spline_converges_to_the_exact_undercut_factor():
    """At 2880 samples the cam's rod-centre path (the code's polar quintic through the samples)
    has the exact smallest 1 - r_d kappa of the bump within 1e-5 (w = 40 mm: 0.4307)."""
    exact = float(exact_undercut_factor(40.0).min())
    cam = _cam(40.0, 2880)
    curves = cam.built.tricycle.curves
    dense = np.linspace(0, 2 * math.pi, 64 * 2880, endpoint=False)
    ours = float(np.min(1 - RD * curves.pitch_curvature(dense)))
    assert exact == pytest.approx(0.4307, abs=1e-4)
    assert ours == pytest.approx(exact, abs=1e-5)


def test_the_rod_undercuts_exactly_below_the_boundary_width():
    """The bump width w* at which the exact rod-centre path's smallest convex radius equals
    r_d = 1.5 mm (root of min(1 - r_d kappa), 29.86 mm): 5 % wider, the cam is made at 720
    samples; 5 % narrower, it undercuts at 720 and 2880 samples, by name, with the exact radius."""
    from scipy.optimize import brentq

    boundary = brentq(lambda w: float(exact_undercut_factor(w, points=40_001).min()), 25.0, 35.0, xtol=1e-4)
    assert 29.0 < boundary < 31.0
    wide = _cam(1.05 * boundary, 720)
    assert wide.contour is not None
    narrow_exact = 1.0 / ((1.0 - float(exact_undercut_factor(0.95 * boundary).min())) / RD)
    assert narrow_exact < RD
    for samples in (720, 2880):
        cam = _cam(0.95 * boundary, samples)
        check = next(c for c in cam.checks if c.name == "undercut")
        assert cam.contour is None and check.failed and check.blocks_manufacture
        assert check.value == pytest.approx(narrow_exact, rel=2e-3) and check.limit == RD


# --------------------------------------------------------------------------------------------
# The steerable radius: R > D + d L / r_b
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("half_track, lever", [(50.0, 30.0), (30.0, 20.0)])
def test_right_turns_are_refused_exactly_below_the_steerable_radius(half_track, lever):
    """eq. (13) rho = d L k / (1 + D k) + r_b with k = -1/R is > 0 iff R > D + d L / r_b: a bump
    whose peak right turn has a radius 0.2 % above that is synthesised (0 < rho_min < 1 % of
    r_b), 0.2 % below it is refused saying the bound."""
    from camgen.mechanisms import tricycle as tc
    from camgen.synthesis.trajectory import PathError, trajectory_from_expression

    device = tc.Tricycle(half_track=half_track, lever=lever)
    r_min = half_track + lever * L / RB
    width = 200.0
    for factor in (1.002, 0.998):
        amplitude = width * width / (2 * factor * r_min)  # peak k = -2 A / w^2 = -1 / (factor r_min)
        path = trajectory_from_expression(f"{amplitude!r}*exp(-((x-1000.0)/{width!r})**2)", 2000.0)
        if factor > 1:
            cam = tc.tricycle_cam(path, device)
            assert 0 < cam.synthesis.rho.min() < 0.01 * RB  # the cam radius just above 0 at the turn
        else:
            with pytest.raises(PathError) as info:
                tc.tricycle_cam(path, device)
            quoted = float(info.value.valid.split("radius > ")[1].split(" mm")[0])
            assert r_min <= quoted < r_min * (1 + 1e-5)  # rounded up: every radius above it steers


def test_a_table_too_sharp_to_steer_names_trajectory_csv(tmp_path, capsys):
    from camgen.cli import main

    x = np.linspace(0.0, 2000.0, 2001)
    y = 5.0 * np.exp(-(((x - 1000.0) / 20.0) ** 2))  # peak right turn radius 40 mm < D
    (tmp_path / "path.csv").write_text("".join(f"{a!r},{b!r}\n" for a, b in zip(x.tolist(), y.tolist())))
    (tmp_path / "s.toml").write_text('[cams.x]\nkind = "trajectory"\ntrajectory_csv = "path.csv"\n')
    assert main(["run", str(tmp_path / "s.toml"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "parameter 'cams.x.trajectory_csv' = 'path.csv'" in err and "right turns" in err, err


def test_a_profile_that_folds_back_names_the_expression(tmp_path, capsys):
    """y = 1200 sin(2 pi x / 2000): its sharpest turn, radius P^2 / (4 pi^2 A) = 84.4 mm, is above
    Table 2's steerable radius (D + d L / r_b = 80.6 mm), but the profile folds back near it (a ray
    from the axis meets it three times): refused naming the expression, nothing written."""
    from camgen.cli import main

    assert 2000.0**2 / (4 * math.pi**2 * 1200.0) == pytest.approx(84.43, abs=0.01)
    (tmp_path / "s.toml").write_text('[cams.x]\nkind = "trajectory"\nexpression = "1200*sin(2*pi*x/2000)"\nperiod_mm = 2000.0\n')
    assert main(["run", str(tmp_path / "s.toml"), "-o", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "parameter 'cams.x.expression' = '1200*sin(2*pi*x/2000)'" in err and "star-shaped" in err, err
    assert not (tmp_path / "out").exists()


# --------------------------------------------------------------------------------------------
# The trajectory CSV reader
# --------------------------------------------------------------------------------------------
ROWS = [(2000.0 * i / 40, 202.4396 * math.sin(math.pi * i / 20)) for i in range(41)]


def _write(tmp_path, text: str):
    path = tmp_path / "path.csv"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("name, line, fields", [("three-columns", 3, 3), ("decimal-commas", 3, 4), ("one-column", 3, 1)])
def test_a_row_of_other_than_two_fields_is_refused_with_its_line(name, line, fields, tmp_path):
    from camgen.synthesis.trajectory import read_trajectory_csv

    body = [f"{a!r},{b!r}" for a, b in ROWS]
    bad = {"three-columns": f"{ROWS[1][0]!r},{ROWS[1][1]!r},1", "decimal-commas": "50,0,31,67",
           "one-column": f"{ROWS[1][0]!r}"}[name]
    text = "x_mm,y_mm\n" + body[0] + "\n" + bad + "\n" + "\n".join(body[2:]) + "\n"  # the bad row is line 3
    with pytest.raises(ParameterError) as info:
        read_trajectory_csv(_write(tmp_path, text))
    exc = info.value
    assert exc.name == "trajectory_csv" and str(exc.value).endswith(f"line {line}")
    assert (f"holds {fields} fields" if fields > 1 else "is one field") in exc.why
    assert bad not in str(exc)  # the row is described, never quoted: the file may not be a table


def test_row_cap_and_its_line(tmp_path):
    from camgen.synthesis.trajectory import MAX_ROWS, read_trajectory_csv

    assert MAX_ROWS == 100_000
    with pytest.raises(ParameterError) as info:
        read_trajectory_csv(_write(tmp_path, "# header comment\n" + "".join(f"{i * 1e-3!r},0\n" for i in range(21))), max_rows=20)
    assert str(info.value.value).endswith("line 22") and "at most 20 rows" in info.value.valid
    rows = "".join(f"{i * 1e-4!r},0\n" for i in range(MAX_ROWS + 1))
    with pytest.raises(ParameterError, match="at most 100000 rows"):
        read_trajectory_csv(_write(tmp_path, rows))


def test_non_increasing_x_names_its_line(tmp_path):
    from camgen.synthesis.trajectory import read_trajectory_csv

    rows = ROWS[:]
    rows[5], rows[6] = rows[6], rows[5]
    with pytest.raises(ParameterError) as info:
        read_trajectory_csv(_write(tmp_path, "".join(f"{a!r},{b!r}\n" for a, b in rows)))
    assert info.value.name == "trajectory_csv" and "line 7: x = 250.0 after 300.0" in str(info.value.value)


def test_separators_comments_and_header_read_the_same_path(tmp_path):
    """Commas, semicolons and blanks, trailing comments and a header: the same points, so the
    same arc length as the expression the rows sample (to the table spline's accuracy)."""
    from camgen.synthesis.trajectory import arc_length, read_trajectory_csv, trajectory_from_expression

    x = np.linspace(0, 2000, 201)
    y = 202.4396 * np.sin(math.pi * x / 1000)
    expected = arc_length(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0)).total
    for sep in (",", ";", " ", "\t"):
        text = f"x{sep}y\n" + "".join(f"{a!r}{sep}{b!r}  # row {i}\n" for i, (a, b) in enumerate(zip(x.tolist(), y.tolist())))
        table = read_trajectory_csv(_write(tmp_path, text))
        assert arc_length(table).total == pytest.approx(expected, rel=1e-9), sep


# --------------------------------------------------------------------------------------------
# The error-model fit: refused where the table does not determine it
# --------------------------------------------------------------------------------------------
def test_a_straight_path_leaves_the_steering_gain_undetermined():
    """On a straight path the rod stays at L: tan(alpha) = g (q - L) / d = 0 whatever the gain
    g, so Table A1 cannot determine g; the fit is refused naming the gain, not reported."""
    from camgen.mechanisms import tricycle as tc
    from camgen.mechanisms.tricycle_fit import FitNotDetermined, fit_error_model
    from camgen.synthesis.trajectory import trajectory_from_expression

    cam = tc.tricycle_cam(trajectory_from_expression("0*x", 2000.0))
    with pytest.raises(FitNotDetermined, match="steering_gain barely changes the ride"):
        fit_error_model(cam, tc.load_measured_table("A1"))


# --------------------------------------------------------------------------------------------
# The long ride, one cam turn at a time
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("errors", [{}, {"steering_offset": 1e-3, "steering_gain": 1.05, "drive_scale": 1.01, "start_heading": 0.01}])
def test_long_ride_error_equals_the_one_shot_integration(errors):
    """720 samples x 10 cam turns: the turn-by-turn running maximum equals the largest lateral
    error of the whole ride integrated at once (simulate_cam) to 1e-12 relative."""
    from camgen.mechanisms import tricycle as tc
    from camgen.synthesis.trajectory import trajectory_from_expression

    cam = tc.tricycle_cam(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0), n_samples=720)
    model = tc.ErrorModel(**errors)
    whole = tc.simulate_cam(cam, model, periods=10)
    expected = float(np.max(np.abs(tc.lateral_error(cam.trajectory, whole.x, whole.y))))
    assert tc.ride_max_lateral_error(cam, 10, model) == pytest.approx(expected, rel=1e-12, abs=0)
    with pytest.raises(ParameterError, match="start_phase"):
        tc.ride_max_lateral_error(cam, 10, tc.ErrorModel(start_phase=0.5))


def test_the_report_figures_are_the_ride_errors_of_an_independent_integration():
    """report.json's ride_max_error_mm and ride_max_error_<N>_periods_mm of the paper's path
    (eq. 15; 180 samples, eq. 12's central differences: an error of 0.017 mm over one turn that
    grows to 0.051 mm over three) against the ride integrated by scipy's DOP853 on the cam as
    exported (the B-spline DXF read back by ezdxf), independent of camgen's ride code
    (test_tricycle._dop853_ride_on)."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import parse_scene
    from test_tricycle import _dop853_ride_on, _dxf_profile

    table = {"kind": "trajectory", "expression": "202.4396*sin(pi*x/1000)", "period_mm": 2000.0, "samples": 180,
             "curvature": "central", "ride_periods": 3}
    cam = compute(parse_scene({"cams": {"x": table}}, "ride"), Plan((), frozenset({"analysis"}))).cams[0]
    one, three = _dop853_ride_on(*_dxf_profile(cam.built.tricycle), periods=3)
    assert three > 2.5 * one > 0.04  # the error grows turn by turn: the two figures differ
    assert cam.figures["ride_max_error_mm"] == pytest.approx(one, rel=1e-5)
    assert cam.figures["ride_max_error_3_periods_mm"] == pytest.approx(three, rel=1e-5)


@pytest.mark.parametrize("expression, period, fits", [
    ("202.4396*sin(pi*x/1000)", 2000.0, True),                         # the paper's path
    ("202.4396*sin(pi*x/1000) + 0.005*sin(3*pi*x/1000)", 2000.0, True),  # within 0.01 mm of it
    ("150*sin(pi*x/1000)+30*sin(3*pi*x/1000)", 2000.0, False),           # another path: 23 mm RMS residual once
    ("202.4396*sin(pi*x/2000)", 4000.0, False),                          # the paper's amplitude, twice its period
])
def test_fit_tables_only_on_the_papers_path(expression, period, fits, tmp_path, capsys):
    """Tables A1/A2 are rides of y = 202.4396 sin(pi x / 1000) (their ideal column, to 4e-4 mm):
    fitted to another path, the model took the paths' difference for the machine's errors and
    advised turning the worm knob 15 deg.  Refused naming fit_tables, with the distance."""
    from camgen.cli import main

    scene = tmp_path / "s.toml"
    scene.write_text(f'[cams.x]\nkind = "trajectory"\nexpression = "{expression}"\nperiod_mm = {period!r}\nfit_tables = ["A1"]\n'
                     '[output]\nformats = ["dxf"]\n')
    status = main(["run", str(scene), "-o", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err
    if fits:
        assert status in (0, 1) and "fit_tables" not in err, err
    else:
        assert status == 2 and "parameter 'cams.x.fit_tables'" in err and "ideal column" in err, err
        assert not (tmp_path / "out").exists()
