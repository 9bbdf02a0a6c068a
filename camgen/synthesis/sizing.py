"""Sizing of disk cams: the smallest base radius (and offset) that meets the design limits.

A design is *feasible* when the profile can be made (no undercut, cusp or backward-turning face,
see :func:`camgen.synthesis.followers.cam_envelope`) and, on the dense cam-angle grid of
:func:`camgen.synthesis.followers.check_grid`,

* the largest ``|pressure angle|`` is ``<= max_pressure_angle``;
* the smallest convex radius of curvature of the profile is ``>= min_convex_radius`` (for a
  roller ``rho_pitch - r``: a margin over the roller radius on the pitch curve);
* the smallest concave radius of curvature of the profile is ``>= min_concave_radius`` (the
  cutter radius: a concave part tighter than the tool cannot be cut); a flat face allows no
  concave part at all.

All quantities come from the closed forms of :func:`camgen.synthesis.followers.kinematics`.
The base radius is searched by a scan over the valid range followed by bisection between the
last infeasible and the first feasible value, to ``tol`` mm; the value returned is feasible.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

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
    "BaseRadiusAdvice", "DEFAULT_SIZE_TOL", "DesignLimits", "DesignMeasures", "FaceWidth", "MAX_BASE_RADIUS",
    "SizingResult", "base_radius_advice", "face_width", "measure", "min_base_radius", "min_base_radius_and_offset",
    "require_design",
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
    """

    max_pressure_angle: float = math.radians(30.0)
    min_convex_radius: float = 0.0
    min_concave_radius: float = 0.0
    check_step: float = DEFAULT_CHECK_STEP

    def __post_init__(self) -> None:
        a = require_finite("max_pressure_angle", self.max_pressure_angle)
        if not 0.0 < a < math.pi / 2:
            raise ParameterError("max_pressure_angle", a, "0 < max_pressure_angle < pi/2 rad (0 to 90 deg)")
        for name in ("min_convex_radius", "min_concave_radius"):
            if require_finite(name, getattr(self, name)) < 0:
                raise ParameterError(name, getattr(self, name), f"{name} >= 0 mm")
        require_positive("check_step", self.check_step, "rad")


@dataclass(frozen=True)
class DesignMeasures:
    """What a design achieves on the check grid.

    ``max_pressure_angle`` (rad, of ``|alpha|``), ``min_convex_radius`` / ``min_concave_radius``
    (mm, of the profile; ``inf`` when there is no such part), each with the cam angle (deg) where
    it occurs; ``failures``: the reasons the profile cannot be made (empty when it can).
    """

    max_pressure_angle: float
    max_pressure_angle_deg_at: float
    min_convex_radius: float
    min_convex_radius_deg_at: float
    min_concave_radius: float
    min_concave_radius_deg_at: float
    failures: list[str] = field(default_factory=list)

    def violations(self, limits: DesignLimits) -> list[str]:
        """One sentence per limit the design breaks (empty: feasible)."""
        out = list(self.failures)
        if self.max_pressure_angle > limits.max_pressure_angle:
            out.append(f"pressure angle {math.degrees(self.max_pressure_angle):.4g} deg > {math.degrees(limits.max_pressure_angle):.4g} deg "
                       f"at cam angle {self.max_pressure_angle_deg_at:.3f} deg")
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
            self._theta, self._values = theta.copy(), tuple(np.asarray(v, dtype=float) for v in self._law(theta))
        return self._values

    def __getattr__(self, name: str):  # breaks, break_continuity, peak values ... of the law itself
        return getattr(self._law, name)


