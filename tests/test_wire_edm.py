"""Wire-EDM programs (dialect = "wire_edm"), run through LinuxCNC's rs274 and cut in a simulation.

Every number the programs are judged by comes from outside camgen.export.wire_edm: the exact
profile (the contour the program was made from), the offsets of the rule the header states
(wire radius + spark gap + allowance), rs274's canonical moves with its own cutter compensation
(the registers D<k> loaded from a tool table), and the profile's arc length.

The wire is a disc of radius wire radius + spark gap swept along rs274's wire-centre path, cut
by cut (the moves between two program stops, M00):

* cut k stays at least offset_k - CUT_TOL from the profile and reaches every point of it outside
  the tab within offset_k + CUT_TOL: it leaves allowance_k, the last cut none, within 1 um;
* the tab: the stretch of the profile between the support point of the entry's tangent move
  and the foot of the wire's stop has the stated length; the cut-off after the last stop cuts
  exactly that stretch, at the last cut's offset.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.export.gcode import MachiningSpec
from camgen.export.wire_edm import wire_edm_program
from camgen.export.wire_edm_spec import WireEdmSpec
from cutting import CUT_TOL, ExactProfile, sample_moves
from helpers import require_tool, rs274_env
from test_gcode import TEMPLATES as GCODE_TEMPLATES, template_cams  # noqa: F401 (template_cams: a fixture)

#: Lines of the programs LinuxCNC does not know, masked before rs274 reads them: none (%, M00,
#: G41 D<k>, G54 and M30 are all LinuxCNC's).
MASKED: tuple[str, ...] = ()
#: Spacing of the samples along every wire move, mm (the proud bound is step^2 / (8 offset) too large).
STEP = 0.005
#: rs274's tool table is in inches (its machine units).
INCH = 25.4


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


@pytest.fixture(scope="module")
def cams():
    """The plate cam of two templates, built by the pipeline: [(name, contour, thickness)]."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    out = []
    for name in ("plate_cam", "oscillating_roller"):
        scene = load_template(name)
        cam = compute(scene, Plan((), frozenset())).cams[0]
        out.append((name, cam.contour, cam.body.thickness))
    return out


def _masked(program: str) -> str:
    return "".join(line + "\n" for line in program.splitlines() if not any(line.startswith(m) for m in MASKED))


def run_rs274(program: str, offsets, workdir) -> tuple[int, str, list[list[dict]]]:
    """rs274 with tools 1..n of radius offsets[k - 1] (mm; the table in inches); the canonical
    feed moves in chains split at every program stop and traverse."""
    table = workdir / "wire.tbl"
    table.write_text("".join(f"T{k} P{k} D{2.0 * o / INCH:.12f}\n" for k, o in enumerate(offsets, 1)))
    path = workdir / "wire.ngc"
    path.write_text(_masked(program))
    proc = subprocess.run(["rs274", "-t", str(table), "-g", str(path)], stdin=subprocess.DEVNULL, capture_output=True, text=True,
                          timeout=120, env=rs274_env(workdir, table.read_text()))  # HOME: a tool table of its own (helpers.rs274_env)
    number = r"(-?\d+(?:\.\d+)?)"
    straight = re.compile(rf"STRAIGHT_(FEED|TRAVERSE)\({number}, {number}, {number}")
    arc = re.compile(rf"ARC_FEED\({number}, {number}, {number}, {number}, (-?\d+), {number}")
    chains: list[list[dict]] = [[]]
    current = np.zeros(3)
    for line in proc.stdout.splitlines():
        m = straight.search(line)
        if m:
            end = np.array([float(m.group(i)) for i in (2, 3, 4)])
            if m.group(1) == "FEED":
                chains[-1].append({"kind": "line", "start": current, "end": end})
            else:
                chains.append([])
            current = end
            continue
        m = arc.search(line)
        if m:
            end = np.array([float(m.group(1)), float(m.group(2)), float(m.group(6))])
            chains[-1].append({"kind": "arc", "start": current, "end": end, "centre": np.array([float(m.group(3)), float(m.group(4))]),
                               "turn": int(m.group(5))})
            current = end
        elif "PROGRAM_STOP" in line:
            chains.append([])
    return proc.returncode, proc.stderr + (proc.stdout[-2000:] if proc.returncode else ""), [c for c in chains if c]


def _arc_lengths(vertices: np.ndarray) -> np.ndarray:
    closed = np.vstack([vertices, vertices[:1]])
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])


