"""CNC point lists (XY CSV at a chord tolerance) and polar lift tables of a profile.

Each table's meaning and settings are stated by its ``*_metadata`` function, which report.json's
``tables`` object holds (:mod:`camgen.export.tablemeta`); the CSV itself is a header row and
numbers (:func:`camgen.export.tables.csv_table`).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from camgen.contour import Contour
from camgen.export.atomic import write_atomic
from camgen.export.tables import csv_table

if TYPE_CHECKING:
    from camgen.kinds.base import Pocket

__all__ = [
    "LIFT_COLUMNS", "POCKET_POINTS_COLUMNS", "POINTS_COLUMNS", "base_radius", "lift_angles", "lift_csv", "lift_metadata", "points_csv",
    "points_metadata", "wall_column", "write_points_csv",
]

#: Columns of the point list (``<cam>_points.csv``) and what they hold.
POINTS_COLUMNS = {
    "x_mm": "x of a vertex of the profile polygon in the cam frame (origin on the rotation axis), mm",
    "y_mm": "y of that vertex in the cam frame, mm",
}
#: Columns of the point list of a body with pockets: the vertices and the wall each lies on.
POCKET_POINTS_COLUMNS = {
    **POINTS_COLUMNS,
    "wall": "the loop the vertex lies on: PROFILE (the body's outline) or a pocket wall (its DXF layer name)",
}
#: Columns of the polar lift table (``<cam>_lift.csv``) and what they hold.
LIFT_COLUMNS = {
    "polar_angle_deg": "polar angle on the cam (cam frame, counter-clockwise from +x; a direction on the cam, not a cam rotation), deg",
    "radius_mm": "distance from the rotation axis to the profile along the ray at that polar angle, mm",
    "lift_mm": "radius_mm minus the base radius (base_radius_mm: the smallest distance from the axis to the profile), mm",
}


def points_csv(contour: Contour, chord_tol: float, pockets: "Sequence[Pocket]" = ()) -> str:
    """CSV text of the flattened contour: header ``x_mm,y_mm``, one vertex a row, counter-clockwise.

    Every chord between consecutive rows (and from the last row back to the first) stays within
    ``chord_tol`` mm of the true contour.

    A body with ``pockets`` (:class:`camgen.kinds.base.Pocket`) has a third column ``wall``: the
    outline's rows (``PROFILE``), then each wall's (its layer name), each a closed
    counter-clockwise polygon of its own within ``chord_tol`` mm (its last row joins its first).
    """
    pts = contour.flatten(chord_tol)
    if not pockets:
        return csv_table(dict(zip(POINTS_COLUMNS, (pts[:, 0], pts[:, 1]))))
    from camgen.errors import ExportError
    from camgen.export.dxf import PROFILE_LAYER
    from camgen.export.pocket import wall_loops
    from camgen.export.tables import format_rows

    rows = []
    for layer, loop in [(PROFILE_LAYER, pts), *wall_loops(pockets, chord_tol)]:
        if not np.all(np.isfinite(loop)):
            raise ExportError(f"point list: the {layer} polygon holds non-finite values")
        # the numbers as csv_table writes them (9 decimals, no -0), then the wall's name
        rows.append(format_rows(np.round(loop, 9) + 0.0, "%.9f,%.9f," + layer.replace("%", "%%")))
    return ",".join(POCKET_POINTS_COLUMNS) + "\n" + "".join(rows)


def points_metadata(chord_tol: float, pockets: "Sequence[Pocket]" = ()) -> dict[str, Any]:
    """What :func:`points_csv` holds (report.json ``tables``); with ``pockets`` the ``wall``
    column and the walls, in the order of the rows."""
    if not pockets:
        return {
            "content": "XY point list of the profile: the vertices of a polygon within chord_tol_mm of it, counter-clockwise, closed "
                       "(the last row joins the first)",
            "columns": dict(POINTS_COLUMNS),
            "chord_tol_mm": float(chord_tol),
        }
    from camgen.export.dxf import PROFILE_LAYER

    return {
        "content": "XY point lists of the body's outline (wall PROFILE) and of each pocket wall (wall: its DXF layer), in that order: "
                   "each the vertices of a polygon within chord_tol_mm of it, counter-clockwise, closed (a wall's last row joins "
                   "its first)",
        "columns": dict(POCKET_POINTS_COLUMNS),
        "walls": [PROFILE_LAYER] + [wall.layer for pocket in pockets for wall in pocket.walls],
        "pockets": [{"name": pocket.name, "depth_mm": float(pocket.depth), "walls": [wall.layer for wall in pocket.walls]}
                    for pocket in pockets],
        "chord_tol_mm": float(chord_tol),
    }


def write_points_csv(contour: Contour, path: str | Path, chord_tol: float, pockets: "Sequence[Pocket]" = ()) -> Path:
    """Write :func:`points_csv` to ``path`` atomically."""
    return write_atomic(path, points_csv(contour, chord_tol, pockets))


def lift_angles(step: float) -> np.ndarray:
    """Polar angles (rad) of the lift table: the whole turn in equal steps, the nearest to
    ``step`` rad that divides it."""
    count = int(round(2.0 * math.pi / step))
    return 2.0 * math.pi * np.arange(count) / count


def wall_column(layer: str) -> str:
    """The lift table's column of a pocket wall: its layer in lower case, ``_radius_mm`` after it
    (``GROOVE_OUTER`` -> ``groove_outer_radius_mm``; characters a column name cannot hold: ``_``)."""
    import re

    name = re.sub(r"[^a-z0-9_]", "_", layer.lower())
    return (name if name[:1].isalpha() else f"wall_{name}") + "_radius_mm"


def lift_csv(contour: Contour, step: float, pockets: "Sequence[Pocket]" = ()) -> str:
    """Polar lift table of the profile: polar angle on the cam -> radius and lift above the base radius.

    ``step`` is the angle step (rad, :func:`lift_angles`).  The radius is the exact distance
    from the rotation axis to the profile along the ray at that polar angle
    (:meth:`Contour.polar_radius`); the base radius is :func:`base_radius`.

    A body with ``pockets`` has one more column per pocket wall (:func:`wall_column`): the
    distance from the axis to the wall along the same ray; :class:`GeometryError` naming the
    wall when a ray from the axis does not meet it exactly once (a slot beside the axis).
    """
    from camgen.errors import GeometryError

    angle = lift_angles(step)
    radius = contour.polar_radius(angle)
    columns = dict(zip(LIFT_COLUMNS, (np.degrees(angle), radius, radius - base_radius(contour))))
    for pocket in pockets:
        for wall in pocket.walls:
            try:
                columns[wall_column(wall.layer)] = wall.contour.polar_radius(angle)
            except GeometryError as exc:
                raise GeometryError(f"wall {wall.layer}: {exc}") from None
    return csv_table(columns)


def lift_metadata(contour: Contour, step: float, pockets: "Sequence[Pocket]" = ()) -> dict[str, Any]:
    """What :func:`lift_csv` holds (report.json ``tables``): its angle step and base radius (and
    a column per pocket wall)."""
    count = lift_angles(step).size
    columns = dict(LIFT_COLUMNS)
    for pocket in pockets:
        for wall in pocket.walls:
            columns[wall_column(wall.layer)] = (f"distance from the rotation axis to the pocket wall {wall.layer} along the ray at "
                                                "that polar angle, mm")
    return {
        "content": "polar lift table of the profile: polar angle on the cam -> its radius and the lift above the base radius"
                   + ("; and the radius of each pocket wall" if pockets else ""),
        "columns": columns,
        "angle_step_deg": 360.0 / count,
        "base_radius_mm": base_radius(contour),
    }


def base_radius(contour: Contour) -> float:
    """Smallest distance (mm) from the rotation axis to the profile.

    Exact for arcs (the point of the circle nearest the axis, where it lies on the arc);
    elsewhere the smallest radius of the vertices of a 1e-7 mm flattening (which lie on the
    curve, so this is at most 1e-7 mm too large).
    """
    from camgen.contour import Arc
    from camgen.geometry import angle_in_sweep

    candidates = [float(np.min(np.hypot(*contour.flatten(1e-7).T)))]
    for seg in contour.segments:
        if isinstance(seg, Arc):
            distance = math.hypot(*seg.center)
            toward_axis = math.atan2(-seg.center[1], -seg.center[0]) if distance > 0 else seg.start_angle
            if angle_in_sweep(np.array([toward_axis]), seg.start_angle, seg.sweep)[0]:
                candidates.append(abs(distance - seg.radius))
    return min(candidates)
