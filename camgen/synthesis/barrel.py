"""Barrel (cylindrical) cams: conventions and the exact groove walls as envelopes of the roller.

Conventions
-----------
**Cam frame.** ``z`` along the cam axis; ``z = 0`` the cylinder's bottom face, ``z = length`` its
top face.  The cam turns about ``+z`` by ``sigma theta``: ``sigma = +1`` (``rotation = "ccw"``,
counter-clockwise seen from ``+z``, the plate cams' convention) or ``-1`` (``"cw"``).  A cam point
at polar angle ``phi`` (rad) and radius ``r`` (mm) is at world polar angle ``u = phi + sigma theta``.

**Follower station.** The follower stands at world polar angle 0 (the ``+x`` side): at cam angle
``theta`` it reads the cam at cam polar angle ``phi_r(theta) = -sigma theta`` (a cam feature at
``phi`` passes the follower at ``theta = -sigma phi``).  Every ``phi`` this module returns is
unwrapped about ``phi_r`` (within ``pi/2`` of it).

**Radii.** Rim ``R_o`` (the cylinder's outer radius), root ``R_i = R_o - depth``, mean (pitch)
radius ``R_m = (R_o + R_i) / 2``: the pressure angle and the developed drawing "at the mean radius"
mean this one.

**Roller.** Its axis radial, parallel to the world ``x`` axis: the line ``{(t, e, z_c)}``, ``t``
along it (mm).  ``"cylindrical"`` (radius ``Rr``) or ``"conical"`` (apex on the cam axis at the
roller centre's height, radius ``Rr`` at ``t = R_m``; translating only).  The walls are the
envelopes of the roller widened by half the clearance ``c``: ``w = Rr + c / 2`` (the cone: radius
``w`` at ``R_m``, same apex, slope ``k = w / R_m``).

**Translating follower**: ``e = 0``, ``z_c(theta) = z0 + s(theta)`` (``s`` the law's lift, mm).
**Oscillating follower**: the arm (length ``L``) swings about a pivot axis parallel to ``x`` through
``(y, z) = (-L, z_p)``; arm angle ``psi = psi0 + s(theta)`` (``s`` the law's swing, rad), so
``e = L (cos psi - 1)`` and ``z_c = z_p + L sin psi``.

The exact contact (derived here)
--------------------------------
The roller is cut out of the cam: a cam point is removed when, at some ``theta``, it lies inside the
roller.  For the cylinder, with ``g = r sin(u) - e`` its offset from the roller's axis plane,
``(r sin u - e)^2 + (z - z_c)^2 < w^2`` and ``r cos u > 0``; the upper wall is
``z_upper(r, phi) = max_theta F``, ``F = z_c + sqrt(w^2 - g^2)``, the lower its twin (min,
``-sqrt``).  Its stationary points are the envelope.

*Contact on the roller* (the theory of envelopes: the relative velocity of cam and roller is
tangent to the roller at the contact; e.g. Litvin and Fuentes, *Gear Geometry and Applied Theory*,
2004, ch. 6).  Write the contact on the roller's section at ``t`` as ``(t, e + w sin b, z_c + w cos b)``
(``b`` its angle from ``+z``; ``cos b > 0`` on the upper wall).  The cam moves it at
``sigma (-y, x, 0)`` per rad, the roller (a rigid body turning about an axis parallel to its own)
moves its normal's component at the axis' velocity ``(e', z_c')``; equal normal components give

    sin(b) (sigma t - e') = z_c' cos(b),   i.e.  (sin b, cos b) = side (sigma z_c', t - sigma e') / D,
    D = sqrt(z_c'^2 + (t - sigma e')^2)                                        (valid for t > sigma e').

Translating (``e' = 0``) this is the issue's ``tan(psi) = rho / s'`` (``psi = pi/2 - b``,
``rho = t``).  The contact at *cam* radius ``r`` solves ``r^2 = t^2 + (e + w sin b(t))^2``: for a
translating roller, with ``a = w sin b`` (``t^2 = r^2 - a^2``), squaring the condition gives
``s'^2 (w^2 - a^2) = a^2 (r^2 - a^2)``, a quadratic in ``a^2`` whose root below ``w^2`` is
``a^2 = 2 s'^2 w^2 / ((r^2 + s'^2) + sqrt((r^2 + s'^2)^2 - 4 s'^2 w^2))``, ``sign(a) = side sigma
sign(s')``; oscillating, by a bracketed Newton iteration on ``t`` (:data:`CONTACT_TOL`).  Then
``phi = atan2(e + a, t) - sigma theta`` and ``z = z_c + side sqrt(w^2 - a^2)``.

*The cone* (apex ``(0, 0, z_c)``, slope ``k``): a point ``(t, t k sin b, z_c + t k cos b)`` has
the normal ``(-k, sin b, cos b)`` (constant along the generator); the same argument gives
``tan b = s' / (sigma t (1 + k^2))``: ``b`` changes along ``t`` whenever ``s' != 0``, so the contact
is a generator (straight, through the axis) only where the follower dwells; during a rise it is a
curve (as for the cylinder, by the factor ``1 + k^2``).  At cam radius ``r``:
``r^2 = t^2 (1 + k^2 sin^2 b)``, a quadratic in ``t^2``:
``K t^4 + (s'^2 - K r^2) t^2 - r^2 s'^2 / K = 0`` (``K = 1 + k^2``), one positive root.
The cone rolls on the wall without slip at every radius in a dwell (the cam's surface speed and the
cone's both grow as ``t``); a cylinder does so at one radius only.

**Pressure angle** at the roller section whose centre is at distance ``r`` from the cam axis
(``t = sqrt(r^2 - e^2)``): the angle between the axis' velocity ``lambda d`` (``d`` the unit
direction of a positive lift: ``(0, 1)`` translating, ``(-sin psi, cos psi)`` oscillating in
``(y, z)``; ``lambda = s'`` or ``L s'``) and the wall normal at that section's contact.  From the
contact condition above, signed positive on a rise:

    tan(alpha) = (lambda - sigma t d_y) / (t d_z)           (translating: s' / t)

The cone's normal also leans by ``k`` along the roller axis; its angle with the (axial) velocity is
``tan(alpha) = sqrt(s'^2 / (K t^2) + k^2)`` (signed like ``s'``).  The issue's example (``R_m = 50``,
depth 10, ``Rr = 4``, a 40 mm cycloidal rise over 120 deg, ``s'_max = 38.197`` mm/rad) gives
40.33 deg at the root section (``t = 45``) and 37.37 deg at the mean one: the issue's 40.3 and 37.4.
(The contact *point* at cam radius 45 lies on the section ``t = sqrt(45^2 - a^2) = 44.93`` mm, whose
angle is 40.37 deg: the section, not the contact point, is what "at the root" means here.)

**Undercut.** At a fixed radius the wall's section ``theta -> (phi, z)`` is a plane envelope.
Differentiating ``F_theta(phi(theta), theta) = 0``: ``dphi/dtheta = -F_tt / F_tp``
(``F_tt``, ``F_tp`` the second partial derivatives of ``F`` in closed form below).  A regular section
runs the way ``phi_r`` does (``-sigma dphi/dtheta > 0``); where it stops and turns back
(``-sigma dphi/dtheta <= 0``) the section folds (a swallowtail): the roller cuts away the envelope
there and the groove cannot give the motion.

**Wrapped approximation** (:meth:`BarrelGroove.wrapped_wall_height`): the groove drawn flat at
``R_m`` (the developed pitch curve offset by ``+-w`` along its normal in the developed plane) and
wrapped onto the cylinder along radial lines, the same at every radius: what the open-source tools
do.  It is here to measure its error against the exact wall, never to make a cam.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camgen.errors import GeometryError
from camgen.synthesis.laws import Displacement

__all__ = [
    "BarrelGroove", "BarrelLayout", "BarrelRib", "CONTACT_TOL", "MAX_NEWTON_STEPS", "MOTIONS", "ROLLER_SHAPES", "WALL_ANGLE_TOL", "floor_radius",
]

#: Follower motions a barrel cam drives.
MOTIONS = ("translating", "oscillating")
#: Roller shapes.
ROLLER_SHAPES = ("cylindrical", "conical")
#: The contact's station ``t`` on the roller axis is solved to this (mm) where it has no closed form.
CONTACT_TOL = 1e-12
#: :meth:`BarrelGroove.wall_height` and the wrapped wall solve the cam angle to this (rad).
WALL_ANGLE_TOL = 1e-14
#: Newton steps (each bracketed, bisecting when a step leaves the bracket) before a solve gives up.
MAX_NEWTON_STEPS = 200


@dataclass(frozen=True)
class BarrelLayout:
    """Where the follower stands and what it is (mm, rad; conventions in the module notes).

    Parameters
    ----------
    motion : str
        ``"translating"`` (the roller axis moves along ``z``) or ``"oscillating"`` (the arm swings).
    sigma : int
        ``+1``: the cam turns counter-clockwise seen from ``+z`` (``"ccw"``); ``-1``: clockwise.
    roller_radius : float
        ``Rr``, mm (conical: its radius at the mean radius).
    roller_shape : str
        ``"cylindrical"`` or ``"conical"`` (translating only).
    mean_radius : float
        ``R_m``, mm.
    z0 : float
        Translating: the roller axis' height at lift 0; oscillating: the pivot height ``z_p`` (mm).
    arm_length : float
        Oscillating: ``L``, mm (0 for a translating follower).
    rest_angle : float
        Oscillating: ``psi0``, the arm angle at swing 0 (rad; the arm points from the pivot along
        ``(cos psi, sin psi)`` in the ``(y, z)`` plane, so the roller axis is at
        ``(e, z_c) = (L (cos psi0 - 1), z_p + L sin psi0)``).
    """

    motion: str
    sigma: int
    roller_radius: float
    roller_shape: str
    mean_radius: float
    z0: float
    arm_length: float = 0.0
    rest_angle: float = 0.0

    def __post_init__(self) -> None:
        if self.motion not in MOTIONS:
            raise GeometryError(f"a barrel follower is one of {MOTIONS}, not {self.motion!r}")
        if self.sigma not in (1, -1):
            raise GeometryError(f"sigma is +1 (ccw) or -1 (cw), not {self.sigma!r}")
        if self.roller_shape not in ROLLER_SHAPES:
            raise GeometryError(f"a barrel roller is one of {ROLLER_SHAPES}, not {self.roller_shape!r}")
        if self.roller_shape == "conical" and self.motion != "translating":
            raise GeometryError("a conical roller rides a translating follower only")
        if not (self.roller_radius > 0.0 and self.mean_radius > self.roller_radius):
            raise GeometryError(f"need 0 < roller radius ({self.roller_radius:g} mm) < mean radius ({self.mean_radius:g} mm)")
        if self.motion == "oscillating" and not self.arm_length > 0.0:
            raise GeometryError(f"an oscillating follower needs an arm length > 0 (got {self.arm_length:g} mm)")


def _bracketed_newton(fun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]], lo: np.ndarray, hi: np.ndarray,
                      x0: np.ndarray, tol: float) -> np.ndarray:
    """Elementwise root of ``fun`` (returning the value and the derivative) in ``[lo, hi]``, where
    ``fun`` changes sign: Newton from ``x0``, a bisection whenever a step leaves the bracket.
    Vectorised (a loop over steps, never over points); stops when every step (or bracket) is below
    ``tol`` plus a few units in the last place of the root.  Raises :class:`GeometryError` when
    :data:`MAX_NEWTON_STEPS` do not get there (a bisection halves the bracket each step, so a
    bracket that holds a sign change always does)."""
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    f_lo = fun(lo)[0]
    rising = f_lo <= 0.0  # orient: f(lo) <= 0 <= f(hi) where rising
    x = np.clip(np.array(x0, dtype=float), lo, hi)
    for _ in range(MAX_NEWTON_STEPS):
        f, df = fun(x)
        below = (f < 0.0) == rising
        lo = np.where(below, x, lo)
        hi = np.where(below, hi, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(df != 0.0, f / df, np.inf)
        nxt = x - step
        bad = ~((nxt >= lo) & (nxt <= hi))  # a root on the bracket's end is a root
        nxt = np.where(bad, 0.5 * (lo + hi), nxt)
        moved = np.abs(nxt - x)
        x = nxt
        enough = tol + 4.0 * np.finfo(float).eps * np.abs(x)
        if np.all((moved <= enough) | (hi - lo <= enough)):
            return x
    raise GeometryError(f"a barrel contact did not converge to {tol:g} in {MAX_NEWTON_STEPS} Newton steps")


@dataclass(frozen=True)
class _Axis:
    """The roller axis at cam angles theta: height ``z``, tangential offset ``e`` and their first
    two derivatives by theta (mm, mm/rad, mm/rad^2); ``lam`` the speed along ``d = (dy, dz)``, the
    unit direction of a positive lift (``(e', z_c') = lam d``)."""

    z: np.ndarray
    z1: np.ndarray
    z2: np.ndarray
    e: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    lam: np.ndarray
    dy: np.ndarray
    dz: np.ndarray


@dataclass(frozen=True)
class BarrelGroove:
    """The exact groove of a barrel cam (mm, rad; conventions in the module notes).

    Parameters
    ----------
    layout : BarrelLayout
        The follower.
    law : Displacement
        ``law(theta) -> (s, s', s'', s''')``: the lift (mm, translating) or swing (rad, oscillating).
    rim_radius, root_radius : float
        ``R_o``, ``R_i`` (mm); ``layout.mean_radius`` is their mean.
    length : float
        The cylinder's length (mm).
    bore_radius : float
        The bore's radius (mm); 0: no bore.
    clearance : float
        ``c`` (mm): the groove is ``2 w = 2 Rr + c`` wide across the roller.
    fit_tol : float
        The walls' stated tolerance (mm), for the exports that approximate them.
    axis_offset : float
        ``o`` (mm): where the roller axis rides from the layout's (0: the groove's roller; a rib's
        two rollers, :class:`BarrelRib`, ride at ``o = -+(rib width / 2 + w)``).  Translating: a
        constant shift along ``z``.  Oscillating: a shift along the arm's normal
        ``n = (-sin psi, cos psi)`` in ``(y, z)`` (a point of the rigid arm, turning with it): the
        roller axis is the end of an arm of length ``hypot(L, o)`` at ``psi + atan2(o, L)`` about
        the same pivot.
    """

    layout: BarrelLayout
    law: Displacement
    rim_radius: float
    root_radius: float
    length: float
    bore_radius: float
    clearance: float
    fit_tol: float
    axis_offset: float = 0.0

    def __post_init__(self) -> None:
        lay = self.layout
        if not 0.0 <= self.bore_radius < self.root_radius < self.rim_radius:
            raise GeometryError(f"need 0 <= bore ({self.bore_radius:g} mm) < root ({self.root_radius:g} mm) "
                                f"< rim radius ({self.rim_radius:g} mm)")
        if not math.isclose(lay.mean_radius, 0.5 * (self.rim_radius + self.root_radius), rel_tol=1e-12, abs_tol=1e-12):
            raise GeometryError(f"the mean radius ({lay.mean_radius:g} mm) is not the mean of the rim and root radii")
        if self.root_radius <= self.half_width:
            raise GeometryError(f"the root radius ({self.root_radius:g} mm) must exceed the groove's half width "
                                f"({self.half_width:g} mm)")
        if not self.clearance >= 0.0:
            raise GeometryError(f"the clearance must be >= 0 (got {self.clearance:g} mm)")

    # ------------------------------------------------------------------------------ the follower
    @property
    def half_width(self) -> float:
        """``w = Rr + c / 2`` (mm): the widened roller's radius (the cone's at the mean radius)."""
        return self.layout.roller_radius + 0.5 * self.clearance

    @property
    def cone_slope(self) -> float:
        """``k = w / R_m``: the widened cone's radius per mm along its axis (conical roller)."""
        return self.half_width / self.layout.mean_radius

    def _axis(self, theta: np.ndarray) -> _Axis:
        lay = self.layout
        s, s1, s2, _ = self.law(np.asarray(theta, dtype=float))
        if lay.motion == "translating":
            zero = np.zeros_like(s)
            return _Axis(lay.z0 + s + self.axis_offset if self.axis_offset else lay.z0 + s, s1, s2, zero, zero, zero, s1, zero, np.ones_like(s))
        arm, psi = lay.arm_length, lay.rest_angle + s
        if self.axis_offset:  # a roller on the arm's normal (a rib's): an arm of length hypot(L, o), turned by atan2(o, L)
            return self._offset_arm_axis(s1, s2, psi)
        cos, sin = np.cos(psi), np.sin(psi)
        return _Axis(lay.z0 + arm * sin + self.axis_offset if self.axis_offset else lay.z0 + arm * sin, arm * cos * s1, arm * (cos * s2 - sin * s1 * s1),
                     arm * (cos - 1.0), -arm * sin * s1, -arm * (sin * s2 + cos * s1 * s1), arm * s1, -sin, cos)

    def _offset_arm_axis(self, s1: np.ndarray, s2: np.ndarray, psi: np.ndarray) -> _Axis:
        """The axis of an oscillating follower's roller carried ``o = axis_offset`` along the arm's
        normal ``n = (-sin psi, cos psi)`` (in ``(y, z)``) from the arm's end: the point
        ``(-L, z_p) + L (cos psi, sin psi) + o n`` of the rigid arm, i.e. the end of an arm of length
        ``L' = hypot(L, o)`` at the angle ``psi + atan2(o, L)`` about the same pivot:
        ``e = L' cos psi' - L``, ``z_c = z_p + L' sin psi'``."""
        lay = self.layout
        arm, offset = lay.arm_length, self.axis_offset
        reach = math.hypot(arm, offset)
        turned = psi + math.atan2(offset, arm)
        cos, sin = np.cos(turned), np.sin(turned)
        return _Axis(lay.z0 + reach * sin, reach * cos * s1, reach * (cos * s2 - sin * s1 * s1),
                     reach * cos - arm, -reach * sin * s1, -reach * (sin * s2 + cos * s1 * s1), reach * s1, -sin, cos)

    def axis(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The roller axis at cam angles ``theta`` (rad): its height ``z_c`` and tangential offset
        ``e`` (mm; ``e = 0`` for a translating follower): the line ``{(t, e, z_c)}``."""
        a = self._axis(theta)
        return a.z, a.e

    # ------------------------------------------------------------------------------ the contact
    def _station(self, side: int, r: np.ndarray, ax: _Axis) -> np.ndarray:
        """The station ``t`` (mm) on the roller axis of the contact at cam radius ``r`` (cylinder)."""
        w, sig = self.half_width, self.layout.sigma
        if self.layout.motion == "translating":
            # the quadratic s'^2 (w^2 - a^2) = a^2 (r^2 - a^2) in a^2, its root below w^2 (stable form)
            p = r * r + ax.z1 * ax.z1
            a2 = 2.0 * ax.z1 * ax.z1 * w * w / (p + np.sqrt(np.maximum(p * p - 4.0 * ax.z1 * ax.z1 * w * w, 0.0)))
            return np.sqrt(r * r - a2)

        def fun(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            m = t - sig * ax.e1
            d = np.sqrt(ax.z1 * ax.z1 + m * m)
            sin_b = side * sig * ax.z1 / d
            y = ax.e + w * sin_b
            dsin = -side * sig * ax.z1 * m / d**3
            return t * t + y * y - r * r, 2.0 * t + 2.0 * y * w * dsin

        lo = np.sqrt(np.maximum(r * r - (np.abs(ax.e) + w) ** 2, 0.0))
        return _bracketed_newton(fun, lo, r + 0.0 * lo, np.sqrt(np.maximum(r * r - ax.e * ax.e, 0.0)), CONTACT_TOL)

    def _contact(self, side: int, r: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, _Axis]:
        """World contact ``(t, y, z)`` on wall ``side`` at cam radius ``r``, cam angle ``theta``."""
        r, theta = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(theta, dtype=float))
        ax = self._axis(theta)
        sig, w = self.layout.sigma, self.half_width
        if self.layout.roller_shape == "conical":
            k2 = self.cone_slope**2
            big = 1.0 + k2
            s1 = ax.z1
            # K T^2 + (s'^2 - K r^2) T - r^2 s'^2 / K = 0, its positive root (stable form)
            b = s1 * s1 - big * r * r
            c = -r * r * s1 * s1 / big
            root = np.sqrt(b * b - 4.0 * big * c)
            with np.errstate(divide="ignore", invalid="ignore"):
                tt = np.where(b <= 0.0, (root - b) / (2.0 * big), -2.0 * c / (b + root))
            t = np.sqrt(tt)
            d = np.sqrt(s1 * s1 + (t * big) ** 2)
            sin_b, cos_b = side * sig * s1 / d, side * t * big / d
            k = self.cone_slope
            return t, t * k * sin_b, ax.z + t * k * cos_b, ax
        t = self._station(side, r, ax)
        m = t - sig * ax.e1
        d = np.sqrt(ax.z1 * ax.z1 + m * m)
        return t, ax.e + w * side * sig * ax.z1 / d, ax.z + w * side * m / d, ax

    def wall(self, side: int, r: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The exact contact point of wall ``side`` at cam radius ``r`` for cam angle ``theta``.

        Parameters
        ----------
        side : int
            ``+1`` the upper wall (``z`` above the roller axis), ``-1`` the lower.
        r : array_like
            Cam radius of the point (mm), ``R_i <= r <= R_o`` in use; broadcast with ``theta``.
        theta : array_like
            Cam angle (rad).

        Returns
        -------
        phi, z : ndarray
            The point's cam polar angle (rad, within ``pi/2`` of ``phi_r = -sigma theta``) and height (mm).
        """
        t, y, z, _ = self._contact(side, r, theta)
        theta = np.broadcast_to(np.asarray(theta, dtype=float), t.shape)
        return np.arctan2(y, t) - self.layout.sigma * theta, z

    def _section_slope(self, side: int, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """``-sigma dphi/dtheta`` of the wall's section at radius ``r`` (> 0: regular; module notes)."""
        t, y, z, ax = self._contact(side, r, theta)
        r = np.hypot(t, y)
        sig = self.layout.sigma
        u = np.arctan2(y, t)
        cos_u, sin_u = np.cos(u), np.sin(u)
        if self.layout.roller_shape == "conical":
            # F = z_c + side r H(u), H = sqrt(k^2 cos^2 u - sin^2 u)
            big = 1.0 + self.cone_slope**2
            h = (z - ax.z) * side / r
            q_u = -big * np.sin(2.0 * u)
            q_uu = -2.0 * big * np.cos(2.0 * u)
            h_uu = q_uu / (2.0 * h) - q_u * q_u / (4.0 * h**3)
            f_tt = ax.z2 + side * r * h_uu
            f_tp = side * sig * r * h_uu
        else:
            # F = z_c + side sqrt(w^2 - g^2), g = r sin(u) - e, u = phi + sigma theta
            w = self.half_width
            g = y - ax.e
            h2 = w * w - g * g
            h3 = h2 ** 1.5
            g_t = sig * r * cos_u - ax.e1
            g_tt = -r * sin_u - ax.e2
            g_p = r * cos_u
            g_tp = -sig * r * sin_u
            f_tt = ax.z2 - side * (g_t * g_t * w * w + g * g_tt * h2) / h3
            f_tp = -side * ((g_p * g_t + g * g_tp) * h2 + g * g * g_t * g_p) / h3
        return sig * f_tt / f_tp

    def wall_height(self, side: int, r: np.ndarray, phi: np.ndarray) -> np.ndarray:
        """The wall ``side`` (``+1`` upper, ``-1`` lower) at cam radius ``r`` (mm) and cam polar
        angle ``phi`` (rad, any real), mm: the cam angle whose contact lies at ``phi`` is solved by a
        bracketed Newton iteration (:data:`WALL_ANGLE_TOL`).  Exact where the section does not fold
        (:meth:`undercut` false); where it folds it returns one branch of the envelope, not the
        groove."""
        r, phi = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(phi, dtype=float))
        sig = self.layout.sigma

        def fun(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # v = sigma theta
            p, _ = self.wall(side, r, sig * v)
            return p - phi, -self._section_slope(side, r, sig * v)

        half = 0.5 * math.pi
        v = _bracketed_newton(fun, -phi - half, -phi + half, -phi, WALL_ANGLE_TOL)
        return self.wall(side, r, sig * v)[1]

    # ------------------------------------------------------------------------------ checks
    def pressure_angle(self, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Signed pressure angle (rad, > 0 on a rise) of the roller section whose centre is at
        distance ``r`` (mm) from the cam axis, at cam angle ``theta`` (rad): the angle between the
        roller axis' velocity and the wall normal at that section's contact (module notes:
        ``tan(alpha) = (lambda - sigma t d_y) / (t d_z)``, translating ``s' / r``; the cone
        ``sqrt(s'^2 / ((1 + k^2) r^2) + k^2)``).  Largest at the root for the cylinder."""
        r, theta = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(theta, dtype=float))
        ax = self._axis(theta)
        if self.layout.roller_shape == "conical":
            k2 = self.cone_slope**2
            mag = np.arctan(np.sqrt(ax.lam**2 / ((1.0 + k2) * r * r) + k2))
            return np.where(ax.lam < 0.0, -mag, mag)
        t = np.sqrt(r * r - ax.e * ax.e)
        return np.arctan2(ax.lam - self.layout.sigma * t * ax.dy, t * ax.dz)

    def undercut(self, side: int, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Where the wall ``side``'s section at cam radius ``r`` (mm) folds at cam angle ``theta``
        (rad): ``-sigma dphi/dtheta <= 0`` (module notes); a boolean array (true: cannot be made).

        These are the contacts the neighbouring roller positions cut away (the envelope's
        stationary point is a local minimum of the cut, not a maximum).  Beside a fold the
        envelope's wings are cut away too, by positions farther off: a groove with an undercut
        anywhere gives the wrong motion over more than the flagged angles."""
        slope = self._section_slope(side, r, theta)
        return ~(slope > 0.0)

    # ------------------------------------------------------------------------------ drawings
    def pitch_developed(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The pitch curve (the roller axis' point at distance ``R_m`` from the cam axis) unrolled at
        ``R_m``: ``x = R_m phi`` (mm; ``phi = phi_r + asin(e / R_m)``, ``phi_r`` for a translating
        follower) and ``z = z_c`` (mm), at cam angles ``theta`` (rad)."""
        theta = np.asarray(theta, dtype=float)
        z, e = self.axis(theta)
        rm = self.layout.mean_radius
        return rm * (np.arcsin(e / rm) - self.layout.sigma * theta), z

    def _developed_offset(self, side: int, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The developed pitch curve offset by ``side w`` along its normal (the side of ``+z`` for
        ``side = +1``): ``x``, ``z`` and ``dx/dtheta`` (mm, mm/rad)."""
        ax = self._axis(theta)
        rm, sig, w = self.layout.mean_radius, self.layout.sigma, self.half_width
        root = np.sqrt(rm * rm - ax.e * ax.e)
        x = rm * (np.arcsin(ax.e / rm) - sig * theta)
        x1 = rm * ax.e1 / root - sig * rm
        x2 = rm * (ax.e2 / root + ax.e * ax.e1 * ax.e1 / root**3)
        z1, z2 = ax.z1, ax.z2
        speed = np.hypot(x1, z1)
        flip = np.sign(x1)  # the normal with a +z component: (-z', x') sign(x') / |c'|
        nx, nz = -z1 * flip / speed, x1 * flip / speed
        return x + side * w * nx, ax.z + side * w * nz, x1 + side * w * _dnx(x1, z1, x2, z2, flip)

    def wrapped_wall_height(self, side: int, r: np.ndarray, phi: np.ndarray) -> np.ndarray:
        """The wrapped-groove approximation of wall ``side`` at cam polar angle ``phi`` (rad), mm: the
        developed pitch curve offset by ``side w`` along its normal in the developed plane, read at
        ``x = R_m phi``; the same at every radius ``r`` (broadcast only).  For comparison with the
        exact :meth:`wall_height`; never used to make a cam.

        The issue's figures (wrapped wall 0.436 mm too low at the root, 0.324 mm too high at the
        rim, the groove 0.87 mm too narrow at the bottom; ``R_m = 50``, depth 10, a 40 mm cycloidal
        rise over 120 deg) are the largest differences over ``phi`` on each wall for ``w = 8`` mm
        (its "8 mm roller" a radius), 0.87 being the two walls' root errors added (they fall at
        different angles; the narrowest point of the width is 0.837 mm short).  With ``w = 4`` mm they
        are about half (tests/test_barrel_geometry.py checks the figures)."""
        r, phi = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(phi, dtype=float))
        sig, rm, w = self.layout.sigma, self.layout.mean_radius, self.half_width
        target = rm * phi

        def fun(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # v = sigma theta
            x, _, dx = self._developed_offset(side, sig * v)
            return x - target, sig * dx

        span = (w + rm * math.pi / 2.0) / rm
        v = _bracketed_newton(fun, -phi - span, -phi + span, -phi, WALL_ANGLE_TOL)
        return self._developed_offset(side, sig * v)[1]


def _dnx(x1: np.ndarray, z1: np.ndarray, x2: np.ndarray, z2: np.ndarray, flip: np.ndarray) -> np.ndarray:
    """d/dtheta of ``nx = -z' sign(x') / |c'|`` (the developed normal's x)."""
    speed2 = x1 * x1 + z1 * z1
    return -flip * (z2 * speed2 - z1 * (x1 * x2 + z1 * z2)) / speed2**1.5


def floor_radius(root_radius: float, e: np.ndarray, tool_radius: float) -> np.ndarray:
    """Tip radius of the finishing pass (mm) for the roller axis' tangential offsets ``e`` (mm):
    ``sqrt(R_i^2 - (|e| + D/2)^2)``, where the flat tip reaches the root radius at the tool's rim
    (a flat end mill with its axis on the roller's, :mod:`camgen.export.gcode_barrel`).  Raises :class:`GeometryError` where the tool reaches the axis' side of
    the root (``|e| + D/2 >= R_i``)."""
    reach = np.abs(e) + tool_radius
    if np.any(reach >= root_radius):
        raise GeometryError(f"a tool of radius {tool_radius:g} mm at the follower's tangential offset reaches {float(np.max(reach)):.4g} mm "
                            f"from the axis, not inside the root radius {root_radius:g} mm: its tip cannot cut the walls to the root")
    return np.sqrt(root_radius**2 - reach * reach)


@dataclass(frozen=True)
class BarrelRib:
    """A rib standing on the root cylinder (radius ``R_i``) up to the rim (``R_o``), straddled by two
    rollers of the follower whose axes ride ``o = rib_width / 2 + w`` below and above the pitch line
    (``w = Rr + c / 2``: each roller clears the rib by half the clearance ``c``).  The rib's faces
    are the two rollers' envelopes on its side: the lower roller's upper envelope is the rib's
    lower face, the upper roller's lower envelope its upper face; each is
    :meth:`BarrelGroove.wall` of a groove whose roller axis is shifted by ``-+o``
    (:attr:`BarrelGroove.axis_offset`), so the closed forms, the undercut and the pressure angle
    are the groove's.  In a dwell the faces are ``rib_width`` apart along ``z``; during a rise the
    rib is thinner along the faces' normal than along ``z`` and, where ``rib_width`` is too small for
    the spacing of the rollers, the faces cross (:meth:`thickness` < 0).

    **Oscillating follower.**  Both rollers sit on the one arm, at its end, their axes parallel to
    ``x`` (radial at the station, as the groove's roller), spaced ``2 o`` along the arm's normal
    ``n = (-sin psi, cos psi)`` in the plane ``(y, z)`` tangent to the cylinder at the station:
    the axes at ``A +- o n``, ``A = (-L, z_p) + L (cos psi, sin psi)`` the arm's end (the pitch
    line, :meth:`axis`).  Seen along ``-x`` (onto the tangent plane), drawn at ``psi = 0`` (the pair
    turns with the arm)::

          z
          ^                               (+)   upper roller, axis at A + o n
          |      ==============================  the rib's upper face
          | pivot o------------------------A     the arm (length L, at psi = 0 along +y) to A
          |      ==============================  the rib's lower face
          |                               (-)   lower roller, axis at A - o n
          +--------------------------------------> y

    (the arm and the rollers' axles lie outside the rim, ``x > R_o``; the rollers reach in along
    ``-x`` across the rib's height).

    Each roller is rigid on the arm: its axis is the end of an arm of length ``hypot(L, o)`` at
    ``psi -+ atan2(o, L)`` about the same pivot (:attr:`BarrelGroove.axis_offset`), so the contact,
    the undercut and the pressure angle of each are the oscillating groove's (the envelope argument
    holds for any roller turning about an axis parallel to its own).  The rollers' axes are
    ``rib_width + 2 w`` apart along ``n``: where the follower dwells at arm angle ``psi`` the faces
    are ``(rib_width + 2 w) cos(psi) - 2 w`` apart along ``z`` (``rib_width`` at ``psi = 0``), the
    rollers ``(rib_width + 2 w) sin(psi)`` apart along ``y``.

    Parameters
    ----------
    groove : BarrelGroove
        The follower, law, cylinder and clearance (its ``axis_offset`` 0: the pitch line).
    width : float
        ``rib_width``, mm (> 0): the rib's width along ``z`` where the follower dwells.
    """

    groove: BarrelGroove
    width: float

    def __post_init__(self) -> None:
        if not self.width > 0.0:
            raise GeometryError(f"a rib's width must be > 0 (got {self.width:g} mm)")
        if self.groove.axis_offset != 0.0:
            raise GeometryError("a rib's groove is the pitch line's (axis_offset 0)")

    # the shapes every export reads from a groove
    @property
    def layout(self) -> BarrelLayout:
        return self.groove.layout

    @property
    def rim_radius(self) -> float:
        return self.groove.rim_radius

    @property
    def root_radius(self) -> float:
        return self.groove.root_radius

    @property
    def length(self) -> float:
        return self.groove.length

    @property
    def bore_radius(self) -> float:
        return self.groove.bore_radius

    @property
    def fit_tol(self) -> float:
        return self.groove.fit_tol

    @property
    def half_width(self) -> float:
        """``w = Rr + c / 2`` (mm): each roller widened by half the clearance."""
        return self.groove.half_width

    @property
    def roller_offset(self) -> float:
        """``o = rib_width / 2 + w`` (mm): each roller axis' distance along ``z`` from the pitch line."""
        return 0.5 * self.width + self.groove.half_width

    def roller(self, side: int) -> BarrelGroove:
        """The groove of the roller on the rib's ``side`` (``+1`` the upper roller, its axis at
        ``z_c + o``; ``-1`` the lower, at ``z_c - o``)."""
        from dataclasses import replace

        return replace(self.groove, axis_offset=side * self.roller_offset)

    def axis(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The pitch line (midway between the roller axes) at cam angles ``theta``: ``z_c``, ``e`` (mm)."""
        return self.groove.axis(theta)

    def pitch_developed(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The pitch line unrolled at ``R_m`` (:meth:`BarrelGroove.pitch_developed`)."""
        return self.groove.pitch_developed(theta)

    def wall(self, side: int, r: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The exact contact point of the rib's face ``side`` (``+1`` the upper face: the upper
        roller's lower envelope; ``-1`` the lower face: the lower roller's upper envelope) at cam
        radius ``r`` (mm) for cam angle ``theta`` (rad): ``(phi, z)`` as :meth:`BarrelGroove.wall`."""
        return self.roller(side).wall(-side, r, theta)

    def wall_height(self, side: int, r: np.ndarray, phi: np.ndarray) -> np.ndarray:
        """The face ``side`` at cam radius ``r`` (mm) and polar angle ``phi`` (rad), mm
        (:meth:`BarrelGroove.wall_height`)."""
        return self.roller(side).wall_height(-side, r, phi)

    def undercut(self, side: int, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Where the face ``side``'s section at radius ``r`` folds at cam angle ``theta``
        (:meth:`BarrelGroove.undercut` of its roller's envelope)."""
        return self.roller(side).undercut(-side, r, theta)

    def pressure_angle(self, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """The pressure angle (rad) of either roller's section at distance ``r`` from the cam axis.
        Translating: a shift of the axis along ``z`` changes neither its velocity nor the contact's
        normal, so it is the groove's (:meth:`BarrelGroove.pressure_angle`).  Oscillating: the two
        rollers move along different directions (each about the pivot); at each ``(r, theta)`` the
        one of the larger magnitude (:meth:`roller_pressure_angle`; either roller may carry the load)."""
        if self.layout.motion == "translating":
            return self.groove.pressure_angle(r, theta)
        upper, lower = self.roller_pressure_angle(1, r, theta), self.roller_pressure_angle(-1, r, theta)
        return np.where(np.abs(upper) >= np.abs(lower), upper, lower)

    def roller_pressure_angle(self, side: int, r: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """The pressure angle (rad, > 0 on a rise) of the roller on the rib's ``side`` (``+1`` the
        upper roller, on the rib's upper face) at its section whose centre is ``r`` (mm) from the cam
        axis, at cam angle ``theta`` (rad): its own axis' velocity against its contact normal
        (:meth:`BarrelGroove.pressure_angle` of its groove; both of its contacts lie on that line)."""
        return self.roller(side).pressure_angle(r, theta)

    def thickness(self, r: np.ndarray, phi: np.ndarray) -> np.ndarray:
        """The rib's width along ``z`` (mm) at cam radius ``r`` and polar angle ``phi``: the upper face
        less the lower (negative: the faces cross, the rollers cut the rib away)."""
        return self.wall_height(1, r, phi) - self.wall_height(-1, r, phi)
