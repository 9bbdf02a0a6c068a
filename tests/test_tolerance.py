"""camgen tolerance (issue 28 item 4): the made cam re-ridden against closed forms and a brute-force
contact, the tricycle's type I/II errors against its own ride simulation, the statistics against
closed forms, the files read back by independent readers, and bad input refused."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.stats import norm

from camgen.cli import main
from camgen.kinds import get_kind
from camgen.scene import load_scene, template_path
from camgen.study.tolerance_plate import plate_nominal, ride_plate
from camgen.study.tolerance_stats import first_order_indices, noise_floor, percentile

#: The contact's interpolation floor (tolerance_plate: h^2 max|y''| / 8 with h = 2 pi / 8192, 2.1e-6 mm
#: for these laws), with room for rounding, mm.
FLOOR_MM = 5e-6
#: The brute-force contact's own error: profile points 1.5 um apart, the touching height's maximum
#: found to second order in the spacing, mm.
BRUTE_MM = 2e-5

RISE, HOLD, FALL = 120.0, 60.0, 120.0


def _scene(offset: float = 0.0, follower: str = "roller", extra: str = "", tolerance: str = "") -> str:
    roller = "roller_radius_mm = 10.0\n" if follower == "roller" else ""
    return f"""
[output]
formats = ["dxf"]
[cams.plate]
kind = "motion_law"
base_radius_mm = 40.0
follower = "{follower}"
{roller}follower_offset_mm = {offset}
rotation = "ccw"
{extra}
[[cams.plate.segments]]
law = "cycloidal"
span_deg = {RISE}
lift_mm = 20.0
[[cams.plate.segments]]
law = "dwell"
span_deg = {HOLD}
[[cams.plate.segments]]
law = "poly345"
span_deg = {FALL}
lift_mm = -20.0
[[cams.plate.segments]]
law = "dwell"
span_deg = 60.0
{tolerance}"""


def _lift(theta: np.ndarray) -> np.ndarray:
    """The law of _scene written out (Norton, Design of Machinery, ch. 8: cycloidal and 3-4-5), mm."""
    deg = np.degrees(np.mod(theta, 2 * math.pi))
    x = np.clip(deg / RISE, 0, 1)
    rise = 20.0 * (x - np.sin(2 * math.pi * x) / (2 * math.pi))
    u = np.clip((deg - RISE - HOLD) / FALL, 0, 1)
    fall = 20.0 * (1 - (10 * u**3 - 15 * u**4 + 6 * u**5))
    return np.where(deg < RISE, rise, np.where(deg < RISE + HOLD, 20.0, np.where(deg < RISE + HOLD + FALL, fall, 0.0)))


def _built(tmp_path, text: str):
    path = tmp_path / "cam.toml"
    path.write_text(text, encoding="utf-8")
    spec = load_scene(path).cams[0]
    return get_kind(spec.kind, spec.form).build(spec, frozenset())


def _dwell(theta: np.ndarray) -> np.ndarray:
    """Cam angles well inside the two dwells (the cam there is an arc about the axis)."""
    deg = np.degrees(theta)
    return ((deg > RISE + 2) & (deg < RISE + HOLD - 2)) | (deg > RISE + HOLD + FALL + 2)


@pytest.mark.parametrize("offset", [0.0, 8.0])
def test_a_roller_radius_error_on_a_dwell_is_the_closed_form(tmp_path, offset):
    """On a dwell the cam is a circle about the axis: the roller centre is at sqrt((Rp + dr)^2 - e^2),
    so the error is sqrt((Rp + dr)^2 - e^2) - sqrt(Rp^2 - e^2) (= dr exactly for e = 0)."""
    built = _built(tmp_path, _scene(offset))
    dr = np.array([-0.05, -0.01, 0.0, 0.003, 0.05])
    ride = ride_plate(plate_nominal(built.spec_follower, built.law), {"roller_radius_mm": dr}, dr.size)
    keep = _dwell(ride.theta)
    # bottom dwell: the prime radius 50 mm; top dwell: the radius of the centre lifted 20 mm on x = e
    top = math.hypot(math.sqrt(50.0**2 - offset**2) + 20.0, offset)
    rp = np.where(np.degrees(ride.theta[keep]) < 300, top, 50.0)
    expected = np.sqrt((rp[None] + dr[:, None]) ** 2 - offset**2) - np.sqrt(rp[None] ** 2 - offset**2)
    assert np.max(np.abs(ride.error[:, keep] - expected)) < 1e-9
    if offset == 0.0:
        assert np.max(np.abs(ride.error[:, keep] - dr[:, None])) < 1e-9


def test_a_flat_face_rides_the_support_function(tmp_path):
    """A flat face rests on the cam's support function h: a normal offset delta adds delta at every
    angle, a scale k multiplies h = base radius + s(theta) by 1 + k, a phase error shifts the law."""
    built = _built(tmp_path, _scene(0.0, follower="flat", extra="face_half_length_mm = 30.0"))
    errors = {"profile_offset_mm": np.array([0.02, -0.01, 0.0]), "profile_scale": np.array([0.0, 0.001, 0.0]),
              "phase_deg": np.array([0.0, 0.0, 1.0])}
    ride = ride_plate(plate_nominal(built.spec_follower, built.law), errors, 3)
    assert ride.pressure_peak is None
    h = 40.0 + _lift(ride.theta)
    assert np.max(np.abs(ride.error[0] - 0.02)) < FLOOR_MM
    assert np.max(np.abs(ride.error[1] - (0.001 * h - 0.01))) < FLOOR_MM
    assert np.max(np.abs(ride.error[2] - (_lift(ride.theta - math.radians(1.0)) - _lift(ride.theta)))) < FLOOR_MM


def test_a_knife_on_a_dwell_moves_by_the_profile_offset(tmp_path):
    """A knife edge on a dwell (an arc about the axis, radius R): the profile offset delta moves the
    tip to sqrt((R + delta)^2 - e^2)."""
    built = _built(tmp_path, _scene(5.0, follower="knife"))
    delta = np.array([-0.03, 0.01, 0.04])
    ride = ride_plate(plate_nominal(built.spec_follower, built.law), {"profile_offset_mm": delta}, 3)
    keep = _dwell(ride.theta)
    top = math.hypot(math.sqrt(40.0**2 - 25.0) + 20.0, 5.0)
    radius = np.where(np.degrees(ride.theta[keep]) < 300, top, 40.0)
    expected = np.sqrt((radius[None] + delta[:, None]) ** 2 - 25.0) - np.sqrt(radius[None] ** 2 - 25.0)
    assert np.max(np.abs(ride.error[:, keep] - expected)) < 1e-9


ROCKER = """
[output]
formats = ["dxf"]
[cams.rocker]
kind = "motion_law"
follower = "roller"
follower_motion = "oscillating"
base_radius_mm = 40.0
roller_radius_mm = 8.0
pivot_x_mm = 90.0
pivot_y_mm = 50.0
arm_length_mm = 80.0
swing_turn = "ccw"
rotation = "cw"
[[cams.rocker.segments]]
law = "cycloidal"
span_deg = 100.0
swing_deg = 18.0
[[cams.rocker.segments]]
law = "dwell"
span_deg = 60.0
[[cams.rocker.segments]]
law = "poly345"
span_deg = 120.0
swing_deg = -18.0
[[cams.rocker.segments]]
law = "dwell"
span_deg = 80.0
"""


def _swing(theta: np.ndarray) -> np.ndarray:
    """ROCKER's swing written out (cycloidal rise, dwell, 3-4-5 return, dwell), deg."""
    deg = np.degrees(np.mod(theta, 2 * math.pi))
    x = np.clip(deg / 100.0, 0, 1)
    u = np.clip((deg - 160.0) / 120.0, 0, 1)
    rise = 18.0 * (x - np.sin(2 * math.pi * x) / (2 * math.pi))
    fall = 18.0 * (1 - (10 * u**3 - 15 * u**4 + 6 * u**5))
    return np.where(deg < 100, rise, np.where(deg < 160, 18.0, np.where(deg < 280, fall, 0.0)))


