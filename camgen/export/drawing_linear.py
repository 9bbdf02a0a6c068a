"""The manufacturing drawing (SVG, PDF) and inspection table (CSV) of a linear cam
(``form = "linear"``; the form's writers for ``drawing``, ``drawing_pdf`` and
``inspection``).

The plate is drawn in its frame (:mod:`camgen.synthesis.linear`: ``x = 0`` where the follower's
point is at travel 0, ``y = 0`` the pitch line) at the stated scale: its outline (flattened within
the chord tolerance), a slot's wall, the pitch line and the line ``x = 0`` (dash-dot), the plate's
length and height dimensioned (dimension lines with arrowheads, the length below the plate, the
height right of it), the travel from ``x = 0`` to ``x = travel`` dimensioned above it, the
direction the plate moves, the inspection table, a scale bar 100 mm long on the page and the title
block; the sheet, border and text sizes are the disk cam drawing's (:mod:`camgen.export.drawing`).

Inspection: a checking roller of the follower's radius (a probe point for a knife) on the
follower's line, the plate moved by ``x``: its centre's height above the pitch line is the lift
``s(x)`` (the follower point is ``(x, s(x))`` in the plate frame), the profile made within
``fit_tol_mm`` of it.  An oscillating follower's table gives the arm's swing ``s(x)`` from its
rest angle instead (deg: the roller on the arm resting on the profile).  The rows: the travel in
as many equal steps as ``inspection_step_deg`` makes of a turn (the motion reads the travel onto
one turn, ``theta = 2 pi x / travel``), both ends included.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import ParameterError
from camgen.export.drawing import BORDER, DASH_DOT, ROW, TEXT, THIN, WIDE, Fill, Label, Sheet, Stroke
from camgen.export.drawing_forms import mm_text
from camgen.export.drawing_sheets import choose_sheet, frame, right_width, scale_bar_and_title
from camgen.export.drawing_spec import SHEETS, DrawingSpec, scale_factor
from camgen.export.inspection import inspection_angles
from camgen.export.tables import csv_table

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["LINEAR_COLUMNS", "LinearTable", "SWING_COLUMNS", "drawing_pdf", "drawing_svg", "inspection", "linear_inspection_metadata", "linear_table"]

#: Columns of a linear cam's ``<cam>_inspection.csv``.
LINEAR_COLUMNS = {
    "x_mm": "plate travel x: the plate moved by x, the follower's line at x = x on the plate, mm",
    "lift_mm": "height of the checking roller's centre (the follower's point) above the pitch line y = 0: the lift s(x), mm",
}
#: ... and with an oscillating follower.
SWING_COLUMNS = {
    "x_mm": LINEAR_COLUMNS["x_mm"],
    "swing_deg": "the arm's swing from its rest angle, the roller on it resting on the profile: s(x), deg",
}
#: Width of one column block of the table (mm) and the room (mm) around the plate for its dimensions.
BLOCK = 30.0
ROOM_X, ROOM_Y = 60.0, 44.0


@dataclass(frozen=True)
class LinearTable:
    """Travels and lifts (mm) of the inspection table, the roller's radius and how far (mm) the made
    profile may be from the exact one (``fit_tol_mm``); ``swing``: an oscillating follower's table,
    ``lift`` its swing (deg)."""

    x: np.ndarray
    lift: np.ndarray
    roller_radius: float
    tolerance: float
    swing: bool = False

    @property
    def columns(self) -> dict[str, str]:
        return SWING_COLUMNS if self.swing else LINEAR_COLUMNS


def _params(cam: "CamResult", fmt: str) -> Any:
    from camgen.kinds.linear import LinearCam

    built = cam.built
    assert isinstance(built, LinearCam), f"cam {cam.name!r} is not a linear cam"
    if cam.contour is None:
        raise ParameterError("output.formats", fmt, f"formats without {fmt} for cam '{cam.name}'", "the cam cannot be made")
    return built.params


def linear_table(cam: "CamResult", spec: DrawingSpec, fmt: str) -> LinearTable:
    """The inspection table of the linear cam ``cam`` (module notes)."""
    from camgen.synthesis.linear import law_in_x

    p = _params(cam, fmt)
    radius = p.follower.roller_radius
    if spec.inspection_roller_radius is not None and spec.inspection_roller_radius != radius:
        raise ParameterError("output.inspection_roller_radius_mm", spec.inspection_roller_radius,
                             f"{radius:g} (the follower's roller) for linear cam '{cam.name}', or left out",
                             "a linear cam's table is read with the follower's own roller")
    count = inspection_angles(spec.inspection_step).size
    x = p.travel * np.arange(count + 1) / count
    s = law_in_x(p.law, p.travel, x)[0]
    if p.follower.motion == "oscillating":  # the swing, rad -> deg
        return LinearTable(x, np.degrees(s), float(radius), float(p.fit_tol), swing=True)
    return LinearTable(x, s, float(radius), float(p.fit_tol))


def inspection(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """``<cam>_inspection.csv`` of a linear cam."""
    t = linear_table(cam, run.output.drawing, fmt)
    return csv_table(dict(zip(t.columns, (t.x, t.lift))))


def linear_inspection_metadata(cam: "CamResult", spec: DrawingSpec) -> dict[str, Any]:
    """What a linear cam's ``<cam>_inspection.csv`` holds (report.json ``tables``)."""
    t = linear_table(cam, spec, "inspection")
    return {"content": "inspection table of a linear cam: the plate moved by x, a checking roller of the follower's radius on the "
                       "follower's line rests on the profile; its centre's height above the pitch line",
            "columns": dict(t.columns), "x_step_mm": float(t.x[1] - t.x[0]), "roller_radius_mm": t.roller_radius,
            "profile_fit_tol_mm": t.tolerance}


