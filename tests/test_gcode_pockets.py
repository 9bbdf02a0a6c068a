"""G-code for pockets (a groove cam's groove), run through LinuxCNC's rs274 and cut in a simulation.

Every number the programs are judged by comes from outside camgen.export: the walls and the
slot as closed forms (concentric circles; the pitch curve r = 40 + 6 cos 3 theta and its exact
offsets by +-w/2 along the closed-form normal, sampled densely), rs274's canonical moves, and the
cutting simulation of tests/cutting.py (the tool disc swept along them).  The program is given
the walls as contours (exact arcs; cubic splines through 1441 points of the closed forms, within
1e-7 mm of them), the way a groove cam's BuiltCam carries them.
"""
from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

from camgen.contour import Arc, Contour, Spline
from camgen.errors import ParameterError
from camgen.export.gcode import MachiningSpec, gcode_program
from camgen.kinds.base import Pocket, Wall
from cutting import CUT_TOL, simulate_pockets
from helpers import require_tool

#: The groove of every case: a roller of radius 5 mm with 0.1 mm clearance, 4 mm deep in a 10 mm plate.
ROLLER, CLEARANCE, DEPTH, THICKNESS = 5.0, 0.1, 4.0, 10.0
WIDTH = 2 * ROLLER + CLEARANCE
RIM = 70.0


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


def circle(radius: float) -> Contour:
    return Contour([Arc((0.0, 0.0), radius, 0.0, 2 * math.pi)])


class Sampled:
    """A closed curve given by dense samples of its closed form: what tests/cutting.py's
    ExactProfile flattens (``flatten`` returns the samples; their chords stay within ``sagitta``
    of the curve, s^2 / (8 rho) for spacing s and least radius of curvature rho)."""

    def __init__(self, points: np.ndarray, sagitta: float) -> None:
        self.points = points
        self.sagitta = sagitta

    def flatten(self, tol: float) -> np.ndarray:
        assert self.sagitta <= tol, (self.sagitta, tol)
        return self.points


