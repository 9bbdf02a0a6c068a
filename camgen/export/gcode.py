"""G-code (RS274/NGC) for milling the cam profile: LinuxCNC dialect by default, GRBL or Fanuc/Haas on request
(the Fanuc words around the same moves: :mod:`camgen.export.gcode_fanuc`).

The program cuts the outside of the profile in step-down passes to the stock bottom and
``breakthrough`` below it:

* header ``G21 G90 G17 G40 G49 G80 G94`` (+ ``G64 P<blend>`` path blending tolerance for LinuxCNC; ``G20`` and every
  number in inches with ``units = "inch"``: :mod:`camgen.export.gcode_units`);
* by default the **tool-centre path**: the profile offset outward by the tool radius (exact
  arcs stay ``G2/G3``; spline segments become biarcs ``G2/G3`` or ``G1`` chords);
* optionally **cutter compensation** (LinuxCNC, Fanuc): the profile itself with ``G41.1/G42.1
  D<diameter>`` (Fanuc ``G41/G42 D<register>``), switched on in a straight move of the lead-in
  and off (``G40``) in a straight move of the lead-out;
* climb milling (clockwise around the outside with a clockwise spindle, ``M3``) or conventional.

Lead-in and lead-out (:mod:`camgen.export.gcode_leads`; the same tool-centre path in both
modes).  ``S`` is a **support point** of the profile: its tangent line touches the profile and
has all of it on one side (a point of the convex hull where the curvature is > 0; the sharpest
such point is taken); ``n`` the outward normal there, ``t`` the travel direction, ``r`` the tool
radius, ``S' = S + r n`` the tool centre at the start, ``L`` = ``lead_mm``, ``rho`` =
``lead_radius_mm``.  With ``lead_style = "arc"`` (the default) the tool plunges at
``P0 = S' + rho n - rho t + L n``, runs straight along ``-n`` for ``L``, then on a quarter arc of
centre ``C = S' + rho n`` (outside the part) tangentially into the tool path at ``S'``; after
the closed contour it leaves on the mirror quarter arc of the same circle and runs straight on
along ``+n`` for ``L``.  With ``lead_style = "line"`` it runs along the tangent of the tool path:
from ``P0 = S' - L t`` to ``S'`` and on to ``S' + L t``.  Every point of the leads and the
plunge is at least ``r`` from the tangent line at ``S`` (``r + rho (1 - cos a)`` on the arcs),
which has the whole profile on its other side: the tool disc swept along them never touches
the part.

Cutter compensation.  Compensation is switched on and off on straight moves only.  LinuxCNC's
interpreter (``convert_straight_comp1``) ends the entry move at ``A' = A + r u_perp`` (``A``
the programmed point, ``u`` the direction from the tool to ``A``); a following line that turns
the other way is a concave corner and moves that end to the intersection of the two offset
lines.  camgen therefore programs the entry to a point ``A`` on the programmed straight lead
(the tool's lead line pushed out by ``r``), at an angle above LinuxCNC's 0.05 rad to it: the
interpreter ends the entry move on the tool's lead line, and the tool runs straight from
``P0`` on into the lead arc (programmed with radius ``rho + r`` about ``C``) and the contour
with no corner; the exit programs the lead-out arc, a line along its tangent, then ``G40``
with a straight move to the tool-centre end point, on the same line (details and the lengths:
:mod:`camgen.export.gcode_leads`).  A concave arc whose radius is not above the tool radius is
refused (LinuxCNC's own rule); arcs too short to print safely are written as lines, never as
arcs that the control could read as full circles.

Error budget.  The program follows the ideal tool path within ``chord_tol``:
``FIT_SHARE`` for the biarc / chord fit of spline segments, ``REFIT_SHARE`` for the offset
refit of spline segments, ``ROUNDING_SHARE`` for the printed decimals (a printed point is
within ``sqrt(2)/2 * 10^-decimals`` of its value; an arc, whose centre and both ends are
printed, within three times that) and ``BLEND_SHARE`` for LinuxCNC's path blending
(``G64 P``).  ``decimals`` too coarse for ``chord_tol`` is a :class:`ParameterError`.

Passes (:mod:`camgen.export.gcode_passes`).  Each pass goes down at ``P0`` (where the lead-in
starts) from the floor of the pass before (Z0 for the first) by a helix (default) or a zig-zag
ramp at most ``ramp_angle`` steep, or a plunge (:mod:`camgen.export.gcode_entry`), on the side of
``P0`` away from the part: with arc leads the helix is centred beside ``P0`` along the tangent
line at ``S`` (every point of it at least ``r + rho + L - r/2 > r`` from that line) and touches
the lead-in's straight move, the ramp runs out along ``n`` and back; with straight leads the
helix is centred outward of ``P0`` and the ramp runs back along the lead line.  With a
``stock_allowance`` the passes cut the profile grown by it (programmed, or offset by ``r`` more
for the tool centre), then one finishing pass at full depth cuts the profile, gone down where
the roughing entry cleared the stock.  ``holding_tabs``: the passes below the tabs' top rise
over them by Z moves (:mod:`camgen.export.gcode_tabs`).

Pockets.  A cam with pockets (a groove cam's groove, :class:`camgen.kinds.base.Pocket`) has them
milled first, to their depth, while the stock still holds the part; then its outline as above
(:mod:`camgen.export.gcode_pockets`: one pass along the pitch curve with a tool of the groove's
width, or two wall passes and the slot cleared with a smaller one; the header says which).

Bore.  The cam's shaft bore and keyway are milled first (helix, keyway slot) or drilled, or the
header says they are left to another operation (:mod:`camgen.export.gcode_bore`).

A concave radius of the profile smaller than the tool radius would be gouged: that is a
:class:`GeometryError` naming the cam angle.  Z = 0 is the top face of the stock.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np

from camgen.contour import Contour
from camgen.errors import CornerError, GeometryError, ParameterError, ceil_significant, require_positive
# the settings, their error budget and the moves live in their own modules (the pockets' passes
# share them); their names stay importable from here
from camgen.export.entry_settings import tab_size, turn_length
from camgen.export.gcode_entry import entry_text, plan_entry
from camgen.export.gcode_leads import COMP_ENTRY_ANGLE, COMP_STRAIGHT, Leads, lead_blocks, lead_moves
from camgen.export.gcode_passes import Operation, grown_paths, outline_passes, passes_text
from camgen.export.gcode_tabs import path_tabs, plan_tabs, tabs_text
from camgen.export.gcode_moves import START_SAMPLING, comment, loop_moves, primitives, reverse_primitives, rotate, split_segment
from camgen.export.gcode_spec import (BLEND_SHARE, DIALECTS, DIRECTIONS, FIT_SHARE, MIN_GCODE_CHORD_TOL, REFIT_SHARE, ROUNDING_SHARE,
                                      SPLINE_MODES, MM_PER_INCH, MachiningSpec, depth_passes, rounding_error)

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.kinds.base import Pocket

__all__ = ["BLEND_SHARE", "COMP_ENTRY_ANGLE", "COMP_STRAIGHT", "DIALECTS", "DIRECTIONS", "FIT_SHARE", "MAX_PASSES", "MAX_PROGRAM_MOVES",
           "MIN_GCODE_CHORD_TOL", "MachiningSpec", "REFIT_SHARE", "ROUNDING_SHARE", "SPLINE_MODES", "START_BATCH", "SUPPORT_TOL",
           "blend_word", "depth_passes", "gcode_program", "rounding_error", "start_parameter", "tool_path"]

#: gcode._split: the segment split of :func:`camgen.export.gcode_moves.split_segment` (its old name)
_split = split_segment

#: Largest distance (mm) the profile may reach beyond the tangent line at the start point.
SUPPORT_TOL = 1e-7
#: Candidates of the start point whose support is tested at once (in order of falling curvature).
START_BATCH = 32


def tool_path(contour: Contour, spec: MachiningSpec) -> Contour:
    """The contour the tool centre follows: ``contour`` offset outward by the tool radius.

    Spline segments are refitted within ``REFIT_SHARE * chord_tol`` (at most 1e-6 mm).
    Raises :class:`GeometryError` where a concave radius is smaller than the tool radius.
    """
    try:
        return contour.offset(spec.tool_radius, spline_tol=min(1e-6, REFIT_SHARE * spec.chord_tol))
    except CornerError as exc:  # no tool radius follows a corner exactly
        raise CornerError(f"a tool of diameter {spec.tool_diameter:g} mm cannot follow the profile: {exc}") from None
    except GeometryError as exc:
        raise GeometryError(
            f"a tool of diameter {spec.tool_diameter:g} mm would gouge the profile ({exc}); "
            "use a tool whose radius is below the smallest concave radius"
        ) from None


# ------------------------------------------------------------------------------------------
# start point and contour rotation
# ------------------------------------------------------------------------------------------
def start_parameter(path: Contour, what: str = "lead") -> float:
    """Global parameter of the start point on ``path``: a support point (the tangent line has
    the whole path on one side, within ``SUPPORT_TOL`` mm) with positive curvature, the sharpest one.

    Candidates are the chord midpoints of a coarse flattening (never a segment end).  Raises
    :class:`GeometryError` naming ``what`` when no candidate qualifies (a hull made of corners).
    """
    params = path.flatten_params(START_SAMPLING * max(path.size, 1.0))
    mid = 0.5 * (params + np.append(params[1:], path.n_segments))
    points = path.evaluate(mid)
    normals = path.normal(mid)
    kappa = path.curvature(mid)
    psi = np.arctan2(normals[:, 1], normals[:, 0])
    # the sharpest convex candidate on the hull: test the support in order of falling curvature,
    # a batch at a time (the support costs pieces x directions; the first batches decide)
    order = np.argsort(-kappa, kind="stable")
    order = order[kappa[order] > 0.0]
    for lo in range(0, order.size, START_BATCH):
        batch = order[lo:lo + START_BATCH]
        gap = path.support(psi[batch]) - np.einsum("ij,ij->i", points[batch], normals[batch])
        ok = gap <= SUPPORT_TOL
        if ok.any():
            return float(mid[batch[np.argmax(ok)]])
    raise GeometryError(
        f"no safe start for the {what}: no point of the contour's convex hull has a tangent "
        "(the hull is made of corners); the tangent lead-in needs a smooth convex stretch"
        + ("; set cutter_compensation = false" if what == "cutter_compensation" else "")
    )


def _check_compensated_arcs(prims: list[tuple], spec: MachiningSpec) -> None:
    """Concave arcs of the counter-clockwise profile ``prims`` under cutter compensation.

    LinuxCNC refuses an arc with the tool inside whose radius is not above the tool radius, and
    an arc whose compensated chord is too short to print (< 100 units of the last decimal)
    could run as a full circle: both are a :class:`GeometryError` naming ``cutter_compensation``.
    """
    r = spec.tool_radius
    least = 100.0 * 10.0 ** (-spec.decimals)
    for kind, arc in prims:
        if kind != "arc" or arc.sweep > 0:  # convex: the tool runs outside the arc
            continue
        half = math.sin(min(abs(arc.sweep), math.pi) / 2.0)
        written_as_arc = 2.0 * arc.radius * half >= least
        if arc.radius <= r or (written_as_arc and 2.0 * (arc.radius - r) * half < least):
            mid = arc.point(np.array([0.5]))[0]
            polar = math.degrees(math.atan2(mid[1], mid[0])) % 360.0
            raise GeometryError(
                f"cutter_compensation: the concave arc of radius {arc.radius:.4g} mm near cam angle {polar:.3f} deg "
                f"leaves the tool (radius {r:g} mm) too little room for LinuxCNC's compensation; "
                "set cutter_compensation = false (camgen then writes the exact tool-centre path) or use a smaller tool"
            )


def blend_word(tol: float, decimals: int) -> str:
    """``P`` value of ``G64`` printed rounded down (P0 would mean no tolerance at all)."""
    for k in range(decimals, decimals + 6):
        value = math.floor(tol * 10**k) / 10**k
        if value >= 0.5 * tol:
            return f"{value:.{k}f}"
    return f"{tol:.3e}"


#: Most moves (lines) of one G-code program: about 60 MB of text, what controllers and CAM
#: viewers still load (the contour is repeated in every depth pass).
MAX_PROGRAM_MOVES = 2_000_000


#: Most depth passes of a G-code program (thickness + breakthrough over step_down_mm).
MAX_PASSES = 1000


def _refuse_long_program(spec: MachiningSpec, depth: float, n_passes: int, per_pass: int, fixed: int) -> None:
    """Raise the :class:`ParameterError` for a program of more than :data:`MAX_PROGRAM_MOVES`
    moves (``n_passes`` passes of at most ``per_pass`` moves and ``fixed`` moves that do not
    depend on the passes: the entries' descent, pockets, bore, finishing pass): fewer passes
    (``step_down_mm``) where one pass fits, else a coarser path."""
    why = (f"{n_passes} passes of {per_pass} moves and {fixed} more would make {n_passes * per_pass + fixed} lines, more than the "
           f"{MAX_PROGRAM_MOVES} a program may hold")
    passes = (MAX_PROGRAM_MOVES - fixed) // per_pass
    if passes >= 1:
        raise ParameterError("step_down_mm", spec.step_down, f">= {ceil_significant(depth / passes, 3):.3g} mm", why)
    coarser = '"biarcs" or a larger chord_tol' if spec.spline_mode == "lines" else "a larger chord_tol"
    raise ParameterError("spline_mode" if spec.spline_mode == "lines" else "chord_tol", spec.spline_mode if spec.spline_mode == "lines" else spec.chord_tol,
                         coarser, why)


@dataclass(frozen=True)
class _Outline:
    """One programmed closed path with its leads (mm): ``leads`` (their tool-centre geometry: the
    plunge point P0, S', the lead arc), ``travel`` and ``normal`` (outward) unit vectors at the
    start, program text of the leads and of the closed path (``moves``), the header's ``mode``,
    the path's printable primitives and its first point (the tabs split them)."""

    leads: Leads
    travel: np.ndarray
    normal: np.ndarray
    lead_in: str
    moves: str
    lead_out: str
    mode: str
    prims: list[tuple]
    start: np.ndarray
    count: int  # blocks of the leads and the closed path


def _outline(contour: Contour, offset: Contour, spec: MachiningSpec, t_start: float) -> _Outline:
    """The closed path (``contour`` programmed under cutter compensation, else its tool-centre
    ``offset``) started at global parameter ``t_start``, its moves and its leads (module docstring)."""
    comp = spec.cutter_compensation
    path = rotate(contour if comp else offset, t_start)
    prims = primitives(path, spec)
    if comp:
        _check_compensated_arcs(prims, spec)
    start = path.segments[0].start_point
    tangent = path.tangent(np.array([0.0]))[0]  # counter-clockwise
    normal = np.array([tangent[1], -tangent[0]])  # outward
    climb = spec.direction == "climb"
    if climb:
        prims = reverse_primitives(prims, start)
    travel = -tangent if climb else tangent
    # the lead-in and lead-out (camgen.export.gcode_leads): straight moves and tangent arcs;
    # plunge: the tool-centre point where the lead-in starts (leads.away: away from the part)
    leads = lead_moves(start, travel, normal, spec)
    entry_blocks = lead_blocks(leads.entry, spec.decimals, leads.plunge)
    exit_blocks = lead_blocks(leads.exit, spec.decimals, start)
    contour_moves = loop_moves(prims, start, spec.decimals)
    d = spec.decimals
    feed = f"F{spec.feed:.{spec.feed_decimals}f}"

    def blocks(moves: list[tuple[str, str]]) -> str:
        return "".join(f"{word} {words}\n" for word, words in moves)

    if comp:
        # G41: tool left of the travel direction = outside of a clockwise (climb) path
        side = "G41.1" if climb else "G42.1"
        (word, words), *rest = entry_blocks
        lead_in = f"{side} D{spec.tool_diameter:.{d}f} {word} {words} {feed}\n" + blocks(rest)
        lead_out = blocks(exit_blocks[:-1]) + "G40 " + blocks(exit_blocks[-1:])
        mode = f"cutter compensation {side} on the profile"
    else:
        (word, words), *rest = entry_blocks
        lead_in = f"{word} {words} {feed}\n" + blocks(rest)
        lead_out = blocks(exit_blocks)
        mode = "tool-centre path = profile offset by the tool radius"
    if spec.dialect == "fanuc":  # Fanuc/Haas: G41/G42 D<register> on the leads' G1 blocks (camgen.export.gcode_fanuc)
        from camgen.export.gcode_fanuc import fanuc_leads

        lead_in, lead_out, mode = fanuc_leads(spec, climb, entry_blocks, exit_blocks)
    count = contour_moves.count("\n") + len(entry_blocks) + len(exit_blocks)
    return _Outline(leads, travel, normal, lead_in, contour_moves, lead_out, mode, prims, start, count)


def gcode_program(contour: Contour, spec: MachiningSpec, cam: str = "cam", scene: str = "", thickness: float | None = None,
                  pockets: "Sequence[Pocket]" = (), cam_body: "BodySpec | None" = None) -> str:
    """RS274/NGC program text that mills ``contour`` (the cam profile) to ``thickness`` (mm; the
    cam's, default ``spec.thickness``) plus ``spec.breakthrough``, with tangent lead-in and
    lead-out (see the module docstring).  ``spec`` is final (the scene reader checked it against
    its chord tolerance and the cam's depth): it is used as it is.

    ``pockets`` (a groove cam's groove) are milled first, to their depth, while the stock still
    holds the part (:mod:`camgen.export.gcode_pockets`: one pass along the pitch curve, or two
    wall passes and the slot cleared); then the outline as without them.  ``cam_body``: the cam's
    bore and keyway, milled first or left to another operation (:mod:`camgen.export.gcode_bore`)."""
    from camgen import __version__

    if spec.program_unit != 1.0:  # inch: the same program of the scaled geometry and spec (camgen.export.gcode_units)
        from camgen.export.gcode_units import in_program_units

        return in_program_units(gcode_program, contour, spec, cam, scene, thickness, pockets, cam_body)
    from camgen.export.gcode_units import units_note

    pocketed = None
    if pockets:
        from camgen.export.gcode_pockets import pocket_program

        pocketed = pocket_program(pockets, spec)

    comp = spec.cutter_compensation
    # the start is chosen on the profile; the offset keeps the parameter (arcs: same angles,
    # splines: refitted at the same parameter values), so it starts at the same global parameter
    t_start = start_parameter(contour, "cutter_compensation" if comp else "lead")
    offset = tool_path(contour, spec)  # in compensation mode still refuses a gouging tool
    fin = _outline(contour, offset, spec, t_start)
    leads, mode = fin.leads, fin.mode
    centre_start, plunge = leads.centre_start, leads.plunge
    r, lead = spec.tool_radius, spec.lead_length
    rough = grown = None
    if spec.stock_allowance > 0.0:  # roughing passes on the profile grown by the allowance (camgen.export.gcode_passes)
        grown = grown_paths(contour, spec)
        rough = _outline(*grown, spec, t_start)
    # the way down to each pass at P0, clear of the part (camgen.export.gcode_entry, module docstring):
    # arc leads leave P0 along -n, the helix beside it along the tangent line; straight leads along the travel
    first = rough or fin
    entry = spec.entry or "plunge"  # resolved by MachiningSpec (camgen.export.entry_settings); None only for wire EDM
    if leads.arc_centre is None:
        way_down = plan_entry(entry, spec.ramp_angle, first.leads.plunge, first.travel, first.normal, r, lead)
    else:
        way_down = plan_entry(entry, spec.ramp_angle, first.leads.plunge, -first.normal, -first.travel, r, lead)

    d = spec.decimals

    def xy(p: np.ndarray) -> str:
        return f"X{p[0]:.{d}f} Y{p[1]:.{d}f}"

    stock = spec.thickness if thickness is None else require_positive("thickness", thickness, "mm")
    depth = stock + spec.breakthrough
    n_passes = max(1, math.ceil(depth / spec.step_down - 1e-9))
    # the program's moves: per pass the leads and the path, the rapid to P0, the way down, the
    # rapid up, a rise and a drop at each tab (and 2 for the rounding up of the entry's turns);
    # besides, the entries' turns (2 blocks a turn, at most 2 / (turn x tan(angle)) per mm down),
    # the pockets, the bore and the finishing pass
    per_pass = max(fin.count, rough.count if rough is not None else 0) + 3 + 2 * spec.holding_tabs + (2 if entry != "plunge" else 0)
    descent = 0.0 if entry == "plunge" else 2.0 / (turn_length(entry, r, lead) * math.tan(spec.ramp_angle))
    from camgen.export.gcode_bore import bore_program, with_bore  # the bore and keyway, first

    bored = bore_program(cam_body, spec, depth)
    fixed = (math.ceil(descent * depth) + (pocketed.count if pocketed is not None else 0) + (bored.count if bored is not None else 0)
             + (per_pass + 2 if rough is not None else 0))
    if n_passes * per_pass + fixed > MAX_PROGRAM_MOVES:
        _refuse_long_program(spec, depth, n_passes, per_pass, fixed)
    depths = -np.minimum(spec.step_down * np.arange(1, n_passes + 1), depth)
    fin_tabs = rough_tabs = None
    tab_line: list[str] = []
    if spec.holding_tabs:  # holding tabs: the passes below their top rise over them (camgen.export.gcode_tabs)
        width, height = tab_size(spec.holding_tab_width, spec.holding_tab_height, spec.tool_diameter, stock,
                                 1.0 / MM_PER_INCH if spec.converted and spec.units == "inch" else 1.0)
        t_ends, angles, top = plan_tabs(spec.holding_tabs, width, height, stock, contour, offset, t_start, r)
        fin_tabs = path_tabs(t_ends, angles, top, contour if comp else offset, fin.prims, fin.start, d)
        if rough is not None and grown is not None:
            rough_tabs = path_tabs(t_ends, angles, top, grown[0] if comp else grown[1], rough.prims, rough.start, d)
        tab_line = [comment(tabs_text(fin_tabs, width, height))]
    chord_tol = spec.chord_tol
    blend = blend_word(BLEND_SHARE * chord_tol, d)
    fit_what = "biarc" if spec.spline_mode == "biarcs" else "chord"
    lines = [
        comment(f"camgen {__version__}: cam '{cam}'" + (f", scene '{scene}'" if scene else "")),
        comment(f"{units_note(spec)}; tool diameter {spec.tool_diameter:g}; {mode}; {spec.direction} milling, outside contour"),
        comment(f"stock top Z0, bottom Z{-stock:g}; last pass Z{-depth:g} = {spec.breakthrough:g} below the stock bottom "
                 f"(breakthrough); {n_passes} passes of <= {spec.step_down:g}" + passes_text(spec, tuple(float(z) for z in depths))),
        comment(f"path tolerance {chord_tol:g} = {fit_what} fit {FIT_SHARE * chord_tol:.3g} + offset refit "
                 f"{min(1e-6, REFIT_SHARE * chord_tol):.3g} "
                 f"+ {d} printed decimals {rounding_error(d):.3g}"
                 + (f" + G64 blending {blend}" if spec.dialect == "linuxcnc" else "")),
        comment(f"tangent lead-in and lead-out of {lead:g} at tool-centre point {xy(centre_start)}, plunge at {xy(plunge)}"
                if leads.arc_centre is None else
                f"lead-in and lead-out: straight {lead:g} and a tangent quarter arc of tool-centre radius {leads.radius:g} about "
                f"{xy(leads.arc_centre)}, into and out of tool-centre point {xy(centre_start)}; plunge at {xy(plunge)}"),
        comment(entry_text(way_down)),
    ] + tab_line
    if pocketed is not None:
        lines += list(pocketed.header)
    if bored is not None:
        lines += list(bored.header)
    if spec.dialect == "fanuc":  # Fanuc/Haas: register line, units, safe start, tool call, G43 (camgen.export.gcode_fanuc)
        from camgen.export.gcode_fanuc import fanuc_start

        starting = fanuc_start(spec, pocketed is not None)
    else:
        starting = [f"{spec.units_word} G90 G17 G40 G49 G80 G94"] + ([f"G64 P{blend}"] if spec.dialect == "linuxcnc" else [])
        starting += [f"G0 Z{spec.safe_z:.{d}f}", f"M3 S{spec.spindle_rpm:.0f}"]
    lines += starting if bored is None else with_bore(starting, bored, spec)
    body = ["\n".join(lines) + "\n"]
    if pocketed is not None:
        body.append(pocketed.moves)
    levels = tuple(float(z) for z in depths)
    if rough is None:
        body.append(outline_passes(Operation(plunge, fin.lead_in, fin.moves, fin.lead_out, levels, entry=way_down,
                                             tabs=fin_tabs), spec))
    else:  # roughing to the full depth, then one finishing pass there, gone down at the roughing's entry
        body.append(outline_passes(Operation(rough.leads.plunge, rough.lead_in, rough.moves, rough.lead_out, levels, "roughing pass",
                                             entry=way_down, tabs=rough_tabs), spec))
        body.append(outline_passes(Operation(plunge, fin.lead_in, fin.moves, fin.lead_out, levels[-1:], "finishing pass",
                                             approach=rough.leads.plunge, tabs=fin_tabs), spec))
    if spec.dialect == "fanuc":  # % O-number ... M05 M30 %, comments Fanuc-safe (camgen.export.gcode_fanuc)
        from camgen.export.gcode_fanuc import fanuc_end

        return fanuc_end(spec, cam, body)
    body.append("M5\nM2\n")
    return "".join(body)
