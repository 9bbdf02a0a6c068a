"""The outline's passes (issue 27 item 3): helix or ramp entry instead of a plunge, roughing with a
stock allowance then a finishing pass, holding tabs; run through LinuxCNC's rs274 and cut in
the simulation of tests/cutting.py.

The numbers the programs are judged by come from outside camgen.export: the lobed profile and
its growth by the allowance are circle geometry (concentric arcs, :func:`lobes`), the tool
path and its Z are rs274's canonical moves, the ramp angle and the allowance are the scene's.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from camgen.contour import Arc, Contour
from camgen.errors import ParameterError
from camgen.export.gcode import MachiningSpec, gcode_program
from cutting import CUT_TOL, ExactProfile, sample_moves, simulate
from helpers import arc_sweep, require_tool, rs274_canon
from test_gcode_fanuc import masked, tool_table
from test_gcode import lobes as gcode_lobes

MODES = [(comp, direction) for comp in (False, True) for direction in ("climb", "conventional")]
DIALECTS = ("linuxcnc", "fanuc")
#: Rounding of the canonical moves (rs274 prints 4 decimals) in a measured angle, rad.
ANGLE_SLACK = 2e-3


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


def lobes(lobe: float = 15.0, valley: float = 10.0, distance: float = 30.0, n: int = 4) -> Contour:
    """test_gcode's n convex arcs (radius ``lobe``) joined by concave arcs of radius ``valley``.
    ``lobes(15 + a, 10 - a)`` is the same profile grown by ``a``: the valleys' centres stay where
    they are (their distance from the lobes' centres is lobe + valley), every arc is concentric
    with the one it grows."""
    return gcode_lobes(distance, lobe, valley, n)


def spec_for(dialect: str, comp: bool, direction: str, **kw) -> MachiningSpec:
    return MachiningSpec(tool_diameter=6.0, thickness=5.0, step_down=2.0, breakthrough=0.2, dialect=dialect,
                         cutter_compensation=comp, direction=direction, **kw)


def run(program: str, spec: MachiningSpec, contour: Contour, workdir, profile: ExactProfile | None = None):
    """simulate() of the program as rs274 reads it (a Fanuc one masked, with its tool table)."""
    if spec.dialect == "fanuc":
        return simulate(masked(program), contour, spec.tool_radius, workdir, profile=profile, tool_table=tool_table(program))
    return simulate(program, contour, spec.tool_radius, workdir, profile=profile)


def assert_cut(report, label: str, bottom: float) -> None:
    assert report.status == 0, (label, report.message)
    assert report.gouge <= CUT_TOL, (label, "gouge", report.gouge)
    assert report.proud <= CUT_TOL, (label, "proud", report.proud)
    assert all(p.outside for p in report.passes), label
    assert abs(report.deepest - bottom) < 1e-9, (label, report.deepest)
    assert report.rapid_clearance >= 0.0, (label, report.rapid_clearance)


def horizontal_length(move: dict) -> float:
    """Length of a canonical move's projection on XY, mm (an arc: radius x sweep)."""
    if move["kind"] == "arc":
        return float(np.hypot(*(move["start"][:2] - move["centre"])) * abs(arc_sweep(move["start"], move["end"], move["centre"], move["turn"])))
    return float(np.hypot(*(move["end"][:2] - move["start"][:2])))


def descents(canon: list[dict]) -> tuple[list[dict], list[tuple[float, float]]]:
    """The feed moves that go down while moving in XY, and every straight feed down (no XY) as
    (its end Z, the deepest Z any feed move reached before it)."""
    sloped, straight = [], []
    floor = 0.0
    for move in canon:
        if move["kind"] == "traverse":
            continue
        dz = move["end"][2] - move["start"][2]
        if dz < 0.0 and horizontal_length(move) > 1e-9:
            sloped.append(move)
        elif dz < 0.0:
            straight.append((float(move["end"][2]), floor))
        floor = min(floor, float(move["end"][2]))
    return sloped, straight


# ---------------------------------------------------------------------------------------------
# entry: helix or ramp from the floor reached before, clear of the part, at most the ramp angle
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("entry", ["helix", "ramp"])
@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.usefixtures("needs_rs274")
def test_entry_descends_clear_of_the_part_within_the_ramp_angle(entry, dialect, tmp_path):
    contour = lobes()
    profile = ExactProfile(contour)
    angle = 4.0
    for comp, direction in MODES:
        spec = spec_for(dialect, comp, direction, entry=entry, ramp_angle=math.radians(angle))
        label = f"{entry} {dialect} comp={comp} {direction}"
        program = gcode_program(contour, spec)
        report = run(program, spec, contour, tmp_path, profile)
        assert_cut(report, label, -5.2)
        sloped, straight = descents(report.canon)
        # the descent: every pass's, down to its depth, on moves that go sideways
        assert {round(m["end"][2], 4) for m in sloped} >= {-2.0, -4.0, -5.2}, label
        steepest = max(math.atan2(m["start"][2] - m["end"][2], horizontal_length(m)) for m in sloped)
        assert steepest <= math.radians(angle) + ANGLE_SLACK, (label, math.degrees(steepest))
        # straight feeds down only through stock cut before (the first pass's to Z0, the top)
        assert all(z >= floor - 1e-9 for z, floor in straight), (label, straight)
        # every tool-centre point of the descent (between samples too: cutting.py's bound) r clear of the profile
        pts = sample_moves(sloped, 0.01)[0]
        assert float(np.min(profile.distance_lower_bound(pts))) >= spec.tool_radius - 1e-6, label
        # brute force on a dense polygon of the profile (vertices on the arcs)
        vertices = contour.flatten(1e-5)
        least = min(float(np.min(np.hypot(*(vertices[None] - p[:, None]).transpose(2, 0, 1)))) for p in np.array_split(pts, 20))
        assert least >= spec.tool_radius - 1e-6, (label, least)


@pytest.mark.usefixtures("needs_rs274")
def test_the_straight_plunge_is_what_the_entry_check_catches(tmp_path):
    """entry = "plunge" (the program before): the check above finds the straight feeds below the
    floor, and no sloped descent (so the check can fail)."""
    spec = spec_for("linuxcnc", False, "climb", entry="plunge")
    status, message, canon = rs274_canon(gcode_program(lobes(), spec), tmp_path)
    assert status == 0, message
    sloped, straight = descents(canon)
    assert not sloped and [z for z, floor in straight if z < floor - 1e-9] == pytest.approx([-2.0, -4.0, -5.2])


def test_entry_settings_are_checked():
    with pytest.raises(ParameterError, match="entry"):
        spec_for("linuxcnc", False, "climb", entry="spiral")
    with pytest.raises(ParameterError, match="ramp_angle_deg"):
        spec_for("linuxcnc", False, "climb", ramp_angle=math.radians(45.0))
    # a helix of radius 1.5 mm (half the tool radius) descends 2 mm in 200 turns at atan(2 / (200 * 3 pi)) = 0.061 deg
    with pytest.raises(ParameterError, match=r"ramp_angle_deg.*>= 0\.061"):
        spec_for("linuxcnc", False, "climb", entry="helix", ramp_angle=math.radians(0.05))
    assert spec_for("linuxcnc", False, "climb", entry="helix", ramp_angle=math.radians(0.062)).entry == "helix"


def _descends(step_down: float, turn: float, angle_deg: float, turns: int = 200) -> bool:
    """Whether ``turns`` turns (or ramp round trips) of horizontal length ``turn`` mm descend
    ``step_down`` mm at ``angle_deg``: each rises turn x tan(angle)."""
    return step_down <= turns * turn * math.tan(math.radians(angle_deg))


@pytest.mark.parametrize("tool", [0.01, 5e-324])
def test_the_default_entry_of_a_tiny_tool_is_a_ramp_and_a_given_helix_is_refused_with_a_working_hint(tool):
    """entry left out: the helix (radius r/2, a turn 2 pi r/2 long) where it descends step_down
    in <= 200 turns, else the ramp (to and fro along max(lead, 2 r), lead = r + 3 mm by default).
    A 0.01 mm tool at 3 deg: the helix needs 2 / (pi 0.005 tan 3 deg) = 2,430 turns, the ramp
    2 / (2 x 3.005 x tan 3 deg) = 6.4; the vanishing tool's helix never gets down at all.  The
    helix given anyway is refused naming entry (its least angle, atan(2 / (200 pi 0.005)) = 32.5
    deg, is beyond the 30 deg limit), and the value the refusal names works."""
    r = tool / 2.0
    assert not _descends(2.0, 2.0 * math.pi * r / 2.0, 3.0) and _descends(2.0, 2.0 * (r + 3.0), 3.0)
    spec = MachiningSpec(tool_diameter=tool, step_down=2.0, ramp_angle=math.radians(3.0))
    assert spec.entry == "ramp"
    with pytest.raises(ParameterError) as err:
        MachiningSpec(tool_diameter=tool, step_down=2.0, ramp_angle=math.radians(3.0), entry="helix")
    assert err.value.name == "entry" and '"ramp"' in err.value.valid, err.value
    assert MachiningSpec(tool_diameter=tool, step_down=2.0, ramp_angle=math.radians(3.0), entry="ramp").entry == "ramp"


# ---------------------------------------------------------------------------------------------
# roughing with a stock allowance, then one finishing pass
# ---------------------------------------------------------------------------------------------
ALLOWANCE = 0.5


def roughing_only(program: str) -> str:
    """The program up to its finishing pass (the passes before it), then the end."""
    head = program.split("(finishing pass", 1)[0].split("(FINISHING PASS", 1)[0]
    return head + ("M30\n%\n" if program.startswith("%") else "M2\n")


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.usefixtures("needs_rs274")
def test_roughing_leaves_the_allowance_and_the_finishing_pass_the_profile(dialect, tmp_path):
    contour = lobes()
    grown = lobes(15.0 + ALLOWANCE, 10.0 - ALLOWANCE)  # closed form: concentric arcs
    exact, rough = ExactProfile(contour), ExactProfile(grown)
    for comp, direction in MODES:
        spec = spec_for(dialect, comp, direction, stock_allowance=ALLOWANCE)
        label = f"{dialect} comp={comp} {direction}"
        program = gcode_program(contour, spec)
        # the roughing passes alone leave the profile grown by the allowance
        report = run(roughing_only(program), spec, grown, tmp_path, rough)
        assert_cut(report, label + " roughing", -5.2)
        assert [round(z, 4) for z in report.z_levels] == [-2.0, -4.0, -5.2], label
        # with the finishing pass: the exact profile, that pass at the full depth
        report = run(program, spec, contour, tmp_path, exact)
        assert report.status == 0, (label, report.message)
        finishing = report.passes[-1]
        assert round(finishing.z, 4) == -5.2 and len(report.passes) == 4, (label, report.z_levels)
        assert finishing.gouge <= CUT_TOL and finishing.proud <= CUT_TOL, (label, finishing)
        assert report.gouge <= CUT_TOL and report.rapid_clearance >= 0.0, label
        # the roughing passes stood the allowance off the profile (proud by it, within the rounding)
        assert all(abs(p.proud - ALLOWANCE) <= 1e-3 for p in report.passes[:-1]), (label, [p.proud for p in report.passes])
        _, straight = descents(report.canon)
        assert all(z >= floor - 1e-9 for z, floor in straight), (label, straight)


def test_an_allowance_that_closes_a_concave_radius_is_refused():
    # valleys of radius 10 with a tool of radius 3: the allowance must stay below 7
    with pytest.raises(ParameterError, match="stock_allowance_mm"):
        gcode_program(lobes(), spec_for("linuxcnc", False, "climb", stock_allowance=7.5))
    with pytest.raises(ParameterError, match="stock_allowance"):
        spec_for("linuxcnc", False, "climb", stock_allowance=-0.1)
    assert "finishing pass" in gcode_program(lobes(), spec_for("linuxcnc", False, "climb", stock_allowance=6.5))


# ---------------------------------------------------------------------------------------------
# holding tabs
# ---------------------------------------------------------------------------------------------
TAB_RADIUS, TAB_WIDTH, TAB_HEIGHT, TABS = 30.0, 4.0, 1.5, 3
#: How closely the raised stretch of a spline cam's tool path is held, mm: the stretch is measured
#: on the exact tool-centre path, the control runs biarcs or chords; under compensation LinuxCNC
#: runs chord corners below 0.05 rad straight on (camgen.export.gcode_moves), so its tool path
#: over G1 chords is up to 15 um longer or shorter than the exact one over the plate cam's 11 mm.
TAB_STRETCH_TOL = 0.02


def circle(radius: float = TAB_RADIUS) -> Contour:
    return Contour([Arc((0.0, 0.0), radius, 0.0, 2 * math.pi)])


def covered(points: np.ndarray, tool: np.ndarray, radius: float, slack: float) -> np.ndarray:
    """Points (n, 2) within ``radius + slack`` of a tool-centre sample (m, 2)."""
    from scipy.spatial import cKDTree

    return cKDTree(tool).query(points)[0] <= radius + slack


def runs(mask: np.ndarray) -> list[int]:
    """Lengths (in samples) of the runs of True in a closed loop of booleans."""
    if mask.all():
        return [mask.size]
    roll = np.roll(mask, -int(np.argmin(mask)))  # start on a False
    edges = np.diff(np.concatenate([[0], roll.astype(int), [0]]))
    return list(np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1))


