"""Motion ``motion_law``: a motion program (rise, dwell, return segments), a displacement law.

The segments follow the laws of :mod:`camgen.synthesis.laws` (closed-form displacement,
velocity, acceleration and jerk on normalised segments); every cam form that realises a law takes it
(the open plate cam: :mod:`camgen.forms.plate`).  Segment keys:
``law``, ``span_deg``, ``lift_mm`` (translating followers) or ``swing_deg`` (oscillating ones),
``blend`` (constant_velocity), ``start`` / ``end`` (polynomial: the displacement, velocity,
acceleration and jerk at the segment's ends, per degree of cam angle; converted to per rad),
``scca`` (scca: [b, c, d]), ``accel_fraction`` (the asymmetric modified sine / trapezoid),
``points`` and ``degree`` (bspline), ``interior`` (polynomial: conditions inside the span); a
``velocity_blend`` segment has no key of its own: its ends are its neighbours'.

**The abscissa.**  The form tells the motion what its program runs over through the follower it
drives (``follower.abscissa``, :data:`ANGLE` when it has none): a cam angle (``span_deg``, the
conditions per degree) or a plate travel (:data:`TRAVEL`: ``span_mm``, the conditions per mm,
``v`` in mm/mm and ``a`` in mm/mm^2).  A travel program is read onto one turn: the spans'
sum is the travel ``T`` (``figures["travel_mm"]``), a span of ``x`` mm is ``2 pi x / T`` rad
and a condition per mm^k is multiplied by ``(T / 2 pi)^k``; the key of the other abscissa is
refused naming the one to use.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.errors import ParameterError
from camgen.frozen import Copies, Keyed, Unfreezable
from camgen.keynames import renamed
from camgen.motions.base import LawReading, Motion
from camgen.motions.segment_rows import Rows, rows_per_rad
from camgen.schema import REQUIRED, Angle, Choice, Count, Key, Number, NumberList, TableList

if TYPE_CHECKING:
    from camgen.synthesis.followers import FollowerSpec

#: Law names scene files may use (camgen.synthesis.laws.LAWS, kept here so reading the key
#: reference imports no synthesis module; a test keeps them equal).
LAW_NAMES = ("constant_velocity", "cycloidal", "double_harmonic", "dwell", "harmonic", "modified_cycloidal", "modified_sine",
             "modified_trapezoid", "poly345", "poly4567", "polynomial", "simple_harmonic",
             # issue 26 LAWS
             "constant_acceleration", "trapezoidal", "scca", "asymmetric_modified_sine", "asymmetric_modified_trapezoid",
             "bspline", "velocity_blend")  # SPLINE (issue 26)

_CONDITIONS = NumberList(Number(""), 1, 4)
#: The abscissae of a motion program (``follower.abscissa``): a cam angle, or a plate travel in mm.
ANGLE, TRAVEL = "angle", "travel"

SEGMENT_KEYS = (
    Key("law", Choice(LAW_NAMES), "Motion law of the segment (dwell: no motion; harmonic is simple_harmonic; see "
        "camgen/synthesis/laws.py for each law's formula and source).", ("profile",), default=REQUIRED),
    Key("span_deg", Angle(0.0, 360.0, low_open=True), "Cam angle the segment spans (required, except on a linear cam, whose "
        "segments give span_mm instead and refuse span_deg).", ("profile",)),
    Key("span_mm", Number("mm", 0.0, 1e5, low_open=True), "Linear cam (form = \"linear\") only: plate travel the segment spans; "
        "the spans add up to the travel (travel_mm, derived from them when left out, else equal to their sum).", ("profile",),
        attr="span_travel"),
    Key("lift_mm", Number("mm", -1e4, 1e4), "Translating follower: travel over the segment (> 0 rise, < 0 return; 0 or left out "
        "for a dwell; a polynomial's follows from its start and end, as a bspline's given start/end; a bspline's may be 0; a "
        "velocity_blend's may be left out: the lift of the lowest-degree blend, between two constant velocities their mean times "
        "the span).", ("profile",)),
    Key("swing_deg", Angle(-180.0, 180.0), "Oscillating follower: swing of the arm over the segment (> 0 away from the cam, "
        "< 0 back; 0 or left out for a dwell; left out for a velocity_blend: as lift_mm).", ("profile",), feeds=("lift",)),
    Key("blend", Number("", 0.0, 0.5), "constant_velocity only: fraction of the span in each end blend that ramps the velocity "
        "(0: plain constant velocity, whose velocity jumps at the ends: a knife follower only).", ("profile",)),
    Key("start", _CONDITIONS, "polynomial and bspline only: [s, v, a] (optionally j) at the segment's start: lift mm (oscillating: swing deg), "
        "velocity per degree of cam angle, acceleration per degree^2, jerk per degree^3 (converted to per rad); on a linear cam per "
        "mm of plate travel (v in mm/mm, a in mm/mm^2, j in mm/mm^3; oscillating: deg/mm, ...).", ("profile",)),
    Key("end", _CONDITIONS, "polynomial and bspline only: [s, v, a] (optionally j) at the segment's end, in the units of start.", ("profile",)),
    # issue 26 LAWS
    Key("scca", NumberList(Number("", 0.0, 1.0), 3, 3), "scca only (required there): [b, c, d], the fractions of the span in "
        "the sine ramps (b), the constant acceleration (c) and the middle cosine (d) of Norton's SCCA family; b + c + d = 1 "
        "(within 1e-9). [0, 1, 0] is constant acceleration, [0.25, 0.5, 0.25] the modified trapezoid, [0, 0, 1] simple "
        "harmonic, [0.25, 0, 0.75] the modified sine, [0.5, 0, 0.5] cycloidal.", ("profile",), example=[0.25, 0.5, 0.25]),
    Key("accel_fraction", Number("", 0.05, 0.95), "asymmetric_modified_sine and asymmetric_modified_trapezoid only "
        "(required there): fraction of the span in the positive acceleration pulse, the negative one takes the rest "
        "(Rothbart's skewed curves: the peak velocity stays the symmetric law's, the positive peak acceleration is its "
        "times 1/(2 accel_fraction)); 0.5 is the symmetric law.", ("profile",), example=0.4),
    # SPLINE (issue 26)
    Key("points", Rows(2, 2), "bspline only: [[position, lift], ...] the points the spline passes through exactly: position from the "
        "segment's start in deg of cam angle (a linear cam: mm of travel), strictly inside the span and increasing; lift in mm above "
        "the segment's start (oscillating: swing deg). bspline's ends: at rest (v = a = 0; lift_mm the lift, 0 allowed: back to "
        "the start) or, both given, start/end = [s, v] (degree 3), [s, v, a] (5), [s, v, a, j] (7) in the units of a polynomial's.",
        ("profile",)),
    Key("degree", Count(3, 7), "bspline only: degree of the interpolating spline, 3, 5 or 7 (odd): C2, C4 or C6 at the points; "
        "(degree - 1)/2 derivatives (v; v, a; v, a, j) prescribed at each end (default 5).", ("profile",)),
    Key("interior", Rows(2, 4, 12), "polynomial only: interior conditions [[position, s, v, a], ...] (v, a optional): the "
        "displacement s (and velocity, acceleration) at a position from the segment's start (deg; a linear cam: mm), strictly "
        "inside the span and increasing, in the units of start/end (s absolute like start[0]); the polynomial is the "
        "lowest-degree one meeting every condition (degree = their number - 1, at most 15).", ("profile",)),
)

KEYS = (
    Key("segments", TableList(SEGMENT_KEYS, what="[[segments]] tables"),
        "The motion program: [[cams.<name>.segments]] tables in order from cam angle 0 (a linear cam: from travel 0); spans "
        "add up to 360 deg (a linear cam's span_mm to the travel) and the follower returns to where it started.", ("profile",),
        default=REQUIRED),
)


def _per_rad(values: tuple[float, ...], oscillating: bool, per_unit: float = 180.0 / math.pi) -> tuple[float, ...]:
    """[s, v, a, j] per unit^k of the abscissa (s in mm, or deg of swing) -> per rad^k of the turn
    (mm or rad); ``per_unit``: the abscissa's units in one rad (a degree: 180 / pi; a travel of
    T mm: T / (2 pi))."""
    factor = math.pi / 180.0 if oscillating else 1.0  # deg of swing -> rad
    return tuple(v * factor * per_unit**k for k, v in enumerate(values))


def _spans(where: str, segments: tuple[dict[str, Any], ...], abscissa: str) -> tuple[list[float], float | None]:
    """Each segment's span on the turn (rad) and, for a travel program, the travel (mm: the sum of
    the spans); the other abscissa's key is refused naming the one to use."""
    travel = abscissa == TRAVEL
    given, other = ("span_travel", "span") if travel else ("span", "span_travel")
    key, other_key = ("span_mm", "span_deg") if travel else ("span_deg", "span_mm")
    for i, seg in enumerate(segments):
        path = f"{where}.segments[{i}]"
        if other in seg:
            shown = round(math.degrees(seg[other]), 9) if travel else seg[other]
            raise ParameterError(f"{path}.{other_key}", shown, f"{key} (leave {other_key} out)",
                                 "a linear cam's program runs over the plate travel: use span_mm (mm)" if travel else
                                 "span_mm is a linear cam's (form = \"linear\"): this cam's program runs over the cam angle, use span_deg")
        if given not in seg:
            raise ParameterError(f"{path}.{key}", None, "a length in mm > 0" if travel else "an angle in (0, 360] deg",
                                 "every segment gives its span")
    if not travel:
        return [seg["span"] for seg in segments], None
    total = math.fsum(seg["span_travel"] for seg in segments)
    return [2.0 * math.pi * seg["span_travel"] / total for seg in segments], total


