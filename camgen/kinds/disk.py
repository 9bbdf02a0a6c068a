"""Disk cams (kinds ``motion_law`` and ``lift_table``): follower keys, exact envelope, sizing and
the checks from the closed-form kinematics.

A disk cam is a displacement law (a :class:`camgen.synthesis.laws.MotionProgram` or a
:class:`camgen.synthesis.lift_table.LiftTable`) and a follower
(:class:`camgen.synthesis.followers.FollowerSpec`): translating or oscillating; roller, flat face
or knife edge; the cam turning either way.  The conventions (cam angle 0, offset side, positive
lift, rotation) are those of :mod:`camgen.synthesis.followers`; the README repeats them in user
terms.  The profile is the exact envelope of the follower
(:func:`~camgen.synthesis.followers.cam_envelope`, within ``fit_tol_mm``); every check comes
from the closed forms of :func:`~camgen.synthesis.followers.kinematics` on its dense cam-angle
grid, never from sampling the contour, and every angle in them is a cam angle (the cam's
rotation from cam angle 0).

The kinds share :func:`follower_keys`, :func:`read_follower`, :func:`build_disk` and
:func:`evaluate_disk`; each adds the keys of its law.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, TypeVar

import numpy as np

from camgen.errors import FitToleranceError, GeometryError, ParameterError, ceil_significant
from camgen.kinds.base import BuiltCam, CamSpec, ZeroMark, with_cam
from camgen.planning import REPORT_FIGURES_STAGE
from camgen.schema import Choice, Key, Length, Number

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation, CheckResult, Motion
    from camgen.contour import Contour
    from camgen.followers import Contact
    from camgen.report.model import RideAnimation
    from camgen.synthesis.followers import CamEnvelope, FollowerSpec
    from camgen.synthesis.sizing import SizingResult

_T = TypeVar("_T")

#: Default of ``fit_tol_mm`` (camgen.synthesis.followers.DEFAULT_FIT_TOL, kept here so reading the
#: key reference imports no synthesis module; a test keeps them equal).
DEFAULT_FIT_TOL = 1e-7
#: Largest fit_tol_mm (mm).
FIT_TOL_MAX = 1e-2
#: Samples per turn of the follower-motion curves and the follower table (0.1 deg).
MOTION_SAMPLES = 3600
#: Frames per turn of the report's animation (2 deg).
ANIMATION_FRAMES = 180
#: Seconds one cam turn takes in the report's animation (slowed down or sped up to be watched).
ANIMATION_SECONDS = 8.0
#: Default pressure-angle limits, rad: translating and oscillating followers.
DEFAULT_LIMITS = {"translating": math.radians(30.0), "oscillating": math.radians(45.0)}
#: Largest difference (1/mm) between a joint's curvature jump and the law's closed-form jump.
CURVATURE_JUMP_TOL = 1e-6
SIZING = ("none", "base_radius", "base_radius_and_offset")
_OSC = {"follower_motion": ("oscillating",)}


def own_keys(contacts: "tuple[Contact, ...]") -> tuple[Key, ...]:
    """The own keys of the registered followers with one of ``contacts`` (a roller's radius, ...),
    each allowed only with the followers that own it."""
    from camgen.followers import follower_names, get_follower

    owners: dict[str, list[str]] = {}
    first: dict[str, Key] = {}
    for name in follower_names(contacts):
        for key in get_follower(name).keys:
            owners.setdefault(key.name, []).append(name)
            first.setdefault(key.name, key)
    return tuple(replace(key, requires={**key.requires, "follower": tuple(owners[key.name])}) for key in first.values())


def follower_keys() -> tuple[Key, ...]:
    """The keys of a disk cam's follower (every registered follower with a point or face
    contact), rotation, base radius, sizing and representation."""
    from camgen.followers import follower_names, get_follower

    return (
        Key("base_radius_mm", Length(), "Radius of the cam where the follower rests at zero lift or swing (roller: where the roller "
            "touches, its centre on the prime circle base + roller radius; flat: the face's distance from the axis). "
            "Required unless sizing computes it.", ("profile",)),
        Key("sizing", Choice(SIZING), "Let camgen find the smallest base radius (base_radius), or base radius and offset "
            "(base_radius_and_offset: translating roller or knife) that meets the pressure-angle limit and, when a tool is named, "
            "the tool radius as the smallest concave radius (plate cams: also the margin keys and, with the dynamics keys and "
            "allowable_contact_stress_mpa, the Hertz stress at rpm); base_radius_mm (and follower_offset_mm) are then refused and the "
            "result is in the report's figures.", ("profile",), default="none"),
        Key("follower", Choice(follower_names(("point", "face"))), "Follower (camgen.followers): " + "; ".join(
            f"{name}, {get_follower(name).summary}" for name in follower_names(("point", "face"))) + ".", ("profile",),
            default="roller", feeds=("kind",)),
        Key("follower_motion", Choice(("translating", "oscillating")),
            "Translating along +y (the line x = follower_offset_mm), or oscillating about a pivot (pivot_x_mm, pivot_y_mm).",
            ("profile",), default="translating", feeds=("motion",)),
    ) + own_keys(("point", "face")) + (
        Key("follower_offset_mm", Length(-1e5, 1e5, low_open=False),
            "Translating follower: its axis is the line x = offset (> 0: right of the cam axis, looking at the DXF with the "
            "follower above the cam); default 0. A flat face's offset moves only the face centre (the face-length check and "
            "drawing).", ("profile", "report"), requires={"follower_motion": ("translating",)}, feeds=("offset",)),
        Key("pivot_x_mm", Length(-1e5, 1e5, low_open=False), "Oscillating follower: x of the arm's pivot (fixed frame, cam axis at 0).",
            ("profile",), requires=_OSC, feeds=("pivot",)),
        Key("pivot_y_mm", Length(-1e5, 1e5, low_open=False), "Oscillating follower: y of the arm's pivot.", ("profile",), requires=_OSC,
            feeds=("pivot",)),
        Key("arm_length_mm", Length(), "Oscillating roller or knife: pivot to roller centre (knife tip).", ("profile",),
            requires={**_OSC, "follower": follower_names(("point",))}),
        Key("face_offset_mm", Length(-1e5, 1e5, low_open=False), "Oscillating flat face: distance of the face line from the pivot "
            "(> 0: the face lies between the pivot and the cam axis; 0: the face line passes through the pivot).", ("profile",),
            default=0.0, requires={**_OSC, "follower": follower_names(("face",))}),
        Key("swing_turn", Choice(("ccw", "cw")), "Oscillating follower: the way the arm turns about its pivot for a positive swing "
            "(the follower moves away from the cam).", ("profile",), default="ccw", requires=_OSC, feeds=("lift_turn",)),
        Key("rotation", Choice(("ccw", "cw")), "Direction the cam turns, seen looking at the DXF (from +z); the cam angle is "
            "measured in this direction.", ("profile",), default="ccw"),
        Key("face_half_length_mm", Length(), "Flat face: usable half-length of the face (checked against the contact's reach; "
            "oscillating: about the middle of the contact's range).", ("report",), requires={"follower": follower_names(("face",))}),
        Key("fit_tol_mm", Number("mm", 1e-10, FIT_TOL_MAX), "Largest distance of the profile's spline representation from the exact "
            "envelope (measured at the quarter and mid points of every piece).", ("profile",), default=DEFAULT_FIT_TOL),
    )


@dataclass(frozen=True)
class DiskParams:
    """A disk cam: its law, follower (base radius as given, or a placeholder while ``sizing``
    finds it), sizing method, spline tolerance (mm), face half-length (mm), figures of the law,
    and a note of where the numbers come from."""

    law: Any  # a Displacement: MotionProgram or LiftTable
    follower: "FollowerSpec"
    sizing: str = "none"
    fit_tol: float = DEFAULT_FIT_TOL
    face_half_length: float | None = None
    law_figures: Mapping[str, Any] = field(default_factory=dict)
    source: str | None = None
    margins: Any = None  # SIZING (issue 26 item 4): camgen.kinds.disk_margins.Margins, None: none
    sizing_ranges: tuple[str, ...] = ()  # SIZE2 (issue 26 item 4): the quantities sizing_ranges names


@dataclass(frozen=True, kw_only=True)
class DiskCam(BuiltCam):
    """A built disk cam: the envelope, the law and the follower it was made for, the sizing
    result (None: not sized), the follower motion (exact, per unit cam speed), and the report's
    drawing data (None without the plots stage)."""

    envelope: "CamEnvelope"
    law: Any  # a Displacement (camgen.motions.base.LawReading.law)
    spec_follower: "FollowerSpec"
    motion: "Motion"
    sizing: "SizingResult | None" = None
    drawing: list[tuple[str, np.ndarray]] | None = None
    animation: "RideAnimation | None" = None


def _given(value: "_T | None", what: str) -> "_T":
    """``value``, which the follower's kind guarantees is there (``what``: what it is)."""
    assert value is not None, f"{what} is missing"
    return value


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------
def _follower_spec(where: str, **kwargs: Any) -> "FollowerSpec":
    from camgen.keynames import renamed
    from camgen.synthesis.followers import FollowerSpec

    try:  # the usual case first: the key schema (rebuilt per call: the registered followers) only names a refused value
        return FollowerSpec(**kwargs)
    except ParameterError:
        pass
    except GeometryError as exc:
        raise GeometryError(f"{where}: {exc}") from None
    try:  # refused: the same spec again, its error renamed to the scene key
        return renamed(where, follower_keys(), lambda: FollowerSpec(**kwargs))
    except GeometryError as exc:
        raise GeometryError(f"{where}: {exc}") from None


