"""Constant-breadth and constant-diameter cams for any displacement law: keys, reading, building
and checks (the machinery of :mod:`camgen.forms.constant_breadth`).

The follower translates along ``+y`` through the cam axis and holds the cam from both sides: a
yoke (two parallel flat faces ``B`` apart: constant breadth) or two rollers of one radius whose
centres are ``D`` apart (constant diameter of the pitch curve).  The law obeys
``s(theta + pi) = C - s(theta)`` with ``C = B - 2 Rb`` (yoke) or ``C = D - 2 (Rb + r)`` (rollers);
the derivation is in :mod:`camgen.synthesis.breadth`.  The user gives the first half-turn
(``half_turn = true``: the motion completes it by the rule) or the whole turn (checked against
the rule, refused naming the segment that breaks it).

The profile is the plate machinery's exact envelope of the upper face (a flat face) or the upper
roller (:func:`camgen.kinds.disk.build_disk`); the lower face or roller touches it by the rule.
The checks are the plate cam's closed-form ones over the whole turn (the lower face or roller
meets at cam angle ``theta`` what the upper one meets at ``theta + 180 deg``, so undercut,
curvature, face length and pressure angle cover both), plus the breadth (diameter) measured on
the profile (pitch curve) in 3600 directions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.errors import ParameterError
from camgen.kinds.base import CamSpec, body_keys, check_keys, source_key
from camgen.kinds.disk import ANIMATION_FRAMES, ANIMATION_SECONDS, DEFAULT_FIT_TOL, FIT_TOL_MAX, DiskCam, DiskParams, own_keys
from camgen.schema import Choice, Flag, Key, Length, Number

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation, CheckResult
    from camgen.motions.base import Motion

__all__ = ["BREADTH_TOL_FACTOR", "BreadthCam", "BreadthParams", "DIRECTIONS", "build_breadth", "evaluate_breadth", "keys",
           "read_breadth"]

#: The breadth (diameter) check's limit is this many times ``fit_tol_mm``: each of the two
#: opposite contacts lies within the fit tolerance of the exact envelope.
BREADTH_TOL_FACTOR = 2.0
#: Directions (uniform over the turn) in which the breadth or diameter is measured.
DIRECTIONS = 3600
#: Default pressure-angle limit of a yoke, rad (pressure_angle_limit_deg's documented default).
YOKE_PRESSURE_LIMIT = math.radians(45.0)
#: Largest |B - (2 Rb + C)| (relative to max(1, B)) when both base_radius_mm and the size are given.
SIZE_AGREEMENT = 1e-9


def _faces_followers() -> tuple[str, ...]:
    from camgen.followers import follower_names

    return follower_names(("faces",))


def _roller_followers() -> tuple[str, ...]:
    from camgen.followers import follower_names, get_follower

    return tuple(n for n in follower_names(("point",)) if get_follower(n).has_radius)


def keys() -> tuple[Key, ...]:
    """The keys of the constant-breadth form (after the motion's)."""
    from camgen.followers import get_follower

    faces, rollers = _faces_followers(), _roller_followers()
    allowed = faces + rollers
    return (
        Key("follower", Choice(allowed), "Follower holding the cam from both sides, translating along +y through the cam axis: "
            + "; ".join(f"{n}, {get_follower(n).summary}" for n in faces) + " (constant breadth: breadth_mm); "
            + "; ".join(f"{n}, two of them on one follower" for n in rollers)
            + " (constant diameter of the pitch curve: roller_spacing_mm).", ("profile",), default=faces[0] if faces else None,
            feeds=("kind",)),
        Key("half_turn", Flag(), "true: the motion gives the first half-turn (segments' spans add up to 180 deg; a lift table's rows "
            "run from 0 to 180 deg) and the rule s(theta + 180 deg) = C - s(theta) the second; false: the motion gives the whole "
            "turn, which is checked against the rule (refused naming the segment that breaks it).", ("profile",), default=False),
        Key("base_radius_mm", Length(), "Distance from the cam axis to the upper face (yoke), or where the upper roller touches "
            "the cam, at zero lift. Give it, or the breadth (spacing), or both (they must agree: B = 2 base + C, "
            "C = s(0) + s(180 deg)).", ("profile",)),
        Key("breadth_mm", Length(), "Yoke: the distance between its two faces (the cam's constant breadth), "
            "= 2 base_radius_mm + C with C = s(0) + s(180 deg).", ("profile",), requires={"follower": faces}),
        Key("roller_spacing_mm", Length(), "Two rollers: the distance between their centres (the pitch curve's constant "
            "diameter), = 2 (base_radius_mm + roller_radius_mm) + C with C = s(0) + s(180 deg).", ("profile",),
            requires={"follower": rollers}),
    ) + tuple(k for k in own_keys(("point",)) if set(k.requires.get("follower", ())) & set(rollers)) + (
        Key("rotation", Choice(("ccw", "cw")), "Direction the cam turns, seen looking at the DXF (from +z); the cam angle is "
            "measured in this direction.", ("profile",), default="ccw"),
        Key("face_half_length_mm", Length(), "Yoke: usable half-length of each face (checked against the contact's reach, the "
            "same on both faces half a turn apart).", ("report",), requires={"follower": faces}),
        Key("fit_tol_mm", Number("mm", 1e-10, FIT_TOL_MAX), "Largest distance of the profile's spline representation from the "
            "exact envelope (measured at the quarter and mid points of every piece); the breadth (diameter) check's limit is "
            f"{BREADTH_TOL_FACTOR:g} times it.", ("profile",), default=DEFAULT_FIT_TOL),
        source_key(),
    ) + body_keys() + check_keys(oscillating=False)


@dataclass(frozen=True)
class BreadthParams:
    """A constant-breadth (diameter) cam: the plate cam the envelope is made as (its law over the
    whole turn and its upper face or roller), the scene's follower, the size (breadth ``B`` or
    roller spacing ``D``, mm), the rule's constant ``C`` (mm) and whether the motion gave half a turn."""

    disk: DiskParams
    follower: str
    faces: bool
    size: float
    constant: float
    half_turn: bool


@dataclass(frozen=True, kw_only=True)
class BreadthCam(DiskCam):
    """A built constant-breadth (diameter) cam: the plate cam of its upper face or roller, the
    size it keeps and the measured error (mm; NaN when the profile cannot be made)."""

    params: BreadthParams
    size_error: float = float("nan")
    size_error_at: float = 0.0  # the direction (rad) of the largest error


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------
def _law_reading(where: str, parsed: Mapping[str, Any], motion: "Motion", follower: Any, base_dir: Path | None):
    """The motion's law over the whole turn: completed from the first half-turn, or the whole turn
    checked against the rule (refused naming the segment, or the motion's key, that breaks it)."""
    from camgen.synthesis.breadth import RULE_TOL, rule_break

    if parsed["half_turn"]:
        if motion.read_half_law is None:
            raise ParameterError(f"{where}.half_turn", True, "false (give the whole turn)",
                                 f"motion {motion.name!r} takes no half-turn program")
        return motion.read_half_law(where, parsed, follower, base_dir)
    assert motion.read_law is not None, f"motion {motion.name!r} is not a displacement law"
    reading = motion.read_law(where, parsed, follower, base_dir)
    law = reading.law
    broken = rule_break(law, law.stroke)
    if broken is None:
        return reading
    unit = follower.lift_unit
    deg = math.degrees(broken.theta)
    segments = getattr(law, "segments", None)
    if segments is not None and hasattr(law, "starts"):  # a motion program: the segment of the second half-turn there
        i = int(np.searchsorted(np.asarray(law.starts), broken.theta, side="right")) - 1
        name = segments[i].where or f"{where}.segments[{i}]"
    else:
        name = f"{where}.{motion.keys[0].name}" if motion.keys else f"{where}.kind"
    raise ParameterError(name, f"s = {broken.value:.9g} {unit} at {deg:.6g} deg",
                         f"s(theta) = C - s(theta - 180 deg) = {broken.required:.9g} {unit} there, C = s(0) + s(180 deg) = "
                         f"{broken.constant:.9g} {unit} (within {RULE_TOL:g} of the stroke)",
                         "a constant-breadth cam's second half-turn mirrors the first (s(theta + 180 deg) = C - s(theta)); "
                         "give the first half with half_turn = true")


def read_breadth(where: str, name: str, parsed: Mapping[str, Any], motion: "Motion", base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a constant-breadth (diameter) cam table; errors name the scene keys."""
    from camgen.followers import follower_names, get_follower
    from camgen.kinds.base import read_body, read_checks
    from camgen.keynames import renamed
    from camgen.synthesis.followers import FollowerSpec

    kind = parsed["follower"]
    model = get_follower(kind)
    faces = model.contact == "faces"
    radius = 0.0 if faces else model.radius(parsed)
    size_key = "breadth" if faces else "roller_spacing"
    size_name = f"{size_key}_mm"
    given_base: float | None = parsed.get("base_radius")
    given_size: float | None = parsed.get(size_key)
    if given_base is None and given_size is None:
        raise ParameterError(f"{where}.base_radius_mm", None, "a length in mm", f"required unless {size_name} gives it")
    # the upper face is a flat face (the registered follower with a face contact), the upper roller this roller
    envelope_kind = follower_names(("face",))[0] if faces else kind

    def spec(rb: float) -> FollowerSpec:
        return renamed(where, keys(), lambda: FollowerSpec(kind=envelope_kind, base_radius=rb, roller_radius=radius,
                                                           rotation=parsed["rotation"]))

    follower = spec(given_base if given_base is not None else 1.0)  # the base radius follows from the size below
    reading = _law_reading(where, parsed, motion, follower, base_dir)
    from camgen.synthesis.breadth import rule_constant

    constant = rule_constant(reading.law)
    extra = 2.0 * radius + constant  # size = 2 base + extra
    if given_base is None:
        assert given_size is not None  # one of the two is given (above)
        size, base = given_size, 0.5 * (given_size - extra)
        if not base > 0:
            raise ParameterError(f"{where}.{size_name}", size, f"> {extra:.9g} mm ({'' if faces else '2 roller_radius_mm + '}C, "
                                 f"C = s(0) + s(180 deg) = {constant:.9g} mm)", "the base radius, (size - that) / 2, would be <= 0")
    elif given_size is None:
        base, size = given_base, 2.0 * given_base + extra
    else:
        base, size = given_base, given_size
    if abs(size - (2.0 * base + extra)) > SIZE_AGREEMENT * max(1.0, abs(size)):
        raise ParameterError(f"{where}.{size_name}", size, f"{2.0 * base + extra:.9g} mm for base_radius_mm = {base:g} (2 base + "
                             f"{'' if faces else '2 roller radius + '}C, C = s(0) + s(180 deg) = {constant:.9g} mm), or leave one out",
                             "the rule s(theta + 180 deg) = C - s(theta) ties the size to the base radius")
    follower = spec(base)
    if 0.5 * size <= radius and not faces:
        raise ParameterError(f"{where}.roller_spacing_mm", size, f"> {2.0 * radius:g} mm (two roller radii)", "the rollers would overlap")
    figures = dict(reading.figures)
    disk = DiskParams(reading.law, follower, "none", parsed["fit_tol"], parsed.get("face_half_length"), figures, parsed.get("source"))
    params = BreadthParams(disk, kind, faces, float(size), constant, bool(parsed["half_turn"]))
    checks = read_checks(parsed)
    if faces and checks.pressure_angle_limit is None:  # the documented default of a yoke (pressure_angle_limit_deg)
        checks = replace(checks, pressure_angle_limit=YOKE_PRESSURE_LIMIT)
    return CamSpec(name, motion.name, params, read_body(where, parsed), checks, None, None)


# --------------------------------------------------------------------------------------------
# Building
# --------------------------------------------------------------------------------------------
def _as_disk(spec: CamSpec) -> CamSpec:
    """The spec of the plate cam the envelope is made as (its upper face or roller)."""
    p: BreadthParams = spec.params
    return replace(spec, params=p.disk)


def _size_error(profile: Any, pitch: Any, p: BreadthParams) -> tuple[float, float]:
    """Largest |breadth - B| (faces: support function h(psi) + h(psi + pi)) or |diameter - D|
    (rollers: the pitch curve's polar radius r(phi) + r(phi + pi)) over DIRECTIONS directions, mm,
    and the direction (rad)."""
    psi = 2.0 * math.pi * np.arange(DIRECTIONS) / DIRECTIONS
    if p.faces:
        err = np.abs(profile.support(psi) + profile.support(psi + math.pi) - p.size)
    else:
        err = np.abs(pitch.polar_radius(psi) + pitch.polar_radius(psi + math.pi) - p.size)
    i = int(np.argmax(err))
    return float(err[i]), float(psi[i])


def _shapes(p: BreadthParams, s: float, reach: float, frame: float) -> list[tuple[str, np.ndarray]]:
    """The follower at lift ``s`` (fixed frame, mm): both faces (yoke) or both rollers, and the
    frame joining them round the cam (``reach``: half the face length; ``frame``: the frame's x)."""
    f = p.disk.follower
    upper = f.prime_radius + s
    lower = upper - p.size
    out: list[tuple[str, np.ndarray]] = []
    if p.faces:
        for y in (upper, lower):
            out.append(("follower face", np.array([[-reach, y], [reach, y]])))
        top, bottom = upper, lower
    else:
        a = np.linspace(0.0, 2.0 * math.pi, 49)
        for y in (upper, lower):
            out.append(("roller", np.stack([f.roller_radius * np.cos(a), y + f.roller_radius * np.sin(a)], axis=1)))
        top, bottom = upper + f.roller_radius, lower - f.roller_radius
    gap = 0.1 * frame
    out.append(("follower frame", np.array([[0.0, top], [0.0, top + gap], [frame, top + gap], [frame, bottom - gap],
                                            [0.0, bottom - gap], [0.0, bottom]])))
    return out


def build_breadth(spec: CamSpec, stages: frozenset[str]) -> BreadthCam:
    """The exact envelope of the upper face or roller (the plate machinery), the breadth or
    diameter measured, and with the ``plots`` stage the drawing and animation of both."""
    from camgen.kinds.disk import build_disk
    from camgen.report.animation import RideAnimation

    p: BreadthParams = spec.params
    disk = build_disk(_as_disk(spec), stages)
    f = p.disk.follower
    figures = dict(disk.figures)
    key = "breadth_mm" if p.faces else "roller_spacing_mm"
    figures.update({key: p.size, "rule_constant_mm": p.constant, "half_turn": p.half_turn, "follower": {**figures["follower"],
                    "kind": p.follower}})
    error, at = float("nan"), 0.0
    if disk.contour is not None:
        error, at = _size_error(disk.contour, disk.pitch, p)
        figures["breadth_error_mm" if p.faces else "diameter_error_mm"] = error
    drawing = animation = None
    if "plots" in stages:
        outline = disk.contour if disk.contour is not None else disk.pitch
        reach = (p.disk.face_half_length or 0.6 * (f.base_radius + 0.5 * p.size)) if p.faces else 0.0
        frame = 1.25 * max(abs(c) for c in outline.bounds) if outline is not None else p.size
        law = p.disk.law
        s0 = float(law(np.zeros(1))[0][0])
        drawing = _shapes(p, s0, reach, frame)
        if outline is not None and disk.zero_mark is not None:
            chord = max(1e-3, 2e-4 * p.size)
            theta = 2.0 * math.pi * np.arange(ANIMATION_FRAMES) / ANIMATION_FRAMES
            animation = RideAnimation(outline.flatten(chord), f.sigma, _shapes(p, 0.0, reach, frame), "translating", None,
                                      law(theta)[0], ANIMATION_SECONDS, disk.zero_mark)
    values = {fl.name: getattr(disk, fl.name) for fl in fields(disk)}
    values.update(figures=figures, breadth=p.size if p.faces else None, drawing=drawing, animation=animation)
    return BreadthCam(**values, params=p, size_error=error, size_error_at=at)


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------
def _size_check(cam: BreadthCam, fit_tol: float) -> "CheckResult":
    from camgen.checks import CheckResult, where_degrees

    p = cam.params
    what = "breadth" if p.faces else "diameter"
    name = "constant_breadth" if p.faces else "constant_diameter"
    limit = BREADTH_TOL_FACTOR * fit_tol
    measured = ("the distance between the two faces, h(psi) + h(psi + 180 deg) of the profile" if p.faces else
                "the pitch curve's chord through the axis, r(phi) + r(phi + 180 deg)")
    note = (f"{measured}, stays {p.size:.9g} mm within {cam.size_error:.3g} mm over {DIRECTIONS} directions "
            f"(limit {BREADTH_TOL_FACTOR:g} x fit_tol_mm)")
    return CheckResult(name, cam.size_error, limit, "<=", "mm", cam.size_error <= limit, where_degrees(cam.size_error_at), note,
                       blocks_manufacture=True)


def _both(check: "CheckResult", p: BreadthParams) -> "CheckResult":
    """A check of the upper face or roller over the whole turn, which covers the lower one too."""
    other = "face" if p.faces else "roller"
    return replace(check, note=check.note + f"; over the whole turn, so both {other}s: the lower {other} meets at cam angle theta "
                   f"what the upper one meets at theta + 180 deg")


def evaluate_breadth(cam: Any, spec: CamSpec, tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    """The plate cam's closed-form checks of the upper face or roller over the whole turn (they
    cover the lower one), the breadth or diameter measured, and the drawing of both."""
    from camgen.kinds.disk import evaluate_disk
    from camgen.synthesis.followers import kinematics

    assert isinstance(cam, BreadthCam), f"a constant-breadth cam's checks on a {type(cam).__name__}"
    p: BreadthParams = spec.params
    ev = evaluate_disk(cam, _as_disk(spec), tool_radius, tool_is_limit)
    checks = []
    for check in ev.checks:
        if check.name in ("undercut", "face_length"):
            check = _both(check, p)
        elif check.name == "pressure_angle" and not p.faces:
            # the lower roller at theta sits where the upper one is at theta + 180 deg, moving the other way: alpha2 = -alpha1(theta + pi)
            theta = cam.envelope.data.theta
            lower = np.abs(kinematics(p.disk.follower, p.disk.law, theta + math.pi).pressure_angle)
            upper = np.abs(cam.envelope.data.pressure_angle)
            check = replace(check, note=check.note + f"; upper roller {math.degrees(float(np.max(upper))):.6g} deg, lower roller "
                            f"{math.degrees(float(np.max(lower))):.6g} deg (the upper's half a turn later, sign reversed)")
        elif check.name == "pressure_angle":
            check = replace(check, note="a translating yoke's faces move along their own normal: pressure angle 0 on both faces at "
                            "every cam angle")
        elif check.name == "min_base_radius":
            check = replace(check, note=check.note.replace('; or set sizing = "base_radius")', "; leave the size key out and the "
                                                           "breadth or spacing follows from it)"))
        checks.append(check)
    if cam.contour is not None:
        checks.insert(1, _size_check(cam, p.disk.fit_tol))
    label = ev.pressure_angle_label + (" (upper roller; the lower one's is the same half a turn later, sign reversed)"
                                       if not p.faces else " (both faces)")
    return replace(ev, checks=tuple(checks), follower_drawing=cam.drawing, animation=cam.animation, pressure_angle_label=label)