def _peak(values: np.ndarray, s: np.ndarray, i: int) -> float:
    """Arc length of the extremum of ``values`` near vertex i (parabola through i - 1, i, i + 1)."""
    n = len(values)
    a, b, c = values[(i - 1) % n], values[i], values[(i + 1) % n]
    h = 0.5 * ((s[i + 1] - s[i]) + (s[i] - s[i - 1] if i > 0 else s[-1] - s[-2]))
    denom = a - 2.0 * b + c
    return float(s[i] + (0.5 * (a - c) / denom * h if denom != 0.0 else 0.0))


def cut_report(chain: list[dict], profile: ExactProfile, offset: float, skip: np.ndarray | None = None) -> tuple[float, float]:
    """(gouge, proud) of one cut with a wire offset ``offset``: gouge = offset - the least distance
    (rigorous lower bound) of the wire centre from the profile; proud = the largest distance of a
    profile vertex (those not in ``skip``) from the wire-centre path minus ``offset``."""
    from scipy.spatial import cKDTree

    pts, move, h, rho = sample_moves(chain, STEP)
    reach = offset + 1.0
    f = profile.distance_lower_bound(pts, reach)
    same = move[:-1] == move[1:]
    slack = ((1.0 + (reach + h) / rho) * h * h / 4.0)[move[:-1]]
    pair = np.minimum(f[:-1], f[1:])
    low = np.where(pair > 0, np.sqrt(np.maximum(pair * pair - slack, 0.0)), pair)
    low = float(min(np.min(low[same], initial=np.inf), np.min(f)))
    inside = profile.contains_many(pts)
    if inside.any():
        low = -1.0
    d_s, _ = cKDTree(pts).query(profile.vertices, distance_upper_bound=reach)
    if skip is not None:
        d_s = d_s[~skip]
    return offset - low, float(np.max(d_s)) - offset


def tab_stretch(chain: list[dict], profile: ExactProfile) -> tuple[float, float]:
    """Arc lengths (along the profile's vertices, counter-clockwise) of the start point, where the
    entry's tangent move touches the profile (the support point of its outward normal), and of the
    stop point, the foot of the wire's last position."""
    s = _arc_lengths(profile.vertices)
    leg = chain[1]  # the entry: hole -> tangent line (compensation on), then along the tangent line
    u = (leg["end"][:2] - leg["start"][:2]) / np.hypot(*(leg["end"][:2] - leg["start"][:2]))
    outward = np.array([-u[1], u[0]])  # the wire runs with the part on its right (G41, outside)
    height = profile.vertices @ outward
    s_start = _peak(height, s, int(np.argmax(height)))
    last = chain[-1]["end"][:2]
    dist2 = np.sum((profile.vertices - last) ** 2, axis=1)
    s_stop = _peak(dist2, s, int(np.argmin(dist2)))
    return s_start, s_stop


def _in_stretch(s: np.ndarray, lo: float, hi: float, total: float) -> np.ndarray:
    return ((s - lo) % total) < ((hi - lo) % total)


@pytest.mark.parametrize("skims, allowances", [(2, None), (0, None), (3, (0.15, 0.05, 0.01))])
@pytest.mark.usefixtures("needs_rs274")
def test_each_cut_leaves_its_allowance_and_the_tab_its_width(cams, skims, allowances, tmp_path):
    for name, contour, thickness in cams:
        wire = WireEdmSpec(wire_diameter=0.25, spark_gap=0.03, skim_cuts=skims, cut_allowances=allowances, tab_width=4.0)
        spec = MachiningSpec(dialect="wire_edm", chord_tol=1e-3, wire_edm=wire)
        program = wire_edm_program(contour, spec, name, "edm", thickness)
        kerf = 0.125 + 0.03
        expected = [kerf + a for a in (allowances or tuple(0.1 * 0.2**k for k in range(skims)))] + [kerf]  # the documented rule
        assert all(f"D{k} = {o:.4f}" in program for k, o in enumerate(expected, 1)), name
        status, message, chains = run_rs274(program, expected, tmp_path)
        assert status == 0, (name, message)
        n = skims + 1
        assert len(chains) == n + 1, (name, len(chains))  # n cuts, then the cut-off after the last stop
        profile = ExactProfile(contour)
        s = _arc_lengths(profile.vertices)[:-1]
        total = float(_arc_lengths(profile.vertices)[-1])
        for k, (chain, offset) in enumerate(zip(chains[:n], expected), 1):
            s_start, s_stop = tab_stretch(chain, profile)
            width = (s_stop - s_start) % total
            assert abs(width - wire.tab_width) <= CUT_TOL, (name, k, width)
            tab = _in_stretch(s, s_start, s_stop, total)
            gouge, proud = cut_report(chain, profile, offset, skip=tab)
            assert gouge <= CUT_TOL and proud <= CUT_TOL, (name, k, gouge, proud)
        # the cut-off: exactly the tab stretch, at the last offset; the last cut and it leave the whole profile
        cut_off = chains[n]
        gouge, proud = cut_report(cut_off, profile, expected[-1], skip=~tab)
        assert gouge <= CUT_TOL and proud <= CUT_TOL, (name, "cut-off", gouge, proud)
        assert all(abs(mv["end"][2]) == 0.0 and abs(mv["start"][2]) == 0.0 for c in chains for mv in c), name  # no Z