def _placeholder_base(contact: str, motion: str, roller: float, offset: float, pivot: tuple[float, float] | None,
                      arm: float, face: float) -> float:
    """A base radius the other follower parameters allow (sizing replaces it)."""
    if motion == "translating":
        return abs(offset) + 1.0 if contact == "point" else 1.0
    d = math.hypot(*pivot)  # type: ignore[misc]
    lo, hi = (max(0.0, -d - face), d - face) if contact == "face" else (max(0.0, abs(d - arm) - roller), d - roller)
    return 0.5 * (lo + hi) if hi > lo else 1.0


def read_follower(where: str, parsed: Mapping[str, Any]) -> tuple["FollowerSpec", str]:
    """The follower of a disk cam table and its sizing method; errors name the scene keys."""
    from camgen.followers import get_follower
    from camgen.keynames import scene_key

    kind, motion, sizing = parsed["follower"], parsed["follower_motion"], parsed["sizing"]
    model = get_follower(kind)
    contact = model.contact
    roller = model.radius(parsed)
    if sizing == "none" and "base_radius" not in parsed:
        raise ParameterError(f"{where}.base_radius_mm", None, "a length in mm, > 0",
                             'required unless sizing = "base_radius" or "base_radius_and_offset" computes it')
    if sizing != "none" and "base_radius" in parsed:
        raise ParameterError(f"{where}.base_radius_mm", parsed["base_radius"], "no base_radius_mm with sizing",
                             f"sizing = {sizing!r} computes the base radius")
    if sizing == "base_radius_and_offset":
        if motion != "translating" or contact != "point":
            raise ParameterError(f"{where}.sizing", sizing, '"none" or "base_radius" for this follower',
                                 "an offset is sized for a translating roller or knife only (a flat face's offset does not change the cam)")
        if "follower_offset" in parsed:
            raise ParameterError(f"{where}.follower_offset_mm", parsed["follower_offset"], "no follower_offset_mm with this sizing",
                                 'sizing = "base_radius_and_offset" computes the offset')
    pivot = None
    arm = face = 0.0
    if motion == "oscillating":
        for key in ("pivot_x", "pivot_y") + (("arm_length",) if contact == "point" else ()):
            if key not in parsed:
                raise ParameterError(f"{where}.{scene_key(follower_keys(), key)}", None, "a length in mm",
                                     f"required for an oscillating {kind} follower")
        pivot = (parsed["pivot_x"], parsed["pivot_y"])
        arm = parsed.get("arm_length", 0.0)
        face = parsed.get("face_offset", 0.0) if contact == "face" else 0.0
    offset = parsed.get("follower_offset", 0.0) if motion == "translating" else 0.0
    base = parsed.get("base_radius")
    if base is None:
        base = _placeholder_base(contact, motion, roller, offset, pivot, arm, face)
    spec = _follower_spec(where, kind=kind, base_radius=base, motion=motion, roller_radius=roller, offset=offset, pivot=pivot,
                          arm_length=arm, face_offset=face, lift_turn=parsed.get("swing_turn", "ccw"), rotation=parsed["rotation"])
    return spec, sizing


