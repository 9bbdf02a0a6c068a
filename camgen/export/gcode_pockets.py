"""G-code passes of the pockets cut into a cam's top face (a groove cam's groove, a linear cam's slot).

A pocket (:class:`camgen.kinds.base.Pocket`) here is either a slot between two closed walls,
its outer wall ``walls[0]`` and its inner wall ``walls[1]``, ``width`` apart, with the closed
curve midway between them (``centre``: a groove's pitch curve); or the region inside **one
closed wall** ``walls[0]``, ``width`` its widest (twice the largest distance of a point inside
from the wall), with an open centre chain (``centre_path``: a slot closed by half circles, whose
pitch curve between the ends is the path of a tool of the slot's width).  No form is named
here.  The program mills every pocket before the outline (the part is still held by the stock),
in depth levels of at most ``step_down`` down to the pocket's depth (not through the plate).
The strategy follows from the tool diameter ``D`` against the width ``w``:

* ``|D - w| <= ONE_PASS_SHARE * 2 * chord_tol`` (:func:`one_pass_tol`): **one pass along the
  pitch curve** per level.  The tool disc swept along the centre is bounded by the centre's
  offsets by +-D/2, which are the walls (offsets by +-w/2) within ``|D - w| / 2``: the walls are
  exact to the path tolerance.  The path is the centre itself (no offset), so the offset-refit
  share of the path tolerance holds the mismatch instead.  An open centre (one wall) is run
  there and back: the ramp down along it to its end, then back to its start at the level's
  depth (the tool's half discs at the two ends are the wall's half circles).
* ``D < w``: two walls: **two wall passes, slot cleared**.  Per level, clearing passes along the
  centre's offsets by ``s`` strictly between the wall passes, evenly spaced with a stepover of
  at most ``SLOT_STEPOVER * D`` (< D, so neighbouring discs overlap and no island is left
  between them), then a finishing pass along each wall: the wall offset into the pocket by the
  tool radius (outer wall inward, inner wall outward), the outer wall first.
  One wall: **pocket cleared, one wall pass**.  The wall's inward offsets by
  ``r + k (w/2 - r) / g`` (``k = g-1 .. 1``, innermost first; ``g`` the least count with a
  stepover ``(w/2 - r) / g <= SLOT_STEPOVER * D``: the innermost loop lies within ``r`` of the
  deepest point inside, so its disc reaches it), then the finishing pass along the wall offset
  inward by the tool radius.
* ``D > w``: refused, naming ``tool_diameter`` and the width.

The tool must fit every concave radius of each wall, seen from the pocket (the outer wall's
convex arcs, the inner wall's concave ones; the sampled radii of curvature of
:func:`camgen.checks.radius_of_curvature`): else refused naming the least radius.

Entry.  No plunge into uncut stock: each level starts above the first pass's start at the
previous level's depth (the stock top for the first) and ramps down along that pass, one whole
loop with Z falling linearly along the path (lines with Z, helical G2/G3), then runs the loop at
the level's depth.  The ramp's angle to the floor is ``atan(step / loop length)``, stated in the
header.  Passes of one level are joined by straight feeds along the centre's normal at the start
(one stepover each; the last one crosses the cleared slot).

Direction (spindle M3): climb milling keeps the finished wall on the right of the travel, so the
outer wall runs counter-clockwise and the inner wall clockwise; clearing passes and the one pass
run as the outer wall.  Conventional milling reverses both.  Cutter compensation is not used for
pockets (a scene asking for it is refused for a cam with pockets: the one pass has no wall to
compensate against, and the passes are tool-centre paths).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np

from camgen.contour import Arc
from camgen.errors import GeometryError, ParameterError, floor_significant
from camgen.export.gcode_moves import START_SAMPLING, MoveWriter, comment, loop_moves, primitives, reverse_primitives, rotate
from camgen.export.gcode_spec import REFIT_SHARE, MachiningSpec, depth_passes

if TYPE_CHECKING:
    from camgen.contour import Contour, Spline
    from camgen.kinds.base import Pocket

__all__ = ["CLEARED", "ONE_PASS", "ONE_PASS_SHARE", "SLOT_STEPOVER", "TWO_WALLS", "PocketPass", "PocketPlan", "PocketProgram", "least_concave_radius",
           "one_pass_tol", "plan_pocket", "pocket_program", "ramp_moves"]

#: Share of ``chord_tol`` the one-pass strategy spends on the tool's mismatch with the width:
#: the path is the centre itself, so the offset-refit share (:data:`camgen.export.gcode_spec.REFIT_SHARE`)
#: is free; each wall moves by half the mismatch.
ONE_PASS_SHARE = REFIT_SHARE
#: Largest stepover between neighbouring passes clearing a slot, as a fraction of the tool
#: diameter (below 1: the tool discs of neighbouring passes overlap, no island between them).
SLOT_STEPOVER = 0.5
#: Strategy names, as the program's header says them.
ONE_PASS = "one pass along the pitch curve"
TWO_WALLS = "two wall passes, slot cleared"
CLEARED = "pocket cleared, one wall pass"


def one_pass_tol(spec: MachiningSpec) -> float:
    """Largest ``|tool diameter - pocket width|`` (mm) for which the tool cuts the pocket in one
    pass along its centre: ``2 ONE_PASS_SHARE chord_tol`` (each wall then within
    ``ONE_PASS_SHARE chord_tol`` of the tool's envelope)."""
    return 2.0 * ONE_PASS_SHARE * spec.chord_tol


@dataclass(frozen=True)
class PocketPass:
    """One tool-centre path of a pocket: ``path``, a closed contour (counter-clockwise, starting
    near the pocket's start) or an open chain of segments (a pocket's ``centre_path``: run to its
    end and back); ``clockwise`` (a closed path run the other way round), ``what`` it cuts (for
    the header)."""

    path: "Contour | tuple[Arc | Spline, ...]"
    clockwise: bool
    what: str

    @property
    def is_open(self) -> bool:
        return isinstance(self.path, tuple)


@dataclass(frozen=True)
class PocketPlan:
    """How one pocket is milled: its strategy, its passes per level in order, the stepover of
    the clearing passes (mm, None for one pass) and the least concave radius of its walls seen
    from the pocket (mm, inf when none) with the wall's layer."""

    pocket: "Pocket"
    strategy: str
    passes: tuple[PocketPass, ...]
    stepover: float | None
    least_radius: float
    least_wall: str


def least_concave_radius(pocket: "Pocket") -> tuple[float, str, float]:
    """The least radius of curvature of the pocket's walls that is concave seen from inside the
    pocket (mm): the outer (or only) wall's convex parts, every other wall's concave parts; with the wall's
    layer and the polar angle there (deg).  ``(inf, "", 0)`` when no wall has one."""
    from camgen.checks import radius_of_curvature

    best = (math.inf, "", 0.0)
    for k, wall in enumerate(pocket.walls):
        rho, angle = radius_of_curvature(wall.contour)
        seen = rho if k == 0 else -rho  # > 0: the wall curves round the tool
        seen = np.where(seen > 0.0, seen, np.inf)
        i = int(np.argmin(seen))
        if seen[i] < best[0]:
            best = (float(seen[i]), wall.layer, math.degrees(float(angle[i])) % 360.0)
    return best


def _refuse_tool(spec: MachiningSpec, limit: float, why: str) -> None:
    raise ParameterError("tool_diameter", spec.tool_diameter, f"<= {floor_significant(limit, 6):g} mm", why)


def _starting_near(path: "Contour", point: np.ndarray) -> "Contour":
    """``path`` rotated to start at its vertex (chord polygon of sagitta START_SAMPLING x size)
    nearest to ``point``."""
    params = path.flatten_params(START_SAMPLING * max(path.size, 1.0))
    nearest = int(np.argmin(np.hypot(*(path.evaluate(params) - point).T)))
    return rotate(path, float(params[nearest]))


def _offset(contour: "Contour", distance: float, spec: MachiningSpec, what: str) -> "Contour":
    try:
        return contour.offset(distance, spline_tol=min(1e-6, REFIT_SHARE * spec.chord_tol))
    except GeometryError as exc:
        raise GeometryError(f"the {what} of a tool of diameter {spec.tool_diameter:g} mm cannot be made: {exc}") from None


def plan_pocket(pocket: "Pocket", spec: MachiningSpec) -> PocketPlan:
    """The strategy and passes of ``pocket`` for the tool of ``spec`` (module docstring).

    Raises
    ------
    ParameterError
        ``tool_diameter`` wider than the pocket, or wider than twice the least concave radius of
        a wall; ``cutter_compensation`` asked for.
    GeometryError
        A pocket that is neither a slot between two walls with a width and a centre nor one wall
        with a width (and, for one pass, a centre).
    """
    if spec.cutter_compensation:
        raise ParameterError("cutter_compensation", True, f"false for a cam with pockets (pocket '{pocket.name}')",
                             "the pocket passes are tool-centre paths: one pass along the pitch curve has no wall to compensate against")
    one_wall = len(pocket.walls) == 1
    if pocket.width is None or not (one_wall or (len(pocket.walls) == 2 and pocket.centre is not None)):
        raise GeometryError(f"G-code for pocket '{pocket.name}' needs a slot between two walls with its width and centre, or one wall "
                            f"with its width (it has {len(pocket.walls)} walls, width {pocket.width}, "
                            f"centre {'given' if pocket.centre is not None else 'none'})")
    width = pocket.width
    d, r, tol = spec.tool_diameter, spec.tool_radius, one_pass_tol(spec)
    if d > width + tol:
        _refuse_tool(spec, width, f"wider than pocket '{pocket.name}' ({width:g} mm): it would cut beyond {'its wall' if one_wall else 'both walls'}; "
                                  f"a tool of the width (within {tol:.3g} mm) cuts it in one pass along the pitch curve, a smaller one in "
                                  f"{'a wall pass with the pocket cleared' if one_wall else 'two wall passes'}")
    least, layer, polar = least_concave_radius(pocket)
    climb = spec.direction == "climb"  # the finished wall on the right of the travel (spindle M3)
    if abs(d - width) <= tol:
        # the walls are the tool's envelope along the centre within half the mismatch: so is a wall's radius
        if r > least + 0.5 * tol:
            _refuse_tool(spec, 2.0 * least * (1.0 - 1e-9), f"the tool must fit the least concave radius {least:.6g} mm of wall {layer} "
                                                          f"of pocket '{pocket.name}' (near polar angle {polar:.3f} deg)")
        if pocket.centre is not None:
            return PocketPlan(pocket, ONE_PASS, (PocketPass(pocket.centre, not climb, "pitch curve"),), None, least, layer)
        if pocket.centre_path is None:
            raise GeometryError(f"G-code for pocket '{pocket.name}' in one pass needs its centre (a tool of its width runs along it)")
        return PocketPlan(pocket, ONE_PASS, (PocketPass(tuple(pocket.centre_path), False, "pitch curve, there and back"),), None,
                          least, layer)
    if r > least:
        _refuse_tool(spec, 2.0 * least * (1.0 - 1e-9), f"the tool must fit the least concave radius {least:.6g} mm of wall {layer} "
                                                      f"of pocket '{pocket.name}' (near polar angle {polar:.3f} deg)")
    if one_wall:
        return _cleared(pocket, spec, least, layer)
    assert pocket.centre is not None
    centre = pocket.centre
    outward = centre.normal(np.array([0.0]))[0]
    start = centre.evaluate(np.array([0.0]))[0]
    outer, inner = pocket.walls
    half = width / 2.0 - r  # the wall passes' distance from the centre
    gaps = max(1, math.ceil((width - d) / (SLOT_STEPOVER * d) - 1e-9))
    offsets = np.linspace(-half, half, gaps + 1)[1:-1]
    passes = [PocketPass(_starting_near(_offset(centre, float(s), spec, "clearing pass"), start + s * outward), not climb,
                         f"clearing at {float(s):+.4g} from the centre") for s in offsets]
    passes.append(PocketPass(_starting_near(_offset(outer.contour, -r, spec, f"pass along wall {outer.layer}"), start + half * outward),
                             not climb, f"wall {outer.layer}"))
    passes.append(PocketPass(_starting_near(_offset(inner.contour, r, spec, f"pass along wall {inner.layer}"), start - half * outward),
                             climb, f"wall {inner.layer}"))
    return PocketPlan(pocket, TWO_WALLS, tuple(passes), (width - d) / gaps, least, layer)


def _cleared(pocket: "Pocket", spec: MachiningSpec, least: float, layer: str) -> PocketPlan:
    """A pocket of one wall cleared by the wall's inward offsets, innermost first, then the
    finishing pass along the wall offset inward by the tool radius (module docstring)."""
    assert pocket.width is not None
    wall = pocket.walls[0]
    d, r = spec.tool_diameter, spec.tool_radius
    climb = spec.direction == "climb"
    inset = pocket.width / 2.0 - r  # from the finishing pass to the deepest point inside
    gaps = max(1, math.ceil(inset / (SLOT_STEPOVER * d) - 1e-9))
    start = wall.contour.evaluate(np.array([0.0]))[0]
    inward = -wall.contour.normal(np.array([0.0]))[0]
    distances = r + inset * np.arange(gaps - 1, -1, -1) / gaps  # innermost first, the finishing pass (r) last
    passes = [PocketPass(_starting_near(_offset(wall.contour, -float(s), spec, "clearing pass" if s > r else f"pass along wall {wall.layer}"),
                                        start + s * inward), not climb,
                         f"clearing at {float(s):.4g} inside wall {wall.layer}" if s > r else f"wall {wall.layer}") for s in distances]
    return PocketPlan(pocket, CLEARED, tuple(passes), inset / gaps, least, layer)


def _open_primitives(segments: "tuple[Arc | Spline, ...]", spec: MachiningSpec) -> list[tuple]:
    """Primitives of an open chain in its order, as :func:`camgen.export.gcode_moves.primitives`
    makes them for a closed one: arcs kept, splines as biarcs (``spline_mode = "biarcs"``) or
    chords, within the fit share of ``chord_tol``."""
    from camgen.contour.arcspline import spline_to_biarcs
    from camgen.export.gcode_spec import FIT_SHARE

    tol = FIT_SHARE * spec.chord_tol
    out: list[tuple] = []
    for seg in segments:
        pieces = [seg] if isinstance(seg, Arc) or spec.spline_mode != "biarcs" else spline_to_biarcs(seg, tol)
        for piece in pieces:
            if isinstance(piece, Arc):
                out.append(("arc", piece))
            else:
                u = np.append(piece.flatten_params(tol)[1:], 1.0)
                out.append(("lines", piece.point(u)))
    return out


def _loop(pocket_pass: PocketPass, spec: MachiningSpec) -> tuple[np.ndarray, list[tuple]]:
    """Start point and primitives of a pass in its direction of travel (an open one: forward)."""
    path = pocket_pass.path
    if isinstance(path, tuple):
        return np.asarray(path[0].start_point, dtype=float), _open_primitives(path, spec)
    start = path.segments[0].start_point
    prims = []
    for kind, item in primitives(path, spec):  # an arc of more than half a turn (a whole circle) in halves:
        if kind == "arc" and abs(item.sweep) > math.pi:  # its printed ends never coincide
            half = item.sweep / 2.0
            prims += [("arc", Arc(item.center, item.radius, item.start_angle, half)),
                      ("arc", Arc(item.center, item.radius, item.start_angle + half, half))]
        else:
            prims.append((kind, item))
    return start, (reverse_primitives(prims, start) if pocket_pass.clockwise else prims)


def _lengths(prims: list[tuple], start: np.ndarray) -> list[np.ndarray]:
    """Length (mm) of every move of ``prims`` from ``start``: one per arc, one per line point."""
    out, previous = [], start
    for kind, item in prims:
        if kind == "arc":
            out.append(np.array([item.radius * abs(item.sweep)]))
            previous = item.end_point
        else:
            out.append(np.hypot(*np.diff(np.vstack([previous[None], item]), axis=0).T))
            previous = item[-1]
    return out


def ramp_moves(prims: list[tuple], start: np.ndarray, z_from: float, z_to: float, decimals: int, end: np.ndarray | None = None) -> str:
    """The closed path ``prims`` from ``start`` with Z falling linearly along it from ``z_from``
    to ``z_to`` (mm): lines with a Z word, arcs as helical G2/G3; it ends at ``z_to``.  ``end``:
    the path is open and ends there (not back at ``start``)."""
    lengths = _lengths(prims, start)
    total = float(sum(float(x.sum()) for x in lengths))
    writer = MoveWriter(decimals, start, z_from)
    done = 0.0
    for (kind, item), length in zip(prims, lengths):
        run = done + np.cumsum(length)
        z = z_from + (z_to - z_from) * run / total
        if kind == "arc":
            writer.arc(item, z=float(z[-1]))
        else:
            writer.lines(item, z=z)
        done = float(run[-1])
    writer.line(start if end is None else end, z=z_to)  # the loop's closing gap, or its last Z, if printing dropped them
    return writer.text()


def _end_point(prims: list[tuple]) -> np.ndarray:
    kind, item = prims[-1]
    return np.asarray(item.end_point if kind == "arc" else item[-1], dtype=float)


def back_moves(prims: list[tuple], start: np.ndarray, decimals: int) -> str:
    """The open path ``prims`` (from ``start``) run back from its end to ``start`` (XY only)."""
    end = _end_point(prims)
    writer = MoveWriter(decimals, end)
    for kind, item in reverse_primitives(prims, start):
        if kind == "arc":
            writer.arc(item)
        else:
            writer.lines(item)
    writer.line(start)
    return writer.text()


@dataclass(frozen=True)
class PocketProgram:
    """The pocket part of a program: header comment lines, the moves (text) and their count."""

    header: tuple[str, ...]
    moves: str
    count: int


def pocket_program(pockets: Sequence["Pocket"], spec: MachiningSpec) -> PocketProgram:
    """Header lines and moves milling ``pockets`` (module docstring), from and back to safe Z."""
    d = spec.decimals
    header: list[str] = []
    blocks: list[str] = []
    for pocket in pockets:
        plan = plan_pocket(pocket, spec)
        loops = [_loop(p, spec) for p in plan.passes]
        texts = [back_moves(prims, start, d) if p.is_open else loop_moves(prims, start, d) for p, (start, prims) in zip(plan.passes, loops)]
        ramp_end = _end_point(loops[0][1]) if plan.passes[0].is_open else None
        n_levels = int(depth_passes(pocket.depth, spec.step_down))
        levels = -np.minimum(spec.step_down * np.arange(1, n_levels + 1), pocket.depth)
        first_start, first_prims = loops[0]
        loop_length = float(sum(float(x.sum()) for x in _lengths(first_prims, first_start)))
        steepest = max(float(-levels[0]), float(np.max(-np.diff(levels), initial=0.0)))
        walls = ", ".join(w.layer for w in pocket.walls)
        n_walls = len(pocket.walls)
        how = (f"{plan.strategy}: tool diameter = width within {one_pass_tol(spec):.3g}, each wall within half the difference"
               + ("; the open pitch curve run down to its end and back" if plan.passes[0].is_open else "")
               if plan.strategy == ONE_PASS else
               f"{plan.strategy}: {len(plan.passes) - n_walls} clearing passes at stepover {plan.stepover:.4g} "
               f"<= {SLOT_STEPOVER:g} x tool diameter, then a finishing pass along {'each wall' if n_walls > 1 else 'the wall'}, "
               f"tool centre {spec.tool_radius:g} into the pocket")
        header += [
            comment(f"pocket '{pocket.name}', walls {walls}, width {pocket.width:g}, depth {pocket.depth:g}: {how}"),
            comment(f"pocket '{pocket.name}': tool-centre paths, {spec.direction} milling; {n_levels} levels of <= {spec.step_down:g} "
                    f"down to Z{-pocket.depth:g}; entry: a ramp along the first pass, {'to its end' if plan.passes[0].is_open else 'one loop'} from the previous level "
                    f"at {math.degrees(math.atan2(steepest, loop_length)):.3g} deg at most, no plunge into the stock; pockets first, then the outline"),
        ]
        joins = [f"G1 X{s[0]:.{d}f} Y{s[1]:.{d}f}\n" for s, _ in loops]
        for k, z in enumerate(levels, 1):
            z_prev = 0.0 if k == 1 else float(levels[k - 2])
            parts = [f"(pocket '{pocket.name}' level {k} of {n_levels}: Z{z:.{d}f})\n",
                     f"G0 X{first_start[0]:.{d}f} Y{first_start[1]:.{d}f}\n",
                     f"G1 Z{z_prev:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}\n",
                     f"F{spec.feed:.{spec.feed_decimals}f}\n",
                     ramp_moves(first_prims, first_start, z_prev, float(z), d, end=ramp_end),
                     texts[0]]
            for join, text in zip(joins[1:], texts[1:]):
                parts += [join, text]
            parts.append(f"G0 Z{spec.safe_z:.{d}f}\n")
            blocks.append("".join(parts))
    moves = "".join(blocks)
    return PocketProgram(tuple(header), moves, moves.count("\n"))