def test_an_oscillating_roller_on_a_dwell_turns_by_the_law_of_cosines(tmp_path):
    """On a dwell the roller centre is on a circle about the axis (radius R + dr) and on the arm's
    circle (L about the pivot, d + dc from the axis): the arm's angle from the line pivot -> axis is
    acos((d^2 + L^2 - R^2) / (2 d L)), so the swing error is the change of that angle (its side
    and the swing's sense from the nominal rest)."""
    built = _built(tmp_path, ROCKER)
    f = built.spec_follower
    dc, dr = np.array([-0.3, 0.0, 0.2, 0.5]), np.array([0.0, 0.02, -0.01, 0.01])
    ride = ride_plate(plate_nominal(f, built.law), {"centre_distance_mm": dc, "roller_radius_mm": dr}, 4)
    assert plate_nominal(f, built.law).unit == "deg"
    d, arm, axis = math.hypot(90.0, 50.0), 80.0, math.atan2(-50.0, -90.0)  # the direction pivot -> axis
    deg = np.degrees(ride.theta)
    for lo, hi, swing in ((102.0, 158.0, 18.0), (282.0, 358.0, 0.0)):
        keep = (deg > lo) & (deg < hi)
        g = f.rest_arm_angle + math.radians(swing)  # ccw swing_turn: tau = +1
        centre = complex(90.0, 50.0) + arm * complex(math.cos(g), math.sin(g))
        side = math.copysign(1.0, math.remainder(g - axis, 2 * math.pi))
        beta = math.acos((d * d + arm * arm - abs(centre) ** 2) / (2 * d * arm))
        moved = np.arccos(((d + dc) ** 2 + arm * arm - (abs(centre) + dr) ** 2) / (2 * (d + dc) * arm))
        expected = np.degrees(side * (moved - beta))
        assert np.max(np.abs(ride.error[:, keep] - expected[:, None])) < 1e-9


