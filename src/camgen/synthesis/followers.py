"""Followers of disk cams: conventions, exact envelopes and closed-form kinematics.

Conventions
-----------
**Frames.** The *cam frame* is fixed to the cam: origin on the rotation axis, ``x`` and ``y``
in the plane of the cam, angles counter-clockwise as seen looking at the DXF (from ``+z``).
The *fixed frame* (the machine) coincides with the cam frame at cam angle 0: every contour and
file camgen writes shows the cam at cam angle 0, placed as in the machine at that instant.

**Rotation.** The cam angle ``theta`` (rad, ``>= 0``) is measured in the direction of rotation.
``rotation = "ccw"``: after ``theta`` the cam has turned counter-clockwise by ``theta``;
``"cw"``: clockwise.  With ``sigma = +1`` (ccw) or ``-1`` (cw) a cam point ``q`` is at
``R(sigma theta) q`` in the fixed frame (``R(a)`` the rotation by ``a``).  The displacement law
gives the follower position per rad of cam angle in the direction of rotation, so the same law
gives the same follower motion either way.  For a follower symmetric about the ``y`` axis
(translating with zero offset) the ``cw`` cam is the mirror image ``x -> -x`` of the ``ccw`` cam.

**Translating followers** move along the fixed ``+y`` direction on the line ``x = offset``
(``offset = e`` mm: ``e > 0`` puts the follower axis on the ``+x`` side of the cam axis, to the
right looking at the DXF with the follower above the cam).  The lift ``s`` (mm) is positive away
from the cam axis.  Roller centre / knife tip: ``(e, sqrt(Rp^2 - e^2) + s)`` with the prime
radius ``Rp = base_radius + roller_radius``.  Flat face: the line ``y = base_radius + s``,
perpendicular to the motion, its centre on the follower axis ``x = e`` (the offset moves the face
centre only, not the cam).  For a ``ccw`` cam a positive offset lowers the pressure angle during
a rise: ``tan(alpha) = (s' - sigma e) / (sqrt(Rp^2 - e^2) + s)`` (Norton, *Design of Machinery*,
ch. 8, pressure angle of an eccentric roller follower, with eccentricity ``epsilon = sigma e``).

**Oscillating followers** turn about a pivot at ``pivot = (px, py)`` (fixed frame, mm).  The law
gives the swing ``phi`` (rad); a positive swing turns the arm about the pivot in the direction
``lift_turn`` (``tau = +1`` for ``"ccw"``, ``-1`` for ``"cw"``) and moves the follower away from
the cam.  Roller / knife: the roller centre is ``C = pivot + arm_length (cos g, sin g)`` with the
arm angle ``g = g0 + tau phi``; at zero swing ``C`` lies on the prime circle ``|C| = Rp``, at the
one of the two crossings of the arm circle with the prime circle where a positive swing moves
``C`` away from the cam axis (the other crossing suits the other ``lift_turn``).  Flat face: a
straight face fixed to the arm, at the distance ``face_offset = f`` from the pivot (``f > 0``:
the face lies between the pivot and the cam axis; ``f = 0``: the face line passes through the
pivot).  With ``w`` its unit normal pointing away from the cam, the face is the line
``(X - pivot) . w = -f``.  At zero swing the face is tangent to the base circle
(``pivot . w0 - f = base_radius``), at the one of the two tangent positions where a positive
swing lifts the face; the swing turns ``w`` by ``tau phi``.

**Base radius** (``base_radius``, mm): the radius of the cam where the follower rests at zero
lift or swing; for a dwell at zero lift the cam is an arc of that radius about the axis, and it
is the smallest radius of the cam when the lift never goes below zero.  Roller: the roller
(radius ``r``) touches the cam at distance ``Rb`` from the axis, its centre on the prime circle
``Rp = Rb + r``.  Knife: the tip is at distance ``Rb`` (``Rp = Rb``).  Flat: the face line is at
distance ``Rb`` from the axis.

**Signs of derived quantities.**  Radii of curvature are signed, ``> 0`` where the curve is
convex (the contour runs counter-clockwise).  The pressure angle (rad) is the angle between the
common normal at the contact and the direction of motion of the follower point there; for
rollers and knives it is signed like ``V . m`` (``V`` the velocity of the roller centre relative
to the cam, ``m`` the follower's positive direction of motion): positive during a rise of a
centred translating follower.  Flat faces: 0 for a translating face normal to its motion;
``arctan(f / xi)`` for an oscillating face (``xi`` the contact's position along the face from the
foot of the pivot's perpendicular).

Envelopes (exact, from ``s, s', s''``; never a refit of an offset): roller: the pitch curve
(roller-centre path) ``P = R(-sigma theta) C(theta)`` and the profile ``P - r n`` (``n`` the
outward normal of ``P``); knife: the pitch curve itself; flat: the envelope of the face lines
from the support function ``h(psi)`` (contact ``h u + h' u_perp``, radius of curvature
``h + h''``).  Both curves are represented by cubic :class:`~camgen.contour.Spline` segments,
one per law segment between breaks: C2 cubic splines through exact points, clamped to the exact
tangents at every break where the law's acceleration (or velocity) jumps, knots at every break,
refined until the spline is within ``fit_tol`` (mm) of the exact curve at the quarter and mid
points of every piece.  The curve is therefore G2 at every break where ``s''`` is continuous and
exactly G1 (a curvature jump) where ``s''`` jumps.  The contour has one segment per interval
between the law's breaks (one segment from cam angle 0 round to itself when there are none), and
each segment's spline parameter is ``t = -sigma theta`` (rad, shifted by a multiple of 2 pi): the
spline at ``t`` is the contact point of cam angle ``theta``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np

from camgen.contour import Contour, Spline, cubic_with_end_derivatives
from camgen.errors import GeometryError, ParameterError, require_finite, require_positive

TWO_PI = 2.0 * math.pi

KINDS = ("roller", "flat", "knife")
MOTIONS = ("translating", "oscillating")
ROTATIONS = ("ccw", "cw")

#: Default largest distance (mm) of the spline representation from the exact curve.
DEFAULT_FIT_TOL = 1e-7
#: Default spacing (rad) of the dense cam-angle grid of the undercut and curvature data (0.05 deg).
DEFAULT_CHECK_STEP = math.radians(0.05)
#: Step (rad of cam angle) of the one-sided extrapolation of the tangents at a break.
_ONE_SIDED_STEP = 1e-5


class Displacement(Protocol):
    """Follower displacement law over one cam turn (what the motion-law library provides).

    ``__call__(theta)`` returns ``s, ds, d2s, d3s`` per rad of cam angle (mm for translating
    followers, rad of swing for oscillating ones); ``breaks`` (rad, sorted, in ``[0, 2 pi)``) are
    the cam angles where a derivative may jump and ``break_continuity`` the highest continuous
    derivative order there (0: ``s'`` jumps, 1: ``s''`` jumps, 2: ``s'''`` jumps).
    """

    breaks: np.ndarray
    break_continuity: np.ndarray

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]: ...


# --------------------------------------------------------------------------------------------
# The follower
# --------------------------------------------------------------------------------------------
def _choice(name: str, value: object, options: tuple[str, ...]) -> str:
    if value not in options:
        raise ParameterError(name, value, f"one of {list(options)}")
    return str(value)


@dataclass(frozen=True)
class FollowerSpec:
    """A follower and the cam's rotation (mm, rad); see the module docstring for the conventions.

    Attributes
    ----------
    kind : ``"roller"``, ``"flat"`` or ``"knife"``.
    base_radius : float
        ``Rb`` (mm, > 0): the cam radius where the follower rests at zero lift or swing.
    motion : ``"translating"`` or ``"oscillating"``.
    roller_radius : float
        ``r`` (mm): > 0 for a roller, 0 for a knife or flat face.
    offset : float
        Translating only: the follower axis is the line ``x = offset`` (mm); ``|offset| < Rp``
        for a roller or knife (for a flat face it places the face centre only).
    pivot : tuple of float or None
        Oscillating only: the pivot ``(x, y)`` in the fixed frame, mm, outside the prime circle.
    arm_length : float
        Oscillating roller / knife: pivot to roller centre (tip), mm, with
        ``|pivot distance - arm_length| < Rp < pivot distance + arm_length``.
    face_offset : float
        Oscillating flat: distance of the face line from the pivot, mm (> 0 towards the cam),
        with ``|base_radius + face_offset| < pivot distance``.
    lift_turn : ``"ccw"`` or ``"cw"``
        Oscillating only: the way the arm turns about its pivot for a positive swing.
    rotation : ``"ccw"`` or ``"cw"``
        The cam's direction of rotation.
    """

    kind: str
    base_radius: float
    motion: str = "translating"
    roller_radius: float = 0.0
    offset: float = 0.0
    pivot: tuple[float, float] | None = None
    arm_length: float = 0.0
    face_offset: float = 0.0
    lift_turn: str = "ccw"
    rotation: str = "ccw"

    def __post_init__(self) -> None:
        _choice("kind", self.kind, KINDS)
        _choice("motion", self.motion, MOTIONS)
        _choice("rotation", self.rotation, ROTATIONS)
        _choice("lift_turn", self.lift_turn, ROTATIONS)
        base = require_positive("base_radius", self.base_radius)
        r = require_finite("roller_radius", self.roller_radius)
        if self.kind == "roller" and r <= 0:
            raise ParameterError("roller_radius", self.roller_radius, "roller_radius > 0 mm for a roller follower")
        if self.kind != "roller" and r != 0:
            raise ParameterError("roller_radius", self.roller_radius, f"0 for a {self.kind} follower")
        offset = require_finite("offset", self.offset)
        arm = require_finite("arm_length", self.arm_length)
        face = require_finite("face_offset", self.face_offset)
        object.__setattr__(self, "base_radius", base)
        object.__setattr__(self, "roller_radius", r)
        object.__setattr__(self, "offset", offset)
        object.__setattr__(self, "arm_length", arm)
        object.__setattr__(self, "face_offset", face)
        prime = base + r
        if self.motion == "translating":
            if self.pivot is not None:
                raise ParameterError("pivot", self.pivot, "None for a translating follower (a pivot is for motion = 'oscillating')")
            if arm != 0:
                raise ParameterError("arm_length", arm, "0 for a translating follower")
            if face != 0:
                raise ParameterError("face_offset", face, "0 for a translating follower (use offset)")
            if self.kind != "flat" and abs(offset) >= prime:
                raise ParameterError("offset", offset, f"|offset| < prime radius = {prime:g} mm (base_radius + roller_radius)")
            return
        if offset != 0:
            raise ParameterError("offset", offset, "0 for an oscillating follower (place the pivot instead)")
        if self.pivot is None or len(self.pivot) != 2:
            raise ParameterError("pivot", self.pivot, "a point (x, y) in mm for an oscillating follower")
        pivot = (require_finite("pivot", self.pivot[0]), require_finite("pivot", self.pivot[1]))
        object.__setattr__(self, "pivot", pivot)
        d = math.hypot(*pivot)
        if self.kind == "flat":
            if arm != 0:
                raise ParameterError("arm_length", arm, "0 for an oscillating flat face (its face_offset places the face)")
            if not abs(base + face) < d:
                raise ParameterError("face_offset", face, f"-{d:g} - base_radius < face_offset < {d:g} - base_radius mm "
                                     f"(the face at rest must be tangent to the base circle; pivot distance {d:g} mm)",
                                     f"|base_radius + face_offset| = {abs(base + face):g} mm >= pivot distance")
            return
        if face != 0:
            raise ParameterError("face_offset", face, f"0 for an oscillating {self.kind} follower")
        if not d > prime:
            raise ParameterError("pivot", pivot, f"a point farther than the prime radius {prime:g} mm from the cam axis",
                                 f"its distance is {d:g} mm")
        if arm <= 0:
            raise ParameterError("arm_length", arm, "arm_length > 0 mm")
        if not abs(d - arm) < prime:
            raise ParameterError("arm_length", arm, f"{d - prime:g} < arm_length < {d + prime:g} mm",
                                 f"the arm must reach the prime circle of radius {prime:g} mm from the pivot at distance {d:g} mm")

    # -- derived constants ---------------------------------------------------------------------
    @property
    def sigma(self) -> float:
        """+1 for a ccw cam, -1 for a cw cam."""
        return 1.0 if self.rotation == "ccw" else -1.0

    @property
    def tau(self) -> float:
        """+1 if a positive swing turns the arm counter-clockwise about the pivot, else -1."""
        return 1.0 if self.lift_turn == "ccw" else -1.0

    @property
    def prime_radius(self) -> float:
        """``Rp = base_radius + roller_radius`` (mm): the roller-centre (knife-tip) radius at rest."""
        return self.base_radius + self.roller_radius

    @property
    def lift_unit(self) -> str:
        """Unit of the displacement law: ``"mm"`` (translating) or ``"rad"`` (oscillating)."""
        return "mm" if self.motion == "translating" else "rad"

    @property
    def rest_height(self) -> float:
        """Translating roller / knife: ``sqrt(Rp^2 - e^2)``, the roller-centre ``y`` at zero lift (mm)."""
        return math.sqrt(self.prime_radius**2 - self.offset**2)

    @property
    def rest_arm_angle(self) -> float:
        """Oscillating roller / knife: the arm angle ``g0`` at zero swing (rad, fixed frame)."""
        px, py = self.pivot  # type: ignore[misc]
        d, rp, arm = math.hypot(px, py), self.prime_radius, self.arm_length
        # the roller centre C0 on both circles |C| = Rp and |C - pivot| = L (law of cosines)
        half = math.acos(max(-1.0, min(1.0, (d * d + rp * rp - arm * arm) / (2.0 * d * rp))))
        base = math.atan2(py, px)
        for sign in (1.0, -1.0):
            c = rp * np.array([math.cos(base + sign * half), math.sin(base + sign * half)])
            g = math.atan2(c[1] - py, c[0] - px)
            # d|C|^2/dg = 2 L C . J u(g): a positive swing (dg = tau dphi) must move C outwards
            if self.tau * (-c[0] * math.sin(g) + c[1] * math.cos(g)) > 0:
                return g
        raise GeometryError("no rest position of the arm moves the roller outward (arm tangent to the prime circle)")

    @property
    def rest_face_angle(self) -> float:
        """Oscillating flat: the angle of the face normal ``w0`` at zero swing (rad, fixed frame)."""
        px, py = self.pivot  # type: ignore[misc]
        d = math.hypot(px, py)
        half = math.acos((self.base_radius + self.face_offset) / d)  # pivot . w0 = Rb + f
        base = math.atan2(py, px)
        for sign in (1.0, -1.0):
            a = base + sign * half
            # d(pivot . w)/dswing = tau pivot . J w0 must be > 0: the face moves away from the cam
            if self.tau * (-px * math.sin(a) + py * math.cos(a)) > 0:
                return a
        raise GeometryError("no rest position of the face lifts it for a positive swing")


# --------------------------------------------------------------------------------------------
# Closed-form kinematics
# --------------------------------------------------------------------------------------------
def _rot(angle: np.ndarray | tuple[np.ndarray, np.ndarray], v: np.ndarray) -> np.ndarray:
    """Rotate vectors ``v`` (n, 2) by ``angle`` (n,) rad, or by the angle whose (cos, sin) are given."""
    c, s = angle if isinstance(angle, tuple) else (np.cos(angle), np.sin(angle))
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]], axis=-1)


def _perp(v: np.ndarray) -> np.ndarray:
    """``J v``: vectors (n, 2) turned by +90 deg."""
    return np.stack([-v[:, 1], v[:, 0]], axis=-1)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]


@dataclass(frozen=True)
class Kinematics:
    """Closed-form follower kinematics and cam geometry at cam angles ``theta`` (all arrays (n,) or (n, 2)).

    Attributes
    ----------
    theta : cam angles, rad.
    s, ds, d2s, d3s : the law's displacement and its derivatives per rad of cam angle (mm or
        rad of swing, per rad^k): the follower's SVAJ, for both rotation directions.
    unit : ``"mm"`` or ``"rad"``: unit of ``s``.
    pressure_angle : rad, signed (see the module docstring).
    follower_point : the roller centre / knife tip / flat-face contact point in the fixed frame, mm.
    arm_angle : oscillating roller / knife: the arm angle ``g`` (rad, fixed frame); oscillating
        flat: the face-normal angle (rad, fixed frame); translating: None.
    pitch_point : roller / knife: the pitch curve (roller-centre path) in the cam frame, mm; flat: None.
    pitch_curvature : signed curvature of the pitch curve, 1/mm (flat: None).
    contact_point : the contact point on the cam profile, cam frame, mm.
    profile_curvature : signed curvature of the cam profile at the contact, 1/mm (> 0 convex).
    profile_radius : its signed radius of curvature, mm (``inf`` where the curvature is 0).
    face_position : flat faces: the contact's position along the face, mm: translating, from
        the face centre (follower axis), positive towards ``+x``; oscillating, ``xi`` from the foot
        of the pivot's perpendicular, positive along ``J w``.  None for rollers and knives.
    normal_turn_rate : flat faces: ``-sigma dpsi/dtheta`` (> 0 required: the face normal seen
        from the cam turns monotonically); None otherwise.
    """

    theta: np.ndarray
    s: np.ndarray
    ds: np.ndarray
    d2s: np.ndarray
    d3s: np.ndarray
    unit: str
    pressure_angle: np.ndarray
    follower_point: np.ndarray
    arm_angle: np.ndarray | None
    pitch_point: np.ndarray | None
    pitch_curvature: np.ndarray | None
    contact_point: np.ndarray
    profile_curvature: np.ndarray
    profile_radius: np.ndarray
    face_position: np.ndarray | None
    normal_turn_rate: np.ndarray | None
    # internal: exact first and second derivatives d/dtheta of the pitch and the profile (cam frame)
    pitch_d1: np.ndarray | None = field(default=None, repr=False)
    pitch_d2: np.ndarray | None = field(default=None, repr=False)
    contact_d1: np.ndarray | None = field(default=None, repr=False)
    contact_d2: np.ndarray | None = field(default=None, repr=False)

    @property
    def pitch_radius(self) -> np.ndarray | None:
        """Signed radius of curvature of the pitch curve, mm (``inf`` where straight; None for a flat face)."""
        if self.pitch_curvature is None:
            return None
        k = self.pitch_curvature
        with np.errstate(divide="ignore"):
            return np.where(k != 0, 1.0 / np.where(k != 0, k, 1.0), np.inf)


def _centre(f: FollowerSpec, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray):
    """Roller centre C and dC/dtheta .. d3C/dtheta3 (fixed frame, (n, 2)), the unit direction of
    motion m (n, 2) and the arm angle (oscillating) or None."""
    n = s.size
    if f.motion == "translating":
        zero = np.zeros(n)
        c = np.stack([np.full(n, f.offset), f.rest_height + s], axis=-1)
        m = np.tile([0.0, 1.0], (n, 1))
        return c, np.stack([zero, ds], -1), np.stack([zero, d2s], -1), np.stack([zero, d3s], -1), m, None
    tau, arm = f.tau, f.arm_length
    g = f.rest_arm_angle + tau * s
    g1, g2, g3 = tau * ds, tau * d2s, tau * d3s
    u = np.stack([np.cos(g), np.sin(g)], axis=-1)
    ju = _perp(u)
    c = np.asarray(f.pivot) + arm * u
    c1 = (arm * g1)[:, None] * ju
    c2 = arm * (g2[:, None] * ju - (g1 * g1)[:, None] * u)
    c3 = arm * ((g3 - g1**3)[:, None] * ju - (3.0 * g1 * g2)[:, None] * u)
    return c, c1, c2, c3, tau * ju, g


def _kinematics_from(f: FollowerSpec, theta: np.ndarray, s, ds, d2s, d3s) -> Kinematics:
    sigma = f.sigma
    back = (np.cos(theta), -sigma * np.sin(theta))  # fixed -> cam frame: R(-sigma theta), as (cos, sin)
    if f.kind == "flat":
        n = theta.size
        if f.motion == "translating":
            psi_f = np.full(n, math.pi / 2)
            h, h1, h2, h3 = f.base_radius + s, ds, d2s, d3s
            psi1, psi2, psi3 = np.full(n, -sigma), np.zeros(n), np.zeros(n)
        else:
            tau, pivot, face = f.tau, np.asarray(f.pivot), f.face_offset
            psi_f = f.rest_face_angle + tau * s
            w = np.stack([np.cos(psi_f), np.sin(psi_f)], axis=-1)
            p, q = w @ pivot, _perp(w) @ pivot
            # h = pivot . w - f with d(pivot . w)/dpsi_f = pivot . J w = q, dq/dpsi_f = -p, dpsi_f = tau ds
            h = p - face
            h1 = tau * ds * q
            h2 = tau * d2s * q - ds * ds * p
            h3 = tau * (d3s - ds**3) * q - 3.0 * ds * d2s * p
            psi1, psi2, psi3 = tau * ds - sigma, tau * d2s, tau * d3s
        w = np.stack([np.cos(psi_f), np.sin(psi_f)], axis=-1)
        jw = _perp(w)
        with np.errstate(divide="ignore", invalid="ignore"):
            # support function H(psi) of the cam, psi(theta) = psi_f - sigma theta (cam frame):
            # H = h, H_psi = h1 / psi1, H_psipsi = N / psi1^3 with N = h2 psi1 - h1 psi2;
            # the envelope's radius of curvature is rho = H + H_psipsi
            dh = h1 / psi1
            num = h2 * psi1 - h1 * psi2
            rho = h + num / psi1**3
            rho1 = h1 + (h3 * psi1 - h1 * psi3) / psi1**3 - 3.0 * num * psi2 / psi1**4  # d rho / d theta
            kappa = 1.0 / rho
        x_fixed = h[:, None] * w + dh[:, None] * jw
        u_cam, ju_cam = _rot(back, w), _rot(back, jw)
        # Q(theta) = H u(psi) + H_psi J u(psi): dQ/dtheta = psi1 rho J u, d2Q = (psi1 rho)' J u - psi1^2 rho u
        d1 = (psi1 * rho)[:, None] * ju_cam
        d2 = (psi2 * rho + psi1 * rho1)[:, None] * ju_cam - (psi1 * psi1 * rho)[:, None] * u_cam
        if f.motion == "translating":
            face_pos = x_fixed[:, 0] - f.offset
            alpha = np.zeros(n)
            arm_angle = None
        else:
            face_pos = dh - jw @ np.asarray(f.pivot)
            with np.errstate(divide="ignore", invalid="ignore"):
                alpha = np.where(face_pos != 0, np.arctan(f.face_offset / face_pos), math.copysign(math.pi / 2, f.face_offset or 1.0))
            arm_angle = psi_f
        return Kinematics(theta, s, ds, d2s, d3s, f.lift_unit, alpha, x_fixed, arm_angle, None, None, _rot(back, x_fixed),
                          kappa, rho, face_pos, -sigma * psi1, None, None, d1, d2)
    c, c1, c2, c3, m, g = _centre(f, s, ds, d2s, d3s)
    # P = R(-sigma theta) C; with D = d/dtheta - sigma J on fixed-frame vectors ((sigma J)^2 = -1):
    # P' = R V, P'' = R A, P''' = R B with V = D C, A = D^2 C, B = D^3 C
    v = c1 - sigma * _perp(c)
    a = c2 - 2.0 * sigma * _perp(c1) - c
    b = c3 - 3.0 * sigma * _perp(c2) - 3.0 * c1 + sigma * _perp(c)
    speed = np.hypot(v[:, 0], v[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        # the counter-clockwise contour runs against theta for a ccw cam: signed curvature -sigma (V x A) / |V|^3
        kappa_p = -sigma * _cross(v, a) / speed**3
        kappa_p1 = -sigma * (_cross(v, b) / speed**3 - 3.0 * _cross(v, a) * _dot(v, a) / speed**5)
        t_ccw = (-sigma / speed)[:, None] * v  # unit tangent along the counter-clockwise contour
    n_out = np.stack([t_ccw[:, 1], -t_ccw[:, 0]], axis=-1)
    r = f.roller_radius
    x_fixed = c - r * n_out  # Q = P - r n: Q' = P' (1 - r kappa), Q'' = P'' (1 - r kappa) - r kappa' P'
    factor = 1.0 - r * kappa_p
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = kappa_p / factor  # profile: rho = rho_pitch - r
        rho = np.where(kappa != 0, 1.0 / kappa, np.inf)
    alpha = np.arctan2(_dot(v, m), np.abs(_cross(v, m)))
    q1 = v * factor[:, None]
    q2 = a * factor[:, None] - (r * kappa_p1)[:, None] * v
    return Kinematics(theta, s, ds, d2s, d3s, f.lift_unit, alpha, c, g, _rot(back, c), kappa_p, _rot(back, x_fixed),
                      kappa, rho, None, None, _rot(back, v), _rot(back, a), _rot(back, q1), _rot(back, q2))


def kinematics(follower: FollowerSpec, law: Displacement, theta: object) -> Kinematics:
    """Closed-form kinematics and geometry of ``follower`` driven by ``law`` at cam angles ``theta`` (rad).

    Everything comes from ``s, s', s''`` of the law pointwise (the jerk is the law's ``s'''``):
    pressure angle, contact point, radii of curvature of the pitch curve and the profile.
    At a break where ``s''`` jumps the value is the law's own value at that angle.
    """
    theta = np.atleast_1d(np.asarray(theta, dtype=float)).ravel()
    s, ds, d2s, d3s = (np.asarray(x, dtype=float).ravel() for x in law(theta))
    return _kinematics_from(follower, theta, s, ds, d2s, d3s)


# --------------------------------------------------------------------------------------------
# Undercut / validity
# --------------------------------------------------------------------------------------------
def profile_failures(f: FollowerSpec, k: Kinematics) -> list[tuple[str, np.ndarray]]:
    """(reason, mask) pairs of the conditions that make the profile impossible."""
    out = []
    if f.kind == "flat":
        if f.motion == "translating":
            out.append(("the face passes through the rotation axis (base_radius + s <= 0)", f.base_radius + k.s <= 0))
        out.append(("the face normal turns backwards seen from the cam (1 - sigma tau phi' <= 0)", ~(k.normal_turn_rate > 0)))
        out.append(("undercut: the envelope's radius of curvature h + h'' <= 0", ~(k.profile_radius > 0) & (k.normal_turn_rate > 0)))
        return out
    if f.motion == "translating":
        out.append(("the follower passes through the rotation axis (sqrt(Rp^2 - e^2) + s <= 0)", f.rest_height + k.s <= 0))
    speed = np.hypot(*k.pitch_d1.T)
    scale = max(1.0, f.prime_radius)
    out.append(("cusp: the pitch curve stops (zero relative velocity)", ~(speed > 1e-12 * scale)))
    if f.kind == "roller":
        out.append((f"undercut: convex radius of curvature of the pitch curve <= roller radius {f.roller_radius:g} mm",
                    f.roller_radius * k.pitch_curvature >= 1.0))
    return out


def _run_ranges(mask: np.ndarray, theta: np.ndarray) -> list[tuple[float, float]]:
    """(start, end) cam angles in deg of the runs of True in ``mask`` over the sorted angles ``theta`` (one turn, periodic)."""
    if not mask.any():
        return []
    deg = np.degrees(theta)
    if mask.all():
        return [(float(deg[0]), float(deg[-1]))]
    starts = np.nonzero(mask & ~np.roll(mask, 1))[0]
    ends = np.nonzero(mask & ~np.roll(mask, -1))[0]
    if ends[0] < starts[0]:  # a run wraps through 360 deg
        ends = np.roll(ends, -1)
    return [(round(float(deg[a]), 6), round(float(deg[b]), 6)) for a, b in zip(starts, ends)]


def check_grid(law: Displacement, check_step: float = DEFAULT_CHECK_STEP) -> np.ndarray:
    """Sorted cam angles (rad, one turn) for dense checks: a uniform grid of ``check_step`` plus
    every break and both one-sided neighbours of it (1e-9 rad away)."""
    require_positive("check_step", check_step, "rad")
    n = max(8, math.ceil(TWO_PI / check_step))
    brk = np.asarray(getattr(law, "breaks", np.zeros(0)), dtype=float)
    extra = np.concatenate([brk, brk - 1e-9, brk + 1e-9])
    return np.unique(np.mod(np.concatenate([np.arange(n) * (TWO_PI / n), extra]), TWO_PI))


# --------------------------------------------------------------------------------------------
# The spline representation
# --------------------------------------------------------------------------------------------
_PROBES = np.array([0.25, 0.5, 0.75])


def _c2_spline(t: np.ndarray, q: np.ndarray, start: tuple[np.ndarray, np.ndarray], end: tuple[np.ndarray, np.ndarray]):
    """C2 cubic spline through ``q`` (n, d) at ``t`` (n,), n >= 4, with the given first and second
    derivatives (dQ/dt, d2Q/dt2, each (d,)) at both ends; an extra knot in the first and in the
    last interval gives the two degrees of freedom the second-derivative conditions need
    (:func:`camgen.contour.cubic_with_end_derivatives`, numpy only).
    Returns the break points (p + 1,) and the coefficients (4, p, d), highest power first."""
    return cubic_with_end_derivatives(t, q, start, end)


def _inner_knots(t: np.ndarray) -> np.ndarray:
    """Interior knots of :func:`_c2_spline`: the inner samples and the midpoints of the first and last intervals."""
    return np.sort(np.concatenate([t[1:-1], [0.5 * (t[0] + t[1]), 0.5 * (t[-2] + t[-1])]]))


def _eval_pieces(x: np.ndarray, coeffs: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Values (m, d) at ``t`` (m,) of the piecewise cubic (breaks ``x``, coefficients (4, p, d))."""
    i = np.clip(np.searchsorted(x, t, side="right") - 1, 0, x.size - 2)
    h = (t - x[i])[:, None]
    c = coeffs[:, i]
    return ((c[0] * h + c[1]) * h + c[2]) * h + c[3]


def _breaks_of(law: Displacement) -> tuple[np.ndarray, np.ndarray]:
    brk = np.mod(np.asarray(getattr(law, "breaks", np.zeros(0)), dtype=float), TWO_PI)
    cont = np.asarray(getattr(law, "break_continuity", np.full(brk.size, 2)), dtype=int)
    if brk.shape != cont.shape:
        raise ParameterError("break_continuity", f"{cont.size} values", f"one per break ({brk.size})")
    return brk, cont


#: Weights of the one-sided extrapolation of the derivatives at a break from 1, 2, 3 steps away
#: (quadratic, error O(step^3)).
_ONE_SIDED_WEIGHTS = np.array([3.0, -3.0, 1.0])


def _spline_contours(exact: Callable, dims: int, sigma: float, law: Displacement, fit_tol: float,
                     initial_step: float = math.radians(5.0), max_rounds: int = 12,
                     max_pieces: int = 100_000) -> tuple[list[Contour], list[float]]:
    """Contours of ``dims`` exact curves at once: ``exact(theta) -> (Q, dQ/dtheta, d2Q/dtheta2)``, each
    (n, 2 dims) (the curves side by side), one cubic spline segment per interval between the law's
    breaks (one segment from cam angle 0 when there are none); the curves share their knots.

    The spline parameter is ``t = -sigma theta`` (the contour runs counter-clockwise).  Every
    segment is a C2 cubic spline through exact points on ``count`` uniform pieces (plus the two
    extra knots of :func:`_c2_spline`) that takes the exact one-sided tangent and second derivative
    at both ends, so neighbours join with the exact curve's own continuity: G2 where the law's
    ``s''`` is continuous, G1 (the exact curvature jump) where it jumps, G0 where ``s'`` jumps.  A
    segment gets more pieces (its error falls as h^4) until the distance of every curve from its
    exact points at the quarter and mid points of every piece is <= ``fit_tol`` mm.  The exact
    curves are evaluated for all segments in one call per refinement round.
    Returns the contours and the largest measured distance of each.
    """
    brk, _ = _breaks_of(law)
    tb = np.unique(np.mod(-sigma * brk, TWO_PI))
    if tb.size == 0:
        tb = np.zeros(1)
    cuts = np.append(tb, tb[0] + TWO_PI)
    lo, hi = cuts[:-1], cuts[1:]
    nseg = lo.size

    def at_t(t: np.ndarray):
        q, d1, d2 = exact(-sigma * t)
        return q, -sigma * d1, d2

    # one-sided dQ/dt and d2Q/dt2 at every segment's two ends, in one evaluation
    steps = _ONE_SIDED_STEP * np.array([1.0, 2.0, 3.0])
    probe_ends = np.concatenate([lo[:, None] + steps[None, :], hi[:, None] - steps[None, :]], axis=1).ravel()
    _, e1, e2 = at_t(probe_ends)
    w = _ONE_SIDED_WEIGHTS[None, :, None]
    e1, e2 = e1.reshape(nseg, 2, 3, -1), e2.reshape(nseg, 2, 3, -1)
    ends1, ends2 = (w * e1).sum(axis=2), (w * e2).sum(axis=2)  # (nseg, 2 [start, end], 2 dims)
    count = np.maximum(4, np.ceil((hi - lo) / initial_step)).astype(int)
    fits: list[tuple[np.ndarray, np.ndarray] | None] = [None] * nseg
    errors = np.zeros((nseg, dims))
    todo = list(range(nseg))
    for _ in range(max_rounds):
        grids, probes = [], []
        for k in todo:
            t = np.linspace(lo[k], hi[k], count[k] + 1)
            x = np.concatenate([[t[0]], _inner_knots(t), [t[-1]]])
            grids.append(t)
            probes.append((x[:-1, None] + _PROBES[None, :] * np.diff(x)[:, None]).ravel())
        sizes = [g.size + p.size for g, p in zip(grids, probes)]
        q_all = at_t(np.concatenate([np.concatenate([g, p]) for g, p in zip(grids, probes)]))[0]
        parts = np.split(q_all, np.cumsum(sizes)[:-1])
        left = []
        for k, t, probe, q in zip(todo, grids, probes, parts):
            x, coeffs = _c2_spline(t, q[: t.size], (ends1[k, 0], ends2[k, 0]), (ends1[k, 1], ends2[k, 1]))
            diff = _eval_pieces(x, coeffs, probe) - q[t.size:]
            err = np.array([float(np.max(np.hypot(diff[:, 2 * c], diff[:, 2 * c + 1]))) for c in range(dims)])
            fits[k], errors[k] = (x, coeffs), err
            worst = float(err.max())
            if worst > fit_tol:
                if count[k] >= max_pieces:
                    raise GeometryError(f"the spline representation does not reach fit_tol = {fit_tol:g} mm (error {worst:.3g} mm "
                                        f"with {count[k]} pieces): the curve is too close to a cusp; increase fit_tol or the base radius")
                count[k] = min(max_pieces, math.ceil(count[k] * min(16.0, max(1.25, (worst / (0.5 * fit_tol)) ** 0.25))))
                left.append(k)
        todo = left
        if not todo:
            break
    if todo:
        worst = float(errors[todo].max())
        raise GeometryError(f"the spline representation does not reach fit_tol = {fit_tol:g} mm (error {worst:.3g} mm "
                            f"with {int(count[todo].max())} pieces): the curve is too close to a cusp; increase fit_tol or the base radius")
    contours = []
    for c in range(dims):
        contours.append(Contour([Spline(x, coeffs[:, :, 2 * c: 2 * c + 2]) for x, coeffs in fits]))  # type: ignore[misc]
    return contours, [float(v) for v in errors.max(axis=0)]


# --------------------------------------------------------------------------------------------
# The cam
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CamEnvelope:
    """A cam for a follower and a law: the curves, the dense curvature data and the failures.

    Attributes
    ----------
    follower : the :class:`FollowerSpec`.
    profile : the cam profile (:class:`Contour`), or None when it cannot be made (report-only).
    pitch : roller / knife: the pitch curve (roller-centre path; the knife's is the profile);
        flat: None.
    data : :class:`Kinematics` on the dense check grid (see :func:`check_grid`).
    failures : one entry per failed condition: ``{"reason": str, "ranges_deg": [(start, end), ...],
        "worst_deg": float}`` (empty when the cam can be made).
    fit_tol : the requested tolerance of the spline representation, mm.
    fit_error : the largest measured distance of ``profile`` (else ``pitch``) from the exact
        curve at the probe points, mm (NaN when neither was built).
    """

    follower: FollowerSpec
    profile: Contour | None
    pitch: Contour | None
    data: Kinematics
    failures: list[dict] = field(default_factory=list)
    fit_tol: float = DEFAULT_FIT_TOL
    fit_error: float = float("nan")

    @property
    def ok(self) -> bool:
        return not self.failures


def _failure_message(f: FollowerSpec, failures: list[dict]) -> str:
    parts = []
    for item in failures:
        ranges = ", ".join(f"{a:.3f}..{b:.3f}" for a, b in item["ranges_deg"][:6])
        parts.append(f"{item['reason']} at cam angles {ranges} deg")
    return (f"{f.kind} follower ({f.motion}, base_radius {f.base_radius:g} mm) cannot ride this law: " + "; ".join(parts)
            + "; increase base_radius (camgen.synthesis.sizing.min_base_radius gives the smallest that works)"
            + (" or reduce the roller radius" if f.kind == "roller" else ""))


def cam_envelope(follower: FollowerSpec, law: Displacement, *, fit_tol: float = DEFAULT_FIT_TOL,
                 report_only: bool = False, check_step: float = DEFAULT_CHECK_STEP) -> CamEnvelope:
    """The exact cam profile (and pitch curve) of ``follower`` driven by ``law``.

    Parameters
    ----------
    follower : FollowerSpec
    law : Displacement
        ``s`` in mm (translating) or rad of swing (oscillating) per rad of cam angle.
    fit_tol : float
        Largest distance (mm) of the spline representation from the exact curve, measured at the
        quarter and mid points of every spline piece; the piece count follows from it.
    report_only : bool
        False: raise :class:`GeometryError` naming the cam angles when the profile cannot be made
        (undercut, cusp, face normal turning backwards).  True: return the envelope anyway with
        ``profile = None``, the pitch curve where it exists and the failure data.
    check_step : float
        Spacing (rad) of the dense grid of the undercut check and of ``data``.

    Raises
    ------
    GeometryError
        The profile cannot be made (unless ``report_only``), or the law's velocity jumps under a
        roller or flat follower (a corner of the pitch curve), or ``fit_tol`` cannot be reached.
    """
    fit_tol = require_positive("fit_tol", fit_tol)
    f = follower
    brk, cont = _breaks_of(law)
    if f.kind != "knife" and np.any(cont <= 0):
        where = ", ".join(f"{math.degrees(b):.3f}" for b in brk[cont <= 0])
        raise GeometryError(f"the law's velocity jumps at cam angles {where} deg: a {f.kind} follower cannot follow "
                            "a corner of the pitch curve exactly; use laws with continuous velocity there (or a knife follower)")
    theta = check_grid(law, check_step)
    data = kinematics(f, law, theta)
    failures = []
    for reason, mask in profile_failures(f, data):
        if mask.any():
            worst = float(theta[np.argmax(mask)])
            failures.append({"reason": reason, "ranges_deg": _run_ranges(mask, theta), "worst_deg": math.degrees(worst)})
    if failures and not report_only:
        raise GeometryError(_failure_message(f, failures))

    sigma = f.sigma
    pitch = profile = None
    error = float("nan")
    pitch_ok = f.kind != "flat" and not any(item["reason"].startswith(("cusp", "the follower passes")) for item in failures)
    # the curves to represent: roller: pitch and profile (pitch only when the profile cannot be made);
    # knife: its pitch curve is its profile; flat: the profile
    want = [] if failures else ["profile"]
    if pitch_ok and f.kind == "roller":
        want.insert(0, "pitch")

    def exact(th: np.ndarray):
        k = kinematics(f, law, th)
        out = []
        for name in want:
            out.append((k.pitch_point, k.pitch_d1, k.pitch_d2) if name == "pitch" else (k.contact_point, k.contact_d1, k.contact_d2))
        return tuple(np.concatenate([o[i] for o in out], axis=1) for i in range(3))

    if want:
        try:
            curves, errors = _spline_contours(exact, len(want), sigma, law, fit_tol)
        except GeometryError as exc:  # report-only: show what failed instead of the pitch curve
            if not failures:
                raise
            failures.append({"reason": f"pitch curve: {exc}", "ranges_deg": [], "worst_deg": float("nan")})
            curves, errors = [], []
        made = dict(zip(want, zip(curves, errors)))
        if "pitch" in made:
            pitch, error = made["pitch"]
        if "profile" in made:
            profile, error = made["profile"]
            if f.kind == "knife":
                pitch = profile
    return CamEnvelope(f, profile, pitch, data, failures, fit_tol, error)
