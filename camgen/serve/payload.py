"""A run's cams as the live page draws them (``POST /api/evaluate``'s ``cams``).

Read from the report's input (:func:`camgen.report_data.report_input` with the plot data) and
report.json's tree of the same run (:func:`camgen.report.report_dict`): the figures and checks are
report.json's, the curves report.html's, thinned to at most :data:`MAX_OUTLINE_POINTS` outline
points and :data:`MAX_PLOT_SAMPLES` plot samples.  Angles go out in degrees, lengths in mm;
a value JSON cannot hold (NaN, an infinite radius of curvature) goes out as null.
"""
from __future__ import annotations

import math
from collections import abc
from typing import TYPE_CHECKING, Any, Collection, Mapping

import numpy as np

from camgen.serve.remedies import keys_to_change

if TYPE_CHECKING:
    from camgen.report.model import CamPlots, CamReport, DynamicsCurves, RideAnimation

__all__ = ["MAX_OUTLINE_POINTS", "MAX_PATH_SAMPLES", "MAX_PLOT_SAMPLES", "cam_payload", "json_safe", "where_text"]

#: Most points of an outline (profile, pitch curve, pocket wall) sent to the page.
MAX_OUTLINE_POINTS = 2000
#: Most samples of a plotted curve (SVAJ, pressure angle, curvature, dynamics).
MAX_PLOT_SAMPLES = 721
#: Most cam angles of the follower's path (the animation's frames).
MAX_PATH_SAMPLES = 360


def json_safe(value: Any) -> Any:
    """``value`` with numpy values as Python's, tuples as lists, and every non-finite float as
    None (JSON has no NaN or infinity)."""
    if isinstance(value, float):
        return float(value) if math.isfinite(value) else None
    if value is None or isinstance(value, (str, int)):
        return value
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "f":
            finite = np.isfinite(value)
            if bool(finite.all()):
                return value.tolist()
            out = value.astype(object)
            out[~finite] = None
            return out.tolist()
        return json_safe(value.tolist())
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, (dict, abc.Mapping)):
        return {str(k): json_safe(v) for k, v in value.items()}
    if isinstance(value, np.generic):
        return json_safe(value.item())
    return value


def _thin(n: int, most: int) -> slice:
    """Every k-th of ``n`` samples, k the least step that keeps at most ``most``."""
    return slice(None, None, max(1, math.ceil(n / most)))


def _outline(points: Any) -> list[list[float]] | None:
    if points is None:
        return None
    array = np.asarray(points, dtype=float)
    if len(array) > MAX_OUTLINE_POINTS:  # every k-th vertex (the page's drawing; the files keep every one)
        array = array[_thin(len(array), MAX_OUTLINE_POINTS - 1)]
    return json_safe(np.round(array, 6))


def _curve(x_rad: Any, *ys: Any, scale_y: float = 1.0) -> list[list[Any]]:
    """[theta_deg, y1, y2, ...] thinned together."""
    x = np.asarray(x_rad, dtype=float)
    cut = _thin(len(x), MAX_PLOT_SAMPLES)
    return [json_safe(np.degrees(x[cut]))] + [json_safe(np.asarray(y, dtype=float)[cut] * scale_y) for y in ys]


def where_text(check: Mapping[str, Any]) -> str:
    """The angles (or a linear cam's travel) a check names, as ``camgen check`` prints them."""
    for unit in ("deg", "mm"):
        angles = check.get(f"where_{unit}")
        if angles:
            shown = ", ".join(f"{w:g}" for w in angles[:6]) + (f" and {len(angles) - 6} more" if len(angles) > 6 else "")
            return f"{shown} {unit}"
    return ""


def _checks(name: str, checks: Any, cam_keys: Collection[str]) -> list[dict[str, Any]]:
    out = []
    for check in checks:
        row = dict(check)
        row["where"] = where_text(check)
        row["keys"] = keys_to_change(str(check["name"]), name, cam_keys)
        out.append(json_safe(row))
    return out


def _follower(figures: Mapping[str, Any]) -> dict[str, Any] | None:
    follower = figures.get("follower")
    if not isinstance(follower, Mapping):
        return None
    out = json_safe(follower)
    if "roller_radius_mm" in out and "radius_mm" not in out:
        out["radius_mm"] = out["roller_radius_mm"]
    return dict(out)