def disk_spec(where: str, name: str, kind: str, parsed: Mapping[str, Any], law: Any, follower: "FollowerSpec", sizing: str,
              law_figures: Mapping[str, Any], base_dir: Path | None = None, form_closed: bool = False) -> CamSpec:
    """The :class:`CamSpec` of a disk cam (no generic follower model: the kind checks its own),
    with its follower train when the table gives one (:mod:`camgen.kinds.dynamics`; ``form_closed``:
    the form holds the follower both ways, a groove)."""
    from camgen.kinds.base import read_checks
    from camgen.kinds.disk_margins import read_margins
    from camgen.kinds.part_cache import body_and_dynamics

    from camgen.kinds.disk_ranges import read_sizing_ranges

    margins = read_margins(parsed)  # SIZING (issue 26 item 4): the plate form's margin keys
    ranges = read_sizing_ranges(where, parsed, follower)  # SIZE2 (issue 26 item 4): the sizing answers the scene asks for
    params = DiskParams(law, follower, sizing, parsed["fit_tol"], parsed.get("face_half_length"), dict(law_figures), parsed.get("source"),
                        margins, ranges)
    checks = read_checks(parsed)
    # the body and the train: read once while their keys stay the same (camgen.kinds.part_cache)
    body, dynamics = body_and_dynamics(where, parsed, motion=follower.motion, follower=follower.kind, rpm=checks.rpm,
                                       base_dir=base_dir, form_closed=form_closed)
    return CamSpec(name, kind, params, body, checks, None, dynamics)


def pressure_limit(spec: CamSpec) -> float:
    """The pressure-angle limit of a disk cam, rad (the scene's, else 30 deg translating, 45 deg oscillating)."""
    limit = spec.checks.pressure_angle_limit
    return limit if limit is not None else DEFAULT_LIMITS[spec.params.follower.motion]


# --------------------------------------------------------------------------------------------
# Building
# --------------------------------------------------------------------------------------------
class EnvelopeJoins:
    """A law as the envelope sees it: only the breaks where a derivative up to the jerk jumps
    (a quintic lift table is smooth through the jerk at its rows: no knot is needed there)."""

    def __init__(self, law: Any) -> None:
        from camgen.synthesis.laws import SMOOTH

        keep = np.asarray(law.break_continuity) < SMOOTH
        self.law = law
        self.breaks = np.asarray(law.breaks, dtype=float)[keep]
        self.break_continuity = np.asarray(law.break_continuity, dtype=int)[keep]

    def __call__(self, theta: np.ndarray):
        return self.law(theta)


def _limits(spec: CamSpec, tool_radius: float | None):
    from camgen.kinds.disk_margins import design_limits
    from camgen.synthesis.sizing import DesignLimits

    return design_limits(spec, DesignLimits(max_pressure_angle=pressure_limit(spec), min_concave_radius=tool_radius or 0.0), sizing=True)


def _ceil(value: float, digits: int = 3) -> float:
    scale = 10.0**digits
    return math.ceil(value * scale - 1e-9) / scale


