"""Mechanism job ``horse_leg``: the leg of paper 000 driven by two three-arc cams of the scene.

Scene table ``[mechanisms.horse_leg]``.  The job solves the leg at each inclination in
``inclinations_deg`` (always: the two cams' pressure-angle checks come from it), writes
``leg_path_alpha_<deg>.csv`` for each, and, with the ``analysis`` stage, sweeps the inclination
(``sweep_deg = [from, to, step]``) for the trajectory cluster.  It returns its checks and
report data; the pipeline merges them (it never edits the cams itself).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.errors import CamgenError, GeometryError, ParameterError
from camgen.jobs.base import JobResult, MechanismJob
from camgen.schema import REQUIRED, Angle, Count, Key, Number, NumberList, Text

if TYPE_CHECKING:
    from camgen.kinds.base import BuiltCam, CamSpec
    from camgen.mechanisms.horse_leg import HorseLeg, LegSolution
    from camgen.report.sections import HorseLegSection

__all__ = [
    "HorseLegSpec", "JOB", "KEYS", "LEG_PATH_COLUMNS", "MAX_SWEEP_STEPS", "WHERE", "label", "leg_path_metadata",
    "read", "run", "sweep_steps", "sweep_values",
]


def _ground_default() -> float:
    from camgen.kinds.base import field_default
    from camgen.mechanisms.horse_leg import HorseLeg

    return field_default(HorseLeg, "ground_y")


#: Most steps of ``sweep_deg`` (its values are ``steps + 1`` leg solutions).
MAX_SWEEP_STEPS = 200

KEYS = (
    Key("stride_cam", Text(64), "Name of the scene's three_arc cam driving the stride (yoke at O1).", ("mechanism",), default=REQUIRED),
    Key("height_cam", Text(64), "Name of the scene's three_arc cam driving the leg height (fork swinging about O5).", ("mechanism",),
        default=REQUIRED),
    Key("inclinations_deg", NumberList(Number("deg", -90.0, 90.0), 1, 20, distinct_decimals=6),
        "Swing-rod inclinations alpha1: a leg path file and report figures each; the pressure-angle checks take the worst.",
        ("mechanism",), default=[12.5, 14.5, 18.5], attr="inclinations_deg"),
    Key("sweep_deg", NumberList(Number("deg", -90.0, 90.0), 3, 3), "Inclination sweep [from, to, step] for the trajectory cluster "
        f"(to >= from, step > 0, at most {MAX_SWEEP_STEPS} steps, counted on the decimal values given).", ("report",), default=[10.0, 19.0, 0.5], attr="sweep_deg"),
    Key("pressure_angle_limit_deg", Angle(0.0, 90.0, low_open=True, high_open=True), "Largest pressure angle allowed in the leg.",
        ("report",), default=45.0),
    Key("ground_y_mm", Number("mm", -1e5, 1e5), "Ground line below the stride-cam centre O1 (splits swing and stance): the foot path must cross it twice at every inclination, a band of about 116 mm for the paper's leg (the error gives the band).", ("mechanism",),
        default=_ground_default()),
    Key("positions", Count(36, 36000), "Cam positions per turn in the leg path files.", ("mechanism",), default=3600),
)


@dataclass(frozen=True)
class HorseLegSpec:
    """The job's settings: cam names, inclinations and sweep (deg), limit (rad), ground (mm)."""

    stride_cam: str
    height_cam: str
    inclinations_deg: tuple[float, ...]
    sweep_deg: tuple[float, float, float]
    pressure_angle_limit: float
    ground_y: float
    positions: int


def read(where: str, parsed: Mapping[str, Any], cams: Mapping[str, "CamSpec"]) -> HorseLegSpec:
    """The typed spec; the two cams must be three_arc cams of the scene."""
    three_arc = sorted(n for n, c in cams.items() if c.kind == "three_arc")
    for key in ("stride_cam", "height_cam"):
        if parsed[key] not in three_arc:
            raise ParameterError(f"{where}.{key}", parsed[key], f"the name of a three_arc cam of this scene: {three_arc}")
    sweep = parsed["sweep_deg"]
    ordered = sweep[2] > 0 and sweep[1] >= sweep[0]
    steps = sweep_steps(sweep) if ordered else 0
    if not ordered or steps > MAX_SWEEP_STEPS:
        raise ParameterError(f"{where}.sweep_deg", list(sweep), f"[from, to, step] with to >= from, step > 0, at most "
                             f"{MAX_SWEEP_STEPS} steps", "" if not ordered else f"{steps} steps" if steps < 10**6 else "over a million steps")
    return HorseLegSpec(parsed["stride_cam"], parsed["height_cam"], parsed["inclinations_deg"], sweep,
                        parsed["pressure_angle_limit"], parsed["ground_y"], parsed["positions"])


