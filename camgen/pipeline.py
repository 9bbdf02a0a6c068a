"""The lazy pipeline: scene -> synthesis -> contour -> checks -> report and exports.

Only the stages a scene's outputs need are run, and their libraries are imported only then
(ezdxf for DXF; nothing heavier is touched by a DXF/CSV job).  Everything is computed before
the first file is written, so a user error leaves no partial output behind.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from camgen.scene import CamSpec, Scene


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
    device = _from_params(tc.Tricycle, p, ("wheelbase", "half_track", "lever", "rod_radius", "z_rear", "z_cam", "worm_teeth"))
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


def build_cams(scene: Scene) -> list[BuiltCam]:
    """Synthesise and check every cam of ``scene``.

    A :class:`ParameterError` raised inside a builder is re-raised with the scene key
    (``cams.<name>.<key>``) so the user finds the line to change.
    """
    from camgen.errors import ParameterError
    from camgen.scene import BODY_KEYS, CAM_KINDS

    built = []
    for spec in scene.cams:
        try:
            cam = BUILDERS[spec.kind](spec, scene.output.chord_tol)
            cam.body = _body(spec)
            _evaluate(scene, spec, cam)
            if cam.body.bore_diameter > 0:
                cam.checks.append(_wall_check(cam))
            built.append(cam)
        except ParameterError as exc:
            if exc.name.startswith("cams."):
                raise
            schema = {**CAM_KINDS[spec.kind], **BODY_KEYS}
            key = next((k for k in (exc.name, f"{exc.name}_mm", f"{exc.name}_deg") if k in schema), exc.name)
            raise ParameterError(f"cams.{spec.name}.{key}", exc.value, exc.valid, exc.why) from None
    return built


def _follower(spec: CamSpec, cam: BuiltCam) -> Any:
    """The follower model of a cam: scene keys, else the kind's natural follower."""
    from camgen.checks import Follower

    p = spec.params
    if spec.kind == "trajectory":  # the tricycle's steering rod: a radially translating roller on +x
        default = Follower("roller", "translating", roller_radius=cam.model.device.rod_radius)
    elif spec.kind == "motion_law":  # the follower moves along +y (camgen.synthesis.motion_law)
        default = Follower(p.get("follower", "roller"), roller_radius=p.get("roller_radius", 10.0), direction=math.pi / 2)
    else:
        default = Follower("yoke")
    kind = p.get("follower", default.kind)
    return Follower(
        kind=kind,
        motion=p.get("follower_motion", default.motion),
        roller_radius=p.get("roller_radius", default.roller_radius if kind == "roller" else 0.0),
        offset=p.get("follower_offset", 0.0),
        direction=p.get("follower_direction", default.direction),
        pivot_distance=p.get("pivot_distance", 0.0),
        pivot_angle=p.get("pivot_angle", 0.0),
        arm_length=p.get("arm_length", 0.0),
        face_half_length=p.get("face_half_length"),
        pressure_angle_limit=p.get("pressure_angle_limit"),
    )


def _evaluate(scene: Scene, spec: CamSpec, cam: BuiltCam) -> None:
    """Design checks of one cam (camgen.checks), kept for the report."""
    from camgen.checks import evaluate_cam

    follower = _follower(spec, cam)
    tool = scene.machining.get("tool_diameter", 6.0) / 2.0
    breadth = cam.model.get("breadth_mm") if isinstance(cam.model, dict) else None
    pitch = None
    if follower.kind == "roller" and cam.pitch is not None:
        synthesis_roller = cam.model.device.rod_radius if spec.kind == "trajectory" else spec.params.get("roller_radius", 10.0)
        pitch = cam.pitch if follower.roller_radius == synthesis_roller else None
    cam.evaluation = evaluate_cam(cam.contour, follower, tool, spec.params.get("rpm"), breadth, pitch)
    cam.checks.extend(cam.evaluation.checks)
    cam.figures["follower"] = {"kind": follower.kind, "motion": follower.motion, "roller_radius_mm": follower.roller_radius,
                               "offset_mm": follower.offset, "pressure_angle_limit_deg": math.degrees(follower.limit)}
    if spec.params.get("rpm"):
        cam.figures["motion_at_rpm"] = {"rpm": spec.params["rpm"], **cam.evaluation.motion.at_rpm(spec.params["rpm"])}


def _body(spec: CamSpec) -> Any:
    from camgen.export.solid import SolidSpec

    p = spec.params
    defaults = SolidSpec()
    return SolidSpec(
        thickness=p.get("thickness", defaults.thickness),
        bore_diameter=p.get("bore_diameter", 0.0),
        keyway_width=p.get("keyway_width", 0.0),
        keyway_depth=p.get("keyway_depth", 0.0),
        keyway_angle=p.get("keyway_angle", defaults.keyway_angle),
        min_wall=p.get("min_wall", defaults.min_wall),
    )


