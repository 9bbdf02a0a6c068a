"""Report sections of the kinds and mechanism jobs that have their own: each draws only the
data its stage computed (:class:`TricycleSection`, :class:`HorseLegSection`, made by the
``plots`` stage of the ``trajectory`` kind and the ``horse_leg`` job) and the figures of
report.json (no simulation here)."""
from __future__ import annotations

import html
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camgen.report.format import FigureMaker, fmt, thin
from camgen.report.model import FloatArray, SectionData, json_number, json_object, json_objects

if TYPE_CHECKING:
    from camgen.report.model import CamReport, MechanismReport

__all__ = ["FitCurves", "HorseLegSection", "LegPath", "TricycleSection", "horse_leg_section", "tricycle_section"]


@dataclass(frozen=True)
class LegPath:
    """The horse leg at one swing-rod inclination ``alpha_deg``: the leg end point W relative to
    the body (n, 2) mm, the stride-cam angles theta1 and its pressure angle (rad), and the body's
    path during stance (n, 2) mm (None: the path misses the ground, or not drawn)."""

    alpha_deg: float
    w: FloatArray
    theta1: FloatArray
    pressure_angle: FloatArray
    body: FloatArray | None = None


@dataclass(frozen=True)
class HorseLegSection(SectionData):
    """What the horse leg's section draws (paper 000): the ground line (mm), the pressure-angle
    limit (rad), the leg at each inclination of the scene and over the sweep (the sweep's own
    table and the Section 6.1 figures are report.json's)."""

    ground_y: float
    limit: float
    legs: tuple[LegPath, ...]
    sweep: tuple[LegPath, ...] = ()


@dataclass(frozen=True)
class FitCurves:
    """One measured table (paper 004, Appendix A) against the fitted error model: the table's x,
    measured y and the ideal and model paths at ``xs`` (the model from ``xs[1:]``), mm; the fit's
    parameters in order as (name, value, 1-sigma), its rms residual (mm) and advice."""

    name: str
    x: FloatArray
    measured: FloatArray
    xs: FloatArray
    ideal: FloatArray
    model: FloatArray
    parameters: tuple[tuple[str, float, float], ...]
    residual_rms_mm: float
    advice: str


@dataclass(frozen=True)
class TricycleSection(SectionData):
    """What a trajectory cam's section draws (paper 004), mm and rad: the target path y = f(x)
    over one period, the ride on the cam as made (cam angle, x, y, lateral error), the rides
    with the error types (label, x, y) and the fitted tables."""

    target_x: FloatArray
    target_y: FloatArray
    ride_theta: FloatArray
    ride_x: FloatArray
    ride_y: FloatArray
    ride_error: FloatArray
    error_rides: tuple[tuple[str, FloatArray, FloatArray], ...]
    fits: tuple[FitCurves, ...] = ()


def horse_leg_section(Figure: FigureMaker, mechanism: "MechanismReport") -> str:
    """The horse leg's part of report.html (paper 000): paths, pressure angles, the sweep."""
    data = mechanism.section
    assert isinstance(data, HorseLegSection)
    report, limit = mechanism.figures, data.limit
    parts = ["<h2>Horse-robot single leg (paper 000)</h2>",
             f"<p class='note'>Four-bar Grashof margin {json_number(report['grashof_margin_mm']):.4f} mm (a crank-rocker by a hair); "
             f"ground line y = {data.ground_y:g} mm below the stride-cam centre O1.</p>"]
    fig = Figure(figsize=(10, 4.6))
    ax1, ax2 = fig.subplots(1, 2)
    for leg in data.legs:
        w = np.vstack([leg.w, leg.w[:1]])[thin(leg.w.shape[0], 720)]
        line = ax1.plot(w[:, 0], w[:, 1], width=1, label=f"alpha1 = {leg.alpha_deg:g} deg")
        if leg.body is not None:  # a path that misses the ground has no stance
            ax2.plot(leg.body[:, 0], leg.body[:, 1], "-", width=1, color=line.get_color(), label=f"alpha1 = {leg.alpha_deg:g} deg")
    ax1.hline(data.ground_y, color="k", width=0.8, dash="--", label="ground line")
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
    for leg in data.legs:
        keep = thin(leg.theta1.size, 720)
        ax1.plot(np.degrees(leg.theta1)[keep], np.degrees(leg.pressure_angle)[keep], width=1, label=f"alpha1 = {leg.alpha_deg:g} deg")
    ax1.hline(math.degrees(limit), color="tab:red", dash="--", width=0.8)
    ax1.xlabel("stride-cam angle theta1 (deg)")
    ax1.ylabel("pressure angle (deg)")
    ax1.title("stride-cam pressure angle (paper 000, Fig. 13)", font_size=9)
    ax1.legend(font_size=7)
    fig2 = Figure(figsize=(10, 4.2))
    bx1, bx2 = fig2.subplots(1, 2)
    for leg in data.sweep:
        within = bool(leg.pressure_angle.max() <= limit)
        colour = "tab:green" if within else "tab:red"
        w = np.vstack([leg.w, leg.w[:1]])
        bx1.plot(w[:, 0], w[:, 1], color=colour, width=0.7, alpha=0.8)
        bx2.plot(np.degrees(leg.theta1), np.degrees(leg.pressure_angle), color=colour, width=0.7, alpha=0.8)
    bx1.hline(data.ground_y, color="k", width=0.8, dash="--")
    bx1.equal_aspect()
    bx1.xlabel("x (mm)")
    bx1.ylabel("y (mm)")
    bx1.title("trajectory cluster over the sweep (green: within the limit)", font_size=9)
    bx2.hline(math.degrees(limit), color="tab:red", dash="--", width=0.8)
    bx2.xlabel("stride-cam angle theta1 (deg)")
    bx2.ylabel("pressure angle (deg)")
    bx2.title("pressure angle over the sweep", font_size=9)
    sweep = json_objects(report.get("sweep"))
    ok = [r for r in sweep if "max_pressure_angle_deg" in r]
    ax2.plot([json_number(r["alpha1_deg"]) for r in ok], [json_number(r["max_pressure_angle_deg"]) for r in ok], "o-", marker_size=3)
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
        f"<tr><td>{html.escape(name)}</td>" + "".join(f"<td>{fmt(json_object(v)[k])}</td>" for k in keys) + "</tr>"
        for name, v in report.items() if name.startswith("alpha_")
    )
    parts.append(f"<h3>Section 6.1 figures</h3><table><tr><th>case</th>{head}</tr>{rows}</table>")
    srows = "".join(
        f"<tr><td>{fmt(r['alpha1_deg'])}</td><td>{fmt(r.get('max_pressure_angle_deg', '-'))}</td>"
        f"<td class='{'pass' if r['within_limit'] else 'fail'}'>{'yes' if r['within_limit'] else 'no'}</td>"
        f"<td>{html.escape(str(r.get('error', '')))}</td></tr>"
        for r in sweep
    )
    parts.append(f"<h3>Trajectory cluster</h3><table><tr><th>alpha1 (deg)</th><th>max pressure angle (deg)</th><th>within {math.degrees(limit):g} deg</th><th>note</th></tr>{srows}</table>")
    return "".join(parts)


