"""Cams and bodies shared by the export tests (the fixtures ``steering`` and ``contours`` are in conftest.py)."""
from __future__ import annotations

import numpy as np

from camgen.body import BodySpec

STRIDE = (220.0, 160.0, 25.0)
HEIGHT = (220.0, 220.0, 10.0)
BODIES = {
    "stride": BodySpec(thickness=20.0, bore_diameter=20.0, keyway_width=6.0, keyway_depth=2.8, min_wall=3.0),
    "height": BodySpec(thickness=20.0, bore_diameter=8.0, keyway_width=2.0, keyway_depth=1.0, min_wall=3.0),
    "steering": BodySpec(thickness=8.0, bore_diameter=8.0, keyway_width=2.0, keyway_depth=1.0, min_wall=3.0),
}


def radial_error(contour, points):
    """|r - polar radius of the contour| at the points' polar angles (>= their normal distance)."""
    ang = np.arctan2(points[:, 1], points[:, 0])
    return np.abs(np.hypot(points[:, 0], points[:, 1]) - contour.polar_radius(ang))