def _wall_check(cam: BuiltCam) -> Any:
    """Wall between bore/keyway and profile: a GeometryError below min_wall, else a check result."""
    from camgen.checks import CheckResult
    from camgen.export.solid import check_wall, wall_left

    check_wall(cam.contour, cam.body, cam.name)
    wall, where = wall_left(cam.contour, cam.body)
    return CheckResult("wall_thickness", wall, cam.body.min_wall, "mm", True, [round(where, 6)],
                       f"thinnest wall between the bore/keyway and the profile, {wall:.3f} mm")


def _machining(scene: Scene, cam: BuiltCam) -> Any:
    from camgen.export.gcode import MachiningSpec

    fields = ("tool_diameter", "step_down", "safe_z", "spindle_rpm", "direction", "dialect", "cutter_compensation",
              "lead", "spline_mode", "decimals")
    renamed = {"feed": "feed_mm_per_min", "plunge_feed": "plunge_feed_mm_per_min"}
    return _from_params(MachiningSpec, scene.machining, fields, renamed, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol)


def _from_params(cls: Any, params: Any, fields: tuple[str, ...], renamed: dict[str, str] | None = None, **fixed: Any) -> Any:
    """``cls(**...)`` from the scene ``params`` that are given; the dataclass defaults fill the rest."""
    keys = {name: name for name in fields} | (renamed or {})
    return cls(**{name: params[key] for name, key in keys.items() if key in params}, **fixed)


def analyse_mechanisms(scene: Scene, cams: list[BuiltCam]) -> tuple[dict[str, Any], dict[str, str], dict[str, Any]]:
    """Mechanism analyses of the scene: report sections, their files, and their data for report.html."""
    report: dict[str, Any] = {}
    files: dict[str, str] = {}
    context: dict[str, Any] = {}
    if "horse_leg" in scene.mechanisms:
        from camgen.mechanisms.horse_leg_job import horse_leg_job

        report["horse_leg"], leg_files, context["horse_leg"] = horse_leg_job(scene, {c.name: c for c in cams})
        files.update(leg_files)
    return report, files, context


def render_files(scene: Scene, cams: list[BuiltCam]) -> dict[str, str | bytes]:
    """Every output file of the run except report.json, in memory (name -> content)."""
    out = scene.output
    files: dict[str, str | bytes] = {}
    for cam in cams:
        if "dxf" in out.formats:
            from camgen.export.dxf import DxfOptions, contour_to_dxf

            options = DxfOptions(splines=out.dxf_splines, biarc_tol=out.chord_tol)
            # follower-centre path: the synthesis' own, else the roller checks' pitch curve
            pitch = (cam.pitch if cam.pitch is not None else getattr(cam.evaluation, "pitch", None)) if out.dxf_pitch else None
            files[f"{cam.name}.dxf"] = contour_to_dxf(cam.contour, cam.body, pitch, options)
        if "points" in out.formats:
            from camgen.export.points import points_csv

            files[f"{cam.name}_points.csv"] = points_csv(cam.contour, out.chord_tol, cam.name, scene.name)
        if "lift" in out.formats:
            from camgen.export.points import lift_csv

            files[f"{cam.name}_lift.csv"] = lift_csv(cam.contour, out.lift_step, cam.name, scene.name)
        from camgen.export import solid as solid_export

        meshes = [f for f in out.formats if f in solid_export.MESH_FORMATS]
        if meshes:
            body = solid_export.cam_solid(cam.contour, cam.body, out.chord_tol, cam.name)
            cam.figures["solid_volume_mm3"] = body.volume
            cam.figures["solid_triangles"] = int(len(body.triangles))
            for fmt in meshes:
                files[cam.name + solid_export.SUFFIX[fmt]] = solid_export.mesh_bytes(body, fmt, cam.name)
        if "step" in out.formats:
            from camgen.export.step import step_bytes

            files[f"{cam.name}.step"] = step_bytes(cam.contour, cam.body, cam.name)
        if "ngc" in out.formats:
            from camgen.export.gcode import gcode_program

            files[f"{cam.name}.ngc"] = gcode_program(cam.contour, _machining(scene, cam), cam.name, scene.name)
        files.update(cam.files)
    return files


def run_scene(scene: Scene, outdir: str | Path = "outputs") -> list[Path]:
    """Run ``scene`` and write its outputs into ``outdir/<scene name>/``; return the paths written."""
    from camgen.report import report_json, report_dict

    target = Path(outdir) / scene.name
    cams = build_cams(scene)
    mechanisms, mechanism_files, context = analyse_mechanisms(scene, cams)
    # render everything in memory first: nothing is written unless all of it succeeded
    files = render_files(scene, cams)
    files.update(mechanism_files)
    names = sorted(files) + ["report.json"] + (["report.html"] if "html" in scene.output.formats else [])
    files["report.json"] = report_json(report_dict(scene, cams, names, mechanisms))
    if "html" in scene.output.formats:
        from camgen.report_html import report_html

        files["report.html"] = report_html(scene, cams, mechanisms, context, scene.machining.get("tool_diameter", 6.0) / 2.0)

    from camgen.export.atomic import write_atomic

    return [write_atomic(target / name, data) for name, data in files.items()]
