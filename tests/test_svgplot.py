"""camgen.report.svgplot: the SVG read back with xml.etree and checked against numbers computed
here (the affine map the axis limits imply, circle geometry, exact decimal arithmetic for the
ticks), and a page of figures rendered by headless Chromium."""
from __future__ import annotations

import hashlib
import math
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from decimal import Decimal
from itertools import pairwise

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.report.svgplot import Figure
from helpers import require_tool

NS = {"s": "http://www.w3.org/2000/svg"}
PX_PER_INCH = 96.0  # CSS: 96 px per inch; the module's documented unit
COORD_TOL = 0.0101  # px: coordinates are written rounded to 0.01 px; a position computed here from the
# (rounded) frame and compared with a (rounded) vertex can be off by two half-hundredths
NUM = r"-?\d+(?:\.\d+)?"


def parse(svg: str) -> ET.Element:
    assert not svg.startswith("<?xml")
    return ET.fromstring(svg)


def vertices(d: str) -> list[np.ndarray]:
    """Subpaths of an 'M x,y x,y ... M x,y ...' path as (n, 2) arrays."""
    return [np.array([[float(a), float(b)] for a, b in re.findall(rf"({NUM}),({NUM})", part)]) for part in d.split("M")[1:]]


def axes_info(group: ET.Element) -> dict:
    """What a reader sees in one axes group: frame, tick marks with their label values, curves."""
    frame = group.find("s:rect[@class='frame']", NS)
    left, top, w, h = (float(frame.get(k)) for k in ("x", "y", "width", "height"))
    ticks = group.find("s:path[@class='ticks']", NS).get("d")
    xpos = [float(a) for a, _ in re.findall(rf"M({NUM}),({NUM})v", ticks)]
    ypos = [float(b) for _, b in re.findall(rf"M({NUM}),({NUM})h", ticks)]

    def factor(cls: str) -> int:
        node = group.find(f"s:text[@class='{cls}']", NS)
        return 0 if node is None else int(node.find("s:tspan", NS).text.replace("\u2212", "-"))

    xlabels = [t.text for t in group.findall("s:g[@class='xticks']/s:text", NS)]
    ylabels = [t.text for t in group.findall("s:g[@class='yticks']/s:text", NS)]
    lines = [vertices(p.get("d")) for p in group.findall("s:g[@class='data']/s:path[@class='line']", NS)]
    return {"left": left, "top": top, "w": w, "h": h, "xpos": np.array(xpos), "ypos": np.array(ypos),
            "xlabels": xlabels, "ylabels": ylabels, "xfactor": factor("xfactor"), "yfactor": factor("yfactor"), "lines": lines,
            "group": group}


def all_axes(svg: str) -> list[dict]:
    return [axes_info(g) for g in parse(svg).findall("s:g[@class='axes']", NS)]


def label_value(s: str, power: int) -> Decimal:
    assert re.fullmatch(r"\u2212?\d+(\.\d+)?", s), s  # plain decimal, true minus sign, no exponent
    return Decimal(s.replace("\u2212", "-")).scaleb(power)


def expected_px(info: dict, lim: tuple[float, float, float, float], x, y):
    """Pixel of data (x, y) for the plot area and limits: the affine map, y down (computed here)."""
    x0, x1, y0, y1 = lim
    return (info["left"] + (np.asarray(x) - x0) / (x1 - x0) * info["w"],
            info["top"] + info["h"] - (np.asarray(y) - y0) / (y1 - y0) * info["h"])


def fit_axis(positions: np.ndarray, labels: list[str], power: int) -> tuple[float, float]:
    """px = a + b * value through the tick marks and the values their labels read (least squares)."""
    values = np.array([float(label_value(s, power)) for s in labels])
    b, a = np.polyfit(values, positions, 1)
    assert np.max(np.abs(a + b * values - positions)) < COORD_TOL * 2  # ticks where their labels say
    return a, b


# ------------------------------------------------------------------------------ structure

