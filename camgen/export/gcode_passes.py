"""The depth passes of one milling operation of a G-code program (:mod:`camgen.export.gcode`).

An :class:`Operation` is one programmed closed path with its leads, cut at its depths: per pass
a rapid to the entry point ``P0`` (the tool centre where the lead-in starts, outside the part),
the descent to the pass depth (:mod:`camgen.export.gcode_entry`: a helix or ramp from the floor
the tool reached before, or a plunge), the lead-in, the closed path, the lead-out and a rapid up
to the safe height.  The leads are given as text, one block each, so their geometry lives
elsewhere.

An operation with an ``approach`` point (the finishing pass after roughing with a stock
allowance) goes down straight there, where an earlier operation's entry has cleared the stock to
its depth, and feeds across to ``P0`` at that depth.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camgen.contour import Contour
from camgen.errors import GeometryError, ParameterError
from camgen.export.gcode_entry import Entry, entry_moves
from camgen.export.gcode_spec import MachiningSpec
from camgen.export.gcode_tabs import Tabs

__all__ = ["Operation", "grown_paths", "outline_passes", "passes_text"]


def grown_paths(contour: Contour, spec: MachiningSpec) -> tuple[Contour, Contour]:
    """The roughing paths for ``stock_allowance``: (the profile grown by the allowance, the
    programmed path under cutter compensation; its offset by the tool radius on top, the
    tool-centre path).  An allowance that makes a concave radius of the profile vanish, or leaves
    it below the tool radius, is a :class:`ParameterError` naming ``stock_allowance_mm``."""
    a, r = spec.stock_allowance, spec.tool_radius
    tol = min(1e-6, 0.05 * spec.chord_tol)
    try:
        return contour.offset(a, spline_tol=tol), contour.offset(a + r, spline_tol=tol)
    except GeometryError as exc:
        raise ParameterError("stock_allowance_mm", a, "a smaller allowance: every concave radius of the profile must stay above "
                             f"the tool radius {r:g} mm plus the allowance", str(exc)) from None


def passes_text(spec: MachiningSpec, levels: tuple[float, ...]) -> str:
    """The header's words on the roughing and finishing passes (empty without an allowance)."""
    if spec.stock_allowance <= 0.0:
        return ""
    return (f"; stock allowance {spec.stock_allowance:g}: the {len(levels)} passes rough the profile grown by it, "
            f"then one finishing pass at Z{levels[-1]:g} on the profile")


@dataclass(frozen=True)
class Operation:
    """One outline operation (mm).

    ``plunge``: the entry point ``P0`` (2,), the tool centre where the lead-in starts;
    ``lead_in``, ``moves``, ``lead_out``: the program text of the lead-in (from ``P0``), of the
    closed path and of the lead-out (ending with the tool outside the part); ``depths``: the Z of
    its passes, falling, < 0; ``name``: how the pass comments call it; ``entry``: the way down
(None: a plunge); ``floor``: the Z the first pass descends from (the stock top, 0, or the depth
an earlier operation reached at ``P0``); ``approach``: where the tool goes down instead of ``P0``
(module docstring); ``tabs``: the holding tabs the passes below their top rise over.
    """

    plunge: np.ndarray
    lead_in: str
    moves: str
    lead_out: str
    depths: tuple[float, ...]
    name: str = "pass"
    entry: Entry | None = None
    floor: float = 0.0
    approach: np.ndarray | None = None
    tabs: Tabs | None = None


def outline_passes(op: Operation, spec: MachiningSpec) -> str:
    """The program text of every pass of ``op``: rapid to ``P0`` (or the approach point) at the
    safe height, the way down to the pass depth at the plunge feed, the leads and the closed path,
    a rapid up."""
    d = spec.decimals
    out = []
    n = len(op.depths)
    floor = op.floor
    for k, z in enumerate(op.depths, 1):
        out.append(f"({op.name} {k} of {n}: Z{z:.{d}f})\n")
        if op.approach is not None:  # down where the stock is cleared, across to P0 at the depth
            out.append(f"G0 X{op.approach[0]:.{d}f} Y{op.approach[1]:.{d}f}\nG1 Z{z:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}\n"
                       f"G1 X{op.plunge[0]:.{d}f} Y{op.plunge[1]:.{d}f}\n")
        else:
            out.append(f"G0 X{op.plunge[0]:.{d}f} Y{op.plunge[1]:.{d}f}\n")
            if op.entry is None or op.entry.kind == "plunge":
                out.append(f"G1 Z{z:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}\n")
            else:  # straight down to the floor reached before, then the helix or ramp
                out.append(f"G1 Z{floor:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}\n" + entry_moves(op.entry, floor, z, d, spec.plunge_feed, spec.feed_decimals))
        moves = op.tabs.moves(z) if op.tabs is not None and z < op.tabs.top - 1e-9 else op.moves
        out.append(f"{op.lead_in}{moves}{op.lead_out}G0 Z{spec.safe_z:.{d}f}\n")
        floor = z
    return "".join(out)
