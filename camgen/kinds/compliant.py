"""The compliant follower train at scene level: its keys, reading them, its figures and checks.

The keys (:func:`compliant_keys`, appended to :func:`camgen.kinds.dynamics.dynamics_keys`)
give the train's stiffness between the cam contact and the follower's mass (translating
``train_stiffness_n_per_mm``; oscillating ``train_stiffness_n_mm_per_rad`` about the pivot),
the damping ratio of its mode and a residual-vibration limit.  Without a stiffness the train
is rigid, as before (nothing changes).  The physics is :mod:`camgen.compliant`; the stage
(:func:`camgen.kinds.dynamics.run_dynamics`) calls :func:`run_compliant`, whose figures go to
report.json's ``figures.dynamics.compliant`` and whose checks ("residual_vibration",
"dynamic_jump") fail the run (exit 1) like every design check.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.compliant_two import SPRING_PLACES
from camgen.errors import GeometryError, ParameterError
from camgen.schema import Choice, Key, Length, Number

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.compliant import CompliantResult, TrainCompliance
    from camgen.dynamics import FollowerTrain, Kinematics

_T = {"follower_motion": ("translating",)}
_O = {"follower_motion": ("oscillating",)}
_R = ("report",)
STIFFNESS_KEYS = ("train_stiffness_n_per_mm", "train_stiffness_n_mm_per_rad")
#: kg, the least mass of each of a two-mass train's masses (1 mg: a lighter one is rounding noise).
MIN_MASS_KG = 1e-6
#: The two-mass train's keys: given together (translating), with the train stiffness.
TWO_MASS_KEYS = ("follower_stiffness_n_per_mm", "tool_mass_kg")
#: The damping ratio when a stiffness is given without one (a lightly damped train).
DEFAULT_DAMPING_RATIO = 0.05


def compliant_keys() -> tuple[Key, ...]:
    """The compliant train's keys (each stored under its own name)."""
    return (
        Key("train_stiffness_n_per_mm", Number("N/mm", 0.0, 1e10, low_open=True), "Translating follower: stiffness of the "
            "follower train between the cam contact and its mass (follower rod, roller pin, guide); given, the train vibrates on "
            "it (one degree of freedom, natural frequency sqrt((stiffness + spring rate) / mass_kg)): the periodic response "
            "over a turn, the dynamic contact force and jump, the residual vibration after each rise and return, the "
            "acceleration spectrum against the natural frequency (left out: a rigid train).", _R, example=2000.0, requires=_T,
            feeds=("train_stiffness",)),
        Key("train_stiffness_n_mm_per_rad", Number("N*mm/rad", 0.0, 1e13, low_open=True), "Oscillating follower: torsional "
            "stiffness of the arm train about the pivot between the cam contact and the arm's inertia (natural frequency "
            "sqrt((stiffness + spring rate) / inertia_kg_m2)); as train_stiffness_n_per_mm.", _R, example=2e7, requires=_O,
            feeds=("train_stiffness",)),
        Key("damping_ratio", Number("", 0.0, 1.0, high_open=True), "With a train stiffness: damping ratio of the train's mode "
            f"(0 undamped, < 1; default {DEFAULT_DAMPING_RATIO:g}, a lightly damped train: give a measured one).", _R,
            example=0.1, feeds=("damping_ratio",)),
        Key("residual_vibration_limit_mm", Length(), "With a train stiffness: largest residual vibration amplitude allowed in "
            "the dwell after each rise and return (an arm: at the roller centre; a two-mass train: of the tool mass); the "
            "residual_vibration check fails above it (left out: the amplitude is information).", _R, example=0.05,
            feeds=("residual_vibration_limit",)),
        # two degrees of freedom (camgen/compliant_two.py)
        Key("follower_stiffness_n_per_mm", Number("N/mm", 0.0, 1e10, low_open=True), "Translating follower, with "
            "train_stiffness_n_per_mm and tool_mass_kg: the follower's own stiffness between its cam-side mass (roller, rod end: "
            "mass_kg - tool_mass_kg, behind the train stiffness) and the tool mass; the train then has two masses and two modes "
            "(a damper across each spring, c = 2 damping_ratio sqrt(k m) with the train's k1 + spring rate on mass_kg and the "
            "follower's k2 on the masses' reduced mass): both natural frequencies against the spectrum, the tool's dynamic "
            "error and residual vibration, the contact force on the train stiffness (left out: one mass).", _R,
            example=5000.0, requires=_T, feeds=("follower_stiffness",)),
        Key("tool_mass_kg", Number("kg", MIN_MASS_KG, 1e4), "With follower_stiffness_n_per_mm: the tool-side part of "
            "mass_kg (mass_kg stays the whole moving mass, the rigid model's and the weight's; tool_mass_kg < mass_kg), beyond "
            "the follower's own stiffness; the external load presses on it, the weight is shared by mass.", _R, example=0.2,
            requires=_T, feeds=("tool_mass",)),
        Key("return_spring_on", Choice(SPRING_PLACES), "With follower_stiffness_n_per_mm: the mass the return spring (its "
            "rate, preload and the follower's damping_n_s_per_m) acts on: \"tool\" (the tool-side mass, as a valve spring) or "
            "\"cam_side\" (the roller's rod end).", _R, default="tool", example="cam_side", requires=_T,
            feeds=("spring_at",)),
    )


