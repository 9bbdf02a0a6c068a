"""Design checks on cases with known answers."""
from __future__ import annotations

import math

import numpy as np
import pytest

import camgen
from camgen.checks import (
    Follower,
    evaluate_cam,
    flat_motion,
    machinability_check,
    roller_kinematics,
    undercut_check,
)
from camgen.contour import Contour, Spline


def _closed_spline(points_fn, n=1440):
    """A periodic spline through points_fn(phi) at n polar parameters (counter-clockwise)."""
    phi = np.linspace(0, 2 * math.pi, n + 1)
    pts = points_fn(phi)
    pts[-1] = pts[0]
    return Contour([Spline.interpolate(phi, pts)])


def test_roller_undercut_angle_closed_form():
    """Pitch curve = ellipse (60, 40): radius of curvature (A^2 sin^2 t + B^2 cos^2 t)^1.5 / (A B).
    With a 30 mm roller it is too sharp where sin^2 t < ((A B r)^(2/3) - B^2) / (A^2 - B^2),
    i.e. within +-10.0 deg (polar angle) of the x axis."""
    a, b, r = 60.0, 40.0, 30.0
    pitch = _closed_spline(lambda t: np.stack([a * np.cos(t), b * np.sin(t)], 1), 2880)
    check = undercut_check(pitch, Follower("roller", roller_radius=r))
    assert not check.passed and check.value == pytest.approx(b * b / a, rel=1e-4)
    t_edge = math.asin(math.sqrt(((a * b * r) ** (2 / 3) - b * b) / (a * a - b * b)))
    edge = math.degrees(math.atan2(b * math.sin(t_edge), a * math.cos(t_edge)))
    # the failing runs begin and end at -edge..+edge (around 0) and 180-edge..180+edge
    ends = sorted(w if w < 270 else w - 360 for w in check.where_deg)
    assert ends == pytest.approx([-edge, edge, 180 - edge, 180 + edge], abs=0.1)
    assert undercut_check(pitch, Follower("roller", roller_radius=26.0)).passed  # below B^2 / A = 26.67


def test_translating_roller_pressure_angle_with_offset_closed_form():
    """Harmonic rise/fall s = h (1 - cos theta) / 2 on a roller whose axis is offset by e:
    tan(alpha) = (s' + e) / (sqrt(Rp^2 - e^2) + s) (derived in the docstring of roller_kinematics'
    geometry: the pitch tangent in the fixed frame is (s' + e) d - (d0 + s) d_perp)."""
    rp, e, h = 50.0, 12.0, 20.0
    d0 = math.sqrt(rp * rp - e * e)
    direction = math.pi / 2
    d = np.array([math.cos(direction), math.sin(direction)])
    dp = np.array([-d[1], d[0]])

    def pitch_points(phi):
        theta = -phi  # polar parameter phi runs counter-clockwise; the cam angle is -phi
        s = h * (1 - np.cos(theta)) / 2
        c = e * dp[None, :] + (d0 + s)[:, None] * d[None, :]
        cos, sin = np.cos(-theta), np.sin(-theta)
        return np.stack([cos * c[:, 0] - sin * c[:, 1], sin * c[:, 0] + cos * c[:, 1]], 1)

    pitch = _closed_spline(pitch_points, 1440)
    follower = Follower("roller", roller_radius=5.0, offset=e, direction=direction)
    kin = roller_kinematics(pitch, follower)
    s = h * (1 - np.cos(kin.cam_angle)) / 2
    ds = h * np.sin(kin.cam_angle) / 2
    closed = np.arctan((ds + e) / (d0 + s))
    assert np.max(np.abs(kin.pressure_angle - closed)) <= 1e-6
    assert np.max(np.abs(kin.position - (d0 + s))) <= 1e-6
    # the eccentric circle, no offset: sin(alpha) = eps sin(theta) / (R + r) (closed form)
    eps, radius = 8.0, 40.0
    circle = Contour([camgen.Arc((eps, 0.0), radius, 0.0, 2 * math.pi)])
    follower = Follower("roller", roller_radius=6.0, direction=0.0)
    ev = evaluate_cam(circle, follower)
    angle, alpha = ev.pressure_angle
    assert np.max(np.abs(np.abs(alpha) - np.arcsin(eps * np.abs(np.sin(angle)) / (radius + 6.0)))) <= 1e-9
    pa = next(c for c in ev.checks if c.name == "pressure_angle")
    assert pa.value == pytest.approx(math.degrees(math.asin(eps / 46.0)), abs=1e-3) and pa.limit == pytest.approx(30.0)


