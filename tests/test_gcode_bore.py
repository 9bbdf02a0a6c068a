"""The shaft bore and keyway in the milling programs (``bore_operation``, ``bore_tool_diameter_mm``),
run through LinuxCNC's rs274 and cut in a simulation.

Every number the programs are judged by comes from outside camgen.export.gcode_bore: the cam's
body (bore diameter, keyway width, depth and angle), the rule the header and README state (the
bore round to its diameter; the keyway its rectangle except its two inner corners, left at the
tool radius), the scene's step_down and depth, and rs274's canonical moves:

* the expected hole (:class:`HoleWall`) is built here from that rule with numpy: the bore
  circle, the keyway's sides and bottom, quarter circles of the tool radius at its bottom
  corners; the tool disc swept along rs274's tool-centre moves (tests/cutting.py
  ``simulate_pockets``) gouges no point of it and leaves none proud by more than 1 um;
* every bore arc of rs274's output is centred on the axis, its radius at most ``R - r`` (the
  tool disc never reaches beyond the bore wall, at entry too) to rs274's printed precision
  (4 decimals: :data:`PRINTED`), its helix pitch at most step_down;
* the outline's passes (with the outline's tool) leave the profile within 1 um as before.
"""
from __future__ import annotations

import dataclasses
import math
import re
import subprocess
import sys

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.export.gcode import MachiningSpec, gcode_program
from cutting import CUT_TOL, simulate_pockets
from helpers import arc_sweep, require_tool, rs274_canon
from test_wire_edm import run_rs274

#: rs274 prints 4 decimals: a printed point is within sqrt(2)/2 * 1e-4 mm of the interpreter's.
PRINTED = math.sqrt(2.0) / 2.0 * 1e-4
#: The lines of a Fanuc program masked for rs274 (as tests/test_gcode_fanuc.py): % and the O line.
FANUC_MASKED = (re.compile(r"%"), re.compile(r"O\d{4} \(.*\)"))
#: rs274's tool table is in inches.
INCH = 25.4


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


