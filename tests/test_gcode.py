"""G-code programs, run through LinuxCNC's rs274 and cut in a simulation (tests/cutting.py).

Every number the programs are judged by comes from outside camgen.export.gcode: the exact
profile (the contour the program was made from), closed forms (circles, the trefoil
r = 40 + 8 cos 3 theta), rs274's canonical output, and shapely's polygon sweep.
"""
from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from camgen.contour import Arc, Contour, Spline
from camgen.errors import CornerError, GeometryError, ParameterError
from camgen.export.gcode import MachiningSpec, gcode_program
from cutting import CUT_TOL, ExactProfile, _passes, part_left, sample_moves, simulate
from helpers import distance_to_arcs, require_tool, rs274_canon

TEMPLATES = ("default", "tricycle", "horse_leg", "motion_law", "plate_cam", "flat_follower", "knife_follower", "oscillating_roller",
             "oscillating_flat", "lift_table", "groove_cam", "conjugate_cam", "constant_breadth")
# (linear_cam: its plate's 354 mm bottom edge is one chord, too long for ExactProfile's distance bound; tests/test_linear_cam.py
# cuts its program with the chords split)
MODES = [(comp, direction) for comp in (False, True) for direction in ("climb", "conventional")]


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


@pytest.fixture(scope="module")
def template_cams():
    """Every cam of every bundled template, built by the pipeline: {template: [(cam, spec)]}."""
    import dataclasses

    from camgen.pipeline import Plan, compute
    from camgen.scene import load_template

    out = {}
    for name in TEMPLATES:
        scene = load_template(name)
        cams = compute(scene, Plan((), frozenset())).cams
        # the machining spec the ngc writer uses (camgen.writers.gcode)
        out[name] = [(cam, dataclasses.replace(scene.machining, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol))
                     for cam in cams]
    return out


def trefoil() -> Contour:
    """r = 40 + 8 cos 3 theta (periodic spline through 48 points): concave at 60, 180, 300 deg,
    radius of curvature there (r^2 + 2 r'^2 - r r'')^-1 (r^2 + r'^2)^1.5 = 32^3 / (32^2 - 32 * 72) -> 25.6 mm."""
    theta = np.linspace(0, 2 * math.pi, 49)
    r = 40 + 8 * np.cos(3 * theta)
    return Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])


def lobes(distance: float = 30.0, lobe: float = 15.0, valley: float = 10.0, n: int = 4) -> Contour:
    """n convex arcs (radius ``lobe``, centres ``distance`` from the axis) joined by concave arcs
    of radius ``valley`` tangent to both neighbours (circle geometry only)."""
    centres = [distance * np.array([math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)]) for k in range(n)]
    valleys = []
    for k in range(n):
        u = np.array([math.cos(2 * math.pi * (k + 0.5) / n), math.sin(2 * math.pi * (k + 0.5) / n)])
        b, c = -2 * u @ centres[k], centres[k] @ centres[k] - (valley + lobe) ** 2  # |e u - c_k| = valley + lobe
        valleys.append((-b + math.sqrt(b * b - 4 * c)) / 2 * u)
    segments = []
    for k in range(n):
        c, before, after = centres[k], valleys[k - 1], valleys[k]
        a0, a1 = (math.atan2(*(v - c)[::-1]) for v in (before, after))
        segments.append(Arc(tuple(c), lobe, a0, (a1 - a0) % (2 * math.pi)))
        b0, b1 = (math.atan2(*(w - after)[::-1]) for w in (c, centres[(k + 1) % n]))
        segments.append(Arc(tuple(after), valley, b0, -((b0 - b1) % (2 * math.pi))))
    return Contour(segments, closure_tol=1e-9)


def _assert_cut(report, spec: MachiningSpec, label: str, tol: float = CUT_TOL) -> None:
    """The simulation's verdict: rs274 ran it, nothing gouged or left proud beyond ``tol``, the
    passes step down by <= step_down to the stock bottom + breakthrough, rapids below Z 0 (the
    retracts) keep the tool disc off the part."""
    assert report.status == 0, (label, report.message)
    assert report.gouge <= tol, (label, "gouge", report.gouge)
    assert report.proud <= tol, (label, "proud", report.proud)
    assert all(p.outside for p in report.passes), label
    z = np.array(report.z_levels)
    bottom = -(spec.thickness + spec.breakthrough)
    assert z[0] >= -spec.step_down - 1e-9 and np.all(np.diff(z) < 0) and np.all(np.diff(z) >= -spec.step_down - 1e-9), (label, z)
    assert abs(z[-1] - bottom) < 1e-9 and abs(report.deepest - bottom) < 1e-9, (label, z[-1], report.deepest)
    assert report.rapid_clearance >= 0.0, (label, report.rapid_clearance)  # rapids below Z 0 (retracts) clear of the part


