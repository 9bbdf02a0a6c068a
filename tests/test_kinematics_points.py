"""A roller's or knife's Kinematics make their points (follower, pitch and contact point, the
curves' derivatives) on first use (a design evaluation reads the pressure angle and the
curvatures only): the points are the spline's curves (``_roller`` without the kinematics, which
makes them: a check of the wiring), the same as ``contact_points`` (its own arithmetic of the
contact alone), and they are checked against their own geometry (the contact one roller radius
from the pitch point, the pitch point the follower point turned into the cam frame) and against
central differences of the points (independent); a pickled Kinematics carries them.  Then the
values the synthesis keeps across designs against the code before and against fresh cams."""
from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from camgen.synthesis.followers import FollowerSpec, _roller, cam_envelope, contact_points, kinematics
from camgen.synthesis.laws import MotionProgram, Segment

D = math.radians
FOLLOWERS = {
    "roller_offset": dict(kind="roller", base_radius=40.0, roller_radius=10.0, offset=12.0),
    "roller_cw": dict(kind="roller", base_radius=35.0, roller_radius=6.0, offset=-4.0, rotation="cw"),
    "knife": dict(kind="knife", base_radius=40.0, offset=-6.0),
    "osc_roller": dict(kind="roller", base_radius=40.0, motion="oscillating", roller_radius=8.0, pivot=(110.0, 40.0), arm_length=95.0),
    "osc_knife": dict(kind="knife", base_radius=40.0, motion="oscillating", pivot=(110.0, 40.0), arm_length=95.0),
}
#: lift (mm) or swing (deg) of each follower's program
LIFT = {"roller_offset": 16.0, "roller_cw": 12.0, "knife": 16.0, "osc_roller": 12.0, "osc_knife": 10.0}
#: Relative tolerance of a central difference of step H (rad) against the exact derivative: error ~ H^2 / 6 of the third derivative.
H, FD_TOL = 1e-5, 1e-6


def _case(name):
    kind = FOLLOWERS[name]
    oscillating = kind.get("motion") == "oscillating"
    unit, lift = ("rad", D(LIFT[name])) if oscillating else ("mm", LIFT[name])
    law = MotionProgram([Segment("cycloidal", D(110), lift), Segment("dwell", D(50)),
                         Segment("poly345", D(90), -lift), Segment("dwell", D(110))], unit=unit)
    return FollowerSpec(**kind), law


def _complex(xy):
    return xy[:, 0] + 1j * xy[:, 1]


@pytest.mark.parametrize("name", sorted(FOLLOWERS))
def test_points_made_on_first_use_are_the_curves_arithmetic(name):
    f, law = _case(name)
    theta = np.linspace(0.0, 2.0 * math.pi, 721)[:-1] + 0.0003
    k = kinematics(f, law, theta)
    s, ds, d2s, d3s = (np.asarray(x, dtype=float).ravel() for x in law(theta))
    (pitch, p1, p2), (contact, q1, q2) = _roller(f, theta, s, ds, d2s, d3s, False, ("pitch", "profile"))
    for got, want in ((k.pitch_point, pitch), (k.pitch_d1, p1), (k.pitch_d2, p2), (k.contact_point, contact),
                      (k.contact_d1, q1), (k.contact_d2, q2)):
        assert got is not None and got.shape == (theta.size, 2)
        assert np.array_equal(_complex(got), want)  # bit for bit
    assert np.array_equal(k.contact_point, contact_points(f, law, theta))
    # geometry: the contact one roller radius from the pitch point; the pitch point the follower point in the cam frame
    assert np.allclose(np.abs(_complex(k.contact_point) - _complex(k.pitch_point)), f.roller_radius, rtol=0, atol=1e-12)
    turned = _complex(k.follower_point) * np.exp(-1j * f.sigma * theta)
    assert np.allclose(turned, _complex(k.pitch_point), rtol=0, atol=1e-12)
    # the derivatives against central differences of the points (away from the breaks: the law is smooth there)
    plus, minus = kinematics(f, law, theta + H), kinematics(f, law, theta - H)
    smooth = np.all(np.abs(np.mod(theta[:, None] - law.breaks[None, :] + math.pi, 2 * math.pi) - math.pi) > 1e-3, axis=1)
    for point, d1, d2 in (("pitch_point", "pitch_d1", "pitch_d2"), ("contact_point", "contact_d1", "contact_d2")):
        a, b, c = (_complex(getattr(x, point)) for x in (plus, k, minus))
        first, second = _complex(getattr(k, d1)), _complex(getattr(k, d2))
        scale = np.max(np.abs(first))
        assert np.max(np.abs(((a - c) / (2 * H) - first)[smooth])) <= FD_TOL * scale
        d2_plus, d2_minus = (_complex(getattr(x, d1)) for x in (plus, minus))
        assert np.max(np.abs(((d2_plus - d2_minus) / (2 * H) - second)[smooth])) <= FD_TOL * np.max(np.abs(second))


