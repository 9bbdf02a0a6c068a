"""The inspection table of a plate cam: the checking roller's centre distance per cam-angle step.

How the cam is checked: it turns on its axis from its zero mark in its sense of rotation; a
checking roller of radius ``r`` (0: a probe point) moves along the fixed ray from the axis through
the zero mark (:class:`camgen.kinds.base.ZeroMark`: where the follower touches at cam angle 0)
and rests on the profile; the table gives the distance of its centre from the axis.  On the cam
that ray lies at polar angle ``phi0 - sigma * theta`` at cam angle ``theta`` (``phi0`` the zero
mark's polar angle, ``sigma`` +1 counter-clockwise), and the roller's centre lies on the profile
offset by ``r`` (the centres of every roller of radius ``r`` touching it from outside): the table
is that curve's polar radius.  A roller of the follower's own radius rests on its pitch curve,
which the synthesis made within ``fit_tol_mm`` of the exact one, so that curve is used as it is;
another radius offsets the profile (:meth:`camgen.contour.Contour.offset`, splines refitted within
:data:`OFFSET_TOL`).  For an in-line translating follower whose law starts at rest, the table is
the follower's own lift plus the prime radius.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.export.tables import csv_table

if TYPE_CHECKING:
    from camgen.contour import Contour
    from camgen.kinds.base import ZeroMark

__all__ = ["INSPECTION_COLUMNS", "OFFSET_TOL", "InspectionTable", "inspection_angles", "inspection_csv", "inspection_metadata",
           "inspection_table"]

#: Largest distance (mm) of the refitted spline pieces of the profile offset by the checking
#: roller's radius from the exact offset (:meth:`camgen.contour.Contour.offset`'s ``spline_tol``).
OFFSET_TOL = 1e-8

#: Columns of ``<cam>_inspection.csv`` and what they hold.
INSPECTION_COLUMNS = {
    "cam_angle_deg": "cam angle: the cam turned from its zero mark in its sense of rotation, deg",
    "polar_angle_deg": "polar angle on the cam (cam frame, counter-clockwise from +x) of the ray the checking roller moves on at "
                       "that cam angle, deg",
    "centre_radius_mm": "distance from the rotation axis to the checking roller's centre resting on the profile, mm",
    "lift_mm": "centre_radius_mm minus (base_radius_mm + roller_radius_mm): the rise above the base circle, mm",
}


@dataclass(frozen=True)
class InspectionTable:
    """Cam angles and polar angles (rad), the checking roller's centre distance and lift (mm) per
    row; its radius, the profile's base radius (mm) and the curve's stated tolerance (mm)."""

    cam_angle: np.ndarray
    polar_angle: np.ndarray
    centre_radius: np.ndarray
    lift: np.ndarray
    roller_radius: float
    base_radius: float
    tolerance: float


def inspection_angles(step: float) -> np.ndarray:
    """Cam angles (rad) of the table: the whole turn in equal steps, the nearest to ``step`` rad that divides it."""
    count = int(round(2.0 * math.pi / step))
    return 2.0 * math.pi * np.arange(count) / count


def inspection_table(profile: "Contour", zero: "ZeroMark", step: float, roller_radius: float, pitch: "Contour | None" = None,
                     follower_radius: float = 0.0, fit_tol: float = 0.0) -> InspectionTable:
    """The inspection table of ``profile`` (see the module).

    ``pitch``: the follower's pitch curve, used when ``roller_radius`` equals ``follower_radius``
    (the roller's centres are then exactly it); ``fit_tol``: how far (mm) the profile and pitch
    curves may be from the exact ones (stated in the table's tolerance).  Raises
    :class:`camgen.errors.GeometryError` when the offset profile has no polar radius (a concave
    radius smaller than the roller's; a ray that meets it more than once).
    """
    from camgen.export.points import base_radius

    theta = inspection_angles(step)
    phi0 = math.atan2(zero.point[1], zero.point[0])
    phi = np.mod(phi0 - zero.sigma * theta, 2.0 * math.pi)
    if roller_radius == 0.0:
        centres, tol = profile, fit_tol
    elif pitch is not None and roller_radius == follower_radius:
        centres, tol = pitch, fit_tol
    else:
        centres, tol = profile.offset(roller_radius, spline_tol=OFFSET_TOL), fit_tol + OFFSET_TOL
    radius = centres.polar_radius(phi)
    base = base_radius(profile)
    return InspectionTable(theta, phi, radius, radius - (base + roller_radius), float(roller_radius), base, float(tol))


def inspection_csv(table: InspectionTable) -> str:
    """CSV text of ``table`` (:data:`INSPECTION_COLUMNS`)."""
    values = (np.degrees(table.cam_angle), np.degrees(table.polar_angle), table.centre_radius, table.lift)
    return csv_table(dict(zip(INSPECTION_COLUMNS, values)))


def inspection_metadata(table: InspectionTable, zero: "ZeroMark") -> dict[str, Any]:
    """What :func:`inspection_csv` holds (report.json ``tables``): the checking roller, the ray it
    moves on, the step, base radius and tolerance."""
    count = table.cam_angle.size
    return {
        "content": "inspection table: the cam turned from its zero mark in its sense of rotation; a checking roller moving along "
                   "the fixed ray from the axis through the zero mark rests on the profile; its centre's distance from the axis",
        "columns": dict(INSPECTION_COLUMNS),
        "angle_step_deg": 360.0 / count,
        "roller_radius_mm": table.roller_radius,
        "base_radius_mm": table.base_radius,
        "zero_mark_polar_angle_deg": math.degrees(math.atan2(zero.point[1], zero.point[0])) % 360.0,
        "rotation": "ccw" if zero.sigma > 0 else "cw",
        "radius_tol_mm": table.tolerance,
    }
