"""An oscillating follower's rib (track = "rib", follower_motion = "oscillating"): its STEP and its
4th-axis program against the issue's brute force, computed here from the arm (never from camgen's
contact formulas or camgen.synthesis.barrel.BarrelRib).

The arm (test_barrel_rib_oscillating's ``ArmRollers``, rebuilt from the stated geometry): both
rollers on the arm's end, their axes parallel to x, ``o = rib_width / 2 + w`` either side of the
arm's end along the arm's normal in the tangent plane; the roller on side ``k`` (+1 upper) has its
axis at

    y_k = -L + L cos psi - k o sin psi,    z_k = z_p + L sin psi + k o cos psi,

``psi = psi0 + s(theta)``, ``s`` the cycloidal swing in closed form (Norton, *Design of Machinery*,
eq. 8.6; test_barrel_dynamics' ``cycloid``).  The rib's faces are the issue's brute force: a cam
point at (r, phi, z) is cut when some cam angle puts it inside a roller (widened by half the
clearance), ``(r sin(phi + sigma theta) - y_k)^2 + (z - z_k)^2 < w^2``, ``r cos(...) > 0``; the
upper face is the least lower edge of the upper roller over theta, the lower face the largest upper
edge of the lower roller, found here on a grid of the world angle refined three times (vectorised).

* STEP: one solid OCCT and FreeCAD find valid; its volume against pi (R_i^2 - R_b^2) L plus the
  integral of the brute-force width times r (Gauss-Legendre in r, trapezoid over the periodic polar
  angle) within 1e-6 relative; both faces, read by OCCT's line intersections, within fit_tol of the
  brute force.
* The program: rs274 (LinuxCNC) accepts it; the face passes' poses within 1 um of each roller's axis
  (X = z_k, Y = -y_k) between their ends too, the tip down to min sqrt(R_i^2 - (|y_k| + w)^2); the
  clearing passes at constant X offsets from the face pass, Y = -y_k, the tip on the root radius;
  the cutter swept through rs274's poses leaves the faces within the chord tolerance, clears the root
  to the ends and cuts nothing below the root outside the rollers' tracks nor below the floor.
"""
from __future__ import annotations

import dataclasses
import math
import subprocess

import numpy as np
import pytest

from helpers import require_tool
from test_barrel_dynamics import cycloid

D = math.radians
SIGMA = -1  # clockwise, the pipeline test's scene
R_O, R_I, BORE, LENGTH = 55.0, 45.0, 10.0, 90.0
RR, CLEARANCE, RIB_W = 8.0, 0.05, 10.0
W = RR + CLEARANCE / 2  # each roller widened by half the clearance
O = RIB_W / 2 + W  # each roller axis from the arm's end along its normal
ARM, SWING = 60.0, D(20.0)
PIVOT_Z, REST = LENGTH / 2, -SWING / 2  # the defaults: pivot at half the length, the swing symmetric
STEP_TOL = 1e-5
CHORD_TOL = 1e-3
TOOL = 2 * W


def axis(side: int, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(y_k, z_k) of the roller on ``side`` (module notes), mm."""
    psi = REST + cycloid(theta, SWING)[0]
    return -ARM + ARM * np.cos(psi) - side * O * np.sin(psi), PIVOT_Z + ARM * np.sin(psi) + side * O * np.cos(psi)


def envelope(side: int, sense: int, r: np.ndarray, phi: np.ndarray, sigma: int = SIGMA) -> np.ndarray:
    """The union of the roller ``side``'s solids at cam points (r, phi): its upper edge's largest
    height over the cam angle (``sense`` +1) or its lower edge's least (-1), mm.  A grid of 2001 world
    angles u = phi + sigma theta across the roller, then twice 201 across the best step's neighbours."""
    r, phi = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(phi, dtype=float))
    shape = r.shape
    r, phi = r.ravel(), phi.ravel()
    out = np.empty(r.size)
    reach = np.arcsin(np.minimum(1.0, (W + ARM * (1.0 - math.cos(SWING)) + O * math.sin(SWING) + 0.5) / r))
    for lo_i in range(0, r.size, 256):
        rr, pp = r[lo_i:lo_i + 256, None], phi[lo_i:lo_i + 256, None]
        lo, hi = -reach[lo_i:lo_i + 256], reach[lo_i:lo_i + 256]
        for n in (2001, 201, 201):
            u = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, n)[None, :]
            theta = sigma * (u - pp)
            y, z = axis(side, theta)
            g = rr * np.sin(u) - y
            val = np.where(g * g < W * W, z + sense * np.sqrt(np.maximum(W * W - g * g, 0.0)), -sense * np.inf)
            k = np.argmax(sense * val, axis=1)
            best = val[np.arange(len(rr)), k]
            step = (hi - lo) / (n - 1)
            centre = u[np.arange(len(rr)), k]
            lo, hi = centre - 2 * step, centre + 2 * step
        out[lo_i:lo_i + 256] = best
    return out.reshape(shape)