def _fits(size: tuple[float, float], rows: int, k: float, sheet: str) -> bool:
    w, h = SHEETS[sheet]
    right, _ = right_width(rows, h, BLOCK)
    return k * size[0] + ROOM_X + right + 5.0 <= w - 2 * BORDER and k * size[1] + ROOM_Y <= h - 2 * BORDER


def _dimension(a: np.ndarray, b: np.ndarray, text: str, name: str, strokes: list, fills: list, labels: list) -> None:
    """A dimension line ``a -> b`` (page mm) with arrowheads at both ends and ``text`` beside its middle."""
    d = (b - a) / np.hypot(*(b - a))
    strokes.append(Stroke(np.array([a, b]), THIN, name=name))
    for tip, way in ((a, -d), (b, d)):
        n = np.array([-way[1], way[0]])
        back = tip - 3.0 * way
        fills.append(Fill(np.array([tip, back + 0.5 * n, back - 0.5 * n])))
    mid = 0.5 * (a + b)
    if abs(d[0]) > 0.5:  # horizontal: the text below
        labels.append(Label(float(mid[0]), float(mid[1] + 4.0), text, anchor="middle"))
    else:  # vertical: the text right of it
        labels.append(Label(float(mid[0] + 2.0), float(mid[1] + TEXT / 2), text))


