"""Mechanism job ``machine``: several cams of the scene on one shaft (issue 25, item 1).

Scene table ``[mechanisms.machine]`` with one ``[[mechanisms.machine.cams]]`` table per cam on the
shaft (its ``name`` and ``phase_deg``: the cam angle when the machine angle is 0).  A mechanism
job is the seam: jobs run after every cam's design checks and dynamics (:func:`camgen.pipeline.compute`),
receive the cams by name, and put their own section in report.json (``mechanisms.machine``) and
report.html; the scene reader validates their keys like every other table and ``camgen keys``
documents them.

The machine speed ``rpm`` is the shaft's: a cam of the machine that gives its own ``rpm`` (every
cam with dynamics keys does) must give the same, or the scene is refused naming ``cams.<cam>.rpm``.
The job writes the timing diagram (every follower's displacement, and velocity and acceleration
on request, against machine angle), the camshaft torque and power of the machine (the sum of
its cams' torques from their dynamics, each read at its phase: :mod:`camgen.machine`), the
flywheel that holds ``speed_fluctuation`` and the motor's torque and power.  A cam without
dynamics keys contributes no torque and is named in ``cams_without_dynamics``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.errors import ParameterError
from camgen.jobs.base import JobResult, MechanismJob
from camgen.schema import REQUIRED, Angle, ChoiceList, Count, Key, Number, TableList, Text

if TYPE_CHECKING:
    from camgen.kinds.base import CamSpec
    from camgen.report.machine import MachineSection
    from camgen.results import CamResult

__all__ = ["CAM_KEYS", "JOB", "KEYS", "MachineCam", "MachineSpec", "TIMING_CURVES", "WHERE", "read", "run"]

WHERE = "mechanisms.machine"
#: The curves the timing diagram can show.
TIMING_CURVES = ("displacement", "velocity", "acceleration")
#: Most cams on one machine.
MAX_CAMS = 64

CAM_KEYS = (
    Key("name", Text(64), "Name of a cam of the scene on the machine's shaft.", ("report",), default=REQUIRED),
    Key("phase_deg", Angle(0.0, 360.0, high_open=True), "The cam's angle when the machine angle is 0 (both in the direction of "
        "rotation): the cam is at cam angle machine angle + phase.", ("report",), default=0.0, attr="phase"),
)

KEYS = (
    Key("cams", TableList(CAM_KEYS, 1, MAX_CAMS, "[[mechanisms.machine.cams]] tables"), "The cams on the shaft, each once, with "
        "its phase.", ("report",), default=REQUIRED),
    Key("rpm", Number("rev/min", 1e-3, 1e6), "Machine (shaft) speed; a cam of the machine that gives its own rpm must give this "
        "one.", ("report",), default=REQUIRED),
    Key("speed_fluctuation", Number("", 0.0, 1.0, low_open=True, high_open=True), "Coefficient of speed fluctuation Cs = "
        "(w_max - w_min) / w_mean the flywheel must hold (energy method, Norton, Design of Machinery, ch. 11).", ("report",),
        default=0.05),
    Key("samples", Count(360, 36000), "Machine angles per turn at which the cams' torques are summed, the flywheel sized and "
        "the curves of report.json given.", ("report",), default=1440),
    Key("timing_curves", ChoiceList(TIMING_CURVES), "What the timing diagram shows for every follower against machine angle "
        "(velocity and acceleration at the machine speed).", ("report",), default=["displacement"]),
    Key("motor_torque_limit_n_m", Number("N*m", 0.0, 1e8, low_open=True), "The motor's rated torque: the machine_motor_torque "
        "check fails when the motor torque with the flywheel (the mean camshaft torque) exceeds it (left out: no check; the figure is in report.json).",
        ("report",), example=2.0, attr="motor_torque_limit"),
    Key("motor_power_limit_w", Number("W", 0.0, 1e9, low_open=True), "The motor's rated power: the machine_motor_power check "
        "fails when the motor's peak power with the flywheel exceeds it (left out: no check; the figure is in report.json).", ("report",), example=100.0,
        attr="motor_power_limit"),
)


@dataclass(frozen=True)
class MachineCam:
    """A cam on the shaft: its name and phase (rad)."""

    name: str
    phase: float


@dataclass(frozen=True)
class MachineSpec:
    """The machine: its cams, speed (rpm), Cs, samples per turn, timing curves, motor limits
    (N*m, W; None: information)."""

    cams: tuple[MachineCam, ...]
    rpm: float
    speed_fluctuation: float
    samples: int
    timing_curves: tuple[str, ...]
    motor_torque_limit: float | None = None
    motor_power_limit: float | None = None


def read(where: str, parsed: Mapping[str, Any], cams: Mapping[str, "CamSpec"]) -> MachineSpec:
    """The typed spec: every cam a turning cam of the scene, named once, at the machine's speed."""
    names = sorted(cams)
    seen: dict[str, int] = {}
    out = []
    rpm = parsed["rpm"]
    for i, entry in enumerate(parsed["cams"]):
        name = entry["name"]
        key = f"{where}.cams[{i}].name"
        if name not in cams:
            raise ParameterError(key, name, f"the name of a cam of this scene: {names}")
        if name in seen:
            raise ParameterError(key, name, "each cam of the machine named once", f"cam '{name}' is also cams[{seen[name]}]")
        seen[name] = i
        spec = cams[name]
        if spec.form == "linear":
            raise ParameterError(key, name, "a cam turning on the shaft", f"cam '{name}' is a linear (translating) cam")
        own = spec.checks.rpm
        if own is not None and own != rpm:
            raise ParameterError(f"cams.{name}.rpm", own, f"the machine's speed, {rpm:g} rev/min ({where}.rpm)",
                                 f"cam '{name}' turns on the machine's shaft")
        out.append(MachineCam(name, entry["phase"]))
    return MachineSpec(tuple(out), rpm, parsed["speed_fluctuation"], parsed["samples"], parsed["timing_curves"],
                       parsed.get("motor_torque_limit"), parsed.get("motor_power_limit"))


