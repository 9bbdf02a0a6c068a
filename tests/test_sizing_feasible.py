"""The sizing search's pass/fail of a trial base radius (issue 28 item 6: a failing design's
advice searches a few radii): ``_feasible`` answers from the extremes alone, without the
measures' cam angles and the violations' sentences; on every follower kind, limits of every kind
(a return limit of its own, Norton's pitch rule, convex and concave radii) and base radii from
undercut to comfortable, it says what ``measure(...).violations(limits)`` says."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.synthesis.followers import FollowerSpec, check_grid
from camgen.synthesis.laws import MotionProgram
from camgen.synthesis.laws import Segment as MotionSegment
from camgen.synthesis.sizing import DesignLimits, _feasible, measure

D = math.radians
LAW = MotionProgram([MotionSegment("cycloidal", D(100), 20.0), MotionSegment("dwell", D(60), 0.0),
                     MotionSegment("poly345", D(120), -20.0), MotionSegment("dwell", D(80), 0.0)])
SWING = MotionProgram([MotionSegment("cycloidal", D(120), D(15)), MotionSegment("dwell", D(60), 0.0),
                       MotionSegment("cycloidal", D(120), -D(15)), MotionSegment("dwell", D(60), 0.0)])
FOLLOWERS = {
    "roller": (lambda b: FollowerSpec("roller", b, roller_radius=8.0, offset=5.0), LAW),
    "knife": (lambda b: FollowerSpec("knife", b), LAW),
    "flat": (lambda b: FollowerSpec("flat", b), LAW),
    "oscillating_roller": (lambda b: FollowerSpec("roller", b, motion="oscillating", roller_radius=8.0, pivot=(110.0, 0.0),
                                                  arm_length=90.0), SWING),
}
LIMITS = [
    DesignLimits(),
    DesignLimits(max_pressure_angle=D(35), max_pressure_angle_return=D(25)),
    DesignLimits(max_pressure_angle=D(45), min_pitch_radius_factor=2.5),
    DesignLimits(max_pressure_angle=D(60), min_convex_radius=15.0, min_concave_radius=30.0),
    DesignLimits(max_pressure_angle=D(85), min_concave_radius=500.0),  # a concave flank fails it alone
]


@pytest.mark.parametrize("kind", sorted(FOLLOWERS))
def test_a_trials_verdict_is_the_measures_violations(kind):
    make, law = FOLLOWERS[kind]
    theta = check_grid(law, D(0.5))
    verdicts = set()
    for limits in LIMITS:
        for base in np.linspace(6.0, 95.0, 12):
            try:
                follower = make(float(base))
            except ParameterError:
                continue
            expected = not measure(follower, law, theta=theta, stress=limits.contact_stress).violations(limits)
            assert _feasible(follower, law, limits, theta) == expected, (kind, limits, base)
            verdicts.add(expected)
    assert verdicts == {True, False}  # the sample has both verdicts
