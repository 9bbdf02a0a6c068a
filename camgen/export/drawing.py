"""The manufacturing drawing of a plate cam, laid out on a sheet (page mm, y down).

One layout (:func:`drawing_sheet`) of strokes, filled shapes and labels, rendered to SVG and PDF
by :mod:`camgen.export.drawing_render`: the profile at the stated scale (flattened within the
chord tolerance, so the drawn line is within scale x chord tolerance of the exact profile on the
page), the base circle (dash-dot) and its diameter, the bore and keyway (cut: full lines) and
their dimensions, the centre lines, the zero mark and the rotation arrow; on the right the
inspection table (:mod:`camgen.export.inspection`), a scale bar 100 mm long on the page (what it
is on the part at that scale), and the title block: cam, scene, material, tolerance, scale,
sheet.  Layout: ISO 5457 border 10 mm; ISO 7200 title block in the bottom right corner.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.export.drawing_forms import FormFeatures, form_strokes
from camgen.export.drawing_spec import DRAWING_SCALES, SHEETS, DrawingSpec, scale_factor
from camgen.export.inspection import InspectionTable

__all__ = ["BORDER", "DASH_DOT", "DrawingInput", "Fill", "Label", "ROW", "SCALE_BAR", "Sheet", "Stroke", "TEXT", "THIN", "TITLE_ROW",
           "TITLE_ROWS", "TITLE_WIDTH", "WIDE", "drawing_sheet", "fitting_scales", "sheet_for"]

#: Border of the drawing frame from the sheet's edge, mm (ISO 5457: 10 mm on A4 and A3).
BORDER = 10.0
#: Length of the scale bar on the page, mm (what a 100 mm ruler measures on the print).
SCALE_BAR = 100.0
#: Text height of the labels, mm (ISO 3098: 2.5 mm on A4/A3), and the height of a table row.
TEXT = 2.5
ROW = 3.0
#: Widths of the title block and of one column block of the inspection table, mm.
TITLE_WIDTH, TITLE_ROW, TITLE_ROWS = 130.0, 6.0, 6
TABLE_BLOCK = 42.0
#: Room beside the view for the dimension labels, mm, and between the profile and the rotation arrow.
LABEL_ROOM, ARROW_GAP = 46.0, 6.0
#: Line widths (ISO 128: 0.5 mm visible outlines, 0.25 mm thin lines) and the chord tolerance of drawn circles (page mm).
WIDE, THIN = 0.5, 0.25
CIRCLE_TOL = 0.005
#: Dash patterns (page mm): dash-dot for centre lines and the base circle (ISO 128 type 04).
DASH_DOT = (8.0, 1.5, 0.5, 1.5)


@dataclass(frozen=True)
class Stroke:
    """A polyline (n, 2) in page mm, closed or open, of a line width (mm) and a dash pattern (mm, empty: solid)."""

    points: np.ndarray
    width: float = THIN
    dash: tuple[float, ...] = ()
    closed: bool = False
    name: str = ""


@dataclass(frozen=True)
class Fill:
    """A filled polygon (n, 2) in page mm (arrowheads, the scale bar)."""

    points: np.ndarray
    name: str = ""


@dataclass(frozen=True)
class Label:
    """Text of height ``size`` mm with its baseline at (x, y) page mm; ``anchor``: start, middle or end."""

    x: float
    y: float
    text: str
    size: float = TEXT
    anchor: str = "start"


@dataclass(frozen=True)
class Sheet:
    """A laid-out drawing: its size (mm) and what is drawn on it."""

    width: float
    height: float
    strokes: tuple[Stroke, ...]
    fills: tuple[Fill, ...]
    labels: tuple[Label, ...]
    name: str


@dataclass(frozen=True)
class DrawingInput:
    """What the drawing shows of one cam (part mm, rad): the profile flattened within ``chord_tol``
    (closed, counter-clockwise), its base radius and largest radius, the bore diameter and keyway
    corners (4, 2) outside the bore (None: none), keyway width and reach, the zero mark point and
    rotation sense, the thickness, the inspection table and the title block's words; ``features``:
    what the cam's form adds (:mod:`camgen.export.drawing_forms`: a groove's walls, a breadth)."""

    cam: str
    scene: str
    profile: np.ndarray
    chord_tol: float
    base_radius: float
    outer_radius: float
    bore_diameter: float
    keyway: np.ndarray | None
    keyway_width: float
    keyway_reach: float
    zero: tuple[float, float]
    sigma: float
    thickness: float
    table: InspectionTable
    features: FormFeatures = FormFeatures()


# -- fitting the sheet ----------------------------------------------------------------------
def _table_blocks(rows: int, height: float) -> int:
    """Column blocks the inspection table needs in ``height`` mm (its caption and header rows above each block)."""
    per_block = int((height - 3 * ROW) // ROW)
    return -(-rows // per_block) if per_block > 0 else 10 ** 6


def _right_column(rows: int, sheet_h: float) -> tuple[float, float]:
    """Width of the right column (table, scale bar, title block) and the table's height, mm."""
    table_h = sheet_h - 2 * BORDER - TITLE_ROWS * TITLE_ROW - 16.0
    return max(TITLE_WIDTH, _table_blocks(rows, table_h) * TABLE_BLOCK), table_h