#: A segment's options (their fields) and the laws that take each (read_program refuses the others).
_OPTION_OWNERS = (("blend", "constant_velocity"), ("start", "polynomial or bspline"), ("end", "polynomial or bspline"),
                  ("scca", "scca"), ("accel_fraction", "asymmetric_modified_sine or asymmetric_modified_trapezoid"),
                  ("points", "bspline"), ("degree", "bspline"), ("interior", "polynomial"))
_OPTION_FIELDS = frozenset(name for name, _ in _OPTION_OWNERS)


@lru_cache(maxsize=2)
def _segment_keys(other: str) -> tuple[Key, ...]:
    """:data:`SEGMENT_KEYS` without ``other`` (the other follower motion's lift key), made once."""
    return tuple(k for k in SEGMENT_KEYS if k.name != other)


def read_program(where: str, segments: tuple[dict[str, Any], ...], motion: str, complete: Any = None, abscissa: str = ANGLE):
    """The :class:`~camgen.synthesis.laws.MotionProgram` of the ``[[segments]]`` tables over one
    turn (``abscissa``: :data:`ANGLE` or :data:`TRAVEL`, module notes); ``complete``: segments ->
    the segments that follow them (a half-turn program's second half)."""
    from camgen.synthesis import laws

    spans, travel = _spans(where, segments, abscissa)
    per_unit = 180.0 / math.pi if travel is None else travel / (2.0 * math.pi)
    oscillating = motion == "oscillating"
    key, other = ("swing_deg", "lift_mm") if oscillating else ("lift_mm", "swing_deg")
    field, other_field = key.rsplit("_", 1)[0], other.rsplit("_", 1)[0]
    segment_keys = _segment_keys(other)  # the segment's lift is this follower's key
    built = []
    for i, seg in enumerate(segments):
        path = f"{where}.segments[{i}]"
        if other_field in seg:
            article = "an" if oscillating else "a"
            raise ParameterError(f"{path}.{other}", seg[other_field], f"{key} for {article} {motion} follower",
                                 f"{article} {motion} follower's segments give {'the swing in deg' if oscillating else 'the lift in mm'}")
        law = seg["law"]
        lift = seg.get(field)
        shown = math.degrees(lift) if oscillating and lift is not None else lift
        if law == "dwell" and lift not in (None, 0.0):
            raise ParameterError(f"{path}.{key}", shown, "0 (or leave it out) for a dwell")
        if law not in ("dwell", "polynomial", "bspline", "velocity_blend") and not lift:
            raise ParameterError(f"{path}.{key}", shown, f"a non-zero {key} for a {law} segment (a segment without motion is a dwell)")
        if not _OPTION_FIELDS.isdisjoint(seg):  # (a segment without options has nothing to refuse here)
            for name, allowed in _OPTION_OWNERS:
                if name in seg and law not in allowed.split(" or "):
                    raise ParameterError(f"{path}.{name}", seg[name], f"no {name} for a {law} segment", f"only for {allowed}")
        if law == "polynomial" and ("start" not in seg or "end" not in seg):
            raise ParameterError(f"{path}.{'start' if 'start' not in seg else 'end'}", None,
                                 "[s, v, a] (optionally j) at both ends of a polynomial segment")
        start = _per_rad(seg["start"], oscillating, per_unit) if "start" in seg else None
        end = _per_rad(seg["end"], oscillating, per_unit) if "end" in seg else None
        # SPLINE (issue 26): a bspline's points, a polynomial's interior conditions (positions checked in scene units)
        rows = {}
        if "points" in seg or "interior" in seg:
            span_scene, span_unit = (math.degrees(spans[i]), "deg") if travel is None else (seg["span_travel"], "mm")
            rows = {name: rows_per_rad(f"{path}.{name}", seg[name], span_scene, span_unit, per_unit, oscillating)
                    for name in ("points", "interior") if name in seg}
        built.append(renamed(path, segment_keys, lambda: laws.Segment(law, spans[i], lift, seg.get("blend"), start, end,
                                                                      seg.get("scca"), seg.get("accel_fraction"), where=path, points=rows.get("points"), degree=seg.get("degree"),
                                                                      interior=rows.get("interior"))))
    if complete is not None:
        built += complete(built)
    try:
        return laws.MotionProgram(built, unit="rad" if oscillating else "mm")
    except ParameterError as exc:
        name = exc.name if exc.name.startswith(where) else f"{where}.{exc.name}"
        raise ParameterError(name, exc.value, exc.valid, exc.why) from None


