"""CNC point lists: XY CSV at a chord tolerance."""
from __future__ import annotations

from pathlib import Path

from camgen.contour import Contour
from camgen.export.atomic import write_atomic
from camgen.export.tables import csv_table


def points_csv(contour: Contour, chord_tol: float, cam: str, scene: str) -> str:
    """CSV text of the flattened contour: ``#`` comment lines, header ``x_mm,y_mm``, one vertex a row.

    Every chord between consecutive rows (and from the last row back to the first) stays within
    ``chord_tol`` mm of the true contour.
    """
    pts = contour.flatten(chord_tol)
    comments = [
        f"camgen point list of cam '{cam}' (scene '{scene}')",
        "units: mm, cam frame (origin on the rotation axis), counter-clockwise, closed (last row joins the first)",
        f"chord tolerance: {chord_tol:g} mm; points: {len(pts)}",
    ]
    return csv_table(comments, {"x_mm": pts[:, 0], "y_mm": pts[:, 1]})


def write_points_csv(contour: Contour, path: str | Path, chord_tol: float, cam: str, scene: str) -> Path:
    """Write :func:`points_csv` to ``path`` atomically."""
    return write_atomic(path, points_csv(contour, chord_tol, cam, scene))
