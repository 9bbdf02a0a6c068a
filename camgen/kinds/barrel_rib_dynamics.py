"""Dynamics of a barrel cam's rib (track = "rib"): the follower kinematics of its two rollers for
:func:`camgen.dynamics.analyse`, and the form's follower-dynamics entry (a rib's or a groove's).

The rib is form-closed, as the groove is (:mod:`camgen.kinds.barrel_dynamics`, whose keys, reading
and model this follows): its two faces hold the follower both ways between its two rollers, so the
train has no spring (the spring keys and ``jump_margin_n`` are refused) and cannot jump.
``mass_kg`` (translating) and ``inertia_kg_m2`` (oscillating, about the pivot) are the whole
follower's, **both rollers included** (the second roller's mass, and on an arm its
``m (L^2 + o^2)``, count there); ``cg_distance_mm`` locates the whole arm's centre of mass.

**Which roller carries the load (the sign rule).**  ``Q`` is the generalised force the cam must
give the follower along ``+s`` (up the cam axis; an arm towards ``+psi``): inertia, damping, the
external load and the weight (:func:`camgen.dynamics.force_coefficients`).  The upper roller sits
on the rib's upper face, which can only push it up: it carries ``Q`` where ``Q > 0`` (contact 1).
The lower roller sits under the rib's lower face, which can only push it down: it carries ``-Q``
where ``Q < 0`` (contact 2).  Where ``Q`` changes sign the follower crosses the clearance and the
load passes from one roller to the other (the crossovers: with inertia the only load, the zeros of
``s''`` where it changes sign, :func:`camgen.kinds.barrel_dynamics.barrel_crossovers`).

**The contacts** (at the mean radius, as the groove's): each roller's resultant acts on its
section whose centre lies ``R_m`` from the cam axis, along that section's contact normal, at the
roller's own pressure angle (:meth:`camgen.synthesis.barrel.BarrelRib.roller_pressure_angle`):
translating, both ``atan(s' / R_m)``; oscillating, each roller's axis moves about the pivot along its
own direction (it is the end of an arm of length ``L' = hypot(L, o)`` at ``psi -+ atan2(o, L)``),
so the normal force is ``Q / (L' cos(alpha_i))``: the normal passes through the roller's axis,
``L' cos(alpha_i)`` from the pivot.  The camshaft torque is the power balance ``T = Q s'``.

**Hertz stress** (Johnson, *Contact Mechanics*, 1985, eq. 4.45): the real roller (radius Rr)
against the face's section at the mean radius, developed flat as the groove's walls are: the
roller's axis path developed at ``R_m`` has the signed curvature ``kappa_i`` (> 0 bending towards
+z; :func:`camgen.kinds.barrel_dynamics.developed_curvature` of that roller), and the face is its
offset by ``w`` towards the rib, so seen from the roller the upper face (below the upper roller,
as a groove's lower wall) has the radius ``-(1 / kappa_+ + w)`` and the lower face (above the lower
roller, as a groove's upper wall) ``1 / kappa_- - w`` (> 0 convex towards the roller).  The
contact length defaults to the rib's height (``groove_depth_mm``).  Where a roller's path bends
tighter than ``w`` a face folds: the dynamics are then not computed.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from camgen.dynamics import Kinematics
    from camgen.kinds.base import BuiltCam, CamSpec

__all__ = ["barrel_follower_kinematics", "rib_kinematics"]


def barrel_follower_kinematics(cam: "BuiltCam", spec: "CamSpec") -> tuple["Kinematics", float]:
    """The barrel form's follower dynamics: a rib's (:func:`rib_kinematics`) or a groove's
    (:func:`camgen.kinds.barrel_dynamics.barrel_kinematics`)."""
    if getattr(cam, "rib", None) is not None:
        return rib_kinematics(cam, spec)
    from camgen.kinds.barrel_dynamics import barrel_kinematics

    return barrel_kinematics(cam, spec)


def _face_radius(rib: Any, side: int, theta: np.ndarray) -> np.ndarray:
    """The radius (mm, signed: > 0 convex towards the roller, inf straight) of the rib's face
    ``side`` seen from its roller, developed at the mean radius (module notes)."""
    from camgen.kinds.barrel_dynamics import developed_curvature
    from camgen.kinds.dynamics import DynamicsNotComputed

    kappa = developed_curvature(rib.roller(side), theta)
    w = rib.half_width
    with np.errstate(divide="ignore"):
        rho_path = np.where(kappa != 0.0, 1.0 / np.where(kappa != 0.0, kappa, 1.0), np.inf)  # inf where straight
    if np.any(np.abs(rho_path) < w):  # the face, offset by w from a path bending tighter than w, has a cusp
        i = int(np.argmin(np.abs(rho_path)))
        name = "upper" if side > 0 else "lower"
        raise DynamicsNotComputed(
            f"the {name} roller's path developed at the mean radius bends to a radius of {abs(rho_path[i]):.6g} mm at cam angle "
            f"{math.degrees(theta[i]):.6g} deg, tighter than the roller's half width {w:g} mm: the rib's {name} face folds there "
            "(see the undercut check), so the contact forces and stresses are computed for a rib that can be made")
    # the upper face lies below its roller (as a groove's lower wall), the lower face above its roller
    return -(rho_path + w) if side > 0 else rho_path - w


def rib_kinematics(cam: Any, spec: "CamSpec") -> tuple["Kinematics", float]:
    """The dynamics kinematics of a rib cam (a :class:`camgen.kinds.barrel.BarrelCam` with its
    ``rib``) on its check grid, and the lever (mm) of an oscillating follower: contact 1 the upper
    roller on the rib's upper face (pushes along +s), contact 2 the lower roller on the lower face,
    each along its own normal at the mean radius, each against the real roller (radius Rr); the
    lever ``hypot(L, o)`` (pivot to either roller's axis; 0 translating).  Module notes."""
    from camgen import dynamics as dy
    from camgen.kinds.dynamics import checked_kinematics

    rib, p = cam.rib, cam.params
    theta = cam.motion.cam_angle
    s, s1, s2, _ = rib.groove.law(theta)
    rm = np.asarray(p.mean_radius)
    alpha_1, alpha_2 = rib.roller_pressure_angle(1, rm, theta), rib.roller_pressure_angle(-1, rm, theta)
    rho_1, rho_2 = _face_radius(rib, 1, theta), _face_radius(rib, -1, theta)
    if p.follower.motion == "translating":
        direction: Any = math.pi / 2  # along +z in the (y, z) plane, measured from +y
        lever = 0.0
    else:
        direction = p.rest_angle + s + math.pi / 2  # the arm's points (its centre of mass) move along (-sin psi, cos psi)
        lever = math.hypot(p.arm_length, rib.roller_offset)
    kin = checked_kinematics(lambda: dy.Kinematics(theta, s, s1, s2, alpha_1, rho_1, p.roller_radius, direction,
                                                   pressure_angle_2=alpha_2, rho_cam_2=rho_2, follower_radius_2=p.roller_radius))
    return kin, lever