def test_svg_is_well_formed_inline_svg_of_the_figure_size():
    fig = Figure(figsize=(10, 3.2), id_prefix="a")
    ax1, _ = fig.subplots(1, 2)
    ax1.plot([0, 1], [0, 1], label="a & b < c")
    ax1.title('title with "quotes"')
    svg = fig.to_svg()
    root = parse(svg)
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    assert float(root.get("width")) == pytest.approx(10 * PX_PER_INCH) and float(root.get("height")) == pytest.approx(3.2 * PX_PER_INCH)
    assert len(root.findall("s:g[@class='axes']", NS)) == 2
    assert root.find(".//s:text[@class='title']", NS).text == 'title with "quotes"'


def test_data_to_pixel_mapping_with_explicit_limits():
    fig = Figure(figsize=(6, 4))
    ax = fig.add_subplot()
    x = np.array([0.0, 2.5, 7.0, 10.0])
    y = np.array([-5.0, 1.25, 4.0, 5.0])
    ax.plot(x, y)
    ax.hline(2.5, color="tab:red")
    ax.vline(3.0, color="tab:red")
    ax.text(0.25, 0.75, "a quarter in, a quarter down", coords="axes", anchor="middle")
    ax.text(7.0, -2.0, "at (7, -2)")
    ax.xlim(0, 10)
    ax.ylim(-5, 5)
    ax.xlabel("x (mm)")
    ax.ylabel("y (mm)")
    info = all_axes(fig.to_svg())[0]
    lim = (0.0, 10.0, -5.0, 5.0)
    px, py = expected_px(info, lim, x, y)
    assert np.allclose(info["lines"][0][0], np.column_stack([px, py]), atol=COORD_TOL)
    refs = [p.get("d") for p in info["group"].findall("s:g[@class='data']/s:path[@class='ref']", NS)]
    _, hy = expected_px(info, lim, 0, 2.5)
    vx, _ = expected_px(info, lim, 3.0, 0)
    assert float(re.match(rf"M{NUM},({NUM})H", refs[0]).group(1)) == pytest.approx(hy, abs=COORD_TOL)
    assert float(re.match(rf"M({NUM}),{NUM}V", refs[1]).group(1)) == pytest.approx(vx, abs=COORD_TOL)
    notes = info["group"].findall("s:text[@class='note']", NS)
    assert float(notes[0].get("x")) == pytest.approx(info["left"] + info["w"] / 4, abs=COORD_TOL)
    assert float(notes[0].get("y")) == pytest.approx(info["top"] + info["h"] / 4, abs=COORD_TOL)  # baseline
    nx, ny = expected_px(info, lim, 7.0, -2.0)
    assert (float(notes[1].get("x")), float(notes[1].get("y"))) == pytest.approx((nx, ny), abs=COORD_TOL)
    # the tick labels sit where their values map: the same affine map read from the ticks
    a, b = fit_axis(info["xpos"], info["xlabels"], info["xfactor"])
    assert (a, a + 10 * b) == pytest.approx((info["left"], info["left"] + info["w"]), abs=COORD_TOL)
    a, b = fit_axis(info["ypos"], info["ylabels"], info["yfactor"])
    assert (a - 5 * b, a + 5 * b) == pytest.approx((info["top"] + info["h"], info["top"]), abs=COORD_TOL)


@pytest.mark.parametrize("limit_line", [False, True])
def test_automatic_limits_add_five_percent_each_side(limit_line):
    """matplotlib's default margins (axes.xmargin = axes.ymargin = 0.05): data [2, 12] x [-1, 3]
    shows [1.5, 12.5] x [-1.2, 3.2]; a limit line at y = 7 is data too: [-1.4, 7.4].  Read
    back through the tick marks and their labels."""
    fig = Figure(figsize=(6, 4))
    ax = fig.add_subplot()
    ax.plot([2, 7, 12], [3, -1, 0])
    if limit_line:
        ax.hline(7.0, dash="--")
    info = all_axes(fig.to_svg())[0]
    a, b = fit_axis(info["xpos"], info["xlabels"], info["xfactor"])
    assert ((info["left"] - a) / b, (info["left"] + info["w"] - a) / b) == pytest.approx((1.5, 12.5), abs=1e-3)
    a, b = fit_axis(info["ypos"], info["ylabels"], info["yfactor"])
    expect = (-1.4, 7.4) if limit_line else (-1.2, 3.2)
    assert ((info["top"] + info["h"] - a) / b, (info["top"] - a) / b) == pytest.approx(expect, abs=1e-3)


