"""The continuity check's joint angles and where-lists in Python floats (camgen/kinds/disk.py
``_continuity``) against numpy's fmod and remainder and its where-list of a masked array, as the check
computed them before, bit for bit (profile_curvatures' split arrays: tests/test_build_reuse.py)."""
import math

import numpy as np


def test_python_fmod_and_remainder_are_numpys_bit_for_bit():
    rng = np.random.default_rng(7)
    two_pi = 2.0 * math.pi
    ends = np.concatenate([rng.uniform(-20.0, 20.0, 2000), [0.0, -0.0, two_pi, -two_pi, 4.0 * math.pi, 1e-300, -1e-300,
                                                          math.nextafter(two_pi, 0.0), math.nextafter(two_pi, 7.0)]])
    for sigma in (1.0, -1.0):
        before = np.mod(np.fmod(-sigma * ends, two_pi), two_pi)
        now = np.array([math.fmod(-sigma * e, two_pi) % two_pi for e in ends.tolist()])
        assert before.tobytes() == now.tobytes()  # the signs of zeros too


def test_the_continuity_where_list_is_numpys_for_any_mask():
    from camgen.checks import where_degrees

    rng = np.random.default_rng(3)
    angles = rng.uniform(0.0, 2.0 * math.pi, 9)
    for _ in range(20):
        jumps = (rng.random(9) < 0.4).tolist()
        now = [w for a, jump in zip(angles.tolist(), jumps) if jump for w in where_degrees(a)]
        # camgen.checks.where_degrees of the masked array before issue 28 item 6, verbatim
        before = [round(float(a), 6) for a in np.mod(np.degrees(np.atleast_1d(angles[np.array(jumps, dtype=bool)])), 360.0)]
        assert now == before

