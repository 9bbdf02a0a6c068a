"""Cam-follower dynamics: contact force, jump, camshaft torque and Hertz stress over one cam turn.

The model is the classic rigid-body one (Rothbart, *Cam Design Handbook*, McGraw-Hill 2004,
ch. 8 "Cam mechanism forces"): the cam turns at a constant speed ``w``; the
follower train is one rigid body with one coordinate ``q`` (translating: the follower's travel
``s``, mm; oscillating: the arm angle ``psi``, rad), pressed onto the cam by a spring, loads
and gravity; the contact has no friction.  All kinematics are given per radian of cam angle
(``q' = dq/dtheta``, ``q'' = d2q/dtheta2``), so at speed ``w`` the follower velocity is
``w q'`` and its acceleration ``w^2 q''``.

The generalised force the cam must supply along ``q`` (N for a translating follower, N*mm
about the pivot for an oscillating one) is

    Q(theta) = M w^2 q'' + C w q' + K (q - q_min) + P0 + L(theta) + G(theta)

with the inertia ``M``, viscous damping ``C``, spring rate ``K`` and preload ``P0`` (the
spring force at the follower's lowest position ``q_min``), the external load ``L`` and the
weight's component ``G`` against the motion.  Along the common normal the contact carries
``F = Q / (lever cos(phi))`` (``phi`` the pressure angle, ``lever`` 1 for a translating
follower and the arm length for an oscillating one: the normal through the roller centre
passes ``arm cos(phi)`` from the pivot).

* Jump: the follower leaves the cam where ``F <= 0``.  ``Q`` is a quadratic in ``w`` at every
  cam angle, so the speed at which the contact force first reaches a margin is the smallest
  positive root over the samples, found in closed form (:func:`jump_speed`), not by scanning.
* Camshaft torque, from the power balance: with a frictionless contact the cam's input power
  ``T w`` equals the power the contact delivers to the follower, ``Q w q'``, so ``T = Q q'``
  exactly, for every follower type, without the contact point's lever (which the tests check
  against the lever computed from the contact geometry).
* Hertz line-contact stress (Rothbart, eq. 9.11; two cylinders with parallel axes):
  ``p_max = sqrt(F (1/rho_cam + 1/rho_follower) / (pi b ((1-nu_c^2)/E_c + (1-nu_f^2)/E_f)))``,
  with the signed radius of curvature of the *profile* (not of the pitch curve) at the contact:
  a concave profile point (``rho_cam < 0``) gives the conformal contact, a flat face
  (``rho_follower = inf``) the cam's radius alone.
* Form-closed trains (yoke on a constant-breadth cam, conjugate cams): no spring; the net
  force ``Q`` is carried by contact 1 (pushing along +q) where ``Q > 0`` and by contact 2 where
  ``Q < 0``; there is no jump, both contacts are Hertz-checked.

Units: at the edge (the dataclass fields) kg, kg*m^2, N/mm, N*s/m, GPa, m/s^2 as documented;
inside mm, rad, s, N, N*mm, MPa, converted with the named constants below.  Results: forces
N, torque N*m, power W, stress MPa, speeds rpm.
"""
from __future__ import annotations

import functools
import math
import threading
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Callable, ParamSpec, TypeVar, cast

import numpy as np

from camgen.checks import run_ends
from camgen.errors import GeometryError, ParameterError, floor_significant, require_finite

__all__ = [
    "CLOSURES", "ContactMaterial", "DynamicsResult", "FollowerTrain", "GPA_TO_MPA", "KG_M2_PER_S2_TO_N_MM",
    "KG_MM_PER_S2_TO_N", "Kinematics", "MOTIONS", "N_MM_TO_N_M", "N_M_TO_N_MM", "N_S_PER_M_TIMES_MM_PER_S_TO_N",
    "RPM_TO_RAD_PER_S", "STANDARD_GRAVITY", "analyse", "force_coefficients", "hertz_line_stress", "jump_speed",
    "min_contact_force", "smallest_positive_root", "spring_hints",
]

TWO_PI = 2.0 * math.pi
MOTIONS = ("translating", "oscillating")
CLOSURES = ("force", "form")

#: kg * mm/s^2 -> N (1 N = 1 kg*m/s^2 = 1e3 kg*mm/s^2).
KG_MM_PER_S2_TO_N = 1e-3
#: kg*m^2 * rad/s^2 -> N*mm (1 kg*m^2/s^2 = 1 N*m = 1e3 N*mm).
KG_M2_PER_S2_TO_N_MM = 1e3
#: N*s/m * mm/s -> N.
N_S_PER_M_TIMES_MM_PER_S_TO_N = 1e-3
#: N*m*s/rad * rad/s -> N*mm.
N_M_TO_N_MM = 1e3
#: N*mm -> N*m.
N_MM_TO_N_M = 1e-3
#: GPa -> MPa.
GPA_TO_MPA = 1e3
#: rev/min -> rad/s.
RPM_TO_RAD_PER_S = TWO_PI / 60.0
#: Standard gravity, m/s^2 (the default of :attr:`FollowerTrain.gravity`).
STANDARD_GRAVITY = 9.80665


def _nonnegative(name: str, value: Any, unit: str) -> float:
    number = require_finite(name, value)
    if number < 0:
        raise ParameterError(name, value, f"{name} >= 0 {unit}")
    return number


