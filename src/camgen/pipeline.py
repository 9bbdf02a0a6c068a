"""The lazy pipeline: scene -> synthesis -> contour -> checks -> report and exports.

Only the stages a scene's outputs need are run, and their libraries are imported only then
(ezdxf for DXF; nothing heavier is touched by a DXF/CSV job).  Everything is computed before
the first file is written, so a user error leaves no partial output behind.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from camgen.builders import BUILDERS, BuiltCam, from_params
from camgen.scene import CamSpec, Scene


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
    return from_params(MachiningSpec, scene.machining, fields, renamed, thickness=cam.body.thickness, chord_tol=scene.output.chord_tol)


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