def size_follower(spec: CamSpec) -> "SizingResult":
    """The smallest base radius (and offset) of ``spec``'s follower meeting its limits, rounded up
    to 0.001 mm (the offset to 0.001 mm) where the rounded design still meets them."""
    from camgen.synthesis import sizing as sz

    p: DiskParams = spec.params
    limits = _limits(spec, spec.checks.tool_radius)
    law = p.law
    if p.sizing == "base_radius_and_offset":
        found = sz.min_base_radius_and_offset(p.follower, law, limits)
        offset = round(found.offset, 3)
        start = replace(p.follower, offset=offset, base_radius=abs(offset) + 1.0)
        found = sz.min_base_radius(start, law, limits)
    else:
        found = sz.min_base_radius(p.follower, law, limits)
    base = _ceil(found.base_radius)
    try:
        rounded = replace(found.follower, base_radius=base)
        measures = sz.measure(rounded, law, limits.check_step)
        if not measures.violations(limits):
            return sz.SizingResult(base, rounded.offset, rounded, measures, found.tol)
    except ParameterError:
        pass
    return found


@functools.lru_cache(maxsize=2)
def _sample_angles(n: int) -> np.ndarray:
    """The motion samples' cam angles ``2 pi arange(n) / n`` (rad), read-only, made once (a pure
    function of ``n``: every disk cam's :func:`_motion` shares them)."""
    theta = 2.0 * math.pi * np.arange(n) / n
    theta.setflags(write=False)
    return theta


def _motion(follower: "FollowerSpec", law: Any) -> "Motion":
    """The follower's SVAJ per unit cam speed on a uniform grid, exactly from the law."""
    from camgen.checks import Motion, where_degrees

    theta = _sample_angles(MOTION_SAMPLES)
    samples = getattr(law, "on_sample_grid", None)  # a motion program: the same numbers, kept across designs
    s, ds, d2s, d3s = samples(MOTION_SAMPLES) if samples is not None else law(theta)
    peaks = law.peak_values()
    jumps = np.asarray(law.breaks)[np.asarray(law.break_continuity) < 2]
    return Motion(theta, s, ds, d2s, d3s, follower.lift_unit, where_degrees(jumps), lift_zero=0.0,
                  peaks=(peaks.velocity, peaks.acceleration, peaks.jerk))


def _circle(centre: np.ndarray, radius: float, n: int = 49) -> np.ndarray:
    a = np.linspace(0.0, 2.0 * math.pi, n)
    return np.stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)], axis=1)


def follower_shapes(f: "FollowerSpec", s: float, size: float, face: tuple[float, float] | None = None) -> list[tuple[str, np.ndarray]]:
    """Polylines (label, (n, 2) mm, fixed frame) of follower ``f`` at lift or swing ``s``.

    ``size``: a length for the stem and the knife (mm); ``face``: flat faces, the extent of the
    face drawn along it (translating: from the face centre; oscillating: ``xi`` from the foot of
    the pivot's perpendicular).
    """
    from camgen.synthesis.followers import kinematics

    class _At:
        breaks = np.zeros(0)
        break_continuity = np.zeros(0, dtype=int)

        def __call__(self, theta):
            z = np.zeros_like(np.asarray(theta, dtype=float))
            return z + s, z, z, z

    k = kinematics(f, _At(), np.zeros(1))
    out: list[tuple[str, np.ndarray]] = []
    stem = 0.35 * size
    if f.contact == "face":
        if f.motion == "translating":
            y = f.base_radius + s
            lo, hi = face if face is not None else (-0.3 * size, 0.3 * size)
            out.append(("follower face", np.array([[f.offset + lo, y], [f.offset + hi, y]])))
            out.append(("follower stem", np.array([[f.offset, y], [f.offset, y + stem]])))
            return out
        arm_angle = _given(k.arm_angle, "an oscillating face's normal angle")
        w = np.array([math.cos(arm_angle[0]), math.sin(arm_angle[0])])
        jw = np.array([-w[1], w[0]])
        foot = np.asarray(f.pivot) - f.face_offset * w
        lo, hi = face if face is not None else (-0.3 * size, 0.3 * size)
        out.append(("follower face", np.stack([foot + lo * jw, foot + hi * jw])))
        near = 0.0 if lo <= 0.0 <= hi else (lo if abs(lo) < abs(hi) else hi)  # the face's end nearer the pivot's foot
        out.append(("arm", np.stack([np.asarray(f.pivot), foot, foot + near * jw])))
        out.append(("pivot", _circle(np.asarray(f.pivot), 0.03 * size, 25)))
        return out
    c = k.follower_point[0]
    if f.motion == "translating":
        up = np.array([0.0, 1.0])
        top = c + (f.roller_radius + stem) * up
        out.append(("follower stem", np.stack([c if f.has_radius else c + 0.25 * size * up, top])))
    else:
        out.append(("arm", np.stack([np.asarray(f.pivot), c])))
        out.append(("pivot", _circle(np.asarray(f.pivot), 0.03 * size, 25)))
        up = (c - np.asarray(f.pivot)) / f.arm_length
        up = np.array([-up[1], up[0]]) * f.tau  # the direction of lift: the knife's body lies that way from its tip
    if f.has_radius:
        out.append(("roller", _circle(c, f.roller_radius)))
    else:
        side = np.array([-up[1], up[0]])
        out.append(("knife", np.stack([c + 0.25 * size * up + 0.08 * size * side, c, c + 0.25 * size * up - 0.08 * size * side])))
    return out


