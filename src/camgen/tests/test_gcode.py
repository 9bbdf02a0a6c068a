"""G-code programs, run through LinuxCNC's rs274."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.errors import GeometryError, ParameterError
from camgen.export.gcode import MachiningSpec, gcode_program
from camgen.tests.cams import radial_error
from camgen.tests.helpers import require_tool, rs274_toolpath


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


def _check_program(program, intended, tmp_path, spec):
    status, message, moves = rs274_toolpath(program, tmp_path)
    assert status == 0, message
    depth = -spec.thickness
    cutting = [pts for z, pts in moves if abs(z - depth) < 1e-9]
    assert cutting
    # the lead-in/out lines are not on the contour: drop the first and last move of the pass
    contour_pts = np.concatenate([p[1:] for p in cutting[1:-1]])
    assert np.max(radial_error(intended, contour_pts)) <= 1e-3
    z_levels = sorted({round(z, 6) for z, _ in moves if z < 0})
    assert len(z_levels) == math.ceil(spec.thickness / spec.step_down)
    return contour_pts


@pytest.mark.parametrize("direction", ["climb", "conventional"])
@pytest.mark.usefixtures("needs_rs274")
def test_gcode_three_arc_runs_in_rs274_and_follows_the_offset(direction, contours, tmp_path):
    spec = MachiningSpec(thickness=6.0, step_down=2.5, direction=direction, tool_diameter=8.0)
    program = gcode_program(contours["stride"], spec, "stride")
    assert program.count("G2 ") + program.count("G3 ") == 6 * 3  # exact arcs, 3 passes
    intended = contours["stride"].offset(4.0)
    pts = _check_program(program, intended, tmp_path, spec)
    signed = 0.5 * np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - pts[:, 1] * np.roll(pts[:, 0], -1))
    assert (signed < 0) == (direction == "climb")  # climb: clockwise round the outside


@pytest.mark.parametrize("mode", ["biarcs", "lines"])
@pytest.mark.usefixtures("needs_rs274")
def test_gcode_spline_cam_runs_in_rs274(mode, contours, tmp_path):
    spec = MachiningSpec(thickness=4.0, step_down=2.0, tool_diameter=6.0, spline_mode=mode, chord_tol=5e-4)
    program = gcode_program(contours["steering"], spec, "steering")
    if mode == "biarcs":
        assert "G1 X" in program and program.count("G2 ") > 20
    intended = contours["steering"].offset(3.0, spline_tol=1e-7)
    _check_program(program, intended, tmp_path, spec)


@pytest.mark.parametrize("direction", ["climb", "conventional"])
@pytest.mark.usefixtures("needs_rs274")
def test_gcode_cutter_compensation_done_by_rs274(direction, contours, tmp_path):
    spec = MachiningSpec(thickness=2.0, step_down=2.0, tool_diameter=8.0, cutter_compensation=True, direction=direction)
    program = gcode_program(contours["stride"], spec, "stride")
    assert ("G41.1 D8.0000 G1" in program) == (direction == "climb")
    assert ("G42.1 D8.0000 G1" in program) == (direction != "climb")
    _check_program(program, contours["stride"].offset(4.0), tmp_path, spec)


def test_gcode_header_dialects_and_errors(contours):
    linux = gcode_program(contours["stride"], MachiningSpec())
    assert "G21 G90 G17 G40 G49 G80 G94" in linux and "G64 P0.0010" in linux and linux.rstrip().endswith("M2")
    grbl = gcode_program(contours["stride"], MachiningSpec(dialect="grbl"))
    assert "G64" not in grbl and "G41" not in grbl and "M3 S8000" in grbl
    with pytest.raises(ParameterError, match="cutter_compensation"):
        MachiningSpec(dialect="grbl", cutter_compensation=True)
    with pytest.raises(ParameterError, match="lead"):
        MachiningSpec(lead=2.0, tool_diameter=6.0)


def test_gcode_refuses_a_tool_that_would_gouge():
    from camgen.contour import Contour, Spline

    theta = np.linspace(0, 2 * math.pi, 49)
    r = 40 + 8 * np.cos(3 * theta)  # concave at 60, 180, 300 deg with radius 25.6 mm
    contour = Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])
    gcode_program(contour, MachiningSpec(tool_diameter=40.0))
    with pytest.raises(GeometryError, match=r"diameter 60 mm would gouge.*cam angle (59|60|179|180|299|300)\.\d+ deg"):
        gcode_program(contour, MachiningSpec(tool_diameter=60.0))

