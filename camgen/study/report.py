"""The sweep report: one self-contained HTML page of a study's rows, and the scenes of its best
designs.

:func:`sweep_report_files` gives the files a sweep writes into its folder (name -> text):
``report.html`` and ``best/<key>.toml`` for each of the best designs.  The page (inline SVG, no
script, no external file; the same rows give the same bytes) has:

- a header: the scene, its hash, the method, the points and how many passed, failed, were
  refused (error) or killed their worker (crashed), camgen's version, the varied keys;
- the feasibility map of two varied keys (:func:`report_options`: the first two unless
  ``map_keys`` names others): with at most two varied keys (and at most :data:`MAP_POINTS`
  designs) each design is a disc coloured by its first failing check (pass green, error grey,
  crashed black, a legend of the checks); with more varied keys each cell of the two keys'
  values (a value each when a key has at most :data:`MAP_CATEGORIES` values, else
  :data:`MAP_BINS` equal bins) is shaded by the share of its designs that pass;
- the Pareto front of two figures among the passing designs (default the first cam's outer
  radius and peak pressure angle, both minimised), drawn over every passing design;
- the best designs (ranked by ``rank``, default the outer radius, smallest first, among the
  passing ones) with their inputs and figures and a link to their scene;
- the most frequent error lines.
"""
from __future__ import annotations

import html
from collections import Counter
from dataclasses import dataclass
from typing import TYPE_CHECKING, Mapping, Sequence

from camgen.errors import ParameterError
from camgen.study.best import best_rows, best_scene_text, check_best, default_rank
from camgen.study.columns import FigureColumn, cam_names, check_label, number, resolve_figure, row_category
from camgen.study.mapplot import Axis, Cell, Mark, category_axis, numeric_axis, plot_svg

if TYPE_CHECKING:
    from pathlib import Path

    from camgen.study.design import StudyScene
    from camgen.study.space import Variable

__all__ = ["CHECK_COLORS", "MAP_BINS", "MAP_CATEGORIES", "MAP_POINTS", "PARETO_DRAWN", "PARETO_LISTED", "ReportOptions",
           "STATUS_COLORS", "report_options", "sweep_report_files", "write_report_files"]

#: Most designs a feasibility map draws one by one (more: the map shows cells, as for more than
#: two varied keys).
MAP_POINTS = 5_000
#: Radius of a design's disc in a map, px: up to MAP_SMALL designs, and more.
MAP_RADIUS, MAP_RADIUS_MANY, MAP_SMALL = 4.0, 2.5, 1_000
#: A key with at most this many distinct values has a map cell per value; more are binned.
MAP_CATEGORIES = 40
#: Equal bins of a key's range in a map of cells (keys with more than MAP_CATEGORIES values).
MAP_BINS = 20
#: Most passing designs drawn behind the Pareto front (more: every k-th of them, said under the plot).
PARETO_DRAWN = 5_000
#: Most designs of the Pareto front listed in its table (all are drawn).
PARETO_LISTED = 50
#: Most distinct error lines listed.
ERRORS_LISTED = 10
#: The colours of a design's status in a map.
STATUS_COLORS = {"pass": "#1a9850", "error": "#9e9e9e", "crashed": "#000000", "fail": "#7f3b08"}
#: The colours of the first failing checks, in order of their first appearance (Okabe & Ito
#: first, then more distinct hues; repeated past the end, the legend says which is which).
CHECK_COLORS = ("#0072B2", "#E69F00", "#D55E00", "#CC79A7", "#56B4E9", "#F0E442", "#8C564B", "#9467BD", "#17BECF",
                "#BCBD22")
