"""Dynamics of a barrel cam: its keys, its follower kinematics for :func:`camgen.dynamics.analyse`,
and where the roller changes walls.

The groove of a barrel cam is form-closed, as a plate's groove is (:mod:`camgen.kinds.groove`):
its two walls hold the roller both ways, so the train has no spring (the spring keys and
``jump_margin_n`` are refused) and cannot jump; contact 1 is the **lower wall** (below the roller
axis, it pushes the follower towards +s: up the cam axis, or the arm towards +psi) and contact 2
the **upper wall**.  Conventions: :mod:`camgen.synthesis.barrel`.

The model (rigid train, frictionless contact, :mod:`camgen.dynamics`):

* **Coordinate.** Translating: the lift s (mm), the roller axis at height z0 + s; the moving mass
  ``mass_kg``.  Oscillating: the arm's swing (rad) about the pivot axis (parallel to x), the arm's
  moment of inertia ``inertia_kg_m2`` about it; the generalised force Q is a torque (N*mm).
* **Where the contact acts.** The contact runs along the roller from the root to the rim; its
  resultant is taken at the **mean radius** R_m, the middle of the engaged length (a load spread
  evenly along the contact line), i.e. on the roller's section whose centre lies at R_m from the
  cam axis.  Its direction there is the wall normal of that section's contact, at the pressure
  angle :meth:`camgen.synthesis.barrel.BarrelGroove.pressure_angle` (translating
  ``tan(alpha) = s' / R_m``), the same line for both walls (their contacts lie on opposite ends of
  one diameter of the section).  The normal force is then ``Q / cos(alpha)`` (translating) or
  ``Q / (L cos(alpha))`` (oscillating: every point of the roller axis moves at ``L psi' w`` about
  the pivot).
* **Camshaft torque** from the power balance ``T w = Q w q'`` (:func:`camgen.dynamics.analyse`):
  exact whatever the contact's moment arm about the cam axis (the mean radius, not a plate's polar
  radius), so no lever of the cam enters.
* **Hertz stress** (line contact, Johnson, *Contact Mechanics*, 1985, eq. 4.45 with
  ``1/R = 1/R1 + 1/R2``): the roller, a cylinder of radius Rr (the real roller, not widened)
  whose axis lies along the contact line, against the wall's section perpendicular to it at the
  mean radius.  That section is taken on the cylinder r = R_m developed flat (the standard
  treatment of a cylindrical cam as a translating cam unrolled at its pitch radius): the
  developed pitch curve ``(x, z) = (R_m (asin(e / R_m) - sigma theta), z_c)`` has the signed
  curvature ``kappa`` (> 0 where it bends towards +z, a valley) and the walls are its offsets by
  w = Rr + c / 2, so the wall's radius of curvature seen from the roller is
  ``rho_lower = -(1 / kappa + w)`` and ``rho_upper = 1 / kappa - w`` (> 0 convex towards the
  roller, < 0 concave; translating ``kappa = R_m s'' / (R_m^2 + s'^2)^(3/2)``).  The contact
  length (``contact_width_mm``) defaults to the groove's depth, the engaged length of the roller.
  A conical roller's contact leans along the cone; its Hertz stress is not modelled (the contact
  keys are refused for it), its forces and torque are.  Where the developed pitch curve bends
  tighter than w a wall folds: the dynamics are then stated as not computed (as for a plate cam
  that cannot be made).
* **Gravity** acts in the plane the follower moves in, the plane tangent to the cylinder at the
  follower's station, (y, z): ``gravity_deg`` is measured there counter-clockwise from +y towards
  +z (default -90: along -z, down the axis of a cam standing on its bottom face).
"""
from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.errors import ParameterError

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.dynamics import Kinematics
    from camgen.kinds.base import CamSpec
    from camgen.kinds.dynamics import DynamicsSpec
    from camgen.schema import Key

__all__ = ["barrel_crossovers", "barrel_dynamics_keys", "barrel_kinematics", "developed_curvature",
           "read_barrel_dynamics"]

_DOCS = {
    "gravity": "The follower's weight loads the contact, along gravity_deg in the plane the follower moves in (false: gravity "
               "lies along the radial line x through the follower's station and does not load it).",
    "gravity_deg": "Direction of gravity in the plane tangent to the cylinder at the follower's station (y, z), counter-clockwise "
                   "from +y towards +z (-90: along -z, down the axis of a cam standing on its bottom face).",
    "contact_width_mm": "Length of the contact line for the Hertz stress (cylindrical roller): the engaged length of the roller, "
                        "default groove_depth_mm (give the roller's width if it is shorter). A conical roller has no Hertz check "
                        "(refused).",
}