@pytest.fixture(scope="module")
def plate():
    """The plate_cam template's cam (bore 12 mm, keyway 4 x 1.8 mm at 90 deg) and its machining spec
    as the ngc writer uses it."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    scene = load_template("plate_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    spec = dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol)
    return cam, spec


class HoleWall:
    """The expected bore and keyway after milling with a tool of radius ``r`` (the stated rule),
    as a counter-clockwise polygon within ``flatten``'s tolerance of the exact curve (vertices on it,
    the circle's chords of sagitta <= tol, straight sides sampled at the circle's spacing).
    ``keyway``: the keyway is cut (else the bore circle alone)."""

    def __init__(self, body, r: float, keyway: bool) -> None:
        self.body, self.r, self.keyway = body, r, keyway

    def flatten(self, tol: float) -> np.ndarray:
        body, r = self.body, self.r
        big = body.bore_diameter / 2.0
        step = 2.0 * math.acos(1.0 - tol / big)  # chord angle of sagitta tol on the bore circle
        spacing = big * step

        def arc(centre, radius, a0, a1):  # without its end point
            n = max(1, math.ceil(abs(a1 - a0) / (2.0 * math.acos(1.0 - min(tol / radius, 1.0)))))
            a = a0 + (a1 - a0) * np.arange(n) / n
            return np.asarray(centre) + radius * np.stack([np.cos(a), np.sin(a)], axis=1)

        def line(p, q):
            n = max(1, math.ceil(math.hypot(q[0] - p[0], q[1] - p[1]) / spacing))
            w = np.arange(n)[:, None] / n
            return np.asarray(p) + w * (np.asarray(q) - np.asarray(p))

        if not self.keyway:
            return arc((0.0, 0.0), big, 0.0, 2.0 * math.pi)
        half, reach = body.keyway_width / 2.0, body.bore_diameter / 2.0 + body.keyway_depth
        beta = math.asin(half / big)
        chord = math.sqrt(big * big - half * half)
        # in the keyway's frame (along, across), then turned by the keyway angle
        pieces = [arc((0.0, 0.0), big, beta, 2.0 * math.pi - beta),
                  line((chord, -half), (reach - r, -half)),
                  arc((reach - r, -(half - r)), r, -math.pi / 2.0, 0.0),
                  line((reach, -(half - r)), (reach, half - r)),
                  arc((reach - r, half - r), r, 0.0, math.pi / 2.0),
                  line((reach - r, half), (chord, half))]
        local = np.vstack([p for p in pieces if len(p)])
        c, s = math.cos(body.keyway_angle), math.sin(body.keyway_angle)
        return local @ np.array([[c, s], [-s, c]])


def masked(program: str, dialect: str) -> str:
    if dialect != "fanuc":
        return program
    return "".join(line + "\n" for line in program.splitlines() if not any(p.fullmatch(line) for p in FANUC_MASKED))


def tool_table(program: str, dialect: str, spec: MachiningSpec) -> str | None:
    """A LinuxCNC tool table of every tool the program calls (length offsets 0); the Fanuc radius
    register (tool 1 by default) holds what the header states: the tool radius with compensation, else 0."""
    numbers = {int(n) for n in re.findall(r"^T(\d+) M0?6\b", program, re.M)}
    if not numbers:
        return None
    rows = {n: 10.0 for n in numbers}
    if dialect == "fanuc":
        m = re.search(r"^\(RADIUS REGISTER D(\d+) = ([\d.]+) MM ", program, re.M)
        rows[int(m.group(1))] = 2.0 * float(m.group(2))
    return "".join(f"T{n} P{n} Z0 D{diameter / INCH:.12f} ;\n" for n, diameter in rows.items())


def bore_moves(canon: list[dict], outline) -> list[dict]:
    """rs274's feed moves inside the outline below Z 0 (the bore and keyway)."""
    from cutting import ExactProfile

    part = ExactProfile(outline, tol=1e-3)
    return [m for m in canon if m["kind"] != "traverse" and min(m["start"][2], m["end"][2]) < 0.0
            and part.contains(np.asarray(m["end"][:2]))]


CASES = [  # dialect, direction, bore tool diameter (None: the outline's 6 mm tool), cutter compensation of the outline
    ("linuxcnc", "climb", 3.0, False),  # keyway 4 wide: two lanes and the bottom, the corners at 1.5
    ("linuxcnc", "conventional", 4.0, True),  # a tool of the keyway's width: one lane, the bottom a half circle
    ("grbl", "climb", 2.5, False),
    ("grbl", "conventional", None, False),  # the outline's tool: wider than the keyway, which is left
    ("fanuc", "climb", 4.0, False),
    ("fanuc", "conventional", 3.0, True),
]