#: A map cell's shade: none passing -> all passing.
_SHARE_LOW, _SHARE_HIGH = (0xF2, 0xF2, 0xF2), (0x1A, 0x98, 0x50)
_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em auto;max-width:1100px;color:#222;padding:0 1em}
h1{font-size:1.6em}h2{border-bottom:2px solid #ccc;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}td,th{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}
th{background:#f3f3f3}td.num{text-align:right;font-variant-numeric:tabular-nums}.note{color:#555;font-size:.9em}
ul.legend{list-style:none;padding:0;display:flex;flex-wrap:wrap;gap:.3em 1.2em}ul.legend li{white-space:nowrap}
.swatch{display:inline-block;width:.9em;height:.9em;border-radius:50%;vertical-align:-.1em;margin-right:.35em;border:1px solid #888}
.ramp{display:inline-block;width:12em;height:.9em;vertical-align:-.1em;border:1px solid #888;
background:linear-gradient(to right,#f2f2f2,#1a9850)}code{background:#f3f3f3;padding:0 .2em}.wide{overflow-x:auto}
"""


@dataclass(frozen=True)
class ReportOptions:
    """The report's choices, validated: the map's keys (one or two varied keys), the Pareto
    front's two figures, the ranking figure and how many best designs."""

    map_keys: "tuple[Variable, ...]"
    pareto: tuple[FigureColumn, FigureColumn]
    rank: FigureColumn
    best: int


def _map_key(study: "StudyScene", variables: "Sequence[Variable]", name: object) -> "Variable":
    from camgen.study.keys import resolve_key

    valid = "one of the varied keys: " + ", ".join(v.name for v in variables)
    if not isinstance(name, str):
        raise ParameterError("--map", name, valid)
    try:
        path = resolve_key(study.data, name, "--map")
    except ParameterError:
        raise ParameterError("--map", name, valid) from None
    found = next((v for v in variables if v.name == path.name), None)
    if found is None:
        raise ParameterError("--map", name, valid)
    return found


def report_options(study: "StudyScene", variables: "Sequence[Variable]", map_keys: "Sequence[str] | None" = None,
                   pareto: "Sequence[str] | None" = None, best: int = 10, rank: str | None = None) -> ReportOptions:
    """The report's options checked against the study (call it before the sweep runs: a bad
    option is refused before any design is evaluated).

    Parameters
    ----------
    map_keys : two varied keys (one when one key varies), as ``--vary`` names them; None: the first two.
    pareto : two figures (:func:`camgen.study.columns.resolve_figure`); None: the first cam's
        ``outer_radius_mm`` and ``pressure_angle_deg``.
    best : how many best designs (0 to :data:`camgen.study.best.MAX_BEST`).
    rank : the figure that ranks them; None: the first cam's ``outer_radius_mm``.

    Raises
    ------
    ParameterError
        Naming the option (``--map``, ``--pareto``, ``--best``, ``--rank``), the value and the valid ones.
    """
    if not variables:
        raise ParameterError("--vary", "", "at least one varied key (--vary KEY=... or a [sweep.vary] table)")
    wanted = min(2, len(variables))
    if map_keys is None:
        chosen = tuple(variables[:wanted])
    else:
        if isinstance(map_keys, str) or len(map_keys) != wanted:
            raise ParameterError("--map", map_keys, f"{wanted} of the varied keys: " + ", ".join(v.name for v in variables))
        chosen = tuple(_map_key(study, variables, k) for k in map_keys)
        if len({v.name for v in chosen}) != len(chosen):
            raise ParameterError("--map", map_keys, "two different varied keys")
    cams = cam_names(study.data)
    first = cams[0] if cams else ""
    names = (f"fig.{first}.outer_radius_mm", f"fig.{first}.pressure_angle_deg") if pareto is None else pareto
    if isinstance(names, str) or len(names) != 2:
        raise ParameterError("--pareto", pareto, "two figures, e.g. outer_radius_mm,pressure_angle_deg")
    a, b = (resolve_figure(study.data, n, "--pareto") for n in names)
    if a.column == b.column:
        raise ParameterError("--pareto", pareto, "two different figures")
    figure = resolve_figure(study.data, default_rank(study.data) if rank is None else rank, "--rank")
    return ReportOptions(chosen, (a, b), figure, check_best(best))


def sweep_report_files(study: "StudyScene", variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], *,
                       map_keys: "Sequence[str] | None" = None, pareto: "Sequence[str] | None" = None, best: int = 10,
                       rank: str | None = None, method: str = "") -> dict[str, str]:
    """The report's files, relative to the sweep's folder: ``report.html`` and, for each of the
    ``best`` designs, ``best/<key>.toml`` (the base scene's text with the design's values,
    comments kept: ``camgen run`` accepts it).

    ``rows``: the study's rows (:func:`camgen.study.design.evaluate_point`, or read back from its
    Parquet files); ``method``: how the points were chosen (grid, lhs, sobol, file), for the header.
    The options are those of :func:`report_options` (refused the same way).
    """
    options = report_options(study, variables, map_keys, pareto, best, rank)
    chosen = best_rows(rows, options.rank, options.best)
    files = {f"best/{row['key']}.toml": best_scene_text(study, variables, row) for row in chosen}
    files["report.html"] = _page(study, variables, rows, options, chosen, method)
    return files


def write_report_files(folder: "str | Path", files: Mapping[str, str]) -> list["Path"]:
    """Write ``files`` (name relative to ``folder`` -> text, as :func:`sweep_report_files` gives
    them) into ``folder``, each atomically (:func:`camgen.export.atomic.write_atomic`); the paths."""
    from pathlib import Path

    from camgen.export.atomic import write_atomic

    base = Path(folder)
    out = []
    for name, text in files.items():
        if Path(name).is_absolute() or ".." in Path(name).parts:
            raise ParameterError("report file", name, "a name inside the sweep's folder")
        out.append(write_atomic(base / name, text))
    return out


# --------------------------------------------------------------------------------------- text

def _text(value: object) -> str:
    """A cell as the page writes it (numbers to 6 significant digits; None and NaN as '-')."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return value
    v = number(value)
    if v is None:
        return "-"
    if isinstance(value, int):
        return str(value)
    return f"{v:.6g}"


def _e(value: object) -> str:
    return html.escape(_text(value))


def _variable_text(v: "Variable") -> str:
    if v.values:
        return ", ".join(_text(x) for x in v.values[:12]) + (f", ... ({len(v.values)} values)" if len(v.values) > 12 else "")
    return f"{_text(v.low)} to {_text(v.high)}" + (f", step {_text(v.step)}" if v.step is not None else "")


def _header(study: "StudyScene", variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], method: str) -> str:
    from camgen import __version__

    counts = Counter(str(r.get("status")) for r in rows)
    versions = sorted({str(r.get("camgen_version")) for r in rows if r.get("camgen_version")}) or [__version__]
    items = [("scene", study.source), ("scene hash", study.scene_hash), ("method", method or "-"), ("points", str(len(rows)))]
    items += [(status, str(counts.get(status, 0))) for status in ("pass", "fail", "error", "crashed")]
    items.append(("camgen version", ", ".join(versions)))
    body = "".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in items)
    keys = "".join(f"<tr><td><code>{html.escape(v.name)}</code></td><td>{html.escape(_variable_text(v))}</td></tr>" for v in variables)
    return (f"<table class='header'>{body}</table><table class='varied'><tr><th>varied key</th><th>values</th></tr>{keys}</table>")


# ---------------------------------------------------------------------------------- the map

def _is_numeric(values: Sequence[object]) -> bool:
    return all(not isinstance(v, (bool, str)) and number(v) is not None for v in values)


def _categories(values: Sequence[object]) -> list[str]:
    """The distinct values as text, numbers in numeric order, then words in text order."""
    distinct = {_text(v): v for v in values}
    return sorted(distinct, key=lambda t: (0, number(distinct[t]) or 0.0, t) if _is_numeric([distinct[t]]) else (1, 0.0, t))


def _legend(colors: Mapping[str, str], counts: Counter[str]) -> str:
    items = "".join(f"<li data-category='{html.escape(c)}'><span class='swatch' style='background:{colors[c]}'></span>"
                    f"{html.escape(c)} ({counts[c]})</li>" for c in colors if counts[c])
    return f"<ul class='legend'>{items}</ul>"


def _category_colors(categories: Sequence[str]) -> dict[str, str]:
    """pass first, then the failing checks in order of first appearance, then error and crashed."""
    checks = [c for c in dict.fromkeys(categories) if c not in STATUS_COLORS]
    colors = {"pass": STATUS_COLORS["pass"]}
    colors.update({c: CHECK_COLORS[i % len(CHECK_COLORS)] for i, c in enumerate(checks)})
    colors.update({s: STATUS_COLORS[s] for s in ("fail", "error", "crashed")})
    return colors


def _points_map(variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], cats: Sequence[str],
                colors: Mapping[str, str]) -> str:
    axes: list[Axis] = []
    positions: list[list[float]] = []
    for v in variables:
        values = [r.get(v.name) for r in rows]
        if _is_numeric(values):
            numbers = [float(number(x) or 0.0) for x in values]
            axes.append(numeric_axis(v.name, numbers))
            positions.append(numbers)
        else:
            names = _categories(values)
            index = {n: i for i, n in enumerate(names)}
            axes.append(category_axis(v.name, names))
            positions.append([float(index[_text(x)]) for x in values])
    if len(axes) == 1:
        axes.append(category_axis("", [""]))
        positions.append([0.0] * len(rows))
    marks = []
    radius = MAP_RADIUS if len(rows) <= MAP_SMALL else MAP_RADIUS_MANY
    for i, (row, cat) in enumerate(zip(rows, cats)):
        inputs = ", ".join(f"{v.name} = {_text(row.get(v.name))}" for v in variables)
        why = f": {row.get('error')}" if cat in ("error", "crashed") and row.get("error") else ""
        marks.append(Mark(positions[0][i], positions[1][i], colors[cat], f"{row.get('key')}: {inputs}; {cat}{why}",
                          (("data-key", str(row.get("key"))), ("data-status", str(row.get("status"))), ("data-category", cat)),
                          radius))
    return plot_svg(axes[0], axes[1], marks=marks, svg_id="feasibility")


def _cell_axis(v: "Variable", values: Sequence[object]) -> tuple[Axis, list[int], list[str]]:
    """A map axis of cells: per design its cell index, per cell its label."""
    numeric = _is_numeric(values)
    if not numeric or len(set(values)) <= MAP_CATEGORIES:
        names = _categories(values)
        index = {n: i for i, n in enumerate(names)}
        return category_axis(v.name, names), [index[_text(x)] for x in values], names
    import numpy as np

    numbers = np.array([number(x) for x in values], dtype=float)
    lo, hi = float(numbers.min()), float(numbers.max())
    cell = np.minimum(((numbers - lo) / (hi - lo) * MAP_BINS).astype(int), MAP_BINS - 1)
    edges = lo + (hi - lo) * np.arange(MAP_BINS + 1) / MAP_BINS
    labels = [f"{_text(float(edges[i]))} to {_text(float(edges[i + 1]))}" for i in range(MAP_BINS)]
    return Axis(v.name, lo, hi), [int(c) for c in cell], labels


def _share_color(share: float) -> str:
    return "#" + "".join(f"{round(a + (b - a) * share):02x}" for a, b in zip(_SHARE_LOW, _SHARE_HIGH))


def _cells_map(variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], cats: Sequence[str]) -> str:
    built = [_cell_axis(v, [r.get(v.name) for r in rows]) for v in variables]
    if len(built) == 1:
        built.append((category_axis("", [""]), [0] * len(rows), [""]))
    (xaxis, xi, xl), (yaxis, yi, yl) = built
    groups: dict[tuple[int, int], Counter[str]] = {}
    for i, cat in enumerate(cats):
        groups.setdefault((xi[i], yi[i]), Counter())[cat] += 1

    def span(axis: Axis, i: int) -> tuple[float, float]:
        if axis.categories:
            return i - 0.5, i + 0.5
        step = (axis.hi - axis.lo) / MAP_BINS
        return axis.lo + i * step, axis.lo + (i + 1) * step

    cells = []
    for (i, j), counts in sorted(groups.items()):
        total, passed = sum(counts.values()), counts.get("pass", 0)
        share = passed / total
        failing = ", ".join(f"{c} {n}" for c, n in counts.most_common() if c != "pass")
        x0, x1 = span(xaxis, i)
        y0, y1 = span(yaxis, j)
        title = (f"{variables[0].name} {xl[i]}" + (f", {variables[1].name} {yl[j]}" if len(variables) > 1 else "")
                 + f": {passed} of {total} pass" + (f"; first failing: {failing}" if failing else ""))
        cells.append(Cell(x0, x1, y0, y1, _share_color(share), title, f"{round(100 * share)}%",
                          (("data-x", xl[i]), ("data-y", yl[j]), ("data-count", str(total)), ("data-pass", str(passed)))))
    return plot_svg(xaxis, yaxis, cells=cells, svg_id="feasibility")


def _feasibility(study: "StudyScene", variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]],
                 options: ReportOptions) -> str:
    if not rows:
        return "<p class='note'>No design was evaluated.</p>"
    cams = cam_names(study.data)
    cats = [row_category(r, cams) for r in rows]
    counts = Counter(cats)
    keys = options.map_keys
    what = " and ".join(f"<code>{html.escape(v.name)}</code>" for v in keys)
    if len(variables) <= 2 and len(rows) <= MAP_POINTS:
        colors = _category_colors(cats)
        return (f"<p class='note'>Each design of {what}, coloured by its first failing check (pass green, "
                "error grey, crashed black); hover over a design for its key and values.</p>"
                + _points_map(keys, rows, cats, colors) + _legend(colors, counts))
    why = f"{len(variables)} keys vary" if len(variables) > 2 else f"{len(rows)} designs (more than {MAP_POINTS} are shown as cells)"
    return (f"<p class='note'>{why}: each cell of {what} shaded by the share of its designs that pass "
            "(a value per cell, or equal bins of a key with many values); hover for the counts and the first failing checks.</p>"
            + _cells_map(keys, rows, cats)
            + "<p class='note'>none pass <span class='ramp'></span> all pass</p>"
            + "<p class='note'>designs by their first failing check (pass: none failed): "
            + html.escape(", ".join(f"{c} {n}" for c, n in counts.most_common())) + "</p>")


# ------------------------------------------------------------------------------- the front

def _pareto(variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], options: ReportOptions) -> str:
    from camgen.study.pareto import pareto_front

    fa, fb = options.pareto
    passing = [(r, a, b) for r in rows if r.get("status") == "pass"
               and (a := number(r.get(fa.column))) is not None and (b := number(r.get(fb.column))) is not None]
    title = (f"<p class='note'>{html.escape(fa.label)} ({'largest' if fa.maximise else 'smallest'} best) against "
             f"{html.escape(fb.label)} ({'largest' if fb.maximise else 'smallest'} best), passing designs only.</p>")
    if not passing:
        return title + "<p class='note'>No passing design has both figures.</p>"
    mask = pareto_front([fa.sign() * a for _, a, _ in passing], [fb.sign() * b for _, _, b in passing])
    front = sorted((p for p, on in zip(passing, mask) if on), key=lambda p: (fa.sign() * p[1], fb.sign() * p[2], str(p[0].get("key"))))
    stride = max(1, -(-len(passing) // PARETO_DRAWN))
    marks = [Mark(a, b, "#bbbbbb", f"{r.get('key')}: {fa.label} {_text(a)}, {fb.label} {_text(b)}", (("data-key", str(r.get("key"))),),
                  3.0, "passing") for r, a, b in passing[::stride]]
    marks += [Mark(a, b, "#d55e00", f"{r.get('key')}: {fa.label} {_text(a)}, {fb.label} {_text(b)} (on the front)",
                   (("data-key", str(r.get("key"))),), 4.5, "front") for r, a, b in front]
    line: list[tuple[float, float]] = []
    for (_, a, b), nxt in zip(front, front[1:] + [None]):
        line.append((a, b))
        if nxt is not None:
            line.append((nxt[1], b))
    svg = plot_svg(numeric_axis(fa.label, [a for _, a, _ in passing]), numeric_axis(fb.label, [b for _, _, b in passing]),
                   marks=marks, line=line, svg_id="pareto")
    drawn = "" if stride == 1 else f" Every {stride}th of the {len(passing)} passing designs is drawn grey; the front whole."
    head = "".join(f"<th>{html.escape(v.name)}</th>" for v in variables)
    body = "".join(f"<tr><td><code>{html.escape(str(r.get('key')))}</code></td><td class='num'>{_e(a)}</td><td class='num'>{_e(b)}</td>"
                   + "".join(f"<td class='num'>{_e(r.get(v.name))}</td>" for v in variables) + "</tr>" for r, a, b in front[:PARETO_LISTED])
    more = f"<p class='note'>{len(front) - PARETO_LISTED} more designs on the front are drawn, not listed.</p>" if len(front) > PARETO_LISTED else ""
    return (title + svg + f"<p class='note'>{len(front)} of {len(passing)} passing designs on the front (orange).{drawn}</p>"
            + f"<div class='wide'><table class='front'><tr><th>key</th><th>{html.escape(fa.label)}</th><th>{html.escape(fb.label)}</th>{head}</tr>{body}</table></div>"
            + more)


# ------------------------------------------------------------------------------ the best

def _best(study: "StudyScene", variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], options: ReportOptions,
          chosen: Sequence[Mapping[str, object]]) -> str:
    cams = cam_names(study.data)
    passing = sum(1 for r in rows if r.get("status") == "pass")
    note = (f"<p class='note'>The {len(chosen)} passing designs with the {'largest' if options.rank.maximise else 'smallest'} "
            f"{html.escape(options.rank.label)} (of {passing} passing); each one's scene is <code>best/&lt;key&gt;.toml</code> "
            "(the base scene with the design's values, comments kept): <code>camgen run</code> it for its files.</p>")
    if not chosen:
        if options.best and passing:
            return (f"<p class='note'>No passing design has a value of {html.escape(options.rank.label)} "
                    "(rank them by another figure).</p>")
        return note
    figures = list(dict.fromkeys(c for r in chosen for c in r if c.startswith("fig.")))
    labels = [check_label(c[4:], cams) for c in figures]
    head = ("<tr><th>#</th><th>key</th>" + "".join(f"<th>{html.escape(v.name)}</th>" for v in variables)
            + "".join(f"<th>{html.escape(lab)}</th>" for lab in labels) + "<th>scene</th></tr>")
    body = ""
    for i, r in enumerate(chosen, 1):
        key = html.escape(str(r.get("key")))
        body += (f"<tr data-key='{key}'><td class='num'>{i}</td><td><code>{key}</code></td>"
                 + "".join(f"<td class='num'>{_e(r.get(v.name))}</td>" for v in variables)
                 + "".join(f"<td class='num'>{'<b>' if c == options.rank.column else ''}{_e(r.get(c))}"
                           f"{'</b>' if c == options.rank.column else ''}</td>" for c in figures)
                 + f"<td><a href='best/{key}.toml'>best/{key}.toml</a></td></tr>")
    return note + f"<div class='wide'><table class='best'>{head}{body}</table></div>"


def _errors(rows: Sequence[Mapping[str, object]]) -> str:
    lines = Counter(str(r.get("error")) for r in rows if r.get("status") in ("error", "crashed") and r.get("error"))
    if not lines:
        return ""
    body = "".join(f"<tr><td class='num'>{n}</td><td>{html.escape(line)}</td></tr>" for line, n in lines.most_common(ERRORS_LISTED))
    more = f"<p class='note'>{len(lines) - ERRORS_LISTED} more distinct lines.</p>" if len(lines) > ERRORS_LISTED else ""
    return f"<h2>Errors</h2><table class='errors'><tr><th>designs</th><th>error</th></tr>{body}</table>{more}"


def _page(study: "StudyScene", variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], options: ReportOptions,
          chosen: Sequence[Mapping[str, object]], method: str) -> str:
    name = html.escape(study.name)
    return ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            "<meta name='viewport' content='width=device-width,initial-scale=1'>"
            f"<title>camgen sweep: {name}</title><style>{_CSS}</style></head><body>"
            f"<h1>Sweep of {name}</h1>{_header(study, variables, rows, method)}"
            f"<h2>Feasibility</h2>{_feasibility(study, variables, rows, options)}"
            f"<h2>Pareto front</h2>{_pareto(variables, rows, options)}"
            f"<h2>Best designs</h2>{_best(study, variables, rows, options, chosen)}"
            f"{_errors(rows)}</body></html>\n")
