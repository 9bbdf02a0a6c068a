"""The sheet of a drawing built view by view (a linear cam's plate, a barrel cam's side view and
developed groove): the right column's width for an inspection table of so many rows, the choice
of the sheet at the stated scale or the refusal naming the largest scale that fits, and the
frame.  The disk cam's drawing (:mod:`camgen.export.drawing`) sizes its own plan view."""
from __future__ import annotations

from typing import Callable

import numpy as np

from camgen.errors import ParameterError
from camgen.export.drawing import BORDER, ROW, SCALE_BAR, THIN, TITLE_ROW, TITLE_ROWS, TITLE_WIDTH, WIDE, Fill, Label, Stroke
from camgen.export.drawing_spec import DRAWING_SCALES, SHEETS, DrawingSpec, scale_factor

__all__ = ["choose_sheet", "frame", "right_width", "scale_bar_and_title"]


def right_width(rows: int, height: float, block: float) -> tuple[float, int]:
    """The right column's width (mm: the title block's, or as many table blocks ``block`` mm wide
    as ``rows`` rows need on a sheet ``height`` mm high) and the rows a block holds."""
    per_block = int((height - 2 * BORDER - TITLE_ROWS * TITLE_ROW - 16.0 - 3 * ROW) // ROW)
    blocks = -(-rows // per_block) if per_block > 0 else 10**6
    return max(TITLE_WIDTH, blocks * block), per_block


def choose_sheet(fits: Callable[[float, str], bool], spec: DrawingSpec, cam: str, fmt: str, views: str) -> str:
    """The sheet (``spec.sheet``, or for ``"auto"`` A4 where the views fit, else A3) on which
    ``fits(scale factor, sheet)``; else the :class:`ParameterError` naming the largest scale that
    fits (``output.drawing_scale``) or, at none, ``output.formats``.  ``views``: what does not fit,
    with its size in mm, for the message."""
    k = scale_factor(spec.scale)
    sheet = next((s for s in (SHEETS if spec.sheet == "auto" else (spec.sheet,)) if fits(k, s)), None)
    if sheet is not None:
        return sheet
    where = "A3" if spec.sheet == "auto" else spec.sheet
    scales = [s for s in DRAWING_SCALES if fits(scale_factor(s), where)]
    if scales:
        raise ParameterError("output.drawing_scale", spec.scale, f"{scales[0]} or smaller for cam '{cam}' on the {where} sheet", views)
    raise ParameterError("output.formats", fmt, f"formats without {fmt} for cam '{cam}'",
                         f"{views}: they do not fit the {where} sheet at any scale")


def frame(width: float, height: float) -> tuple[Stroke, tuple[float, float, float, float]]:
    """The frame of a ``width`` x ``height`` mm sheet, ``BORDER`` in, and its bounds (x0, y0, x1, y1)."""
    x0, y0, x1, y1 = BORDER, BORDER, width - BORDER, height - BORDER
    return Stroke(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]), WIDE, closed=True, name="frame"), (x0, y0, x1, y1)


def scale_bar_and_title(spec: DrawingSpec, bar_x: float, x1: float, y1: float, words: tuple[tuple[str, str], ...],
                        fills: list[Fill], labels: list[Label], strokes: list[Stroke]) -> None:
    """The scale bar (``SCALE_BAR`` mm on the page, left end at ``bar_x``) above the title block,
    and the title block in the frame's lower right corner (``x1``, ``y1``): ``TITLE_ROWS`` rows of
    two cells, ``words`` (left, right) in each; appended to ``fills``, ``labels``, ``strokes``."""
    k = scale_factor(spec.scale)
    base = y1 - TITLE_ROWS * TITLE_ROW - 6.0
    fills.append(Fill(np.array([[bar_x, base - 3.0], [bar_x + SCALE_BAR, base - 3.0], [bar_x + SCALE_BAR, base], [bar_x, base]]),
                      "scale_bar"))
    labels.append(Label(bar_x, base - 4.0, f"SCALE BAR: {SCALE_BAR:g} mm ON THE PAGE = {SCALE_BAR / k:g} mm ON THE PART "
                        f"(SCALE {spec.scale})", 2.2))
    tl, tt = x1 - TITLE_WIDTH, y1 - TITLE_ROWS * TITLE_ROW
    strokes.append(Stroke(np.array([[tl, tt], [x1, tt], [x1, y1], [tl, y1]]), WIDE, closed=True, name="title"))
    for i, (left, right) in enumerate(words):
        y = tt + (i + 1) * TITLE_ROW
        if i + 1 < TITLE_ROWS:
            strokes.append(Stroke(np.array([[tl, y], [x1, y]]), THIN))
        labels += [Label(tl + 1.5, y - 1.8, left, 2.5), Label(tl + 66.5, y - 1.8, right, 2.5)]
    strokes.append(Stroke(np.array([[tl + 65.0, tt], [tl + 65.0, y1]]), THIN))