def _view_size(outer_radius: float, k: float) -> tuple[float, float]:
    """Width and height (mm) the plan view needs at scale ``k``: the profile, the rotation arrow and the labels beside."""
    half = k * outer_radius + ARROW_GAP + 6.0
    return 2.0 * (half + LABEL_ROOM), 2.0 * half + 8.0


def _fits(outer_radius: float, rows: int, k: float, sheet: str) -> bool:
    w, h = SHEETS[sheet]
    right, _ = _right_column(rows, h)
    view_w, view_h = _view_size(outer_radius, k)
    return view_w + right + 5.0 <= w - 2 * BORDER and view_h <= h - 2 * BORDER


def sheet_for(outer_radius: float, rows: int, spec: DrawingSpec) -> str | None:
    """The sheet the drawing of a cam of ``outer_radius`` mm with a table of ``rows`` rows takes at
    ``spec.scale`` (``spec.sheet``, or for ``"auto"`` A4 if it fits, else A3), or None if it fits none."""
    k = scale_factor(spec.scale)
    for sheet in (SHEETS if spec.sheet == "auto" else (spec.sheet,)):
        if _fits(outer_radius, rows, k, sheet):
            return sheet
    return None


def fitting_scales(outer_radius: float, rows: int, sheet: str) -> tuple[str, ...]:
    """The scales (:data:`DRAWING_SCALES`, largest first) at which the drawing fits ``sheet`` (``"auto"``: A3, the larger)."""
    size = "A3" if sheet == "auto" else sheet
    return tuple(s for s in DRAWING_SCALES if _fits(outer_radius, rows, scale_factor(s), size))


# -- drawing helpers -----------------------------------------------------------------------
def _circle(centre: tuple[float, float], radius: float, start: float = 0.0, sweep: float = 2 * math.pi) -> np.ndarray:
    """Points (page mm) of a circle or arc (angles rad, counter-clockwise on the part: the page's y is down),
    chords within :data:`CIRCLE_TOL`."""
    step = 2.0 * math.acos(max(0.0, 1.0 - CIRCLE_TOL / radius)) if radius > CIRCLE_TOL else math.pi / 2
    n = max(8, int(math.ceil(abs(sweep) / step)))
    a = start + sweep * np.arange(n + 1) / n
    return np.column_stack([centre[0] + radius * np.cos(a), centre[1] - radius * np.sin(a)])


def _arrowhead(tip: np.ndarray, direction: np.ndarray, name: str = "") -> Fill:
    """A filled arrowhead (3 mm long, 1 mm wide) at ``tip`` pointing along ``direction`` (page)."""
    d = direction / np.hypot(*direction)
    n = np.array([-d[1], d[0]])
    back = tip - 3.0 * d
    return Fill(np.array([tip, back + 0.5 * n, back - 0.5 * n]), name)


def _leader(start: np.ndarray, angle: float, reach: float, text: str, strokes: list, fills: list, labels: list) -> None:
    """A leader from ``start`` (page) out along the part's polar ``angle`` to the radius ``reach`` from the view
    centre's side, a shoulder and ``text``; the arrowhead on ``start``."""
    d = np.array([math.cos(angle), -math.sin(angle)])
    end = start + reach * d
    side = 1.0 if d[0] >= 0 else -1.0
    shoulder = end + np.array([side * 4.0, 0.0])
    strokes.append(Stroke(np.array([start, end, shoulder]), THIN))
    fills.append(_arrowhead(start, -d))
    labels.append(Label(float(shoulder[0] + side * 1.0), float(shoulder[1] + TEXT / 2 - 0.2), text,
                        anchor="start" if side > 0 else "end"))


def _fmt(x: float) -> str:
    """Three decimals (um), no "-0.000"."""
    return f"{round(float(x), 3) + 0.0:.3f}"