@pytest.mark.parametrize("name", ["roller_offset", "osc_knife"])
def test_envelope_data_points_and_a_pickled_kinematics(name):
    """The check grid's Kinematics give their points when asked (after the curvatures were read),
    the same as kinematics() at the grid's angles made fresh; a pickled copy carries them, asked or not."""
    f, law = _case(name)
    env = cam_envelope(f, law)
    data = env.data
    before = pickle.loads(pickle.dumps(data))  # pickled before any point was asked
    least = float(np.min(data.profile_radius))
    fresh = kinematics(f, law, env.grid.theta)
    for got in (data, before, pickle.loads(pickle.dumps(data))):
        assert float(np.min(got.profile_radius)) == least
        for name_ in ("follower_point", "pitch_point", "contact_point", "pitch_d1", "pitch_d2", "contact_d1", "contact_d2"):
            assert np.allclose(getattr(got, name_), getattr(fresh, name_), rtol=0, atol=1e-12), name_
    assert data.contact_point is data.contact_point  # made once


#: (follower, base radius, roller radius or None: the follower's): passing cams and, with a small
#: base radius and a large roller, translating rollers that undercut
FAILING = [(n, 40.0, None) for n in sorted(FOLLOWERS)] + [(n, 23.0, None) for n in ("osc_knife", "osc_roller")] \
    + [("knife", 8.0, None), ("roller_offset", 4.0, 25.0), ("roller_cw", 4.0, 25.0), ("roller_offset", 4.0, 16.0)]


@pytest.mark.parametrize("name, base, roller", FAILING)
def test_failures_from_the_kinematics_measures_are_the_direct_ones(name, base, roller):
    """profile_failures of a roller's or knife's Kinematics (from the measures kept when the
    curvatures were made) are _pitch_failures from the law's s, s', s'' (reasons and masks); the
    undercut mask is where r kappa >= 1 of the pitch curvature (away from its boundary) and not
    empty for the small base radii with a large roller."""
    from camgen.synthesis.followers import _pitch_failures, profile_failures

    _, law = _case(name)
    f = FollowerSpec(**{**FOLLOWERS[name], "base_radius": base, **({} if roller is None else {"roller_radius": roller})})
    theta = np.linspace(0.0, 2.0 * math.pi, 3601)[:-1]
    k = kinematics(f, law, theta)
    got = profile_failures(f, k)
    want = _pitch_failures(f, k.s, k.ds, k.d2s)
    assert [r for r, _ in got] == [r for r, _ in want]
    for (_, a), (_, b) in zip(got, want):
        assert np.array_equal(a, b)
    if f.has_radius:
        undercut = got[-1][1]
        r_kappa = f.roller_radius * k.pitch_curvature
        clear = np.abs(r_kappa - 1.0) > 1e-9
        assert np.array_equal(undercut[clear], (r_kappa >= 1.0)[clear])
        assert undercut.any() == (roller is not None)


