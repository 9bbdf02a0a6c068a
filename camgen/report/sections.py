"""Report sections of the kinds and mechanism jobs that have their own: each draws only the
data its stage computed (no simulation here)."""
from __future__ import annotations

import html
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.report.html import _fmt, _thin

if TYPE_CHECKING:
    from camgen.jobs.horse_leg import HorseLegPlots
    from camgen.kinds.trajectory import TrajectoryCam

def horse_leg_section(Figure: Any, report: dict[str, Any], plots: "HorseLegPlots") -> str:
    """The horse leg's part of report.html (paper 000): paths, pressure angles, the sweep."""
    leg, solutions, sweep, limit = plots.leg, plots.solutions, plots.sweep, plots.limit
    parts = ["<h2>Horse-robot single leg (paper 000)</h2>",
             f"<p class='note'>Four-bar Grashof margin {report['grashof_margin_mm']:.4f} mm (a crank-rocker by a hair); "
             f"ground line y = {leg.ground_y:g} mm below the stride-cam centre O1.</p>"]
    fig = Figure(figsize=(10, 4.6))
    ax1, ax2 = fig.subplots(1, 2)
    for alpha, sol in solutions.items():
        w = np.vstack([sol.w, sol.w[:1]])[_thin(sol.w.shape[0], 720)]
        line = ax1.plot(w[:, 0], w[:, 1], width=1, label=f"alpha1 = {alpha:g} deg")
        body = plots.body_paths.get(alpha)
        if body is not None:  # a path that misses the ground has no stance
            ax2.plot(body[:, 0], body[:, 1], "-", width=1, color=line.get_color(), label=f"alpha1 = {alpha:g} deg")
    ax1.hline(leg.ground_y, color="k", width=0.8, dash="--", label="ground line")
    ax1.equal_aspect()
    ax1.xlabel("x (mm)")
    ax1.ylabel("y (mm)")
    ax1.title("leg end point W relative to the body", font_size=9)
    ax1.legend(font_size=7)
    ax2.xlabel("x (mm)")
    ax2.ylabel("y (mm)")
    ax2.title("body (O1) during stance, foot on the ground at W4 (axes not to scale)", font_size=9)
    ax2.legend(font_size=7)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    fig = Figure(figsize=(10, 3.4))
    ax1, ax2 = fig.subplots(1, 2)
    for alpha, sol in solutions.items():
        keep = _thin(sol.theta1.size, 720)
        ax1.plot(np.degrees(sol.theta1)[keep], np.degrees(sol.pressure_angle)[keep], width=1, label=f"alpha1 = {alpha:g} deg")
    ax1.hline(math.degrees(limit), color="tab:red", dash="--", width=0.8)
    ax1.xlabel("stride-cam angle theta1 (deg)")
    ax1.ylabel("pressure angle (deg)")
    ax1.title("stride-cam pressure angle (paper 000, Fig. 13)", font_size=9)
    ax1.legend(font_size=7)
    fig2 = Figure(figsize=(10, 4.2))
    bx1, bx2 = fig2.subplots(1, 2)
    for sol in plots.sweep_solutions.values():
        within = bool(sol.pressure_angle.max() <= limit)
        style = {"color": "tab:green" if within else "tab:red", "width": 0.7, "alpha": 0.8}
        w = np.vstack([sol.w, sol.w[:1]])
        bx1.plot(w[:, 0], w[:, 1], **style)
        bx2.plot(np.degrees(sol.theta1), np.degrees(sol.pressure_angle), **style)
    bx1.hline(leg.ground_y, color="k", width=0.8, dash="--")
    bx1.equal_aspect()
    bx1.xlabel("x (mm)")
    bx1.ylabel("y (mm)")
    bx1.title("trajectory cluster over the sweep (green: within the limit)", font_size=9)
    bx2.hline(math.degrees(limit), color="tab:red", dash="--", width=0.8)
    bx2.xlabel("stride-cam angle theta1 (deg)")
    bx2.ylabel("pressure angle (deg)")
    bx2.title("pressure angle over the sweep", font_size=9)
    ok = [r for r in sweep if "max_pressure_angle_deg" in r]
    ax2.plot([r["alpha1_deg"] for r in ok], [r["max_pressure_angle_deg"] for r in ok], "o-", marker_size=3)
    ax2.hline(math.degrees(limit), color="tab:red", dash="--", width=0.8, label="limit")
    ax2.xlabel("inclination alpha1 (deg)")
    ax2.ylabel("max pressure angle (deg)")
    ax2.title("inclination sweep", font_size=9)
    ax2.legend(font_size=7)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    parts.append(f"<div class='fig'>{fig2.to_svg()}</div>")
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