# ---------------------------------------------------------------------------------------------
# the simulation itself, against closed forms
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("error", [0.002, -0.002])
@pytest.mark.usefixtures("needs_rs274")
def test_cutting_simulation_measures_a_circle_exactly(error, tmp_path):
    """A 40 mm circle cut with a 3 mm tool on a circle of radius 43 - e: the gouge is e and the
    proud material -e (closed form), both to the 4 decimals rs274 prints."""
    circle = Contour([Arc((0.0, 0.0), 40.0, 0.0, 2 * math.pi)])
    x = 43.0 - error
    program = f"G21 G90 G17\nG0 Z5\nG0 X{x:.4f} Y0\nG1 Z-1 F100\nG3 X{x:.4f} Y0 I{-x:.4f} J0 F400\nG0 Z5\nM2\n"
    report = simulate(program, circle, 3.0, tmp_path)
    assert report.status == 0, report.message
    assert report.gouge == pytest.approx(error, abs=2e-5)
    assert report.proud == pytest.approx(-error, abs=2e-5)
    # a chord through the part: the tool centre 40 - 40 cos(30 deg) = 5.36 mm inside the profile
    a = np.radians([-30.0, 30.0])
    chord = f"G21 G90 G17\nG0 Z5\nG0 X{40 * math.cos(a[0]):.4f} Y{40 * math.sin(a[0]):.4f}\nG1 Z-1 F100\nG1 X{40 * math.cos(a[1]):.4f} Y{40 * math.sin(a[1]):.4f}\nG0 Z5\nM2\n"
    assert simulate(chord, circle, 3.0, tmp_path).gouge == pytest.approx(3.0 + 40 - 40 * math.cos(math.radians(30)), abs=0.01)


# ---------------------------------------------------------------------------------------------
# every bundled template, both directions, with and without cutter compensation
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("template", TEMPLATES)
@pytest.mark.usefixtures("needs_rs274")
def test_every_template_cuts_its_exact_profile(template, template_cams, tmp_path):
    for cam, base in template_cams[template]:
        profile = ExactProfile(cam.contour)
        assert base.thickness == cam.body.thickness
        for comp, direction in MODES:
            spec = dataclasses.replace(base, cutter_compensation=comp, direction=direction)
            program = gcode_program(cam.contour, spec, cam.name, template)
            assert ("G41.1" in program) == (comp and direction == "climb") and ("G42.1" in program) == (comp and direction != "climb")
            report = simulate(program, cam.contour, spec.tool_radius, tmp_path, profile=profile)
            _assert_cut(report, spec, f"{template}/{cam.name} comp={comp} {direction}")


@pytest.mark.parametrize("comp", [False, True])
@pytest.mark.usefixtures("needs_rs274")
def test_spline_cam_in_lines_mode_cuts_its_exact_profile(comp, template_cams, tmp_path):
    """The tricycle's steering cam in G1 chords, at the template's 1 um and at 0.5 um (5 decimals)."""
    cam, base = template_cams["tricycle"][0]
    profile = ExactProfile(cam.contour)
    for direction, tol, decimals in (("climb", 1e-3, 4), ("conventional", 5e-4, 5)):
        spec = dataclasses.replace(base, spline_mode="lines", cutter_compensation=comp, direction=direction, chord_tol=tol, decimals=decimals)
        program = gcode_program(cam.contour, spec, cam.name)
        # a spline cam in chords only: the arcs in the plane are the two lead arcs of each pass
        # (the helix entry's arcs go down in Z)
        arcs = [line for line in program.splitlines() if line.startswith(("G2 ", "G3 ")) and " Z" not in line]
        assert len(arcs) == 2 * program.count("(pass ")
        _assert_cut(simulate(program, cam.contour, spec.tool_radius, tmp_path, profile=profile), spec, f"lines comp={comp} {direction}", tol)


