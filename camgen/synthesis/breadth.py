"""Constant-breadth and constant-diameter cams: the half-turn rule, its constant and its check.

A constant-breadth cam turns between the two parallel faces of a yoke a breadth ``B`` apart; a
constant-diameter cam between two rollers of radius ``r`` whose centres are ``D`` apart on one
translating follower.  Both followers translate along ``+y`` through the cam axis (the
conventions of :mod:`camgen.synthesis.followers`, offset 0); ``s(theta)`` is the lift (mm).

Derivation of the rule ``s(theta + pi) = C - s(theta)``
-------------------------------------------------------
*Yoke.*  The upper face is the line ``y = Rb + s(theta)``; it touches the cam where the support
function of the cam is ``h(psi) = Rb + s(theta)``, ``psi = pi/2 - sigma theta`` the face's
outward normal seen in the cam frame.  The lower face is the line ``y = Rb + s(theta) - B``
with outward normal ``-y``, i.e. ``psi + pi`` in the cam frame: it touches the cam exactly when
``h(psi + pi) = B - Rb - s(theta)``.  At cam angle ``theta + pi`` the upper face's normal in the
cam frame is ``psi - sigma pi = psi + pi`` (mod 2 pi), so ``h(psi + pi) = Rb + s(theta + pi)``.
The upper face touches at every cam angle (the profile is its envelope); the lower one does too
exactly when ``Rb + s(theta + pi) = B - Rb - s(theta)``:

    ``s(theta + pi) = C - s(theta)``,  ``C = B - 2 Rb``.

Then ``h(psi) + h(psi + pi) = B`` for every direction: the breadth is constant.

*Two rollers.*  The roller centres are ``(0, Rp + s)`` and ``(0, Rp + s - D)`` with the prime
radius ``Rp = Rb + r``; in the cam frame the lower one is ``R(-sigma theta) (0, Rp + s - D) =
R(-sigma (theta + pi)) (0, D - Rp - s)``, which is the upper centre's position at cam angle
``theta + pi`` (the pitch curve) exactly when ``Rp + s(theta + pi) = D - Rp - s(theta)``:

    ``s(theta + pi) = C - s(theta)``,  ``C = D - 2 Rp = D - 2 (Rb + r)``.

Both rollers then ride the one pitch curve, whose chords through the axis are all ``D`` long
(constant diameter), and touch the one profile, its inner offset by ``r``.  An offset roller
line would need ``x = e = -e``: the rollers' line passes through the axis.

At ``theta = 0`` the rule gives ``C = s(0) + s(pi)``: the law fixes ``C``, so ``B`` (or ``D``)
and ``Rb`` fix each other.  Differentiating, ``s^(k)(theta + pi) = -s^(k)(theta)``: a program
over the first half-turn completes the turn (:func:`mirror_segments`, :func:`mirror_rows`) if
its velocity at 180 deg is minus its velocity at 0 (else the follower's velocity jumps there).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

if TYPE_CHECKING:
    from camgen.synthesis.followers import Displacement
    from camgen.synthesis.laws import Segment

__all__ = ["RULE_STEP", "RULE_TOL", "RuleBreak", "mirror_rows", "mirror_segments", "rule_break", "rule_constant"]

#: Largest |s(theta) + s(theta + pi) - C| allowed, relative to max(1, stroke) (mm or rad): the
#: rule holds to rounding for a law that keeps it (a mirrored program, a mirrored table).
RULE_TOL = 1e-9
#: Spacing (rad) of the grid over the first half-turn on which the rule is checked (0.05 deg,
#: the check grid's), the law's breaks and their partners half a turn away added.
RULE_STEP = math.radians(0.05)


def rule_constant(law: "Displacement") -> float:
    """``C = s(0) + s(pi)`` (mm or rad): the constant of the rule (module docstring)."""
    s = law(np.array([0.0, math.pi]))[0]
    return float(s[0] + s[1])


@dataclass(frozen=True)
class RuleBreak:
    """Where a whole-turn law breaks the rule: the cam angle ``theta`` (rad, in ``[pi, 2 pi)``) of
    the second half-turn, ``s(theta)`` there, the value ``C - s(theta - pi)`` the rule asks and the
    rule's constant ``C`` (mm or rad)."""

    theta: float
    value: float
    required: float
    constant: float