def test_three_arc_checks_known_breadth_joints_and_motion():
    a, b, c = 220.0, 160.0, 25.0
    cam = camgen.three_arc_cam(a, b, c)
    ev = evaluate_cam(cam, Follower("yoke"), tool_radius=4.0, rpm=30.0, breadth=2 * a + 2 * c - b)
    by_name = {ch.name: ch for ch in ev.checks}
    assert by_name["constant_breadth"].passed and by_name["constant_breadth"].value <= 1e-9
    cont = by_name["continuity"]
    assert cont.value == "G1" and "infinite jerk" in cont.note
    half = math.degrees(math.asin(b / (2 * a)))
    # joints B, C, D, F, G, H at polar angles +-theta_x/2 ... (their points' polar angles)
    joints = sorted(cont.where_deg)
    assert joints[0] == pytest.approx(half, abs=1e-6) and joints[-1] == pytest.approx(360 - half, abs=1e-6)
    assert max(abs(j.curvature_jump_per_mm) for j in cam.joints()) == pytest.approx(1 / c - 1 / (a + c), rel=1e-12)
    motion, _ = flat_motion(cam, Follower("yoke"))
    # stroke 2a - b, largest velocity sqrt(a^2 - b^2/4) (flank arc about O' at C), acceleration a
    assert np.ptp(motion.displacement) == pytest.approx(2 * a - b, abs=1e-9)
    assert np.max(np.abs(motion.velocity)) == pytest.approx(math.sqrt(a * a - b * b / 4), rel=1e-6)
    assert np.max(np.abs(motion.acceleration)) == pytest.approx(a, rel=1e-6)
    assert len(motion.jerk_impulses_deg) == 6
    omega = 2 * math.pi * 30 / 60
    assert motion.at_rpm(30)["max_velocity_mm_per_s"] == pytest.approx(math.sqrt(a * a - b * b / 4) * omega, rel=1e-6)
    assert by_name["undercut"].passed and by_name["pressure_angle"].value == 0.0
    short = evaluate_cam(cam, Follower("yoke", face_half_length=150.0), breadth=330.0)
    face = next(ch for ch in short.checks if ch.name == "face_length")
    assert not face.passed and face.value == pytest.approx(math.sqrt(a * a - b * b / 4), rel=1e-6)


def test_machinability_fails_for_a_tool_larger_than_the_smallest_concave_radius():
    theta = np.linspace(0, 2 * math.pi, 49)
    r = 40 + 8 * np.cos(3 * theta)  # concave at 60, 180, 300 deg, radius of curvature ~25.6 mm
    contour = Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])
    ok = {c.name: c for c in machinability_check(contour, 20.0)}
    bad = {c.name: c for c in machinability_check(contour, 30.0)}
    assert ok["min_concave_radius"].passed and not bad["min_concave_radius"].passed
    # independent: curvature of the spline by finite differences of its points (the exact curve has 25.6)
    t = np.linspace(0, 1, 20000, endpoint=False)
    step = 1e-5
    p0, pm, pp = contour.evaluate(t), contour.evaluate(t - step), contour.evaluate(t + step)
    d1, d2 = (pp - pm) / (2 * step), (pp - 2 * p0 + pm) / step**2
    kappa = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
    assert bad["min_concave_radius"].value == pytest.approx(1 / -kappa.min(), rel=1e-3)
    assert bad["min_concave_radius"].value == pytest.approx(25.6, rel=0.05)
    assert len(bad["min_concave_radius"].where_deg) == 6  # three concave regions: start and end of each
    assert all(any(abs(w - c) < 15 for c in (60, 180, 300)) for w in bad["min_concave_radius"].where_deg)
    # a convex cam has no concave radius: any tool passes
    assert {c.name: c for c in machinability_check(camgen.three_arc_cam(220, 160, 25), 50.0)}["min_concave_radius"].passed


def test_flat_follower_on_a_concave_cam_is_undercut():
    theta = np.linspace(0, 2 * math.pi, 49)
    r = 40 + 8 * np.cos(3 * theta)
    contour = Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])
    ev = evaluate_cam(contour, Follower("flat"))
    undercut = next(c for c in ev.checks if c.name == "undercut")
    assert not undercut.passed and undercut.value < 0


