"""Fanuc / Haas programs (``dialect = "fanuc"``), run through LinuxCNC's rs274 and cut in a simulation.

rs274 reads a Fanuc program once the lines LinuxCNC does not know are masked (:data:`MASKED`:
the ``%`` framing and the ``O`` program number line; nothing else is changed).  The radius
register is checked by cutting: rs274 is given a tool table whose entry for the program's ``D``
register has the diameter twice the radius the program's header asks for (LinuxCNC's ``G41 D``
reads a tool's diameter), and every other tool a wrong diameter; the simulation
(tests/cutting.py, the real tool radius swept over the exact profile) must then leave the profile
within 1 um.  So a header that states the wrong value, or a ``D`` word that names another
register, shows as a gouge or proud material.
"""
from __future__ import annotations

import dataclasses
import re
import subprocess
import sys

import numpy as np
import pytest

from camgen.contour import Arc, Contour
from camgen.export.gcode import MachiningSpec, gcode_program
from cutting import CUT_TOL, ExactProfile, simulate, simulate_pockets
from helpers import require_tool, rs274_canon, rs274_command, rs274_env

TEMPLATES = ("default", "tricycle", "horse_leg", "motion_law", "plate_cam", "flat_follower", "knife_follower", "oscillating_roller",
             "oscillating_flat", "lift_table", "groove_cam", "conjugate_cam", "constant_breadth")
MODES = [(comp, direction) for comp in (False, True) for direction in ("climb", "conventional")]

#: The only lines masked for rs274: the % framing and the O-number line (LinuxCNC reads O as a subroutine label).
MASKED = (re.compile(r"%"), re.compile(r"O\d{4} \([A-Z0-9 .,=_\-+*]*\)"))
#: A diameter no tool of these programs has (mm): a tool-table entry the program must not use for compensation.
WRONG_DIAMETER = 97.0


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


@pytest.fixture(scope="module")
def template_cams():
    """Every cam of every listed template, built by the pipeline: {template: [(cam, spec)]}
    (the machining spec the ngc writer uses, camgen.writers.gcode, in the fanuc dialect)."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    out = {}
    for name in TEMPLATES:
        scene = load_template(name)
        cams = compute(scene, Plan((), frozenset())).cams
        out[name] = [(cam, dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol,
                                               dialect="fanuc")) for cam in cams]
    return out


def masked(program: str) -> str:
    """The program without the lines of :data:`MASKED` (each must be there: two ``%`` and one ``O`` line)."""
    lines = program.splitlines()
    kept = [line for line in lines if not any(p.fullmatch(line) for p in MASKED)]
    assert len(lines) - len(kept) == 3 and lines[0] == "%" and lines[-1] == "%" and re.fullmatch(r"O\d{4} .*", lines[1]), lines[:2]
    return "\n".join(kept) + "\n"


def stated_register(program: str) -> tuple[int, float]:
    """The radius register and the value (mm) the program's header says it must hold."""
    m = re.search(r"^\(RADIUS REGISTER D(\d+) = ([\d.]+) MM ", program, re.M)
    assert m, "the header names the radius register"
    return int(m.group(1)), float(m.group(2))


#: rs274 (standalone) reads its tool table in inches: a length offset Z1 there is applied as 25.4 mm.
TABLE_UNIT_MM = 25.4


def tool_table(program: str, register_diameter: float | None = None) -> str:
    """A LinuxCNC tool table for ``program``: the D register's diameter twice the stated radius
    (or ``register_diameter``, mm), the tool called by T (if another number) at
    :data:`WRONG_DIAMETER`, length offsets 0; in the table's inches."""
    register, radius = stated_register(program)
    tool = int(re.search(r"^T(\d+) M06$", program, re.M).group(1))
    rows = {tool: WRONG_DIAMETER, register: 2.0 * radius if register_diameter is None else register_diameter}
    return "".join(f"T{n} P{n} Z0 D{diameter / TABLE_UNIT_MM:.12f} ;\n" for n, diameter in rows.items())


def _assert_cut(report, spec: MachiningSpec, label: str) -> None:
    """rs274 ran it, nothing gouged or left proud beyond 1 um, the last pass at the stock bottom
    + breakthrough, rapids below Z 0 clear of the part."""
    assert report.status == 0, (label, report.message)
    assert report.gouge <= CUT_TOL, (label, "gouge", report.gouge)
    assert report.proud <= CUT_TOL, (label, "proud", report.proud)
    assert all(p.outside for p in report.passes), label
    assert abs(report.deepest + spec.thickness + spec.breakthrough) < 1e-9, (label, report.deepest)
    assert report.rapid_clearance >= 0.0, (label, report.rapid_clearance)