@pytest.mark.parametrize("template", GCODE_TEMPLATES)
@pytest.mark.usefixtures("needs_rs274")
def test_every_templates_wire_program_cuts_its_profile(template, template_cams, tmp_path):
    """Every cam of every plate template (tests/test_gcode.py's list) cut by the wire, a first cut
    and a skim: each leaves the profile at its wire offset within 1 um (rs274's moves, the wire
    swept over the stock) but for the tab, which the cut-off then cuts at the last offset; a cam
    with pockets (the groove cam) is refused, naming a key."""
    for cam, base in template_cams[template]:
        spec = MachiningSpec(dialect="wire_edm", chord_tol=base.chord_tol, wire_edm=WireEdmSpec(skim_cuts=1))
        if cam.pockets:
            with pytest.raises(ParameterError):
                wire_edm_program(cam.contour, spec, cam.name, template, cam.body.thickness, cam.pockets)
            continue
        program = wire_edm_program(cam.contour, spec, cam.name, template, cam.body.thickness)
        assert spec.wire_edm is not None
        offsets = list(spec.wire_edm.offsets)
        status, message, chains = run_rs274(program, offsets, tmp_path)
        assert status == 0, message
        profile = ExactProfile(cam.contour)
        s = _arc_lengths(profile.vertices)[:-1]
        total = float(_arc_lengths(profile.vertices)[-1])
        n = len(offsets)
        assert len(chains) == n + 1, (template, cam.name, len(chains))
        for k, (chain, offset) in enumerate(zip(chains[:n], offsets), 1):
            s_start, s_stop = tab_stretch(chain, profile)
            tab = _in_stretch(s, s_start, s_stop, total)
            gouge, proud = cut_report(chain, profile, offset, skip=tab)
            assert gouge <= CUT_TOL and proud <= CUT_TOL, (template, cam.name, k, gouge, proud)
        gouge, proud = cut_report(chains[n], profile, offsets[-1], skip=~tab)
        assert gouge <= CUT_TOL and proud <= CUT_TOL, (template, cam.name, "cut-off", gouge, proud)


@pytest.mark.usefixtures("needs_rs274")
def test_the_simulation_sees_a_wrong_offset(cams, tmp_path):
    """The check itself: a register 5 um smaller than the program's rule gouges by 5 um (within the
    program's path tolerance), more than the tests accept."""
    name, contour, thickness = cams[0]
    spec = MachiningSpec(dialect="wire_edm", chord_tol=1e-3, wire_edm=WireEdmSpec(skim_cuts=0))
    program = wire_edm_program(contour, spec, name, "edm", thickness)
    offset = 0.125 + 0.02
    status, message, chains = run_rs274(program, [offset - 0.005], tmp_path)
    assert status == 0, message
    profile = ExactProfile(contour)
    gouge, _ = cut_report(chains[0], profile, offset, skip=np.zeros(len(profile.vertices), bool))
    assert gouge > CUT_TOL and abs(gouge - 0.005) <= CUT_TOL, gouge


def test_no_z_and_compensation_switched_on_linear_moves_only(cams):
    name, contour, thickness = cams[1]
    program = wire_edm_program(contour, MachiningSpec(dialect="wire_edm", chord_tol=1e-3), name, "edm", thickness)
    code = [re.sub(r"\(.*?\)", "", line).strip() for line in program.splitlines()]
    assert not any(re.search(r"\bZ", line) for line in code)
    motion = [line for line in code if re.search(r"\bG(40|41|42)\b", line)]
    assert motion[0] == "G21 G90 G17 G40 G54"  # the safe start: no motion
    switches = motion[1:]
    assert len(switches) == 2 * 3  # on and off once per cut (3 cuts by default)
    assert all(re.search(r"\bG1\b", line) and not re.search(r"\bG[23]\b", line) for line in switches), switches
    assert program.startswith("%\n") and program.endswith("M30\n%\n")


