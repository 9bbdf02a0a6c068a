"""Friction and loads of a cam's follower train: the guide's bushing reactions and binding, the
roller pin's friction and the roller's slip, a flat face's friction torque on the camshaft.

First-order friction: every friction force is Coulomb's ``mu N`` with ``N`` from the
frictionless contact force of :func:`camgen.dynamics.analyse` (N, along the common normal);
the friction does not feed back into that force.  Each friction's torque on the camshaft
follows from the power it dissipates (the power balance of :mod:`camgen.dynamics`):
``T w = mu N v_slip``, so ``T = mu N (v_slip / w)`` with ``v_slip / w`` per radian of cam angle.

* Guide of a translating follower (statics of the stem, derived here): two bushings a
  ``guide_length`` L apart, the near one ``guide_overhang`` a from the contact along the stem.
  The cam's force on the follower, lateral ``Fx`` and axial ``Fy``, acts ``x`` off the stem's
  axis (0 for a roller or a knife, whose force passes through the roller centre or tip on the
  axis; a flat face's contact point lies ``face_position`` along the face).  Lateral balance
  and moments about the near bushing give ``R2 = (x Fy + a Fx) / L`` (far bushing) and
  ``R1 = -Fx - R2`` (near).  A roller (``Fx = F sin phi``, the side load ``F_axial tan phi``)
  has ``|R1| = Fx (L + a) / L``, ``|R2| = Fx a / L``.  A flat face adds its own friction across
  the face, ``Fx = -sigma mu_c F`` (the cam's surface drags the face along its motion).
* Binding (self-locking of the sliding pair, Coulomb's law at each bushing): the bushings'
  friction ``mu_g (|R1| + |R2|)`` resists the stem's motion; the cam cannot drive it where
  that friction reaches the axial component, ``mu_g (|R1| + |R2|) >= Fy``.  For a roller this
  is ``tan phi >= L / (mu_g (L + 2a))``: :func:`binding_ratio` is their quotient (binds at >= 1).
* Roller pin (journal friction, the pin carrying the contact force): torque
  ``mu_p F r_pin`` on the roller; the roller slips where the torque that turns it (pin friction
  plus its inertia ``J alpha``) exceeds the traction the contact holds, ``mu_c F R``.
* Flat face (derived from the sliding speed): the face, normal fixed along the motion, touches
  the cam at a point ``h`` from the cam axis along the normal (the face's distance from the
  axis, the support function; ``h = rho_cam - s''`` as ``rho = h + h''``).  The cam's surface
  slides along the face at ``w h`` (the face does not move across itself), so the friction
  torque on the camshaft is ``mu_c F h``.

Units: mm, N, rad inside; torques N*m at the edge, reactions N.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.errors import ParameterError, require_finite

__all__ = [
    "DEFAULT_CONTACT_FRICTION", "DEFAULT_GUIDE_FRICTION", "DEFAULT_PIN_FRICTION", "FrictionGeometry", "FrictionResult",
    "FrictionSettings", "analyse_friction", "binding_ratio", "face_distance", "guide_reactions", "roller_spin",
]

#: Bushing friction of the guide: lubricated steel in a bronze bushing (a common design value).
DEFAULT_GUIDE_FRICTION = 0.1
#: Roller on its pin: a plain (bushed) roller, boundary-lubricated.
DEFAULT_PIN_FRICTION = 0.1
#: At the cam contact: lubricated steel on steel (sliding of a flat face; the traction a roller can take).
DEFAULT_CONTACT_FRICTION = 0.1
#: N*mm per N*m.
N_MM_PER_N_M = 1e3
#: kg*mm^2 * rad/s^2 -> N*mm (1 kg*mm^2/s^2 = 1e-6 N*m = 1e-3 N*mm).
KG_MM2_PER_S2_TO_N_MM = 1e-3


def guide_reactions(lateral: np.ndarray, axial: np.ndarray, offset: np.ndarray | float, overhang: float,
                    length: float) -> tuple[np.ndarray, np.ndarray]:
    """Signed lateral reactions (N) of the near and far bushings of a translating follower's
    guide on the stem, from lateral and moment equilibrium: the cam's force ``(lateral, axial)``
    (N) acts ``offset`` (mm) off the axis, ``overhang`` (mm) short of the near bushing; the
    bushings are ``length`` (mm) apart.  ``R_far = (offset axial + overhang lateral) / length``,
    ``R_near = -lateral - R_far``."""
    far = (np.asarray(offset, dtype=float) * axial + overhang * np.asarray(lateral, dtype=float)) / length
    near = -np.asarray(lateral, dtype=float) - far
    return near, far


def binding_ratio(friction: float, near: np.ndarray, far: np.ndarray, axial: np.ndarray) -> np.ndarray:
    """``mu (|R1| + |R2|) / F_axial`` where the cam pushes the follower (axial > 0), 0 elsewhere:
    the guide binds where it reaches 1 (Coulomb friction at both bushings locks the stem)."""
    axial = np.asarray(axial, dtype=float)
    held = friction * (np.abs(near) + np.abs(far))
    pushed = axial > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(pushed, held / np.where(pushed, axial, 1.0), 0.0)


def roller_spin(pitch_d1: np.ndarray, pitch_d2: np.ndarray, roller_radius: float, sigma: float, tau: float = 0.0,
                ds: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The roller's angular velocity on its pin and its absolute angular acceleration, per unit
    cam speed (rad/rad and rad/rad^2), from rolling without slip (module :mod:`camgen.contact_life`):
    ``spin = sigma (1 - |V| / R) - tau s'`` (``tau s'`` the oscillating arm's own rate, 0
    translating) and ``d/dtheta`` of the absolute part, ``-sigma (V . V') / (|V| R)``.

    ``pitch_d1``, ``pitch_d2`` (N, 2): the pitch curve's first and second derivatives per radian of
    cam angle in the cam frame (mm/rad, mm/rad^2)."""
    speed = np.hypot(pitch_d1[:, 0], pitch_d1[:, 1])
    absolute = sigma * (1.0 - speed / roller_radius)
    arm = 0.0 if ds is None else tau * np.asarray(ds, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        dspeed = np.where(speed > 0, np.sum(pitch_d1 * pitch_d2, axis=1) / np.where(speed > 0, speed, 1.0), 0.0)
    return absolute - arm, -sigma * dspeed / roller_radius


def face_distance(rho_cam: np.ndarray, d2s: np.ndarray) -> np.ndarray:
    """A translating flat face's distance from the cam axis (mm) along its normal: the support
    function ``h = rho - h''`` (``rho = h + h''``, ``h'' = s''``)."""
    return np.asarray(rho_cam, dtype=float) - np.asarray(d2s, dtype=float)


@dataclass(frozen=True)
class FrictionSettings:
    """The friction the scene asks for (None: that part is not computed).

    Attributes
    ----------
    guide_length, guide_overhang : mm, the bushings' spacing and the contact to the near bushing.
    guide_friction : the bushings' Coulomb coefficient.
    contact_friction : at the cam contact: a flat face's sliding, a roller's traction limit.
    pin_friction, pin_radius : the roller on its pin (coefficient, mm).
    roller_inertia : kg*mm^2, the roller about its pin (for the slip check; 0: not counted).
    """

    guide_length: float | None = None
    guide_overhang: float | None = None
    guide_friction: float = DEFAULT_GUIDE_FRICTION
    contact_friction: float | None = None
    pin_friction: float = DEFAULT_PIN_FRICTION
    pin_radius: float | None = None
    roller_inertia: float = 0.0

    def __post_init__(self) -> None:
        for name in ("guide_friction", "pin_friction", "roller_inertia"):
            if not require_finite(name, getattr(self, name)) >= 0:
                raise ParameterError(name, getattr(self, name), f"{name} >= 0")
        if (self.guide_length is None) != (self.guide_overhang is None):
            raise ParameterError("guide_overhang", self.guide_overhang, "given together with guide_length (both mm)")
        if self.guide_length is not None and not require_finite("guide_length", self.guide_length) > 0:
            raise ParameterError("guide_length", self.guide_length, "guide_length > 0 mm")
        if self.guide_overhang is not None and not require_finite("guide_overhang", self.guide_overhang) >= 0:
            raise ParameterError("guide_overhang", self.guide_overhang, "guide_overhang >= 0 mm")
        if self.contact_friction is not None and not require_finite("contact_friction", self.contact_friction) >= 0:
            raise ParameterError("contact_friction", self.contact_friction, "contact_friction >= 0")
        if self.pin_radius is not None and not require_finite("pin_radius", self.pin_radius) > 0:
            raise ParameterError("pin_radius", self.pin_radius, "pin_radius > 0 mm")


@dataclass(frozen=True, eq=False)
class FrictionGeometry:
    """What the friction needs of the contact besides :class:`camgen.dynamics.Kinematics`.

    Attributes
    ----------
    follower : ``"roller"``, ``"flat"`` or ``"knife"``; motion : ``"translating"`` / ``"oscillating"``.
    sigma : +1 ccw cam, -1 cw; tau : oscillating arm, +1 when a positive swing turns it ccw.
    roller_radius : mm (rollers).
    face_position : mm (N,), a translating flat face's contact from the stem's axis along +x.
    roller_spin, roller_spin_rate : rad/rad (N,), :func:`roller_spin` (rollers).
    """

    follower: str
    motion: str
    sigma: float = 1.0
    tau: float = 1.0
    roller_radius: float = 0.0
    face_position: np.ndarray | None = None
    roller_spin: np.ndarray | None = None
    roller_spin_rate: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class FrictionResult:
    """Friction loads and torques over a turn (arrays (N,); None: not computed).

    Attributes
    ----------
    side_load : N, the force across a translating follower's motion (its guide load).
    guide_near, guide_far : N, the bushing reactions (signed).
    binding : the binding ratio ``mu_g (|R1| + |R2|) / F_axial`` (>= 1: binds).
    guide_torque, pin_torque_shaft, face_torque : N*m, each friction's torque on the camshaft.
    pin_torque : N*mm, the pin's friction torque on the roller.
    slip : the roller's slip ratio, torque to turn it / traction the contact holds (> 1: slips;
        0 where the contact carries no force).
    friction_torque : N*m, their sum; total_torque : N*m, the frictionless torque plus it.
    """

    side_load: np.ndarray | None = None
    guide_near: np.ndarray | None = None
    guide_far: np.ndarray | None = None
    binding: np.ndarray | None = None
    guide_torque: np.ndarray | None = None
    pin_torque: np.ndarray | None = None
    pin_torque_shaft: np.ndarray | None = None
    slip: np.ndarray | None = None
    face_torque: np.ndarray | None = None
    friction_torque: np.ndarray | None = None
    total_torque: np.ndarray | None = None


def analyse_friction(contact_force: np.ndarray, pressure_angle: np.ndarray, ds: np.ndarray, d2s: np.ndarray,
                     rho_cam: np.ndarray, frictionless_torque: np.ndarray, omega: float, geometry: FrictionGeometry,
                     settings: FrictionSettings) -> FrictionResult:
    """The friction of ``settings`` over a turn.

    Parameters
    ----------
    contact_force : N, along the common normal (< 0: lifted; counted as 0).
    pressure_angle : rad; ds, d2s : the law's s', s'' (mm/rad, mm/rad^2 translating).
    rho_cam : mm, the profile's signed radius of curvature at the contact.
    frictionless_torque : N*m, :attr:`camgen.dynamics.DynamicsResult.torque`.
    omega : rad/s, the cam speed.
    """
    force = np.maximum(np.asarray(contact_force, dtype=float), 0.0)
    zero = np.zeros_like(force)
    friction = zero.copy()
    out: dict[str, np.ndarray] = {}
    mu_c = settings.contact_friction
    flat = geometry.follower == "flat"
    if flat and mu_c is not None:
        out["face_torque"] = mu_c * force * face_distance(rho_cam, d2s) / N_MM_PER_N_M
        friction = friction + out["face_torque"]
    if geometry.motion == "translating":
        axial = force * np.cos(pressure_angle)
        lateral = force * np.sin(pressure_angle)
        offset: np.ndarray | float = 0.0
        if flat:
            if mu_c is not None:
                lateral = lateral - geometry.sigma * mu_c * force  # the cam's surface drags the face along -sigma x
            assert geometry.face_position is not None  # a translating flat face's contact point
            offset = geometry.face_position
        out["side_load"] = lateral
        if settings.guide_length is not None and settings.guide_overhang is not None:
            near, far = guide_reactions(lateral, axial, offset, settings.guide_overhang, settings.guide_length)
            out["guide_near"], out["guide_far"] = near, far
            out["binding"] = binding_ratio(settings.guide_friction, near, far, axial)
            out["guide_torque"] = settings.guide_friction * (np.abs(near) + np.abs(far)) * np.abs(ds) / N_MM_PER_N_M
            friction = friction + out["guide_torque"]
    if geometry.follower == "roller" and geometry.roller_spin is not None and (settings.pin_radius is not None
                                                                             or settings.roller_inertia > 0):
        pin = settings.pin_friction * force * (settings.pin_radius or 0.0)  # N*mm on the roller
        out["pin_torque"] = pin
        out["pin_torque_shaft"] = pin * np.abs(geometry.roller_spin) / N_MM_PER_N_M  # its power over w
        friction = friction + out["pin_torque_shaft"]
        assert geometry.roller_spin_rate is not None  # set with the spin
        inertia = settings.roller_inertia * omega**2 * np.abs(geometry.roller_spin_rate) * KG_MM2_PER_S2_TO_N_MM
        traction = (DEFAULT_CONTACT_FRICTION if mu_c is None else mu_c) * force * geometry.roller_radius
        need = pin + inertia
        loaded = force > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            out["slip"] = np.where(loaded, need / np.where(traction > 0, traction, math.inf), 0.0)
            out["slip"] = np.where(loaded & (traction == 0) & (need > 0), math.inf, out["slip"])
    out["friction_torque"] = friction
    out["total_torque"] = np.asarray(frictionless_torque, dtype=float) + friction
    return FrictionResult(**out)