def blocks_switching_compensation(program: str) -> list[str]:
    """The blocks (not comments) with G40, G41 or G42, the safe start line excluded."""
    return [line for line in program.splitlines() if not line.startswith("(") and re.search(r"\bG4[012]\b", line)
            and not line.startswith("G17 ")]


def assert_compensation_on_lines(program: str, spec: MachiningSpec) -> None:
    """G41/G42 D and G40 only in G1 blocks (never with G2/G3, nor G0); every D word the stated
    register; the stated value the tool radius (the profile programmed) or 0 (the tool-centre
    path); per pass one switch on and one off, on before the contour's first arc or line."""
    register, value = stated_register(program)
    assert value == pytest.approx(spec.tool_radius if spec.cutter_compensation else 0.0, abs=10.0 ** -spec.decimals)
    switches = blocks_switching_compensation(program)
    assert switches, "compensation is switched on and off"
    for block in switches:
        assert re.search(r"\bG0?1\b", block) and not re.search(r"\bG0?[023]\b", block), block
    side = "G41" if spec.direction == "climb" else "G42"
    ons = [b for b in switches if side in b]
    offs = [b for b in switches if "G40" in b]
    assert len(ons) == len(offs) == program.count("(PASS ") and len(ons) + len(offs) == len(switches)
    assert set(re.findall(r"\bD(\d+)\b", program)) == {f"{register:02d}"}
    assert all(f"D{register:02d}" in b for b in ons)


# ---------------------------------------------------------------------------------------------
# every bundled template with a plate-cam program, compensation on and off, both directions
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("template", TEMPLATES)
@pytest.mark.usefixtures("needs_rs274")
def test_every_template_fanuc_program_cuts_its_exact_profile(template, template_cams, tmp_path):
    for cam, base in template_cams[template]:
        profile = ExactProfile(cam.contour)
        for comp, direction in MODES:
            spec = dataclasses.replace(base, cutter_compensation=comp, direction=direction)
            program = gcode_program(cam.contour, spec, cam.name, template)
            assert_compensation_on_lines(program, spec)
            report = simulate(masked(program), cam.contour, spec.tool_radius, tmp_path, profile=profile, tool_table=tool_table(program))
            _assert_cut(report, spec, f"{template}/{cam.name} comp={comp} {direction}")


def test_program_frame_and_words(template_cams):
    """%, O number, G21 alone, the safe start line, T M06 then S M03 then G43 H at safe Z before
    any XY move, arcs by I/J only (no R), M30 and % at the end; comments upper-case."""
    cam, base = template_cams["default"][0]
    program = gcode_program(cam.contour, dataclasses.replace(base, program_number=42, tool_number=7), cam.name, "default")
    lines = program.splitlines()
    assert lines[:2] == ["%", f"O0042 ({cam.name.upper()})"] and lines[-3:] == ["M05", "M30", "%"]
    blocks = [line for line in lines[2:] if not line.startswith("(")]
    assert blocks[:5] == ["G21", "G17 G40 G49 G80 G90 G94 G54", "T7 M06", f"S{base.spindle_rpm:.0f} M03",
                          f"G0 G43 H07 Z{base.safe_z:.4f}"]
    assert "H07" in program and "D07" in program  # the radius register defaults to the tool number
    arcs = [b for b in blocks if re.match(r"G[23] ", b)]
    assert arcs and all(re.fullmatch(r"G[23] X-?[\d.]+ Y-?[\d.]+( Z-?[\d.]+)? I-?[\d.]+ J-?[\d.]+( F\d+)?", b) for b in arcs)  # Z: the helix
    assert not re.search(r"\bR-?[\d.]", program) and "M2\n" not in program and "G64" not in program
    assert all(line == line.upper() for line in lines)


