"""Design checks on a contour with its follower model.

Every check returns a :class:`CheckResult` (``name``, ``value``, ``limit``, ``unit``,
``passed``, ``where_deg``, ``note``) that report.json and report.html show as they are.
Angles in results are degrees.  "Cam angle" means one thing everywhere: the cam's rotation from
cam angle 0 (motion, pressure angle, and every check of a kind that evaluates its follower in
closed form).  The geometric checks of a bare contour (continuity, undercut, convexity,
curvature) give the *polar angle on the cam* of the point concerned (cam frame,
counter-clockwise from +x) and say so.

Followers (:class:`Follower`): a translating or oscillating roller (radius > 0, the steering
rod of the tricycle is one), a translating flat face, or a translating yoke (two parallel flat
faces, the constant-breadth cams).  Geometry of the roller checks comes from the pitch curve
(the path of the roller centre): the profile offset outward by the roller radius.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np
import numpy.typing as npt

from camgen.contour import Contour
from camgen.errors import GeometryError, ParameterError, require_finite
from camgen.geometry import wrap_pi
from camgen.numerics.order import median

__all__ = [
    "COMPARISONS", "CamEvaluation", "CheckResult", "Follower", "MAX_CHECK_SAMPLES", "MOTIONS",
    "Motion", "NO_CONCAVE_PART", "RollerKinematics", "breadth_error", "constant_breadth_check", "continuity_check",
    "convexity_check", "evaluate_cam", "face_length_check", "flat_motion", "information", "limited",
    "machinability_check", "machinability_from_radii", "motion_check", "pitch_curve", "pressure_angle_check",
    "radius_of_curvature", "roller_kinematics", "roller_motion", "run_ends", "undercut_check",
    "where_degrees",
]

_ORDER = ["none", "G0", "G1", "G2"]
MOTIONS = ("translating", "oscillating")


#: The value of ``min_concave_radius`` for a profile with no concave part (any tool cuts it).
NO_CONCAVE_PART = "no concave part"

#: Comparisons a check's value is held to against its limit ("at least" orders continuity levels).
COMPARISONS = ("<=", "<", ">=", ">", "at least")


#: What a check's ``where`` list may hold: angles (deg) or a linear cam's plate travel (mm).
WHERE_UNITS = ("deg", "mm")


@dataclass(frozen=True)
class CheckResult:
    """One design check.

    Attributes
    ----------
    name : str
        What is checked (snake_case).
    value : float or str
        The measured value, in ``unit``.
    limit : float, str or None
        The limit it is held against, in ``unit``; None for information without a limit.
    comparison : str
        How ``value`` must compare with ``limit`` to pass (:data:`COMPARISONS`); "" for information.
    unit : str
        Unit of ``value`` and ``limit`` (``mm``, ``deg``, ``1/mm``, or ``""``).
    passed : bool or None
        Whether ``value`` satisfies ``limit``; None for information (never a pass).
    where_deg : list of float
        Cam angles (deg) where the check is worst or fails (in ``where_unit``).
    note : str
        One sentence a designer reads.
    blocks_manufacture : bool
        A failure means the cam cannot be made as designed (undercut, gouge, broken wall): no
        manufacturing file is written for it.
    where_unit : str
        ``"deg"`` (cam angles or polar angles) or ``"mm"`` (a linear cam's plate travel): what
        ``where_deg`` holds; report.json names the list ``where_deg`` or ``where_mm`` by it.
    """

    name: str
    value: Any
    limit: Any
    comparison: str
    unit: str
    passed: bool | None
    where_deg: list[float] = field(default_factory=list)
    note: str = ""
    blocks_manufacture: bool = False
    where_unit: str = "deg"

    def __post_init__(self) -> None:
        assert self.where_unit in WHERE_UNITS, f"where_unit {self.where_unit!r} not one of {WHERE_UNITS}"

    @property
    def status(self) -> str:
        """"pass", "fail" or "info"."""
        return "info" if self.passed is None else "pass" if self.passed else "fail"

    @property
    def failed(self) -> bool:
        return self.passed is False

    def as_dict(self) -> dict[str, Any]:
        return {"name": self.name, "status": self.status, "value": self.value, "limit": self.limit, "comparison": self.comparison,
                "unit": self.unit, f"where_{self.where_unit}": self.where_deg, "note": self.note,
                "blocks_manufacture": self.blocks_manufacture}


def limited(name: str, value: float, comparison: str, limit: float, unit: str, where: list[float], note: str,
            blocks_manufacture: bool = False) -> CheckResult:
    """A check of a number against a limit; ``passed`` follows from ``comparison``."""
    passed = {"<=": value <= limit, "<": value < limit, ">=": value >= limit, ">": value > limit}[comparison]
    return CheckResult(name, value, limit, comparison, unit, bool(passed), where, note, blocks_manufacture)


def information(name: str, value: Any, unit: str, where: list[float], note: str) -> CheckResult:
    """A figure shown as information: no limit, neither pass nor fail."""
    return CheckResult(name, value, None, "", unit, None, where, note)


@dataclass(frozen=True)
class Follower:
    """Follower model (mm, rad).

    Attributes
    ----------
    kind : a registered follower (:mod:`camgen.followers`) whose contact these sampled checks
        know: faces (``"yoke"``), a face (``"flat"``) or a point with a radius (``"roller"``);
        ``contact`` is its contact.
    motion : ``"translating"`` or ``"oscillating"`` (roller only).
    roller_radius : roller radius (> 0 for ``"roller"``).
    offset : translating: distance of the follower axis from the cam axis (e).
    direction : translating: direction of the follower's motion in the fixed frame.
    pivot_distance, pivot_angle, arm_length : oscillating: pivot position (polar, fixed frame)
        and the arm length from the pivot to the roller centre.
    face_half_length : flat / yoke: usable half-length of the face (None: not checked).
    pressure_angle_limit : None for the defaults, 30 deg translating, 45 deg oscillating/yoke.
    """

    kind: str = "yoke"
    motion: str = "translating"
    roller_radius: float = 0.0
    offset: float = 0.0
    direction: float = 0.0
    pivot_distance: float = 0.0
    pivot_angle: float = 0.0
    arm_length: float = 0.0
    face_half_length: float | None = None
    pressure_angle_limit: float | None = None
    contact: str = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        from camgen.followers import get_follower, sampled_follower_names

        kinds = sampled_follower_names()
        if self.kind not in kinds:
            raise ParameterError("follower", self.kind, f"one of {kinds}")

        object.__setattr__(self, "contact", get_follower(self.kind).contact)
        if self.motion not in MOTIONS:
            raise ParameterError("follower_motion", self.motion, f"one of {MOTIONS}")
        if self.contact == "point" and not require_finite("roller_radius", self.roller_radius) > 0:
            raise ParameterError("roller_radius", self.roller_radius, "roller_radius > 0 mm for a roller follower")
        if self.contact != "point" and self.motion != "translating":
            raise ParameterError("follower_motion", self.motion, "translating for flat and yoke followers")
        if self.motion == "oscillating" and not (self.pivot_distance > 0 and self.arm_length > 0):
            raise ParameterError("arm_length", self.arm_length, "pivot_distance > 0 and arm_length > 0 mm for an oscillating follower")

    @property
    def limit(self) -> float:
        """Pressure-angle limit, rad."""
        if self.pressure_angle_limit is not None:
            return self.pressure_angle_limit
        return math.radians(30.0 if (self.motion == "translating" and self.contact != "faces") else 45.0)


def where_degrees(angles: npt.ArrayLike) -> list[float]:
    """Cam or polar angles ``angles`` (rad: one, or an array) as a list of degrees in [0, 360),
    rounded to 1e-6 deg."""
    if isinstance(angles, float):  # one double (a Python float or numpy.float64): Python's degrees
        # and %, the same operations as numpy's rad2deg (x * (180 / pi)) and remainder (fmod, then
        # the divisor's sign), without the ufunc calls (tests/test_checks.py compares them)
        return [round(math.degrees(angles) % 360.0, 6)]
    deg = np.mod(np.degrees(angles), 360.0)  # elementwise: a scalar's value is a one-element array's
    return [round(a, 6) for a in (deg.tolist() if deg.ndim else [float(deg)])]


def _polar_deg(points: np.ndarray) -> list[float]:
    points = np.atleast_2d(points)
    return where_degrees(np.arctan2(points[:, 1], points[:, 0]))


def run_ends(mask: np.ndarray, angles: np.ndarray) -> list[float]:
    """Start and end cam angles (deg) of every run of True in ``mask`` (samples in curve order,
    periodic): where a failing region begins and ends."""
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        return []
    if mask.all():
        return where_degrees(angles[[0, -1]])
    # np.roll(mask, 1) and np.roll(mask, -1), each one concatenation; every run's start and end
    # in one elementwise where_degrees: [start, end, start, end, ...]
    starts = np.flatnonzero(mask & ~np.concatenate((mask[-1:], mask[:-1])))
    ends = np.flatnonzero(mask & ~np.concatenate((mask[1:], mask[:1])))
    return where_degrees(angles[np.stack((starts, ends), axis=1).ravel()])


#: Most samples of the dense checks on one spline segment (a refitted offset can have 440,000
#: pieces: 32 samples each took 6 s); above it fewer per piece, never fewer than 1.
MAX_CHECK_SAMPLES = 1 << 20


def _samples(contour: Contour, per_segment: int = 512) -> np.ndarray:
    """Global parameters for dense checks: ``per_segment`` per segment (32 per spline piece at
    least, fewer when that would pass :data:`MAX_CHECK_SAMPLES`), spline break points included
    (the curvature of a cubic spline peaks there)."""
    if contour.n_segments == 1 and hasattr(contour.segments[0], "n_pieces"):
        pieces = contour.segments[0].n_pieces
        per_segment = max(per_segment, max(1, min(32, MAX_CHECK_SAMPLES // pieces)) * pieces)
    u = np.arange(per_segment) / per_segment
    return (np.arange(contour.n_segments)[:, None] + u[None, :]).ravel()


# --------------------------------------------------------------------------------------------
# Breadth, continuity, convexity, curvature
# --------------------------------------------------------------------------------------------
def breadth_error(contour: Contour, breadth: float, n_directions: int = 3600) -> tuple[float, float]:
    """Largest ``|h(psi) + h(psi + pi) - breadth|`` (mm) over ``n_directions`` face directions, and where (rad)."""
    psi = np.linspace(0.0, math.pi, n_directions, endpoint=False)
    err = np.abs(contour.support(psi) + contour.support(psi + math.pi) - breadth)
    worst = int(np.argmax(err))
    return float(err[worst]), float(psi[worst])


def constant_breadth_check(contour: Contour, breadth: float, tol: float = 1e-6) -> CheckResult:
    """Constant breadth for a yoke (double flat-faced) follower: error against ``tol`` mm."""
    err, psi = breadth_error(contour, breadth)
    return limited(
        "constant_breadth", err, "<=", tol, "mm", where_degrees(psi),
        f"distance between the parallel yoke faces stays {breadth:g} mm within {err:.3g} mm over 3600 directions",
    )


def continuity_check(contour: Contour, required: str = "G1", curvature_tol: float = 1e-6) -> CheckResult:
    """Lowest joint continuity against ``required``; ``where_deg`` lists joints with curvature jumps.

    A curvature jump below ``curvature_tol`` (1/mm; 1e-6 changes a 50 mm radius of curvature
    by 2.5 um) counts as G2: refitted offsets match position and tangent exactly but curvature
    only to their fitting error.
    """
    joints = contour.joints(curvature_tol=curvature_tol)
    level = min((j.continuity for j in joints), key=_ORDER.index)
    jumps = [j for j in joints if j.continuity != "G2"]
    where = _polar_deg(np.array([j.point for j in jumps])) if jumps else []
    note = f"lowest continuity {level} over {len(joints)} joints"
    if level == "G1":
        biggest = max(abs(j.curvature_jump_per_mm) for j in jumps)
        note += (
            f"; curvature jumps at {len(jumps)} joints (largest {biggest:.6g} 1/mm): the follower "
            "acceleration jumps there, i.e. infinite jerk"
        )
    return CheckResult("continuity", level, required, "at least", "", _ORDER.index(level) >= _ORDER.index(required), where, note)


def convexity_check(contour: Contour) -> CheckResult:
    """Undercut for flat-faced and yoke followers: the cam must be convex, its smallest signed
    curvature > 0 (1/mm)."""
    t = _samples(contour, 64)
    kappa = contour.curvature(t)
    worst = int(np.argmin(kappa))
    bad = kappa <= 0
    pts = contour.evaluate(t)
    where = run_ends(bad, np.arctan2(pts[:, 1], pts[:, 0])) if bad.any() else _polar_deg(pts[worst])
    return CheckResult(
        "undercut", float(kappa[worst]), 0.0, ">", "1/mm", bool(not bad.any()), where,
        "convex everywhere: a flat face touches the cam at one point in every direction" if not bad.any()
        else "concave parts: a flat face would bridge them (undercut of the flat follower)", blocks_manufacture=True,
    )


def radius_of_curvature(contour: Contour) -> tuple[np.ndarray, np.ndarray]:
    """Signed radius of curvature (mm; < 0 concave) and cam angle (rad) at dense samples."""
    t = _samples(contour)
    kappa = contour.curvature(t)
    pts = contour.evaluate(t)
    with np.errstate(divide="ignore"):
        rho = np.where(kappa != 0, 1.0 / kappa, np.inf)
    return rho, np.arctan2(pts[:, 1], pts[:, 0])


def machinability_check(contour: Contour, tool_radius: float, tool_is_limit: bool = True) -> list[CheckResult]:
    """Smallest convex and concave radii of curvature against the cutting-tool radius (mm).

    A concave radius below the tool radius cannot be cut (the tool would gouge): with
    ``tool_is_limit`` (the scene names its tool or writes G-code) that fails the check and blocks
    the manufacturing files; otherwise it is information.  A convex radius has no lower limit
    but is reported for the machinist.  ``where_deg``: polar angles of the points on the cam.
    """
    rho, angle = radius_of_curvature(contour)
    return machinability_from_radii(rho, angle, tool_radius, tool_is_limit)


def machinability_from_radii(rho: np.ndarray, angle: np.ndarray, tool_radius: float, tool_is_limit: bool = True,
                             where: str = "polar angles on the cam") -> list[CheckResult]:
    """:func:`machinability_check` from signed radii of curvature ``rho`` (mm, < 0 concave) at
    ``angle`` (rad, in curve order: polar angles, or cam angles for a kind that knows them);
    ``where`` names what the angles are in the notes (e.g. "cam angles")."""
    out = []
    pairs = f" (between the listed pairs of {where})"
    convex_at: int | None = int(rho.argmin()) if rho.size else None
    concave: np.ndarray | None = None
    if convex_at is None or not rho[convex_at] > 0:  # else every radius > 0 (argmin picks a NaN first): no concave part
        convex = rho > 0
        least = np.where(convex, rho, np.inf)
        convex_at = int(least.argmin()) if rho.size else None
        if convex_at is not None and not least[convex_at] < np.inf and not convex.any():  # a finite least is a convex sample
            convex_at = None
        concave = rho < 0
    if convex_at is not None:
        out.append(information("min_convex_radius", float(rho[convex_at]), "mm", where_degrees(angle[convex_at]),
                               f"smallest convex radius of the profile (no limit; the tool radius is {tool_radius:g} mm)"))
    if concave is not None and concave.any():
        i = int(np.where(concave, rho, -np.inf).argmax())
        value = float(-rho[i])
        bad = concave & (rho > -tool_radius)  # -rho < tool_radius, the negation exact
        where_deg = run_ends(bad, angle) if bad.any() else where_degrees(angle[i])
        note = "a concave radius below the tool radius cannot be cut without gouging" + (pairs if bad.any() else "")
        if tool_is_limit:
            out.append(limited("min_concave_radius", value, ">", tool_radius, "mm", where_deg, note, blocks_manufacture=True))
        else:
            out.append(information("min_concave_radius", value, "mm", where_deg,
                                   note + f"; no tool is named (machining.tool_diameter_mm), {tool_radius:g} mm is the default radius"))
    elif tool_is_limit:
        out.append(CheckResult("min_concave_radius", NO_CONCAVE_PART, tool_radius, ">", "mm", True, [], "no concave parts: any tool radius cuts the profile"))
    else:
        out.append(information("min_concave_radius", NO_CONCAVE_PART, "mm", [], "no concave parts: any tool radius cuts the profile"))
    return out


# --------------------------------------------------------------------------------------------
# Roller followers: undercut and pressure angle from the pitch curve
# --------------------------------------------------------------------------------------------
def pitch_curve(contour: Contour, follower: Follower) -> Contour:
    """Path of the roller centre: the profile offset outward by the roller radius."""
    return contour.offset(follower.roller_radius, spline_tol=1e-7)


def undercut_check(pitch: Contour, follower: Follower) -> CheckResult:
    """Roller follower: where the pitch curve's convex radius of curvature is not larger than
    the roller radius, the profile (pitch offset inward by the roller radius) reverses: undercut."""
    t = _samples(pitch)
    kappa = pitch.curvature(t)
    pts = pitch.evaluate(t)
    with np.errstate(divide="ignore"):
        rho = np.where(kappa > 0, 1.0 / kappa, np.inf)
    i = int(np.argmin(rho))
    bad = rho <= follower.roller_radius
    where = run_ends(bad, np.arctan2(pts[:, 1], pts[:, 0])) if bad.any() else _polar_deg(pts[i])
    return CheckResult(
        "undercut", float(rho[i]), follower.roller_radius, ">", "mm", bool(not bad.any()), where,
        "smallest convex radius of the pitch curve against the roller radius"
        + ("" if not bad.any() else ": the profile undercuts (cusps) between the listed pairs of polar angles on the cam"),
        blocks_manufacture=True,
    )


@dataclass(frozen=True)
class RollerKinematics:
    """Roller-centre kinematics sampled along the pitch curve, sorted by cam angle.

    ``cam_angle`` (rad, in [0, 2 pi)), ``position`` (translating: distance along the motion
    direction, mm; oscillating: arm angle, rad), ``pressure_angle`` (rad, signed).
    """

    cam_angle: np.ndarray
    position: np.ndarray
    pressure_angle: np.ndarray


def roller_kinematics(pitch: Contour, follower: Follower, samples: int = 7200) -> RollerKinematics:
    """Cam angle, follower position and pressure angle for every sampled pitch point.

    Each pitch point P (cam frame) is on the follower's path at one cam angle theta (the cam
    turns counter-clockwise): translating, ``Rot(theta) P`` on the follower axis (offset e from
    the cam axis, moving along ``direction``); oscillating, ``|Rot(theta) P - A| = arm``.  The
    pressure angle is the angle between the pitch-curve normal there and the roller centre's
    velocity (the motion direction; perpendicular to the arm for oscillating followers).
    """
    t = np.linspace(0.0, pitch.n_segments, samples, endpoint=False)
    p = pitch.evaluate(t)
    n = pitch.normal(t)
    radius = np.hypot(p[:, 0], p[:, 1])
    phi = np.arctan2(p[:, 1], p[:, 0])
    if follower.motion == "translating":
        e = follower.offset
        if np.any(radius <= abs(e)):
            raise GeometryError(f"the follower axis (offset {e:g} mm) misses part of the pitch curve")
        theta = follower.direction + np.arcsin(e / radius) - phi
        position = np.sqrt(radius**2 - e * e)
        velocity_dir = np.full(t.shape, follower.direction)
    else:
        a, la = follower.pivot_distance, follower.arm_length
        cos = (radius**2 + a * a - la * la) / (2.0 * radius * a)
        if np.any(np.abs(cos) > 1):
            raise GeometryError("the oscillating follower's arm cannot reach part of the pitch curve")
        phi_x = follower.pivot_angle + np.arccos(cos)
        theta = phi_x - phi
        x = radius[:, None] * np.stack([np.cos(phi_x), np.sin(phi_x)], axis=1)
        rel = x - a * np.array([math.cos(follower.pivot_angle), math.sin(follower.pivot_angle)])
        position = np.arctan2(rel[:, 1], rel[:, 0])
        velocity_dir = position + math.pi / 2
    normal_angle = np.arctan2(n[:, 1], n[:, 0]) + theta
    pressure = wrap_pi(normal_angle - velocity_dir)
    pressure = np.where(pressure > math.pi / 2, pressure - math.pi, np.where(pressure < -math.pi / 2, pressure + math.pi, pressure))
    theta = np.mod(theta, 2.0 * math.pi)
    order = np.argsort(theta)
    return RollerKinematics(theta[order], position[order], pressure[order])


def pressure_angle_check(values: np.ndarray, cam_angle: np.ndarray, limit: float, what: str) -> CheckResult:
    """Largest |pressure angle| (deg) of ``values`` (rad) at ``cam_angle`` (rad) against ``limit`` (rad)."""
    mag = np.abs(values)
    i = int(mag.argmax())
    failed = False
    if not mag[i] <= limit:  # the largest beyond the limit, or NaN (argmax points at the first NaN): look at every sample
        bad = mag > limit
        failed = bool(bad.any())
    where = run_ends(bad, cam_angle) if failed else where_degrees(cam_angle[i])
    return CheckResult("pressure_angle", float(np.degrees(mag[i])), float(np.degrees(limit)), "<=", "deg", not failed,
                       where, f"largest pressure angle of the {what}" + (" (above the limit between the listed pairs of cam angles)" if failed else ""))


# --------------------------------------------------------------------------------------------
# Flat faces and yokes: face length and motion
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Motion:
    """Follower motion per unit cam speed against cam angle (uniform grid, rad).

    ``displacement`` mm (or rad for an oscillating arm), ``velocity`` per rad,
    ``acceleration`` per rad^2, ``jerk`` per rad^3 (finite part: impulses at curvature jumps
    are listed in ``jerk_impulses_deg``).  ``lift_zero``: the displacement of zero lift (None:
    the lowest displacement); ``peaks``: exact largest |velocity|, |acceleration|, |jerk| per
    rad^n when the kind knows them in closed form (None: the grid's).
    """

    cam_angle: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    unit: str = "mm"
    jerk_impulses_deg: list[float] = field(default_factory=list)
    lift_zero: float | None = None
    peaks: tuple[float, float, float] | None = None

    @property
    def lift(self) -> np.ndarray:
        """Displacement from zero lift (``lift_zero``, else the lowest displacement), mm or rad."""
        zero = float(np.min(self.displacement)) if self.lift_zero is None else self.lift_zero
        return self.displacement - zero

    def peak_values(self) -> tuple[float, float, float]:
        """Largest |velocity| (per rad), |acceleration| (per rad^2), |jerk| (per rad^3)."""
        if self.peaks is not None:
            return self.peaks
        return (float(np.max(np.abs(self.velocity))), float(np.max(np.abs(self.acceleration))), float(np.max(np.abs(self.jerk))))

    def rates(self, rpm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, str]]:
        """Velocity, acceleration and jerk at ``rpm`` in the report's units and those units:
        mm/s, m/s^2, m/s^3 (translating) or rad/s, rad/s^2, rad/s^3 (oscillating)."""
        omega = 2.0 * math.pi * rpm / 60.0
        scale = 1e-3 if self.unit == "mm" else 1.0  # mm/s^2 -> m/s^2
        units = {"velocity": f"{self.unit}/s", "acceleration": "m/s^2" if self.unit == "mm" else "rad/s^2",
                 "jerk": "m/s^3" if self.unit == "mm" else "rad/s^3"}
        return self.velocity * omega, self.acceleration * (omega**2 * scale), self.jerk * (omega**3 * scale), units

    def at_rpm(self, rpm: float) -> dict[str, float]:
        """Largest |velocity| (mm/s or rad/s), |acceleration| (m/s^2 or rad/s^2), |jerk| (m/s^3 or
        rad/s^3) at ``rpm``: translating followers in mm and m, oscillating ones in rad."""
        omega = 2.0 * math.pi * rpm / 60.0
        v, a, j = self.peak_values()
        if self.unit == "mm":
            return {"max_velocity_mm_per_s": v * omega, "max_acceleration_m_per_s2": a * omega**2 * 1e-3,
                    "max_jerk_m_per_s3": j * omega**3 * 1e-3}
        return {f"max_velocity_{self.unit}_per_s": v * omega, f"max_acceleration_{self.unit}_per_s2": a * omega**2,
                f"max_jerk_{self.unit}_per_s3": j * omega**3}


def flat_motion(contour: Contour, follower: Follower, samples: int = 3600) -> tuple[Motion, np.ndarray]:
    """Translating flat/yoke follower: motion from the support function, and the contact
    offset along the face (mm) at every cam angle (``h'(psi)``)."""
    theta = 2.0 * math.pi * np.arange(samples) / samples
    psi = follower.direction - theta
    h, dh, d2h = contour.support_derivatives(psi)
    acc = d2h
    step = theta[1] - theta[0]
    jerk = (np.roll(acc, -1) - np.roll(acc, 1)) / (2.0 * step)
    jumps = np.abs(np.roll(acc, -1) - acc)
    typical = median(np.abs(np.diff(acc))) + 1e-12
    impulses = jumps > 50.0 * typical
    # the finite part of the jerk: drop the differences that straddle a jump
    finite = ~(impulses | np.roll(impulses, 1))
    jerk = np.where(finite, jerk, np.nan)
    jerk = np.where(np.isnan(jerk), np.interp(theta, theta[finite], jerk[finite]), jerk)
    motion = Motion(theta, h, -dh, acc, jerk, "mm", where_degrees(theta[impulses] + 0.5 * step))
    return motion, dh


def roller_motion(kin: RollerKinematics, samples: int = 3600, unit: str = "mm") -> Motion:
    """Roller follower motion on a uniform cam-angle grid (periodic interpolation, central differences)."""
    theta = 2.0 * math.pi * np.arange(samples) / samples
    pos = np.interp(theta, kin.cam_angle, kin.position, period=2.0 * math.pi)
    step = theta[1] - theta[0]

    def d(a: np.ndarray) -> np.ndarray:
        return (np.roll(a, -1) - np.roll(a, 1)) / (2.0 * step)

    vel = d(pos)
    acc = (np.roll(pos, -1) - 2.0 * pos + np.roll(pos, 1)) / step**2
    return Motion(theta, pos, vel, acc, d(acc), unit)


def face_length_check(offsets: np.ndarray, cam_angle: np.ndarray, half_length: float | None) -> CheckResult:
    """Largest contact offset along the flat face (mm) against the face half-length."""
    mag = np.abs(offsets)
    i = int(np.argmax(mag))
    if half_length is None:
        return information("face_length", float(mag[i]), "mm", where_degrees(cam_angle[i]),
                           "largest contact offset along the face: the face must reach this far from its centre "
                           "(give face_half_length_mm to check it)")
    bad = mag > half_length
    where = run_ends(bad, cam_angle) if bad.any() else where_degrees(cam_angle[i])
    return CheckResult("face_length", float(mag[i]), half_length, "<=", "mm", bool(not bad.any()), where,
                       "largest contact offset along the face against the face half-length")


def motion_check(motion: Motion, rpm: float | None) -> CheckResult:
    """Summary of the follower motion (largest |v|, |a|, |jerk| per unit cam speed), informational."""
    v, a, j = motion.peak_values()
    u = motion.unit
    ptp = motion.displacement.max() - motion.displacement.min()  # np.ptp: the same two reductions
    note = (f"stroke {ptp:.6g} {u}; largest |velocity| {v:.6g} {u}/rad, "
            f"|acceleration| {a:.6g} {u}/rad^2, |jerk| {j:.6g} {u}/rad^3 (finite part)")
    if rpm:
        at = motion.at_rpm(rpm)
        note += f"; at {rpm:g} rpm: " + ", ".join(f"{k} {v:.6g}" for k, v in at.items())
    if motion.jerk_impulses_deg:
        note += f"; jerk impulses (acceleration jumps) at {len(motion.jerk_impulses_deg)} cam angles"
    stroke, unit = float(ptp), motion.unit
    if unit == "rad":  # an oscillating follower's swing: degrees at the edges, as every other angle
        stroke, unit = math.degrees(stroke), "deg"
    return information("follower_motion", stroke, unit, motion.jerk_impulses_deg[:12], note)


# --------------------------------------------------------------------------------------------
# All checks of one cam
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CamEvaluation:
    """The checks stage's result for one cam (frozen): its checks, the figures they add to the
    report (``figures``: the follower, the motion at speed) and the curves report.html draws
    (cam angles in rad)."""

    checks: tuple[CheckResult, ...]
    follower: Follower | None  # the generic follower model; None for kinds with their own (disk cams)
    motion: Motion | None
    pressure_angle: tuple[np.ndarray, np.ndarray] | None  # (cam angle, rad)
    curvature_radius: tuple[np.ndarray, np.ndarray] | None  # (angle, signed radius mm): see curvature_angle_label
    pitch: Contour | None = None
    pressure_angle_label: str = ""
    curvature_label: str = "radius of curvature (mm, < 0 concave)"
    curvature_limit: float | None = None  # the radius the curvature plot is held to (roller radius)
    curvature_angle_label: str = "polar angle on the cam (deg)"  # what the curvature curve's angles are
    follower_drawing: list[tuple[str, np.ndarray]] | None = None  # (label, polyline (n, 2) mm) at cam angle 0
    animation: Any = None  # camgen.report.animation.RideAnimation: the follower riding the cam
    figures: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        from types import MappingProxyType

        object.__setattr__(self, "checks", tuple(self.checks))
        object.__setattr__(self, "figures", MappingProxyType(dict(self.figures)))


def evaluate_cam(contour: Contour | None, follower: Follower, tool_radius: float | None = None, rpm: float | None = None,
                 breadth: float | None = None, pitch: Contour | None = None, tool_is_limit: bool = True) -> CamEvaluation:
    """Run every check that applies to ``contour`` with ``follower``.

    Yoke and flat followers: undercut (convexity), constant breadth (yoke), face length, motion
    (pressure angle 0 for a translating face normal to its motion: reported as such).  Roller
    followers: undercut from the pitch curve, pressure angle, motion.  Always: continuity and,
    with ``tool_radius``, machinability (a limit when ``tool_is_limit``, else information).

    ``contour`` None: the profile could not be made (the roller undercuts the ``pitch`` curve);
    the checks of the pitch curve still run, so the report shows where and why.
    """
    if contour is None:
        return _evaluate_pitch_only(follower, pitch, rpm)
    checks = [continuity_check(contour)]
    rho, rho_angle = radius_of_curvature(contour)
    pressure = None
    motion = None
    if follower.contact in ("faces", "face"):
        checks.append(convexity_check(contour))
        if follower.contact == "faces" and breadth is not None:
            checks.append(constant_breadth_check(contour, breadth))
        motion, offsets = flat_motion(contour, follower)
        checks.append(face_length_check(offsets, motion.cam_angle, follower.face_half_length))
        pressure = (motion.cam_angle, np.zeros_like(motion.cam_angle))
        checks.append(limited("pressure_angle", 0.0, "<=", math.degrees(follower.limit), "deg", [],
                              "a translating flat face moves along its own normal: pressure angle 0 at every cam angle"))
    else:
        try:
            pitch = pitch if pitch is not None else pitch_curve(contour, follower)
        except GeometryError as exc:  # the roller does not fit a concave part: no pitch curve
            checks.append(CheckResult("undercut", "no pitch curve", follower.roller_radius, ">", "mm", False, [],
                                      f"the roller cannot follow the profile: {exc}", blocks_manufacture=True))
            pitch = None
        if pitch is not None:
            checks.append(undercut_check(pitch, follower))
            kin = roller_kinematics(pitch, follower)
            pressure = (kin.cam_angle, kin.pressure_angle)
            what = f"{follower.motion} roller follower" + (f" (offset {follower.offset:g} mm)" if follower.offset else "")
            checks.append(pressure_angle_check(kin.pressure_angle, kin.cam_angle, follower.limit, what))
            motion = roller_motion(kin, unit="mm" if follower.motion == "translating" else "rad")
    if motion is not None:
        checks.append(motion_check(motion, rpm))
    if tool_radius is not None:  # the radii sampled above (machinability_check would sample them again)
        checks.extend(machinability_from_radii(rho, rho_angle, tool_radius, tool_is_limit))
    return CamEvaluation(tuple(checks), follower, motion, pressure, (rho_angle, rho), pitch)


def _evaluate_pitch_only(follower: Follower, pitch: Contour | None, rpm: float | None) -> CamEvaluation:
    """The checks of a roller cam whose profile cannot be made: undercut, pressure angle and
    motion from the pitch curve; the curvature plot shows the pitch curve against the roller."""
    if pitch is None or follower.contact != "point":
        return CamEvaluation((), follower, None, None, None, pitch)
    checks = [undercut_check(pitch, follower)]
    kin = roller_kinematics(pitch, follower)
    what = f"{follower.motion} roller follower" + (f" (offset {follower.offset:g} mm)" if follower.offset else "")
    checks.append(pressure_angle_check(kin.pressure_angle, kin.cam_angle, follower.limit, what))
    motion = roller_motion(kin, unit="mm" if follower.motion == "translating" else "rad")
    checks.append(motion_check(motion, rpm))
    rho, angle = radius_of_curvature(pitch)
    return CamEvaluation(tuple(checks), follower, motion, (kin.cam_angle, kin.pressure_angle), (angle, rho), pitch,
                         curvature_label="radius of curvature of the pitch curve (mm)", curvature_limit=follower.roller_radius)