# --------------------------------------------------------------------------------------------
# Inputs
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class FollowerTrain:
    """The follower train: inertia, spring, damping, loads, gravity.

    Attributes
    ----------
    motion : ``"translating"`` or ``"oscillating"``.
    closure : ``"force"`` (a spring keeps the follower on the cam) or ``"form"`` (yoke on a
        constant-breadth cam, conjugate cams: two contacts, no spring).
    mass : kg.  Translating: the effective moving mass (follower, roller, a third of the
        spring), used for inertia and weight.  Oscillating: the arm's mass, used for its weight
        only (its inertia is ``inertia``).
    inertia : kg*m^2, oscillating: moment of inertia of the arm (with roller) about the pivot.
    arm_length : mm, oscillating: pivot to the roller centre (or contact point).
    cg_distance : mm, oscillating: pivot to the arm's centre of mass, measured along the arm
        towards the roller (for its weight).
    spring_rate : translating N/mm; oscillating N*mm/rad (torsional).
    preload : translating N; oscillating N*mm: the spring force (torque) at the follower's
        lowest position.  None: from the spring lengths, or 0.
    spring_free_length, spring_installed_length : mm, translating: the spring's free length
        and its length with the follower at its lowest position (preload
        ``rate * (free - installed)``); give these or ``preload``, not both.
    damping : translating N*s/m; oscillating N*m*s/rad (viscous, on the follower coordinate).
    load : the external load against the motion (pressing the follower onto the cam):
        translating N, oscillating N*mm; a constant, or a table ``(angles, values)`` over cam
        angle (rad, strictly increasing in [0, 2 pi); interpolated linearly, periodically).
    gravity : m/s^2 (0 to ignore weight).
    gravity_angle : rad, direction of gravity in the fixed frame, counter-clockwise from +x
        (default -pi/2: down, -y).
    """

    motion: str = "translating"
    closure: str = "force"
    mass: float = 0.0
    inertia: float = 0.0
    arm_length: float = 0.0
    cg_distance: float = 0.0
    spring_rate: float = 0.0
    preload: float | None = None
    spring_free_length: float | None = None
    spring_installed_length: float | None = None
    damping: float = 0.0
    load: float | tuple[Sequence[float], Sequence[float]] = 0.0
    gravity: float = STANDARD_GRAVITY
    gravity_angle: float = -math.pi / 2

    def __post_init__(self) -> None:
        if self.motion not in MOTIONS:
            raise ParameterError("follower_motion", self.motion, f"one of {MOTIONS}")
        if self.closure not in CLOSURES:
            raise ParameterError("closure", self.closure, f"one of {CLOSURES}")
        _nonnegative("mass", self.mass, "kg")
        _nonnegative("inertia", self.inertia, "kg*m^2")
        _nonnegative("spring_rate", self.spring_rate, "N/mm" if self.motion == "translating" else "N*mm/rad")
        _nonnegative("damping", self.damping, "N*s/m" if self.motion == "translating" else "N*m*s/rad")
        _nonnegative("gravity", self.gravity, "m/s^2")
        require_finite("gravity_angle", self.gravity_angle)
        require_finite("cg_distance", self.cg_distance)
        if self.motion == "oscillating" and not require_finite("arm_length", self.arm_length) > 0:
            raise ParameterError("arm_length", self.arm_length, "arm_length > 0 mm for an oscillating follower")
        lengths = (self.spring_free_length, self.spring_installed_length)
        if any(v is not None for v in lengths):
            if self.motion != "translating":
                raise ParameterError("spring_free_length", self.spring_free_length,
                                     "absent for an oscillating follower (give the preload torque, N*mm)")
            if None in lengths:
                raise ParameterError("spring_installed_length", self.spring_installed_length,
                                     "given together with spring_free_length (both mm)")
            if self.preload is not None:
                raise ParameterError("preload", self.preload, "absent when the spring lengths are given (they set the preload)")
            free = _nonnegative("spring_free_length", self.spring_free_length, "mm")
            installed = _nonnegative("spring_installed_length", self.spring_installed_length, "mm")
            if installed > free:
                raise ParameterError("spring_installed_length", installed,
                                     f"<= spring_free_length = {free:g} mm (a compression spring is shorter when installed)")
        elif self.preload is not None:
            _nonnegative("preload", self.preload, "N" if self.motion == "translating" else "N*mm")
        if self.closure == "form" and (self.spring_rate != 0 or self.spring_preload != 0):
            raise ParameterError("spring_rate", self.spring_rate,
                                 "0 with no preload for a form-closed train (yoke, conjugate cams: the second contact holds the follower)")
        if not isinstance(self.load, (int, float)) or isinstance(self.load, bool):
            try:
                angles, values = (np.asarray(a, dtype=float) for a in cast("tuple[Sequence[float], Sequence[float]]", self.load))
            except (TypeError, ValueError):
                raise ParameterError("load", self.load, "a number or a table (angles rad, values)") from None
            if angles.ndim != 1 or angles.shape != values.shape or angles.size < 1:
                raise ParameterError("load", f"table of shapes {angles.shape}, {values.shape}", "two 1-D arrays of one length >= 1")
            if not (np.all(np.isfinite(angles)) and np.all(np.isfinite(values))):
                raise ParameterError("load", "a table with non-finite entries", "finite angles and values")
            if angles[0] < 0 or angles[-1] >= TWO_PI or np.any(np.diff(angles) <= 0):
                raise ParameterError("load", "table angles", "strictly increasing cam angles in [0, 2 pi) rad")
            object.__setattr__(self, "load", (tuple(angles.tolist()), tuple(values.tolist())))
        else:
            require_finite("load", self.load)

    @property
    def spring_preload(self) -> float:
        """Spring force at the follower's lowest position: N (translating) or N*mm (oscillating)."""
        if self.spring_free_length is not None and self.spring_installed_length is not None:
            return self.spring_rate * (self.spring_free_length - self.spring_installed_length)
        return 0.0 if self.preload is None else float(self.preload)

    @property
    def force_unit(self) -> str:
        """Unit of the generalised force (spring, preload, load): "N" or "N*mm"."""
        return "N" if self.motion == "translating" else "N*mm"

    def load_at(self, theta: np.ndarray) -> np.ndarray:
        """External load (N or N*mm) at cam angles ``theta`` (rad)."""
        if isinstance(self.load, tuple):
            angles, values = self.load
            return np.interp(np.mod(theta, TWO_PI), angles, values, period=TWO_PI)
        return np.full(np.shape(theta), float(self.load))


@dataclass(frozen=True)
class ContactMaterial:
    """Elastic constants of cam and follower, the contact width and the allowable stress.

    Attributes
    ----------
    width : mm, the length of the contact line (cam thickness or roller width, the smaller).
    cam_modulus, follower_modulus : GPa (default 210, steel).
    cam_poisson, follower_poisson : Poisson's ratios (default 0.3).
    allowable_stress : MPa, the allowable Hertz stress; None: the stress is information.
    """

    width: float
    cam_modulus: float = 210.0
    cam_poisson: float = 0.3
    follower_modulus: float = 210.0
    follower_poisson: float = 0.3
    allowable_stress: float | None = None

    def __post_init__(self) -> None:
        for name, unit in (("width", "mm"), ("cam_modulus", "GPa"), ("follower_modulus", "GPa")):
            if not require_finite(name, getattr(self, name)) > 0:
                raise ParameterError(name, getattr(self, name), f"{name} > 0 {unit}")
        for name in ("cam_poisson", "follower_poisson"):
            nu = require_finite(name, getattr(self, name))
            if not -1.0 < nu < 0.5:
                raise ParameterError(name, nu, "-1 < Poisson's ratio < 0.5")
        if self.allowable_stress is not None and not require_finite("allowable_stress", self.allowable_stress) > 0:
            raise ParameterError("allowable_stress", self.allowable_stress, "allowable_stress > 0 MPa")

    @property
    def compliance(self) -> float:
        """``(1 - nu_c^2)/E_c + (1 - nu_f^2)/E_f`` in 1/MPa."""
        return ((1.0 - self.cam_poisson**2) / (self.cam_modulus * GPA_TO_MPA)
                + (1.0 - self.follower_poisson**2) / (self.follower_modulus * GPA_TO_MPA))


def _array(name: str, value: Any, n: int | None, allow_inf: bool = False) -> np.ndarray:
    return _array_range(name, value, n, allow_inf)[0]


