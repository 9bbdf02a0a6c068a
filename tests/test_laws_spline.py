"""B-spline motion through user points and polynomials with interior conditions (issue 26, item 1).

Outside references: scipy's ``make_interp_spline`` built here in cam-angle units (the law builds
its own in normalised units and converts to pieces); Norton, *Design of Machinery*, ch. 8, the
single-dwell cam designed as one polynomial (rise-fall over 180 deg, no dwell between, s = h at 90
deg, rest at both ends: the 3-4-5-6 polynomial ``h (64 x^3 - 192 x^4 + 192 x^5 - 64 x^6)``, checked
by hand below); a confluent Vandermonde system in cam-angle units solved by numpy.linalg.solve;
8th-order central finite differences; the lift table camgen writes, read back as CSV.
"""
from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest
from scipy.interpolate import make_interp_spline

from camgen.cli import main
from camgen.motions.motion_law import read_program
from camgen.synthesis.laws import MotionProgram, Segment
from helpers import scene_toml

D = math.radians
PI = math.pi
FD8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])


def fd(f, x, h):
    """d f / dx at x by the 8th-order central stencil."""
    return sum(c * f(x + k * h) for c, k in zip(FD8, range(-4, 5)) if c) / h


#: a bspline rise of 20 mm over 120 deg through three points, then a dwell, a cycloidal return, a dwell
POINTS_DEG = [(25.0, 2.0), (60.0, 11.0), (95.0, 18.5)]


def spline_program(degree=5, start=None, end=None, lift=20.0):
    seg = Segment("bspline", D(120), None if start is not None else lift, points=[(D(a), s) for a, s in POINTS_DEG],
                  degree=degree, start=start, end=end)
    rest = seg.end_values(True)[0] + (seg.start_level or 0.0)
    return MotionProgram([seg, Segment("dwell", D(60)), Segment("cycloidal", D(120), -rest + (seg.start_level or 0.0)),
                          Segment("dwell", D(60))])


def scipy_reference(degree, start, end, lift):
    """The spline built independently here: abscissa the cam angle in rad, ordinates in mm, end
    derivatives per rad (what the law builds in tau units and converts)."""
    x = np.array([0.0] + [D(a) for a, _ in POINTS_DEG] + [D(120)])
    y = np.array([start[0]] + [start[0] + s for _, s in POINTS_DEG] + [start[0] + lift])
    m = (degree - 1) // 2
    return make_interp_spline(x, y, k=degree, bc_type=([(k + 1, start[k + 1]) for k in range(m)], [(k + 1, end[k + 1]) for k in range(m)]))


CASES = {
    "quintic at rest": (5, None, None),
    "cubic from a velocity": (3, (1.0, 8.0), (21.0, 0.0)),
    "quintic with end velocity and acceleration": (5, (1.0, 6.0, -3.0), (21.0, 4.0, 2.0)),
    "septic with jerk": (7, (0.0, 0.0, 0.0, 40.0), (20.0, 0.0, 0.0, 0.0)),
}


@pytest.mark.parametrize("case", CASES)
def test_bspline_passes_through_every_point_and_meets_its_end_conditions(case):
    degree, start, end = CASES[case]
    program = spline_program(degree, start, end)
    m = (degree - 1) // 2
    start = start or (0.0,) + (0.0,) * m
    end = end or (20.0,) + (0.0,) * m
    s, *_ = program(np.array([D(a) for a, _ in POINTS_DEG]))
    assert np.abs(s - np.array([start[0] + lift for _, lift in POINTS_DEG])).max() <= 1e-12 * 20.0
    at_start = [v[0] for v in program(np.array([0.0]))]
    at_end = [v[0] for v in program(np.array([D(120) - 1e-12]))]
    for k in range(m + 1):
        scale = max(1.0, abs(start[k]), abs(end[k]))
        assert at_start[k] == pytest.approx(start[k], abs=1e-9 * scale), (case, "start", k)
        assert at_end[k] == pytest.approx(end[k], abs=1e-9 * scale * 10 ** k), (case, "end", k)