def _sheet(cam: "CamResult", run: "RunSettings", fmt: str) -> Sheet:
    p = _params(cam, fmt)
    spec, tol = run.output.drawing, run.output.chord_tol
    table = linear_table(cam, spec, fmt)
    assert cam.contour is not None
    outline = cam.contour.flatten(tol)
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    size = (float(hi[0] - lo[0]), float(hi[1] - lo[1]))
    rows = table.x.size
    k = scale_factor(spec.scale)
    sheet = choose_sheet(lambda scale, s: _fits(size, rows, scale, s), spec, cam.name, fmt, f"its plate is {size[0]:.1f} x {size[1]:.1f} mm")
    width, height = SHEETS[sheet]
    right_w, per_block = right_width(rows, height, BLOCK)
    fills: list[Fill] = []
    labels: list[Label] = []
    border, (x0, y0, x1, y1) = frame(width, height)
    strokes: list[Stroke] = [border]
    view_right = x1 - right_w - 5.0
    # the plate centred in the view, its dimensions' room below and right
    left = x0 + (view_right - x0 - ROOM_X - k * size[0]) / 2.0 + 10.0
    top = y0 + (y1 - y0 - ROOM_Y - k * size[1]) / 2.0 + 18.0

    def page(q: np.ndarray) -> np.ndarray:
        return np.column_stack([left + k * (q[:, 0] - lo[0]), top + k * (hi[1] - q[:, 1])])

    strokes.append(Stroke(page(outline), WIDE, closed=True, name="profile"))
    for pocket in cam.pockets:
        for wall in pocket.walls:
            strokes.append(Stroke(page(wall.contour.flatten(tol)), WIDE, closed=True, name=wall.layer.lower()))
    bl, tr = page(np.array([[lo[0], lo[1]], [hi[0], hi[1]]]))  # bottom left, top right corners on the page
    # pitch line and x = 0 (dash-dot), the travel above the plate
    zero_pt = page(np.array([[0.0, 0.0], [p.travel, 0.0]]))
    strokes.append(Stroke(np.array([[bl[0] - 3.0, zero_pt[0, 1]], [tr[0] + 3.0, zero_pt[0, 1]]]), THIN, DASH_DOT, name="pitch_line"))
    labels.append(Label(float(tr[0] - 2.0), float(zero_pt[0, 1] - 1.0), "y = 0 PITCH LINE", anchor="end"))
    strokes.append(Stroke(np.array([[zero_pt[0, 0], bl[1] + 3.0], [zero_pt[0, 0], tr[1] - 12.0]]), THIN, DASH_DOT, name="x_zero"))
    strokes.append(Stroke(np.array([[zero_pt[1, 0], tr[1] - 2.0], [zero_pt[1, 0], tr[1] - 12.0]]), THIN, name="x_travel"))
    _dimension(np.array([zero_pt[0, 0], tr[1] - 10.0]), np.array([zero_pt[1, 0], tr[1] - 10.0]),
               f"TRAVEL {mm_text(p.travel)} FROM x = 0", "travel", strokes, fills, labels)
    labels.append(Label(float(zero_pt[0, 0]), float(tr[1] - 14.0), "x = 0", anchor="middle"))
    labels.append(Label(float(bl[0]), float(tr[1] - 20.0), "PLATE MOVES IN -x: THE FOLLOWER READS IT FROM x = 0 TO x = TRAVEL"))
    # length below, height right of the plate
    strokes.append(Stroke(np.array([[bl[0], bl[1] + 1.0], [bl[0], bl[1] + 9.0]]), THIN, name="length_left"))
    strokes.append(Stroke(np.array([[tr[0], bl[1] + 1.0], [tr[0], bl[1] + 9.0]]), THIN, name="length_right"))
    _dimension(np.array([bl[0], bl[1] + 7.0]), np.array([tr[0], bl[1] + 7.0]), f"LENGTH {mm_text(size[0])}", "length",
               strokes, fills, labels)
    strokes.append(Stroke(np.array([[tr[0] + 1.0, tr[1]], [tr[0] + 9.0, tr[1]]]), THIN, name="height_top"))
    strokes.append(Stroke(np.array([[tr[0] + 1.0, bl[1]], [tr[0] + 9.0, bl[1]]]), THIN, name="height_bottom"))
    _dimension(np.array([tr[0] + 7.0, tr[1]]), np.array([tr[0] + 7.0, bl[1]]), f"HEIGHT {mm_text(size[1])}", "height",
               strokes, fills, labels)
    if cam.pockets:
        labels.append(Label(float(bl[0]), float(bl[1] + 16.0), cam.pockets[0].note.upper()))
    # the table
    tx = x1 - right_w
    probe = f"ROLLER R{mm_text(table.roller_radius)}" if table.roller_radius > 0 else "PROBE POINT"
    labels.append(Label(tx, y0 + ROW, f"INSPECTION: {probe} ON THE FOLLOWER{' ARM' if table.swing else chr(39) + 'S LINE'}, "
                        "PLATE MOVED BY x", 2.2))
    labels.append(Label(tx, y0 + 2 * ROW, "SWING OF THE ARM FROM REST, deg" if table.swing else
                        f"LIFT ABOVE THE PITCH LINE, TOLERANCE \u00b1{spec.tolerance:g}", 2.2))
    for b in range(-(-rows // per_block)):
        bx, y = tx + b * BLOCK, y0 + 3 * ROW
        labels += [Label(bx + 12.0, y, "x", 2.0, "end"), Label(bx + 26.0, y, "SWING \u00b0" if table.swing else "LIFT", 2.0, "end")]
        strokes.append(Stroke(np.array([[bx, y + 0.9], [bx + BLOCK - 3.0, y + 0.9]]), THIN))
        for i in range(b * per_block, min(rows, (b + 1) * per_block)):
            y += ROW
            labels += [Label(bx + 12.0, y, mm_text(table.x[i]), 2.0, "end"), Label(bx + 26.0, y, mm_text(table.lift[i]), 2.0, "end")]
    words = ((f"CAM {cam.name}", f"SCENE {run.scene_name}"),
             (f"MATERIAL {spec.material}", f"THICKNESS {mm_text(cam.body.thickness)} mm"),
             (f"PROFILE TOLERANCE \u00b1{spec.tolerance:g} mm", f"DRAWN WITHIN {tol:g} mm"),
             (f"SCALE {spec.scale}", f"SHEET {sheet} LANDSCAPE"),
             ("UNITS mm", f"TRAVEL {mm_text(p.travel)} mm"),
             ("DRAWN BY camgen", f"LINEAR CAM {cam.name}"))
    scale_bar_and_title(spec, tx + 2.0, x1, y1, words, fills, labels, strokes)
    numbers = [s.points for s in strokes] + [f.points for f in fills] + [table.lift]
    if not all(bool(np.all(np.isfinite(a))) for a in numbers):
        from camgen.errors import ExportError

        raise ExportError(f"drawing of cam '{cam.name}': a non-finite coordinate or number")
    return Sheet(width, height, tuple(strokes), tuple(fills), tuple(labels), cam.name)


def drawing_svg(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """``<cam>_drawing.svg`` of a linear cam."""
    from camgen.export.drawing_render import sheet_svg

    return sheet_svg(_sheet(cam, run, fmt))


def drawing_pdf(cam: "CamResult", run: "RunSettings", fmt: str) -> bytes:
    """``<cam>_drawing.pdf`` of a linear cam (needs the drawing extra: fpdf2)."""
    from camgen.export.drawing_render import sheet_pdf

    return sheet_pdf(_sheet(cam, run, fmt))

