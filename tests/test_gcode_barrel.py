"""The barrel cam's 4th-axis program (camgen.export.gcode_barrel), run through LinuxCNC's rs274.

Every number the programs are judged by comes from outside the writer: the cycloidal law's
closed form (Rothbart, *Cam Design Handbook*, 2004, ch. 3: s = h (x/b - sin(2 pi x/b) / (2 pi))),
the oscillating arm's kinematics of tasks24/api.md (e = L (cos psi - 1), z_c = z_p + L sin psi),
rs274's canonical moves, and the exact groove as the union of the widened roller (api.md's brute
force over the cam angle) against the stock removed by the cutter at the canonical poses.
The machine setup the tests read the poses with is the one the program's header states: X = cam
z, Z radial (the tip's distance from the A axis), the tool's axis at Y = -e, and the cam turned by
A counter-clockwise about +X, so that a cam point at polar angle phi is at world polar angle
phi + A and cam angle theta = sigma A.
"""
from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.export.gcode_spec import MachiningSpec
from helpers import require_tool, rs274_env

D = math.radians
RIM, ROOT, LENGTH = 55.0, 45.0, 80.0  # the example: mean radius 50, depth 10
ROLLER, CLEARANCE = 4.0, 0.5  # groove width 2 x 4 + 0.5 = 8.5 mm
WIDTH = 2 * ROLLER + CLEARANCE
RISE, BETA = 40.0, D(120.0)  # cycloidal rise of 40 mm over 120 deg, dwell 60, return 120, dwell 60
SWING = D(20.0)  # the oscillating follower's swing, same program
ARM, PIVOT_Z = 60.0, 40.0
CHORD_TOL = 1e-3


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


# ---------------------------------------------------------------------------------------------
# the reference: closed forms, independent of camgen's laws and of the writer
# ---------------------------------------------------------------------------------------------
def cycloidal_program(theta: np.ndarray, h: float) -> np.ndarray:
    """Rise h over BETA, dwell 60 deg, return over BETA, dwell 60 deg (period 2 pi), closed form."""
    t = np.mod(theta, 2 * math.pi)
    x = t / BETA
    rise = h * (x - np.sin(2 * math.pi * x) / (2 * math.pi))
    back = (t - BETA - D(60.0)) / BETA
    ret = h * (1.0 - (back - np.sin(2 * math.pi * back) / (2 * math.pi)))
    return np.where(t < BETA, rise, np.where(t < BETA + D(60.0), h, np.where(t < 2 * BETA + D(60.0), ret, 0.0)))


@dataclasses.dataclass(frozen=True)
class Case:
    motion: str
    sigma: int

    @property
    def z0(self) -> float:
        return (LENGTH - RISE) / 2.0  # the roller axis centred: (length - (s_max + s_min)) / 2

    def axis(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z_c, e) of the roller axis (api.md)."""
        if self.motion == "translating":
            return self.z0 + cycloidal_program(theta, RISE), np.zeros_like(theta)
        psi = -SWING / 2.0 + cycloidal_program(theta, SWING)
        return PIVOT_Z + ARM * np.sin(psi), ARM * (np.cos(psi) - 1.0)


def groove(case: Case, roller_shape: str = "cylindrical"):
    """camgen's BarrelGroove of ``case`` (the law built by camgen.synthesis.laws)."""
    from camgen.synthesis.barrel import BarrelGroove, BarrelLayout
    from camgen.synthesis.laws import MotionProgram, Segment

    h = RISE if case.motion == "translating" else SWING
    law = MotionProgram([Segment("cycloidal", BETA, h), Segment("dwell", D(60.0)), Segment("cycloidal", BETA, -h),
                         Segment("dwell", D(60.0))], unit="mm" if case.motion == "translating" else "rad")
    oscillating = case.motion == "oscillating"
    layout = BarrelLayout(case.motion, case.sigma, ROLLER, roller_shape, (RIM + ROOT) / 2.0, PIVOT_Z if oscillating else case.z0,
                          ARM if oscillating else 0.0, -SWING / 2.0 if oscillating else 0.0)
    return BarrelGroove(layout, law, RIM, ROOT, LENGTH, 10.0, CLEARANCE, 1e-6)


def spec(**changes) -> MachiningSpec:
    return dataclasses.replace(MachiningSpec(tool_diameter=WIDTH, step_down=2.5, chord_tol=CHORD_TOL), **changes)


_FEED = re.compile(r"STRAIGHT_FEED\(" + ", ".join([r"(-?\d+(?:\.\d+)?)"] * 6) + r"\)")


