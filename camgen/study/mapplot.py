"""Scatter and cell plots of a study as inline SVG: numeric or categorical axes, one element per
design or cell carrying its data (``data-*`` attributes and a ``<title>`` tooltip).

:mod:`camgen.report.svgplot` draws curves as one path each; a sweep's maps need each design as
its own element (its colour tells its first failing check, hovering names it, a test reads it),
so this module lays out the axes itself with the same tick rule (:func:`camgen.report.svgplot.nice_ticks`),
fonts and colours.  Coordinates are rounded to 0.01 px; the same input gives the same bytes.
"""
from __future__ import annotations

import html
import math
from dataclasses import dataclass
from typing import Sequence

__all__ = ["Axis", "Cell", "Mark", "category_axis", "numeric_axis", "plot_svg"]

#: Plot size and the margins around the plot area, px (CSS pixels).
WIDTH, HEIGHT = 720.0, 440.0
LEFT, RIGHT, TOP, BOTTOM = 112.0, 16.0, 12.0, 58.0  # LEFT: room for a word tick (modified_sine) and the rotated title
#: Text size, px; a label's width is estimated at this many font sizes per character.
FONT_PX = 12.0
CHAR_EM = 0.6
#: Automatic limits: the data's range plus this fraction of it each side.
MARGIN = 0.05
FONT_FAMILY = "system-ui,-apple-system,'Segoe UI',Roboto,'Helvetica Neue',Arial,sans-serif"


@dataclass(frozen=True)
class Axis:
    """One axis: its label, its limits in data units and, for a categorical axis, the category
    names (category ``i`` at ``i``; limits ``-0.5`` to ``n - 0.5``)."""

    label: str
    lo: float
    hi: float
    categories: tuple[str, ...] = ()


def numeric_axis(label: str, values: Sequence[float]) -> Axis:
    """An axis over the finite ``values`` with :data:`MARGIN` each side (one value: +-5 % of it)."""
    finite = [v for v in values if math.isfinite(v)]
    lo, hi = (min(finite), max(finite)) if finite else (0.0, 1.0)
    if hi <= lo:
        d = abs(lo) * 0.05 or 1.0
        return Axis(label, lo - d, hi + d)
    pad = MARGIN * (hi - lo)
    return Axis(label, lo - pad, hi + pad)


def category_axis(label: str, names: Sequence[str]) -> Axis:
    """An axis of the categories ``names``, in order."""
    return Axis(label, -0.5, len(names) - 0.5, tuple(names))


@dataclass(frozen=True)
class Mark:
    """A design drawn as a disc at (x, y) data units, ``radius`` px, filled ``color``."""

    x: float
    y: float
    color: str
    title: str
    attrs: tuple[tuple[str, str], ...] = ()
    radius: float = 4.0
    cls: str = "point"


@dataclass(frozen=True)
class Cell:
    """A rectangle from (x0, y0) to (x1, y1) data units filled ``color``, with ``text`` inside."""

    x0: float
    x1: float
    y0: float
    y1: float
    color: str
    title: str
    text: str = ""
    attrs: tuple[tuple[str, str], ...] = ()


def _n(v: float) -> str:
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _esc(s: str) -> str:
    return html.escape(s, quote=True)


def _attrs(pairs: Sequence[tuple[str, str]]) -> str:
    return "".join(f' {name}="{_esc(value)}"' for name, value in pairs)


def _ticks(axis: Axis, length: float) -> tuple[list[float], list[str], int]:
    """Tick positions (data), labels and the power of ten of the labels."""
    if axis.categories:
        n = len(axis.categories)
        widest = max((len(c) for c in axis.categories), default=1) * CHAR_EM * FONT_PX + 8.0
        step = max(1, math.ceil(n * min(widest, 160.0) / length)) if length > 0 else 1
        return [float(i) for i in range(0, n, step)], [axis.categories[i] for i in range(0, n, step)], 0
    from camgen.report.svgplot import nice_ticks

    values, labels, power = nice_ticks(axis.lo, axis.hi, length,
                                       lambda ls: max(len(s) for s in ls) * CHAR_EM * FONT_PX + 1.2 * FONT_PX)
    return [float(v) for v in values], list(labels), power