@pytest.mark.parametrize("dialect, direction, tool, comp", CASES)
@pytest.mark.usefixtures("needs_rs274")
def test_bore_round_keyway_rectangle_and_outline_exact(plate, dialect, direction, tool, comp, tmp_path):
    cam, base = plate
    body = cam.body
    spec = dataclasses.replace(base, dialect=dialect, direction=direction, bore_operation="helix", bore_tool_diameter=tool,
                               cutter_compensation=comp)
    program = gcode_program(cam.contour, spec, cam.name, "bore", body.thickness, cam_body=body)
    text = masked(program, dialect)
    table = tool_table(program, dialect, spec)
    diameter = spec.tool_diameter if tool is None else tool
    r, big = diameter / 2.0, body.bore_diameter / 2.0
    keyway = diameter <= body.keyway_width
    assert ("keyway" in program.lower() and ("not cut" in program.lower()) != keyway), "the header says whether the keyway is cut"
    wall = HoleWall(body, r, keyway)
    cut = simulate_pockets(text, cam.contour, {"bore": wall}, r, tmp_path, tool_table=table)
    assert cut.outline.status == 0, cut.outline.message
    pocket = cut.pocket
    assert pocket is not None and pocket.between, "the bore's moves stay inside the expected hole"
    assert pocket.gouge["bore"] <= CUT_TOL, ("gouge", pocket.gouge)
    assert pocket.proud["bore"] <= CUT_TOL, ("proud", pocket.proud)
    depth = body.thickness + spec.breakthrough
    assert abs(pocket.deepest + depth) < 1e-9
    assert cut.order.index("outline") > max(i for i, o in enumerate(cut.order) if o == "pocket"), "the bore before the outline"
    # the bore's arcs: centred on the axis, radius <= R - r (no gouge, entry included), pitch <= step_down, the turn's sense
    arcs = [m for m in bore_moves(cut.outline.canon, cam.contour) if m["kind"] == "arc"]
    assert arcs
    centres = np.array([m["centre"] for m in arcs])
    radii = np.array([[np.hypot(*m["start"][:2]), np.hypot(*m["end"][:2])] for m in arcs])
    assert np.max(np.hypot(*centres.T)) <= 1e-9 and np.max(radii) <= big - r + PRINTED, (np.max(radii), big - r)
    sweeps = np.array([arc_sweep(m["start"], m["end"], m["centre"], m["turn"]) for m in arcs])
    drops = np.array([m["start"][2] - m["end"][2] for m in arcs])
    assert np.all(drops >= 0.0) and np.max(drops * 2.0 * math.pi / np.abs(sweeps)) <= spec.step_down + 2e-4
    assert np.all(sweeps > 0) if direction == "climb" else np.all(sweeps < 0), "climb: counter-clockwise inside the hole"
    bottom = np.abs(np.array([m["end"][2] for m in arcs]) + depth) < 1e-9
    finish = np.abs(radii[:, 1] - (big - r)) <= PRINTED
    assert np.sum(np.abs(sweeps[bottom & finish])) >= 2.0 * math.pi - 1e-9, "a full circle at the bottom on the finishing radius"
    # the outline, with its own tool (the Fanuc register holds 0 or the tool radius, as the header says)
    outline = simulate_pockets(text, cam.contour, {"bore": wall}, spec.tool_radius, tmp_path, tool_table=table).outline
    assert outline.passes and outline.gouge <= CUT_TOL and outline.proud <= CUT_TOL, (outline.gouge, outline.proud)
    assert all(p.outside for p in outline.passes)


@pytest.mark.parametrize("dialect, direction", [("linuxcnc", "climb"), ("fanuc", "conventional")])
@pytest.mark.usefixtures("needs_rs274")
def test_drilled_bore_round_pecks_and_outline_exact(plate, dialect, direction, tmp_path):
    """bore_operation = "drill": rs274 runs the G83 cycle at the axis; a drill of the bore's
    diameter there cuts the bore round (the simulation's disc of radius R at the axis); its point
    (118 deg, the standard twist drill) through: the deepest Z = the last pass's depth + R / tan 59
    deg; every peck at most step_down deeper than the one before; the keyway left (said)."""
    cam, base = plate
    body = cam.body
    spec = dataclasses.replace(base, dialect=dialect, direction=direction, bore_operation="drill")
    program = gcode_program(cam.contour, spec, cam.name, "bore", body.thickness, cam_body=body)
    assert re.search(r"KEYWAY\W+4 WIDE\W+IS NOT CUT\W+LEFT TO ANOTHER OPERATION", program.upper())  # Fanuc: no brackets or colons
    text, table = masked(program, dialect), tool_table(program, dialect, spec)
    big = body.bore_diameter / 2.0
    cut = simulate_pockets(text, cam.contour, {"bore": HoleWall(body, big, False)}, big, tmp_path, tool_table=table)
    assert cut.outline.status == 0, cut.outline.message
    drill = [m for m in cut.outline.canon if m["kind"] != "traverse" and min(m["start"][2], m["end"][2]) < 0.0
             and np.hypot(*m["end"][:2]) < 1.0]
    assert drill and all(np.hypot(*m["start"][:2]) == 0.0 and np.hypot(*m["end"][:2]) == 0.0 for m in drill)
    depth = body.thickness + spec.breakthrough + big / math.tan(math.radians(59.0))
    ends = np.array([m["end"][2] for m in drill])
    assert abs(ends.min() + depth) <= 1e-4, (ends.min(), depth)
    pecks = np.concatenate([[min(0.0, drill[0]["start"][2])], ends])
    assert np.all(np.diff(pecks) < 0.0) and np.max(-np.diff(pecks)) <= spec.step_down + 1e-4, pecks
    assert cut.pocket.gouge["bore"] <= CUT_TOL and cut.pocket.proud["bore"] <= CUT_TOL
    outline = simulate_pockets(text, cam.contour, {"bore": HoleWall(body, big, False)}, spec.tool_radius, tmp_path, tool_table=table).outline
    assert outline.passes and outline.gouge <= CUT_TOL and outline.proud <= CUT_TOL, (outline.gouge, outline.proud)