def canon_moves(program: str, workdir) -> np.ndarray:
    """rs274's canonical feed moves of ``program`` as rows (x, y, z, a) of their end points, the
    first row the start of the first one (rs274 prints 4 decimals)."""
    import subprocess

    path = workdir / "barrel.ngc"
    path.write_text(program)
    proc = subprocess.run(["rs274", "-g", str(path)], stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=300,
                          env=rs274_env(path.parent))  # a tool table file of its own (helpers.rs274_env)
    assert proc.returncode == 0, proc.stderr + proc.stdout[-2000:]
    assert "error" not in proc.stderr.lower(), proc.stderr
    rows = [[float(m.group(i)) for i in (1, 2, 3, 4)] for m in map(_FEED.search, proc.stdout.splitlines()) if m]
    return np.array(rows)


def cutting_moves(ends: np.ndarray) -> np.ndarray:
    """The moves that turn A (the groove's turns), as (start, end) pairs: (n, 2, 4)."""
    pairs = np.stack([ends[:-1], ends[1:]], axis=1)
    return pairs[pairs[:, 1, 3] != pairs[:, 0, 3]]


# ---------------------------------------------------------------------------------------------
# rs274 accepts the program; X(A) is the law, A covers the turns, the tip reaches the floor
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("case", [Case("translating", 1), Case("translating", -1), Case("oscillating", 1)], ids=str)
@pytest.mark.usefixtures("needs_rs274")
def test_rs274_runs_the_program_and_x_follows_the_law(case, tmp_path):
    from camgen.export.gcode_barrel import barrel_program

    machining = spec()
    program = barrel_program(groove(case), machining, "barrel")
    assert program.index("\nG93\n") < program.index("\nG94\nG0")
    moves = cutting_moves(canon_moves(program, tmp_path))
    # X (and Y = -e) along every move, between its ends too (the control interpolates linearly)
    u = np.linspace(0.0, 1.0, 9)
    pose = moves[:, :1, :] + (moves[:, 1:, :] - moves[:, :1, :]) * u[None, :, None]
    theta = case.sigma * np.radians(pose[..., 3])
    z_c, e = case.axis(theta)
    assert np.max(np.abs(pose[..., 0] - z_c)) <= CHORD_TOL  # within 1 um of z0 + s(theta)
    assert np.max(np.abs(pose[..., 1] + e)) <= CHORD_TOL
    # A: monotonic, whole turns; the last one (the finishing turn on the floor) covers 360 deg
    a = np.concatenate([moves[:1, 0, 3], moves[:, 1, 3]])
    assert np.all(np.diff(a) > 0) and a[0] == 0.0 and a[-1] % 360.0 == 0.0
    # the rim's chord of every move (for a control moving the tool centre point in straight lines) within the tolerance
    assert np.max(RIM * (1.0 - np.cos(np.radians(np.diff(a)) / 2.0))) <= CHORD_TOL
    turns = round(a[-1] / 360.0)
    floor = np.sqrt(ROOT**2 - (np.abs(case.axis(theta)[1]) + WIDTH / 2) ** 2)  # the tip reaches the walls at the root radius
    last = moves[:, 0, 3] >= a[-1] - 360.0
    assert np.max(np.abs(pose[last][..., 2] - floor[last])) < 1e-3
    z = np.concatenate([moves[:1, 0, 2], moves[:, 1, 2]])
    assert z[0] == RIM and z.min() <= ROOT - (ROOT - math.sqrt(ROOT**2 - (WIDTH / 2) ** 2)) + 5e-5
    # roughing: the tip falls at most step_down per turn, and reaches the floor by the last turn
    drop = z[:-1] - np.interp(a[:-1] + 360.0, a, z)
    assert drop.max() <= machining.step_down + 1e-4
    assert turns == math.ceil((RIM - z.min()) / machining.step_down - 1e-9) + 1


@pytest.mark.usefixtures("needs_rs274")
def test_inverse_time_feed_is_the_feed_at_the_rim(tmp_path):
    """Each G93 move lasts 1/F min: its length at the rim (sqrt((R_o dA)^2 + dX^2 + dY^2 + dZ^2))
    over that time is the machining feed, rounded down by at most the printed F's last digit."""
    from camgen.export.gcode_barrel import barrel_program

    machining = spec(feed=350.0)
    program = barrel_program(groove(Case("translating", 1)), machining)
    moves = cutting_moves(canon_moves(program, tmp_path))
    body = program[program.index("\nG93\n"):program.index("G94\nG0")]
    f = np.array([float(x) for x in re.findall(r"^G1 .* F([\d.]+)$", body, re.M)])
    assert f.size == len(moves)
    d = moves[:, 1] - moves[:, 0]
    length = np.sqrt((RIM * np.radians(d[:, 3])) ** 2 + d[:, 0] ** 2 + d[:, 1] ** 2 + d[:, 2] ** 2)
    speed = length * f
    assert np.all(speed <= machining.feed * (1 + 1e-9)) and np.all(speed >= machining.feed - 1e-4 * length.max() - 1e-9)


