"""Motion ``trajectory``: a steering cam from a required periodic path (paper 004, the tricycle).

Synthesis by arc length, curvature and a periodic cubic spline
(:func:`camgen.mechanisms.tricycle.tricycle_cam`); the follower is the steering rod, a
radially translating roller of radius ``rod_radius_mm``.  Stages: ``analysis`` simulates the
ride on the cam as made (figures and ``<cam>_ride.csv``) and fits the paper's error model to
the measured tables; ``plots`` computes what report.html draws (rides with the error types,
fitted model curves).  The path is what the vehicle must do, not a follower law: the paper's
synthesis realises it as an open plate cam (form ``plate``) directly, so this motion is a design
of its own.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError, ParameterError, SceneError, UndercutError
from camgen.kinds.base import (
    BuiltCam,
    CamKind,
    CamSpec,
    body_keys,
    check_keys,
    field_default,
    read_body,
    read_checks,
    rename_errors,
    source_key,
    with_cam,
)
from camgen.kinds.groove import groove_keys
from camgen.motions.base import Motion
from camgen.schema import Choice, ChoiceList, Count, Key, Length, Text

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation
    from camgen.contour import Contour
    from camgen.mechanisms.tricycle import GrooveWalls, Ride, Tricycle, TricycleCam
    from camgen.report.sections import TricycleSection
    from camgen.synthesis.trajectory import Trajectory

#: Largest number of samples per cam turn (the spline and its offset grow with it).
MAX_SAMPLES = 20000
#: Largest distance (mm) between a cam's path and a measured table's ideal column (printed to
#: 1e-5 mm; the paper's formula meets it within 4.1e-4 mm) for ``fit_tables`` to fit that table.
FIT_PATH_TOL = 0.01


def _device_default(name: str) -> Any:
    from camgen.mechanisms.tricycle import Tricycle

    return field_default(Tricycle, name)


_DEVICE = ("wheelbase", "half_track", "lever", "rod_radius", "z_rear", "z_cam", "worm_teeth")

KEYS = (
    Key("expression", Text(2000), "The path y = f(x) over one period, mm: numbers, x, pi, + - * / **, sin cos tan exp log sqrt abs. "
        "Give exactly one of expression (with period_mm) and trajectory_csv. Right turns must keep a radius > "
        "half_track_mm + lever_mm * wheelbase_mm / (wheelbase_mm - rod_radius_mm) (80.6 mm for Table 2), else the cam "
        "radius of eq. (13) is <= 0: such a path is refused naming this key.", ("profile",), feeds=("trajectory",)),
    Key("trajectory_csv", Text(), "A CSV file of x, y rows (mm) over one period, relative to the scene file: two fields a row "
        "(comma, semicolon or blanks; no decimal commas), # comments, one optional header row, at most 100000 rows. The path "
        "obeys expression's limits.", ("profile",), feeds=("trajectory", "trajectory table")),
    Key("period_mm", Length(), "Period of the expression's path: the distance travelled per cam turn along x.", ("profile",)),
    Key("samples", Count(16, MAX_SAMPLES), "Cam angles per turn at which the cam radius is computed (N).", ("profile",), default=720),
    Key("curvature", Choice(("exact", "forward", "central")),
        "Path curvature: exact derivatives, or the paper's eq. (12) forward/central differences.", ("profile",), default="exact"),
    Key("wheelbase_mm", Length(), "L: rear shaft to the steered wheel (Table 2); > rod_radius_mm.", ("profile",), default=_device_default("wheelbase")),
    Key("half_track_mm", Length(), "D: lateral distance of each rear wheel from the centre line.", ("profile",),
        default=_device_default("half_track")),
    Key("lever_mm", Length(), "d: active length of the steering rod (eq. 14 uses 30 mm).", ("profile",), default=_device_default("lever")),
    Key("rod_radius_mm", Length(), "r_d: radius of the steering rod, the cam's follower (< wheelbase_mm: r_b = L - r_d > 0).", ("profile", "pitch"),
        default=_device_default("rod_radius")),
    Key("z_rear", Count(1, 100000, "teeth"), "Z1: teeth of the rear-shaft gear (drive-wheel diameter).", ("report",),
        default=_device_default("z_rear")),
    Key("z_cam", Count(1, 100000, "teeth"), "Z2: teeth of the camshaft gear (drive-wheel diameter).", ("report",),
        default=_device_default("z_cam")),
    Key("worm_teeth", Count(1, 100000, "teeth"), "Z3: teeth of the fine-tuning worm wheel (eq. 17), for the fits' advice.", ("report",)),
    Key("ride_periods", Count(1, 1000), "Cam turns of the long ride simulation (its error in the report).", ("report",), default=10),
    Key("fit_tables", ChoiceList(("A1", "A2")),
        "Fit the error model to the paper's measured trajectories (Appendix A: rides of the paper's path "
        "202.4396*sin(pi*x/1000), period 2000 mm); only for a path within 0.01 mm of that one at the tables' x (on another path "
        "the fit would take the difference between the paths for the machine's errors). A table that does not determine the five parameters for this cam (the model's "
        "ride does not reach the table's last x, 2296 mm for A1 and 2063 mm for A2, or the scaled Jacobian's condition number exceeds 1e6) is refused naming this "
        "key: its uncertainties would be infinite and its adjustment advice meaningless.", ("report",)),
    source_key(),
) + body_keys() + check_keys(oscillating=False)


@dataclass(frozen=True)
class TrajectoryParams:
    """The path, the device and the synthesis options (mm, rad)."""

    trajectory: "Trajectory"
    device: "Tricycle"
    samples: int
    curvature: str
    ride_periods: int
    fit_tables: tuple[str, ...] = ()
    source: str | None = None
    #: the scene key that gave the path ("expression" or "trajectory_csv") and its value there
    path_key: str = "expression"
    path_value: str = ""


@dataclass(frozen=True)
class TrajectoryCam(BuiltCam):
    """A built trajectory cam: the tricycle model (and, with the plots stage, its report section's
    data in ``section``: :class:`camgen.report.sections.TricycleSection`)."""

    tricycle: "TricycleCam | None" = None


def read(where: str, name: str, parsed: dict[str, Any], base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a ``trajectory`` cam table: the path is parsed or read now."""
    from camgen.checks import Follower
    from camgen.mechanisms.tricycle import Tricycle
    from camgen.synthesis import trajectory as tr

    if ("expression" in parsed) == ("trajectory_csv" in parsed):
        raise SceneError(f"[{where}]: give exactly one of 'expression' (with 'period_mm') or 'trajectory_csv'")
    if "expression" in parsed:
        if "period" not in parsed:
            raise SceneError(f"[{where}]: 'expression' needs 'period_mm'")
        traj = rename_errors(where, lambda: tr.trajectory_from_expression(parsed["expression"], parsed["period"]),
                             tuple(k for k in KEYS if k.name != "trajectory_csv"))
    else:
        if "period" in parsed:
            raise ParameterError(f"{where}.period_mm", parsed["period"], "only with expression",
                                 "a table's period is its last x minus its first")
        path = Path(parsed["trajectory_csv"])
        path = path if path.is_absolute() or base_dir is None else base_dir / path
        traj = rename_errors(where, lambda: tr.read_trajectory_csv(str(path)),
                             tuple(k for k in KEYS if k.name != "expression"))
    if "worm_teeth" in parsed and not parsed.get("fit_tables"):
        raise ParameterError(f"{where}.worm_teeth", parsed["worm_teeth"], "only with fit_tables",
                             "Z3 enters only the fitted error model's worm-knob advice")
    device = rename_errors(where, lambda: Tricycle(**{k: parsed[k] for k in _DEVICE if k in parsed}), KEYS)
    checks = read_checks(parsed)
    follower = Follower("roller", "translating", roller_radius=device.rod_radius, pressure_angle_limit=checks.pressure_angle_limit)
    path_key = "expression" if "expression" in parsed else "trajectory_csv"
    params = TrajectoryParams(traj, device, parsed["samples"], parsed["curvature"], parsed["ride_periods"],
                              parsed.get("fit_tables", ()), parsed.get("source"), path_key, str(parsed[path_key]))
    return CamSpec(name, "trajectory", params, read_body(where, parsed), checks, follower)