@pytest.mark.parametrize("dialect, words", [
    ("linuxcnc", ["T2 M6", "G43 H2", "T1 M6", "G43 H1"]),
    ("fanuc", ["T2 M06", "G0 G43 H02 Z", "T1 M06", "G0 G43 H01 Z"]),
    ("grbl", ["M0 (load the bore tool, diameter 3", "M0 (load the outline's tool, diameter 6"]),
])
def test_tool_changes_in_order(plate, dialect, words):
    """The bore tool is called (or, GRBL, asked for with M0) before the bore's first move, the
    outline's tool after its last one; one call each."""
    cam, base = plate
    spec = dataclasses.replace(base, dialect=dialect, bore_tool_diameter=3.0)
    program = gcode_program(cam.contour, spec, cam.name, "bore", cam.body.thickness, cam_body=cam.body)
    lines = program.splitlines()
    at = [next(i for i, line in enumerate(lines) if line.startswith(w)) for w in words]
    assert at == sorted(at), at
    first_helix = next(i for i, line in enumerate(lines) if re.match(r"G3 .*Z", line))
    first_outline = next(i for i, line in enumerate(lines) if "PASS 1 OF" in line.upper())
    half = len(words) // 2
    assert at[half - 1] < first_helix < at[half] < first_outline
    assert sum(1 for line in lines if re.match(r"T\d+ M0?6$", line)) == (2 if dialect != "grbl" else 0)


@pytest.mark.usefixtures("needs_rs274")
def test_the_simulation_sees_a_bore_too_small(plate, tmp_path):
    """The check itself: the bore cut with a tool 10 um smaller than the program's leaves the wall
    10 um proud, more than the tests accept."""
    cam, base = plate
    spec = dataclasses.replace(base, bore_tool_diameter=3.0)
    program = gcode_program(cam.contour, spec, cam.name, "bore", cam.body.thickness, cam_body=cam.body)
    table = tool_table(program, "linuxcnc", spec)
    cut = simulate_pockets(program, cam.contour, {"bore": HoleWall(cam.body, 1.5, True)}, 1.5 - 0.01, tmp_path, tool_table=table)
    assert cut.pocket.proud["bore"] > CUT_TOL and abs(cut.pocket.proud["bore"] - 0.01) <= CUT_TOL


def test_none_by_default_says_so_and_cuts_nothing_inside(plate):
    """Without the bore keys the program cuts no bore and its header says the bore and keyway are
    left to another operation; the same moves as a cam without a bore."""
    cam, spec = plate
    program = gcode_program(cam.contour, spec, cam.name, "bore", cam.body.thickness, cam_body=cam.body)
    assert "(the bore and keyway [diameter 12] are not cut: left to another operation" in program
    plain = gcode_program(cam.contour, spec, cam.name, "bore", cam.body.thickness)
    assert [line for line in program.splitlines() if not line.startswith("(")] == [line for line in plain.splitlines()
                                                                                    if not line.startswith("(")]