# ---------------------------------------------------------------------------------------------
# the stock removed against the exact groove
# ---------------------------------------------------------------------------------------------
def exact_walls(case: Case, r: np.ndarray, phi: np.ndarray, w: float) -> tuple[np.ndarray, np.ndarray]:
    """api.md's brute force: z_upper = max over theta of [z_c + sqrt(w^2 - (r sin(phi + sigma theta) - e)^2)] with
    r cos(phi + sigma theta) > 0, z_lower its twin; over the world angle u = phi + sigma theta on a grid of 4001
    points across the roller, then 2001 points across the best grid step's neighbours."""
    reach = np.arcsin(np.minimum(1.0, (w + abs(ARM * (math.cos(SWING / 2) - 1.0)) + 0.01) / r))
    out = []
    for side in (1.0, -1.0):
        lo, hi = -reach, reach
        for n in (4001, 2001):
            u = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, n)[None, :]
            theta = case.sigma * (u - phi[:, None])
            z_c, e = case.axis(theta)
            g = r[:, None] * np.sin(u) - e
            val = np.where(g * g < w * w, z_c + side * np.sqrt(np.maximum(w * w - g * g, 0.0)), -side * np.inf)
            k = np.argmax(side * val, axis=1)
            best = val[np.arange(len(r)), k]
            step = (hi - lo) / (n - 1)
            centre = u[np.arange(len(r)), k]
            lo, hi = centre - 2 * step, centre + 2 * step
        out.append(best)
    return out[0], out[1]


def removed(points: np.ndarray, poses: np.ndarray, tool_radius: float, chunk: int = 64) -> np.ndarray:
    """Whether each point (r, phi, z) lies inside the cutter at some pose (X, Y, Z tip, A deg): the
    cam turned by A, the point at world (x, y) = r (cos, sin)(phi + A); machine (X, Y, Z) = (z, -y, x);
    the cutter is the cylinder of ``tool_radius`` about the line (X, Y) above its tip Z.

    Every pose is tested that could hold the point: the cutter is over a point only where
    ``|z - X| < tool_radius`` (its axis' distance along the cam axis) and A is within the angle the
    cutter spans at radius r, so the poses are sorted by their band of X (``tool_radius`` wide) and
    then by A, and each point tests the poses of the bands that reach ``[z - R, z + R]`` (widened
    by 1e-9 mm against rounding) within its angular window: a superset of the poses that can hold
    it, the test itself unchanged (a bruteforce over all poses gives the same answer)."""
    band_width = tool_radius
    a = np.mod(np.radians(poses[:, 3]), 2 * math.pi)
    band = np.floor(poses[:, 0] / band_width).astype(np.int64)
    a = np.concatenate([a - 2 * math.pi, a, a + 2 * math.pi]) + 2 * math.pi  # wrapped, in [0, 6 pi)
    band = np.concatenate([band, band, band])
    poses = np.concatenate([poses, poses, poses])
    span = 8 * math.pi  # > 6 pi: one band's angles never reach the next band's
    key = band * span + a
    order = np.argsort(key, kind="stable")
    key, poses = key[order], poses[order]
    out = np.zeros(len(points), dtype=bool)
    half = np.arcsin(np.minimum(1.0, (tool_radius + np.abs(poses[:, 1]).max() + 0.01) / points[:, 0]))
    margin = 1e-9
    low_band = np.floor((points[:, 2] - tool_radius - margin) / band_width).astype(np.int64)
    high_band = np.floor((points[:, 2] + tool_radius + margin) / band_width).astype(np.int64)
    for lo_i in range(0, len(points), chunk):
        p = points[lo_i:lo_i + chunk]
        centre = np.mod(-p[:, 1], 2 * math.pi) + 2 * math.pi  # the poses whose tool is over the point: A = -phi
        h = half[lo_i:lo_i + chunk]
        lo_b, hi_b = low_band[lo_i:lo_i + chunk], high_band[lo_i:lo_i + chunk]
        for k in range(int((hi_b - lo_b).max()) + 1):
            b = lo_b + k
            first = np.searchsorted(key, b * span + centre - h)
            last = np.where(b <= hi_b, np.searchsorted(key, b * span + centre + h), first)
            width = int((last - first).max())
            if width == 0:
                continue
            idx = first[:, None] + np.arange(width)[None, :]
            valid = idx < last[:, None]
            q = poses[np.minimum(idx, len(poses) - 1)]
            ang = p[:, 1:2] + np.radians(q[..., 3])
            x_m, y_m, z_m = p[:, 2:3], -p[:, 0:1] * np.sin(ang), p[:, 0:1] * np.cos(ang)
            inside = ((x_m - q[..., 0]) ** 2 + (y_m - q[..., 1]) ** 2 < tool_radius**2) & (z_m >= q[..., 2]) & valid
            out[lo_i:lo_i + chunk] |= inside.any(axis=1)
    return out


