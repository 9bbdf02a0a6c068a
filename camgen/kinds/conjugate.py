"""Conjugate (dual) plate cams: two plate cams on one shaft holding one follower with two rollers.

One displacement law ``s(theta)`` (a motion program or a lift table) moves one rigid follower
carrying two rollers.  Roller **A** rides cam **A** (``<cam>_a``) exactly as a plate cam's roller
does (:mod:`camgen.kinds.disk`: base radius, offset or pivot and arm, rotation).  Roller **B**
rides cam **B** (``<cam>_b``) on the other side of the shaft, so the two cams hold the follower
both ways without a spring (form closure).

Placement of roller B
---------------------
* **Translating**: roller B is on the same stem (the line ``x = e``, ``e`` the follower offset),
  ``D = roller_b_distance_mm`` below roller A's centre: roller A's centre is ``(e, Y + s)`` with
  ``Y = sqrt(Rp^2 - e^2)`` (the plate cam's rest height), roller B's ``(e, Y + s - D)``, below the
  shaft for every lift when ``D > Y + s_max``.
* **Oscillating**: roller B is on a second arm of the same rocker: the arm from the pivot ``P`` to
  roller B, of length ``L_B = arm_b_length_mm``, is turned ``beta = arm_b_angle_deg``
  counter-clockwise from the arm to roller A (angle ``g``), so its angle is ``g + beta``.

Each second cam is itself a plate cam (derivation)
--------------------------------------------------
Let ``C = s_max`` (the law's largest value) and ``s_B = C - s >= 0``.

* Translating: turn the fixed frame (and with it the cam frame) by 180 deg about the shaft,
  ``X' = -X``.  A rotation commutes with the cam's rotation ``R(sigma theta)``, so the cam turns the
  same way by the same cam angle in the turned frame.  There roller B's centre is
  ``(-e, D - Y - s) = (-e, Y_B + s_B)`` with ``Y_B = D - Y - C``: a translating roller moving along
  ``+y'`` with offset ``-e``, prime radius ``Rp_B = sqrt(Y_B^2 + e^2)`` and lift law ``s_B``, which
  is the plate cam's convention exactly.  So cam B is the plate cam of that follower and law in
  the turned frame (its exact envelope, its closed-form pressure angle, curvature, undercut and
  tool checks, :mod:`camgen.kinds.disk`), turned back by 180 deg (``q -> -q``, exact in floating
  point) for its files.  The pressure angle, the radii of curvature and every cam angle are the
  same in both frames.
* Oscillating: no turn is needed.  Arm B's angle is ``g + beta = g0 + beta + tau s =
  g0_B + tau_B s_B`` with ``g0_B = g0 + beta + tau C`` and ``tau_B = -tau``: an oscillating roller
  on the same pivot with arm ``L_B``, swing law ``s_B`` and the opposite ``swing_turn``, resting
  (``s_B = 0``) on the prime circle ``Rp_B = |P + L_B u(g0_B)|``.  The plate cam's rest position
  (:attr:`camgen.synthesis.followers.FollowerSpec.rest_arm_angle`) is the crossing of the arm
  circle with the prime circle where a positive swing moves the roller away from the cam: it must
  be ``g0_B``, i.e. when roller A moves away from cam A, roller B moves towards cam B.  A
  ``beta`` for which it is not (both rollers on the same side of their cams) is refused.

Preload and backlash
--------------------
``conjugate_preload_mm = p``: cam B is the exact envelope of a roller of radius ``r_B - p`` on
roller B's path, so with the roller of radius ``r_B`` the gap between roller B and cam B (the
distance from roller B's centre to cam B's profile less ``r_B``) is ``-p`` at every cam angle:
``p > 0`` an interference (preload) of ``p``, ``p < 0`` a clearance (backlash) of ``-p``.  Cam A is
made for roller A exactly.  The checks of cam B (undercut, curvature, tool) are of the profile as
made (the envelope of the roller of radius ``r_B - p``).

Dynamics
--------
A pair is a form-closed follower train (:mod:`camgen.kinds.dynamics`, ``closure = "form"``): with
``rpm`` and the mass (translating) or the rocker's inertia (oscillating) the dynamics keys give the
follower train; no spring and no ``jump_margin_n`` (refused: cam B holds the follower, it cannot
jump).  Contact 1 is roller A on cam A (pushing the follower along ``+s``), contact 2 roller B on
cam B (pushing it along ``-s``), each from its own cam's closed-form kinematics on the one check
grid: cam A's pressure angle and profile radius at the contact with roller A's radius; cam B's
pressure angle and profile radius (the profile as made) with roller B's radius and, oscillating,
arm B's length as the lever of contact 2.  The pair is one train on one shaft, so its dynamics
(both contacts' forces and Hertz stresses, the camshaft torque of the pair, the cam angles where
the load passes from one roller to the other) are computed and reported once, on cam A
(``<cam>_a``); cam B's report points there (its ``dynamics`` check).

The pair in the run
-------------------
The scene cam ``x`` is realised as two cams, ``x_a`` (cam A) and ``x_b`` (cam B)
(:attr:`camgen.forms.base.CamForm.expand`), each built, checked and written as a cam of its own
(DXF, points, meshes, STEP, G-code, at cam angle 0 as in the machine); the report draws the pair
together in cam ``x_a``'s section.  Both cams' follower motion (the follower table, the motion
check) is the follower's, ``s``.
"""
from __future__ import annotations