def test_settings_are_refused_naming_the_key(plate):
    cam, spec = plate
    body = cam.body
    for tool in (12.0, 11.9, 0.3):  # the bore's diameter, a helix circle under 0.1 mm, a tool under 0.4 mm
        with pytest.raises(ParameterError) as err:
            gcode_program(cam.contour, dataclasses.replace(spec, bore_tool_diameter=tool), cam.name, "b", body.thickness, cam_body=body)
        assert err.value.name == "bore_tool_diameter" and "11.8" in err.value.valid, err.value
    with pytest.raises(ParameterError) as err:  # the outline's tool cuts the bore: its key is named
        big = dataclasses.replace(body, bore_diameter=6.1, keyway_width=0.0, keyway_depth=0.0)
        gcode_program(cam.contour, dataclasses.replace(spec, bore_operation="helix"), cam.name, "b", body.thickness, cam_body=big)
    assert err.value.name == "tool_diameter"
    for changes, name in (({"bore_tool_number": 3}, "bore_tool_number"),  # no bore tool: nothing to change to
                          ({"bore_tool_diameter": 3.0, "bore_tool_number": 1}, "bore_tool_number"),  # the outline's own number
                          ({"dialect": "grbl", "bore_tool_diameter": 3.0, "bore_tool_number": 3}, "bore_tool_number"),
                          ({"bore_operation": "none", "bore_tool_diameter": 3.0}, "bore_tool_diameter"),
                          ({"dialect": "grbl", "bore_operation": "drill"}, "bore_operation"),  # no canned cycle
                          ({"bore_operation": "drill", "bore_tool_diameter": 12.0}, "bore_tool_diameter"),
                          ({"bore_operation": "spiral"}, "bore_operation")):
        with pytest.raises(ParameterError) as err:
            dataclasses.replace(spec, **changes)
        assert err.value.name == name, (changes, err.value)


def _cli(machining: str, tmp_path, template: str = "plate_cam") -> subprocess.CompletedProcess:
    from importlib.resources import files

    body = files("camgen.templates").joinpath(f"{template}.toml").read_text()
    if template == "barrel_cam":  # the groove's tool kept
        machining += "\ntool_diameter_mm = " + re.search(r"tool_diameter_mm = ([0-9.]+)", body).group(1)
    body = re.sub(r"\[machining\][^\[]*", "", body)
    body = re.sub(r"formats = \[[^\]]*\]", 'formats = ["ngc"]', body, count=1)
    path = tmp_path / "bore.toml"
    path.write_text(f"[machining]\n{machining}\n" + body)
    return subprocess.run([sys.executable, "-P", "-m", "camgen", "run", str(path), "-o", str(tmp_path / "out")], capture_output=True,
                          text=True, timeout=300)


@pytest.mark.parametrize("machining, key, template", [
    ("bore_tool_diameter_mm = 12.0", "machining.bore_tool_diameter_mm", "plate_cam"),
    ("bore_tool_diameter_mm = 3.0", "machining.bore_tool_diameter_mm", "barrel_cam"),  # its program cuts the groove only
    ('dialect = "wire_edm"\nbore_operation = "helix"', "machining.bore_operation", "plate_cam"),
    ('dialect = "grbl"\nbore_tool_diameter_mm = 3.0\nbore_tool_number = 2', "machining.bore_tool_number", "plate_cam"),
])
def test_bad_input_exits_2_naming_the_key(machining, key, template, tmp_path):
    proc = _cli(machining, tmp_path, template)
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camgen: error: ") and key in lines[0], proc.stderr


def test_the_ngc_writer_mills_the_bore(tmp_path):
    """The scene keys reach the written program (camgen.writers passes the cam's body)."""
    proc = _cli('bore_tool_diameter_mm = 3.0\nbore_tool_number = 7', tmp_path)
    assert proc.returncode == 0, proc.stderr
    program = next((tmp_path / "out").rglob("*.ngc")).read_text()
    assert "T7 M6" in program and "G43 H7" in program and "inner corners left at the tool radius 1.5" in program


# ---------------------------------------------------------------------------------------------
# wire EDM: the bore and keyway an inner contour, cut first, each cut at its register's offset
# ---------------------------------------------------------------------------------------------
#: Spacing of the samples along every wire move, mm (the proud bound is step^2 / (8 offset) too large).
WIRE_STEP = 0.005