@pytest.mark.parametrize("case,direction", [(Case("translating", 1), "climb"), (Case("translating", -1), "conventional"),
                                            (Case("oscillating", -1), "climb")], ids=str)
@pytest.mark.usefixtures("needs_rs274")
def test_the_cutter_swept_through_the_program_leaves_the_exact_groove(case, direction, tmp_path):
    """Stock sampled beside both walls at the root, mean and rim radius, 200 polar angles each:
    every sample CHORD_TOL inside the exact groove is cut by the cutter at the canonical poses (each
    move subdivided to <= 0.01 mm at the rim), none CHORD_TOL outside the walls is."""
    from camgen.export.gcode_barrel import barrel_program

    machining = spec(direction=direction)
    program = barrel_program(groove(case), machining)
    moves = cutting_moves(canon_moves(program, tmp_path))
    d = moves[:, 1] - moves[:, 0]
    parts = np.maximum(1, np.ceil(RIM * np.abs(np.radians(d[:, 3])) / 0.01)).astype(int)
    k = np.repeat(np.arange(len(moves)), parts)
    frac = (np.arange(parts.sum()) - np.repeat(np.cumsum(parts) - parts, parts)) / np.repeat(parts, parts)
    poses = np.concatenate([moves[k, 0] + d[k] * frac[:, None], moves[-1:, 1]])

    rng = np.random.default_rng(24)
    phi = np.concatenate([np.linspace(0.0, 2 * math.pi, 200, endpoint=False) + rng.uniform(0, 0.03, 200) for _ in range(3)])
    r = np.repeat([ROOT, (RIM + ROOT) / 2, RIM], 200)
    upper, lower = exact_walls(case, r, phi, WIDTH / 2)
    assert np.all(upper - lower > WIDTH * 0.5)
    tol = CHORD_TOL
    inside = np.concatenate([np.column_stack([r, phi, upper - tol]), np.column_stack([r, phi, lower + tol])])
    outside = np.concatenate([np.column_stack([r, phi, upper + tol]), np.column_stack([r, phi, lower - tol])])
    cut_in = removed(inside, poses, machining.tool_radius)
    cut_out = removed(outside, poses, machining.tool_radius)
    assert cut_in.all(), inside[~cut_in][:5]
    assert not cut_out.any(), outside[cut_out][:5]


# ---------------------------------------------------------------------------------------------
# refusals
# ---------------------------------------------------------------------------------------------
def test_a_tool_that_is_not_the_groove_width_is_refused_naming_the_key():
    """Through the writer: machining.tool_diameter_mm, its value and the width (which is itself
    accepted) within the stated tolerance; a conical roller names its roller_shape."""
    from camgen.export.gcode_barrel import barrel_program, width_tol

    g = groove(Case("translating", 1))
    tol = width_tol(spec())
    for diameter in (WIDTH - 1.5 * tol, WIDTH + 1.5 * tol, 8.0):
        with pytest.raises(ParameterError) as err:
            barrel_program(g, spec(tool_diameter=diameter), "barrel")
        assert err.value.name == "tool_diameter" and err.value.value == diameter
        quoted = float(re.match(r"([\d.]+) mm", err.value.valid).group(1))
        assert quoted == pytest.approx(WIDTH, abs=1e-12)
    for diameter in (WIDTH - 0.9 * tol, WIDTH + 0.9 * tol):
        assert "G93" in barrel_program(g, spec(tool_diameter=diameter))
    with pytest.raises(ParameterError) as err:
        barrel_program(groove(Case("translating", 1), "conical"), spec(), "barrel")
    assert err.value.name == "cams.barrel.roller_shape" and err.value.value == "conical"


