"""Tangent arc lead-in and lead-out (``lead_style = "arc"``, camgen/export/gcode_leads.py), measured
in what LinuxCNC's interpreter makes of the programs.

The leads are judged in rs274's canonical moves (tests/helpers.py ``rs274_canon``: with cutter
compensation these are the compensated tool-centre moves), on the stride cam of paper 000: a
contour of exact arcs, so the distance of any point to the profile is exact (the circle
equation, tests/helpers.py ``distance_to_arcs``) and the tool path's own tangent at its start is
the perpendicular of the radius to its first arc's centre, as rs274 prints it.

rs274 prints 4 decimals: every point and centre it prints is within ``PRINT`` = sqrt(2)/2 x
1e-4 mm of its value, so the direction of a radius or chord of length ``l`` it prints is within
``2 PRINT / l`` rad of the true one; the tangency asserted on rs274's moves is to that bound.  The
same tangency to 1e-6 rad, and the clearance to 1e-6 mm, are asserted on the program text itself
at 6 decimals (tool-centre programs: the text is the tool path).
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
from cutting import ExactProfile, _passes, sample_moves, simulate
from helpers import arc_sweep, distance_to_arcs, require_tool, rs274_canon

#: Largest distance (mm) of a point rs274 prints (4 decimals) from its value.
PRINT = math.sqrt(2.0) / 2.0 * 1e-4


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


def _unit(v):
    return v / np.linalg.norm(v)


def _cross(a, b):
    return float(a[0] * b[1] - a[1] * b[0])


def _tangent(move, at):
    """Unit tangent (direction of travel) of a canonical move at its point ``at``."""
    if move["kind"] == "arc":
        radial = _unit(at - move["centre"])
        return np.sign(move["turn"]) * np.array([-radial[1], radial[0]])
    return _unit(move["end"][:2] - move["start"][:2])


def _angle(u, v):
    return abs(math.atan2(_cross(u, v), float(u @ v)))


def _split(chain):
    """A pass's canonical moves: the plunge, the straight lead-in moves, the lead-in arc, the
    contour's moves, the lead-out arc and the straight lead-out moves (a contour of arcs only)."""
    plunge, rest = chain[0], chain[1:]
    arcs = [k for k, m in enumerate(rest) if m["kind"] == "arc"]
    first, last = arcs[0], arcs[-1]
    return plunge, rest[:first], rest[first], rest[first + 1:last], rest[last], rest[last + 1:]


def _program(contour, spec, dialect):
    """The program as rs274 reads it, and the tool table it needs (Fanuc: tests/test_gcode_fanuc.py's masking and register table)."""
    program = gcode_program(contour, spec)
    if dialect != "fanuc":
        return program, None
    from test_gcode_fanuc import masked, tool_table

    return masked(program), tool_table(program)


CASES = [(dialect, comp, direction, radius) for dialect in ("linuxcnc", "fanuc") for comp in (False, True)
         for direction in ("climb", "conventional") for radius in (None,)]
CASES += [("linuxcnc", True, "climb", 0.1), ("linuxcnc", True, "conventional", 40.0), ("grbl", False, "climb", 2.5)]


