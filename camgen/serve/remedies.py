"""The scene keys that change a check's value: what the page names next to a failed check.

One line per check (its name in report.json) listing the keys of the cam's table (``base_radius_mm``)
or of another table (``machining.tool_diameter_mm``) a designer changes to move the check's value,
the first the one that usually helps most (a larger base radius lowers the pressure angle).  A cam
is shown only the keys its own table has (:func:`keys_to_change`).
"""
from __future__ import annotations

from typing import Collection

__all__ = ["REMEDIES", "keys_to_change"]

#: check name -> keys that change its value (cam table keys bare, other tables' keys dotted).
REMEDIES: dict[str, tuple[str, ...]] = {
    "pressure_angle": ("base_radius_mm", "follower_offset_mm", "segments", "pressure_angle_limit_deg", "c_mm"),
    "undercut": ("base_radius_mm", "roller_radius_mm", "segments", "c_mm"),
    "min_concave_radius": ("machining.tool_diameter_mm", "base_radius_mm", "roller_radius_mm", "segments"),
    "min_convex_radius": ("base_radius_mm", "roller_radius_mm", "segments"),
    "wall_thickness": ("bore_diameter_mm", "keyway_depth_mm", "min_wall_mm", "base_radius_mm", "c_mm"),
    "continuity": ("segments",),
    "law_joins": ("segments",),
    "follower_motion": ("segments",),
    "face_length": ("face_half_length_mm", "face_margin_mm", "base_radius_mm", "segments"),
    "jump": ("spring_preload_n", "spring_rate_n_per_mm", "spring_preload_n_mm", "spring_rate_n_mm_per_rad", "rpm", "mass_kg", "jump_margin_n"),
    "contact_force": ("spring_preload_n", "spring_rate_n_per_mm", "spring_preload_n_mm", "spring_rate_n_mm_per_rad", "rpm", "mass_kg"),
    "hertz_stress": ("contact_width_mm", "roller_radius_mm", "base_radius_mm", "allowable_contact_stress_mpa", "spring_preload_n"),
    "camshaft_torque": ("torque_limit_n_m", "spring_preload_n", "spring_rate_n_per_mm", "rpm", "base_radius_mm", "segments"),
    "conjugate_preload": ("conjugate_preload_mm",),
    "groove_tool": ("machining.tool_diameter_mm", "roller_radius_mm"),
    "groove_floor": ("groove_depth_mm", "thickness_mm", "groove_clearance_mm"),
    "rim_wall": ("rim_radius_mm", "base_radius_mm", "roller_radius_mm"),
    "wall_crossover": ("base_radius_mm", "roller_radius_mm", "segments"),
    "sizing": ("sizing", "pressure_angle_limit_deg", "machining.tool_diameter_mm"),
    "fit_error": ("fit_tol_mm", "samples"),
    "cylinder_length": ("cylinder_length_mm",),
    "plate_length": ("travel_mm", "margin_start_mm", "margin_end_mm"),
    "plate_height": ("base_radius_mm", "segments"),
    "machine_motor_power": ("mechanisms.machine.motor_power_limit_w",),
    "machine_motor_torque": ("mechanisms.machine.motor_torque_limit_n_m",),
}


def keys_to_change(check: str, cam: str, cam_keys: Collection[str]) -> list[str]:
    """The dotted scene keys (``cams.<cam>.base_radius_mm``, ``machining.tool_diameter_mm``) that
    change ``check``'s value, of those the cam's table has (``cam_keys``: its key names); [] for
    a check with none listed."""
    out = []
    for key in REMEDIES.get(check, ()):
        if "." in key:
            out.append(key)
        elif key in cam_keys:
            out.append(f"cams.{cam}.{key}")
    return out