def test_a_program_too_long_is_refused_naming_the_least_step_down():
    """2 um steps down 10.2 mm would take over 5000 turns of ~980 moves, more than the 2,000,000 moves
    a program may hold: refused naming step_down with a least step whose turns x moves fit."""
    from camgen.export.gcode import MAX_PROGRAM_MOVES
    from camgen.export.gcode_barrel import barrel_program, tool_path

    g = groove(Case("translating", 1))
    with pytest.raises(ParameterError) as err:
        barrel_program(g, spec(step_down=0.002))
    assert err.value.name == "step_down"
    least = float(re.fullmatch(r">= ([\d.]+) mm", err.value.valid).group(1))
    per_turn = tool_path(g, spec()).a.size - 1
    depth = RIM - math.sqrt(ROOT**2 - (WIDTH / 2) ** 2)
    assert (math.ceil(depth / least - 1e-9) + 1) * per_turn <= MAX_PROGRAM_MOVES < (math.ceil(depth / (0.98 * least)) + 1) * per_turn


def _barrel_result(g):
    """A CamResult as the pipeline hands it to the barrel form's ngc writer (cam.built.groove)."""
    from typing import Any

    from camgen.body import BodySpec
    from camgen.kinds.base import BuiltCam, CamSpec, CheckSettings
    from camgen.results import CamResult

    @dataclasses.dataclass(frozen=True)
    class Built(BuiltCam):
        groove: Any = None

    body = BodySpec(thickness=LENGTH)
    return CamResult(CamSpec("barrel", "motion_law", None, body, CheckSettings(), form="barrel"),
                     Built("barrel", "motion_law", None, {}, body, groove=g))


def test_the_writer_names_the_scene_keys():
    """camgen.export.gcode_barrel:writer (the barrel form's ngc): machining.tool_diameter_mm with the
    width for the cam; the grbl dialect (no rotary axis) and cutter compensation likewise."""
    from camgen.export.gcode_barrel import writer
    from camgen.outputs import OutputSpec
    from camgen.writers import RunSettings

    cam = _barrel_result(groove(Case("translating", 1)))
    run = RunSettings("s", OutputSpec(formats=("ngc",), chord_tol=CHORD_TOL), spec(tool_diameter=8.0))
    with pytest.raises(ParameterError) as err:
        writer(cam, run, "ngc")
    assert err.value.name == "machining.tool_diameter_mm" and err.value.value == 8.0
    assert re.fullmatch(r"8\.5 mm \(the groove's width .*\) for cam 'barrel'", err.value.valid), err.value.valid
    for key, change in (("machining.dialect", {"dialect": "grbl"}), ("machining.cutter_compensation", {"cutter_compensation": True})):
        with pytest.raises(ParameterError) as err:
            writer(cam, dataclasses.replace(run, machining=spec(**change)), "ngc")
        assert err.value.name == key
    assert writer(cam, dataclasses.replace(run, machining=spec()), "ngc").startswith("(camgen ")


def test_a_run_with_the_wrong_tool_exits_2_and_writes_nothing(tmp_path, capsys):
    """The whole run: exit 2, one stderr line naming machining.tool_diameter_mm, its value and the
    groove's width; the output folder is not made."""
    from camgen.cli import main
    from camgen.forms import form_names

    if "barrel" not in form_names():
        pytest.skip("the barrel form (camgen.forms.barrel) is not on this branch yet")
    segments = "".join(f'\n[[cams.b.segments]]\nlaw = "{law}"\nspan_deg = {span}\n' + (f"lift_mm = {lift}\n" if lift else "")
                       for law, span, lift in (("cycloidal", 120.0, RISE), ("dwell", 60.0, 0), ("cycloidal", 120.0, -RISE), ("dwell", 60.0, 0)))
    scene = ('[output]\nformats = ["ngc"]\n\n[machining]\ntool_diameter_mm = 8.0\n\n[cams.b]\nkind = "motion_law"\nform = "barrel"\n'
             f'roller_radius_mm = {ROLLER}\ncylinder_radius_mm = {RIM}\ncylinder_length_mm = {LENGTH}\ngroove_depth_mm = {RIM - ROOT}\n'
             f'groove_clearance_mm = {CLEARANCE}\npressure_angle_limit_deg = 45.0\n' + segments)
    path = tmp_path / "scene.toml"
    path.write_text(scene, encoding="utf-8")
    parent = tmp_path / "parent"
    parent.mkdir()
    status = main(["run", str(path), "-o", str(parent / "out")])
    err = capsys.readouterr().err
    assert status == 2, err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1 and "Traceback" not in err, err
    assert "machining.tool_diameter_mm" in err and "8" in err and "8.5 mm" in err, err
    assert list(parent.iterdir()) == []