@pytest.mark.parametrize(("dialect", "comp", "direction", "radius"), CASES)
@pytest.mark.usefixtures("needs_rs274")
def test_the_lead_arcs_are_tangent_arcs_in_rs274s_moves(dialect, comp, direction, radius, contours, tmp_path):
    """In rs274's tool-centre moves: after the plunge, straight feeds along one line reach an arc
    (ARC_FEED) of the lead radius whose centre lies on the outward normal of the tool path at its
    start S', the radius away: tangent to the line where it begins and to the tool path at S'; the
    lead-out arc on the same circle leaves the tool path tangentially at S' and the straight moves
    go on along its end tangent.  Every tool-centre point of the leads is >= r from the exact
    profile and from the tangent line at the start point."""
    contour = contours["stride"]
    spec = MachiningSpec(tool_diameter=8.0, thickness=1.0, step_down=2.0, direction=direction, cutter_compensation=comp, dialect=dialect,
                         lead_radius=radius, entry="plunge")  # the leads alone (the helix and ramp: tests/test_gcode_passes.py)
    rho, r = spec.lead_arc_radius, spec.tool_radius
    program, table = _program(contour, spec, dialect)
    status, message, canon = rs274_canon(program, tmp_path, table)
    assert status == 0, message
    plunge, lines_in, arc_in, path, arc_out, lines_out = _split(_passes(canon)[0])
    assert np.allclose(plunge["start"][:2], plunge["end"][:2]) and plunge["end"][2] < 0
    assert lines_in and lines_out and all(m["kind"] == "line" for m in lines_in + lines_out)
    p0, m_point, s_dash = plunge["end"][:2], arc_in["start"][:2], arc_in["end"][:2]
    # the straight lead-in: one line from the plunge point to the arc's start (rs274's compensated entry on it)
    u = _unit(m_point - p0)
    for move in lines_in:
        assert abs(_cross(u, move["end"][:2] - p0)) < 2 * PRINT
    assert np.linalg.norm(m_point - p0) == pytest.approx(spec.lead_length, abs=2 * PRINT)
    # the lead arcs: radius rho, both on one circle, quarter turns
    centre = arc_in["centre"]
    for arc in (arc_in, arc_out):
        for point in (arc["start"][:2], arc["end"][:2]):
            assert np.linalg.norm(point - arc["centre"]) == pytest.approx(rho, abs=2 * PRINT)
        assert abs(abs(arc_sweep(arc["start"], arc["end"], arc["centre"], arc["turn"])) - math.pi / 2) < 4 * PRINT / rho
    assert np.linalg.norm(arc_out["centre"] - centre) < 2 * PRINT
    # the tool path starts and ends at S'; its first and last moves are arcs of the profile's arcs + r
    assert np.linalg.norm(path[0]["start"][:2] - s_dash) < 2 * PRINT and np.linalg.norm(arc_out["start"][:2] - s_dash) < 2 * PRINT
    radii = {round(seg.radius + r, 3) for seg in contour.segments}
    assert round(float(np.linalg.norm(s_dash - path[0]["centre"])), 3) in radii
    # tangent at the joins (rs274's 4 decimals: a printed direction of length l is within 2 PRINT / l rad)
    first_radius = np.linalg.norm(s_dash - path[0]["centre"])
    bound_s = 2 * PRINT / rho + 2 * PRINT / first_radius
    assert _angle(_tangent(arc_in, s_dash), _tangent(path[0], s_dash)) < bound_s
    assert _angle(_tangent(arc_out, s_dash), _tangent(path[-1], s_dash)) < bound_s
    assert _angle(u, _tangent(arc_in, m_point)) < 2 * PRINT / rho + 2 * PRINT / spec.lead_length
    n_out = arc_out["end"][:2]
    v = _unit(lines_out[-1]["end"][:2] - n_out)
    for move in lines_out:
        assert abs(_cross(v, move["end"][:2] - n_out)) < 2 * PRINT
    assert _angle(v, _tangent(arc_out, n_out)) < 2 * PRINT / rho + 2 * PRINT / spec.lead_length
    # the centre outside the part, on the tool path's outward normal at S', rho from it
    profile = ExactProfile(contour)
    assert profile.contains(path[0]["centre"])  # the path starts on a convex arc: its outward normal points away from the centre
    normal = _unit(s_dash - path[0]["centre"])
    assert np.linalg.norm(centre - (s_dash + rho * normal)) < 4 * PRINT
    assert not profile.contains(centre)
    # no gouge: the tool centre on every lead move >= r from the exact profile (circle equation) and
    # from the tangent line at the start point S = S' - r n
    leads = lines_in + [arc_in, arc_out] + lines_out
    points = sample_moves(leads, 0.005)[0]
    assert np.min(distance_to_arcs(points, contour.segments)) >= r - 2 * PRINT
    start = s_dash - r * normal
    assert np.min((points - start) @ normal) >= r - 2 * PRINT
    assert distance_to_arcs(p0[None], contour.segments)[0] >= r + rho  # the plunge clear of the part


