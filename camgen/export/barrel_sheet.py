"""The manufacturing drawing (SVG, PDF) and inspection table (CSV) of a barrel cam's groove or rib
(``form = "barrel"``; the form's writers for ``drawing``, ``drawing_pdf`` and ``inspection``).

The sheet, border, text sizes, scale bar and title block are the disk cam drawing's
(:mod:`camgen.export.drawing`).  Two views share the page's vertical (the cam axis ``z``, up; ``z = 0``
the bottom face):

* the side view, seen from the follower's station at cam angle 0 (the cam's polar angle 0, the
  zero mark, faces the viewer): the cylinder's outline, the axis (dash-dot), the bore (hidden
  lines, dashed), the outer diameter dimensioned below, the length left of it, the bore above;
* the developed groove at the mean radius ``R_m`` (:mod:`camgen.export.barrel_drawing`: ``x = R_m
  phi``, ``phi`` the cam's polar angle): the developed cylinder ``0 <= x <= 2 pi R_m`` (its
  length ``2 pi R_m`` dimensioned below it), both walls' sections at ``R_m`` (full lines) and the
  pitch curve (dash-dot), each within ``chord_tol_mm`` of the exact curve (so within scale x
  ``chord_tol_mm`` on the page); the groove's width dimensioned across the walls where the pitch
  curve is highest (a dwell of a translating follower: ``2 w``, ``w = Rr + c / 2``; a rib
  (``track = "rib"``): its two faces instead of the walls, the pitch line between them, the rib's
  width dimensioned there: ``rib_width_mm`` where a translating follower dwells); the zero mark
  (``x = 0``, cam angle 0) and ticks at cam angles 90, 180 and 270 deg at ``x = R_m (-sigma theta mod
  2 pi)`` (the cam turned by ``theta`` brings the polar angle ``-sigma theta`` to the follower), and
  an arrow the way the surface passes the follower.

Inspection (the datum): the cam turned by ``theta`` from its zero mark in its sense of rotation; a
plug of the groove's width (radius ``w``) with its axis radial at the follower's station rests on
both walls: its axis' height above the bottom face is the roller axis' ``z_c(theta) = z0 +
s(theta)`` (``z0`` the axis' height at lift 0), so the table gives ``axial_position_mm = z_c`` and
``lift_mm = s``.  An oscillating follower's table gives the arm's angle ``psi = psi0 + s(theta)``
(deg, in the plane through the cam axis, from the plane perpendicular to it) and its swing ``s``.
A rib is read by a fork of two rollers of radius ``w`` straddling it, their axes ``rib_width + 2 w``
apart along the follower's normal (the follower's own pair): the midpoint of their axes is the
pitch line's ``z_c``, so the columns are the same.
The rows: the whole turn in equal steps (:func:`camgen.export.inspection.inspection_angles`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import ExportError, ParameterError
from camgen.export.drawing import BORDER, DASH_DOT, ROW, TEXT, THIN, WIDE, Fill, Label, Sheet, Stroke
from camgen.export.drawing_forms import mm_text
from camgen.export.drawing_sheets import choose_sheet, frame, right_width, scale_bar_and_title
from camgen.export.drawing_spec import SHEETS, DrawingSpec, scale_factor
from camgen.export.inspection import inspection_angles
from camgen.export.tables import csv_table

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["BarrelTable", "HIDDEN", "SLIDE_COLUMNS", "SWING_COLUMNS", "barrel_inspection_metadata", "barrel_table", "drawing_pdf",
           "drawing_svg", "inspection"]

#: Columns of a barrel cam's ``<cam>_inspection.csv`` (translating follower) and what they hold.
SLIDE_COLUMNS = {
    "cam_angle_deg": "cam angle: the cam turned from its zero mark in its sense of rotation, deg",
    "axial_position_mm": "height above the bottom face (z = 0) of the axis of a plug of the groove's width resting on both walls, "
                         "its axis radial at the follower's station (a rib: the midpoint of the axes of a fork of two rollers "
                         "straddling it): the roller axis' (the pitch line's) z_c, mm",
    "lift_mm": "axial_position_mm minus the axis' height at lift 0 (z0): the law's lift s, mm",
}
#: ... and with an oscillating follower.
SWING_COLUMNS = {
    "cam_angle_deg": SLIDE_COLUMNS["cam_angle_deg"],
    "arm_angle_deg": "the arm's angle psi = psi0 + s in the plane through the cam axis, from the plane perpendicular to it, "
                     "with the plug of the groove's width at its end resting on both walls, deg",
    "swing_deg": "the arm's swing s from its rest angle psi0, deg",
}
#: Dash pattern of hidden lines (ISO 128 type 02), page mm.
HIDDEN = (3.0, 1.5)
#: Width of one column block of the drawing's table, mm; room (mm) left of the side view (the
#: length's dimension), between the views (the bore's label), right of the developed view, above
#: and below the views (labels, dimensions).
BLOCK = 36.0
ROOM_LEFT, ROOM_GAP, ROOM_RIGHT, ROOM_TOP, ROOM_BOTTOM = 18.0, 24.0, 6.0, 34.0, 40.0


@dataclass(frozen=True)
class BarrelTable:
    """Cam angles (rad) and the two columns of the table (mm, or deg for a swing), the plug's
    radius (mm), the walls' stated tolerance (mm) and ``z0`` (mm); ``swing``: an oscillating follower."""

    cam_angle: np.ndarray
    position: np.ndarray
    lift: np.ndarray
    plug_radius: float
    tolerance: float
    z0: float
    swing: bool = False

    @property
    def columns(self) -> dict[str, str]:
        return SWING_COLUMNS if self.swing else SLIDE_COLUMNS