def tricycle_section(Figure: FigureMaker, cam: "CamReport") -> str:
    """A trajectory cam's part of report.html (paper 004): the ride on the cam as made, the
    error types, the measured tables against the fitted model."""
    data = cam.section
    if not isinstance(data, TricycleSection):  # undercut: no cam was made, so there is nothing to ride
        return (f"<h3>{html.escape(cam.name)}: ride on the cam as made</h3><p class='note'>No ride: the steering rod cannot "
                "follow this cam (see the undercut check), so no profile was made and no ride, error type or fit is shown. "
                "The profile plot above shows the rod-centre path the cam would need.</p>")
    parts = [f"<h3>{html.escape(cam.name)}: ride on the cam as made</h3>"]
    fig = Figure(figsize=(10, 3.4))
    ax1, ax2 = fig.subplots(1, 2)
    ax1.plot(data.target_x, data.target_y, color="k", width=2.5, alpha=0.4, label="target y = f(x)")
    keep = thin(data.ride_x.size, 900)
    ax1.plot(data.ride_x[keep], data.ride_y[keep], color="tab:blue", width=1, label="ride simulation")
    ax1.xlabel("x (mm)")
    ax1.ylabel("y (mm)")
    ax1.legend(font_size=7)
    ax1.title("drive wheel A: target and simulated path", font_size=9)
    ax2.plot(np.degrees(data.ride_theta)[keep], data.ride_error[keep] * 1e3, width=1)
    ax2.xlabel("cam angle (deg)")
    ax2.ylabel("lateral error (um)")
    ax2.title("distance from the target path", font_size=9)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    # error types (paper 004, Figs. 9-10)
    fig = Figure(figsize=(10, 3.4))
    ax = fig.add_subplot()
    for label, x, y in data.error_rides:
        keep = thin(x.size, 900)
        ax.plot(x[keep], y[keep], width=1, label=label)
    ax.xlabel("x (mm)")
    ax.ylabel("y (mm)")
    ax.title("error types over two periods: type I skews to its side, type II larger amplitude drifts right", font_size=9)
    ax.legend(font_size=7, ncol=3)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    if data.fits:
        fig = Figure(figsize=(10, 3.4))
        axes = np.atleast_1d(fig.subplots(1, len(data.fits)))
        for ax, fit in zip(axes, data.fits):
            ax.plot(fit.x, fit.measured, "o", marker_size=3, label="measured")
            ax.plot(fit.xs, fit.ideal, color="k", alpha=0.4, width=2, label="ideal")
            ax.plot(fit.xs[1:], fit.model, color="tab:red", width=1, label="fitted model")
            ax.title(f"Table {fit.name}: rms residual {fit.residual_rms_mm:.2f} mm", font_size=9)
            ax.xlabel("x (mm)")
            ax.legend(font_size=7)
        axes[0].ylabel("y (mm)")
        parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
        rows = "".join(
            f"<tr><td>{html.escape(fit.name)}</td>" + "".join(f"<td>{value:.5g} &plusmn; {sigma:.2g}</td>" for _, value, sigma in fit.parameters)
            + f"<td>{fit.residual_rms_mm:.3g}</td><td>{html.escape(fit.advice)}</td></tr>"
            for fit in data.fits
        )
        head = "".join(f"<th>{name}</th>" for name, _, _ in data.fits[0].parameters)
        parts.append(f"<table><tr><th>table</th>{head}<th>rms (mm)</th><th>advice</th></tr>{rows}</table>")
    return "".join(parts)