# ------------------------------------------------------------------------------------ ticks

def check_ticks(labels: list[str], positions: np.ndarray, power: int, lo: float, hi: float, rel_tol: float = 1e-9) -> Decimal:
    """The axis' ticks are nice, cover [lo, hi] (to ``rel_tol`` of the span: limits read back
    from pixels are known to about 1e-4) and their labels are exact decimals: checked with
    Decimal arithmetic (no floats).  Returns the step."""
    assert 4 <= len(labels) <= 10, labels
    values = [label_value(s, power) for s in labels]
    steps = {b - a for a, b in pairwise(values)}
    assert len(steps) == 1, labels  # evenly spaced
    step = steps.pop()
    mantissa, exponent = step.normalize().as_tuple().digits, step.normalize().as_tuple().exponent
    assert len(mantissa) == 1 and mantissa[0] in (1, 2, 5), step  # 1, 2 or 5 x 10^k
    assert all((v / step) == (v / step).to_integral_value() for v in values)  # on multiples of the step
    lo, hi = Decimal(repr(float(lo))), Decimal(repr(float(hi)))
    slack = (hi - lo) * Decimal(repr(rel_tol))
    assert lo - slack <= values[0] and values[-1] <= hi + slack
    assert values[0] - lo < step and hi - values[-1] < step  # cover the limits
    # no float noise: as many decimals as the step needs, the same on every label
    decimals = {len(s.split(".")[1]) if "." in s else 0 for s in labels}
    assert decimals == {max(0, -(exponent - power))}, (labels, step)
    assert np.all(np.diff(positions) != 0) and len(positions) == len(labels)
    return step


RANGES = [(0.0, 0.1 + 0.2), (0.0, 360.0), (-0.5, 0.5), (-273.15, 1000.0), (1e5, 3e6), (-1e-7, 3e-7), (999.9, 1000.1),
          (0.07, 0.13), (-2.5e6, 2.5e6), (12.5, 18.5), (0.0, 1.0), (-1.0, 0.0)]


@pytest.mark.parametrize("seed", range(3))
def test_ticks_are_nice_cover_the_limits_and_read_back_exactly(seed):
    rng = np.random.default_rng(seed)
    ranges = list(RANGES) if seed == 0 else []
    for _ in range(12):
        a = rng.integers(-6, 8)
        lo = float(rng.uniform(-1, 1) * 10.0**a)
        ranges.append((lo, lo + float(rng.uniform(1, 10) * 10.0 ** (a + rng.integers(-3, 2)))))
    for lo, hi in ranges:
        for figsize, grid in (((6.4, 4.8), (1, 1)), ((10, 4.2), (2, 2))):
            fig = Figure(figsize=figsize)
            ax = np.atleast_1d(fig.subplots(*grid)).ravel()[0]
            ax.plot([lo, hi], [lo, hi])
            ax.xlim(lo, hi)
            ax.ylim(lo, hi)
            info = all_axes(fig.to_svg())[0]
            check_ticks(info["xlabels"], info["xpos"], info["xfactor"], lo, hi)
            check_ticks(info["ylabels"], info["ypos"], info["yfactor"], lo, hi)
            fit_axis(info["xpos"], info["xlabels"], info["xfactor"])
            fit_axis(info["ypos"], info["ylabels"], info["yfactor"])
    # the brief's example: 0.1 + 0.2 shows as 0.3, negative values with a true minus sign
    fig = Figure()
    ax = fig.add_subplot()
    ax.plot([0, 1], [-0.3, 0.1 + 0.2])
    ax.xlim(0, 1)
    ax.ylim(-0.30000000000000004, 0.1 + 0.2)
    info = all_axes(fig.to_svg())[0]
    assert "0.3" in info["ylabels"] and "\u22120.3" in info["ylabels"]


# ----------------------------------------------------------------------------- equal aspect