@pytest.mark.parametrize("template", TEMPLATES)
@pytest.mark.usefixtures("needs_rs274")
def test_grbl_program_cuts_the_profile(template, template_cams, tmp_path):
    """The GRBL dialect writes the same tool-centre path (no G41/G42, no G64): every template's
    cams cut by it, both directions."""
    for cam, base in template_cams[template]:
        profile = ExactProfile(cam.contour)
        for direction in ("climb", "conventional"):
            spec = dataclasses.replace(base, dialect="grbl", direction=direction)
            program = gcode_program(cam.contour, spec, cam.name, template)
            assert "G41" not in program and "G42" not in program and "G64" not in program
            _assert_cut(simulate(program, cam.contour, spec.tool_radius, tmp_path, profile=profile), spec,
                        f"grbl {template}/{cam.name} {direction}")


@pytest.mark.usefixtures("needs_rs274")
def test_part_left_matches_the_profile_in_a_polygon_sweep(template_cams, tmp_path):
    """Coarse cross-check with shapely: the stock minus the tool disc swept along the last pass
    of the motion-law cam (compensated, climb: the program that gouged 17.7 mm) is the profile."""
    cam, base = template_cams["motion_law"][0]
    spec = dataclasses.replace(base, cutter_compensation=True, direction="climb")
    status, message, canon = rs274_canon(gcode_program(cam.contour, spec), tmp_path)
    assert status == 0, message
    chain = _passes(canon)[-1]
    pts = sample_moves(chain, 0.05)[0]
    left, profile = part_left(cam.contour, pts, spec.tool_radius)
    assert left.hausdorff_distance(profile) < 5e-3
    assert abs(left.area - profile.area) < 5e-3 * profile.length


# ---------------------------------------------------------------------------------------------
# concave profiles: spline and arcs
# ---------------------------------------------------------------------------------------------
def test_biarcs_follow_a_concave_spline_with_tangent_joints():
    from scipy.spatial import cKDTree

    from camgen.contour.arcspline import to_arc_spline

    spline = trefoil()
    tol = 6e-4
    arcs = to_arc_spline(spline, tol).segments
    assert all(isinstance(a, Arc) for a in arcs)
    # spline -> arcs, by the circle equation (helpers.distance_to_arcs)
    curve = spline.evaluate(np.linspace(0, 1, 200001)[:-1])
    assert np.max(distance_to_arcs(curve, arcs)) <= tol
    # arcs -> spline: points of every arc against a 1e-8 mm chord polygon of the spline
    poly = spline.flatten(1e-8)
    spacing = np.max(np.hypot(*np.diff(np.vstack([poly, poly[:1]]), axis=0).T))
    on_arcs = np.concatenate([a.point(np.linspace(0, 1, 40)) for a in arcs])
    d_v = cKDTree(poly).query(on_arcs)[0]
    assert np.max(np.sqrt(np.maximum(d_v**2 - spacing**2 / 4, 0))) <= tol * (1 + 1e-9) + 1e-8
    # G1 chain: each arc starts where the previous ends, with the same tangent
    for a, b in zip(arcs, arcs[1:] + arcs[:1]):
        assert np.hypot(*(a.end_point - b.start_point)) < 1e-9
        ta = math.copysign(1, a.sweep) * np.array([-math.sin(a.start_angle + a.sweep), math.cos(a.start_angle + a.sweep)])
        tb = math.copysign(1, b.sweep) * np.array([-math.sin(b.start_angle), math.cos(b.start_angle)])
        assert ta @ tb > 1 - 1e-12
    # concave arcs (clockwise) exactly where the polar curve is concave (closed-form curvature)
    mid = np.array([a.point(np.array([0.5]))[0] for a in arcs])
    th = np.arctan2(mid[:, 1], mid[:, 0])
    r, r1, r2 = 40 + 8 * np.cos(3 * th), -24 * np.sin(3 * th), -72 * np.cos(3 * th)
    kappa = (r * r + 2 * r1 * r1 - r * r2) / (r * r + r1 * r1) ** 1.5
    sweep = np.array([a.sweep for a in arcs])
    clear = np.abs(kappa) > 0.005  # away from the six inflections
    assert np.all(np.sign(sweep[clear]) == np.sign(kappa[clear]))
    concave = [a.radius for a in arcs if a.sweep < 0]
    assert min(concave) == pytest.approx(25.6, rel=0.05)  # the 48-point interpolant itself reaches 24.7


