"""Inch programs (``machining.units = "inch"``): G20, every length in inches, feeds in in/min.

Judged from outside camgen.export.gcode_units:

* rs274 (LinuxCNC) accepts every inch program (Fanuc: after masking the lines of
  tests/test_gcode_fanuc.py) and reads it in inches (``USE_LENGTH_UNITS(CANON_UNITS_INCHES)``);
* the program converted back to mm **by this test** (each X, Y, Z, I, J, F word, the G64 P
  blend and the D diameter of G41.1/G42.1 times 25.4, G20 -> G21; a regular expression, not
  camgen) is cut by the simulation of tests/cutting.py from rs274's canonical moves: the
  profile within 1 um, compensation on and off, both directions.  rs274 prints 4 decimals of
  its units; of an inch that is 1.27 um per number, too coarse for the 1 um check, hence the
  conversion; that rs274 reads the inch program as the converted one is checked by comparing
  the two canonical outputs within their printed precision (0.5e-4 in + 0.5e-4 mm);
* the wire-EDM program's moves, converted back, match the mm program's within the two
  programs' rounding; a barrel cam's programs (its groove's, a rib's translating or oscillating)
  likewise, every number of them (A in degrees and the inverse-time F unchanged);
* the decimals rule: the least decimals whose printed rounding (an arc's centre and both ends
  each rounded by half a unit in x and y: up to 3 x sqrt(2)/2 x 10^-d in, times 25.4 mm) is
  within a quarter of chord_tol, computed here, is the default, and one fewer is refused;
* the feeds: F in in/min = mm/min / 25.4 within the 2 printed decimals.
"""
from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.export.gcode import MachiningSpec, gcode_program
from cutting import CUT_TOL, ExactProfile, simulate
from helpers import require_tool, rs274_canon, tree  # noqa: F401 (tree: a fixture)

INCH = 25.4  # mm, by definition
MODES = [(comp, direction) for comp in (False, True) for direction in ("climb", "conventional")]
#: rs274 prints 4 decimals of its units: the inch and the mm reading differ by at most these (mm).
PRINT_GAP = 0.5e-4 * INCH + 0.5e-4 + 1e-9
_WORD = re.compile(r"\b([XYZIJF])(-?\d+(?:\.\d+)?)")


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


