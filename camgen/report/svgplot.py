"""Small line plots as inline SVG for report.html: axes, nice ticks, legends; numpy only.

Units (as matplotlib, so a figure keeps its size and look): the figure size is in inches,
line widths, marker sizes and font sizes are in points (1/72 in).  The SVG is drawn in CSS
pixels at 96 px per inch (1 pt = 4/3 px): a ``figsize=(10, 3.2)`` figure is 960 x 307.2 px,
the size at which a browser shows matplotlib's SVG of the same figsize (which is written in
pt).  The root ``<svg>`` has ``max-width:100%`` so it shrinks with a narrow page.

Output: an SVG string without XML prolog (inlines into HTML); the same input gives the same
bytes; text stays text (system font stack); coordinates rounded to 0.01 px; curves are
``<path>`` elements clipped to their plot area; a plot whose limits leave data out says so in
a note under it (:attr:`Axes.clip_note`).  Curves with more than ``max_vertices``
points are thinned by min/max decimation per pixel column (M4: Jugel et al., "M4: a
visualization-oriented time series data aggregation", VLDB 2014), so peaks survive.

Usage::

    fig = Figure(figsize=(10, 3.2), id_prefix="cam1-curves")
    ax1, ax2 = fig.subplots(1, 2)
    ax1.plot(angle_deg, pressure_deg, color="tab:blue", width=1, label="pressure angle")
    ax1.hline(30, color="tab:red", dash="--", width=0.8)
    ax1.xlabel("cam angle (deg)")
    svg = fig.to_svg()
"""
from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Sequence
from typing import Any

import numpy as np

from camgen.errors import ParameterError

__all__ = ["Axes", "Figure", "Line", "nice_ticks", "thin"]

PX_PER_INCH = 96.0
PX_PER_PT = PX_PER_INCH / 72.0
MARGIN = 0.05  # automatic limits: data range plus 5 % each side (matplotlib's axes.xmargin)
MAX_VERTICES = 2000  # a longer curve is thinned to about this many vertices
MAX_PX = 1.0e6  # pixel coordinates are clamped to +-MAX_PX (data far outside explicit limits)
FONT_FAMILY = "system-ui,-apple-system,'Segoe UI',Roboto,'Helvetica Neue',Arial,sans-serif"
MINUS = "\u2212"
CLIP_NOTE_SIZE = 0.9  # the clipped-data note's font size, in tick-label sizes
CLIP_NOTE_COLOR = "#b00000"
_LABEL_UNIT = re.compile(r"(.*?)\s*\(([^()]*)\)\s*\Z")  # "radius of curvature (mm)" -> name, unit

# Okabe & Ito (2008), "Color Universal Design": distinguishable with every common colour-vision
# deficiency; yellow and black left out (too light on white; black is for reference lines).
CYCLE = ("#0072B2", "#E69F00", "#009E73", "#D55E00", "#CC79A7", "#56B4E9")
NAMED_COLORS = {
    "tab:blue": "#1f77b4", "tab:orange": "#ff7f0e", "tab:green": "#2ca02c", "tab:red": "#d62728",
    "tab:purple": "#9467bd", "tab:brown": "#8c564b", "tab:pink": "#e377c2", "tab:gray": "#7f7f7f",
    "tab:grey": "#7f7f7f", "tab:olive": "#bcbd22", "tab:cyan": "#17becf",
    "k": "#000000", "black": "#000000", "w": "#ffffff", "white": "#ffffff", "r": "#ff0000", "red": "#ff0000",
    "g": "#008000", "green": "#008000", "b": "#0000ff", "blue": "#0000ff", "c": "#00bfbf", "m": "#bf00bf",
    "y": "#bfbf00", "gray": "#808080", "grey": "#808080", "orange": "#ffa500", "purple": "#800080",
    **{f"C{i}": c for i, c in enumerate(CYCLE)},
}
# dash patterns in units of the line width, as matplotlib (lines.dashed_pattern etc.)
DASHES: dict[str, tuple[float, ...] | None] = {"-": None, "solid": None, "--": (3.7, 1.6), "dashed": (3.7, 1.6),
                                               ":": (1.0, 1.65), "dotted": (1.0, 1.65), "-.": (6.4, 1.6, 1.0, 1.6),
                                               "dashdot": (6.4, 1.6, 1.0, 1.6)}
NO_LINE = ("none", "None", "", " ")
MARKERS = (".", "o", "+", "x", "s")
LEGEND_LOCATIONS = ("upper right", "upper left", "lower left", "lower right", "center right", "center left",
                    "lower center", "upper center", "center")
_HEX = re.compile(r"#(?:[0-9a-fA-F]{3}|[0-9a-fA-F]{6})\Z")
_ID = re.compile(r"[A-Za-z][A-Za-z0-9_-]*\Z")
_FMT = re.compile(r"(?P<line>--|-\.|-|:)|(?P<marker>[.o+xs])|(?P<color>[krgbcmyw])")

# advance widths (em) of DejaVu Sans, the widest common system sans-serif face (measured in
# Chromium with getComputedTextLength); for layout only, so other faces come out a little narrower
_GLYPH_WIDTHS = {c: w for w, chars in (
    (0.28, "'ijlIJ"), (0.32, " ,."), (0.34, "/:;\\|"), (0.35, "f"), (0.36, "-"), (0.39, "()[]t"), (0.40, "!"), (0.41, "r"),
    (0.46, '"'), (0.50, "*_`"), (0.52, "sz"), (0.53, "?"), (0.55, "c"), (0.56, "L"), (0.59, "Fkvxy"), (0.61, "PTYoae"),
    (0.64, "EhnuSbdgpq0123456789${}"), (0.66, "K"), (0.69, "AVXZBRC"), (0.73, "U"), (0.75, "NH"), (0.78, "DGOQ&"),
    (0.82, "w"), (0.84, "#+<=>^~\u2212\u00d7"), (0.86, "M"), (0.95, "%"), (0.97, "m"), (0.99, "W@")) for c in chars}


def _text_width(s: str, font_px: float) -> float:
    """Estimated advance width of ``s`` (px) at ``font_px`` (0.7 em for a glyph not in the table)."""
    return sum(_GLYPH_WIDTHS.get(ch, 0.7) for ch in s) * font_px


def _limit_text(v: float) -> str:
    """A plot limit in a note: 4 significant digits, the minus sign of the tick labels."""
    return f"{v:.4g}".replace("-", MINUS)