# ---------------------------------------------------------------------------------------------
# the program text at 6 decimals: tangency to 1e-6 rad, clearance to 1e-6 mm
# ---------------------------------------------------------------------------------------------
_BLOCK = re.compile(r"^(?:G4[0-2](?:\.1)? (?:D[\d.]+ )?)?G([0123]) X(-?[\d.]+) Y(-?[\d.]+)(?: I(-?[\d.]+) J(-?[\d.]+))?")


def _text_moves(program: str) -> list[dict]:
    """The programmed XY moves of the first pass of a program, from its words (after the plunge)."""
    body = program.split("(pass 1 of", 1)[1].split("G0 Z", 1)[0]
    moves, current = [], None
    for line in body.splitlines():
        m = _BLOCK.match(line)
        if not m:
            continue
        end = np.array([float(m.group(2)), float(m.group(3))])
        if m.group(1) == "0":
            current = end
            continue
        move = {"kind": "line" if m.group(1) == "1" else "arc", "start": np.append(current, 0.0), "end": np.append(end, 0.0)}
        if m.group(4) is not None:
            move.update(centre=current + np.array([float(m.group(4)), float(m.group(5))]), turn=1 if m.group(1) == "3" else -1)
        moves.append(move)
        current = end
    return moves


@pytest.mark.parametrize("comp", [False, True])
@pytest.mark.parametrize("direction", ["climb", "conventional"])
def test_the_lead_arcs_are_tangent_within_1e_6_rad_in_the_program(comp, direction, contours):
    """A program at 6 decimals (each printed point within 7.1e-7 mm): the straight lead-in meets its
    arc, the arc meets the contour and the lead-out arc leaves it, then meets the straight lead-out,
    with the tangent turning by < 1e-6 rad.  Tool-centre programs: every point of the leads is
    >= r - 1e-6 mm from the exact profile.  Compensated programs: the programmed leads are tangent
    to the profile itself (LinuxCNC runs such tangent joins straight on: the tool path is tangent too)."""
    contour = contours["stride"]
    spec = MachiningSpec(tool_diameter=8.0, thickness=1.0, step_down=2.0, direction=direction, decimals=6, chord_tol=1e-4,
                         cutter_compensation=comp, entry="plunge")
    moves = _text_moves(gcode_program(contour, spec))
    if comp:  # the entry move (compensation on) and the move to the tool-centre end (off) are not on the programmed path
        moves = moves[1:-1]
    line_in, arc_in, first, last, arc_out, line_out = moves[0], moves[1], moves[2], moves[-3], moves[-2], moves[-1]
    assert [m["kind"] for m in (line_in, arc_in, arc_out, line_out)] == ["line", "arc", "arc", "line"]
    s_dash = arc_in["end"][:2]
    assert np.array_equal(first["start"][:2], s_dash) and np.array_equal(last["end"][:2], s_dash) and np.array_equal(arc_out["start"][:2], s_dash)
    assert _angle(_tangent(line_in, line_in["end"][:2]), _tangent(arc_in, arc_in["start"][:2])) < 1e-6
    assert _angle(_tangent(arc_in, s_dash), _tangent(first, s_dash)) < 1e-6
    assert _angle(_tangent(last, s_dash), _tangent(arc_out, s_dash)) < 1e-6
    assert _angle(_tangent(arc_out, arc_out["end"][:2]), _tangent(line_out, line_out["start"][:2])) < 1e-6
    if comp:  # the programmed arcs: radius lead radius + r, touching the profile at S from outside
        for arc in (arc_in, arc_out):
            assert np.linalg.norm(s_dash - arc["centre"]) == pytest.approx(spec.lead_arc_radius + spec.tool_radius, abs=2e-6)
        assert distance_to_arcs(s_dash[None], contour.segments)[0] < 1e-6
        return
    points = sample_moves([line_in, arc_in, arc_out, line_out], 0.002)[0]
    assert np.min(distance_to_arcs(points, contour.segments)) >= spec.tool_radius - 1e-6