def build(spec: CamSpec, stages: frozenset[str]) -> TrajectoryCam:
    """Synthesis; with ``analysis`` the ride figures, the ride file and the fits; with
    ``plots`` the report's curves."""
    from camgen.mechanisms import tricycle as tc
    from camgen.synthesis.trajectory import PathError

    p: TrajectoryParams = spec.params
    traj, device = p.trajectory, p.device
    where = f"cams.{spec.name}"
    try:
        cam = with_cam(where, lambda: tc.tricycle_cam(traj, device, p.samples, p.curvature))
    except UndercutError as exc:  # the rod cannot follow this cam: the report shows where and why
        from camgen.contour import Contour

        figures = {"trajectory": traj.source, "period_mm": traj.period, "base_radius_mm": device.base_radius}
        pitch = exc.pitch if isinstance(exc.pitch, Contour) else None
        return TrajectoryCam(spec.name, spec.kind, None, figures, spec.body, spec.follower, pitch=pitch, undercut=exc)
    except PathError as exc:  # a path this device cannot steer: the key that gave it, and which paths it can
        why = str(exc).removeprefix(f"{where}: ")
        raise ParameterError(f"{where}.{p.path_key}", p.path_value, exc.valid, why) from None
    try:
        return _analysed(spec, cam, stages)
    except GeometryError as exc:  # e.g. a profile folding back near a turn close to the steerable radius
        why = str(exc).removeprefix(f"{where}: ")
        raise ParameterError(f"{where}.{p.path_key}", p.path_value,
                             "a path whose cam profile is star-shaped about the cam axis (each ray from the axis meets it once: "
                             "the ride and the contact are measured along those rays); its sharpest right turns need a radius "
                             "somewhat above the steerable one", why) from None