@pytest.mark.parametrize("mode", ["biarcs", "lines"])
@pytest.mark.usefixtures("needs_rs274")
def test_concave_spline_profile_cut_exactly(mode, tmp_path):
    """The trefoil (concave radius 25.6 mm) with 20 and 40 mm tools, in both output modes (chords
    under compensation: LinuxCNC's straight-on corners need finer chords where the tool nearly
    fills the concave radius)."""
    contour = trefoil()
    profile = ExactProfile(contour)
    # (the offset of a non-convex contour checks itself for crossings: ~1 s per program)
    cases = {"biarcs": [(20.0, False, "climb"), (20.0, True, "conventional")],
             "lines": [(20.0, True, "climb"), (20.0, False, "conventional"), (40.0, True, "conventional")]}
    for diameter, comp, direction in cases[mode]:
        spec = MachiningSpec(tool_diameter=diameter, thickness=3.0, step_down=3.0, spline_mode=mode, cutter_compensation=comp, direction=direction)
        program = gcode_program(contour, spec)
        if mode == "biarcs":
            assert re.search(r"^G[23] .*", program, re.M)
        _assert_cut(simulate(program, contour, spec.tool_radius, tmp_path, profile=profile), spec, f"{mode} comp={comp} {direction}")


@pytest.mark.parametrize("diameter", [12.0, 19.0])
@pytest.mark.usefixtures("needs_rs274")
def test_concave_arc_profile_cut_exactly(diameter, tmp_path):
    """Four convex lobes joined by concave arcs of radius 10 mm; tools of radius 6 and 9.5 mm."""
    contour = lobes()
    profile = ExactProfile(contour)
    for comp, direction in MODES[:: 3] if diameter < 15 else MODES[1:3]:
        spec = MachiningSpec(tool_diameter=diameter, thickness=2.0, step_down=2.0, cutter_compensation=comp, direction=direction)
        program = gcode_program(contour, spec)
        assert program.count("G2 ") + program.count("G3 ") >= 8  # exact arcs, not chords
        _assert_cut(simulate(program, contour, spec.tool_radius, tmp_path, profile=profile), spec, f"d={diameter} comp={comp} {direction}")


@pytest.mark.usefixtures("needs_rs274")
def test_arcs_too_short_to_print_never_become_full_circles(tmp_path):
    """A lobe arc split off a 1e-6 rad piece (15 nm long): printed with 4 decimals its
    ends coincide, and LinuxCNC runs such an arc as a full circle.  It must not be written as one."""
    arcs = list(lobes().segments)
    first = arcs[0]
    tiny = 1e-6
    arcs[:1] = [Arc(first.center, first.radius, first.start_angle, first.sweep - tiny),
                Arc(first.center, first.radius, first.start_angle + first.sweep - tiny, tiny)]
    contour = Contour(arcs, closure_tol=1e-9)
    profile = ExactProfile(contour)
    for comp, direction in MODES[1:3]:
        spec = MachiningSpec(tool_diameter=12.0, thickness=2.0, step_down=2.0, cutter_compensation=comp, direction=direction)
        _assert_cut(simulate(gcode_program(contour, spec), contour, 6.0, tmp_path, profile=profile), spec, f"comp={comp}")


def test_tools_that_would_gouge_are_refused():
    contour = trefoil()
    gcode_program(contour, MachiningSpec(tool_diameter=40.0))
    for comp in (False, True):
        with pytest.raises(GeometryError, match=r"diameter 60 mm would gouge.*cam angle (59|60|179|180|299|300)\.\d+ deg"):
            gcode_program(contour, MachiningSpec(tool_diameter=60.0, cutter_compensation=comp))
    # concave arcs of radius 10: a 20 mm tool does not fit, and a 19.999 mm tool leaves LinuxCNC's
    # compensated arc 1 um of radius (refused under compensation only)
    with pytest.raises(GeometryError, match="would gouge"):
        gcode_program(lobes(), MachiningSpec(tool_diameter=20.0))
    with pytest.raises(GeometryError, match="cutter_compensation"):
        gcode_program(lobes(), MachiningSpec(tool_diameter=19.998, cutter_compensation=True))