@pytest.fixture(scope="module")
def plate():
    """The plate cam of the plate_cam template (biarcs of its splines) and its scene's machining spec."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    scene = load_template("plate_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    return cam, dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol)


def to_mm(program: str) -> str:
    """``program`` (inches) converted to mm word by word, comments kept as they are."""
    out = []
    for line in program.splitlines():
        if line.startswith("(") or line.startswith("%") or re.match(r"O\d", line):
            out.append(line)
            continue
        line = _WORD.sub(lambda m: f"{m.group(1)}{float(m.group(2)) * INCH:.8f}", line)
        if line.startswith("G64 P"):
            line = re.sub(r"P(\d+(?:\.\d+)?)", lambda m: f"P{float(m.group(1)) * INCH:.8f}", line)
        if re.search(r"G4[12]\.1", line):
            line = re.sub(r"\bD(\d+(?:\.\d+)?)", lambda m: f"D{float(m.group(1)) * INCH:.8f}", line)
        out.append(line.replace("G20", "G21"))
    return "\n".join(out) + "\n"


def _numbers(canon: list[dict]) -> np.ndarray:
    return np.concatenate([np.concatenate([m["start"], m["end"], m.get("centre", np.zeros(2))]) for m in canon])


@pytest.mark.usefixtures("needs_rs274")
@pytest.mark.parametrize("dialect", ["linuxcnc", "grbl", "fanuc"])
def test_inch_programs_cut_the_exact_profile(dialect, plate, tmp_path):
    from test_gcode_fanuc import TABLE_UNIT_MM, masked

    cam, base = plate
    profile = ExactProfile(cam.contour)
    for comp, direction in MODES:
        if comp and dialect == "grbl":
            continue
        spec = dataclasses.replace(base, units="inch", decimals=0, dialect=dialect, cutter_compensation=comp, direction=direction)
        assert spec.decimals == 6  # the default chord_tol 1e-3 mm in inches
        program = gcode_program(cam.contour, spec, cam.name, "plate_cam")
        label = f"{dialect} comp={comp} {direction}"
        assert "G21" not in program and re.search(r"^G20\b", program, re.M), label
        table = None
        if dialect == "fanuc":
            m = re.search(r"^\(RADIUS REGISTER D(\d+) = ([\d.]+) IN ", program, re.M)  # the header's value, in inches
            assert m, label
            register, radius = int(m.group(1)), float(m.group(2))
            assert radius == pytest.approx(spec.tool_radius / INCH if comp else 0.0, abs=1e-6), label
            table = f"T1 P1 Z0 D{2.0 * radius:.12f} ;\n" if register == 1 else None  # rs274's table is in inches (as the program)
            assert table is not None and TABLE_UNIT_MM == INCH
            program = masked(program)
        status, message, inch_canon = rs274_canon(program, tmp_path, table)
        assert status == 0, (label, message)
        status, message, mm_canon = rs274_canon(to_mm(program), tmp_path, table)
        assert status == 0, (label, message)
        assert len(inch_canon) == len(mm_canon), label
        assert np.max(np.abs(_numbers(inch_canon) * INCH - _numbers(mm_canon))) <= PRINT_GAP, label  # rs274 reads inches
        report = simulate(to_mm(program), cam.contour, spec.tool_radius, tmp_path, profile=profile, tool_table=table)
        assert report.status == 0, (label, report.message)
        assert report.gouge <= CUT_TOL and report.proud <= CUT_TOL, (label, report.gouge, report.proud)
        assert all(p.outside for p in report.passes) and report.rapid_clearance >= 0.0, label
        assert abs(report.deepest + spec.thickness + spec.breakthrough) < 1e-6, (label, report.deepest)


def test_the_header_says_inch_and_the_tolerance_in_both_units(plate):
    cam, base = plate
    program = gcode_program(cam.contour, dataclasses.replace(base, units="inch", decimals=0), cam.name)
    head = [line for line in program.splitlines() if line.startswith("(")][:8]
    assert any("units inch" in line for line in head)
    tol = re.search(r"path tolerance ([\d.e-]+) in = ([\d.e-]+) mm", "\n".join(head))
    assert tol and float(tol.group(2)) == pytest.approx(base.chord_tol) and float(tol.group(1)) == pytest.approx(base.chord_tol / INCH, rel=1e-5)
    assert all(len(line) <= 255 for line in program.splitlines())  # LinuxCNC reads lines of up to 256 characters
    blend = float(re.search(r"^G64 P([\d.]+)$", program, re.M).group(1))
    mm_blend = float(re.search(r"^G64 P([\d.]+)$", gcode_program(cam.contour, base, cam.name), re.M).group(1))
    assert blend * INCH <= 0.1 * base.chord_tol and blend * INCH == pytest.approx(mm_blend, rel=0.5)  # the blend share, in inches


def test_feeds_are_in_inches_per_minute(plate):
    cam, base = plate
    spec = dataclasses.replace(base, units="inch", decimals=0, feed=437.0, plunge_feed=123.0)
    program = gcode_program(cam.contour, spec, cam.name)
    feeds = {float(f) for f in re.findall(r"\bF([\d.]+)", program)}
    assert len(feeds) == 2
    assert min(feeds) == pytest.approx(123.0 / INCH, abs=0.005) and max(feeds) == pytest.approx(437.0 / INCH, abs=0.005)
    mm = gcode_program(cam.contour, dataclasses.replace(base, feed=437.0, plunge_feed=123.0), cam.name)
    assert {float(f) for f in re.findall(r"\bF([\d.]+)", mm)} == {437.0, 123.0}


def least_inch_decimals(chord_tol: float) -> int | None:
    """The least d in 3..6 whose printed rounding of an arc (its centre and two ends each off by
    up to half a unit in x and in y, a point of the arc by the sum of the three) in inches stays
    within a quarter of ``chord_tol`` (mm)."""
    for d in range(3, 7):
        half_unit = 0.5 * 10.0 ** -d * INCH  # mm
        if 3.0 * math.hypot(half_unit, half_unit) <= 0.25 * chord_tol:
            return d
    return None


@pytest.mark.parametrize("chord_tol", [1e-3, 2e-3, 1e-2, 0.3])
def test_decimals_rule_at_its_bound(chord_tol):
    least = least_inch_decimals(chord_tol)
    assert least is not None
    spec = MachiningSpec(chord_tol=chord_tol, units="inch")
    assert spec.decimals == least  # the default: the least that keeps the budget
    assert MachiningSpec(chord_tol=chord_tol).decimals == 4  # mm: 4 as before
    for d in range(least, 7):
        assert MachiningSpec(chord_tol=chord_tol, units="inch", decimals=d).decimals == d
    if least > 3:
        with pytest.raises(ParameterError) as info:
            MachiningSpec(chord_tol=chord_tol, units="inch", decimals=least - 1)
        assert info.value.name == "decimals" and f"{least}..6" in info.value.valid


def test_too_fine_a_tolerance_for_inches_is_refused():
    """6 decimals of an inch round an arc by up to 5.4e-5 mm: chord_tol below 4 x that is refused."""
    bound = 3.0 * math.hypot(0.5e-6, 0.5e-6) * INCH / 0.25
    MachiningSpec(chord_tol=bound * 1.001, units="inch")
    with pytest.raises(ParameterError) as info:
        MachiningSpec(chord_tol=bound * 0.999, units="inch")
    assert info.value.name == "chord_tol" and "inches" in info.value.valid


def test_scene_units_and_decimals_named(tmp_path):
    from camgen.scene import parse_scene

    cam = {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0}
    ok = parse_scene({"output": {"formats": ["ngc"]}, "machining": {"units": "inch"}, "cams": {"c": cam}}, "s", base_dir=tmp_path)
    assert ok.machining.units == "inch" and ok.machining.decimals == 6
    with pytest.raises(ParameterError) as info:
        parse_scene({"output": {"formats": ["ngc"]}, "machining": {"units": "inch", "decimals": 5}, "cams": {"c": cam}}, "s",
                    base_dir=tmp_path)
    assert info.value.name == "machining.decimals" and "6..6" in info.value.valid
    with pytest.raises(ParameterError) as info:
        parse_scene({"output": {"formats": ["ngc"]}, "machining": {"units": "feet"}, "cams": {"c": cam}}, "s", base_dir=tmp_path)
    assert info.value.name == "machining.units"


def _moves(program: str) -> np.ndarray:
    """(X, Y) of every motion block of ``program`` with both, in order."""
    rows = []
    for line in program.splitlines():
        if line.startswith("("):
            continue
        x, y = re.search(r"\bX(-?[\d.]+)", line), re.search(r"\bY(-?[\d.]+)", line)
        if x and y:
            rows.append((float(x.group(1)), float(y.group(1))))
    return np.array(rows)


@pytest.mark.usefixtures("needs_rs274")
def test_wire_edm_inch_program_matches_the_mm_program(plate, tmp_path):
    """The same moves, converted back: within half a unit of each program's last decimal; the
    inch program accepted by rs274 with its registers D<k> (tool table in inches) holding the
    offsets the header states."""
    from camgen.export.wire_edm import wire_edm_program

    cam, base = plate
    spec = MachiningSpec(dialect="wire_edm", chord_tol=base.chord_tol, thickness=base.thickness)
    mm = wire_edm_program(cam.contour, spec, cam.name)
    inch = wire_edm_program(cam.contour, dataclasses.replace(spec, units="inch", decimals=0), cam.name)
    assert "G20 G90" in inch and "G21" not in inch and "G21 G90" in mm
    a, b = _moves(mm), _moves(inch) * INCH
    assert a.shape == b.shape and len(a) > 10
    assert np.max(np.hypot(*(a - b).T)) <= math.hypot(0.5e-4 + 0.5e-6 * INCH, 0.5e-4 + 0.5e-6 * INCH)
    regs = {int(k): float(v) for k, v in re.findall(r"^\(register D(\d) = ([\d.]+)", inch, re.M)}
    wire = spec.wire_edm
    assert wire is not None and regs and all(regs[k + 1] * INCH == pytest.approx(o, abs=0.5e-6 * INCH) for k, o in enumerate(wire.offsets))
    table = "".join(f"T{k} P{k} D{2.0 * regs[k]:.12f} ;\n" for k in sorted(regs))  # rs274 reads D as a diameter
    status, message, canon = rs274_canon(inch, tmp_path, table)
    assert status == 0 and canon, message
    feed = float(re.search(r"G41 D1 G1 .* F([\d.e-]+)", inch).group(1))
    assert feed == pytest.approx(wire.wire_feed / INCH, rel=1e-4)


_ROW = re.compile(r"^G1 X(-?[\d.]+)(?: Y(-?[\d.]+))? Z(-?[\d.]+) A(-?[\d.]+) F([\d.]+)$", re.M)


@pytest.mark.usefixtures("needs_rs274")
def test_barrel_groove_inch_program_matches_the_mm_program(tmp_path):
    """The barrel_cam template's groove on the A axis: the inch program is accepted by rs274
    (read in inches), and its moves converted back are the mm program's within the two
    programs' rounding: X, Z within half a unit of each last decimal, A within half a unit of
    each A decimal (A in degrees, not converted), the inverse-time F (1/min) the same within
    the rounding of the move lengths; the plunge feed in in/min."""
    from camgen.export.gcode_barrel import barrel_program
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    scene = load_template("barrel_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    groove = cam.built.groove
    spec = dataclasses.replace(scene.machining, chord_tol=scene.output.chord_tol)
    mm = barrel_program(groove, spec, cam.name)
    inch = barrel_program(groove, dataclasses.replace(spec, units="inch", decimals=0), cam.name)
    assert "G20 G90" in inch and "G21" not in inch and "G21 G90" in mm and "units inch" in inch
    status, message, canon = rs274_canon(inch, tmp_path)
    assert status == 0, message
    a = np.array([[float(v or 0.0) for v in row] for row in _ROW.findall(mm)])
    b = np.array([[float(v or 0.0) for v in row] for row in _ROW.findall(inch)])
    assert a.shape == b.shape and len(a) > 1000
    d_mm = len(re.search(r"^G1 X-?\d+\.(\d+)", mm, re.M).group(1))
    da_mm = len(re.search(r" A-?\d+\.(\d+)", mm).group(1))
    da_in = len(re.search(r" A-?\d+\.(\d+)", inch).group(1))
    xyz = 0.5 * 10.0 ** -d_mm + 0.5e-6 * INCH + 1e-12
    assert np.max(np.abs(b[:, [0, 1, 2]] * INCH - a[:, [0, 1, 2]])) <= xyz
    assert np.max(np.abs(b[:, 3] - a[:, 3])) <= 0.5 * 10.0 ** -da_mm + 0.5 * 10.0 ** -da_in + 1e-12
    assert np.allclose(b[:, 4], a[:, 4], rtol=2e-3)  # feed / length: the same ratio in either unit
    plunge = float(re.search(r"^G1 Z[\d.]+ F([\d.]+)$", inch, re.M).group(1))
    assert plunge == pytest.approx(spec.plunge_feed / INCH, abs=0.005)
    assert max(m["end"][2] for m in canon if m["kind"] != "traverse") * INCH == pytest.approx(groove.rim_radius, abs=0.5e-4 * INCH)  # rs274 prints 4 decimals of an inch


@pytest.mark.usefixtures("needs_rs274")
def test_groove_cam_inch_program_cuts_groove_and_outline(tmp_path):
    """The groove_cam template's pockets (ramped passes with Z on lines and helical arcs) and
    outline in inches: accepted by rs274, and converted back cut within 1 um."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template
    from cutting import simulate_pockets

    scene = load_template("groove_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    assert cam.pockets
    spec = dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol, units="inch", decimals=0)
    program = gcode_program(cam.contour, spec, cam.name, "groove_cam", cam.body.thickness, cam.pockets)
    status, message, inch_canon = rs274_canon(program, tmp_path)
    assert status == 0, message
    walls = {wall.layer: wall.contour for wall in cam.pockets[0].walls}
    report = simulate_pockets(to_mm(program), cam.contour, walls, spec.tool_radius, tmp_path)
    assert np.max(np.abs(_numbers(inch_canon) * INCH - _numbers(report.outline.canon))) <= PRINT_GAP
    pocket, outline = report.pocket, report.outline
    assert outline.status == 0 and pocket is not None
    for layer in walls:
        assert pocket.gouge[layer] <= CUT_TOL and pocket.proud[layer] <= CUT_TOL, (layer, pocket.gouge, pocket.proud)
    assert pocket.deepest == pytest.approx(-cam.pockets[0].depth, abs=1e-6)
    assert outline.gouge <= CUT_TOL and outline.proud <= CUT_TOL and outline.rapid_clearance >= 0.0