@pytest.mark.parametrize("case", CASES)
def test_bspline_against_scipy_make_interp_spline_in_cam_angle(case):
    degree, start, end = CASES[case]
    m = (degree - 1) // 2
    start_ = start or (0.0,) * (m + 1)
    end_ = end or (20.0,) + (0.0,) * m
    reference = scipy_reference(degree, start_, end_, end_[0] - start_[0])
    theta = np.linspace(0.0, D(120), 1201)[:-1]
    ours = spline_program(degree, start, end)(theta)
    for n in range(4):
        ref = reference(theta, nu=n)
        assert np.abs(ours[n] - ref).max() <= 1e-9 * max(1.0, float(np.abs(ref).max())), (case, n)


@pytest.mark.parametrize("case", CASES)
def test_bspline_derivatives_against_finite_differences(case):
    """V, A, J of the closed-form pieces against 8th-order central differences of S, V, A, away
    from the knots (the points) where the degree-th derivative may jump."""
    degree, start, end = CASES[case]
    law = spline_program(degree, start, end).segments[0].shape
    h = 2e-4
    tau = np.linspace(5 * h, 1 - 5 * h, 2001)
    for a, _ in POINTS_DEG:
        tau = tau[np.abs(tau - a / 120.0) > 5 * h]
    vals = law.evaluate(tau)
    for n in range(3):
        numeric = fd(lambda x, n=n: law.evaluate(x)[n], tau, h)
        assert np.abs(numeric - vals[n + 1]).max() <= 2e-7 * max(1.0, float(np.abs(vals[n + 1]).max())), (case, n)


@pytest.mark.parametrize("degree, continuous", [(3, 2), (5, 3), (7, 3)])
def test_bspline_continuity_at_the_points_measured_from_both_sides(degree, continuous):
    """A B-spline of degree k is C^(k-1) at simple knots: the cubic's jerk jumps at the points, the
    quintic's and the septic's do not; the law's breaks say the same."""
    law = spline_program(degree).segments[0].shape
    scale = [1.0] + [max(1.0, p) for p, _ in law.peaks]
    for a, _ in POINTS_DEG:
        tau = a / 120.0
        left = [v[0] for v in law.evaluate(np.array([tau - 1e-9]))]
        right = [v[0] for v in law.evaluate(np.array([tau + 1e-9]))]
        jumps = [abs(r - l) / s for r, l, s in zip(right, left, scale)]
        measured = next((n - 1 for n in range(1, 4) if jumps[n] > 1e-6), 3)
        assert measured == continuous, (degree, a, jumps)
    assert sorted(round(b.tau * 120.0, 9) for b in law.breaks) == [a for a, _ in POINTS_DEG]
    assert {b.continuity for b in law.breaks} == {continuous}


def test_bspline_without_points_is_the_polynomial_of_its_conditions():
    """No points, rest to rest, degree 5: the 3-4-5 polynomial (Norton ch. 8), 10 t^3 - 15 t^4 + 6 t^5."""
    seg = Segment("bspline", D(90), 12.0)
    t = np.linspace(0.0, 1.0, 101)
    s = seg.values(t)[0]
    assert np.abs(s - 12.0 * (10 * t**3 - 15 * t**4 + 6 * t**5)).max() <= 1e-12 * 12.0


def test_bspline_rise_fall_through_points_with_zero_lift():
    seg = Segment("bspline", D(180), 0.0, points=[(D(90), 15.0)])
    program = MotionProgram([seg, Segment("dwell", D(180))])
    s = program(np.array([0.0, D(90), D(180) - 1e-12]))[0]
    assert s == pytest.approx([0.0, 15.0, 0.0], abs=1e-9)


# ------------------------------------------------------------------------------------------------
# polynomials with interior conditions
# ------------------------------------------------------------------------------------------------
def test_nortons_single_dwell_polynomial_from_interior_conditions():
    """Norton, Design of Machinery, ch. 8 (single-dwell cam as one polynomial): rise and fall over
    beta = 180 deg with no dwell between, s = h at 90 deg, s = v = a = 0 at both ends; the published
    polynomial is s = h (64 x^3 - 192 x^4 + 192 x^5 - 64 x^6), x = theta / beta.  Hand check: at
    x = 1/2, 64/8 - 192/16 + 192/32 - 64/64 = 8 - 12 + 6 - 1 = 1."""
    h = 25.0
    seg = Segment("polynomial", D(180), start=(0.0, 0.0, 0.0), end=(0.0, 0.0, 0.0), interior=[(D(90), h)])
    coeffs = seg.shape.pieces[0].poly
    assert seg.shape.options["degree"] == 6
    assert np.allclose(np.array(coeffs) / h, [0, 0, 0, 64, -192, 192, -64], rtol=0, atol=1e-12)
    program = MotionProgram([seg, Segment("dwell", D(180))])
    x = np.linspace(0.0, 1.0, 181)
    s = program(x * D(180))[0]
    assert np.abs(s - h * (64 * x**3 - 192 * x**4 + 192 * x**5 - 64 * x**6)).max() <= 1e-12 * h