def trefoil_groove(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pitch curve r = 40 + 6 cos 3 theta: points (n, 2), outward unit normals (n, 2) and signed
    radius of curvature (n,) (r^2 + r'^2)^1.5 / (r^2 + 2 r'^2 - r r''), > 0 convex: 21.2 mm at
    theta = 0, -57.8 mm (concave) at 60 deg."""
    r, r1, r2 = 40 + 6 * np.cos(3 * theta), -18 * np.sin(3 * theta), -54 * np.cos(3 * theta)
    c, s = np.cos(theta), np.sin(theta)
    point = np.stack([r * c, r * s], axis=1)
    tangent = np.stack([r1 * c - r * s, r1 * s + r * c], axis=1)
    tangent /= np.hypot(*tangent.T)[:, None]
    normal = np.stack([tangent[:, 1], -tangent[:, 0]], axis=1)
    rho = (r * r + r1 * r1) ** 1.5 / (r * r + 2 * r1 * r1 - r * r2)
    return point, normal, rho


def groove(shape: str) -> tuple[Pocket, dict, callable]:
    """The pocket a groove cam carries, the exact walls {layer: curve} for the simulation, and
    ``slot(n)``: points of the floor between the walls (closed form)."""
    if shape == "circles":
        pitch = 35.0
        walls = {"GROOVE_OUTER": circle(pitch + WIDTH / 2), "GROOVE_INNER": circle(pitch - WIDTH / 2)}
        pocket = Pocket("groove", tuple(Wall(k, v) for k, v in walls.items()), DEPTH, WIDTH, circle(pitch), CLEARANCE)

        def slot(n: int) -> np.ndarray:
            th, s = np.meshgrid(np.linspace(0, 2 * math.pi, n), np.linspace(-WIDTH / 2, WIDTH / 2, 61))
            return np.stack([((pitch + s) * np.cos(th)).ravel(), ((pitch + s) * np.sin(th)).ravel()], axis=1)

        return pocket, walls, slot
    theta = np.linspace(0, 2 * math.pi, 1441)
    point, normal, _ = trefoil_groove(theta)
    splines = {k: Contour([Spline.interpolate(theta, point + side * WIDTH / 2 * normal)]) for k, side in (("GROOVE_OUTER", 1), ("GROOVE_INNER", -1))}
    centre = Contour([Spline.interpolate(theta, point)])
    pocket = Pocket("groove", tuple(Wall(k, v) for k, v in splines.items()), DEPTH, WIDTH, centre, CLEARANCE)
    dense = np.linspace(0, 2 * math.pi, 100_001)[:-1]
    p, n, rho = trefoil_groove(dense)
    walls = {}
    for layer, side in (("GROOVE_OUTER", 1), ("GROOVE_INNER", -1)):
        curve = p + side * WIDTH / 2 * n
        spacing = float(np.max(np.hypot(*np.diff(np.vstack([curve, curve[:1]]), axis=0).T)))
        least = float(np.min(np.abs(rho + side * WIDTH / 2)))  # radius of the parallel curve: rho +- w/2
        walls[layer] = Sampled(curve, spacing**2 / (8 * least))

    def slot(n: int) -> np.ndarray:
        q, m, _ = trefoil_groove(np.linspace(0, 2 * math.pi, n))
        s = np.linspace(-WIDTH / 2, WIDTH / 2, 61)
        return (q[None] + s[:, None, None] * m[None]).reshape(-1, 2)

    return pocket, walls, slot


def _header(program: str) -> str:
    return "\n".join(line for line in program.splitlines() if line.startswith("("))


def _assert_groove_cut(program: str, spec: MachiningSpec, walls: dict, slot, workdir, label: str) -> None:
    """rs274 runs the program; the pocket is cut before the outline; no cutting move touches a
    wall beyond CUT_TOL, and at the floor the tool reaches every point of both walls within
    CUT_TOL; every cut lies between the walls; the levels step down by <= step_down, each ramp
    starting at the previous floor, to the pocket's depth and no deeper; the whole slot floor is
    cleared (no island); the outline is cut as without a pocket."""
    r = spec.tool_radius
    report = simulate_pockets(program, circle(RIM), walls, r, workdir)
    outline, pocket = report.outline, report.pocket
    assert outline.status == 0, (label, outline.message)
    assert pocket is not None, label
    first_outline = report.order.index("outline")
    assert set(report.order[:first_outline]) == {"pocket"} and set(report.order[first_outline:]) == {"outline"}, (label, report.order)
    for layer in walls:
        assert pocket.gouge[layer] <= CUT_TOL, (label, layer, "gouge", pocket.gouge[layer])
        assert pocket.proud[layer] <= CUT_TOL, (label, layer, "proud", pocket.proud[layer])
    assert pocket.between, label
    starts, floors = np.array(pocket.levels).T
    assert starts[0] == 0.0 and np.all(starts[1:] == floors[:-1]), (label, pocket.levels)  # each ramp from the previous floor
    assert np.all(starts - floors <= spec.step_down + 1e-9) and np.all(np.diff(floors) < 0), (label, pocket.levels)
    assert floors[-1] == -DEPTH and pocket.deepest == -DEPTH, (label, pocket.levels)
    assert len(pocket.levels) == math.ceil(DEPTH / spec.step_down), label
    assert pocket.island(slot(3601), r) <= CUT_TOL, (label, "island")
    # the outline as tests/test_gcode.py judges it: through the plate, nothing gouged or proud
    assert outline.gouge <= CUT_TOL and outline.proud <= CUT_TOL and all(p.outside for p in outline.passes), label
    assert outline.deepest == pytest.approx(-(THICKNESS + spec.breakthrough), abs=1e-9), label
    assert outline.rapid_clearance >= 0.0, label


CASES = [  # shape, tool diameter, dialect, direction
    ("circles", WIDTH, "linuxcnc", "climb"),
    ("circles", WIDTH, "grbl", "conventional"),
    ("circles", 4.0, "linuxcnc", "climb"),
    ("circles", 4.0, "grbl", "conventional"),
    ("trefoil", WIDTH, "linuxcnc", "conventional"),
    ("trefoil", 3.0, "grbl", "climb"),
]


@pytest.mark.parametrize(("shape", "diameter", "dialect", "direction"), CASES)
@pytest.mark.usefixtures("needs_rs274")
def test_groove_is_cut_to_its_exact_walls(shape, diameter, dialect, direction, tmp_path):
    pocket, walls, slot = groove(shape)
    spec = MachiningSpec(tool_diameter=diameter, thickness=THICKNESS, step_down=1.5, dialect=dialect, direction=direction)
    program = gcode_program(circle(RIM), spec, "groove_cam", pockets=(pocket,))
    header = _header(program)
    one_pass = diameter == WIDTH
    assert ("one pass along the pitch curve" in header) == one_pass
    assert ("two wall passes, slot cleared" in header) == (not one_pass)
    assert "ramp" in header and f"down to Z{-DEPTH:g}" in header
    if not one_pass:  # the stated stepover: the clearing passes split w - D evenly, each gap <= D / 2
        gaps = math.ceil((WIDTH - diameter) / (diameter / 2))
        stated = re.search(r"(\d+) clearing passes at stepover ([\d.]+)", header)
        assert int(stated.group(1)) == gaps - 1 and float(stated.group(2)) == pytest.approx((WIDTH - diameter) / gaps, abs=1e-4)
    assert ("G64" in program) == (dialect == "linuxcnc")
    _assert_groove_cut(program, spec, walls, slot, tmp_path, f"{shape} D={diameter} {dialect} {direction}")


@pytest.mark.usefixtures("needs_rs274")
def test_the_simulation_sees_a_wall_left_standing_and_a_missing_level(tmp_path):
    """The checks above can fail: a program cut with a tool 0.01 mm narrower than the groove but
    written as if it were the groove's width leaves 5 um on each wall; a program whose last level
    is missing leaves the floor 0.5 mm high (both found by the simulation, closed-form numbers)."""
    pocket, walls, slot = groove("circles")
    spec = MachiningSpec(tool_diameter=WIDTH, thickness=THICKNESS, step_down=1.5)
    program = gcode_program(circle(RIM), spec, pockets=(pocket,))
    narrower = simulate_pockets(program, circle(RIM), walls, WIDTH / 2 - 0.005, tmp_path).pocket
    assert all(v == pytest.approx(0.005, abs=1e-4) for v in narrower.proud.values())
    last = program.index("(pocket 'groove' level 3 of 3")
    cut = program[:last] + program[program.index("(pass 1 of", last):]
    shallow = simulate_pockets(cut, circle(RIM), walls, WIDTH / 2, tmp_path).pocket
    assert shallow.deepest == pytest.approx(-3.0) and len(shallow.levels) == 2


def test_the_stated_width_tolerance_chooses_the_strategy():
    """The header states the tolerance within which the tool counts as the groove's width;
    just inside it: one pass; just outside, smaller: two wall passes; larger: refused."""
    pocket, _, _ = groove("circles")
    spec = MachiningSpec(tool_diameter=WIDTH, thickness=THICKNESS)
    tol = float(re.search(r"tool diameter = width within ([\d.e-]+)", gcode_program(circle(RIM), spec, pockets=(pocket,))).group(1))
    assert 0 < tol <= spec.chord_tol

    def strategy(diameter: float) -> str:
        program = gcode_program(circle(RIM), dataclasses.replace(spec, tool_diameter=diameter), pockets=(pocket,))
        return "one" if "one pass along the pitch curve" in program else "two"

    assert strategy(WIDTH - 0.9 * tol) == "one" and strategy(WIDTH + 0.9 * tol) == "one"
    assert strategy(WIDTH - 1.1 * tol) == "two"
    with pytest.raises(ParameterError, match="tool_diameter"):
        gcode_program(circle(RIM), dataclasses.replace(spec, tool_diameter=WIDTH + 1.1 * tol), pockets=(pocket,))


def _cam_result(pocket: Pocket):
    """A CamResult as the pipeline hands it to the ngc writer: the rim and the groove."""
    from camgen.body import BodySpec
    from camgen.kinds.base import BuiltCam, CamSpec, CheckSettings
    from camgen.results import CamResult

    body = BodySpec(thickness=THICKNESS)
    built = BuiltCam("groove_cam", "motion_law", circle(RIM), {}, body, pockets=(pocket,))
    return CamResult(CamSpec("groove_cam", "motion_law", None, body, CheckSettings(), form="groove"), built)


def test_a_tool_wider_than_the_groove_is_refused_naming_the_key_and_the_width():
    """Through the ngc writer: the error names machining.tool_diameter_mm, its value and the
    valid range <= the width; the width quoted is itself accepted (one pass)."""
    from camgen.outputs import OutputSpec
    from camgen.writers import RunSettings, gcode

    cam = _cam_result(groove("circles")[0])
    run = RunSettings("s", OutputSpec(formats=("ngc",)), MachiningSpec(tool_diameter=12.0, thickness=THICKNESS))
    with pytest.raises(ParameterError) as err:
        gcode(cam, run, "ngc")
    assert err.value.name == "machining.tool_diameter_mm" and err.value.value == 12.0
    valid = re.fullmatch(r"<= ([\d.]+) mm for cam 'groove_cam'", err.value.valid)
    assert valid and float(valid.group(1)) == pytest.approx(WIDTH, abs=1e-9)
    accepted = dataclasses.replace(run, machining=dataclasses.replace(run.machining, tool_diameter=float(valid.group(1))))
    assert "one pass along the pitch curve" in gcode(cam, accepted, "ngc")
    with pytest.raises(ParameterError) as err:
        gcode(cam, dataclasses.replace(run, machining=dataclasses.replace(run.machining, tool_diameter=4.0, cutter_compensation=True)), "ngc")
    assert err.value.name == "machining.cutter_compensation" and "pockets" in str(err.value)


def test_a_wall_the_tool_cannot_fit_is_refused_naming_its_least_radius():
    """An inner wall of four lobes (radius 15 mm) joined by concave arcs of radius 10 mm (circle
    geometry, tests/test_gcode.py): a 24 mm tool is refused naming the least radius 10 mm and the
    range <= 20 mm; the largest tool the message allows makes the pass along that wall."""
    from test_gcode import lobes

    pocket = Pocket("groove", (Wall("GROOVE_OUTER", circle(80.0)), Wall("GROOVE_INNER", lobes())), DEPTH, 30.0, circle(62.0))
    spec = MachiningSpec(tool_diameter=24.0, thickness=THICKNESS, step_down=DEPTH)
    with pytest.raises(ParameterError) as err:
        gcode_program(circle(RIM + 30), spec, pockets=(pocket,))
    assert err.value.name == "tool_diameter" and "GROOVE_INNER" in str(err.value)
    assert float(re.search(r"least concave radius ([\d.]+) mm", str(err.value)).group(1)) == pytest.approx(10.0, rel=1e-6)
    largest = float(re.fullmatch(r"<= ([\d.]+) mm", err.value.valid).group(1))
    assert 19.99 <= largest < 20.0
    program = gcode_program(circle(RIM + 30), dataclasses.replace(spec, tool_diameter=largest), pockets=(pocket,))
    assert "two wall passes, slot cleared" in program


# ---------------------------------------------------------------------------------------------
# A pocket of one closed wall: a stadium (a straight slot closed by half circles), exact lines and arcs
# ---------------------------------------------------------------------------------------------
STADIUM_HALF_LENGTH = 30.0


def _segment(p, q) -> Spline:
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    length = float(np.hypot(*(q - p)))
    return Spline.hermite(np.array([0.0, length]), np.stack([p, q]), np.stack([(q - p) / length] * 2))


def stadium() -> tuple[Pocket, dict, callable]:
    """A slot of width WIDTH along the segment from (-30, 0) to (30, 0), closed by half circles
    about its ends: its one wall (exact lines and arcs), its open centre (the segment), the wall
    densely sampled for the simulation (chords on lines are exact, on the arcs of radius w/2 their
    sagitta is s^2 / (8 w/2)), and ``slot(n)``: points of its floor."""
    a, h = STADIUM_HALF_LENGTH, WIDTH / 2
    wall = Contour([_segment((-a, -h), (a, -h)), Arc((a, 0.0), h, -math.pi / 2, math.pi), _segment((a, h), (-a, h)),
                    Arc((-a, 0.0), h, math.pi / 2, math.pi)])
    pocket = Pocket("slot", (Wall("SLOT", wall),), DEPTH, WIDTH, None, CLEARANCE, centre_path=(_segment((-a, 0.0), (a, 0.0)),))
    step = 0.002
    x = np.linspace(-a, a, int(2 * a / step) + 1)
    t = np.linspace(-math.pi / 2, math.pi / 2, int(math.pi * h / step) + 1)[1:-1]
    dense = np.vstack([np.stack([x, np.full_like(x, -h)], axis=1), np.stack([a + h * np.cos(t), h * np.sin(t)], axis=1),
                       np.stack([x[::-1], np.full_like(x, h)], axis=1), np.stack([-a - h * np.cos(t), -h * np.sin(t)], axis=1)])

    def slot(n: int) -> np.ndarray:
        gx, gy = np.meshgrid(np.linspace(-a - h, a + h, n), np.linspace(-h, h, 61))
        pts = np.stack([gx.ravel(), gy.ravel()], axis=1)
        inside = (np.abs(pts[:, 0]) <= a) | (np.hypot(np.abs(pts[:, 0]) - a, pts[:, 1]) <= h)
        return pts[inside]

    return pocket, {"SLOT": Sampled(dense, (math.pi * h / (t.size + 1)) ** 2 / (8 * h))}, slot


@pytest.mark.parametrize(("diameter", "dialect", "direction"), [(WIDTH, "linuxcnc", "climb"), (WIDTH, "grbl", "conventional"),
                                                                  (4.0, "linuxcnc", "climb"), (2.5, "grbl", "conventional")])
@pytest.mark.usefixtures("needs_rs274")
def test_a_pocket_of_one_wall_is_cut_to_its_exact_wall(diameter, dialect, direction, tmp_path):
    """rs274 runs the program; a tool of the slot's width goes along the open centre there and
    back, a narrower one clears the slot by the wall's inward offsets (the stated count and
    stepover: (w/2 - r) split evenly, each <= D/2) and finishes along the wall; the simulation
    leaves the exact wall within 1 um (no gouge, nothing proud), every cut inside it, the floor
    at the depth without islands, each level ramped from the previous floor."""
    pocket, walls, slot = stadium()
    spec = MachiningSpec(tool_diameter=diameter, thickness=THICKNESS, step_down=1.5, dialect=dialect, direction=direction)
    program = gcode_program(circle(RIM), spec, "slot_plate", pockets=(pocket,))
    header = _header(program)
    one_pass = diameter == WIDTH
    assert ("one pass along the pitch curve" in header and "run down to its end and back" in header) == one_pass
    assert ("pocket cleared, one wall pass" in header) == (not one_pass)
    if not one_pass:
        inset = WIDTH / 2 - diameter / 2
        gaps = math.ceil(inset / (diameter / 2))
        stated = re.search(r"(\d+) clearing passes at stepover ([\d.]+)", header)
        assert int(stated.group(1)) == gaps - 1 and float(stated.group(2)) == pytest.approx(inset / gaps, abs=1e-4)
    _assert_groove_cut(program, spec, walls, slot, tmp_path, f"stadium D={diameter} {dialect} {direction}")


def test_the_stated_width_tolerance_chooses_the_strategy_of_a_one_wall_pocket():
    """As for a groove: within the stated tolerance of the width, one pass along the open centre;
    just outside, smaller: the pocket cleared; larger: refused naming tool_diameter and <= the
    width; a one-wall pocket without a centre cannot be cut in one pass (a GeometryError names it)."""
    from camgen.errors import GeometryError

    pocket, _, _ = stadium()
    spec = MachiningSpec(tool_diameter=WIDTH, thickness=THICKNESS)
    tol = float(re.search(r"tool diameter = width within ([\d.e-]+)", gcode_program(circle(RIM), spec, pockets=(pocket,))).group(1))

    def strategy(diameter: float) -> str:
        program = gcode_program(circle(RIM), dataclasses.replace(spec, tool_diameter=diameter), pockets=(pocket,))
        return "one" if "one pass along the pitch curve" in program else "cleared" if "pocket cleared" in program else "?"

    assert strategy(WIDTH - 0.9 * tol) == "one" and strategy(WIDTH + 0.9 * tol) == "one"
    assert strategy(WIDTH - 1.1 * tol) == "cleared"
    with pytest.raises(ParameterError) as err:
        gcode_program(circle(RIM), dataclasses.replace(spec, tool_diameter=WIDTH + 1.1 * tol), pockets=(pocket,))
    assert err.value.name == "tool_diameter" and float(re.fullmatch(r"<= ([\d.]+) mm", err.value.valid).group(1)) == pytest.approx(WIDTH)
    with pytest.raises(GeometryError, match="needs its centre"):
        gcode_program(circle(RIM), spec, pockets=(dataclasses.replace(pocket, centre_path=None),))
