"""The force terms :func:`camgen.dynamics.analyse` keeps for the next design on the same motion
values, train and speed (issue 28 item 6: a radius sweep's law, train and speed do not change):
designs in a row, each against the same analysis on writable copies (never kept), bit for bit,
and the generalised force against its closed form ``k (s - s_min) + P + W + c s' w + m s'' w^2``
(translating follower, Rothbart ch. 10's force balance)."""
from __future__ import annotations

import math

import numpy as np

from camgen import dynamics as dy

N = 720
THETA = 2 * math.pi * np.arange(N) / N
THETA.flags.writeable = False
#: The closed form adds the terms in another order: relative tolerance of the comparison.
CLOSED_FORM_RTOL = 1e-12


def _block(lift: float) -> np.ndarray:
    """A read-only (3, N) block of s, s', s'' (mm, mm/rad, mm/rad^2) of a harmonic lift, owning its data."""
    block = np.stack([lift * (1 - np.cos(THETA)) / 2, lift * np.sin(THETA) / 2, lift * np.cos(THETA) / 2])
    block.flags.writeable = False
    return block


def _kin(block: np.ndarray, phi_scale: float, copies: bool = False, theta: np.ndarray = THETA) -> dy.Kinematics:
    s, ds, d2s = (np.array(row) if copies else row for row in block)
    phi = phi_scale * np.sin(theta)
    return dy.Kinematics(np.array(theta) if copies else theta, s, ds, d2s, phi, np.full(N, 40.0 + 10 * phi_scale), 10.0)


def _same(kept: dy.DynamicsResult, fresh: dy.DynamicsResult) -> None:
    for name in ("generalised_force", "contact_force", "follower_force", "torque", "power", "hertz_stress"):
        assert np.array_equal(getattr(kept, name), getattr(fresh, name)), name
    for name in ("jump_rpm", "min_preload", "min_spring_rate", "torque_peak", "torque_peak_index", "torque_rms", "power_peak",
                 "power_rms", "energy_per_turn", "mean_power"):
        assert getattr(kept, name) == getattr(fresh, name), name
    assert kept.jump_ranges_deg == fresh.jump_ranges_deg


def test_designs_in_a_row_equal_each_analysed_alone():
    material = dy.ContactMaterial(width=10.0, allowable_stress=1000.0)
    train = dy.FollowerTrain(mass=0.4, spring_rate=1.5, preload=40.0, damping=10.0)
    other_train = dy.FollowerTrain(mass=0.4, spring_rate=1.5, preload=40.0, damping=10.0)  # equal, another object
    heavy = dy.FollowerTrain(mass=4.0, spring_rate=0.5, preload=5.0, damping=10.0)  # jumps at 600 rpm
    first, second = _block(20.0), _block(25.0)
    rows = [(first, 0.3, train, 300.0), (first, 0.2, train, 300.0), (first, 0.1, train, 300.0),  # a radius sweep: kept
            (first, 0.2, train, 600.0), (first, 0.2, other_train, 600.0), (first, 0.2, heavy, 600.0), (first, 0.2, heavy, 600.0),
            (second, 0.2, heavy, 600.0), (second, 0.3, heavy, 300.0), (second, 0.2, train, 300.0)]  # each change alone
    for i, (block, scale, tr, rpm) in enumerate(rows):
        kept = dy.analyse(_kin(block, scale), tr, rpm, material, jump_margin=2.0)
        fresh = dy.analyse(_kin(block, scale, copies=True), tr, rpm, material, jump_margin=2.0)
        _same(kept, fresh)
        assert kept.generalised_force.flags.writeable == (i not in (1, 2, 6)) and fresh.generalised_force.flags.writeable  # kept from the second design
        assert dy.spring_hints(kept, kept.analysed[0]) == dy.spring_hints(fresh, fresh.analysed[0])
        s, ds, d2s = block
        w = rpm * dy.RPM_TO_RAD_PER_S
        weight = tr.mass * tr.gravity  # down, against +y: resists the motion
        closed = (tr.spring_rate * (s - s.min()) + tr.preload + weight + tr.damping * 1e-3 * ds * w
                  + tr.mass * 1e-3 * d2s * w * w)
        np.testing.assert_allclose(kept.generalised_force, closed, rtol=CLOSED_FORM_RTOL, atol=CLOSED_FORM_RTOL * 100)
    assert dy.analyse(_kin(_block(20.0), 0.2), heavy, 600.0).jump_rpm < 600.0  # the heavy train jumps in its rows at 600 rpm


