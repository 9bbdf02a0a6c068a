"""The report's input from a run's results: the one place that reads the built cams, their
evaluations and the mechanism jobs' results for the report (:mod:`camgen.report.model`).

:func:`report_input` is called by the pipeline once every other file of the run is rendered
(the cams' checks then hold the export failures, their withheld files are known).  It copies;
the report never sees the run.  The curves report.html draws are taken only for a run that
writes it (``drawn``): report.json alone needs none of them.
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation, CheckResult
    from camgen.jobs.base import JobResult
    from camgen.results import CamResult
    from camgen.report.model import (
        CamBody,
        CamPlots,
        CamReport,
        CheckRow,
        CompliantCurves,
        DynamicsCurves,
        FloatArray,
        FrictionCurves,
        JsonValue,
        MotionCurves,
        ReportInput,
        SectionData,
    )
    from camgen.scene import Scene

__all__ = ["frozen_json", "report_input"]

#: Chord tolerance (mm) of the profile and pitch curve drawn to scale in report.html.
DRAWING_CHORD_MM = 0.01


def report_input(scene: "Scene", cams: "Sequence[CamResult]", jobs: "Mapping[str, JobResult]", stages: Iterable[str],
                 files: Sequence[str], drawn: bool) -> "ReportInput":
    """The report of a run of ``scene`` that built ``cams``, ran ``jobs`` and the ``stages``, and
    writes ``files`` (report.json and report.html included); ``drawn``: with the curves
    report.html draws."""
    from camgen import __version__
    from camgen.export.tablemeta import tables_metadata
    from camgen.jobs import get_job
    from camgen.report.model import MechanismReport, ReportInput
    from camgen.textfile import display_path

    mechanisms = {name: job.report for name, job in jobs.items()}
    return ReportInput(
        scene=scene.name,
        camgen_version=__version__,
        source_file=display_path(scene.source),
        chord_tol_mm=scene.output.chord_tol,
        tool_radius_mm=scene.machining.tool_radius,
        stages=tuple(sorted(stages)),
        files=tuple(files),
        cams=tuple(_cam(cam, drawn) for cam in cams),
        mechanisms=tuple(MechanismReport(name, _json_object(job.report), get_job(name).report_section,
                                         _section(job.plots) if drawn else None) for name, job in jobs.items()),
        tables=_json_object(tables_metadata(scene, cams, files, mechanisms)),
    )


def frozen_json(value: Any) -> "JsonValue":
    """A read-only copy of a report.json tree: dicts as read-only mappings, lists as tuples,
    numpy values as Python's (what report.json writes)."""
    if isinstance(value, Mapping):
        return MappingProxyType({str(k): frozen_json(v) for k, v in value.items()})
    if isinstance(value, (list, tuple)):
        return tuple(frozen_json(v) for v in value)
    if isinstance(value, np.ndarray):
        return frozen_json(value.tolist())
    if isinstance(value, np.generic):
        return frozen_json(value.item())
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    from camgen.errors import ExportError

    raise ExportError(f"report value {value!r} has unsupported type {type(value).__name__}")


def _json_object(value: Mapping[str, Any]) -> "Mapping[str, JsonValue]":
    frozen = frozen_json(value)
    assert isinstance(frozen, Mapping)
    return frozen


def _array(values: Any) -> "FloatArray":
    """A read-only view of ``values`` as floats (no copy of a float array)."""
    out = np.asarray(values, dtype=float).view()
    out.flags.writeable = False
    return out


def _check(check: "CheckResult") -> "CheckRow":
    from camgen.report.model import CheckRow

    status: Literal["pass", "fail", "info"] = "info" if check.passed is None else "pass" if check.passed else "fail"
    return CheckRow(check.name, status, check.value, check.limit, check.comparison, check.unit, tuple(check.where_deg), check.note,
                    check.blocks_manufacture, check.where_unit)


def _cam(cam: "CamResult", drawn: bool) -> "CamReport":
    from camgen.kinds import get_kind
    from camgen.report.model import CamReport

    ev = cam.evaluation
    return CamReport(
        name=cam.name,
        kind=cam.kind,
        form=cam.spec.form,
        manufacturable=cam.manufacturable,
        withheld_files=tuple(cam.withheld),
        figures=_json_object(cam.figures),
        checks=tuple(_check(c) for c in cam.checks),
        rpm=cam.rpm,
        body=_body(cam) if drawn and cam.built.planar else None,  # a plate's thickness, bore and keyway (a barrel states its cylinder)
        plots=_plots(cam, ev) if drawn and ev is not None and cam.built.planar else None,  # a body that is no plate draws its own
        dynamics=_dynamics(cam) if drawn else None,
        report_section=get_kind(cam.kind, cam.spec.form).report_section,
        section=_section(cam.built.section) if drawn else None,
    )