def test_oscillating_roller_on_an_eccentric_circle():
    """Pitch circle (centre (eps, 0), radius R) and a roller arm of length La about a pivot A:
    the roller centre X lies on the arm circle and on the rotated pitch circle, and the pressure
    angle is the angle between the circle's normal X - C and the arm's velocity, perpendicular
    to X - A (closed form from X)."""
    eps, radius = 6.0, 40.0
    pivot = 90.0 * np.array([math.cos(0.3), math.sin(0.3)])
    arm = 60.0
    pitch = Contour([camgen.Arc((eps, 0.0), radius, 0.0, 2 * math.pi)])
    follower = Follower("roller", "oscillating", roller_radius=5.0, pivot_distance=90.0, pivot_angle=0.3, arm_length=arm)
    kin = roller_kinematics(pitch, follower)
    x = pivot + arm * np.stack([np.cos(kin.position), np.sin(kin.position)], 1)
    centre = eps * np.stack([np.cos(kin.cam_angle), np.sin(kin.cam_angle)], 1)  # pitch centre after turning the cam
    assert np.max(np.abs(np.linalg.norm(x - centre, axis=1) - radius)) <= 1e-9
    normal = (x - centre) / radius
    velocity = (x - pivot) / arm
    velocity = np.stack([-velocity[:, 1], velocity[:, 0]], 1)
    closed = np.arccos(np.clip(np.abs(np.sum(normal * velocity, 1)), 0, 1))
    assert np.max(np.abs(np.abs(kin.pressure_angle) - closed)) <= 1e-9
    assert follower.limit == pytest.approx(math.radians(45.0))


def test_motion_at_speed_scales_with_w_w2_w3():
    """s = 5 sin(theta) mm per unit cam speed: at n rpm (w = 2 pi n / 60 rad/s) the peaks are
    5 w mm/s, 5 w^2 mm/s^2 = 5e-3 w^2 m/s^2 and 5e-3 w^3 m/s^3 (chain rule, closed form)."""
    from camgen.checks import Motion

    theta = np.linspace(0, 2 * math.pi, 3601)
    motion = Motion(theta, 5 * np.sin(theta), 5 * np.cos(theta), -5 * np.sin(theta), -5 * np.cos(theta))
    for rpm in (60.0, 150.0):
        w = 2 * math.pi * rpm / 60
        at = motion.at_rpm(rpm)
        assert at["max_velocity_mm_per_s"] == pytest.approx(5 * w, rel=1e-12)
        assert at["max_acceleration_m_per_s2"] == pytest.approx(5e-3 * w**2, rel=1e-6)
        assert at["max_jerk_m_per_s3"] == pytest.approx(5e-3 * w**3, rel=1e-6)


def test_where_degrees_of_one_angle_is_numpys_bit_for_bit():
    """A check's angle from one double (Python's math.degrees and %, issue 28 item 6) against
    numpy's rad2deg and remainder of a one-element array (the arithmetic before), over angles
    of every sign and size, multiples of a degree and of a right angle, and signed zeros."""
    from camgen.checks import where_degrees

    rng = np.random.default_rng(286)
    angles = np.concatenate([rng.uniform(-50.0, 50.0, 20000), rng.normal(0.0, 1e-3, 2000), rng.uniform(-1e6, 1e6, 2000),
                             np.arange(-800, 800) * (math.pi / 180.0), np.arange(-40, 40) * (math.pi / 2.0),
                             [0.0, -0.0, 1e-320, -1e-320, 2.0 * math.pi, -2.0 * math.pi, math.pi]])
    expected = [round(float(a), 6) for a in np.mod(np.degrees(angles), 360.0)]
    assert [v for a in angles for v in where_degrees(a)] == expected  # numpy.float64, a float
    assert [v for a in angles.tolist() for v in where_degrees(a)] == expected  # Python floats
    assert where_degrees(angles) == expected  # the array path
    assert where_degrees(np.float32(1.0)) == [round(float(np.mod(np.degrees(np.float32(1.0)), 360.0)), 6)]  # single precision: numpy's


def _degrees_before(angles):
    """camgen.checks.where_degrees before issue 28 item 6, verbatim."""
    return [round(float(a), 6) for a in np.mod(np.degrees(np.atleast_1d(angles)), 360.0)]