def test_interior_velocity_condition_against_a_hand_solved_vandermonde_system():
    """A rise of 30 mm over 150 deg from rest to rest (s, v, a at each end) passing 12 mm at 60 deg
    with velocity 0.25 mm/deg there: 8 conditions, degree 7.  The reference solves the confluent
    Vandermonde system in the cam angle (rad) with numpy.linalg.solve and evaluates it (the law
    works in normalised units and exact rationals)."""
    beta, t1 = D(150), D(60)
    v1 = 0.25 * 180.0 / PI  # mm/rad
    rows, rhs = [], []

    def condition(t, k, value):
        rows.append([math.perm(i, k) * t ** (i - k) if i >= k else 0.0 for i in range(8)])
        rhs.append(value)
    for k, value in enumerate((0.0, 0.0, 0.0)):
        condition(0.0, k, value)
    for k, value in enumerate((30.0, 0.0, 0.0)):
        condition(beta, k, value)
    condition(t1, 0, 12.0)
    condition(t1, 1, v1)
    c = np.linalg.solve(np.array(rows), np.array(rhs))
    seg = Segment("polynomial", beta, start=(0.0, 0.0, 0.0), end=(30.0, 0.0, 0.0), interior=[(t1, 12.0, v1)])
    assert seg.shape.options["degree"] == 7
    program = MotionProgram([seg, Segment("poly345", 2 * PI - beta, -30.0)])
    theta = np.linspace(0.0, beta, 301)[:-1]
    ours = program(theta)
    powers = np.polynomial.polynomial
    for n in range(4):
        ref = powers.polyval(theta, powers.polyder(c, n) if n else c)
        assert np.abs(ours[n] - ref).max() <= 1e-7 * max(1.0, float(np.abs(ref).max())), n
    assert program(np.array([t1]))[1][0] == pytest.approx(v1, rel=1e-12)


def test_interior_acceleration_condition_and_peaks():
    """An interior (s, v, a) condition is met to rounding; joins report as for any polynomial."""
    seg = Segment("polynomial", D(120), start=(0.0, 0.0, 0.0), end=(20.0, 0.0, 0.0), interior=[(D(40), 5.0, 12.0, 3.0)])
    program = MotionProgram([seg, Segment("dwell", D(60)), Segment("cycloidal", D(120), -20.0), Segment("dwell", D(60))])
    s, v, a, _ = (x[0] for x in program(np.array([D(40)])))
    assert (s, v, a) == pytest.approx((5.0, 12.0, 3.0), rel=1e-11)
    assert [j.continuity for j in program.joins()] == [2, 2, 2, 2]  # the cycloid's jerk jumps against the dwells


def test_scene_units_of_points_and_interior():
    """The reader converts scene units: a bspline's points in deg of cam angle and deg of swing
    (oscillating), an interior condition's position and velocity per deg; a linear cam's positions in
    mm of travel."""
    segs = ({"law": "bspline", "span": D(120), "swing": D(10.0), "points": ((40.0, 2.0), (80.0, 8.0))},
            {"law": "dwell", "span": D(60)}, {"law": "cycloidal", "span": D(120), "swing": D(-10.0)}, {"law": "dwell", "span": D(60)})
    program = read_program("cams.c", segs, "oscillating")
    assert program(np.array([D(40), D(80)]))[0] == pytest.approx([D(2.0), D(8.0)], rel=1e-12)
    segs = ({"law": "polynomial", "span_travel": 100.0, "start": (0.0, 0.0, 0.0), "end": (10.0, 0.0, 0.0),
             "interior": ((30.0, 4.0, 0.2),)}, {"law": "poly345", "span_travel": 100.0, "lift": -10.0})
    program = read_program("cams.c", segs, "translating", abscissa="travel")
    s, v = (x[0] for x in program(np.array([2 * PI * 30.0 / 200.0]))[:2])
    assert s == pytest.approx(4.0, rel=1e-12)
    assert v == pytest.approx(0.2 * 200.0 / (2 * PI), rel=1e-12)  # 0.2 mm/mm of travel -> per rad of the turn


