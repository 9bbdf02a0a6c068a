"""The fast paths of the exact envelope, each against a number from outside the code under test.

* the motion program's fast paths (a sorted grid in [0, 2 pi), angles in [-2 pi, 0)) against the
  closed forms of its laws written out here;
* the dense check grid against its definition (np.unique of the grid, the breaks and their
  neighbours, computed here), and its rotation into the cam frame (phasor tables) against numpy's
  cosine and sine of the grid angles;
* the C2 splines of several segments solved as one system against scipy's B-spline interpolant
  with the same knots and end conditions, segment by segment;
* the estimate of max |d4Q/dtheta4| from second differences of d2Q against a curve whose fourth
  derivative is known in closed form;
* the first piece count, from the error bound 5/384 h^4 max|f''''| of a clamped cubic spline
  interpolant (Hall & Meyer 1976), meets fit_tol without a measured refinement round for every
  follower, yet is not wasteful (the measured error is a sizeable part of fit_tol);
* a fit across a dwell shorter than those windows against the envelope of the roller's positions
  built here (least distances by golden-section search), not camgen's kinematics.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.synthesis.followers import (
    BOUND_SPACING,
    CheckGrid,
    FollowerSpec,
    _grid_layout,
    _sixth_derivatives,
    _uniform_knots,
    cam_envelope,
    check_grid,
)
from camgen.synthesis.laws import MotionProgram, Segment

D = math.radians
PI = math.pi
TWO_PI = 2.0 * PI


# --------------------------------------------------------------------------------------------
# The motion program on the grids the envelope uses
# --------------------------------------------------------------------------------------------
def program_and_closed_forms():
    """A program whose velocity jumps (constant velocity after a dwell) and whose jerk jumps, with
    its s and s' written out here from the textbook formulas (Norton, ch. 8)."""
    program = MotionProgram([Segment("cycloidal", D(120), 20.0), Segment("dwell", D(40)), Segment("constant_velocity", D(80), -12.0),
                             Segment("poly345", D(60), -8.0), Segment("dwell", D(60))])

    def closed(theta):
        t = np.mod(theta, TWO_PI)
        x1, x3, x4 = t / D(120), (t - D(160)) / D(80), (t - D(240)) / D(60)
        conds = [t < D(120), t < D(160), t < D(240), t < D(300), t >= D(300)]
        s = np.select(conds, [20 * (x1 - np.sin(2 * PI * x1) / (2 * PI)), 20 + 0 * t, 20 - 12 * x3,
                              8 - 8 * (10 * x4**3 - 15 * x4**4 + 6 * x4**5), 0 * t])
        v = np.select(conds, [20 / D(120) * (1 - np.cos(2 * PI * x1)), 0 * t, -12 / D(80) + 0 * t,
                              -8 / D(60) * (30 * x4**2 - 60 * x4**3 + 30 * x4**4), 0 * t])
        return s, v

    return program, closed