@pytest.mark.parametrize("figsize, explicit", [((10, 3.4), False), ((4, 6), False), ((6, 6), True)])
def test_equal_aspect_draws_a_circle_round_with_nice_ticks(figsize, explicit):
    fig = Figure(figsize=figsize)
    ax = fig.add_subplot()
    t = np.linspace(0, 2 * math.pi, 721)
    ax.plot(3 + 10 * np.cos(t), -2 + 10 * np.sin(t))  # radius 10 mm about (3, -2)
    ax.equal_aspect()
    if explicit:
        ax.xlim(-10, 20)
        ax.ylim(-15, 10)
    info = all_axes(fig.to_svg())[0]
    ring = info["lines"][0][0]
    width, height = np.ptp(ring[:, 0]), np.ptp(ring[:, 1])
    assert width == pytest.approx(height, abs=2 * COORD_TOL)  # 1 mm in x is 1 mm in y on screen
    assert ring[:, 0].min() >= info["left"] and ring[:, 0].max() <= info["left"] + info["w"]
    assert ring[:, 1].min() >= info["top"] and ring[:, 1].max() <= info["top"] + info["h"]
    _, bx = fit_axis(info["xpos"], info["xlabels"], info["xfactor"])
    _, by = fit_axis(info["ypos"], info["ylabels"], info["yfactor"])
    assert bx == pytest.approx(-by, rel=1e-4)  # px per mm equal in x and y (y down)
    assert width == pytest.approx(20 * bx, abs=0.05)  # the 20 mm diameter at that scale
    a, b = fit_axis(info["xpos"], info["xlabels"], info["xfactor"])
    check_ticks(info["xlabels"], info["xpos"], info["xfactor"], (info["left"] - a) / b, (info["left"] + info["w"] - a) / b, 1e-3)
    a, b = fit_axis(info["ypos"], info["ylabels"], info["yfactor"])
    check_ticks(info["ylabels"], info["ypos"], info["yfactor"], (info["top"] + info["h"] - a) / b, (info["top"] - a) / b, 1e-3)


# --------------------------------------------------------------------- legend, labels, text

def test_legend_lists_the_labelled_curves_and_avoids_the_data():
    fig = Figure(figsize=(6, 4))
    ax = fig.add_subplot()
    x = np.linspace(0, 10, 200)
    first = ax.plot(x, x, label="rising")  # through the lower-left and upper-right corners
    ax.plot(x, x + 1, "--", color="tab:green", label="shifted")
    ax.plot(x, x - 1, color="k")  # no label: not in the legend
    ax.plot(x, x - 2, label="_hidden")
    ax.hline(5, color="tab:red", dash="--", label="limit")
    ax.legend()
    ax.title("a title")
    ax.xlabel("x (mm)")
    ax.ylabel("y (mm)")
    svg = fig.to_svg()
    info = all_axes(svg)[0]
    legend = info["group"].find("s:g[@class='legend']", NS)
    assert [t.text for t in legend.findall("s:text", NS)] == ["rising", "shifted", "limit"]
    handles = legend.findall("s:path", NS)
    assert [h.get("stroke") for h in handles] == [first.color, "#2ca02c", "#d62728"]
    box = legend.find("s:rect", NS)
    bx, by, bw, bh = (float(box.get(k)) for k in ("x", "y", "width", "height"))
    assert info["left"] <= bx and bx + bw <= info["left"] + info["w"] and info["top"] <= by and by + bh <= info["top"] + info["h"]
    drawn = np.vstack([v for line in info["lines"] for v in line])
    inside = (drawn[:, 0] >= bx) & (drawn[:, 0] <= bx + bw) & (drawn[:, 1] >= by) & (drawn[:, 1] <= by + bh)
    assert not inside.any()  # 'best' found a corner clear of the diagonal curves
    texts = {t.get("class"): t.text for t in parse(svg).iter("{http://www.w3.org/2000/svg}text") if t.get("class")}
    assert texts["title"] == "a title" and texts["xlabel"] == "x (mm)" and texts["ylabel"] == "y (mm)"


