"""report.html's tables of a cam's numbers: the design (what the scene gave and what sizing
found), the motion program segment by segment, and the computed figures, each value with its
unit.

The numbers are the cam's ``figures`` (the same as report.json's) and its body
(:class:`camgen.report.model.CamReport`); a figure's
unit is read from its key's suffix (``_mm``, ``_deg``, ``_N_per_mm``, ...: report.json's
convention), so nothing is shown as a Python literal.
"""
from __future__ import annotations

import html
import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Iterable, Sequence

from camgen.report.format import number, value_text

from camgen.report.model import json_number, json_numbers, json_object, json_objects

if TYPE_CHECKING:
    from camgen.report.model import CamBody, CamReport, JsonValue

__all__ = ["DESIGN", "LABELS", "OWN_TABLE", "UNITS", "design_table", "dynamics_rows", "figures_table", "program_table", "quantity"]

#: Key suffixes and the unit they name, longest first (report.json's key convention).
UNITS = (
    ("_Nmm_per_rad", "N·mm/rad"), ("_N_per_mm", "N/mm"), ("_mm_per_s", "mm/s"), ("_m_per_s2", "m/s²"), ("_m_per_s3", "m/s³"),
    ("_rad_per_s2", "rad/s²"), ("_rad_per_s3", "rad/s³"), ("_rad_per_s", "rad/s"), ("_mm2", "mm²"), ("_mm", "mm"),
    ("_deg", "deg"), ("_rad", "rad"), ("_Nmm", "N·mm"), ("_Nm", "N·m"), ("_MPa", "MPa"), ("_N", "N"), ("_W", "W"),
    ("_J", "J"), ("_rpm", "rpm"), ("_kg", "kg"), ("_s", "s"),
)

#: Names clearer than the key's words (keys of the figures and of their groups).
LABELS = {
    "base_radius_mm": "base radius",
    "roller_radius_mm": "roller radius",
    "prime_radius_mm": "prime circle radius (base + roller)",
    "offset_mm": "follower offset (its axis: x = offset)",
    "pivot_mm": "arm pivot (x, y)",
    "swing_turn": "arm turns for a positive swing",
    "arm_length_mm": "arm length (pivot to roller centre or knife tip)",
    "rest_arm_angle_deg": "arm direction at zero swing",
    "face_offset_mm": "face line's distance from the pivot",
    "rest_face_normal_deg": "face normal at zero swing",
    "pressure_angle_limit_deg": "pressure angle limit",
    "min_concave_radius_mm": "least concave radius (tool radius)",
    "fit_tol_mm": "spline fit tolerance",
    "fit_error_mm": "spline fit error",
    "profile_pieces": "profile spline pieces",
    "area_mm2": "profile area",
    "perimeter_mm": "profile perimeter",
    "bounds_mm": "profile bounds (x min, y min, x max, y max)",
    "stroke_mm": "stroke",
    "stroke_deg": "stroke (arm swing)",
    "trajectory": "target path y = f(x)",
    "period_mm": "period of the path",
    "samples": "cam angles per turn",
    "curvature_scheme": "path curvature",
    "gear_teeth_rear_cam": "gear teeth (rear shaft, camshaft)",
    "lever_mm": "steering lever d",
    "lift_table_csv": "lift table",
    "table_rows": "lift table rows",
    "table_spline_degree": "lift table spline degree",
    "a_mm": "a (pivot to the off-axis centres)",
    "b_mm": "b (between the off-axis centres)",
    "c_mm": "c (base circle radius)",
    "source": "source of the numbers",
    "rpm": "cam speed",
    "motion_at_rpm": "at the cam speed",
    "jump_rpm": "jump speed (the follower leaves the cam)",
    "jump_ranges_deg": "cam angles where the follower leaves the cam",
    "max_contact_force_deg": "cam angle of the largest contact force",
    "min_contact_force_deg": "cam angle of the smallest contact force",
    "torque_peak_deg": "cam angle of the torque peak",
    "hertz_stress_peak_deg": "cam angle of the Hertz stress peak",
}

#: Figures that are the design itself (given by the scene, or found by sizing); the others are results.
DESIGN = ("base_radius_mm", "a_mm", "b_mm", "c_mm", "trajectory", "period_mm", "samples", "curvature_scheme", "lever_mm",
          "gear_teeth_rear_cam", "lift_table_csv", "table_rows", "table_spline_degree", "fit_tol_mm", "source")
#: Figures with a table of their own (the motion program, the dynamics section, the fitted tables).
OWN_TABLE = ("segments", "dynamics", "fits", "follower", "sizing", "smoothing", "sizing_ranges", "vdi2143",
             "acceleration_harmonics")  # VDI: report/vdi.py