def plot_svg(xaxis: Axis, yaxis: Axis, *, marks: Sequence[Mark] = (), cells: Sequence[Cell] = (),
             line: Sequence[tuple[float, float]] = (), line_color: str = "#d55e00", svg_id: str = "plot") -> str:
    """An ``<svg>`` of ``cells`` under ``marks`` (designs in the order given, later on top) and a
    ``line`` through points (data units), over the axes ``xaxis`` and ``yaxis``."""
    w, h = WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM
    sx, sy = w / (xaxis.hi - xaxis.lo), h / (yaxis.hi - yaxis.lo)

    def px(x: float) -> float:
        return LEFT + (x - xaxis.lo) * sx

    def py(y: float) -> float:
        return TOP + h - (y - yaxis.lo) * sy

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" id="{_esc(svg_id)}" width="{_n(WIDTH)}" height="{_n(HEIGHT)}" '
           f'viewBox="0 0 {_n(WIDTH)} {_n(HEIGHT)}" style="max-width:100%;height:auto" font-family="{FONT_FAMILY}" '
           f'font-size="{_n(FONT_PX)}" fill="#222222"><rect width="{_n(WIDTH)}" height="{_n(HEIGHT)}" fill="#ffffff"/>']
    xt, xl, xp = _ticks(xaxis, w)
    yt, yl, yp = _ticks(yaxis, h)
    grid = "".join(f"M{_n(px(v))},{_n(TOP)}V{_n(TOP + h)}" for v in xt) + "".join(f"M{_n(LEFT)},{_n(py(v))}H{_n(LEFT + w)}" for v in yt)
    out.append(f'<path class="grid" d="{grid}" fill="none" stroke="#dddddd" stroke-width="1"/>')
    clip = f"{svg_id}-clip"
    out.append(f'<clipPath id="{_esc(clip)}"><rect x="{_n(LEFT)}" y="{_n(TOP)}" width="{_n(w)}" height="{_n(h)}"/></clipPath>'
               f'<g class="data" clip-path="url(#{_esc(clip)})">')
    for c in cells:
        x0, x1 = sorted((px(c.x0), px(c.x1)))
        y0, y1 = sorted((py(c.y0), py(c.y1)))
        out.append(f'<rect class="cell" x="{_n(x0)}" y="{_n(y0)}" width="{_n(x1 - x0)}" height="{_n(y1 - y0)}" fill="{c.color}" '
                   f'stroke="#ffffff" stroke-width="1"{_attrs(c.attrs)}><title>{_esc(c.title)}</title></rect>')
        if c.text and x1 - x0 >= len(c.text) * CHAR_EM * 11.0 + 4.0 and y1 - y0 >= 14.0:
            out.append(f'<text x="{_n((x0 + x1) / 2)}" y="{_n((y0 + y1) / 2 + 4.0)}" text-anchor="middle" font-size="11" '
                       f'pointer-events="none">{_esc(c.text)}</text>')
    if line:
        d = "M" + " ".join(f"{_n(px(x))},{_n(py(y))}" for x, y in line)
        out.append(f'<path class="front" d="{d}" fill="none" stroke="{line_color}" stroke-width="1.5"/>')
    for m in marks:
        out.append(f'<circle class="{_esc(m.cls)}" cx="{_n(px(m.x))}" cy="{_n(py(m.y))}" r="{_n(m.radius)}" fill="{m.color}" '
                   f'stroke="#ffffff" stroke-width="0.6"{_attrs(m.attrs)}><title>{_esc(m.title)}</title></circle>')
    out.append("</g>")
    out.append(f'<rect x="{_n(LEFT)}" y="{_n(TOP)}" width="{_n(w)}" height="{_n(h)}" fill="none" stroke="#000000" stroke-width="1"/>')
    ticks = "".join(f"M{_n(px(v))},{_n(TOP + h)}v5" for v in xt) + "".join(f"M{_n(LEFT)},{_n(py(v))}h-5" for v in yt)
    out.append(f'<path class="ticks" d="{ticks}" stroke="#000000" stroke-width="1"/>')
    out.append('<g class="xticks" text-anchor="middle">' + "".join(
        f'<text x="{_n(px(v))}" y="{_n(TOP + h + 8.0 + FONT_PX)}">{_esc(s)}</text>' for v, s in zip(xt, xl)) + "</g>")
    out.append('<g class="yticks" text-anchor="end">' + "".join(
        f'<text x="{_n(LEFT - 8.0)}" y="{_n(py(v) + 4.0)}">{_esc(s)}</text>' for v, s in zip(yt, yl)) + "</g>")
    xlabel = xaxis.label + (f" (\u00d710^{xp})" if xp else "")
    ylabel = yaxis.label + (f" (\u00d710^{yp})" if yp else "")
    out.append(f'<text class="xlabel" x="{_n(LEFT + w / 2)}" y="{_n(HEIGHT - 8.0)}" text-anchor="middle">{_esc(xlabel)}</text>')
    yy = TOP + h / 2
    out.append(f'<text class="ylabel" x="16" y="{_n(yy)}" transform="rotate(-90 16 {_n(yy)})" text-anchor="middle">{_esc(ylabel)}</text>')
    out.append("</svg>")
    return "".join(out)
