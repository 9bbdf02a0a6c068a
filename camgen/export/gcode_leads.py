"""The lead-in and lead-out of a milled outline: the moves from the plunge point onto the closed
contour at its start and from there off it again (mm, rad).

Notation: ``S`` the start point on the profile (a **support point**: its tangent line has the
whole profile on one side, :func:`camgen.export.gcode.start_parameter`), ``t`` the travel
direction there, ``n`` the outward normal, ``r`` the tool radius, ``S' = S + r n`` the tool
centre at the start, ``L`` the length of the straight leads (``lead_mm``), ``rho`` the radius of
the lead arcs (``lead_radius_mm``), all of the tool centre.

``lead_style = "arc"`` (the default).  The tool centre runs on the circle of centre
``C = S' + rho n`` (outside the part): tangent to the tool path at ``S'``, it reaches ``S'`` on a
quarter arc (sweep :data:`LEAD_SWEEP`) from ``M = C - rho t``, where it arrives along ``-n``,
after a straight move of length ``L`` from the plunge point ``P0 = M + L n``; it leaves on the
mirror quarter arc of the same circle to ``N = C + rho t`` and runs straight on along ``+n`` to
``Q = N + L n``.  Every point of these moves is at a distance ``r + rho (1 - cos a) >= r``
(``a`` the angle on the arc) or ``r + rho + s`` (the straight moves) from the tangent line at
``S``, which has the whole profile on its other side: the tool disc swept along them never
touches the part (the support-line argument), and the tool path is tangent-continuous at ``M``,
``S'`` and ``N``.

``lead_style = "line"``.  Straight tangent leads: ``P0 = S' - L t``, ``Q = S' + L t``.

Cutter compensation (the profile programmed).  Compensation is switched on and off on
**straight** moves only (LinuxCNC and Fanuc both require it).  The programmed lead arc is the
tool-centre arc pushed out by ``r`` away from its centre: radius ``R = rho + r`` about the same
``C``, the tool inside it (``R > r`` always), so it runs tangentially into ``S``.  Before it a
programmed straight line runs along the tangent of that arc at ``Am = C + R (M - C) / rho``,
and the compensation is switched on by an entry move to ``A1 = Am - (L - L') v`` (``v`` the
direction at ``M``; ``L' = min(sqrt(L^2 - r^2) / 2, r / tan(COMP_ENTRY_ANGLE))``).  LinuxCNC's
interpreter (``convert_straight_comp1``) ends that entry move at ``A1 + r perp(u)`` (``u`` the
direction from the tool to ``A1``); as the next line turns by more than ``COMP_STRAIGHT`` the
corner is concave and the end moves to the intersection of the two offset lines, which is on
the tool-centre line through ``P0`` and ``M``, ``sqrt(L'^2 + r^2) < L`` ahead of ``P0`` (before
``M``).  So the tool runs from ``P0`` straight to ``M``, then on the arc (the line->arc and
arc->contour joints are tangent: LinuxCNC runs them straight on) to ``S'``: the same tool-centre
path as without compensation, with no corner.  The exit mirrors it: the programmed arc from
``S`` to ``Nm``, a line ``Nm -> Nm + (L / 2) v_N`` (the tool on the offset line), then ``G40``
with a straight move to the tool-centre point ``Q``, on the same line.  A Fanuc control (start-up
type A or B) ends the entry block on the offset line of the next block as well.
With ``lead_style = "line"`` the same holds with the arc left out (``M = S'``, ``Am = S``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.contour import Arc
from camgen.export.gcode_moves import MoveWriter
from camgen.export.gcode_spec import LEAD_STYLES, MachiningSpec

__all__ = ["COMP_ENTRY_ANGLE", "COMP_STRAIGHT", "LEAD_STYLES", "LEAD_SWEEP", "LeadMove", "Leads", "entry_along", "lead_blocks", "lead_moves",
           "wear_limit"]

#: LinuxCNC's TOLERANCE_CONCAVE_CORNER (rad): compensated corners flatter than this are run
#: straight on (interp_internal.hh).
COMP_STRAIGHT = 0.05
#: Angle (rad) between the compensation entry move and the straight lead, above COMP_STRAIGHT
#: so that LinuxCNC treats the corner as concave and moves the entry's end onto the offset line.
COMP_ENTRY_ANGLE = 0.1
#: Sweep (rad) of each lead arc: a quarter circle.
LEAD_SWEEP = math.pi / 2


@dataclass(frozen=True)
class LeadMove:
    """One programmed move of a lead: a straight feed to ``end`` (mm), or the arc ``arc``."""

    end: np.ndarray
    arc: Arc | None = None


@dataclass(frozen=True)
class Leads:
    """The lead-in and lead-out of an outline (mm; programmed points: the profile's side with
    cutter compensation, else the tool centre).

    ``entry``: the moves from ``plunge`` to the contour's start (compensation, if any, switched
    on in the first, a straight move); ``exit``: from the contour's start off it (compensation
    switched off in the last, a straight move to the tool-centre point ``leave``).
    ``plunge``: the tool-centre point where the lead-in starts (P0); ``away``: the unit vector
    pointing from ``plunge`` away from the part, against the lead-in's first move (every point
    ``plunge + s away``, s >= 0, is at least as far as P0 from the tangent line at the start);
    ``centre_start``: the tool centre at the start (S'); ``arc_centre``: the lead arcs' centre
    (None for straight leads); ``radius``: the lead arcs' tool-centre radius (0 for straight).
    """

    entry: tuple[LeadMove, ...]
    exit: tuple[LeadMove, ...]
    plunge: np.ndarray
    away: np.ndarray
    centre_start: np.ndarray
    leave: np.ndarray
    arc_centre: np.ndarray | None
    radius: float


def _arc(centre: np.ndarray, radius: float, start: np.ndarray, sweep: float) -> Arc:
    """The arc about ``centre`` of ``radius`` (mm) from the direction of ``start`` (a point) by ``sweep`` (rad)."""
    a0 = math.atan2(start[1] - centre[1], start[0] - centre[0])
    return Arc((float(centre[0]), float(centre[1])), radius, a0, sweep)


def entry_along(spec: MachiningSpec) -> float:
    """``L'`` (mm): the compensation entry move's length along the straight lead, so that its angle
    ``atan(r / L')`` to it stays above :data:`COMP_STRAIGHT` (LinuxCNC then takes the corner as
    concave) and its end ``sqrt(L'^2 + r^2) < L`` from the plunge point."""
    length, r = spec.lead_length, spec.tool_radius
    return min(math.sqrt(length * length - r * r) / 2.0, r / math.tan(COMP_ENTRY_ANGLE))


def wear_limit(spec: MachiningSpec) -> float:
    """The largest wear (mm) a control's radius register may add to the radius the program expects
    (the tool radius with cutter compensation, else 0) before the leads fail: the compensation
    entry move must stay longer than the radius the control offsets by (LinuxCNC's and Fanuc's
    rule), and the tool must fit inside the lead arcs (their tool-centre radius)."""
    if spec.cutter_compensation:
        room = math.hypot(entry_along(spec), spec.tool_radius) - spec.tool_radius
    else:
        room = spec.lead_length  # the entry move runs from the plunge point to the lead's end (the tool centre)
    return min(room, spec.lead_arc_radius) if spec.lead_style == "arc" else room


def lead_moves(start: np.ndarray, travel: np.ndarray, normal: np.ndarray, spec: MachiningSpec) -> Leads:
    """The leads of the outline that starts at ``start`` (the programmed point: ``S`` on the
    profile with ``spec.cutter_compensation``, else the tool centre ``S'``), travelling along the
    unit vector ``travel``, ``normal`` the outward unit normal there (module docstring)."""
    comp = spec.cutter_compensation
    r, length = spec.tool_radius, spec.lead_length
    t, n = np.asarray(travel, float), np.asarray(normal, float)
    centre_start = start + r * n if comp else np.asarray(start, float)
    if spec.lead_style == "arc":
        rho = spec.lead_arc_radius
        c = centre_start + rho * n
        phi = LEAD_SWEEP
        turn = math.copysign(1.0, float(t[0] * n[1] - t[1] * n[0]))  # > 0: the centre left of the travel (a G3 arc)
        m = c - rho * (n * math.cos(phi) + t * math.sin(phi))  # start of the lead-in arc (tool centre)
        v_in = t * math.cos(phi) - n * math.sin(phi)  # direction there
        q = c - rho * (n * math.cos(phi) - t * math.sin(phi))  # end of the lead-out arc
        v_out = t * math.cos(phi) + n * math.sin(phi)
        big = rho + r if comp else rho  # the programmed arcs' radius
        on_in = c + big * (m - c) / rho  # programmed start of the lead-in arc
        on_out = c + big * (q - c) / rho
        arc_in = LeadMove(np.asarray(start, float), _arc(c, big, on_in, turn * phi))
        arc_out = LeadMove(on_out, _arc(c, big, np.asarray(start, float), turn * phi))
        arc_centre: np.ndarray | None = c
    else:
        rho, m, q, v_in, v_out = 0.0, centre_start, centre_start, t, t
        on_in = on_out = np.asarray(start, float)
        arc_centre = None
    plunge = m - length * v_in
    leave = q + length * v_out
    entry: list[LeadMove] = []
    exit_: list[LeadMove] = []
    if comp:
        along = entry_along(spec)  # L': the entry move's length along the straight lead
        entry.append(LeadMove(on_in - (length - along) * v_in))
        entry.append(LeadMove(on_in))
        if arc_centre is not None:
            entry.append(arc_in)
            exit_.append(arc_out)
        exit_.append(LeadMove(on_out + 0.5 * length * v_out))
    else:
        entry.append(LeadMove(m))
        if arc_centre is not None:
            entry.append(arc_in)
            exit_.append(arc_out)
    exit_.append(LeadMove(leave))
    return Leads(tuple(entry), tuple(exit_), plunge, -v_in, centre_start, leave, arc_centre, rho)


def lead_blocks(moves: tuple[LeadMove, ...], decimals: int, current: np.ndarray) -> list[tuple[str, str]]:
    """The blocks of ``moves`` from the point ``current`` (mm), printed with ``decimals``: per
    move its motion word (``G1``, ``G2``, ``G3``) and its words (``X.. Y..``, for arcs ``I.. J..``
    from the printed start, as :class:`camgen.export.gcode_moves.MoveWriter` writes them)."""
    out: list[tuple[str, str]] = []
    writer = MoveWriter(decimals, current)
    for move in moves:
        end = writer.round(move.end)
        if move.arc is not None:  # (never short: a lead radius >= gcode_spec.MIN_LEAD_RADIUS)
            ij = writer.round(np.asarray(move.arc.center)) - writer.current
            out.append(("G3" if move.arc.sweep > 0 else "G2", f"{writer.xy(end)} I{ij[0]:.{decimals}f} J{ij[1]:.{decimals}f}"))
        else:
            out.append(("G1", writer.xy(end)))
        writer.current = end
    return out
