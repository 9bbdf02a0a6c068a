"""The horse-leg analysis of a scene: leg paths per inclination, Section 6.1 figures, sweep.

Scene table ``[mechanisms.horse_leg]``: ``stride_cam`` and ``height_cam`` name three-arc cams
of the scene; ``inclinations_deg`` (default 12.5, 14.5, 18.5) get a path file and report
figures; ``sweep_deg = [from, to, step]`` (default 10, 19, 0.5) the trajectory cluster with
the pressure-angle limit ``pressure_angle_limit_deg`` (default 45); ``ground_y_mm``;
``positions`` per cam turn (default 3600).
"""
from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from camgen.errors import CamgenError, ParameterError
from camgen.mechanisms import horse_leg as hl


def _leg(params: Mapping[str, Any], cams: Mapping[str, Any]) -> hl.HorseLeg:
    stride = cams[params["stride_cam"]].figures
    height = cams[params["height_cam"]].figures
    return hl.HorseLeg(
        stride_cam=(stride["a_mm"], stride["b_mm"], stride["c_mm"]),
        height_cam=(height["a_mm"], height["b_mm"], height["c_mm"]),
        ground_y=params.get("ground_y", hl.HorseLeg.ground_y),
    )


def sweep_values(params: Mapping[str, Any]) -> np.ndarray:
    """Inclinations (rad) of the sweep ``[from, to, step]`` (deg in the scene)."""
    sweep = params.get("sweep", (10.0, 19.0, 0.5))
    if len(sweep) != 3 or sweep[2] <= 0 or sweep[1] < sweep[0] or (sweep[1] - sweep[0]) / sweep[2] > 200:
        raise ParameterError("mechanisms.horse_leg.sweep_deg", list(sweep), "[from, to, step] with to >= from, step > 0, at most 200 steps")
    count = int(math.floor((sweep[1] - sweep[0]) / sweep[2] + 1e-9)) + 1
    return np.radians(sweep[0] + sweep[2] * np.arange(count))


def horse_leg_job(scene: Any, cams: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, str], dict[str, Any]]:
    """Report section ``mechanisms.horse_leg``, the files ``leg_path_alpha_<deg>.csv``, and the
    solutions (for report.html).  Adds the mechanism's pressure-angle checks to the two cams."""
    from camgen.export.tables import csv_table

    params = scene.mechanisms["horse_leg"]
    leg = _leg(params, cams)
    positions = params.get("positions", 3600)
    theta1 = hl.cycle(positions)
    limit = params.get("pressure_angle_limit", math.radians(45.0))
    cam_contours = hl._cams(leg)
    report: dict[str, Any] = {
        "grashof_margin_mm": hl.grashof_margin(leg),
        "ground_y_mm": leg.ground_y,
        "pressure_angle_limit_deg": math.degrees(limit),
        "positions": positions,
    }
    files: dict[str, str] = {}
    solutions = {}
    for alpha_deg in params.get("inclinations", (12.5, 14.5, 18.5)):
        sol = hl.solve_leg(leg, math.radians(alpha_deg), theta1, cams=cam_contours)
        solutions[alpha_deg] = sol
        figures = hl.gait_figures(leg, sol)
        figures["alpha1_deg"] = float(alpha_deg)
        figures["pressure_angle_within_limit"] = bool(np.max(sol.pressure_angle) <= limit)
        label = f"{alpha_deg:g}"
        report[f"alpha_{label}"] = figures
        files[f"leg_path_alpha_{label}.csv"] = csv_table(
            [
                f"camgen horse-robot leg end point W (paper 000, eq. 18), alpha1 = {label} deg, scene '{scene.name}'",
                "units: deg, mm; frame: origin O1 at the stride-cam centre, x right, y up",
                f"pressure_angle_deg: stride-cam pressure angle (eqs. 19-25 with the slide term of eq. 4); ground line y = {leg.ground_y:g} mm",
            ],
            {"theta1_deg": np.degrees(theta1), "x_mm": sol.w[:, 0], "y_mm": sol.w[:, 1], "pressure_angle_deg": np.degrees(sol.pressure_angle)},
        )
    sweep = []
    sweep_solutions = {}
    for alpha in sweep_values(params):
        row: dict[str, Any] = {"alpha1_deg": round(math.degrees(alpha), 9)}
        try:
            sol = hl.solve_leg(leg, alpha, hl.cycle(720), cams=cam_contours)
            sweep_solutions[row["alpha1_deg"]] = sol
            row["max_pressure_angle_deg"] = float(np.degrees(sol.pressure_angle.max()))
            row["within_limit"] = bool(sol.pressure_angle.max() <= limit)
            row["foot_y_range_mm"] = [float(sol.w[:, 1].min()), float(sol.w[:, 1].max())]
            row["foot_x_range_mm"] = [float(sol.w[:, 0].min()), float(sol.w[:, 0].max())]
        except CamgenError as exc:
            row["error"] = str(exc)
            row["within_limit"] = False
        sweep.append(row)
    report["sweep"] = sweep
    _add_checks(leg, params, cams, solutions, limit)
    for alpha_deg, sol in solutions.items():  # how far along the stride fork's face the cam touches
        report[f"alpha_{alpha_deg:g}"]["stride_fork_contact_offset_range_mm"] = [float(sol.h.min()), float(sol.h.max())]
    return report, files, {"leg": leg, "solutions": solutions, "sweep": sweep, "sweep_solutions": sweep_solutions, "limit": limit}


def _add_checks(leg: hl.HorseLeg, params: Mapping[str, Any], cams: Mapping[str, Any], solutions: Mapping[float, Any], limit: float) -> None:
    """Pressure-angle checks of the two cams in the mechanism (worst over the inclinations)."""
    from camgen.checks import CheckResult

    for cam_key, values, what in (
        ("stride_cam", lambda s: s.pressure_angle, "stride cam on its yoke (eqs. 19-25)"),
        ("height_cam", lambda s: hl.height_fork_pressure_angle(leg, s), "height cam on its fork swinging about O5"),
    ):
        worst_alpha, worst_sol = max(solutions.items(), key=lambda item: float(np.max(values(item[1]))))
        angle = values(worst_sol)
        i = int(np.argmax(angle))
        check = CheckResult(
            "pressure_angle", float(np.degrees(angle[i])), float(np.degrees(limit)), "deg", bool(angle[i] <= limit),
            [round(float(np.degrees(worst_sol.theta1[i])), 6)],
            f"largest pressure angle of the {what} over alpha1 = {', '.join(f'{a:g}' for a in solutions)} deg "
            f"(worst at alpha1 = {worst_alpha:g} deg; where_deg is the stride-cam angle theta1)",
        )
        cam = cams[params[cam_key]]
        cam.checks[:] = [c for c in cam.checks if c.name != "pressure_angle"] + [check]
        if cam.evaluation is not None:  # report.html draws the mechanism's curve, not the translating face's zero
            cam.evaluation.pressure_angle = (worst_sol.theta1, angle)
            cam.evaluation.pressure_angle_label = f"in the horse leg, alpha1 = {worst_alpha:g} deg, against the stride-cam angle theta1"