def test_program_on_the_check_grid_and_on_negative_angles_against_closed_forms():
    """The sorted check grid (breaks and their neighbours included: at a break the following
    piece) and the angles -t of a ccw envelope (in [-2 pi, 0], the exact ends included) give the
    textbook values; so do angles far outside one turn, and the same angles shuffled (the breaks
    included) and as a 2-D array."""
    program, closed = program_and_closed_forms()
    grid = check_grid(program)
    assert np.all(np.diff(grid) > 0)
    shuffled = np.random.default_rng(5).permutation(np.concatenate([grid, program.breaks, grid[::7] - 3 * TWO_PI]))
    for theta in (grid, -grid, grid - TWO_PI, np.array([0.0, -0.0, -1e-300, -TWO_PI, TWO_PI, -D(160), D(160)]), grid + 14 * PI,
                  shuffled, shuffled[: shuffled.size // 3 * 3].reshape(-1, 3)):
        s, v, _, _ = program(theta)
        ref_s, ref_v = closed(theta)
        assert np.max(np.abs(s - ref_s)) <= 1e-12 * 20, theta[:3]
        assert np.max(np.abs(v - ref_v)) <= 1e-11 * 20, theta[:3]
    # at the break 160 deg the velocity jumps: the following piece's (constant velocity)
    assert program(np.array([D(160), D(160) - TWO_PI]))[1] == pytest.approx([-12 / D(80)] * 2, rel=1e-12)


def test_check_grid_is_the_uniform_grid_with_the_breaks_and_their_neighbours():
    rng = np.random.default_rng(5)

    class Law:
        breaks = np.zeros(0)

    for trial in range(300):
        step = D(float(rng.choice([0.05, 0.3, 1.0, 45.0])))
        n = max(8, math.ceil(TWO_PI / step))
        special = np.array([0.0, (n // 3) * (TWO_PI / n), TWO_PI - 1e-9, (n // 2) * (TWO_PI / n) + 1e-9])  # on the grid, at its ends
        brk = np.concatenate([rng.uniform(0.0, TWO_PI, int(rng.integers(0, 9))), special[: int(rng.integers(0, 5))]])
        Law.breaks = np.sort(brk)
        reference = np.unique(np.mod(np.concatenate([np.arange(n) * (TWO_PI / n), brk, brk - 1e-9, brk + 1e-9]), TWO_PI))
        assert np.array_equal(check_grid(Law, step), reference), trial


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_check_grid_rotation_is_the_cosine_and_sine_of_the_grid_angles(rotation):
    """exp(-i sigma theta) on the check grid from two short tables (angle addition) is numpy's
    cos(theta) -+ i sin(theta) within a few ulps, whatever the step and wherever the breaks lie
    (on the grid, between grid angles, none)."""
    rng = np.random.default_rng(17)
    follower = FollowerSpec("knife", 40.0, rotation=rotation)
    sigma = 1.0 if rotation == "ccw" else -1.0

    class Law:
        breaks = np.zeros(0)

    for trial in range(60):
        step = D(float(rng.choice([0.05, 0.07, 0.3, 1.0, 45.0])))
        n = max(8, math.ceil(TWO_PI / step))
        Law.breaks = np.sort(np.concatenate([rng.uniform(0.0, TWO_PI, int(rng.integers(0, 6))),
                                             [(n // 3) * (TWO_PI / n)] * int(rng.integers(0, 2))]))
        size, added = _grid_layout(Law, step)
        grid = CheckGrid(Law, size, added)
        theta = grid.theta
        assert np.array_equal(theta, check_grid(Law, step)) and size == n
        assert np.array_equal(theta[grid.added_at], added)
        got = grid.to_cam(follower.sigma)
        assert np.max(np.abs(got - (np.cos(theta) - 1j * sigma * np.sin(theta)))) <= 2e-15, trial


# --------------------------------------------------------------------------------------------
# The knots of several segments at once
# --------------------------------------------------------------------------------------------
def test_uniform_knots_of_several_segments_are_numpys_linspaces():
    """Four segments of different spans and piece counts (2 to 57) laid out together: each
    segment's knots are np.linspace(lo, hi, count + 1), its first and last indices delimit them."""
    lo = np.array([0.0, 0.7, 1.9, 2.0])
    hi = np.array([0.7, 1.9, 2.0, 6.1])
    count = np.array([9, 57, 2, 23])
    x, first, last = _uniform_knots(lo, hi, count)
    assert x.size == int((count + 1).sum())
    for k in range(4):
        assert np.array_equal(x[first[k]: last[k] + 1], np.linspace(lo[k], hi[k], count[k] + 1)), k


# --------------------------------------------------------------------------------------------
# The sixth derivative from the check data, and the first piece count
# --------------------------------------------------------------------------------------------
def test_sixth_derivative_estimate_against_a_closed_form_curve():
    """Q = a_k e^{i theta} + b_k e^{3 i theta} with other (a_k, b_k) between each pair of breaks:
    |d6Q/dtheta6| = |a_k e^{i theta} + 729 b_k e^{3 i theta}|, its largest value per interval
    sampled densely here; the estimate must not mix the intervals (d2Q jumps at the breaks)."""
    brk = np.array([0.0, D(100), D(130), D(250)])
    coef = [(40.0, 0.5), (55.0, -1.2), (30.0, 0.1), (70.0, 2.0)]

    class Law:
        breaks = brk

    theta = np.arange(720) * BOUND_SPACING  # the uniform part of the coarse grid
    k = np.searchsorted(brk, theta, side="right") - 1
    a = np.array([c[0] for c in coef])[k]
    b = np.array([c[1] for c in coef])[k]
    d2 = -a * np.exp(1j * theta) - 9 * b * np.exp(3j * theta)
    estimate = _sixth_derivatives(theta, d2[None], brk)
    ends = np.append(brk, TWO_PI)
    for j, (aj, bj) in enumerate(coef):
        # the differences use five grid angles BOUND_SPACING apart inside the interval: the largest
        # value lies between the maximum over the interval without its last 4 spacings at each end and
        # the maximum over the whole interval, up to the error of the fourth difference of e^{i w theta}:
        # (2 sin(w h / 2) / (w h))^4 - 1 ~ -(w h)^2 / 6 for the highest harmonic w = 3 here
        h = BOUND_SPACING
        slack = 2 * (3 * h) ** 2 / 6
        dense = np.linspace(ends[j], ends[j + 1], 200_001)
        d6 = np.abs(aj * np.exp(1j * dense) + 729 * bj * np.exp(3j * dense))
        inner = d6[(dense > ends[j] + 4 * h) & (dense < ends[j + 1] - 4 * h)]
        assert np.max(inner) * (1 - slack) <= estimate[j] <= np.max(d6) * (1 + slack), j


FOLLOWERS = {
    "roller_offset": dict(kind="roller", base_radius=40.0, roller_radius=10.0, offset=12.0),
    "flat": dict(kind="flat", base_radius=80.0, offset=3.0),
    "knife": dict(kind="knife", base_radius=40.0, offset=-6.0),
    "osc_roller": dict(kind="roller", base_radius=40.0, motion="oscillating", roller_radius=8.0, pivot=(110.0, 40.0), arm_length=95.0),
    "osc_flat": dict(kind="flat", base_radius=60.0, motion="oscillating", pivot=(130.0, 50.0), face_offset=20.0, lift_turn="cw"),
}
#: lift (mm) or swing (deg) of each follower's program: as much as its base radius allows
LIFT = {"roller_offset": 16.0, "flat": 16.0, "knife": 16.0, "osc_roller": 12.0, "osc_flat": 7.0}


class _Counted:
    """A law that counts its evaluations (the envelope evaluates it once on the coarse grid, once on
    the dense check grid when that is needed (a flat face's checks; a roller or knife cam the coarse
    screening does not clear) and once per round of spline fitting)."""

    def __init__(self, law):
        self.law, self.calls = law, 0
        self.breaks, self.break_continuity = law.breaks, law.break_continuity

    def __call__(self, theta):
        self.calls += 1
        return self.law(theta)


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("name", sorted(FOLLOWERS))
@pytest.mark.parametrize("fit_tol", [1e-7, 1e-4])
def test_first_piece_count_meets_fit_tol_in_one_round(name, rotation, fit_tol):
    kind = FOLLOWERS[name]
    oscillating = kind.get("motion") == "oscillating"
    unit, lift = ("rad", D(LIFT[name])) if oscillating else ("mm", LIFT[name])
    law = _Counted(MotionProgram([Segment("modified_sine", D(110), lift), Segment("dwell", D(50)),
                                  Segment("double_harmonic", D(90), -lift), Segment("dwell", D(110))], unit=unit))
    cam = cam_envelope(FollowerSpec(**kind, rotation=rotation), law, fit_tol=fit_tol)
    # the coarse grid, the dense grid (a flat face only: these rollers and knives are clear of their
    # limits) and one round of spline fitting: no measured refinement
    assert law.calls == (3 if kind["kind"] == "flat" else 2)
    assert cam.fit_error <= fit_tol
    # the bound is not wasteful: the error reached is a sizeable part of fit_tol (pieces ~ error^(-1/6):
    # 0.3 of fit_tol is 1.2 times the pieces that would reach fit_tol itself)
    assert cam.fit_error >= 0.3 * fit_tol


# --------------------------------------------------------------------------------------------
# The checks without the full kinematics, and the kinematics made on first use
# --------------------------------------------------------------------------------------------
def _pitch_by_brute_force(f: FollowerSpec, law, theta: np.ndarray) -> np.ndarray:
    """Pitch curve points (complex, cam frame) of a centred or offset translating roller written
    out here: the roller centre (e, sqrt(Rp^2 - e^2) + s) turned back by the cam angle."""
    s = law(theta)[0]
    centre = f.offset + 1j * (math.sqrt(f.prime_radius**2 - f.offset**2) + s)
    return centre * np.exp(-1j * f.sigma * theta)


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("base, roller, offset", [(10.0, 20.0, 0.0), (20.0, 12.0, 6.0), (25.0, 15.0, -8.0), (30.0, 4.0, -5.0)])
def test_undercut_ranges_against_finite_difference_curvature_of_the_pitch_curve(rotation, base, roller, offset):
    """The undercut check reads only the law and the pitch curve's speed and curvature; here the
    curvature comes from central differences of pitch points computed independently, and the
    angles where r kappa >= 1 must be the failed angles wherever the two are not within 1e-5 of
    the limit."""
    law = MotionProgram([Segment("cycloidal", D(40), 18.0), Segment("dwell", D(30)), Segment("poly345", D(50), -18.0),
                         Segment("dwell", D(240))])
    f = FollowerSpec("roller", base, roller_radius=roller, offset=offset, rotation=rotation)
    env = cam_envelope(f, law, report_only=True)
    theta = env.grid.theta
    step = 1e-4
    p0, pp, pm = (_pitch_by_brute_force(f, law, theta + d) for d in (0.0, step, -step))
    d1, d2 = (pp - pm) / (2 * step), (pp - 2 * p0 + pm) / step**2
    # the contour runs counter-clockwise, against theta for a ccw cam: curvature -sigma (P' x P'') / |P'|^3
    kappa = -f.sigma * (d1.real * d2.imag - d1.imag * d2.real) / np.abs(d1) ** 3
    expected = roller * kappa >= 1.0
    failed = np.zeros(theta.size, dtype=bool)
    for item in env.failures:
        assert item["reason"].startswith("undercut"), item["reason"]
        for a, b in item["ranges_deg"]:
            failed |= (np.degrees(theta) >= a - 1e-9) & (np.degrees(theta) <= b + 1e-9) if a <= b else \
                (np.degrees(theta) >= a - 1e-9) | (np.degrees(theta) <= b + 1e-9)
    clear = np.abs(roller * kappa - 1.0) > 1e-5
    assert expected.any() == (base != 30.0)  # three of the cases undercut (one in two places), one does not
    assert np.array_equal(failed[clear], expected[clear])
    assert env.ok == (not expected.any())


@pytest.mark.parametrize("name", sorted(FOLLOWERS))
def test_check_data_is_made_on_first_use_and_is_the_public_kinematics(name):
    """A roller or knife envelope does not make its dense Kinematics until asked (the profile does
    not need them); when asked they are camgen.synthesis.followers.kinematics at the grid angles
    (cosines and sines computed directly there instead of the grid's phasor products)."""
    from camgen.synthesis.followers import kinematics

    kind = FOLLOWERS[name]
    oscillating = kind.get("motion") == "oscillating"
    unit, lift = ("rad", D(LIFT[name])) if oscillating else ("mm", LIFT[name])
    law = MotionProgram([Segment("modified_sine", D(110), lift), Segment("dwell", D(50)),
                         Segment("double_harmonic", D(90), -lift), Segment("dwell", D(110))], unit=unit)
    f = FollowerSpec(**kind)
    env = cam_envelope(f, law)
    assert ("data" in vars(env)) == (f.kind == "flat")  # a flat face's checks need its kinematics
    data = env.data
    assert env.data is data
    ref = kinematics(f, law, env.grid.theta)
    scale = f.prime_radius
    assert np.max(np.abs(data.contact_point - ref.contact_point)) <= 1e-12 * scale
    assert np.max(np.abs(data.pressure_angle - ref.pressure_angle)) <= 1e-12
    assert np.max(np.abs(data.profile_curvature - ref.profile_curvature)) <= 1e-12 * np.max(np.abs(ref.profile_curvature))
    assert np.array_equal(data.theta, ref.theta)


@pytest.mark.parametrize("law_name", ["cycloidal", "modified_sine", "modified_trapezoid", "double_harmonic", "modified_cycloidal", "poly345"])
def test_program_on_the_uniform_grid_is_the_program_at_those_angles(law_name):
    """MotionProgram.on_uniform_grid (sines and cosines by angle addition) against the direct
    evaluation of the same program at the grid angles, and the envelope's check data against the
    direct evaluation at its grid angles (breaks and their neighbours included): a few ulps of each
    derivative's peak."""
    program = MotionProgram([Segment(law_name, D(97), 14.0), Segment("dwell", D(41)), Segment(law_name, D(130), -14.0),
                             Segment("dwell", D(92))])
    n = 7200
    grid = np.arange(n) * (TWO_PI / n)
    direct = np.array(program(grid))
    fast = np.array(program.on_uniform_grid(n))
    peak = np.max(np.abs(direct), axis=1)
    assert np.all(np.max(np.abs(fast - direct), axis=1) <= 8e-16 * n**0.5 * peak)
    env = cam_envelope(FollowerSpec("roller", 60.0, roller_radius=10.0), program)
    g = env.grid
    direct = np.array(program(g.theta))
    ours = np.array([g.s, g.ds, g.d2s, g.d3s])
    assert np.all(np.max(np.abs(ours - direct), axis=1) <= 8e-16 * n**0.5 * peak)
    assert np.array_equal(ours[:, g.added_at], direct[:, g.added_at])  # the added angles directly


# --------------------------------------------------------------------------------------------
# The coarse screening that lets a roller or knife cam skip the dense check
# --------------------------------------------------------------------------------------------
def _random_pitch_cam(rng):
    """A roller or knife (translating or oscillating, either rotation) and a rise-dwell-return-dwell
    program of random laws and spans, sized from past the undercut limit to comfortably clear of it."""
    laws = ["cycloidal", "modified_sine", "modified_trapezoid", "double_harmonic", "poly345", "harmonic"]
    spans = rng.dirichlet(np.ones(4)) * 320.0 + 10.0  # deg: rise, dwell, return, dwell, adding up to 360
    oscillating = bool(rng.integers(0, 2))
    lift = D(float(rng.uniform(5.0, 15.0))) if oscillating else float(rng.uniform(5.0, 30.0))
    segments = [Segment(str(rng.choice(laws)), D(spans[0]), lift), Segment("dwell", D(spans[1])),
                Segment(str(rng.choice(laws)), D(spans[2]), -lift), Segment("dwell", D(spans[3]))]
    program = MotionProgram(segments, unit="rad" if oscillating else "mm")
    kind = str(rng.choice(["roller", "knife"]))
    base = float(rng.uniform(8.0, 80.0))
    roller = float(rng.uniform(2.0, 30.0)) if kind == "roller" else 0.0
    rotation = str(rng.choice(["ccw", "cw"]))
    if oscillating:
        follower = FollowerSpec(kind, base, motion="oscillating", roller_radius=roller, pivot=(base + roller + 60.0, 20.0),
                                arm_length=float(np.hypot(base + roller + 60.0, 20.0) * 0.9), rotation=rotation)
    else:
        follower = FollowerSpec(kind, base, roller_radius=roller, offset=float(rng.uniform(-0.3, 0.3)) * base, rotation=rotation)
    return follower, program


def test_screened_cams_are_clear_on_a_ten_times_finer_grid():
    """_pitch_clear says a cam is clear of its limits from the 1-deg coarse grid; for 400 random
    rollers and knives (many of them near or past the undercut) every cam it clears is clear on a
    0.01 deg grid by the closed-form kinematics (r kappa < 1 everywhere, no cusp, away from the axis),
    and every cam whose dense check fails is one it did not clear.  It is not vacuous: it clears
    most of the cams that are comfortably clear."""
    from camgen.errors import CamgenError
    from camgen.synthesis.followers import (
        SCREEN_UNDERCUT,
        _law_on_grid,
        _pitch_clear,
        _pitch_terms,
        kinematics,
    )

    rng = np.random.default_rng(2026)
    fine = np.arange(36000) * (TWO_PI / 36000)
    cleared = comfortable = failing = 0
    for trial in range(400):
        try:
            follower, program = _random_pitch_cam(rng)
        except CamgenError:  # a random geometry the follower refuses (pivot inside the cam ...)
            continue
        n, added = _grid_layout(program, BOUND_SPACING)
        clear = _pitch_clear(follower, _pitch_terms(follower, *_law_on_grid(program, n, added)), TWO_PI / n)
        k = kinematics(follower, program, np.concatenate([fine, program.breaks]))
        r_kappa = follower.roller_radius * k.pitch_curvature
        speed = np.hypot(*k.pitch_d1.T)
        worst = float(np.max(r_kappa)) if follower.kind == "roller" else 0.0
        height_ok = True if follower.motion == "oscillating" else bool(np.min(follower.rest_height + k.s) > 0)
        fine_ok = worst < 1.0 and float(np.min(speed)) > 1e-9 * follower.prime_radius and height_ok
        if clear:
            cleared += 1
            assert fine_ok, (trial, worst)
            assert worst <= SCREEN_UNDERCUT + 1e-9, (trial, worst)
        if fine_ok and worst < 0.5:
            comfortable += 1
        failing += not fine_ok
    assert comfortable >= 100 and failing >= 20  # both sides of the limits are exercised
    assert cleared >= 0.8 * comfortable


def test_bound_second_derivatives_match_finite_differences_of_the_curves():
    """The second derivatives the fit's sixth-derivative bound is taken from (the pitch curve's and
    the profile's, from the screening terms and the curvature) against the 5-point second
    difference (error O(h^4), h = 1e-3 rad) of the closed-form pitch and contact points (the
    roller centre turned into the cam frame, offset by r along the normal: no curvature involved),
    for random rollers and knives clear of the undercut, at angles away from the law's breaks;
    allowed: twice the difference's own error estimate (against the same difference at 2h) plus
    rounding."""
    from camgen.errors import CamgenError
    from camgen.synthesis.followers import (
        _pitch_second_derivatives,
        _pitch_terms,
        kinematics,
    )

    rng = np.random.default_rng(7)
    h = 1e-3
    stencil = np.array([-1.0, 16.0, -30.0, 16.0, -1.0]) / (12.0 * h * h)
    checked = 0
    for _ in range(60):
        try:
            follower, program = _random_pitch_cam(rng)
        except CamgenError:
            continue
        theta = np.arange(360) * (TWO_PI / 360) + D(0.3)
        gap = np.abs((theta[:, None] - program.breaks[None, :] + PI) % TWO_PI - PI).min(axis=1)
        theta = theta[gap > 5 * h]
        k = kinematics(follower, program, theta)
        if not (np.all(follower.roller_radius * k.pitch_curvature < 0.9) and np.all(np.hypot(*k.pitch_d1.T) > 1e-3)):
            continue
        want = ("pitch", "profile") if follower.kind == "roller" else ("pitch",)
        got = _pitch_second_derivatives(follower, theta, _pitch_terms(follower, *program(theta)), want)
        differences = []
        for step in (h, 2 * h):
            near = kinematics(follower, program, (theta[None, :] + step * np.arange(-2, 3)[:, None]).ravel())
            points = [near.pitch_point] + ([near.contact_point] if follower.kind == "roller" else [])
            differences.append([np.einsum("k,kni->ni", stencil * (h / step) ** 2, xy.reshape(5, theta.size, 2)) for xy in points])
        for z, fine, coarse in zip(got, *differences):
            allowed = 2.0 * np.abs(fine - coarse) + 1e-8 * float(np.max(np.abs(fine)))
            assert np.all(np.abs(np.column_stack([z.real, z.imag]) - fine) <= allowed)
        checked += 1
    assert checked >= 30


@pytest.mark.parametrize("n", [360, 7200])
def test_program_on_a_uniform_grid_with_added_angles(n):
    """on_uniform_grid(n, extra) on the coarse grid (360: each piece evaluated once at its uniform
    and added angles together) and on the dense one (7200: angle addition on the uniform part),
    the added angles at and next to every break and inside pieces: s and s' against the textbook
    formulas (program_and_closed_forms: the right-hand piece at a break, where the velocity jumps
    at 160 deg), and all four against the direct evaluation at the same angles (a few ulps of each
    derivative's peak)."""
    program, closed = program_and_closed_forms()
    brk = program.breaks
    extra = np.sort(np.concatenate([brk, brk + 1e-9, (brk - 1e-9) % TWO_PI, [D(12.3), D(200.7)]]))
    theta = np.concatenate([np.arange(n) * (TWO_PI / n), extra])
    fast = np.array(program.on_uniform_grid(n, extra))
    ref_s, ref_v = closed(theta)
    assert np.max(np.abs(fast[0] - ref_s)) <= 1e-12 * 20
    assert np.max(np.abs(fast[1] - ref_v)) <= 1e-11 * 20
    direct = np.array(program(theta))
    peak = np.max(np.abs(direct), axis=1)
    assert np.all(np.max(np.abs(fast - direct), axis=1) <= 8e-16 * n**0.5 * peak)


def _stub_law():
    class Law:  # a law without breaks: the fit makes one segment over the turn
        breaks = np.zeros(0)

    return Law()


@pytest.mark.parametrize("curve, message", [
    (lambda th: (1.0 + 0.01 * th) * np.exp(1j * th), "not closed"),  # a spiral: it ends 0.063 mm from its start
    (lambda th: 30.0 * np.exp(1j * th), "counter-clockwise"),         # a circle run clockwise in t = -theta
])
def test_fit_refuses_an_open_or_clockwise_curve(curve, message):
    """The envelope fit checks closure and orientation of all its curves at once; a curve that is
    not closed (a spiral) or runs clockwise is refused with the message of the Contour constructor."""
    from camgen.errors import GeometryError
    from camgen.synthesis.followers import _spline_contours

    def exact(th):
        h = 1e-4  # derivatives of the closed form by central differences: the fit tolerance below is loose
        q = curve(th)
        d1 = (curve(th + h) - curve(th - h)) / (2 * h)
        d2 = (curve(th + h) - 2 * q + curve(th - h)) / (h * h)
        return q[:, None], d1[:, None], d2[:, None]

    with pytest.raises(GeometryError, match=message):
        _spline_contours(exact, 1, 1.0, _stub_law(), 1e-3)


def test_fit_of_a_counter_clockwise_circle_has_the_circles_area():
    """The Green area the fit computes for its contour (from the scaled quintic coefficients) is the
    circle's pi r^2 (to the fit's h^6 error), and the contour meets r at every cam angle."""
    from camgen.synthesis.followers import _spline_contours

    r = 30.0

    def exact(th):  # t = -theta: counter-clockwise in t
        z = r * np.exp(-1j * th)
        return z[:, None], (-1j * z)[:, None], (-z)[:, None]

    (contour,), (error,) = _spline_contours(exact, 1, 1.0, _stub_law(), 1e-9)
    assert error <= 1e-9
    assert abs(contour.area - math.pi * r * r) <= 2 * math.pi * r * 1e-9
    pts = contour.evaluate(np.linspace(0.0, contour.n_segments, 1000, endpoint=False))
    assert np.max(np.abs(np.hypot(*pts.T) - r)) <= 1e-9


def golden_minimum(f, lo: np.ndarray, hi: np.ndarray, iterations: int = 60) -> tuple[np.ndarray, np.ndarray]:
    """Vectorised golden-section search: (argument, value) of the least f in [lo, hi] elementwise
    (f unimodal there); the bracket shrinks to 0.618^iterations of its width."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iterations):
        left = fc < fd  # the minimum is in [a, d]
        a, b = np.where(left, a, c), np.where(left, d, b)
        c, d = np.where(left, b - g * (b - a), d), np.where(left, c, a + g * (b - a))
        fc, fd = np.where(left, f(c), fd), np.where(left, fc, f(d))
    x = 0.5 * (a + b)
    return x, f(x)


def test_a_segment_shorter_than_the_bound_windows_is_fitted_within_fit_tol():
    """A dwell of 0.5 deg between two rises (shorter than the five 1-deg angles of the sixth-derivative
    windows): the fit still meets fit_tol, measured against the envelope built here from the
    follower's positions, not from camgen's kinematics: the roller centre (0, Rp + s(theta)) of the
    cycloidal program written out, turned into the cam frame (R(-theta), a ccw cam), and

    * every profile point (4001 per spline segment) is the roller radius from that path: the least
      distance over the cam angle by golden-section search, bracketed by the nearest of 7200 path points;
    * every roller position (3600 cam angles and the breaks) touches the profile and cuts it
      nowhere: the least distance over the profile's parameter, bracketed likewise, is r."""
    from scipy.spatial import cKDTree

    program = MotionProgram([Segment("cycloidal", D(179.5), 12.0), Segment("dwell", D(0.5)), Segment("cycloidal", D(180.0), -12.0)])
    follower = FollowerSpec("roller", 50.0, roller_radius=8.0)
    r, prime, tol = 8.0, 58.0, 1e-7
    cam = cam_envelope(follower, program, fit_tol=tol)
    assert cam.fit_error <= tol
    profile = cam.profile

    def centre(theta: np.ndarray) -> np.ndarray:
        t = np.mod(theta, TWO_PI)
        up, down = t / D(179.5), (t - D(180.0)) / D(180.0)
        s = np.where(t < D(179.5), 12.0 * (up - np.sin(TWO_PI * up) / TWO_PI),
                     np.where(t < D(180.0), 12.0, 12.0 * (1.0 - down + np.sin(TWO_PI * down) / TWO_PI)))
        y = prime + s
        return np.stack([y * np.sin(theta), y * np.cos(theta)], axis=-1)

    grid = np.arange(7200) * (TWO_PI / 7200)
    step = grid[1]
    path_tree = cKDTree(centre(grid))
    points = np.concatenate([seg.eval_t(np.linspace(seg.breaks[0], seg.breaks[-1], 4001)) for seg in profile.segments])
    _, nearest = path_tree.query(points)
    _, gap = golden_minimum(lambda th: np.hypot(*(points - centre(th)).T), grid[nearest] - 2 * step, grid[nearest] + 2 * step)
    assert np.max(np.abs(gap - r)) <= tol

    n = profile.n_segments
    u = np.linspace(0.0, n, 200_000, endpoint=False)
    du = u[1]
    profile_tree = cKDTree(profile.evaluate(u))
    theta = np.concatenate([np.arange(3600) * (TWO_PI / 3600), program.breaks])
    rollers = centre(theta)
    _, nearest = profile_tree.query(rollers)
    _, gap = golden_minimum(lambda v: np.hypot(*(rollers - profile.evaluate(np.mod(v, n))).T), u[nearest] - 2 * du, u[nearest] + 2 * du)
    assert np.max(np.abs(gap - r)) <= tol + 1e-10
