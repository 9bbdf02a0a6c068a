"""4th-axis G-code (RS274/NGC, LinuxCNC) milling a barrel cam's rib with a rotary A axis.

The machine setup, the stations, the feed and the error budget are the groove's
(:mod:`camgen.export.gcode_barrel`: X = cam z, Z radial, the cam turned by A about the X axis,
G93 inverse time, stations from the chord tolerance at the rim); this module plans the passes.

The stock is the cylinder turned to the rim radius ``R_o``; the body is the root cylinder
(radius ``R_i``) with the rib on it (:class:`camgen.synthesis.barrel.BarrelRib`): the rib's
lower face is the upper envelope of the lower roller (its axis at ``z_c(theta) - o``), its
upper face the lower envelope of the upper roller (``z_c + o``), ``o = rib_width / 2 + w``,
``w = Rr + c / 2``.

Passes (each a pass of the groove's program: helical roughing turns from the rim down by at most
``step_down`` a turn, then one turn on its floor; A runs on from pass to pass, never unwound):

* **The faces' passes.**  An end mill of diameter ``2 w`` with its axis on a roller's axis is
  that roller widened by half the clearance (down to its tip), so the union of its poses along
  ``X = z_c - o`` is the union of the lower roller's solids, whose upper envelope is the lower
  face exactly; along ``X = z_c + o`` the upper face.  The tip runs on the groove's floor
  ``Z_f = sqrt(R_i^2 - (D/2)^2)`` (:func:`camgen.synthesis.barrel.floor_radius`): a face point at
  radius ``r >= R_i`` meets the tool at a tangential offset up to ``D/2``, where the flat tip
  reaches ``sqrt(Z_f^2 + (D/2)^2) = R_i``, so the faces are cut down to the root; along each
  roller's track the root cylinder is cut up to ``R_i - Z_f`` below the root radius (the rollers
  do not run on it; the program's header states it).
* **The clearing passes.**  Beyond the rollers' reach, from the rib to the cylinder's ends, the
  stock is cleared by passes along ``X = z_c - o - k p`` (below the rib) and ``z_c + o + k p``
  (above it), ``k = 1 .. n``, the stepover ``p = SLOT_STEPOVER D`` (< D); their tip runs on the
  root radius ``R_i``.  A cam point passes under the tool's axis (tangential offset 0) once a turn,
  where the flat tip at ``Z`` removes it when its radius is ``>= Z`` and it lies within ``D/2`` of
  the pass's X along the axis: each pass clears a band ``D`` wide along z down to its tip, the
  bands of neighbouring passes overlap (``p < D``), and ``n`` is the least count whose last band
  reaches the end face at every cam angle.  So everything from the rib to the ends is cut down to
  the root radius, and not below it, by the clearing passes.
  *A clearing pass cannot touch the rib*: its poses are the face pass's poses translated by
  ``k p`` along X away from the rib, so the region it sweeps is the face pass's translated (a
  union of translates is the translate of the union), and its envelope on the rib's side is the
  face's envelope translated away from the rib by ``k p > 0``.

**An oscillating follower** (:class:`~camgen.synthesis.barrel.BarrelRib`: both rollers on the
arm's end, ``o`` either side of it along the arm's normal, each axis the line ``{(t, e_k, z_k)}``
of its groove :meth:`~camgen.synthesis.barrel.BarrelRib.roller`).  Each face's pass is that
roller's groove program's pass (:func:`camgen.export.gcode_barrel.tool_path`): the tool's axis on
the roller's, ``X = z_k``, ``Y = -e_k``, the tip on ``sqrt(R_i^2 - (|e_k| + D/2)^2)``, the same
argument as the groove's (the tool is the widened roller, so its poses' union is the roller's
union, whose envelope on the rib's side is the face).  The clearing passes are the face pass's
poses translated along X by ``k p`` away from the rib (the same ``Y = -e_k``), their tip on the
root radius ``R_i``: the translation argument above holds unchanged (the cam turns about its
axis, so a translation along it commutes with the turning), so *they cannot touch the rib*, and
a flat tip at ``Z = R_i`` reaches no radius below ``R_i`` anywhere (a tip point at ``Y`` lies at
radius ``sqrt(R_i^2 + Y^2)``).  Their reach: a cam point passes ``Y = 0`` once a turn, at radius
``r >= R_i`` above the tip, where the tool (its axis at ``Y = -e_k``) spans ``X -+ h``,
``h = sqrt((D/2)^2 - e_k^2)``: each pass clears a band ``2 h`` wide (not ``D``: the tool's axis
is off the cam's), so the stepover is ``p = SLOT_STEPOVER x 2 h_min`` (``h_min`` the least ``h``
over the turn on that side: neighbouring bands overlap by ``h_min``), and ``n`` the least count
whose last band reaches the end face at every station (between stations X and ``e_k`` run
linearly and ``X -+ h`` is convex there, so the stations bound it).  The face pass's band (its
tip below ``R_i``) joins its own cut from the face.  A roller whose tangential offset reaches
the tool's radius leaves no band at ``Y = 0``: refused (:class:`GeometryError`).

Direction (spindle M3, as the groove's): with A increasing the tool's +X side climbs, so the
faces are climb milled (``direction = "climb"``) with A increasing below the rib (the lower face
on the tool's +X side) and decreasing above it; ``"conventional"`` reverses both.  The passes
below the rib run first, the face's pass then outwards, then those above it.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError, ParameterError, ceil_significant
from camgen.export.gcode_barrel import (BarrelToolPath, a_decimals, check_tool, framed, named_program, tool_path, turn_blocks,
                                        width_tol)
from camgen.export.gcode_barrel import writer as groove_writer
from camgen.export.gcode_moves import comment
from camgen.export.gcode_spec import BLEND_SHARE, FIT_SHARE, ROUNDING_SHARE, MachiningSpec, depth_passes, rounding_error

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["RibPass", "arm_band", "arm_stepover", "rib_passes", "rib_program", "rib_stepover", "writer"]

#: What the rib's tool must match, as a refusal names it.
ROLLER_WIDTH = "the rollers' diameter 2 x roller radius + clearance"
#: Why another tool is refused for a rib.
RIB_ONE_PASS = ("a barrel cam's rib faces are cut by a tool of the rollers' diameter along their axes' paths; a wall-offset strategy "
                "for another tool is not built")


@dataclass(frozen=True)
class RibPass:
    """One pass of a rib's program: ``side`` (-1 below the rib, +1 above), ``index`` (0 the face's
    pass along a roller's axis, ``k >= 1`` the k-th clearing pass outwards), ``offset`` (mm, signed:
    the tool axis' X less the pitch line's ``z_c``), ``path`` (the stations, the tip's floor and
    the roughing turns; its ``x`` the pitch line's) and ``floor_what`` naming its last turn."""

    side: int
    index: int
    offset: float
    path: BarrelToolPath
    floor_what: str
    #: An oscillating follower's rib: the pass's ``path`` is its roller's own (``x`` that roller's
    #: axis height ``z_k``, ``y = -e_k``) and ``offset`` is along X from it.
    on_roller: bool = False

    @property
    def label(self) -> str:
        where = "below" if self.side < 0 else "above"
        what = f"{'lower' if self.side < 0 else 'upper'} face" if self.index == 0 else f"clearing pass {self.index} {where} the rib"
        if self.on_roller:
            roller = "lower" if self.side < 0 else "upper"
            shift = f" {'-' if self.offset < 0 else '+'} {abs(self.offset):.6g}" if self.offset else ""
            return f"{what}, X = the {roller} roller's axis height{shift}, Y = -its tangential offset: "
        return f"{what}, X = z_c {'-' if self.offset < 0 else '+'} {abs(self.offset):.6g}: "


#: Longest header comment line (characters): LinuxCNC reads lines of up to 256.
COMMENT_WIDTH = 200


def _comment_lines(text: str) -> list[str]:
    """``text`` as RS274 comments of at most :data:`COMMENT_WIDTH` characters each, broken at spaces."""
    import textwrap

    return [comment(part) for part in textwrap.wrap(text, COMMENT_WIDTH - 2, break_long_words=False, break_on_hyphens=False)]


def rib_stepover(spec: MachiningSpec) -> float:
    """The clearing passes' stepover along X (mm): ``SLOT_STEPOVER`` times the tool diameter (the
    plate cams' slot clearing's, below the diameter so that neighbouring bands overlap)."""
    from camgen.export.gcode_pockets import SLOT_STEPOVER

    return SLOT_STEPOVER * spec.tool_diameter


def _clearing_count(reach: float, stepover: float) -> int:
    """The least ``n >= 0`` with ``reach - n stepover <= 0`` (mm)."""
    return max(0, math.ceil(reach / stepover - 1e-9))


def rib_passes(rib: Any, spec: MachiningSpec, cam: str = "cam") -> tuple[RibPass, ...]:
    """The passes milling ``rib`` (a :class:`camgen.synthesis.barrel.BarrelRib`) with the tool of
    ``spec``, in the program's order (module notes); the spec is checked first (:func:`rib_program`).
    Raises :class:`GeometryError` (naming ``cam``) for an oscillating follower's roller riding off
    the station's radial line by the tool's radius or more (:func:`arm_band`)."""
    if rib.layout.motion == "oscillating":
        return _arm_passes(rib, spec, cam)
    flip = {"climb": "conventional", "conventional": "climb"}
    o, r = rib.roller_offset, spec.tool_radius
    p = rib_stepover(spec)
    s_min, s_max = rib.groove.law.s_bounds
    z_low, z_high = rib.layout.z0 + s_min, rib.layout.z0 + s_max  # the pitch line's extremes (translating: z0 + s)
    root, rim = rib.root_radius, rib.rim_radius
    clearing_turns = int(depth_passes(rim - root, spec.step_down))
    passes: list[RibPass] = []
    for side, direction, reach in ((-1, spec.direction, z_high - o - r), (1, flip[spec.direction], rib.length - (z_low + o + r))):
        base = tool_path(rib.groove, dataclasses.replace(spec, direction=direction))
        passes.append(RibPass(side, 0, side * o, base, "finishing turn on the floor: the face"))
        clearing = dataclasses.replace(base, floor=np.full_like(base.floor, root), turns=clearing_turns)
        for k in range(1, _clearing_count(reach, p) + 1):
            passes.append(RibPass(side, k, side * (o + k * p), clearing, "turn on the root radius"))
    return tuple(passes)


def arm_band(path: BarrelToolPath, tool_radius: float, cam: str = "cam") -> np.ndarray:
    """Half the band ``h = sqrt((D/2)^2 - e^2)`` (mm) a pass along ``path`` (the tool's axis at
    ``Y = path.y = -e``) clears at ``Y = 0``, at its stations (module notes); GeometryError where
    ``|e|`` reaches the tool's radius."""
    reach = float(np.max(np.abs(path.y)))
    if not reach < tool_radius:
        raise GeometryError(f"cam '{cam}': a roller of the rib rides {reach:.6g} mm off the radial line through the station, not inside "
                            f"the tool's radius {tool_radius:g} mm: the clearing passes' flat tip on the root radius cannot clear the "
                            "root beside it")
    return np.sqrt(tool_radius * tool_radius - path.y * path.y)


def arm_stepover(band: np.ndarray) -> float:
    """An oscillating rib's clearing stepover along X (mm): ``SLOT_STEPOVER`` times the least band
    ``2 h`` (``band``: :func:`arm_band`'s ``h``; the translating rib's ``SLOT_STEPOVER D`` where
    ``e = 0``)."""
    from camgen.export.gcode_pockets import SLOT_STEPOVER

    return SLOT_STEPOVER * 2.0 * float(np.min(band))


def _arm_passes(rib: Any, spec: MachiningSpec, cam: str) -> tuple[RibPass, ...]:
    """The passes of an oscillating follower's rib (module notes: each face's pass along its
    roller's axis, the clearing passes its poses translated along X away from the rib)."""
    flip = {"climb": "conventional", "conventional": "climb"}
    r, root = spec.tool_radius, rib.root_radius
    clearing_turns = int(depth_passes(rib.rim_radius - root, spec.step_down))
    passes: list[RibPass] = []
    for side, direction in ((-1, spec.direction), (1, flip[spec.direction])):
        base = tool_path(rib.roller(side), dataclasses.replace(spec, direction=direction))
        passes.append(RibPass(side, 0, 0.0, base, "finishing turn on the floor: the face", on_roller=True))
        h = arm_band(base, r, cam)
        p = arm_stepover(h)
        # the band's far edge from the end face: below the rib X - h (down to z = 0), above it length - (X + h)
        reach = float(np.max(base.x - h)) if side < 0 else float(np.max(rib.length - (base.x + h)))
        clearing = dataclasses.replace(base, floor=np.full_like(base.floor, root), turns=clearing_turns)
        for k in range(1, _clearing_count(reach, p) + 1):
            passes.append(RibPass(side, k, side * k * p, clearing, "turn on the root radius", on_roller=True))
    return tuple(passes)


def _refuse_long(passes: tuple[RibPass, ...], spec: MachiningSpec) -> None:
    """Refuse a program of more than :data:`camgen.export.gcode.MAX_PROGRAM_MOVES` moves naming the
    least ``step_down`` that fits (each pass's turns ``ceil(depth / s) + 1 <= depth / s + 2``), or
    ``chord_tol`` when none does."""
    from camgen.export.gcode import MAX_PROGRAM_MOVES

    per_turn = max(q.path.a.size - 1 for q in passes)
    moves = sum((q.path.turns + 1) * (q.path.a.size - 1) for q in passes)  # at most: steps finer than the decimals are dropped
    if moves <= MAX_PROGRAM_MOVES:
        return
    why = (f"{len(passes)} passes of {sum(q.path.turns + 1 for q in passes)} turns of up to {per_turn} moves would make {moves} lines, "
           f"more than the {MAX_PROGRAM_MOVES} a program may hold")
    spare = MAX_PROGRAM_MOVES // per_turn - 2 * len(passes)
    if spare >= 1:
        depth = sum(q.path.rim - float(q.path.floor.min()) for q in passes)
        raise ParameterError("step_down", spec.step_down, f">= {ceil_significant(depth / spare, 3):.3g} mm", why)
    raise ParameterError("chord_tol", spec.chord_tol, "a larger chord_tol", why)


def rib_program(rib: Any, spec: MachiningSpec, cam: str = "cam", scene: str = "") -> str:
    """RS274/NGC program text milling ``rib`` (a :class:`camgen.synthesis.barrel.BarrelRib`) on a
    4th axis with the tool of ``spec`` (module notes); ``spec`` is final (the scene reader checked
    its decimals against its chord tolerance).

    Raises
    ------
    ParameterError
        A conical roller (``cams.<cam>.roller_shape``); a tool that is not the rollers' diameter
        ``2 w`` within :func:`camgen.export.gcode_barrel.width_tol` (``tool_diameter``); the grbl
        dialect; cutter compensation; a program of more than
        :data:`camgen.export.gcode.MAX_PROGRAM_MOVES` moves (``step_down``).
    GeometryError
        A tool whose radius is not inside the root radius.
    """
    from camgen import __version__
    from camgen.export.gcode import blend_word

    if spec.program_unit != 1.0:  # inch: the same program of the scaled rib and spec (camgen.export.gcode_units)
        from camgen.export.gcode_units import groove_in_program_units, scaled_rib

        return groove_in_program_units(rib_program, rib, spec, cam, scene, scaled_rib)
    check_tool(rib.groove, spec, cam, ROLLER_WIDTH, RIB_ONE_PASS)
    passes = rib_passes(rib, spec, cam)
    _refuse_long(passes, spec)
    arm = rib.layout.motion == "oscillating"
    d = spec.decimals
    rim, root = rib.rim_radius, rib.root_radius
    da = a_decimals(d, rim)
    safe = rim + spec.safe_z
    body: list[str] = []
    a_start = 0.0
    first_x = first_y = 0.0
    for i, q in enumerate(passes):
        xs = np.round(q.path.x + q.offset, d) + 0.0
        ys = np.round(q.path.y, d) + 0.0
        if i == 0:
            first_x, first_y = float(xs[0]), float(ys[0])
        else:  # up, over to the next pass's start (A where the last pass ended), down to the rim
            over = f"G0 X{xs[0]:.{d}f} Y{ys[0]:.{d}f}" if arm else f"G0 X{xs[0]:.{d}f}"
            body.append(f"G94\nG0 Z{safe:.{d}f}\n{over}\nG1 Z{rim:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}\nG93\n")
        body.extend(turn_blocks(q.path, xs, ys, d, da, spec.feed, rim, a_start, oscillating=True if arm else None, label=q.label,
                                floor_what=q.floor_what))
        a_start += float(np.sign(q.path.a[-1])) * 360.0 * (q.path.turns + 1)

    chord_tol = spec.chord_tol
    blend = blend_word(BLEND_SHARE * chord_tol, d)
    unit = 10.0 ** (-d)
    rounding = math.hypot(0.5 * unit, 0.5 * unit + rim * math.radians(0.5 * 10.0 ** (-da)))
    assert rounding <= rounding_error(d) <= ROUNDING_SHARE * chord_tol * (1 + 1e-12)  # the spec's decimals check covers it
    faces = [q for q in passes if q.index == 0]
    floor = float(min(float(q.path.floor.min()) for q in faces))
    counts = {side: sum(1 for q in passes if q.side == side and q.index > 0) for side in (-1, 1)}
    sigma = rib.layout.sigma
    step_deg = max(float(np.max(np.abs(np.diff(q.path.a)))) for q in faces)
    stations = max(q.path.a.size - 1 for q in faces)
    climb = spec.direction == "climb"
    if arm:
        step_text = " and ".join(f"{abs(next(q.offset for q in passes if q.side == side and q.index == 1)):.6g} {where}"
                                 for side, where in ((-1, "below"), (1, "above")) if counts[side])
        y_most = max(float(np.max(np.abs(q.path.y))) for q in faces)
        axes = (f"the rib's faces are the envelopes of the two rollers on the oscillating arm's end, their axes {rib.roller_offset:.10g} "
                "[rib width / 2 + roller radius + clearance / 2] either side of it along the arm's normal: each roller's axis at "
                "X = its height z_k, Y = -e_k, its tangential offset")
        clear = (f"clearing: {counts[-1]} passes below the rib and {counts[1]} above it, each the face pass's poses [Y = -e_k too] "
                 f"offset a further stepover [{step_text or 'none'}: half the least band 2 sqrt[[D/2]^2 - e_k^2] the tool spans "
                 f"at Y0, e_k up to {y_most:.4g}] along X away from the rib, the tip on the root radius Z{root:.{d}f}, the last one "
                 "reaching the cylinder's end face: everything between the rib and the ends cleared to the root radius, nothing "
                 "below it; a pass offset away from the rib sweeps the face pass's region translated away from the rib, so it "
                 "cannot touch the rib")
    else:
        axes = (f"the rib's faces are the envelopes of the two rollers, their axes at X = z_c -+ "
                f"{rib.roller_offset:.10g} [rib width / 2 + roller radius + clearance / 2], z_c the pitch line")
        clear = (f"clearing: {counts[-1]} passes below the rib and {counts[1]} above it, each offset a further stepover "
                 f"{rib_stepover(spec):.6g} [half the tool diameter] along X away from the rib, the tip down to the root radius "
                 f"Z{root:.{d}f}, the last one reaching the cylinder's end face: everything between the rib and the ends cleared to the "
                 "root radius; a pass offset away from the rib sweeps the face pass's region translated away from the rib, so it "
                 "cannot touch the rib")
    lines = [
        (f"camgen {__version__}: barrel cam '{cam}' with a rib" + (f", scene '{scene}'" if scene else "") + "; LinuxCNC, 4th axis"),
        ("machine: the cam's axis on the A axis along X; X0 at the cam's bottom face [cam z = 0], +X to its top face; "
                "Z radial: the tool tip's distance from the A axis; Y0 through the axis"
                + ("; the tool's axis at Y = -e_k, the roller's tangential offset" if arm else "")),
        (f"units {spec.units}, A in degrees: the cam turned by A counter-clockwise seen from +X [right-hand rule]; at A the tool is over cam "
                f"polar angle -A, cam angle theta = {'+' if sigma > 0 else '-'}A [rotation {'ccw' if sigma > 0 else 'cw'}]"),
        # one line (< COMMENT_WIDTH): an inch program's units line follows it (camgen.export.gcode_units)
        "A runs on from pass to pass, not unwound",
        (f"tool: end mill diameter {spec.tool_diameter:g} = the rollers' diameter + clearance {2.0 * rib.half_width:.10g} within "
                f"{width_tol(spec):.3g}, axis radial; {axes}"),
        (f"stock: cylinder turned to the rim radius {rim:g}, length {rib.length:g}; the body: the root cylinder radius {root:g} "
                f"with the rib on it up to the rim"),
        (f"faces: one pass along each roller's axis, the lower face first: the tool there is the roller, so it sweeps the exact "
                f"face; its tip down to Z{floor:.{d}f}, where the flat tip reaches the face at the root radius: along each roller's "
                f"track the root is cut up to {root - floor:.4g} below the root radius"),
        clear,
        (f"each pass: helical roughing turns down <= {spec.step_down:g} a turn from the rim, then a turn on its floor; "
                f"{spec.direction} milling of both faces: below the rib A {'increasing' if climb else 'decreasing'}, above it A "
                f"{'decreasing' if climb else 'increasing'}"),
        (f"feed: G93 inverse time, F = {spec.feed:g} / [move length at the rim radius: sqrt[[R dA]^2 + dX^2 + dY^2 + dZ^2]]"),
        (f"path tolerance {chord_tol:g} = stations {FIT_SHARE * chord_tol:.3g} [up to {stations} a turn, A step <= {step_deg:.4g} "
                f"deg, X {'Y ' if arm else ''}Z between stations and the rim chord] + {d} and {da} printed decimals {rounding:.3g} + G64 blending {blend} "
                f"+ tool width mismatch {0.5 * width_tol(spec):.3g}"),
        ("not used by this program: machining.lead_mm, lead_style, lead_radius_mm, breakthrough_mm, spline_mode, entry, ramp_angle_deg, stock_allowance_mm, holding_tabs"),
    ]
    header = "\n".join(line for text in lines for line in _comment_lines(text))
    return framed(header, body, spec, blend, safe, rim, (float(first_x), float(first_y)), d, da)


def writer(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """The barrel cam's ``ngc`` (:attr:`camgen.forms.base.CamForm.writers`): a rib's
    (``cam.built.rib``) milled by :func:`rib_program`, a groove's by
    :func:`camgen.export.gcode_barrel.writer`; errors name the scene keys."""
    rib = getattr(cam.built, "rib", None)
    if rib is None:
        return groove_writer(cam, run, fmt)
    return named_program(cam, run, lambda: rib_program(rib, run.machining, cam.name, run.scene_name))
