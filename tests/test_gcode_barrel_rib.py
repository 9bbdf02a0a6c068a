"""A barrel cam's rib milled on a 4th axis (camgen.export.gcode_barrel_rib), run through LinuxCNC's rs274.

Every number the program is judged by comes from outside the writer: the cycloidal law's closed
form (Rothbart, *Cam Design Handbook*, 2004, ch. 3; ``cycloidal_program`` of test_gcode_barrel),
the rib's two rollers riding ``o = rib_width / 2 + w`` below and above the pitch line (issue 24's
rib: ``w = Rr + c / 2``), rs274's canonical moves, and the rib's faces as the issue's brute force
(the union of the two roller solids: the lower roller's upper envelope, the upper roller's lower
one; ``exact_walls`` of test_gcode_barrel over the cam angle) against the stock removed by the
cutter at the canonical poses.  The machine setup is the one the program's header states (the
groove's: X = cam z, Z radial, the cam turned by A counter-clockwise about +X, theta = sigma A).
"""
from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.export.gcode_spec import MachiningSpec
from helpers import require_tool
from test_gcode_barrel import BETA, canon_moves, cutting_moves, cycloidal_program, exact_walls, removed

D = math.radians
RIM, ROOT, LENGTH = 55.0, 45.0, 50.0
ROLLER, CLEARANCE, RIB_WIDTH = 4.0, 0.5, 6.0
W = ROLLER + CLEARANCE / 2  # each roller widened by half the clearance
TOOL = 2 * W  # 8.5 mm: the rollers' diameter + clearance
OFFSET = RIB_WIDTH / 2 + W  # each roller axis from the pitch line: 7.25 mm
RISE = 10.0  # cycloidal rise over 120 deg, dwell 60, return over 120, dwell 60
Z0 = (LENGTH - RISE) / 2.0  # the travel centred
CHORD_TOL = 1e-3
FLOOR = math.sqrt(ROOT**2 - W**2)  # a flat tip there reaches radius ROOT at the tool's rim (tangential offset W)


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