def _array_range(name: str, value: Any, n: int | None, allow_inf: bool = False) -> tuple[np.ndarray, float, float]:
    """:func:`_array` and the least and largest values it checked (the largest nan with ``allow_inf``)."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim != 1 or (n is not None and arr.size != n):
        raise ParameterError(name, f"array of shape {arr.shape}", f"a 1-D array of {n} samples (one per cam angle)")
    low = float(arr.min()) if arr.size else 0.0  # a nan anywhere is the minimum (numpy propagates it)
    high = math.nan if allow_inf or not math.isfinite(low) else float(arr.max())
    if not (not math.isnan(low) if allow_inf else math.isfinite(low) and math.isfinite(high)):
        bad = np.isnan(arr) if allow_inf else ~np.isfinite(arr)
        raise ParameterError(name, f"non-finite value at sample {int(np.argmax(bad))}",
                             "finite values" + (" (+-inf allowed)" if allow_inf else ""))
    return arr, low, high


@dataclass(frozen=True, eq=False)
class Kinematics:
    """The follower's kinematics and the contact geometry over one cam turn (arrays of shape (N,)).

    Attributes
    ----------
    theta : rad, cam angles, strictly increasing in [0, 2 pi) (uniform for plots; any spacing
        works: peaks are sample maxima, RMS and work use periodic trapezoid weights).
    s, ds, d2s : the follower coordinate and its derivatives per rad of cam angle:
        translating mm, mm/rad, mm/rad^2; oscillating (arm angle) rad, rad/rad, rad/rad^2.
    pressure_angle : rad, between the contact normal and the velocity of the contact point
        (translating) or the roller centre (oscillating); |phi| < pi/2.
    rho_cam : mm, signed radius of curvature of the cam profile at the contact point
        (convex > 0, concave < 0, +inf on a straight flank).
    follower_radius : mm, radius of the follower's surface at the contact: the roller radius,
        ``math.inf`` for a flat face, a knife's tip radius (0: a sharp knife, no Hertz stress).
    direction : rad, fixed-frame direction in which the contact point (translating) or the
        roller centre (oscillating) moves when ``s`` increases: a number, or an array (N,) for
        an oscillating arm.  Used for the weight only.  Default pi/2 (+y).
    pressure_angle_2, rho_cam_2, follower_radius_2 : the second contact of a form-closed
        train (the one pushing towards -s): yoke face or conjugate roller.
    lever : mm, oscillating followers whose pressure angle refers to a point that moves along
        the arm: the distance from the pivot to that point at each cam angle, an array (N,)
        (an oscillating flat face: pivot to contact point, so that ``lever cos(phi)`` is the
        moment arm of the contact normal about the pivot).  None: the train's ``arm_length``.
    lever_2 : mm, oscillating form-closed trains whose second contact is on an arm of its own
        (a conjugate pair's arm B): pivot to the second roller's centre at each cam angle, an
        array (N,).  None: the first contact's lever.
    """

    theta: np.ndarray
    s: np.ndarray
    ds: np.ndarray
    d2s: np.ndarray
    pressure_angle: np.ndarray
    rho_cam: np.ndarray
    follower_radius: float
    direction: float | np.ndarray = math.pi / 2
    pressure_angle_2: np.ndarray | None = None
    rho_cam_2: np.ndarray | None = None
    follower_radius_2: float | None = None
    lever: np.ndarray | None = None
    lever_2: np.ndarray | None = None

    def __post_init__(self) -> None:
        theta = self.theta
        if not _CHECKED_THETA.holds(theta):  # a study's designs share their check grid's angles: checked once
            theta = _array("theta", theta, None)
            if theta.size < 3:
                raise ParameterError("theta", f"{theta.size} samples", "at least 3 cam angles")
            if theta[0] < 0 or theta[-1] >= TWO_PI or np.any(theta[1:] <= theta[:-1]):  # (finite: a difference <= 0 is this)
                raise ParameterError("theta", "cam angles", "strictly increasing cam angles in [0, 2 pi) rad")
            _CHECKED_THETA.keep(theta)
        n = theta.size
        object.__setattr__(self, "theta", theta)
        bounds: dict[str, tuple[float, float]] = {}  # the pressure angles' least and largest (their check below)
        rows = (self.s, self.ds, self.d2s)
        kept = _CHECKED_ROWS.bounds(rows, n)  # a kept law's values: checked once
        for name, given, known in zip(("s", "ds", "d2s", "pressure_angle"), (*rows, self.pressure_angle), (*kept, None)):
            arr, low, high = (given, *known) if known is not None else _array_range(name, given, n)
            object.__setattr__(self, name, arr)
            bounds[name] = (low, high)
        _CHECKED_ROWS.keep([(arr, *bounds[name]) for name, arr, known in zip(("s", "ds", "d2s"), (self.s, self.ds, self.d2s), kept)
                            if known is None])
        self.__dict__["s_least"] = bounds["s"][0]  # the lowest position, found by the check (float(s.min()))
        for name in ("rho_cam", "rho_cam_2"):
            rho = getattr(self, name)
            if rho is None:
                continue
            rho = _array(name, rho, n, allow_inf=True)
            if np.any(rho == 0):
                raise ParameterError(name, f"0 at cam angle {math.degrees(theta[int(np.argmax(rho == 0))]):.6g} deg",
                                     "a nonzero radius of curvature (a cusp has no contact stress)")
            object.__setattr__(self, name, rho)
        for name in ("pressure_angle", "pressure_angle_2"):
            phi = getattr(self, name)
            if phi is None:
                continue
            if name == "pressure_angle_2":  # the first contact's was converted with s, ds, d2s above
                phi, low, high = _array_range(name, phi, n)
                object.__setattr__(self, name, phi)
                bounds[name] = (low, high)
            low, high = bounds[name]
            if low <= -math.pi / 2 or high >= math.pi / 2:  # some |phi| >= pi / 2
                i = int(np.argmax(np.abs(phi)))
                raise ParameterError(name, f"{math.degrees(phi[i]):.6g} deg at cam angle {math.degrees(theta[i]):.6g} deg",
                                     "|pressure angle| < 90 deg (the contact transmits no force along the motion)")
        for name in ("follower_radius", "follower_radius_2"):
            r = getattr(self, name)
            if r is None:
                continue
            if isinstance(r, bool) or not isinstance(r, (int, float, np.floating)) or math.isnan(r) or r < 0:
                raise ParameterError(name, r, f"{name} >= 0 mm (math.inf for a flat face)")
        if np.ndim(self.direction) == 0:
            require_finite("direction", float(self.direction))
        else:
            object.__setattr__(self, "direction", _array("direction", self.direction, n))
        for name in ("lever", "lever_2"):
            if getattr(self, name) is None:
                continue
            lever = _array(name, getattr(self, name), n)
            if not np.all(lever > 0):
                raise ParameterError(name, f"{float(np.min(lever)):g} mm", f"{name} > 0 mm at every cam angle")
            object.__setattr__(self, name, lever)

    @functools.cached_property
    def s_least(self) -> float:
        """The lowest follower position ``float(s.min())`` (mm or rad), found by the check of ``s``."""
        return float(self.s.min())

    @functools.cached_property
    def cos_pressure_angle(self) -> np.ndarray:
        """``cos(pressure_angle)``, made once (the contact projection, the force along the motion,
        the spring hints share it; read-only)."""
        return _read_only(np.cos(self.pressure_angle))

    @functools.cached_property
    def cos_pressure_angle_2(self) -> np.ndarray | None:
        """``cos(pressure_angle_2)`` of a form-closed train's second contact (None without it), made once; read-only."""
        return None if self.pressure_angle_2 is None else _read_only(np.cos(self.pressure_angle_2))


_P = ParamSpec("_P")
_R = TypeVar("_R")
#: What the designs evaluated in one process share here (the last checked cam angles and law
#: values, the last law terms and their summaries) is read and replaced under this lock: requests
#: that `camgen serve` evaluates at once in threads must not see another design's half-replaced slot.
_SHARED = threading.RLock()


def _shared(method: Callable[_P, _R]) -> Callable[_P, _R]:
    """``method`` run holding :data:`_SHARED`."""
    @functools.wraps(method)
    def run(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        with _SHARED:
            return method(*args, **kwargs)
    return run


class _CheckedAngles:
    """The last cam angles that passed :class:`Kinematics`' checks of ``theta``: a read-only array
    that owns its data (no writable base can change it), held so that its id is not reused.  A study's
    designs build their kinematics on one check grid's angles (the same read-only array): each design
    after the first skips the angles' four passes (finite, least, largest, increasing).  One slot:
    bounded; any other array is checked as before."""

    __slots__ = ("angles",)

    def __init__(self) -> None:
        self.angles: np.ndarray | None = None

    @_shared
    def holds(self, theta: object) -> bool:
        """``theta`` is the kept array, still read-only; any other answer forgets the kept array
        (what is checked next is kept only if it passes: an array made writable is never kept again
        unchecked).  An array made writable, changed and made read-only again between two designs is
        outside this rule: the check grid's angles are never written."""
        if theta is self.angles and not cast(np.ndarray, theta).flags.writeable:
            return True
        self.angles = None
        return False

    @_shared
    def keep(self, theta: np.ndarray) -> None:
        """Keep ``theta`` (checked) if it is read-only and owns its data, else keep nothing."""
        self.angles = theta if theta.base is None and not theta.flags.writeable and theta.dtype == np.float64 else None


_CHECKED_THETA = _CheckedAngles()


class _CheckedRows:
    """The least and largest values (:func:`_array_range`) of the checked views of one read-only
    block that owns its data (a motion program's kept check-grid values ``s``, ``ds``, ``d2s``): a
    radius sweep's designs view the same block, each view's values are checked once.  The views
    (so the block) are held, their ids not reused; a view of another block replaces them; at most
    a few.  The views' places in the block are found only when a later view is of the same block."""

    __slots__ = ("block", "views", "places")

    def __init__(self) -> None:
        self.block: object = None
        self.views: list[tuple[np.ndarray, float, float]] = []
        self.places: dict[tuple[int, tuple[int, ...], tuple[int, ...]], tuple[float, float]] | None = None

    @_shared
    def bounds(self, rows: tuple[object, ...], n: int) -> list[tuple[float, float] | None]:
        """The kept least and largest values of each of ``rows`` (a view of the kept block, of ``n``
        samples), or None (all are asked before any is kept: a new block's views find no places)."""
        out: list[tuple[float, float] | None] = []
        for values in rows:
            if (self.block is None or not isinstance(values, np.ndarray) or values.base is not self.block or values.shape != (n,)
                    or not _in_held_block(values)):
                out.append(None)
                continue
            if self.places is None:
                self.places = {_places((view,))[0]: (low, high) for view, low, high in self.views}
            out.append(self.places.get(_places((values,))[0]))
        return out

    @_shared
    def keep(self, checked: list[tuple[np.ndarray, float, float]]) -> None:
        """Keep the least and largest values of each checked view of a held block (view, least, largest)."""
        for values, low, high in checked:
            if not _in_held_block(values):
                continue
            if values.base is not self.block or len(self.views) >= 4:
                self.block, self.views = values.base, []
            self.views.append((values, low, high))
            self.places = None


_CHECKED_ROWS = _CheckedRows()


def _read_only(values: np.ndarray) -> np.ndarray:
    values.flags.writeable = False
    return values


# --------------------------------------------------------------------------------------------
# The physics
# --------------------------------------------------------------------------------------------
def _rpm_to_omega(rpm: float) -> float:
    rpm = require_finite("rpm", rpm)
    if rpm <= 0:
        raise ParameterError("rpm", rpm, "rpm > 0 (the cam turns counter-clockwise at constant speed)")
    return rpm * RPM_TO_RAD_PER_S


def _lever(train: FollowerTrain, kin: Kinematics | None = None) -> float | np.ndarray:
    """mm per unit of the follower coordinate: 1 (translating, Q in N) or the arm (Q in N*mm):
    ``kin.lever`` where the kinematics give it per cam angle, else the train's arm length."""
    if train.motion == "translating":
        return 1.0
    return kin.lever if kin is not None and kin.lever is not None else float(train.arm_length)


def force_coefficients(kin: Kinematics, train: FollowerTrain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(A, B, C)`` with ``Q(theta, w) = A + B w + C w^2`` (N or N*mm; ``w`` in rad/s).

    ``A``: spring, preload, external load and weight; ``B``: viscous damping; ``C``: inertia.
    """
    parts = _force_parts(kin, train)
    return parts.spring_term(train), parts.b, parts.c


@dataclass(frozen=True, eq=False)
class _ForceParts:
    """The terms of :func:`force_coefficients` that a change of the spring (rate, preload,
    lengths) leaves alone: the lift above the lowest position ``q - q_min`` (mm or rad), the
    external load and the weight (N or N*mm), ``B`` and ``C``; :meth:`spring_term` makes ``A``
    for a train with another spring in the same operations."""

    lift: np.ndarray
    load: np.ndarray | float
    weight: Any
    b: np.ndarray
    c: np.ndarray

    def spring_term(self, train: FollowerTrain) -> np.ndarray:
        """``A``: spring, preload, external load and weight of ``train`` (N or N*mm)."""
        return self.spring_term_of(train.spring_rate, train.spring_preload)

    def spring_term_of(self, rate: float, preload: float) -> np.ndarray:
        """``A`` of a train with the spring ``rate`` (N/mm or N*mm/rad) and ``preload`` (its
        :attr:`FollowerTrain.spring_preload`, N or N*mm): :meth:`spring_term` without making the train."""
        a = rate * self.lift  # ((rate lift + preload) + load) + weight, added in place
        if isinstance(a, np.ndarray) and a.shape == self.lift.shape and a.dtype == np.float64:
            a += preload
            a += self.load
            a += self.weight  # a number, or an array of the samples' shape (an oscillating arm's direction)
            return a
        a = a + preload + self.load + self.weight
        if isinstance(a, np.ndarray) and a.shape == self.lift.shape and a.dtype == np.float64:
            return a  # a new array of the lift's shape already (what the copy below would make)
        return np.broadcast_to(a, self.lift.shape).astype(float)


def _force_parts(kin: Kinematics, train: FollowerTrain) -> _ForceParts:
    """:class:`_ForceParts` of ``kin`` and ``train`` (what :func:`force_coefficients` adds up)."""
    if train.motion == "translating":
        inertia = train.mass * KG_MM_PER_S2_TO_N  # N per (mm/s^2)
        damping = train.damping * N_S_PER_M_TIMES_MM_PER_S_TO_N  # N per (mm/s)
        weight_lever = 1.0
    else:
        inertia = train.inertia * KG_M2_PER_S2_TO_N_MM  # N*mm per (rad/s^2)
        damping = train.damping * N_M_TO_N_MM  # N*mm per (rad/s)
        weight_lever = train.cg_distance  # mm
    # the weight's component along +q, with the sign that resists the motion: -m g . e_q
    weight = -train.mass * train.gravity * weight_lever * np.cos(train.gravity_angle - np.asarray(kin.direction, dtype=float))
    load = train.load_at(kin.theta) if isinstance(train.load, tuple) else float(train.load)  # a constant added as a number
    return _ForceParts(kin.s - kin.s_least, load, weight, damping * kin.ds, inertia * kin.d2s)  # (s_least: float(s.min()))


def _contact_projection(kin: Kinematics, train: FollowerTrain, second: bool = False) -> np.ndarray:
    """``lever * cos(phi)``: the generalised force per newton along the contact normal (the
    second contact's own lever where the kinematics give one, ``kin.lever_2``)."""
    cos_phi = kin.cos_pressure_angle_2 if second else kin.cos_pressure_angle
    assert cos_phi is not None  # a second contact: a form-closed train's kinematics (analyse checks they are given)
    if second and kin.lever_2 is not None and train.motion == "oscillating":
        return kin.lever_2 * cos_phi
    lever = _lever(train, kin)
    return cos_phi if isinstance(lever, float) and lever == 1.0 else lever * cos_phi  # 1 * x is x (read-only)


def smallest_positive_root(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Smallest ``w > 0`` with ``a + b w + c w^2 = 0`` where ``a > 0``, elementwise; inf where none.

    ``w = 2a / (-b + sqrt(b^2 - 4ac))`` covers every case without cancellation: for ``c < 0``
    it is the one positive root, for ``c > 0`` (then ``b < 0``) the smaller of two, for
    ``c = 0`` it is ``-a/b``.
    """
    disc = b * b - 4.0 * a * c
    ok = disc >= 0
    den = -b + np.sqrt(np.where(ok, disc, 0.0))
    ok &= den > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(ok, 2.0 * a / np.where(ok, den, 1.0), np.inf)


def jump_speed(kin: Kinematics, train: FollowerTrain, margin: float = 0.0) -> float:
    """Cam speed (rpm) at which the smallest contact force first falls to ``margin`` (N).

    Exact for the samples given: per cam angle the force ``(A + B w + C w^2) / (lever cos phi)``
    reaches the margin at the smallest positive root of a quadratic; the jump speed is the
    smallest over the samples.  0 when the force is below the margin at rest, ``math.inf``
    when it never gets there (e.g. a follower that only decelerates against the spring).
    Form-closed trains do not jump: ``math.inf``.
    """
    if train.closure == "form":
        return math.inf
    margin = require_finite("margin", margin)
    a, b, c = force_coefficients(kin, train)
    return _jump_rpm(a, b, c, _contact_projection(kin, train), margin)


def _jump_rpm(a: np.ndarray, b: np.ndarray, c: np.ndarray, projection: np.ndarray, margin: float) -> float:
    """:func:`jump_speed` from the force coefficients and the contact projection (rpm)."""
    if margin != 0.0:  # a - 0 * projection is a itself
        a = a - margin * projection
    if np.any(a <= 0):
        return 0.0
    w = _least_positive_root(a, b, c)
    return w / RPM_TO_RAD_PER_S if math.isfinite(w) else math.inf


def _least_positive_root(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """``min(smallest_positive_root(a, b, c))`` (rad/s; inf: none) where ``a > 0``: the same roots
    in the same operations (``sqrt(disc) - b`` is ``-b + sqrt(disc)`` exactly), without the
    arrays of the roots that are not positive (fewer passes over the samples)."""
    disc = b * b
    four_ac = 4.0 * a
    four_ac *= c
    disc -= four_ac
    ok = disc >= 0
    den = np.sqrt(disc, out=np.zeros(disc.shape), where=ok)  # where disc < 0: 0, as the elementwise function's where
    den -= b
    ok &= den > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        return float(np.min(np.divide(2.0 * a, den), where=ok, initial=np.inf))


def min_contact_force(kin: Kinematics, train: FollowerTrain, rpm: np.ndarray) -> np.ndarray:
    """Smallest contact force over the turn (N) at each cam speed of ``rpm`` (rev/min, >= 0), shape of ``rpm``.

    The force at every cam angle is ``(A + B w + C w^2) / (lever cos phi)``
    (:func:`force_coefficients`); this is its minimum over the samples, for the report's plot
    of the jump margin against speed (it reaches the margin at :func:`jump_speed`).  Force
    closure only (a form-closed train does not jump).
    """
    if train.closure == "form":
        raise ParameterError("closure", train.closure, '"force" (a form-closed train has no jump margin)')
    rpm = np.asarray(rpm, dtype=float)
    if not (np.all(np.isfinite(rpm)) and np.all(rpm >= 0)):
        raise ParameterError("rpm", "a speed array", "finite speeds >= 0 rpm")
    a, b, c = force_coefficients(kin, train)
    return _min_force(a, b, c, _contact_projection(kin, train), rpm)


def _min_force(a: np.ndarray, b: np.ndarray, c: np.ndarray, projection: np.ndarray, rpm: np.ndarray) -> np.ndarray:
    """:func:`min_contact_force` from the force coefficients and the contact projection (N)."""
    w = rpm.reshape(-1, 1) * RPM_TO_RAD_PER_S
    q = a + b * w + c * w**2  # (R, N)
    return np.min(q / projection, axis=1).reshape(rpm.shape)


def hertz_line_stress(force: np.ndarray | float, rho_cam: np.ndarray | float, rho_follower: float,
                      material: ContactMaterial) -> np.ndarray:
    """Largest Hertz pressure (MPa) of a line contact, elementwise.

    Rothbart, *Cam Design Handbook* (McGraw-Hill 2004), eq. (9.11), the two-cylinder formula:
    ``p_max = sqrt(F (1/rho_cam + 1/rho_follower) / (pi b K))`` with
    ``K = (1-nu_c^2)/E_c + (1-nu_f^2)/E_f``.  ``force`` N (negative values, a contact that
    has lifted, count as 0); radii mm, signed (concave < 0, ``inf`` flat).

    Raises :class:`GeometryError` where the combined curvature is negative: a concave profile
    tighter than the follower (the follower cannot sit in it).  Zero combined curvature (a
    flat face on a straight flank) gives 0: the force spreads over the face, no line contact.
    """
    force, rho = np.asarray(force, dtype=float), np.asarray(rho_cam, dtype=float)
    if force.shape != rho.shape:  # a scalar against an array (analyse gives two arrays of one shape)
        force, rho = np.broadcast_arrays(force, rho)
    if not rho_follower > 0:
        raise ParameterError("follower_radius", rho_follower, "> 0 mm (a sharp knife edge has no finite contact stress)")
    curvature = 1.0 / rho
    curvature += 1.0 / rho_follower  # 1/inf = 0: a straight flank or a flat face
    if curvature.size and not float(curvature.min()) >= 0 and np.any(curvature < 0):  # (min is nan when any is: look again)
        worst = float(np.max(rho[curvature < 0]))
        largest = floor_significant(-worst, 6)  # rounded down: a follower of that radius touches it (combined curvature >= 0)
        shown = f"{largest:g}" if largest <= -worst else repr(-worst)
        what = ("a flat face cannot touch a concave profile: the cam must be convex" if math.isinf(rho_follower)
                else f"use a follower radius of at most {shown} mm")
        raise GeometryError(
            f"a concave part of the profile (radius of curvature {-worst:.6g} mm) is tighter than the follower "
            f"(radius {rho_follower:g} mm), which cannot touch it: {what}")
    load = np.maximum(force, 0.0)  # sqrt(load * curvature / (pi b K)), in place
    load *= curvature
    load /= math.pi * material.width * material.compliance
    return np.sqrt(load, out=load) if isinstance(load, np.ndarray) else np.sqrt(load)  # (a number from numbers)


@dataclass(frozen=True, eq=False)
class DynamicsResult:
    """Forces, torque, power and contact stress at one cam speed (arrays of shape (N,)).

    Attributes
    ----------
    rpm, omega : the cam speed, rev/min and rad/s.
    theta : rad, the cam angles of :class:`Kinematics`.
    train : the :class:`FollowerTrain` analysed.
    generalised_force : ``Q``, N (translating) or N*mm (oscillating, about the pivot).
    contact_force : N, along the common normal at contact 1 (force closure: < 0 where the
        follower would have to be pulled, i.e. it jumps; form closure: >= 0).
    contact_force_2 : N, contact 2 of a form-closed train, else None.
    pressure_angle : rad, the direction of the contact force (from the contact point's velocity).
    follower_force, side_force : N, the contact force's components along the follower's
        motion (``F cos phi``) and across it (``F sin phi``: guide or pivot load); ``side_force``
        is a property: a force-closed train's is made on first use (the report draws it, no
        check reads it), a form-closed train's is given (``given_side_force``, else None).
    torque : N*m, camshaft torque (> 0: the shaft drives the cam); power : W, ``torque * omega``.
    hertz_stress, hertz_stress_2 : MPa, or None without a material (or a sharp knife).
    jump_rpm : rpm at which the contact force first reaches 0 (inf: never; 0: at rest).
    jump_ranges_deg : start/end cam angles (deg) of the runs where the force <= 0.
    min_preload : the smallest preload (N or N*mm) that keeps the force >= the margin at this
        speed with the given rate (0 if none is needed); None for form closure.
    min_spring_rate : the smallest rate (N/mm or N*mm/rad) that does it with the given
        preload; None if no rate can (the force falls short where the spring is at its
        lowest) or for form closure.
    jump_margin : N, the margin the jump check holds the contact force to.
    analysed : what :func:`analyse` made of its kinematics and train, kept for :func:`spring_hints`:
        the :class:`Kinematics`, the :class:`FollowerTrain`, the force terms a change of the spring
        leaves alone and the contact projection (None, or others than the hints are given: made again).
    """

    rpm: float
    omega: float
    theta: np.ndarray
    train: FollowerTrain
    generalised_force: np.ndarray
    contact_force: np.ndarray
    contact_force_2: np.ndarray | None
    pressure_angle: np.ndarray
    follower_force: np.ndarray
    given_side_force: np.ndarray | None
    torque: np.ndarray
    power: np.ndarray
    hertz_stress: np.ndarray | None
    hertz_stress_2: np.ndarray | None
    jump_rpm: float
    jump_ranges_deg: list[float]
    min_preload: float | None
    min_spring_rate: float | None
    jump_margin: float
    analysed: "tuple[Kinematics, FollowerTrain, _ForceParts, np.ndarray] | None" = field(default=None, repr=False)

    # ---- scalar summaries (each made once: the checks' notes and the figures share them) ------
    @functools.cached_property
    def weights(self) -> np.ndarray:
        """Periodic trapezoid weights (rad) of the samples: ``sum(weights * f)`` ~ ``int f dtheta``
        (made once: the summaries below share them; read-only)."""
        theta = self.theta  # 0.5 * (next - previous), the turn closed at both ends, in place (the same operations)
        out = np.empty(theta.shape)
        np.subtract(theta[2:], theta[:-2], out=out[1:-1])
        out[0] = theta[1] - (theta[-1] - TWO_PI)
        out[-1] = (theta[0] + TWO_PI) - theta[-2]
        out *= 0.5
        out.flags.writeable = False
        return out

    @functools.cached_property
    def side_force(self) -> np.ndarray:
        """N, the contact force's component across the follower's motion: ``F sin phi`` (force
        closure, made on first use) or what :func:`analyse` gave (form closure: both contacts')."""
        if self.given_side_force is not None:
            return self.given_side_force
        return self.contact_force * np.sin(self.pressure_angle)

    def _rms(self, values: np.ndarray) -> float:
        squares = np.square(values)  # sqrt(sum(weights * values**2) / 2 pi), the product in place
        squares *= self.weights
        return math.sqrt(float(np.sum(squares)) / TWO_PI)

    @functools.cached_property
    def torque_peak(self) -> float:
        """Largest |torque|, N*m."""
        return float(abs(self.torque[self.torque_peak_index]))

    @functools.cached_property
    def torque_peak_index(self) -> int:
        """The first sample of the largest |torque| (the checks' and figures' cam angle of the peak)."""
        return int(np.argmax(np.abs(self.torque)))

    @functools.cached_property
    def torque_rms(self) -> float:
        """RMS torque over one turn, N*m."""
        return self._rms(self.torque)

    @functools.cached_property
    def power_peak(self) -> float:
        """Largest |power|, W: the peak torque times the speed, exactly the largest |torque * omega|
        (a product with omega > 0 keeps the order of the |torque| and rounds symmetrically)."""
        return self.torque_peak * self.omega

    @functools.cached_property
    def power_rms(self) -> float:
        """RMS power over one turn, W."""
        return self._rms(self.power)

    @functools.cached_property
    def energy_per_turn(self) -> float:
        """Work the shaft does per turn, J (``int T dtheta``): the energy the damping dissipates."""
        return float(np.sum(self.weights * self.torque))

    @functools.cached_property
    def mean_power(self) -> float:
        """Mean input power, W."""
        return self.energy_per_turn * self.omega / TWO_PI

    @functools.cached_property
    def min_contact_force(self) -> float:
        """Smallest contact force, N (form closure: the smaller contact's smallest force, 0)."""
        forces = self.contact_force if self.contact_force_2 is None else np.minimum(self.contact_force, self.contact_force_2)
        return float(np.min(forces))

    @functools.cached_property
    def hertz_peak(self) -> float | None:
        """Largest Hertz stress over both contacts, MPa."""
        stresses = [h for h in (self.hertz_stress, self.hertz_stress_2) if h is not None]
        return float(max(np.max(h) for h in stresses)) if stresses else None

    def curves(self) -> dict[str, np.ndarray]:
        """The arrays a report draws against cam angle, keyed with their unit."""
        out = {
            "cam_angle_deg": np.degrees(self.theta),
            "contact_force_N": self.contact_force,
            "pressure_angle_deg": np.degrees(self.pressure_angle),
            "follower_force_N": self.follower_force,
            "side_force_N": self.side_force,
            "torque_Nm": self.torque,
            "power_W": self.power,
        }
        if self.contact_force_2 is not None:
            out["contact_force_2_N"] = self.contact_force_2
        if self.hertz_stress is not None:
            out["hertz_stress_MPa"] = self.hertz_stress
        if self.hertz_stress_2 is not None:
            out["hertz_stress_2_MPa"] = self.hertz_stress_2
        return out

    def row_figures(self) -> dict[str, Any]:
        """The figures of :meth:`figures` a design's row reads (:func:`camgen.study.design.main_figures`),
        the same values: the peak torque (N*m), the jump speed (rpm, force closure; None: never) and
        the peak Hertz stress (MPa, with a material).  A design evaluation makes only these (its
        plan has no report figures: :attr:`camgen.planning.Plan.report_figures`)."""
        out: dict[str, Any] = {"torque_peak_Nm": self.torque_peak}
        if self.train.closure == "force":
            out["jump_rpm"] = self.jump_rpm if math.isfinite(self.jump_rpm) else None
        if self.hertz_peak is not None:
            out["hertz_stress_peak_MPa"] = self.hertz_peak
        return out

    def figures(self) -> dict[str, Any]:
        """Scalar results for report.json (keys carry their unit; no inf or NaN: None instead)."""
        unit = "N" if self.train.motion == "translating" else "Nmm"
        rate_unit = "N_per_mm" if self.train.motion == "translating" else "Nmm_per_rad"
        out: dict[str, Any] = {
            "rpm": self.rpm,
            "min_contact_force_N": self.min_contact_force,
            "max_contact_force_N": float(np.max(self.contact_force if self.contact_force_2 is None
                                                else np.maximum(self.contact_force, self.contact_force_2))),
            "torque_peak_Nm": self.torque_peak,
            "torque_rms_Nm": self.torque_rms,
            "power_peak_W": self.power_peak,
            "power_rms_W": self.power_rms,
            "mean_power_W": self.mean_power,
            "energy_per_turn_J": self.energy_per_turn,
        }
        if self.train.closure == "force":
            out.update({
                "jump_rpm": self.jump_rpm if math.isfinite(self.jump_rpm) else None,
                "jump_margin_N": self.jump_margin,
                "jump_ranges_deg": self.jump_ranges_deg,
                f"min_preload_{unit}": self.min_preload,
                f"min_spring_rate_{rate_unit}": self.min_spring_rate,
            })
        if self.hertz_peak is not None:
            out["hertz_stress_peak_MPa"] = self.hertz_peak
        return out


def _required_spring(a: np.ndarray, damping: np.ndarray, inertia: np.ndarray, projection: np.ndarray,
                     margin: float, train: FollowerTrain, lift: np.ndarray, position_tol: float) -> tuple[float, float | None]:
    """Smallest preload (given rate) and smallest rate (given preload) that keep the contact
    force >= ``margin`` at the speed whose damping and inertia terms ``B w`` and ``C w^2`` are
    given (N or N*mm): both follow from ``Q`` being linear in each."""
    need = margin * projection - (damping + inertia)  # what A must reach
    without_preload = a - train.spring_preload
    min_preload = max(0.0, float(np.max(need - without_preload)))
    without_spring = a - train.spring_rate * lift
    short = need - without_spring  # what rate * lift must cover
    lifted = lift > position_tol
    falls_short = short > 0
    if np.any(falls_short & ~lifted):
        return min_preload, None
    with np.errstate(divide="ignore", invalid="ignore"):  # the largest short / lift where short > 0 (lifted there), else 0
        return min_preload, float(np.max(np.divide(short, lift), where=falls_short, initial=0.0))


def _least_quoted(value: float, keeps_margin: Any, digits: int = 6) -> float | None:
    """``value`` rounded up to ``digits`` significant digits, raised by a unit of the last digit
    until ``keeps_margin`` (the force check redone with it) holds: the number a note quotes as
    a least value is one that was tried.  None when four such values fail."""
    from camgen.errors import ceil_significant

    if value <= 0.0:
        return 0.0
    quoted = ceil_significant(value, digits)
    for _ in range(4):
        if keeps_margin(quoted):
            return quoted
        quoted = float(f"{quoted + 10.0 ** (math.floor(math.log10(quoted)) - digits + 1):.{digits}g}")
    return None


def spring_hints(result: "DynamicsResult", kin: Kinematics) -> tuple[float | None, float | None, float | None]:
    """What the jump check's note quotes, each tried: the least preload (N or N*mm; with the
    rate given), the largest installed length (mm; a spring given by its lengths, with its rate
    and free length) and the least rate (with the preload, or the lengths, given) that keep the
    contact force >= the margin at ``result.rpm``; None where none exists or none applies."""
    train, margin = result.train, result.jump_margin
    if result.analysed is not None and result.analysed[0] is kin and result.analysed[1] is train:  # analyse's own, of these
        parts, projection = result.analysed[2], result.analysed[3]
    else:
        parts = _force_parts(kin, train)  # what a change of the spring leaves alone: made once for every value tried
        projection = _contact_projection(kin, train)

    w = float(result.rpm) * RPM_TO_RAD_PER_S  # _min_force's terms a change of the spring leaves alone, made once
    damping, inertia = parts.b * w, parts.c * (w * w)  # (its speeds' w**2 is w * w)

    def keeps(rate: float, preload: float) -> bool:  # min_contact_force of the train with this spring (_min_force's operations)
        q = parts.spring_term_of(rate, preload)
        q += damping
        q += inertia
        q /= projection
        return float(q.min()) >= margin

    free, fitted = train.spring_free_length, train.spring_installed_length
    lengths = None if free is None or fitted is None else (free, fitted)  # a spring given by its lengths (mm)
    preload = installed = rate = None
    if result.min_preload is not None and lengths is None:
        preload = _least_quoted(result.min_preload, lambda p: keeps(train.spring_rate, float(p)))
    if result.min_preload is not None and lengths is not None and train.spring_rate > 0 and result.min_preload > train.spring_preload:
        from camgen.errors import floor_significant

        longest = lengths[0] - result.min_preload / train.spring_rate
        if longest > 0.0:
            installed = floor_significant(longest, 6)
            installed = installed if keeps(train.spring_rate, train.spring_rate * (lengths[0] - installed)) else None
    if lengths is not None:  # the preload is rate x (free - installed): it grows with the rate (Q is linear in the rate)
        squeeze = parts.lift + (lengths[0] - lengths[1])
        short = margin * projection - result.generalised_force
        pressed = squeeze > 0.0
        if not np.any((short > 0) & ~pressed):
            least = train.spring_rate + float(np.max(np.where(pressed, short / np.where(pressed, squeeze, 1.0), -np.inf)))
            span = lengths[0] - lengths[1]  # the train's spring_preload is rate x span
            rate = _least_quoted(max(least, 0.0), lambda k: keeps(k, k * span))
    elif result.min_spring_rate is not None:
        rate = _least_quoted(result.min_spring_rate, lambda k: keeps(k, train.spring_preload))
    return preload, installed, rate


@dataclass(eq=False)
class _LawTerms:
    """What :func:`analyse` makes from the follower's motion alone (``s``, ``ds``, ``d2s``, the cam
    angles, the weight's direction), the train and the speed: the force parts, ``A``, the damping
    and inertia terms ``B w``, ``C w^2``, ``Q``, the torque (N*m), the power (W) and, made on
    first use, the jump speed (rpm; it needs no contact projection: margin 0)."""

    parts: _ForceParts
    a: np.ndarray
    damping: np.ndarray
    inertia: np.ndarray
    q: np.ndarray
    torque: np.ndarray
    power: np.ndarray
    jump: float | None = None
    kept: bool = False  # kept for the next design (_KeptLawTerms): its results share the summaries below
    theta: np.ndarray | None = None  # the cam angles the summaries were made on (read-only, owning its data; held)
    summaries: dict[str, Any] | None = None

    @_shared
    def share_summaries(self, result: "DynamicsResult") -> None:
        """Give ``result`` (made from these kept terms) the torque and power summaries of the last
        result made from them on the same read-only cam angles (they read only the torque, the
        power, the speed and the angles' weights), or make them now and keep them."""
        theta = result.theta
        if self.summaries is not None and theta is self.theta and not theta.flags.writeable:
            result.__dict__.update(self.summaries)
            return
        self.theta = theta if theta.base is None and not theta.flags.writeable else None
        self.summaries = {name: getattr(result, name) for name in _SUMMARIES} if self.theta is not None else None

    def jump_rpm(self) -> float:
        """:func:`_jump_rpm` of ``A``, ``B``, ``C`` at margin 0 (made once)."""
        if self.jump is None:
            self.jump = _jump_rpm(self.a, self.parts.b, self.parts.c, self.a, 0.0)  # (the projection is unused at margin 0)
        return self.jump


def _make_law_terms(kin: Kinematics, train: FollowerTrain, omega: float) -> _LawTerms:
    parts = _force_parts(kin, train)
    a, b, c = parts.spring_term(train), parts.b, parts.c  # force_coefficients
    damping, inertia = b * omega, c * omega**2
    q = a + damping
    q += inertia  # (a + damping) + inertia
    torque = q * kin.ds  # power balance, T w = Q w q'
    torque *= N_MM_TO_N_M
    return _LawTerms(parts, a, damping, inertia, q, torque, torque * omega)


def _in_held_block(values: np.ndarray) -> bool:
    """``values`` is a read-only float view of a read-only block that owns its data (its values
    cannot change)."""
    base = values.base
    return (not values.flags.writeable and isinstance(base, np.ndarray) and base.base is None and not base.flags.writeable
            and values.dtype == np.float64)


def _places(views: tuple[np.ndarray, ...]) -> tuple[tuple[int, tuple[int, ...], tuple[int, ...]], ...]:
    """Each view's place in its block: the byte offset, the shape and the strides."""
    out = []
    for values in views:
        assert isinstance(values.base, np.ndarray)  # (_in_held_block)
        offset = values.__array_interface__["data"][0] - values.base.__array_interface__["data"][0]
        out.append((offset, values.shape, values.strides))
    return tuple(out)


class _KeptLawTerms:
    """The last :class:`_LawTerms` made for a motion whose ``s``, ``ds``, ``d2s`` are views of a
    read-only block that owns its data (a motion program's kept check-grid values), with a scalar
    weight direction, a train object (frozen) whose load is a number (no cam angle enters the terms)
    and a speed: the next design of a radius sweep (the same law, train and speed) reads them again
    (their arrays read-only).  The views (so their blocks) and the train are held, so their ids are
    not reused; one slot.  The views' places in their blocks are compared only when the blocks,
    the direction, the train and the speed are the kept ones (a lift sweep's new law: a new block).
    The terms are kept from the second design on the same values: a lift sweep, whose every design
    has a new law, holds no arrays of a past design."""

    __slots__ = ("key", "views", "places", "train", "terms")

    def __init__(self) -> None:
        self.key: object = None
        self.views: tuple[np.ndarray, ...] = ()
        self.places: object = None
        self.train: FollowerTrain | None = None
        self.terms: _LawTerms | None = None

    @_shared
    def terms_of(self, kin: Kinematics, train: FollowerTrain, omega: float) -> _LawTerms:
        views = (kin.s, kin.ds, kin.d2s)
        if (not (_in_held_block(kin.s) and _in_held_block(kin.ds) and _in_held_block(kin.d2s)) or not isinstance(train.load, float)
                or isinstance(kin.direction, np.ndarray)):
            return _make_law_terms(kin, train, omega)
        direction = float(kin.direction)
        key = (id(kin.s.base), id(kin.ds.base), id(kin.d2s.base), direction, math.copysign(1.0, direction), id(train),
               omega)  # (omega > 0: equal is identical)
        if key == self.key:
            if self.places is None:
                self.places = _places(self.views)
            if _places(views) == self.places:  # the second design on these values: kept from now on
                if self.terms is not None:
                    return self.terms
                terms = _make_law_terms(kin, train, omega)
                for arr in (terms.parts.lift, terms.parts.b, terms.parts.c, terms.a, terms.damping, terms.inertia, terms.q,
                            terms.torque, terms.power):
                    arr.flags.writeable = False
                terms.kept = True
                self.terms = terms
                return terms
        self.key, self.views, self.places, self.train, self.terms = key, views, None, train, None  # seen once: nothing kept yet
        return _make_law_terms(kin, train, omega)


_LAW_TERMS = _KeptLawTerms()

#: The :class:`DynamicsResult` summaries that read only the torque, the power, the speed and the cam
#: angles' weights (shared by the results of kept :class:`_LawTerms` on the same angles).
_SUMMARIES = ("weights", "torque_peak_index", "torque_peak", "torque_rms", "power_peak", "power_rms", "energy_per_turn",
              "mean_power")


def _law_terms(kin: Kinematics, train: FollowerTrain, omega: float) -> _LawTerms:
    """:class:`_LawTerms` of ``kin``, ``train`` and ``omega`` (rad/s): kept for the next design
    on the same kept motion values, angles, train and speed (:class:`_KeptLawTerms`)."""
    return _LAW_TERMS.terms_of(kin, train, omega)


def analyse(kin: Kinematics, train: FollowerTrain, rpm: float, material: ContactMaterial | None = None, *,
            jump_margin: float = 0.0, position_tol: float = 1e-9) -> DynamicsResult:
    """Contact forces, camshaft torque and power, Hertz stress, the jump speed and the spring
    that keeps the contact at ``rpm`` (the checks of them: :func:`camgen.kinds.dynamics.dynamics_checks`).

    Parameters
    ----------
    kin : the follower's kinematics and contact geometry (:class:`Kinematics`).
    train : the follower train (:class:`FollowerTrain`).
    rpm : cam speed, rev/min (> 0, constant, counter-clockwise).
    material : elastic constants, contact width, allowable stress; None: no Hertz stress.
    jump_margin : N, the contact force the "jump" check requires everywhere (>= 0): the least
        preload and rate are those that keep it.
    position_tol : mm (rad for an oscillating arm): samples within it of the lowest position
        count as lowest when finding the smallest spring rate (the spring adds nothing there).

    Returns
    -------
    DynamicsResult
    """
    omega = _rpm_to_omega(rpm)
    margin = _nonnegative("jump_margin", jump_margin, "N")
    position_tol = _nonnegative("position_tol", position_tol, "mm")
    form = train.closure == "form"
    if form and (kin.pressure_angle_2 is None or kin.rho_cam_2 is None):
        raise ParameterError("pressure_angle_2", None, "arrays for the second contact of a form-closed train (and rho_cam_2)")
    terms = _law_terms(kin, train, omega)
    parts, a, damping, inertia, q = terms.parts, terms.a, terms.damping, terms.inertia, terms.q
    projection = _contact_projection(kin, train)
    if form:
        assert kin.pressure_angle_2 is not None and kin.rho_cam_2 is not None  # refused above otherwise
        force_1 = np.maximum(q, 0.0) / projection
        force_2 = np.maximum(-q, 0.0) / _contact_projection(kin, train, second=True)
        # the follower-direction component carried by whichever contact is loaded (signed: + pushes along +s)
        along = q / _lever(train, kin)
        side = force_1 * np.sin(kin.pressure_angle) - force_2 * np.sin(kin.pressure_angle_2)
    else:
        force_1 = q / projection
        force_2 = None
        along = force_1 * kin.cos_pressure_angle
        side = None  # force_1 * sin(phi), made on first use (DynamicsResult.side_force: the report's, no check's)
    torque, power = terms.torque, terms.power
    hertz = hertz_2 = None
    if material is not None and kin.follower_radius > 0:
        hertz = hertz_line_stress(force_1, kin.rho_cam, kin.follower_radius, material)
        if form and force_2 is not None and kin.rho_cam_2 is not None:
            r2 = kin.follower_radius if kin.follower_radius_2 is None else kin.follower_radius_2
            hertz_2 = hertz_line_stress(force_2, kin.rho_cam_2, r2, material) if r2 > 0 else None
    if form:
        jump_rpm, ranges, min_preload, min_rate = math.inf, [], None, None
    else:
        jump_rpm = terms.jump_rpm()  # jump_speed(kin, train): the same coefficients
        ranges = run_ends(force_1 <= 0, kin.theta)
        min_preload, min_rate = _required_spring(a, damping, inertia, projection, margin, train, parts.lift, position_tol)
    result = DynamicsResult(rpm, omega, kin.theta, train, q, force_1, force_2, kin.pressure_angle, along, side, torque, power,
                            hertz, hertz_2, jump_rpm, ranges, min_preload, min_rate, margin, (kin, train, parts, projection))
    if terms.kept:  # a radius sweep's next design: the same torque, power and angles, the same summaries
        terms.share_summaries(result)
    return result