def _face_extent(f: "FollowerSpec", data: Any, half: float | None) -> tuple[float, float]:
    """Extent of a flat face to draw: translating about its centre, oscillating along xi."""
    xi = data.face_position
    if f.motion == "translating":
        reach = max(float(np.max(np.abs(xi))) * 1.15, 0.1 * f.base_radius) if half is None else half
        return -reach, reach
    lo, hi = float(np.min(xi)), float(np.max(xi))
    mid = 0.5 * (lo + hi)
    half = max(0.6 * (hi - lo), 0.1 * f.base_radius) if half is None else half
    return mid - half, mid + half


def _reachable_fit_tol(follower: "FollowerSpec", law: Any, failure: FitToleranceError, tries: int = 4) -> str:
    """The valid range of ``fit_tol_mm`` after ``failure``: the least tolerance (two significant
    digits, rounded up) at which the envelope was then built, or what else to change."""
    from camgen.synthesis.followers import cam_envelope

    for _ in range(tries):
        least = ceil_significant(failure.reached * 1.01, 2)
        if least > FIT_TOL_MAX:
            break
        try:
            cam_envelope(follower, law, fit_tol=least, report_only=True)
        except FitToleranceError as exc:
            failure = exc
            continue
        except GeometryError:  # the profile fails otherwise at that tolerance: no least value to quote
            break
        return f">= {least:.2g} mm"
    return f"<= {FIT_TOL_MAX:g} mm, with no tolerance tried up to it building the profile: change the base radius (or use fewer table rows)"


def build_disk(spec: CamSpec, stages: frozenset[str]) -> DiskCam:
    """The exact envelope of the follower (report-only when it cannot be made), with sizing,
    the exact motion and, with the ``plots`` stage, the report's animation."""
    from camgen.synthesis.followers import cam_envelope, contact_points

    p: DiskParams = spec.params
    where = f"cams.{spec.name}"
    sizing = None
    follower = p.follower
    if p.sizing != "none":
        try:
            sizing = size_follower(spec)
        except GeometryError as exc:  # no base radius meets the limits: the key that asked for one
            from camgen.synthesis.sizing import MAX_BASE_RADIUS

            raise ParameterError(f"{where}.sizing", p.sizing, '"none" (and a base_radius_mm), or a follower and law that some base '
                                 f"radius up to {MAX_BASE_RADIUS:g} mm makes meet the pressure-angle limit "
                                 f"{math.degrees(pressure_limit(spec)):g} deg", str(exc)) from None
        follower = sizing.follower
    envelope_law = p.law if hasattr(p.law, "joins") else EnvelopeJoins(p.law)  # a lift table: knots where it jumps only
    try:
        env = with_cam(where, lambda: cam_envelope(follower, envelope_law, fit_tol=p.fit_tol, report_only=True))
    except FitToleranceError as exc:  # the key to change, and a least value tried and found to work
        raise ParameterError(f"{where}.fit_tol_mm", p.fit_tol, _reachable_fit_tol(follower, envelope_law, exc),
                             str(exc).removeprefix(f"{where}: ")) from None
    profile = env.profile
    lo, hi = p.law.s_bounds
    unit = follower.lift_unit
    stroke = {"stroke_mm": hi - lo} if unit == "mm" else {"stroke_deg": math.degrees(hi - lo)}
    figures: dict[str, Any] = {"base_radius_mm": follower.base_radius, "follower": _follower_figures(follower), **stroke,
                               **p.law_figures}
    if sizing is not None:
        figures["sizing"] = {"method": p.sizing, "base_radius_mm": sizing.base_radius,
                             **({"offset_mm": sizing.offset} if p.sizing == "base_radius_and_offset" else {}),
                             "pressure_angle_limit_deg": round(math.degrees(pressure_limit(spec)), 9),
                             "min_concave_radius_mm": spec.checks.tool_radius or 0.0}
    if p.sizing_ranges:  # SIZE2 (issue 26 item 4): every passing interval of the quantities the scene names
        from camgen.kinds.disk_ranges import sizing_range_figures

        figures["sizing_ranges"] = sizing_range_figures(p.sizing_ranges, follower, p.law, _limits(spec, spec.checks.tool_radius))
    figures["fit_tol_mm"] = p.fit_tol
    if profile is not None:
        figures["fit_error_mm"] = env.fit_error
        figures["profile_pieces"] = int(sum(seg.n_pieces for seg in profile.segments))
        if REPORT_FIGURES_STAGE in stages:  # the report's figures of the shape (no check reads them)
            figures["area_mm2"] = profile.area
            figures["perimeter_mm"] = profile.length
            figures["bounds_mm"] = list(profile.bounds)
    if p.source is not None:
        figures["source"] = p.source
    zero = contact_points(follower, p.law, np.zeros(1))[0]
    zero_mark = ZeroMark((float(zero[0]), float(zero[1])), follower.sigma)
    pitch = env.pitch if follower.has_radius else None  # a knife's pitch curve is its profile
    drawing = animation = None
    if "plots" in stages:  # what report.html draws: the follower at cam angle 0, the animation
        size = follower.prime_radius + (p.law.stroke if unit == "mm" else 0.0)
        face = _face_extent(follower, env.data, p.face_half_length) if follower.contact == "face" else None
        s0 = float(p.law(np.zeros(1))[0][0])
        drawing = follower_shapes(follower, s0, size, face)
        animation = ride_animation(profile if profile is not None else env.pitch, zero_mark, follower, p.law, size, face)
    return DiskCam(spec.name, spec.kind, profile, figures, spec.body, None, pitch=pitch, zero_mark=zero_mark,
                   envelope=env, law=p.law, spec_follower=follower, sizing=sizing, motion=_motion(follower, p.law),
                   drawing=drawing, animation=animation)


