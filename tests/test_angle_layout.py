"""The angle layouts motion programs share across programs (camgen.synthesis.laws ``_angle_layout``):
a program asked at angles (``program(theta)``, ``on_sample_grid``) takes the sorted angles, the
pieces' bounds and their bases kept for programs whose pieces lie at the same places (a sweep of
the rise and return), and must give what a program evaluated with nothing kept gives, bit for bit
(the code before, ``_values`` without a key), and the closed form of the cycloidal rise (Norton,
Cam Design and Manufacturing Handbook, 2nd ed., eq. 3.9: s = h (x - sin(2 pi x) / (2 pi)),
x = theta / beta)."""
from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.synthesis import laws
from camgen.synthesis.laws import MotionProgram, Segment

D = math.radians
TWO_PI = 2.0 * math.pi
#: Closed form against the law's values (direct sines: a few ulps of the lift).
CLOSED_FORM_TOL = 1e-12


def _program(lift: float, rise_deg: float = 120.0, dwell_deg: float = 40.0, back: str = "poly345") -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(rise_deg), lift), Segment("dwell", D(dwell_deg)),
                          Segment(back, D(130.0), -lift), Segment("dwell", D(230.0 - rise_deg - dwell_deg))])


# (lift, rise span, first dwell, the return's law): lifts only (the same places), other spans, a
# tilted-cycloid return (a piece evaluated by itself), back again
SEQUENCE = [(12.0, 120.0, 40.0, "poly345"), (17.0, 120.0, 40.0, "poly345"), (-9.0, 120.0, 40.0, "poly345"),
            (-14.0, 120.0, 40.0, "poly345"), (12.0, 100.0, 60.0, "poly345"), (17.0, 100.0, 60.0, "poly345"),
            (12.0, 120.0, 40.0, "modified_cycloidal"), (8.0, 120.0, 40.0, "modified_cycloidal"),
            (10.0, 120.0, 40.0, "poly345")]

_RNG = np.random.default_rng(28)
#: Angle sets a design asks: unsorted ones around and beyond the turn, one angle, the breaks, a grid's
ANGLES = [_RNG.uniform(-TWO_PI, 2.0 * TWO_PI, 257), np.array([D(50.0)]), np.array([0.0, D(120.0), D(160.0), D(290.0)]),
          np.array([[D(10.0), -0.0], [D(359.0), D(200.0)]]), np.arange(0.0, TWO_PI, D(0.5))]


def _fresh(program_args: tuple, theta: np.ndarray) -> np.ndarray:
    """The values of a program evaluated with nothing kept: the angles' own evaluation (no key)."""
    laws._angle_layout.cache_clear()
    theta = np.asarray(theta, dtype=float)
    return _program(*program_args)._values(theta, None)


@pytest.mark.parametrize("which", range(len(ANGLES)))
def test_programs_with_other_lifts_share_layouts_and_give_fresh_values(which):
    theta = ANGLES[which]
    laws._angle_layout.cache_clear()
    gots = []
    for k, args in enumerate(SEQUENCE):  # the programs in a row, as a sweep's designs
        hits = laws._angle_layout.cache_info().hits
        gots.append(_program(*args)(theta))
        if k % 2 and k < 6:  # the places of the program before (evaluated last): its layout serves this one
            assert laws._angle_layout.cache_info().hits > hits, k
    assert laws._angle_layout.cache_info().currsize > 0
    for k, (args, got) in enumerate(zip(SEQUENCE, gots)):
        want = _fresh(args, theta)
        for a, b in zip(got, want):
            assert a.shape == theta.shape
            assert np.array_equal(a.ravel(), b, equal_nan=False), (k, which)
            assert np.array_equal(np.signbit(a.ravel()), np.signbit(b)), (k, which)
        # the closed form of the cycloidal rise at the angles inside it (on the turn)
        lift, rise = args[0], D(args[1])
        on_turn = np.mod(theta.ravel(), TWO_PI)
        inside = on_turn < rise
        x = on_turn[inside] / rise
        assert np.allclose(got[0].ravel()[inside], lift * (x - np.sin(TWO_PI * x) / TWO_PI), rtol=0.0,
                           atol=CLOSED_FORM_TOL * abs(lift) * 10), k


