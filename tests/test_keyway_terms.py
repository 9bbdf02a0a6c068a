"""The keyway's own numbers kept per body (camgen.body.kept_keyway_terms, a bounded cache):
wall_left of bodies in a row (other keyway angles, widths, depths, bores, -0.0 and 0.0, the first
again) bit for bit what it gives with nothing kept, and what camgen.wall_polygon gives from the
corners alone; the kept arrays read-only."""
import math

import numpy as np
import pytest

from camgen.body import BodySpec, _kept_terms, kept_keyway_terms, wall_left
from camgen.synthesis.followers import FollowerSpec, cam_envelope
from camgen.synthesis.laws import MotionProgram, Segment
from camgen.wall_polygon import keyway_terms, wall_polygon

D = math.radians


@pytest.fixture(scope="module")
def profile():
    law = MotionProgram([Segment("cycloidal", D(120), 20.0), Segment("dwell", D(40)), Segment("poly345", D(130), -20.0),
                         Segment("dwell", D(70))], unit="mm")
    return cam_envelope(FollowerSpec(kind="roller", base_radius=14.0, roller_radius=8.0, offset=3.0), law).profile


BODIES = [BodySpec(bore_diameter=12.0, keyway_width=4.0, keyway_depth=1.8),
          BodySpec(bore_diameter=12.0, keyway_width=4.0, keyway_depth=1.8, keyway_angle=0.0),
          BodySpec(bore_diameter=12.0, keyway_width=4.0, keyway_depth=1.8, keyway_angle=-0.0),
          BodySpec(bore_diameter=16.0, keyway_width=5.0, keyway_depth=2.3, keyway_angle=D(200.0)),
          BodySpec(bore_diameter=12.0, keyway_width=3.0, keyway_depth=1.8, keyway_angle=D(33.0)),
          BodySpec(bore_diameter=12.0),
          BodySpec(bore_diameter=12.0, keyway_width=4.0, keyway_depth=1.8)]


def test_bodies_in_a_row_are_each_body_with_nothing_kept(profile):
    kept = [wall_left(profile, body) for body in BODIES]
    fresh = []
    for body in BODIES:
        _kept_terms.cache_clear()
        fresh.append(wall_left(profile, body))
    assert kept == fresh
    assert len({w for w in kept}) >= 4  # the bodies differ in their walls


def test_kept_terms_are_the_corners_own_and_read_only(profile):
    for body in BODIES[:5]:
        terms = kept_keyway_terms(body)
        corners = body.keyway_corners()
        assert terms.corners.tobytes() == corners.tobytes()
        assert np.signbit(terms.along).tolist() == np.signbit(np.array([math.cos(body.keyway_angle), math.sin(body.keyway_angle)])).tolist()
        assert terms.corner_reach == float(np.hypot(corners[1:3, 0], corners[1:3, 1]).max())
        for a in (terms.corners, terms.side, terms.across, terms.mid, terms.along, terms.across_dir):
            assert not a.flags.writeable
        # the wall polygon from the corners alone (its terms made there) is the one with the kept terms
        bore = body.bore_diameter / 2
        a, b = wall_polygon(profile, 1e-4, bore, corners), wall_polygon(profile, 1e-4, bore, terms.corners, terms)
        assert a.points.tobytes() == b.points.tobytes() and a.successor.tolist() == b.successor.tolist() and a.near_axis == b.near_axis
        assert corners.flags.writeable  # the caller's corners are not made read-only
    assert keyway_terms(BODIES[2].keyway_corners(), -0.0).across_dir.tobytes() != keyway_terms(BODIES[1].keyway_corners(), 0.0).across_dir.tobytes()