@dataclass(frozen=True)
class FollowerTiming:
    """One follower against machine angle: s, s', s'' per rad of cam angle (mm, or rad of swing
    for an oscillating follower) at the machine angles, its phase (rad) and unit ("mm", "rad")."""

    name: str
    phase: float
    unit: str
    s: np.ndarray
    ds: np.ndarray
    d2s: np.ndarray


def _motion(cam: "CamResult") -> str:
    """``"translating"`` or ``"oscillating"``: how the follower of ``cam`` moves."""
    stage = cam.dynamics_stage
    if stage is not None and stage.outcome is not None:
        return stage.outcome.result.train.motion
    follower = getattr(cam.built, "spec_follower", None)
    return getattr(follower, "motion", "translating")


def _timing(cam: "CamResult", phase: float, angles: np.ndarray) -> FollowerTiming | None:
    """The follower of ``cam`` at machine angles ``angles``: from the cam's displacement law
    (exact at every angle), else from its dynamics kinematics (interpolated); None: neither."""
    from camgen.machine import shifted

    unit = "rad" if _motion(cam) == "oscillating" else "mm"
    law = getattr(cam.built, "law", None)
    if callable(law):
        s, ds, d2s, _ = law(np.mod(angles + phase, 2.0 * math.pi))
        return FollowerTiming(cam.name, phase, unit, np.asarray(s, float), np.asarray(ds, float), np.asarray(d2s, float))
    stage = cam.dynamics_stage
    if stage is not None and stage.outcome is not None:
        kin = stage.outcome.kinematics
        return FollowerTiming(cam.name, phase, unit, *(shifted(kin.theta, v, phase, angles) for v in (kin.s, kin.ds, kin.d2s)))
    return None


def _floats(values: np.ndarray) -> list[float]:
    return [float(v) for v in values]