@pytest.mark.parametrize("n", [3600, 1000])
def test_sample_grids_across_programs_are_fresh_programs_values(n):
    theta = 2.0 * math.pi * np.arange(n) / n
    laws._angle_layout.cache_clear()
    gots = []
    for k, args in enumerate(SEQUENCE):
        hits = laws._angle_layout.cache_info().hits
        gots.append(_program(*args).on_sample_grid(n))
        if k % 2 and k < 6:
            assert laws._angle_layout.cache_info().hits > hits, k
    for k, (args, got) in enumerate(zip(SEQUENCE, gots)):
        want = _fresh(args, theta)
        for a, b in zip(got, want):
            assert a.flags.writeable
            assert np.array_equal(a, b), (k, n)


def test_kept_layouts_are_read_only_refuse_non_finite_angles_and_are_not_pickled():
    laws._angle_layout.cache_clear()
    program = _program(15.0)
    theta = ANGLES[0]
    program(theta)
    ths, order, bounds, bases = laws._angle_layout(theta.tobytes(), program._places())
    assert order is not None and not order.flags.writeable and not ths.flags.writeable
    assert bool(np.all(ths[1:] >= ths[:-1])) and float(ths.min()) >= 0.0 and float(ths.max()) < TWO_PI
    assert list(bounds) == [0] + np.searchsorted(ths, program._piece_lo[1:]).tolist() + [theta.size]
    shown = [b for b in bases if b is not None]
    assert shown and all(not b.flags.writeable for b in shown)
    with pytest.raises(ValueError):
        shown[0][0, 0] = 2.0
    for _ in range(2):  # refused each time (nothing kept for it)
        with pytest.raises(ParameterError):
            program(np.array([0.1, math.nan]))
    assert "_places_key" not in pickle.loads(pickle.dumps(program)).__dict__


def _fill_uniform_before(entry: tuple, n: int, lo: int, hi: int, ths: np.ndarray, out: np.ndarray) -> None:
    """MotionProgram._fill_uniform before the grid layouts were kept (verbatim)."""
    start, span, ref, forward, const, omegas, matrix, custom = entry
    if custom is not None or matrix.shape[1] == 1 or math.copysign(1.0, ref) < 0.0:
        MotionProgram._fill(entry, ths, out, TWO_PI / n)
        return
    np.matmul(matrix, laws._uniform_basis(n, lo, hi, start, span, ref, forward, omegas, matrix.shape[1] - 1 - 2 * len(omegas)),
              out=out)


def _grid_before(program: MotionProgram, n: int, extra: np.ndarray) -> np.ndarray:
    """MotionProgram.on_uniform_grid's loop before the grid layouts were kept (verbatim, but for
    the values kept on the program), with nothing kept."""
    laws._uniform_basis.cache_clear()
    laws._grid_layout.cache_clear()
    step = TWO_PI / n
    grid = np.arange(n) * step
    starts = program._piece_lo[1:]
    bounds = [0] + np.searchsorted(grid, starts, side="left").tolist() + [n]
    extra_bounds = [0] + np.searchsorted(extra, starts, side="left").tolist() + [extra.size]
    res = np.empty((4, n + extra.size))
    for g, entry in enumerate(program._plan()):
        lo, hi = bounds[g], bounds[g + 1]
        elo, ehi = n + extra_bounds[g], n + extra_bounds[g + 1]
        if hi - lo >= laws._PHASOR_MIN_POINTS:
            _fill_uniform_before(entry, n, lo, hi, grid[lo:hi], res[:, lo:hi])
            if elo < ehi:
                program._fill(entry, extra[elo - n: ehi - n], res[:, elo:ehi], None)
        elif lo < hi or elo < ehi:
            both = np.empty((4, hi - lo + ehi - elo))
            program._fill(entry, np.concatenate([grid[lo:hi], extra[elo - n: ehi - n]]), both, None)
            res[:, lo:hi] = both[:, : hi - lo]
            res[:, elo:ehi] = both[:, hi - lo:]
    return res


@pytest.mark.parametrize("n", [7200, 2880, 360])
def test_uniform_grids_across_programs_are_the_loop_before(n):
    """on_uniform_grid of programs in a row (the grid layouts kept across them) against the loop
    before the layouts were kept, bit for bit (few and many uniform angles per piece, dwells, the
    tilted cycloid, the breaks added)."""
    laws._grid_layout.cache_clear()
    gots, hits = [], []
    for args in SEQUENCE:
        program = _program(*args)
        before = laws._grid_layout.cache_info().hits
        gots.append(program.on_uniform_grid(n, np.unique(np.mod(program.breaks, TWO_PI))))
        hits.append(laws._grid_layout.cache_info().hits > before)
    assert hits[1] and hits[3] and hits[5] and hits[7]
    for k, (args, got) in enumerate(zip(SEQUENCE, gots)):
        program = _program(*args)
        want = _grid_before(program, n, np.unique(np.mod(program.breaks, TWO_PI)))
        for a, b in zip(got, want):
            assert np.array_equal(a, b), (k, n)
            assert np.array_equal(np.signbit(a), np.signbit(b)), (k, n)