def _follower_path(anim: "RideAnimation | None") -> dict[str, Any] | None:
    """Where the follower is per cam angle: a translating follower's reference point (its roller's
    centre, else the first point of its drawing) moved along +y by the lift; an oscillating one's
    turned about the pivot by the swing.  With the drawing at zero motion (fixed frame) and the
    rotation sense, the page animates the ride as report.html does."""
    if anim is None:
        return None
    moves = np.asarray(anim.moves, dtype=float)
    cut = _thin(len(moves), MAX_PATH_SAMPLES)
    moves = moves[cut]
    theta = np.arange(len(anim.moves), dtype=float)[cut] * 360.0 / len(anim.moves)
    drawing = {label: np.asarray(poly, dtype=float) for label, poly in anim.follower}
    shape = drawing.get("roller", next(iter(drawing.values()), np.zeros((1, 2))))
    ref = shape.mean(axis=0) if "roller" in drawing else shape[0]
    if anim.motion == "translating" or anim.pivot is None:
        points = np.column_stack([np.full_like(moves, ref[0]), ref[1] + moves])
    else:
        turn = np.radians(moves)
        px, py = anim.pivot
        dx, dy = ref[0] - px, ref[1] - py
        points = np.column_stack([px + dx * np.cos(turn) - dy * np.sin(turn), py + dx * np.sin(turn) + dy * np.cos(turn)])
    return {"theta_deg": json_safe(theta), "points": json_safe(np.round(points, 6)), "motion": anim.motion,
            "moves": json_safe(moves), "move_unit": "mm" if anim.motion == "translating" else "deg",
            "pivot": json_safe(anim.pivot), "sigma": anim.sigma,
            "drawing": [{"label": label, "points": _outline(poly)} for label, poly in anim.follower]}


def _plots(plots: "CamPlots | None", dynamics: "DynamicsCurves | None", checks: Any) -> dict[str, Any]:
    out: dict[str, Any] = {"svaj": None, "pressure_angle": None, "curvature": None, "dynamics": None}
    if plots is not None and plots.motion is not None:
        m = plots.motion
        per_rad = {"s": m.unit, "v": f"{m.unit}/rad", "a": f"{m.unit}/rad^2", "j": f"{m.unit}/rad^3"}
        if m.at_speed is not None:
            sp = m.at_speed
            theta, s, v, a, j = _curve(m.cam_angle, m.lift, sp.velocity, sp.acceleration, sp.jerk)
            units = {"s": m.unit, "v": sp.velocity_unit, "a": sp.acceleration_unit, "j": sp.jerk_unit, "rpm": sp.rpm}
        else:
            theta, s, v, a, j = _curve(m.cam_angle, m.lift, m.velocity, m.acceleration, m.jerk)
            units = dict(per_rad)
        out["svaj"] = {"theta_deg": theta, "s": s, "v": v, "a": a, "j": j, "units": units}
    if plots is not None and plots.pressure_angle is not None:
        theta, deg = _curve(plots.pressure_angle[0], plots.pressure_angle[1], scale_y=180.0 / math.pi)
        limit = plots.follower_limit_deg
        if limit is None:  # the check's limit (a kind whose follower states none)
            limit = next((c["limit"] for c in checks if c["name"] == "pressure_angle" and c.get("unit") == "deg"
                          and isinstance(c.get("limit"), (int, float))), None)
        out["pressure_angle"] = {"theta_deg": theta, "deg": deg, "limit_deg": json_safe(limit), "label": plots.pressure_angle_label}
    if plots is not None and plots.curvature is not None:
        theta, radius = _curve(plots.curvature[0], plots.curvature[1])
        out["curvature"] = {"theta_deg": theta, "radius_mm": radius, "label": plots.curvature_label,
                            "angle_label": plots.curvature_angle_label, "limit_mm": json_safe(plots.curvature_limit)}
    if dynamics is not None:
        theta, force, torque = _curve(dynamics.theta, dynamics.contact_force, dynamics.torque)
        out["dynamics"] = {"theta_deg": theta, "contact_force_n": force, "torque_n_m": torque, "rpm": dynamics.rpm}
    return out


def cam_payload(cam: "CamReport", cam_json: Mapping[str, Any], cam_keys: Collection[str]) -> dict[str, Any]:
    """One cam for the page: ``cam`` (the report's input, with plot data), ``cam_json`` (its
    report.json object: figures, checks), ``cam_keys`` (the key names of its scene table, for the
    keys each check names)."""
    plots = cam.plots
    anim = plots.animation if plots is not None else None
    zero = plots.zero_mark if plots is not None else None
    sigma = anim.sigma if anim is not None else zero.sigma if zero is not None else 1.0
    figures = cam_json.get("figures", {})
    checks = cam_json.get("checks", [])
    return {
        "name": cam.name, "kind": cam.kind, "form": cam.form, "rotation": "ccw" if sigma > 0 else "cw",
        "manufacturable": cam.manufacturable,
        "profile": _outline(plots.profile) if plots is not None else None,
        "pockets": [_outline(poly) for _, poly in plots.walls] if plots is not None else [],
        "pitch": _outline(plots.pitch) if plots is not None else None,
        "follower": _follower(figures),
        "follower_path": _follower_path(anim),
        "checks": _checks(cam.name, checks, cam_keys),
        "figures": json_safe(figures),
        "plots": _plots(plots, cam.dynamics, checks),
    }