@pytest.mark.usefixtures("needs_rs274")
def test_the_radius_register_is_the_one_stated_and_used(template_cams, tmp_path):
    """Tool 7 with its radius in register D27: the program says D27 and the value, and cuts the
    profile with a tool table whose tool 7 has a wrong diameter (so the D word is what rs274
    compensates with); told D27 held the tool 7's wrong diameter instead, it gouges."""
    cam, base = template_cams["motion_law"][0]
    profile = ExactProfile(cam.contour)
    spec = dataclasses.replace(base, cutter_compensation=True, tool_number=7, radius_register=27, program_number=9999)
    program = gcode_program(cam.contour, spec, cam.name)
    assert stated_register(program) == (27, pytest.approx(spec.tool_radius))
    assert re.search(r"^G0 G43 H07 Z", program, re.M) and "O9999 " in program
    assert_compensation_on_lines(program, spec)
    table = tool_table(program)
    assert f"T7 P7 Z0 D{WRONG_DIAMETER / TABLE_UNIT_MM:.12f}" in table and f"T27 P27 Z0 D{spec.tool_diameter / TABLE_UNIT_MM:.12f}" in table
    _assert_cut(simulate(masked(program), cam.contour, spec.tool_radius, tmp_path, profile=profile, tool_table=table), spec, "D27")
    wrong = tool_table(program, spec.tool_diameter - 0.01)
    report = simulate(masked(program), cam.contour, spec.tool_radius, tmp_path, profile=profile, tool_table=wrong)
    assert report.status == 0 and report.gouge == pytest.approx(0.005, abs=CUT_TOL)  # 0.01 mm less diameter: 5 um into the part (+- the path tolerance)


@pytest.mark.usefixtures("needs_rs274")
def test_compensation_switches_on_a_line_in_rs274s_moves(template_cams, tmp_path):
    """In rs274's canonical output the move after 'compensation on' and the move after
    'compensation off' are straight feeds, never arcs."""
    cam, base = template_cams["plate_cam"][0]
    for comp, direction in MODES:
        spec = dataclasses.replace(base, cutter_compensation=comp, direction=direction)
        program = gcode_program(cam.contour, spec, cam.name)
        path = tmp_path / "program.ngc"
        path.write_text(masked(program))
        table = tool_table(program)
        out = subprocess.run(rs274_command(path, tmp_path, table), stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120,
                             env=rs274_env(tmp_path, table)).stdout.splitlines()
        switches = [k for k, line in enumerate(out) if "cutter radius compensation o" in line][1:]  # the first: the reset
        assert len(switches) == 2 * program.count("(PASS "), (comp, direction)
        for k in switches:
            following = next(line for line in out[k + 1:] if "_FEED(" in line or "TRAVERSE(" in line)
            assert "STRAIGHT_FEED(" in following, (comp, direction, out[k], following)


# ---------------------------------------------------------------------------------------------
# pockets: tool-centre passes, then the outline with its register
# ---------------------------------------------------------------------------------------------
@pytest.mark.usefixtures("needs_rs274")
def test_groove_cam_fanuc_program_cuts_groove_and_outline(template_cams, tmp_path):
    """The groove's passes are the dialect-independent tool-centre passes (tests/test_gcode_pockets.py
    runs both directions): climb here, the frame and the outline's register being what is Fanuc's."""
    cam, base = template_cams["groove_cam"][0]
    assert cam.pockets
    for direction in ("climb",):
        spec = dataclasses.replace(base, direction=direction)
        program = gcode_program(cam.contour, spec, cam.name, "groove_cam", cam.body.thickness, cam.pockets)
        assert "POCKETS WITHOUT COMPENSATION" in program
        assert_compensation_on_lines(program, spec)
        walls = {wall.layer: wall.contour for wall in cam.pockets[0].walls}
        report = simulate_pockets(masked(program), cam.contour, walls, spec.tool_radius, tmp_path, tool_table=tool_table(program))
        outline, pocket = report.outline, report.pocket
        assert outline.status == 0, outline.message
        assert pocket is not None
        first_outline = report.order.index("outline")  # the pockets first, while the stock holds the part
        assert set(report.order[:first_outline]) == {"pocket"} and set(report.order[first_outline:]) == {"outline"}, report.order
        for layer in walls:
            assert pocket.gouge[layer] <= CUT_TOL and pocket.proud[layer] <= CUT_TOL, (direction, layer, pocket.gouge, pocket.proud)
        assert pocket.deepest == pytest.approx(-cam.pockets[0].depth, abs=1e-9)
        assert outline.gouge <= CUT_TOL and outline.proud <= CUT_TOL and outline.rapid_clearance >= 0.0, direction


