"""Measured lift data (issue 26 item 3): the undercut, contact-stress and jump checks of a
smoothed lift table say how far the readings' noise would have moved them.

The rule (README, "Measured lift data"): each check's value on the smoothed curve (what camgen
builds) is compared with the same check on the interpolation of the raw readings
(``smoothing_mm = 0``), on the same cam-angle grid; the note states the unsmoothed value and
its relative difference, and says the readings' noise, not the design, drives the value when the
two differ by more than :data:`NOISE_SHARE` or one passes where the other fails.  An unsmoothed
table whose undercut check fails is fitted within half its readings' last digit (the readings'
resolution): when that fit passes, the note says the noise drives the failure and names the
``smoothing_mm`` that makes the cam (tests/test_smoothing.py uses it).  Passing unsmoothed tables
get no note (nothing is computed: their outputs and run time are unchanged).
"""
from __future__ import annotations

import math
from dataclasses import replace
from types import SimpleNamespace
from typing import TYPE_CHECKING, Any, Callable, Sequence

if TYPE_CHECKING:
    from camgen.checks import CheckResult

__all__ = ["NOISE_SHARE", "RESOLUTION_DIGITS", "dynamics_noise_notes", "noise_note", "readings_resolution", "undercut_noise_note"]

#: Relative difference between a check's value on the smoothed curve and on the raw readings'
#: interpolation above which the readings' noise, not the design, is said to drive it.
NOISE_SHARE = 0.01
#: Finest step (10^-k mm) a table's readings are taken to be given to (finer: no resolution stated).
RESOLUTION_DIGITS = 6


def _raw_cam(cam: Any) -> Any:
    """A stand-in of ``cam`` (a disk cam of a smoothed lift table) riding the raw readings'
    interpolation on the same check grid, for the kinds' check functions; None for other cams."""
    from camgen.synthesis.followers import kinematics
    from camgen.synthesis.smoothing import SmoothedLiftTable

    law = getattr(cam, "law", None)
    if not isinstance(law, SmoothedLiftTable):
        return None
    f = cam.spec_follower
    data = kinematics(f, law.raw, cam.envelope.data.theta)
    return SimpleNamespace(spec_follower=f, law=law.raw, envelope=SimpleNamespace(data=data), contour=cam.contour, planar=True)


def noise_note(smoothed: "CheckResult", raw: "CheckResult", tolerance: float, what: str = "") -> "CheckResult":
    """``smoothed`` with a sentence comparing it with ``raw`` (the same check on the raw
    readings' interpolation) by the module's rule."""
    a, b = smoothed.value, raw.value
    head = f"; smoothing_mm = {tolerance:g}: on the raw readings' interpolation {what or 'the value'} would be "
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and math.isfinite(a) and math.isfinite(b) and a != 0:
        share = (b - a) / abs(a)
        verdict = abs(share) > NOISE_SHARE or smoothed.passed != raw.passed
        text = head + f"{b:.6g} {smoothed.unit} ({share:+.2%})".replace("  ", " ")
    else:
        verdict = smoothed.passed != raw.passed or a != b
        text = head + f"{b}"
    if raw.passed is not None and raw.passed != smoothed.passed:
        text += f" and the check would {'pass' if raw.passed else 'fail'}"
    text += (": the readings' noise, not the design, drives the difference" if verdict
             else f": within {NOISE_SHARE:.0%}, the design, not the readings' noise, sets it")
    return replace(smoothed, note=smoothed.note + text)


def readings_resolution(lifts: Any, finest: int = RESOLUTION_DIGITS) -> float | None:
    """The step the readings are given to (mm): the largest 10^-k, k = 0 .. ``finest``, of which
    every reading is a whole multiple (within 1e-6 of the step); None: finer than 10^-finest."""
    import numpy as np

    values = np.asarray(lifts, dtype=float)
    for k in range(finest + 1):
        step = 10.0**-k
        q = values / step
        if np.all(np.abs(q - np.round(q)) <= 1e-6):
            return step
    return None


