"""How the tool gets down to each pass depth of an outline operation (``machining.entry``).

The entry point ``P0`` (the tool centre where the lead-in starts) lies at least the tool radius
``r`` outside the profile's tangent line at its support point ``S`` (:mod:`camgen.export.gcode`):
the whole profile lies on the inner side of that line, so every tool-centre point whose distance
outward from the line (the ``outward`` unit normal ``n``) is >= ``r`` keeps the tool disc off the
part.  From the floor the tool reached before (the previous pass's depth, or Z0, the stock top,
for the first pass) it goes down to the pass depth by

* ``helix``: whole turns of a helix (``G2/G3`` half turns with Z) of radius ``HELIX_SHARE * r``
  through ``P0``, its centre ``P0 + HELIX_SHARE r n`` outward of ``P0``: every point of the
  circle is at least as far outward as ``P0``.  It turns the way the tool leaves ``P0`` along the
  lead-in (climb: counter-clockwise, the climb sense of a hole), its radius below ``r`` so no
  core is left standing inside it;
* ``ramp``: a zig-zag of straight ramps along the line through ``P0`` parallel to the tangent
  line (hence as far outward as ``P0``), ``ramp_length`` back from ``P0`` (the side away from the
  lead-in) and forward again, ending at ``P0``;
* ``plunge``: a straight feed down (the program before issue 27).

The descent of the helix and of the ramp makes at most ``ramp_angle`` with the XY plane, at the
tool centre: the number of turns (ramps) per pass is the least that keeps it, and the pitch is
the pass's descent divided among them.  The feed is ``plunge_feed``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.contour import Arc
from camgen.export.entry_settings import ENTRIES, HELIX_SHARE, MAX_ENTRY_TURNS, MAX_RAMP_ANGLE_DEG, check_entry_settings, ramp_length
from camgen.export.gcode_moves import MoveWriter

__all__ = ["ENTRIES", "Entry", "HELIX_SHARE", "MAX_ENTRY_TURNS", "MAX_RAMP_ANGLE_DEG", "check_entry_settings", "entry_moves",
           "entry_text", "plan_entry"]

@dataclass(frozen=True)
class Entry:
    """The way down at an entry point (mm, rad).

    ``kind``: one of :data:`ENTRIES`; ``point``: ``P0`` (2,); ``angle``: the largest descent
    angle; ``centre`` and ``radius``: the helix's; ``ccw``: its sense; ``back``: the unit
    direction of the ramp's first leg; ``length``: the ramp's leg length, or the helix's turn.
    """

    kind: str
    point: np.ndarray
    angle: float
    centre: np.ndarray
    radius: float
    ccw: bool
    back: np.ndarray
    length: float


def plan_entry(kind: str, angle: float, point: np.ndarray, travel: np.ndarray, outward: np.ndarray, tool_radius: float,
               lead: float) -> Entry:
    """The entry at ``point`` (P0): ``travel`` the unit direction the lead-in leaves it in,
    ``outward`` the unit normal of the clear half-plane (module docstring)."""
    radius = HELIX_SHARE * tool_radius
    centre = point + radius * outward
    # the sense in which the circle through P0 about the centre runs along the travel at P0
    rel = point - centre
    ccw = bool(rel[0] * travel[1] - rel[1] * travel[0] > 0.0)
    along = np.array([-outward[1], outward[0]])  # parallel to the tangent line
    back = -along if float(along @ travel) > 0.0 else along
    length = 2.0 * math.pi * radius if kind == "helix" else ramp_length(tool_radius, lead)
    return Entry(kind, np.asarray(point, dtype=float), angle, centre, radius, ccw, back, length)


def _turns(entry: Entry, drop: float) -> int:
    per_turn = entry.length if entry.kind == "helix" else 2.0 * entry.length
    return max(1, math.ceil(drop / (per_turn * math.tan(entry.angle)) - 1e-9))


def entry_moves(entry: Entry, z_from: float, z_to: float, decimals: int, feed: float, feed_decimals: int = 0) -> str:
    """The moves from ``P0`` at ``z_from`` down to ``P0`` at ``z_to`` (the first with ``F feed``,
    printed with ``feed_decimals``: 0 in mm/min, more in in/min)."""
    if entry.kind == "plunge" or z_to >= z_from:
        return f"G1 Z{z_to:.{decimals}f} F{feed:.{feed_decimals}f}\n"
    n = _turns(entry, z_from - z_to)
    writer = MoveWriter(decimals, entry.point, z_from)
    if entry.kind == "helix":
        sense = math.pi if entry.ccw else -math.pi
        a0 = math.atan2(*(entry.point - entry.centre)[::-1])
        for k in range(2 * n):  # half turns: never a whole circle in one block
            writer.arc(Arc(tuple(entry.centre), entry.radius, a0 + k * sense, sense), z=z_from + (z_to - z_from) * (k + 1) / (2 * n))
    else:
        far = entry.point + entry.length * entry.back
        for k in range(2 * n):  # out along ``back`` and in again, n times
            writer.line(far if k % 2 == 0 else entry.point, z=z_from + (z_to - z_from) * (k + 1) / (2 * n))
    text = writer.text()
    first, rest = text.split("\n", 1)
    return f"{first} F{feed:.{feed_decimals}f}\n{rest}"


def entry_text(entry: Entry) -> str:
    """The header's description of the entry."""
    deg = math.degrees(entry.angle)
    if entry.kind == "helix":
        return (f"entry by helix {'G3' if entry.ccw else 'G2'} of radius {entry.radius:g} about X{entry.centre[0]:.4f} "
                f"Y{entry.centre[1]:.4f}, descent <= {deg:g} deg, from the previous pass floor (Z0 first)")
    if entry.kind == "ramp":
        return f"entry by zig-zag ramp of length {entry.length:g} back from the entry point, descent <= {deg:g} deg, from the previous pass floor (Z0 first)"
    return "entry by straight plunge"