def _analysed(spec: CamSpec, cam: "TricycleCam", stages: frozenset[str]) -> TrajectoryCam:
    """The figures, files and plots of a synthesised steering cam."""
    from camgen.contour import Spline
    from camgen.mechanisms import tricycle as tc

    p: TrajectoryParams = spec.params
    traj, device = p.trajectory, p.device
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
    }
    files: dict[str, str] = {}
    one = None
    if "analysis" in stages:
        one = tc.simulate_cam(cam, periods=1)
        figures["ride_max_error_mm"] = float(abs(tc.lateral_error(traj, one.x, one.y)).max())
        # one cam turn at a time, the running maximum only: memory O(samples) for any ride_periods
        figures[f"ride_max_error_{p.ride_periods}_periods_mm"] = tc.ride_max_lateral_error(cam, p.ride_periods)
    (profile,) = cam.profile.segments  # one periodic spline (paper 004's synthesis)
    assert isinstance(profile, Spline)
    figures["profile_pieces"] = int(profile.n_pieces)
    figures["area_mm2"] = cam.profile.area
    figures["perimeter_mm"] = cam.profile.length
    if p.source is not None:
        figures["source"] = p.source
    if "analysis" in stages and p.fit_tables:
        figures["fits"] = _fits(f"cams.{spec.name}", cam, p.fit_tables)
    if one is not None:
        files[f"{spec.name}_ride.csv"] = _ride_csv(spec.name, traj, one)
    plots = _plots(cam, figures.get("fits", {}), one) if "plots" in stages else None
    return TrajectoryCam(spec.name, spec.kind, cam.profile, figures, spec.body, spec.follower, pitch=cam.pitch, files=files, tricycle=cam,
                         section=plots)