def _groove(cam: "CamResult") -> Any:
    """What the drawing shows: the rib (:class:`camgen.synthesis.barrel.BarrelRib`) or the groove."""
    groove = getattr(cam.built, "groove", None)
    assert groove is not None, f"cam {cam.name!r} is not a barrel cam"
    rib = getattr(cam.built, "rib", None)
    return rib if rib is not None else groove


def _is_rib(surfaces: Any) -> bool:
    return hasattr(surfaces, "roller_offset")


def barrel_table(cam: "CamResult", spec: DrawingSpec, fmt: str) -> BarrelTable:
    """The inspection table of the barrel cam ``cam`` (module notes)."""
    groove = _groove(cam)
    w = groove.half_width
    if spec.inspection_roller_radius is not None and spec.inspection_roller_radius != w:
        raise ParameterError("output.inspection_roller_radius_mm", spec.inspection_roller_radius,
                             f"{w:g} (the follower's roller widened by half the clearance) for barrel cam '{cam.name}', or left out",
                             "a plug in a groove rests on both walls (a fork straddling a rib on both faces) only at that radius")
    theta = inspection_angles(spec.inspection_step)
    s = getattr(groove, "groove", groove).law(theta)[0]  # a rib's law: its pitch line's groove's
    lay = groove.layout
    if lay.motion == "oscillating":
        return BarrelTable(theta, np.degrees(lay.rest_angle + s), np.degrees(s), float(w), float(groove.fit_tol), float(lay.z0), True)
    z_c, _ = groove.axis(theta)
    return BarrelTable(theta, z_c, z_c - lay.z0, float(w), float(groove.fit_tol), float(lay.z0))