def _segment_figures(segments: tuple[dict[str, Any], ...], oscillating: bool) -> list[dict[str, Any]]:
    out = []
    for seg in segments:
        item: dict[str, Any] = ({"law": seg["law"], "span_deg": round(math.degrees(seg["span"]), 9)} if "span" in seg else
                                {"law": seg["law"], "span_mm": seg["span_travel"]})
        if "lift" in seg:
            item["lift_mm"] = seg["lift"]
        if "swing" in seg:
            item["swing_deg"] = round(math.degrees(seg["swing"]), 9)
        for name in ("blend", "start", "end", "scca", "accel_fraction", "degree"):
            if name in seg:
                item[name] = list(seg[name]) if name not in ("blend", "accel_fraction", "degree") else seg[name]
        for name in ("points", "interior"):  # SPLINE (issue 26)
            if name in seg:
                item[name] = [list(row) for row in seg[name]]
        out.append(item)
    return out


def read_law(where: str, parsed: Mapping[str, Any], follower: "FollowerSpec", base_dir: Path | None = None) -> LawReading:
    """The motion program of a cam table for ``follower`` (a lift in mm for a translating one, a
    swing in rad for an oscillating one) over one turn of the follower's abscissa (``abscissa``:
    a cam angle, or a plate travel whose length the figures give as ``travel_mm``); a velocity
    jump is refused unless the follower is a knife.

    The same segments for the same follower give the SAME law object (:data:`LAW_CACHE` programs
    kept, its arrays read-only): a study whose designs keep the motion reads it once, and what the
    law keeps of its own evaluation serves every design; the figures are the caller's own copy."""
    abscissa = getattr(follower, "abscissa", ANGLE)  # the form's follower says what the program runs over
    segments = parsed["segments"]
    args = (where, follower.motion, abscissa, follower.edge, follower.kind)
    try:
        keyed = Keyed(segments)
    except Unfreezable:  # not a parsed table (a caller's own values): read without the cache
        program, figures = _read_law(segments, *args)
        return LawReading(program, figures)
    program, copies = _cached_law(keyed, *args)
    return LawReading(program, copies.copy())


