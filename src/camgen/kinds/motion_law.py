"""Cam kind ``motion_law``: a disk cam from a motion program (rise, dwell, return segments).

The profile is the exact envelope of the follower (:mod:`camgen.synthesis.motion_law`): a
translating roller (with offset) or a translating flat face, moving along +y.  Oscillating
followers for this kind are not implemented yet: ``follower_motion`` accepts only
"translating" and says so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camgen.errors import ParameterError, UndercutError
from camgen.kinds.base import (
    BuiltCam,
    CamKind,
    CamSpec,
    body_keys,
    check_keys,
    read_body,
    read_checks,
    rename_errors,
    source_key,
    with_cam,
)
from camgen.schema import REQUIRED, Angle, Choice, Count, Key, Length, Number, TableList

if TYPE_CHECKING:
    from camgen.synthesis.motion_law import MotionProgram

#: Largest number of samples per cam turn.
MAX_SAMPLES = 20000

SEGMENT_KEYS = (
    Key("law", Choice(("cycloidal", "harmonic", "poly345", "poly4567", "dwell")),
        "Motion law of the segment (dwell: no motion).", ("profile",), default=REQUIRED),
    Key("span_deg", Angle(0.0, 360.0, low_open=True), "Cam angle the segment spans.", ("profile",), default=REQUIRED),
    Key("lift_mm", Number("mm", -1e4, 1e4), "Follower travel over the segment: > 0 rise, < 0 return, 0 for a dwell.", ("profile",),
        default=0.0),
)

KEYS = (
    Key("base_radius_mm", Length(), "Smallest radius of the cam on the follower's side (roller: prime radius minus the roller).",
        ("profile",), default=REQUIRED),
    Key("segments", TableList(SEGMENT_KEYS, what="[[segments]] tables"),
        "The motion program: [[cams.<name>.segments]] tables in order from cam angle 0; spans add up to 360 deg, lifts to 0.",
        ("profile",), default=REQUIRED),
    Key("samples", Count(36, MAX_SAMPLES), "Cam angles per turn at which the envelope is computed.", ("profile",), default=720),
    source_key(),
) + body_keys() + (
    Key("follower", Choice(("roller", "flat")), "Translating roller or translating flat face, moving along +y.", ("profile",),
        default="roller"),
    Key("follower_motion", Choice(("translating",)),
        "Translating (oscillating followers of motion-law cams are not implemented yet).", ("profile",), default="translating"),
    Key("roller_radius_mm", Length(), "Roller radius.", ("profile", "pitch"), default=10.0, requires={"follower": ("roller",)}),
    Key("follower_offset_mm", Length(-1e5, 1e5, low_open=False),
        "Offset of the roller's axis from the cam axis: the axis is the line x = -offset.", ("profile",),
        requires={"follower": ("roller",)}),
    Key("face_half_length_mm", Length(), "Flat face: usable half-length of the face (checked against the contact's reach).",
        ("report",), requires={"follower": ("flat",)}),
) + check_keys()


@dataclass(frozen=True)
class MotionLawParams:
    """The motion program, base radius (mm), samples per turn and follower (mm, rad)."""

    program: "MotionProgram"
    segments: tuple[dict[str, Any], ...]
    base_radius: float
    samples: int
    follower: str
    roller_radius: float
    offset: float
    source: str | None = None


def read(where: str, name: str, parsed: dict[str, Any], base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a ``motion_law`` cam table."""
    from camgen.checks import Follower
    from camgen.synthesis import motion_law as ml

    segments = parsed["segments"]
    for i, seg in enumerate(segments):
        if (seg["law"] == "dwell") != (seg["lift"] == 0.0):
            what = "lift_mm = 0 (or leave it out) for a dwell" if seg["law"] == "dwell" else f"lift_mm != 0 for a {seg['law']} segment (a segment without lift is a dwell)"
            raise ParameterError(f"{where}.segments[{i}].lift_mm", seg["lift"], what)
    program = rename_errors(where, lambda: ml.MotionProgram([ml.MotionSegment(s["law"], s["span"], s["lift"]) for s in segments]), KEYS)
    checks = read_checks(parsed)
    kind = parsed["follower"]
    roller = parsed.get("roller_radius", 10.0) if kind == "roller" else 0.0
    offset = parsed.get("follower_offset", 0.0)
    if kind == "roller" and abs(offset) >= parsed["base_radius"] + roller:
        raise ParameterError(f"{where}.follower_offset_mm", offset, f"|offset| < base radius + roller radius = {parsed['base_radius'] + roller:g} mm")
    follower = rename_errors(where, lambda: Follower(kind, roller_radius=roller, offset=offset, direction=math.pi / 2,
                                                     face_half_length=parsed.get("face_half_length"),
                                                     pressure_angle_limit=checks.pressure_angle_limit), KEYS)
    params = MotionLawParams(program, segments, parsed["base_radius"], parsed["samples"], kind, roller, offset, parsed.get("source"))
    return CamSpec(name, "motion_law", params, read_body(where, parsed), checks, follower)


def build(spec: CamSpec, stages: frozenset[str]) -> BuiltCam:
    """The exact envelope of the follower for the motion program."""
    from camgen.synthesis import motion_law as ml

    p: MotionLawParams = spec.params
    try:
        if p.follower == "roller":
            profile, pitch = with_cam(f"cams.{spec.name}", lambda: ml.roller_cam(p.program, p.base_radius, p.roller_radius, p.offset, p.samples))
        else:
            profile, pitch = with_cam(f"cams.{spec.name}", lambda: ml.flat_cam(p.program, p.base_radius, p.samples)), None
    except UndercutError as exc:  # the follower cannot ride this cam: the report shows where and why
        figures = {"base_radius_mm": p.base_radius, "stroke_mm": p.program.stroke}
        return BuiltCam(spec.name, spec.kind, None, figures, spec.body, spec.follower, pitch=exc.pitch, undercut=exc)
    figures: dict[str, Any] = {
        "base_radius_mm": p.base_radius,
        "stroke_mm": p.program.stroke,
        "segments": [{"law": s["law"], "span_deg": math.degrees(s["span"]), "lift_mm": s["lift"]} for s in p.segments],
        "samples": p.samples,
        "area_mm2": profile.area,
        "perimeter_mm": profile.length,
        "bounds_mm": list(profile.bounds),
    }
    if p.source is not None:
        figures["source"] = p.source
    return BuiltCam(spec.name, spec.kind, profile, figures, spec.body, spec.follower, pitch=pitch)


KIND = CamKind(
    name="motion_law",
    summary="disk cam from a motion program (cycloidal, harmonic, 3-4-5, 4-5-6-7, dwell) for a translating roller or flat face",
    keys=KEYS,
    read=read,
    build=build,
)