def _fits(where: str, cam: "TricycleCam", tables: tuple[str, ...]) -> dict[str, Any]:
    """The error model fitted to each measured table; a table that does not determine it for
    this cam is refused naming ``fit_tables`` (no infinite uncertainty, no advice from noise)."""
    from camgen.mechanisms import tricycle as tc
    from camgen.mechanisms.tricycle_fit import FIT_MAX_CONDITION, FitNotDetermined, fit_error_model

    fits = {}
    for name in tables:
        table = tc.load_measured_table(name)
        # the tables are rides of the paper's own path: on another path the fit would blame the
        # machine's errors for the difference between the paths
        gap = np.abs(cam.trajectory.wrapped(table.x) - table.ideal)
        if not np.max(gap) <= FIT_PATH_TOL:
            worst = int(np.argmax(gap))
            raise ParameterError(
                f"{where}.fit_tables", list(tables),
                "tables measured on this cam's path: A1 and A2 are rides of paper 004's path y = 202.4396 sin(pi x / 1000) "
                f"(period 2000 mm), their ideal column within {FIT_PATH_TOL:g} mm",
                f"this cam's path '{cam.trajectory.source}' is {gap[worst]:.3g} mm from table {name}'s ideal column at x = "
                f"{table.x[worst]:g} mm: a fit would take the difference between the paths for the machine's errors",
            )
        try:
            fits[name] = fit_error_model(cam, table).as_dict()
        except FitNotDetermined as exc:
            raise ParameterError(
                f"{where}.fit_tables", list(tables),
                "tables that determine the error model for this cam: A1 and A2 are the paper's rides of its own path "
                f"y = 202.4396 sin(pi x / 1000) (period 2000 mm) measured to x = 2296 mm (A1) and 2063 mm (A2) (scaled Jacobian condition number <= {FIT_MAX_CONDITION:g})",
                f"table {name} fitted to this cam's path '{cam.trajectory.source}' does not determine the model: {exc.reason}",
            ) from None
    return fits


#: Rows per degree of cam angle of the ride table (<cam>_ride.csv): one turn in 3600 rows.
RIDE_ROWS_PER_DEG = 10
#: Columns of the ride table and what they hold.
RIDE_COLUMNS = {
    "theta_deg": "cam angle from the start of the ride, deg",
    "x_mm": "x of drive wheel A (the tracked point) in the frame of the target path, mm",
    "y_mm": "y of drive wheel A, mm",
    "lateral_error_mm": "distance of drive wheel A from the target path y = f(x) along its normal (positive to the left), mm",
}


def _ride_csv(name: str, traj: "Trajectory", one: "Ride") -> str:
    from camgen.export.tables import csv_table
    from camgen.mechanisms import tricycle as tc

    theta = np.radians(np.arange(360 * RIDE_ROWS_PER_DEG) / RIDE_ROWS_PER_DEG)
    x, y, _ = one.at(theta)
    return csv_table(dict(zip(RIDE_COLUMNS, (np.degrees(theta), x, y, tc.lateral_error(traj, x, y)))))


def ride_metadata(trajectory: str) -> dict[str, Any]:
    """What ``<cam>_ride.csv`` holds (report.json ``tables``); ``trajectory`` is the target
    path as the report's figures name it."""
    return {
        "content": "the simulated ride of drive wheel A on the cam as made (its profile contour), one cam turn",
        "columns": dict(RIDE_COLUMNS),
        "trajectory": trajectory,
        "theta_step_deg": 1.0 / RIDE_ROWS_PER_DEG,
    }


#: The error types report.html shows (paper 004, Figs. 9-10).
ERROR_CASES = {
    "design": {},
    "type I: +0.1 deg": {"steering_offset": math.radians(0.1)},
    "type I: -0.1 deg": {"steering_offset": math.radians(-0.1)},
    "type II: gain 1.1": {"steering_gain": 1.1},
    "type II: gain 0.9": {"steering_gain": 0.9},
}


#: Samples of the target path y = f(x) drawn over one period.
TARGET_SAMPLES = 801
#: Samples of each fitted table's ideal path and model curve.
FIT_CURVE_SAMPLES = 400


def _plots(cam: "TricycleCam", fits: dict[str, Any], one: "Ride | None") -> "TricycleSection":
    """What the report section draws: the target path, the ride on the cam as made with its
    lateral error, the rides with the error types, and each fitted table against its model."""
    from camgen.mechanisms import tricycle as tc
    from camgen.report.sections import FitCurves, TricycleSection

    ride = one if one is not None else tc.simulate_cam(cam)
    error_rides = {label: tc.simulate_cam(cam, tc.ErrorModel(**changes), periods=2) for label, changes in ERROR_CASES.items()}
    curves: list[FitCurves] = []
    if fits:
        from camgen.mechanisms.tricycle_fit import PARAMETERS, model_y

        geom = tc.ride_geometry(cam.profile, cam.device.rod_radius, 4)
        for name, fit in fits.items():
            table = tc.load_measured_table(name)
            xs = np.linspace(0, table.x.max(), FIT_CURVE_SAMPLES)
            p = np.array([fit["parameters"][k] for k in PARAMETERS])
            curves.append(FitCurves(name, table.x, table.measured, xs, cam.trajectory.f(np.mod(xs, cam.trajectory.period)),
                                    model_y(cam, geom, p, xs[1:]),
                                    tuple((k, fit["parameters"][k], fit["uncertainty_1sigma"][k]) for k in PARAMETERS),
                                    fit["residual_rms_mm"], fit["advice"]["note"]))
    traj = cam.trajectory
    x = np.linspace(0, traj.period, TARGET_SAMPLES)
    return TricycleSection(x, traj.f(x), ride.theta, ride.x, ride.y, tc.lateral_error(traj, ride.x, ride.y),
                           tuple((label, path.x, path.y) for label, path in error_rides.items()), tuple(curves))


