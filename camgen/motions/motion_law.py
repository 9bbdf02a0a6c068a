"""Motion ``motion_law``: a motion program (rise, dwell, return segments), a displacement law.

The segments follow the laws of :mod:`camgen.synthesis.laws` (closed-form displacement,
velocity, acceleration and jerk on normalised segments); every cam form that realises a law takes it
(the open plate cam: :mod:`camgen.forms.plate`).  Segment keys:
``law``, ``span_deg``, ``lift_mm`` (translating followers) or ``swing_deg`` (oscillating ones),
``blend`` (constant_velocity) and ``start`` / ``end`` (polynomial: the displacement, velocity,
acceleration and jerk at the segment's ends, per degree of cam angle; converted to per rad).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.errors import ParameterError
from camgen.keynames import renamed
from camgen.motions.base import LawReading, Motion
from camgen.schema import REQUIRED, Angle, Choice, Key, Number, NumberList, TableList

if TYPE_CHECKING:
    from camgen.synthesis.followers import FollowerSpec

#: Law names scene files may use (camgen.synthesis.laws.LAWS, kept here so reading the key
#: reference imports no synthesis module; a test keeps them equal).
LAW_NAMES = ("constant_velocity", "cycloidal", "double_harmonic", "dwell", "harmonic", "modified_cycloidal", "modified_sine",
             "modified_trapezoid", "poly345", "poly4567", "polynomial", "simple_harmonic")

_CONDITIONS = NumberList(Number(""), 1, 4)

SEGMENT_KEYS = (
    Key("law", Choice(LAW_NAMES), "Motion law of the segment (dwell: no motion; harmonic is simple_harmonic; see "
        "camgen/synthesis/laws.py for each law's formula and source).", ("profile",), default=REQUIRED),
    Key("span_deg", Angle(0.0, 360.0, low_open=True), "Cam angle the segment spans.", ("profile",), default=REQUIRED),
    Key("lift_mm", Number("mm", -1e4, 1e4), "Translating follower: travel over the segment (> 0 rise, < 0 return; 0 or left out "
        "for a dwell; a polynomial's follows from its start and end).", ("profile",)),
    Key("swing_deg", Angle(-180.0, 180.0), "Oscillating follower: swing of the arm over the segment (> 0 away from the cam, "
        "< 0 back; 0 or left out for a dwell).", ("profile",), feeds=("lift",)),
    Key("blend", Number("", 0.0, 0.5), "constant_velocity only: fraction of the span in each end blend that ramps the velocity "
        "(0: plain constant velocity, whose velocity jumps at the ends: a knife follower only).", ("profile",)),
    Key("start", _CONDITIONS, "polynomial only: [s, v, a] (optionally j) at the segment's start: lift mm (oscillating: swing deg), "
        "velocity per degree of cam angle, acceleration per degree^2, jerk per degree^3 (converted to per rad).", ("profile",)),
    Key("end", _CONDITIONS, "polynomial only: [s, v, a] (optionally j) at the segment's end, in the units of start.", ("profile",)),
)

KEYS = (
    Key("segments", TableList(SEGMENT_KEYS, what="[[segments]] tables"),
        "The motion program: [[cams.<name>.segments]] tables in order from cam angle 0; spans add up to 360 deg and the "
        "follower returns to where it started.", ("profile",), default=REQUIRED),
)


def _per_rad(values: tuple[float, ...], oscillating: bool) -> tuple[float, ...]:
    """[s, v, a, j] per degree^k of cam angle (s in mm, or deg of swing) -> per rad^k (mm or rad)."""
    factor = math.pi / 180.0 if oscillating else 1.0  # deg of swing -> rad
    return tuple(v * factor * (180.0 / math.pi) ** k for k, v in enumerate(values))


def read_program(where: str, segments: tuple[dict[str, Any], ...], motion: str, complete: Any = None):
    """The :class:`~camgen.synthesis.laws.MotionProgram` of the ``[[segments]]`` tables;
    ``complete``: segments -> the segments that follow them (a half-turn program's second half)."""
    from camgen.synthesis import laws

    oscillating = motion == "oscillating"
    key, other = ("swing_deg", "lift_mm") if oscillating else ("lift_mm", "swing_deg")
    field, other_field = key.rsplit("_", 1)[0], other.rsplit("_", 1)[0]
    segment_keys = tuple(k for k in SEGMENT_KEYS if k.name != other)  # the segment's lift is this follower's key
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
        if law not in ("dwell", "polynomial") and not lift:
            raise ParameterError(f"{path}.{key}", shown, f"a non-zero {key} for a {law} segment (a segment without motion is a dwell)")
        for name, allowed in (("blend", "constant_velocity"), ("start", "polynomial"), ("end", "polynomial")):
            if name in seg and law != allowed:
                raise ParameterError(f"{path}.{name}", seg[name], f"no {name} for a {law} segment", f"only for {allowed}")
        if law == "polynomial" and ("start" not in seg or "end" not in seg):
            raise ParameterError(f"{path}.{'start' if 'start' not in seg else 'end'}", None,
                                 "[s, v, a] (optionally j) at both ends of a polynomial segment")
        start = _per_rad(seg["start"], oscillating) if "start" in seg else None
        end = _per_rad(seg["end"], oscillating) if "end" in seg else None
        built.append(renamed(path, segment_keys, lambda: laws.Segment(law, seg["span"], lift, seg.get("blend"), start, end, where=path)))
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
        item: dict[str, Any] = {"law": seg["law"], "span_deg": round(math.degrees(seg["span"]), 9)}
        if "lift" in seg:
            item["lift_mm"] = seg["lift"]
        if "swing" in seg:
            item["swing_deg"] = round(math.degrees(seg["swing"]), 9)
        for name in ("blend", "start", "end"):
            if name in seg:
                item[name] = list(seg[name]) if name != "blend" else seg[name]
        out.append(item)
    return out


def read_law(where: str, parsed: Mapping[str, Any], follower: "FollowerSpec", base_dir: Path | None = None) -> LawReading:
    """The motion program of a cam table for ``follower`` (a lift in mm for a translating one, a
    swing in rad for an oscillating one); a velocity jump is refused unless the follower is a knife."""
    program = read_program(where, parsed["segments"], follower.motion)
    _refuse_corners(where, program, parsed["segments"], follower)
    figures = {"segments": _segment_figures(parsed["segments"], follower.motion == "oscillating")}
    return LawReading(program, figures)


def _refuse_corners(where: str, program: Any, segments: tuple[dict[str, Any], ...], follower: "FollowerSpec") -> None:
    """A velocity jump is refused unless the follower is a knife (segment i of a completed
    half-turn program is the user's segment i modulo their number)."""
    if follower.edge:  # a knife edge rides the corner; a roller or a face cannot
        return
    n = len(segments)
    for join in program.joins():
        if join.continuity < 1:
            raise ParameterError(
                f"{where}.segments[{join.after % n}].law", segments[join.after % n]["law"],
                f"a law whose velocity at {math.degrees(join.angle):.6g} deg matches the end of segments[{join.before % n}]",
                f"the velocity jumps by {join.jumps[0]:.6g} {program.unit}/rad there: a {follower.kind} follower cannot follow the "
                "corner this makes in its path; blend it (constant_velocity with blend > 0) or use a knife follower")


def read_half_law(where: str, parsed: Mapping[str, Any], follower: "FollowerSpec", base_dir: Path | None = None) -> LawReading:
    """The motion program of a cam table whose segments cover the first half-turn (spans adding up
    to 180 deg), completed by ``s(theta + 180 deg) = C - s(theta)``
    (:func:`camgen.synthesis.breadth.mirror_segments`)."""
    from camgen.synthesis.breadth import mirror_segments

    segments = parsed["segments"]
    total = math.fsum(seg["span"] for seg in segments)
    if abs(total - math.pi) > 1e-9:
        raise ParameterError(f"{where}.segments", f"spans adding up to {math.degrees(total):.9g} deg", "spans adding up to 180 deg",
                             "half_turn = true: the segments give the first half-turn, the rule s(theta + 180 deg) = C - s(theta) "
                             "the second")
    program = read_program(where, segments, follower.motion, complete=mirror_segments)
    _refuse_corners(where, program, segments, follower)
    return LawReading(program, {"segments": _segment_figures(segments, follower.motion == "oscillating"), "half_turn": True})


MOTION = Motion(
    name="motion_law",
    summary="disk cam from a motion program (cycloidal, harmonic, modified trapezoid/sine/cycloidal, polynomials, ... per segment) "
            "for a translating or oscillating roller, flat face or knife, as the exact envelope",
    keys=KEYS,
    read_law=read_law,
    read_half_law=read_half_law,
)