def face(side: int, r: np.ndarray, phi: np.ndarray, sigma: int = SIGMA) -> np.ndarray:
    """The rib's face ``side`` (+1 upper: the upper roller's lower edge; -1 lower: the lower roller's upper edge)."""
    return envelope(side, -side, r, phi, sigma)


def camgen_rib(sigma: int = SIGMA, fit_tol: float = STEP_TOL):
    from camgen.synthesis.barrel import BarrelGroove, BarrelLayout, BarrelRib
    from camgen.synthesis.laws import MotionProgram, Segment

    law = MotionProgram([Segment("cycloidal", D(120.0), SWING), Segment("dwell", D(60.0)), Segment("cycloidal", D(120.0), -SWING),
                         Segment("dwell", D(60.0))], unit="rad")
    layout = BarrelLayout("oscillating", sigma, RR, "cylindrical", 0.5 * (R_O + R_I), PIVOT_Z, arm_length=ARM, rest_angle=REST)
    return BarrelRib(BarrelGroove(layout, law, R_O, R_I, LENGTH, BORE, CLEARANCE, fit_tol), RIB_W)


def test_the_brute_force_in_a_dwell_is_the_rollers_edge():
    """The brute force itself: where the arm dwells (psi = psi0 + swing over cam angles 120..180 deg)
    the faces are flat, the upper roller's axis height less w and the lower's plus w."""
    psi = REST + SWING
    phi = -SIGMA * D(150.0) * np.ones(3)
    r = np.array([R_I, 0.5 * (R_I + R_O), R_O])
    assert np.max(np.abs(face(1, r, phi) - (PIVOT_Z + ARM * math.sin(psi) + O * math.cos(psi) - W))) <= 1e-9
    assert np.max(np.abs(face(-1, r, phi) - (PIVOT_Z + ARM * math.sin(psi) - O * math.cos(psi) + W))) <= 1e-9


# ----------------------------------------------------------------------------------- STEP
def rib_volume(n_phi: int = 2048, n_r: int = 6) -> float:
    """pi (R_i^2 - R_b^2) L plus the rib: the integral over r in [R_i, R_o] (Gauss-Legendre, n_r
    points) and phi (trapezoid rule over the period, n_phi points) of the brute-force width times r."""
    x, weight = np.polynomial.legendre.leggauss(n_r)
    r = 0.5 * (R_O + R_I) + 0.5 * (R_O - R_I) * x
    phi = 2.0 * math.pi * np.arange(n_phi) / n_phi
    rr, pp = np.meshgrid(r, phi, indexing="ij")
    width = face(1, rr, pp) - face(-1, rr, pp)
    rib = float(np.sum(0.5 * (R_O - R_I) * weight * r * width.sum(axis=1)) * 2.0 * math.pi / n_phi)
    return math.pi * (R_I**2 - BORE**2) * LENGTH + rib


@pytest.fixture(scope="module")
def reference_volume() -> float:
    return rib_volume()


def test_reference_volume_converged(reference_volume):
    """Halving both rules moves the brute-force integral by less than 1e-8 relative (the STEP is held to 1e-6)."""
    assert abs(rib_volume(1024, 4) - reference_volume) <= 1e-8 * reference_volume


@pytest.fixture(scope="module")
def stepped() -> bytes:
    pytest.importorskip("OCP")
    from camgen.export.barrel_rib_step import rib_step_bytes

    return rib_step_bytes(camgen_rib(), "orib")


def test_step_one_valid_solid_of_the_brute_force_volume(stepped, reference_volume):
    """Read back by OCCT: one solid, BRepCheck_Analyzer valid; its volume (mass properties to 1e-9)
    within 1e-6 relative of the brute-force integral."""
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    from test_barrel_solid import _read_step

    assert b"B-spline rib faces within 1e-05 mm" in stepped
    shape = _read_step(stepped)
    solids, explorer = 0, TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        solids += 1
        explorer.Next()
    assert solids == 1 and BRepCheck_Analyzer(shape).IsValid()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-9)
    assert abs(props.Mass() - reference_volume) <= 1e-6 * reference_volume, (props.Mass(), reference_volume)


