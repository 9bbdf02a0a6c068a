"""The laid-out drawing (:class:`camgen.export.drawing.Sheet`) as SVG text and as PDF bytes, both at 1:1
page scale: the SVG's width and height in mm with a viewBox in mm; the PDF's page of the sheet's size
(fpdf2, unit mm).  Both are deterministic (no date, no random file id)."""
from __future__ import annotations

from typing import TYPE_CHECKING
from xml.sax.saxutils import escape, quoteattr

import numpy as np

if TYPE_CHECKING:
    from camgen.export.drawing import Sheet

__all__ = ["COORD_DECIMALS", "sheet_pdf", "sheet_svg"]

#: Decimal places of the page coordinates (mm) in both files: 1e-5 mm, far below any chord tolerance at scale.
COORD_DECIMALS = 5
#: Font of the labels: the PDF's core Helvetica (no font embedded), SVG's sans-serif; a pt is 25.4 / 72 mm.
PT_PER_MM = 72.0 / 25.4


def _num(x: float) -> str:
    text = f"{x:.{COORD_DECIMALS}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _path(points: np.ndarray, closed: bool) -> str:
    coords = [f"{_num(x)} {_num(y)}" for x, y in np.round(points, COORD_DECIMALS).tolist()]
    return "M" + " L".join(coords) + (" Z" if closed else "")


def sheet_svg(sheet: "Sheet") -> str:
    """SVG text of ``sheet``: ``width``/``height`` in mm, ``viewBox`` in mm (1 user unit = 1 mm); each
    named stroke carries its name as ``id`` (``profile``, ``base_circle``, ...)."""
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{_num(sheet.width)}mm" height="{_num(sheet.height)}mm" '
           f'viewBox="0 0 {_num(sheet.width)} {_num(sheet.height)}">',
           f"<title>{escape(sheet.name)}: manufacturing drawing</title>",
           '<rect x="0" y="0" width="100%" height="100%" fill="white"/>']
    for s in sheet.strokes:
        ident = f' id="{s.name}"' if s.name and s.name != "rotation_arrow" else ""
        dash = f' stroke-dasharray="{" ".join(_num(d) for d in s.dash)}"' if s.dash else ""
        out.append(f'<path{ident} d="{_path(s.points, s.closed)}" fill="none" stroke="black" stroke-width="{_num(s.width)}"{dash}/>')
    for f in sheet.fills:
        out.append(f'<path d="{_path(f.points, True)}" fill="black" stroke="none"/>')
    for t in sheet.labels:
        out.append(f'<text x="{_num(t.x)}" y="{_num(t.y)}" font-family="Helvetica, Arial, sans-serif" font-size="{_num(t.size)}" '
                   f'text-anchor="{t.anchor}">{escape(t.text)}</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def sheet_pdf(sheet: "Sheet") -> bytes:
    """PDF bytes of ``sheet``: one page of the sheet's size, coordinates in mm (fpdf2)."""
    from datetime import datetime, timezone

    try:
        from fpdf import FPDF
    except ImportError:
        from camgen.errors import ExportError

        raise ExportError('the "drawing_pdf" output needs fpdf2: pip install "camgen[drawing]"') from None

    pdf = FPDF(orientation="L" if sheet.width > sheet.height else "P", unit="mm",
               format=(min(sheet.width, sheet.height), max(sheet.width, sheet.height)))
    pdf.set_creation_date(datetime(2000, 1, 1, tzinfo=timezone.utc))  # deterministic bytes: no clock in the file
    pdf.set_producer("camgen")
    pdf.set_title(f"{sheet.name}: manufacturing drawing")
    pdf.set_auto_page_break(False)
    pdf.add_page()
    for s in sheet.strokes:
        pts = np.round(s.points, COORD_DECIMALS).tolist()
        with pdf.new_path() as path:
            path.auto_close = False  # fpdf2 closes every path unless told not to
            path.style.fill_color = None
            path.style.stroke_color = "#000000"
            path.style.stroke_width = s.width
            if s.dash:
                path.style.stroke_dash_pattern = list(s.dash)
            path.move_to(*pts[0])
            for x, y in pts[1:]:
                path.line_to(x, y)
            if s.closed:
                path.close()
    pdf.set_fill_color(0, 0, 0)
    for f in sheet.fills:
        pdf.polygon([tuple(p) for p in np.round(f.points, COORD_DECIMALS).tolist()], style="F")
    for t in sheet.labels:
        pdf.set_font("helvetica", size=t.size * PT_PER_MM)
        width = pdf.get_string_width(t.text)
        x = t.x - {"start": 0.0, "middle": width / 2.0, "end": width}[t.anchor]
        pdf.text(x, t.y, t.text)
    return bytes(pdf.output())