def test_bspline_scene_follower_table_passes_the_points(tmp_path):
    """End to end: the follower table camgen writes (cam angle, lift), read back as CSV, has the
    points' lifts at their angles and the rest at the spline's ends (zero velocity)."""
    scene = {"output": {"formats": ["follower"]}, "cams": {"c": {
        "kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 60.0,
        "segments": [{"law": "bspline", "span_deg": 120.0, "lift_mm": 20.0, "points": [list(p) for p in POINTS_DEG]},
                     {"law": "dwell", "span_deg": 60.0}, {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -20.0},
                     {"law": "dwell", "span_deg": 60.0}]}}}
    path = tmp_path / "s.toml"
    path.write_text(scene_toml(scene))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 0
    (table,) = (tmp_path / "out").rglob("c_follower.csv")
    rows = list(csv.reader(io.StringIO(table.read_text())))
    assert rows[0][:4] == ["cam_angle_deg", "time_s", "lift_mm", "velocity_mm_per_s"], rows[0]
    data = np.array([[float(x) for x in r[:4]] for r in rows[1:]])
    for angle, lift in POINTS_DEG + [(120.0, 20.0)]:
        (k,) = np.flatnonzero(np.isclose(data[:, 0], angle))
        assert data[k, 2] == pytest.approx(lift, abs=1e-8)
    (k,) = np.flatnonzero(np.isclose(data[:, 0], 120.0))
    assert abs(data[k, 3]) <= 1e-6


# ------------------------------------------------------------------------------------------------
# bad input: exit 2, one line naming the key
# ------------------------------------------------------------------------------------------------
def _plate(first: dict) -> dict:
    segs = [first, {"law": "dwell", "span_deg": 60.0}, {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -20.0},
            {"law": "dwell", "span_deg": 60.0}]
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0,
                                                           "segments": segs}}}