def test_peaks_of_a_program_against_its_sampled_values_the_first_of_equal_peaks():
    """peak_values against the program's values sampled every 0.001 deg (brute force): the same
    peaks within the sampling's error, the velocity's where the first segment reaching it has it (a
    rise and a return of equal lift and span peak equally) or in the segment of the larger Cv
    (Norton, Table 8-3), and the impulses of a velocity jump."""
    theta = np.arange(360_000) * (TWO_PI / 360_000)
    for program, first in ((MotionProgram([Segment("cycloidal", D(120.0), 10.0), Segment("cycloidal", D(120.0), -10.0),
                                           Segment("dwell", D(120.0))]), (0.0, D(120.0))),
                           (MotionProgram([Segment("dwell", D(60.0)), Segment("poly345", D(100.0), 8.0), Segment("dwell", D(100.0)),
                                           Segment("cycloidal", D(100.0), -8.0)]), (D(260.0), TWO_PI))):  # the cycloid's Cv 2 > the 345's 1.875
        peaks = program.peak_values()
        values = program(theta)
        for got, at, v in ((peaks.velocity, peaks.velocity_at, values[1]), (peaks.acceleration, peaks.acceleration_at, values[2]),
                           (peaks.jerk, peaks.jerk_at, values[3])):
            assert got == pytest.approx(float(np.max(np.abs(v))), rel=1e-6)
        assert first[0] <= peaks.velocity_at <= first[1]
        assert not peaks.infinite_acceleration
    corner = MotionProgram([Segment("constant_velocity", D(180.0), 10.0), Segment("constant_velocity", D(180.0), -10.0)])
    assert corner.peak_values().infinite_acceleration and corner.peak_values().infinite_jerk
    dwelling = MotionProgram([Segment("simple_harmonic", D(180.0), 10.0), Segment("dwell", D(60.0)), Segment("simple_harmonic", D(120.0), -10.0)])
    assert dwelling.peak_values().infinite_jerk and not dwelling.peak_values().infinite_acceleration  # A jumps at a dwell
    smooth = MotionProgram([Segment("simple_harmonic", D(180.0), 10.0), Segment("simple_harmonic", D(180.0), -10.0)])  # one cosine
    assert not smooth.peak_values().infinite_jerk


#: Many angles (beyond __call__'s memo, laws._CALL_MEMO_ANGLES): a plate cam's check grid, and unsorted ones around the turn.
MANY = [np.unique(np.concatenate([np.arange(7200) * (TWO_PI / 7200), [D(120.0), D(160.0), D(290.0)]])),
        _RNG.uniform(-TWO_PI, 2.0 * TWO_PI, 5000)]


@pytest.mark.parametrize("which", range(len(MANY)))
def test_at_kept_angles_across_programs_is_a_fresh_programs_call(which):
    """MotionProgram.at_kept_angles of programs in a row (the many angles' layout kept by their
    bytes across programs at the same places) against the program's own call, evaluated with
    nothing kept, bit for bit (signs of zeros included), and the cycloidal rise's closed form."""
    theta = MANY[which]
    assert theta.size > laws._CALL_MEMO_ANGLES
    laws._angle_layout.cache_clear()
    gots, hits = [], []
    for args in SEQUENCE:
        before = laws._angle_layout.cache_info().hits
        gots.append(_program(*args).at_kept_angles(theta))
        hits.append(laws._angle_layout.cache_info().hits > before)
    assert hits[1] and hits[3] and hits[5] and hits[7] and not hits[4]  # the same places: kept; other spans: made
    for k, (args, got) in enumerate(zip(SEQUENCE, gots)):
        want = _program(*args)(theta)  # more angles than __call__ keys: its own sorting and bases
        for a, b in zip(got, want):
            assert a.flags.writeable and a.shape == theta.shape
            assert np.array_equal(a, b), (k, which)
            assert np.array_equal(np.signbit(a), np.signbit(b)), (k, which)
        lift, rise = args[0], D(args[1])
        on_turn = np.mod(theta, TWO_PI)
        inside = on_turn < rise
        x = on_turn[inside] / rise
        assert np.allclose(got[0][inside], lift * (x - np.sin(TWO_PI * x) / TWO_PI), rtol=0.0, atol=CLOSED_FORM_TOL * abs(lift) * 10), k
    with pytest.raises(ParameterError):
        _program(12.0).at_kept_angles(theta[:10].reshape(5, 2))  # not 1-D
    with pytest.raises(ParameterError):
        _program(12.0).at_kept_angles(np.full(5000, math.nan))