# ---------------------------------------------------------------------------------------------
# the plunge point and the way away from the part (for a ramp or helix there)
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("style", ["arc", "line"])
@pytest.mark.parametrize("comp", [False, True])
def test_plunge_point_and_away_direction(style, comp, contours):
    """``lead_moves``' plunge point is where the program plunges, and the tool centre moved from it
    along ``away`` stays clear of the profile (circle equation), its clearance never falling."""
    from camgen.export.gcode import rotate, start_parameter, tool_path
    from camgen.export.gcode_leads import lead_moves

    contour = contours["stride"]
    spec = MachiningSpec(tool_diameter=8.0, thickness=1.0, step_down=2.0, cutter_compensation=comp, lead_style=style)
    program = gcode_program(contour, spec)
    plunge_xy = np.array([float(v) for v in re.search(r"^G0 X(-?[\d.]+) Y(-?[\d.]+)$", program, re.M).groups()])
    t0 = start_parameter(contour)
    path = rotate(contour if comp else tool_path(contour, spec), t0)
    start = path.segments[0].start_point
    tangent = path.tangent(np.array([0.0]))[0]
    leads = lead_moves(start, -tangent, np.array([tangent[1], -tangent[0]]), spec)  # climb: clockwise
    assert np.linalg.norm(leads.plunge - plunge_xy) < 1e-4
    assert np.linalg.norm(leads.away) == pytest.approx(1.0)
    walk = leads.plunge + np.linspace(0.0, 50.0, 5001)[:, None] * leads.away
    clearance = distance_to_arcs(walk, contour.segments)
    assert clearance[0] >= spec.tool_radius and np.all(np.diff(clearance) >= -1e-9)


# ---------------------------------------------------------------------------------------------
# straight leads still cut, and the keys
# ---------------------------------------------------------------------------------------------
@pytest.mark.usefixtures("needs_rs274")
def test_straight_leads_still_cut_the_profile(contours, tmp_path):
    """``lead_style = "line"``: the tangent lines of before, cut in the simulation, compensation on
    and off, both directions (the arc leads: every template in tests/test_gcode.py)."""
    from test_gcode import MODES, _assert_cut

    contour = contours["steering"]
    profile = ExactProfile(contour)
    for comp, direction in MODES:
        spec = MachiningSpec(tool_diameter=6.0, thickness=2.0, step_down=3.0, cutter_compensation=comp, direction=direction, lead_style="line")
        program = gcode_program(contour, spec)
        assert "quarter arc" not in program
        _assert_cut(simulate(program, contour, spec.tool_radius, tmp_path, profile=profile), spec, f"line comp={comp} {direction}")


def test_lead_settings_are_checked():
    for name, value in (("lead_style", "spiral"), ("lead_radius", 0.09), ("lead_radius", math.nan), ("lead_radius", -1.0)):
        with pytest.raises(ParameterError, match=name):
            MachiningSpec(**{name: value})
    assert MachiningSpec(lead_radius=0.1).lead_arc_radius == 0.1
    assert MachiningSpec(tool_diameter=10.0).lead_arc_radius == 8.0  # default: tool radius + 3 mm


