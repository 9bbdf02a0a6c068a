"""Contact fatigue and life of a cam and its follower roller: Hertz line contact below the
surface, the case depth to ask for, a cycles-based allowable, the roller bearing's L10 life.

From the contact force of :func:`camgen.dynamics.analyse` (N, along the common normal) at each
cam angle and the contact's geometry (:class:`camgen.dynamics.ContactMaterial`, the profile's
signed radius of curvature, the follower's radius):

* Hertz line contact of two parallel cylinders (Johnson, *Contact Mechanics*, CUP 1985,
  eqs. 4.43-4.45), load per unit length ``P = F / width``, ``1/R = 1/rho_cam + 1/rho_follower``,
  ``1/E* = (1-nu_c^2)/E_c + (1-nu_f^2)/E_f``: half-width ``b = sqrt(4 P R / (pi E*))``, peak
  pressure ``p_max = 2 P / (pi b)`` (the same ``p_max`` as :func:`camgen.dynamics.hertz_line_stress`).
  Below the centre of the strip the principal shear stress ``tau_1 = (sigma_x - sigma_z) / 2``
  (McEwen's closed form, Johnson eq. 4.45 with ``y = 0``) peaks at ``0.30 p_max`` at a depth
  ``0.78 b`` (Johnson §4.2); :data:`SHEAR_PEAK_RATIO`, :data:`SHEAR_DEPTH_RATIO`.
* Case depth asked for: ``case_depth_factor`` times the deepest depth of the maximum shear
  over the turn (a rule of thumb, the user's to set: the hardened case must carry the shear
  peak well inside it; default :data:`CASE_DEPTH_FACTOR`).
* A cycles-based allowable contact stress from an S-N point ``(N_ref, S_ref)`` and an exponent
  ``m`` (Basquin's form ``S^m N = const``): ``S(N) = S_ref (N_ref / N)^(1/m)`` at the cam's
  design life ``N`` (cycles: cam turns; every point of the cam is loaded once a turn).
* The roller bearing's basic rating life (ISO 281:2007, eq. 1): ``L10 = (C / P)^p`` million
  revolutions, ``p = 10/3`` roller bearings, ``3`` ball bearings, with the equivalent load over
  the turn by the mean-load rule for a varying load (ISO 281 / Harris, *Rolling Bearing
  Analysis*): ``P = (sum |F_i|^p dN_i / sum dN_i)^(1/p)``, ``dN_i`` the roller's revolutions on
  its pin at sample ``i`` (:func:`roller_spin`).  Hours: ``L10 1e6 / (n_turn rpm 60)`` with
  ``n_turn`` the roller's revolutions per cam turn.

Roller spin (rolling without slip at the contact; derived here): with ``V = dC/dtheta`` the
roller centre's velocity relative to the cam per radian of cam angle (the pitch curve's
tangent, ``|V|`` mm/rad), the cam turning ``sigma`` (+1 ccw) and the roller on the outside of
the profile, the roller's absolute angular velocity per unit cam speed is
``sigma (1 - |V| / R)`` (the contact is the roller's instant centre relative to the cam; the
cam frame itself turns at ``sigma``); an oscillating arm turns at ``tau s'``, so on its pin the
roller turns at ``sigma (1 - |V|/R) - tau s'``.  Over a turn a translating follower's roller
makes ``L_profile / (2 pi R)`` revolutions (the pitch curve is ``2 pi R`` longer than the
profile): the tests check this against the profile's length.

Units: mm, N, MPa, rad inside; results MPa, mm, million revolutions, hours.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.errors import ParameterError, require_finite

__all__ = [
    "BALL_EXPONENT", "CASE_DEPTH_FACTOR", "ContactLife", "LIFE_EXPONENTS", "ROLLER_EXPONENT", "SHEAR_DEPTH_RATIO",
    "SHEAR_PEAK_RATIO", "SnCurve", "bearing_life", "contact_life", "equivalent_load", "hertz_half_width",
    "subsurface_shear",
]

#: Johnson, Contact Mechanics §4.2: line contact, the largest principal shear stress below the
#: surface is 0.30 p_max ...
SHEAR_PEAK_RATIO = 0.30
#: ... at a depth of 0.78 b under the centre of the contact strip.
SHEAR_DEPTH_RATIO = 0.78
#: Default multiple of the depth of the maximum shear asked for as the case depth (a rule of thumb).
CASE_DEPTH_FACTOR = 2.0
#: ISO 281 life exponents: roller bearings 10/3, ball bearings 3.
ROLLER_EXPONENT = 10.0 / 3.0
BALL_EXPONENT = 3.0
LIFE_EXPONENTS = {"roller": ROLLER_EXPONENT, "ball": BALL_EXPONENT}
#: A life of more than 10^300 million revolutions is stated as unbounded (no float overflow).
MAX_LIFE_DECADES = 300.0
#: Million revolutions per L10 unit.
MILLION = 1e6


def hertz_half_width(force: np.ndarray, curvature: np.ndarray, width: float, compliance: float) -> np.ndarray:
    """Half-width ``b`` (mm) of a Hertz line contact, elementwise (Johnson eq. 4.43):
    ``b = sqrt(4 P R / (pi E*))`` with ``P = F / width`` (N/mm), ``R = 1 / curvature`` (mm),
    ``1/E* = compliance`` (1/MPa).  A force <= 0 (lifted) or a curvature <= 0 (no line
    contact) gives 0."""
    force, curvature = np.broadcast_arrays(np.asarray(force, dtype=float), np.asarray(curvature, dtype=float))
    ok = (force > 0) & (curvature > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        b = np.sqrt(4.0 * np.where(ok, force, 0.0) * compliance / (math.pi * width * np.where(ok, curvature, 1.0)))
    return np.where(ok, b, 0.0)


def subsurface_shear(p_max: np.ndarray, half_width: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The largest sub-surface principal shear stress (MPa) and its depth (mm) under a line
    contact of peak pressure ``p_max`` (MPa) and half-width ``b`` (mm): ``0.30 p_max`` at
    ``0.78 b`` (Johnson §4.2)."""
    return SHEAR_PEAK_RATIO * np.asarray(p_max, dtype=float), SHEAR_DEPTH_RATIO * np.asarray(half_width, dtype=float)