def _leg(spec: HorseLegSpec, cams: Mapping[str, "BuiltCam"]) -> "HorseLeg":
    from camgen.mechanisms.horse_leg import HorseLeg

    stride, height = cams[spec.stride_cam].figures, cams[spec.height_cam].figures
    return HorseLeg(stride_cam=(stride["a_mm"], stride["b_mm"], stride["c_mm"]),
                    height_cam=(height["a_mm"], height["b_mm"], height["c_mm"]), ground_y=spec.ground_y)


WHERE = "mechanisms.horse_leg"


def label(alpha_deg: float) -> str:
    """An inclination as written in file names and report keys: rounded to 6 decimals (the
    precision at which ``inclinations_deg`` must be distinct), trailing zeros dropped; two
    distinct inclinations never share a label (``f"{a:g}"`` keeps only 6 significant digits:
    12.499999 and 12.500001 would both be "12.5")."""
    text = f"{round(float(alpha_deg), 6):.6f}".rstrip("0").rstrip(".")
    return "0" if text == "-0" else text


def _degrees(ranges: list[tuple[float, float]]) -> str:
    """Assembly intervals (rad) as text in deg, rounded inwards to 0.001 deg."""
    return ", ".join(f"{math.ceil(math.degrees(lo) * 1000) / 1000:g} to {math.floor(math.degrees(hi) * 1000) / 1000:g}"
                     for lo, hi in ranges)


def _ground_text(lines: list[tuple[float, float]]) -> str:
    """Ground lines (mm, half-open intervals ``[low, high)``) as text, rounded inwards to 0.1 mm
    ("-2142.5 to -2080.1 mm, or -2079.8 to -2033.1 mm")."""
    parts = []
    for low, high in lines:
        lo, hi = math.ceil(low * 10) / 10, math.floor(high * 10) / 10
        if hi >= high:  # the upper end itself is not in the interval
            hi = round(hi - 0.1, 1)
        if lo <= hi:
            parts.append(f"{lo:.1f} to {hi:.1f} mm")
    return ", or ".join(parts) if parts else "no ground line"


def _leg_error(leg: "HorseLeg", spec: HorseLegSpec, index: int, exc: GeometryError, cams: Any,
               sol: "LegSolution | None" = None) -> ParameterError:
    """The leg cannot walk at ``spec.inclinations_deg[index]``: a ParameterError naming the scene
    key to change (the inclination, the ground line or a cam) with the valid values.

    The valid inclinations are those at which the leg assembles *and* its foot path crosses the
    ground line twice (one swing, one stance: :func:`~camgen.mechanisms.horse_leg.gait_range`);
    for a leg that assembles, the ground lines that would serve at this inclination are added
    (:func:`~camgen.mechanisms.horse_leg.ground_lines`)."""
    from camgen.mechanisms import horse_leg as hl

    alpha_deg = spec.inclinations_deg[index]
    key = f"{WHERE}.inclinations_deg[{index}]"
    why = " ".join(str(exc).split())
    try:
        ranges = hl.assembly_range(leg, spec.positions, cams=cams)
    except GeometryError as side:  # the loops that do not depend on alpha1: the height cam does not fit
        return ParameterError(f"{WHERE}.height_cam", spec.height_cam, "a three_arc cam of the scene that the leg's height fork "
                              f"(half-width e5 = {leg.e5:g} mm, pivot O5) can ride", " ".join(str(side).split()))
    if not ranges:
        lo, hi = (math.degrees(a) for a in hl.ASSEMBLY_SCAN)
        return ParameterError(f"{WHERE}.stride_cam", spec.stride_cam, "a three_arc cam of the scene with which the leg assembles "
                              f"at some inclination alpha1", f"no alpha1 from {lo:g} to {hi:g} deg (steps of "
                              f"{math.degrees(hl.ASSEMBLY_STEP):g} deg) closes every loop with cams '{spec.stride_cam}' and "
                              f"'{spec.height_cam}'; at alpha1 = {alpha_deg:g} deg: {why}")
    walking = hl.gait_range(leg, spec.positions, cams=cams, assembly=ranges)
    assembles = f"the leg assembles with cams '{spec.stride_cam}' and '{spec.height_cam}' from {_degrees(ranges)} deg"
    grounds = "" if sol is None else f"; or set ground_y_mm to {_ground_text(hl.ground_lines(sol.w[:, 1]))} for alpha1 = {alpha_deg:g} deg"
    if not walking:
        if sol is None:
            return ParameterError(key, alpha_deg, f"alpha1 at which {assembles}", why)
        return ParameterError(f"{WHERE}.ground_y_mm", spec.ground_y, "a ground line the foot path crosses twice (one swing, one "
                              "stance) at some inclination", f"{why}; {assembles}, but at none of them its foot path crosses this ground line twice{grounds}")
    walks = _degrees(walking)
    if walks != _degrees(ranges):
        assembles += f", but its foot walks on the ground line y = {spec.ground_y:g} mm only from {walks} deg"
    return ParameterError(key, alpha_deg, f"alpha1 at which the leg assembles and its foot path crosses the ground line "
                          f"y = {spec.ground_y:g} mm twice (one swing, one stance): {walks} deg", f"{why}; {assembles}{grounds}")