import html
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import numpy as np

from camgen.errors import GeometryError, ParameterError
from camgen.kinds.base import BuiltCam, CamSpec, ZeroMark
from camgen.report.model import SectionData
from camgen.schema import Angle, Choice, Key, Length

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation
    from camgen.contour import Contour
    from camgen.motions.base import Motion
    from camgen.report.model import CamReport
    from camgen.synthesis.followers import FollowerSpec

__all__ = ["DYNAMICS_MEMBER", "MEMBERS", "ComplementLaw", "ConjugateMember", "ConjugatePair", "ConjugateSection", "build_conjugate",
           "conjugate_keys", "conjugate_kinematics", "evaluate_conjugate", "expand_conjugate", "pair_section", "read_conjugate"]

#: The two cams of a pair: suffix of their names (``<cam>_a``, ``<cam>_b``) and what each drives.
MEMBERS = ("a", "b")
#: The member whose report carries the pair's dynamics (computed once: one train, one shaft).
DYNAMICS_MEMBER = "a"
#: Plate-cam follower keys a conjugate pair does not take (no sizing of a pair; rollers only).
_NOT_TAKEN = ("sizing", "face_offset_mm", "face_half_length_mm")
#: Largest difference (rad) between arm B's rest angle and the plate cam's rest crossing that is
#: still the same crossing (the two crossings are apart by far more on any arm that reaches).
REST_ANGLE_TOL = 1e-9
_TRANS = {"follower_motion": ("translating",)}
_OSC = {"follower_motion": ("oscillating",)}


def _rollers() -> tuple[str, ...]:
    """The registered followers with a point contact of a radius (rollers)."""
    from camgen.followers import follower_names, get_follower

    return tuple(n for n in follower_names(("point",)) if get_follower(n).has_radius)


def conjugate_keys() -> tuple[Key, ...]:
    """The keys of a conjugate pair: roller A's (a plate cam's roller keys), roller B's and the preload."""
    from camgen.kinds.disk import follower_keys

    rollers = _rollers()
    keys = []
    for key in follower_keys():
        if key.name in _NOT_TAKEN:
            continue
        if key.name == "follower":
            key = replace(key, type=Choice(rollers), doc="Follower of both rollers (camgen.followers, rollers): " + ", ".join(rollers) + ".")
        elif key.name == "base_radius_mm":
            key = replace(key, doc="Radius of cam A where roller A touches at zero lift or swing (roller A's centre on the prime circle "
                          "base + roller radius). Required.", default=None)
        keys.append(key)
    return tuple(keys) + (
        Key("roller_b_distance_mm", Length(), "Translating pair: distance from roller A's centre to roller B's along the stem; roller "
            "B is below the shaft (y < 0), on the line x = follower_offset_mm. Required.", ("profile",), requires=_TRANS),
        Key("arm_b_angle_deg", Angle(), "Oscillating pair: angle from arm A (pivot to roller A) to arm B (pivot to roller B), "
            "counter-clockwise seen from +z; a rigid rocker, so roller B moves towards cam B as roller A moves away from cam A. "
            "Required.", ("profile",), requires=_OSC),
        Key("arm_b_length_mm", Length(), "Oscillating pair: pivot to roller B's centre (default: arm_length_mm).", ("profile",),
            requires=_OSC),
        Key("roller_b_radius_mm", Length(), "Radius of roller B (default: the roller radius of roller A).", ("profile",)),
        Key("conjugate_preload_mm", Length(-1e3, 1e3, low_open=False), "Preload between roller B and cam B: > 0 an interference of "
            "this much (cam B is the envelope of a roller of radius roller_b_radius_mm - preload), < 0 a backlash (a gap of "
            "-preload); 0: both rollers touch their cams exactly.", ("profile",), default=0.0),
    )