def run(spec: MachineSpec, cams: Mapping[str, "CamResult"], stages: frozenset[str], scene_name: str) -> JobResult:
    """The timing diagram, the machine's torque and power, the flywheel and the motor."""
    from camgen.kinds.base import with_cam

    return with_cam(WHERE, lambda: _run(spec, cams, stages))


def _run(spec: MachineSpec, cams: Mapping[str, "CamResult"], stages: frozenset[str]) -> JobResult:
    from camgen import machine as mc

    angles = mc.machine_angles(spec.samples)
    omega = spec.rpm * 2.0 * math.pi / 60.0
    torques: list[mc.PhasedTorque] = []
    frictional: list[str] = []  # the cams whose torque includes friction
    without: dict[str, str] = {}
    timings: list[FollowerTiming] = []
    no_motion: list[str] = []
    rows = []
    for entry in spec.cams:
        cam = cams[entry.name]
        stage = cam.dynamics_stage
        if stage is None:
            without[entry.name] = "no dynamics keys"
        elif stage.outcome is None:
            without[entry.name] = "dynamics not computed (see the cam's dynamics check)"
        else:  # with the friction torque where the cam's friction keys give it (camgen.friction: first order)
            life = stage.outcome.friction_life
            with_friction = life.friction.total_torque if life is not None and life.friction is not None else None
            torque_curve = with_friction if with_friction is not None else stage.outcome.result.torque
            if with_friction is not None:
                frictional.append(entry.name)
            torques.append(mc.PhasedTorque(entry.name, stage.outcome.result.theta, torque_curve, entry.phase))
        timing = _timing(cam, entry.phase, angles)
        if timing is None:
            no_motion.append(entry.name)
        else:
            timings.append(timing)
        rows.append({"name": entry.name, "phase_deg": round(math.degrees(entry.phase), 9), "follower_motion": _motion(cam),
                     "torque": entry.name not in without})
    torque = mc.combined_torque(torques, angles)
    power = torque * omega
    fly = mc.flywheel(torque, spec.rpm, spec.speed_fluctuation)
    degrees = np.degrees(angles)
    i_peak = int(np.argmax(np.abs(torque)))
    motor_power = fly.mean_torque * fly.speed
    report: dict[str, Any] = {
        "rpm": spec.rpm,
        "speed_fluctuation": spec.speed_fluctuation,
        "samples": spec.samples,
        "cams": rows,
        "cams_without_dynamics": dict(without),
        "cams_without_motion": list(no_motion),
        "torque_model": "the sum of the cams' camshaft torques (each cam's dynamics at the machine speed, read at cam angle = "
                        "machine angle + phase by periodic linear interpolation of its own samples; with its friction torque where "
                        "its friction keys give one); > 0: the shaft drives the cams",
        "cams_with_friction": list(frictional),
        "torque_peak_Nm": float(abs(torque[i_peak])),
        "torque_peak_deg": round(float(degrees[i_peak]), 6),
        "torque_rms_Nm": mc.turn_rms(torque),
        "torque_mean_Nm": fly.mean_torque,
        "power_peak_W": float(np.max(np.abs(power))),
        "power_rms_W": mc.turn_rms(power),
        "power_mean_W": fly.mean_torque * omega,
        "flywheel": {
            "method": "energy method (Norton, Design of Machinery, ch. 11): I = dE / (Cs w^2), dE the largest swing of "
                      "int (T_mean - T) dphi over a turn, w = (w_max + w_min) / 2 the machine speed",
            "energy_swing_J": fly.energy_swing,
            "inertia_kg_m2": fly.inertia,
            "speed_min_rpm": float(fly.speed.min() * 60.0 / (2.0 * math.pi)),
            "speed_max_rpm": float(fly.speed.max() * 60.0 / (2.0 * math.pi)),
            "speed_time_mean_rpm": fly.time_mean_speed * 60.0 / (2.0 * math.pi),
            "speed_fluctuation_left": fly.fluctuation,
        },
        "motor": {
            "model": "without a flywheel the motor holds the machine speed and gives the shaft torque at every angle; with the "
                     "flywheel it gives a constant torque, the mean shaft torque, and the flywheel the rest (its speed varies "
                     "by speed_fluctuation)",
            "without_flywheel": {"torque_peak_Nm": float(abs(torque[i_peak])), "torque_rms_Nm": mc.turn_rms(torque),
                                 "power_peak_W": float(np.max(np.abs(power))), "power_rms_W": mc.turn_rms(power)},
            "with_flywheel": {"torque_peak_Nm": abs(fly.mean_torque), "torque_rms_Nm": abs(fly.mean_torque),
                              "power_peak_W": float(np.max(np.abs(motor_power))), "power_rms_W": mc.turn_rms(motor_power)},
        },
        "curves": _curves(spec, degrees, omega, timings, torque, power, fly),
    }
    checks = _checks(spec, report, without, torques)
    plots = None
    if "plots" in stages:
        from camgen.report.machine import MachineSection

        plots = MachineSection(angles, tuple(timings), spec.timing_curves, omega, torque, fly.speed, fly.mean_torque,
                               tuple(t.name for t in torques))
    return JobResult(report, {}, checks, {}, plots)