@pytest.fixture(scope="module")
def wire_cam():
    """The wire_edm_cam template's cam (bore 12, keyway 4 x 1.8 at 90 deg) and its machining spec."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    scene = load_template("wire_edm_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    return cam, dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol)


def _wire_cut(chain: list[dict], wall, offset: float) -> tuple[float, np.ndarray, bool]:
    """(gouge, distance of every wall vertex to the wire path minus ``offset``, every sample inside
    the hole) of one cut: gouge = offset - the least distance (rigorous lower bound) of the wire
    centre from the hole's wall."""
    from scipy.spatial import cKDTree

    from cutting import ExactProfile, sample_moves

    profile = ExactProfile(wall)
    pts, move, h, rho = sample_moves(chain, WIRE_STEP)
    reach = offset + 1.0
    f = profile.distance_lower_bound(pts, reach)
    same = move[:-1] == move[1:]
    slack = ((1.0 + (reach + h) / rho) * h * h / 4.0)[move[:-1]]
    pair = np.minimum(f[:-1], f[1:])
    low = np.where(pair > 0, np.sqrt(np.maximum(pair * pair - slack, 0.0)), pair)
    low = float(min(np.min(low[same], initial=np.inf), np.min(f)))
    proud = cKDTree(pts).query(profile.vertices)[0] - offset
    return offset - low, proud, bool(np.all(profile.contains_many(pts)))


@pytest.mark.parametrize("keyway, skims", [(True, 2), (False, 0), (True, 1)])
@pytest.mark.usefixtures("needs_rs274")
def test_wire_bore_is_the_hole_offset_by_each_cut(wire_cam, keyway, skims, tmp_path):
    """rs274 runs the program with registers of the stated rule (wire radius + gap + allowance):
    each bore cut stays >= its offset from the hole (the body's bore circle and keyway rectangle)
    and reaches every point of it within its offset + 1 um (the keyway's bottom corners at that
    offset) except one stretch of the bore wall of the tab's length; the cut-off after the last
    stop cuts that stretch; then the outline's cuts follow."""
    from camgen.export.wire_edm import wire_edm_program
    from camgen.export.wire_edm_spec import WireEdmSpec

    cam, base = wire_cam
    body = cam.body if keyway else dataclasses.replace(cam.body, keyway_width=0.0, keyway_depth=0.0, keyway_angle=0.5)
    wire = WireEdmSpec(wire_diameter=0.25, spark_gap=0.03, skim_cuts=skims, tab_width=2.5)
    spec = dataclasses.replace(base, wire_edm=wire)
    program = wire_edm_program(cam.contour, spec, cam.name, "edm", body.thickness, cam_body=body)
    kerf = 0.125 + 0.03
    offsets = [kerf + a for a in (0.1 * 0.2**k for k in range(skims))] + [kerf]  # the rule of the header and README
    status, message, chains = run_rs274(program, offsets, tmp_path)  # tests/test_wire_edm.py's runner
    assert status == 0, message
    n = skims + 1
    assert len(chains) == 2 * (n + 1)  # bore cuts and cut-off, then the outline's
    centre_first = [np.hypot(*c[0]["start"][:2]) for c in chains[:n]]
    assert max(centre_first) <= PRINTED, "every bore cut threads at the axis"
    for k, (chain, offset) in enumerate(zip(chains[:n], offsets), 1):
        wall = HoleWall(body, offset, keyway)
        gouge, proud, inside = _wire_cut(chain, wall, offset)
        assert inside and gouge <= CUT_TOL, (k, gouge)
        vertices = wall.flatten(1e-7)
        s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(vertices, axis=0).T))])
        left = np.flatnonzero(proud > CUT_TOL)
        assert left.size and np.all(np.diff(left) == 1), (k, "one stretch left: the tab")
        span = s[left[-1]] - s[left[0]]
        # within offset + CUT_TOL of the wire's disc lie the wall points up to sqrt(2 rho CUT_TOL R / (R - rho)) along the
        # wall (radius R) from where a circle of radius rho inside touches it: the wire at the stop (rho = offset), and the
        # lead-in arc (rho = its radius, stated in the header) touching the bore at the start point
        big = body.bore_diameter / 2.0
        lead = float(re.search(r"then an arc of radius ([0-9.]+) touching the bore", program).group(1))
        reach = sum(math.sqrt(2.0 * rho * CUT_TOL * big / (big - rho)) for rho in (offset, lead))
        assert wire.tab_width - reach - 0.01 <= span <= wire.tab_width, (k, span, reach)
        assert np.all(np.abs(np.hypot(*vertices[left].T) - body.bore_diameter / 2.0) < 1e-6), "the tab lies on the bore wall"
    wall = HoleWall(body, offsets[-1], keyway)
    gouge, proud_off, inside = _wire_cut(chains[n], wall, offsets[-1])
    _, proud_last, _ = _wire_cut(chains[n - 1], wall, offsets[-1])
    assert inside and gouge <= CUT_TOL, gouge
    assert np.max(np.minimum(proud_off, proud_last)) <= CUT_TOL, "the last cut and the cut-off leave the whole hole"
    outside = [np.hypot(*c[0]["end"][:2]) for c in chains[n + 1:]]
    assert min(outside) > body.bore_diameter, "then the outline"


