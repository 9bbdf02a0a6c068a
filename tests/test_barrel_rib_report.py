"""A barrel cam's report section for a rib (track = "rib"): the faces are named as the rib's, and
the animation shows the rib between the follower's two rollers, each roller's axis at the
cycloidal law's height (closed form: Norton, *Design of Machinery*, eq. 8.6) less or plus
o = rib_width / 2 + Rr + c / 2, against the groove's one roller on the pitch curve."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from test_barrel_form import CLEAR, H, RR, cam, cycloidal, run

RIB_W, LENGTH = 12.0, 90.0
#: the animation's frames are written to 4 decimals
FRAME_TOL = 1e-4
#: how far a drawn roller (radius w, centred on its axis) may stand off the drawn face it rides: the
#: drawing develops the cam at R_m, where the roller's true section is a circle only to about
#: w^2 / (2 R_m) * (its slope)^2 (< 0.02 mm here), and the faces are polylines of 720 points
CONTACT_TOL = 0.02


def _faces(html: str) -> tuple[list[np.ndarray], float, float]:
    """The drawn faces (x, z polylines of the strip's first copy) and the strip's translation at the
    first and the last frame."""
    paths = re.findall(r"<path d='M ([^']*)' fill='none' stroke='#1f4e79'", html)
    shift = re.search(r"type='translate' from='([-\d.]+) 0' to='([-\d.]+) 0'", html)
    assert shift is not None
    return ([np.array([[float(v) for v in point.split(",")] for point in p.split()]) for p in paths],
            float(shift.group(1)), float(shift.group(2)))


def _rollers(html: str) -> list[np.ndarray]:
    """Each animated roller's frames (e, z) from the report's SVG animation."""
    tracks = re.findall(r"type='translate' values='([^']*)'", html)
    return [np.array([[float(v) for v in frame.split()] for frame in track.split(";")]) for track in tracks]


@pytest.mark.parametrize("track", ["groove", "rib"])
def test_the_animation_shows_a_groove_under_one_roller_and_a_rib_between_two(track):
    extra = {"track": "rib", "rib_width_mm": RIB_W} if track == "rib" else {}
    files, _ = run(cam(cylinder_length_mm=LENGTH, **extra))
    page = files["report.html"]
    rollers = _rollers(page)
    z0 = (LENGTH - H) / 2.0  # the default pitch_z_mm: the travel centred on the cylinder (lift 0 .. H)
    o = RIB_W / 2.0 + RR + CLEAR / 2.0
    offsets = (-o, o) if track == "rib" else (0.0,)
    assert len(rollers) == len(offsets)
    for frames, offset in zip(rollers, offsets):
        theta = np.linspace(0.0, 2.0 * math.pi, len(frames))
        assert np.max(np.abs(frames[:, 0])) <= FRAME_TOL  # a translating follower: no tangential offset
        assert np.max(np.abs(frames[:, 1] - (z0 + cycloidal(theta) + offset))) <= FRAME_TOL
    faces, first, last = _faces(page)
    w = RR + CLEAR / 2.0
    for k in range(0, len(rollers[0]) - 1, 7):  # the strip moves linearly in time, the rollers frame by frame
        shift = first + (last - first) * k / (len(rollers[0]) - 1)
        for frames in rollers:
            gap = min(float(np.min(np.hypot(f[:, 0] + shift - frames[k, 0], f[:, 1] - frames[k, 1]))) for f in faces)
            assert w - FRAME_TOL <= gap <= w + CONTACT_TOL, (k, gap)
    named = "face of the rib" if track == "rib" else "wall"
    other = "wall at R_m" if track == "rib" else "face of the rib"
    assert f"upper {named} at R_m" in page and f"lower {named} at R_m" in page
    assert other not in page
    assert ("between the rollers" in page) == (track == "rib")