def _section(data: object) -> "SectionData | None":
    from camgen.report.model import SectionData

    return data if isinstance(data, SectionData) else None


def _body(cam: "CamResult") -> "CamBody | None":
    from camgen.report.model import CamBody

    body = cam.body
    if body is None:
        return None
    corners = _array(body.keyway_corners()) if body.bore_diameter > 0 and body.keyway_width > 0 else None
    return CamBody(body.thickness, body.bore_diameter, body.keyway_width, body.keyway_depth, body.keyway_angle, body.min_wall, corners)


def _plots(cam: "CamResult", ev: "CamEvaluation") -> "CamPlots":
    from camgen.report.model import CamPlots, FollowerFaces, RollerAtZero

    outline = cam.contour if cam.contour is not None else ev.pitch
    follower = ev.follower
    faces = roller = None
    if ev.follower_drawing is None and follower is not None and cam.contour is not None:
        d = np.array([math.cos(follower.direction), math.sin(follower.direction)])
        side = np.array([-d[1], d[0]])
        if follower.contact in ("faces", "face"):  # the face touches the profile where its support function says
            h = float(cam.contour.support(np.array([follower.direction]))[0])
            faces = FollowerFaces(follower.direction, (h,) + ((h - cam.breadth,) if follower.contact == "faces" and cam.breadth is not None else ()))
        elif ev.motion is not None and follower.motion == "translating":
            centre = ev.motion.displacement[0] * d + follower.offset * side
            roller = RollerAtZero((float(centre[0]), float(centre[1])), follower.roller_radius)
    return CamPlots(
        profile=_array(cam.contour.flatten(DRAWING_CHORD_MM)) if cam.contour is not None else None,
        pitch=_array(ev.pitch.flatten(DRAWING_CHORD_MM)) if ev.pitch is not None else None,
        outline_bounds=_bounds(outline.bounds) if outline is not None else None,
        zero_mark=cam.zero_mark,
        follower_drawing=tuple((label, _array(poly)) for label, poly in ev.follower_drawing) if ev.follower_drawing is not None else None,
        faces=faces,
        roller=roller,
        pressure_angle=(_array(ev.pressure_angle[0]), _array(ev.pressure_angle[1])) if ev.pressure_angle is not None else None,
        pressure_angle_label=ev.pressure_angle_label,
        follower_limit_deg=math.degrees(follower.limit) if follower is not None else None,
        curvature=(_array(ev.curvature_radius[0]), _array(ev.curvature_radius[1])) if ev.curvature_radius is not None else None,
        curvature_label=ev.curvature_label,
        curvature_angle_label=ev.curvature_angle_label,
        curvature_limit=ev.curvature_limit,
        motion=_motion(ev, cam.rpm),
        animation=ev.animation,
        walls=tuple((wall.layer, _array(wall.contour.flatten(DRAWING_CHORD_MM))) for pocket in cam.pockets for wall in pocket.walls),
    )