def _esc(s: str) -> str:
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def _n(v: float) -> str:
    """One coordinate, rounded to 0.01 px, without trailing zeros."""
    s = f"{v:.2f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _color(value: Any, name: str = "color") -> str:
    if isinstance(value, str):
        if value in NAMED_COLORS:
            return NAMED_COLORS[value]
        if _HEX.match(value):
            return value.lower()
    elif isinstance(value, (tuple, list)) and len(value) in (3, 4):
        rgb = [float(v) for v in value[:3]]
        if all(0.0 <= v <= 1.0 for v in rgb):
            return "#" + "".join(f"{round(v * 255):02x}" for v in rgb)
    raise ParameterError(name, value, "a name (" + ", ".join(sorted(NAMED_COLORS)[:6]) + ", ...), '#rrggbb' or an (r, g, b) tuple in 0..1")


def _positive(name: str, value: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ParameterError(name, value, "a finite number > 0")
    return v


# ---------------------------------------------------------------------------------------- ticks

def _tick_label(n: int, k: int, p: int) -> str:
    """The label of the tick n * 10**k shown in units of 10**p, written from integers (no float noise)."""
    e = k - p
    if e >= 0:
        s = str(abs(n) * 10**e)
    else:
        digits = str(abs(n)).rjust(-e + 1, "0")
        s = digits[:e] + "." + digits[e:]
    return (MINUS if n < 0 else "") + s


def _factor_exponent(lo: float, hi: float) -> int:
    """Power of ten (a multiple of 3) the tick labels are shown in: 0 unless the values are >= 1e5 or < 1e-3."""
    big = max(abs(lo), abs(hi))
    if big >= 1e5 or 0 < big < 1e-3:
        return 3 * math.floor(math.log10(big) / 3)
    return 0


def nice_ticks(lo: float, hi: float, length_px: float, min_spacing: Any, min_ticks: int = 4,
               max_ticks: int = 10) -> tuple[np.ndarray, list[str], int]:
    """Tick values m * 10**k (m in 1, 2, 5) between ``lo`` and ``hi``, their labels, and the
    power of ten ``p`` the labels are written in (value = float(label) * 10**p).

    Takes the finest step whose ticks are at most ``max_ticks`` and at least
    ``min_spacing(labels)`` px apart on an axis ``length_px`` long; a step one notch finer is
    accepted at 0.75 of that spacing to reach ``min_ticks``.  Labels have the same number of
    decimals along the axis and a minus sign (U+2212) for negative values.
    """
    span = hi - lo
    p = _factor_exponent(lo, hi)
    e = math.floor(math.log10(span))
    found: list[tuple[np.ndarray, list[str], float, float]] = []
    for k in range(e - 2, e + 2):
        for m in (1, 2, 5):
            step = m * 10.0**k
            slack = 1e-9 * span / step
            i0, i1 = math.ceil(lo / step - slack), math.floor(hi / step + slack)
            count = i1 - i0 + 1
            if count > max_ticks or count < 1:
                continue
            ns = [i * m for i in range(i0, i1 + 1)]
            values = np.array([n * 10**k if k >= 0 else n / 10**-k for n in ns], dtype=float)
            labels = [_tick_label(n, k, p) for n in ns]
            found.append((values, labels, step / span * length_px, min_spacing(labels)))
    if not found:  # cannot happen for a finite span > 0; keep the ends
        return np.array([lo, hi]), [f"{lo:g}", f"{hi:g}"], 0
    for j, (values, labels, spacing, need) in enumerate(found):
        if spacing >= need:
            if values.size < min_ticks and j > 0:
                finer = found[j - 1]
                if finer[0].size >= min_ticks and finer[2] >= 0.75 * finer[3]:
                    return finer[0], finer[1], p
            return values, labels, p
    values, labels, _, _ = next((f for f in reversed(found) if f[0].size >= 2), found[-1])
    return values, labels, p


# ------------------------------------------------------------------------------------- thinning

def _m4(px: np.ndarray, py: np.ndarray, seg: np.ndarray, bin_px: float) -> np.ndarray:
    """Indices kept by one M4 pass: for every run of consecutive points in one column of width
    ``bin_px`` (and one segment), the first and last point and those with the least and the
    greatest y and x (x: for curves that double back inside a column), in order."""
    n = px.size
    col = np.floor(px / bin_px)
    brk = np.empty(n, dtype=bool)
    brk[0] = True
    brk[1:] = (col[1:] != col[:-1]) | (seg[1:] != seg[:-1])
    starts = np.flatnonzero(brk)
    ends = np.append(starts[1:], n) - 1
    run = np.cumsum(brk) - 1
    idx = np.arange(n)
    keep = np.zeros(n, dtype=bool)
    keep[starts] = keep[ends] = True
    for reduce, values in ((np.minimum, py), (np.maximum, py), (np.minimum, px), (np.maximum, px)):
        extreme = reduce.reduceat(values, starts)
        first = np.where(values == extreme[run], idx, n)  # the first point reaching the extreme
        keep[np.minimum.reduceat(first, starts)] = True
    return np.flatnonzero(keep)


def thin(px: np.ndarray, py: np.ndarray, seg: np.ndarray, width_px: float, height_px: float,
         max_vertices: int = MAX_VERTICES) -> np.ndarray:
    """Indices of the vertices to draw of a polyline in pixels (``seg``: segment number of each
    vertex, non-decreasing), about ``max_vertices`` or fewer; every vertex kept is an original one.

    M4 passes by columns (extremes in y survive: the peaks of a time series), then by rows
    (extremes in x: the sides of a closed curve), with bins of ``4 * extent / max_vertices``
    px (at least 1 px), doubled until the count fits (at most 4 rounds).
    """
    keep = np.arange(px.size)
    if px.size <= max_vertices:
        return keep
    bx = max(1.0, 4.0 * width_px / max_vertices)
    by = max(1.0, 4.0 * height_px / max_vertices)
    for _ in range(4):
        keep = keep[_m4(px[keep], py[keep], seg[keep], bx)]
        keep = keep[_m4(py[keep], px[keep], seg[keep], by)]
        if keep.size <= max_vertices:
            break
        bx, by = 2 * bx, 2 * by
    return keep


# -------------------------------------------------------------------------------------- artists

class Line:
    """A curve drawn by :meth:`Axes.plot`; ``color`` is its resolved '#rrggbb' colour."""

    def __init__(self, x: np.ndarray, y: np.ndarray, color: str, width: float, dash: str | None,
                 marker: str | None, marker_size: float, alpha: float, label: str | None) -> None:
        self.x, self.y = x, y
        self.color, self.width, self.dash = color, width, dash
        self.marker, self.marker_size, self.alpha, self.label = marker, marker_size, alpha, label

    def get_color(self) -> str:
        """The resolved colour (as matplotlib's ``Line2D.get_color``)."""
        return self.color


class _Ref:
    """A horizontal (``axis == "y"``) or vertical reference line across the plot area."""

    def __init__(self, axis: str, value: float, color: str, width: float, dash: str, alpha: float, label: str | None) -> None:
        self.axis, self.value = axis, value
        self.color, self.width, self.dash, self.alpha, self.label = color, width, dash, alpha, label
        self.marker, self.marker_size = None, 0.0


def _stroke(color: str, width_pt: float, dash: str | None, alpha: float) -> str:
    """Stroke attributes of a line ``width_pt`` wide (dash pattern scaled by the width, as matplotlib)."""
    w = width_pt * PX_PER_PT
    out = f' stroke="{color}" stroke-width="{_n(w)}"'
    pattern = DASHES.get(dash or "-")
    if pattern:
        out += ' stroke-dasharray="' + ",".join(_n(v * max(w, 1.0)) for v in pattern) + '"'
    if alpha < 1:
        out += f' stroke-opacity="{_n(alpha)}"'
    return out


def _marker_path(marker: str, size_pt: float, color: str, alpha: float, px: np.ndarray, py: np.ndarray, cls: str = "markers") -> str:
    """One ``<path>`` drawing ``marker`` at every (px, py): dots and squares as zero-length
    subpaths with round or square caps (filled disc/square), crosses as two strokes."""
    if px.size == 0:
        return ""
    opacity = f' stroke-opacity="{_n(alpha)}"' if alpha < 1 else ""
    xy = tuple(np.column_stack([px, py]).ravel().tolist())
    if marker in (".", "o", "s"):
        # drawn size = marker size (half of it for '.') plus matplotlib's default 1 pt edge
        d = ((0.5 if marker == "." else 1.0) * size_pt + 1.0) * PX_PER_PT
        cap = "square" if marker == "s" else "round"
        path = ("M%.2f,%.2fh0" * px.size) % xy
        return f'<path class="{cls}" d="{path}" stroke="{color}" stroke-width="{_n(d)}" stroke-linecap="{cap}"{opacity}/>'
    r = 0.5 * size_pt * PX_PER_PT
    if marker == "+":
        path = (f"M%.2f,%.2fh{_n(2 * r)}m{_n(-r)},{_n(-r)}v{_n(2 * r)}" * px.size) % tuple(
            np.column_stack([px - r, py]).ravel().tolist())
    else:  # "x"
        path = (f"M%.2f,%.2fl{_n(2 * r)},{_n(2 * r)}m0,{_n(-2 * r)}l{_n(-2 * r)},{_n(2 * r)}" * px.size) % tuple(
            np.column_stack([px - r, py - r]).ravel().tolist())
    return f'<path class="{cls}" d="{path}" stroke="{color}" stroke-width="{_n(PX_PER_PT)}"{opacity}/>'


def _parse_fmt(fmt: str) -> tuple[str | None, str | None, str | None]:
    """matplotlib's format string ('o-', '--', '.', 'k+'): (line style, marker, colour letter)."""
    line = marker = color = None
    pos = 0
    while pos < len(fmt):
        m = _FMT.match(fmt, pos)
        if m is None:
            raise ParameterError("fmt", fmt, "line style (- -- : -.), marker (. o + x s) and colour letter (k r g b c m y w)")
        line = m.group("line") or line
        marker = m.group("marker") or marker
        color = m.group("color") or color
        pos = m.end()
    return line, marker, color


class Axes:
    """One plot panel of a :class:`Figure` (made by :meth:`Figure.subplots`).

    After :meth:`Figure.to_svg`: ``limits`` = (x0, x1, y0, y1) drawn, data units,
    ``area`` = (left, top, width, height) of the plot area, px, and ``clip_note``: None, or the
    note drawn under the plot when its limits leave out data of a curve (explicit limits, or
    infinite values), naming the axis and the limits ("clipped, not shown: radius (mm) above 240 mm").
    """

    def __init__(self, figure: Figure, row: int, col: int) -> None:
        self._figure, self._row, self._col = figure, row, col
        self._artists: list[Line | _Ref] = []
        self._texts: list[tuple[float, float, str, str, str, str, str, float | None]] = []
        self._title: tuple[str, float | None] | None = None
        self._xlabel: tuple[str, float | None] | None = None
        self._ylabel: tuple[str, float | None] | None = None
        self._legend: tuple[str, float | None, int] | None = None
        self._equal = False
        self._grid = True
        self._xlim: list[float | None] = [None, None]
        self._ylim: list[float | None] = [None, None]
        self._cycle = 0
        self.limits: tuple[float, float, float, float] | None = None
        self.area: tuple[float, float, float, float] | None = None
        self.clip_note: str | None = None

    # ---- content
    def plot(self, x: Any, y: Any, fmt: str = "", *, color: Any = None, width: float = 1.5, dash: str | None = None,
             marker: str | None = None, marker_size: float = 6.0, alpha: float = 1.0, label: str | None = None) -> Line:
        """Draw y against x (1-D, same length; a NaN or inf point breaks the line).

        ``fmt`` is matplotlib's short form ('o-', '--', '.', 'k+'); keywords override it.
        ``width`` (pt) of the line; ``dash`` one of '-', '--', ':', '-.' or 'none' (markers
        only); ``marker`` one of '.', 'o', '+', 'x', 's' drawn ``marker_size`` pt (as
        matplotlib's markersize); a marker from ``fmt`` without a line style draws no line.
        ``color`` a name ('tab:red', 'k', 'C0'), '#rrggbb' or an (r, g, b) tuple; by default the
        next colour of :data:`CYCLE`.  ``label`` shows in the legend (None or '_...': not shown).
        """
        xs, ys = np.asarray(x, dtype=float).ravel(), np.asarray(y, dtype=float).ravel()
        if xs.shape != ys.shape:
            raise ParameterError("x, y", f"{xs.size} and {ys.size} values", "two arrays of the same length")
        f_line, f_marker, f_color = _parse_fmt(fmt)
        marker = marker if marker is not None else f_marker
        if marker is not None and marker not in MARKERS and marker not in NO_LINE:
            raise ParameterError("marker", marker, " ".join(MARKERS) + " or 'none'")
        marker = None if marker in NO_LINE else marker
        if dash is None:
            dash = f_line if f_line is not None else ("none" if f_marker is not None else "-")
        if dash not in DASHES and dash not in NO_LINE:
            raise ParameterError("dash", dash, "'-', '--', ':', '-.' or 'none'")
        if color is None and f_color is not None:
            color = f_color
        if color is None:
            resolved = CYCLE[self._cycle % len(CYCLE)]
            self._cycle += 1
        else:
            resolved = _color(color)
        alpha = float(alpha)
        if not 0.0 <= alpha <= 1.0:
            raise ParameterError("alpha", alpha, "0 to 1")
        line = Line(xs, ys, resolved, _positive("width", width), None if dash in NO_LINE else dash, marker,
                    _positive("marker_size", marker_size), alpha, label)
        self._artists.append(line)
        return line

    def _ref(self, axis: str, value: float, color: Any, width: float, dash: str, alpha: float, label: str | None) -> None:
        v = float(value)
        if not math.isfinite(v):
            raise ParameterError("value", value, "a finite number")
        if dash not in DASHES:
            raise ParameterError("dash", dash, "'-', '--', ':' or '-.'")
        self._artists.append(_Ref(axis, v, _color(color), _positive("width", width), dash, float(alpha), label))

    def hline(self, y: float, *, color: Any = "k", width: float = 0.8, dash: str = "-", alpha: float = 1.0,
              label: str | None = None) -> None:
        """A horizontal line at ``y`` (data) across the plot area; ``y`` is kept inside automatic limits."""
        self._ref("y", y, color, width, dash, alpha, label)

    def vline(self, x: float, *, color: Any = "k", width: float = 0.8, dash: str = "-", alpha: float = 1.0,
              label: str | None = None) -> None:
        """A vertical line at ``x`` (data) across the plot area; ``x`` is kept inside automatic limits."""
        self._ref("x", x, color, width, dash, alpha, label)

    def text(self, x: float, y: float, s: str, *, coords: str = "data", anchor: str = "start",
             valign: str = "baseline", color: Any = "#222222", font_size: float | None = None) -> None:
        """Text at (x, y): ``coords`` 'data' or 'axes' ((0, 0) bottom left, (1, 1) top right of the
        plot area); ``anchor`` 'start', 'middle' or 'end'; ``valign`` 'baseline', 'middle' or 'top'."""
        if coords not in ("data", "axes"):
            raise ParameterError("coords", coords, "'data' or 'axes'")
        if anchor not in ("start", "middle", "end"):
            raise ParameterError("anchor", anchor, "'start', 'middle' or 'end'")
        if valign not in ("baseline", "middle", "top"):
            raise ParameterError("valign", valign, "'baseline', 'middle' or 'top'")
        self._texts.append((float(x), float(y), str(s), coords, anchor, valign, _color(color), font_size))

    def title(self, s: str, *, font_size: float | None = None) -> None:
        """Title above the plot area (``font_size`` pt; default: the figure's)."""
        self._title = (str(s), font_size)

    def xlabel(self, s: str, *, font_size: float | None = None) -> None:
        """Label of the x axis (include the unit: 'cam angle (deg)')."""
        self._xlabel = (str(s), font_size)

    def ylabel(self, s: str, *, font_size: float | None = None) -> None:
        """Label of the y axis (include the unit)."""
        self._ylabel = (str(s), font_size)

    def legend(self, loc: str = "best", *, font_size: float | None = None, ncol: int = 1) -> None:
        """A legend of the labelled curves and lines, in ``ncol`` columns; ``loc`` 'best' (the
        corner or side covering the fewest drawn vertices) or one of :data:`LEGEND_LOCATIONS`."""
        if loc == "right":
            loc = "center right"
        if loc != "best" and loc not in LEGEND_LOCATIONS:
            raise ParameterError("loc", loc, "'best' or one of " + ", ".join(LEGEND_LOCATIONS))
        if int(ncol) < 1:
            raise ParameterError("ncol", ncol, "an integer >= 1")
        self._legend = (loc, font_size, int(ncol))

    def top_axis(self, scale: float, label: str, *, font_size: float | None = None) -> None:
        """A second x scale along the top edge: the bottom's x times ``scale`` (e.g. cam angle in
        deg to time in s at a constant speed), with its own nice ticks and ``label``."""
        self._top = (_positive("scale", scale), str(label), font_size)

    def equal_aspect(self, on: bool = True) -> None:
        """Same scale in x and y (1 mm in x is as long as 1 mm in y).  With automatic limits the
        limits grow to fill the plot area; with an explicit limit the plot area shrinks."""
        self._equal = bool(on)

    def _lim(self, which: list[float | None], name: str, lo: float | None, hi: float | None) -> None:
        for v in (lo, hi):
            if v is not None and not math.isfinite(float(v)):
                raise ParameterError(name, (lo, hi), "finite numbers or None (automatic)")
        if lo is not None and hi is not None and not float(lo) < float(hi):
            raise ParameterError(name, (lo, hi), "lo < hi")
        which[:] = [None if lo is None else float(lo), None if hi is None else float(hi)]

    def xlim(self, lo: float | None = None, hi: float | None = None) -> None:
        """Explicit x limits (None: automatic, data range plus :data:`MARGIN` each side)."""
        self._lim(self._xlim, "xlim", lo, hi)

    def ylim(self, lo: float | None = None, hi: float | None = None) -> None:
        """Explicit y limits (None: automatic, data range plus :data:`MARGIN` each side)."""
        self._lim(self._ylim, "ylim", lo, hi)

    def grid(self, on: bool = True) -> None:
        """Light grid lines at the ticks (on by default)."""
        self._grid = bool(on)

    # ---- layout
    def _auto_limits(self) -> tuple[float, float, float, float]:
        out = []
        for axis, explicit in (("x", self._xlim), ("y", self._ylim)):
            lo, hi = math.inf, -math.inf
            for a in self._artists:
                if isinstance(a, Line):
                    v = a.x if axis == "x" else a.y
                    ok = np.isfinite(a.x) & np.isfinite(a.y)
                    if ok.any():
                        lo, hi = min(lo, float(v[ok].min())), max(hi, float(v[ok].max()))
                elif a.axis == axis:
                    lo, hi = min(lo, a.value), max(hi, a.value)
            if lo > hi:  # no data
                lo, hi = 0.0, 1.0
            if explicit[0] is not None:
                lo = explicit[0]
            if explicit[1] is not None:
                hi = explicit[1]
            if hi <= lo:  # one value (or explicit limit beyond the data)
                d = abs(lo) * 0.05 or 1.0
                lo, hi = (lo - d if explicit[0] is None else lo), (hi + d if explicit[1] is None else hi)
                if hi <= lo:
                    hi = lo + d
            else:
                pad = MARGIN * (hi - lo)
                lo, hi = (lo - pad if explicit[0] is None else lo), (hi + pad if explicit[1] is None else hi)
            out += [lo, hi]
        return out[0], out[1], out[2], out[3]

    def _fit(self, box: tuple[float, float, float, float], limits: tuple[float, float, float, float],
             fs: float) -> tuple[float, float, float, float]:
        """Place the plot area in ``box``, fix limits and ticks; the margins (l, r, t, b, px) it needs."""
        left, top, w, h = box
        w, h = max(w, 10.0), max(h, 10.0)
        x0, x1, y0, y1 = limits
        if self._equal:
            scale = min(w / (x1 - x0), h / (y1 - y0))  # px per data unit
            if any(v is not None for v in self._xlim + self._ylim):  # explicit: shrink the box
                nw, nh = (x1 - x0) * scale, (y1 - y0) * scale
                left, top, w, h = left + (w - nw) / 2, top + (h - nh) / 2, nw, nh
            else:  # automatic: grow the limits
                cx, cy, hx, hy = (x0 + x1) / 2, (y0 + y1) / 2, w / scale / 2, h / scale / 2
                x0, x1, y0, y1 = cx - hx, cx + hx, cy - hy, cy + hy
        self.area, self.limits = (left, top, w, h), (x0, x1, y0, y1)
        self.clip_note = self._clip_note(x0, x1, y0, y1)
        self._xt = nice_ticks(x0, x1, w, lambda labels: max(_text_width(s, fs) for s in labels) + 1.2 * fs)
        top_axis = getattr(self, "_top", None)
        if top_axis is not None:
            k = top_axis[0]
            self._tt = nice_ticks(x0 * k, x1 * k, w, lambda labels: max(_text_width(s, fs) for s in labels) + 1.2 * fs)
        self._yt = nice_ticks(y0, y1, h, lambda labels: max(2.0 * fs, 24.0))
        tick = 3.5 * PX_PER_PT * 2  # tick length + pad
        pad = 4.0

        def lab(t: tuple[str, float | None]) -> float:  # height of a label line and its pad, px
            return (t[1] if t[1] is not None else self._figure.font_size) * PX_PER_PT * 1.25 + 4.0

        need_l = pad + tick + max(_text_width(s, fs) for s in self._yt[1]) + (lab(self._ylabel) if self._ylabel else 0.0)
        x_last = left + (self._xt[0][-1] - x0) / (x1 - x0) * w
        need_r = pad + max(0.0, _text_width(self._xt[1][-1], fs) / 2 - (left + w - x_last))
        need_t = pad + 0.5 * fs + (lab(self._title) if self._title else 0.0) + (1.3 * fs if self._yt[2] else 0.0)
        if getattr(self, "_top", None) is not None:
            need_t += self._top_height(fs)
        need_b = pad + tick + 1.1 * fs + (lab(self._xlabel) if self._xlabel else 0.0) + (1.3 * fs if self._xt[2] and not self._xlabel else 0.0)
        if self.clip_note:
            need_b += CLIP_NOTE_SIZE * fs * 1.25 + 2.0
        return need_l, need_r, need_t, need_b

    def _outside(self, axis: str, lo: float, hi: float) -> tuple[bool, bool]:
        """Whether a curve has points below ``lo`` and above ``hi`` along ``axis`` (an infinite
        value is beyond either; a point with a NaN is a break in the curve, not data)."""
        below = above = False
        for a in self._artists:
            if isinstance(a, Line):
                v, other = (a.x, a.y) if axis == "x" else (a.y, a.x)
                seen = v[~np.isnan(v) & ~np.isnan(other)]
                below = below or bool(np.any(seen < lo))
                above = above or bool(np.any(seen > hi))
        return below, above

    def _clip_note(self, x0: float, x1: float, y0: float, y1: float) -> str | None:
        """The note under a plot whose limits leave data out: which values, beyond which limits."""
        parts = []
        for axis, lo, hi, label in (("y", y0, y1, self._ylabel), ("x", x0, x1, self._xlabel)):
            below, above = self._outside(axis, lo, hi)
            if not (below or above):
                continue
            m = _LABEL_UNIT.match(label[0]) if label else None
            name, unit = (m.group(1), " " + m.group(2)) if m else (label[0] if label else f"{axis} values", "")
            sides = ([f"above {_limit_text(hi)}{unit}"] if above else []) + ([f"below {_limit_text(lo)}{unit}"] if below else [])
            parts.append(f"{name} {' and '.join(sides)}")
        return "clipped, not shown: " + "; ".join(parts) if parts else None

    def _top_height(self, fs: float) -> float:
        """Height (px) of the top axis: ticks, their labels and the axis label."""
        size = self._top[2] if self._top[2] is not None else self._figure.font_size
        return 3.5 * PX_PER_PT * 2 + 1.1 * fs + size * PX_PER_PT * 1.25 + 4.0

    def _laid_out(self) -> tuple[tuple[float, float, float, float], tuple[float, float, float, float]]:
        """(area, limits) of the panel, once :meth:`Figure.to_svg` has laid it out."""
        assert self.area is not None and self.limits is not None, "drawn before the figure's layout"
        return self.area, self.limits

    def _top_svg(self, fs: float) -> str:
        (left, top, w, _), limits = self._laid_out()
        x0, x1 = limits[0], limits[1]
        k, label, size = self._top
        ticks, labels, _ = self._tt
        px = left + (ticks / k - x0) * (w / (x1 - x0))
        tl = 3.5 * PX_PER_PT
        d = "".join(f"M{_n(v)},{_n(top)}v{_n(-tl)}" for v in px)
        ty = top - 2 * tl
        lf = (size or self._figure.font_size) * PX_PER_PT
        return (f'<path class="topticks" d="{d}" fill="none" stroke="#000000" stroke-width="{_n(0.8 * PX_PER_PT)}"/>'
                + '<g class="topticks" text-anchor="middle">' + "".join(f'<text x="{_n(v)}" y="{_n(ty)}">{t}</text>' for v, t in zip(px, labels))
                + f'</g><text class="toplabel" x="{_n(left + w / 2)}" y="{_n(ty - 1.1 * fs)}" text-anchor="middle"{_size_attr(lf, fs)}>'
                f'{_esc(label)}</text>')

    def _px(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        (left, top, w, h), (x0, x1, y0, y1) = self._laid_out()
        px = left + (x - x0) * (w / (x1 - x0))
        py = top + h - (y - y0) * (h / (y1 - y0))
        return np.clip(px, -MAX_PX, MAX_PX), np.clip(py, -MAX_PX, MAX_PX)

    # ---- drawing
    def _svg(self, clip_id: str, fs: float, max_vertices: int) -> str:
        (left, top, w, h), _ = self._laid_out()
        right, bottom = left + w, top + h
        out = [f'<g class="axes"><clipPath id="{clip_id}"><rect x="{_n(left)}" y="{_n(top)}" width="{_n(w)}" height="{_n(h)}"/></clipPath>']
        xt, xl, xp = self._xt
        yt, yl, yp = self._yt
        txp, _ = self._px(xt, np.zeros_like(xt))
        _, typ = self._px(np.zeros_like(yt), yt)
        if self._grid:
            d = "".join(f"M{_n(v)},{_n(top)}V{_n(bottom)}" for v in txp) + "".join(f"M{_n(left)},{_n(v)}H{_n(right)}" for v in typ)
            out.append(f'<path class="grid" d="{d}" fill="none" stroke="#dddddd" stroke-width="{_n(0.8 * PX_PER_PT)}"/>')
        # data: curves and reference lines in the order they were added, clipped to the plot area
        out.append(f'<g class="data" clip-path="url(#{clip_id})" fill="none" stroke-linejoin="round">')
        drawn: list[tuple[np.ndarray, np.ndarray]] = []  # vertices in px (legend placement)
        for a in self._artists:
            if isinstance(a, _Ref):
                if a.axis == "y":
                    _, py = self._px(np.zeros(1), np.array([a.value]))
                    d = f"M{_n(left)},{_n(py[0])}H{_n(right)}"
                    drawn.append((np.linspace(left, right, 40), np.full(40, py[0])))
                else:
                    px, _ = self._px(np.array([a.value]), np.zeros(1))
                    d = f"M{_n(px[0])},{_n(top)}V{_n(bottom)}"
                    drawn.append((np.full(40, px[0]), np.linspace(top, bottom, 40)))
                out.append(f'<path class="ref" d="{d}"{_stroke(a.color, a.width, a.dash, a.alpha)}/>')
                continue
            ok = np.isfinite(a.x) & np.isfinite(a.y)
            idx = np.flatnonzero(ok)
            if idx.size == 0:
                continue
            px, py = self._px(a.x[idx], a.y[idx])
            if a.dash is not None:
                start = np.ones(idx.size, dtype=bool)
                start[1:] = np.diff(idx) > 1  # a NaN between: a new subpath
                keep = thin(px, py, np.cumsum(start), w, h, max_vertices)
                lx, ly, ls = px[keep], py[keep], start[keep]  # thinning keeps every subpath's first vertex
                xy = tuple(np.column_stack([lx, ly]).ravel().tolist())
                if ls[1:].any():
                    template = "".join(np.where(ls, "M%.2f,%.2f", " %.2f,%.2f").tolist())
                else:
                    template = "M%.2f,%.2f" + " %.2f,%.2f" * (lx.size - 1)
                out.append(f'<path class="line" d="{template % xy}"{_stroke(a.color, a.width, a.dash, a.alpha)}/>')
                drawn.append((lx, ly))
            if a.marker is not None:
                # only markers in or near the plot area, one per 0.5 px cell
                reach = a.marker_size * PX_PER_PT
                inside = np.flatnonzero((px > left - reach) & (px < right + reach) & (py > top - reach) & (py < bottom + reach))
                if inside.size > max_vertices:
                    cells = np.column_stack([np.round(px[inside] * 2), np.round(py[inside] * 2)])
                    _, first = np.unique(cells, axis=0, return_index=True)
                    inside = inside[np.sort(first)]
                out.append(_marker_path(a.marker, a.marker_size, a.color, a.alpha, px[inside], py[inside]))
                drawn.append((px[inside], py[inside]))
        out.append("</g>")
        out.append(f'<rect class="frame" x="{_n(left)}" y="{_n(top)}" width="{_n(w)}" height="{_n(h)}" fill="none" stroke="#000000" '
                   f'stroke-width="{_n(0.8 * PX_PER_PT)}"/>')
        # ticks and their labels
        tl, tp = 3.5 * PX_PER_PT, 3.5 * PX_PER_PT
        d = "".join(f"M{_n(v)},{_n(bottom)}v{_n(tl)}" for v in txp) + "".join(f"M{_n(left)},{_n(v)}h{_n(-tl)}" for v in typ)
        out.append(f'<path class="ticks" d="{d}" fill="none" stroke="#000000" stroke-width="{_n(0.8 * PX_PER_PT)}"/>')
        ty = bottom + tl + tp + 0.8 * fs
        out.append('<g class="xticks" text-anchor="middle">' + "".join(
            f'<text x="{_n(v)}" y="{_n(ty)}">{s}</text>' for v, s in zip(txp, xl)) + "</g>")
        out.append('<g class="yticks" text-anchor="end">' + "".join(
            f'<text x="{_n(left - tl - tp)}" y="{_n(v + 0.35 * fs)}">{s}</text>' for v, s in zip(typ, yl)) + "</g>")
        if yp:
            out.append(f'<text class="yfactor" x="{_n(left)}" y="{_n(top - 0.4 * fs)}">{_power(yp)}</text>')
        top_shift = 0.0
        if getattr(self, "_top", None) is not None:
            out.append(self._top_svg(fs))
            top_shift = self._top_height(fs)
        if xp:
            yy = ty + 1.3 * fs if not self._xlabel else ty + 1.25 * fs + 4.0
            out.append(f'<text class="xfactor" x="{_n(right)}" y="{_n(yy)}" text-anchor="end">{_power(xp)}</text>')
        font = self._figure.font_size
        if self._xlabel:
            s, size = self._xlabel
            lf = (size or font) * PX_PER_PT
            out.append(f'<text class="xlabel" x="{_n(left + w / 2)}" y="{_n(ty + 4.0 + 1.0 * lf)}" text-anchor="middle"'
                       f'{_size_attr(lf, fs)}>{_esc(s)}</text>')
        if self.clip_note:  # below everything under the plot area, from the cell's left edge
            below = ty + (4.0 + 1.0 * (self._xlabel[1] or font) * PX_PER_PT if self._xlabel else 0.0) + (1.3 * fs if xp and not self._xlabel else 0.0)
            nf = CLIP_NOTE_SIZE * fs
            cell = self._figure._cell_width
            nf = min(nf, max(6 * PX_PER_PT, nf * (cell - 8.0) / max(_text_width(self.clip_note, nf), 1.0)))
            out.append(f'<text class="clipnote" x="{_n(self._col * cell + 4.0)}" y="{_n(below + 1.25 * nf + 2.0)}" fill="{CLIP_NOTE_COLOR}"'
                       f'{_size_attr(nf, fs)}>{_esc(self.clip_note)}</text>')
        if self._ylabel:
            s, size = self._ylabel
            lf = (size or font) * PX_PER_PT
            widest = max(_text_width(t, fs) for t in yl)
            xx = left - tl - tp - widest - 4.0 - 0.25 * lf
            yy = top + h / 2
            out.append(f'<text class="ylabel" x="{_n(xx)}" y="{_n(yy)}" transform="rotate(-90 {_n(xx)} {_n(yy)})" '
                       f'text-anchor="middle"{_size_attr(lf, fs)}>{_esc(s)}</text>')
        if self._title:
            s, size = self._title
            tf = (size or font) * PX_PER_PT
            cw, cx = self._figure._cell_width, left + w / 2
            room = 2 * min(cx - self._col * cw, (self._col + 1) * cw - cx) - 8.0  # centred over the plot area, inside the cell
            tf = min(tf, max(6 * PX_PER_PT, tf * room / max(_text_width(s, tf), 1.0)))  # shrink a title wider than that
            out.append(f'<text class="title" x="{_n(left + w / 2)}" y="{_n(top - 0.5 * fs - 4.0 - 0.25 * tf - (1.3 * fs if yp else 0) - top_shift)}" '
                       f'text-anchor="middle"{_size_attr(tf, fs)}>{_esc(s)}</text>')
        for x, y, s, coords, anchor, valign, color, size in self._texts:
            tf = (size or font) * PX_PER_PT
            if coords == "axes":
                px_, py_ = left + x * w, top + (1 - y) * h
            else:
                at_x, at_y = self._px(np.array([x]), np.array([y]))
                px_, py_ = float(at_x[0]), float(at_y[0])
            py_ += {"baseline": 0.0, "middle": 0.35 * tf, "top": 0.8 * tf}[valign]
            anchor_attr = "" if anchor == "start" else f' text-anchor="{anchor}"'
            fill = "" if color == "#222222" else f' fill="{color}"'
            out.append(f'<text class="note" x="{_n(px_)}" y="{_n(py_)}"{anchor_attr}{fill}{_size_attr(tf, fs)}>{_esc(s)}</text>')
        if self._legend:
            out.append(self._legend_svg(drawn, fs))
        out.append("</g>")
        return "".join(out)

    def _legend_svg(self, drawn: list[tuple[np.ndarray, np.ndarray]], fs: float) -> str:
        entries = [a for a in self._artists if a.label is not None and not str(a.label).startswith("_")]
        if not entries or self._legend is None:
            return ""
        loc, size, ncol = self._legend
        lf = (size or self._figure.font_size) * PX_PER_PT
        ncol = min(ncol, len(entries))
        nrow = math.ceil(len(entries) / ncol)
        # matplotlib's legend metrics, in font sizes: handle 2, handle-text pad 0.8, column spacing 2,
        # border pad 0.4, label spacing 0.5, border-axes pad 0.5
        handle, hpad, cspace, bpad, row, apad = 2.0 * lf, 0.8 * lf, 2.0 * lf, 0.4 * lf, 1.5 * lf, 0.5 * lf
        cols = [entries[c * nrow:(c + 1) * nrow] for c in range(ncol)]  # column-major, as matplotlib
        widths = [handle + hpad + max(_text_width(str(a.label), lf) for a in col) for col in cols]
        bw = 2 * bpad + sum(widths) + cspace * (ncol - 1)
        bh = 2 * bpad + nrow * row
        (left, top, w, h), _ = self._laid_out()
        spots = {
            "upper right": (left + w - apad - bw, top + apad), "upper left": (left + apad, top + apad),
            "lower left": (left + apad, top + h - apad - bh), "lower right": (left + w - apad - bw, top + h - apad - bh),
            "center right": (left + w - apad - bw, top + (h - bh) / 2), "center left": (left + apad, top + (h - bh) / 2),
            "lower center": (left + (w - bw) / 2, top + h - apad - bh), "upper center": (left + (w - bw) / 2, top + apad),
            "center": (left + (w - bw) / 2, top + (h - bh) / 2),
        }
        if loc == "best":
            px = np.concatenate([d[0] for d in drawn]) if drawn else np.zeros(0)
            py = np.concatenate([d[1] for d in drawn]) if drawn else np.zeros(0)
            counts = [int(np.count_nonzero((px >= bx) & (px <= bx + bw) & (py >= by) & (py <= by + bh)))
                      for bx, by in (spots[k] for k in LEGEND_LOCATIONS)]
            loc = LEGEND_LOCATIONS[int(np.argmin(counts))]  # first of the least covered, in matplotlib's order
        bx, by = spots[loc]
        out = [(f'<g class="legend"{_size_attr(lf, fs)}><rect x="{_n(bx)}" y="{_n(by)}" width="{_n(bw)}" height="{_n(bh)}" rx="2" '
                f'fill="#ffffff" fill-opacity="0.85" stroke="#cccccc" stroke-width="{_n(0.8 * PX_PER_PT)}"/>')]
        x = bx + bpad
        for col, cw in zip(cols, widths):
            for i, a in enumerate(col):
                yc = by + bpad + (i + 0.5) * row
                if isinstance(a, _Ref) or a.dash is not None:
                    out.append(f'<path d="M{_n(x)},{_n(yc)}h{_n(handle)}" fill="none"{_stroke(a.color, a.width, a.dash, a.alpha)}/>')
                if a.marker is not None:
                    out.append(_marker_path(a.marker, a.marker_size, a.color, a.alpha, np.array([x + handle / 2]), np.array([yc]), "marker"))
                out.append(f'<text x="{_n(x + handle + hpad)}" y="{_n(yc + 0.35 * lf)}">{_esc(str(a.label))}</text>')
            x += cw + cspace
        out.append("</g>")
        return "".join(out)


def _power(p: int) -> str:
    exp = (MINUS if p < 0 else "") + str(abs(p))
    return f'\u00d710<tspan dy="-0.5em" font-size="75%">{exp}</tspan>'


def _size_attr(px: float, default_px: float) -> str:
    return "" if abs(px - default_px) < 1e-9 else f' font-size="{_n(px)}"'


class Figure:
    """A figure of plot panels in a grid, drawn to an SVG string by :meth:`to_svg`.

    Parameters
    ----------
    figsize : (width, height) in inches (96 px each, as a browser shows matplotlib's SVG).
    id_prefix : start of the ids in the SVG (clip paths): give each figure of a page its own
        (letters, digits, '-', '_'; starts with a letter).  The ids also carry a hash of the clip
        rectangle, so two figures with the same prefix can only share an id when the clip
        rectangles are the same.
    font_size : text size, pt (tick labels, axis labels, titles unless given).
    max_vertices : curves with more points are thinned (min/max per pixel column).
    """

    def __init__(self, figsize: Sequence[float] = (6.4, 4.8), *, id_prefix: str = "fig", font_size: float = 9.0,
                 max_vertices: int = MAX_VERTICES) -> None:
        if len(figsize) != 2:
            raise ParameterError("figsize", figsize, "(width, height) in inches")
        self.width = _positive("figsize", figsize[0]) * PX_PER_INCH
        self.height = _positive("figsize", figsize[1]) * PX_PER_INCH
        if not isinstance(id_prefix, str) or not _ID.match(id_prefix):
            raise ParameterError("id_prefix", id_prefix, "letters, digits, '-' and '_', starting with a letter")
        self.id_prefix = id_prefix
        self.font_size = _positive("font_size", font_size)
        if int(max_vertices) < 16:
            raise ParameterError("max_vertices", max_vertices, "an integer >= 16")
        self.max_vertices = int(max_vertices)
        self._grid: tuple[int, int] | None = None
        self._axes: list[Axes] = []
        self._suptitle: tuple[str, float | None] | None = None
        self._cell_width = self.width

    def subplots(self, nrows: int = 1, ncols: int = 1) -> Any:
        """A grid of panels, as matplotlib's ``Figure.subplots``: one :class:`Axes` for 1 x 1, a
        1-D numpy array for one row or column, else a 2-D array (``.ravel()`` for a flat list)."""
        if self._grid is not None:
            raise ParameterError("subplots", (nrows, ncols), "one call per figure", "this figure has its panels already")
        if int(nrows) < 1 or int(ncols) < 1:
            raise ParameterError("nrows, ncols", (nrows, ncols), "integers >= 1")
        self._grid = (int(nrows), int(ncols))
        grid = np.empty((int(nrows), int(ncols)), dtype=object)
        for r in range(int(nrows)):
            for c in range(int(ncols)):
                grid[r, c] = Axes(self, r, c)
                self._axes.append(grid[r, c])
        if grid.size == 1:
            return grid[0, 0]
        return grid.ravel() if 1 in grid.shape else grid

    def add_subplot(self) -> Axes:
        """One panel filling the figure (matplotlib's ``fig.add_subplot()``)."""
        return self.subplots(1, 1)

    def suptitle(self, s: str, *, font_size: float | None = None) -> None:
        """A title above all panels."""
        self._suptitle = (str(s), font_size)

    def to_svg(self) -> str:
        """The figure as an ``<svg>`` element (no XML prolog)."""
        if self._grid is None:
            self.subplots(1, 1)
        assert self._grid is not None
        nrow, ncol = self._grid
        fs = self.font_size * PX_PER_PT
        sup_h = 0.0
        if self._suptitle:
            sup_fs = (self._suptitle[1] or self.font_size) * PX_PER_PT
            sup_h = 1.6 * sup_fs + 4.0
        cw, ch = self.width / ncol, (self.height - sup_h) / nrow
        self._cell_width = cw
        limits = [ax._auto_limits() for ax in self._axes]
        margins: list[tuple[float, ...]] = [(70.0, 10.0, 30.0, 40.0)] * len(self._axes)
        for it in range(4):
            lefts = [max(m[0] for m, ax in zip(margins, self._axes) if ax._col == c) for c in range(ncol)]
            rights = [max(m[1] for m, ax in zip(margins, self._axes) if ax._col == c) for c in range(ncol)]
            tops = [max(m[2] for m, ax in zip(margins, self._axes) if ax._row == r) for r in range(nrow)]
            bottoms = [max(m[3] for m, ax in zip(margins, self._axes) if ax._row == r) for r in range(nrow)]
            need: list[tuple[float, ...]] = []
            for ax, lim in zip(self._axes, limits):
                r, c = ax._row, ax._col
                box = (c * cw + lefts[c], sup_h + r * ch + tops[r], cw - lefts[c] - rights[c], ch - tops[r] - bottoms[r])
                need.append(ax._fit(box, lim, fs))
            if it > 0 and all(n[k] <= m[k] + 0.5 for n, m in zip(need, margins) for k in range(4)):
                break
            # first pass: take what is needed; then only grow (converges)
            margins = need if it == 0 else [tuple(max(a, b) for a, b in zip(n, m)) for n, m in zip(need, margins)]
        w, h = _n(self.width), _n(self.height)
        out = [(f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" '
                f'style="max-width:100%;height:auto" font-family="{FONT_FAMILY}" font-size="{_n(fs)}" fill="#222222">'),
               f'<rect width="{w}" height="{h}" fill="#ffffff"/>']
        if self._suptitle:
            sup_fs = min(sup_fs, max(6 * PX_PER_PT, sup_fs * (self.width - 8.0) / max(_text_width(self._suptitle[0], sup_fs), 1.0)))
            out.append(f'<text class="suptitle" x="{_n(self.width / 2)}" y="{_n(4.0 + 1.1 * sup_fs)}" text-anchor="middle"'
                       f'{_size_attr(sup_fs, fs)}>{_esc(self._suptitle[0])}</text>')
        for ax in self._axes:
            rect = ",".join(_n(v) for v in ax._laid_out()[0])
            clip_id = f"{self.id_prefix}-clip-{hashlib.sha1(rect.encode()).hexdigest()[:10]}"
            out.append(ax._svg(clip_id, fs, self.max_vertices))
        out.append("</svg>")
        return "".join(out)