@dataclass(frozen=True)
class SnCurve:
    """A contact-fatigue S-N point and slope: ``stress`` MPa survives ``cycles``; exponent ``m``
    of Basquin's form ``S^m N = const``.  ``allowable(N) = stress (cycles / N)^(1/m)``."""

    stress: float
    cycles: float
    exponent: float

    def __post_init__(self) -> None:
        for name, key in (("stress", "sn_stress_mpa"), ("cycles", "sn_cycles"), ("exponent", "sn_exponent")):
            if not require_finite(key, getattr(self, name)) > 0:
                raise ParameterError(key, getattr(self, name), f"{key} > 0")

    def allowable(self, cycles: float) -> float:
        """Allowable contact stress (MPa) at ``cycles`` (> 0)."""
        return float(self.stress * (self.cycles / cycles) ** (1.0 / self.exponent))


def equivalent_load(force: np.ndarray, revolutions: np.ndarray, exponent: float) -> float:
    """The bearing's equivalent load (N) over a varying load: ``(sum |F|^p dN / sum dN)^(1/p)``
    (the mean-load rule of ISO 281), ``revolutions`` the revolutions ``dN`` (>= 0) each sample
    stands for.  0 when the roller does not turn."""
    total = float(np.sum(revolutions))
    if not total > 0:
        return 0.0
    return float((np.sum(np.abs(force) ** exponent * revolutions) / total) ** (1.0 / exponent))


def bearing_life(rating: float, load: float, exponent: float) -> float:
    """ISO 281 basic rating life ``(C / P)^p`` in million revolutions (inf for ``P = 0``)."""
    if not load > 0 or exponent * math.log10(rating / load) > MAX_LIFE_DECADES:
        return math.inf  # beyond any float (and any machine): unbounded
    return float((rating / load) ** exponent)


