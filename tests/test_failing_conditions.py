"""camgen.synthesis.followers.failing_conditions (the undercut check's failing conditions, each
screened by one reduction first) against profile_failures' masks with a failing sample (every
sample compared), bit for bit: rollers whose largest r kappa straddles 1 by a few units in the
last place (the roller radius set from the pitch curve's own largest curvature), undercutting and
passing cams, cusps, a translating follower through the axis, knives and flat faces, and a
NaN sample; and the least convex radius with the caller's largest curvature."""
import math

import numpy as np
import pytest

from camgen.kinds.least_radius import least_convex_radius
from camgen.synthesis.followers import FollowerSpec, failing_conditions, kinematics, profile_failures
from camgen.synthesis.laws import MotionProgram, Segment

D = math.radians
THETA = 2.0 * math.pi * np.arange(7200) / 7200


def _law(lift: float, unit: str = "mm") -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(120), lift), Segment("dwell", D(40)), Segment("poly345", D(130), -lift),
                          Segment("dwell", D(70))], unit=unit)


def _same(f: FollowerSpec, k) -> list[str]:
    want = [(r, m) for r, m in profile_failures(f, k) if m.any()]
    got = failing_conditions(f, k)
    assert [r for r, _ in got] == [r for r, _ in want]
    assert all(np.array_equal(a, b) for (_, a), (_, b) in zip(got, want))
    if k.pitch_curvature is not None and f.has_radius:  # the caller's largest curvature
        top = float(k.pitch_curvature.max())
        given = failing_conditions(f, k, top)
        assert [r for r, _ in given] == [r for r, _ in got] and all(np.array_equal(a, b) for (_, a), (_, b) in zip(given, got))
        assert least_convex_radius(k.pitch_curvature, top) == least_convex_radius(k.pitch_curvature)
    return [r for r, _ in got]


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("base", [12.0, 20.0, 30.0, 45.0])
def test_rollers_from_undercut_to_clear(rotation, base):
    law = _law(20.0)
    for roller in (2.0, 8.0, 15.0):
        f = FollowerSpec(kind="roller", base_radius=base, roller_radius=roller, offset=3.0, rotation=rotation)
        _same(f, kinematics(f, law, THETA))


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_a_roller_at_the_undercut_limit_ulp_by_ulp(rotation):
    """The roller radius 1 / max kappa of a pitch curve with a sharp nose (its prime radius kept
    at 40 mm) and its neighbours a few ulps apart: r kappa reaches 1 (the mask's cross >= cube)
    or stays just below; the screen must leave those to the comparison of every sample."""
    law = MotionProgram([Segment("cycloidal", D(70), 25.0), Segment("poly345", D(70), -25.0), Segment("dwell", D(220))], unit="mm")
    probe = FollowerSpec(kind="roller", base_radius=35.0, roller_radius=5.0, rotation=rotation)
    radius = 1.0 / float(kinematics(probe, law, THETA).pitch_curvature.max())
    outcomes = []
    for steps in range(-4, 5):
        r = radius
        for _ in range(abs(steps)):
            r = math.nextafter(r, math.inf if steps > 0 else 0.0)
        for near in (r, r * (1.0 - 5e-13), r * (1.0 - 2e-12)):
            f = FollowerSpec(kind="roller", base_radius=40.0 - near, roller_radius=near, rotation=rotation)
            k = kinematics(f, law, THETA)
            assert k.pitch_curvature.max() * near < 1.0 + 1e-12  # the nose at the limit
            outcomes.append(bool(_same(f, k)))
    assert any(outcomes) and not all(outcomes)  # both sides of the limit met


def test_oscillating_roller_knife_flat_and_the_axis():
    law = _law(20.0)
    osc = FollowerSpec(kind="roller", base_radius=40.0, motion="oscillating", roller_radius=8.0, pivot=(110.0, 40.0), arm_length=95.0)
    assert _same(osc, kinematics(osc, _law(0.2, "rad"), THETA)) == []
    knife = FollowerSpec(kind="knife", base_radius=30.0)
    _same(knife, kinematics(knife, law, THETA))
    flat = FollowerSpec(kind="flat", base_radius=45.0, offset=3.0)
    _same(flat, kinematics(flat, law, THETA))
    # a return deeper than the prime radius: the roller centre reaches the axis (sqrt(Rp^2 - e^2) + s <= 0)
    deep = FollowerSpec(kind="roller", base_radius=10.0, roller_radius=2.0)
    assert "rotation axis" in " ".join(_same(deep, kinematics(deep, _law(-15.0), THETA)))


def test_a_nan_sample_compares_every_sample():
    law = _law(20.0)
    f = FollowerSpec(kind="roller", base_radius=30.0, roller_radius=8.0)
    k = kinematics(f, law, THETA)
    k.pitch_curvature[5] = np.nan  # the screen's reduction is NaN: the masks decide
    k.pitch_measures.cube[5] = 0.0
    k.pitch_measures.cross[5] = 1.0 if f.sigma < 0 else -1.0  # r kappa there: +inf (undercut)
    assert _same(f, k)