def test_wire_bore_none_is_said_and_cuts_nothing(wire_cam):
    from camgen.export.wire_edm import wire_edm_program

    cam, spec = wire_cam
    program = wire_edm_program(cam.contour, dataclasses.replace(spec, bore_operation="none"), cam.name, "edm", cam.body.thickness,
                               cam_body=cam.body)
    assert "the bore and keyway are not cut: another operation" in program and "bore cut" not in program
    cut = wire_edm_program(cam.contour, spec, cam.name, "edm", cam.body.thickness, cam_body=cam.body)
    assert "not cut" not in cut and cut.count("(bore cut ") == 3 and "secure the slug" in cut


def test_wire_bore_settings_refused(wire_cam):
    from camgen.export.wire_edm import wire_edm_program
    from camgen.export.wire_edm_spec import WireEdmSpec

    cam, spec = wire_cam
    for wire, name in ((WireEdmSpec(start_hole_diameter=6.0, start_hole_offset=10.0), "start_hole_diameter"),
                       (WireEdmSpec(tab_width=20.0), "tab_width")):
        with pytest.raises(ParameterError) as err:
            wire_edm_program(cam.contour, dataclasses.replace(spec, wire_edm=wire), cam.name, "edm", cam.body.thickness, cam_body=cam.body)
        assert err.value.name == name, err.value
    with pytest.raises(ParameterError) as err:
        dataclasses.replace(spec, bore_operation="helix")
    assert err.value.name == "bore_operation"


