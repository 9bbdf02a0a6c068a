"""Design margins of a plate cam (issue 26, item 4): separate pressure-angle limits for the rise
and the return, Norton's least pitch-curve radius as a multiple of the roller radius, a
clearance on a flat face, and the Hertz stress as a sizing limit.

The rule for the return: the cam angles where the law's ``s' < 0`` (the follower comes back;
an oscillating arm's swing falls); the rise limit holds everywhere else (rise and dwells).
The keys (:func:`margin_keys`) belong to the plate form; a scene without them gets exactly
the checks it had.  The limits they set are checked (:func:`with_margins`), used by sizing and
by the base-radius hint (:func:`design_limits`), whose notes name them (:func:`margin_text`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.schema import Angle, Key, Length, Number

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.kinds.base import BuiltCam, CamSpec
    from camgen.synthesis.sizing import DesignLimits

__all__ = ["Margins", "design_limits", "margin_keys", "margin_text", "read_margins", "with_margins"]

#: Smallest pressure-angle limit a scene may set for the rise or the return, deg (as pressure_angle_limit_deg).
_MIN_LIMIT_DEG = 0.01


def _roller_names() -> tuple[str, ...]:
    from camgen.followers import follower_names, get_follower

    return tuple(n for n in follower_names(("point",)) if get_follower(n).has_radius)


def margin_keys() -> tuple[Key, ...]:
    """The plate form's margin keys."""
    from camgen.followers import follower_names

    return (
        Key("pressure_angle_limit_rise_deg", Angle(_MIN_LIMIT_DEG, 90.0, high_open=True),
            "Largest pressure angle on the rise and the dwells (cam angles where the law's s' >= 0); default "
            "pressure_angle_limit_deg. Given (or pressure_angle_limit_return_deg given), the pressure_angle check holds the rise "
            "to it and a pressure_angle_return check the return; sizing and the base-radius hint meet both.", ("report",),
            example=25.0),
        Key("pressure_angle_limit_return_deg", Angle(_MIN_LIMIT_DEG, 90.0, high_open=True),
            "Largest pressure angle on the return (cam angles where the law's s' < 0: the follower comes back); default "
            "pressure_angle_limit_deg (see pressure_angle_limit_rise_deg).", ("report",), example=40.0),
        Key("min_pitch_radius_roller_factor", Number("roller radii", 1.0, 100.0),
            "Norton's rule (Design of Machinery, ch. 8): the pitch curve's smallest |radius of curvature| at least this many "
            "roller radii (2 to 3 typical): the pitch_curvature check, met by sizing and the base-radius hint.", ("report",),
            example=2.5, requires={"follower": _roller_names()}),
        Key("face_margin_mm", Length(0.0, 1e4), "Flat face: clearance beyond the contact at each end: the face_length check "
            "asks for the contact's reach plus it (and quotes that least face_half_length_mm).", ("report",), example=2.0,
            requires={"follower": follower_names(("face",))}),
    )


@dataclass(frozen=True)
class Margins:
    """The margins a scene sets (rad, roller radii, mm; None: not given)."""

    rise: float | None = None
    ret: float | None = None
    pitch_factor: float | None = None
    face_margin: float | None = None

    @property
    def split(self) -> bool:
        return self.rise is not None or self.ret is not None


def read_margins(parsed: Mapping[str, Any]) -> Margins:
    """The margins of a cam table (none for a form without the keys)."""
    return Margins(parsed.get("pressure_angle_limit_rise"), parsed.get("pressure_angle_limit_return"),
                   parsed.get("min_pitch_radius_roller_factor"), parsed.get("face_margin"))


def _margins(spec: "CamSpec") -> Margins:
    return getattr(spec.params, "margins", None) or Margins()


def _split_limits(spec: "CamSpec", overall: float) -> tuple[float, float]:
    """The rise and return limits (rad), each the scene's pressure-angle limit ``overall`` (rad) unless given."""
    m = _margins(spec)
    return (overall if m.rise is None else m.rise), (overall if m.ret is None else m.ret)


def _stress_limit(spec: "CamSpec") -> Any:
    """The Hertz stress limit of a scene whose dynamics give an allowable stress, else None."""
    from camgen.synthesis.sizing import ContactStressLimit

    dyn = getattr(spec, "dynamics", None)
    if dyn is None or dyn.material is None or dyn.material.allowable_stress is None or spec.checks.rpm is None:
        return None
    return ContactStressLimit(dyn.train, dyn.material, spec.checks.rpm)