#: Motion programs :func:`read_law` keeps (the last ones read: a scene's cams, a study's designs).
LAW_CACHE = 16


@lru_cache(maxsize=LAW_CACHE)
def _cached_law(segments: Keyed, where: str, motion: str, abscissa: str, edge: bool, kind: str) -> tuple[Any, Copies]:
    program, figures = _read_law(segments.value, where, motion, abscissa, edge, kind)
    read_only(program)
    return program, Copies(figures)


def _read_law(segments: tuple[dict[str, Any], ...], where: str, motion: str, abscissa: str, edge: bool,
              kind: str) -> tuple[Any, dict[str, Any]]:
    """The program and figures of :func:`read_law` from the parsed segments and what it reads of
    the follower (its motion, abscissa, whether it is an edge and its kind's name)."""
    program = read_program(where, segments, motion, abscissa=abscissa)
    figures: dict[str, Any] = {"segments": _segment_figures(segments, motion == "oscillating")}
    for item, seg in zip(figures["segments"], program.segments):  # SPLINE (issue 26): the lift a velocity_blend found
        if item["law"] == "velocity_blend" and "lift_mm" not in item and "swing_deg" not in item:
            item["swing_deg" if motion == "oscillating" else "lift_mm"] = (
                round(math.degrees(seg.lift), 9) if motion == "oscillating" else seg.lift)
    if abscissa == TRAVEL:
        figures["travel_mm"] = math.fsum(seg["span_travel"] for seg in segments)
    _refuse_corners(where, program, segments, _Edge(edge, kind), figures.get("travel_mm"))
    figures["vdi2143"] = _vdi_figures(program)  # VDI: VDI 2143 names, tasks, characteristic values (issue 26 item 2)
    return program, figures