def test_the_same_terms_on_other_angles_have_their_own_summaries():
    """The summaries weigh the samples by the angles' spacing: the same motion values on unevenly
    spaced angles (another read-only array) give another RMS torque and work per turn."""
    train = dy.FollowerTrain(mass=0.4, spring_rate=1.5, preload=40.0, damping=10.0)
    block = _block(20.0)
    uneven = THETA + 0.3 * (2 * math.pi / N) * np.sin(3 * THETA)  # still increasing, in [0, 2 pi)
    uneven.flags.writeable = False
    results = []
    for theta in (THETA, uneven, uneven, THETA):
        kept = dy.analyse(_kin(block, 0.2, theta=theta), train, 300.0)
        _same(kept, dy.analyse(_kin(block, 0.2, copies=True, theta=theta), train, 300.0))
        results.append(kept)
    assert results[2].torque_rms != results[3].torque_rms and results[2].torque is results[3].torque  # the same kept terms


def test_a_view_of_a_writable_block_or_another_place_in_the_block_is_not_taken_for_the_kept_one():
    train = dy.FollowerTrain(mass=0.4, spring_rate=1.5, preload=40.0, damping=10.0)
    block = _block(20.0)
    dy.analyse(_kin(block, 0.2), train, 300.0)
    swapped = dy.Kinematics(THETA, block[0], block[2], block[1], np.zeros(N), np.full(N, 40.0), 10.0)  # the kept block, s' and s'' swapped
    alone = dy.Kinematics(THETA, np.array(block[0]), np.array(block[2]), np.array(block[1]), np.zeros(N), np.full(N, 40.0), 10.0)
    dy.analyse(_kin(block, 0.2), train, 300.0)
    _same(dy.analyse(swapped, train, 300.0), dy.analyse(alone, train, 300.0))
    shifted = np.stack([block[1], block[0], block[2]])  # s and s' swapped: other places than the kept views
    shifted.flags.writeable = False
    _same(dy.analyse(_kin(shifted, 0.2), train, 300.0), dy.analyse(_kin(shifted, 0.2, copies=True), train, 300.0))
    writable = np.array(block)  # the kept values in a block that may change
    s, ds, d2s = writable
    s.flags.writeable = ds.flags.writeable = d2s.flags.writeable = False
    dy.analyse(dy.Kinematics(THETA, s, ds, d2s, np.zeros(N), np.full(N, 40.0), 10.0), train, 300.0)
    writable[0] *= 2.0
    again = dy.analyse(dy.Kinematics(THETA, s, ds, d2s, np.zeros(N), np.full(N, 40.0), 10.0), train, 300.0)
    alone = dy.analyse(dy.Kinematics(THETA, np.array(s), ds, d2s, np.zeros(N), np.full(N, 40.0), 10.0), train, 300.0)
    _same(again, alone)


def test_a_design_analysed_in_another_thread_meanwhile_leaves_the_kept_terms_its_own():
    """Thread B is inside the kept slot's lookup (its law seen once before: the second design) when
    thread A analyses another law laid out alike: afterwards the slot answers A's law with A's terms
    (the analysis of writable copies, never kept).  The slot is read and replaced holding a lock, so
    A waits for B; B's pause ends by itself when A cannot come in."""
    import inspect
    import sys
    import threading

    train = dy.FollowerTrain(mass=0.4, spring_rate=1.5, preload=40.0, damping=10.0)
    first, second = _block(20.0), _block(30.0)
    dy.analyse(_kin(first, 0.2), train, 300.0)  # B's law seen once
    code = dy._KeptLawTerms.terms_of.__wrapped__.__code__
    lines, start = inspect.getsourcelines(dy._KeptLawTerms.terms_of.__wrapped__)
    pause_at = start + next(i for i, line in enumerate(lines) if "if self.places is None" in line)
    b_inside, a_done = threading.Event(), threading.Event()

    def tracer(frame, event, arg):  # type: ignore[no-untyped-def]
        if frame.f_code is not code:
            return None

        def local(fr, ev, a):  # type: ignore[no-untyped-def]
            if ev == "line" and fr.f_lineno == pause_at and not b_inside.is_set():
                b_inside.set()
                a_done.wait(1.0)  # A analyses meanwhile, unless it waits for B
            return local
        return local

    def b() -> None:
        sys.settrace(tracer)
        try:
            dy.analyse(_kin(first, 0.2), train, 300.0)
        finally:
            sys.settrace(None)

    def a() -> None:
        assert b_inside.wait(10)
        dy.analyse(_kin(second, 0.2), train, 300.0)  # A's law, seen once
        a_done.set()

    threads = [threading.Thread(target=b), threading.Thread(target=a)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(20)
    assert b_inside.is_set() and a_done.is_set()
    kept = dy.analyse(_kin(second, 0.2), train, 300.0)  # A's law again: the slot's answer
    _same(kept, dy.analyse(_kin(second, 0.2, copies=True), train, 300.0))