def test_check_grid_values_kept_by_the_program_in_grid_order():
    """CheckGrid.values of a motion program come from the program's kept block in the grid's order
    (MotionProgram.on_uniform_grid_in_order): for designs in a row with the same program (kept),
    another program (other lifts: its own values) and the first again, each against np.insert of a
    fresh program's values on the uniform grid and at the added angles (bit for bit); read-only; another order array
    for the same grid is taken again."""
    from camgen.synthesis.followers import CheckGrid, _grid_layout

    def program(lift):
        return MotionProgram([Segment("cycloidal", D(110), lift), Segment("dwell", D(50)),
                              Segment("poly345", D(90), -lift), Segment("dwell", D(110))])

    first, other = program(16.0), program(9.5)
    for law, lift in ((first, 16.0), (first, 16.0), (other, 9.5), (first, 16.0)):
        n, added = _grid_layout(law, D(0.05))
        at = np.searchsorted(np.arange(n) * (2.0 * math.pi / n), added)
        direct = program(lift).on_uniform_grid(n, added)  # a fresh program: nothing kept
        values = CheckGrid(law, n, added).values
        for got, value in zip(values, direct):
            assert np.array_equal(got, np.insert(value[:n], at, value[n:]))
            assert not got.flags.writeable
    n, added = _grid_layout(first, D(0.05))
    order = np.arange(n + added.size)[::-1].copy()
    block = first.on_uniform_grid_in_order(n, added, order)
    raw = np.stack(first.on_uniform_grid(n, added))
    assert np.array_equal(block, raw[:, ::-1])


def _round_angles_before(lo, hi, count, sigma, lead):
    """The knots, spans and angles of a round of _spline_contours as the code before wrote them (inline, nothing kept)."""
    from camgen.synthesis.followers import _ONE_SIDED_STEPS, _PROBES, _uniform_knots

    lo, hi, count = np.array(lo), np.array(hi), np.array(count)
    x, first, last = _uniform_knots(lo, hi, count)
    span = x[1:] - x[:-1]
    span[last[:-1]] = 1.0
    probes = x[:-1, None] + _PROBES * span[:, None]
    front = (np.stack([lo, hi])[:, :, None] + np.array([1.0, -1.0])[:, None, None] * _ONE_SIDED_STEPS).ravel()
    nlead = front.size if lead else 0
    return x, first, last, span, -sigma * np.concatenate([front[:nlead], x, probes.ravel()])


def test_round_angles_kept_are_the_code_before_and_envelopes_in_a_row_are_fresh_ones():
    """_round_angles (kept across designs) against the code before for layouts in a row (same,
    other counts, other sigma, without the lead, the first again), read-only; too close breaks give
    None each time; cams in a row (other base radii: other piece counts; the first again) have the
    contours of the same cam made with nothing kept (the cache cleared), bit for bit."""
    from camgen.synthesis.followers import _round_angles

    lo, hi = (0.5, 2.0, 4.0), (2.0, 4.0, 0.5 + 2 * math.pi)
    for count, sigma, lead in (((5, 9, 7), 1.0, True), ((5, 9, 7), 1.0, True), ((6, 9, 8), 1.0, True), ((5, 9, 7), -1.0, True),
                               ((5, 9, 7), 1.0, False), ((5, 9, 7), 1.0, True)):
        got = _round_angles(lo, hi, count, sigma, lead)
        assert got is not None
        for a, b in zip(got, _round_angles_before(lo, hi, count, sigma, lead)):
            assert np.array_equal(a, b) and a.dtype == b.dtype and not a.flags.writeable
    for _ in range(2):
        assert _round_angles((0.5, 0.5), (0.5, 7.0), (2, 3), 1.0, True) is None
    f, law = _case("roller_offset")
    for base in (40.0, 25.0, 40.0):
        g = FollowerSpec(**{**FOLLOWERS["roller_offset"], "base_radius": base})
        kept = cam_envelope(g, law)
        _round_angles.cache_clear()
        fresh = cam_envelope(g, law)
        for a, b in ((kept.profile, fresh.profile), (kept.pitch, fresh.pitch)):
            assert len(a.segments) == len(b.segments)
            for sa, sb in zip(a.segments, b.segments):
                assert np.array_equal(sa.breaks, sb.breaks) and np.array_equal(sa.coeffs, sb.coeffs)
        assert kept.fit_error == fresh.fit_error


