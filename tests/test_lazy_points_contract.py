"""What the evaluation's shortcuts promise callers of the public functions (a review of the speed
work, issue 28 item 6): a roller's points made on first use are the points of the angles and law
values asked, whatever the caller does afterwards and from whichever thread; the undercut measures
kept with a Kinematics answer only for the follower they were made for; a NaN radius does not hide
a concave one from the contact-stress refusal."""
from __future__ import annotations

import inspect
import math
import sys
import threading

import numpy as np
import pytest

from camgen import dynamics as dy
from camgen.errors import GeometryError
from camgen.synthesis import followers as fo
from camgen.synthesis.laws import MotionProgram, Segment

D = math.radians


def _law() -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(110), 16.0), Segment("dwell", D(50)),
                          Segment("poly345", D(90), -16.0), Segment("dwell", D(110))], unit="mm")


def _roller(base: float = 40.0) -> fo.FollowerSpec:
    return fo.FollowerSpec(kind="roller", base_radius=base, roller_radius=10.0, offset=12.0)


def test_the_points_are_those_of_the_angles_asked_after_the_caller_reuses_its_buffer() -> None:
    f, law = _roller(), _law()
    theta = np.linspace(0.0, 2.0 * math.pi, 721)[:-1] + 0.0003
    reference = fo.contact_points(f, law, theta.copy())  # the contact point alone, another path
    k = fo.kinematics(f, law, theta)
    theta += 0.5  # the caller's buffer, reused before the points are read
    assert np.array_equal(k.contact_point, reference)
    assert not k.s.flags.writeable and not k.theta.flags.writeable
    with pytest.raises(ValueError):
        k.s[:] = 0.0  # a write that would change the points made later is refused


def test_points_asked_from_two_threads_at_the_worst_moment_are_made_once_for_both() -> None:
    """Thread B stops after it found the points not made and before it reads their terms; thread A
    makes them meanwhile (and drops the terms): B must return A's points."""
    f, law = _roller(), _law()
    theta = np.linspace(0.0, 2.0 * math.pi, 73)[:-1]
    k = fo.kinematics(f, law, theta)
    expected = fo.contact_points(f, law, theta)
    code = fo._CurvePoints.points.__code__
    lines, first = inspect.getsourcelines(fo._CurvePoints.points)
    pause_at = first + next(i for i, line in enumerate(lines) if "terms = self._terms" in line)
    b_inside, a_done = threading.Event(), threading.Event()

    def tracer(frame, event, arg):  # type: ignore[no-untyped-def]
        if frame.f_code is not code:
            return None

        def local(fr, ev, a):  # type: ignore[no-untyped-def]
            if ev == "line" and fr.f_lineno == pause_at:
                b_inside.set()
                a_done.wait(10)
            return local
        return local

    out: dict[str, object] = {}

    def b() -> None:
        sys.settrace(tracer)
        try:
            out["b"] = k.contact_point
        except BaseException as exc:  # noqa: BLE001 (reported below)
            out["b"] = exc
        finally:
            sys.settrace(None)

    def a() -> None:
        assert b_inside.wait(10)
        out["a"] = k.contact_point
        a_done.set()

    threads = [threading.Thread(target=b), threading.Thread(target=a)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(20)
    assert b_inside.is_set() and a_done.is_set()  # the interleaving happened
    for name in "ab":
        assert isinstance(out[name], np.ndarray), out[name]
        assert np.array_equal(out[name], expected)


def test_the_kept_undercut_measures_answer_only_for_their_own_follower() -> None:
    """Kinematics of a base radius 40 mm asked about a 3 mm base: the small cam's own failures
    (its own kinematics, and the measures made from the law's values afresh) and the undercut
    r kappa >= 1 of the small cam's pitch curvature."""
    law, theta = _law(), np.linspace(0.0, 2.0 * math.pi, 3601)[:-1]
    big, small = _roller(40.0), _roller(3.0)
    k_big, k_small = fo.kinematics(big, law, theta), fo.kinematics(small, law, theta)
    asked = fo.profile_failures(small, k_big)
    own = fo.profile_failures(small, k_small)
    fresh = fo._pitch_failures(small, k_big.s, k_big.ds, k_big.d2s)
    assert [r for r, _ in asked] == [r for r, _ in own] == [r for r, _ in fresh]
    for (_, m1), (_, m2), (_, m3) in zip(asked, own, fresh):
        assert np.array_equal(m1, m2) and np.array_equal(m1, m3)
    undercut = asked[-1][1]
    assert k_small.pitch_curvature is not None
    assert undercut.sum() == np.count_nonzero(small.roller_radius * k_small.pitch_curvature >= 1.0) > 0
    assert not fo.profile_failures(big, k_big)[-1][1].any()  # the big cam's own answer: no undercut


def test_a_nan_radius_does_not_hide_a_concave_one_tighter_than_the_follower() -> None:
    material = dy.ContactMaterial(width=10.0)
    rho = np.array([np.nan, -3.0, 20.0])  # the -3 mm concave radius is tighter than the 5 mm follower
    with pytest.raises(GeometryError, match="radius of curvature 3 mm"):
        dy.hertz_line_stress(np.full(3, 100.0), rho, 5.0, material)
    with pytest.raises(GeometryError, match="radius of curvature 3 mm"):
        dy.hertz_line_stress(np.full(2, 100.0), rho[1:], 5.0, material)  # as without the nan


def test_the_failing_conditions_of_another_follower_are_its_own() -> None:
    """:func:`failing_conditions` (the screened undercut check) asked about a 3 mm base with the
    kinematics of a 40 mm base: the small cam's own failing conditions."""
    law, theta = _law(), np.linspace(0.0, 2.0 * math.pi, 3601)[:-1]
    big, small = _roller(40.0), _roller(3.0)
    k_big, k_small = fo.kinematics(big, law, theta), fo.kinematics(small, law, theta)
    asked = fo.failing_conditions(small, k_big)
    own = [(r, m) for r, m in fo._pitch_failures(small, k_small.s, k_small.ds, k_small.d2s) if m.any()]
    assert [r for r, _ in asked] == [r for r, _ in own] and asked
    assert all(np.array_equal(m1, m2) for (_, m1), (_, m2) in zip(asked, own))
    assert fo.failing_conditions(big, k_big) == []
