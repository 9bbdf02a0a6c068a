"""Cam builders: one per scene cam kind, from validated scene parameters to a :class:`BuiltCam`.

Each builder imports its synthesis module when called (scipy only for spline cams).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from camgen.scene import CamSpec


@dataclass
class BuiltCam:
    """A synthesised cam with its figures (report numbers), checks and extra files (name -> text)."""

    name: str
    kind: str
    contour: Any
    figures: dict[str, Any]
    checks: list[Any] = field(default_factory=list)
    files: dict[str, str] = field(default_factory=dict)
    model: Any = None
    body: Any = None
    pitch: Any = None
    evaluation: Any = None


def _build_three_arc(spec: CamSpec) -> BuiltCam:
    from camgen import checks
    from camgen.synthesis import three_arc

    p = spec.params
    a, b, c = three_arc.validate_three_arc(p["a"], p["b"], p["c"])
    contour = three_arc.three_arc_cam(a, b, c)
    width = three_arc.breadth(a, b, c)
    error, _ = checks.breadth_error(contour, width)
    figures = {
        "a_mm": a,
        "b_mm": b,
        "c_mm": c,
        "theta_x_deg": math.degrees(three_arc.theta_x(a, b)),
        "breadth_mm": width,
        "breadth_error_mm": error,
        "base_radius_mm": c,
        "max_radius_mm": 2.0 * a + c - b,
        "area_mm2": contour.area,
        "perimeter_mm": contour.length,
        "bounds_mm": list(contour.bounds),
        "arc_radii_mm": [seg.radius for seg in contour.segments],
    }
    if "source" in p:
        figures["source"] = p["source"]
    return BuiltCam(
        spec.name,
        spec.kind,
        contour,
        figures,
        [],
        model={"breadth_mm": width},
    )


def _build_trajectory(spec: CamSpec, chord_tol: float) -> BuiltCam:
    """Trajectory-driven disk cam for the steered tricycle (paper 004)."""
    from camgen.mechanisms import tricycle as tc
    from camgen.synthesis import trajectory as tr

    p = spec.params
    if "expression" in p:
        traj = tr.trajectory_from_expression(p["expression"], p["period"])
    else:
        traj = tr.read_trajectory_csv(p["trajectory_csv"])
    device = from_params(tc.Tricycle, p, ("wheelbase", "half_track", "lever", "rod_radius", "z_rear", "z_cam", "worm_teeth"))
    cam = tc.tricycle_cam(traj, device, p.get("samples", 720), p.get("curvature", "exact"))
    periods = p.get("ride_periods", 10)
    one = tc.simulate_cam(cam, periods=1)
    many = tc.simulate_cam(cam, periods=periods)
    error_one = tc.lateral_error(traj, one.x, one.y)
    error_many = tc.lateral_error(traj, many.x, many.y)
    synth = cam.synthesis
    figures: dict[str, Any] = {
        "trajectory": traj.source,
        "period_mm": traj.period,
        "samples": int(synth.theta.size),
        "curvature_scheme": synth.scheme,
        "arc_length_mm": synth.arc_length,
        "drive_wheel_diameter_mm": device.drive_wheel_diameter(synth.arc_length),
        "gear_teeth_rear_cam": [device.z_rear, device.z_cam],
        "rho_min_mm": float(synth.rho.min()),
        "rho_max_mm": float(synth.rho.max()),
        "base_radius_mm": device.base_radius,
        "lever_mm": device.lever,
        "steering_angle_range_deg": [math.degrees(math.atan((float(synth.rho.min()) - device.base_radius) / device.lever)),
                                     math.degrees(math.atan((float(synth.rho.max()) - device.base_radius) / device.lever))],
        "contact_vs_rho_max_mm": tc.contact_vs_rho(cam),
        "ride_max_error_mm": float(abs(error_one).max()),
        f"ride_max_error_{periods}_periods_mm": float(abs(error_many).max()),
        "profile_pieces": int(cam.profile.segments[0].n_pieces),
        "area_mm2": cam.profile.area,
        "perimeter_mm": cam.profile.length,
    }
    if "source" in p:
        figures["source"] = p["source"]
    tables = p.get("fit_tables", ())
    if tables:
        from camgen.mechanisms.tricycle_fit import fit_error_model

        figures["fits"] = {name: fit_error_model(cam, tc.load_measured_table(name)).as_dict() for name in tables}
    theta = np.radians(np.arange(0, 3600) / 10.0)
    x, y, _ = one.at(theta)
    from camgen.export.tables import csv_table

    ride_csv = csv_table(
        [
            f"camgen ride simulation of cam '{spec.name}': drive wheel A on the cam as made (profile contour), one cam turn",
            f"units: deg, mm; lateral_error_mm = distance from the target path y = f(x), positive to the left; trajectory: {traj.source}",
        ],
        {"theta_deg": np.degrees(theta), "x_mm": x, "y_mm": y, "lateral_error_mm": tc.lateral_error(traj, x, y)},
    )
    return BuiltCam(spec.name, spec.kind, cam.profile, figures, [], {f"{spec.name}_ride.csv": ride_csv}, cam, pitch=cam.pitch)


def _build_motion_law(spec: CamSpec, chord_tol: float) -> BuiltCam:
    """Disk cam from a motion program for a translating roller or flat follower."""
    from camgen.synthesis import motion_law as ml

    p = spec.params
    program = ml.MotionProgram([ml.MotionSegment(seg["law"], seg["span"], seg.get("lift", 0.0)) for seg in p["segments"]])
    samples = p.get("samples", 720)
    kind = p.get("follower", "roller")
    if kind == "roller":
        profile, pitch = ml.roller_cam(program, p["base_radius"], p.get("roller_radius", 10.0), p.get("follower_offset", 0.0), samples)
    else:
        profile, pitch = ml.flat_cam(program, p["base_radius"], samples), None
    figures: dict[str, Any] = {
        "base_radius_mm": p["base_radius"],
        "stroke_mm": program.stroke,
        "segments": [{"law": seg["law"], "span_deg": math.degrees(seg["span"]), "lift_mm": seg.get("lift", 0.0)} for seg in p["segments"]],
        "samples": samples,
        "area_mm2": profile.area,
        "perimeter_mm": profile.length,
        "bounds_mm": list(profile.bounds),
    }
    if "source" in p:
        figures["source"] = p["source"]
    return BuiltCam(spec.name, spec.kind, profile, figures, [], {}, {"program": program}, pitch=pitch)


BUILDERS: dict[str, Callable[[CamSpec, float], BuiltCam]] = {
    "motion_law": _build_motion_law,
    "three_arc": lambda spec, tol: _build_three_arc(spec),
    "trajectory": _build_trajectory,
}


def from_params(cls: Any, params: Any, fields: tuple[str, ...], renamed: dict[str, str] | None = None, **fixed: Any) -> Any:
    """``cls(**...)`` from the scene ``params`` that are given; the dataclass defaults fill the rest."""
    keys = {name: name for name in fields} | (renamed or {})
    return cls(**{name: params[key] for name, key in keys.items() if key in params}, **fixed)