def test_no_safe_start_on_a_hull_of_corners():
    """A square has no point with a tangent on its convex hull: no tangent lead is possible."""
    corners = np.array([[0, 0], [40, 0], [40, 40], [0, 40], [0, 0]], float)
    sides = []
    for p, q in zip(corners[:-1], corners[1:]):
        coeffs = np.zeros((4, 1, 2))
        coeffs[2, 0], coeffs[3, 0] = q - p, p
        sides.append(Spline(np.array([0.0, 1.0]), coeffs))
    square = Contour(sides)
    with pytest.raises(GeometryError, match="cutter_compensation"):
        gcode_program(square, MachiningSpec(cutter_compensation=True))
    with pytest.raises(GeometryError, match="no safe start for the lead"):
        gcode_program(square, MachiningSpec())


# ---------------------------------------------------------------------------------------------
# lead-in and lead-out, from rs274's output
# ---------------------------------------------------------------------------------------------
def _unit(v):
    return v / np.linalg.norm(v)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


@pytest.mark.parametrize(("comp", "lead"), [(False, None), (True, None), (True, 300.0)])
@pytest.mark.parametrize("direction", ["climb", "conventional"])
@pytest.mark.usefixtures("needs_rs274")
def test_leads_are_tangent_to_the_tool_path_and_end_at_its_start(comp, lead, direction, contours, tmp_path):
    """From rs274's tool-centre moves: after the plunge, straight feeds along one line reach the
    contour's first arc at S'; the line is tangent to that arc and to the last one, S' is r from
    the profile, the lead-out continues along the same line, and nothing on the line comes
    closer than r to the exact profile.  A 300 mm lead under compensation: LinuxCNC runs corners
    flatter than 0.05 rad straight on, so the entry move must still meet the tangent line at a
    steeper angle.  (``lead_style = "line"``; the arc leads: tests/test_gcode_leads.py.)"""
    contour = contours["stride"]
    spec = MachiningSpec(tool_diameter=8.0, thickness=1.0, step_down=2.0, direction=direction, cutter_compensation=comp, lead=lead,
                         lead_style="line", entry="plunge")  # (the helix and ramp entries: tests/test_gcode_passes.py)
    status, message, canon = rs274_canon(gcode_program(contour, spec), tmp_path)
    assert status == 0, message
    chain = _passes(canon)[0]
    plunge, rest = chain[0], chain[1:]
    assert np.allclose(plunge["start"][:2], plunge["end"][:2]) and plunge["end"][2] < 0
    arcs = [i for i, m in enumerate(rest) if m["kind"] == "arc"]
    lead_in, path, lead_out = rest[: arcs[0]], rest[arcs[0] : arcs[-1] + 1], rest[arcs[-1] + 1 :]
    assert lead_in and lead_out and all(m["kind"] == "line" for m in lead_in + lead_out)
    p0, s_in = plunge["end"][:2], lead_in[-1]["end"][:2]
    s_out, q = lead_out[0]["start"][:2], lead_out[-1]["end"][:2]
    u = _unit(s_in - p0)
    # one straight line from the plunge through S' to the end of the lead-out, S' the path's start and end
    for point in [m["end"][:2] for m in lead_in + lead_out]:
        assert abs(_cross(u, point - p0)) < 2e-4
    assert np.hypot(*(s_out - s_in)) < 2e-4 and np.hypot(*(path[0]["start"][:2] - s_in)) < 2e-4
    assert np.linalg.norm(s_in - p0) == pytest.approx(spec.lead_length, abs=2e-4)
    assert np.linalg.norm(q - s_out) == pytest.approx(spec.lead_length, abs=2e-4)
    assert (q - s_out) @ u > 0  # the lead-out goes on forward
    # tangent to the first and the last arc: the radius to S' is perpendicular to u, and the arc turns forward
    for arc, at in ((path[0], path[0]["start"][:2]), (path[-1], path[-1]["end"][:2])):
        radial = at - arc["centre"]
        assert abs(u @ _unit(radial)) < 2e-4
        forward = np.sign(arc["turn"]) * np.array([-radial[1], radial[0]])
        assert forward @ u > 0
    # S' is r from the exact profile; the lead line stays >= r away (rigorous lower bound)
    profile = ExactProfile(contour)
    assert profile.tree.query(s_in)[0] == pytest.approx(spec.tool_radius, abs=1e-4)
    line = p0 + np.linspace(0, 1, 20001)[:, None] * (q - p0)
    assert np.min(profile.distance_lower_bound(line)) >= spec.tool_radius - 1e-4
    assert not profile.contains(p0)
    signed = sum(_cross(m["start"][:2], m["end"][:2]) for m in path)  # twice the area swept about the origin
    assert (signed < 0) == (direction == "climb")  # climb: clockwise round the outside