def undercut_noise_note(cam: Any, check: "CheckResult", measure: "Callable[[Any], CheckResult]") -> "CheckResult":
    """The undercut ``check`` of ``cam`` with the noise note (a smoothed lift table: against the
    raw readings; an unsmoothed one whose undercut check fails: against the fit within half the
    readings' last digit, ``smoothing_mm`` = that, which the note suggests when it passes; else as
    given); ``measure``: the kind's undercut check of a cam."""
    raw = _raw_cam(cam)
    if raw is not None:
        return noise_note(check, measure(raw), cam.law.fit.tolerance, "the smallest radius")
    return _failed_table_note(cam, check, measure)


def _failed_table_note(cam: Any, check: "CheckResult", measure: "Callable[[Any], CheckResult]") -> "CheckResult":
    from camgen.synthesis.followers import kinematics
    from camgen.synthesis.lift_table import LiftTable
    from camgen.synthesis.smoothing import SmoothedLiftTable

    law = getattr(cam, "law", None)
    if type(law) is not LiftTable or law.unit != "mm" or not check.failed:
        return check
    step = readings_resolution(law.lifts)
    if step is None:
        return check
    tolerance = 0.5 * step
    smooth = SmoothedLiftTable(law, tolerance)
    f = cam.spec_follower
    data = kinematics(f, smooth, cam.envelope.data.theta)
    fitted = measure(SimpleNamespace(spec_follower=f, law=smooth, envelope=SimpleNamespace(data=data)))
    head = (f"; the readings are given to {step:g} mm: the smoothest spline within half that, {tolerance:g} mm, of every reading "
            f"has {fitted.value:.6g} {check.unit}".replace("  ", " "))
    if fitted.passed:
        return replace(check, note=check.note + head + f" and passes: the readings' noise, not the design, drives this failure "
                       f"(smoothing_mm = {tolerance:g} makes the cam)")
    return replace(check, note=check.note + head + " and fails too: the design, not the readings' noise, drives it")


def dynamics_noise_notes(cam: Any, result: Any, checks: "Sequence[CheckResult]",
                         recheck: "Callable[[Any], tuple[Any, Sequence[CheckResult]]] | None") -> "list[CheckResult]":
    """The dynamics ``checks`` of ``cam`` (``result``: its :class:`camgen.dynamics.DynamicsResult`)
    with the noise notes on ``hertz_stress`` and ``jump`` (the jump speed too) for a smoothed lift
    table; ``recheck(cam)``: the dynamics result and checks of a cam riding the raw readings (a
    plate cam's; None: a form whose dynamics need more than the follower's kinematics, a groove:
    the notes say the comparison is not made)."""
    raw = _raw_cam(cam)
    if raw is None:
        return list(checks)
    if recheck is None:
        tolerance = cam.law.fit.tolerance
        return [replace(c, note=c.note + f"; smoothing_mm = {tolerance:g}: not compared with the raw readings' interpolation for "
                        "this cam form (plate cams only)") if c.name in ("hertz_stress", "jump", "contact_force") else c for c in checks]
    raw_result, raw_checks = recheck(raw)
    by_name = {c.name: c for c in raw_checks}
    tolerance = cam.law.fit.tolerance
    out = []
    for check in checks:
        other = by_name.get(check.name)
        if check.name == "hertz_stress" and other is not None:
            check = noise_note(check, other, tolerance, "the largest contact stress")
        elif check.name == "jump" and other is not None:
            check = noise_note(check, other, tolerance, "the smallest contact force")
            jump, raw_jump = result.jump_rpm, raw_result.jump_rpm
            if math.isfinite(jump) and math.isfinite(raw_jump) and jump > 0:
                share = (raw_jump - jump) / jump
                check = replace(check, note=check.note + f"; the jump speed would be {raw_jump:.6g} rpm ({share:+.2%}): " + (
                    "the readings' noise, not the design, drives the difference" if abs(share) > NOISE_SHARE
                    else f"within {NOISE_SHARE:.0%}, the design sets it"))
        out.append(check)
    return out