def _run_ends_before(mask, angles):
    """camgen.checks.run_ends before issue 28 item 6, verbatim."""
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return []
    if mask.all():
        return _degrees_before(angles[[0, -1]])
    starts = np.nonzero(mask & ~np.roll(mask, 1))[0]
    ends = np.nonzero(mask & ~np.roll(mask, -1))[0]
    return [v for s, e in zip(starts, ends) for v in _degrees_before(angles[[s, e]])]


def _pressure_before(values, cam_angle, limit):
    """camgen.checks.pressure_angle_check's pass/fail and angles before issue 28 item 6, verbatim."""
    run_ends, where_degrees = _run_ends_before, _degrees_before

    mag = np.abs(values)
    i = int(np.argmax(mag))
    bad = mag > limit
    failed = bool(bad.any())
    where = run_ends(bad, cam_angle) if failed else where_degrees(cam_angle[i])
    return float(np.degrees(mag[i])), not failed, where


def _radii_before(rho, angle, tool_radius):
    """camgen.checks.machinability_from_radii's values and angles before issue 28 item 6, verbatim."""
    run_ends, where_degrees = _run_ends_before, _degrees_before

    out = []
    convex = rho > 0
    if convex.any():
        i = int(np.argmin(np.where(convex, rho, np.inf)))
        out.append(("min_convex_radius", float(rho[i]), where_degrees(angle[i])))
    concave = rho < 0
    if concave.any():
        i = int(np.argmax(np.where(concave, rho, -np.inf)))
        bad = concave & (-rho < tool_radius)
        out.append(("min_concave_radius", float(-rho[i]), run_ends(bad, angle) if bad.any() else where_degrees(angle[i])))
    return out


def test_pressure_and_radius_checks_are_the_every_sample_passes_bit_for_bit():
    """The pressure-angle check that looks at every sample only when the largest is beyond the
    limit (or NaN), and the radius checks with fewer passes (issue 28 item 6), against the code
    before: random curves within and beyond the limit, with NaN, infinite and zero samples."""
    from camgen.checks import machinability_from_radii, pressure_angle_check

    rng = np.random.default_rng(2868)
    angle = np.linspace(0.0, 2.0 * math.pi, 97, endpoint=False)
    for _ in range(600):
        values = rng.normal(0.0, 0.4, angle.size)
        rho = rng.normal(float(rng.uniform(-10.0, 30.0)), 20.0, angle.size)
        for array in (values, rho):
            if rng.random() < 0.2:
                array[rng.integers(angle.size)] = np.nan
            if rng.random() < 0.2:
                array[rng.integers(angle.size)] = rng.choice([np.inf, -np.inf, 0.0])
        if rng.random() < 0.3:
            rho = np.abs(rho) * rng.choice([1.0, -1.0])  # all convex, or all concave
        if rng.random() < 0.1:
            rho = np.where(rho > 0, np.inf, rho)  # straight: every convex radius infinite
        limit = float(rng.uniform(0.1, 1.5))
        got = pressure_angle_check(values, angle, limit, "curve")
        assert repr((got.value, got.passed, got.where_deg)) == repr(_pressure_before(values, angle, limit))  # NaN too
        tool = float(rng.uniform(1.0, 30.0))
        if rng.random() < 0.3:
            rho[rng.integers(angle.size)] = -tool  # a concave radius exactly the tool's
        checks = machinability_from_radii(rho, angle, tool)
        assert repr([(c.name, c.value, c.where_deg) for c in checks if c.where_deg]) == repr(_radii_before(rho, angle, tool))
    empty = machinability_from_radii(np.zeros(0), np.zeros(0), 3.0)
    assert [(c.name, c.value) for c in empty] == [("min_concave_radius", "no concave part")]  # and no convex radius


def test_run_ends_are_each_runs_bit_for_bit():
    """Every run's start and end in one pass (issue 28 item 6) against the code before: random
    masks of every density, runs through the wrap, one sample, all and none."""
    from camgen.checks import run_ends

    rng = np.random.default_rng(2869)
    for n in (1, 2, 3, 7, 360):
        angle = np.sort(rng.uniform(-1.0, 7.5, n))
        for _ in range(200):
            mask = rng.random(n) < float(rng.uniform(0.0, 1.0))
            assert run_ends(mask, angle) == _run_ends_before(mask, angle)
        for mask in (np.zeros(n, dtype=bool), np.ones(n, dtype=bool)):
            assert run_ends(mask, angle) == _run_ends_before(mask, angle)