def _follower_figures(f: "FollowerSpec") -> dict[str, Any]:
    out: dict[str, Any] = {"kind": f.kind, "motion": f.motion, "rotation": f.rotation}
    if f.has_radius:
        out["roller_radius_mm"] = f.roller_radius
    out["prime_radius_mm"] = f.prime_radius
    if f.motion == "translating":
        out["offset_mm"] = f.offset
    else:
        out["pivot_mm"] = list(f.pivot)  # type: ignore[arg-type]
        out["swing_turn"] = f.lift_turn
        if f.contact == "face":
            out["face_offset_mm"] = f.face_offset
            out["rest_face_normal_deg"] = math.degrees(f.rest_face_angle)
        else:
            out["arm_length_mm"] = f.arm_length
            out["rest_arm_angle_deg"] = math.degrees(f.rest_arm_angle)
    return out


def ride_animation(outline: Any, zero_mark: ZeroMark, f: "FollowerSpec", law: Any, size: float, face: tuple[float, float] | None):
    """The data of the report's animation: the profile (or, where it cannot be made, the pitch
    curve) ``outline``, the follower at zero lift, and per frame the follower's lift
    (translating, mm) or swing (deg, signed as the arm turns)."""
    from camgen.report.animation import RideAnimation

    if outline is None:
        return None
    chord = max(1e-3, 2e-4 * size)
    theta = 2.0 * math.pi * np.arange(ANIMATION_FRAMES) / ANIMATION_FRAMES
    s = law(theta)[0]
    if f.motion == "translating":
        moves, pivot = s, None
    else:
        px, py = _given(f.pivot, "an oscillating follower's pivot")
        moves, pivot = np.degrees(f.tau * s), (px, py)
    return RideAnimation(outline.flatten(chord), f.sigma, follower_shapes(f, 0.0, size, face), f.motion, pivot, moves,
                         ANIMATION_SECONDS, zero_mark)


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------
_ORDER = ["none", "G0", "G1", "G2"]


def _continuity(cam: DiskCam, contour: "Contour") -> "CheckResult":
    """The contour's joints against the law: each joint as continuous as the law there (G2, G1
    where the acceleration jumps, G0 where the velocity jumps), its curvature jump the law's."""
    from camgen.checks import CheckResult, where_degrees
    from camgen.contour import Spline
    from camgen.synthesis.followers import profile_curvatures

    f = cam.spec_follower
    joints = contour.joints(curvature_tol=CURVATURE_JUMP_TOL)
    # the spline parameter is t = -sigma theta: each joint ends a segment at t = its last break
    splines = [seg for seg in contour.segments if isinstance(seg, Spline)]
    assert len(splines) == len(contour.segments), "a disk cam's envelope is made of splines"
    # the joints' cam angles in Python floats: numpy's fmod is C's (math.fmod) and its remainder
    # Python's % (fmod, then the divisor's sign), the same operations elementwise
    two_pi = 2.0 * math.pi
    at = [math.fmod(-f.sigma * float(seg.breaks[-1]), two_pi) % two_pi for seg in splines]
    angles = np.array(at)
    eps = 1e-9
    before, after = profile_curvatures(f, cam.law, angles + f.sigma * eps, angles - f.sigma * eps)  # the contour runs against sigma theta
    # where the law's velocity jumps (break continuity 0) the profile has a corner (a handful of
    # joints and breaks: Python floats, the arithmetic of numpy's mod elementwise)
    corners_at = [b for b, c in zip(np.asarray(cam.law.breaks, dtype=float).tolist(), np.asarray(cam.law.break_continuity).tolist())
                  if c == 0]
    expected = ["G0" if any(abs((a - b + math.pi) % two_pi - math.pi) <= 1e-9 for b in corners_at) else
                "G1" if abs(k_after - k_before) > CURVATURE_JUMP_TOL else "G2" for a, k_before, k_after in zip(at, before.tolist(), after.tolist())]
    levels = [j.continuity for j in joints]
    deviation = max((abs(j.curvature_jump_per_mm - (a - b)) for j, a, b, e in zip(joints, after.tolist(), before.tolist(), expected)
                     if e != "G0"), default=0.0)
    lowest = min(levels, key=_ORDER.index)
    required = min(expected, key=_ORDER.index) if "G0" in expected else "G1"
    passed = levels == expected and deviation <= CURVATURE_JUMP_TOL and _ORDER.index(lowest) >= _ORDER.index(required)
    jumps = [level != "G2" for level in levels]
    note = f"{len(joints)} joints at the law's breaks; lowest continuity {lowest}"
    if any(jumps):
        note += (f"; curvature jumps at {sum(jumps)} cam angles where the law's acceleration (or velocity) jumps: "
                 "the follower's acceleration jumps there (infinite jerk)")
    note += f"; each joint's curvature jump is the law's within {deviation:.2g} 1/mm"
    if not passed:
        bad = [i for i, (level, e) in enumerate(zip(levels, expected)) if level != e]
        note += "; joints not as continuous as the law: " + ", ".join(f"{levels[i]} at {math.degrees(at[i]):.3f} deg "
                                                                      f"(law: {expected[i]})" for i in bad[:6])
    where = [w for a, jump in zip(at, jumps) if jump for w in where_degrees(a)]  # (one double: numpy's values, tests/test_checks.py)
    return CheckResult("continuity", lowest, required, "at least", "", passed, where, note)


