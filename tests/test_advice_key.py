"""The law key of the base-radius advice cache (camgen.synthesis.advice_cache) kept on its motion
program (made once per program object: a radius sweep's failing designs ask with the same
program): equal programs (other objects, the same segments) share one search, a program with
other lifts asked right after is searched again and gets the search's own answer (made with
nothing kept), and a pickled program carries no key."""
from __future__ import annotations

import math
import pickle

from camgen.synthesis import advice_cache
from camgen.synthesis.followers import FollowerSpec
from camgen.synthesis.laws import MotionProgram, Segment
from camgen.synthesis.sizing import DesignLimits, _advice_search, base_radius_advice

D = math.radians
LIMITS = DesignLimits(max_pressure_angle=D(30.0))


def _program(lift: float) -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(120.0), lift), Segment("dwell", D(60.0)), Segment("poly345", D(120.0), -lift),
                          Segment("dwell", D(60.0))])


def test_programs_in_a_row_share_a_search_only_when_equal():
    advice_cache._outcome.cache_clear()
    follower = FollowerSpec("roller", 18.0, roller_radius=10.0)
    # (lift, another object of an earlier lift, expected hit)
    sequence = [(20.0, False), (20.0, True), (24.0, False), (20.0, True), (24.0, True), (22.0, False)]
    kept: dict[float, MotionProgram] = {}
    for lift, hit in sequence:
        program = _program(lift)
        for _ in range(2):  # the same object twice: its kept key
            before = advice_cache._outcome.cache_info().hits
            got = base_radius_advice(FollowerSpec("roller", 18.0 + lift / 100.0, roller_radius=10.0), program, LIMITS)
            assert got == _advice_search(follower, _program(lift), LIMITS, 1e-4, 32, 3), lift  # the search itself, nothing kept
            assert (advice_cache._outcome.cache_info().hits > before) == (hit or _ > 0), (lift, _)
        assert advice_cache.PROGRAM_KEY in program.__dict__
        assert advice_cache.PROGRAM_KEY not in pickle.loads(pickle.dumps(program)).__dict__
        kept[lift] = program
    assert base_radius_advice(follower, kept[20.0], LIMITS) != base_radius_advice(follower, kept[24.0], LIMITS)