_ROTATION = {"ccw": "counter-clockwise (ccw)", "cw": "clockwise (cw)"}
_SIZING = {"base_radius": "the smallest base radius", "base_radius_and_offset": "the smallest base radius and its offset"}


def quantity(key: str) -> tuple[str, str]:
    """The label and unit of a figure key: ``"max_contact_force_N"`` -> ("max contact force", "N")."""
    if key == "rpm":
        return LABELS[key], "rpm"
    unit = ""
    stem = key
    for suffix, name in UNITS:
        if key.endswith(suffix) and len(key) > len(suffix):
            stem, unit = key[: -len(suffix)], name
            break
    return LABELS.get(key, stem.replace("_", " ")), unit


def _row(label: str, value: str, unit: str, cls: str = "", numeric: bool = True) -> str:
    attr = f" class='{cls}'" if cls else ""
    align = " class='num'" if numeric else ""
    return (f"<tr{attr}><td>{html.escape(label)}</td><td{align}>{value}</td>"
            f"<td>{html.escape(unit)}</td></tr>")


def _table(rows: Iterable[str], caption: str, cls: str) -> str:
    body = "".join(rows)
    if not body:
        return ""
    return (f"<table class='{cls}'><caption>{html.escape(caption)}</caption>"
            f"<thead><tr><th>quantity</th><th>value</th><th>unit</th></tr></thead><tbody>{body}</tbody></table>")


def _figure_rows(items: Iterable[tuple[str, "JsonValue"]], prefix: str = "") -> list[str]:
    rows = []
    for key, value in items:
        label, unit = quantity(key)
        if isinstance(value, Mapping):
            rows += _figure_rows(value.items(), f"{prefix}{label}: ")
        elif key == "jump_rpm" and value is None:  # report.json's null jump speed: the follower never leaves the cam
            rows.append(_row(prefix + label, "never", "", numeric=False))
        else:
            rows.append(_row(prefix + label, value_text(value), unit if value not in (None, [], ()) else "", numeric=_numeric(value)))
    return rows


def _numeric(value: "JsonValue") -> bool:
    if isinstance(value, (list, tuple)):
        return all(_numeric(v) for v in value)
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def design_table(cam: "CamReport") -> str:
    """The design of ``cam``: follower, rotation, base radius, speed, sizing, body (what the scene
    gave, and the values sizing found, marked so)."""
    figures = cam.figures
    follower = json_object(figures.get("follower"))
    sizing = json_object(figures.get("sizing"))
    sized = {"base_radius_mm"} | ({"offset_mm"} if "offset_mm" in sizing else set()) if sizing else set()

    def add(key: str, value: "JsonValue") -> None:
        label, unit = quantity(key)
        value = _ROTATION.get(value, value) if key == "swing_turn" and isinstance(value, str) else value
        mark = key in sized
        rows.append(_row(label + (" (sized)" if mark else ""), value_text(value), unit, "sized" if mark else "", _numeric(value)))

    rows: list[str] = []
    if follower:
        rows.append(_row("follower", html.escape(", ".join(str(follower[k]) for k in ("kind", "motion") if k in follower)), "",
                         numeric=False))
        if "rotation" in follower:
            rotation = str(follower["rotation"])
            seen = "as the DXF is drawn" if cam.body is not None else "seen from the +z end of the cam axis"  # a plate, or a barrel
            rows.append(_row(f"cam rotation ({seen})", html.escape(_ROTATION.get(rotation, rotation)), "", numeric=False))
    if sizing:
        limits = f"pressure angle <= {number(json_number(sizing['pressure_angle_limit_deg']))} deg"
        if sizing.get("min_concave_radius_mm"):
            limits += f", concave radii >= {number(json_number(sizing['min_concave_radius_mm']))} mm"
        method = str(sizing["method"])
        rows.append(_row("sizing", html.escape(f"{_SIZING.get(method, method)} meeting {limits}"), "", numeric=False))
    if "base_radius_mm" in figures:
        add("base_radius_mm", figures["base_radius_mm"])
    for key, value in follower.items():
        if key not in ("kind", "motion", "rotation"):
            add(key, value)
    for key in DESIGN:
        if key in figures and key not in ("base_radius_mm", "fit_tol_mm", "source"):
            add(key, figures[key])
    groove = json_object(figures.get("groove"))
    for key, label in (("width_mm", "groove width (roller diameter + clearance)"), ("clearance_mm", "groove clearance"),
                       ("depth_mm", "groove depth"), ("rim_radius_mm", "rim radius")):
        if key in groove:
            rows.append(_row(label, value_text(groove[key]), "mm", "", _numeric(groove[key])))
    if cam.rpm:
        rows.append(_row("cam speed", number(cam.rpm), "rpm"))
    rows += _body_rows(cam.body)
    for key in ("fit_tol_mm", "source"):
        if key in figures:
            add(key, figures[key])
    return _table(rows, "Design: the scene's values" + (" and those sizing found" if sizing else ""), "design")


