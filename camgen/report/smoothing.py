"""The smoothing part of report.html (a lift table with ``smoothing_mm`` > 0, issue 26 item 3):
the residual at every reading against the band of +-smoothing_mm, and the fit's numbers (from
report.json's ``figures.smoothing``)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from camgen.report.format import FigureMaker, number
from camgen.report.model import json_number, json_numbers, json_object

if TYPE_CHECKING:
    from camgen.report.model import CamReport

__all__ = ["smoothing_section"]


def smoothing_section(Figure: FigureMaker, cam: "CamReport") -> str:
    """The residuals of a smoothed lift table ("" when the table is not smoothed)."""
    if "smoothing" not in cam.figures:
        return ""
    fit = json_object(cam.figures["smoothing"])
    band = json_number(fit["smoothing_mm"])
    deg = np.asarray(json_numbers(fit["reading_deg"]), dtype=float)
    residual = np.asarray(json_numbers(fit["residual_mm"]), dtype=float)
    fig = Figure(figsize=(10, 3.0))
    ax = fig.add_subplot()
    ax.plot(deg, residual * 1e3, width=0.8, label="reading - smoothed lift")
    ax.hline(band * 1e3, color="tab:red", dash="--", width=0.8, label=f"+-smoothing_mm = {band:g} mm")
    ax.hline(-band * 1e3, color="tab:red", dash="--", width=0.8)
    ax.xlabel("cam angle (deg)")
    ax.ylabel("residual (um)")
    ax.title("lift table smoothing: residual at every reading", font_size=9)
    ax.legend(font_size=7)
    rows = "".join(f"<tr><td>{what}</td><td class='num'>{value}</td><td>{unit}</td></tr>" for what, value, unit in (
        ("tolerance (smoothing_mm)", number(band), "mm"),
        ("largest |residual|", number(json_number(fit["largest_residual_mm"])), "mm"),
        ("at cam angle", number(json_number(fit["largest_residual_deg"])), "deg"),
        ("RMS residual", number(json_number(fit["rms_residual_mm"])), "mm"),
        ("readings", str(deg.size), ""),
        ("penalty bandwidth", number(json_number(fit["bandwidth_deg"])), "deg"),
        ("integral of squared jerk: smoothed / interpolated", f"{number(json_number(fit['jerk_integral_mm2_per_rad5']))} / "
         f"{number(json_number(fit['jerk_integral_interpolated_mm2_per_rad5']))}", "mm²/rad⁵"),
    ))
    return ("<h3>Lift table smoothing</h3><p class='note'>The smoothest periodic quintic spline (least integral of the squared "
            "jerk) within smoothing_mm of every reading: a penalised smoothing spline whose penalty is raised by bisection until "
            "the largest residual reaches the tolerance, verified at every reading. The undercut, contact-stress and jump checks "
            "say what the raw readings' interpolation would give.</p>"
            f"<table><tbody>{rows}</tbody></table><div class='fig'>{fig.to_svg()}</div>")
