"""The shaft bore and keyway in a milling program (``linuxcnc``, ``grbl``, ``fanuc``): helical
interpolation of the bore, the keyway slotted with the same tool, or a header note that they are
left to another operation.

Settings (``[machining]``, checked in :mod:`camgen.export.bore_settings`): ``bore_operation`` =
``"helix"``, ``"drill"`` or ``"none"`` (default: ``"helix"`` when ``bore_tool_diameter`` is given, else
``"none"``: the programs of a scene without the bore keys cut no bore); ``bore_tool_diameter`` (mm; default: the outline's tool, no tool change);
``bore_tool_number`` (LinuxCNC and Fanuc: ``T<n> M6`` and ``G43 H<n>``; default the outline's
tool number + 1).  GRBL has no tool changer: the program stops (``M0``) with a comment naming the
tool to load, before the bore and before the outline.

The bore (radius ``R``, tool radius ``r``, axis at X0 Y0) is cut before the outline, while the
stock still holds the part, as a tool-centre path (no cutter compensation):

* tool-centre circles of radius ``rho_k = rho_n k / g`` (``k = 1 .. g``), ``rho_n = R - r`` the
  finishing circle, ``g`` the least count with a stepover ``rho_n / g <= BORE_STEPOVER * 2 r``:
  the first circle's disc covers the axis (``rho_1 <= r``) and neighbouring discs overlap, so no
  core is left to fall loose at the breakthrough;
* each circle is a **helix** from Z0 (the stock top) down to ``-(thickness + breakthrough)`` in
  ``ceil(depth / step_down)`` turns (pitch ``<= step_down``), written as half turns ``G2/G3`` with
  ``I J`` (never a full circle in one block), then a full circle (two half turns) at the bottom;
* climb milling (spindle ``M3``) runs counter-clockwise inside a hole (``G3``: the wall on the
  right of the travel), conventional clockwise (``G2``).

The tool enters each helix above the stock at ``(rho_k, 0)`` and every tool-centre position
stays within ``rho_n = R - r`` of the axis: the bore wall is never gouged.

``bore_operation = "drill"`` (linuxcnc, fanuc: GRBL has no canned cycle): ``G98 G83`` peck drilling
at the axis, pecks of ``step_down``, with a drill of the bore's diameter (its own tool, ``T M6``),
its point (:data:`DRILL_POINT_ANGLE`) through: the full diameter reaches the last pass's depth;
the keyway is then left to another operation.

The keyway (width ``w``, bottom at ``R + keyway_depth`` from the axis, along ``keyway_angle``) is
slotted with the bore tool where it fits (``2 r <= w``), in depth levels of at most ``step_down``
(each fed down inside the cleared bore): lanes parallel to the keyway's centre line at the
lateral offsets ``y_k`` evenly from ``-(w/2 - r)`` to ``w/2 - r`` (stepover <= ``BORE_STEPOVER *
2 r``), from the axis out to ``R + keyway_depth - r``; the first lane, the bottom and the last
lane are run as one pass (the finished walls on the right of the travel in climb milling), the
others out and back.  The keyway's two inner (bottom) corners are left at the tool radius ``r``;
the header says so.  A tool wider than the keyway leaves it to another operation (broach, wire
EDM): the header says so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camgen.errors import ParameterError, floor_significant
from camgen.export.bore_settings import bore_operation_of, bore_tool_number_of, outline_tool_number
from camgen.export.gcode_moves import comment
from camgen.export.gcode_spec import MM_PER_INCH, MachiningSpec, depth_passes

if TYPE_CHECKING:
    from camgen.body import BodySpec

__all__ = ["BORE_STEPOVER", "DRILL_POINT_ANGLE", "DRILL_R_PLANE", "MIN_BORE_TOOL", "MIN_HELIX_RADIUS", "BoreProgram", "bore_program", "helix_radii", "with_bore"]

#: Largest stepover between neighbouring helix circles and keyway lanes, as a fraction of the
#: tool diameter (below 1: the discs overlap, no core or rib is left between them).
BORE_STEPOVER = 0.5
#: Least radius (mm) of a helix circle: an arc of a smaller radius is hard to print and to run.
MIN_HELIX_RADIUS = 0.1
#: Least bore tool diameter (mm): its first circle (radius > a quarter of it when several) is a printable helix.
MIN_BORE_TOOL = 4.0 * MIN_HELIX_RADIUS
#: Point angle (deg) of the drill of ``bore_operation = "drill"``: the standard twist drill's 118 deg
#: (Machinery's Handbook, "Twist Drills"); its point reaches 0.3 x the diameter below the full diameter.
DRILL_POINT_ANGLE = 118.0
#: Height (mm) above the stock top of the drilling cycle's R plane (the pecks start there; at most safe_z).
DRILL_R_PLANE = 1.0


def _mm(spec: MachiningSpec) -> float:
    """One mm in the units of ``spec``'s lengths: 1/25.4 in an inch program's converted spec
    (:func:`camgen.export.gcode_units.program_spec`), else 1."""
    return 1.0 / MM_PER_INCH if spec.converted and spec.units == "inch" else 1.0


def helix_radii(bore_radius: float, tool_radius: float) -> np.ndarray:
    """Radii (mm, rising) of the tool-centre circles that clear a bore of ``bore_radius`` with a
    tool of ``tool_radius`` (module docstring): ``rho_n k / g``, ``rho_n = bore_radius - tool_radius``."""
    outer = bore_radius - tool_radius
    g = max(1, math.ceil(outer / (BORE_STEPOVER * 2.0 * tool_radius) - 1e-9))
    return outer * np.arange(1, g + 1) / g


@dataclass(frozen=True)
class BoreProgram:
    """The bore's part of a program: ``header`` comment lines; ``moves`` the blocks that cut it
    ('' when nothing is cut), inserted before the outline's tool is set up (``own_tool``) or after
    (the outline's tool cuts it); ``count`` the moves."""

    header: tuple[str, ...]
    moves: str
    own_tool: bool
    count: int


def _tool_words(spec: MachiningSpec, diameter: float, what: str = "bore tool") -> tuple[list[str], list[str], str]:
    """Blocks before and after the bore (tool change, spindle) and the header's tool text;
    ``what`` the bore's tool (a drill has its own; an end mill only with ``bore_tool_diameter``)."""
    safe, rpm = f"{spec.safe_z:.{spec.decimals}f}", f"{spec.spindle_rpm:.0f}"
    if spec.bore_tool_diameter is None and what == "bore tool":
        return [], [], f"the outline's tool [diameter {spec.tool_diameter:g}], no tool change"
    main, bore = outline_tool_number(spec.tool_number), bore_tool_number_of(spec.bore_tool_number, spec.tool_number)
    if spec.dialect == "fanuc":
        return ([f"T{bore} M06", f"S{rpm} M03", f"G0 G43 H{bore:02d} Z{safe}"], ["M05"],
                f"{what} T{bore} [diameter {diameter:g}, length offset H{bore:02d}], then T{main} for the outline")
    if spec.dialect == "linuxcnc":
        return ([f"T{bore} M6", f"G43 H{bore}", f"G0 Z{safe}", f"M3 S{rpm}"], ["M5", f"T{main} M6", f"G43 H{main}"],
                f"{what} T{bore} [diameter {diameter:g}, length offset H{bore}], then T{main} for the outline")
    return ([f"M0 (load the bore tool, diameter {diameter:g}; touch off Z0 on the stock top)", f"G0 Z{safe}", f"M3 S{rpm}"],
            ["M5", f"M0 (load the outline's tool, diameter {spec.tool_diameter:g}; touch off Z0 on the stock top)"],
            f"bore tool diameter {diameter:g}: GRBL has no tool changer, the program stops [M0] to load it and again to load "
            f"the outline's tool [diameter {spec.tool_diameter:g}]")


def _helix(rho: float, depth: float, spec: MachiningSpec) -> tuple[list[str], int, float]:
    """Blocks of one helix of radius ``rho`` from Z0 to ``-depth`` and the full circle there
    (half turns), its number of turns and pitch (mm)."""
    d = spec.decimals
    turns = int(depth_passes(depth, spec.step_down))
    pitch = depth / turns
    word = "G3" if spec.direction == "climb" else "G2"
    halves = np.arange(1, 2 * turns + 3)  # 2 per turn, then the full circle at the bottom
    z = -np.minimum(0.5 * pitch * halves, depth)
    ends = np.where(halves % 2 == 1, -rho, rho)  # half turns from (rho, 0): (-rho, 0), (rho, 0), ...
    # the centre (the axis) from the previous end (-end): I = end, J = 0
    blocks = [f"G0 X{rho:.{d}f} Y{0.0:.{d}f}", f"G1 Z{0.0:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}"]
    blocks += [f"{word} X{xk:.{d}f} Y{0.0:.{d}f} Z{zk:.{d}f} I{xk:.{d}f} J{0.0:.{d}f}" for xk, zk in zip(ends, z)]
    blocks[2] += f" F{spec.feed:.{spec.feed_decimals}f}"
    blocks.append(f"G0 Z{spec.safe_z:.{d}f}")
    return blocks, turns, pitch


def _keyway(body: "BodySpec", depth: float, spec: MachiningSpec, radius: float) -> tuple[list[str], list[str]]:
    """Blocks slotting the keyway with a tool of ``radius`` (module docstring) and the header text."""
    d = spec.decimals
    w = body.keyway_width
    half = w / 2.0 - radius
    lanes = max(1, math.ceil(2.0 * half / (BORE_STEPOVER * 2.0 * radius) - 1e-9)) if half > 0.0 else 0
    ys = np.linspace(-half, half, lanes + 1) if lanes else np.zeros(1)
    if spec.direction != "climb":
        ys = ys[::-1]
    out = body.keyway_reach - radius
    c, s = math.cos(body.keyway_angle), math.sin(body.keyway_angle)

    def at(along: float, y: float) -> str:
        return f"X{along * c - y * s:.{d}f} Y{along * s + y * c:.{d}f}"

    # one level: first lane out, along the bottom, last lane in; the lanes between out and back
    level = [f"G1 {at(out, ys[0])} F{spec.feed:.{spec.feed_decimals}f}", f"G1 {at(out, ys[-1])}", f"G1 {at(0.0, ys[-1])}"] if ys.size > 1 else \
        [f"G1 {at(out, ys[0])} F{spec.feed:.{spec.feed_decimals}f}", f"G1 {at(0.0, ys[0])}"]
    for y in ys[1:-1]:
        level += [f"G1 {at(0.0, y)}", f"G1 {at(out, y)}", f"G1 {at(0.0, y)}"]
    n = int(depth_passes(depth, spec.step_down))
    zs = -np.minimum(spec.step_down * np.arange(1, n + 1), depth)
    home = f"G1 {at(0.0, ys[0])}"
    blocks = [f"G0 {at(0.0, ys[0])}"]
    for z in zs:
        if blocks[-1] != home and not blocks[-1].startswith("G0 "):  # back to the first lane's start, inside the bore
            blocks.append(home)
        blocks += [f"G1 Z{z:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}", *level]
    blocks.append(f"G0 Z{spec.safe_z:.{d}f}")
    text = [f"keyway {w:g} wide to {body.keyway_reach:g} from the axis at {math.degrees(body.keyway_angle):g} deg: slotted with the bore "
            f"tool after the bore, {n} levels of <= {spec.step_down:g} fed down inside the bore, lanes: {ys.size}",
            f"keyway: its two inner corners left at the tool radius {radius:g}"]
    return blocks, text


def bore_program(body: "BodySpec | None", spec: MachiningSpec, depth: float) -> BoreProgram | None:
    """The bore's blocks and header of a program cutting to ``depth`` mm (thickness +
    breakthrough); None without a body, or for a cam without a bore when no bore is asked for
    (asked for, the header says the cam has none).

    Raises
    ------
    ParameterError
        ``bore_tool_diameter`` (or ``tool_diameter`` when the outline's tool cuts the bore) outside
        ``[4 MIN_HELIX_RADIUS, bore diameter - 2 MIN_HELIX_RADIUS]``.
    """
    if body is None:
        return None
    if body.bore_diameter <= 0.0:  # bore settings given for a scene whose other cams have a bore: said, not silent
        if bore_operation_of(spec.bore_operation, spec.bore_tool_diameter, spec.dialect) == "none":
            return None
        return BoreProgram((comment("the cam has no bore: the bore settings cut nothing here"),), "", False, 0)
    keyway = body.keyway_width > 0.0
    what = "bore and keyway" if keyway else "bore"
    operation = bore_operation_of(spec.bore_operation, spec.bore_tool_diameter, spec.dialect)
    if operation == "drill":
        return _drill(body, spec, depth)
    if operation == "none":
        return BoreProgram((comment(f"the {what} [diameter {body.bore_diameter:g}] are not cut: left to another operation "
                                    "[bore_operation = none; bore_tool_diameter_mm mills the bore by a helix]"),), "", False, 0)
    name, diameter = ("bore_tool_diameter", spec.bore_tool_diameter) if spec.bore_tool_diameter is not None else \
        ("tool_diameter", spec.tool_diameter)
    radius, bore = diameter / 2.0, body.bore_diameter / 2.0
    mm = _mm(spec)  # the least sizes are in mm: in an inch program's spec, in inches
    low, high = MIN_BORE_TOOL * mm, body.bore_diameter - 2.0 * MIN_HELIX_RADIUS * mm
    if not low <= diameter <= high:
        raise ParameterError(name, diameter, f"{low:g} mm <= diameter <= bore diameter - {2.0 * MIN_HELIX_RADIUS:g} = "
                                             f"{floor_significant(high, 6):g} mm" if high > low else "a cam with a larger bore",
                             f"the helix that mills the bore [diameter {body.bore_diameter:g} mm] needs a circle of at least "
                             f"{MIN_HELIX_RADIUS:g} mm radius")
    before, after, tool_text = _tool_words(spec, diameter)
    radii = helix_radii(bore, radius)
    blocks = [comment(f"bore diameter {body.bore_diameter:g}: helical interpolation")] + before
    turns, pitch = 0, 0.0
    for rho in radii:
        helix, turns, pitch = _helix(float(rho), depth, spec)
        blocks += helix
    d = spec.decimals
    step = float(radii[0])
    header = [comment(f"bore diameter {body.bore_diameter:g} at the axis, cut first, while the stock holds the part; {tool_text}"),
              comment(f"bore: {radii.size} tool-centre circles of radius {step:.{d}f} to {float(radii[-1]):.{d}f} in steps of "
                      f"{step:.{d}f} [<= {BORE_STEPOVER:g} x tool: no core left]; no compensation"),
              comment(f"bore: each circle a helix of {turns} turns of pitch {pitch:.4g} <= step_down {spec.step_down:g} from Z0 to "
                      f"Z{-depth:g}, then a full circle there; {'G3 counter-clockwise' if spec.direction == 'climb' else 'G2 clockwise'} "
                      f"[{spec.direction}]")]
    if keyway:
        if diameter <= body.keyway_width:
            slot, text = _keyway(body, depth, spec, radius)
            blocks += slot
            header += [comment(line) for line in text]
        else:
            header.append(comment(f"the keyway [{body.keyway_width:g} wide] is not cut: the bore tool [diameter {diameter:g}] is wider; "
                                  "left to another operation [broach or wire EDM]"))
    blocks += after
    return BoreProgram(tuple(header), "\n".join(blocks) + "\n", spec.bore_tool_diameter is not None, len(blocks))


def _drill(body: "BodySpec", spec: MachiningSpec, depth: float) -> BoreProgram:
    """The bore drilled (``G98 G83`` peck drilling, pecks of ``step_down``) with a drill of its
    diameter, its point (:data:`DRILL_POINT_ANGLE`) through the stock: the full diameter reaches the
    last pass's depth; the keyway left to another operation."""
    d, diameter = spec.decimals, body.bore_diameter
    tip = 0.5 * diameter / math.tan(math.radians(DRILL_POINT_ANGLE) / 2.0)  # the cone of the drill's point
    bottom = depth + tip
    before, after, tool_text = _tool_words(spec, diameter, "drill")
    safe, plane = f"{spec.safe_z:.{d}f}", f"{min(spec.safe_z, DRILL_R_PLANE * _mm(spec)):.{d}f}"
    blocks = [comment(f"bore diameter {diameter:g}: peck drilling"), *before, f"G0 X{0.0:.{d}f} Y{0.0:.{d}f}",
              f"G98 G83 X{0.0:.{d}f} Y{0.0:.{d}f} Z{-bottom:.{d}f} R{plane} Q{spec.step_down:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}", "G80",
              f"G0 Z{safe}", *after]
    header = [comment(f"bore diameter {diameter:g} at the axis, drilled first, while the stock holds the part; {tool_text}"),
              comment(f"bore: a drill of the bore's diameter, point angle {DRILL_POINT_ANGLE:g} deg: G98 G83 pecks of <= step_down "
                      f"{spec.step_down:g} from R{plane} to Z{-bottom:.{d}f} = the last pass's depth {depth:g} + the point {tip:.4g}")]
    if body.keyway_width > 0.0:
        header.append(comment(f"the keyway [{body.keyway_width:g} wide] is not cut: left to another operation [broach or wire EDM]"))
    return BoreProgram(tuple(header), "\n".join(blocks) + "\n", True, len(blocks))


def with_bore(start: list[str], bored: BoreProgram, spec: MachiningSpec) -> list[str]:
    """The program's start blocks ``start`` with the bore's blocks inserted: before the outline's
    tool is set up (its ``T M06`` for fanuc, its ``G0 Z<safe>`` otherwise) when the bore has its
    own tool, else after the start (spindle running)."""
    if not bored.moves:
        return start
    at = len(start)
    if bored.own_tool:
        first = f"T{outline_tool_number(spec.tool_number)} M06" if spec.dialect == "fanuc" else f"G0 Z{spec.safe_z:.{spec.decimals}f}"
        at = start.index(first)
    return start[:at] + [bored.moves.rstrip("\n")] + start[at:]