# --------------------------------------------------------------------------------------------
# The groove form: the rod runs in a groove cut into a plate
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class TrajectoryGrooveParams(TrajectoryParams):
    """A steering cam cut as a groove: the clearance (mm), the groove depth and the rim radius
    (mm; None: chosen, see :func:`camgen.kinds.groove.groove_keys`)."""

    clearance: float = 0.0
    depth: float | None = None
    rim_radius: float | None = None

    @property
    def half_width(self) -> float:
        """w = r_d + c / 2 (mm): the distance of each wall from the groove's centre line, the
        rod-centre path."""
        return self.device.rod_radius + 0.5 * self.clearance


@dataclass(frozen=True, kw_only=True)
class TrajectoryGrooveCam(TrajectoryCam):
    """A steering cam whose rod runs in a groove: ``contour`` the rim circle, the walls (None
    where they cannot be made) and the conditions they were checked against (``walls``), the
    groove's offset w, depth and rim radius (mm); ``tricycle`` is the cam the ride runs on (a
    rod of radius w on the inner wall: its centre on the groove's centre line)."""

    walls: "GrooveWalls | None" = None
    inner_wall: "Contour | None" = None
    outer_wall: "Contour | None" = None
    half_width: float = 0.0
    depth: float = 0.0
    rim_radius: float = 0.0


