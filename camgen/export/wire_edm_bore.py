"""The shaft bore and keyway in a wire-EDM program (``dialect = "wire_edm"``, ``bore_operation``
``"wire"``, the default for a cam with a bore): an inner contour cut before the outline.

The hole is the bore circle (radius ``R``, at the axis) with the keyway's rectangle (width ``w``,
to ``R + keyway_depth`` along ``keyway_angle``), exactly as the cam's body defines it
(:meth:`camgen.body.BodySpec.keyway_corners`).  Each cut programs that contour itself,
counter-clockwise with ``G41 D<k>`` (wire left of the travel = inside the hole), so the wire path is
the hole offset inward by the cut's register: wire radius + spark gap + allowance, as for the
outline (:mod:`camgen.export.wire_edm`).  The control rolls the wire round the two sharp corners
where the keyway meets the bore (left sharp) and stops it short of the keyway's two bottom
corners, left at the wire offset of the last cut (wire radius + spark gap).

Geometry in the frame of the start point ``S = (R, 0)``, on the bore circle opposite the keyway
(world angle ``keyway_angle + pi``):

* start hole at the axis; the wire enters along a line from the axis to ``A``, switching
  compensation on (``G41 D<k>``: on a linear move), tangent there to the **lead-in arc** of radius
  ``q = R / LEAD_SHARE`` centred at ``(R - q, 0)``, which touches the bore circle at ``S`` from
  inside; ``A`` is the arc's tangent point seen from the axis: ``cos alpha = -q / (R - q)``.  The
  compensated entry ends on the offset lead-in arc (LinuxCNC: at ``A + offset x`` the left normal of
  the entry, which is the arc's inward normal there), so the wire joins the bore's offset path at
  ``S`` tangentially, with no corner;
* each cut runs counter-clockwise from ``S`` round to the stop point ``T``, ``tab_width`` before
  ``S`` along the bore circle: the stretch ``T -> S`` (the tab) holds the slug.  Cuts before the
  last end there with ``G40 G1`` to the wire's own position, the wire is cut (``M00``) and the next
  cut threads again at the axis; the last cut stops at ``T`` (``M00``: secure the slug), then cuts
  the tab at its offset and the slug drops.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camgen.contour import Arc
from camgen.errors import ParameterError
from camgen.export.gcode_moves import MoveWriter, comment

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.export.gcode_spec import MachiningSpec

__all__ = ["LEAD_SHARE", "WireBore", "wire_bore"]

#: The lead-in arc's radius is the bore radius over this (> 2: the axis lies outside its circle,
#: so a line from the axis touches it).
LEAD_SHARE = 3.0


@dataclass(frozen=True)
class WireBore:
    """The bore's part of a wire program: ``header`` comment lines and the text of each cut
    (threading at the axis to the stop after it; the last also cuts the tab off)."""

    header: tuple[str, ...]
    cuts: tuple[str, ...]


def _turned(p: np.ndarray, phi: float) -> np.ndarray:
    c, s = math.cos(phi), math.sin(phi)
    return np.asarray(p, dtype=float) @ np.array([[c, s], [-s, c]])


def wire_bore(body: "BodySpec | None", spec: "MachiningSpec") -> WireBore | None:
    """The bore and keyway as an inner contour of the wire program (module docstring); None for a
    cam without a bore or with ``bore_operation = "none"``.

    Raises
    ------
    ParameterError
        ``start_hole_diameter`` not below half the bore diameter; ``tab_width`` longer than the
        bore wall from the keyway to the start point; a bore or keyway too small for the wire.
    """
    from camgen.export.bore_settings import bore_operation_of

    wire = spec.wire_edm
    assert wire is not None
    if body is None or body.bore_diameter <= 0.0 or bore_operation_of(spec.bore_operation, None, spec.dialect, wire.wire_compensation) != "wire":
        return None
    big = body.bore_diameter / 2.0
    offsets = wire.offsets
    q = big / LEAD_SHARE
    if not q - offsets[0] >= 100.0 * 10.0 ** (-spec.decimals):
        raise ParameterError("bore_operation", "wire", f'"none" for a bore of diameter {body.bore_diameter:g} mm',
                             f"its lead-in arc of radius {q:.4g} mm leaves no room for the first cut's wire offset {offsets[0]:.4g} mm")
    if not wire.start_hole_diameter < big:
        raise ParameterError("start_hole_diameter", wire.start_hole_diameter, f"< bore diameter / 2 = {big:g} mm",
                             "the bore's start hole at the axis must lie well inside the slug")
    keyway = body.keyway_width > 0.0
    half = body.keyway_width / 2.0
    beta = math.asin(half / big) if keyway else 0.0
    if not wire.tab_width < big * (math.pi - beta):
        raise ParameterError("tab_width", wire.tab_width, f"< {big * (math.pi - beta):.4g} mm for the bore",
                             "the bore's tab lies on the bore wall between the keyway and the start point")
    if keyway and not half > offsets[0]:
        raise ParameterError("bore_operation", "wire", '"none" for this keyway', f"the keyway [{body.keyway_width:g} mm] is not wider than "
                                                                               f"twice the first cut's wire offset {offsets[0]:.4g} mm")
    phi = body.keyway_angle + math.pi  # the start point's world angle, opposite the keyway
    start = _turned(np.array([big, 0.0]), phi)
    tab_angle = wire.tab_width / big
    # the contour S -> T counter-clockwise (local frame: the keyway along -x), then the tab T -> S
    main: list[tuple[str, object]] = []
    if keyway:
        chord, reach = math.sqrt(big * big - half * half), body.keyway_reach
        main.append(("arc", Arc((0.0, 0.0), big, phi, math.pi - beta)))
        corners = np.array([[-reach, half], [-reach, -half], [-chord, -half]])  # keyway frame (along, across) -> (-along, -across)
        main.append(("lines", _turned(corners, phi)))
        main.append(("arc", Arc((0.0, 0.0), big, phi + math.pi + beta, math.pi - beta - tab_angle)))
    else:
        main.append(("arc", Arc((0.0, 0.0), big, phi, 2.0 * math.pi - tab_angle)))
    stop_angle = phi - tab_angle
    stop = big * np.array([math.cos(stop_angle), math.sin(stop_angle)])
    tab = Arc((0.0, 0.0), big, stop_angle, tab_angle)
    # the lead-in: a line from the axis tangent to the arc of radius q touching the bore at S
    ecc = big - q
    alpha = -math.acos(-q / ecc)
    centre = _turned(np.array([ecc, 0.0]), phi)
    lead = Arc((float(centre[0]), float(centre[1])), q, phi + alpha, -alpha)
    entry = lead.start_point

    d = spec.decimals

    def xy(p: np.ndarray) -> str:
        q = np.round(np.asarray(p, dtype=float), d) + 0.0  # no "-0.0000"
        return f"X{q[0]:.{d}f} Y{q[1]:.{d}f}"

    def written(items: list[tuple[str, object]], begin: np.ndarray) -> str:
        writer = MoveWriter(d, begin)
        for kind, item in items:
            writer.arc(item) if isinstance(item, Arc) else writer.lines(np.asarray(item))
        return writer.text()

    lead_text = written([("arc", lead)], entry)
    main_text = written(main, start)
    tab_text = written([("arc", tab)], stop)
    n = wire.cuts
    cuts = []
    for k, offset in enumerate(offsets, 1):
        text = (f"(bore cut {k} of {n}: wire offset D{k} = {offset:.{d}f})\n"
                f"G0 {xy(np.zeros(2))}\n"
                "M00 (thread the wire in the bore's start hole)\n"
                f"G41 D{k} G1 {xy(entry)} F{wire.wire_feed:g}\n"
                f"{lead_text}{main_text}")
        if k < n:
            text += f"G40 G1 {xy(stop * (1.0 - offset / big))}\nM00 (cut the wire)\n"
        else:
            text += (f"M00 (stop: secure the slug; the next moves cut the tab off and the slug drops)\n{tab_text}"
                     f"G40 G1 {xy(start * (1.0 - offset / big))}\nM00 (cut the wire: the bore is free)\n")
        cuts.append(text)
    what = f"bore diameter {body.bore_diameter:g}" + (f" and keyway {body.keyway_width:g} wide to {body.keyway_reach:g} from the axis"
                                                        if keyway else "")
    header = [
        comment(f"{what}: cut first, an inner contour, wire inside [G41 D<k>, counter-clockwise], the same cuts and registers"),
        comment(f"bore start hole diameter {wire.start_hole_diameter:g} at the axis X0 Y0 [drill it first]; lead-in: a line to "
                f"{xy(entry)} [G41 on], then an arc of radius {q:.4g} touching the bore at the start point {xy(start)}"),
        comment(f"bore tab {wire.tab_width:g} long along the bore wall from {xy(stop)} to the start point: every cut stops there; the "
                "last stops [M00: secure the slug], then cuts the tab and the slug drops"),
    ]
    if keyway:
        header.append(comment(f"keyway: its two inner corners left at the last cut's wire offset {offsets[-1]:.{d}f}, the corners "
                              "where it meets the bore sharp"))
    return WireBore(tuple(header), tuple(cuts))
