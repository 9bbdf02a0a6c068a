"""Sizing of disk cams: the smallest base radius (and offset) that meets the design limits.

A design is *feasible* when the profile can be made (no undercut, cusp or backward-turning face,
see :func:`camgen.synthesis.followers.cam_envelope`) and, on the dense cam-angle grid of
:func:`camgen.synthesis.followers.check_grid`,

* the largest ``|pressure angle|`` is ``<= max_pressure_angle`` (with a separate
  ``max_pressure_angle_return``: that limit on the return, the cam angles where ``s' < 0``, and
  ``max_pressure_angle`` everywhere else: the rise and the dwells);
* a roller's pitch curve has ``|radius of curvature| >= min_pitch_radius_factor`` roller radii
  everywhere (Norton's rule, *Design of Machinery*, ch. 8: 2 to 3 roller radii; 0: off);
* the peak Hertz contact stress at speed (:class:`ContactStressLimit`: the follower train, the
  contact's materials and the cam speed, :func:`camgen.dynamics.hertz_line_stress`) is at most
  the allowable stress, when a stress limit is given;
* the smallest convex radius of curvature of the profile is ``>= min_convex_radius`` (for a
  roller ``rho_pitch - r``: a margin over the roller radius on the pitch curve);
* the smallest concave radius of curvature of the profile is ``>= min_concave_radius`` (the
  cutter radius: a concave part tighter than the tool cannot be cut); a flat face allows no
  concave part at all.

All quantities come from the closed forms of :func:`camgen.synthesis.followers.kinematics`.
The base radius is searched by a scan over the valid range followed by bisection between the
last infeasible and the first feasible value, to ``tol`` mm; the value returned is feasible.
Where the passing values of a parameter are bounded on both sides (an oscillating follower's
base radius, roller radius, arm length or pivot distance) every passing run the scan finds is
returned, both ends bracketed the same way (:func:`feasible_intervals`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Callable

import numpy as np

from camgen.errors import GeometryError, ParameterError, require_finite, require_positive
from camgen.numerics.minimise import golden_section
from camgen.synthesis.followers import (
    DEFAULT_CHECK_STEP,
    Displacement,
    FollowerSpec,
    profile_failures,
    check_grid,
    kinematics,
)

__all__ = [
    "BaseRadiusAdvice", "ContactStressLimit", "DEFAULT_SIZE_TOL", "DesignLimits", "DesignMeasures", "FaceWidth", "Intervals",
    "MAX_BASE_RADIUS", "SizingResult", "arm_length_intervals", "base_radius_advice", "base_radius_intervals", "face_width",
    "feasible_intervals", "measure", "min_base_radius", "min_base_radius_and_offset", "pivot_distance_intervals",
    "require_design", "roller_radius_intervals",
]

#: Default resolution of the base-radius (and offset) search, mm.
DEFAULT_SIZE_TOL = 1e-4


@dataclass(frozen=True)
class DesignLimits:
    """Limits a cam design must meet (rad, mm).

    Attributes
    ----------
    max_pressure_angle : float
        Largest allowed ``|pressure angle|``, rad, in ``(0, pi/2)`` (typical: 30 deg translating,
        45 deg oscillating).
    min_convex_radius : float
        Smallest allowed convex radius of curvature of the profile, mm (>= 0; the profile must
        also be free of undercut, i.e. > 0).
    min_concave_radius : float
        Smallest allowed concave radius of curvature of the profile, mm (>= 0; the cutter radius).
    check_step : float
        Spacing of the cam-angle grid the limits are checked on, rad.
    max_pressure_angle_return : float or None
        Largest allowed ``|pressure angle|`` on the return (where ``s' < 0``), rad, in
        ``(0, pi/2)``; ``max_pressure_angle`` then holds on the rise and the dwells (``s' >= 0``).
        None: ``max_pressure_angle`` everywhere.
    min_pitch_radius_factor : float
        Norton's rule (*Design of Machinery*, ch. 8): a roller's pitch curve keeps
        ``|radius of curvature| >= factor * roller radius`` (2 to 3 typical; >= 0; 0: off; a
        follower without a roller radius meets it trivially).
    contact_stress : ContactStressLimit or None
        The Hertz contact stress at speed must stay at most its allowable stress; None: no limit.
    """

    max_pressure_angle: float = math.radians(30.0)
    min_convex_radius: float = 0.0
    min_concave_radius: float = 0.0
    check_step: float = DEFAULT_CHECK_STEP
    max_pressure_angle_return: float | None = None
    min_pitch_radius_factor: float = 0.0
    contact_stress: "ContactStressLimit | None" = None

    def __post_init__(self) -> None:
        for name in ("max_pressure_angle", "max_pressure_angle_return"):
            if name == "max_pressure_angle_return" and self.max_pressure_angle_return is None:
                continue
            a = require_finite(name, getattr(self, name))
            if not 0.0 < a < math.pi / 2:
                raise ParameterError(name, a, f"0 < {name} < pi/2 rad (0 to 90 deg)")
        for name in ("min_convex_radius", "min_concave_radius"):
            if require_finite(name, getattr(self, name)) < 0:
                raise ParameterError(name, getattr(self, name), f"{name} >= 0 mm")
        if require_finite("min_pitch_radius_factor", self.min_pitch_radius_factor) < 0:
            raise ParameterError("min_pitch_radius_factor", self.min_pitch_radius_factor, "min_pitch_radius_factor >= 0 (roller radii)")
        require_positive("check_step", self.check_step, "rad")

    @property
    def split(self) -> bool:
        """The rise and the return have limits of their own."""
        return self.max_pressure_angle_return is not None


@dataclass(frozen=True)
class ContactStressLimit:
    """The Hertz contact stress as a design limit: the follower ``train``
    (:class:`camgen.dynamics.FollowerTrain`), the contact ``material``
    (:class:`camgen.dynamics.ContactMaterial`, its ``allowable_stress`` the limit, MPa) and the
    cam speed ``rpm`` (rev/min) at which the stress is computed (:func:`camgen.dynamics.analyse`)."""

    train: Any
    material: Any
    rpm: float

    def __post_init__(self) -> None:
        if self.material.allowable_stress is None:
            raise ParameterError("allowable_stress", None, "an allowable contact stress, MPa (the limit the stress is held to)")
        require_positive("rpm", self.rpm, "rev/min")

    @property
    def allowable(self) -> float:
        """The allowable Hertz stress, MPa."""
        return float(self.material.allowable_stress)


@dataclass(frozen=True)
class DesignMeasures:
    """What a design achieves on the check grid.

    ``max_pressure_angle`` (rad, of ``|alpha|``), ``min_convex_radius`` / ``min_concave_radius``
    (mm, of the profile; ``inf`` when there is no such part), each with the cam angle (deg) where
    it occurs; ``failures``: the reasons the profile cannot be made (empty when it can).
    ``max_pressure_angle_rise`` / ``max_pressure_angle_return``: the largest ``|alpha|`` where
    ``s' >= 0`` and where ``s' < 0`` (rad, 0 where there is none), with their cam angles (deg);
    ``min_pitch_radius``: a roller's smallest ``|radius of curvature|`` of the pitch curve (mm,
    ``inf`` without a roller) and its cam angle; ``max_contact_stress``: the peak Hertz stress
    at speed (MPa; None when no stress limit was given, ``inf`` when the contact cannot carry it).
    """

    max_pressure_angle: float
    max_pressure_angle_deg_at: float
    min_convex_radius: float
    min_convex_radius_deg_at: float
    min_concave_radius: float
    min_concave_radius_deg_at: float
    failures: list[str] = field(default_factory=list)
    max_pressure_angle_rise: float = 0.0
    max_pressure_angle_rise_deg_at: float = 0.0
    max_pressure_angle_return: float = 0.0
    max_pressure_angle_return_deg_at: float = 0.0
    min_pitch_radius: float = math.inf
    min_pitch_radius_deg_at: float = 0.0
    max_contact_stress: float | None = None
    max_contact_stress_deg_at: float = 0.0
    roller_radius: float = 0.0  #: mm, the follower's roller radius (0: none), which Norton's rule scales

    def violations(self, limits: DesignLimits) -> list[str]:
        """One sentence per limit the design breaks (empty: feasible).  :func:`_feasible` judges the
        same limits from the extremes alone (tests/test_sizing_feasible.py compares the two): a
        limit added or changed here is added or changed there too."""
        out = list(self.failures)
        roller_radius = self.roller_radius
        if limits.max_pressure_angle_return is not None:
            for what, value, at, limit in (
                    ("rise", self.max_pressure_angle_rise, self.max_pressure_angle_rise_deg_at, limits.max_pressure_angle),
                    ("return", self.max_pressure_angle_return, self.max_pressure_angle_return_deg_at, limits.max_pressure_angle_return)):
                if value > limit:
                    out.append(f"pressure angle on the {what} {math.degrees(value):.6g} deg > {math.degrees(limit):.6g} deg "
                               f"at cam angle {at:.3f} deg")
        elif self.max_pressure_angle > limits.max_pressure_angle:
            out.append(f"pressure angle {math.degrees(self.max_pressure_angle):.4g} deg > {math.degrees(limits.max_pressure_angle):.4g} deg "
                       f"at cam angle {self.max_pressure_angle_deg_at:.3f} deg")
        least_pitch = limits.min_pitch_radius_factor * roller_radius
        if least_pitch > 0 and not self.min_pitch_radius >= least_pitch:
            out.append(f"pitch-curve radius of curvature {self.min_pitch_radius:.6g} mm < {limits.min_pitch_radius_factor:g} x the roller "
                       f"radius {roller_radius:g} mm = {least_pitch:.6g} mm at cam angle {self.min_pitch_radius_deg_at:.3f} deg")
        if limits.contact_stress is not None and self.max_contact_stress is not None \
                and not self.max_contact_stress <= limits.contact_stress.allowable:
            out.append(f"Hertz contact stress {self.max_contact_stress:.6g} MPa > {limits.contact_stress.allowable:g} MPa at "
                       f"{limits.contact_stress.rpm:g} rpm at cam angle {self.max_contact_stress_deg_at:.3f} deg")
        if self.min_convex_radius < limits.min_convex_radius:
            out.append(f"convex radius of curvature {self.min_convex_radius:.6g} mm < {limits.min_convex_radius:g} mm "
                       f"at cam angle {self.min_convex_radius_deg_at:.3f} deg")
        if self.min_concave_radius < limits.min_concave_radius:
            out.append(f"concave radius of curvature {self.min_concave_radius:.6g} mm < {limits.min_concave_radius:g} mm "
                       f"at cam angle {self.min_concave_radius_deg_at:.3f} deg")
        return out


class _SampledLaw:
    """``law`` with its values on the last cam-angle grid kept: a sizing search evaluates the same
    law on the same grid for every base radius and offset it tries (the law does not depend on them)."""

    def __init__(self, law: Displacement) -> None:
        self._law = law
        self._theta: np.ndarray | None = None
        self._values: tuple | None = None

    def __call__(self, theta: np.ndarray):
        theta = np.asarray(theta, dtype=float)
        if self._theta is None or self._theta.shape != theta.shape or not np.array_equal(self._theta, theta):
            # a motion program at the check grid's many angles: law(theta)'s values, the angles' layout
            # kept across programs at the same places (a lift sweep's failing designs search on one grid)
            kept = getattr(self._law, "at_kept_angles", None) if theta.ndim == 1 else None
            values = self._law(theta) if kept is None else kept(theta)
            self._theta, self._values = theta.copy(), tuple(np.asarray(v, dtype=float) for v in values)
        return self._values

    def __getattr__(self, name: str):  # breaks, break_continuity, peak values ... of the law itself
        return getattr(self._law, name)


def measure(follower: FollowerSpec, law: Displacement, check_step: float = DEFAULT_CHECK_STEP,
            theta: np.ndarray | None = None, stress: "ContactStressLimit | None" = None) -> DesignMeasures:
    """Largest pressure angle (overall, on the rise, on the return), smallest convex / concave
    radii of curvature of the profile, a roller's smallest pitch-curve radius, the failures of
    ``follower`` on ``law`` over the check grid (or the given cam angles ``theta``) and, with
    ``stress``, the peak Hertz stress at its speed."""
    theta = check_grid(law, check_step) if theta is None else theta
    k = kinematics(follower, law, theta)
    deg = np.degrees(theta)
    failures = [reason for reason, mask in profile_failures(follower, k) if mask.any()]
    alpha = np.abs(k.pressure_angle)
    i = int(np.argmax(alpha))
    rho = k.profile_radius
    convex = np.where(rho > 0, rho, np.inf)
    concave = np.where(rho < 0, -rho, np.inf)
    if follower.contact == "face":  # a flat face bridges any concave part: that is the undercut itself
        concave = np.full(theta.shape, np.inf)
    j, m = int(np.argmin(convex)), int(np.argmin(concave))
    ret = k.ds < 0  # the return: the follower comes back (s' < 0); the rise and the dwells elsewhere
    rise_alpha, ret_alpha = np.where(ret, 0.0, alpha), np.where(ret, alpha, 0.0)
    a, b = int(np.argmax(rise_alpha)), int(np.argmax(ret_alpha))
    pitch, p = math.inf, 0
    if follower.has_radius and k.pitch_curvature is not None:
        with np.errstate(divide="ignore"):
            pitch_radius = 1.0 / np.abs(k.pitch_curvature)
        p = int(np.argmin(pitch_radius))
        pitch = float(pitch_radius[p])
    peak, q = None, 0
    if stress is not None:
        from camgen.synthesis.sizing_stress import contact_stress

        peak, q = contact_stress(follower, k, stress.train, stress.material, stress.rpm) if not failures else (math.inf, 0)
    return DesignMeasures(float(alpha[i]), float(deg[i]), float(convex[j]), float(deg[j]), float(concave[m]), float(deg[m]), failures,
                          float(rise_alpha[a]), float(deg[a]), float(ret_alpha[b]), float(deg[b]), pitch, float(deg[p]), peak, float(deg[q]),
                          follower.roller_radius if follower.has_radius else 0.0)


@dataclass(frozen=True)
class SizingResult:
    """The smallest base radius found (mm; with the offset when that was searched too), the
    follower with it, and what that design achieves."""

    base_radius: float
    offset: float
    follower: FollowerSpec
    measures: DesignMeasures
    tol: float


def _feasible(follower: FollowerSpec, law: Displacement, limits: DesignLimits, theta: np.ndarray) -> bool:
    """Whether ``follower`` meets ``limits`` on ``law`` at the cam angles ``theta``: what
    ``not measure(follower, law, theta=theta, stress=limits.contact_stress).violations(limits)``
    says, from the same kinematics and the same comparisons of each measure with its limit (the
    extremes as np.max / np.min, which are the values measure takes at its argmax / argmin, a nan
    included), without the cam angles, the degrees or the sentences of the violations (a search
    asks only whether a trial passes)."""
    k = kinematics(follower, law, theta)
    if any(mask.any() for _, mask in profile_failures(follower, k)):
        return False
    stress = limits.contact_stress
    if stress is not None:  # measure computes it for a profile that can be made (and may raise)
        from camgen.synthesis.sizing_stress import contact_stress

        peak = contact_stress(follower, k, stress.train, stress.material, stress.rpm)[0]
        if peak is not None and not peak <= stress.allowable:
            return False
    alpha = np.abs(k.pressure_angle)
    if limits.max_pressure_angle_return is not None:
        ret = k.ds < 0
        if float(np.max(alpha, where=~ret, initial=0.0)) > limits.max_pressure_angle:  # measure's np.where(ret, 0.0, alpha)
            return False
        if float(np.max(alpha, where=ret, initial=0.0)) > limits.max_pressure_angle_return:  # np.where(ret, alpha, 0.0)
            return False
    elif float(np.max(alpha)) > limits.max_pressure_angle:
        return False
    roller_radius = follower.roller_radius if follower.has_radius else 0.0
    least_pitch = limits.min_pitch_radius_factor * roller_radius
    if least_pitch > 0 and follower.has_radius and k.pitch_curvature is not None:
        with np.errstate(divide="ignore"):
            pitch = float(np.min(1.0 / np.abs(k.pitch_curvature)))
        if not pitch >= least_pitch:
            return False
    rho = k.profile_radius
    if float(np.min(rho, where=rho > 0, initial=np.inf)) < limits.min_convex_radius:  # measure's np.where(rho > 0, rho, inf)
        return False
    # measure's least of np.where(rho < 0, -rho, inf): minus the largest negative radius (negation is exact)
    if follower.contact != "face" and -float(np.max(rho, where=rho < 0, initial=-np.inf)) < limits.min_concave_radius:
        return False
    return True


def _with_base(follower: FollowerSpec, base: float, offset: float | None = None) -> FollowerSpec | None:
    try:
        if offset is None:
            return replace(follower, base_radius=base)
        return replace(follower, base_radius=base, offset=offset)
    except ParameterError:
        return None


def _base_range(follower: FollowerSpec, offset: float) -> tuple[float, float | None]:
    """Open range of base radii the follower's other parameters allow (upper None: unbounded)."""
    r = follower.roller_radius
    if follower.motion == "translating":
        lo = max(0.0, abs(offset) - r) if follower.contact == "point" else 0.0
        return lo, None
    d = math.hypot(*follower.pivot_xy)
    if follower.contact == "face":
        f = follower.face_offset
        return max(0.0, -d - f), d - f
    return max(0.0, abs(d - follower.arm_length) - r), d - r


def _pressure_bound(follower: FollowerSpec, law: Displacement, limits: DesignLimits, theta: np.ndarray) -> float:
    """Translating roller / knife: the smallest base radius the pressure-angle limit alone allows,
    in closed form: ``|s' - sigma e| <= tan(limit) (d0 + s)`` for every cam angle, so
    ``d0 >= max(|s' - sigma e| / tan(limit) - s)`` and ``Rp = sqrt(d0^2 + e^2)`` (Norton, *Design of Machinery*, ch. 8)."""
    s, ds, _, _ = (np.asarray(x, dtype=float) for x in law(theta))
    e = follower.offset
    limit = np.full(theta.shape, limits.max_pressure_angle)
    if limits.max_pressure_angle_return is not None:  # the return's own limit where s' < 0
        limit = np.where(ds < 0, limits.max_pressure_angle_return, limit)
    d0 = float(np.max(np.abs(ds - follower.sigma * e) / np.tan(limit) - s))
    d0 = max(d0, float(np.max(-s)), 0.0)
    return math.hypot(d0, e) - follower.roller_radius


#: Largest base radius a search tries, mm (the largest ``base_radius_mm`` a scene may give).
MAX_BASE_RADIUS = 1e5


def feasible_intervals(ok: Callable[[float], bool], lo: float, hi: float, *, tol: float = DEFAULT_SIZE_TOL, scan: int = 32,
                       high_is_cap: bool = False) -> list[tuple[float, float]]:
    """Every run of values in the open range ``(lo, hi)`` at which ``ok`` holds, as the scan of
    ``scan`` equally spaced interior values finds them: ``[(low, high), ...]`` in increasing
    order, each end a value ``ok`` passed, within ``tol`` of one it failed (bisection between
    the last failing and the first passing scan value; the range's ends count as failing, no
    follower there) or, with ``high_is_cap``, ``hi`` itself when it passes (a stated cap on the
    range, not a geometric end).  A run narrower than the scan's spacing may be missed."""
    tol = require_positive("tol", tol)

    def bisect(bad: float, good: float) -> float:
        while abs(good - bad) > tol:
            mid = 0.5 * (bad + good)
            bad, good = (bad, mid) if ok(mid) else (mid, good)
        return good

    grid = lo + (hi - lo) * (np.arange(1, scan + 1) / (scan + 1))  # inside the open range
    feasible = [ok(float(b)) for b in grid]
    cap_passes = high_is_cap and ok(hi)
    runs: list[tuple[float, float]] = []
    i = 0
    while i < grid.size:
        if not feasible[i]:
            i += 1
            continue
        j = i
        while j + 1 < grid.size and feasible[j + 1]:
            j += 1
        low = bisect(float(grid[i - 1]) if i > 0 else lo, float(grid[i]))
        if j + 1 == grid.size and cap_passes:
            high = hi
        else:
            high = bisect(float(grid[j + 1]) if j + 1 < grid.size else hi, float(grid[j]))
        runs.append((low, high))
        i = j + 1
    return runs


def _search(follower: FollowerSpec, law: Displacement, limits: DesignLimits, tol: float, scan: int,
            upper: bool, theta: np.ndarray | None = None) -> tuple[list[tuple[float, float | None]], int]:
    """The runs of base radii meeting ``limits``: ([(lower end, upper end or None), ...], the base
    radii tried).  Both ends are feasible and within ``tol`` of an infeasible value; translating
    followers have one run whose upper end is None (no upper end is sought: the pressure angle
    falls and the radii of curvature grow with the base radius); oscillating followers every run
    the scan of the open range finds (only the first, its upper end None, when ``upper`` is False).
    ``theta``: the check grid of ``law`` when the caller has made it."""
    tol = require_positive("tol", tol)
    theta = check_grid(law, limits.check_step) if theta is None else theta
    offset = follower.offset
    lo, hi = _base_range(follower, offset)
    tried = 0

    def ok(base: float) -> bool:
        nonlocal tried
        tried += 1
        spec = _with_base(follower, base)
        return spec is not None and _feasible(spec, law, limits, theta)

    def bisect(bad: float, good: float) -> float:
        while abs(good - bad) > tol:
            mid = 0.5 * (bad + good)
            bad, good = (bad, mid) if ok(mid) else (mid, good)
        return good

    if hi is not None:  # oscillating: a bounded range, not monotonic
        if upper:
            runs = feasible_intervals(ok, lo, hi, tol=tol, scan=scan)
            if not runs:
                grid_top = lo + (hi - lo) * scan / (scan + 1)
                raise GeometryError(_no_base_message(follower, law, limits, theta, float(grid_top)))
            return [(a, b) for a, b in runs], tried
        grid = lo + (hi - lo) * (np.arange(1, scan + 1) / (scan + 1))
        feasible = [ok(float(b)) for b in grid]
        if not any(feasible):
            raise GeometryError(_no_base_message(follower, law, limits, theta, float(grid[-1])))
        k = int(np.argmax(feasible))
        return [(bisect(float(grid[k - 1]) if k > 0 else lo, float(grid[k])), None)], tried
    if follower.motion == "translating" and follower.contact == "point":
        bound = _pressure_bound(follower, law, limits, theta)
        if bound > MAX_BASE_RADIUS:
            raise GeometryError(_no_base_message(follower, law, limits, theta, MAX_BASE_RADIUS))
        if bound > lo:
            lo = bound
            start = bound * (1.0 + 1e-12) + 1e-12  # the bound itself meets the pressure limit with equality
            if ok(start):
                return [(start, None)], tried
    # the pressure angle falls and the radii of curvature grow with the base radius
    top = max(2.0 * lo, lo + 10.0 * tol, 1.0)
    while not ok(top):
        if top >= MAX_BASE_RADIUS:
            raise GeometryError(_no_base_message(follower, law, limits, theta, MAX_BASE_RADIUS))
        top = min(lo + 2.0 * (top - lo), MAX_BASE_RADIUS)
    grid = lo + (top - lo) * (np.arange(1, scan + 1) / scan)  # up to top, which is feasible
    feasible = [ok(float(b)) for b in grid]
    first = int(np.argmax(feasible))
    return [(bisect(float(grid[first - 1]) if first > 0 else lo, float(grid[first])), None)], tried


def min_base_radius(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                    tol: float = DEFAULT_SIZE_TOL, scan: int = 32) -> SizingResult:
    """The smallest base radius (mm, within ``tol``) at which ``follower`` (its other parameters
    kept) meets ``limits`` on ``law``.

    Translating followers: the search starts at the smallest base radius the geometry allows
    (``|offset| - roller_radius`` or 0), for rollers and knives at the closed-form bound of the
    pressure-angle limit, and doubles an upper end until a feasible design appears (up to
    :data:`MAX_BASE_RADIUS`); oscillating followers search the open range the pivot and arm
    allow.  ``scan`` points of the range are tried upwards and the first feasible one is
    bracketed by bisection.  Raises :class:`GeometryError` when no base radius works, naming
    what else to change.
    """
    law = law if isinstance(law, _SampledLaw) else _SampledLaw(law)
    runs, _ = _search(follower, law, limits, tol, scan, upper=False)
    low = runs[0][0]
    spec = _with_base(follower, low)
    assert spec is not None  # the search returns a base radius that passed: its spec was valid
    return SizingResult(float(low), follower.offset, spec, measure(spec, law, limits.check_step, stress=limits.contact_stress), tol)


@dataclass(frozen=True)
class BaseRadiusAdvice:
    """Base radii (mm) that meet the design limits, each quoted value tried and found to pass.

    ``low``: the least base radius of the first run that passes; ``high``: the largest of that
    run, or None when it has no upper end (translating followers: the pressure angle only falls
    and the radii of curvature grow with the base radius).  Both are rounded inwards to
    ``digits`` decimals when the rounded value passes too, else quoted as found (``text``
    prints them exactly).  An oscillating follower's pressure angle is not monotonic in the base
    radius (it falls, then rises again as the cam grows towards the pivot): its passing base
    radii are an interval, bounded on both sides, or several (``more``: the further runs,
    ``(low, high)`` each, in increasing order, quoted and tried the same way).  ``tried``: the
    base radii evaluated.
    """

    low: float
    high: float | None
    tried: int
    digits: int = 3
    step: float | None = None  #: spacing of the base radii tried between low and high (mm), oscillating followers
    more: tuple[tuple[float, float], ...] = ()

    def number(self, value: float) -> str:
        """``value`` as the message prints it: ``digits`` decimals if that is exact, else the
        shortest text that reads back as ``value``."""
        text = f"{value:.{self.digits}f}"
        return text if float(text) == value else repr(value)

    def text(self, current: float) -> str:
        """What to set: "increase base_radius_mm to at least 43.935" or "set base_radius_mm
        between 42.039 and 54.321" (``current``: the base radius the design has)."""
        if self.high is None:
            verb = "increase" if self.low > current else "set"
            return f"{verb} base_radius_mm to at least {self.number(self.low)}"
        return f"set base_radius_mm between {self.number(self.low)} and {self.number(self.high)}" + "".join(
            f", or between {self.number(a)} and {self.number(b)}" for a, b in self.more)


def base_radius_advice(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                       tol: float = DEFAULT_SIZE_TOL, scan: int = 32, digits: int = 3) -> BaseRadiusAdvice:
    """The base radii to quote in a hint (:class:`BaseRadiusAdvice`): the first run of passing
    base radii found by the search of :func:`min_base_radius` (and, for oscillating followers,
    its upper end by bisection too), each end rounded inwards to ``digits`` decimals and tried
    again at the rounded value.  Raises :class:`GeometryError` when no base radius passes.

    The advice does not depend on ``follower.base_radius`` (every radius tried replaces it): the
    last few advices are kept (:mod:`camgen.synthesis.advice_cache`), so the
    failing designs of a sweep that changes only the base radius (or keys the search does not
    read: speed, dynamics, machining) share one search when their laws are equal (the same
    object, or motion programs of equal segments)."""
    from camgen.synthesis.advice_cache import cached_advice

    return cached_advice(_advice_search, follower, law, limits, tol, scan, digits)


def _advice_search(follower: FollowerSpec, law: Displacement, limits: DesignLimits, tol: float, scan: int,
                   digits: int) -> BaseRadiusAdvice:
    """:func:`base_radius_advice` computed (no cache)."""
    law = law if isinstance(law, _SampledLaw) else _SampledLaw(law)
    theta = check_grid(law, limits.check_step)
    runs, tried = _search(follower, law, limits, tol, scan, upper=True, theta=theta)

    def passes(base: float) -> bool:
        nonlocal tried
        tried += 1
        spec = _with_base(follower, base)
        return spec is not None and _feasible(spec, law, limits, theta)

    scale = 10.0**digits
    quoted: list[tuple[float, float | None]] = []
    for low, high in runs:
        up = math.ceil(low * scale - 1e-9) / scale
        low = up if (high is None or up <= high) and passes(up) else low
        if high is not None:
            down = math.floor(high * scale + 1e-9) / scale
            high = down if down >= low and passes(down) else high
        quoted.append((float(low), None if high is None else float(high)))
    (low, high), rest = quoted[0], quoted[1:]
    step = None
    if high is not None:
        lo, hi = _base_range(follower, follower.offset)
        assert hi is not None  # an upper end is sought only for oscillating followers, whose range is bounded
        step = (hi - lo) / (scan + 1)
    more = tuple((a, b) for a, b in rest if b is not None)
    return BaseRadiusAdvice(low, high, tried, digits, step, more)


@dataclass(frozen=True)
class Intervals:
    """The values of one follower parameter (``name``, mm) at which the design meets the limits,
    the others kept: ``runs`` of ``(low, high)`` in increasing order (each end tried and found to
    pass, within ``tol`` of one that fails, rounded inwards to 0.001 mm where the rounded value
    passes too), over the open ``searched`` range; ``tried``: the designs evaluated."""

    name: str
    runs: tuple[tuple[float, float], ...]
    searched: tuple[float, float]
    tried: int

    def text(self) -> str:
        """The runs as a hint prints them: ``roller_radius between 3.2 and 9.125 mm, or between ...``
        (or that none passes)."""
        if not self.runs:
            return f"no {self.name} in ({self.searched[0]:.6g}, {self.searched[1]:.6g}) mm meets the limits"
        return f"{self.name} between " + ", or between ".join(f"{_quoted(a)} and {_quoted(b)}" for a, b in self.runs) + " mm"


def _quoted(value: float, digits: int = 3) -> str:
    text = f"{value:.{digits}f}"
    return text if float(text) == value else repr(value)


def _intervals(name: str, make: Callable[[float], FollowerSpec | None], law: Displacement, limits: DesignLimits, lo: float, hi: float,
               tol: float, scan: int, high_is_cap: bool = False, digits: int = 3) -> Intervals:
    law = law if isinstance(law, _SampledLaw) else _SampledLaw(law)
    theta = check_grid(law, limits.check_step)
    tried = 0

    def ok(value: float) -> bool:
        nonlocal tried
        tried += 1
        try:
            spec = make(value)
        except (ParameterError, GeometryError):  # no follower with that value (the arm cannot reach the prime circle)
            return False
        return spec is not None and _feasible(spec, law, limits, theta)

    runs = []
    scale = 10.0**digits
    for low, high in feasible_intervals(ok, lo, hi, tol=tol, scan=scan, high_is_cap=high_is_cap):
        up, down = math.ceil(low * scale - 1e-9) / scale, math.floor(high * scale + 1e-9) / scale
        low = up if up <= high and ok(up) else low
        high = down if down >= low and ok(down) else high
        runs.append((float(low), float(high)))
    return Intervals(name, tuple(runs), (lo, hi), tried)


def base_radius_intervals(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                          tol: float = DEFAULT_SIZE_TOL, scan: int = 64) -> Intervals:
    """Oscillating followers: every run of base radii (mm) in the open range the pivot and arm
    allow at which ``follower`` meets ``limits`` (:func:`feasible_intervals`)."""
    if follower.motion != "oscillating":
        raise ParameterError("follower", follower.motion, "an oscillating follower (a translating one's base radii have no upper end: "
                             "min_base_radius)")
    lo, hi = _base_range(follower, follower.offset)
    assert hi is not None  # an oscillating follower's range is bounded
    return _intervals("base_radius", lambda b: _with_base(follower, b), law, limits, lo, hi, tol, scan)


def roller_radius_intervals(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                            largest: float | None = None, tol: float = DEFAULT_SIZE_TOL, scan: int = 64) -> Intervals:
    """The roller radii (mm) at which ``follower`` (its base radius and the rest kept) meets
    ``limits``: the least end is set by the contact stress (a larger roller carries the load at
    a lower stress), the largest by the curvature (a larger roller needs a flatter pitch curve:
    the undercut and Norton's rule) or, for an oscillating arm, by the pivot.  Searched over
    ``(0, largest)``: ``largest`` defaults to the base radius (translating: stated, a cap the
    answer may reach) or ``pivot distance - base radius`` (oscillating: the roller reaches the
    pivot there)."""
    if not follower.has_radius:
        raise ParameterError("follower", follower.kind, "a roller follower (a point contact with a radius)")
    cap = largest is not None or follower.motion == "translating"
    if largest is None:
        largest = follower.base_radius if follower.motion == "translating" else math.hypot(*follower.pivot_xy) - follower.base_radius
    largest = require_positive("largest", largest, "mm")
    return _intervals("roller_radius", lambda r: replace(follower, roller_radius=r), law, limits, 0.0, largest, tol, scan, high_is_cap=cap)


def arm_length_intervals(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                         tol: float = DEFAULT_SIZE_TOL, scan: int = 64) -> Intervals:
    """Oscillating roller or knife: the arm lengths (mm; pivot, base radius and roller kept) at
    which ``follower`` meets ``limits``, over the open range in which the arm reaches the prime
    circle, ``|d - L| < Rb + r`` (``d`` the pivot's distance from the cam axis)."""
    if follower.motion != "oscillating" or follower.contact != "point":
        raise ParameterError("follower", f"{follower.motion} {follower.kind}", "an oscillating roller or knife (an arm to a point contact)")
    d, rp = math.hypot(*follower.pivot_xy), follower.base_radius + follower.roller_radius
    return _intervals("arm_length", lambda arm: replace(follower, arm_length=arm), law, limits, max(0.0, d - rp), d + rp, tol, scan)


def pivot_distance_intervals(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                             tol: float = DEFAULT_SIZE_TOL, scan: int = 64) -> Intervals:
    """Oscillating roller or knife: the pivot's distances from the cam axis (mm; the pivot moved
    along its own direction from the axis, base radius, arm and roller kept) at which
    ``follower`` meets ``limits``, over the open range ``d > Rb + r`` and ``|d - L| < Rb + r``."""
    if follower.motion != "oscillating" or follower.contact != "point":
        raise ParameterError("follower", f"{follower.motion} {follower.kind}", "an oscillating roller or knife (an arm to a point contact)")
    px, py = follower.pivot_xy
    d0 = math.hypot(px, py)
    rp = follower.base_radius + follower.roller_radius
    lo, hi = max(rp, follower.arm_length - rp), follower.arm_length + rp

    def at(d: float) -> FollowerSpec:
        return replace(follower, pivot=(px * d / d0, py * d / d0))

    return _intervals("pivot_distance", at, law, limits, lo, hi, tol, scan)


def _no_base_message(follower: FollowerSpec, law: Displacement, limits: DesignLimits, theta: np.ndarray, largest: float) -> str:
    spec = _with_base(follower, largest)
    why = "; ".join(measure(spec, law, theta=theta, stress=limits.contact_stress).violations(limits)) if spec is not None else "invalid geometry"
    if follower.motion == "oscillating":
        change = ("move the pivot farther from the cam axis or change arm_length" if follower.contact == "point"
                  else "move the pivot or change face_offset")
        return f"no base radius the pivot and arm allow meets the limits ({why} at base_radius_mm = {largest:.6g}): {change}, or relax the limits"
    return f"no base radius up to {largest:.6g} mm meets the limits ({why}): change the roller radius, the offset or the limits"


def min_base_radius_and_offset(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                               offset_range: tuple[float, float] | None = None, tol: float = DEFAULT_SIZE_TOL,
                               offsets: int = 21) -> SizingResult:
    """Translating roller or knife: the offset (mm) in ``offset_range`` and base radius that give the
    smallest base radius meeting ``limits``.

    ``offset_range`` defaults to ``+-`` the base radius found for a centred follower.  The offsets
    are scanned at ``offsets`` points, then the best one is refined by golden-section search in the
    bracket around it (the minimum base radius is assumed unimodal in the offset there) to ``tol``.
    """
    if follower.motion != "translating" or follower.contact != "point":
        raise ParameterError("follower", f"{follower.motion} {follower.kind}", "a translating roller or knife (a point contact: the offset of a face does not change the cam)")
    tol = require_positive("tol", tol)
    law = _SampledLaw(law)
    centred = min_base_radius(replace(follower, offset=0.0), law, limits, tol=tol)
    if offset_range is None:
        offset_range = (-centred.base_radius, centred.base_radius)
    e_lo, e_hi = (require_finite("offset_range", v) for v in offset_range)
    if not e_lo < e_hi:
        raise ParameterError("offset_range", offset_range, "(low, high) with low < high, mm")

    def best_base(e: float) -> float:
        try:
            return min_base_radius(replace(follower, offset=e, base_radius=abs(e) + 1.0),
                                   law, limits, tol=tol).base_radius
        except GeometryError:
            return math.inf

    grid = np.linspace(e_lo, e_hi, offsets)
    values = np.array([best_base(e) for e in grid])
    k = int(np.argmin(values))
    a, b = grid[max(0, k - 1)], grid[min(offsets - 1, k + 1)]
    (c, fc), (d, fd) = golden_section(best_base, a, b, tol=tol, max_steps=10_000)
    candidates = [(values[k], grid[k]), (fc, c), (fd, d)]
    base, e = min(candidates)
    if not math.isfinite(base):
        raise GeometryError("no offset in the range meets the limits: widen offset_range or relax the limits")
    spec = _with_base(follower, base, e)
    assert spec is not None  # base and e came from the candidates that passed: a valid spec
    return SizingResult(float(base), float(e), spec, measure(spec, law, limits.check_step, stress=limits.contact_stress), tol)


def require_design(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits()) -> DesignMeasures:
    """The design's measures if it meets ``limits``; else a :class:`GeometryError` that says what
    breaks and which values of ``base_radius_mm`` would work, each tried (:func:`base_radius_advice`:
    "increase base_radius_mm to at least 42.317", "set base_radius_mm between 42.039 and
    54.321"), or what else to change when no base radius does."""
    theta = check_grid(law, limits.check_step)
    m = measure(follower, law, theta=theta, stress=limits.contact_stress)
    broken = m.violations(limits)
    if not broken:
        return m
    what = "; ".join(broken)
    try:
        advice = base_radius_advice(follower, law, limits)
    except GeometryError as exc:
        raise GeometryError(f"the cam breaks the design limits ({what}) and {exc}") from None
    raise GeometryError(f"the cam breaks the design limits ({what}): {advice.text(follower.base_radius)}")


@dataclass(frozen=True)
class FaceWidth:
    """Extent of the contact on a flat face, mm.

    Translating: ``left`` and ``right`` are the distances from the face centre (on the follower
    axis) to the farthest contact towards ``-x`` and ``+x`` (0 if the contact never goes that
    way); the face must reach at least that far on each side.  Oscillating: ``left`` / ``right``
    are the nearest and farthest contact distances along the face from the foot of the pivot's
    perpendicular (``xi``, positive along ``J w``).  ``left_deg`` / ``right_deg``: cam angles where
    they occur.  ``width`` = the length of face the contact uses.  ``margin``: the clearance
    asked beyond the contact at each end (mm); ``half_length``: the least face half-length that
    holds the contact with that margin (the ``face_length`` check's measure: translating, about
    the face centre, ``max(left, right) + margin``; oscillating, about the middle of the
    contact's range, ``width / 2 + margin``).
    """

    left: float
    right: float
    left_deg: float
    right_deg: float
    width: float
    margin: float = 0.0
    half_length: float = 0.0


def face_width(follower: FollowerSpec, law: Displacement, check_step: float = DEFAULT_CHECK_STEP, margin: float = 0.0) -> FaceWidth:
    """The face extent a flat follower needs with ``margin`` mm of clearance beyond the contact
    at each end (see :class:`FaceWidth`)."""
    if require_finite("margin", margin) < 0:
        raise ParameterError("margin", margin, "margin >= 0 mm")
    if follower.contact != "face":
        raise ParameterError("follower", follower.kind, "a flat follower (a face contact)")
    theta = check_grid(law, check_step)
    xi = kinematics(follower, law, theta).face_position
    assert xi is not None  # a flat face's Kinematics carry the contact's position on the face
    deg = np.degrees(theta)
    i, j = int(np.argmin(xi)), int(np.argmax(xi))
    if follower.motion == "translating":
        left, right = max(0.0, -float(xi[i])), max(0.0, float(xi[j]))
        return FaceWidth(left, right, float(deg[i]), float(deg[j]), left + right, margin, max(left, right) + margin)
    width = float(xi[j] - xi[i])
    return FaceWidth(float(xi[i]), float(xi[j]), float(deg[i]), float(deg[j]), width, margin, 0.5 * width + margin)