@dataclass(frozen=True)
class _Edge:
    """What :func:`_refuse_corners` reads of a follower."""

    edge: bool
    kind: str


def read_only(law: Any) -> None:
    """Make the arrays a law object holds read-only (a cached law is shared by its readers)."""
    import numpy as np

    for value in vars(law).values():
        if isinstance(value, np.ndarray):
            value.flags.writeable = False


def _refuse_corners(where: str, program: Any, segments: tuple[dict[str, Any], ...], follower: "FollowerSpec | _Edge",
                    travel: float | None = None) -> None:
    """A velocity jump is refused unless the follower is a knife (segment i of a completed
    half-turn program is the user's segment i modulo their number); ``travel``: a travel
    program's (mm), where the jump is said in mm of travel."""
    if follower.edge:  # a knife edge rides the corner; a roller or a face cannot
        return
    n = len(segments)
    for join in program.joins():
        if join.continuity < 1:
            at = (f"{math.degrees(join.angle):.6g} deg" if travel is None else f"travel {travel * join.angle / (2.0 * math.pi):.6g} mm")
            jump = (f"{join.jumps[0]:.6g} {program.unit}/rad" if travel is None else
                    f"{join.jumps[0] * 2.0 * math.pi / travel:.6g} {program.unit}/mm")
            raise ParameterError(
                f"{where}.segments[{join.after % n}].law", segments[join.after % n]["law"],
                f"a law whose velocity at {at} matches the end of segments[{join.before % n}]",
                f"the velocity jumps by {jump} there: a {follower.kind} follower cannot follow the "
                "corner this makes in its path; blend it (constant_velocity with blend > 0) or use a knife follower")


def read_half_law(where: str, parsed: Mapping[str, Any], follower: "FollowerSpec", base_dir: Path | None = None) -> LawReading:
    """The motion program of a cam table whose segments cover the first half-turn (spans adding up
    to 180 deg), completed by ``s(theta + 180 deg) = C - s(theta)``
    (:func:`camgen.synthesis.breadth.mirror_segments`)."""
    from camgen.synthesis.breadth import mirror_segments

    segments = parsed["segments"]
    _spans(where, segments, ANGLE)  # every segment gives span_deg (a span_mm is refused naming it)
    for i, seg in enumerate(segments):  # SPLINE (issue 26): the mirror rebuilds segments from lifts and end conditions only
        if seg["law"] in ("bspline", "velocity_blend") or "interior" in seg:
            key = "interior" if "interior" in seg else "law"
            raise ParameterError(f"{where}.segments[{i}].{key}", seg[key] if key == "law" else [list(r) for r in seg[key]],
                                 "a law without points, interior conditions or neighbour-made ends (half_turn = true)",
                                 "the half-turn rule mirrors the first half's segments; give the whole turn instead")
    total = math.fsum(seg["span"] for seg in segments)
    if abs(total - math.pi) > 1e-9:
        raise ParameterError(f"{where}.segments", f"spans adding up to {math.degrees(total):.9g} deg", "spans adding up to 180 deg",
                             "half_turn = true: the segments give the first half-turn, the rule s(theta + 180 deg) = C - s(theta) "
                             "the second")
    program = read_program(where, segments, follower.motion, complete=mirror_segments)
    _refuse_corners(where, program, segments, follower)
    return LawReading(program, {"segments": _segment_figures(segments, follower.motion == "oscillating"), "half_turn": True,
                                "vdi2143": _vdi_figures(program)})  # VDI: issue 26 item 2


# ---- VDI 2143 (issue 26 item 2: camgen/synthesis/vdi2143.py) ---------------------------------
def _vdi_figures(program: Any) -> dict[str, Any]:
    from camgen.synthesis.vdi2143 import program_figures

    return program_figures(program)
# ---- end VDI 2143 ----------------------------------------------------------------------------


MOTION = Motion(
    name="motion_law",
    summary="disk cam from a motion program (cycloidal, harmonic, modified trapezoid/sine/cycloidal, polynomials, ... per segment) "
            "for a translating or oscillating roller, flat face or knife, as the exact envelope",
    keys=KEYS,
    read_law=read_law,
    read_half_law=read_half_law,
)
