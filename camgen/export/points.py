"""CNC point lists: XY CSV at a chord tolerance."""
from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from camgen.contour import Contour
from camgen.export.atomic import write_atomic


def points_csv(contour: Contour, chord_tol: float, cam: str, scene: str) -> str:
    """CSV text of the flattened contour: ``#`` comment lines, header ``x_mm,y_mm``, one vertex a row.

    Every chord between consecutive rows (and from the last row back to the first) stays within
    ``chord_tol`` mm of the true contour.
    """
    pts = contour.flatten(chord_tol)
    header = (
        f"# camgen point list of cam '{cam}' (scene '{scene}')\n"
        "# units: mm, cam frame (origin on the rotation axis), counter-clockwise, closed (last row joins the first)\n"
        f"# chord tolerance: {chord_tol:g} mm; points: {len(pts)}\n"
        "x_mm,y_mm\n"
    )
    body = io.StringIO()
    np.savetxt(body, np.round(pts, 9) + 0.0, fmt="%.9f", delimiter=",")  # + 0.0 turns -0.0 into 0.0
    return header + body.getvalue()


def write_points_csv(contour: Contour, path: str | Path, chord_tol: float, cam: str, scene: str) -> Path:
    """Write :func:`points_csv` to ``path`` atomically."""
    return write_atomic(path, points_csv(contour, chord_tol, cam, scene))
