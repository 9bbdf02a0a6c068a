"""The dynamics' shortcuts of issue 28 item 6, each against what it replaces or an independent fact:
the finiteness check of the kinematics' arrays (their least and largest values: a nan is the least), the periodic trapezoid weights made in place, and the force terms :func:`analyse`
keeps for :func:`spring_hints` (which makes them again for other kinematics or another train)."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from camgen import dynamics as dy
from camgen.errors import ParameterError
from camgen.synthesis.laws import MotionProgram
from camgen.synthesis.laws import Segment as MotionSegment

N = 720
THETA = 2 * math.pi * np.arange(N) / N


def _kin(s: np.ndarray | None = None, **extra) -> dy.Kinematics:
    program = MotionProgram([MotionSegment("cycloidal", math.radians(120), 20.0), MotionSegment("dwell", math.radians(60), 0.0),
                             MotionSegment("cycloidal", math.radians(120), -20.0), MotionSegment("dwell", math.radians(60), 0.0)])
    s0, ds, d2s, _ = program(THETA)
    return dy.Kinematics(THETA, s0 if s is None else s, ds, d2s, np.zeros(N), np.full(N, 40.0), 10.0, **extra)


def test_finite_values_whose_sum_overflows_are_accepted_and_a_nan_or_inf_is_refused():
    huge = np.full(N, 1e308)  # every value finite (their sum is not)
    assert np.array_equal(_kin(s=huge).s, huge)
    for bad in (math.nan, math.inf, -math.inf):
        s = np.zeros(N)
        s[17] = bad
        with pytest.raises(ParameterError, match="non-finite value at sample 17"):
            _kin(s=s)
    # radii of curvature may be +-inf (straight flanks) but not nan: +inf and -inf sum to nan
    rho = np.full(N, 40.0)
    rho[3], rho[5] = math.inf, -math.inf
    kin = dy.Kinematics(THETA, *(_kin().s, _kin().ds, _kin().d2s), np.zeros(N), rho, 10.0)
    assert kin.rho_cam[3] == math.inf and kin.rho_cam[5] == -math.inf
    rho[7] = math.nan
    with pytest.raises(ParameterError, match="non-finite value at sample 7"):
        dy.Kinematics(THETA, _kin().s, _kin().ds, _kin().d2s, np.zeros(N), rho, 10.0)


@pytest.mark.parametrize("seed", range(4))
def test_the_trapezoid_weights_are_the_closed_turns_half_gaps(seed):
    """Bit for bit the weights as they were made before (np.append / np.insert, verbatim), on
    uneven grids; they add up to the turn (2 pi) and integrate cos^2 to pi."""
    rng = np.random.default_rng(seed)
    theta = np.sort(rng.uniform(0.0, 2 * math.pi, 50 + 100 * seed))
    theta = theta[np.diff(theta, prepend=-1.0) > 0]
    result = dy.analyse(dy.Kinematics(theta, np.zeros_like(theta), np.zeros_like(theta), np.zeros_like(theta),
                                      np.zeros_like(theta), np.full_like(theta, 40.0), 10.0), dy.FollowerTrain(mass=1.0), 100.0)
    nxt = np.append(theta[1:], theta[0] + 2 * math.pi)
    prv = np.insert(theta[:-1], 0, theta[-1] - 2 * math.pi)
    assert np.array_equal(result.weights, 0.5 * (nxt - prv))
    assert math.isclose(float(np.sum(result.weights)), 2 * math.pi, rel_tol=1e-12)
    dense = dy.analyse(_kin(), dy.FollowerTrain(mass=1.0), 100.0)
    assert math.isclose(float(np.sum(dense.weights * np.cos(THETA) ** 2)), math.pi, rel_tol=1e-12)


def test_the_spring_hints_from_analyses_terms_are_those_made_again():
    """The least preload and rate quoted from the terms analyse kept are those made afresh (the
    result without them), and hints for another train are that train's, not the kept ones."""
    kin = _kin()
    train = dy.FollowerTrain(mass=1.5, spring_rate=1.0, preload=10.0, gravity=0.0)
    result = dy.analyse(kin, train, 900.0, jump_margin=5.0)
    assert result.analysed is not None and result.analysed[0] is kin
    kept = dy.spring_hints(result, kin)
    assert kept[0] is not None and kept[2] is not None  # the spring is too weak at this speed: both hints quoted
    assert kept == dy.spring_hints(replace(result, analysed=None), kin)
    assert kept == dy.spring_hints(result, _kin())  # other (equal) kinematics: made again, the same
    heavier = dy.FollowerTrain(mass=3.0, spring_rate=1.0, preload=10.0, gravity=0.0)
    heavy = dy.analyse(kin, heavier, 900.0, jump_margin=5.0)
    assert dy.spring_hints(heavy, kin) != kept  # a heavier follower needs a stronger spring
    # terms kept for another train (the heavier one) are not used for this one's hints
    assert dy.spring_hints(replace(result, analysed=heavy.analysed), kin) == kept