@pytest.mark.parametrize(("dialect", "allowance"), [("linuxcnc", 0.0), ("fanuc", 0.0), ("linuxcnc", ALLOWANCE)])
@pytest.mark.usefixtures("needs_rs274")
def test_tabs_hold_the_part_at_their_width_and_height(dialect, allowance, tmp_path):
    """A 30 mm disc, tool radius 3 (tool-centre circle rho = 33), 3 tabs 4 mm wide and 1.5 mm high in
    5 mm stock: over each the passes below Z-3.5 rise along w + 2r = 10 mm of the tool-centre
    circle (measured between rs274's Z-only moves); at full depth the tool-centre circle is left
    uncut along w + 2r - 4 rho asin(r / (2 rho)) per tab and the profile along (w + 2r) R / rho
    (circle geometry; less the stretch where a profile point is within 1 um of the tool's reach),
    everywhere else the profile is cut to within 1 um, and over every tab the
    tool never went below Z-3.5: the tab stands 1.5 mm from the stock bottom.  With a stock allowance
    the roughing passes leave the tabs at the same cam angles (the finishing pass is measured: the
    roughing tool reaches less far into the tab along the centre line and never to the profile)."""
    contour, r, rho = circle(), 3.0, TAB_RADIUS + 3.0
    top = -(5.0 - TAB_HEIGHT)
    profile_pts = contour.flatten(1e-6)
    centre_line = circle(rho).flatten(1e-6)
    for comp, direction in MODES:
        spec = spec_for(dialect, comp, direction, holding_tabs=TABS, holding_tab_width=TAB_WIDTH, holding_tab_height=TAB_HEIGHT,
                        stock_allowance=allowance)
        label = f"{dialect} comp={comp} {direction}"
        program = gcode_program(contour, spec)
        report = run(program, spec, contour, tmp_path)
        assert report.status == 0 and report.gouge <= CUT_TOL and report.rapid_clearance >= 0.0, (label, report.message, report.gouge)
        feeds = [m for m in report.canon if m["kind"] != "traverse"]
        # the rises and descents: Z-only moves between the pass depth and the tabs' top
        z_only = [m for m in feeds if horizontal_length(m) == 0.0 and abs(m["end"][2] - m["start"][2]) > 0.0
                  and top in (round(m["start"][2], 4), round(m["end"][2], 4))]
        deep_passes = 2 + (allowance > 0)  # the passes at Z-4 and Z-5.2 (and the finishing pass)
        assert len(z_only) == 2 * TABS * deep_passes, (label, len(z_only))
        ends = np.array([m["end"][:2] for m in z_only[-2 * TABS:]])  # the last pass: rise, descend, ...
        angle = np.arctan2(ends[:, 1], ends[:, 0])
        stretch = rho * np.abs((angle[1::2] - angle[0::2] + math.pi) % (2 * math.pi) - math.pi)
        assert np.allclose(stretch, TAB_WIDTH + 2 * r, atol=1e-3), (label, stretch)
        assert np.allclose(np.hypot(*ends.T), rho, atol=1e-4), label  # on the tool-centre circle (compensation applied)
        # the part at full depth
        pts, _, _, _, z = sample_moves(feeds, 0.005, with_z=True)
        deep = pts[z <= -5.2 + 1e-9]
        kerf = runs(~covered(centre_line, deep, r, 0.0))
        step = 2 * math.pi * rho / len(centre_line)
        expected = TAB_WIDTH + 2 * r - 4 * rho * math.asin(r / (2 * rho))
        assert len(kerf) == TABS and np.allclose(np.array(kerf) * step, expected, atol=0.02), (label, kerf, expected)
        left = ~covered(profile_pts, deep, r, CUT_TOL)  # (the rest of the profile: cut to within 1 um)
        face = np.array(runs(left)) * 2 * math.pi * TAB_RADIUS / len(profile_pts)
        # a profile point at angle d beyond a stretch's end is r + rho R d^2 / (2 r) from its tool centre:
        # within r + CUT_TOL for d <= sqrt(2 r CUT_TOL / (rho R))
        blur = 2 * TAB_RADIUS * math.sqrt(2 * r * CUT_TOL / (rho * TAB_RADIUS))
        assert len(face) == TABS and np.allclose(face, (TAB_WIDTH + 2 * r) * TAB_RADIUS / rho - blur, atol=0.02), (label, face)
        # over each tab (the tool discs that reach its middle on the centre line) the lowest Z is its top
        middles = centre_line[~covered(centre_line, deep, r, 0.0)]
        near = covered(pts, middles, r, 0.0)
        assert abs(float(np.min(z[near])) - top) < 1e-9, (label, float(np.min(z[near])))
        assert float(np.min(z)) == pytest.approx(-5.2), label