# ---------------------------------------------------------------------------------------------
# program text: header, dialects, parameters
# ---------------------------------------------------------------------------------------------
def test_gcode_header_dialects_and_errors(contours):
    linux = gcode_program(contours["stride"], MachiningSpec())
    assert "G21 G90 G17 G40 G49 G80 G94" in linux and linux.rstrip().endswith("M2")
    blend = float(re.search(r"^G64 P([\d.]+)$", linux, re.M).group(1))
    assert 0 < blend <= 1e-3  # LinuxCNC's path blending stays inside chord_tol
    # the header states the error budget, and its parts add up to chord_tol at most
    budget = re.search(r"\(path tolerance ([\d.e-]+) = (.*)\)", linux)
    parts = [float(x) for x in re.findall(r" ([\d.]+(?:e-\d+)?)(?: \+|$)", budget.group(2))]
    assert float(budget.group(1)) == 1e-3 and len(parts) == 4 and sum(parts) <= 1e-3 * (1 + 1e-9)
    assert parts[-1] == blend
    assert "breakthrough" in linux and "Z-10.2" in linux  # default stock 10 mm, breakthrough 0.2
    grbl = gcode_program(contours["stride"], MachiningSpec(dialect="grbl"))
    assert "G64" not in grbl and "G41" not in grbl and "G42" not in grbl and "M3 S8000" in grbl
    with pytest.raises(ParameterError, match="cutter_compensation"):
        MachiningSpec(dialect="grbl", cutter_compensation=True)
    with pytest.raises(ParameterError, match="lead"):
        MachiningSpec(lead=2.0, tool_diameter=6.0)


def test_decimals_too_coarse_for_the_tolerance_are_refused():
    """Rounding to d decimals moves a coordinate by up to 0.5 * 10^-d; at most 5 % of chord_tol
    (the brief's budget) allows d = 4 for 1 um and d = 5 for 0.5 um, and refuses d = 3 and 4 there."""
    MachiningSpec(chord_tol=1e-3, decimals=4)
    MachiningSpec(chord_tol=5e-4, decimals=5)
    for tol, d in ((1e-3, 3), (5e-4, 4)):
        with pytest.raises(ParameterError, match="decimals"):
            MachiningSpec(chord_tol=tol, decimals=d)


def test_a_tolerance_the_program_cannot_print_is_refused_before_anything_is_computed(tmp_path):
    """Scene level: 6 decimals round an arc by up to 3 sqrt(2)/2 10^-6 mm (its centre and ends),
    more than a quarter of chord_tol below 8.49e-6 mm: `camgen run` exits 2 at once naming
    output.chord_tol_mm and writes nothing; a coarse decimals names machining.decimals and 5..6."""
    import subprocess
    import sys

    from camgen.scene import template_path

    base = template_path("default").read_text(encoding="utf-8")
    cases = ((base.replace("chord_tol_mm = 0.001", "chord_tol_mm = 0.000008"), "output.chord_tol_mm", ">= 8.5e-06 mm"),
             (base.replace("chord_tol_mm = 0.001", "chord_tol_mm = 0.0001"), "machining.decimals", "an integer 5..6"))
    assert 3 * math.sqrt(2) / 2 * 1e-6 / 0.25 == pytest.approx(8.485e-6, rel=1e-3)
    for number, (text, key, valid) in enumerate(cases):
        scene = tmp_path / f"fine{number}.toml"
        scene.write_text(text, encoding="utf-8")
        run = subprocess.run([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(tmp_path / "out")],
                             capture_output=True, text=True, timeout=60)
        assert run.returncode == 2, run.stderr
        assert key in run.stderr and valid in run.stderr and run.stderr.count("\n") == 1
        assert not (tmp_path / "out").exists()