# --------------------------------------------------------------------------------------------
# The law of cam B
# --------------------------------------------------------------------------------------------
class ComplementLaw:
    """``s_B = total - s`` and its derivatives (the law of cam B), with ``s``'s breaks."""

    def __init__(self, law: Any, total: float) -> None:
        self.law = law
        self.total = float(total)
        self.breaks = law.breaks
        self.break_continuity = law.break_continuity

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        s, ds, d2s, d3s = self.law(theta)
        return self.total - s, -ds, -d2s, -d3s

    @property
    def s_bounds(self) -> tuple[float, float]:
        lo, hi = self.law.s_bounds
        return self.total - hi, self.total - lo

    @property
    def stroke(self) -> float:
        lo, hi = self.s_bounds
        return float(hi - lo)

    def peak_values(self) -> Any:
        """The law's peaks: |s_B^(k)| = |s^(k)| for k >= 1."""
        return self.law.peak_values()


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ConjugatePair:
    """A conjugate pair as read from its scene table (mm, rad).

    ``law``: the follower's law ``s``; ``first``: roller A's plate-cam follower; ``second``: roller
    B's as the plate machinery sees it (translating: in the frame turned by 180 deg, offset
    ``-e``; oscillating: the same pivot, the opposite ``lift_turn``), with the radius of the
    envelope, ``roller_b_radius - preload``; ``second_law``: ``s_B = s_max - s``; ``turned``: cam
    B is made in the turned frame; ``distance`` (translating, mm) or ``arm_angle`` and
    ``arm_b_length`` (oscillating, rad and mm) place roller B.
    """

    law: Any
    first: "FollowerSpec"
    second: "FollowerSpec"
    second_law: ComplementLaw
    turned: bool
    roller_b_radius: float
    preload: float
    distance: float | None = None
    arm_angle: float | None = None
    arm_b_length: float | None = None
    fit_tol: float = 1e-7
    law_figures: Mapping[str, Any] = field(default_factory=dict)
    source: str | None = None


@dataclass(frozen=True)
class ConjugateMember:
    """One cam of a pair: ``member`` ``"a"`` or ``"b"`` (:data:`MEMBERS`) of the scene cam ``pair``;
    ``dynamics``: the pair has a follower train (computed on :data:`DYNAMICS_MEMBER`)."""

    pair: str
    member: str
    params: ConjugatePair
    dynamics: bool = False


def _second_translating(where: str, first: "FollowerSpec", law: Any, parsed: Mapping[str, Any], r_env: float) -> "FollowerSpec":
    from camgen.synthesis.followers import FollowerSpec

    if "roller_b_distance" not in parsed:
        raise ParameterError(f"{where}.roller_b_distance_mm", None, "a length in mm", "required for a translating conjugate pair")
    distance = parsed["roller_b_distance"]
    e, top = first.offset, first.rest_height + law.s_bounds[1]
    y_b = distance - top  # roller B's centre below the shaft at the largest lift (its rest in the turned frame)
    least = top + math.sqrt(max(r_env * r_env - e * e, 0.0))  # Y_B > 0 and Rp_B = hypot(Y_B, e) > r_env: base radius B > 0
    if not (y_b > 0.0 and math.hypot(y_b, e) > r_env):
        raise ParameterError(f"{where}.roller_b_distance_mm", distance, f"> {least:.6g} mm",
                             f"roller B must pass below the shaft with cam B's base radius > 0 (roller A's centre reaches "
                             f"{top:.6g} mm at the largest lift)")
    return FollowerSpec(first.kind, math.hypot(y_b, e) - r_env, "translating", r_env, -e, rotation=first.rotation)


def _second_oscillating(where: str, first: "FollowerSpec", law: Any, parsed: Mapping[str, Any], r_env: float,
                        arm_b: float) -> "FollowerSpec":
    from camgen.synthesis.followers import FollowerSpec

    if "arm_b_angle" not in parsed:
        raise ParameterError(f"{where}.arm_b_angle_deg", None, "an angle in deg", "required for an oscillating conjugate pair")
    beta = parsed["arm_b_angle"]
    shown = round(math.degrees(beta), 9)
    px, py = first.pivot_xy
    rest = first.rest_arm_angle + beta + first.tau * law.s_bounds[1]  # arm B at the largest swing of arm A (s_B = 0)
    centre = (px + arm_b * math.cos(rest), py + arm_b * math.sin(rest))
    base = math.hypot(*centre) - r_env
    valid = "an angle putting roller B on the far side of cam B from its pivot, moving towards cam B as roller A moves away"
    if not base > 0.0:
        raise ParameterError(f"{where}.arm_b_angle_deg", shown, valid, f"roller B's centre comes within {r_env:g} mm (its envelope "
                             "radius) of the shaft")
    turn = "cw" if first.lift_turn == "ccw" else "ccw"
    try:
        second = FollowerSpec(first.kind, base, "oscillating", r_env, pivot=first.pivot, arm_length=arm_b, lift_turn=turn,
                              rotation=first.rotation)
        found = second.rest_arm_angle
    except (ParameterError, GeometryError) as exc:
        raise ParameterError(f"{where}.arm_b_angle_deg", shown, valid, str(exc)) from None
    if abs(math.remainder(found - rest, 2.0 * math.pi)) > REST_ANGLE_TOL:
        raise ParameterError(f"{where}.arm_b_angle_deg", shown, valid, "with it roller B moves away from cam B as roller A moves "
                             "away from cam A: the two cams would not hold the follower")
    return second