def _cli(scene_text: str, tmp_path) -> subprocess.CompletedProcess:
    path = tmp_path / "edm.toml"
    path.write_text(scene_text)
    return subprocess.run([sys.executable, "-P", "-m", "camgen", "run", str(path), "-o", str(tmp_path / "out")], capture_output=True,
                          text=True, timeout=300)


CAM = """
[cams.c]
kind = "motion_law"
base_radius_mm = 40.0
follower = "roller"
roller_radius_mm = 10.0
[[cams.c.segments]]
law = "cycloidal"
span_deg = 180.0
lift_mm = 10.0
[[cams.c.segments]]
law = "cycloidal"
span_deg = 180.0
lift_mm = -10.0
"""


@pytest.mark.parametrize("machining, key", [
    ('dialect = "wire_edm"\nstep_down_mm = 2.0', "machining.step_down_mm"),
    ('dialect = "wire_edm"\nspindle_rpm = 1000.0', "machining.spindle_rpm"),
    ('dialect = "wire_edm"\ntool_diameter_mm = 6.0', "machining.tool_diameter_mm"),
    ('wire_diameter_mm = 0.2', "machining.wire_diameter_mm"),  # a wire key with a milling dialect
    ('dialect = "wire_edm"\nskim_cuts = 2\ncut_allowances_mm = [0.1]', "machining.cut_allowances_mm"),
    ('dialect = "wire_edm"\ncut_allowances_mm = [0.02, 0.1]', "machining.cut_allowances_mm"),
    ('dialect = "wire_edm"\nstart_hole_offset_mm = 1.0', "machining.start_hole_offset_mm"),
    ('dialect = "wire_edm"\ntab_width_mm = 500.0', "machining.tab_width_mm"),
    ('dialect = "wire_edm"\nwire_diameter_mm = -0.2', "machining.wire_diameter_mm"),
])
def test_bad_input_exits_2_naming_the_key(machining, key, tmp_path):
    proc = _cli(f'[output]\nformats = ["ngc"]\n[machining]\n{machining}\n{CAM}', tmp_path)
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camgen: error: ") and key in lines[0], proc.stderr
    assert not (tmp_path / "out").exists()


def test_a_groove_cam_is_refused_for_wire_edm(tmp_path):
    """A groove is blind: a wire cannot cut it (exit 2 naming machining.dialect)."""
    from importlib.resources import files

    body = files("camgen.templates").joinpath("groove_cam.toml").read_text()
    body = re.sub(r"\[machining\][^\[]*", "", body)
    body = re.sub(r"formats = \[[^\]]*\]", 'formats = ["ngc"]', body, count=1)
    proc = _cli('[machining]\ndialect = "wire_edm"\n' + body, tmp_path)
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    assert "machining.dialect" in proc.stderr and "pockets" in proc.stderr, proc.stderr


@pytest.mark.usefixtures("needs_rs274")
def test_the_template_program_cuts_its_profile(tmp_path):
    """wire_edm_cam as the ngc writer writes it: rs274 runs it with the registers its header
    names, the last cut and the cut-off leave the profile within 1 um."""
    import dataclasses

    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    scene = load_template("wire_edm_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    spec = dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol)
    program = wire_edm_program(cam.contour, spec, cam.name, scene.name, cam.body.thickness)
    registers = [float(v) for v in re.findall(r"\(register D\d+ = ([0-9.]+)", program)]
    kerf = 0.25 / 2 + 0.02
    assert registers == pytest.approx([kerf + 0.1, kerf + 0.02, kerf], abs=1e-12)  # the template's keys, by the stated rule
    status, message, chains = run_rs274(program, registers, tmp_path)
    assert status == 0, message
    profile = ExactProfile(cam.contour)
    s = _arc_lengths(profile.vertices)[:-1]
    total = float(_arc_lengths(profile.vertices)[-1])
    s_start, s_stop = tab_stretch(chains[2], profile)
    assert abs((s_stop - s_start) % total - 3.0) <= CUT_TOL
    tab = _in_stretch(s, s_start, s_stop, total)
    for chain, skip in ((chains[2], tab), (chains[3], ~tab)):
        gouge, proud = cut_report(chain, profile, kerf, skip=skip)
        assert gouge <= CUT_TOL and proud <= CUT_TOL, (gouge, proud)