def read_compliance(where: str, parsed: Mapping[str, Any], given: tuple[str, ...], *, translating: bool,
                    form_closed: bool) -> "TrainCompliance | None":
    """The :class:`camgen.compliant.TrainCompliance` of a cam table, None without a stiffness.

    Raises :class:`ParameterError` naming the key: a damping ratio or limit without a
    stiffness, a stiffness on a form-closed train or with no moving mass."""
    from camgen.compliant import TrainCompliance

    stiffness = STIFFNESS_KEYS[0] if translating else STIFFNESS_KEYS[1]
    keys = {k.name: k for k in compliant_keys()}  # stored under their own names (dynamics_keys)
    follower = read_follower_compliance(where, parsed, given, stiffness)
    if stiffness not in given:
        for name in ("damping_ratio", "residual_vibration_limit_mm"):
            if name in given:
                raise ParameterError(f"{where}.{name}", keys[name].type.to_scene(parsed.get(name)),
                                     f"left out without {stiffness}",
                                     f"it describes the compliant follower train, which {stiffness} turns on")
        return None
    value = float(parsed[stiffness])  # given: the key's type read it as a number
    if form_closed:
        raise ParameterError(f"{where}.{stiffness}", value, "left out for a form-closed train",
                             "the compliant model is of a spring-loaded follower (a form-closed train's two contacts are not modelled)")
    inertia = "mass_kg" if translating else "inertia_kg_m2"
    if not parsed.get(inertia, 0.0) > 0:
        raise ParameterError(f"{where}.{inertia}", parsed.get(inertia, 0.0), f"{inertia} > 0 with {stiffness}",
                             "the compliant train's mass vibrates on its stiffness")
    zeta = parsed.get("damping_ratio")
    limit = parsed.get("residual_vibration_limit_mm")
    try:
        return TrainCompliance(value, DEFAULT_DAMPING_RATIO if zeta is None else float(zeta),
                               None if limit is None else float(limit), follower)
    except ParameterError as exc:  # the ranges of the keys refuse these first: kept for a direct caller
        name = {"train_stiffness": stiffness, "damping_ratio": "damping_ratio",
                "residual_vibration_limit": "residual_vibration_limit_mm"}.get(exc.name, exc.name)
        raise ParameterError(f"{where}.{name}", exc.value, exc.valid, exc.why) from None


def read_follower_compliance(where: str, parsed: Mapping[str, Any], given: tuple[str, ...], stiffness: str) -> Any:
    """The two-mass train's :class:`camgen.compliant_two.FollowerCompliance`, None without its keys.

    Raises :class:`ParameterError` naming the key: one of :data:`TWO_MASS_KEYS` without the
    other or without the train stiffness, ``return_spring_on`` without them, a tool mass not
    below ``mass_kg`` (the keys' ``requires`` refuse them on an oscillating follower)."""
    from camgen.compliant_two import FollowerCompliance

    present = [name for name in TWO_MASS_KEYS if name in given]
    if not present:
        if "return_spring_on" in given:
            raise ParameterError(f"{where}.return_spring_on", parsed.get("return_spring_on"),
                                 "left out without follower_stiffness_n_per_mm and tool_mass_kg",
                                 "it places the return spring on one of a two-mass train's masses")
        return None
    for name in TWO_MASS_KEYS:
        if name not in given:
            first = present[0]
            raise ParameterError(f"{where}.{first}", parsed[first], f"given with {name}",
                                 "the two-mass train needs the follower's stiffness and the tool mass together")
    if stiffness not in given:
        raise ParameterError(f"{where}.{TWO_MASS_KEYS[0]}", parsed[TWO_MASS_KEYS[0]], f"given with {stiffness}",
                             "the follower's stiffness is the second spring of a compliant train")
    tool, total = float(parsed["tool_mass_kg"]), float(parsed.get("mass_kg", 0.0))
    if not tool <= total - MIN_MASS_KG:
        raise ParameterError(f"{where}.tool_mass_kg", tool, f"tool_mass_kg <= mass_kg - {MIN_MASS_KG:g} ({total - MIN_MASS_KG:g} kg)",
                             "mass_kg is the whole moving mass, the tool's part of it beyond the follower's stiffness")
    return FollowerCompliance(float(parsed["follower_stiffness_n_per_mm"]), tool, str(parsed.get("return_spring_on") or "tool"))


