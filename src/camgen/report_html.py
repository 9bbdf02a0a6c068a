"""report.html: one self-contained page a designer reads (inline SVG plots, no scripts).

Per cam: the profile to scale with pitch curve, follower, bore and keyway; pressure angle and
radius of curvature against cam angle with their limits; the follower motion; the checks.
For the horse leg: foot and body paths, pressure angle curves, the inclination sweep.  For the
tricycle: target path against the ride on the cam as made, the error types, and the measured
tables against the fitted model.

Needs matplotlib (``pip install "camgen[report]"``).  The same input gives the same bytes:
SVG hash salt fixed, no dates, text kept as text.
"""
from __future__ import annotations

import html
import io
import math
from typing import Any, Sequence

import numpy as np

from camgen.errors import ExportError

_CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em auto;max-width:1100px;color:#222;padding:0 1em}
h1{font-size:1.6em}h2{border-bottom:2px solid #ccc;padding-bottom:.2em;margin-top:2em}h3{margin-top:1.4em}
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}td,th{border:1px solid #ccc;padding:.25em .5em;text-align:left;vertical-align:top}
th{background:#f3f3f3}.pass{color:#0a0;font-weight:bold}.fail{color:#c00;font-weight:bold}
.fig{margin:.5em 0}.note{color:#555;font-size:.9em}code{background:#f3f3f3;padding:0 .2em}
"""


def _matplotlib():
    try:
        import matplotlib
    except ImportError:  # pragma: no cover - depends on the install
        raise ExportError("report.html needs matplotlib: install camgen with the report extra (pip install \".[report]\")") from None
    matplotlib.use("Agg")
    matplotlib.rcParams.update({"svg.hashsalt": "camgen", "svg.fonttype": "none", "font.size": 9, "axes.grid": True, "grid.alpha": 0.3})
    from matplotlib.figure import Figure

    return Figure


def _svg(fig: Any) -> str:
    buf = io.StringIO()
    fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None}, bbox_inches="tight")
    text = buf.getvalue()
    text = text[text.index("<svg"):]
    start, end = text.find("<metadata>"), text.find("</metadata>")
    if start >= 0 and end > start:  # RDF creator/date block: nothing a reader needs
        text = text[:start] + text[end + len("</metadata>"):]
    return text


def _thin(n: int, most: int = 900) -> slice:
    """A slice that keeps at most about ``most`` of ``n`` evenly spaced samples (plots only)."""
    return slice(None, None, max(1, math.ceil(n / most)))


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, tuple)):
        return ", ".join(_fmt(v) for v in value[:12]) + (" ..." if len(value) > 12 else "")
    return html.escape(str(value))


def _checks_table(checks: Sequence[Any]) -> str:
    rows = "".join(
        f"<tr><td>{html.escape(c.name)}</td><td class='{'pass' if c.passed else 'fail'}'>{'pass' if c.passed else 'FAIL'}</td>"
        f"<td>{_fmt(c.value)}</td><td>{_fmt(c.limit)}</td><td>{html.escape(c.unit)}</td><td>{_fmt(c.where_deg)}</td>"
        f"<td>{html.escape(c.note)}</td></tr>"
        for c in checks
    )
    return ("<table><tr><th>check</th><th>result</th><th>value</th><th>limit</th><th>unit</th><th>where (deg)</th>"
            f"<th>note</th></tr>{rows}</table>")


def _figures_table(figures: dict[str, Any]) -> str:
    rows = "".join(f"<tr><td>{html.escape(k)}</td><td>{_fmt(v)}</td></tr>" for k, v in figures.items() if not isinstance(v, dict))
    return f"<table><tr><th>figure</th><th>value</th></tr>{rows}</table>"


def _profile_figure(Figure: Any, cam: Any) -> str:
    ev = cam.evaluation
    fig = Figure(figsize=(5.2, 5.2))
    ax = fig.add_subplot()
    pts = cam.contour.flatten(0.01)
    closed = np.vstack([pts, pts[:1]])
    ax.plot(closed[:, 0], closed[:, 1], color="k", lw=1.2, label="profile")
    if ev.pitch is not None:
        pitch = ev.pitch.flatten(0.01)
        pitch = np.vstack([pitch, pitch[:1]])
        ax.plot(pitch[:, 0], pitch[:, 1], "--", color="tab:blue", lw=0.8, label="pitch curve (roller centre)")
    body = cam.body
    if body is not None and body.bore_diameter > 0:
        a = np.linspace(0, 2 * math.pi, 181)
        r = body.bore_diameter / 2
        ax.plot(r * np.cos(a), r * np.sin(a), color="tab:orange", lw=0.8, label="bore")
        if body.keyway_width > 0:
            from camgen.export.solid import keyway_rectangle

            rect = keyway_rectangle(body)
            rect = np.vstack([rect, rect[:1]])
            ax.plot(rect[:, 0], rect[:, 1], color="tab:green", lw=0.8, label="keyway")
    follower = ev.follower
    xmin, ymin, xmax, ymax = cam.contour.bounds
    span = max(xmax - xmin, ymax - ymin)
    d = np.array([math.cos(follower.direction), math.sin(follower.direction)])
    side = np.array([-d[1], d[0]])
    if follower.kind in ("yoke", "flat"):
        h = float(cam.contour.support(np.array([follower.direction]))[0])
        faces = [h] + ([h - cam.model["breadth_mm"]] if follower.kind == "yoke" and isinstance(cam.model, dict) else [])
        for k, dist in enumerate(faces):
            line = np.array([dist * d - 0.6 * span * side, dist * d + 0.6 * span * side])
            ax.plot(line[:, 0], line[:, 1], color="tab:red", lw=1.0, label="follower face at cam angle 0" if k == 0 else None)
    else:
        pos = ev.motion.displacement
        if follower.motion == "translating":
            centre = pos[0] * d + follower.offset * side
            a = np.linspace(0, 2 * math.pi, 91)
            ax.plot(centre[0] + follower.roller_radius * np.cos(a), centre[1] + follower.roller_radius * np.sin(a), color="tab:red", lw=1.0,
                    label="follower at cam angle 0")
    ax.plot([0], [0], "+", color="k", ms=10)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"{cam.name}: profile to scale (cam frame)")
    ax.legend(loc="upper right", fontsize=7)
    return _svg(fig)


def _curves_figure(Figure: Any, cam: Any, tool_radius: float) -> str:
    ev = cam.evaluation
    fig = Figure(figsize=(10, 3.2))
    ax1, ax2 = fig.subplots(1, 2)
    angle, pressure = ev.pressure_angle
    pa_check = next((c for c in cam.checks if c.name == "pressure_angle"), None)
    limit = float(pa_check.limit) if pa_check is not None else math.degrees(ev.follower.limit)
    keep = _thin(angle.size, 900)
    ax1.plot(np.degrees(angle)[keep], np.degrees(pressure)[keep], color="tab:blue", lw=1)
    for sign in (1, -1):
        ax1.axhline(sign * limit, color="tab:red", ls="--", lw=0.8)
    ax1.set_xlabel("cam angle (deg)")
    ax1.set_ylabel("pressure angle (deg)")
    title = "pressure angle, limit dashed"
    if ev.pressure_angle_label:
        title += f" ({ev.pressure_angle_label})"
    ax1.set_title(title, fontsize=8)
    rho_angle, rho = ev.curvature_radius
    order = np.argsort(np.mod(rho_angle, 2 * math.pi))
    size = max(abs(v) for v in cam.contour.bounds)
    clipped = np.clip(rho[order], -3 * size, 3 * size)
    keep = _thin(order.size, 1200)
    ax2.plot(np.degrees(np.mod(rho_angle[order], 2 * math.pi))[keep], clipped[keep], ".", ms=1.5, color="tab:blue")
    for sign in (1, -1):
        ax2.axhline(sign * tool_radius, color="tab:red", ls="--", lw=0.8)
    ax2.set_xlabel("cam angle (deg)")
    ax2.set_ylabel("radius of curvature (mm, < 0 concave)")
    ax2.set_title(f"radius of curvature; tool radius {tool_radius:g} mm dashed", fontsize=8)
    return _svg(fig)


def _motion_figure(Figure: Any, cam: Any) -> str:
    m = cam.evaluation.motion
    fig = Figure(figsize=(10, 4.2))
    axes = fig.subplots(2, 2).ravel()
    keep = _thin(m.cam_angle.size, 720)
    deg = np.degrees(m.cam_angle)[keep]
    for ax, values, label in zip(axes, (m.displacement[keep], m.velocity[keep], m.acceleration[keep], m.jerk[keep]),
                                 (f"displacement ({m.unit})", f"velocity ({m.unit}/rad)", f"acceleration ({m.unit}/rad^2)", f"jerk ({m.unit}/rad^3)")):
        ax.plot(deg, values, lw=1, color="tab:purple")
        ax.set_ylabel(label, fontsize=8)
    for angle in m.jerk_impulses_deg:
        axes[3].axvline(angle, color="tab:red", lw=0.6, ls=":")
    axes[2].set_xlabel("cam angle (deg)")
    axes[3].set_xlabel("cam angle (deg)" + (" (dotted: jerk impulses)" if m.jerk_impulses_deg else ""))
    fig.suptitle(f"{cam.name}: follower motion per unit cam speed", fontsize=9)
    return _svg(fig)


def _horse_leg_section(Figure: Any, report: dict[str, Any], context: dict[str, Any]) -> str:
    from camgen.mechanisms import horse_leg as hl

    leg, solutions, sweep, limit = context["leg"], context["solutions"], context["sweep"], context["limit"]
    parts = ["<h2>Horse-robot single leg (paper 000)</h2>",
             f"<p class='note'>Four-bar Grashof margin {report['grashof_margin_mm']:.4f} mm (a crank-rocker by a hair); "
             f"ground line y = {leg.ground_y:g} mm below the stride-cam centre O1.</p>"]
    fig = Figure(figsize=(10, 4.6))
    ax1, ax2 = fig.subplots(1, 2)
    for alpha, sol in solutions.items():
        w = np.vstack([sol.w, sol.w[:1]])[_thin(sol.w.shape[0], 720)]
        line, = ax1.plot(w[:, 0], w[:, 1], lw=1, label=f"alpha1 = {alpha:g} deg")
        try:
            body = hl.body_path(leg, sol)
            ax2.plot(body[:, 0], body[:, 1], "-", lw=1, color=line.get_color(), label=f"alpha1 = {alpha:g} deg")
        except Exception:  # noqa: BLE001 - a path that misses the ground has no stance
            pass
    ax1.axhline(leg.ground_y, color="k", lw=0.8, ls="--", label="ground line")
    ax1.set_aspect("equal")
    ax1.set_xlabel("x (mm)")
    ax1.set_ylabel("y (mm)")
    ax1.set_title("leg end point W relative to the body", fontsize=9)
    ax1.legend(fontsize=7)
    ax2.set_xlabel("x (mm)")
    ax2.set_ylabel("y (mm)")
    ax2.set_title("body (O1) during stance, foot on the ground at W4 (axes not to scale)", fontsize=9)
    ax2.legend(fontsize=7)
    parts.append(f"<div class='fig'>{_svg(fig)}</div>")
    fig = Figure(figsize=(10, 3.4))
    ax1, ax2 = fig.subplots(1, 2)
    for alpha, sol in solutions.items():
        keep = _thin(sol.theta1.size, 720)
        ax1.plot(np.degrees(sol.theta1)[keep], np.degrees(sol.pressure_angle)[keep], lw=1, label=f"alpha1 = {alpha:g} deg")
    ax1.axhline(math.degrees(limit), color="tab:red", ls="--", lw=0.8)
    ax1.set_xlabel("stride-cam angle theta1 (deg)")
    ax1.set_ylabel("pressure angle (deg)")
    ax1.set_title("stride-cam pressure angle (paper 000, Fig. 13)", fontsize=9)
    ax1.legend(fontsize=7)
    fig2 = Figure(figsize=(10, 4.2))
    bx1, bx2 = fig2.subplots(1, 2)
    for sol in context.get("sweep_solutions", {}).values():
        within = bool(sol.pressure_angle.max() <= limit)
        style = {"color": "tab:green" if within else "tab:red", "lw": 0.7, "alpha": 0.8}
        w = np.vstack([sol.w, sol.w[:1]])
        bx1.plot(w[:, 0], w[:, 1], **style)
        bx2.plot(np.degrees(sol.theta1), np.degrees(sol.pressure_angle), **style)
    bx1.axhline(leg.ground_y, color="k", lw=0.8, ls="--")
    bx1.set_aspect("equal")
    bx1.set_xlabel("x (mm)")
    bx1.set_ylabel("y (mm)")
    bx1.set_title("trajectory cluster over the sweep (green: within the limit)", fontsize=9)
    bx2.axhline(math.degrees(limit), color="tab:red", ls="--", lw=0.8)
    bx2.set_xlabel("stride-cam angle theta1 (deg)")
    bx2.set_ylabel("pressure angle (deg)")
    bx2.set_title("pressure angle over the sweep", fontsize=9)
    ok = [r for r in sweep if "max_pressure_angle_deg" in r]
    ax2.plot([r["alpha1_deg"] for r in ok], [r["max_pressure_angle_deg"] for r in ok], "o-", ms=3)
    ax2.axhline(math.degrees(limit), color="tab:red", ls="--", lw=0.8, label="limit")
    ax2.set_xlabel("inclination alpha1 (deg)")
    ax2.set_ylabel("max pressure angle (deg)")
    ax2.set_title("inclination sweep", fontsize=9)
    ax2.legend(fontsize=7)
    parts.append(f"<div class='fig'>{_svg(fig)}</div>")
    parts.append(f"<div class='fig'>{_svg(fig2)}</div>")
    keys = ("lift_mm", "leg_horizontal_mm", "body_height_change_mm", "body_horizontal_mm", "stride_mm", "max_pressure_angle_deg")
    head = "".join(f"<th>{k}</th>" for k in keys)
    rows = "".join(
        f"<tr><td>{html.escape(name)}</td>" + "".join(f"<td>{_fmt(v[k])}</td>" for k in keys) + "</tr>"
        for name, v in report.items() if name.startswith("alpha_")
    )
    parts.append(f"<h3>Section 6.1 figures</h3><table><tr><th>case</th>{head}</tr>{rows}</table>")
    srows = "".join(
        f"<tr><td>{_fmt(r['alpha1_deg'])}</td><td>{_fmt(r.get('max_pressure_angle_deg', '-'))}</td>"
        f"<td class='{'pass' if r['within_limit'] else 'fail'}'>{'yes' if r['within_limit'] else 'no'}</td><td>{html.escape(r.get('error', ''))}</td></tr>"
        for r in sweep
    )
    parts.append(f"<h3>Trajectory cluster</h3><table><tr><th>alpha1 (deg)</th><th>max pressure angle (deg)</th><th>within {math.degrees(limit):g} deg</th><th>note</th></tr>{srows}</table>")
    return "".join(parts)


def _tricycle_section(Figure: Any, cam: Any) -> str:
    from camgen.mechanisms import tricycle as tc

    tcam = cam.model
    traj = tcam.trajectory
    parts = [f"<h3>{html.escape(cam.name)}: ride on the cam as made</h3>"]
    ride = tc.simulate_cam(tcam)
    fig = Figure(figsize=(10, 3.4))
    ax1, ax2 = fig.subplots(1, 2)
    x = np.linspace(0, traj.period, 801)
    ax1.plot(x, traj.f(x), color="k", lw=2.5, alpha=0.4, label="target y = f(x)")
    keep = _thin(ride.x.size, 900)
    ax1.plot(ride.x[keep], ride.y[keep], color="tab:blue", lw=1, label="ride simulation")
    ax1.set_xlabel("x (mm)")
    ax1.set_ylabel("y (mm)")
    ax1.legend(fontsize=7)
    ax1.set_title("drive wheel A: target and simulated path", fontsize=9)
    ax2.plot(np.degrees(ride.theta)[keep], tc.lateral_error(traj, ride.x, ride.y)[keep] * 1e3, lw=1)
    ax2.set_xlabel("cam angle (deg)")
    ax2.set_ylabel("lateral error (um)")
    ax2.set_title("distance from the target path", fontsize=9)
    parts.append(f"<div class='fig'>{_svg(fig)}</div>")
    # error types (paper 004, Figs. 9-10)
    fig = Figure(figsize=(10, 3.4))
    ax = fig.add_subplot()
    cases = {"design": tc.ErrorModel(), "type I: +0.1 deg": tc.ErrorModel(steering_offset=math.radians(0.1)),
             "type I: -0.1 deg": tc.ErrorModel(steering_offset=math.radians(-0.1)),
             "type II: gain 1.1": tc.ErrorModel(steering_gain=1.1), "type II: gain 0.9": tc.ErrorModel(steering_gain=0.9)}
    for label, errors in cases.items():
        path = tc.simulate_cam(tcam, errors, periods=2)
        keep = _thin(path.x.size, 900)
        ax.plot(path.x[keep], path.y[keep], lw=1, label=label)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title("error types over two periods: type I skews to its side, type II larger amplitude drifts right", fontsize=9)
    ax.legend(fontsize=7, ncol=3)
    parts.append(f"<div class='fig'>{_svg(fig)}</div>")
    fits = cam.figures.get("fits", {})
    if fits:
        from camgen.mechanisms.tricycle_fit import PARAMETERS, model_y

        geom = tc.ride_geometry(tcam.profile, tcam.device.rod_radius, 4)
        fig = Figure(figsize=(10, 3.4))
        axes = fig.subplots(1, len(fits))
        axes = np.atleast_1d(axes)
        for ax, (name, fit) in zip(axes, fits.items()):
            table = tc.load_measured_table(name)
            xs = np.linspace(0, table.x.max(), 400)
            p = np.array([fit["parameters"][k] for k in PARAMETERS])
            ax.plot(table.x, table.measured, "o", ms=3, label="measured")
            ax.plot(xs, traj.f(np.mod(xs, traj.period)), color="k", alpha=0.4, lw=2, label="ideal")
            ax.plot(xs[1:], model_y(tcam, geom, p, xs[1:]), color="tab:red", lw=1, label="fitted model")
            ax.set_title(f"Table {name}: rms residual {fit['residual_rms_mm']:.2f} mm", fontsize=9)
            ax.set_xlabel("x (mm)")
            ax.legend(fontsize=7)
        axes[0].set_ylabel("y (mm)")
        parts.append(f"<div class='fig'>{_svg(fig)}</div>")
        rows = "".join(
            f"<tr><td>{html.escape(name)}</td>" + "".join(
                f"<td>{fit['parameters'][k]:.5g} &plusmn; {fit['uncertainty_1sigma'][k]:.2g}</td>" for k in PARAMETERS)
            + f"<td>{fit['residual_rms_mm']:.3g}</td><td>{html.escape(fit['advice']['note'])}</td></tr>"
            for name, fit in fits.items()
        )
        head = "".join(f"<th>{k}</th>" for k in PARAMETERS)
        parts.append(f"<table><tr><th>table</th>{head}<th>rms (mm)</th><th>advice</th></tr>{rows}</table>")
    return "".join(parts)


def report_html(scene: Any, cams: Sequence[Any], mechanisms: dict[str, Any], context: dict[str, Any], tool_radius: float) -> str:
    """The page for a run (UTF-8 text)."""
    Figure = _matplotlib()
    from camgen import __version__

    summary = "".join(
        f"<tr><td><a href='#{html.escape(c.name)}'>{html.escape(c.name)}</a></td><td>{html.escape(c.kind)}</td>"
        f"<td class='{'pass' if all(k.passed for k in c.checks) else 'fail'}'>"
        f"{sum(k.passed for k in c.checks)} / {len(c.checks)} passed</td></tr>"
        for c in cams
    )
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>camgen report: {html.escape(scene.name)}</title><style>{_CSS}</style></head><body>",
        f"<h1>camgen design-check report: {html.escape(scene.name)}</h1>",
        f"<p class='note'>camgen {__version__}; scene <code>{html.escape(scene.source)}</code>; chord tolerance "
        f"{scene.output.chord_tol:g} mm; units mm and deg.</p>",
        f"<table><tr><th>cam</th><th>kind</th><th>checks</th></tr>{summary}</table>",
    ]
    for cam in cams:
        parts.append(f"<h2 id='{html.escape(cam.name)}'>{html.escape(cam.name)} ({html.escape(cam.kind)})</h2>")
        if cam.evaluation is not None:
            parts.append(f"<div class='fig'>{_profile_figure(Figure, cam)}</div>")
            parts.append(f"<div class='fig'>{_curves_figure(Figure, cam, tool_radius)}</div>")
            parts.append(f"<div class='fig'>{_motion_figure(Figure, cam)}</div>")
        parts.append("<h3>Checks</h3>" + _checks_table(cam.checks))
        parts.append("<h3>Figures</h3>" + _figures_table(cam.figures))
        if cam.kind == "trajectory":
            parts.append(_tricycle_section(Figure, cam))
    if "horse_leg" in context:
        parts.append(_horse_leg_section(Figure, mechanisms["horse_leg"], context["horse_leg"]))
    parts.append("</body></html>\n")
    return "".join(parts)
