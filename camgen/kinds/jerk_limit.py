"""The jerk limit (issue 26 item 5): the follower's largest jerk at the cam speed against a limit.

Two keys, one per follower motion, each in the unit of that motion's jerk at speed (the unit
``figures.motion_at_rpm`` states): ``jerk_limit_m_per_s3`` for a translating follower (m/s^3),
``jerk_limit_rad_per_s3`` for an oscillating arm (rad/s^3); the other motion's key is refused
naming the right one.  The jerk at speed needs the cam's speed: the check uses the cam's
``rpm`` (the key every kind with these keys has; the dynamics run at the same speed) and the
keys are refused without it.

The check (``jerk_limit``) compares the largest |jerk| at ``rpm``, ``max|s'''| w^3`` (``w = 2 pi
rpm / 60``; the closed-form peak when the kind knows it, :attr:`camgen.checks.Motion.peaks`;
m/s^3 from mm/rad^3 by 1e-3), with the limit; where the acceleration jumps (a join of two laws
whose accelerations differ, Norton's infinite ``Cj``) the jerk is an impulse, unbounded: the
check fails there naming the cam angles.  A failed check fails the run (exit 1) like every
design check; it withholds no file.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Mapping

from camgen.errors import ParameterError
from camgen.schema import Key, Number

if TYPE_CHECKING:
    from camgen.checks import CheckResult, Motion

__all__ = ["JERK_KEYS", "jerk_limit_check", "jerk_limit_keys", "read_jerk_limit"]

#: The keys by follower motion: (scene name, attribute, unit of the jerk at speed).
JERK_KEYS = {"translating": ("jerk_limit_m_per_s3", "jerk_limit", "m/s^3"),
             "oscillating": ("jerk_limit_rad_per_s3", "jerk_limit_angular", "rad/s^3")}


def jerk_limit_keys(oscillating: bool = True) -> tuple[Key, ...]:
    """The jerk-limit keys (module notes); ``oscillating`` False: the translating follower's only
    (a kind whose follower only translates)."""
    keys = (
        Key("jerk_limit_m_per_s3", Number("m/s^3", 0.0, 1e15, low_open=True), "Translating follower: the largest follower jerk "
            "allowed at the cam speed rpm (which it needs); the jerk_limit check fails above it, and where the acceleration jumps "
            "(an unbounded jerk).", ("report",), example=5000.0, attr="jerk_limit"),
        Key("jerk_limit_rad_per_s3", Number("rad/s^3", 0.0, 1e15, low_open=True), "Oscillating follower: the largest angular jerk "
            "of the arm allowed at the cam speed rpm (which it needs); the jerk_limit check fails above it, and where the "
            "acceleration jumps (an unbounded jerk).", ("report",), example=50000.0, attr="jerk_limit_angular",
            requires={"follower_motion": ("oscillating",)}),
    )
    return keys if oscillating else keys[:1]


def read_jerk_limit(where: str, parsed: Mapping[str, Any]) -> None:
    """Refuse a jerk limit of the other follower motion's unit, or one without ``rpm`` (a cam
    table read by :func:`camgen.schema.parse_table`; ``where``: its scene path)."""
    given: frozenset[str] = getattr(parsed, "given", frozenset())
    motion = parsed.get("follower_motion", "translating")  # a kind without the key moves its follower along a line
    for other, (name, attr, unit) in JERK_KEYS.items():
        if name not in given:
            continue
        if other != motion:
            right = JERK_KEYS[motion][0]
            raise ParameterError(f"{where}.{name}", parsed[attr], f"{right} for a {motion} follower",
                                 f"the jerk of a {motion} follower is in {JERK_KEYS[motion][2]}, not {unit}")
        if parsed.get("rpm") is None:
            raise ParameterError(f"{where}.rpm", None, "a cam speed in rev/min (> 0)",
                                 f"the jerk limit ({name} given) holds the jerk at the cam speed")


def jerk_limit_check(limit: float | None, rpm: float | None, motion: "Motion | None") -> "list[CheckResult]":
    """The ``jerk_limit`` check of a cam (a list of one; empty without a ``limit``), at ``rpm``
    (the cam's check settings: :attr:`camgen.kinds.base.CheckSettings.jerk_limit`)."""
    from camgen.checks import CheckResult, limited, where_degrees

    if limit is None:
        return []
    assert rpm is not None  # read_jerk_limit refuses a limit without rpm
    if motion is None:
        return [CheckResult("jerk_limit", "not computed", limit, "<=", "", False, [],
                            "this cam has no follower motion to hold to the jerk limit")]
    translating = motion.unit == "mm"
    unit = "m/s^3" if translating else f"{motion.unit}/s^3"
    omega = 2.0 * math.pi * rpm / 60.0
    scale = omega**3 * (1e-3 if translating else 1.0)
    if motion.jerk_impulses_deg:
        at = [round(a, 6) for a in motion.jerk_impulses_deg]
        return [CheckResult("jerk_limit", "unbounded", limit, "<=", unit, False, at,
                            f"the acceleration jumps at {len(at)} cam angle(s): the jerk is an impulse there (a law whose "
                            "acceleration does not match its neighbour's, Norton's infinite Cj); use laws that join with equal "
                            "acceleration")]
    import numpy as np

    peak = motion.peak_values()[2] * scale
    where = where_degrees(float(motion.cam_angle[int(np.argmax(np.abs(motion.jerk)))]))
    note = f"largest follower jerk at {rpm:g} rpm"
    return [limited("jerk_limit", peak, "<=", limit, unit, where, note if peak <= limit else note + ": lower the speed, "
                    "lengthen the segments or use a law of smaller Cj")]