@dataclass(frozen=True, eq=False)
class ContactLife:
    """Contact fatigue over a turn (arrays (N,) over the cam angles of the dynamics).

    Attributes
    ----------
    half_width : mm, Hertz half-width ``b`` (contact 1).
    p_max : MPa, the Hertz peak pressure.
    shear : MPa, the largest sub-surface principal shear stress (0.30 p_max).
    shear_depth : mm, its depth (0.78 b).
    case_depth : mm, the case depth to ask for (``case_depth_factor`` x the deepest ``shear_depth``).
    case_depth_factor : the multiple used.
    allowable : MPa, the S-N allowable at ``design_cycles`` (None: no S-N point given).
    design_cycles : cam turns the allowable is for (None: not given).
    roller_revs_per_turn : the roller's revolutions on its pin per cam turn (None: no roller).
    equivalent_load : N, the bearing's equivalent load P (None: no load rating given).
    l10_mrev, l10_hours : the basic rating life, million revolutions and hours at the cam speed.
    life_exponent : p (10/3 roller, 3 ball).
    """

    half_width: np.ndarray
    p_max: np.ndarray
    shear: np.ndarray
    shear_depth: np.ndarray
    case_depth: float
    case_depth_factor: float
    allowable: float | None = None
    design_cycles: float | None = None
    roller_revs_per_turn: float | None = None
    equivalent_load: float | None = None
    l10_mrev: float | None = None
    l10_hours: float | None = None
    life_exponent: float | None = None


def contact_life(force: np.ndarray, p_max: np.ndarray, curvature: np.ndarray, width: float, compliance: float, *,
                 case_depth_factor: float = CASE_DEPTH_FACTOR, sn: SnCurve | None = None, design_cycles: float | None = None,
                 roller_spin: np.ndarray | None = None, weights: np.ndarray | None = None, rating: float | None = None,
                 exponent: float = ROLLER_EXPONENT, rpm: float | None = None) -> ContactLife:
    """Contact fatigue and the roller bearing's life over a turn.

    Parameters
    ----------
    force : N, contact force at each cam angle (< 0: lifted, no load).
    p_max : MPa, the Hertz peak pressure there (:func:`camgen.dynamics.hertz_line_stress`).
    curvature : 1/mm, the combined curvature ``1/rho_cam + 1/rho_follower``.
    width : mm, contact length; compliance : 1/MPa, ``1/E*``.
    case_depth_factor : the case depth asked for, in depths of the maximum shear.
    sn, design_cycles : an S-N curve and the cam turns to hold (both or neither).
    roller_spin : the roller's angular velocity on its pin per unit cam speed (rad/rad) at each
        sample (:func:`camgen.friction.roller_spin`); with ``weights`` (rad, periodic trapezoid)
        it gives the revolutions each sample stands for.
    rating : N, the roller bearing's dynamic load rating C; exponent : p; rpm : cam speed.
    """
    b = hertz_half_width(force, curvature, width, compliance)
    shear, depth = subsurface_shear(p_max, b)
    factor = require_finite("case_depth_factor", case_depth_factor)
    out = ContactLife(b, np.asarray(p_max, dtype=float), shear, depth, factor * float(np.max(depth)), factor)
    allowable = None
    if sn is not None:
        if design_cycles is None or not require_finite("design_cycles", design_cycles) > 0:
            raise ParameterError("design_cycles", design_cycles, "design_cycles > 0 (cam turns) with an S-N curve")
        allowable = sn.allowable(design_cycles)
    revs = load = l10 = hours = None
    if roller_spin is not None and weights is not None:
        per_sample = np.abs(roller_spin) * weights / (2.0 * math.pi)  # revolutions on the pin at each sample
        revs = float(np.sum(per_sample))
        if rating is not None:
            load = equivalent_load(np.maximum(force, 0.0), per_sample, exponent)
            l10 = bearing_life(rating, load, exponent)
            if rpm is not None and math.isfinite(l10) and revs > 0:
                hours = l10 * MILLION / (revs * rpm * 60.0)
            elif not math.isfinite(l10) or revs == 0:
                hours = math.inf
    return ContactLife(out.half_width, out.p_max, out.shear, out.shear_depth, out.case_depth, factor, allowable,
                       design_cycles if sn is not None else None, revs, load, l10, hours,
                       exponent if rating is not None else None)