def measure(follower: FollowerSpec, law: Displacement, check_step: float = DEFAULT_CHECK_STEP,
            theta: np.ndarray | None = None) -> DesignMeasures:
    """Largest pressure angle, smallest convex / concave radii of curvature of the profile and the
    failures of ``follower`` on ``law`` over the check grid (or the given cam angles ``theta``)."""
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
    return DesignMeasures(float(alpha[i]), float(deg[i]), float(convex[j]), float(deg[j]), float(concave[m]), float(deg[m]), failures)


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
    return not measure(follower, law, theta=theta).violations(limits)


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
    d0 = float(np.max(np.abs(ds - follower.sigma * e) / math.tan(limits.max_pressure_angle) - s))
    d0 = max(d0, float(np.max(-s)), 0.0)
    return math.hypot(d0, e) - follower.roller_radius


#: Largest base radius a search tries, mm (the largest ``base_radius_mm`` a scene may give).
MAX_BASE_RADIUS = 1e5


def _search(follower: FollowerSpec, law: Displacement, limits: DesignLimits, tol: float, scan: int,
            upper: bool) -> tuple[float, float | None, int]:
    """The first run of base radii meeting ``limits``: (its lower end, its upper end or None,
    the base radii tried).  Both ends are feasible and within ``tol`` of an infeasible value;
    the upper end is None for translating followers (no upper end is sought: the pressure angle
    falls and the radii of curvature grow with the base radius) or when ``upper`` is False."""
    tol = require_positive("tol", tol)
    theta = check_grid(law, limits.check_step)
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

    if follower.motion == "translating" and follower.contact == "point":
        bound = _pressure_bound(follower, law, limits, theta)
        if bound > MAX_BASE_RADIUS:
            raise GeometryError(_no_base_message(follower, law, limits, theta, MAX_BASE_RADIUS))
        if bound > lo:
            lo = bound
            first = bound * (1.0 + 1e-12) + 1e-12  # the bound itself meets the pressure limit with equality
            if ok(first):
                return first, None, tried
    if hi is None:  # the pressure angle falls and the radii of curvature grow with the base radius
        hi = max(2.0 * lo, lo + 10.0 * tol, 1.0)
        while not ok(hi):
            if hi >= MAX_BASE_RADIUS:
                raise GeometryError(_no_base_message(follower, law, limits, theta, MAX_BASE_RADIUS))
            hi = min(lo + 2.0 * (hi - lo), MAX_BASE_RADIUS)
        grid = lo + (hi - lo) * (np.arange(1, scan + 1) / scan)  # up to hi, which is feasible
        top = None
    else:
        grid = lo + (hi - lo) * (np.arange(1, scan + 1) / (scan + 1))  # inside the open range
        top = hi
    feasible = [ok(b) for b in grid]
    if not any(feasible):
        raise GeometryError(_no_base_message(follower, law, limits, theta, float(grid[-1])))
    first = int(np.argmax(feasible))
    low = bisect(grid[first - 1] if first > 0 else lo, grid[first])
    if top is None or not upper:
        return low, None, tried
    last = first
    while last + 1 < grid.size and feasible[last + 1]:
        last += 1
    beyond = float(grid[last + 1]) if last + 1 < grid.size else top  # infeasible (the range's end: no follower)
    return low, bisect(beyond, float(grid[last])), tried


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
    low, _, _ = _search(follower, law, limits, tol, scan, upper=False)
    spec = _with_base(follower, low)
    assert spec is not None  # the search returns a base radius that passed: its spec was valid
    return SizingResult(float(low), follower.offset, spec, measure(spec, law, limits.check_step), tol)


@dataclass(frozen=True)
class BaseRadiusAdvice:
    """Base radii (mm) that meet the design limits, each quoted value tried and found to pass.

    ``low``: the least base radius of the first run that passes; ``high``: the largest of that
    run, or None when it has no upper end (translating followers: the pressure angle only falls
    and the radii of curvature grow with the base radius).  Both are rounded inwards to
    ``digits`` decimals when the rounded value passes too, else quoted as found (``text``
    prints them exactly).  An oscillating follower's pressure angle is not monotonic in the base
    radius (it falls, then rises again as the cam grows towards the pivot): its passing base
    radii are an interval, bounded on both sides.  ``tried``: the base radii evaluated.
    """

    low: float
    high: float | None
    tried: int
    digits: int = 3
    step: float | None = None  #: spacing of the base radii tried between low and high (mm), oscillating followers

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
        return f"set base_radius_mm between {self.number(self.low)} and {self.number(self.high)}"