def read_conjugate(where: str, name: str, parsed: Mapping[str, Any], motion: "Motion", base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a conjugate pair (the scene cam; :func:`expand_conjugate` makes its two cams)."""
    from camgen.kinds.base import read_body, read_checks
    from camgen.kinds.disk import read_follower

    assert motion.read_law is not None, f"motion {motion.name!r} is not a displacement law"
    if "base_radius" not in parsed:
        raise ParameterError(f"{where}.base_radius_mm", None, "a length in mm, > 0", "required for a conjugate pair (cam A's base radius)")
    first, _ = read_follower(where, {**parsed, "sizing": "none"})
    reading = motion.read_law(where, parsed, first, base_dir)
    law = reading.law
    r_b = parsed.get("roller_b_radius", first.roller_radius)
    preload = parsed["conjugate_preload"]
    r_env = r_b - preload
    if not r_env > 0.0:
        raise ParameterError(f"{where}.conjugate_preload_mm", preload, f"< {r_b:g} mm (roller B's radius)",
                             "cam B is the envelope of a roller of radius roller_b_radius_mm - preload, which must be > 0")
    total = law.s_bounds[1]
    if first.motion == "translating":
        second = _second_translating(where, first, law, parsed, r_env)
        distance, beta, arm_b = parsed["roller_b_distance"], None, None
    else:
        arm_b = parsed.get("arm_b_length", first.arm_length)
        second = _second_oscillating(where, first, law, parsed, r_env, arm_b)
        distance, beta = None, parsed["arm_b_angle"]
    pair = ConjugatePair(law, first, second, ComplementLaw(law, total), first.motion == "translating", r_b, preload, distance, beta,
                         arm_b, parsed["fit_tol"], dict(reading.figures), parsed.get("source"))
    body, checks = read_body(where, parsed), read_checks(parsed)
    return CamSpec(name, motion.name, pair, body, checks, None, _read_pair_dynamics(where, parsed, first, checks.rpm, body.thickness,
                                                                                     base_dir))


def _read_pair_dynamics(where: str, parsed: Mapping[str, Any], first: "FollowerSpec", rpm: float | None, thickness: float,
                        base_dir: Path | None) -> Any:
    """The pair's follower train (form-closed: a spring or a jump margin is refused naming the key)."""
    from camgen.kinds.dynamics import SPRING_KEYS, dynamics_keys, read_dynamics
    from camgen.schema import given_keys

    keys = {k.name: k for k in dynamics_keys()}
    given = given_keys(parsed, tuple(keys.values()))
    for name in (*SPRING_KEYS, "jump_margin_n"):
        if name in given:
            raise ParameterError(f"{where}.{name}", keys[name].type.to_scene(parsed.get(keys[name].field)), "left out for a conjugate pair",
                                 "a conjugate pair is form-closed: cam B holds the follower on cam A (roller B pushes it back), so it "
                                 "has no spring and cannot jump (both rollers' contacts are checked instead)")
    return read_dynamics(where, parsed, motion=first.motion, follower=first.kind, rpm=rpm, thickness=thickness, base_dir=base_dir,
                         form_closed=True)


def expand_conjugate(spec: CamSpec) -> tuple[CamSpec, ...]:
    """The pair's two cams, ``<name>_a`` and ``<name>_b``, each a cam of the run; the pair's
    follower train goes with cam A only (:data:`DYNAMICS_MEMBER`: its dynamics are the pair's)."""
    pair: ConjugatePair = spec.params
    has = spec.dynamics is not None
    return tuple(replace(spec, name=f"{spec.name}_{m}", params=ConjugateMember(spec.name, m, pair, has),
                         dynamics=spec.dynamics if m == DYNAMICS_MEMBER else None) for m in MEMBERS)


# --------------------------------------------------------------------------------------------
# Building
# --------------------------------------------------------------------------------------------
def _disk_spec(spec: CamSpec) -> CamSpec:
    """The plate cam a member is made as (cam B: in the turned frame when the pair translates)."""
    from camgen.kinds.disk import DiskParams

    m: ConjugateMember = spec.params
    p = m.params
    follower, law = (p.first, p.law) if m.member == "a" else (p.second, p.second_law)
    return replace(spec, params=DiskParams(law, follower, "none", p.fit_tol, None, dict(p.law_figures), p.source))


def _turned(contour: "Contour") -> "Contour":
    """``contour`` turned by 180 deg about the shaft (every coefficient negated: exact)."""
    from camgen.contour import Contour, Spline

    assert all(isinstance(seg, Spline) for seg in contour.segments), "a plate cam's envelope is made of splines"
    return Contour([Spline(seg.breaks, -seg.coeffs) for seg in contour.segments])  # type: ignore[union-attr]


def _turn_shapes(shapes: Sequence[tuple[str, np.ndarray]] | None) -> list[tuple[str, np.ndarray]] | None:
    """Polylines turned by 180 deg about the axis (cam B's frame back to the machine's)."""
    return None if shapes is None else [(label, -np.asarray(poly)) for label, poly in shapes]


def _member_figures(spec: CamSpec, cam: Any) -> dict[str, Any]:
    m: ConjugateMember = spec.params
    p = m.params
    other = [x for x in MEMBERS if x != m.member][0]
    out: dict[str, Any] = {"pair": m.pair, "cam": m.member.upper(), "other_cam": f"{m.pair}_{other}", "preload_mm": p.preload,
                           "roller_b_radius_mm": p.roller_b_radius, "cam_b_envelope_roller_radius_mm": p.second.roller_radius}
    if p.turned:
        out["roller_distance_mm"] = p.distance
    else:
        out["arm_b_angle_deg"] = round(math.degrees(_given(p.arm_angle)), 9)
        out["arm_b_length_mm"] = p.arm_b_length
    return out


def _given(value: Any) -> Any:
    assert value is not None
    return value


def _real_follower_figures(p: ConjugatePair) -> dict[str, Any]:
    """Roller B as it is in the machine (not in the turned frame)."""
    f = p.second
    out: dict[str, Any] = {"kind": f.kind, "motion": f.motion, "rotation": f.rotation, "roller_radius_mm": p.roller_b_radius}
    if p.turned:
        out["offset_mm"] = p.first.offset
        out["centre_at_largest_lift_mm"] = [p.first.offset, -f.rest_height]
    else:
        out["pivot_mm"] = list(_given(f.pivot))
        out["arm_length_mm"] = f.arm_length
        out["swing_turn"] = f.lift_turn
        out["rest_arm_angle_deg"] = math.degrees(f.rest_arm_angle)
    return out


def _follower_motion(p: ConjugatePair) -> Any:
    """The follower's SVAJ per unit cam speed, exactly from its law ``s`` (both cams of a pair move
    the one follower; as :class:`camgen.kinds.disk.DiskCam`'s motion)."""
    from camgen.checks import Motion, where_degrees
    from camgen.kinds.disk import MOTION_SAMPLES

    theta = 2.0 * math.pi * np.arange(MOTION_SAMPLES) / MOTION_SAMPLES
    s, ds, d2s, d3s = p.law(theta)
    peaks = p.law.peak_values()
    jumps = np.asarray(p.law.breaks)[np.asarray(p.law.break_continuity) < 2]
    return Motion(theta, s, ds, d2s, d3s, p.first.lift_unit, where_degrees(jumps), lift_zero=0.0,
                  peaks=(peaks.velocity, peaks.acceleration, peaks.jerk))


def _build_member(spec: CamSpec, stages: frozenset[str]) -> Any:
    """A member as a :class:`~camgen.kinds.disk.DiskCam` in the machine's frame."""
    from camgen.kinds.disk import build_disk

    m: ConjugateMember = spec.params
    p = m.params
    cam = build_disk(_disk_spec(spec), stages)
    figures = dict(cam.figures)
    figures["conjugate"] = _member_figures(spec, cam)
    changes: dict[str, Any] = {"name": spec.name, "motion": _follower_motion(p)}  # the follower's motion, s
    if m.member == "b":
        figures["follower"] = _real_follower_figures(p)
    if m.member == "b" and p.turned:
        profile = _turned(cam.contour) if cam.contour is not None else None
        if profile is not None:
            figures["bounds_mm"] = list(profile.bounds)
        anim = cam.animation
        if anim is not None:
            anim = replace(anim, profile=-anim.profile, follower=[(label, -np.asarray(poly, dtype=float)) for label, poly in anim.follower],
                           moves=-anim.moves,
                           zero_mark=ZeroMark((-anim.zero_mark.point[0], -anim.zero_mark.point[1]), anim.zero_mark.sigma)
                           if anim.zero_mark is not None else None)
        zero = cam.zero_mark
        changes.update(contour=profile, pitch=_turned(cam.pitch) if cam.pitch is not None else None,
                       zero_mark=ZeroMark((-zero.point[0], -zero.point[1]), zero.sigma) if zero is not None else None,
                       drawing=_turn_shapes(cam.drawing), animation=anim)
    return replace(cam, figures=figures, **changes)


def build_conjugate(spec: CamSpec, stages: frozenset[str]) -> BuiltCam:
    """One cam of a pair (``spec.params``: a :class:`ConjugateMember`); with the ``plots`` stage cam
    A carries the drawing of the pair (both cams, both rollers, the follower, the animation)."""
    m: ConjugateMember = spec.params
    assert isinstance(m, ConjugateMember), "a conjugate cam is built from a member of its pair (expand_conjugate)"
    cam = _build_member(spec, stages)
    if m.member == "a" and "plots" in stages:
        other = replace(spec, name=f"{m.pair}_b", params=replace(m, member="b"))
        cam_b = _build_member(other, frozenset(stages) - {"plots"})
        cam = replace(cam, section=_pair_data(m, cam.contour, cam_b.contour, spec.name, other.name))
    return cam


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------
def evaluate_conjugate(cam: BuiltCam, spec: CamSpec, tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    """A member's checks: the plate cam's (pressure angle, undercut, curvature, tool, motion, from
    the closed forms) and the pair's preload and roller placement as information."""
    from camgen.checks import information
    from camgen.kinds.disk import evaluate_disk

    m: ConjugateMember = spec.params
    p = m.params
    evaluation = evaluate_disk(cam, _disk_spec(spec), tool_radius, tool_is_limit)
    if p.turned:
        where = f"roller B {p.distance:g} mm from roller A along the stem, below the shaft"
    else:
        where = (f"roller B on arm B ({p.arm_b_length:g} mm from the pivot) at {math.degrees(_given(p.arm_angle)):g} deg "
                 "counter-clockwise from arm A")
    kind = "preload (interference)" if p.preload > 0 else ("backlash (gap)" if p.preload < 0 else "no preload, no backlash")
    note = (f"cam {m.member.upper()} of the pair {m.pair} ({m.pair}_a drives roller A, {m.pair}_b roller B); {where}; "
            f"{kind}: roller B (radius {p.roller_b_radius:g} mm) against cam B, made as the envelope of a roller of radius "
            f"{p.second.roller_radius:g} mm")
    if m.dynamics and m.member == DYNAMICS_MEMBER:
        note += (f"; the pair's dynamics (one follower train, one shaft) are reported on this cam: contact 1 is roller A on cam A "
                 f"({m.pair}_a, pushing the follower along +s), contact 2 roller B on cam B ({m.pair}_b, pushing it back); the "
                 "camshaft torque is the pair's")
    added = [information("conjugate_preload", p.preload, "mm", [], note)]
    if m.dynamics and m.member != DYNAMICS_MEMBER:
        home = f"{m.pair}_{DYNAMICS_MEMBER}"
        added.append(information("dynamics", f"on {home}", "", [],
                                 f"the dynamics of the pair {m.pair} are computed once, on {home}: both rollers' contact forces "
                                 f"(contact 2 there is roller B on this cam) and Hertz stresses, the camshaft torque of the pair "
                                 "and the cam angles where the load passes from one roller to the other"))
    return replace(evaluation, checks=evaluation.checks + tuple(added))


# --------------------------------------------------------------------------------------------
# Dynamics
# --------------------------------------------------------------------------------------------
def conjugate_kinematics(cam: BuiltCam, spec: CamSpec) -> tuple[Any, float]:
    """The dynamics kinematics of a pair (on cam A, :data:`DYNAMICS_MEMBER`): a form-closed train
    whose contact 1 is roller A on cam A and contact 2 roller B on cam B, each from its own plate
    cam's closed forms (:func:`camgen.synthesis.followers.kinematics`) on cam A's check grid:
    the pressure angle, the profile's radius of curvature at the contact (cam B's as made, the
    envelope of a roller of radius ``roller_b_radius - preload``) and the roller's radius;
    oscillating, arm B's length is contact 2's lever (its moment arm ``L_B cos(phi_B)``) and the
    rocker's coordinate is arm A's swing.  Raises
    :class:`~camgen.kinds.dynamics.DynamicsNotComputed` when cam B cannot be made."""
    from camgen import dynamics as dy
    from camgen.kinds.dynamics import DynamicsNotComputed, checked_kinematics
    from camgen.synthesis.followers import kinematics, profile_failures

    m: ConjugateMember = spec.params
    assert isinstance(m, ConjugateMember) and m.member == DYNAMICS_MEMBER, "a pair's dynamics are computed on its cam A"
    p = m.params
    f, k = p.first, cam.envelope.data  # type: ignore[attr-defined]
    kb = kinematics(p.second, p.second_law, k.theta)  # cam B in its own frame: angles and radii are those of the machine
    if any(mask.any() for _, mask in profile_failures(p.second, kb)):
        raise DynamicsNotComputed(f"cam B ({m.pair}_b) cannot be made (see its undercut check): the pair's contact forces, "
                                  "Hertz stresses and camshaft torque are computed for a pair that can be made")
    n = k.theta.size
    if f.motion == "translating":
        direction: Any = math.pi / 2  # the follower moves along fixed +y
        arm, lever_2 = 0.0, None
    else:
        direction = k.arm_angle + f.tau * math.pi / 2  # roller A's centre moves along tau J u(arm angle)
        arm, lever_2 = f.arm_length, np.full(n, float(_given(p.arm_b_length)))
    kin = checked_kinematics(lambda: dy.Kinematics(k.theta, k.s, k.ds, k.d2s, k.pressure_angle, k.profile_radius, f.roller_radius,
                                                   direction, pressure_angle_2=kb.pressure_angle, rho_cam_2=kb.profile_radius,
                                                   follower_radius_2=p.roller_b_radius, lever_2=lever_2))
    return kin, arm


# --------------------------------------------------------------------------------------------
# The report: the pair drawn together
# --------------------------------------------------------------------------------------------
#: Frames per turn of the pair's animation, and the seconds a turn takes on screen.
PAIR_FRAMES = 180
PAIR_SECONDS = 8.0
#: Chord (mm) of the drawn profiles.
DRAWING_CHORD_MM = 0.05


@dataclass(frozen=True)
class ConjugateSection(SectionData):
    """What the pair's drawing shows (mm, deg; fixed frame at cam angle 0 = cam frame then).

    ``profiles``: cam A's and cam B's outlines (None: that cam cannot be made); ``follower``:
    (label, polyline) of the follower at cam angle 0 (both rollers, the stem or both arms, the
    pivot); ``moves``: per frame (uniform cam angles from 0) the follower's lift from its position
    at cam angle 0 (mm) or its rocker's turn about the pivot (deg, counter-clockwise positive).
    """

    cams: tuple[str, str]
    profiles: tuple[np.ndarray | None, np.ndarray | None]
    follower: tuple[tuple[str, np.ndarray], ...]
    motion: str
    pivot: tuple[float, float] | None
    moves: np.ndarray
    sigma: float
    seconds: float
    note: str


def _circle(c: np.ndarray, r: float, n: int = 49) -> np.ndarray:
    a = np.linspace(0.0, 2.0 * math.pi, n)
    return np.stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)], axis=1)