def _body_rows(body: "CamBody | None") -> list[str]:
    if body is None:
        return []
    rows = [_row("thickness", number(body.thickness), "mm")]
    if body.bore_diameter > 0:
        rows.append(_row("bore diameter", number(body.bore_diameter), "mm"))
        if body.keyway_width > 0:
            rows.append(_row("keyway width x depth", f"{number(body.keyway_width)} x {number(body.keyway_depth)}", "mm"))
            rows.append(_row("keyway direction (from +x, ccw)", number(math.degrees(body.keyway_angle)), "deg"))
    else:
        rows.append(_row("bore", "no bore", "", numeric=False))
    rows.append(_row("least wall allowed (bore to profile)", number(body.min_wall), "mm"))
    return rows


def _conditions(values: Sequence[float], unit: str, per: str = "deg") -> str:
    """A polynomial segment's end conditions [s, v, a, j] (per degree of cam angle, or per
    ``per``: mm of plate travel)."""
    names = (("s", unit), ("v", f"{unit}/{per}"), ("a", f"{unit}/{per}²"), ("j", f"{unit}/{per}³"))
    return ", ".join(f"{n} = {number(v)} {u}" for (n, u), v in zip(names, values))


def program_table(cam: "CamReport") -> str:
    """The motion program of a ``motion_law`` cam: each segment's law, where it starts and ends
    (cam angle, in the direction of rotation from cam angle 0; a program in plate travel: mm
    from travel 0), its span, lift or swing, and its parameters."""
    segments = json_objects(cam.figures.get("segments"))
    if not segments:
        return ""
    swing = any("swing_deg" in s for s in segments)
    unit = "deg" if swing else "mm"
    rotation = json_object(cam.figures.get("follower")).get("rotation")
    travel = any("span_mm" in s for s in segments)  # a program in plate travel (a linear cam)
    per = "mm" if travel else "deg"
    rows = []
    start = 0.0
    for i, seg in enumerate(segments):
        span = json_number(seg["span_mm" if travel else "span_deg"])
        end = start + span
        if "start" in seg and "end" in seg:  # a polynomial: the motion follows from its end conditions
            first, last = json_numbers(seg["start"]), json_numbers(seg["end"])
            motion = last[0] - first[0]
            params = f"start: {_conditions(first, unit, per)}; end: {_conditions(last, unit, per)}"
        else:
            motion = json_number(seg.get("swing_deg" if swing else "lift_mm", 0.0))
            params = ""
        if "blend" in seg:
            params = f"blend {number(json_number(seg['blend']))} of the span at each end (velocity ramps)"
        if "scca" in seg:  # issue 26 LAWS: Norton's SCCA fractions
            b, c, d = json_numbers(seg["scca"])
            params = f"b {number(b)}, c {number(c)}, d {number(d)} (sine ramps, constant, middle cosine)"
        if "accel_fraction" in seg:  # issue 26 LAWS: the skewed laws
            params = f"positive acceleration over {number(json_number(seg['accel_fraction']))} of the span"
        rows.append(f"<tr><td class='num'>{i}</td><td>{html.escape(str(seg['law']))}</td><td class='num'>{number(start)}</td>"
                    f"<td class='num'>{number(end)}</td><td class='num'>{number(span)}</td>"
                    f"<td class='num'>{number(motion)}</td><td>{html.escape(params)}</td></tr>")
        start = end
    direction = f", in the direction of rotation ({_ROTATION.get(str(rotation), rotation)})" if rotation else ""
    what = "swing (deg)" if swing else "lift (mm)"
    caption = "plate travel from travel 0 (mm)" if travel else f"cam angles from cam angle 0{direction}"
    return (f"<table class='program'><caption>Motion program: {html.escape(caption)}</caption>"
            f"<thead><tr><th>segment</th><th>law</th><th>from ({per})</th><th>to ({per})</th><th>span ({per})</th><th>{what}</th>"
            f"<th>parameters</th></tr></thead><tbody>{''.join(rows)}</tbody></table>")


def figures_table(cam: "CamReport") -> str:
    """The computed figures of ``cam`` (those not in the design or a table of their own)."""
    items = [(k, v) for k, v in cam.figures.items() if k not in DESIGN and k not in OWN_TABLE]
    return _table(_figure_rows(items), "Computed figures", "figures")


def dynamics_rows(figures: "Mapping[str, JsonValue]") -> str:
    """The dynamics figures (report.json's ``figures.dynamics``) as table rows with units."""
    return "".join(_figure_rows(figures.items()))
