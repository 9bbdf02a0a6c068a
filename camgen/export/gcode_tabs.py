"""Holding tabs (``machining.holding_tabs``): bridges of stock the outline's deepest passes leave,
so the part stays held to the plate until they are cut free by hand.

The tabs are evenly spaced along the tool-centre path (the profile offset by the tool radius),
their centres at ``(i + 1/2) L / n`` of its length ``L`` from the lead-in's start (so the lead
lies midway between two tabs).  Over each, every pass below the tab's top ``Z = -(thickness -
height)`` rises to that Z and back down (Z moves only: the XY path, programmed profile or
tool-centre path, is unchanged; so they work under cutter compensation too) along a stretch of
``width + tool diameter`` of the tool-centre path: the tool disc at either end of the stretch
reaches ``r`` into it, so the bridge left is ``width`` wide where it is narrowest (on a straight
stretch; on an arc of tool-centre radius ``rho`` the tool-centre line keeps
``width + 2 r - 4 rho asin(r / (2 rho))`` of it).  Where the tab meets the profile it is the
stretch's length scaled to the profile (``width + 2 r`` on a straight stretch).

Stretches are found by arc length on the tool-centre path (chords within ``ARC_LENGTH_TOL`` of
it), their ends mapped to the programmed path at the same parameter (offsets keep the parameter)
and located on the printed primitives exactly (arcs by angle, chords by projection).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.contour import Arc, Contour
from camgen.errors import ParameterError
from camgen.export.gcode_moves import MoveWriter

__all__ = ["ARC_LENGTH_TOL", "Tabs", "path_tabs", "plan_tabs", "tabs_text"]

#: Chord tolerance (mm) of the flattening that measures arc length along the tool-centre path.
ARC_LENGTH_TOL = 1e-6


@dataclass(frozen=True)
class Tabs:
    """The tabs of one programmed path (mm): ``splits`` the stretch ends on its primitives
    ``prims`` (travel order from ``start``) as (primitive index, fraction, point), sorted;
    ``top`` the tabs' top Z; ``angles`` the cam angles (deg) of their centres on the profile;
    ``decimals`` of the program.  :meth:`moves` writes a pass rising over them."""

    splits: list[tuple[int, float, np.ndarray]]
    top: float
    angles: np.ndarray
    decimals: int
    prims: list[tuple]
    start: np.ndarray

    def moves(self, z: float) -> str:
        """The closed path from its start back to it at depth ``z`` (below the tabs' top), rising
        to the top at the first end of each stretch and back down to ``z`` at its other end."""
        writer = MoveWriter(self.decimals, self.start)
        by_prim: dict[int, list[tuple[float, np.ndarray]]] = {}
        for index, fraction, point in self.splits:
            by_prim.setdefault(index, []).append((fraction, point))
        up = True
        begin = np.asarray(self.start, dtype=float)
        for i, (kind, item) in enumerate(self.prims):
            done = 0.0
            for fraction, _ in sorted(by_prim.get(i, []), key=lambda fp: fp[0]):
                _write_part(writer, kind, item, begin, done, fraction)
                writer.out.write(f"G1 Z{self.top if up else z:.{self.decimals}f}\n")  # Z alone: the XY path is unchanged
                up, done = not up, fraction
            _write_part(writer, kind, item, begin, done, 1.0)
            begin = np.asarray(item.end_point if kind == "arc" else item[-1], dtype=float)
        writer.line(self.start)
        return writer.text()


def _write_part(writer: MoveWriter, kind: str, item, begin: np.ndarray, lo: float, hi: float) -> None:
    """Write the part ``lo .. hi`` (fractions) of one primitive (starting at ``begin``) from the
    writer's current point.  A polyline of m chords ``W_0 = begin .. W_m`` has its fraction ``f``
    at ``x = f m``: on chord ``floor(x)``, ``x - floor(x)`` along it."""
    if hi <= lo:
        return
    if kind == "arc":
        writer.arc(Arc(item.center, item.radius, item.start_angle + lo * item.sweep, (hi - lo) * item.sweep))
        return
    w = np.vstack([begin[None], item])
    m = len(item)
    x_lo, x_hi = lo * m, hi * m
    inner = np.arange(math.floor(x_lo) + 1, math.ceil(x_hi))  # vertices strictly between
    k = min(int(math.floor(x_hi)), m - 1)
    last = w[k] + (x_hi - k) * (w[k + 1] - w[k])
    writer.lines(np.vstack([w[inner], last[None]]))


def _locate(prims: list[tuple], start: np.ndarray, points: np.ndarray) -> list[tuple[int, float]]:
    """(primitive index, fraction) of the point of the closed path ``prims`` (from ``start``)
    nearest each of ``points`` (k, 2): arcs by angle, chords by projection (a polyline's fraction
    is ``(chord index + u) / chords``)."""
    best = np.full(len(points), np.inf)
    index = np.zeros(len(points), dtype=int)
    fraction = np.zeros(len(points))
    begin = np.asarray(start, dtype=float)
    for i, (kind, item) in enumerate(prims):
        if kind == "arc":
            c = np.asarray(item.center)
            v = points - c
            rel = (np.arctan2(v[:, 1], v[:, 0]) - item.start_angle) * math.copysign(1.0, item.sweep) % (2 * math.pi)
            frac = np.clip(rel / abs(item.sweep), 0.0, 1.0)
            ang = item.start_angle + frac * item.sweep
            foot = c + item.radius * np.stack([np.cos(ang), np.sin(ang)], axis=1)
            dist = np.hypot(*(points - foot).T)
            end = item.end_point
        else:
            a = np.vstack([begin[None], item[:-1]])
            b = item
            ab = b - a
            ap = points[:, None, :] - a[None]
            u = np.clip(np.einsum("kij,ij->ki", ap, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0.0, 1.0)
            d = np.hypot(*(ap - u[..., None] * ab[None]).transpose(2, 0, 1))
            j = np.argmin(d, axis=1)
            dist = d[np.arange(len(points)), j]
            frac = (j + u[np.arange(len(points)), j]) / len(item)
            end = item[-1]
        better = dist < best
        index = np.where(better, i, index)
        fraction = np.where(better, frac, fraction)
        best = np.where(better, dist, best)
        begin = np.asarray(end, dtype=float)
    return [(int(i), float(f)) for i, f in zip(index, fraction)]


def plan_tabs(count: int, width: float, height: float, stock: float, contour: Contour, offset: Contour, t_start: float,
              tool_radius: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Where the tabs are: (the global parameters (2 count,) of the ends of the raised stretches,
    on the tool-centre path ``offset`` of the profile ``contour``, the start at ``t_start``; the
    cam angles (deg) of the tab centres on the profile; the tabs' top Z).  Raises
    :class:`ParameterError` where the tabs do not fit (each stretch ``width + 2 r`` and a tool
    diameter of full cut between them) or are as high as the stock."""
    r = tool_radius
    if height >= stock:
        raise ParameterError("holding_tab_height", height, f"< the stock thickness {stock:g} mm")
    params = np.append(offset.flatten_params(ARC_LENGTH_TOL), offset.n_segments)
    pts = offset.evaluate(params)
    cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    total = float(cum[-1])
    if count * (width + 4.0 * r) > total:
        most = int(total // (width + 4.0 * r))
        raise ParameterError("holding_tabs", count, f"<= {most}",
                             f"{count} tabs of {width:g} mm, each with a tool radius on both sides and a tool diameter of "
                             f"full cut between them, do not fit on the {total:.4g} mm tool path")
    s0 = float(np.interp(t_start, params, cum))
    centres = (np.arange(count) + 0.5) * total / count
    half = 0.5 * width + r
    ends = np.stack([centres - half, centres + half], axis=1).ravel()
    t_ends = np.interp((s0 + ends) % total, cum, params)
    mid = contour.evaluate(np.interp((s0 + centres) % total, cum, params))
    return t_ends, np.degrees(np.arctan2(mid[:, 1], mid[:, 0])) % 360.0, -(stock - height)


def path_tabs(t_ends: np.ndarray, angles: np.ndarray, top: float, programmed: Contour, prims: list[tuple], start: np.ndarray,
              decimals: int) -> Tabs:
    """The tabs of :func:`plan_tabs` on the path ``prims`` (travel order, from ``start``) programmed
    on ``programmed`` (the profile, grown or not, under compensation, else its tool-centre path:
    all share the profile's parameter)."""
    points = programmed.evaluate(t_ends)
    located = _locate(prims, start, points)
    splits = sorted(((i, f, p) for (i, f), p in zip(located, points)), key=lambda s: (s[0], s[1]))
    return Tabs(splits, top, angles, decimals, prims, start)


def tabs_text(tabs: Tabs, width: float, height: float) -> str:
    """The header's list of the tabs."""
    where = ", ".join(f"{a:.2f}" for a in tabs.angles)
    return (f"holding tabs: {len(tabs.angles)} at cam angles {where} deg, {width:g} wide [narrowest], {height:g} high "
            f"[top Z{tabs.top:g}]: passes below it rise over them; cut the tabs free after the program")