def mask_where(mask: np.ndarray, theta: np.ndarray, worst: int) -> list[float]:
    """Where a check points (deg): the start and end cam angles of every run of ``mask`` over
    ``theta`` (rad), else the cam angle of sample ``worst``."""
    from camgen.checks import run_ends, where_degrees

    return run_ends(mask, theta) if mask.any() else where_degrees(theta[worst])


def _undercut(cam: DiskCam) -> "CheckResult":
    from camgen.checks import CheckResult, where_degrees
    from camgen.kinds.least_radius import least_convex_radius
    from camgen.synthesis.followers import failing_conditions

    f, k, theta = cam.spec_follower, cam.envelope.data, cam.envelope.data.theta
    # a roller's largest pitch curvature: its undercut screen's and the least convex radius's
    top = float(k.pitch_curvature.max()) if f.has_radius and k.pitch_curvature is not None and k.pitch_curvature.size else None
    masks = failing_conditions(f, k, top)  # the failing conditions
    reasons = [r for r, _ in masks]
    bad = np.logical_or.reduce([m for _, m in masks]) if masks else None  # None: no sample fails
    if f.has_radius:
        least, i = least_convex_radius(_given(k.pitch_curvature, "a roller's pitch curve"), top)  # the pitch curve's radii, 1 / k
        value: Any = least if math.isfinite(least) else "none"
        limit, unit, what = f.roller_radius, "mm", "smallest convex radius of the pitch curve (roller-centre path) against the roller radius"
    elif f.contact == "face":
        rho = k.profile_radius
        i = int(np.argmin(rho))
        value, limit, unit, what = float(rho[i]), 0.0, "mm", "smallest radius of curvature of the envelope of the face (h + h'') against 0"
    else:
        speed = np.hypot(*_given(k.pitch_d1, "a knife's pitch curve").T)
        i = int(np.argmin(speed))
        value, limit, unit, what = float(speed[i]), 0.0, "mm/rad", "smallest speed of the knife tip over the cam (|dP/dtheta|, a cusp at 0) against 0"
    if bad is not None:
        i = int(bad.argmax())
    note = what + ("; " + "; ".join(reasons) + " (between the listed pairs of cam angles): the profile cannot be made" if reasons else "")
    where = mask_where(bad, theta, i) if bad is not None else where_degrees(theta[i])
    return CheckResult("undercut", value, limit, ">", unit, not reasons, where, note, blocks_manufacture=True)


def _face_length(cam: DiskCam, half: float | None) -> "CheckResult":
    from camgen.checks import face_length_check

    f, k = cam.spec_follower, cam.envelope.data
    xi = _given(k.face_position, "a flat face's contact position")
    if f.motion == "translating":
        return face_length_check(xi, k.theta, half)
    mid = 0.5 * (float(np.min(xi)) + float(np.max(xi)))
    check = face_length_check(xi - mid, k.theta, half)
    return replace(check, note=check.note + f"; oscillating face: about the middle of the contact's range, {mid:.6g} mm along the "
                   "face from the foot of the pivot's perpendicular (the contact runs from "
                   f"{float(np.min(xi)):.6g} to {float(np.max(xi)):.6g} mm)")


def law_joins_check(cam: DiskCam, rpm: float | None) -> "CheckResult":
    """The ``law_joins`` information: where the law's derivatives up to the jerk jump (and the
    largest acceleration jump at ``rpm``)."""
    from camgen.checks import information, where_degrees
    from camgen.synthesis.laws import SMOOTH

    law = cam.law
    if not hasattr(law, "joins") and hasattr(law, "angles"):
        rows = len(law.angles)
        return information("law_joins", 0, "", [], f"lift table: a periodic quintic spline through {rows} rows, continuous through the "
                           "jerk everywhere (its 4th derivative steps at the rows)")
    if not hasattr(law, "joins"):  # another law (camgen.motions): its breaks and the continuity the law states there
        breaks, continuity = np.asarray(law.breaks, dtype=float), np.asarray(law.break_continuity, dtype=int)
        where = where_degrees(breaks[continuity < SMOOTH])
        return information("law_joins", len(where), "", where, "breaks where a derivative up to the jerk jumps" if where else
                           "no break: the law is continuous through the jerk everywhere")
    jumps = [j for j in law.joins() if j.continuity < SMOOTH]
    note = "; ".join(j.describe() for j in jumps) if jumps else "every segment joins its neighbours smoothly up to the jerk"
    if rpm and jumps and cam.spec_follower.motion == "translating":
        omega = 2.0 * math.pi * rpm / 60.0
        worst = max((j for j in jumps if j.continuity == 1), key=lambda j: abs(j.jumps[1]), default=None)
        if worst is not None:
            note += f"; at {rpm:g} rpm the largest acceleration jump is {abs(worst.jumps[1]) * omega**2 * 1e-3:.6g} m/s^2"
    return information("law_joins", len(jumps), "", where_degrees(np.array([j.angle for j in jumps])), note)


