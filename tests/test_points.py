"""Point lists and lift tables."""
from __future__ import annotations

import io
import math

import numpy as np
import pytest

import camgen
from camgen.export.points import base_radius, lift_csv
from cams import HEIGHT, STRIDE


def test_lift_table_against_table_1():
    import pandas

    cam = camgen.three_arc_cam(*STRIDE)
    frame = pandas.read_csv(io.StringIO(lift_csv(cam, math.radians(0.5))))  # the reader's defaults
    assert list(frame.columns) == ["polar_angle_deg", "radius_mm", "lift_mm"]
    data = frame.to_numpy()
    assert data.shape == (720, 3)
    _, radius = camgen.yoke_law(*STRIDE, np.radians(data[:, 0]))  # Table 1's radius vector R
    assert np.max(np.abs(data[:, 1] - radius)) <= 2e-9
    assert np.allclose(data[:, 2], data[:, 1] - 25.0, atol=2e-9)
    assert base_radius(camgen.three_arc_cam(*HEIGHT)) == pytest.approx(10.0, abs=1e-12)



def test_format_rows_writes_what_numpy_savetxt_writes():
    """The one-operation row formatter gives numpy.savetxt's bytes (ints, floats, mixed rows)."""
    import io

    from camgen.export.tables import format_rows

    rng = np.random.default_rng(5)
    data = np.column_stack([np.arange(1, 301), rng.normal(size=(300, 3)) * 1e3, -np.zeros(300)])
    for fmt in (["%d", "%.14g", "%.9f", "%.3e", "%.17g"], ["%d"] + ["%.17g"] * 4):
        reference = io.StringIO()
        np.savetxt(reference, data, fmt=fmt, delimiter=", ")
        assert format_rows(data, ", ".join(fmt)) == reference.getvalue()
    assert format_rows(np.zeros((0, 2)), "%g,%g") == ""