@pytest.mark.parametrize(("add", "key", "valid"), [
    ("lead_radius_mm = 0.05", "machining.lead_radius_mm", "0.1 <= x <= 1000"),
    ('lead_style = "line"\nlead_radius_mm = 5.0', "machining.lead_radius_mm", "only with lead_style"),
    ('lead_style = "spiral"', "machining.lead_style", '"arc"'),
    ('dialect = "wire_edm"\nlead_style = "line"', "machining.lead_style", "wire_edm"),
])
def test_bad_lead_keys_exit_2_naming_the_key(add, key, valid, tmp_path):
    from camgen.scene import template_path

    text = template_path("default").read_text(encoding="utf-8")
    text, n = re.subn(r"^\[machining\][^\n]*\n", lambda m: f"{m.group(0)}{add}\n", text, count=1, flags=re.M)
    assert n == 1
    if "wire_edm" in add:  # the wire's dialect refuses the milling keys: the template's among them go
        text = re.sub(r"^(tool_diameter_mm|step_down_mm|safe_z_mm|feed_mm_per_min|plunge_feed_mm_per_min|spindle_rpm|direction|"
                      r"cutter_compensation|lead_mm|breakthrough_mm) = .*\n", "", text, flags=re.M)
    scene = tmp_path / "scene.toml"
    scene.write_text(text, encoding="utf-8")
    run = subprocess.run([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(tmp_path / "out")], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 2, run.stderr
    assert run.stderr.startswith("camgen: error: ") and run.stderr.count("\n") == 1, run.stderr
    assert key in run.stderr and valid in run.stderr, run.stderr


def test_the_header_states_the_lead_geometry(contours):
    """The header names the lead arcs' tool-centre radius and centre, and the plunge point; the
    straight style says it is straight."""
    spec = MachiningSpec(tool_diameter=8.0, lead_radius=12.5, lead=9.0)
    program = gcode_program(contours["stride"], spec)
    header = re.search(r"^\(lead-in and lead-out: straight 9 and a tangent quarter arc of tool-centre radius 12\.5 about "
                       r"X(-?[\d.]+) Y(-?[\d.]+), into and out of tool-centre point X(-?[\d.]+) Y(-?[\d.]+); plunge at "
                       r"X(-?[\d.]+) Y(-?[\d.]+)\)$", program, re.M)
    assert header
    c, s_dash, p0 = (np.array([float(header.group(k)), float(header.group(k + 1))]) for k in (1, 3, 5))
    assert np.linalg.norm(c - s_dash) == pytest.approx(12.5, abs=2e-4)
    assert np.linalg.norm(p0 - s_dash) == pytest.approx(math.hypot(12.5 + 9.0, 12.5), abs=2e-4)  # 9 along the normal beyond the quarter arc
    straight = gcode_program(contours["stride"], dataclasses.replace(spec, lead_radius=None, lead_style="line"))
    assert "(tangent lead-in and lead-out of 9 at tool-centre point" in straight and "quarter arc" not in straight


@pytest.mark.parametrize(("comp", "lead_radius", "lead"), [(False, 2.0, None), (True, 2.0, None), (True, 9.0, 4.5), (False, None, 5.0)])
@pytest.mark.usefixtures("needs_rs274")
def test_the_wear_a_fanuc_header_allows_runs_and_no_more(comp, lead_radius, lead, contours, tmp_path):
    """The Fanuc header states the largest wear the D register may add for the leads: rs274, told
    the register holds the stated value + 0.99 x that wear, runs the program; + 1.01 x it, it
    refuses the entry move or the lead arc (the tool would not fit)."""
    from test_gcode_fanuc import masked, stated_register, tool_table

    spec = MachiningSpec(tool_diameter=8.0, thickness=1.0, step_down=2.0, dialect="fanuc", cutter_compensation=comp, lead_radius=lead_radius,
                         lead=lead)
    program = gcode_program(contours["stride"], spec)
    wear = float(re.search(r"PLUS THE WEAR, BELOW ([\d.]+) MM FOR THE LEADS", program).group(1))
    _, value = stated_register(program)
    for factor, runs in ((0.99, True), (1.01, False)):
        status, message, _ = rs274_canon(masked(program), tmp_path, tool_table(program, 2.0 * (value + factor * wear)))
        assert (status == 0) == runs, (factor, wear, message)