def test_the_wire_template_program_cuts_its_bore_first(tmp_path):
    """wire_edm_cam as the ngc writer writes it: the bore's cuts come before the outline's."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template

    scene = load_template("wire_edm_cam")
    files = execute(scene, plan_run(scene)).files
    program = next(data for name, data in files.items() if name.endswith(".ngc"))
    assert program.index("(bore cut 1 of 3") < program.index("(bore cut 3 of 3") < program.index("(cut 1 of 3")
    assert "not cut" not in program and "keyway: its two inner corners left at the last cut's wire offset 0.1450" in program


def test_a_cam_without_a_bore_says_the_settings_cut_nothing(plate):
    cam, spec = plate
    body = dataclasses.replace(cam.body, bore_diameter=0.0, keyway_width=0.0, keyway_depth=0.0)
    program = gcode_program(cam.contour, dataclasses.replace(spec, bore_tool_diameter=3.0), cam.name, "b", body.thickness, cam_body=body)
    assert "(the cam has no bore: the bore settings cut nothing here)" in program and "T2" not in program
    plain = gcode_program(cam.contour, spec, cam.name, "b", body.thickness, cam_body=body)
    assert "bore" not in plain


def test_wire_bore_no_z_and_compensation_switched_on_linear_moves_only(wire_cam):
    """The bore's cuts as the outline's: no Z word, G41 D<k> on and G40 off in G1 blocks only, once
    per cut (3 bore cuts + 3 outline cuts by default)."""
    from camgen.export.wire_edm import wire_edm_program

    cam, spec = wire_cam
    program = wire_edm_program(cam.contour, spec, cam.name, "edm", cam.body.thickness, cam_body=cam.body)
    code = [re.sub(r"\(.*?\)", "", line).strip() for line in program.splitlines()]
    assert not any(re.search(r"\bZ", line) for line in code)
    switches = [line for line in code if re.search(r"\bG4[012]\b", line) and not line.startswith("G21 ")]
    assert len(switches) == 2 * 3 * 2
    assert all(re.search(r"\bG1\b", line) and not re.search(r"\bG[23]\b", line) for line in switches), switches
    assert [line.split()[1] for line in switches if line.startswith("G41")] == ["D1", "D2", "D3"] * 2  # the bore's cuts, the outline's


@pytest.mark.parametrize("dialect, direction, tool", [("linuxcnc", "climb", 3.0), ("grbl", "conventional", 2.5)])
@pytest.mark.usefixtures("needs_rs274")
def test_an_inch_program_cuts_the_same_bore_and_keyway(plate, dialect, direction, tool, tmp_path):
    """units = "inch": the bore (tool, keyway, least sizes) is written in inches too; rs274 runs the
    inch program, and converted back to mm word by word (x 25.4, in the test) it cuts the bore round
    and the keyway to its rectangle within 1 um, as the mm program does."""
    from test_gcode_inch import to_mm

    cam, base = plate
    body = cam.body
    spec = dataclasses.replace(base, dialect=dialect, direction=direction, bore_operation="helix", bore_tool_diameter=tool, units="inch",
                               decimals=6)
    program = gcode_program(cam.contour, spec, cam.name, "bore", body.thickness, cam_body=body)
    assert re.search(r"^G20\b", program, re.M) and not re.search(r"^G21\b", program, re.M)
    status, message, _ = rs274_canon(program, tmp_path, tool_table(program, dialect, spec))
    assert status == 0, message
    text = to_mm(program)
    wall = HoleWall(body, tool / 2.0, tool <= body.keyway_width)
    cut = simulate_pockets(text, cam.contour, {"bore": wall}, tool / 2.0, tmp_path, tool_table=tool_table(text, dialect, spec))
    assert cut.outline.status == 0, cut.outline.message
    assert cut.pocket is not None and cut.pocket.between
    # the inch program's printed decimals (6 of an inch: 1.8e-5 mm) stay inside the cut tolerance
    assert cut.pocket.gouge["bore"] <= CUT_TOL and cut.pocket.proud["bore"] <= CUT_TOL, (cut.pocket.gouge, cut.pocket.proud)
    assert abs(cut.pocket.deepest + (body.thickness + spec.breakthrough)) < 1e-4


def test_wire_centre_mode_leaves_the_bore_and_refuses_to_wire_it(wire_cam):
    """wire_compensation = false (the wire-centre path): the bore's cuts need the control's wire
    offset, so by default the bore is left to another operation (said), and "wire" is refused."""
    from camgen.export.wire_edm import wire_edm_program

    cam, spec = wire_cam
    assert spec.wire_edm is not None
    centre = dataclasses.replace(spec, wire_edm=dataclasses.replace(spec.wire_edm, wire_compensation=False))
    program = wire_edm_program(cam.contour, centre, cam.name, "edm", cam.body.thickness, cam_body=cam.body)
    assert "the bore and keyway are not cut: another operation" in program and "(bore cut " not in program
    assert not re.search(r"^G4[12]\b", program, re.M), "no wire offset anywhere in a wire-centre program"
    with pytest.raises(ParameterError) as err:
        dataclasses.replace(centre, bore_operation="wire")
    assert err.value.name == "bore_operation" and "wire_compensation" in str(err.value)
