"""Motion ``lift_table`` with ``smoothing_mm`` > 0 (issue 26 item 3): the table's readings
smoothed within the tolerance (:class:`camgen.synthesis.smoothing.SmoothedLiftTable`), and the
figures report.json and the report's section (:mod:`camgen.report.smoothing`) show: the
largest and RMS residual, and the residual at every reading against the band."""
from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from camgen.errors import GeometryError, ParameterError
from camgen.motions.base import LawReading

__all__ = ["smoothed_table"]


def smoothed_table(where: str, table: Any, tolerance: float, oscillating: bool, figures: Mapping[str, Any]) -> LawReading:
    """The :class:`LawReading` of ``table`` (a :class:`~camgen.synthesis.lift_table.LiftTable` as
    read) smoothed within ``tolerance`` mm; errors name ``<where>.smoothing_mm``."""
    from camgen.synthesis.smoothing import SmoothedLiftTable

    key = f"{where}.smoothing_mm"
    if oscillating:
        raise ParameterError(key, tolerance, "0 for an oscillating follower",
                             "the tolerance is in mm of lift: a swing table (deg) is not smoothed")
    try:
        smoothed = SmoothedLiftTable(table, tolerance)
    except GeometryError as exc:
        raise GeometryError(f"{where}: {exc}") from None
    fit = smoothed.fit
    residuals = smoothed.residuals
    out = dict(figures)
    out["smoothing"] = {
        "smoothing_mm": tolerance,
        "method": "periodic quintic smoothing spline (least integral of the squared jerk plus squared residuals), its penalty raised "
                  "by bisection until the largest residual reaches smoothing_mm",
        "largest_residual_mm": float(np.max(np.abs(residuals))),
        "largest_residual_deg": round(math.degrees(float(table.angles[int(np.argmax(np.abs(residuals)))])), 9),
        "rms_residual_mm": float(np.sqrt(np.mean(residuals**2))),
        "bandwidth_deg": math.degrees(fit.bandwidth),
        "jerk_integral_mm2_per_rad5": fit.jerk_integral,
        "jerk_integral_interpolated_mm2_per_rad5": fit.jerk_integral_interpolated,
        "reading_deg": np.round(np.degrees(table.angles), 9).tolist(),
        "residual_mm": residuals.tolist(),
    }
    return LawReading(smoothed, out)
