"""The sizing answers a plate-cam scene asks for (issue 26, item 4): the ``sizing_ranges`` key.

For each quantity it names (``roller_radius``, ``arm_length``, ``pivot_distance``), every
interval of values at which the cam meets all its design limits, the other values as the scene
gives them (:func:`camgen.synthesis.sizing.roller_radius_intervals`,
:func:`~camgen.synthesis.sizing.arm_length_intervals`,
:func:`~camgen.synthesis.sizing.pivot_distance_intervals`: the limits of the scene's checks,
with the Hertz stress when the dynamics keys give an allowable stress).  Each quoted end has
been tried and passes; the value :data:`BEYOND` mm outside it is tried too and what it breaks
is quoted as the end's bound (a check's name), so every end is verified by use.  An end where
no follower exists beyond (the roller radius 0, the arm no longer reaching the prime circle) is
bounded by ``"geometry"``; the top of a stated search cap that still passes (a translating
roller searched up to the base radius) by ``"range_searched"``.
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Callable, Mapping

from camgen.errors import GeometryError, ParameterError
from camgen.schema import ChoiceList, Key

if TYPE_CHECKING:
    from camgen.synthesis.followers import FollowerSpec
    from camgen.synthesis.sizing import DesignLimits, DesignMeasures, Intervals

__all__ = ["BEYOND", "QUANTITIES", "ranges_key", "read_sizing_ranges", "sizing_range_figures"]

#: The quantities the key may name.
QUANTITIES = ("roller_radius", "arm_length", "pivot_distance")
#: How far outside each quoted end the design is tried and must fail, mm.
BEYOND = 1e-3
#: Most BEYOND steps an end is moved outwards when the value beyond it still passes (a run the
#: scan's bisection ended early); bounds the work by construction.
_MAX_EXTEND = 1000


def ranges_key() -> tuple[Key, ...]:
    """The plate form's ``sizing_ranges`` key."""
    return (
        Key("sizing_ranges", ChoiceList(QUANTITIES),
            "Quantities whose passing values the report quotes: every interval of roller_radius (a roller follower), arm_length "
            "or pivot_distance (the pivot moved along its own direction from the cam axis; an oscillating roller or knife) at which "
            "the cam meets all its design limits (pressure angle(s), curvature, Norton's factor, undercut, the tool, the Hertz "
            "stress with allowable_contact_stress_mpa), the other values as given; each end tried and passing, 0.001 mm beyond it "
            "tried and failing, with what bounds it (report.json figures.sizing_ranges).", ("report",), example=["roller_radius"]),
    )


def read_sizing_ranges(where: str, parsed: Mapping[str, Any], follower: "FollowerSpec") -> tuple[str, ...]:
    """The quantities ``sizing_ranges`` names (``()`` when not given); a quantity the follower
    does not have is refused, naming the key."""
    names: tuple[str, ...] = tuple(parsed.get("sizing_ranges") or ())
    allowed = tuple(n for n in QUANTITIES if (n == "roller_radius" and follower.has_radius)
                    or (n != "roller_radius" and follower.motion == "oscillating" and follower.contact == "point"))
    for i, name in enumerate(names):
        if name not in allowed:
            need = "a roller follower" if name == "roller_radius" else "an oscillating roller or knife"
            valid = ", ".join(f'"{n}"' for n in allowed) if allowed else "none (leave sizing_ranges out)"
            raise ParameterError(f"{where}.sizing_ranges[{i}]", name, f"for a {follower.motion} {follower.kind} follower: {valid}",
                                 f"{name} needs {need}")
    return names


def _bounds(spec: "FollowerSpec | None", law: Any, limits: "DesignLimits", measure: Callable[..., "DesignMeasures"]) -> list[str]:
    """The checks ``spec`` breaks (empty: it passes); ``["geometry"]`` when there is no follower."""
    if spec is None:
        return ["geometry"]
    m = measure(spec, law, limits.check_step, stress=limits.contact_stress)
    if not m.violations(limits):
        return []
    out = ["undercut"] if m.failures or m.min_convex_radius < limits.min_convex_radius else []
    if limits.max_pressure_angle_return is not None:
        out += ["pressure_angle"] if m.max_pressure_angle_rise > limits.max_pressure_angle else []
        out += ["pressure_angle_return"] if m.max_pressure_angle_return > limits.max_pressure_angle_return else []
    elif m.max_pressure_angle > limits.max_pressure_angle:
        out.append("pressure_angle")
    least_pitch = limits.min_pitch_radius_factor * m.roller_radius
    if least_pitch > 0 and not m.min_pitch_radius >= least_pitch:
        out.append("pitch_curvature")
    if limits.contact_stress is not None and m.max_contact_stress is not None and not m.max_contact_stress <= limits.contact_stress.allowable:
        out.append("hertz_stress")
    if m.min_concave_radius < limits.min_concave_radius:
        out.append("min_concave_radius")
    return out or ["design_limits"]