def sweep_steps(sweep_deg: tuple[float, float, float]) -> int:
    """Whole steps of the sweep ``[from, to, step]`` (deg, step > 0) from ``from`` up to ``to``,
    counted exactly on the numbers as the scene wrote them (their shortest decimal text):
    ``[0, 20, 0.1]`` is 200 steps, although ``20 / 0.1`` is 200.00000000000003 in binary."""
    start, stop, step = (Fraction(repr(float(v))) for v in sweep_deg)
    return int((stop - start) // step)


#: Columns of the leg path tables (leg_path_alpha_<deg>.csv) and what they hold.
LEG_PATH_COLUMNS = {
    "theta1_deg": "stride-cam angle theta1, deg",
    "x_mm": "x of the leg end point W (paper 000, eq. 18; origin O1 at the stride-cam centre, x right, y up), mm",
    "y_mm": "y of W, mm",
    "pressure_angle_deg": "stride-cam pressure angle (paper 000, eqs. 19-25 with the slide term of eq. 4), deg",
}


def leg_path_metadata(alpha_deg: float, ground_y: float) -> dict[str, Any]:
    """What ``leg_path_alpha_<deg>.csv`` holds (report.json ``tables``)."""
    return {
        "content": "the horse-robot leg's end point W over one turn of the stride cam at one swing-rod inclination alpha1",
        "columns": dict(LEG_PATH_COLUMNS),
        "alpha1_deg": float(alpha_deg),
        "ground_y_mm": float(ground_y),
    }


def sweep_values(sweep_deg: tuple[float, float, float]) -> np.ndarray:
    """Inclinations (rad) of the sweep ``[from, to, step]`` (deg): ``from + k step`` for
    ``k = 0 .. sweep_steps``, the last never beyond ``to`` by rounding."""
    start, stop, step = sweep_deg
    values = start + step * np.arange(sweep_steps(sweep_deg) + 1)
    return np.radians(np.minimum(values, stop))


def run(spec: HorseLegSpec, cams: Mapping[str, "BuiltCam"], stages: frozenset[str], scene_name: str) -> JobResult:
    """Leg paths per inclination, Section 6.1 figures, the cams' pressure-angle checks and,
    with ``analysis``, the inclination sweep; errors name the mechanism's table."""
    from camgen.kinds.base import with_cam

    return with_cam("mechanisms.horse_leg", lambda: _run(spec, cams, stages, scene_name))


def _run(spec: HorseLegSpec, cams: Mapping[str, "BuiltCam"], stages: frozenset[str], scene_name: str) -> JobResult:
    from camgen.export.tables import csv_table
    from camgen.mechanisms import horse_leg as hl

    leg = _leg(spec, cams)
    theta1 = hl.cycle(spec.positions)
    limit = spec.pressure_angle_limit
    cam_contours = hl.leg_cams(leg)
    report: dict[str, Any] = {
        "grashof_margin_mm": hl.grashof_margin(leg),
        "ground_y_mm": leg.ground_y,
        "pressure_angle_limit_deg": math.degrees(limit),
        "positions": spec.positions,
    }
    files: dict[str, str] = {}
    solutions = {}
    for index, alpha_deg in enumerate(spec.inclinations_deg):
        sol = None
        try:
            sol = hl.solve_leg(leg, math.radians(alpha_deg), theta1, cams=cam_contours)
            figures = hl.gait_figures(leg, sol)
        except GeometryError as exc:
            raise _leg_error(leg, spec, index, exc, cam_contours, sol) from None
        solutions[alpha_deg] = sol
        figures["alpha1_deg"] = float(alpha_deg)
        figures["pressure_angle_within_limit"] = bool(np.max(sol.pressure_angle) <= limit)
        name = label(alpha_deg)
        report[f"alpha_{name}"] = figures
        files[f"leg_path_alpha_{name}.csv"] = csv_table(dict(zip(
            LEG_PATH_COLUMNS, (np.degrees(theta1), sol.w[:, 0], sol.w[:, 1], np.degrees(sol.pressure_angle)))))
    sweep: list[dict[str, Any]] = []
    sweep_solutions = {}
    if "analysis" in stages:
        for alpha in sweep_values(spec.sweep_deg):
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
    checks, curves = _checks(leg, spec, solutions, limit)
    for alpha_deg, sol in solutions.items():  # how far along the stride fork's face the cam touches
        report[f"alpha_{label(alpha_deg)}"]["stride_fork_contact_offset_range_mm"] = [float(sol.h.min()), float(sol.h.max())]
    plots = _plots(leg, solutions, sweep_solutions, limit) if "plots" in stages else None
    return JobResult(report, files, checks, curves, plots)


def _plots(leg: "HorseLeg", solutions: Mapping[float, "LegSolution"], sweep_solutions: Mapping[float, "LegSolution"],
           limit: float) -> "HorseLegSection":
    """What the report section draws: the leg at each inclination with its stance body path,
    and over the sweep (:class:`camgen.report.sections.HorseLegSection`)."""
    from camgen.mechanisms import horse_leg as hl
    from camgen.report.sections import HorseLegSection, LegPath

    legs = []
    for alpha, sol in solutions.items():
        try:
            body = hl.body_path(leg, sol)
        except CamgenError:  # a path that misses the ground has no stance
            body = None
        legs.append(LegPath(alpha, sol.w, sol.theta1, sol.pressure_angle, body))
    sweep = tuple(LegPath(alpha, sol.w, sol.theta1, sol.pressure_angle) for alpha, sol in sweep_solutions.items())
    return HorseLegSection(leg.ground_y, limit, tuple(legs), sweep)


def _checks(leg: "HorseLeg", spec: HorseLegSpec, solutions: Mapping[float, "LegSolution"], limit: float):
    """Pressure-angle checks of the two cams in the mechanism (worst over the inclinations),
    and the curves report.html draws for them."""
    from camgen.checks import CheckResult
    from camgen.mechanisms import horse_leg as hl

    checks: dict[str, list[CheckResult]] = {}
    curves: dict[str, tuple[np.ndarray, np.ndarray, str]] = {}
    for cam_name, values, what in (
        (spec.stride_cam, lambda s: s.pressure_angle, "stride cam on its yoke (eqs. 19-25)"),
        (spec.height_cam, lambda s: hl.height_fork_pressure_angle(leg, s), "height cam on its fork swinging about O5"),
    ):
        worst_alpha, worst_sol = max(solutions.items(), key=lambda item: float(np.max(values(item[1]))))
        angle = values(worst_sol)
        i = int(np.argmax(angle))
        check = CheckResult(
            "pressure_angle", float(np.degrees(angle[i])), float(np.degrees(limit)), "<=", "deg", bool(angle[i] <= limit),
            [round(float(np.degrees(worst_sol.theta1[i])), 6)],
            f"largest pressure angle of the {what} over alpha1 = {', '.join(label(a) for a in solutions)} deg "
            f"(worst at alpha1 = {label(worst_alpha)} deg; where_deg is the stride-cam angle theta1)",
        )
        checks.setdefault(cam_name, []).append(check)
        curves[cam_name] = (worst_sol.theta1, angle, f"in the horse leg, alpha1 = {label(worst_alpha)} deg, against the stride-cam angle theta1")
    return checks, curves


JOB = MechanismJob(
    name="horse_leg",
    summary="single leg of the quadruped horse robot driven by two three-arc cams (paper 000, Sections 3-6)",
    keys=KEYS,
    read=read,
    run=run,
    report_section="camgen.report.sections:horse_leg_section",
)
