"""The checks stage: one built cam in, its :class:`~camgen.checks.CamEvaluation` out (frozen).

A kind with its own checks (closed-form kinematics: the disk cams) evaluates itself; the others
get the generic checks of their contour with the scene's follower
(:func:`camgen.checks.evaluate_cam`).  This stage adds what every cam shares: an undercut the
synthesis found becomes a failed check (with its curvature curve to plot), the wall between
bore/keyway and profile is checked, and the follower and its motion at speed go into the figures.
"""
from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation, CheckResult
    from camgen.kinds.base import BuiltCam, CamSpec

__all__ = ["evaluate", "wall_check"]


def evaluate(cam: "BuiltCam", spec: "CamSpec", tool_radius: float, tool_is_limit: bool,
             report_figures: bool = True) -> "CamEvaluation":
    """The design checks of one built cam, its wall check and the figures they add.

    ``tool_radius``: the cutting tool's radius (mm); ``tool_is_limit``: the concave radii are held
    to it (the scene names a tool or machines the cam), else it is information; ``report_figures``
    False leaves out the figures no check needs (the acceleration harmonics:
    :attr:`camgen.planning.Plan.report_figures`).
    """
    from camgen.checks import CheckResult, evaluate_cam
    from camgen.kinds import get_kind

    follower = cam.follower
    own = get_kind(spec.kind, spec.form).evaluate
    if own is not None:  # the kind's own (closed-form) checks
        evaluation = own(cam, spec, tool_radius, tool_is_limit)
    else:
        assert follower is not None, f"kind {spec.kind!r} has neither its own checks nor a follower model"
        pitch = cam.pitch if follower.contact == "point" else None
        evaluation = evaluate_cam(cam.contour, follower, tool_radius, spec.checks.rpm, cam.breadth, pitch, tool_is_limit)
    checks: list[CheckResult] = list(evaluation.checks)
    changes: dict[str, Any] = {}
    if cam.contour is None and cam.undercut is not None and not any(c.name == "undercut" and c.failed for c in checks):
        exc = cam.undercut  # the synthesis found the undercut: a failed check, with its curvature curve when it has one
        curve: Any = exc.curve  # (cam angle rad, radius of curvature mm) arrays, or None
        value: Any = float(curve[1].min()) if curve is not None else "undercut"
        checks = [CheckResult("undercut", value, exc.limit, ">", "mm", False, exc.where_deg, " ".join(str(exc).split()),
                              blocks_manufacture=True)] + [c for c in checks if c.name != "undercut"]
        if exc.curve is not None:
            changes.update(curvature_radius=exc.curve, curvature_label="radius of curvature of the envelope (mm)",
                           curvature_limit=exc.limit)
    if cam.body.bore_diameter > 0 and cam.contour is not None and not any(c.name == "wall_thickness" for c in checks):
        checks.append(wall_check(cam))  # (a form with pockets checks the wall to its innermost wall itself)
    figures: dict[str, Any] = dict(evaluation.figures)
    if own is None and follower is not None:  # a kind with its own checks reports its follower itself
        figures["follower"] = {"kind": follower.kind, "motion": follower.motion, "roller_radius_mm": follower.roller_radius,
                               "offset_mm": follower.offset, "pressure_angle_limit_deg": math.degrees(follower.limit)}
    rpm = spec.checks.rpm
    if rpm and evaluation.motion is not None:
        figures["motion_at_rpm"] = {"rpm": rpm, **evaluation.motion.at_rpm(rpm)}
    # ---- VDI (issue 26 item 5): the jerk limit at rpm, the law's harmonic content ----
    from camgen.kinds.jerk_limit import jerk_limit_check
    from camgen.synthesis.harmonics import harmonic_figures

    checks += jerk_limit_check(spec.checks.jerk_limit, spec.checks.rpm, evaluation.motion)
    harmonics = harmonic_figures(evaluation.motion, rpm) if report_figures else {}
    if harmonics:
        figures["acceleration_harmonics"] = harmonics
    # ---- end VDI ----
    return dataclasses.replace(evaluation, checks=tuple(checks), figures=figures, **changes)


def wall_check(cam: "BuiltCam") -> "CheckResult":
    """Wall left between bore/keyway and profile against ``min_wall`` (blocks manufacture)."""
    from camgen.body import wall_left
    from camgen.checks import limited

    assert cam.contour is not None
    wall, where = wall_left(cam.contour, cam.body)
    what = "the bore/keyway breaks through the profile" if wall <= 0 else f"thinnest wall between the bore/keyway and the profile, {wall:.3f} mm"
    note = what if wall >= cam.body.min_wall else what + ": use a smaller bore or keyway, or a smaller min_wall_mm"
    return limited("wall_thickness", wall, ">=", cam.body.min_wall, "mm", [round(where, 6)], note, blocks_manufacture=True)