def _pair_data(m: ConjugateMember, profile_a: "Contour | None", profile_b: "Contour | None", name_a: str, name_b: str) -> ConjugateSection:
    p = m.params
    f = p.first
    s0 = float(p.law(np.zeros(1))[0][0])
    theta = 2.0 * math.pi * np.arange(PAIR_FRAMES) / PAIR_FRAMES
    s = p.law(theta)[0] - s0
    shapes: list[tuple[str, np.ndarray]] = []
    if p.turned:
        d = _given(p.distance)
        a = np.array([f.offset, f.rest_height + s0])
        b = a - np.array([0.0, d])
        shapes.append(("follower stem", np.stack([b, a + np.array([0.0, 0.35 * d])])))
        moves, pivot = s, None
        where = f"roller B {d:g} mm below roller A on the stem"
    else:
        piv = np.asarray(_given(f.pivot))
        g = f.rest_arm_angle + f.tau * s0
        a = piv + f.arm_length * np.array([math.cos(g), math.sin(g)])
        gb = g + _given(p.arm_angle)
        b = piv + _given(p.arm_b_length) * np.array([math.cos(gb), math.sin(gb)])
        shapes += [("arm", np.stack([a, piv, b])), ("pivot", _circle(piv, 0.03 * f.arm_length, 25))]
        moves, pivot = np.degrees(f.tau * s), (float(piv[0]), float(piv[1]))
        where = f"arm B {math.degrees(_given(p.arm_angle)):g} deg counter-clockwise from arm A"
    shapes += [("roller A", _circle(a, f.roller_radius)), ("roller B", _circle(b, p.roller_b_radius))]
    kind = "preload" if p.preload > 0 else ("backlash" if p.preload < 0 else "preload")
    note = (f"{name_a} (cam A) drives roller A, {name_b} (cam B) roller B; {where}; {kind} {abs(p.preload):g} mm between roller B "
            "and cam B")
    if p.turned:
        note += f"; the roller centres are {_given(p.distance):g} mm apart"
    outline = tuple(c.flatten(DRAWING_CHORD_MM) if c is not None else None for c in (profile_a, profile_b))
    return ConjugateSection((name_a, name_b), (outline[0], outline[1]), tuple(shapes), f.motion, pivot, moves, f.sigma, PAIR_SECONDS, note)


