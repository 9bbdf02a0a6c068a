"""The bases a motion program's uniform grids share across programs (camgen.synthesis.laws
``_uniform_basis``): programs that differ in their lifts (a sweep of the rise and return) take the
kept powers and sines of their pieces and must give what a program evaluated with nothing kept
gives, bit for bit, and the closed form of the cycloidal rise (Norton, Cam Design and
Manufacturing Handbook, 2nd ed., eq. 3.9: s = h (x - sin(2 pi x) / (2 pi)), x = theta / beta)."""
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
#: Closed form against the grid's values (angle-addition sines: a few ulps of the lift).
CLOSED_FORM_TOL = 1e-12


def _program(lift: float, rise_deg: float = 120.0, dwell_deg: float = 40.0) -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(rise_deg), lift), Segment("dwell", D(dwell_deg)),
                          Segment("poly345", D(130.0), -lift), Segment("dwell", D(230.0 - rise_deg - dwell_deg))])


def _added(program: MotionProgram) -> np.ndarray:
    return np.unique(np.mod(program.breaks, TWO_PI))


# (rise and return lift, rise span, first dwell): lifts only (the same places), other spans, back again
SEQUENCE = [(12.0, 120.0, 40.0), (17.0, 120.0, 40.0), (-9.0, 120.0, 40.0), (-14.0, 120.0, 40.0), (12.0, 100.0, 60.0),
            (17.0, 100.0, 60.0)]


def _kept_hits() -> int:
    """Hits of the bases kept across programs: the pieces' (_uniform_basis) and the grid's layout
    (_grid_layout, which holds them)."""
    return laws._uniform_basis.cache_info().hits + laws._grid_layout.cache_info().hits


def _nothing_kept() -> None:
    laws._uniform_basis.cache_clear()
    laws._grid_layout.cache_clear()


@pytest.mark.parametrize("n", [7200, 2880])
def test_programs_with_other_lifts_share_bases_and_give_fresh_values(n):
    _nothing_kept()
    gots = []
    for k, (lift, rise, dwell) in enumerate(SEQUENCE):  # the programs in a row, as a sweep's designs
        program = _program(lift, rise, dwell)
        hits = _kept_hits()
        gots.append(program.on_uniform_grid(n, _added(program)))
        if k % 2:  # the places of the program before (evaluated last): its bases serve this one
            assert _kept_hits() > hits, k
    for k, ((lift, rise, dwell), got) in enumerate(zip(SEQUENCE, gots)):
        _nothing_kept()  # a program evaluated with nothing kept
        program = _program(lift, rise, dwell)
        want = program.on_uniform_grid(n, _added(program))
        for a, b in zip(got, want):
            assert np.array_equal(a, b), (k, n)
        # the closed form of the cycloidal rise on the uniform angles inside it
        theta = np.arange(n) * (TWO_PI / n)
        inside = theta < D(rise)
        x = theta[inside] / D(rise)
        assert np.allclose(got[0][:n][inside], lift * (x - np.sin(TWO_PI * x) / TWO_PI), rtol=0.0,
                           atol=CLOSED_FORM_TOL * abs(lift)), k
        assert np.allclose(got[1][:n][inside], lift / D(rise) * (1.0 - np.cos(TWO_PI * x)), rtol=0.0,
                           atol=CLOSED_FORM_TOL * abs(lift) / D(rise)), k


def test_kept_bases_are_read_only_and_the_direct_evaluation_s_neighbours():
    _nothing_kept()
    program = _program(15.0)
    n = 7200
    got = program.on_uniform_grid(n, _added(program))
    assert laws._uniform_basis.cache_info().currsize > 0
    basis = laws._uniform_basis(n, 0, 10, 0.0, D(120.0), 0.0, True, (TWO_PI,), 1)
    assert not basis.flags.writeable
    with pytest.raises(ValueError):
        basis[0, 0] = 2.0
    direct = program(np.arange(n) * (TWO_PI / n))  # direct sines and cosines
    for a, b in zip(got, direct):
        assert np.allclose(a[:n], b, rtol=0.0, atol=1e-9 * max(1.0, float(np.max(np.abs(b)))))


# A segment's options and the laws the Segment docstring gives them to (camgen.synthesis.laws.Segment)
OPTIONS = [("blend", 0.2, "constant_velocity"), ("scca", (0.25, 0.5, 0.25), "scca"),
           ("accel_fraction", 0.4, "asymmetric_modified_sine"), ("start", (0.0, 0.0, 0.0), "polynomial"),
           ("degree", 5, "bspline"), ("interior", ((0.5, 1.0),), "polynomial")]


@pytest.mark.parametrize("key, value, owner", OPTIONS)
def test_a_segment_refuses_another_law_s_option_naming_it(key, value, owner):
    with pytest.raises(ParameterError) as info:
        Segment("cycloidal", D(120.0), 10.0, where="cams.c.segments[0]", **{key: value})
    assert info.value.name == f"cams.c.segments[0].{key}"
    assert owner in info.value.valid


@pytest.mark.parametrize("n", [3600, 1000])
def test_sample_grid_values_are_the_direct_call_s_across_programs_with_other_lifts(n):
    """on_sample_grid(n) against program(2 pi k / n) of a program evaluated with nothing kept, for
    programs in a row that differ in lifts and spans, twice each (kept values); fresh writeable
    arrays each call."""
    theta = 2.0 * math.pi * np.arange(n) / n
    for k, (lift, rise, dwell) in enumerate(SEQUENCE):
        program = _program(lift, rise, dwell)
        got = program.on_sample_grid(n)
        want = _program(lift, rise, dwell)(theta)  # (the direct evaluation: no kept basis)
        for a, b in zip(got, want):
            assert np.array_equal(a, b), (k, n)
        got[0][:] = -1.0  # the caller's own arrays
        again = program.on_sample_grid(n)
        assert again[0].flags.writeable
        for a, b in zip(again, want):
            assert np.array_equal(a, b), (k, n)
        again[1][:] = -2.0
        third = program.on_sample_grid(n)  # (asked twice before: the kept values)
        for a, b in zip(third, want):
            assert np.array_equal(a, b), (k, n)
        half = program.on_sample_grid(n // 2)  # another sample count on the same program
        for a, b in zip(half, _program(lift, rise, dwell)(2.0 * math.pi * np.arange(n // 2) / (n // 2))):
            assert np.array_equal(a, b), (k, n)
    assert "_sample_memo" not in pickle.loads(pickle.dumps(program)).__dict__  # a pickled program: its definition only


#: A segment's exact end values against its evaluated ones at tau = 0 and 1 (relative).
END_TOL = 1e-12


@pytest.mark.parametrize("law, lift", [("cycloidal", 12.0), ("poly345", -7.5), ("harmonic", 3.0), ("modified_trapezoid", 20.0)])
def test_a_segment_s_end_values_are_its_values_at_its_ends(law, lift):
    seg = Segment(law, D(100.0), lift)
    for at_end in (False, True):
        got = seg.end_values(at_end)
        want = [float(v[0]) for v in seg.values(np.array([1.0 if at_end else 0.0]))]
        for n, (a, b) in enumerate(zip(got, want)):
            assert abs(a - b) <= END_TOL * max(1.0, abs(lift) / D(100.0) ** n * 100.0), (law, at_end, n, a, b)
