"""The settings of the manufacturing drawing and its inspection table, and their ``[output]`` keys.

The drawing (``<cam>_drawing.svg``, ``<cam>_drawing.pdf``) and the inspection table
(``<cam>_inspection.csv``) read these from :class:`camgen.outputs.OutputSpec` ``.drawing``; the
scene reader builds them from the parsed ``[output]`` table (:func:`drawing_spec`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from camgen.schema import Angle, Choice, Key, Number, Text

__all__ = ["DRAWING_FORMATS", "DRAWING_SCALES", "DrawingSpec", "INSPECTION_FORMATS", "SHEETS", "drawing_keys", "drawing_spec",
           "scale_factor"]

#: The drawing scales a scene may give (ISO 5455's preferred scales): page mm per part mm is the
#: left number over the right one.
DRAWING_SCALES = ("10:1", "5:1", "2:1", "1:1", "1:2", "1:5", "1:10", "1:20")
#: Sheets (ISO 216, landscape): name -> (width, height) mm.
SHEETS = {"A4": (297.0, 210.0), "A3": (420.0, 297.0)}
#: The formats the drawing keys change (the drawing as SVG and PDF) and those the inspection keys change.
DRAWING_FORMATS = ("drawing", "drawing_pdf")
INSPECTION_FORMATS = DRAWING_FORMATS + ("inspection",)


def scale_factor(scale: str) -> float:
    """Page mm per part mm of a scale ``"a:b"`` (``"1:2"`` -> 0.5)."""
    page, part = scale.split(":")
    return float(page) / float(part)


@dataclass(frozen=True)
class DrawingSpec:
    """The drawing's scale (``"1:1"``, :data:`DRAWING_SCALES`) and sheet (``"auto"``: A4 landscape if
    the drawing fits it, else A3), the inspection table's cam-angle step (rad) and checking-roller
    radius (mm; None: the follower's roller radius, 0 for other followers: a probe point), and the
    title block's material and profile tolerance (+/- mm)."""

    scale: str = "1:1"
    sheet: str = "auto"
    inspection_step: float = math.radians(10.0)
    inspection_roller_radius: float | None = None
    material: str = "not stated"
    tolerance: float = 0.02


def drawing_keys() -> tuple[Key, ...]:
    """The ``[output]`` keys of the drawing and the inspection table (defaults owned by :class:`DrawingSpec`)."""
    d = DrawingSpec()
    return (
        Key("drawing_scale", Choice(DRAWING_SCALES), "Scale of the manufacturing drawing (<cam>_drawing.svg and .pdf), page mm to "
            "part mm; a cam that does not fit the sheet at it is refused naming the largest scale that fits.", ("drawing",),
            default=d.scale, example="1:2"),
        Key("drawing_sheet", Choice(("auto",) + tuple(SHEETS)), "Sheet of the drawing, landscape: A4 (297 x 210 mm), A3 "
            "(420 x 297 mm), or auto: A4 where the drawing fits it, else A3.", ("drawing",), default=d.sheet, example="A3"),
        Key("inspection_step_deg", Angle(2.0, 45.0), "Cam-angle step of the inspection table (<cam>_inspection.csv and the "
            "drawing's table): the whole turn in equal steps, the nearest that divides 360 deg (a linear cam: its travel in as "
            "many equal steps).", ("drawing",),
            default=math.degrees(d.inspection_step), example=5.0),
        Key("inspection_roller_radius_mm", Number("mm", 0.0, 1000.0), "Radius of the checking roller of the inspection table, "
            "moving along the ray through the axis and the zero mark: the table gives its centre's distance from the axis "
            "(default: the follower's roller radius, 0 for other followers: a probe point, the profile's own radius; a groove cam and "
            "a barrel cam: only the roller widened by half the clearance, a plug resting on both walls or, a barrel's rib, a fork "
            "of two rollers straddling it, whose axis' height along the cam axis the table gives).",
            ("drawing",), example=5.0),
        Key("drawing_material", Text(40), "Material of the cam, printed in the drawing's title block.", ("drawing",),
            default=d.material, example="C45E, hardened 55 HRC"),
        Key("drawing_tolerance_mm", Number("mm", 0.0, 10.0, low_open=True), "Profile tolerance (+/- mm) printed in the drawing's "
            "title block and beside its inspection table.", ("drawing",), default=d.tolerance, example=0.05),
    )


def drawing_spec(parsed: Mapping[str, Any]) -> DrawingSpec:
    """The :class:`DrawingSpec` of a parsed ``[output]`` table (its keys' fields)."""
    return DrawingSpec(parsed["drawing_scale"], parsed["drawing_sheet"], parsed["inspection_step"],
                       parsed.get("inspection_roller_radius"), parsed["drawing_material"], parsed["drawing_tolerance"])