def read_groove(where: str, name: str, parsed: dict[str, Any], base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a steering cam cut as a groove: the trajectory's keys, then the groove's."""
    from dataclasses import replace

    from camgen.kinds.groove import read_groove_depth

    spec = read(where, name, parsed, base_dir)
    p: TrajectoryParams = spec.params
    clearance = parsed["groove_clearance"]
    depth = read_groove_depth(where, parsed, spec.body.thickness)
    if not p.device.rod_radius + 0.5 * clearance < p.device.wheelbase:
        raise ParameterError(f"{where}.groove_clearance_mm", clearance,
                             f"< 2 (wheelbase_mm - rod_radius_mm) = {2.0 * (p.device.wheelbase - p.device.rod_radius):g} mm",
                             "the groove's inner wall would reach the cam axis")
    params = TrajectoryGrooveParams(**{f: getattr(p, f) for f in p.__dataclass_fields__}, clearance=clearance, depth=depth,
                                    rim_radius=parsed.get("rim_radius"))
    return replace(spec, params=params)


def build_groove(spec: CamSpec, stages: frozenset[str]) -> TrajectoryGrooveCam:
    """The groove's walls: the exact offsets of the rod-centre path by -+w
    (:func:`camgen.mechanisms.tricycle.groove_walls`); the ride and the report run on the
    groove's centre line (a rod of radius w on the inner wall: its centre on the path)."""
    from dataclasses import replace

    from camgen.kinds.base import Pocket, Wall
    from camgen.kinds.groove import INNER, OUTER, max_radius, rim_circle, rim_radius_for
    from camgen.mechanisms import tricycle as tc

    p: TrajectoryGrooveParams = spec.params
    w = p.half_width
    plate = build(spec, frozenset())  # the rod-centre path (and the rod's own undercut) as the plate cam has them
    depth = p.depth if p.depth is not None else 0.5 * spec.body.thickness
    figures = {k: v for k, v in plate.figures.items() if k not in ("profile_pieces", "area_mm2", "perimeter_mm", "contact_vs_rho_max_mm")}
    groove = {"clearance_mm": p.clearance, "width_mm": 2.0 * w, "depth_mm": depth, "wall_offset_mm": w,
              "walls": "exact offsets of the rod-centre path by -+ (rod_radius_mm + clearance / 2), one periodic spline each"}
    if plate.tricycle is None:  # the rod itself (radius r_d < w) cannot follow the path: neither wall can be made
        return TrajectoryGrooveCam(spec.name, spec.kind, None, {**figures, "groove": groove}, spec.body, spec.follower, pitch=plate.pitch,
                                   undercut=plate.undercut, half_width=w, depth=depth)
    cam = plate.tricycle
    walls = with_cam(f"cams.{spec.name}", lambda: tc.groove_walls(cam, w))
    inner, outer = walls.inner, walls.outer
    rim = p.rim_radius if p.rim_radius is not None else rim_radius_for(max_radius(outer if outer is not None else cam.pitch) +
                                                                       (0.0 if outer is not None else w), spec.body.min_wall)
    groove["rim_radius_mm"] = rim
    # the rod's centre lies anywhere within c / 2 of the centre line: tan(alpha) = (R - L) / d (paper 004, eq. 1)
    device = cam.device
    radius = cam.synthesis.rho + device.rod_radius
    alpha = np.arctan((radius - device.wheelbase) / device.lever)
    play = np.maximum(np.abs(np.arctan((radius + 0.5 * p.clearance - device.wheelbase) / device.lever) - alpha),
                      np.abs(np.arctan((radius - 0.5 * p.clearance - device.wheelbase) / device.lever) - alpha))
    groove["steering_play_deg"] = math.degrees(float(play.max()))
    if inner is None or outer is None:
        return TrajectoryGrooveCam(spec.name, spec.kind, None, {**figures, "groove": groove}, spec.body, spec.follower, pitch=cam.pitch,
                                   tricycle=cam, walls=walls, half_width=w, depth=depth, rim_radius=rim)
    assert cam.curves is not None  # groove_walls made the walls from the polar form's curves
    centre = replace(cam, profile=inner, device=replace(device, rod_radius=w), curves=replace(cam.curves, rod_radius=w),
                     fit_error=max(cam.fit_error, walls.fit_error))
    analysed = _analysed(spec, centre, stages)
    # the device's figures (r_b = L - r_d, the steering range) are the real rod's; the analysis adds the rides and fits
    figures = {k: v for k, v in {**analysed.figures, **figures}.items()
               if k not in ("profile_pieces", "area_mm2", "perimeter_mm", "contact_vs_rho_max_mm")}
    groove.update(wall_pieces=int(inner.segments[0].n_pieces), fit_error_mm=walls.fit_error,
                  groove_area_mm2=outer.area - inner.area)
    contour = rim_circle(rim)
    figures.update(groove=groove, area_mm2=contour.area)
    pocket = Pocket("groove", (Wall(OUTER, outer), Wall(INNER, inner)), depth, width=2.0 * w, centre=cam.pitch, clearance=p.clearance,
                    note=f"groove {2.0 * w:g} mm wide (steering rod {2.0 * device.rod_radius:g} mm + clearance {p.clearance:g} mm), "
                         f"{depth:g} mm deep")
    return TrajectoryGrooveCam(spec.name, spec.kind, contour, figures, spec.body, spec.follower, pitch=cam.pitch, files=analysed.files,
                               tricycle=centre, section=analysed.section, pockets=(pocket,), walls=walls, inner_wall=inner,
                               outer_wall=outer, half_width=w, depth=depth, rim_radius=rim)


def evaluate_groove(cam: BuiltCam, spec: CamSpec, tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    """The design checks of a steering cam cut as a groove (:func:`build_groove`): both walls can
    be made (the rod-centre path's |radius of curvature| > w, neither wall crossing itself), their
    continuity, the pressure angle on the rod, the walls to the bore, rim and floor, the tool."""
    from dataclasses import replace

    from camgen.checks import (CamEvaluation, CheckResult, continuity_check, evaluate_cam, motion_check, pressure_angle_check,
                               radius_of_curvature, roller_kinematics, roller_motion)
    from camgen.kinds.disk import mask_where
    from camgen.kinds.groove import groove_tool_check, groove_wall_checks

    assert isinstance(cam, TrajectoryGrooveCam), f"a steering groove's checks on a {type(cam).__name__}"
    follower = spec.follower
    assert follower is not None
    w = cam.half_width
    walls = cam.walls
    if walls is None:  # the rod itself cannot follow the path: the checks of the pitch curve against w
        return evaluate_cam(None, replace(follower, roller_radius=w), pitch=cam.pitch, rpm=spec.checks.rpm)
    order = np.argsort(walls.cam_angle)
    theta, kappa = walls.cam_angle[order], walls.pitch_curvature[order]
    inner_bad, outer_bad = walls.inner_fails[order], walls.outer_fails[order]
    bad = inner_bad | outer_bad
    with np.errstate(divide="ignore"):
        radius = np.abs(1.0 / kappa)
    worst = int(np.argmin(radius))  # the sharpest turn either way (the failing runs are listed where they are)
    parts = [f"{what}: the rod-centre path's {side} radius is at most {w:g} mm between the listed pairs of cam angles"
             for what, mask, side in (("inner wall (GROOVE_INNER)", inner_bad, "convex"), ("outer wall (GROOVE_OUTER)", outer_bad, "concave"))
             if mask.any()]
    note = (f"smallest |radius of curvature| of the rod-centre path against the walls' offset w = rod_radius_mm + clearance / 2 = {w:g} mm "
            "(the outer wall needs the concave radius above w too)")
    if parts:
        note += "; " + "; ".join(parts) + ": the groove cannot be made"
    passed = not bad.any() and walls.crossing is None
    if walls.crossing is not None:
        note += (f"; a wall crosses itself near polar angle {math.degrees(walls.crossing):.3f} deg (a neck of the rod-centre path narrower "
                 "than 2 w): the groove cannot be made")
    checks: list[CheckResult] = [CheckResult("undercut", float(radius[worst]), w, ">", "mm", passed, mask_where(bad, theta, worst), note,
                                             blocks_manufacture=True)]
    if cam.inner_wall is not None and cam.outer_wall is not None:
        inner_c, outer_c = continuity_check(cam.inner_wall), continuity_check(cam.outer_wall)
        order_names = ["none", "G0", "G1", "G2"]
        lowest = min((inner_c, outer_c), key=lambda c: order_names.index(str(c.value)))
        checks.insert(0, replace(lowest, where_deg=sorted(set(inner_c.where_deg) | set(outer_c.where_deg)), passed=inner_c.passed and outer_c.passed,
                                 note=f"inner wall: {inner_c.note}; outer wall: {outer_c.note}"))
    kin = roller_kinematics(cam.pitch, follower) if cam.pitch is not None else None
    pressure = motion = None
    if kin is not None:
        pressure = (kin.cam_angle, kin.pressure_angle)
        checks.append(pressure_angle_check(kin.pressure_angle, kin.cam_angle, follower.limit, "steering rod (translating, radial) in a groove"))
        motion = roller_motion(kin, unit="mm")
        checks.append(motion_check(motion, spec.checks.rpm))
    if cam.inner_wall is not None and cam.outer_wall is not None:
        checks.extend(groove_wall_checks(cam))
        checks.append(groove_tool_check(cam, tool_radius, tool_is_limit))
    assert cam.pitch is not None
    rho, angle = radius_of_curvature(cam.pitch)
    return CamEvaluation(tuple(checks), follower, motion, pressure, (angle, rho), cam.pitch,
                         curvature_label="radius of curvature of the rod-centre path (mm, < 0 concave); the walls need |radius| > w",
                         curvature_limit=w)


_SUMMARY = "steering cam from a required periodic path y = f(x), by arc length and a periodic spline (paper 004)"

MOTION = Motion(
    name="trajectory",
    summary=_SUMMARY,
    realisations={
        "plate": CamKind(name="trajectory", summary=_SUMMARY, keys=KEYS, read=read, build=build,
                         report_section="camgen.report.sections:tricycle_section"),
        "groove": CamKind(name="trajectory", summary=_SUMMARY + ", its rod running in a groove", keys=KEYS + groove_keys("rod_radius_mm", "rod"),
                          read=read_groove, build=build_groove, report_section="camgen.report.sections:tricycle_section",
                          evaluate=evaluate_groove),
    },
)