@pytest.mark.parametrize("seed", range(6))
def test_the_least_positive_root_is_the_least_of_the_elementwise_roots(seed):
    """The jump speed's root (issue 28 item 6: no arrays of the non-positive roots) is bit for bit
    the least of :func:`smallest_positive_root`'s, and a root: numpy.roots of each quadratic."""
    rng = np.random.default_rng(seed)
    n = 200
    a = rng.uniform(0.1, 10.0, n)
    b = rng.choice([-1.0, 0.0, 1.0], n) * rng.uniform(0.0, 5.0, n)
    c = rng.choice([-1.0, 0.0, 1.0], n) * rng.uniform(0.0, 5.0, n)  # c > 0 with b < 0: two roots or none (disc < 0)
    if seed == 5:  # none: Q grows with speed everywhere
        b, c = np.abs(b), np.abs(c)
    least = dy._least_positive_root(a, b, c)
    assert least == float(np.min(dy.smallest_positive_root(a, b, c)))
    roots = [r.real for i in range(n) for r in np.roots([c[i], b[i], a[i]]) if abs(r.imag) < 1e-12 and r.real > 0]
    assert least == (pytest.approx(min(roots), rel=1e-9) if roots else math.inf)


@pytest.mark.parametrize("seed", range(4))
def test_the_least_spring_rate_is_the_one_made_before(seed):
    """The least preload and rate (issue 28 item 6: a masked maximum, no np.where passes) bit for
    bit as made before (its np.where operations, verbatim), on random force terms with the lowest
    position, lifts within the tolerance and samples the spring cannot help (seed 3: none)."""
    rng = np.random.default_rng(seed)
    n = 300
    lift = np.abs(rng.normal(0.0, 5.0, n))
    lift[rng.integers(0, n, 20)] = 0.0
    lift[rng.integers(0, n, 5)] = 1e-12
    a, damping, inertia = rng.normal(20.0, 10.0, n), rng.normal(0.0, 3.0, n), rng.normal(0.0, 8.0, n)
    if seed == 3:
        a = np.where(lift <= 1e-9, 100.0, a)  # where the spring is at its lowest the force suffices
    projection = rng.uniform(0.5, 1.0, n)
    train = dy.FollowerTrain(spring_rate=1.5, preload=12.0)
    need = 10.0 * projection - (damping + inertia)
    min_preload = max(0.0, float(np.max(need - (a - train.spring_preload))))
    short = need - (a - train.spring_rate * lift)
    lifted = lift > 1e-9
    if np.any((short > 0) & ~lifted):
        expected = (min_preload, None)
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(lifted & (short > 0), short / np.where(lifted, lift, 1.0), 0.0)
        expected = (min_preload, float(np.max(ratio)))
    got = dy._required_spring(a, damping, inertia, projection, 10.0, train, lift, 1e-9)
    assert got == expected
    assert (got[1] is None) == (seed != 3)


