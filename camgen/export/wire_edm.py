"""Wire-EDM program (ISO G-code, ``dialect = "wire_edm"``) that cuts a plate cam's outline.

XY only: the wire runs through the plate (no Z word anywhere).  The wire offset is the
control's: every cut programs the profile itself with ``G41 D<k>`` (wire left of a clockwise
travel = outside the part), switched on and off (``G40``) on ``G1`` moves only; register ``D<k>``
holds cut k's offset, ``wire radius + spark gap + allowance_k`` (:mod:`camgen.export.wire_edm_spec`;
the header lists the values).

Geometry (``S`` the start point on the profile, a support point: its tangent line has the
whole profile on one side, :func:`camgen.export.gcode.start_parameter`; ``t`` the
counter-clockwise tangent and ``n`` the outward normal there; ``h`` = ``start_hole_offset``):

* start hole centre ``H = S + h t + h n``; the wire enters ``H -> A = S + h t`` (along the normal,
  compensation switched on) and ``A -> S`` along the tangent line, outside the part (the
  support line), so the wire reaches its offset path before ``S`` whatever the control's
  start-up type (LinuxCNC: the concave corner at ``A``, ``h`` > the offset);
* each cut runs clockwise from ``S`` round to the stop point ``T``, ``tab_width`` before ``S``
  measured along the profile: the stretch ``T -> S`` (the tab) holds the part.  Cuts before the
  last end there with ``G40 G1`` to the wire's own position (it does not move), the wire is cut
  (``M00``), and the next cut threads again at ``H``;
* the last cut (no allowance) stops at ``T`` with ``M00`` (secure the part), then cuts the tab
  ``T -> S`` at its offset: the part drops at ``S``.  The tab stretch is cut once, at the final
  offset (no skim: its surface is a first cut's).

With ``wire_compensation = false`` every cut programs the wire-centre path instead (the profile
offset by the cut's offset, the same entry and tab moved out by it, no ``G41``):
:mod:`camgen.export.wire_edm_centre`.

The bore and keyway (``cam_body``) are cut first, before the outline, as an inner contour with the
same cuts and registers (:mod:`camgen.export.wire_edm_bore`), unless ``bore_operation = "none"``
leaves them to another operation (the header says which).
"""
from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Sequence

import numpy as np

from camgen.contour import Arc, Contour
from camgen.errors import GeometryError, ParameterError, require_positive
from camgen.export.gcode import start_parameter
from camgen.export.gcode_moves import MoveWriter, comment, primitives, reverse_primitives, rotate, split_segment
from camgen.export.gcode_spec import FIT_SHARE, MachiningSpec, rounding_error
from camgen.export.wire_edm_centre import centre_cut_text, centre_cuts, refit_tolerance

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.kinds.base import Pocket

__all__ = ["LENGTH_TOL", "length_parameter", "wire_edm_program"]

#: Accuracy (mm) of the stop point's distance along the profile from the start point.
LENGTH_TOL = 1e-9


def length_parameter(path: Contour, length: float) -> float:
    """Global parameter of the point ``length`` mm along ``path`` from its start (arcs exactly,
    spline segments by bisection on the length of their head to within :data:`LENGTH_TOL`)."""
    rest = length
    for i, seg in enumerate(path.segments):
        if rest <= seg.length:
            if isinstance(seg, Arc):
                return i + rest / seg.length
            lo, hi = 0.0, 1.0
            while (hi - lo) * seg.length > LENGTH_TOL:
                mid = 0.5 * (lo + hi)
                head = split_segment(seg, mid)[0]
                if (head.length if head is not None else 0.0) < rest:
                    lo = mid
                else:
                    hi = mid
            return i + 0.5 * (lo + hi)
        rest -= seg.length
    return float(path.n_segments)


def _split_at(path: Contour, t: float) -> Contour:
    """``path`` with a segment boundary at global parameter ``t`` (the same closed curve)."""
    i, u = int(math.floor(t)), t - math.floor(t)
    if u <= 0.0:
        return path
    head, tail = split_segment(path.segments[i], u)
    segs = list(path.segments[:i]) + [s for s in (head, tail) if s is not None] + list(path.segments[i + 1:])
    return Contour(segs, closure_tol=1e-5)


