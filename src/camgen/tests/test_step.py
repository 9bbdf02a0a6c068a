"""STEP solids, read back by OpenCASCADE."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.tests.cams import BODIES


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_step_solid_is_exact(name, contours):
    from camgen.export.step import step_bytes, step_volume

    contour, body = contours[name], BODIES[name]
    data = step_bytes(contour, body, name)
    assert data == step_bytes(contour, body, name)  # deterministic
    text = data.decode("ascii")
    assert text.startswith("ISO-10303-21;") and "AUTOMOTIVE_DESIGN" in text and "SI_UNIT(.MILLI.,.METRE.)" in text
    cubic = "B_SPLINE_CURVE_WITH_KNOTS('',3,"  # (degree-1 B-splines are OCCT's parameter-space pcurves)
    if name == "stride":
        assert text.count("CIRCLE(") >= 2 * (6 + 1)  # six arcs and the bore, on both faces
        assert cubic not in text
    else:
        assert cubic in text
    r, h = body.bore_diameter / 2, body.keyway_width / 2
    keyway = 2 * h * (r + body.keyway_depth) - (h * math.sqrt(r * r - h * h) + r * r * math.asin(h / r))
    exact = (contour.area - math.pi * r * r - keyway) * body.thickness
    # OCCT integrates planar faces bounded by circles exactly; on B-spline boundaries its default
    # integration is approximate (shared/research/ecosystem.md section 6)
    assert step_volume(data) == pytest.approx(exact, rel=1e-9 if name == "stride" else 1e-4)


def test_bspline_form_has_the_fewest_knots_and_is_exact(steering):
    from scipy.interpolate import BSpline

    from camgen.export.dxf import spline_bspline

    for contour, per_piece in ((steering.pitch, 1), (steering.profile, 2)):  # C2 pitch, C1 refitted offset
        seg = contour.segments[0]
        knots, controls = spline_bspline(seg)
        assert len(controls) == per_piece * seg.n_pieces + (3 if per_piece == 1 else 2)
        curve = BSpline(knots, controls, 3)  # scipy evaluates the written form independently
        t = np.linspace(seg.breaks[0], seg.breaks[-1], 20001)
        assert np.max(np.abs(curve(t) - seg.eval_t(t))) <= 1e-9