# -- the sheet -----------------------------------------------------------------------------
def drawing_sheet(data: DrawingInput, spec: DrawingSpec, sheet: str) -> Sheet:
    """The drawing of ``data`` at ``spec.scale`` on ``sheet`` (landscape; :func:`sheet_for` says it fits)."""
    k = scale_factor(spec.scale)
    width, height = SHEETS[sheet]
    rows = data.table.cam_angle.size
    right_w, table_h = _right_column(rows, height)
    strokes: list[Stroke] = []
    fills: list[Fill] = []
    labels: list[Label] = []
    # the frame
    x0, y0, x1, y1 = BORDER, BORDER, width - BORDER, height - BORDER
    strokes.append(Stroke(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]), WIDE, closed=True, name="frame"))
    # the plan view, centred in the space left of the right column
    view_right = x1 - right_w - 5.0
    cx, cy = (x0 + view_right) / 2.0, (y0 + y1) / 2.0
    centre = np.array([cx, cy])

    def page(p: np.ndarray) -> np.ndarray:
        return np.column_stack([cx + k * p[:, 0], cy - k * p[:, 1]])

    strokes.append(Stroke(page(data.profile), WIDE, closed=True, name="profile"))
    reach = k * data.outer_radius
    # centre lines through the axis, 3 mm past the profile
    strokes.append(Stroke(np.array([[cx - reach - 3.0, cy], [cx + reach + 3.0, cy]]), THIN, DASH_DOT, name="centre_x"))
    strokes.append(Stroke(np.array([[cx, cy - reach - 3.0], [cx, cy + reach + 3.0]]), THIN, DASH_DOT, name="centre_y"))
    # the base circle and its diameter
    rb = k * data.base_radius
    strokes.append(Stroke(_circle((cx, cy), rb), THIN, DASH_DOT, closed=True, name="base_circle"))
    out = reach + 8.0
    a = math.radians(135.0)
    _leader(centre + rb * np.array([math.cos(a), -math.sin(a)]), a, out - rb, f"\u00d8{_fmt(2 * data.base_radius)} BASE CIRCLE",
            strokes, fills, labels)
    # the bore and the keyway (cut: full lines), dimensioned by leaders
    if data.bore_diameter > 0:
        rbore = k * data.bore_diameter / 2.0
        strokes.append(Stroke(_circle((cx, cy), rbore), WIDE, closed=True, name="bore"))
        a = math.radians(225.0)
        _leader(centre + rbore * np.array([math.cos(a), -math.sin(a)]), a, out - rbore, f"\u00d8{_fmt(data.bore_diameter)} BORE",
                strokes, fills, labels)
    if data.keyway is not None:
        strokes.append(Stroke(page(data.keyway), WIDE, name="keyway"))
        corner = data.keyway[1:3].mean(axis=0)
        a = math.atan2(corner[1], corner[0]) - math.radians(60.0)
        start = page(corner[None, :])[0]
        _leader(start, a, out - k * data.keyway_reach * 0.5, f"KEYWAY {_fmt(data.keyway_width)} WIDE, BOTTOM "
                f"{_fmt(data.keyway_reach)} FROM AXIS", strokes, fills, labels)
    # the zero mark: the ray from the axis through the follower's contact at cam angle 0
    zero = np.array(data.zero)
    phi0 = math.atan2(zero[1], zero[0])
    u = np.array([math.cos(phi0), -math.sin(phi0)])
    strokes.append(Stroke(np.array([centre, centre + (reach + ARROW_GAP + 2.0) * u]), THIN, name="zero_mark"))
    tip = centre + (reach + ARROW_GAP + 4.5) * u
    labels.append(Label(float(tip[0]), float(tip[1] + TEXT / 2), "0\u00b0", anchor="middle"))
    # the rotation arrow: an arc outside the profile from the zero mark 40 deg in the sense of rotation
    r_arrow = reach + ARROW_GAP
    sweep = data.sigma * math.radians(40.0)
    arc = _circle((cx, cy), r_arrow, phi0 + data.sigma * math.radians(8.0), sweep)
    strokes.append(Stroke(arc, THIN, name="rotation_arrow"))
    fills.append(_arrowhead(arc[-1], arc[-1] - arc[-3], "rotation_arrow"))
    mid = arc[len(arc) // 2]
    labels.append(Label(float(mid[0] + 2.0 * (mid[0] - cx) / r_arrow), float(mid[1] + 2.0 * (mid[1] - cy) / r_arrow + 1.0),
                        "ROTATION " + ("CCW" if data.sigma > 0 else "CW"), anchor="start" if mid[0] >= cx else "end"))
    # the form's features: a groove's walls and pitch curve, a constant breadth (camgen.export.drawing_forms)
    form_strokes(data.features, data.profile, page, (x0, y0), lambda p, w, d, c, n: strokes.append(Stroke(p, w, d, c, n)),
                 lambda tip, d: fills.append(_arrowhead(tip, d)), lambda x, y, t, a: labels.append(Label(x, y, t, anchor=a)),
                 WIDE, THIN, DASH_DOT, _fmt)
    _table(data, spec, x1 - right_w, y0, right_w, table_h, labels, strokes)
    _scale_bar(spec, x1 - right_w, y1 - TITLE_ROWS * TITLE_ROW - 6.0, fills, labels, strokes)
    _title_block(data, spec, sheet, x1 - TITLE_WIDTH, y1 - TITLE_ROWS * TITLE_ROW, x1, labels, strokes)
    return Sheet(width, height, tuple(strokes), tuple(fills), tuple(labels), data.cam)


def _table(data: DrawingInput, spec: DrawingSpec, left: float, top: float, width: float, height: float, labels: list,
           strokes: list) -> None:
    """The inspection table: a caption, then column blocks of cam angle, centre radius and lift."""
    t = data.table
    probe = f"ROLLER R{_fmt(t.roller_radius)}" if t.roller_radius > 0 else "PROBE POINT"
    labels.append(Label(left, top + ROW, f"INSPECTION: {probe} ON THE RAY THROUGH THE 0\u00b0 MARK", 2.2))
    labels.append(Label(left, top + 2 * ROW, f"CENTRE RADIUS R FROM THE AXIS, TOLERANCE \u00b1{spec.tolerance:g}", 2.2))
    per_block = int((height - 3 * ROW) // ROW)
    theta, radius, lift = np.degrees(t.cam_angle), t.centre_radius, t.lift
    for b in range(-(-theta.size // per_block)):
        bx = left + b * TABLE_BLOCK
        y = top + 3 * ROW
        for text, dx in (("ANGLE \u00b0", 11.0), ("R", 26.0), ("LIFT", 39.0)):
            labels.append(Label(bx + dx, y, text, 2.0, "end"))
        strokes.append(Stroke(np.array([[bx, y + 0.9], [bx + TABLE_BLOCK - 3.0, y + 0.9]]), THIN))
        for i in range(b * per_block, min(theta.size, (b + 1) * per_block)):
            y += ROW
            labels.append(Label(bx + 11.0, y, f"{theta[i]:.2f}", 2.0, "end"))
            labels.append(Label(bx + 26.0, y, _fmt(radius[i]), 2.0, "end"))
            labels.append(Label(bx + 39.0, y, _fmt(lift[i]), 2.0, "end"))


def _scale_bar(spec: DrawingSpec, left: float, base: float, fills: list, labels: list, strokes: list) -> None:
    """A bar :data:`SCALE_BAR` mm long on the page (3 mm high), labelled with its length on the part."""
    part = SCALE_BAR / scale_factor(spec.scale)
    x = left + 2.0
    fills.append(Fill(np.array([[x, base - 3.0], [x + SCALE_BAR, base - 3.0], [x + SCALE_BAR, base], [x, base]]), "scale_bar"))
    labels.append(Label(x, base - 4.0, f"SCALE BAR: {SCALE_BAR:g} mm ON THE PAGE = {part:g} mm ON THE PART (SCALE {spec.scale})", 2.2))


def _title_block(data: DrawingInput, spec: DrawingSpec, sheet: str, left: float, top: float, right: float, labels: list,
                 strokes: list) -> None:
    """The title block: cam, scene, material, tolerances, scale, sheet, units."""
    bottom = top + TITLE_ROWS * TITLE_ROW
    strokes.append(Stroke(np.array([[left, top], [right, top], [right, bottom], [left, bottom]]), WIDE, closed=True, name="title"))
    rows = (
        (f"CAM {data.cam}", f"SCENE {data.scene}"),
        (f"MATERIAL {spec.material}", f"THICKNESS {_fmt(data.thickness)} mm"),
        (f"PROFILE TOLERANCE \u00b1{spec.tolerance:g} mm", f"DRAWN WITHIN {data.chord_tol:g} mm"),
        (f"SCALE {spec.scale}", f"SHEET {sheet} LANDSCAPE"),
        ("UNITS mm, ANGLES deg", "ROTATION " + ("COUNTER-CLOCKWISE" if data.sigma > 0 else "CLOCKWISE")),
        ("DRAWN BY camgen", f"{data.features.form} {data.cam}"),
    )
    for i, (a, b) in enumerate(rows):
        y = top + (i + 1) * TITLE_ROW
        if i + 1 < TITLE_ROWS:
            strokes.append(Stroke(np.array([[left, y], [right, y]]), THIN))
        labels.append(Label(left + 1.5, y - 1.8, a, 2.5))
        labels.append(Label(left + 66.5, y - 1.8, b, 2.5))
    strokes.append(Stroke(np.array([[left + 65.0, top], [left + 65.0, bottom]]), THIN))