def _verified(name: str, answer: "Intervals", make: Callable[[float], "FollowerSpec | None"], law: Any, limits: "DesignLimits",
              cap: bool) -> list[dict[str, Any]]:
    """Each run of ``answer`` with its ends verified: the end passes, the value BEYOND outside
    fails (an end whose beyond still passes is moved out by BEYOND steps), and what it breaks."""
    from camgen.synthesis.sizing import measure

    def at(value: float) -> "FollowerSpec | None":
        try:
            return make(value)
        except (ParameterError, GeometryError):
            return None

    def broken(value: float) -> list[str]:
        return _bounds(at(value), law, limits, measure)

    runs = []
    lo, hi = answer.searched
    for low, high in answer.runs:
        if broken(low) or broken(high):  # the sizing search tried both: a quoted end always passes
            raise AssertionError(f"{name}: a quoted end ({low}, {high}) fails when used")
        ends: dict[str, Any] = {}
        for side, value, step in (("low", low, -BEYOND), ("high", high, BEYOND)):
            if side == "high" and cap and value >= hi:
                ends.update({"high_mm": value, "high_bound": "range_searched"})
                continue
            why = broken(round(value + step, 9))
            for _ in range(_MAX_EXTEND):
                if why:
                    break
                value = round(value + step, 9)
                why = broken(round(value + step, 9))
            ends.update({f"{side}_mm": value, f"{side}_bound": " and ".join(why) if why else "not found"})
        runs.append(ends)
    return runs


def _maker(follower: "FollowerSpec", name: str) -> Callable[[float], "FollowerSpec | None"]:
    """``follower`` with the quantity ``name`` set to a value (mm); a pivot moved along its own
    direction from the cam axis to that distance."""
    if name == "roller_radius":
        return lambda r: replace(follower, roller_radius=r)
    if name == "arm_length":
        return lambda arm: replace(follower, arm_length=arm)
    px, py = follower.pivot_xy
    d0 = math.hypot(px, py)
    return lambda d: replace(follower, pivot=(px * d / d0, py * d / d0))


def sizing_range_figures(names: tuple[str, ...], follower: "FollowerSpec", law: Any, limits: "DesignLimits") -> dict[str, Any]:
    """report.json's ``figures.sizing_ranges`` for the quantities ``names`` of ``follower`` on
    ``law`` against ``limits``: per quantity the value the scene gives, the open range searched
    (mm) and every passing interval, each end (mm) with what bounds it; a pivot's ends also as
    the pivot's (x, y) (mm) along its direction from the cam axis."""
    from camgen.synthesis import sizing as sz

    out: dict[str, Any] = {}
    for name in names:
        if name == "roller_radius":
            answer = sz.roller_radius_intervals(follower, law, limits)
            given, cap = follower.roller_radius, follower.motion == "translating"
        elif name == "arm_length":
            answer = sz.arm_length_intervals(follower, law, limits)
            given, cap = follower.arm_length, False
        else:
            answer = sz.pivot_distance_intervals(follower, law, limits)
            given, cap = math.hypot(*follower.pivot_xy), False
        runs = _verified(name, answer, _maker(follower, name), law, limits, cap)
        entry: dict[str, Any] = {"scene_mm": given, "searched_mm": [answer.searched[0], answer.searched[1]], "intervals": runs}
        if name == "pivot_distance":
            px, py = follower.pivot_xy
            entry["direction_deg"] = math.degrees(math.atan2(py, px))
            for run in runs:
                for side in ("low", "high"):
                    d = run[f"{side}_mm"]
                    run[f"{side}_pivot_mm"] = [px * d / given, py * d / given]
        out[name] = entry
    return out