def test_step_faces_within_fit_tol_of_the_brute_force(stepped):
    """Vertical lines through 200 random points of the rib's annulus meet the solid twice: the
    lower and the upper face, each within fit_tol of the brute force."""
    from test_barrel_rib_files import _hits
    from test_barrel_solid import _read_step

    shape = _read_step(stepped)
    rng = np.random.default_rng(24)
    r = rng.uniform(R_I + 0.05, R_O - 0.05, 200)
    phi = rng.uniform(0.0, 2.0 * math.pi, 200)
    hits = _hits(shape, np.column_stack([r * np.cos(phi), r * np.sin(phi), np.full(200, -1.0)]), (0.0, 0.0, 1.0), LENGTH + 2.0)
    assert all(len(h) == 2 for h in hits), hits
    lower, upper = (np.array(hits) - 1.0).T
    assert np.max(np.abs(upper - face(1, r, phi))) <= STEP_TOL
    assert np.max(np.abs(lower - face(-1, r, phi))) <= STEP_TOL


def test_step_opens_in_freecad(stepped, reference_volume, tmp_path):
    """FreeCAD (its own STEP import into its Part workbench) finds one valid solid of the
    brute-force volume within 1e-6 relative."""
    freecad = require_tool("freecadcmd")
    path = tmp_path / "orib.step"
    path.write_bytes(stepped)
    script = tmp_path / "check.py"
    script.write_text("import Part\nshape = Part.read(%r)\nprint('CHECK', shape.isValid(), len(shape.Solids), repr(shape.Volume))\n"
                      % str(path))
    done = subprocess.run([freecad, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    line = [ln for ln in done.stdout.splitlines() if ln.startswith("CHECK")]
    assert line, done.stdout + done.stderr
    _, valid, solids, volume = line[0].split()
    assert valid == "True" and solids == "1"
    assert abs(float(volume) - reference_volume) <= 1e-6 * reference_volume


# ----------------------------------------------------------------------------------- the program
def spec(**changes):
    from camgen.export.gcode_spec import MachiningSpec

    return dataclasses.replace(MachiningSpec(tool_diameter=TOOL, step_down=5.0, chord_tol=CHORD_TOL), **changes)


def floor_of_faces() -> float:
    """The face passes' lowest tip: sqrt(R_i^2 - (|y_k| + w)^2) at the largest |y_k| of both rollers (the flat tip reaches
    the root radius at the tool's rim)."""
    theta = np.linspace(0.0, 2 * math.pi, 36001)
    most = max(float(np.max(np.abs(axis(k, theta)[0]))) for k in (-1, 1))
    return math.sqrt(R_I**2 - (most + W) ** 2)


@pytest.fixture(scope="module", params=[(SIGMA, "climb"), (-SIGMA, "conventional")], ids=str)
def program(request, tmp_path_factory):
    """(sigma, direction, rs274's canonical feed moves (n, 2, 4) of the program that turn A)."""
    require_tool("rs274")
    from camgen.export.gcode_barrel_rib import rib_program
    from test_gcode_barrel import canon_moves, cutting_moves

    sigma, direction = request.param
    text = rib_program(camgen_rib(sigma), spec(direction=direction), "orib")
    return sigma, direction, cutting_moves(canon_moves(text, tmp_path_factory.mktemp("orib")))


def test_rs274_runs_the_program_and_the_face_passes_follow_each_rollers_axis(program):
    """Every cutting move (between its ends too) at a constant X offset from one roller's axis height
    z_k(theta) with Y = -y_k(theta) within 1 um; the passes nearest the rib on the rollers' axes
    (offset 0: the lower roller's below the rib, the upper's above), the tip down to the floor
    sqrt(R_i^2 - (|y_k| + w)^2); the others step away from the rib with the tip on the root radius."""
    sigma, direction, moves = program
    u = np.linspace(0.0, 1.0, 9)
    pose = moves[:, :1, :] + (moves[:, 1:, :] - moves[:, :1, :]) * u[None, :, None]
    theta = sigma * np.radians(pose[..., 3])
    floor = floor_of_faces()
    seen = {}
    for side in (-1, 1):
        y, z = axis(side, theta)
        fits_y = np.max(np.abs(pose[..., 1] + y), axis=1) <= CHORD_TOL
        offset = pose[..., 0] - z
        per_move = offset.mean(axis=1)
        mine = fits_y & (np.max(np.abs(offset - per_move[:, None]), axis=1) <= CHORD_TOL) & (side * per_move > -CHORD_TOL)
        seen[side] = mine
        levels = np.unique(np.round(per_move[mine], 2))
        assert levels[0 if side > 0 else -1] == 0.0  # the face's pass on the roller's axis
        on_axis = mine & (np.abs(per_move) < 0.005)
        assert np.max(np.abs(offset[on_axis])) <= CHORD_TOL  # X(A) = z_k within 1 um
        assert np.max(np.abs(pose[on_axis][..., 1] + y[on_axis])) <= CHORD_TOL  # Y(A) = -y_k within 1 um
        assert abs(pose[on_axis][..., 2].min() - floor) <= 2e-4
        clearing = mine & (np.abs(per_move) >= 0.005)
        assert clearing.any() and abs(pose[clearing][..., 2].min() - R_I) <= 1e-4
        assert np.all(np.abs(np.diff(levels)) < TOOL)
    assert np.all(seen[-1] | seen[1]) and not np.any(seen[-1] & seen[1])  # every move one roller's
    da = np.diff(moves[:, :, 3], axis=1)[:, 0]
    assert np.all((da[seen[-1]] > 0) == (direction == "climb")) and np.all((da[seen[1]] > 0) != (direction == "climb"))


def test_the_cutter_swept_through_the_program_leaves_the_exact_rib_and_clears_the_root(program):
    """The cutter at rs274's poses (each move subdivided to <= 0.05 mm at the rim) against points of
    the stock: beside both faces at the root, mean and rim radius (150 polar angles each) every point
    CHORD_TOL outside the rib cut, none CHORD_TOL inside; CHORD_TOL above the root radius from each
    face to the cylinder's end, all cut; CHORD_TOL below the root outside the two rollers' unions
    (their tracks, where the faces' passes dip below it), none; CHORD_TOL below the floor, none."""
    from test_gcode_barrel import removed
    from test_gcode_barrel_rib import RIM, poses_along

    assert RIM == R_O  # poses_along subdivides at that rim
    sigma, _, moves = program
    poses = poses_along(moves, 0.05)
    cut = lambda pts: removed(pts, poses, W)  # noqa: E731
    tol, n = CHORD_TOL, 150
    rng = np.random.default_rng(26)
    phi1 = np.linspace(0.0, 2 * math.pi, n, endpoint=False) + rng.uniform(0, 0.04, n)
    phi = np.tile(phi1, 3)
    r = np.repeat([R_I, 0.5 * (R_I + R_O), R_O], n)
    upper, lower = face(1, r, phi, sigma), face(-1, r, phi, sigma)
    assert np.all(upper - lower > 0.5 * RIB_W)
    got = cut(np.concatenate([np.column_stack([r, phi, lower - tol]), np.column_stack([r, phi, upper + tol])]))
    assert got.all(), np.flatnonzero(~got)[:5]
    got = cut(np.concatenate([np.column_stack([r, phi, lower + tol]), np.column_stack([r, phi, upper - tol])]))
    assert not got.any(), np.flatnonzero(got)[:5]

    r_above = np.full(n, R_I + tol)
    low, up = face(-1, r_above, phi1, sigma), face(1, r_above, phi1, sigma)
    f = rng.uniform(0.0, 1.0, (n, 25))
    z_below = tol + (low - 2 * tol)[:, None] * f
    z_above = (up + tol)[:, None] + (LENGTH - 2 * tol - up)[:, None] * f
    pts = np.concatenate([np.column_stack([np.repeat(r_above, 25), np.repeat(phi1, 25), z.ravel()]) for z in (z_below, z_above)])
    got = cut(pts)
    assert got.all(), pts[~got][:5]

    r_below = np.full(n, R_I - tol)
    z = rng.uniform(tol, LENGTH - tol, (n, 40))
    in_track = np.zeros(z.shape, dtype=bool)
    for side in (-1, 1):
        top, bottom = envelope(side, 1, r_below, phi1, sigma), envelope(side, -1, r_below, phi1, sigma)
        in_track |= (z > (bottom - tol)[:, None]) & (z < (top + tol)[:, None])
    keep = ~in_track
    pts = np.column_stack([np.repeat(r_below, 40)[keep.ravel()], np.repeat(phi1, 40)[keep.ravel()], z[keep]])
    assert len(pts) > 15 * n
    got = cut(pts)
    assert not got.any(), pts[got][:5]
    pts = np.column_stack([np.full(n * 10, floor_of_faces() - tol), np.repeat(phi1, 10), rng.uniform(0.0, LENGTH, n * 10)])
    got = cut(pts)
    assert not got.any(), pts[got][:5]


def test_a_roller_riding_off_the_station_by_the_tool_radius_is_refused():
    """A long swing carries the rollers' axes sideways by more than the tool's radius (|y_k| from the
    arm's closed form here): no band of the clearing passes reaches Y = 0 at the root, so the program
    is refused (GeometryError naming the cam and that offset)."""
    from camgen.errors import GeometryError
    from camgen.export.gcode_barrel_rib import rib_program
    from camgen.synthesis.barrel import BarrelRib

    groove = camgen_rib().groove
    small = dataclasses.replace(groove, layout=dataclasses.replace(groove.layout, roller_radius=3.0))
    w = 3.0 + CLEARANCE / 2
    wide = BarrelRib(small, 20.0)  # o = 13.025 mm: o sin(10 deg) + L (1 - cos 10 deg) = 3.17 mm > w at the swing's ends
    o = 10.0 + w
    most = o * math.sin(SWING / 2) + ARM * (1.0 - math.cos(SWING / 2))
    assert most > w
    with pytest.raises(GeometryError, match=r"cam 'wide'.* rides %s mm off" % f"{most:.6g}"):
        rib_program(wide, spec(tool_diameter=2 * w), "wide")


# ----------------------------------------------------------------------------------- the run
def test_a_run_writes_the_oscillating_ribs_step_and_program(tmp_path, capsys):
    """`camgen run` of test_barrel_rib_oscillating's scene with step and ngc exits 0 (no longer
    refused) and writes both: the program with the Y words of the rollers' offsets, the STEP one
    valid solid."""
    pytest.importorskip("OCP")
    from OCP.BRepCheck import BRepCheck_Analyzer

    from camgen.cli import main
    from helpers import scene_toml
    from test_barrel_rib_oscillating import osc_rib
    from test_barrel_solid import _read_step

    path = tmp_path / "s.toml"
    path.write_text(scene_toml({"output": {"formats": ["step", "ngc"]}, "cams": {"c": osc_rib()}}).replace(
        "[cams.c]", "[machining]\ntool_diameter_mm = 16.05\nstep_down_mm = 5.0\n\n[cams.c]", 1))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 0, capsys.readouterr().err
    (step,) = list((tmp_path / "out").rglob("c.step"))
    assert BRepCheck_Analyzer(_read_step(step.read_bytes())).IsValid()
    (ngc,) = list((tmp_path / "out").rglob("c.ngc"))
    text = ngc.read_text()
    assert "with a rib" in text and "oscillating arm" in text and " Y" in text and text.endswith("M2\n")


def test_the_wall_to_the_bore_is_checked_to_the_floor_the_program_cuts():
    """The oscillating rib's faces' passes cut the root down to sqrt(R_i^2 - (|y_k| + w)^2) at the
    largest tangential offset of either roller (the arm's closed form here): the wall_thickness check
    measures from there to the bore, passing at min_wall_mm just below it and failing just above."""
    from test_barrel_rib_oscillating import OSC_ARM, OSC_SWING, check, osc_rib, report_of

    theta = np.linspace(0.0, 2 * math.pi, 3601)[:-1]
    psi = -OSC_SWING / 2 + cycloid(theta, OSC_SWING)[0]
    o = 5.0 + 8.025
    most = max(float(np.max(np.abs(-OSC_ARM + OSC_ARM * np.cos(psi) - k * o * np.sin(psi)))) for k in (-1, 1))
    wall = math.sqrt(R_I**2 - (most + 8.025) ** 2) - 15.0
    base = osc_rib(bore_diameter_mm=30.0)
    assert check(report_of(base), "wall_thickness")["value"] == pytest.approx(wall, abs=1e-9)
    assert check(report_of({**base, "min_wall_mm": wall - 1e-6}), "wall_thickness")["status"] == "pass"
    assert check(report_of({**base, "min_wall_mm": wall + 1e-6}), "wall_thickness")["status"] == "fail"