def tricycle_section(Figure: Any, cam: "TrajectoryCam") -> str:
    """A trajectory cam's part of report.html (paper 004): the ride on the cam as made, the
    error types, the measured tables against the fitted model."""
    from camgen.mechanisms import tricycle as tc

    built = cam.built  # a TrajectoryCam
    if built.tricycle is None or built.plots is None:  # undercut: no cam was made, so there is nothing to ride
        return (f"<h3>{html.escape(cam.name)}: ride on the cam as made</h3><p class='note'>No ride: the steering rod cannot "
                "follow this cam (see the undercut check), so no profile was made and no ride, error type or fit is shown. "
                "The profile plot above shows the rod-centre path the cam would need.</p>")
    traj = built.tricycle.trajectory
    plots = built.plots
    parts = [f"<h3>{html.escape(cam.name)}: ride on the cam as made</h3>"]
    ride = plots.ride
    fig = Figure(figsize=(10, 3.4))
    ax1, ax2 = fig.subplots(1, 2)
    x = np.linspace(0, traj.period, 801)
    ax1.plot(x, traj.f(x), color="k", width=2.5, alpha=0.4, label="target y = f(x)")
    keep = _thin(ride.x.size, 900)
    ax1.plot(ride.x[keep], ride.y[keep], color="tab:blue", width=1, label="ride simulation")
    ax1.xlabel("x (mm)")
    ax1.ylabel("y (mm)")
    ax1.legend(font_size=7)
    ax1.title("drive wheel A: target and simulated path", font_size=9)
    ax2.plot(np.degrees(ride.theta)[keep], tc.lateral_error(traj, ride.x, ride.y)[keep] * 1e3, width=1)
    ax2.xlabel("cam angle (deg)")
    ax2.ylabel("lateral error (um)")
    ax2.title("distance from the target path", font_size=9)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    # error types (paper 004, Figs. 9-10)
    fig = Figure(figsize=(10, 3.4))
    ax = fig.add_subplot()
    for label, path in plots.error_rides.items():
        keep = _thin(path.x.size, 900)
        ax.plot(path.x[keep], path.y[keep], width=1, label=label)
    ax.xlabel("x (mm)")
    ax.ylabel("y (mm)")
    ax.title("error types over two periods: type I skews to its side, type II larger amplitude drifts right", font_size=9)
    ax.legend(font_size=7, ncol=3)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    fits = cam.figures.get("fits", {})
    if fits:
        from camgen.mechanisms.tricycle_fit import PARAMETERS

        fig = Figure(figsize=(10, 3.4))
        axes = fig.subplots(1, len(fits))
        axes = np.atleast_1d(axes)
        for ax, (name, fit) in zip(axes, fits.items()):
            curve = plots.fits[name]
            xs = curve["xs"]
            ax.plot(curve["x"], curve["measured"], "o", marker_size=3, label="measured")
            ax.plot(xs, curve["ideal"], color="k", alpha=0.4, width=2, label="ideal")
            ax.plot(xs[1:], curve["model"], color="tab:red", width=1, label="fitted model")
            ax.title(f"Table {name}: rms residual {fit['residual_rms_mm']:.2f} mm", font_size=9)
            ax.xlabel("x (mm)")
            ax.legend(font_size=7)
        axes[0].ylabel("y (mm)")
        parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
        rows = "".join(
            f"<tr><td>{html.escape(name)}</td>" + "".join(
                f"<td>{fit['parameters'][k]:.5g} &plusmn; {fit['uncertainty_1sigma'][k]:.2g}</td>" for k in PARAMETERS)
            + f"<td>{fit['residual_rms_mm']:.3g}</td><td>{html.escape(fit['advice']['note'])}</td></tr>"
            for name, fit in fits.items()
        )
        head = "".join(f"<th>{k}</th>" for k in PARAMETERS)
        parts.append(f"<table><tr><th>table</th>{head}<th>rms (mm)</th><th>advice</th></tr>{rows}</table>")
    return "".join(parts)
