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


def lift_csv(contour: Contour, step: float, cam: str, scene: str) -> str:
    """Polar lift table of the profile: polar angle on the cam -> radius and lift above the base radius.

    ``step`` is the angle step (rad).  The radius is the exact distance from the rotation axis
    to the profile along the ray at that polar angle (:meth:`Contour.polar_radius`); the base
    radius is the smallest distance from the axis to the profile (exact for arcs; for splines
    from the vertices of a 1e-7 mm flattening, which lie on the curve).
    """
    import math

    import numpy as np

    count = int(round(2.0 * math.pi / step))
    angle = 2.0 * math.pi * np.arange(count) / count
    radius = contour.polar_radius(angle)
    base = base_radius(contour)
    comments = [
        f"camgen polar lift table of cam '{cam}' (scene '{scene}')",
        "units: deg, mm; polar_angle_deg = polar angle on the cam (cam frame, counter-clockwise from +x), not a cam rotation",
        f"radius_mm = distance from the rotation axis to the profile; lift_mm = radius_mm - base radius {base:.9f} mm",
        f"angle step: {math.degrees(2.0 * math.pi / count):g} deg; {count} rows",
    ]
    return csv_table(comments, {"polar_angle_deg": np.degrees(angle), "radius_mm": radius, "lift_mm": radius - base})


def base_radius(contour: Contour) -> float:
    """Smallest distance (mm) from the rotation axis to the profile.

    Exact for arcs (the point of the circle nearest the axis, where it lies on the arc);
    elsewhere the smallest radius of the vertices of a 1e-7 mm flattening (which lie on the
    curve, so this is at most 1e-7 mm too large).
    """
    import math

    import numpy as np

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
