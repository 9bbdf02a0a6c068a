"""Blends into and out of constant velocity that need not start from rest (issue 26, item 1).

A ``velocity_blend`` segment takes the velocity, acceleration and jerk where its neighbours end and
start.  Outside references: the program evaluated on both sides of each join (not its join
metadata); the closed form derived by hand for a blend between two constant velocities without a
lift (its velocity ramps as the 3-4-5 polynomial, V0 + (V1 - V0)(10 u^3 - 15 u^4 + 6 u^5), so its
lift is the mean velocity times the span); 8th-order central finite differences.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from camgen.cli import main
from camgen.errors import ParameterError
from camgen.synthesis.laws import MotionProgram, Segment
from helpers import scene_toml

D = math.radians
PI = math.pi
FD8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
DELTA = 1e-9  # rad either side of a join


def sides(program, angle):
    """(s, v, a, j) just before and just after ``angle`` (rad), from the program's values."""
    left = [x[0] for x in program(np.array([angle - DELTA]))]
    right = [x[0] for x in program(np.array([angle + DELTA]))]
    return np.array(left), np.array(right)


def measured_continuity(program, angle):
    """Highest order whose jump across ``angle`` is below 1e-6 of that order's peak over the turn."""
    theta = np.linspace(0.0, 2 * PI, 7201)
    peaks = [max(1.0, float(np.abs(x).max())) for x in program(theta)]
    left, right = sides(program, angle)
    for n in range(1, 4):
        if abs(right[n] - left[n]) > 1e-6 * peaks[n]:
            return n - 1
    return 3


def dwell_blend_cv_blend_dwell(lift_blend=None):
    """Dwell 60, blend 30, constant velocity 30 mm over 120 deg, blend 30, dwell 30, 3-4-5 return 90."""
    segs = [Segment("dwell", D(60)), Segment("velocity_blend", D(30), lift_blend), Segment("constant_velocity", D(120), 30.0),
            Segment("velocity_blend", D(30), lift_blend)]
    blend_lift = 2 * (30.0 / D(120) * D(30) / 2 if lift_blend is None else lift_blend)
    return MotionProgram(segs + [Segment("dwell", D(30)), Segment("poly345", D(90), -(30.0 + blend_lift))])


def test_dwell_blend_constant_velocity_blend_dwell_is_continuous_up_to_jerk():
    program = dwell_blend_cv_blend_dwell()
    for angle in (D(60), D(90), D(210), D(240)):
        assert measured_continuity(program, angle) == 3, math.degrees(angle)
    # the program's own join report agrees (and the 3-4-5 return's jerk jumps against the dwells)
    assert [(round(math.degrees(j.angle), 6), j.continuity) for j in program.joins()] == [
        (0.0, 2), (60.0, 3), (90.0, 3), (210.0, 3), (240.0, 3), (270.0, 2)]


def test_blend_ends_have_the_requested_velocities():
    """The constant-velocity segment's velocity is 30 mm / 120 deg; each blend meets it at one end
    and rest (the dwell's) at the other, with zero acceleration and jerk."""
    program = dwell_blend_cv_blend_dwell()
    vc = 30.0 / D(120)
    for angle, left_v, right_v in ((D(60), 0.0, 0.0), (D(90), vc, vc), (D(210), vc, vc), (D(240), 0.0, 0.0)):
        left, right = sides(program, angle)
        assert left[1] == pytest.approx(left_v, abs=1e-7 * vc) and right[1] == pytest.approx(right_v, abs=1e-7 * vc)
        assert abs(left[2]) <= 1e-6 and abs(right[2]) <= 1e-6


def test_blend_between_two_speeds_is_the_345_velocity_ramp():
    """Constant velocity 10 mm over 60 deg, blend over 40 deg, constant velocity 30 mm over 60 deg:
    the blend's velocity is V0 + (V1 - V0)(10 u^3 - 15 u^4 + 6 u^5) (hand-derived: the lowest-degree
    blend meeting v, a = 0, j = 0 at both ends) and its lift (V0 + V1)/2 times the span."""
    v0, v1, span = 10.0 / D(60), 30.0 / D(60), D(40)
    blend = Segment("velocity_blend", span)
    segs = [Segment("constant_velocity", D(60), 10.0), blend, Segment("constant_velocity", D(60), 30.0)]
    lift = 10.0 + 30.0 + (v0 + v1) / 2 * span
    program = MotionProgram(segs + [Segment("velocity_blend", D(60)), Segment("dwell", D(40)),
                                    Segment("velocity_blend", D(100), -lift - v1 * D(60) / 2)])
    assert program.segments[1].lift == pytest.approx((v0 + v1) / 2 * span, rel=1e-12)
    u = np.linspace(0.0, 1.0, 201)[:-1]
    v = program(D(60) + u * span)[1]
    assert np.abs(v - (v0 + (v1 - v0) * (10 * u**3 - 15 * u**4 + 6 * u**5))).max() <= 1e-9 * v1
    for angle in np.cumsum([0.0] + [D(a) for a in (60, 40, 60, 60, 40)]):
        assert measured_continuity(program, float(angle)) == 3, math.degrees(angle)
    left, right = sides(program, D(100))
    assert left[1] == pytest.approx(v1, rel=1e-7) and right[1] == pytest.approx(v1, rel=1e-7)