def test_breakthrough_is_checked():
    for bad in (-0.1, math.nan, math.inf):
        with pytest.raises(ParameterError, match="breakthrough"):
            MachiningSpec(breakthrough=bad)


@pytest.mark.parametrize("breakthrough", [0.0, 0.5])
@pytest.mark.usefixtures("needs_rs274")
def test_breakthrough_sets_the_last_pass(breakthrough, contours, tmp_path):
    """Three-arc stride cam: passes of <= 2.5 mm down to 6 mm + breakthrough, cut exactly, with a
    finer tolerance (0.5 um, 5 decimals) than the templates."""
    spec = MachiningSpec(thickness=6.0, step_down=2.5, tool_diameter=8.0, breakthrough=breakthrough, chord_tol=5e-4, decimals=5,
                         entry="plunge")  # (the helix's arcs: tests/test_gcode_passes.py)
    program = gcode_program(contours["stride"], spec)
    report = simulate(program, contours["stride"], 4.0, tmp_path)
    _assert_cut(report, spec, f"breakthrough {breakthrough}", tol=5e-4)
    passes = math.ceil((6.0 + breakthrough) / 2.5)
    assert len(report.passes) == passes
    # the exact arcs stay arcs: per pass two G1 leads, every other move a G2/G3 whose offset radius
    # is one of the six radii of the cam + the tool radius, or the lead arcs' radius (tool radius + 3 mm)
    assert program.count("G1 X") == 2 * passes
    radii = {round(seg.radius + 4.0, 3) for seg in contours["stride"].segments} | {4.0 + 3.0}
    arcs = [m for m in report.canon if m["kind"] == "arc"]
    assert len(arcs) >= 6 * passes
    assert {round(float(np.hypot(*(m["end"][:2] - m["centre"]))), 3) for m in arcs} <= radii


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_a_knife_cams_corner_is_named_not_called_a_gouge(rotation):
    """A knife cam whose law's velocity jumps (a constant-velocity rise without blends) has corners:
    the tool path refuses it naming the corner where the rise ends: its polar angle on the cam and
    the tangent's turn, both written out here from the knife tip (e, sqrt(Rb^2 - e^2) + s) and its
    velocity relative to the cam, (sigma y, s' - sigma e) in the fixed frame, on both sides."""
    from camgen.synthesis.followers import FollowerSpec, cam_envelope
    from camgen.synthesis.laws import MotionProgram, Segment

    base, offset, lift, span = 45.0, -6.0, 18.0, math.radians(150.0)
    law = MotionProgram([Segment("constant_velocity", span, lift), Segment("dwell", math.radians(30)),
                         Segment("cycloidal", math.radians(120), -lift), Segment("dwell", math.radians(60))])
    f = FollowerSpec("knife", base, offset=offset, rotation=rotation)
    profile = cam_envelope(f, law).profile
    with pytest.raises(CornerError) as err:
        gcode_program(profile, MachiningSpec(tool_diameter=4.0))
    text = str(err.value)
    assert "cannot follow the profile" in text and "gouge" not in text
    # the corners of the rise's ends: the first one named in contour order (the contour runs against theta for ccw)
    sigma = f.sigma
    y0 = math.sqrt(base**2 - offset**2)
    corners = []
    for theta, s, before, after in ((0.0, 0.0, 0.0, lift / span), (span, lift, lift / span, 0.0)):
        tip = complex(offset, y0 + s) * complex(math.cos(theta), -sigma * math.sin(theta))
        polar = math.degrees(math.atan2(tip.imag, tip.real)) % 360.0
        v0, v1 = complex(sigma * (y0 + s), before - sigma * offset), complex(sigma * (y0 + s), after - sigma * offset)
        turn = math.degrees(math.atan2((v0.conjugate() * v1).imag, (v0.conjugate() * v1).real))
        corners.append((polar, abs(turn)))
    named = re.search(r"meet at cam angle ([\d.]+) deg, the tangent turning by (-?[\d.]+) deg", text)
    polar, turn = float(named.group(1)), abs(float(named.group(2)))
    assert any(abs(polar - p) < 1e-3 and abs(turn - t) < 1e-3 for p, t in corners), (polar, turn, corners)