_COLOURS = {"roller A": "#c0392b", "roller B": "#d35400", "follower stem": "#7f8c8d", "arm": "#7f8c8d", "pivot": "#2c3e50"}


def _path(points: np.ndarray, closed: bool = False) -> str:
    return "M " + " ".join(f"{x:.3f},{y:.3f}" for x, y in points) + (" Z" if closed else "")


def _pair_svg(data: ConjugateSection, title: str, width_px: int = 460) -> str:
    """The pair turning and the follower riding both cams: SMIL, no script (as :mod:`camgen.report.animation`)."""
    profiles = [q for q in data.profiles if q is not None]
    pts = profiles + [poly for _, poly in data.follower]
    if data.motion == "translating":
        pts += [poly + np.array([0.0, float(np.max(data.moves))]) for _, poly in data.follower]
        pts += [poly + np.array([0.0, float(np.min(data.moves))]) for _, poly in data.follower]
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 0.06 * float(np.max(hi - lo))
    lo, hi = lo - pad, hi + pad
    w, h = hi - lo
    stroke = 0.004 * float(max(w, h))
    dur = f"{data.seconds:g}s"
    parts = [f"<svg xmlns='http://www.w3.org/2000/svg' width='{width_px}' height='{int(round(width_px * h / w))}' "
             f"viewBox='{lo[0]:.3f} {-hi[1]:.3f} {w:.3f} {h:.3f}' role='img' aria-label='{html.escape(title)}'>",
             f"<title>{html.escape(title)}</title><g transform='scale(1,-1)'>",
             f"<circle cx='0' cy='0' r='{3 * stroke:.3f}' fill='#000'/><g>",
             f"<animateTransform attributeName='transform' type='rotate' from='0 0 0' to='{360.0 * data.sigma:g} 0 0' dur='{dur}' "
             "repeatCount='indefinite'/>"]
    for q, fill, line in zip(data.profiles, ("#d6e4f0", "none"), ("#1f3a5f", "#d35400")):
        if q is not None:
            parts.append(f"<path d='{_path(q, True)}' fill='{fill}' stroke='{line}' stroke-width='{1.5 * stroke:.3f}'/>")
    parts.append("</g>")
    if data.motion == "translating":
        values = ";".join(f"0,{v:.4f}" for v in np.append(data.moves, data.moves[0]))
        motion = f"<animateTransform attributeName='transform' type='translate' values='{values}' dur='{dur}' repeatCount='indefinite'/>"
    else:
        px, py = _given(data.pivot)
        values = ";".join(f"{v:.4f} {px:.3f} {py:.3f}" for v in np.append(data.moves, data.moves[0]))
        motion = f"<animateTransform attributeName='transform' type='rotate' values='{values}' dur='{dur}' repeatCount='indefinite'/>"
    parts.append("<g>" + motion)
    for label, poly in data.follower:
        parts.append(f"<path d='{_path(poly, label.startswith('roller') or label == 'pivot')}' fill='none' "
                     f"stroke='{_COLOURS.get(label, '#c0392b')}' stroke-width='{2 * stroke:.3f}'/>")
    parts.append("</g></g></svg>")
    return "".join(parts)