def base_radius_advice(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits(), *,
                       tol: float = DEFAULT_SIZE_TOL, scan: int = 32, digits: int = 3) -> BaseRadiusAdvice:
    """The base radii to quote in a hint (:class:`BaseRadiusAdvice`): the first run of passing
    base radii found by the search of :func:`min_base_radius` (and, for oscillating followers,
    its upper end by bisection too), each end rounded inwards to ``digits`` decimals and tried
    again at the rounded value.  Raises :class:`GeometryError` when no base radius passes."""
    law = law if isinstance(law, _SampledLaw) else _SampledLaw(law)
    theta = check_grid(law, limits.check_step)
    low, high, tried = _search(follower, law, limits, tol, scan, upper=True)

    def passes(base: float) -> bool:
        nonlocal tried
        tried += 1
        spec = _with_base(follower, base)
        return spec is not None and _feasible(spec, law, limits, theta)

    scale = 10.0**digits
    up = math.ceil(low * scale - 1e-9) / scale
    low = up if (high is None or up <= high) and passes(up) else low
    if high is not None:
        down = math.floor(high * scale + 1e-9) / scale
        high = down if down >= low and passes(down) else high
    step = None
    if high is not None:
        lo, hi = _base_range(follower, follower.offset)
        assert hi is not None  # an upper end is sought only for oscillating followers, whose range is bounded
        step = (hi - lo) / (scan + 1)
    return BaseRadiusAdvice(float(low), None if high is None else float(high), tried, digits, step)


def _no_base_message(follower: FollowerSpec, law: Displacement, limits: DesignLimits, theta: np.ndarray, largest: float) -> str:
    spec = _with_base(follower, largest)
    why = "; ".join(measure(spec, law, theta=theta).violations(limits)) if spec is not None else "invalid geometry"
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
    return SizingResult(float(base), float(e), spec, measure(spec, law, limits.check_step), tol)


def require_design(follower: FollowerSpec, law: Displacement, limits: DesignLimits = DesignLimits()) -> DesignMeasures:
    """The design's measures if it meets ``limits``; else a :class:`GeometryError` that says what
    breaks and which values of ``base_radius_mm`` would work, each tried (:func:`base_radius_advice`:
    "increase base_radius_mm to at least 42.317", "set base_radius_mm between 42.039 and
    54.321"), or what else to change when no base radius does."""
    theta = check_grid(law, limits.check_step)
    m = measure(follower, law, theta=theta)
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
    they occur.  ``width`` = the length of face the contact uses.
    """

    left: float
    right: float
    left_deg: float
    right_deg: float
    width: float


def face_width(follower: FollowerSpec, law: Displacement, check_step: float = DEFAULT_CHECK_STEP) -> FaceWidth:
    """The face extent a flat follower needs (see :class:`FaceWidth`); add a clearance to it."""
    if follower.contact != "face":
        raise ParameterError("follower", follower.kind, "a flat follower (a face contact)")
    theta = check_grid(law, check_step)
    xi = kinematics(follower, law, theta).face_position
    assert xi is not None  # a flat face's Kinematics carry the contact's position on the face
    deg = np.degrees(theta)
    i, j = int(np.argmin(xi)), int(np.argmax(xi))
    if follower.motion == "translating":
        left, right = max(0.0, -float(xi[i])), max(0.0, float(xi[j]))
        return FaceWidth(left, right, float(deg[i]), float(deg[j]), left + right)
    return FaceWidth(float(xi[i]), float(xi[j]), float(deg[i]), float(deg[j]), float(xi[j] - xi[i]))
