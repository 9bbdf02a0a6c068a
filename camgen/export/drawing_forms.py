"""What the manufacturing drawing shows of a cam form beyond a plate cam's profile
(:mod:`camgen.export.drawing`): a groove cam's two groove walls (full lines, the pocket's edges
on the top face), its pitch curve (dash-dot: the groove's centre line) and a note with the
groove's width and depth; a constant-breadth cam's breadth as a dimension between the two
tangents of the profile parallel to the y axis (extension lines and a dimension line with
arrowheads below the view: what a caliper across the cam measures in that direction, the same in
every direction), or a constant-diameter cam's roller spacing as a note.

Part mm in, page mm out (``page`` maps the part to the sheet at the drawing's scale).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["DIM_DROP", "EXT_GAP", "FormFeatures", "form_strokes", "mm_text"]

#: Gap (page mm) between the profile and the start of the breadth's extension lines, and how far
#: below the profile's lowest point the dimension line runs.
EXT_GAP, DIM_DROP = 1.0, 4.0


def mm_text(x: float) -> str:
    """A length in mm with three decimals (um), no "-0.000" (the drawing's numbers)."""
    return f"{round(float(x), 3) + 0.0:.3f}"


@dataclass(frozen=True)
class FormFeatures:
    """A cam form's extra features (part mm): named closed curves (n, 2) drawn as full lines
    (``walls``: a groove's edges), one drawn dash-dot (``centre_line``: a groove's pitch curve),
    notes printed in the view's top left corner, and the constant breadth (mm) to dimension."""

    walls: tuple[tuple[str, np.ndarray], ...] = ()
    centre_line: np.ndarray | None = None
    notes: tuple[str, ...] = ()
    breadth: float | None = None
    form: str = "PLATE CAM"


def form_strokes(features: FormFeatures, profile: np.ndarray, page: Callable[[np.ndarray], np.ndarray], corner: tuple[float, float],
                 stroke: Callable[..., object], arrow: Callable[[np.ndarray, np.ndarray], object],
                 label: Callable[..., object], wide: float, thin: float, dash: tuple[float, ...], fmt: Callable[[float], str]) -> None:
    """Add the features' strokes, arrowheads and labels through ``stroke(points, width, dash,
    closed, name)``, ``arrow(tip, direction)`` and ``label(x, y, text, anchor)`` (page mm);
    ``corner``: the view's top left corner on the page, where the notes go; ``profile`` the drawn
    profile (part mm); ``fmt`` the drawing's number format."""
    for name, curve in features.walls:
        stroke(page(curve), wide, (), True, name)
    if features.centre_line is not None:
        stroke(page(features.centre_line), thin, dash, True, "centre_line")
    for i, text in enumerate(features.notes):
        label(corner[0] + 3.0, corner[1] + 6.0 + 4.0 * i, text, "start")
    if features.breadth is not None:
        drawn = page(profile)
        left, right = int(np.argmin(profile[:, 0])), int(np.argmax(profile[:, 0]))  # the tangents parallel to the y axis
        bottom = float(np.max(drawn[:, 1]))  # the page's y is down
        y_dim = bottom + DIM_DROP
        for i, name in ((left, "breadth_left"), (right, "breadth_right")):
            x = float(drawn[i, 0])
            stroke(np.array([[x, drawn[i, 1] + EXT_GAP], [x, y_dim + 1.5]]), thin, (), False, name)
        xl, xr = float(drawn[left, 0]), float(drawn[right, 0])
        stroke(np.array([[xl, y_dim], [xr, y_dim]]), thin, (), False, "breadth")
        arrow(np.array([xl, y_dim]), np.array([-1.0, 0.0]))
        arrow(np.array([xr, y_dim]), np.array([1.0, 0.0]))
        label(0.5 * (xl + xr), y_dim + 3.5, f"BREADTH {fmt(features.breadth)} IN EVERY DIRECTION", "middle")
