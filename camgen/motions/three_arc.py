"""Motion ``three_arc``: the constant-breadth three-center cam of paper 000 (Section 4.1, Table 1).

The profile is six exact arcs (:func:`camgen.synthesis.three_arc.three_arc_cam`); it drives a
flat-faced double (yoke) follower by default.  A single flat face or a roller may be analysed
instead: the follower keys change the checks in the report (and the DXF PITCH layer for a
roller), never the profile, which the three parameters fix.  The follower's motion is the
three-arc law the arcs give (their support function), so this motion is a design of its own:
it realises the ``constant_breadth`` form (:mod:`camgen.forms.constant_breadth`) by the paper's
construction.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from camgen.errors import ParameterError
from camgen.followers import sampled_follower_names
from camgen.keynames import scene_key
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
)
from camgen.kinds.dynamics import dynamics_keys, read_dynamics, three_arc_kinematics
from camgen.motions.base import Motion
from camgen.schema import REQUIRED, Angle, Choice, Key, Length

__all__ = ["KEYS", "MOTION", "ThreeArcParams", "build", "read"]


@dataclass(frozen=True)
class ThreeArcParams:
    """a = |OO'| = |OO''|, b = |O'O''|, c = base-circle radius (mm); ``source`` a note."""

    a: float
    b: float
    c: float
    source: str | None = None


_PARAMS = (
    Key("a_mm", Length(), "Distance of the off-axis centres O', O'' from the pivot O (paper 000, Fig. 5).", ("profile",), default=REQUIRED),
    Key("b_mm", Length(), "Distance between O' and O''; valid 0 < b < min(2a, a + c).", ("profile",), default=REQUIRED),
    Key("c_mm", Length(), "Base-circle radius: the dwell arc nearest the axis.", ("profile",), default=REQUIRED),
    source_key(),
)

#: The followers the sampled checks know (camgen.checks.Follower): all, the rollers, the faces.
_SAMPLED, _POINTS, _FACES = sampled_follower_names(), sampled_follower_names(("point",)), sampled_follower_names(("face", "faces"))

_FOLLOWER = (
    Key("follower", Choice(_SAMPLED),
        "Follower analysed by the checks: a yoke (two parallel flat faces, the constant-breadth drive), one flat face, or a roller "
        "(camgen.followers: every follower with faces, a face or a point contact with a radius).",
        ("report", "pitch"), default="yoke"),
    Key("follower_motion", Choice(("translating", "oscillating")),
        "Translating, or (roller only) oscillating about a pivot.", ("report",), default="translating"),
    Key("roller_radius_mm", Length(), "Roller radius.", ("report", "pitch"), requires={"follower": _POINTS}),
    Key("follower_offset_mm", Length(-1e5, 1e5, low_open=False),
        "Distance of a translating roller's axis from the cam axis (to the left of the motion direction).", ("report",),
        requires={"follower": _POINTS, "follower_motion": ("translating",)}),
    Key("follower_direction_deg", Angle(), "Direction in which the follower translates, in the fixed frame (counter-clockwise from +x).",
        ("report",), default=0.0, requires={"follower_motion": ("translating",)}),
    Key("pivot_x_mm", Length(-1e5, 1e5, low_open=False), "Oscillating roller: x of the arm's pivot (fixed frame, cam axis at 0), "
        "as for the disk cams.", ("report",), requires={"follower_motion": ("oscillating",)}),
    Key("pivot_y_mm", Length(-1e5, 1e5, low_open=False), "Oscillating roller: y of the arm's pivot.", ("report",),
        requires={"follower_motion": ("oscillating",)}),
    Key("arm_length_mm", Length(), "Oscillating roller: arm length from the pivot to the roller centre.", ("report",),
        requires={"follower_motion": ("oscillating",)}),
    Key("face_half_length_mm", Length(), "Flat face or yoke: usable half-length of the face (checked against the contact's reach).",
        ("report",), requires={"follower": _FACES}),
)

KEYS = _PARAMS + body_keys() + _FOLLOWER + check_keys() + dynamics_keys(oscillating=False)  # yoke and flat face: translating


def read(where: str, name: str, parsed: dict[str, Any], base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a ``three_arc`` cam table (fields in mm and rad)."""
    from camgen.checks import Follower
    from camgen.synthesis.three_arc import validate_three_arc

    a, b, c = rename_errors(where, lambda: validate_three_arc(parsed["a"], parsed["b"], parsed["c"]), KEYS)
    checks = read_checks(parsed)
    if parsed["follower_motion"] == "oscillating":  # the pivot placed as for every follower: pivot_x_mm, pivot_y_mm
        for key in ("pivot_x", "pivot_y", "arm_length"):
            if key not in parsed:
                raise ParameterError(f"{where}.{scene_key(KEYS, key)}", None, "a length in mm",
                                     "required for an oscillating roller follower")
        if parsed["pivot_x"] == 0.0 and parsed["pivot_y"] == 0.0:
            raise ParameterError(f"{where}.pivot_x_mm", 0.0, "a pivot away from the cam axis (pivot_x_mm, pivot_y_mm not both 0)",
                                 "the arm swings about the pivot, which cannot be the cam's rotation axis")
    follower = rename_errors(where, lambda: Follower(
        kind=parsed["follower"],
        motion=parsed["follower_motion"],
        roller_radius=parsed.get("roller_radius", 0.0),
        offset=parsed.get("follower_offset", 0.0),
        direction=parsed["follower_direction"],
        pivot_distance=math.hypot(parsed.get("pivot_x", 0.0), parsed.get("pivot_y", 0.0)),
        pivot_angle=math.atan2(parsed.get("pivot_y", 0.0), parsed.get("pivot_x", 0.0)),
        arm_length=parsed.get("arm_length", 0.0),
        face_half_length=parsed.get("face_half_length"),
        pressure_angle_limit=checks.pressure_angle_limit,
    ), KEYS)
    body = read_body(where, parsed)
    # a roller's kinematics on this cam are sampled from the contour, not closed-form: no dynamics for it
    dynamics = read_dynamics(where, parsed, motion=follower.motion, follower=follower.kind, rpm=checks.rpm, thickness=body.thickness,
                             base_dir=base_dir, unavailable=(
                                 "the follower dynamics of a three_arc cam are computed for its yoke or a flat face (their motion "
                                 "follows exactly from the arcs' support function); a roller's is not available here"
                                 if follower.contact == "point" else None))
    return CamSpec(name, "three_arc", ThreeArcParams(a, b, c, parsed.get("source")), body, checks, follower, dynamics,
                   form="constant_breadth")


