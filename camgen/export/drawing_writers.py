"""Writers of the drawing (``drawing``: SVG, ``drawing_pdf``: PDF) and the inspection table
(``inspection``: CSV) of a plate cam, registered in :mod:`camgen.outputs`.

A plate cam is one whose body is its profile extruded and that knows its zero mark and sense of
rotation: the plate, conjugate (each cam of the pair its own drawing) and constant-breadth forms,
and the groove cam, whose groove (one pocket of two walls about its pitch curve) the drawing shows
and whose inspection table is read by a checking roller of the groove's width resting on both
walls (its centre on the pitch curve); a cam with other pockets is refused naming
``output.formats``.  A linear cam's drawing and table are its form's writers
(:mod:`camgen.export.drawing_linear`), a barrel cam's (groove or rib) its form's too (:mod:`camgen.export.barrel_sheet`).  The drawing
that does not fit its sheet at its scale is refused naming ``output.drawing_scale`` (and the
largest scale that fits) or ``output.drawing_sheet``.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping

from camgen.errors import ParameterError

if TYPE_CHECKING:
    from camgen.export.drawing import DrawingInput, Sheet
    from camgen.export.drawing_forms import FormFeatures
    from camgen.export.drawing_spec import DrawingSpec
    from camgen.export.inspection import InspectionTable
    from camgen.kinds.base import Pocket, ZeroMark
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["drawing_pdf", "drawing_svg", "inspection", "inspection_description", "plate_inspection"]


def _groove(cam: "CamResult") -> "Pocket | None":
    """The groove of a groove cam: its one pocket, of two walls about a pitch curve; else None."""
    if len(cam.pockets) == 1 and len(cam.pockets[0].walls) == 2 and cam.pockets[0].centre is not None and cam.pockets[0].width:
        return cam.pockets[0]
    return None


def _zero(cam: "CamResult", fmt: str) -> "ZeroMark":
    """The cam's zero mark, or the refusal of ``fmt`` for a cam that is not a plate cam turning about its axis."""
    pocketed = bool(cam.pockets) and _groove(cam) is None
    if pocketed or cam.contour is None or cam.zero_mark is None:
        why = ("its body has pockets other than a groove" if pocketed else "it has no cam angle 0 (zero mark) and sense of rotation")
        raise ParameterError("output.formats", fmt, f"formats without {fmt} for cam '{cam.name}'",
                             f"the drawing and inspection table are of disk cams (plate, groove, conjugate, constant breadth), and {why}")
    return cam.zero_mark


def _follower_radius(cam: "CamResult") -> float:
    """The radius of the cam's follower roller (mm; 0 for other followers): the generic follower
    model's, else the one the cam's figures report (disk cams)."""
    if cam.follower is not None:
        return float(cam.follower.roller_radius) if cam.follower.kind == "roller" else 0.0
    figures = cam.figures.get("follower")
    radius = figures.get("roller_radius_mm") if isinstance(figures, Mapping) and figures.get("kind") == "roller" else None
    return float(radius) if isinstance(radius, (int, float)) else 0.0


def _roller_radius(cam: "CamResult", spec: "DrawingSpec") -> float:
    """The checking roller's radius: the scene's, else the follower's roller (0: a probe point)."""
    return spec.inspection_roller_radius if spec.inspection_roller_radius is not None else _follower_radius(cam)


def plate_inspection(cam: "CamResult", spec: "DrawingSpec", fmt: str) -> "InspectionTable":
    """The inspection table of ``cam`` (:func:`camgen.export.inspection.inspection_table`); a roller
    too large for its concave parts is refused naming ``output.inspection_roller_radius_mm``."""
    from camgen.errors import GeometryError
    from camgen.export.inspection import inspection_table

    zero = _zero(cam, fmt)
    assert cam.contour is not None
    radius = _roller_radius(cam, spec)
    follower_radius = _follower_radius(cam)
    fit = cam.figures.get("fit_tol_mm")
    profile, pitch = cam.contour, cam.pitch
    groove = _groove(cam)
    if groove is not None:  # a plug of the groove's width touches both walls: its centre on the pitch curve
        assert groove.width is not None
        half = 0.5 * groove.width
        if spec.inspection_roller_radius is not None and spec.inspection_roller_radius != half:
            raise ParameterError("output.inspection_roller_radius_mm", spec.inspection_roller_radius,
                                 f"{half:g} (half the groove's width) for groove cam '{cam.name}', or left out",
                                 "a checking roller in a groove rests on both walls only at the groove's width")
        profile, pitch, radius, follower_radius = groove.walls[1].contour, groove.centre, half, half
    try:
        return inspection_table(profile, zero, spec.inspection_step, radius, pitch, follower_radius,
                                float(fit) if isinstance(fit, (int, float)) else 0.0)
    except GeometryError as exc:
        raise ParameterError("output.inspection_roller_radius_mm", radius, f"0 (a probe point) for cam '{cam.name}'",
                             f"a checking roller of this radius cannot rest on every part of the profile ({exc})") from None