def barrel_dynamics_keys() -> tuple["Key", ...]:
    """The dynamics keys of a barrel cam: the disk cams' (:func:`camgen.kinds.dynamics.dynamics_keys`)
    with the gravity direction and the contact length documented in the barrel's frame; the spring
    keys and ``jump_margin_n`` stay listed so that :func:`read_barrel_dynamics` refuses them saying
    why (the groove is form-closed)."""
    from camgen.kinds.dynamics import dynamics_keys

    return tuple(replace(k, doc=_DOCS[k.name]) if k.name in _DOCS else k for k in dynamics_keys())


def read_barrel_dynamics(where: str, parsed: Mapping[str, Any], *, motion: str, roller_shape: str, depth: float,
                         rpm: float | None, base_dir: Path | None = None) -> "DynamicsSpec | None":
    """The follower train of a barrel cam table (None without dynamics keys): read as a groove
    cam's (form-closed: springs and the jump margin refused), the contact length defaulting to the
    groove ``depth`` (mm); a conical roller's contact keys refused and its material left out (no
    Hertz stress)."""
    from camgen.kinds.dynamics import CONTACT_KEYS, dynamics_keys, read_dynamics
    from camgen.schema import given_keys

    dyn = read_dynamics(where, parsed, motion=motion, follower="roller", rpm=rpm, thickness=depth, base_dir=base_dir,
                        form_closed=True)
    if dyn is None or roller_shape != "conical":
        return dyn
    keys = {k.name: k for k in dynamics_keys()}
    given = given_keys(parsed, tuple(keys.values()))
    for name in CONTACT_KEYS:
        if name in given:
            key = keys[name]
            raise ParameterError(f"{where}.{name}", key.type.to_scene(parsed.get(key.field)), 'left out with roller_shape = "conical"',
                                 "a cone's contact leans along its generator: its Hertz stress is not modelled (a cylindrical "
                                 "roller's is)")
    return replace(dyn, material=None)


def developed_curvature(groove: Any, theta: np.ndarray) -> np.ndarray:
    """Signed curvature (1/mm, > 0 where the curve bends towards +z) of the pitch curve developed at
    the mean radius, ``(x, z) = (R_m (asin(e / R_m) - sigma theta), z_c)``
    (:meth:`camgen.synthesis.barrel.BarrelGroove.pitch_developed`), in closed form from the law:
    ``kappa = (x' z'' - z' x'') sign(x') / (x'^2 + z'^2)^(3/2)`` (derivatives by theta).  A roller
    riding ``o = groove.axis_offset`` off the pitch line (a rib's): translating, the curve shifted
    along z (the same curvature); oscillating, the end of an arm of length ``hypot(L, o)`` at
    ``psi + atan2(o, L)`` about the same pivot (``e = hypot(L, o) cos(psi') - L``)."""
    lay = groove.layout
    rm, sig = lay.mean_radius, lay.sigma
    s, s1, s2, _ = groove.law(np.asarray(theta, dtype=float))
    if lay.motion == "translating":
        x1, x2 = np.full_like(s, -sig * rm), np.zeros_like(s)
        z1, z2 = s1, s2
    else:
        arm, psi = lay.arm_length, lay.rest_angle + s
        offset = float(getattr(groove, "axis_offset", 0.0))
        if offset:  # ROSC: a rib's roller on the arm's normal (BarrelGroove.axis_offset)
            psi = psi + math.atan2(offset, arm)
            arm = math.hypot(arm, offset)
        cos, sin = np.cos(psi), np.sin(psi)
        e = arm * (cos - 1.0) if not offset else arm * cos - lay.arm_length
        e1, e2 = -arm * sin * s1, -arm * (sin * s2 + cos * s1 * s1)
        z1, z2 = arm * cos * s1, arm * (cos * s2 - sin * s1 * s1)
        root = np.sqrt(1.0 - (e / rm) ** 2)  # d/dtheta of R_m asin(e / R_m) is e' / root
        x1 = e1 / root - sig * rm
        x2 = e2 / root + e1 * e1 * e / (rm * rm * root**3)
    return (x1 * z2 - z1 * x2) * np.sign(x1) / (x1 * x1 + z1 * z1) ** 1.5