BSPLINE = {"law": "bspline", "span_deg": 120.0, "lift_mm": 20.0}
POLY = {"law": "polynomial", "span_deg": 120.0, "start": [0.0, 0.0, 0.0], "end": [20.0, 0.0, 0.0]}
REFUSED = {
    "point outside the span": (dict(BSPLINE, points=[[30.0, 5.0], [130.0, 18.0]]), "cams.c.segments[0].points[1]", "0 < position < 120 deg"),
    "point at the start": (dict(BSPLINE, points=[[0.0, 0.0]]), "cams.c.segments[0].points[0]", "strictly inside the segment's span: 0 < position < 120 deg"),
    "point at the end": (dict(BSPLINE, points=[[60.0, 10.0], [120.0, 20.0]]), "cams.c.segments[0].points[1]", "0 < position < 120 deg"),
    "points not increasing": (dict(BSPLINE, points=[[60.0, 5.0], [40.0, 8.0]]), "cams.c.segments[0].points[1]", "increasing order"),
    "point of three numbers": (dict(BSPLINE, points=[[60.0, 5.0, 1.0]]), "cams.c.segments[0].points[0]", "2 to 2 numbers"),
    "points closer than 1e-6 of the span": (dict(BSPLINE, points=[[60.0, 10.0], [60.00001, 10.5]]), "cams.c.segments[0].points[1]",
                                            "(1e-06 of the span) after 60 deg"),
    "points too close for their lifts": (dict(BSPLINE, degree=7, points=[[60.0, 10.0], [60.01, 15.0], [60.02, 10.0], [60.03, 15.0]]),
                                         "cams.c.segments[0].points", "points the spline meets to 1e-09 of the lift"),
    "interior too close for its values": (dict(POLY, start=[0.0, 0.0, 0.0, 0.0], end=[20.0, 0.0, 0.0, 0.0],
                                               interior=[[60.0, 10.0], [60.01, 15.0], [60.02, 10.0], [60.03, 15.0]]),
                                          "cams.c.segments[0].interior", "a polynomial meets to 1e-09 of the lift"),
    "even degree": (dict(BSPLINE, degree=4), "cams.c.segments[0].degree", "3, 5 or 7"),
    "end conditions of the wrong degree": (dict(BSPLINE, lift_mm=None, degree=3, start=[0.0, 0.0, 0.0], end=[20.0, 0.0, 0.0]),
                                           "cams.c.segments[0].start", "2 values (s and 1 derivative) for degree 3"),
    "bspline start without end": (dict(BSPLINE, lift_mm=None, start=[0.0, 0.0, 0.0]), "cams.c.segments[0].end", "both ends"),
    "bspline without a lift": (dict(BSPLINE, lift_mm=None, points=[[60.0, 5.0]]), "cams.c.segments[0].lift_mm", "a lift"),
    "lift disagreeing with start/end": (dict(BSPLINE, lift_mm=19.0, start=[0.0, 0.0, 0.0], end=[20.0, 0.0, 0.0]),
                                        "cams.c.segments[0].lift_mm", "end[0] - start[0] = 20"),
    "points on a cycloidal": ({"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0, "points": [[60.0, 10.0]]},
                              "cams.c.segments[0].points", "only for bspline"),
    "degree on a polynomial": (dict(POLY, degree=5), "cams.c.segments[0].degree", "only for bspline"),
    "interior on a bspline": (dict(BSPLINE, interior=[[60.0, 10.0]]), "cams.c.segments[0].interior", "only for polynomial"),
    "interior outside the span": (dict(POLY, interior=[[120.0, 10.0]]), "cams.c.segments[0].interior[0]", "0 < position < 120 deg"),
    "interior twice at one position": (dict(POLY, interior=[[60.0, 10.0], [60.0, 10.0, 0.1]]), "cams.c.segments[0].interior[1]",
                                       "increasing order"),
    "interior of one number": (dict(POLY, interior=[[60.0]]), "cams.c.segments[0].interior[0]", "2 to 4 numbers"),
    "too many conditions": (dict(POLY, start=[0.0, 0.0, 0.0, 0.0], end=[20.0, 0.0, 0.0, 0.0],
                                 interior=[[20.0, 1.0, 0.1, 0.0], [50.0, 6.0, 0.2, 0.0], [80.0, 14.0, 0.2, 0.0]]),
                            "cams.c.segments[0].interior", "at most 16"),
}


def _run_refused(scene, key, why, tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(scene_toml(scene))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert f"'{key}'" in err and why in err, err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").rglob("*"))


@pytest.mark.parametrize("case", REFUSED)
def test_bad_spline_and_interior_input_is_refused_naming_the_key(case, tmp_path, capsys):
    first, key, why = REFUSED[case]
    _run_refused(_plate({k: v for k, v in first.items() if v is not None}), key, why, tmp_path, capsys)


def test_half_turn_program_refuses_points(tmp_path, capsys):
    scene = {"output": {"formats": ["dxf"]}, "cams": {"c": {
        "kind": "motion_law", "form": "constant_breadth", "follower": "yoke", "half_turn": True, "base_radius_mm": 40.0,
        "face_half_length_mm": 30.0,
        "segments": [{"law": "bspline", "span_deg": 120.0, "lift_mm": 10.0, "points": [[60.0, 5.0]]}, {"law": "dwell", "span_deg": 60.0}]}}}
    _run_refused(scene, "cams.c.segments[0].law", "half_turn", tmp_path, capsys)


def _profile_dxf(first: dict, tmp_path, name: str) -> str:
    path = tmp_path / f"{name}.toml"
    path.write_text(scene_toml(_plate(first)))
    assert main(["run", str(path), "-o", str(tmp_path / name)]) in (0, 1)
    (dxf,) = (tmp_path / name).rglob("c.dxf")
    return dxf.read_text()


@pytest.mark.parametrize("key, before, after", [
    ("points", dict(BSPLINE, points=[[60.0, 10.0]]), dict(BSPLINE, points=[[60.0, 11.0]])),
    ("degree", dict(BSPLINE, points=[[40.0, 4.0], [80.0, 16.0]]), dict(BSPLINE, points=[[40.0, 4.0], [80.0, 16.0]], degree=7)),
    ("interior", dict(POLY, interior=[[60.0, 10.0]]), dict(POLY, interior=[[60.0, 10.0, 0.2]])),
])
def test_each_new_key_changes_the_profile(key, before, after, tmp_path):
    """Nothing silent: each key changes the profile its documentation says it changes."""
    assert _profile_dxf(before, tmp_path, "a") != _profile_dxf(after, tmp_path, "b"), key