def _segments_before(brk, sigma):
    """The segments of _spline_contours as the code before wrote them (inline, nothing kept)."""
    from camgen.synthesis.followers import BREAK_MERGE

    sorted_brk = sorted(set(brk))
    tb = []
    for t in sorted({(-sigma * b) % (2 * math.pi) for b in sorted_brk}) or [0.0]:
        if not tb or t - tb[-1] > BREAK_MERGE:
            tb.append(t)
    if len(tb) > 1 and tb[0] + 2 * math.pi - tb[-1] <= BREAK_MERGE:
        tb.pop()
    lo, hi = np.array(tb), np.array(tb[1:] + [tb[0] + 2 * math.pi])
    mid = np.mod(-sigma * 0.5 * (lo + hi), 2 * math.pi)
    return np.array(sorted_brk), lo, hi, hi - lo, (np.searchsorted(sorted_brk, mid, side="right") - 1) % max(1, len(sorted_brk))


@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_segments_kept_are_the_code_before(sigma):
    """_segments_of (kept across designs) against the code before for break sets in a row: none,
    the program's, repeated breaks, breaks closer than BREAK_MERGE (one joint), one next to 0 and
    2 pi (merged round the turn), the program's again; read-only."""
    from camgen.synthesis.followers import _segments_of

    _, law = _case("roller_offset")
    program = tuple(np.mod(law.breaks, 2 * math.pi).tolist())
    for brk in ((), program, program + program[:2], (1.0, 1.0 + 1e-13, 3.0), (0.0, 2 * math.pi - 1e-13, 2.0), program):
        got = _segments_of(brk, sigma)
        want = _segments_before(brk, sigma)
        for a, b in zip(got, want):
            assert np.array_equal(a, b) and not a.flags.writeable
        assert got[4].size == got[1].size and np.all(got[4] < max(1, len(set(brk))))


def _sixth_before(theta, d2, brk):
    """_sixth_derivatives as the code before wrote it (nothing kept)."""
    worst = np.abs(np.diff(d2, 4, axis=1)).max(axis=0)
    worst *= (theta[1] - theta[0]) ** -4
    if not brk.size:
        return worst.max(initial=0.0, keepdims=True)
    below = np.searchsorted(brk, theta, side="right")
    worst *= below[:-4] == below[4:]
    start = np.searchsorted(theta, brk, side="left")
    out = np.maximum.reduceat(worst, np.minimum(start, worst.size - 1))
    if start[0] > 0:
        out[-1] = max(out[-1], worst[: start[0]].max())
    return out


def test_sixth_derivatives_with_kept_break_windows_are_the_code_before():
    """_sixth_derivatives (its break windows kept across designs) against the code before for
    curves and break sets in a row: breaks at the first angle, inside, within the last windows,
    past the last angle, none; the first set again with other curves; two grids."""
    from camgen.synthesis.followers import _sixth_derivatives

    rng = np.random.default_rng(3)
    for n in (360, 500):
        theta = np.arange(n) * (2 * math.pi / n)
        for brk in ([0.0, D(100), D(130), D(250)], [D(3), D(100.2), D(358.9)], [D(359.99)], [], [0.0, D(100), D(130), D(250)]):
            b = np.array(brk, dtype=float)
            d2 = rng.normal(size=(2, n)) + 1j * rng.normal(size=(2, n))
            assert np.array_equal(_sixth_derivatives(theta, d2, b), _sixth_before(theta, d2, b))