def test_the_readme_quotes_the_inch_tolerance_bound(tree):
    """The README's Limits: with inches, chord_tol_mm >= 4 x the rounding of 6 decimals of an inch."""
    bound = 3.0 * math.hypot(0.5e-6, 0.5e-6) * INCH / 0.25
    text = " ".join((tree / "README.md").read_text(encoding="utf-8").split())
    assert f"`chord_tol_mm >= {bound:.1e} mm`".replace("e-04", "e-4") in text


def _rib_and_spec(motion: str):
    """A translating rib (tests/test_gcode_barrel_rib.py) or an oscillating one
    (tests/test_barrel_rib_oscillating_files.py), each with its spec in mm."""
    if motion == "translating":
        from test_gcode_barrel_rib import rib, spec

        return rib(1), spec()
    from test_barrel_rib_oscillating_files import camgen_rib
    from test_barrel_rib_oscillating_files import spec as arm_spec

    return camgen_rib(), arm_spec()


_OTHER = re.compile(r"\b([XYZAF])(-?\d+(?:\.\d+)?)")


@pytest.mark.usefixtures("needs_rs274")
@pytest.mark.parametrize("motion", ["translating", "oscillating"])
def test_barrel_rib_inch_program_matches_the_mm_program(motion, tmp_path):
    """A rib's program on the A axis in inches: accepted by rs274 (read in inches), and every
    number of it converted back is the mm program's within the two programs' rounding: the
    cutting moves' X, Y, Z within half a unit of each last decimal, A within half a unit of each
    A decimal (degrees, not converted), the inverse-time F (1/min) the same within the rounding
    of the move lengths; the moves between the passes (up to the safe height, over to the next
    pass's X and Y, down to the rim) likewise, their plunge feed in in/min.  The rib's nested mm
    values (its rollers' axes, their offset, the pitch line's extremes, the cylinder) would show
    here as a number 25.4 times off."""
    from camgen.export.gcode_barrel_rib import rib_program

    rib, spec = _rib_and_spec(motion)
    mm = rib_program(rib, spec, "rib")
    inch = rib_program(rib, dataclasses.replace(spec, units="inch", decimals=0), "rib")
    assert "G20 G90" in inch and "G21" not in inch and "G21 G90" in mm and "units inch" in inch
    status, message, canon = rs274_canon(inch, tmp_path)
    assert status == 0, message
    a = np.array([[float(v or 0.0) for v in row] for row in _ROW.findall(mm)])
    b = np.array([[float(v or 0.0) for v in row] for row in _ROW.findall(inch)])
    assert a.shape == b.shape and len(a) > 1000
    if motion == "oscillating":
        assert np.max(np.abs(a[:, 1])) > 1.0  # Y is there: the rollers ride off the radial line
    d_mm = len(re.search(r"^G1 X-?\d+\.(\d+)", mm, re.M).group(1))
    da_mm = len(re.search(r" A-?\d+\.(\d+)", mm).group(1))
    da_in = len(re.search(r" A-?\d+\.(\d+)", inch).group(1))
    xyz = 0.5 * 10.0 ** -d_mm + 0.5e-6 * INCH + 1e-12
    angle = 0.5 * 10.0 ** -da_mm + 0.5 * 10.0 ** -da_in + 1e-12
    assert np.max(np.abs(b[:, [0, 1, 2]] * INCH - a[:, [0, 1, 2]])) <= xyz
    assert np.max(np.abs(b[:, 3] - a[:, 3])) <= angle
    assert np.allclose(b[:, 4], a[:, 4], rtol=2e-3)  # feed / length: the same ratio in either unit
    # every other move (start, between the passes, end), word by word
    others = [[line for line in text.splitlines() if line[:1] in "GM" and not _ROW.match(line) and not line.startswith("G64")]
              for text in (mm, inch)]
    assert len(others[0]) == len(others[1]) > 10
    plunges = 0
    for line_mm, line_in in zip(*others):
        words_mm, words_in = _OTHER.findall(line_mm), _OTHER.findall(line_in)
        assert [w[0] for w in words_mm] == [w[0] for w in words_in], (line_mm, line_in)
        for (letter, v_mm), (_, v_in) in zip(words_mm, words_in):
            if letter == "A":
                assert abs(float(v_in) - float(v_mm)) <= angle, (line_mm, line_in)
            elif letter == "F":  # G94 feeds: mm/min and in/min
                plunges += 1
                assert float(v_mm) == spec.plunge_feed and float(v_in) == pytest.approx(spec.plunge_feed / INCH, abs=0.005)
            else:
                assert abs(float(v_in) * INCH - float(v_mm)) <= xyz, (line_mm, line_in)
    assert plunges > 2  # the start's and one a pass after the first
    assert max(m["end"][2] for m in canon if m["kind"] != "traverse") * INCH == pytest.approx(rib.rim_radius, abs=0.5e-4 * INCH)