def _curves(spec: MachineSpec, degrees: np.ndarray, omega: float, timings: list[FollowerTiming], torque: np.ndarray,
            power: np.ndarray, fly: Any) -> dict[str, Any]:
    """report.json's curves against machine angle (units in the keys)."""
    out: dict[str, Any] = {"machine_angle_deg": _floats(degrees), "torque_Nm": _floats(torque), "power_W": _floats(power),
                           "speed_with_flywheel_rpm": _floats(fly.speed * 60.0 / (2.0 * math.pi))}
    followers: dict[str, Any] = {}
    for t in timings:
        scale, unit = (180.0 / math.pi, "deg") if t.unit == "rad" else (1.0, "mm")
        row: dict[str, Any] = {"phase_deg": round(math.degrees(t.phase), 9)}
        if "displacement" in spec.timing_curves:
            row[f"displacement_{unit}"] = _floats(scale * t.s)
        if "velocity" in spec.timing_curves:
            row[f"velocity_{unit}_per_s"] = _floats(scale * omega * t.ds)
        if "acceleration" in spec.timing_curves:
            row[f"acceleration_{unit}_per_s2"] = _floats(scale * omega**2 * t.d2s)
        followers[t.name] = row
    out["followers"] = followers
    return out


def _checks(spec: MachineSpec, report: Mapping[str, Any], without: Mapping[str, str], torques: list[Any]) -> dict[str, list[Any]]:
    """The motor checks where limits are given, on the machine's first cam (a check belongs to a cam)."""
    from camgen.checks import limited

    checks = []
    named = f"machine of cams {', '.join(c.name for c in spec.cams)}"
    quiet = f"; no torque from {', '.join(without)} (no dynamics)" if without else ""
    motor = report["motor"]["with_flywheel"]
    if spec.motor_torque_limit is not None:
        checks.append(limited("machine_motor_torque", motor["torque_peak_Nm"], "<=", spec.motor_torque_limit, "N*m", [],
                              f"the {named}: motor torque with the flywheel (the mean shaft torque) at {spec.rpm:g} rpm" + quiet))
    if spec.motor_power_limit is not None:
        checks.append(limited("machine_motor_power", motor["power_peak_W"], "<=", spec.motor_power_limit, "W", [],
                              f"the {named}: the motor's peak power with the flywheel (mean torque x highest speed)" + quiet))
    return {spec.cams[0].name: checks} if checks else {}


JOB = MechanismJob(
    name="machine",
    summary="several cams on one shaft: timing diagram, combined camshaft torque, flywheel and motor (issue 25)",
    keys=KEYS,
    read=read,
    run=run,
    report_section="camgen.report.machine:machine_section",
)