def _check_concave(prims: list[tuple], offset: float, decimals: int) -> None:
    """A concave arc of the counter-clockwise ``prims`` whose radius is not above the wire
    offset cannot be followed with the wire outside (the control refuses it): a GeometryError."""
    least = 100.0 * 10.0 ** (-decimals)
    for kind, arc in prims:
        if kind != "arc" or arc.sweep > 0:
            continue
        half = math.sin(min(abs(arc.sweep), math.pi) / 2.0)
        if arc.radius <= offset or (2.0 * arc.radius * half >= least and 2.0 * (arc.radius - offset) * half < least):
            mid = arc.point(np.array([0.5]))[0]
            polar = math.degrees(math.atan2(mid[1], mid[0])) % 360.0
            raise GeometryError(f"wire_edm: the concave arc of radius {arc.radius:.4g} mm near cam angle {polar:.3f} deg is not "
                                f"above the first cut's wire offset {offset:.4g} mm; use a thinner wire or a smaller allowance")


def wire_edm_program(contour: Contour, spec: MachiningSpec, cam: str = "cam", scene: str = "", thickness: float | None = None,
                     pockets: "Sequence[Pocket]" = (), cam_body: "BodySpec | None" = None) -> str:
    """ISO wire-EDM program text that cuts the outline ``contour`` of a plate ``thickness`` mm
    thick (default ``spec.thickness``) with the cuts of ``spec.wire_edm`` (module docstring);
    ``cam_body``'s bore and keyway are cut first (:mod:`camgen.export.wire_edm_bore`) or left to
    another operation (the header says which)."""
    from camgen import __version__
    from camgen.export.gcode_units import in_program_units, units_note

    if spec.program_unit != 1.0:  # inch: the same program of the scaled geometry and spec (camgen.export.gcode_units)
        return in_program_units(wire_edm_program, contour, spec, cam, scene, thickness, pockets, cam_body)
    wire = spec.wire_edm
    assert wire is not None, "a wire-EDM program needs the wire spec (dialect = wire_edm)"
    if pockets:
        raise ParameterError("dialect", spec.dialect, "a milling dialect for a cam with pockets",
                             "a pocket (a groove) is blind: a wire cuts only through the plate")
    stock = spec.thickness if thickness is None else require_positive("thickness", thickness, "mm")
    offsets = wire.offsets
    try:
        contour.offset(offsets[0], spline_tol=1e-6)  # the first cut's wire path exists (no undercut, no neck)
    except GeometryError as exc:
        raise GeometryError(f"a wire offset of {offsets[0]:g} mm cannot follow the profile ({exc})") from None
    t_start = start_parameter(contour, "wire_edm start hole")
    path = rotate(contour, t_start)  # counter-clockwise from S
    total = path.length
    if not wire.tab_width < 0.5 * total:
        raise ParameterError("tab_width", wire.tab_width, f"< half the profile's length = {0.5 * total:.4g} mm")
    t_tab = length_parameter(path, wire.tab_width)  # T: tab_width along the profile counter-clockwise from S
    stop = path.evaluate(np.array([t_tab]))[0]
    stop_normal = path.normal(np.array([t_tab]))[0]
    path = _split_at(path, t_tab)
    comp_spec = dataclasses.replace(spec, cutter_compensation=True)  # chords fitted for a compensated path
    prims = primitives(path, comp_spec)
    if wire.wire_compensation:
        _check_concave(prims, offsets[0], spec.decimals)
    start = path.segments[0].start_point
    tangent = path.tangent(np.array([0.0]))[0]  # counter-clockwise
    normal = np.array([tangent[1], -tangent[0]])  # outward
    ends = np.array([p[1].end_point if p[0] == "arc" else p[1][-1] for p in prims])
    n_tab = int(np.argmin(np.hypot(*(ends - stop).T))) + 1  # prims S -> T (counter-clockwise): the tab
    if float(np.hypot(*(ends[n_tab - 1] - stop))) > 1e-6:
        raise GeometryError("wire_edm: the stop point is not a joint of the written path")  # pragma: no cover
    cw = reverse_primitives(prims, start)  # clockwise from S: S -> T (the cut), then T -> S (the tab)
    main, tab = cw[: len(cw) - n_tab], cw[len(cw) - n_tab:]
    h = wire.start_hole_offset
    a_point = start + h * tangent
    hole = a_point + h * normal

    d = spec.decimals
    main_writer = MoveWriter(d, start)
    for kind, item in main:
        main_writer.arc(item) if kind == "arc" else main_writer.lines(item)
    tab_writer = MoveWriter(d, stop)
    for kind, item in tab:
        tab_writer.arc(item) if kind == "arc" else tab_writer.lines(item)
    gap = float(np.hypot(*(tab_writer.current - tab_writer.round(start))))
    if gap > 1e-4:
        raise GeometryError(f"the written contour does not close: it ends {gap:.3g} mm from its start")  # pragma: no cover
    tab_writer.line(start)
    # wire_compensation = false: every cut programs the wire-centre path (camgen.export.wire_edm_centre)
    centre = None if wire.wire_compensation else centre_cuts(path, offsets, spec, stop)

    def xy(p: np.ndarray) -> str:
        return f"X{p[0]:.{d}f} Y{p[1]:.{d}f}"

    from camgen.export.wire_edm_bore import wire_bore  # the bore and keyway: an inner contour, cut first

    bored = wire_bore(cam_body, spec)
    n = wire.cuts
    fit_what = "biarc" if spec.spline_mode == "biarcs" else "chord"
    lines = [
        "%",
        comment(f"camgen {__version__}: cam '{cam}'" + (f", scene '{scene}'" if scene else "") + "; wire EDM, ISO"),
        comment(f"{units_note(spec)}; X0 Y0 = the cam axis; XY only, plate {stock:g} thick; the outline, wire outside, clockwise"),
        comment(f"wire diameter {wire.wire_diameter:g}; spark gap {wire.spark_gap:g}; {n} cuts = 1 + {wire.skim_cuts} skims; "
                "offset of cut k = wire radius + spark gap + allowance k"),
    ]
    for k, (offset, allowance) in enumerate(zip(offsets, wire.allowances), 1):
        lines.append(comment(f"register D{k} = {offset:.{d}f}: cut {k}, allowance {allowance:g}" if centre is None else
                             f"cut {k}: wire-centre path = the profile offset by {offset:.{d}f}, allowance {allowance:g}"))
    if centre is not None:
        lines.append(comment("wire_compensation = false: the wire-centre path is programmed, no G41/G42 [no register used]; "
                             f"spline segments of the offset refitted within {refit_tolerance(spec):.3g}"))
    lines += [
        comment(f"start hole diameter {wire.start_hole_diameter:g} at {xy(hole)} [drill it first]; lead-in {xy(hole)} -> "
                f"{xy(a_point)} {'[G41 on]' if centre is None else '+ the cut offset along the normal'}, then along the tangent to the start point {xy(start)}"),
        comment(f"tab {wire.tab_width:g} long along the profile from the stop point {xy(stop)} to the start point: cuts 1.."
                f"{n} stop there; the last cut stops [M00] before cutting it off and the part drops"),
        comment("the tab stretch is cut once, at the last cut's offset" + ("" if bored is not None else
                                                                          "; the bore and keyway are not cut: another operation")),
        comment(f"path tolerance {spec.chord_tol:g} = {fit_what} fit {FIT_SHARE * spec.chord_tol:.3g} + "
                + ("" if centre is None else f"offset refit {refit_tolerance(spec):.3g} + ") + f"{d} printed decimals {rounding_error(d):.3g}"),
        f"{spec.units_word} G90 G17 G40 G54",
    ]
    if bored is not None:
        lines[-1:-1] = bored.header
    body = ["\n".join(lines) + "\n"] + (list(bored.cuts) if bored is not None else [])
    for k, offset in enumerate(offsets, 1):
        if centre is not None:
            body.append(centre_cut_text(k, n, centre[k - 1], hole, a_point, normal, wire.wire_feed, xy))
            continue
        body.append(
            f"(cut {k} of {n}: wire offset D{k} = {offset:.{d}f})\n"
            f"G0 {xy(hole)}\n"
            "M00 (thread the wire in the start hole)\n"
            f"G41 D{k} G1 {xy(a_point)} F{wire.wire_feed:g}\n"
            f"G1 {xy(start)}\n"
            f"{main_writer.text()}"
        )
        if k < n:
            body.append(f"G40 G1 {xy(stop + offset * stop_normal)}\nM00 (cut the wire)\n")
        else:
            body.append(f"M00 (stop: secure the part; the next moves cut the tab off and the part drops)\n"
                        f"{tab_writer.text()}"
                        f"G40 G1 {xy(start + offset * normal)}\n"
                        "M00 (cut the wire: the part is free)\n")
    body.append("M30\n%\n")
    return "".join(body)