def _base_radius_advice(cam: DiskCam, spec: CamSpec, tool_radius: float, tool_is_limit: bool, failed: bool) -> "CheckResult | None":
    """With sizing: what it found; without, when the pressure angle or the undercut fails: the
    smallest base radius that would pass (:func:`camgen.synthesis.sizing.min_base_radius`)."""
    from camgen.checks import information
    from camgen.synthesis import sizing as sz

    p: DiskParams = spec.params
    from camgen.kinds.disk_margins import design_limits, margin_text  # SIZING (issue 26 item 4)

    limit = round(math.degrees(pressure_limit(spec)), 9)
    tool = f" and concave radii >= the tool radius {tool_radius:g} mm" if tool_is_limit else ""
    tool += margin_text(spec, pressure_limit(spec), sizing=cam.sizing is not None)  # SIZING: the margins met, none without margin keys
    if cam.sizing is not None:
        found = cam.sizing
        extra = f", offset {found.offset:.6g} mm" if p.sizing == "base_radius_and_offset" else ""
        return information("sizing", found.base_radius, "mm", [],
                           f"sizing = {p.sizing!r}: the smallest base radius (rounded up to 0.001 mm){extra} meeting the pressure-angle "
                           f"limit {limit:g} deg{tool} with a profile that can be made")
    if not failed:
        return None
    limits = sz.DesignLimits(max_pressure_angle=pressure_limit(spec), min_concave_radius=tool_radius if tool_is_limit else 0.0)
    limits = design_limits(spec, limits)  # SIZING (issue 26 item 4)
    try:
        advice = sz.base_radius_advice(cam.spec_follower, cam.law, limits)
    except GeometryError as exc:
        return information("min_base_radius", "none", "mm", [], f"no base radius meets the pressure-angle limit {limit:g} deg{tool}: {exc}")
    meets = f"the pressure-angle limit {limit:g} deg{tool} with a profile that can be made"
    if advice.high is None:
        what = f"the smallest base radius meeting {meets}, tried; the pressure angle falls as the base radius grows"
    else:
        what = (f"both tried, and base radii every {advice.step:.3g} mm between: they meet {meets}; an oscillating follower's "
                "pressure angle is not monotonic in the base radius, and the passing run ends within 0.002 mm beyond each")
    return information("min_base_radius", advice.low, "mm", [],
                       f"{advice.text(cam.spec_follower.base_radius)} ({what}; or set sizing = \"base_radius\")")


def evaluate_disk(cam: BuiltCam, spec: CamSpec, tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    """The design checks of a disk cam (built by :func:`build_disk`) from the closed-form
    kinematics on the dense cam-angle grid."""
    from camgen.checks import CamEvaluation, machinability_from_radii, motion_check, pressure_angle_check

    assert isinstance(cam, DiskCam), f"a disk cam's checks on a {type(cam).__name__}"

    f, env = cam.spec_follower, cam.envelope
    k, theta = env.data, env.data.theta
    p: DiskParams = spec.params
    checks: list[CheckResult] = []
    if cam.contour is not None:
        checks.append(_continuity(cam, cam.contour))
    undercut = _undercut(cam)
    # SMOOTH (issue 26 item 3): a smoothed lift table's undercut against the raw readings'
    from camgen.kinds.lift_noise import undercut_noise_note

    undercut = undercut_noise_note(cam, undercut, _undercut)
    checks.append(undercut)
    what = f"{f.motion} {f.kind} follower" + (f" (offset {f.offset:g} mm)" if f.motion == "translating" and f.offset else "")
    pressure = pressure_angle_check(k.pressure_angle, theta, pressure_limit(spec), what)
    pressure = replace(pressure, limit=round(pressure.limit, 9))  # the scene's degrees, not their radian round trip
    if f.contact == "face" and f.motion == "translating":
        pressure = replace(pressure, note="a translating flat face moves along its own normal: pressure angle 0 at every cam angle")
    checks.append(pressure)
    checks.append(motion_check(cam.motion, spec.checks.rpm))
    checks.append(law_joins_check(cam, spec.checks.rpm))
    if f.contact == "face":
        checks.append(_face_length(cam, p.face_half_length))
    if cam.contour is not None:
        checks.extend(machinability_from_radii(k.profile_radius, theta, tool_radius, tool_is_limit, "cam angles"))
    # SIZING (issue 26 item 4): the rise/return limits, Norton's rule, the face's clearance
    from camgen.kinds.disk_margins import with_margins

    checks = with_margins(cam, spec, checks, pressure_limit(spec))
    margin_failed = any(c.failed for c in checks if c.name in ("pressure_angle", "pressure_angle_return", "pitch_curvature"))
    # end SIZING
    advice = _base_radius_advice(cam, spec, tool_radius, tool_is_limit, undercut.failed or margin_failed)
    if advice is not None:
        checks.append(advice)
    if cam.contour is not None:
        rho, label, limit = k.profile_radius, "profile radius of curvature (mm, < 0 concave)", None
    elif f.has_radius:
        rho, label, limit = _given(k.pitch_radius, "a roller's pitch curve"), "radius of curvature of the pitch curve (mm)", f.roller_radius
    else:
        rho, label, limit = k.profile_radius, "radius of curvature of the envelope (mm)", 0.0
    return CamEvaluation(tuple(checks), None, cam.motion, (theta, k.pressure_angle), (theta, rho), cam.pitch,
                         pressure_angle_label=f"{f.motion} {f.kind}, closed form", curvature_label=label, curvature_limit=limit,
                         curvature_angle_label="cam angle (deg)", follower_drawing=cam.drawing, animation=cam.animation)