def test_blend_with_a_given_lift_and_neighbours_not_at_rest():
    """A blend from the end of a polynomial that arrives with velocity and acceleration (not rest)
    into a constant velocity, with its lift given: s(end) is the lift and the joins stay continuous
    up to jerk (the polynomial's jerk at its end included)."""
    poly = Segment("polynomial", D(80), start=(0.0, 0.0, 0.0), end=(8.0, 12.0, -20.0))
    blend = Segment("velocity_blend", D(40), 9.0)
    cv = Segment("constant_velocity", D(100), 15.0)
    program = MotionProgram([poly, blend, cv, Segment("velocity_blend", D(40)), Segment("dwell", D(20)),
                             Segment("poly345", D(80), -(8 + 9 + 15 + 15.0 / D(100) * D(40) / 2))])
    assert program.segments[1].lift == 9.0
    left, right = sides(program, D(80))
    assert right[1] == pytest.approx(12.0, rel=1e-7) and right[2] == pytest.approx(-20.0, rel=1e-6)
    for angle in (D(80), D(120), D(220), D(260)):
        assert measured_continuity(program, angle) == 3, math.degrees(angle)
    assert program(np.array([D(120) - 1e-12]))[0][0] == pytest.approx(8.0 + 9.0, abs=1e-9)


def test_blend_derivatives_against_finite_differences():
    program = dwell_blend_cv_blend_dwell(lift_blend=4.0)
    law = program.segments[1].shape
    h = 2e-4
    tau = np.linspace(5 * h, 1 - 5 * h, 1001)
    vals = law.evaluate(tau)
    for n in range(3):
        numeric = sum(c * law.evaluate(tau + k * h)[n] for c, k in zip(FD8, range(-4, 5)) if c) / h
        assert np.abs(numeric - vals[n + 1]).max() <= 2e-7 * max(1.0, float(np.abs(vals[n + 1]).max())), n


def test_a_blend_between_blends_is_refused():
    segs = [Segment("dwell", D(60)), Segment("velocity_blend", D(30)), Segment("velocity_blend", D(30)), Segment("dwell", D(240))]
    with pytest.raises(ParameterError, match=r"segments\[1\]\.law"):
        MotionProgram(segs)


def _scene(segments, **cam):
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {"kind": "motion_law", "base_radius_mm": 60.0, "roller_radius_mm": 10.0,
                                                           "segments": segments, **cam}}}


PROGRAM = [{"law": "dwell", "span_deg": 60.0}, {"law": "velocity_blend", "span_deg": 30.0},
           {"law": "constant_velocity", "span_deg": 120.0, "lift_mm": 30.0}, {"law": "velocity_blend", "span_deg": 30.0},
           {"law": "dwell", "span_deg": 30.0}, {"law": "poly345", "span_deg": 90.0, "lift_mm": -37.5}]


def test_blend_program_runs_and_a_roller_follows_it(tmp_path):
    """The scene form: a roller follower (refused at a velocity jump) is accepted, the program is
    written (exit 0), and the DXF has its profile."""
    path = tmp_path / "s.toml"
    path.write_text(scene_toml(_scene(PROGRAM)))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 0
    assert any((tmp_path / "out").rglob("c.dxf"))
    (report,) = (tmp_path / "out").rglob("report.json")
    cam = json.loads(report.read_text())["cams"]["c"]
    # the lift each blend found, reported: half the constant velocity (30 mm / 120 deg) times 30 deg
    assert [s.get("lift_mm") for s in cam["figures"]["segments"]][1:4] == [pytest.approx(3.75, rel=1e-12), 30.0, pytest.approx(3.75, rel=1e-12)]
    joins = {c["name"]: c for c in cam["checks"]}["law_joins"]
    assert joins["value"] == 2, joins  # only the 3-4-5 return's jerk steps (at 270 and 0 deg): the blends join smoothly


@pytest.mark.parametrize("segments, key, why", [
    ([PROGRAM[0], PROGRAM[1], dict(PROGRAM[1]), PROGRAM[2], PROGRAM[3], PROGRAM[4], dict(PROGRAM[5], span_deg=60.0)],
     "cams.c.segments[1].law", "between two segments of other laws"),
    ([PROGRAM[0], dict(PROGRAM[1], start=[0.0, 0.0, 0.0], end=[3.75, 0.0, 0.0])] + PROGRAM[2:],
     "cams.c.segments[1].start", "only for polynomial or bspline"),
    ([PROGRAM[0], dict(PROGRAM[1], blend=0.2)] + PROGRAM[2:], "cams.c.segments[1].blend", "only for constant_velocity"),
])
def test_bad_blends_are_refused_naming_the_key(segments, key, why, tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(scene_toml(_scene(segments)))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert f"'{key}'" in err and why in err, err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").rglob("*"))
