"""report.html: one self-contained page a designer reads (inline SVG plots, no scripts).

Per cam: the design and the motion program as tables with units (:mod:`camgen.report.design`)
beside the profile to scale with pitch curve, follower, bore and keyway; pressure angle and
radius of curvature against cam angle with their limits; the follower motion; the checks; the
computed figures.
For the horse leg: foot and body paths, pressure angle curves, the inclination sweep.  For the
tricycle: target path against the ride on the cam as made, the error types, and the measured
tables against the fitted model.

Plots are drawn by :mod:`camgen.report.svgplot` (numpy only).  The same input gives the same
bytes: no dates, figures numbered in page order.  A print style (``@media print``) lays the page
out for the printer's paper (Letter or A4, 15 mm margins): every plot whole on one page and at
most 125 mm tall, headings kept with what follows, the animation left out.
"""
from __future__ import annotations

import html
import math
from typing import TYPE_CHECKING, Callable, Sequence

import numpy as np

from camgen.report.format import FigureMaker, figure_factory, fmt, thin

if TYPE_CHECKING:
    from camgen.report.model import CamReport, CheckRow, ReportInput, ZeroMark
    from camgen.report.svgplot import Axes

__all__ = ["report_html"]

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em auto;max-width:1100px;color:#222;padding:0 1em}
h1{font-size:1.6em}h2{border-bottom:2px solid #ccc;padding-bottom:.2em;margin-top:2em}h3{margin-top:1.4em}
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}td,th{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}
th{background:#f3f3f3}.pass{color:#0a0;font-weight:bold}.fail{color:#c00;font-weight:bold}.info{color:#666}
.fig{margin:.5em 0}.note{color:#555;font-size:.9em}code{background:#f3f3f3;padding:0 .2em}
caption{text-align:left;font-weight:bold;padding:.2em 0}td.num{text-align:right;font-variant-numeric:tabular-nums}td.nw{white-space:nowrap}
tr.sized td{background:#f6f9ff}.tables{display:flex;flex-wrap:wrap;gap:0 1.5em;align-items:flex-start}.tables>table{flex:1 1 20em}
@page{size:auto;margin:15mm}
@media print{
body{max-width:none;margin:0;padding:0;font-size:9pt}h1{font-size:15pt;margin:0 0 .3em}
h2{font-size:13pt;margin-top:1em}h3{font-size:10.5pt;margin:.8em 0 .3em}h2,h3{break-after:avoid}
.fig,.tables,tr,caption{break-inside:avoid}.fig svg{display:block;margin:0 auto;max-height:125mm;width:auto}.fig{margin:.3em 0}
thead{display:table-header-group}table{margin:.3em 0}td,th{padding:.15em .4em}
.tables>.fig{width:52%}.tables>table{flex:1 1 0}.anim{display:none}table.checks{width:100%}
}
"""


_STATUS = {"pass": ("pass", "pass"), "fail": ("fail", "FAIL"), "info": ("info", "info")}


def _checks_table(checks: "Sequence[CheckRow]") -> str:
    rows = "".join(
        f"<tr><td>{html.escape(c.name)}</td><td class='{_STATUS[c.status][0]}'>{_STATUS[c.status][1]}</td>"
        f"<td class='nw'>{fmt(c.value)}</td><td class='nw'>{html.escape(c.comparison)} {fmt(c.limit) if c.limit is not None else '(no limit)'}</td>"
        f"<td class='nw'>{html.escape(c.unit)}</td><td>{fmt(c.where_deg)}{'' if c.where_unit == 'deg' or not c.where_deg else ' mm'}</td>"
        f"<td>{html.escape(c.note)}{' <b>(blocks manufacture)</b>' if c.failed and c.blocks_manufacture else ''}</td></tr>"
        for c in checks
    )
    return ("<table class='checks'><tr><th>check</th><th>result</th><th>value</th><th>limit</th><th>unit</th><th>where (deg)</th>"
            f"<th>note</th></tr>{rows}</table>")


def _profile_figure(Figure: FigureMaker, cam: "CamReport") -> str:
    plots = cam.plots
    assert plots is not None
    fig = Figure(figsize=(5.2, 5.2))
    ax = fig.add_subplot()
    if plots.profile is not None:
        pts = plots.profile
        closed = np.vstack([pts, pts[:1]])
        ax.plot(closed[:, 0], closed[:, 1], color="k", width=1.2, label="outline" if plots.walls else "profile")
    for layer, wall in plots.walls:  # a pocket's walls (a groove's): what the roller runs between
        closed = np.vstack([wall, wall[:1]])
        ax.plot(closed[:, 0], closed[:, 1], color="#1f3a5f", width=1.0, label=layer.lower().replace("_", " "))
    if plots.pitch is not None:
        pitch = np.vstack([plots.pitch, plots.pitch[:1]])
        ax.plot(pitch[:, 0], pitch[:, 1], "--", color="tab:blue", width=0.8, label="pitch curve (roller centre)")
    body = cam.body
    if body is not None and body.bore_diameter > 0:
        a = np.linspace(0, 2 * math.pi, 181)
        r = body.bore_diameter / 2
        ax.plot(r * np.cos(a), r * np.sin(a), color="tab:orange", width=0.8, label="bore")
        if body.keyway_corners is not None:
            rect = np.vstack([body.keyway_corners, body.keyway_corners[:1]])
            ax.plot(rect[:, 0], rect[:, 1], color="tab:green", width=0.8, label="keyway")
    if plots.outline_bounds is None:  # nothing to draw to scale: the checks table says why
        ax.text(0.5, 0.5, "the profile cannot be made (see the checks)", anchor="middle", coords="axes")
        return fig.to_svg()
    if plots.profile is None:
        ax.title(f"{cam.name}: pitch curve to scale; the profile cannot be made (undercut)")
    if plots.follower_drawing is not None:  # the kind drew its follower at cam angle 0
        colours = {"roller": "tab:red", "knife": "tab:red", "follower face": "tab:red"}
        seen: set[str] = set()
        for label, poly in plots.follower_drawing:
            ax.plot(poly[:, 0], poly[:, 1], color=colours.get(label, "#737373"), width=1.0,
                    label=None if label in seen else f"{label} at cam angle 0")
            seen.add(label)
    elif plots.faces is not None:
        xmin, ymin, xmax, ymax = plots.outline_bounds
        span = max(xmax - xmin, ymax - ymin)
        d = np.array([math.cos(plots.faces.direction), math.sin(plots.faces.direction)])
        side = np.array([-d[1], d[0]])
        for k, dist in enumerate(plots.faces.distances):
            line = np.array([dist * d - 0.6 * span * side, dist * d + 0.6 * span * side])
            ax.plot(line[:, 0], line[:, 1], color="tab:red", width=1.0, label="follower face at cam angle 0" if k == 0 else None)
    elif plots.roller is not None:
        (cx, cy), radius = plots.roller.centre, plots.roller.radius
        a = np.linspace(0, 2 * math.pi, 91)
        ax.plot(cx + radius * np.cos(a), cy + radius * np.sin(a), color="tab:red", width=1.0, label="follower at cam angle 0")
    if plots.zero_mark is not None:
        _zero_mark(ax, plots.zero_mark)
    ax.plot([0], [0], "+", color="k", marker_size=10)
    ax.equal_aspect()
    ax.xlabel("x (mm)")
    ax.ylabel("y (mm)")
    if plots.profile is not None:
        ax.title(f"{cam.name}: profile to scale (cam frame)")
    ax.legend("upper right", font_size=7)
    return fig.to_svg()


def _zero_mark(ax: "Axes", mark: "ZeroMark") -> None:
    """Cam angle 0 (a line from the axis to the point the follower touches then) and an arrow
    showing the direction of rotation."""
    p = np.asarray(mark.point, dtype=float)
    r = float(np.hypot(*p))
    ax.plot([0.0, p[0]], [0.0, p[1]], color="tab:purple", width=1.0, label="cam angle 0 (contact point)")
    a0 = math.atan2(p[1], p[0])
    a = a0 + mark.sigma * np.linspace(0.0, math.radians(50.0), 40)
    arc = 0.45 * r * np.stack([np.cos(a), np.sin(a)], axis=1)
    ax.plot(arc[:, 0], arc[:, 1], color="tab:purple", width=1.0)
    # the arrow head: two strokes back from the arc's end at +-25 deg to its direction
    tip, back = arc[-1], arc[-1] - arc[-4]
    back = 0.08 * r * back / np.hypot(*back)
    for turn in (math.radians(155.0), math.radians(-155.0)):
        c, s_ = math.cos(turn), math.sin(turn)
        end = tip + np.array([c * back[0] - s_ * back[1], s_ * back[0] + c * back[1]])
        ax.plot([tip[0], end[0]], [tip[1], end[1]], color="tab:purple", width=1.0)
    label_at = 0.55 * r * np.array([math.cos(a[20]), math.sin(a[20])])
    ax.text(float(label_at[0]), float(label_at[1]), "ccw" if mark.sigma > 0 else "cw", color="tab:purple", font_size=7,
            anchor="middle", valign="middle")


def _curves_figure(Figure: FigureMaker, cam: "CamReport", tool_radius: float) -> str:
    plots = cam.plots
    assert plots is not None
    fig = Figure(figsize=(10, 3.2))
    ax1, ax2 = fig.subplots(1, 2)
    if plots.pressure_angle is None or plots.curvature is None:
        ax1.text(0.5, 0.5, "no curves: the profile cannot be made (see the checks)", anchor="middle", coords="axes")
        return fig.to_svg()
    angle, pressure = plots.pressure_angle
    pa_check = next((c for c in cam.checks if c.name == "pressure_angle"), None)
    limit = float(pa_check.limit) if pa_check is not None and pa_check.limit is not None else plots.follower_limit_deg
    keep = thin(angle.size, 900)
    ax1.plot(np.degrees(angle)[keep], np.degrees(pressure)[keep], color="tab:blue", width=1)
    for sign in (1, -1):
        if limit is not None:
            ax1.hline(sign * limit, color="tab:red", dash="--", width=0.8)
    ax1.xlabel("cam angle (deg)")
    ax1.ylabel("pressure angle (deg)")
    title = "pressure angle, limit dashed"
    if plots.pressure_angle_label:
        title += f" ({plots.pressure_angle_label})"
    ax1.title(title, font_size=8)
    rho_angle, rho = plots.curvature
    order = np.argsort(np.mod(rho_angle, 2 * math.pi))
    bounds = plots.outline_bounds
    size = max(abs(v) for v in bounds) if bounds is not None else float(np.max(np.abs(rho[np.isfinite(rho)])))
    # near an inflection the radius runs off to infinity: the plot shows +-3 cam sizes and its note says what it leaves out
    shown, known = 3 * size, rho[~np.isnan(rho)]
    if known.size:
        ax2.ylim(-shown if known.min() < -shown else None, shown if known.max() > shown else None)
    keep = thin(order.size, 1200)
    ax2.plot(np.degrees(np.mod(rho_angle[order], 2 * math.pi))[keep], rho[order][keep], ".", marker_size=1.5, color="tab:blue")
    if plots.curvature_limit is not None:  # the radius the curve must stay above (roller radius, or 0)
        ax2.hline(plots.curvature_limit, color="tab:red", dash="--", width=0.8)
        ax2.title(f"{plots.curvature_label}; must stay above {plots.curvature_limit:g} mm (dashed)", font_size=8)
    else:
        for sign in (1, -1):
            ax2.hline(sign * tool_radius, color="tab:red", dash="--", width=0.8)
        ax2.title(f"radius of curvature; tool radius {tool_radius:g} mm dashed", font_size=8)
    ax2.xlabel(plots.curvature_angle_label)
    ax2.ylabel(plots.curvature_label)
    return fig.to_svg()


def _motion_figure(Figure: FigureMaker, cam: "CamReport") -> str:
    """Lift (from zero), velocity, acceleration and jerk against cam angle: at the scene's rpm in
    mm, mm/s, m/s^2, m/s^3 (rad, rad/s ... for an oscillating arm; lift in deg) with the time on a
    second axis, else per unit cam speed (per rad of cam angle)."""
    assert cam.plots is not None and cam.plots.motion is not None
    m = cam.plots.motion
    fig = Figure(figsize=(10, 4.6))
    axes = fig.subplots(2, 2).ravel()
    keep = thin(m.cam_angle.size, 720)
    deg = np.degrees(m.cam_angle)[keep]
    lift = np.degrees(m.lift) if m.unit == "rad" else m.lift
    lift_unit = "deg" if m.unit == "rad" else m.unit
    fast = m.at_speed
    if fast is not None:
        values = (lift[keep], fast.velocity[keep], fast.acceleration[keep], fast.jerk[keep])
        labels = (f"lift ({lift_unit})", f"velocity ({fast.velocity_unit})", f"acceleration ({fast.acceleration_unit})",
                  f"jerk ({fast.jerk_unit})")
        title = f"{cam.name}: follower motion at {fast.rpm:g} rpm (one turn {60.0 / fast.rpm:.4g} s)"
    else:
        values = (lift[keep], m.velocity[keep], m.acceleration[keep], m.jerk[keep])
        labels = (f"lift ({lift_unit})", f"velocity ({m.unit}/rad)", f"acceleration ({m.unit}/rad^2)", f"jerk ({m.unit}/rad^3)")
        title = f"{cam.name}: follower motion per unit cam speed (give rpm for the motion at speed)"
    for ax, value, label in zip(axes, values, labels):
        ax.plot(deg, value, width=1, color="tab:purple")
        ax.ylabel(label, font_size=8)
    if fast is not None:  # the same curves against time: a time axis above the top row (the columns share the cam angle)
        seconds = 60.0 / fast.rpm / 360.0
        for ax in axes[:2]:
            ax.top_axis(seconds, "time (s)", font_size=8)
    for angle in m.jerk_impulses_deg:
        axes[3].vline(angle, color="tab:red", width=0.6, dash=":")
    axes[2].xlabel("cam angle (deg)")
    axes[3].xlabel("cam angle (deg)" + (" (dotted: jerk impulses)" if m.jerk_impulses_deg else ""))
    fig.suptitle(title, font_size=9)
    return fig.to_svg()


def _animation(cam: "CamReport") -> str:
    from camgen.report.animation import animation_svg

    assert cam.plots is not None and cam.plots.animation is not None
    anim = cam.plots.animation
    speed = f"; the cam runs at {cam.rpm:g} rpm" if cam.rpm else ""
    svg = animation_svg(anim, html.escape(f"{cam.name}: the follower riding the cam"))
    return (f"<div class='fig anim'>{svg}<p class='note'>The follower riding the cam, one turn in {anim.seconds:g} s on screen{speed}; "
            "the purple line marks cam angle 0 on the cam.</p></div>")


def _vdi_section(Figure: FigureMaker, cam: "CamReport") -> str:
    from camgen.report.vdi import vdi_section

    return vdi_section(Figure, cam)


def _section(path: str) -> Callable[..., str]:
    """The function ``"module:function"`` names (a kind's or mechanism's own report section)."""
    import importlib

    module, function = path.split(":")
    drawn: Callable[..., str] = getattr(importlib.import_module(module), function)
    return drawn


def report_html(report: "ReportInput") -> str:
    """The page of a run (UTF-8 text): every cam, then every mechanism.

    A cam kind's or mechanism's own part of the page is drawn by the function its
    ``report_section`` names, called with the page's figure maker and the
    :class:`~camgen.report.model.CamReport` (a mechanism: its
    :class:`~camgen.report.model.MechanismReport`, when its section has data)."""
    from camgen.report.design import design_table, figures_table, program_table
    from camgen.report.smoothing import smoothing_section
    from camgen.report.sizing_ranges import sizing_ranges_section

    Figure = figure_factory()
    cams = report.cams
    tool_radius = report.tool_radius_mm
    summary = "".join(
        f"<tr><td><a href='#{html.escape(c.name)}'>{html.escape(c.name)}</a></td><td>{html.escape(c.kind)}</td><td>{html.escape(c.form)}</td>"
        f"<td class='{'fail' if c.failed else 'pass'}'>"
        f"{sum(k.status == 'pass' for k in c.checks)} passed, {sum(k.failed for k in c.checks)} failed, "
        f"{sum(k.status == 'info' for k in c.checks)} information</td>"
        f"<td>{'yes' if c.manufacturable else 'no: ' + html.escape(', '.join(c.withheld_files) or 'no manufacturing file')}</td></tr>"
        for c in cams
    )
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>camgen report: {html.escape(report.scene)}</title><style>{_CSS}</style></head><body>",
        f"<h1>camgen design-check report: {html.escape(report.scene)}</h1>",
        f"<p class='note'>camgen {report.camgen_version}; scene <code>{html.escape(report.source_file)}</code>; chord tolerance "
        f"{report.chord_tol_mm:g} mm; units mm and deg.</p>",
        f"<table><tr><th>cam</th><th>kind (motion)</th><th>form</th><th>checks</th><th>manufacturing files written</th></tr>{summary}</table>",
    ]
    for cam in cams:
        parts.append(f"<h2 id='{html.escape(cam.name)}'>{html.escape(cam.name)} ({html.escape(cam.kind)}, {html.escape(cam.form)} cam)</h2>")
        if cam.plots is not None:  # the profile to scale beside the design's numbers
            parts.append(f"<div class='tables'><div class='fig'>{_profile_figure(Figure, cam)}</div>{design_table(cam)}</div>")
        else:
            parts.append(design_table(cam))
        parts.append(program_table(cam))
        # a kind that draws its own curves (a linear cam: against travel) gives none here and its section's data
        own_curves = cam.plots is not None and cam.plots.pressure_angle is None and cam.plots.curvature is None and cam.section is not None
        if cam.plots is not None and not own_curves:
            parts.append(f"<div class='fig'>{_curves_figure(Figure, cam, tool_radius)}</div>")
            if cam.plots.motion is not None:
                parts.append(f"<div class='fig'>{_motion_figure(Figure, cam)}</div>")
            if cam.plots.animation is not None:
                parts.append(_animation(cam))
        if cam.dynamics is not None:
            from camgen.report.dynamics import dynamics_section

            parts.append(dynamics_section(Figure, cam))
        parts.append("<h3>Checks</h3>" + _checks_table(cam.checks))
        parts.append(figures_table(cam))
        parts.append(smoothing_section(Figure, cam))  # SMOOTH: a smoothed lift table's residuals ("" otherwise)
        parts.append(sizing_ranges_section(cam))  # SIZE2: the sizing_ranges key's intervals ("" otherwise)
        parts.append(_vdi_section(Figure, cam))  # VDI: issue 26 items 2 and 5 (camgen/report/vdi.py)
        if cam.report_section:
            parts.append(_section(cam.report_section)(Figure, cam))
    for mechanism in report.mechanisms:
        if mechanism.report_section and mechanism.section is not None:
            parts.append(_section(mechanism.report_section)(Figure, mechanism))
    parts.append("</body></html>\n")
    return "".join(parts)