# ---------------------------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------------------------
def test_settings_are_checked():
    from camgen.errors import ParameterError

    for name, bad in (("program_number", 0), ("program_number", 10000), ("tool_number", 100), ("radius_register", 1000),
                      ("tool_number", True), ("program_number", 1.0)):
        with pytest.raises(ParameterError, match=name):
            MachiningSpec(dialect="fanuc", **{name: bad})
    for dialect in ("linuxcnc", "grbl"):
        with pytest.raises(ParameterError, match="program_number.*only with dialect = 'fanuc'"):
            MachiningSpec(dialect=dialect, program_number=5)
    MachiningSpec(dialect="fanuc", program_number=9999, tool_number=99, radius_register=999)


def _machining(text: str, add: str) -> str:
    """The scene ``text`` with the lines ``add`` at the top of its [machining] table."""
    edited, n = re.subn(r"^\[machining\][^\n]*\n", lambda m: f"{m.group(0)}{add}\n", text, count=1, flags=re.M)
    assert n == 1
    return edited


def _run(tmp_path, template: str, edit) -> subprocess.CompletedProcess:
    from camgen.scene import template_path

    scene = tmp_path / f"{template}.toml"
    scene.write_text(edit(template_path(template).read_text(encoding="utf-8")), encoding="utf-8")
    return subprocess.run([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize(("template", "add", "key", "valid"), [
    ("default", 'dialect = "fanuc"\nprogram_number = 10000', "machining.program_number", "1 <= n <= 9999"),
    ("default", 'dialect = "fanuc"\nprogram_number = 0', "machining.program_number", "1 <= n <= 9999"),
    ("default", 'dialect = "fanuc"\ntool_number = 0', "machining.tool_number", "1 <= n <= 99"),
    ("default", 'dialect = "fanuc"\nradius_register = 1000', "machining.radius_register", "1 <= n <= 999"),
    ("default", "program_number = 12", "machining.program_number", "only with dialect = 'fanuc'"),
    ("default", 'dialect = "grbl"\nradius_register = 3', "machining.radius_register", "only with dialect = 'fanuc'"),
    ("default", 'dialect = "haas"', "machining.dialect", "fanuc"),
    ("barrel_cam", 'dialect = "fanuc"', "machining.dialect", '"linuxcnc" for a barrel cam'),
])
def test_bad_input_exits_2_naming_the_key(template, add, key, valid, tmp_path):
    def edit(text: str) -> str:  # the barrel cam's program only (its solid and STEP need not be built to be refused)
        text = _machining(text, add)
        return re.sub(r"^formats = .*$", 'formats = ["ngc"]', text, count=1, flags=re.M) if template == "barrel_cam" else text

    run = _run(tmp_path, template, edit)
    assert run.returncode == 2, (run.returncode, run.stderr)
    assert run.stderr.startswith("camgen: error: ") and run.stderr.count("\n") == 1, run.stderr
    assert key in run.stderr and valid in run.stderr, run.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.usefixtures("needs_rs274")
def test_a_fanuc_scene_writes_its_program(tmp_path):
    """`camgen run` with the fanuc dialect writes the program the scene asks for (O number, tool, register)."""
    run = _run(tmp_path, "default", lambda text: _machining(text, 'dialect = "fanuc"\nprogram_number = 321\ntool_number = 4\nradius_register = 44'))
    assert run.returncode == 0, run.stderr
    programs = sorted((tmp_path / "out").rglob("*.ngc"))
    assert programs
    text = programs[0].read_text()
    assert text.startswith("%\nO0321 (") and "T4 M06" in text and "G43 H04" in text and " D44 " in text
    status, message, _ = rs274_canon(masked(text), tmp_path, tool_table(text))
    assert status == 0, message


def test_a_whole_circle_is_written_as_arcs_that_never_close():
    """A whole circle (one arc) is written as arcs by I/J that never end where they start (no
    full circle a control could read either way)."""
    circle = Contour([Arc((0.0, 0.0), 30.0, 0.0, 2 * np.pi)])
    program = gcode_program(circle, MachiningSpec(dialect="fanuc", thickness=2.0, step_down=3.0))
    current = None
    for block in program.splitlines():
        m = re.match(r"G[0123]( G4[12] D\d+)? X(-?[\d.]+) Y(-?[\d.]+)", block)
        if m:
            end = (m.group(2), m.group(3))
            if block.startswith(("G2 ", "G3 ")):
                assert end != current, block
            current = end