def test_suptitle_and_a_2x2_grid_are_aligned():
    fig = Figure(figsize=(10, 4.2))
    axes = fig.subplots(2, 2).ravel()
    for k, ax in enumerate(axes):
        ax.plot([0, 360], [0, 10.0 ** (2 * k)])
        ax.ylabel(f"y{k}")
    fig.suptitle("motion")
    svg = fig.to_svg()
    infos = all_axes(svg)
    assert parse(svg).find("s:text[@class='suptitle']", NS).text == "motion"
    # panels in a column share their left edge, panels in a row their top edge
    assert infos[0]["left"] == infos[2]["left"] and infos[1]["left"] == infos[3]["left"]
    assert infos[0]["top"] == infos[1]["top"] and infos[2]["top"] == infos[3]["top"]
    # the largest panel (1e6) shows its labels in units of 10^6
    assert infos[3]["yfactor"] == 6
    check_ticks(infos[3]["ylabels"], infos[3]["ypos"], 6, -5e4, 1.05e6)


# ----------------------------------------------------------------------- NaN, thinning, markers

def test_nan_and_inf_break_the_line():
    fig = Figure()
    ax = fig.add_subplot()
    ax.plot([0, 1, 2, 3, 4, 5, 6], [0, 1, np.nan, 2, 3, np.inf, 4])
    ax.xlim(0, 6)
    ax.ylim(0, 4)
    svg = fig.to_svg()
    assert "nan" not in svg.lower() and "inf" not in svg.lower()
    info = all_axes(svg)[0]
    parts = info["lines"][0]
    lim = (0, 6, 0, 4)
    expect = [([0, 1], [0, 1]), ([3, 4], [2, 3]), ([6], [4])]
    assert len(parts) == 3
    for part, (x, y) in zip(parts, expect):
        assert np.allclose(part, np.column_stack(expected_px(info, lim, x, y)), atol=COORD_TOL)


def _clip_notes(svg: str) -> list[ET.Element]:
    return parse(svg).findall(".//s:text[@class='clipnote']", NS)


@pytest.mark.parametrize("case", ["above", "both", "x", "infinite", "inside", "nan only"])
def test_a_plot_whose_limits_leave_data_out_says_so(case):
    """A note under the plot names the axis (its label, unit apart) and each limit that leaves
    data out; which sides do is computed here from the data and the limits."""
    x = np.linspace(-3.0, 3.0, 601)
    y = x**3  # -27 .. 27
    xlim, ylim = {"above": ((None, None), (None, 8.0)), "both": ((None, None), (-8.0, 8.0)), "x": ((-3.0, 2.0), (None, None)),
                  "infinite": ((None, None), (None, None)), "inside": ((-3.0, 3.0), (-27.0, 27.0)),
                  "nan only": ((None, None), (None, None))}[case]
    if case == "infinite":
        y = np.where(np.abs(x) < 1e-9, np.inf, y)  # a radius of curvature at an inflection
    if case == "nan only":
        y = np.where(np.abs(x) < 0.5, np.nan, y)
    fig = Figure(figsize=(6, 3))
    ax = fig.add_subplot()
    ax.plot(x, y)
    ax.xlim(*xlim)
    ax.ylim(*ylim)
    ax.xlabel("cam angle (deg)")
    ax.ylabel("radius (mm)")
    svg = fig.to_svg()
    x0, x1, y0, y1 = ax.limits
    known = ~np.isnan(y)
    sides = {("radius", "above", y1, "mm"): bool(np.any(y[known] > y1)), ("radius", "below", y0, "mm"): bool(np.any(y[known] < y0)),
             ("cam angle", "above", x1, "deg"): bool(np.any(x > x1)), ("cam angle", "below", x0, "deg"): bool(np.any(x < x0))}
    expected = {"above": 1, "both": 2, "x": 1, "infinite": 1, "inside": 0, "nan only": 0}[case]
    assert sum(sides.values()) == expected  # the cases are what they claim
    notes = _clip_notes(svg)
    if not expected:
        assert notes == [] and ax.clip_note is None
        return
    (note,) = notes
    text = note.text
    assert text == ax.clip_note and text.startswith("clipped, not shown: ")
    for (name, side, limit, unit), out in sides.items():
        phrase = f"{side} {f'{limit:.4g}'.replace('-', chr(0x2212))} {unit}"
        assert (phrase in text) == out, (phrase, text)
        if out:
            assert name in text
    # under the plot and its x label, inside the figure
    info = all_axes(svg)[0]
    xlabel = info["group"].find("s:text[@class='xlabel']", NS)
    height = float(parse(svg).get("height"))
    assert float(xlabel.get("y")) < float(note.get("y")) <= height - 2.0
    assert float(note.get("y")) > info["top"] + info["h"]