def barrel_kinematics(cam: Any, spec: "CamSpec") -> tuple["Kinematics", float]:
    """The dynamics kinematics of a barrel cam (a :class:`camgen.kinds.barrel.BarrelCam`: its
    ``groove``, ``params`` and ``motion``; module notes) on its check grid and the arm length
    (mm, oscillating; 0 translating): contact 1 the lower wall, contact 2 the upper, both along the
    normal at the mean radius, each against the real roller (radius Rr)."""
    from camgen import dynamics as dy
    from camgen.kinds.dynamics import checked_kinematics

    g, p = cam.groove, cam.params
    theta = cam.motion.cam_angle
    s, s1, s2, _ = g.law(theta)
    alpha = g.pressure_angle(np.asarray(p.mean_radius), theta)
    kappa = developed_curvature(g, theta)
    w = g.half_width
    with np.errstate(divide="ignore"):
        rho_pitch = np.where(kappa != 0.0, 1.0 / np.where(kappa != 0.0, kappa, 1.0), np.inf)  # inf where straight
    folds = np.abs(rho_pitch) < w
    if folds.any():  # a wall offset by w from a pitch curve bending tighter than w has a cusp: no contact stress there
        from camgen.kinds.dynamics import DynamicsNotComputed

        i = int(np.argmin(np.abs(rho_pitch)))
        raise DynamicsNotComputed(
            f"the pitch curve developed at the mean radius bends to a radius of {abs(rho_pitch[i]):.6g} mm at cam angle "
            f"{math.degrees(theta[i]):.6g} deg, tighter than the groove's half width {w:g} mm: a wall folds there (see the undercut "
            "check), so the contact forces and stresses are computed for a groove that can be made")
    lower, upper = -(rho_pitch + w), rho_pitch - w  # inf - w = inf: a straight wall
    if p.follower.motion == "translating":
        direction: Any = math.pi / 2  # along +z in the (y, z) plane, measured from +y
        arm = 0.0
    else:
        direction = p.rest_angle + s + math.pi / 2  # the roller axis moves along (-sin psi, cos psi)
        arm = p.arm_length
    kin = checked_kinematics(lambda: dy.Kinematics(theta, s, s1, s2, alpha, lower, p.roller_radius, direction,
                                                   pressure_angle_2=alpha, rho_cam_2=upper, follower_radius_2=p.roller_radius))
    return kin, arm


def barrel_crossovers(cam: Any, rpm: float | None) -> "CheckResult":
    """Where the roller of a :class:`camgen.kinds.barrel.BarrelCam` changes walls with inertia the
    only load: the zeros of the law's s'' where it changes sign (the axial inertia force, or the
    arm's inertia torque, changes sign there), each found by bisection on the law between two
    check-grid samples (as the groove cam's ``wall_crossover``)."""
    from camgen.checks import information, where_degrees

    from camgen.kinds.groove import acceleration_zeros

    m = cam.motion
    zeros = acceleration_zeros(cam.law, m)
    if zeros is None:
        return information("wall_crossover", 0, "", [], "the acceleration never changes sign: the roller stays on one wall")
    angles, here = zeros
    what = "axial inertia force" if m.unit == "mm" else "arm's inertia torque"
    crosses = (f"the roller crosses the {cam.params.clearance:g} mm clearance from the lower wall to the upper or back"
               if getattr(cam, "rib", None) is None else  # ROSC: a rib's two rollers
               f"the load passes from the rib's upper roller to its lower one or back, the follower crossing the "
               f"{cam.params.clearance:g} mm clearance")
    note = (f"{angles.size} cam angles where the follower's acceleration changes sign: with inertia the only load the {what} "
            f"changes sign there and {crosses} (crossover shock; an external load or the weight moves these angles: the dynamics' contact_force check lists "
            "where the load crosses)")
    if rpm:
        omega = 2.0 * math.pi * rpm / 60.0
        scale, unit = (1e-3, ("m/s", "m/s^3")) if m.unit == "mm" else (1.0, ("rad/s", "rad/s^3"))
        speed = float(np.max(np.abs(m.velocity[here]))) * omega * scale
        jerk = float(np.max(np.abs(m.jerk[here]))) * omega**3 * scale
        note += (f"; at {rpm:g} rpm the follower moves at up to {speed:.6g} {unit[0]} there, the acceleration passing zero at up "
                 f"to {jerk:.6g} {unit[1]}")
    return information("wall_crossover", int(angles.size), "", where_degrees(np.sort(angles)), note)