def inspection(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """``<cam>_inspection.csv``."""
    from camgen.export.inspection import inspection_csv

    return inspection_csv(plate_inspection(cam, run.output.drawing, fmt))


def inspection_description(cam: "CamResult", spec: "DrawingSpec") -> dict[str, Any]:
    """What ``<cam>_inspection.csv`` holds (report.json ``tables``)."""
    from camgen.export.inspection import inspection_metadata

    from camgen.kinds.linear import LinearCam

    if isinstance(cam.built, LinearCam):  # a linear cam's table: lift against x (camgen.export.drawing_linear)
        from camgen.export.drawing_linear import linear_inspection_metadata

        return linear_inspection_metadata(cam, spec)
    if getattr(cam.built, "groove", None) is not None:  # a barrel cam's table: the groove's axial position (camgen.export.barrel_sheet)
        from camgen.export.barrel_sheet import barrel_inspection_metadata

        return barrel_inspection_metadata(cam, spec)
    table = plate_inspection(cam, spec, "inspection")
    assert cam.zero_mark is not None
    return inspection_metadata(table, cam.zero_mark)


def _drawing_input(cam: "CamResult", run: "RunSettings", fmt: str) -> "DrawingInput":
    import numpy as np

    from camgen.export.drawing import DrawingInput

    table = plate_inspection(cam, run.output.drawing, fmt)
    zero = _zero(cam, fmt)
    assert cam.contour is not None
    profile = cam.contour.flatten(run.output.chord_tol)
    body = cam.body
    keyway = body.keyway_outside_bore() if body.keyway_width > 0 else None
    return DrawingInput(cam.name, run.scene_name, profile, run.output.chord_tol, table.base_radius,
                        float(np.max(np.hypot(profile[:, 0], profile[:, 1]))) + run.output.chord_tol, body.bore_diameter, keyway,
                        body.keyway_width, body.keyway_reach, zero.point, zero.sigma, body.thickness, table,
                        _features(cam, run.output.chord_tol))


def _features(cam: "CamResult", chord_tol: float) -> "FormFeatures":
    """What the cam's form adds to the drawing (:mod:`camgen.export.drawing_forms`)."""
    from camgen.export.drawing_forms import FormFeatures, mm_text as _fmt

    groove = _groove(cam)
    if groove is not None:
        assert groove.width is not None and groove.centre is not None
        return FormFeatures(tuple((w.layer.lower(), w.contour.flatten(chord_tol)) for w in groove.walls), groove.centre.flatten(chord_tol),
                            (f"GROOVE {_fmt(groove.width)} WIDE, {_fmt(groove.depth)} DEEP FROM THE TOP FACE",
                             f"GROOVE WALLS: FULL LINES; PITCH CURVE: DASH-DOT; ROLLER CLEARANCE {groove.clearance:g}"), form="GROOVE CAM")
    breadth, spacing = cam.figures.get("breadth_mm"), cam.figures.get("roller_spacing_mm")
    if isinstance(breadth, (int, float)):
        return FormFeatures(breadth=float(breadth), form="CONSTANT-BREADTH CAM")
    if isinstance(spacing, (int, float)):
        return FormFeatures(notes=(f"ROLLER SPACING {_fmt(spacing)}: THE PITCH CURVE'S DIAMETER IN EVERY DIRECTION",),
                            form="CONSTANT-DIAMETER CAM")
    if "conjugate" in cam.figures:
        return FormFeatures(notes=("ONE CAM OF A CONJUGATE PAIR: EACH CAM ITS OWN DRAWING",), form="CONJUGATE CAM")
    return FormFeatures()


def _sheet(cam: "CamResult", run: "RunSettings", fmt: str) -> "Sheet":
    from camgen.export.drawing import drawing_sheet, fitting_scales, sheet_for
    from camgen.export.drawing_spec import DRAWING_SCALES

    data = _drawing_input(cam, run, fmt)
    spec = run.output.drawing
    rows = data.table.cam_angle.size
    sheet = sheet_for(data.outer_radius, rows, spec)
    if sheet is None:
        fits = fitting_scales(data.outer_radius, rows, spec.sheet)
        where = "A3" if spec.sheet == "auto" else spec.sheet
        if fits:
            raise ParameterError("output.drawing_scale", spec.scale, f"{fits[0]} or smaller for cam '{cam.name}' on the {where} sheet",
                                 f"its largest radius is {data.outer_radius:.1f} mm")
        raise ParameterError("output.formats", fmt, f"formats without {fmt} for cam '{cam.name}'",
                             f"its largest radius {data.outer_radius:.1f} mm does not fit the {where} sheet at any scale down to "
                             f"{DRAWING_SCALES[-1]}")
    drawn = drawing_sheet(data, spec, sheet)
    _require_finite(cam.name, drawn, data)
    return drawn


def _require_finite(name: str, sheet: "Sheet", data: "DrawingInput") -> None:
    """Every coordinate drawn and every number printed is finite (the PDF's streams are compressed:
    the run's text guard, :mod:`camgen.nonfinite`, cannot read them)."""
    import numpy as np

    from camgen.errors import ExportError

    t = data.table
    numbers = [s.points for s in sheet.strokes] + [f.points for f in sheet.fills] + [t.centre_radius, t.lift]
    scalars = (data.base_radius, data.outer_radius, data.bore_diameter, data.keyway_reach, data.thickness, *data.zero)
    if not (all(bool(np.all(np.isfinite(a))) for a in numbers) and bool(np.all(np.isfinite(scalars)))):
        raise ExportError(f"drawing of cam '{name}': a non-finite coordinate or number")


def drawing_svg(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """``<cam>_drawing.svg``."""
    from camgen.export.drawing_render import sheet_svg

    return sheet_svg(_sheet(cam, run, fmt))


def drawing_pdf(cam: "CamResult", run: "RunSettings", fmt: str) -> bytes:
    """``<cam>_drawing.pdf`` (needs the drawing extra: fpdf2)."""
    from camgen.export.drawing_render import sheet_pdf

    return sheet_pdf(_sheet(cam, run, fmt))