class _CalledLaw:
    """A motion program seen through its call alone (no at_kept_angles): sizing evaluates it as
    before, ``law(theta)``; breaks, peaks and the rest are the program's."""

    def __init__(self, program: MotionProgram) -> None:
        self._program = program

    def __call__(self, theta: np.ndarray):
        return self._program(theta)

    def __getattr__(self, name: str):
        if name == "at_kept_angles":
            raise AttributeError(name)
        return getattr(self._program, name)


def test_base_radius_advice_of_failing_lifts_in_a_row_is_the_advice_with_nothing_kept():
    """The base-radius search of designs that fail the pressure angle, another lift each (a lift
    sweep: the check grid's layout kept across their laws, sizing's _SampledLaw by
    at_kept_angles), against the same searches with nothing kept (no advice, no layout) and the
    search's own claim: the quoted least base radius passes and 0.001 mm less fails (measure)."""
    from camgen.synthesis import advice_cache
    from camgen.synthesis.followers import FollowerSpec
    from camgen.synthesis.sizing import DesignLimits, base_radius_advice, measure

    follower = FollowerSpec("roller", 25.0, roller_radius=5.0)
    limits = DesignLimits(max_pressure_angle=D(30.0))
    lifts = (26.0, 31.5, 26.5, 40.0)
    advice_cache._outcome.cache_clear()
    laws._angle_layout.cache_clear()
    got = [base_radius_advice(follower, _program(lift), limits) for lift in lifts]
    assert laws._angle_layout.cache_info().hits >= len(lifts) - 1
    for lift, advice in zip(lifts, got):
        advice_cache._outcome.cache_clear()
        laws._angle_layout.cache_clear()
        assert advice == base_radius_advice(follower, _program(lift), limits), lift
        # the search before: the law's own call at the check grid (a law without at_kept_angles)
        assert advice == base_radius_advice(follower, _CalledLaw(_program(lift)), limits), lift
        assert measure(follower, _program(lift)).violations(limits)  # a failing design
        passing = measure(FollowerSpec("roller", advice.low, roller_radius=5.0), _program(lift))
        assert not passing.violations(limits), lift
        assert measure(FollowerSpec("roller", round(advice.low - 0.001, 3), roller_radius=5.0), _program(lift)).violations(limits), lift
    assert len({a.low for a in got}) == len(lifts)
    # what the trials read: the law's values at the check grid, those of its own call, bit for bit
    from camgen.synthesis import sizing
    from camgen.synthesis.followers import check_grid

    for lift in lifts:
        program = _program(lift)
        theta = check_grid(program, limits.check_step)
        for a, b in zip(sizing._SampledLaw(program)(theta), program(theta)):
            assert np.array_equal(a, b) and np.array_equal(np.signbit(a), np.signbit(b)), lift


def test_a_jerk_impulse_inside_a_segment_is_an_infinite_jerk():
    """Two constant-acceleration segments (rise, return) join smoothly, but each jumps in
    acceleration at its middle: peak_values' infinite jerk from the law's own breaks, against
    the acceleration on either side of every break (a jump of ~2 x 4 h / beta^2, Norton's
    constant-acceleration law), and none where the law has no jump (the modified trapezoid)."""
    eps = 1e-9
    for name, impulse in (("constant_acceleration", True), ("modified_trapezoid", False)):
        program = MotionProgram([Segment(name, D(180.0), 10.0), Segment(name, D(180.0), -10.0)])
        angles = np.mod(program.breaks, TWO_PI)
        _, _, before, _ = program(angles - eps)
        _, _, after, _ = program(angles + eps)
        jumps = bool(np.any(np.abs(after - before) > 1e-3 * program.peak_values().acceleration))
        assert jumps == impulse, name
        assert program.peak_values().infinite_jerk == impulse, name
        assert not program.peak_values().infinite_acceleration
