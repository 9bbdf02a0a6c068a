"""The kinematics' check of the cam angles done once for a study's shared check-grid angles
(:class:`camgen.dynamics.Kinematics`, issue 28 item 6): the kept angles are a read-only array that
owns its data; an array that is not kept, or was made writable again, is checked as before (the
refusals the rule "strictly increasing cam angles in [0, 2 pi)" asks for), and the lowest position
the check found is ``s.min()`` (numpy's reduction, computed here)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen import dynamics as dy
from camgen.errors import ParameterError

N = 360


def _read_only_angles() -> np.ndarray:
    theta = 2 * math.pi * np.arange(N) / N
    theta.flags.writeable = False
    return theta


def _kin(theta: np.ndarray, s: np.ndarray | None = None) -> dy.Kinematics:
    s = 5.0 * (1.0 - np.cos(theta)) if s is None else s
    return dy.Kinematics(theta, s, 5.0 * np.sin(theta), 5.0 * np.cos(theta), np.zeros(N), np.full(N, 40.0), 10.0)


def test_kept_angles_made_writable_and_changed_are_checked_again():
    theta = _read_only_angles()
    assert _kin(theta).theta is theta  # checked and kept
    assert _kin(theta).theta is theta  # kept: the same array
    theta.flags.writeable = True
    theta[10] = theta[9]  # no longer strictly increasing
    with pytest.raises(ParameterError, match="strictly increasing"):
        _kin(theta)
    theta.flags.writeable = False  # read-only again, still not increasing: it was not kept after the refusal
    with pytest.raises(ParameterError, match="strictly increasing"):
        _kin(theta)


def test_other_arrays_after_kept_angles_are_checked():
    theta = _read_only_angles()
    _kin(theta)
    for bad, why in ((np.r_[theta[:-1], 2 * math.pi], "strictly increasing"), (np.r_[theta[:-1], math.nan], "non-finite value at sample 359"),
                     (theta[::-1].copy(), "strictly increasing"), (np.r_[-1e-9, theta[1:]], "strictly increasing")):
        with pytest.raises(ParameterError, match=why):
            _kin(bad)
        assert _kin(theta).theta is theta
    view = _read_only_angles()[:]  # a read-only view: its base could be changed, never kept
    view.base.flags.writeable = True
    _kin(view)
    view.base[10] = view.base[9]
    with pytest.raises(ParameterError, match="strictly increasing"):
        _kin(view)


def test_lowest_position_is_the_least_sample_and_analyse_matches_unkept_angles():
    theta = _read_only_angles()
    s = 5.0 * (1.0 - np.cos(theta)) + 0.25
    kin = _kin(theta, s)
    assert kin.s_least == float(np.min(s)) == 0.25
    train = dy.FollowerTrain(mass=0.5, spring_rate=2.0, preload=20.0)
    kept = dy.analyse(_kin(theta, s), train, 300.0)
    fresh = dy.analyse(_kin(np.array(theta), s), train, 300.0)  # a writable copy: checked, not kept
    for name in ("generalised_force", "contact_force", "torque"):
        assert np.array_equal(getattr(kept, name), getattr(fresh, name))
    weightless = dy.FollowerTrain(mass=0.0, spring_rate=2.0, preload=20.0, gravity=0.0)
    q = dy.analyse(_kin(theta, s), weightless, 300.0).generalised_force  # no inertia, damping, load or weight: the spring alone
    assert np.array_equal(q, 2.0 * (s - s.min()) + 20.0)


def _rows(values: np.ndarray, writable_block: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Three read-only views (rows) of one block owning its data (read-only unless ``writable_block``)."""
    if not writable_block:
        values.flags.writeable = False
    s, ds, d2s = values
    s.flags.writeable = ds.flags.writeable = d2s.flags.writeable = False
    return s, ds, d2s


def test_views_of_a_kept_block_are_checked_once_per_place_and_other_blocks_as_before():
    theta = _read_only_angles()
    values = np.stack([5.0 * (1.0 - np.cos(theta)) + 0.25, 5.0 * np.sin(theta), 5.0 * np.cos(theta)])
    s, ds, d2s = _rows(values)
    for _ in range(2):  # kept, then read again
        kin = dy.Kinematics(theta, s, ds, d2s, np.zeros(N), np.full(N, 40.0), 10.0)
        assert kin.s_least == float(np.min(s)) == 0.25
    swapped = dy.Kinematics(theta, ds, s, d2s, np.zeros(N), np.full(N, 40.0), 10.0)  # the same block, other places
    assert swapped.s_least == float(np.min(ds)) == -5.0
    bad = np.array(values)
    bad[2, 7] = math.nan
    with pytest.raises(ParameterError, match="non-finite value at sample 7"):
        dy.Kinematics(theta, *_rows(bad), np.zeros(N), np.full(N, 40.0), 10.0)
    block = np.array(values)  # a writable block: its views' values may change, never kept
    s2, ds2, d2s2 = _rows(block, writable_block=True)
    dy.Kinematics(theta, s2, ds2, d2s2, np.zeros(N), np.full(N, 40.0), 10.0)
    block[1, 3] = math.inf
    with pytest.raises(ParameterError, match="non-finite value at sample 3"):
        dy.Kinematics(theta, s2, ds2, d2s2, np.zeros(N), np.full(N, 40.0), 10.0)