def test_thinning_keeps_spikes_and_extremes_of_100k_points():
    n = 100_000
    x = np.linspace(0, 1, n)
    y = np.random.default_rng(1).normal(0, 0.1, n)
    spikes = {1234: 3.0, 45_678: -2.5, 70_001: 2.0, 99_000: -1.5}  # index: height (isolated peaks)
    for i, v in spikes.items():
        y[i] = v
    fig = Figure(figsize=(10, 3.4))
    ax = fig.add_subplot()
    ax.plot(x, y)
    ax.xlim(0, 1)
    ax.ylim(-4, 4)
    info = all_axes(fig.to_svg())[0]
    drawn = info["lines"][0][0]
    assert len(info["lines"][0]) == 1 and 100 < len(drawn) <= 2000
    lim = (0, 1, -4, 4)
    px, py = expected_px(info, lim, x, y)
    for i in spikes:  # each peak drawn at its own pixel
        assert np.min(np.maximum(np.abs(drawn[:, 0] - px[i]), np.abs(drawn[:, 1] - py[i]))) < COORD_TOL
    assert drawn[:, 1].min() == pytest.approx(py.min(), abs=COORD_TOL) and drawn[:, 1].max() == pytest.approx(py.max(), abs=COORD_TOL)
    # every drawn vertex is an original point, in the original order
    assert np.all(np.diff(drawn[:, 0]) >= 0)
    first = np.searchsorted(px, drawn[:, 0] - COORD_TOL)
    last = np.searchsorted(px, drawn[:, 0] + COORD_TOL, side="right")
    assert all(np.any(np.abs(py[a:b] - v) <= COORD_TOL) for a, b, v in zip(first, last, drawn[:, 1]))
    # the envelope survives: in every 25-px window the drawn span covers the data's span
    edges = np.arange(info["left"], info["left"] + info["w"], 25.0)
    for lo, hi in pairwise(edges):
        d = drawn[(drawn[:, 0] >= lo) & (drawn[:, 0] < hi), 1]
        o = py[(px >= lo + 5) & (px < hi - 5)]  # away from bin edges shared with the neighbours
        assert d.min() <= o.min() + COORD_TOL and d.max() >= o.max() - COORD_TOL