def test_tabs_settings_are_checked():
    with pytest.raises(ParameterError, match="holding_tab_width"):
        spec_for("linuxcnc", False, "climb", holding_tab_width=4.0)  # no tabs
    with pytest.raises(ParameterError, match="holding_tabs"):
        spec_for("linuxcnc", False, "climb", holding_tabs=-1)
    # the tool-centre circle of 2 pi 33 = 207.3 mm holds 207.3 // (4 + 4 r) = 12 tabs of 4 mm
    with pytest.raises(ParameterError, match=r"holding_tabs.*<= 12"):
        gcode_program(circle(), spec_for("linuxcnc", False, "climb", holding_tabs=13, holding_tab_width=4.0))
    assert gcode_program(circle(), spec_for("linuxcnc", False, "climb", holding_tabs=12, holding_tab_width=4.0))
    with pytest.raises(ParameterError, match="holding_tab_height"):
        gcode_program(circle(), spec_for("linuxcnc", False, "climb", holding_tabs=2, holding_tab_height=5.0))


# ---------------------------------------------------------------------------------------------
# the scene keys: bad values exit 2 naming the key
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("template", "add", "key", "valid"), [
    ("default", 'entry = "spiral"', "machining.entry", "helix"),
    ("default", "ramp_angle_deg = 0.0", "machining.ramp_angle_deg", "0 < x <= 30"),
    ("default", 'entry = "helix"\nramp_angle_deg = 0.001', "machining.ramp_angle_deg", ">= "),  # (left out, entry falls back to a ramp)
    ("default", "stock_allowance_mm = -1.0", "machining.stock_allowance_mm", "0 <= x"),
    ("default", "holding_tab_width_mm = 3.0", "machining.holding_tab_width_mm", "holding_tabs = 0"),
    ("default", "holding_tabs = 2\nholding_tab_height_mm = 50.0", "machining.holding_tab_height_mm", "< the stock thickness"),
    ("wire_edm_cam", "holding_tabs = 2", "machining.holding_tabs", 'left out with dialect = "wire_edm"'),
    ("wire_edm_cam", 'entry = "ramp"', "machining.entry", 'left out with dialect = "wire_edm"'),
])
def test_bad_input_exits_2_naming_the_key(template, add, key, valid, tmp_path):
    from test_gcode_fanuc import _machining, _run

    run_ = _run(tmp_path, template, lambda text: _machining(text, add))
    assert run_.returncode == 2, (run_.returncode, run_.stderr)
    assert run_.stderr.startswith("camgen: error: ") and run_.stderr.count("\n") == 1, run_.stderr
    assert key in run_.stderr and valid in run_.stderr, run_.stderr


