"""The wire-centre mode of the wire-EDM program (``wire_compensation = false``): every cut
programs the path of the wire's centre itself, no ``G41/G42``.

Cut ``k`` follows the profile offset outward by its wire offset ``o_k = wire radius + spark gap
+ allowance_k`` (:mod:`camgen.export.wire_edm_spec`): arcs stay exact arcs of radius ``r + o_k``
(convex) or ``r - o_k`` (concave), spline segments are refitted within ``min(1e-6, REFIT_SHARE *
chord_tol)`` and written as biarcs or chords like the milling tool-centre path
(:func:`camgen.export.gcode.tool_path`).  The geometry of :mod:`camgen.export.wire_edm` is
kept, moved out by ``o_k`` along the normals: the entry runs from the start hole ``H`` along the
normal to ``A + o_k n`` and along the tangent line (``o_k`` outside the profile's tangent line at
``S``, a support line: the wire clears the part) to ``S + o_k n``; the cut runs clockwise to the
stop point ``T + o_k n_T`` (the offset keeps the segment joint at ``T``), the tab ``T -> S`` is
cut after the last cut's stop, at its offset.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from camgen.contour import Contour
from camgen.errors import GeometryError
from camgen.export.gcode_moves import MoveWriter, primitives, reverse_primitives
from camgen.export.gcode_spec import REFIT_SHARE, MachiningSpec

__all__ = ["CentreCut", "centre_cut_text", "centre_cuts", "refit_tolerance"]


def refit_tolerance(spec: MachiningSpec) -> float:
    """Tolerance (mm) of the refit of spline segments in the wire-centre path (as the milling tool path's)."""
    return min(1e-6, REFIT_SHARE * spec.chord_tol)


@dataclass(frozen=True)
class CentreCut:
    """One cut's wire-centre moves (program text) and its points (mm).

    ``start``: the wire at the start point, ``S + o n``; ``stop``: at the stop point, ``T + o n_T``;
    ``main``: the moves ``start -> stop`` (clockwise); ``tab``: the moves ``stop -> start``.
    """

    offset: float
    start: np.ndarray
    stop: np.ndarray
    main: str
    tab: str


def _write(prims: list[tuple], start: np.ndarray, decimals: int) -> MoveWriter:
    writer = MoveWriter(decimals, start)
    for kind, item in prims:
        writer.arc(item) if kind == "arc" else writer.lines(item)
    return writer


def centre_cuts(path: Contour, offsets: Sequence[float], spec: MachiningSpec, stop: np.ndarray) -> list[CentreCut]:
    """The wire-centre moves of every cut: ``path`` (the profile counter-clockwise from the start
    point, with a segment joint at the stop point ``stop``) offset by each of ``offsets`` (mm)."""
    joints = np.array([seg.end_point for seg in path.segments])
    j = int(np.argmin(np.hypot(*(joints - stop).T)))  # the segment ending at the stop point
    if float(np.hypot(*(joints[j] - stop))) > 1e-9:
        raise GeometryError("wire_edm: the stop point is not a joint of the profile")  # pragma: no cover
    plain = dataclasses.replace(spec, cutter_compensation=False)  # the fit share of chord_tol, as the tool-centre path
    d = spec.decimals
    out = []
    for offset in offsets:
        centre = path.offset(offset, spline_tol=refit_tolerance(spec))
        start = centre.segments[0].start_point
        stop_k = centre.segments[j].end_point
        prims = primitives(centre, plain)
        ends = np.array([p[1].end_point if p[0] == "arc" else p[1][-1] for p in prims])
        n_tab = int(np.argmin(np.hypot(*(ends - stop_k).T))) + 1  # prims S' -> T' (counter-clockwise): the tab
        if float(np.hypot(*(ends[n_tab - 1] - stop_k))) > 1e-6:
            raise GeometryError("wire_edm: the stop point is not a joint of the written path")  # pragma: no cover
        cw = reverse_primitives(prims, start)
        main = _write(cw[: len(cw) - n_tab], start, d)
        tab = _write(cw[len(cw) - n_tab:], stop_k, d)
        gap = float(np.hypot(*(tab.current - tab.round(start))))
        if gap > 1e-4:
            raise GeometryError(f"the written contour does not close: it ends {gap:.3g} mm from its start")  # pragma: no cover
        tab.line(start)
        out.append(CentreCut(offset, start, stop_k, main.text(), tab.text()))
    return out


def centre_cut_text(k: int, n: int, cut: CentreCut, hole: np.ndarray, entry: np.ndarray, normal: np.ndarray, feed: float,
                    xy: Callable[[np.ndarray], str]) -> str:
    """Program text of cut ``k`` of ``n`` in the wire-centre mode: thread at ``hole``, the entry
    to ``entry + o n`` (``entry`` = A on the profile's tangent line, ``normal`` the outward normal
    at S), along the tangent line to the cut's start, the cut; the last cut stops (M00) before
    the tab and then cuts it off."""
    text = (f"(cut {k} of {n}: wire-centre path, offset {cut.offset:.6g})\n"
            f"G0 {xy(hole)}\n"
            "M00 (thread the wire in the start hole)\n"
            f"G1 {xy(entry + cut.offset * normal)} F{feed:g}\n"
            f"G1 {xy(cut.start)}\n"
            f"{cut.main}")
    if k < n:
        return text + "M00 (cut the wire)\n"
    return text + ("M00 (stop: secure the part; the next moves cut the tab off and the part drops)\n"
                   f"{cut.tab}"
                   "M00 (cut the wire: the part is free)\n")