def pair_section(Figure: Any, cam: "CamReport") -> str:
    """The pair's part of report.html (on cam A): both cams, both rollers and the follower at cam
    angle 0, and the animation of the follower riding both cams."""
    data = cam.section
    if not isinstance(data, ConjugateSection):
        return ""  # cam B: the pair is drawn with cam A
    title = f"{data.cams[0]} + {data.cams[1]}: the conjugate pair"
    parts = [f"<h3>{html.escape(title)}</h3><p class='note'>{html.escape(data.note)}. Cam A filled, cam B outlined (orange); "
             "the follower at cam angle 0.</p>"]
    fig = Figure(figsize=(5.2, 5.2))
    ax = fig.add_subplot()
    for q, label, colour in zip(data.profiles, (f"cam A ({data.cams[0]})", f"cam B ({data.cams[1]})"), ("#1f3a5f", "#d35400")):
        if q is not None:
            closed = np.vstack([q, q[:1]])
            ax.plot(closed[:, 0], closed[:, 1], color=colour, width=1.2, label=label)
    for label, poly in data.follower:
        ax.plot(poly[:, 0], poly[:, 1], color=_COLOURS.get(label, "#c0392b"), width=1.2)
    ax.equal_aspect()
    ax.xlabel("x (mm)")
    ax.ylabel("y (mm)")
    ax.legend(font_size=7)
    ax.title("the pair at cam angle 0", font_size=9)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    parts.append(f"<div class='fig'>{_pair_svg(data, title + ', riding')}</div>")
    return "".join(parts)