@pytest.mark.parametrize("spline_mode", ["biarcs", "lines"])
@pytest.mark.usefixtures("needs_rs274")
def test_tabs_on_a_spline_cam_rise_over_the_stated_stretch(spline_mode, tmp_path):
    """The plate_cam template's cam (spline profile), in biarcs and in G1 chords, compensation on and
    off, both directions: rs274's tool path between each rise and the next descent is w + 2r long
    (summed along the canonical moves), the rises lie on the tool-centre path (r from the exact
    profile), and the program cuts the profile with no gouge."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    scene = load_template("plate_cam")
    cam = compute(scene, Plan((), frozenset())).cams[0]
    profile = ExactProfile(cam.contour)
    width = 5.0
    for comp, direction in MODES:
        spec = dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol, spline_mode=spline_mode,
                                   cutter_compensation=comp, direction=direction, holding_tabs=4, holding_tab_width=width)
        label = f"{spline_mode} comp={comp} {direction}"
        program = gcode_program(cam.contour, spec, cam.name)
        report = run(program, spec, cam.contour, tmp_path, profile)
        assert report.status == 0 and report.gouge <= CUT_TOL, (label, report.message, report.gouge)
        feeds = [m for m in report.canon if m["kind"] != "traverse"]
        top = -(spec.thickness - 1.0)  # the default height: 1 mm
        last = max(i for i, m in enumerate(feeds) if horizontal_length(m) == 0.0 and round(m["end"][2], 4) == top)
        z_only = [i for i, m in enumerate(feeds) if horizontal_length(m) == 0.0 and top in (round(m["start"][2], 4), round(m["end"][2], 4))]
        pairs = [i for i in z_only if i > last - 2 * 4 * 1][-8:]  # the last pass's rises and descents
        for rise, descent in zip(pairs[0::2], pairs[1::2]):
            stretch = sum(horizontal_length(m) for m in feeds[rise + 1:descent])
            assert abs(stretch - (width + spec.tool_diameter)) <= TAB_STRETCH_TOL, (label, stretch)
            at = feeds[rise]["end"][:2]
            assert abs(float(profile.tree.query(at)[0]) - spec.tool_radius) <= 1e-3, label