def test_an_oscillating_phase_error_is_the_swing_shifted(tmp_path):
    built = _built(tmp_path, ROCKER)
    dphi = np.array([-3.0, 0.5, 90.0])
    ride = ride_plate(plate_nominal(built.spec_follower, built.law), {"phase_deg": dphi}, 3)
    expected = _swing(ride.theta[None] - np.radians(dphi)[:, None]) - _swing(ride.theta)[None]
    assert np.max(np.abs(ride.error - expected)) < 1e-4  # deg: the interpolation floor, 3e-6 deg here


def test_the_percentiles_of_a_normal_roller_error_are_mu_plus_z_sigma(tmp_path):
    """Through the command: at a dwell angle of a centred roller the error is dr, so the envelope's
    percentiles are the samples' (numpy's PCG64 drawn again here) and the closed form mu + z_p sigma
    lies within the stated order-statistic interval."""
    mu, sigma, n, seed = 0.002, 0.01, 500, 11
    path = tmp_path / "cam.toml"
    path.write_text(_scene(0.0), encoding="utf-8")
    status = main(["tolerance", str(path), "-o", str(tmp_path / "out"), "-q", "--error", f"roller_radius_mm=normal:{mu}:{sigma}",
                   "--samples", str(n), "--seed", str(seed)])
    assert status == 0
    data = json.loads((tmp_path / "out" / "cam-tolerance" / "tolerance.json").read_text())
    drawn = mu + sigma * np.random.default_rng(seed).standard_normal(n)
    env = data["envelope"]
    theta = np.radians(env["theta_deg"])
    keep = _dwell(theta)
    for p in (1, 5, 50, 95, 99):
        values = np.array(env[f"p{p}"])[keep]
        assert np.max(np.abs(values - np.percentile(drawn, p))) < 1e-9
        stated = percentile(drawn, p)  # the interval tolerance.json states for a sample like this one
        assert stated.low <= mu + norm.ppf(p / 100) * sigma <= stated.high
    import csv

    with open(tmp_path / "out" / "cam-tolerance" / "tolerance.csv", newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert list(rows[0]) == ["sample", "roller_radius_mm", "max_abs_error_mm", "pressure_angle_deg"]
    # 17 significant digits: Python's correctly rounded float() gives back the doubles themselves
    assert np.array_equal([float(r["roller_radius_mm"]) for r in rows], drawn)
    assert data["samples"] == n and data["seed"] == seed and data["passed"] is True


def test_a_phase_error_is_the_law_shifted(tmp_path):
    """The cam keyed turned back by dphi (small, or about half a turn): the follower moves as s(theta - dphi), the law
    written out here."""
    built = _built(tmp_path, _scene(8.0))
    dphi = np.array([-175.0, -1.5, -0.2, 0.4, 2.0, 179.9])
    ride = ride_plate(plate_nominal(built.spec_follower, built.law), {"phase_deg": dphi}, dphi.size)
    expected = _lift(ride.theta[None] - np.radians(dphi)[:, None]) - _lift(ride.theta)[None]
    assert np.max(np.abs(ride.error - expected)) < FLOOR_MM


def test_a_follower_offset_error_against_a_brute_force_contact(tmp_path):
    """The roller's touching height found by brute force over 200000 points of the built profile
    (its spline, not the law), for the follower moved sideways, profile offset and scale errors."""
    built = _built(tmp_path, _scene(8.0))
    f = built.spec_follower
    errors = {"follower_offset_mm": np.array([-0.5, 0.3, 1.0]), "profile_offset_mm": np.array([0.0, 0.02, -0.01]),
              "profile_scale": np.array([0.0, 0.0, 0.002])}
    ride = ride_plate(plate_nominal(f, built.law), errors, 3)
    contour = built.contour
    points = contour.evaluate(np.linspace(0.0, contour.n_segments, 200_000, endpoint=False))
    normals = contour.normal(np.linspace(0.0, contour.n_segments, 200_000, endpoint=False))
    r = f.roller_radius
    angles = np.arange(0, ride.theta.size, 50)
    for i in range(3):
        made = (1 + errors["profile_scale"][i]) * points + errors["profile_offset_mm"][i] * normals
        e = f.offset + errors["follower_offset_mm"][i]
        for j in angles:
            th = ride.theta[j]
            c, s = math.cos(th), math.sin(th)  # ccw: a cam point q is at R(theta) q
            x, y = c * made[:, 0] - s * made[:, 1], s * made[:, 0] + c * made[:, 1]
            near = np.abs(x - e) <= r
            centre = np.max(y[near] + np.sqrt(r * r - (x[near] - e) ** 2))
            nominal = math.sqrt(f.prime_radius**2 - f.offset**2) + _lift(np.array([th]))[0]
            assert abs((centre - nominal) - ride.error[i, j]) < BRUTE_MM, (i, math.degrees(th))


@pytest.mark.parametrize("oscillating", [False, True])
def test_the_nominal_pressure_angle_is_camgen_checks(tmp_path, capsys, oscillating):
    """No error: the made cam's peak pressure angle is the one `camgen check` reports (its closed form)."""
    path = tmp_path / "cam.toml"
    path.write_text(ROCKER if oscillating else _scene(8.0), encoding="utf-8")
    assert main(["check", str(path)]) == 0
    row = next(line for line in capsys.readouterr().out.splitlines() if " pressure_angle " in f" {line} ")
    checked = float(row.split()[3])
    assert main(["tolerance", str(path), "-o", str(tmp_path / "out"), "-q", "--error", "phase_deg=normal:0", "--samples", "10"]) == 0
    data = json.loads((tmp_path / "out" / "cam-tolerance" / "tolerance.json").read_text())
    (check,) = data["checks"]
    assert abs(check["nominal"] - checked) < 1e-3
    assert abs(check["at_percentile"]["value"] - checked) < 1e-3  # zero spread: every sample is nominal
    assert data["motion_error"]["percentiles"][-1]["value"] < FLOOR_MM  # mm, or deg of swing (3e-6 deg here)
    assert data["motion_error"]["unit"] == ("deg" if oscillating else "mm")


def test_a_pressure_angle_failing_at_the_percentile_exits_1(tmp_path, capsys):
    """The limit set 0.05 deg above the nominal peak: a 0.5 mm sideways error of the follower (which
    moves the peak by about 0.3 deg per mm) fails the 95th percentile; written, exit 1, one line."""
    path = tmp_path / "cam.toml"
    path.write_text(_scene(8.0), encoding="utf-8")
    main(["check", str(path)])
    row = next(line for line in capsys.readouterr().out.splitlines() if " pressure_angle " in f" {line} ")
    limit = round(float(row.split()[3]) + 0.05, 3)
    path.write_text(_scene(8.0, extra=f"pressure_angle_limit_deg = {limit}"), encoding="utf-8")
    args = ["tolerance", str(path), "-o", str(tmp_path / "out"), "-q", "--error", "follower_offset_mm=normal:0.5", "--samples", "200"]
    assert main(args) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: check failed: cams.plate: pressure_angle at the 95th percentile")
    data = json.loads((tmp_path / "out" / "cam-tolerance" / "tolerance.json").read_text())
    assert data["passed"] is False and data["checks"][0]["at_percentile"]["value"] > limit
    assert main(args + ["--percentile", "50"]) in (0, 1)  # the folder of a previous study is replaced


def test_the_tricycle_errors_are_its_ride_simulation(tmp_path):
    """Type I and II errors: every sample's largest lateral error is that of the tricycle's own
    one-shot ride (simulate_cam + lateral_error) on the cam as made with that ErrorModel."""
    from camgen.mechanisms.tricycle import ErrorModel, lateral_error, simulate_cam

    text = template_path("tricycle").read_text(encoding="utf-8").replace("ride_periods = 10", "ride_periods = 2")
    path = tmp_path / "tri.toml"
    path.write_text(text + '\n[tolerance]\nsamples = 10\nseed = 5\n[tolerance.errors]\nsteering_offset_deg = "normal:0.05"\n'
                    'steering_gain = "uniform:-0.05:0.05"\n', encoding="utf-8")
    assert main(["tolerance", str(path), "-o", str(tmp_path / "out"), "-q"]) == 0
    import pandas

    csv = pandas.read_csv(tmp_path / "out" / "tri-tolerance" / "tolerance.csv")
    spec = load_scene(path).cams[0]
    cam = get_kind(spec.kind, spec.form).build(spec, frozenset()).tricycle
    for _, row in csv.iterrows():
        model = ErrorModel(steering_offset=math.radians(row["steering_offset_deg"]), steering_gain=1 + row["steering_gain"])
        ride = simulate_cam(cam, model, periods=2)
        expected = float(np.max(np.abs(lateral_error(cam.trajectory, ride.x, ride.y))))
        assert abs(row["max_abs_error_mm"] - expected) <= 1e-9 * max(1.0, expected)
    data = json.loads((tmp_path / "out" / "tri-tolerance" / "tolerance.json").read_text())
    assert data["envelope"] is None and data["checks"] == []
    assert {r["error"] for r in data["sensitivity"]["rankings"]["max_abs_error_mm"]} == {"steering_offset_deg", "steering_gain"}


def test_the_ranking_puts_the_error_that_moves_the_follower_first(tmp_path):
    """A phase error of +-1 deg moves the follower by up to s' dphi = 0.3 mm a sample; a 0.1 um profile
    offset by 1e-4 mm: the phase is ranked first, the offset scores at the estimator's noise floor."""
    path = tmp_path / "cam.toml"
    path.write_text(_scene(8.0), encoding="utf-8")
    assert main(["tolerance", str(path), "-o", str(tmp_path / "out"), "-q", "--samples", "400", "--error", "phase_deg=uniform:-1:1",
                 "--error", "profile_offset_mm=normal:0.0001"]) == 0
    data = json.loads((tmp_path / "out" / "cam-tolerance" / "tolerance.json").read_text())
    ranking = data["sensitivity"]["rankings"]["max_abs_error_mm"]
    assert [r["error"] for r in ranking] == ["phase_deg", "profile_offset_mm"]
    assert ranking[0]["first_order_index"] > 0.9 and ranking[1]["first_order_index"] < 3 * data["sensitivity"]["noise_floor"]


def test_first_order_indices_of_a_linear_model():
    """Y = X1 + 2 X2 + 0 X3 with independent standard normals: S = 1/5, 4/5, 0 (Saltelli et al.,
    Global Sensitivity Analysis: The Primer, 2008, ch. 1: S_i = a_i^2 / sum a_j^2 for a linear model)."""
    x = np.random.default_rng(3).standard_normal((10_000, 3))
    s = first_order_indices(x, x[:, 0] + 2 * x[:, 1])
    assert abs(s[0] - 0.2) < 0.03 and abs(s[1] - 0.8) < 0.03 and s[2] < 3 * noise_floor(10_000)


def test_the_order_statistic_interval_covers_as_stated():
    """Over 400 samples of 500 normals the 95 % interval of the 90th percentile holds z_0.9 in about
    95 % of them (binomial count: 380 expected, standard deviation 4.4; 360 is 4.5 below)."""
    rng = np.random.default_rng(8)
    z = norm.ppf(0.9)
    hits = 0
    for _ in range(400):
        p = percentile(rng.standard_normal(500), 90)
        hits += p.low <= z <= p.high
    assert 360 <= hits <= 400


@pytest.mark.parametrize("args, named", [
    (["--error", "wobble_mm=normal:0.1"], "wobble_mm"),
    (["--error", "centre_distance_mm=normal:0.1"], "centre_distance_mm"),  # a translating follower has no pivot
    (["--error", "roller_radius_mm=uniform:-20:-15"], "roller_radius_mm"),  # no roller left: no made cam to ride
    (["--error", "roller_radius_mm=normal:-0.1"], "roller_radius_mm"),
    (["--error", "roller_radius_mm=gauss:0.1"], "roller_radius_mm"),
    (["--error", "roller_radius_mm=uniform:0.2:0.1"], "roller_radius_mm"),
    (["--error", "roller_radius_mm"], "--error"),
    ([], "--error"),
    (["--error", "phase_deg=normal:0.1", "--samples", "3"], "--samples"),
    (["--error", "phase_deg=normal:0.1", "--samples", "20001"], "--samples"),
    (["--error", "phase_deg=normal:0.1", "--percentile", "100"], "--percentile"),
    (["--error", "phase_deg=normal:0.1", "--cam", "nope"], "--cam"),
])
def test_bad_input_is_refused_with_exit_2(tmp_path, capsys, args, named):
    path = tmp_path / "cam.toml"
    path.write_text(_scene(8.0), encoding="utf-8")
    assert main(["tolerance", str(path), "-o", str(tmp_path / "out"), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: error:") and named in err[0]
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("follower, table, named", [
    ("knife", '[tolerance.errors]\nroller_radius_mm = "normal:0.01"\n', "tolerance.errors.roller_radius_mm"),
    ("roller", '[tolerance]\nsampels = 100\n', "sampels"),
    ("roller", '[tolerance.errors]\nphase_deg = 0.1\n', "tolerance.errors.phase_deg"),
    ("roller", '[tolerance]\ncam = "other"\n', "tolerance.cam"),
    ("roller", '[tolerance]\npercentile = 40.0\n', "tolerance.percentile"),
])
def test_a_bad_tolerance_table_is_refused_by_tolerance_and_check(tmp_path, capsys, follower, table, named):
    path = tmp_path / "cam.toml"
    path.write_text(_scene(8.0, follower=follower, tolerance=table), encoding="utf-8")
    for command in (["tolerance", str(path), "-o", str(tmp_path / "out"), "--error", "phase_deg=normal:0.1"], ["check", str(path)]):
        assert main(command) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("camgen: error:") and named in err[0]


def test_run_and_check_take_a_good_tolerance_table_and_change_nothing(tmp_path, capsys):
    path = tmp_path / "cam.toml"
    path.write_text(_scene(8.0), encoding="utf-8")
    assert main(["run", str(path), "-o", str(tmp_path / "a"), "-q"]) == 0
    path.write_text(_scene(8.0, tolerance='[tolerance]\nsamples = 100\n[tolerance.errors]\nphase_deg = "normal:0.1"\n'),
                    encoding="utf-8")
    assert main(["run", str(path), "-o", str(tmp_path / "b"), "-q"]) == 0
    assert (tmp_path / "a" / "cam" / "plate.dxf").read_bytes() == (tmp_path / "b" / "cam" / "plate.dxf").read_bytes()


def test_a_cam_it_cannot_study_and_an_unnamed_one_of_two_are_refused(tmp_path, capsys):
    groove = template_path("groove_cam")
    assert main(["tolerance", str(groove), "-o", str(tmp_path / "out"), "--error", "phase_deg=normal:0.1"]) == 2
    assert "camgen tolerance can study none of this scene's cams" in capsys.readouterr().err
    one = _scene(8.0).replace("[cams.plate]", "[cams.CAM]").replace("[[cams.plate.", "[[cams.CAM.")
    path = tmp_path / "two.toml"
    path.write_text(one.replace("CAM", "a") + one.replace("CAM", "b").replace('[output]\nformats = ["dxf"]\n', ""), encoding="utf-8")
    assert main(["tolerance", str(path), "-o", str(tmp_path / "out"), "--error", "phase_deg=normal:0.1"]) == 2
    assert "'--cam'" in capsys.readouterr().err
    assert main(["tolerance", str(path), "-o", str(tmp_path / "out"), "-q", "--cam", "b", "--samples", "10",
                 "--error", "phase_deg=normal:0.1"]) == 0
    assert json.loads((tmp_path / "out" / "two-tolerance" / "tolerance.json").read_text())["cam"] == "b"
    assert not (tmp_path / "out" / "two").exists()