def design_limits(spec: "CamSpec", limits: "DesignLimits", sizing: bool = False) -> "DesignLimits":
    """``limits`` with the scene's margins: the rise and return limits, Norton's factor and,
    with ``sizing``, the Hertz stress limit of the dynamics keys."""
    m = _margins(spec)
    if m.split:
        rise, ret = _split_limits(spec, limits.max_pressure_angle)
        limits = replace(limits, max_pressure_angle=rise, max_pressure_angle_return=ret)
    if m.pitch_factor is not None:
        limits = replace(limits, min_pitch_radius_factor=m.pitch_factor)
    stress = _stress_limit(spec) if sizing else None
    if stress is not None:
        limits = replace(limits, contact_stress=stress)
    return limits


def margin_text(spec: "CamSpec", overall: float, sizing: bool = False) -> str:
    """What the margins add to a sizing or hint note ("" without them); ``overall``: the scene's
    pressure-angle limit, rad."""
    m, out = _margins(spec), ""
    if m.split:
        rise, ret = _split_limits(spec, overall)
        out += f" (rise {round(math.degrees(rise), 9):g} deg, return {round(math.degrees(ret), 9):g} deg where s' < 0)"
    if m.pitch_factor is not None:
        out += f", pitch-curve radii of curvature >= {m.pitch_factor:g} roller radii (Norton)"
    stress = _stress_limit(spec) if sizing else None
    if stress is not None:
        out += f", the Hertz contact stress <= {stress.allowable:g} MPa at {stress.rpm:g} rpm"
    return out


def with_margins(cam: "BuiltCam", spec: "CamSpec", checks: "list[CheckResult]", overall: float) -> "list[CheckResult]":
    """``checks`` with the margins applied (``overall``: the scene's pressure-angle limit, rad): the pressure_angle check on the rise and a
    pressure_angle_return check (split limits), a pitch_curvature check (Norton's factor), the
    face_length check with the clearance; unchanged without margins."""
    from camgen.checks import information, limited, pressure_angle_check, where_degrees

    m = _margins(spec)
    if not (m.split or m.pitch_factor is not None or m.face_margin is not None):
        return checks
    f, k = cam.spec_follower, cam.envelope.data  # type: ignore[attr-defined]
    theta = k.theta
    out = list(checks)
    if m.split:
        rise, ret = _split_limits(spec, overall)
        back = k.ds < 0
        at = next(i for i, c in enumerate(out) if c.name == "pressure_angle")
        up = pressure_angle_check(np.where(back, 0.0, k.pressure_angle), theta, rise, f"{f.motion} {f.kind} follower")
        down = pressure_angle_check(np.where(back, k.pressure_angle, 0.0), theta, ret, f"{f.motion} {f.kind} follower")
        out[at] = replace(up, limit=round(up.limit, 9), note=up.note + " on the rise and the dwells (cam angles where s' >= 0)")
        out.insert(at + 1, replace(down, name="pressure_angle_return", limit=round(down.limit, 9),
                                   note=down.note + " on the return (cam angles where s' < 0)"))
    if m.pitch_factor is not None and k.pitch_curvature is not None:
        with np.errstate(divide="ignore"):
            radius = 1.0 / np.abs(k.pitch_curvature)
        i = int(np.argmin(radius))
        least = m.pitch_factor * f.roller_radius
        value: Any = float(radius[i]) if math.isfinite(radius[i]) else "none"
        check = (limited("pitch_curvature", float(radius[i]), ">=", least, "mm", where_degrees(theta[i]), "")
                 if math.isfinite(radius[i]) else information("pitch_curvature", value, "mm", [], ""))
        out.append(replace(check, note=f"smallest |radius of curvature| of the pitch curve against {m.pitch_factor:g} x the roller "
                                        f"radius {f.roller_radius:g} mm (Norton, Design of Machinery, ch. 8)"))
    if m.face_margin is not None:
        at = next(i for i, c in enumerate(out) if c.name == "face_length")
        old = out[at]
        need = float(old.value) + m.face_margin
        note = (f"{old.note}; with the clearance face_margin_mm = {m.face_margin:g} mm at each end the face must reach "
                f"{need:.6g} mm (the least face_half_length_mm)")
        if old.limit is None:
            out[at] = replace(old, value=need, note=note)
        else:
            out[at] = replace(old, value=need, passed=bool(need <= old.limit), note=note)
    return out