def run_compliant(kin: "Kinematics", train: "FollowerTrain", compliance: "TrainCompliance", rpm: float,
                  jump_margin: float) -> "tuple[CompliantResult | None, list[CheckResult], dict[str, Any]]":
    """The compliant response at ``rpm``, its checks and figures (``figures.dynamics.compliant``);
    an undamped train in resonance with the turn has none: an information check says why."""
    from camgen.checks import information
    from camgen.compliant import compliant_response

    from dataclasses import replace

    respond = compliant_response
    if compliance.follower is not None:  # two masses: the follower's own stiffness between them (camgen/compliant_two.py)
        from camgen.compliant_two import two_degree_response as respond
    try:
        result = replace(respond(kin, train, compliance, rpm), residual_limit=compliance.residual_limit)
    except GeometryError as exc:
        return None, [information("dynamic_jump", "not computed", "", [], str(exc))], {}
    figures = {"train_stiffness_" + ("N_per_mm" if train.motion == "translating" else "Nmm_per_rad"): compliance.stiffness,
               "damping_ratio": compliance.damping_ratio, **result.figures()}
    if compliance.residual_limit is not None:
        figures["residual_vibration_limit_mm"] = compliance.residual_limit
    return result, compliant_checks(result, compliance, jump_margin), figures


def compliant_checks(result: "CompliantResult", compliance: "TrainCompliance", jump_margin: float) -> "list[CheckResult]":
    """"dynamic_jump" (the least dynamic contact force against the jump margin) and
    "residual_vibration" (the largest amplitude in a dwell against the limit, or information)."""
    from camgen.checks import information, limited, run_ends, where_degrees

    theta, force = result.theta, result.contact_force
    i = int(np.argmin(force))
    bad = force < jump_margin
    where = run_ends(bad, theta) if bad.any() else where_degrees(theta[i])
    modes = getattr(result, "natural_frequencies", None)  # a two-mass train (camgen.compliant_two.TwoDegreeResult)
    if modes is not None:
        zetas = getattr(result, "damping_ratios")
        train = (f"two-mass compliant train (natural frequencies {modes[0]:.6g} and {modes[1]:.6g} Hz = "
                 f"{modes[0] / result.turn_frequency:.4g} and {modes[1] / result.turn_frequency:.4g} x the turn, damping ratios "
                 f"{zetas[0]:.4g} and {zetas[1]:.4g})")
    else:
        train = (f"compliant train (natural frequency {result.natural_frequency:.6g} Hz = "
                 f"{result.natural_frequency / result.turn_frequency:.4g} x the turn, damping ratio {result.damping_ratio:.4g})")
    note = (f"{train}: smallest dynamic contact force {force[i]:.6g} N at cam angle "
            f"{math.degrees(theta[i]):.6g} deg against a margin of {jump_margin:g} N (rigid train: {np.min(result.rigid_force):.6g} N); "
            f"peak dynamic force {np.max(force):.6g} N, {result.amplification:.4g} x the rigid peak")
    if result.jump_ranges_deg:
        note += "; the follower leaves the cam between the listed pairs of cam angles (the linear model holds until it does)"
    checks = [limited("dynamic_jump", float(force[i]), ">=", jump_margin, "N", where, note)]
    starts = result.dwell_start
    if starts.size == 0:
        checks.append(information("residual_vibration", "no dwell", "mm", [], "the law has no dwell: no residual vibration "
                                  "after a rise or return is defined"))
        return checks
    j = int(np.argmax(result.residual))
    note = (("the tool mass's " if modes is not None else "") +
            f"free vibration amplitude at the start of each dwell after a rise or return (listed cam angles; largest "
            f"{result.residual[j]:.6g} mm at {math.degrees(theta[starts[j]]):.6g} deg), about the dwell's static deflection; "
            + ("the sum of both modes' amplitudes at the tool" if modes is not None else
               f"it decays with damping ratio {result.damping_ratio:.4g}"))
    limit = compliance.residual_limit
    if limit is None:
        checks.append(information("residual_vibration", result.residual_peak, "mm", where_degrees(theta[starts]),
                                  note + "; give residual_vibration_limit_mm to check it"))
    else:
        over = starts[result.residual > limit]
        checks.append(limited("residual_vibration", result.residual_peak, "<=", limit, "mm",
                              where_degrees(theta[over if over.size else starts[[j]]]), note))
    return checks