def rule_break(law: "Displacement", stroke: float, tol: float = RULE_TOL, step: float = RULE_STEP) -> RuleBreak | None:
    """The first cam angle of the second half-turn where ``law`` breaks ``s(theta) = C - s(theta -
    pi)`` by more than ``tol * max(1, stroke)`` (position, and velocity against ``tol * max(1, peak
    velocity)``), or None: checked on a grid over the first half-turn of spacing ``step`` with the
    law's breaks (and their partners) added."""
    n = int(math.ceil(math.pi / step))
    brk = np.mod(np.asarray(law.breaks, dtype=float), math.pi)
    first = np.unique(np.concatenate([np.arange(n) * (math.pi / n), brk]))
    s0, v0, _, _ = law(first)
    s1, v1, _, _ = law(first + math.pi)
    constant = rule_constant(law)
    bad_s = np.abs(s0 + s1 - constant) > tol * max(1.0, stroke)
    scale_v = max(1.0, float(np.max(np.abs(v0))), float(np.max(np.abs(v1))))
    bad_v = np.abs(v0 + v1) > tol * scale_v
    bad = bad_s | bad_v
    if not bad.any():
        return None
    i = int(np.argmax(bad))
    return RuleBreak(float(first[i] + math.pi), float(s1[i]), float(constant - s0[i]), constant)


def mirror_segments(segments: Sequence["Segment"]) -> list["Segment"]:
    """The segments of the second half-turn completing ``segments`` (the first half-turn) by
    ``s(theta + pi) = C - s(theta)``, ``C = s(0) + s(pi)``: each segment's shape with its lift
    negated (the same shape, not the time-reversed one a return takes, so that asymmetric laws
    such as double_harmonic keep the rule exactly); a polynomial's end conditions mirrored
    (``C - s``, ``-v``, ``-a``, ``-j``).  Each keeps its ``where`` (a message names the user's
    segment)."""
    from camgen.synthesis.laws import Segment

    level = 0.0
    for seg in segments:
        if seg.start_level is not None:
            level = seg.start_level
        assert seg.lift is not None  # Segment.__post_init__ sets every segment's lift
        level += seg.lift
    constant = (segments[0].start_level or 0.0) + level  # s(0) + s(pi)
    out = []
    for seg in segments:
        if seg.start_level is not None:  # a polynomial: absolute end conditions, per rad^k
            start: Any = (constant - seg.start[0],) + tuple(-x for x in seg.start[1:])  # type: ignore[index]
            end: Any = (constant - seg.end[0],) + tuple(-x for x in seg.end[1:])  # type: ignore[index]
            out.append(Segment("polynomial", seg.span, start=start, end=end, where=seg.where))
            continue
        lift = seg.lift
        assert lift is not None  # Segment.__post_init__ sets every segment's lift
        if lift == 0.0:
            out.append(Segment("dwell", seg.span, where=seg.where))
        else:
            # Segment time-reverses the shape of a negative lift: hand it the reversed shape then
            # (reversal is an involution), so the mirrored segment is -lift times the same shape
            shape = seg.shape.reversed() if lift > 0 else seg.shape
            out.append(Segment(shape, seg.span, -lift, where=seg.where))
    return out


def mirror_rows(angles_deg: np.ndarray, lifts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A lift table over the first half-turn (rows from 0 to 180 deg, both included) completed by
    the rule: the rows ``(a + 180, C - s)`` for the rows before 180 deg, ``C = s(0) + s(180)``.
    The periodic spline through the whole table keeps the rule exactly: its knots are shifted into
    themselves by half a turn and the mirrored spline interpolates the same rows (uniqueness)."""
    constant = float(lifts[0] + lifts[-1])
    first = angles_deg < 180.0
    return np.concatenate([angles_deg, angles_deg[first][1:] + 180.0]), np.concatenate([lifts, constant - lifts[first][1:]])