@pytest.mark.parametrize("rpm", [37.0, 300.0, 1234.5, 4000.0])
def test_the_peaks_and_the_checks_where_are_those_of_the_arrays(rpm):
    """The power peak made from the torque peak (issue 28 item 6) is bit for bit the largest
    |power| of the array; the torque peak's sample is numpy's first argmax; each check's cam angles
    are the runs of its failing samples (a limit that some samples pass) or the extreme's angle."""
    from camgen.checks import run_ends, where_degrees
    from camgen.kinds.dynamics import dynamics_checks

    material = dy.ContactMaterial(width=10.0, allowable_stress=None)
    result = dy.analyse(_kin(), dy.FollowerTrain(mass=0.4, spring_rate=1.5, preload=40.0, damping=10.0), rpm, material,
                        jump_margin=10.0)
    assert result.power_peak == float(np.max(np.abs(result.power)))
    assert result.torque_peak == float(np.max(np.abs(result.torque)))
    assert result.torque_peak_index == int(np.argmax(np.abs(result.torque)))
    flipped = replace(result, torque=-result.torque, power=-result.power)  # the peak |torque| a negative one
    assert flipped.torque_peak_index == int(np.argmax(result.torque)) and flipped.torque_peak == result.torque_peak
    torque, stress, force = np.abs(result.torque), result.hertz_stress, result.contact_force
    assert stress is not None
    for scale in (0.5, 1.0, 2.0):  # limits some samples fail, the peak on the limit (passes), all pass
        limit_t, limit_h, margin = scale * result.torque_peak, scale * float(np.max(stress)), float(np.min(force)) / scale
        res = replace(result, jump_margin=margin)
        checks = {c.name: c for c in dynamics_checks(res, res.analysed[0], replace(material, allowable_stress=limit_h), limit_t)}
        expected = {"camshaft_torque": (torque > limit_t, np.argmax(torque)), "hertz_stress": (stress > limit_h, np.argmax(stress)),
                    "jump": (force < margin, np.argmin(force))}
        for name, (bad, i) in expected.items():
            where = run_ends(bad, THETA) if bad.any() else where_degrees(THETA[i])
            assert checks[name].where_deg == where, name
            assert checks[name].passed == (not bad.any()), name


@pytest.mark.parametrize("second", [False, True])
def test_a_pressure_angle_of_90_deg_either_way_is_refused_from_the_bounds_checked(second):
    """The pressure angles' check from the least and largest values the finiteness check found
    (issue 28 item 6): |phi| >= pi/2 at one sample, + or -, is refused naming that sample's angles;
    just below pi/2 is accepted; a cusp (rho 0) is still named first."""
    kin = _kin()
    key = "pressure_angle_2" if second else "pressure_angle"
    extra = {"rho_cam_2": np.full(N, 40.0)} if second else {}
    for bad in (math.pi / 2, -math.pi / 2, 2.0, -3.0):
        phi = np.zeros(N)
        phi[11] = bad
        with pytest.raises(ParameterError, match=f"{math.degrees(bad):.6g} deg at cam angle {math.degrees(THETA[11]):.6g} deg"):
            replace(kin, **{key: phi}, **extra)
    phi = np.zeros(N)
    phi[11], phi[12] = np.nextafter(math.pi / 2, 0.0), -np.nextafter(math.pi / 2, 0.0)
    assert np.array_equal(getattr(replace(kin, **{key: phi}, **extra), key), phi)
    phi[11], rho = math.pi / 2, np.full(N, 40.0)
    rho[3] = 0.0
    with pytest.raises(ParameterError, match="a nonzero radius of curvature"):
        replace(kin, **{key: phi}, rho_cam=rho, **extra)


def test_cam_angles_that_repeat_or_fall_are_refused():
    """The angles' order checked by comparing neighbours (issue 28 item 6: no array of differences):
    a repeated angle or one that falls is refused, angles one ulp apart are accepted."""
    kin = _kin()
    for i, value in ((5, THETA[4]), (5, THETA[3]), (N - 1, THETA[N - 2])):
        theta = THETA.copy()
        theta[i] = value
        with pytest.raises(ParameterError, match="strictly increasing"):
            replace(kin, theta=theta)
    theta = THETA.copy()
    theta[5] = np.nextafter(theta[4], 7.0)
    assert np.array_equal(replace(kin, theta=theta).theta, theta)
