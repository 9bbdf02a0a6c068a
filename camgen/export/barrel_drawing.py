"""A barrel cam's drawing and point list (the form's own writers, :mod:`camgen.forms.barrel`).

``dxf``: the developed drawing at the mean radius R_m: the cam's surface at R_m unrolled, x = R_m
phi (mm, the cam's polar angle phi from 0 to 2 pi) and z along the axis (mm, 0 the bottom face):
the pitch curve (the roller axis' point at R_m, layer PITCH_DEVELOPED), both walls' sections at
R_m (WALL_UPPER_DEVELOPED, WALL_LOWER_DEVELOPED), the developed cylinder (OUTLINE_DEVELOPED: x from
0 to 2 pi R_m, z from 0 to the length) and a TEXT (layer NOTES) saying so.  Each curve is a
polyline whose chords stay within ``output.chord_tol_mm`` of it.

``points``: the walls' points at the root, mean and rim radius (cam frame, mm; phi in deg), each
closed section a run of rows whose chords stay within ``output.chord_tol_mm`` of the exact wall;
report.json's ``tables`` says what the columns are (:func:`points_metadata`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from camgen.errors import ExportError

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.synthesis.barrel import BarrelGroove
    from camgen.writers import RunSettings

__all__ = ["DEVELOPED_LAYERS", "MAX_CURVE_POINTS", "POINTS_COLUMNS", "developed_curves", "dxf", "points", "points_metadata", "polyline",
           "wall_sections"]

#: Layers of the developed drawing and their ACI colours.
DEVELOPED_LAYERS = {"OUTLINE_DEVELOPED": 7, "PITCH_DEVELOPED": 4, "WALL_UPPER_DEVELOPED": 5, "WALL_LOWER_DEVELOPED": 1, "NOTES": 8}
#: A rib cam's drawing: its faces' layers instead of the walls' (same colours).
RIB_LAYERS = {"OUTLINE_DEVELOPED": 7, "PITCH_DEVELOPED": 4, "RIB_UPPER_DEVELOPED": 5, "RIB_LOWER_DEVELOPED": 1, "NOTES": 8}
#: Columns of the point list.
POINTS_COLUMNS = ("wall", "radius_mm", "phi_deg", "x_mm", "y_mm", "z_mm")
#: Wall names of the point list: side +1, -1.
WALL_NAMES = {1: "UPPER", -1: "LOWER"}
#: A rib's face names in the point list.
RIB_NAMES = {1: "RIB_UPPER", -1: "RIB_LOWER"}
#: Points of one curve to start from (every 0.5 deg) and the most any curve may get: the sampling
#: doubles until every chord is within the tolerance, and stops with an error at the cap (a bound
#: before the work: 2^21 points, 48 MB of text in the point list).
START_POINTS = 720
MAX_CURVE_POINTS = 1 << 21


def _groove(cam: "CamResult") -> Any:
    """The surfaces the drawing shows: the rib (track = "rib": its faces as the walls) or the groove."""
    groove = getattr(cam.built, "groove", None)
    assert groove is not None, f"cam {cam.name!r} is not a barrel cam"
    rib = getattr(cam.built, "rib", None)
    return rib if rib is not None else groove


def _is_rib(surfaces: Any) -> bool:
    return hasattr(surfaces, "roller_offset")


def polyline(curve: Callable[[np.ndarray], np.ndarray], chord_tol: float, what: str) -> np.ndarray:
    """Points (n + 1, k) of ``curve`` (u in [0, 1] -> (len(u), k) points, mm) at n uniform
    parameter steps, n doubled from :data:`START_POINTS` until the curve's points at the quarter,
    middle and three-quarter parameter of every step are within ``chord_tol`` (mm) of its chord;
    ExportError naming ``what`` beyond :data:`MAX_CURVE_POINTS`."""
    n = START_POINTS
    while True:
        u = np.linspace(0.0, 1.0, n + 1)
        pts = curve(u)
        a, b = pts[:-1], pts[1:]
        ab = b - a
        length2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
        worst = 0.0
        for f in (0.25, 0.5, 0.75):
            q = curve(u[:-1] + f / n) - a
            t = np.clip(np.einsum("ij,ij->i", q, ab) / length2, 0.0, 1.0)
            worst = max(worst, float(np.max(np.linalg.norm(q - t[:, None] * ab, axis=1))))
        if worst <= chord_tol:
            return pts
        n *= 2
        if n > MAX_CURVE_POINTS:
            raise ExportError(f"the {what} needs more than {MAX_CURVE_POINTS} points within chord_tol_mm = {chord_tol:g} mm "
                              "(a larger output.chord_tol_mm)")


def developed_curves(groove: Any, chord_tol: float) -> dict[str, np.ndarray]:
    """The developed drawing's curves (layer -> (n, 2) points, mm): the pitch curve over one turn
    from its point at x = 0 (translating; an oscillating roller's tangential offset shifts it), and
    both walls' sections at the mean radius over x = 0 .. 2 pi R_m (a rib, :class:`BarrelRib`:
    its faces' sections, layers RIB_UPPER_DEVELOPED and RIB_LOWER_DEVELOPED)."""
    rm, sigma = groove.layout.mean_radius, groove.layout.sigma
    turn = 2.0 * math.pi

    def pitch(u: np.ndarray) -> np.ndarray:
        x, z = groove.pitch_developed(-sigma * turn * u)  # theta = -sigma phi: the cam's polar angle phi = 2 pi u passes
        return np.stack([x, z], axis=1)

    def wall(side: int) -> Callable[[np.ndarray], np.ndarray]:
        def at(u: np.ndarray) -> np.ndarray:
            phi = turn * u
            return np.stack([rm * phi, groove.wall_height(side, np.asarray(rm), phi)], axis=1)
        return at

    out = {"PITCH_DEVELOPED": polyline(pitch, chord_tol, "developed pitch curve")}
    names = ("RIB_UPPER_DEVELOPED", "RIB_LOWER_DEVELOPED") if _is_rib(groove) else ("WALL_UPPER_DEVELOPED", "WALL_LOWER_DEVELOPED")
    for side, layer in zip((1, -1), names):
        out[layer] = polyline(wall(side), chord_tol, f"{layer} section at the mean radius")
    return out


def dxf(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """The developed drawing at the mean radius (module notes)."""
    from camgen.export.dxfwriter import DxfDocument

    groove = _groove(cam)
    rm, length = groove.layout.mean_radius, groove.length
    span = 2.0 * math.pi * rm
    chord = run.output.chord_tol
    curves = developed_curves(groove, chord)
    doc = DxfDocument(insunits=4, measurement=1, lunits=2, luprec=6, version=run.output.dxf_version)
    height = max(2.5, round(0.04 * length, 1))
    lo_z = min(0.0, float(min(float(c[:, 1].min()) for c in curves.values())))
    hi_z = max(length, float(max(float(c[:, 1].max()) for c in curves.values())))
    doc.set_extents(min(0.0, float(curves["PITCH_DEVELOPED"][:, 0].min())), lo_z - 2.0 * height,
                    max(span, float(curves["PITCH_DEVELOPED"][:, 0].max())), hi_z)
    doc.add_custom_property("camgen_developed_radius_mm", repr(float(rm)))
    doc.add_custom_property("camgen_chord_tol_mm", repr(float(chord)))
    for name, colour in (RIB_LAYERS if _is_rib(groove) else DEVELOPED_LAYERS).items():
        doc.add_layer(name, colour)
    doc.add_lwpolyline([(0.0, 0.0), (span, 0.0), (span, length), (0.0, length)], True, "OUTLINE_DEVELOPED")
    for layer, pts in curves.items():
        doc.add_lwpolyline(pts, False, layer)
    doc.add_text((0.0, -1.5 * height), height, f"{cam.name}: developed at mean radius R_m = {rm:.6g} mm (x = R_m * polar angle, "
                 f"z along the axis from the bottom face; {'rib height' if _is_rib(groove) else 'groove depth'} "
                 f"{groove.rim_radius - groove.root_radius:.6g} mm; "
                 f"chords within {chord:g} mm)", "NOTES")
    return doc.to_text()


def wall_sections(groove: Any, chord_tol: float) -> list[tuple[str, float, np.ndarray]]:
    """The walls' closed sections at the root, mean and rim radius: (wall, radius mm, points (n, 4):
    phi rad, x, y, z mm), phi from 0 (included) to 2 pi (excluded: the section is closed); a rib's
    faces named RIB_UPPER and RIB_LOWER."""
    out = []
    names = RIB_NAMES if _is_rib(groove) else WALL_NAMES
    for r in (groove.root_radius, groove.layout.mean_radius, groove.rim_radius):
        for side in (1, -1):
            def at(u: np.ndarray, r: float = r, side: int = side) -> np.ndarray:
                phi = 2.0 * math.pi * u
                return np.stack([r * np.cos(phi), r * np.sin(phi), groove.wall_height(side, np.asarray(r), phi)], axis=1)

            pts = polyline(at, chord_tol, f"{names[side].lower()} wall at radius {r:g} mm")[:-1]
            phi = 2.0 * math.pi * np.arange(len(pts)) / len(pts)
            out.append((names[side], r, np.column_stack([phi, pts])))
    return out


def points(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """The walls' point list (module notes): the header row, then the rows (9 decimals); what
    they are is in report.json's ``tables`` (:func:`points_metadata`)."""
    from camgen.export.tables import format_rows

    groove = _groove(cam)
    rows = []
    for wall, r, pts in wall_sections(groove, run.output.chord_tol):
        table: Any = np.column_stack([np.full(len(pts), r), np.degrees(pts[:, 0]), pts[:, 1:]])
        if not np.all(np.isfinite(table)):
            raise ExportError(f"point list: the {wall} wall at radius {r:g} mm holds non-finite values")
        rows.append(format_rows(np.round(table, 9) + 0.0, wall + ",%.9f,%.9f,%.9f,%.9f,%.9f"))
    return ",".join(POINTS_COLUMNS) + "\n" + "".join(rows)


def points_metadata(cam: "CamResult", chord_tol: float) -> dict[str, Any]:
    """What :func:`points` holds (report.json ``tables``)."""
    groove = _groove(cam)
    radii = [groove.root_radius, groove.layout.mean_radius, groove.rim_radius]
    if _is_rib(groove):
        return {"content": "the barrel cam's rib faces (exact envelopes of its two rollers) at the root, mean and rim radius: for "
                           "each radius the RIB_UPPER face's closed section, then the RIB_LOWER face's (its last row joins its "
                           "first), every chord within the chord tolerance of the exact face",
                "columns": {"wall": "RIB_UPPER (the rib's face on its +z side, the upper roller's envelope) or RIB_LOWER",
                            "radius_mm": "distance from the cam axis, mm", "phi_deg": "the cam's polar angle, deg",
                            "x_mm": "radius cos(phi), mm", "y_mm": "radius sin(phi), mm", "z_mm": "along the cam axis from the bottom face, mm"},
                "radii_mm": radii, "chord_tol_mm": chord_tol, "fit_tol_mm": groove.fit_tol}
    return {"content": "the barrel cam's groove walls (exact envelopes of the roller) at the root, mean and rim radius: for each "
                       "radius the UPPER wall's closed section, then the LOWER wall's (its last row joins its first), every chord "
                       "within the chord tolerance of the exact wall",
            "columns": {"wall": "UPPER (the wall on the +z side of the roller) or LOWER", "radius_mm": "distance from the cam axis, mm",
                        "phi_deg": "the cam's polar angle, deg", "x_mm": "radius cos(phi), mm", "y_mm": "radius sin(phi), mm",
                        "z_mm": "along the cam axis from the bottom face, mm"},
            "radii_mm": radii, "chord_tol_mm": chord_tol, "fit_tol_mm": groove.fit_tol}