def _bounds(bounds: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    xmin, ymin, xmax, ymax = bounds
    return float(xmin), float(ymin), float(xmax), float(ymax)


def _motion(ev: "CamEvaluation", rpm: float | None) -> "MotionCurves | None":
    from camgen.report.model import MotionAtSpeed, MotionCurves

    m = ev.motion
    if m is None:
        return None
    at_speed = None
    if rpm:
        v, a, j, units = m.rates(rpm)
        at_speed = MotionAtSpeed(rpm, _array(v), _array(a), _array(j), units["velocity"], units["acceleration"], units["jerk"])
    return MotionCurves(_array(m.cam_angle), _array(m.lift), _array(m.velocity), _array(m.acceleration), _array(m.jerk), m.unit,
                        tuple(m.jerk_impulses_deg), at_speed)


def _dynamics(cam: "CamResult") -> "DynamicsCurves | None":
    from camgen.report.model import DynamicsCurves

    outcome = cam.dynamics
    if outcome is None:
        return None
    res = outcome.result

    def optional(values: Any) -> "FloatArray | None":
        return _array(values) if values is not None else None

    return DynamicsCurves(
        rpm=res.rpm, closure="form" if res.train.closure == "form" else "force", motion=res.train.motion, theta=_array(res.theta),
        contact_force=_array(res.contact_force), contact_force_2=optional(res.contact_force_2),
        pressure_angle=_array(res.pressure_angle), torque=_array(res.torque), power=_array(res.power),
        hertz_stress=optional(res.hertz_stress), hertz_stress_2=optional(res.hertz_stress_2),
        follower_force=_array(res.follower_force), side_force=_array(res.side_force), jump_margin=res.jump_margin,
        jump_rpm=res.jump_rpm, torque_peak=res.torque_peak, torque_rms=res.torque_rms, power_peak=res.power_peak,
        power_rms=res.power_rms, mean_power=res.mean_power, hertz_peak=res.hertz_peak, torque_limit=outcome.torque_limit,
        allowable_stress=outcome.allowable_stress, speed_rpm=optional(outcome.speed_rpm), speed_min_force=optional(outcome.speed_min_force),
        compliant=_compliant(outcome), friction=_friction(outcome))


def _compliant(outcome: Any) -> "CompliantCurves | None":
    """The report's curves of a compliant train (issue 25 item 2), None for a rigid one."""
    from camgen.report.model import CompliantCurves

    res = outcome.compliant
    if res is None:
        return None
    translating = res.motion == "translating"
    scale = 1e-3 if translating else 1.0  # mm/s^2 -> m/s^2
    return CompliantCurves(
        theta=_array(res.theta), contact_force=_array(res.contact_force), rigid_force=_array(res.rigid_force),
        error=_array(res.error), error_unit="mm" if translating else "rad", spectrum=_array(res.harmonics() * scale),
        spectrum_unit="m/s^2" if translating else "rad/s^2", natural_frequency=res.natural_frequency,
        turn_frequency=res.turn_frequency, damping_ratio=res.damping_ratio, dwell_theta=_array(res.theta[res.dwell_start]),
        residual=_array(res.residual), residual_limit=res.residual_limit,
        natural_frequencies=getattr(res, "natural_frequencies", None),  # a two-mass train (camgen.compliant_two)
        cam_side_error=None if getattr(res, "cam_side_error", None) is None else _array(res.cam_side_error))


def _friction(outcome: Any) -> "FrictionCurves | None":
    """The report's curves of friction, loads and contact life (issue 25 items 3, 4), None when
    the scene gives none of their keys.  The roller's traction limit ``mu_c F R`` and the torque
    that turns it (the slip ratio times that limit) are read back from the slip ratio of
    :func:`camgen.friction.analyse_friction` (same contact friction, same force)."""
    from camgen.friction import DEFAULT_CONTACT_FRICTION
    from camgen.report.model import FrictionCurves

    block = outcome.friction_life
    if block is None:
        return None
    fr, life, res = block.friction, block.life, outcome.result
    force = np.maximum(res.contact_force, 0.0)  # a lifted follower carries none (as the friction module counts it)
    torques: dict[str, Any] = {}
    if fr.friction_torque is not None and np.any(fr.friction_torque != 0):  # as report.json's torque_with_friction figures
        torques = {"torque": _array(res.torque), "torque_with_friction": _array(fr.total_torque),
                   "friction_torque": _array(fr.friction_torque)}
    guide: dict[str, Any] = {}
    if fr.guide_near is not None and fr.guide_far is not None:
        guide = {"guide_near": _array(np.abs(fr.guide_near)), "guide_far": _array(np.abs(fr.guide_far)),
                 "binding": _array(fr.binding), "guide_friction": float(block.figures["guide_friction"])}
    roller: dict[str, Any] = {}
    if fr.pin_torque is not None and fr.slip is not None:
        mu_c = block.figures.get("contact_friction", DEFAULT_CONTACT_FRICTION)
        traction = mu_c * force * outcome.kinematics.follower_radius  # N*mm, friction.analyse_friction's traction
        drive = np.where(np.isfinite(fr.slip), fr.slip * traction, np.nan)  # slip = drive / traction where loaded
        roller = {"pin_torque": _array(fr.pin_torque), "roller_drive_torque": _array(drive), "traction_limit": _array(traction),
                  "slip_peak": float(np.max(fr.slip))}
    fatigue: dict[str, Any] = {}
    if life is not None:
        fatigue = {"half_width": _array(life.half_width), "shear": _array(life.shear), "shear_depth": _array(life.shear_depth),
                   "case_depth": float(life.case_depth)}
    return FrictionCurves(theta=_array(res.theta), side_load=_array(fr.side_load) if fr.side_load is not None else None,
                          **torques, **guide, **roller, **fatigue)