def test_a_rib_scene_in_inches_writes_its_program_in_inches():
    """`units = "inch"` on a rib scene (no longer refused): its ngc is the inch program (G20, the
    rim radius and the stock length in the header in inches)."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene
    from test_barrel_rib_files import CLEARANCE, LENGTH, RIM, RR, rib_table

    scene = parse_scene({"output": {"formats": ["ngc"]}, "machining": {"units": "inch", "tool_diameter_mm": 2 * RR + CLEARANCE},
                         "cams": {"b": rib_table()}}, "t")
    files = execute(scene, plan_run(scene)).files
    (text,) = [v for k, v in files.items() if str(k).endswith(".ngc")]
    text = text if isinstance(text, str) else text.decode()
    assert "\nG20 G90" in text and "with a rib" in text and text.endswith("M2\n")
    assert f"rim radius {RIM / INCH:g}, length {LENGTH / INCH:g};" in " ".join(text.split())


def test_a_refusal_of_an_inch_program_quotes_the_scene_mm():
    """A tool wider than the groove: refused naming tool_diameter with its value and bound in mm
    (the groove's width, not the width / 25.4 of the inch program)."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    scene = load_template("groove_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    pocket = cam.pockets[0]
    wide = pocket.width + 1.0
    spec = dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol, units="inch", decimals=0,
                               tool_diameter=wide)
    with pytest.raises(ParameterError) as info:
        gcode_program(cam.contour, spec, cam.name, "groove_cam", cam.body.thickness, cam.pockets)
    assert info.value.name == "tool_diameter" and info.value.value == wide
    bound = float(re.search(r"<= ([\d.]+) mm", info.value.valid).group(1))
    assert bound == pytest.approx(pocket.width, rel=1e-5) and "inches" not in info.value.why