def test_thinning_a_closed_curve_keeps_its_outline():
    n = 100_000
    t = np.linspace(0, 2 * math.pi, n)
    x, y = 40 * np.cos(t) + 5 * np.cos(7 * t), 30 * np.sin(t)
    fig = Figure(figsize=(5.2, 5.2))
    ax = fig.add_subplot()
    ax.plot(x, y)
    ax.equal_aspect()
    ax.xlim(-50, 50)
    ax.ylim(-50, 50)
    info = all_axes(fig.to_svg())[0]
    drawn = info["lines"][0][0]
    assert len(drawn) <= 2000
    px, py = expected_px(info, (-50, 50, -50, 50), x, y)
    assert [drawn[:, 0].min(), drawn[:, 0].max(), drawn[:, 1].min(), drawn[:, 1].max()] == pytest.approx(
        [px.min(), px.max(), py.min(), py.max()], abs=COORD_TOL)
    # every original point lies within 1 px of the drawn polyline (brute force, a sample of points)
    a, b = drawn[:-1], drawn[1:]
    for p in np.column_stack([px, py])[::997]:
        ab, ap = b - a, p - a
        s = np.clip(np.einsum("ij,ij->i", ap, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0, 1)
        assert np.min(np.hypot(*(a + s[:, None] * ab - p).T)) < 1.0


def test_markers_sit_at_their_points():
    fig = Figure()
    ax = fig.add_subplot()
    ax.plot([1, 2, 3], [4, 5, 6], "o", marker_size=3)
    ax.plot([2], [5], "+", color="k", marker_size=10)
    ax.xlim(0, 4)
    ax.ylim(3, 7)
    info = all_axes(fig.to_svg())[0]
    paths = info["group"].findall("s:g[@class='data']/s:path[@class='markers']", NS)
    assert not info["group"].findall("s:g[@class='data']/s:path[@class='line']", NS)  # 'o' alone draws no line
    dots = np.array([[float(a), float(b)] for a, b in re.findall(rf"M({NUM}),({NUM})h0", paths[0].get("d"))])
    assert np.allclose(dots, np.column_stack(expected_px(info, (0, 4, 3, 7), [1, 2, 3], [4, 5, 6])), atol=COORD_TOL)
    assert paths[0].get("stroke-linecap") == "round"
    # '+': a horizontal stroke of 10 pt (40/3 px) centred on (2, 5)
    m = re.match(rf"M({NUM}),({NUM})h({NUM})", paths[1].get("d"))
    cx, cy = expected_px(info, (0, 4, 3, 7), 2, 5)
    arm = float(m.group(3))
    assert arm == pytest.approx(10 * 96 / 72, abs=0.01)
    assert (float(m.group(1)) + arm / 2, float(m.group(2))) == pytest.approx((cx, cy), abs=COORD_TOL)


# ------------------------------------------------------------------- determinism and clip ids

def _scene(prefix: str = "fig") -> str:
    fig = Figure(figsize=(10, 3.2), id_prefix=prefix)
    ax1, ax2 = fig.subplots(1, 2)
    t = np.linspace(0, 360, 900)
    ax1.plot(t, 25 * np.sin(np.radians(t)), label="a")
    ax1.hline(30, color="tab:red", dash="--")
    ax1.legend()
    ax2.plot(t, 50 + 40 * np.cos(np.radians(3 * t)), ".", marker_size=1.5)
    ax2.xlabel("cam angle (deg)")
    return fig.to_svg()


def test_same_input_same_bytes_across_processes():
    first = _scene()
    assert _scene() == first
    code = ("import hashlib, sys; sys.path.insert(0, sys.argv[1]); from test_svgplot import _scene; "
            "print(hashlib.sha256(_scene().encode()).hexdigest())")
    src = str(__import__("pathlib").Path(__file__).resolve().parent)  # this test module's folder
    out = subprocess.run([sys.executable, "-c", code, src], capture_output=True, text=True, check=True,
                         env={"PYTHONHASHSEED": "12345", "PATH": ""}).stdout.strip()
    assert out == hashlib.sha256(first.encode()).hexdigest()


def test_clip_paths_are_unique_on_a_page_and_clip_their_own_axes():
    page = "<div>" + _scene("cam1") + _scene("cam2") + "</div>"
    root = ET.fromstring(page)
    clips = root.findall(".//s:clipPath", NS)
    ids = [c.get("id") for c in clips]
    assert len(ids) == 4 and len(set(ids)) == 4
    for group in root.findall(".//s:g[@class='axes']", NS):
        data = group.find("s:g[@class='data']", NS)
        ref = re.fullmatch(r"url\(#(.+)\)", data.get("clip-path")).group(1)
        clip = [c for c in clips if c.get("id") == ref]
        assert len(clip) == 1
        frame = group.find("s:rect[@class='frame']", NS)
        assert [clip[0][0].get(k) for k in ("x", "y", "width", "height")] == [frame.get(k) for k in ("x", "y", "width", "height")]
    # the same prefix on two different layouts still gives different ids
    other = Figure(figsize=(6, 4))
    other.add_subplot().plot([0, 1], [0, 1])
    fig = Figure(figsize=(5, 4))
    fig.add_subplot().plot([0, 1], [0, 1])
    assert re.search(r'clipPath id="([^"]+)"', other.to_svg()).group(1) != re.search(r'clipPath id="([^"]+)"', fig.to_svg()).group(1)


def test_bad_parameters_are_refused():
    fig = Figure()
    ax = fig.add_subplot()
    for call in (lambda: ax.plot([0, 1], [0]), lambda: ax.plot([0, 1], [0, 1], color="nocolour"),
                 lambda: ax.plot([0, 1], [0, 1], dash="~"), lambda: ax.plot([0, 1], [0, 1], "q"),
                 lambda: ax.plot([0, 1], [0, 1], width=-1), lambda: ax.xlim(2, 1), lambda: ax.ylim(0, math.nan),
                 lambda: ax.legend("somewhere"), lambda: ax.hline(math.inf), lambda: Figure(id_prefix="1 bad"),
                 lambda: Figure(figsize=(0, 3)), lambda: fig.subplots(2, 2)):
        with pytest.raises(ParameterError):
            call()


# ------------------------------------------------------------------------- headless Chromium

def test_page_of_figures_renders_in_headless_chromium(tmp_path):
    """Chromium draws what the SVG says: the red reference line at y = 0.5 on the pixel row the
    limits imply, ink in the tick-label columns left of and below each plot area, text above it."""
    browser = require_tool("chromium")
    figs = []
    fig = Figure(figsize=(6, 3), id_prefix="one")
    ax = fig.add_subplot()
    ax.plot([0, 1], [0, 1], color="tab:blue", width=2, label="diagonal")
    ax.hline(0.5, color="#ff0000", width=2)
    ax.xlim(0, 1)
    ax.ylim(0, 1)
    ax.title("first figure")
    ax.xlabel("x (mm)")
    ax.ylabel("y (mm)")
    ax.legend("upper left")
    figs.append(fig.to_svg())
    fig = Figure(figsize=(6, 3), id_prefix="two")
    ax1, ax2 = fig.subplots(1, 2)
    t = np.linspace(0, 360, 2000)
    ax1.plot(t, np.sin(np.radians(t)), color="k")
    ax2.plot(t[::20], np.cos(np.radians(t[::20])), "o", marker_size=3, color="#0000ff")
    figs.append(fig.to_svg())
    html_page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><style>body{margin:0}svg{display:block}</style></head><body>"
                 + "".join(figs) + "</body></html>")
    page = tmp_path / "page.html"
    page.write_text(html_page, encoding="utf-8")
    shot = tmp_path / "shot.png"
    proc = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--hide-scrollbars",
         f"--user-data-dir={tmp_path / 'profile'}", "--force-device-scale-factor=1",
         "--window-size=700,700", f"--screenshot={shot}", page.as_uri()],
        check=False, capture_output=True, text=True, timeout=120,
    )
    assert shot.exists(), proc.stderr[-2000:]
    from PIL import Image

    rgb = np.asarray(Image.open(shot).convert("RGB"), dtype=float)
    gray = rgb.mean(axis=2)
    assert gray.std() > 10  # not blank
    offset = 0.0
    for svg in figs:
        for info in all_axes(svg):
            left, top = int(info["left"]), int(info["top"] + offset)
            right, bottom = int(info["left"] + info["w"]), int(info["top"] + info["h"] + offset)
            assert (gray[top:bottom, max(0, left - 40):left - 6] < 128).sum() > 30  # y tick labels
            assert (gray[bottom + 6:bottom + 22, left:right] < 128).sum() > 30  # x tick labels
            assert (gray[top + 2:bottom - 2, left + 2:right - 2] < 160).sum() > 100  # the curve
        offset += 3 * PX_PER_INCH
    info = all_axes(figs[0])[0]
    red = (rgb[:, :, 0] > 200) & (rgb[:, :, 1] < 80) & (rgb[:, :, 2] < 80)
    rows = np.flatnonzero(red[:, int(info["left"] + 0.8 * info["w"])])
    assert rows.size and abs(rows.mean() + 0.5 - (info["top"] + info["h"] / 2)) < 1.0
    title_band = gray[int(info["top"]) - 20:int(info["top"]) - 2, int(info["left"]):int(info["left"] + info["w"])]
    assert (title_band < 128).sum() > 30
    blue = (rgb[:, :, 2] > 200) & (rgb[:, :, 0] < 60) & (rgb[:, :, 1] < 60)
    assert blue[int(3 * PX_PER_INCH):].sum() > 100  # the 'o' markers (zero-length round-capped subpaths) show