@dataclasses.dataclass(frozen=True)
class Roller:
    """A roller axis along the pitch line shifted by ``shift`` (mm), for test_gcode_barrel.exact_walls."""

    sigma: int
    shift: float = 0.0

    def axis(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return Z0 + cycloidal_program(theta, RISE) + self.shift, np.zeros_like(theta)


def rib(sigma: int):
    """camgen's BarrelRib (the law built by camgen.synthesis.laws)."""
    from camgen.synthesis.barrel import BarrelGroove, BarrelLayout, BarrelRib
    from camgen.synthesis.laws import MotionProgram, Segment

    law = MotionProgram([Segment("cycloidal", BETA, RISE), Segment("dwell", D(60.0)), Segment("cycloidal", BETA, -RISE),
                         Segment("dwell", D(60.0))], unit="mm")
    layout = BarrelLayout("translating", sigma, ROLLER, "cylindrical", (RIM + ROOT) / 2.0, Z0)
    return BarrelRib(BarrelGroove(layout, law, RIM, ROOT, LENGTH, 10.0, CLEARANCE, 1e-6), RIB_WIDTH)


def spec(**changes) -> MachiningSpec:
    return dataclasses.replace(MachiningSpec(tool_diameter=TOOL, step_down=2.5, chord_tol=CHORD_TOL), **changes)


def poses_along(moves: np.ndarray, step: float) -> np.ndarray:
    """The canonical moves (n, 2, 4) sampled every ``step`` mm or less at the rim (the control
    interpolates X, Y, Z and A linearly), both ends included."""
    d = moves[:, 1] - moves[:, 0]
    parts = np.maximum(1, np.ceil(RIM * np.abs(np.radians(d[:, 3])) / step)).astype(int)
    k = np.repeat(np.arange(len(moves)), parts)
    frac = (np.arange(parts.sum()) - np.repeat(np.cumsum(parts) - parts, parts)) / np.repeat(parts, parts)
    return np.concatenate([moves[k, 0] + d[k] * frac[:, None], moves[-1:, 1]])


# ---------------------------------------------------------------------------------------------
# rs274 accepts the program; the faces' passes follow the rollers' axes, the others step away
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("sigma,direction", [(1, "climb"), (-1, "conventional")], ids=str)
@pytest.mark.usefixtures("needs_rs274")
def test_rs274_runs_the_program_and_the_face_passes_follow_the_rollers_axes(sigma, direction, tmp_path):
    """Every cutting move (between its ends too) runs at a constant offset from the pitch line
    z_c(theta) = z0 + s(theta) within 1 um; the offsets nearest the rib are -+o (the rollers' axes)
    with the tip down to sqrt(R_i^2 - w^2), the others step away from the rib by less than the tool
    diameter with the tip on the root radius, and the outermost band reaches both end faces at every
    cam angle."""
    from camgen.export.gcode_barrel_rib import rib_program

    machining = spec(direction=direction)
    program = rib_program(rib(sigma), machining, "rib")
    moves = cutting_moves(canon_moves(program, tmp_path))
    u = np.linspace(0.0, 1.0, 9)
    pose = moves[:, :1, :] + (moves[:, 1:, :] - moves[:, :1, :]) * u[None, :, None]
    theta = sigma * np.radians(pose[..., 3])
    pitch = Roller(sigma).axis(theta)[0]
    offset = pose[..., 0] - pitch  # (n, 9)
    assert np.max(np.abs(pose[..., 1])) == 0.0  # Y = 0: a translating follower's axis through the cam's
    # each move at one offset, within 1 um of its mean along the move
    per_move = offset.mean(axis=1)
    assert np.max(np.abs(offset - per_move[:, None])) <= CHORD_TOL
    levels = np.unique(np.round(per_move, 2))
    lower, upper = levels[levels < 0], levels[levels > 0]
    assert lower.size and upper.size and np.all(np.abs(levels) >= OFFSET - 0.01)
    for face, side in ((lower.max(), -1), (upper.min(), 1)):
        on = np.abs(per_move - face) < 0.005
        assert np.max(np.abs(offset[on] - side * OFFSET)) <= CHORD_TOL  # X(A) = z_c -+ o within 1 um
        z = pose[on][..., 2]
        assert abs(z.min() - FLOOR) <= 1e-4  # down to the floor: the faces cut to the root
    for level in levels[(levels != lower.max()) & (levels != upper.min())]:
        z = pose[np.abs(per_move - level) < 0.005][..., 2]
        assert abs(z.min() - ROOT) <= 1e-4  # the clearing passes stop at the root radius
    # neighbouring bands overlap (the steps less than the tool diameter); the outermost reach the ends
    assert np.all(np.diff(lower) < TOOL) and np.all(np.diff(upper) < TOOL)
    grid = np.linspace(0.0, 2 * math.pi, 3601)
    z_c = Roller(sigma).axis(grid)[0]
    assert np.max(z_c + lower.min()) - TOOL / 2 <= 0.0 and np.min(z_c + upper.max()) + TOOL / 2 >= LENGTH
    # A: one way below the rib, the other above it; climb milling of a face keeps the rib on the tool's +X side
    # with A increasing (the groove's convention, test_gcode_barrel)
    da = np.diff(moves[:, :, 3], axis=1)[:, 0]
    below = per_move < 0
    rising_below = direction == "climb"
    assert np.all((da[below] > 0) == rising_below) and np.all((da[~below] > 0) != rising_below)


# ---------------------------------------------------------------------------------------------
# the stock removed against the exact faces (the union of the two rollers' solids)
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("sigma,direction", [(1, "climb"), (-1, "conventional")], ids=str)
@pytest.mark.usefixtures("needs_rs274")
def test_the_cutter_swept_through_the_program_leaves_the_exact_rib_and_clears_the_root(sigma, direction, tmp_path):
    """The cutter at the canonical poses (each move subdivided to <= 0.05 mm at the rim), against
    points of the stock:

    * beside both faces at the root, mean and rim radius, 150 polar angles each: every point
      CHORD_TOL outside the rib is cut, none CHORD_TOL inside it;
    * CHORD_TOL above the root radius, from each face to the cylinder's end (25 heights a side at
      each of 150 polar angles): all cut;
    * CHORD_TOL below the root radius outside the two rollers' tracks (more than CHORD_TOL beyond
      each roller's union, where the faces' passes dip below the root): none cut; CHORD_TOL below
      the floor sqrt(R_i^2 - w^2): none cut anywhere.
    """
    from camgen.export.gcode_barrel_rib import rib_program

    machining = spec(direction=direction)
    program = rib_program(rib(sigma), machining, "rib")
    poses = poses_along(cutting_moves(canon_moves(program, tmp_path)), 0.05)
    cut = lambda pts: removed(pts, poses, machining.tool_radius)  # noqa: E731

    lower_roller, upper_roller = Roller(sigma, -OFFSET), Roller(sigma, OFFSET)
    rng = np.random.default_rng(28)
    n = 150
    tol = CHORD_TOL
    phi1 = np.linspace(0.0, 2 * math.pi, n, endpoint=False) + rng.uniform(0, 0.04, n)

    # the faces at three radii
    phi = np.tile(phi1, 3)
    r = np.repeat([ROOT, (RIM + ROOT) / 2, RIM], n)
    lower_face = exact_walls(lower_roller, r, phi, W)[0]  # the lower roller's upper envelope
    upper_face = exact_walls(upper_roller, r, phi, W)[1]  # the upper roller's lower envelope
    assert np.all(upper_face - lower_face > 0.5 * RIB_WIDTH)
    outside = np.concatenate([np.column_stack([r, phi, lower_face - tol]), np.column_stack([r, phi, upper_face + tol])])
    inside = np.concatenate([np.column_stack([r, phi, lower_face + tol]), np.column_stack([r, phi, upper_face - tol])])
    got = cut(outside)
    assert got.all(), outside[~got][:5]
    got = cut(inside)
    assert not got.any(), inside[got][:5]

    # the root cylinder from each face to the end faces, just above the root radius: cleared
    r_above = np.full(n, ROOT + tol)
    low_face, up_face = exact_walls(lower_roller, r_above, phi1, W)[0], exact_walls(upper_roller, r_above, phi1, W)[1]
    f = rng.uniform(0.0, 1.0, (n, 25))
    z_below = tol + (low_face - 2 * tol)[:, None] * f
    z_above = (up_face + tol)[:, None] + (LENGTH - tol - up_face - tol)[:, None] * f
    pts = np.concatenate([np.column_stack([np.repeat(r_above, 25), np.repeat(phi1, 25), z.ravel()]) for z in (z_below, z_above)])
    got = cut(pts)
    assert got.all(), pts[~got][:5]

    # just below the root radius: untouched outside the rollers' tracks
    r_below = np.full(n, ROOT - tol)
    tracks = [exact_walls(roller, r_below, phi1, W) for roller in (lower_roller, upper_roller)]  # (upper, lower) envelopes
    z = rng.uniform(tol, LENGTH - tol, (n, 40))
    in_track = np.zeros(z.shape, dtype=bool)
    for top, bottom in tracks:
        in_track |= (z > (bottom - tol)[:, None]) & (z < (top + tol)[:, None])
    keep = ~in_track
    pts = np.column_stack([np.repeat(r_below, 40)[keep.ravel()], np.repeat(phi1, 40)[keep.ravel()], z[keep]])
    assert len(pts) > 20 * n
    got = cut(pts)
    assert not got.any(), pts[got][:5]
    # below the floor: nothing anywhere
    pts = np.column_stack([np.full(n * 10, FLOOR - tol), np.repeat(phi1, 10), rng.uniform(0.0, LENGTH, n * 10)])
    got = cut(pts)
    assert not got.any(), pts[got][:5]


# ---------------------------------------------------------------------------------------------
# refusals and the run
# ---------------------------------------------------------------------------------------------
def test_a_tool_that_is_not_the_rollers_diameter_is_refused_naming_the_key():
    """tool_diameter, its value and the rollers' diameter 2 Rr + c (itself accepted within the
    stated tolerance); a conical roller names its roller_shape."""
    from camgen.export.gcode_barrel import width_tol
    from camgen.export.gcode_barrel_rib import rib_program
    from camgen.synthesis.barrel import BarrelRib

    tol = width_tol(spec())
    for diameter in (TOOL - 1.5 * tol, TOOL + 1.5 * tol, 2 * ROLLER):
        with pytest.raises(ParameterError) as err:
            rib_program(rib(1), spec(tool_diameter=diameter), "rib")
        assert err.value.name == "tool_diameter" and err.value.value == diameter
        assert float(re.match(r"([\d.]+) mm \(the rollers' diameter", err.value.valid).group(1)) == pytest.approx(2 * ROLLER + CLEARANCE,
                                                                                                                  abs=1e-12)
    assert "G93" in rib_program(rib(1), spec(tool_diameter=TOOL + 0.9 * tol))
    r = rib(1)
    conical = BarrelRib(dataclasses.replace(r.groove, layout=dataclasses.replace(r.layout, roller_shape="conical")), RIB_WIDTH)
    with pytest.raises(ParameterError) as err:
        rib_program(conical, spec(), "rib")
    assert err.value.name == "cams.rib.roller_shape"


def test_a_program_too_long_is_refused_naming_a_step_down_that_fits():
    """1 um steps down would take thousands of turns a pass: refused naming step_down with a least
    step; the program with that step holds at most MAX_PROGRAM_MOVES moves (counted from its text)."""
    from camgen.export.gcode import MAX_PROGRAM_MOVES
    from camgen.export.gcode_barrel_rib import rib_passes

    with pytest.raises(ParameterError) as err:
        from camgen.export.gcode_barrel_rib import rib_program

        rib_program(rib(1), spec(step_down=0.001))
    assert err.value.name == "step_down"
    least = float(re.fullmatch(r">= ([\d.]+) mm", err.value.valid).group(1))
    passes = rib_passes(rib(1), spec(step_down=least))
    # every pass: its turns (from the rim to its floor in steps of `least`, then one on the floor) x its moves a turn
    moves = sum((math.ceil((RIM - float(q.path.floor.min())) / least - 1e-9) + 1) * (q.path.a.size - 1) for q in passes)
    assert moves <= MAX_PROGRAM_MOVES


def _rib_scene(tmp_path, tool: float) -> str:
    from helpers import scene_toml
    from test_barrel_form import cam as groove_cam

    table = groove_cam(track="rib", rib_width_mm=12.0, cylinder_length_mm=90.0, pressure_angle_limit_deg=45.0)
    path = tmp_path / "s.toml"
    path.write_text(scene_toml({"output": {"formats": ["ngc"]}, "cams": {"c": table}}).replace(
        "[cams.c]", f"[machining]\ntool_diameter_mm = {tool}\nstep_down_mm = 5.0\n\n[cams.c]", 1))
    return str(path)


def test_a_rib_run_writes_its_program_and_a_wrong_tool_exits_2(tmp_path, capsys):
    """camgen run with ngc on a rib (the form's ngc writer picks the rib's program): the program is
    written; with the roller's diameter without the clearance: exit 2, one line naming
    machining.tool_diameter_mm, its value and the rollers' diameter + clearance 16.05 mm; nothing written."""
    from camgen.cli import main

    status = main(["run", _rib_scene(tmp_path, 16.05), "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 0, err
    text = (tmp_path / "out" / "s" / "c.ngc").read_text()
    assert text.startswith("(camgen ") and "with a rib" in text and text.endswith("M2\n")
    parent = tmp_path / "parent"
    parent.mkdir()
    assert main(["run", _rib_scene(tmp_path, 16.0), "-o", str(parent / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    assert "machining.tool_diameter_mm" in err and "16.05 mm (the rollers' diameter" in err and "for cam 'c'" in err, err
    assert list(parent.iterdir()) == []


def test_a_ribs_wall_to_the_bore_is_checked_to_the_floor_the_program_cuts():
    """The root under each roller's track is cut down to the flat tip's floor sqrt(R_i^2 - w^2)
    (the faces' passes): the wall_thickness check measures from there to the bore, passing at
    min_wall_mm just below it and failing just above."""
    from test_barrel_form import DEPTH, R_O, RR, CLEAR, cam as groove_cam, check, run

    floor = math.sqrt((R_O - DEPTH) ** 2 - (RR + CLEAR / 2) ** 2)
    wall = floor - 15.0  # bore diameter 30 mm
    base = groove_cam(track="rib", rib_width_mm=12.0, cylinder_length_mm=90.0, bore_diameter_mm=30.0)
    assert check(run(base)[1], "wall_thickness")["value"] == pytest.approx(wall, abs=1e-12)
    assert check(run({**base, "min_wall_mm": wall - 1e-9})[1], "wall_thickness")["status"] == "pass"
    assert check(run({**base, "min_wall_mm": wall + 1e-9})[1], "wall_thickness")["status"] == "fail"