def build(spec: CamSpec, stages: frozenset[str]) -> BuiltCam:
    """The six-arc cam and its figures (exact; no analysis stage needed)."""
    from camgen import checks
    from camgen.contour import Arc
    from camgen.synthesis import three_arc

    p: ThreeArcParams = spec.params
    contour = three_arc.three_arc_cam(p.a, p.b, p.c)
    width = three_arc.breadth(p.a, p.b, p.c)
    error, _ = checks.breadth_error(contour, width)
    figures: dict[str, Any] = {
        "a_mm": p.a,
        "b_mm": p.b,
        "c_mm": p.c,
        "theta_x_deg": math.degrees(three_arc.theta_x(p.a, p.b)),
        "breadth_mm": width,
        "breadth_error_mm": error,
        "base_radius_mm": p.c,
        "max_radius_mm": 2.0 * p.a + p.c - p.b,
        "area_mm2": contour.area,
        "perimeter_mm": contour.length,
        "bounds_mm": list(contour.bounds),
        "arc_radii_mm": [seg.radius for seg in contour.segments if isinstance(seg, Arc)],  # six arcs, nothing else
    }
    if p.source is not None:
        figures["source"] = p.source
    return BuiltCam(spec.name, spec.kind, contour, figures, spec.body, spec.follower, breadth=width)


_SUMMARY = "constant-breadth three-center cam of six exact arcs for a yoke follower (paper 000)"

MOTION = Motion(
    name="three_arc",
    summary=_SUMMARY,
    realisations={"constant_breadth": CamKind(name="three_arc", summary=_SUMMARY, keys=KEYS, read=read, build=build,
                                              follower_dynamics=three_arc_kinematics)},
    default_form="constant_breadth",
)