def inspection(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """``<cam>_inspection.csv`` of a barrel cam."""
    t = barrel_table(cam, run.output.drawing, fmt)
    return csv_table(dict(zip(t.columns, (np.degrees(t.cam_angle), t.position, t.lift))))


def barrel_inspection_metadata(cam: "CamResult", spec: DrawingSpec) -> dict[str, Any]:
    """What a barrel cam's ``<cam>_inspection.csv`` holds (report.json ``tables``)."""
    t = barrel_table(cam, spec, "inspection")
    surfaces = _groove(cam)
    sigma = surfaces.layout.sigma
    gauge = ("a fork of two rollers of radius plug_radius_mm, their axes fork_spacing_mm apart, straddles the rib on both faces "
             "at the follower's station (the midpoint of their axes)" if _is_rib(surfaces) else
             "a plug of the groove's width, its axis radial at the follower's station, rests on both walls")
    extra = {"fork_spacing_mm": 2.0 * surfaces.roller_offset} if _is_rib(surfaces) else {}
    return {"content": f"inspection table of a barrel cam's {'rib' if _is_rib(surfaces) else 'groove'}: the cam turned from its zero "
                       f"mark in its sense of rotation; {gauge}"
                       + ("; the arm's angle carrying it" if t.swing else "; its axis' height above the bottom face"),
            "columns": dict(t.columns), "angle_step_deg": 360.0 / t.cam_angle.size, "plug_radius_mm": t.plug_radius, **extra,
            "datum": "z = 0: the cylinder's bottom face" if not t.swing else "psi = 0: the plane perpendicular to the cam axis",
            "lift_zero_axis_height_mm" if not t.swing else "pivot_height_mm": t.z0,
            "rotation": "ccw" if sigma > 0 else "cw", "fit_tol_mm": t.tolerance}


# -- the sheet -----------------------------------------------------------------------------
def _fits(size: tuple[float, float, float], rows: int, k: float, sheet: str) -> bool:
    """``size``: the side view's width, the developed view's width and the views' height (part mm)."""
    w, h = SHEETS[sheet]
    right, _ = right_width(rows, h, BLOCK)
    width = ROOM_LEFT + k * size[0] + ROOM_GAP + k * size[1] + ROOM_RIGHT + right + 5.0
    return width <= w - 2 * BORDER and k * size[2] + ROOM_TOP + ROOM_BOTTOM <= h - 2 * BORDER


def _arrow(tip: np.ndarray, way: np.ndarray) -> Fill:
    d = way / np.hypot(*way)
    n = np.array([-d[1], d[0]])
    back = tip - 3.0 * d
    return Fill(np.array([tip, back + 0.5 * n, back - 0.5 * n]))


def _dimension(a: np.ndarray, b: np.ndarray, text: str, name: str, strokes: list, fills: list, labels: list,
               below: bool = True) -> None:
    """A dimension line ``a -> b`` (page mm) with arrowheads at both ends and ``text`` beside its middle."""
    d = (b - a) / np.hypot(*(b - a))
    strokes.append(Stroke(np.array([a, b]), THIN, name=name))
    fills.extend((_arrow(a, -d), _arrow(b, d)))
    mid = 0.5 * (a + b)
    if abs(d[0]) > 0.5:  # horizontal: the text below (or above)
        labels.append(Label(float(mid[0]), float(mid[1] + (4.0 if below else -1.5)), text, anchor="middle"))
    else:  # vertical: the text left of it
        labels.append(Label(float(mid[0] - 1.5), float(mid[1] + TEXT / 2), text, anchor="end"))


def _sheet(cam: "CamResult", run: "RunSettings", fmt: str) -> Sheet:
    from camgen.export.barrel_drawing import developed_curves

    groove = _groove(cam)
    rib = _is_rib(groove)
    spec, tol = run.output.drawing, run.output.chord_tol
    table = barrel_table(cam, spec, fmt)
    lay = groove.layout
    rm, ro, length, bore = lay.mean_radius, groove.rim_radius, groove.length, 2.0 * groove.bore_radius
    span = 2.0 * math.pi * rm
    curves = developed_curves(groove, tol)
    z_lo = min(0.0, *(float(c[:, 1].min()) for c in curves.values()))
    z_hi = max(length, *(float(c[:, 1].max()) for c in curves.values()))
    size = (2.0 * ro, span, z_hi - z_lo)
    rows = table.cam_angle.size
    k = scale_factor(spec.scale)
    sheet = choose_sheet(lambda scale, s: _fits(size, rows, scale, s), spec, cam.name, fmt,
                         f"its side view and developed groove are {2 * ro + span:.1f} x {size[2]:.1f} mm")
    width, height = SHEETS[sheet]
    right_w, per_block = right_width(rows, height, BLOCK)
    fills: list[Fill] = []
    labels: list[Label] = []
    border, (x0, y0, x1, y1) = frame(width, height)
    strokes: list[Stroke] = [border]
    # the views' origin: z = 0 at page y = base; the side view's axis at page x = axis_x; x = 0 of the developed view at dev_x
    view_w = ROOM_LEFT + k * size[0] + ROOM_GAP + k * span + ROOM_RIGHT
    left = x0 + max(0.0, (x1 - right_w - 5.0 - x0 - view_w) / 2.0)
    axis_x = left + ROOM_LEFT + k * ro
    dev_x = axis_x + k * ro + ROOM_GAP
    top = y0 + max(ROOM_TOP, (y1 - y0 - k * size[2] - ROOM_BOTTOM - ROOM_TOP) / 2.0 + ROOM_TOP)
    base = top + k * z_hi

    def side(q: np.ndarray) -> np.ndarray:
        return np.column_stack([axis_x + k * q[:, 0], base - k * q[:, 1]])

    def developed(q: np.ndarray) -> np.ndarray:
        return np.column_stack([dev_x + k * q[:, 0], base - k * q[:, 1]])

    # the side view: outline, axis, bore (hidden), dimensions
    strokes.append(Stroke(side(np.array([[-ro, 0.0], [ro, 0.0], [ro, length], [-ro, length]])), WIDE, closed=True, name="cylinder"))
    strokes.append(Stroke(side(np.array([[0.0, -3.0 / k], [0.0, length + 3.0 / k]])), THIN, DASH_DOT, name="axis"))
    labels.append(Label(float(axis_x), float(top - 26.0), "SIDE VIEW FROM THE FOLLOWER AT CAM ANGLE 0", 2.2, "middle"))
    bl, tr = side(np.array([[-ro, 0.0], [ro, length]]))
    for x, name in ((bl[0], "diameter_left"), (tr[0], "diameter_right")):
        strokes.append(Stroke(np.array([[x, bl[1] + 1.0], [x, bl[1] + 9.0]]), THIN, name=name))
    _dimension(np.array([bl[0], bl[1] + 7.0]), np.array([tr[0], bl[1] + 7.0]), f"\u00d8{mm_text(2 * ro)}", "outer_diameter",
               strokes, fills, labels)
    for y, name in ((bl[1], "length_bottom"), (tr[1], "length_top")):
        strokes.append(Stroke(np.array([[bl[0] - 1.0, y], [bl[0] - 9.0, y]]), THIN, name=name))
    _dimension(np.array([bl[0] - 7.0, tr[1]]), np.array([bl[0] - 7.0, bl[1]]), mm_text(length), "length", strokes, fills, labels)
    if bore > 0:
        for x, name in ((-bore / 2, "bore_left"), (bore / 2, "bore_right")):
            strokes.append(Stroke(side(np.array([[x, 0.0], [x, length]])), THIN, HIDDEN, name=name))
            px = float(side(np.array([[x, length]]))[0, 0])
            strokes.append(Stroke(np.array([[px, tr[1] - 1.0], [px, tr[1] - 9.0]]), THIN, name=name + "_ext"))
        a, b = side(np.array([[-bore / 2, length], [bore / 2, length]]))
        _dimension(a - [0.0, 7.0], b - [0.0, 7.0], f"\u00d8{mm_text(bore)} BORE THROUGH", "bore", strokes, fills, labels, below=False)
    # the developed view
    strokes.append(Stroke(developed(np.array([[0.0, 0.0], [span, 0.0], [span, length], [0.0, length]])), THIN, closed=True,
                          name="developed_outline"))
    strokes.append(Stroke(developed(curves["PITCH_DEVELOPED"]), THIN, DASH_DOT, name="pitch_curve"))
    for face in ("UPPER", "LOWER"):
        layer = f"RIB_{face}_DEVELOPED" if rib else f"WALL_{face}_DEVELOPED"
        strokes.append(Stroke(developed(curves[layer]), WIDE, name=("rib_" if rib else "wall_") + face.lower()))
    d0, d1 = developed(np.array([[0.0, 0.0], [span, length]]))
    track = "RIB" if rib else "GROOVE"
    labels.append(Label(float(d0[0]), float(top - 26.0), f"{track} DEVELOPED AT MEAN RADIUS R = {mm_text(rm)} (x = R \u00d7 POLAR "
                        "ANGLE OF THE CAM)", 2.2))
    if rib:
        labels.append(Label(float(d0[0]), float(top - 22.0), f"RIB {mm_text(groove.width)} WIDE ALONG z IN A DWELL, "
                            f"{mm_text(groove.rim_radius - groove.root_radius)} HIGH ON ROOT \u00d8{mm_text(2 * groove.root_radius)}; "
                            f"ROLLERS \u00d8{mm_text(2 * groove.half_width)}; FACES FULL, PITCH LINE DASH-DOT", 2.2))
    else:
        labels.append(Label(float(d0[0]), float(top - 22.0), f"GROOVE {mm_text(2 * groove.half_width)} WIDE ACROSS THE ROLLER, "
                            f"{mm_text(groove.rim_radius - groove.root_radius)} DEEP (ROOT \u00d8{mm_text(2 * groove.root_radius)}); "
                            "WALLS: FULL LINES, PITCH CURVE: DASH-DOT", 2.2))
    # the groove's (rib's) width across the walls (faces) where the pitch curve is highest
    pitch = curves["PITCH_DEVELOPED"]
    top_run = np.flatnonzero(pitch[:, 1] >= float(pitch[:, 1].max()) - 1e-9)  # the highest dwell: its middle point
    i = int(top_run[top_run.size // 2])
    xw = float(np.mod(pitch[i, 0], span))
    phi = np.array([xw / rm])
    zu, zl = (float(groove.wall_height(s, np.asarray(rm), phi)[0]) for s in (1, -1))
    a, b = developed(np.array([[xw, zu], [xw, zl]]))
    _dimension(a, b, f"{mm_text(zu - zl)}", "track_width", strokes, fills, labels)
    # the developed length below, the zero mark and the cam-angle ticks
    for x, name in ((d0[0], "span_left"), (d1[0], "span_right")):
        strokes.append(Stroke(np.array([[x, d0[1] + 1.0], [x, d0[1] + 17.0]]), THIN, name=name))
    _dimension(np.array([d0[0], d0[1] + 15.0]), np.array([d1[0], d0[1] + 15.0]), f"2 PI R = {mm_text(span)} (ONE TURN)", "span",
               strokes, fills, labels)
    strokes.append(Stroke(np.array([[d0[0], d1[1] - 12.0], [d0[0], d1[1]]]), THIN, name="zero_mark"))
    labels.append(Label(float(d0[0]), float(d1[1] - 13.0), "0\u00b0 ZERO MARK", 2.2, "middle"))
    sigma = lay.sigma
    for deg in (90, 180, 270):
        x = float(dev_x + k * rm * np.mod(-sigma * math.radians(deg), 2 * math.pi))
        strokes.append(Stroke(np.array([[x, d1[1] - 4.0], [x, d1[1]]]), THIN, name=f"tick_{deg}"))
        labels.append(Label(x, float(d1[1] - 5.0), f"{deg}\u00b0", 2.2, "middle"))
    way = 1.0 if sigma > 0 else -1.0  # the surface passes the follower toward +x when the cam turns ccw
    mid = 0.5 * (d0[0] + d1[0])
    ya = d0[1] + 25.0
    strokes.append(Stroke(np.array([[mid - way * 15.0, ya], [mid + way * 15.0, ya]]), THIN, name="rotation_arrow"))
    fills.append(_arrow(np.array([mid + way * 15.0, ya]), np.array([way, 0.0])))
    labels.append(Label(float(mid), float(ya + 4.0), "THE SURFACE PASSES THE FOLLOWER THIS WAY: ROTATION "
                        + ("CCW" if sigma > 0 else "CW") + " SEEN FROM THE TOP FACE (z UP)", 2.2, "middle"))
    labels.append(Label(float(d0[0]), float(ya + 8.0), f"THE FOLLOWER READS CAM ANGLE T AT THE CAM'S POLAR ANGLE {'-' if sigma > 0 else '+'}T "
                        "(x = R \u00d7 POLAR ANGLE IN rad, MOD 2 PI R); z FROM THE BOTTOM FACE", 2.2))
    _table(table, spec, x1 - right_w, y0, per_block, labels, strokes, 2.0 * groove.roller_offset if rib else 0.0)
    _scale_bar_and_title(cam, run, spec, sheet, table, x1, y1, right_w, length, sigma, fills, labels, strokes)
    numbers = [s.points for s in strokes] + [f.points for f in fills] + [table.position, table.lift]
    if not all(bool(np.all(np.isfinite(q))) for q in numbers):  # the PDF's streams are compressed: the run's text guard cannot read them
        raise ExportError(f"drawing of cam '{cam.name}': a non-finite coordinate or number")
    return Sheet(width, height, tuple(strokes), tuple(fills), tuple(labels), cam.name)


def _table(table: BarrelTable, spec: DrawingSpec, tx: float, y0: float, per_block: int, labels: list, strokes: list,
           fork: float) -> None:
    """The table's caption and column blocks; ``fork``: a rib's fork of two rollers, their axes ``fork`` mm apart (0: a groove's plug)."""
    rows = table.cam_angle.size
    what = ("ARM ANGLE FROM THE PLANE NORMAL TO THE AXIS" if table.swing else "AXIAL POSITION z FROM THE BOTTOM FACE")
    gauge = (f"FORK OF ROLLERS \u00d8{mm_text(2 * table.plug_radius)}, AXES {mm_text(fork)} APART, ON THE RIB" if fork > 0 else
             f"PLUG \u00d8{mm_text(2 * table.plug_radius)} IN THE GROOVE")
    labels.append(Label(tx, y0 + ROW, f"INSPECTION: {gauge} AT THE FOLLOWER", 2.2))
    labels.append(Label(tx, y0 + 2 * ROW, f"{what}, TOLERANCE \u00b1{spec.tolerance:g}", 2.2))
    heads = ("ANGLE \u00b0", "ARM \u00b0", "SWING \u00b0") if table.swing else ("ANGLE \u00b0", "z", "LIFT")
    theta = np.degrees(table.cam_angle)
    for blk in range(-(-rows // per_block)):
        bx, y = tx + blk * BLOCK, y0 + 3 * ROW
        labels.extend(Label(bx + dx, y, h, 2.0, "end") for dx, h in zip((10.0, 22.0, 33.0), heads))
        strokes.append(Stroke(np.array([[bx, y + 0.9], [bx + BLOCK - 3.0, y + 0.9]]), THIN))
        for i in range(blk * per_block, min(rows, (blk + 1) * per_block)):
            y += ROW
            labels += [Label(bx + 10.0, y, f"{theta[i]:.2f}", 2.0, "end"), Label(bx + 22.0, y, mm_text(table.position[i]), 2.0, "end"),
                       Label(bx + 33.0, y, mm_text(table.lift[i]), 2.0, "end")]


def _scale_bar_and_title(cam: "CamResult", run: "RunSettings", spec: DrawingSpec, sheet: str, table: BarrelTable, x1: float, y1: float,
                         right_w: float, length: float, sigma: int, fills: list, labels: list, strokes: list) -> None:
    words = ((f"CAM {cam.name}", f"SCENE {run.scene_name}"),
             (f"MATERIAL {spec.material}", f"LENGTH {mm_text(length)} mm"),
             (f"PROFILE TOLERANCE \u00b1{spec.tolerance:g} mm", f"DRAWN WITHIN {run.output.chord_tol:g} mm"),
             (f"SCALE {spec.scale}", f"SHEET {sheet} LANDSCAPE"),
             ("UNITS mm, ANGLES deg", "ROTATION " + ("COUNTER-CLOCKWISE" if sigma > 0 else "CLOCKWISE")),
             ("DRAWN BY camgen", f"BARREL CAM {cam.name}"))
    scale_bar_and_title(spec, x1 - right_w + 2.0, x1, y1, words, fills, labels, strokes)


def drawing_svg(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """``<cam>_drawing.svg`` of a barrel cam."""
    from camgen.export.drawing_render import sheet_svg

    return sheet_svg(_sheet(cam, run, fmt))


def drawing_pdf(cam: "CamResult", run: "RunSettings", fmt: str) -> bytes:
    """``<cam>_drawing.pdf`` of a barrel cam (needs the drawing extra: fpdf2)."""
    from camgen.export.drawing_render import sheet_pdf

    return sheet_pdf(_sheet(cam, run, fmt))
