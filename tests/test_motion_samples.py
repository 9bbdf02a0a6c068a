"""A disk cam's motion samples (camgen.kinds.disk ``_motion``): their cam angles are made once per
sample count and shared read-only (``_sample_angles``); two cams with other laws in a row each
get the angles ``2 pi k / n`` (numpy's arange, product and division made here) and their own
law's values there, and the cycloidal rise's closed form (Norton, Cam Design and Manufacturing
Handbook, 2nd ed., eq. 3.9: s = h (x - sin(2 pi x) / (2 pi)), x = theta / beta)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.kinds import disk
from camgen.synthesis.followers import FollowerSpec
from camgen.synthesis.laws import MotionProgram, Segment

D = math.radians
#: The closed form against the law's values (direct sines: a few ulps of the lift).
CLOSED_FORM_TOL = 1e-12


def test_motion_samples_of_cams_in_a_row_are_each_laws_own_values():
    follower = FollowerSpec("roller", 40.0, roller_radius=10.0)
    n = disk.MOTION_SAMPLES
    fresh = 2.0 * math.pi * np.arange(n) / n
    for lift, back in ((20.0, "poly345"), (27.5, "cycloidal"), (20.0, "poly345")):
        law = MotionProgram([Segment("cycloidal", D(120.0), lift), Segment("dwell", D(60.0)), Segment(back, D(120.0), -lift),
                             Segment("dwell", D(60.0))])
        motion = disk._motion(follower, law)
        assert np.array_equal(motion.cam_angle, fresh)
        assert not motion.cam_angle.flags.writeable
        with pytest.raises(ValueError):
            motion.cam_angle[0] = 1.0
        for got, want in zip((motion.displacement, motion.velocity, motion.acceleration, motion.jerk), law(fresh.copy())):
            assert np.array_equal(got, want), lift
        inside = fresh < D(120.0)
        x = fresh[inside] / D(120.0)
        assert np.allclose(motion.displacement[inside], lift * (x - np.sin(2.0 * math.pi * x) / (2.0 * math.pi)), rtol=0.0,
                           atol=CLOSED_FORM_TOL * lift * 10)
    for m in (720, 3600, 7):  # other counts in a row: each its own angles
        assert np.array_equal(disk._sample_angles(m), 2.0 * math.pi * np.arange(m) / m), m
