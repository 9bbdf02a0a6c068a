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
``h + h''``).  Both curves are represented by quintic :class:`~camgen.contour.Spline` segments,
one per law segment between breaks: on uniform knots, every piece is the quintic Hermite
interpolant of the exact curve's point, tangent and second derivative at both its ends (C2 inside
a segment), with the exact one-sided tangent and second derivative at every break where the law's
acceleration (or velocity) jumps, knots at every break, the piece count from the error bound
``h^6 max|d6Q/dt6| / 46080`` (``d6Q/dt6`` from the check grid) and refined until the spline is
within ``fit_tol`` (mm) of the exact curve at the quarter and mid points of every piece.  The
curve is therefore G2 at every break where ``s''`` is continuous and exactly G1 (a curvature
jump) where ``s''`` jumps.  The contour has one segment per interval between the law's breaks
(one segment from cam angle 0 round to itself when there are none), and each segment's spline
parameter is ``t = -sigma theta`` (rad, shifted by a multiple of 2 pi): the
spline at ``t`` is the contact point of cam angle ``theta``.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import Any, Callable, Literal, NamedTuple, Protocol, TypeAlias, overload

import numpy as np

from camgen.contour import (
    DEFAULT_CLOSURE_TOL,
    Contour,
    Spline,
    piece_green_areas,
    power_coefficients,
    quintic_hermite_data,
    quintic_hermite_scaled,
)
from camgen.errors import (
    FitToleranceError,
    GeometryError,
    ParameterError,
    require_finite,
    require_positive,
)

__all__ = [
    "BOUND_SPACING", "BREAK_MERGE", "CamEnvelope", "CheckGrid", "DEFAULT_CHECK_STEP", "DEFAULT_FIT_TOL",
    "Displacement", "FollowerSpec", "Kinematics", "MOTIONS", "ROTATIONS", "SCREEN_CLEARANCE",
    "SCREEN_UNDERCUT", "UNDERCUT_SCREEN_MARGIN", "cam_envelope", "failing_conditions", "check_grid", "contact_points", "kinematics", "profile_curvature", "profile_curvatures", "pitch_offset_failures", "pitch_offsets", "profile_failures",
]

TWO_PI = 2.0 * math.pi
#: A law's ``(s, ds, d2s, d3s)`` at some cam angles, (n,) each.
_LawValues: TypeAlias = "tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]"
#: A curve in the cam frame and its first two derivatives by the cam angle, ``(Q, dQ, d2Q)``, complex (n,) each.
_Curve: TypeAlias = "tuple[np.ndarray, np.ndarray, np.ndarray]"

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
    kind : a registered follower with a point or face contact (:mod:`camgen.followers`:
        ``"roller"``, ``"knife"``, ``"flat"``, ...); ``contact`` is its contact and
        ``has_radius`` whether its point contact has a radius (a roller) or not (a knife edge).
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
    contact: str = field(init=False, repr=False, compare=False)
    has_radius: bool = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        from camgen.followers import follower_names, get_follower, known

        model = get_follower(self.kind) if known(self.kind) else None
        if model is None or model.contact not in ("point", "face"):
            _choice("kind", self.kind, follower_names(("point", "face")))
        assert model is not None
        object.__setattr__(self, "contact", model.contact)
        object.__setattr__(self, "has_radius", model.has_radius)
        _choice("motion", self.motion, MOTIONS)
        _choice("rotation", self.rotation, ROTATIONS)
        _choice("lift_turn", self.lift_turn, ROTATIONS)
        base = require_positive("base_radius", self.base_radius)
        r = require_finite("roller_radius", self.roller_radius)
        if self.has_radius and r <= 0:
            raise ParameterError("roller_radius", self.roller_radius, f"roller_radius > 0 mm for a {self.kind} follower")
        if not self.has_radius and r != 0:
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
            if self.contact == "point" and abs(offset) >= prime:
                raise ParameterError("offset", offset, f"|offset| < prime radius = {prime:g} mm (base_radius + roller_radius)")
            return
        if offset != 0:
            raise ParameterError("offset", offset, "0 for an oscillating follower (place the pivot instead)")
        if self.pivot is None or len(self.pivot) != 2:
            raise ParameterError("pivot", self.pivot, "a point (x, y) in mm for an oscillating follower")
        pivot = (require_finite("pivot", self.pivot[0]), require_finite("pivot", self.pivot[1]))
        object.__setattr__(self, "pivot", pivot)
        d = math.hypot(*pivot)
        if self.contact == "face":
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
    def edge(self) -> bool:
        """A point contact of radius 0 (a knife edge): the profile is the pitch curve itself, and
        a corner of it (a velocity jump of the law) can be cut."""
        return self.contact == "point" and not self.has_radius

    @property
    def sigma(self) -> float:
        """+1 for a ccw cam, -1 for a cw cam."""
        return 1.0 if self.rotation == "ccw" else -1.0

    @property
    def tau(self) -> float:
        """+1 if a positive swing turns the arm counter-clockwise about the pivot, else -1."""
        return 1.0 if self.lift_turn == "ccw" else -1.0

    @property
    def pivot_xy(self) -> tuple[float, float]:
        """The pivot ``(x, y)`` (mm) of an oscillating follower (``__post_init__`` requires it there);
        a translating follower has none: :class:`~camgen.errors.ParameterError`."""
        if self.pivot is None:
            raise ParameterError("pivot", None, "a point (x, y) in mm for an oscillating follower")
        return self.pivot

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
        px, py = self.pivot_xy
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
        px, py = self.pivot_xy
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
# The formulas work on the x and y components (real (n,) arrays); the curves in the cam frame are
# complex arrays x + i y (turning them into the cam frame is one product with exp(-i sigma theta)),
# and the (n, 2) arrays of :class:`Kinematics` are float views of those (no copies).
def _xy(z: np.ndarray) -> np.ndarray:
    """The (n, 2) float view ``(x, y)`` of the complex array ``z`` (n,) (no copy)."""
    return z.view(np.float64).reshape(z.shape + (2,))


def _to_cam(f: FollowerSpec, theta: np.ndarray) -> np.ndarray:
    """``exp(-i sigma theta)`` (n,): the rotation R(-sigma theta) from the fixed to the cam frame."""
    return _rotation_to_cam(f.sigma, theta)


def _rotation_to_cam(sigma: float, theta: np.ndarray) -> np.ndarray:
    """:func:`_to_cam` of a cam turning in the direction ``sigma`` (+1 ccw, -1 cw)."""
    back = np.empty(theta.size, dtype=complex)
    np.cos(theta, out=back.real)
    np.sin(theta, out=back.imag)
    if sigma > 0:
        np.negative(back.imag, out=back.imag)
    return back


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
    arm_angle: np.ndarray | None
    pitch_curvature: np.ndarray | None
    profile_curvature: np.ndarray
    profile_radius: np.ndarray
    face_position: np.ndarray | None
    normal_turn_rate: np.ndarray | None
    # internal: the points and the curves' derivatives (made on first use for a roller or knife)
    curves: "_CurvePoints" = field(repr=False, compare=False)
    # internal: a roller's or knife's terms of profile_failures (the same numbers as from s, ds, d2s)
    pitch_measures: "_PitchMeasures | None" = field(default=None, repr=False, compare=False)

    @property
    def follower_point(self) -> np.ndarray:
        """The roller centre / knife tip / flat-face contact point in the fixed frame, mm (n, 2)."""
        return self.curves.points()[0]

    @property
    def pitch_point(self) -> np.ndarray | None:
        """Roller / knife: the pitch curve in the cam frame, mm (n, 2); flat: None."""
        return self.curves.points()[1]

    @property
    def contact_point(self) -> np.ndarray:
        """The contact point on the cam profile, cam frame, mm (n, 2)."""
        return self.curves.points()[2]

    @property
    def pitch_d1(self) -> np.ndarray | None:
        """Exact d/dtheta of the pitch curve (cam frame, mm/rad, (n, 2)); flat: None."""
        return self.curves.points()[3]

    @property
    def pitch_d2(self) -> np.ndarray | None:
        """Exact d2/dtheta2 of the pitch curve (cam frame, mm/rad^2, (n, 2)); flat: None."""
        return self.curves.points()[4]

    @property
    def contact_d1(self) -> np.ndarray:
        """Exact d/dtheta of the profile at the contact (cam frame, mm/rad, (n, 2))."""
        return self.curves.points()[5]

    @property
    def contact_d2(self) -> np.ndarray:
        """Exact d2/dtheta2 of the profile at the contact (cam frame, mm/rad^2, (n, 2))."""
        return self.curves.points()[6]

    @property
    def pitch_radius(self) -> np.ndarray | None:
        """Signed radius of curvature of the pitch curve, mm (``inf`` where straight; None for a flat face)."""
        if self.pitch_curvature is None:
            return None
        k = self.pitch_curvature
        with np.errstate(divide="ignore"):
            return np.where(k != 0, 1.0 / np.where(k != 0, k, 1.0), np.inf)


#: The points of a :class:`Kinematics`: follower point, pitch point, contact point, the pitch
#: curve's two derivatives, the profile's two ((n, 2) each; None where the follower has none).
_Points: TypeAlias = ("tuple[np.ndarray, np.ndarray | None, np.ndarray, np.ndarray | None, np.ndarray | None, "
                      "np.ndarray, np.ndarray]")


class _CurvePoints:
    """The points of a :class:`Kinematics` (:data:`_Points`): given (a flat face) or made on first
    use from a roller's or knife's terms (:func:`_roller_points`: a design evaluation reads the
    pressure angle and the curvatures only; the same numbers whenever they are made)."""

    __slots__ = ("_made", "_terms")

    def __init__(self, made: _Points | None = None, terms: "_RollerTerms | None" = None) -> None:
        self._made = made
        self._terms = terms

    def points(self) -> _Points:
        made = self._made  # (locals: another thread may make them between two reads)
        if made is None:
            terms = self._terms
            if terms is None:  # made by another thread meanwhile
                made = self._made
                assert made is not None  # set before the terms are dropped
                return made
            made = self._made = _roller_points(*terms)
            self._terms = None
        return made

    def __getstate__(self) -> _Points:
        return self.points()

    def __setstate__(self, made: _Points) -> None:
        self._made, self._terms = made, None


#: What :func:`_roller_points` makes the points from: the follower, the cam angles, the law's
#: ``s .. s'``, the rotation into the cam frame there (None: made then) and the roller centre
#: ``(cx, cy)`` (fixed frame, :func:`_centre`).
_RollerTerms: TypeAlias = ("tuple[FollowerSpec, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray | None, "
                           "np.ndarray | float, np.ndarray]")


def _roller_points(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
                   back: np.ndarray | None, cx: np.ndarray | float, cy: np.ndarray) -> _Points:
    """The points of a roller's or knife's :class:`Kinematics` (:data:`_Points`) from its
    :data:`_RollerTerms`: the pitch curve and the profile with their two derivatives by
    :func:`_roller`'s arithmetic (the curves of the spline fit), the follower point ``(cx, cy)``."""
    (pitch, p1, p2), (contact, q1, q2) = _roller(f, theta, s, ds, d2s, d3s, False, ("pitch", "profile"), back)
    follower = np.empty(theta.size, dtype=complex)
    follower.real = cx
    follower.imag = cy
    return _xy(follower), _xy(pitch), _xy(contact), _xy(p1), _xy(p2), _xy(q1), _xy(q2)


def _centre(f: FollowerSpec, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray | None):
    """The roller centre C (fixed frame, mm) as (x, y), its velocity V = D C, acceleration A = D^2 C
    and B = D^3 C (None when ``d3s`` is None) relative to the cam (``D = d/dtheta - sigma J``, components (x, y) each), the
    direction of motion m (x, y) (None for the translating ``+y``) and the arm angle (oscillating) or None."""
    sigma = f.sigma
    if f.motion == "translating":
        # C = (e, Y + s), dC = (0, s'), d2C = (0, s''), d3C = (0, s''')
        e, y = f.offset, f.rest_height + s
        v = (sigma * y, ds - sigma * e)
        a = (2.0 * sigma * ds - e, d2s - y)
        b = None if d3s is None else (sigma * (3.0 * d2s - y), d3s - 3.0 * ds + sigma * e)
        return (e, y), v, a, b, None, None
    tau, arm = f.tau, f.arm_length
    px, py = f.pivot_xy
    g = f.rest_arm_angle + tau * s
    g1, g2 = tau * ds, tau * d2s
    cg, sg = np.cos(g), np.sin(g)  # u = (cg, sg), J u = (-sg, cg)
    cx, cy = px + arm * cg, py + arm * sg
    k1 = arm * g1  # dC = k1 J u
    k2, l2 = arm * g2, arm * (g1 * g1)  # d2C = k2 J u - l2 u
    # V = dC - sigma J C, A = d2C - 2 sigma J dC - C, B = d3C - 3 sigma J d2C - 3 dC + sigma J C  (J J u = -u)
    v = (-k1 * sg + sigma * cy, k1 * cg - sigma * cx)
    a = (-k2 * sg - l2 * cg + 2.0 * sigma * k1 * cg - cx, k2 * cg - l2 * sg + 2.0 * sigma * k1 * sg - cy)
    b = None
    if d3s is not None:
        k3, l3 = arm * (tau * d3s - g1 * g1 * g1), arm * (3.0 * g1 * g2)  # d3C = k3 J u - l3 u
        b = (-k3 * sg - l3 * cg + 3.0 * sigma * (k2 * cg - l2 * sg) + 3.0 * k1 * sg - sigma * cy,
             k3 * cg - l3 * sg + 3.0 * sigma * (k2 * sg + l2 * cg) - 3.0 * k1 * cg + sigma * cx)
    return (cx, cy), v, a, b, (-tau * sg, tau * cg), g


def _in_cam(back: np.ndarray, x: np.ndarray | float, y: np.ndarray | float, out: np.ndarray | None = None) -> np.ndarray:
    """The fixed-frame vectors (x, y) in the cam frame: ``back (x + i y)``, complex (n,) (into ``out``)."""
    z = np.empty(back.size, dtype=complex) if out is None else out
    z.real = x
    z.imag = y
    z *= back
    return z


@overload
def _flat(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
          full: Literal[True], back: np.ndarray | None = None) -> Kinematics: ...
@overload
def _flat(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
          full: Literal[False], back: np.ndarray | None = None) -> tuple[_Curve]: ...
def _flat(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
          full: bool, back: np.ndarray | None = None) -> Kinematics | tuple[_Curve]:
    """Flat face: the :class:`Kinematics` (``full``) or just the profile curve's (Q, dQ, d2Q) in the cam frame
    (``back``: :func:`_to_cam` at ``theta`` when known)."""
    sigma, n = f.sigma, theta.size
    wx: float | np.ndarray  # the face normal w: fixed (translating) or turning with the arm (oscillating)
    wy: float | np.ndarray
    q: np.ndarray | None  # oscillating: pivot . J w
    if f.motion == "translating":
        # the face normal w = u(pi/2) is fixed: psi1 = -sigma, psi2 = psi3 = 0 in the formulas below
        wx, wy = math.cos(math.pi / 2), math.sin(math.pi / 2)
        h = f.base_radius + s
        dh = ds / -sigma
        rho = h + d2s
        rho1 = ds + d3s
        d1 = -sigma * rho  # dQ = d1 J w, d2Q = d2 J w - rho w (fixed frame, turned into the cam frame below)
        d2 = -sigma * rho1
        d1x, d1y, d2x, d2y = -wy * d1, wx * d1, -wy * d2 - wx * rho, wx * d2 - wy * rho
        psi_f = q = None
    else:
        tau, face = f.tau, f.face_offset
        px, py = f.pivot_xy
        psi_f = f.rest_face_angle + tau * s
        wx, wy = np.cos(psi_f), np.sin(psi_f)
        p, q = wx * px + wy * py, wx * py - wy * px  # pivot . w and pivot . J w
        # h = pivot . w - f with d(pivot . w)/dpsi_f = pivot . J w = q, dq/dpsi_f = -p, dpsi_f = tau ds
        h = p - face
        h1 = tau * ds * q
        h2 = tau * d2s * q - ds * ds * p
        h3 = tau * (d3s - ds * ds * ds) * q - 3.0 * ds * d2s * p
        psi1, psi2, psi3 = tau * ds - sigma, tau * d2s, tau * d3s
        with np.errstate(divide="ignore", invalid="ignore"):
            # support function H(psi) of the cam, psi(theta) = psi_f - sigma theta (cam frame):
            # H = h, H_psi = h1 / psi1, H_psipsi = N / psi1^3 with N = h2 psi1 - h1 psi2;
            # the envelope's radius of curvature is rho = H + H_psipsi
            dh = h1 / psi1
            num = h2 * psi1 - h1 * psi2
            cube = psi1 * psi1 * psi1
            rho = h + num / cube
            rho1 = h1 + (h3 * psi1 - h1 * psi3) / cube - 3.0 * num * psi2 / (cube * psi1)  # d rho / d theta
        # Q(theta) = H u(psi) + H_psi J u(psi): dQ/dtheta = psi1 rho J u, d2Q = (psi1 rho)' J u - psi1^2 rho u
        d1 = psi1 * rho
        d2 = psi2 * rho + psi1 * rho1
        r2 = psi1 * psi1 * rho
        d1x, d1y, d2x, d2y = -wy * d1, wx * d1, -wy * d2 - wx * r2, wx * d2 - wy * r2
    # full: rows 0-3 the contact point in the fixed frame, in the cam frame and its two derivatives
    cplx: np.ndarray | list[None] = np.empty((4, n), dtype=complex) if full else [None] * 4
    x_fixed = (h * wx - dh * wy, h * wy + dh * wx)  # h w + dh J w
    back = _to_cam(f, theta) if back is None else back
    contact = _in_cam(back, *x_fixed, cplx[1])
    q1, q2 = _in_cam(back, d1x, d1y, cplx[2]), _in_cam(back, d2x, d2y, cplx[3])
    if not full:
        return ((contact, q1, q2),)
    assert isinstance(cplx, np.ndarray)  # full: the rows, not the placeholders
    cplx[0].real, cplx[0].imag = x_fixed
    real = np.empty((4, n))  # curvature, face position, pressure angle, normal turn rate
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = np.divide(1.0, rho, out=real[0])
        if psi_f is None:
            face_pos = np.subtract(x_fixed[0], f.offset, out=real[1])
            alpha, turn = real[2], real[3]
            alpha.fill(0.0)
            turn.fill(1.0)
        else:
            assert q is not None  # set with psi_f (an oscillating face)
            face_pos = np.subtract(dh, q, out=real[1])
            alpha = real[2]
            alpha[...] = np.where(face_pos != 0, np.arctan(face / face_pos), math.copysign(math.pi / 2, face or 1.0))
            turn = np.multiply(-sigma, psi1, out=real[3])
    return Kinematics(theta, s, ds, d2s, d3s, f.lift_unit, alpha, psi_f, None, kappa, rho, face_pos, turn,
                      _CurvePoints((_xy(cplx[0]), None, _xy(contact), None, None, _xy(q1), _xy(q2))))


def _pitch_kappa(sigma: float, vx: np.ndarray, vy: np.ndarray, ax: np.ndarray, ay: np.ndarray, out: np.ndarray | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The pitch curve's speed ``|V|`` (mm/rad), ``|V|^2``, ``V x A``, ``|V|^3`` and signed curvature
    ``kappa = -sigma (V x A) / |V|^3`` (1/mm, into ``out``; the counter-clockwise contour runs
    against theta for a ccw cam) from the components of ``V``, ``A`` (:func:`_centre`)."""
    with np.errstate(all="ignore"):
        speed2 = vx * vx + vy * vy
        cross = vx * ay - vy * ax
        speed = np.sqrt(speed2)
        cube = speed * speed2
        kappa = np.divide(-sigma * cross, cube, out=out)
    return speed, speed2, cross, cube, kappa


def _pitch_curvature(sigma: float, vx: np.ndarray, vy: np.ndarray, ax: np.ndarray, ay: np.ndarray, bx: np.ndarray,
                     by: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The pitch curve's speed ``|V|`` (mm/rad), ``|V|^2``, ``V . A``, signed curvature ``kappa``
    (:func:`_pitch_kappa`) and ``d kappa / d theta = -sigma ((V x B) / |V|^3 - 3 (V x A)
    (V . A) / |V|^5)`` (``d|V| / d theta = V . A / |V|``) from the components of ``V``, ``A``, ``B``
    (:func:`_centre`)."""
    with np.errstate(all="ignore"):  # (the arithmetic of _pitch_kappa, written out: no second call and errstate)
        speed2 = vx * vx + vy * vy
        dot = vx * ax + vy * ay
        cross = vx * ay - vy * ax
        speed = np.sqrt(speed2)
        cube = speed * speed2
        kappa = np.divide(-sigma * cross, cube)
        kappa1 = vx * by - vy * bx
        kappa1 /= cube
        cross *= dot
        cross *= 3.0
        cube *= speed2
        cross /= cube
        kappa1 -= cross
        kappa1 *= -sigma
    return speed, speed2, dot, kappa, kappa1


@overload
def _roller(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
            full: Literal[True], want: tuple[str, ...] = ("pitch", "profile"), back: np.ndarray | None = None,
            out: np.ndarray | None = None) -> Kinematics: ...
@overload
def _roller(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
            full: Literal[False], want: tuple[str, ...] = ("pitch", "profile"), back: np.ndarray | None = None,
            out: np.ndarray | None = None) -> tuple[_Curve, ...]: ...
def _roller(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
            full: bool, want: tuple[str, ...] = ("pitch", "profile"), back: np.ndarray | None = None,
            out: np.ndarray | None = None) -> Kinematics | tuple[_Curve, ...]:
    """Roller / knife: the :class:`Kinematics` (``full``) or the (Q, dQ, d2Q) of the curves named in
    ``want`` ("pitch", "profile") in the cam frame (``back``: :func:`_to_cam` at ``theta`` when known;
    ``out``: a complex (3, n, len(want)) block to write them into, curve c in ``out[:, :, c]``).  (The
    outputs share blocks of memory and temporaries are released as soon as they are used: fresh
    memory is much of the cost.)"""
    if full:
        return _roller_kinematics(f, theta, s, ds, d2s, d3s, back)
    sigma, r = f.sigma, f.roller_radius
    cplx: list[np.ndarray | None] = [None] * 7  # rows 1-3 the pitch curve and its two derivatives, 4-6 the profile and its two
    if out is not None:
        for c, name in enumerate(want):
            first = 1 if name == "pitch" else 4
            cplx[first: first + 3] = out[0, :, c], out[1, :, c], out[2, :, c]
    (cx, cy), (vx, vy), (ax, ay), (bx, by), _, _ = _centre(f, s, ds, d2s, d3s)
    # P = R(-sigma theta) C; P' = R V, P'' = R A, P''' = R B
    back = _to_cam(f, theta) if back is None else back
    pitch, p1, p2 = _in_cam(back, cx, cy, cplx[1]), _in_cam(back, vx, vy, cplx[2]), _in_cam(back, ax, ay, cplx[3])
    del back
    if "profile" not in want:
        return ((pitch, p1, p2),)
    speed, _, _, kappa_p, kappa_p1 = _pitch_curvature(sigma, vx, vy, ax, ay, bx, by)
    del bx, by
    with np.errstate(divide="ignore", invalid="ignore"):
        k = (sigma * r) / speed  # Q = P - r n with the outward normal n = (sigma / |V|) J V (n = -J t, t = -sigma V / |V|)
    del speed, ax, ay
    # the profile from the pitch curve in the cam frame: Q = P - r n = P - i k P' (n turned with
    # the pitch tangent), Q' = P' (1 - r kappa), Q'' = P'' (1 - r kappa) - r kappa' P'
    contact = np.multiply(p1, k * -1j, out=cplx[4])
    contact += pitch
    del k
    factor = 1.0 - r * kappa_p
    kappa_p1 *= r
    q1 = np.multiply(p1, factor, out=cplx[5])
    q2 = np.multiply(p2, factor, out=cplx[6])
    q2 -= p1 * kappa_p1
    del kappa_p1
    curves = {"pitch": (pitch, p1, p2), "profile": (contact, q1, q2)}
    return tuple(curves[name] for name in want)


def _roller_kinematics(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
                       back: np.ndarray | None = None) -> Kinematics:
    """The :class:`Kinematics` of a roller or knife (:func:`_roller`'s arithmetic): the pressure
    angle and the curvatures now, the points (:class:`_CurvePoints`) on first use."""
    sigma, r, n = f.sigma, f.roller_radius, theta.size
    real = np.empty((4, n))  # pressure angle, pitch and profile curvature, profile radius of curvature
    (cx, cy), (vx, vy), (ax, ay), _, m, g = _centre(f, s, ds, d2s, None)  # (B: only the points' second derivatives)
    _, speed2, cross, cube, kappa_p = _pitch_kappa(sigma, vx, vy, ax, ay, real[1])
    measures = _PitchMeasures(cy, speed2, cross, cube, f)
    factor = 1.0 - r * kappa_p
    if m is None:  # translating: m = (0, 1), V . m = Vy, V x m = Vx
        alpha = np.arctan2(vy, np.abs(vx), out=real[0])
    else:
        alpha = np.arctan2(vx * m[0] + vy * m[1], np.abs(vx * m[1] - vy * m[0]), out=real[0])
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = np.divide(kappa_p, factor, out=real[2])  # profile: rho = rho_pitch - r
        rho = np.divide(1.0, kappa, out=real[3])
        rho[kappa == 0] = np.inf
    points = _CurvePoints(terms=(f, theta, s, ds, d2s, d3s, back, cx, cy))
    return Kinematics(theta, s, ds, d2s, d3s, f.lift_unit, alpha, g, kappa_p, kappa, rho, None, None, points, measures)


def _kinematics_from(f: FollowerSpec, theta: np.ndarray, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray,
                     back: np.ndarray | None = None) -> Kinematics:
    if f.contact == "face":
        return _flat(f, theta, s, ds, d2s, d3s, True, back)
    return _roller(f, theta, s, ds, d2s, d3s, True, back=back)


def kinematics(follower: FollowerSpec, law: Displacement, theta: object) -> Kinematics:
    """Closed-form kinematics and geometry of ``follower`` driven by ``law`` at cam angles ``theta`` (rad).

    Everything comes from ``s, s', s''`` of the law pointwise (the jerk is the law's ``s'''``):
    pressure angle, contact point, radii of curvature of the pitch curve and the profile.
    At a break where ``s''`` jumps the value is the law's own value at that angle.

    The points (follower, pitch and contact point, the curves' derivatives) of a roller or knife
    are made on first use from ``theta`` and the law's values: ``theta`` is copied, and the
    Kinematics' ``theta``, ``s`` .. ``d3s`` are read-only, so they are the points of the angles
    asked whatever the caller writes afterwards.
    """
    theta = np.array(theta, dtype=float, ndmin=1).ravel()  # (a copy: the caller keeps its array)
    theta.setflags(write=False)
    values = []
    for x in law(theta):
        v = np.asarray(x, dtype=float).ravel().view()
        v.setflags(write=False)
        values.append(v)
    return _kinematics_from(follower, theta, *values)


def contact_points(follower: FollowerSpec, law: Displacement, theta: object) -> np.ndarray:
    """The contact points on the cam profile at cam angles ``theta`` (rad): ``kinematics(follower,
    law, theta).contact_point`` (cam frame, mm, (n, 2)), the same numbers, without the pressure
    angle, the curvatures and the follower point."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float)).ravel()
    s, ds, d2s, d3s = (np.asarray(x, dtype=float).ravel() for x in law(theta))
    if follower.contact == "face":
        contact = _flat(follower, theta, s, ds, d2s, d3s, False)[0][0]
    else:  # _roller's contact point alone: Q = P - i k P' with k = sigma r / |V|
        (cx, cy), (vx, vy), _, _, _, _ = _centre(follower, s, ds, d2s, None)
        back = _to_cam(follower, theta)
        p1 = _in_cam(back, vx, vy)
        with np.errstate(all="ignore"):
            k = (follower.sigma * follower.roller_radius) / np.sqrt(vx * vx + vy * vy)
        contact = np.multiply(p1, k * -1j)
        contact += _in_cam(back, cx, cy)
    return _xy(contact)


def profile_curvature(follower: FollowerSpec, law: Displacement, theta: object) -> np.ndarray:
    """The signed curvature of the cam profile (1/mm, > 0 convex) at cam angles ``theta`` (rad):
    ``kinematics(follower, law, theta).profile_curvature``, the same numbers; for a roller or knife
    from the pitch curve's curvature alone (no rotation into the cam frame, no points, no
    pressure angle: a cheap path for a few angles, e.g. either side of the contour's joints)."""
    return profile_curvatures(follower, law, theta)[0]


def profile_curvatures(follower: FollowerSpec, law: Displacement, *thetas: object) -> tuple[np.ndarray, ...]:
    """:func:`profile_curvature` at each of the arrays of cam angles ``thetas`` (rad), the same
    numbers: the law asked at each array as that call does (its own values and kept calls), then
    a roller's or knife's curvature of them all in one elementwise pass (no matrix product, no
    reduction: each angle's value is the one it has alone), split back (one array per ``thetas``)."""
    if follower.contact == "face" or not thetas:
        return tuple(kinematics(follower, law, theta).profile_curvature for theta in thetas)
    values = [[np.asarray(x, dtype=float).ravel() for x in law(np.atleast_1d(np.asarray(theta, dtype=float)).ravel())]
              for theta in thetas]
    s, ds, d2s, d3s = values[0] if len(values) == 1 else (np.concatenate(column) for column in zip(*values))
    _, (vx, vy), (ax, ay), _, _, _ = _centre(follower, s, ds, d2s, None)
    kappa_p = _pitch_kappa(follower.sigma, vx, vy, ax, ay)[4]
    factor = 1.0 - follower.roller_radius * kappa_p
    with np.errstate(divide="ignore", invalid="ignore"):
        curvature = np.divide(kappa_p, factor)  # as in _roller: the profile's rho = rho_pitch - r
    if len(values) == 1:
        return (curvature,)
    out, at = [], 0
    for v in values:  # np.split's views: each array's slice
        out.append(curvature[at: at + v[0].size])
        at += v[0].size
    return tuple(out)


# --------------------------------------------------------------------------------------------
# Undercut / validity
# --------------------------------------------------------------------------------------------
def profile_failures(f: FollowerSpec, k: Kinematics) -> list[tuple[str, np.ndarray]]:
    """(reason, mask) pairs of the conditions that make the profile impossible."""
    if f.contact == "face":
        assert k.normal_turn_rate is not None  # a flat face's Kinematics carry its normal's turn rate
        return _flat_failures(f, k.s, k.normal_turn_rate, k.profile_radius)
    if k.pitch_measures is not None and (k.pitch_measures.follower is f or k.pitch_measures.follower == f):
        return _measured_failures(f, k.pitch_measures)
    return _pitch_failures(f, k.s, k.ds, k.d2s)


def _flat_failures(f: FollowerSpec, s: np.ndarray, turn_rate: np.ndarray, radius: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """:func:`profile_failures` of a flat face from the lift ``s``, the face normal's turn rate and
    the envelope's radius of curvature (mm)."""
    out = []
    if f.motion == "translating":
        out.append(("the face passes through the rotation axis (base_radius + s <= 0)", f.base_radius + s <= 0))
    out.append(("the face normal turns backwards seen from the cam (1 - sigma tau phi' <= 0)", ~(turn_rate > 0)))
    out.append(("undercut: the envelope's radius of curvature h + h'' <= 0", ~(radius > 0) & (turn_rate > 0)))
    return out


_AXIS_REASON = "the follower passes through the rotation axis (sqrt(Rp^2 - e^2) + s <= 0)"
_CUSP_REASON = "cusp: the pitch curve stops (zero relative velocity)"


def _undercut_reason(f: FollowerSpec) -> str:
    return f"undercut: convex radius of curvature of the pitch curve <= roller radius {f.roller_radius:g} mm"


def _pitch_failures(f: FollowerSpec, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray) -> list[tuple[str, np.ndarray]]:
    """:func:`profile_failures` of a roller or knife from the law's displacement and its first two
    derivatives, by the arithmetic of :func:`_roller` without the speed and curvature arrays (no
    rotation into the cam frame, no profile, no division): the follower at or through the axis
    (translating: ``sqrt(Rp^2 - e^2) + s <= 0``), the cusp ``|V| <= 1e-12 scale`` (tested as
    ``|V|^2``; ``scale = max(1 mm, Rp)``) and the undercut ``r kappa >= 1`` of a roller (tested as
    ``-sigma r (V x A) >= |V|^3``, ``kappa = -sigma (V x A) / |V|^3`` the pitch curve's curvature)."""
    (_, cy), (vx, vy), (ax, ay), _, _, _ = _centre(f, s, ds, d2s, None)
    with np.errstate(over="ignore", invalid="ignore"):
        speed2 = vx * vx
        speed2 += vy * vy
        cross = cube = None
        if f.has_radius:
            cross = vx * ay
            cross -= vy * ax
            cube = np.sqrt(speed2)
            cube *= speed2
    return _measured_failures(f, _PitchMeasures(cy, speed2, cross, cube, f))


class _PitchMeasures(NamedTuple):
    """What :func:`_pitch_failures` tests of a roller or knife (fixed frame, (n,) arrays): the
    follower height ``cy`` (:func:`_centre`), ``|V|^2``; ``V x A`` and ``|V|^3`` (a roller's; None
    when not made), and the follower they are of (:func:`profile_failures` uses them for that
    follower only)."""

    cy: np.ndarray
    speed2: np.ndarray
    cross: np.ndarray | None
    cube: np.ndarray | None
    follower: FollowerSpec


#: Relative margin below 1 of a roller's largest ``r kappa`` on the check grid within which
#: :func:`failing_conditions` compares every sample for the undercut (the rounding of ``kappa``
#: and of ``r (V x A)`` is a few units in the last place, 2.2e-16 each).
UNDERCUT_SCREEN_MARGIN = 1e-12


def failing_conditions(f: FollowerSpec, k: Kinematics, top: float | None = None) -> list[tuple[str, np.ndarray]]:
    """The (reason, mask) pairs of :func:`profile_failures` whose mask has a failing sample, in
    its order, the same masks; a roller's or knife's conditions first by one reduction each
    (the least follower height and ``|V|^2``, a roller's largest pitch curvature ``top`` (1/mm:
    ``k.pitch_curvature.max()``, passed when the caller has it): no sample fails where the least
    height is > 0, the least ``|V|^2`` beyond the cusp limit, and ``r top <= 1 -``
    :data:`UNDERCUT_SCREEN_MARGIN` with every ``|V|^3`` finite (``kappa = -sigma (V x A) / |V|^3``
    below ``1 / r`` by more than its rounding: ``r (V x A) (-sigma) < |V|^3``); a NaN makes the
    reduction NaN: every sample is then compared, as otherwise."""
    m = k.pitch_measures
    if f.contact == "face" or m is None or not (m.follower is f or m.follower == f):  # (measures of another follower: not its answer)
        return [(reason, mask) for reason, mask in profile_failures(f, k) if mask.any()]
    out = []
    if f.motion == "translating" and not float(m.cy.min()) > 0:
        out.append((_AXIS_REASON, m.cy <= 0))
    scale = max(1.0, f.prime_radius)
    with np.errstate(over="ignore", invalid="ignore"):
        if not float(m.speed2.min()) > (1e-12 * scale) ** 2:
            out.append((_CUSP_REASON, ~(m.speed2 > (1e-12 * scale) ** 2)))
        if f.has_radius:
            assert m.cross is not None and m.cube is not None and k.pitch_curvature is not None  # made for a roller
            top = float(k.pitch_curvature.max()) if top is None else top
            if not (f.roller_radius * top <= 1.0 - UNDERCUT_SCREEN_MARGIN and math.isfinite(float(m.cube.max()))):
                cross = m.cross * (-f.sigma * f.roller_radius)
                cube = np.maximum(m.cube, np.finfo(float).tiny)  # r kappa is NaN (not >= 1) where |V| = 0: a cusp
                out.append((_undercut_reason(f), cross >= cube))
    return [(reason, mask) for reason, mask in out if mask.any()]


def _measured_failures(f: FollowerSpec, m: _PitchMeasures) -> list[tuple[str, np.ndarray]]:
    """:func:`_pitch_failures` from its :class:`_PitchMeasures` (not changed)."""
    out = []
    if f.motion == "translating":
        out.append((_AXIS_REASON, m.cy <= 0))
    scale = max(1.0, f.prime_radius)
    with np.errstate(over="ignore", invalid="ignore"):
        out.append((_CUSP_REASON, ~(m.speed2 > (1e-12 * scale) ** 2)))
        if f.has_radius:
            assert m.cross is not None and m.cube is not None  # made for a roller
            cross = m.cross * (-f.sigma * f.roller_radius)
            cube = np.maximum(m.cube, np.finfo(float).tiny)  # r kappa is NaN (not >= 1) where |V| = 0: a cusp
            out.append((_undercut_reason(f), cross >= cube))
    return out


#: Screening of a roller or knife cam on the coarse grid (:func:`_pitch_clear`): the largest
#: ``r kappa`` (1 at an undercut) it passes, and the least ``|V| / scale`` and ``(Rp' + s) / scale``
#: (``scale = max(1 mm, Rp)``; 0 at a cusp and at the axis).
SCREEN_UNDERCUT = 0.9
SCREEN_CLEARANCE = 1e-3
#: Largest rise of a cubic between two samples ``h`` apart above the larger of its end values, per
#: unit of ``h max|slope|`` at the ends: ``p(t) = m0 t (1 - t)^2 - m1 t^2 (1 - t)`` on [0, 1] peaks at
#: ``4/27 (|m0| + |m1|) <= 8/27`` of ``max(|m0|, |m1|)``; rounded up.
_CUBIC_RISE = 0.3


class _PitchTerms(NamedTuple):
    """The roller-centre motion relative to the cam at some cam angles (fixed frame, (n,) arrays):
    the follower height ``cy`` (translating) and the law's ``s'``; ``V``, ``A`` (:func:`_centre`),
    ``|V|^2``, ``V . A``; roller only (else None): ``(r kappa, r d kappa / d theta)`` of the
    pitch curve (:func:`_pitch_curvature`)."""

    cy: np.ndarray
    ds: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    ax: np.ndarray
    ay: np.ndarray
    speed2: np.ndarray
    dot: np.ndarray
    roller: tuple[np.ndarray, np.ndarray] | None


def _pitch_terms(f: FollowerSpec, s: np.ndarray, ds: np.ndarray, d2s: np.ndarray, d3s: np.ndarray) -> _PitchTerms:
    """:class:`_PitchTerms` of a roller or knife from the law's displacement and its three derivatives."""
    (_, cy), (vx, vy), (ax, ay), (bx, by), _, _ = _centre(f, s, ds, d2s, d3s)
    _, speed2, dot, kappa, kappa1 = _pitch_curvature(f.sigma, vx, vy, ax, ay, bx, by)
    roller = None
    if f.has_radius:
        roller = f.roller_radius * kappa, f.roller_radius * kappa1
    return _PitchTerms(cy, ds, vx, vy, ax, ay, speed2, dot, roller)


def _pitch_clear(f: FollowerSpec, terms: _PitchTerms, spacing: float) -> bool:
    """Whether a roller or knife cam is clear of every limit of :func:`_pitch_failures` by a margin,
    from its :class:`_PitchTerms` at the coarse grid (samples at most ``spacing`` rad apart, the
    breaks and their one-sided neighbours included): every quantity checked is extrapolated from
    its extreme sample by its largest slope over the grid (``_CUBIC_RISE spacing max|slope|``: the
    reach of a cubic between two samples) and must stay inside :data:`SCREEN_UNDERCUT` and
    :data:`SCREEN_CLEARANCE`.  True: no limit is near, the dense check can be skipped; False: the
    dense check decides (it gives the failed ranges).  The quantities and their slopes: ``r kappa``
    and ``r d kappa / d theta``, ``|V|^2`` and ``2 V . A``, the follower height ``Rp' + s`` and ``s'``."""
    t = terms
    scale = max(1.0, f.prime_radius)
    reach = _CUBIC_RISE * spacing
    # (a NaN anywhere makes its comparison False: not clear)
    if f.motion == "translating" and not float(t.cy.min()) - reach * float(np.abs(t.ds).max()) > SCREEN_CLEARANCE * scale:
        return False
    low = float(t.speed2.min()) - reach * 2.0 * float(np.abs(t.dot).max())
    if not low > (SCREEN_CLEARANCE * scale) ** 2:
        return False
    if t.roller is None:
        return True
    r_kappa, r_slope = t.roller
    high = float(r_kappa.max()) + reach * float(np.abs(r_slope).max())
    return high <= SCREEN_UNDERCUT


def _pitch_second_derivatives(f: FollowerSpec, theta: np.ndarray, terms: _PitchTerms, want: Sequence[str]) -> np.ndarray:
    """``d2Q/dtheta2`` (cam frame, complex (len(want), n)) of the curves named in ``want`` ("pitch",
    "profile") at the cam angles ``theta`` (n,), from the :class:`_PitchTerms` there (their first n
    values): the pitch curve's ``R A`` and the profile's ``R (A (1 - r kappa) - r kappa' V)``
    (:func:`_roller`; a knife's profile is its pitch curve)."""
    n = theta.size
    back = _kept_rotation_to_cam(f.sigma, np.ascontiguousarray(theta, dtype=float).tobytes())
    vx, vy, ax, ay = terms.vx[:n], terms.vy[:n], terms.ax[:n], terms.ay[:n]
    out = np.empty((len(want), n), dtype=complex)
    for row, name in zip(out, want):
        if name == "pitch" or terms.roller is None:
            _in_cam(back, ax, ay, row)
        else:
            factor = 1.0 - terms.roller[0][:n]
            slope = terms.roller[1][:n]
            _in_cam(back, ax * factor - slope * vx, ay * factor - slope * vy, row)
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


#: Check grids whose order and rotations are kept (:func:`_added_angles`, :func:`_grid_order`,
#: :func:`_sorted_grid_to_cam`): a sweep's designs share one or two grids (the grid follows the law's breaks only).
_GRID_CACHE_SIZE = 8


def _read_only(a: np.ndarray) -> np.ndarray:
    """``a``, made read-only (an array kept across designs)."""
    a.setflags(write=False)
    return a


def check_grid(law: Displacement, check_step: float = DEFAULT_CHECK_STEP) -> np.ndarray:
    """Sorted cam angles (rad, one turn) for dense checks: a uniform grid of ``check_step`` plus
    every break and both one-sided neighbours of it (1e-9 rad away)."""
    n, added = _grid_layout(law, check_step)
    return _insert_added(np.arange(n) * (TWO_PI / n), added)


def _grid_layout(law: Displacement, check_step: float) -> tuple[int, np.ndarray]:
    """How the check grid of :func:`check_grid` is made: the size ``n`` of its uniform part (the
    angles ``k 2 pi / n``) and the sorted angles added to it (the breaks and their one-sided
    neighbours that are not on the uniform grid already)."""
    require_positive("check_step", check_step, "rad")
    n = max(8, math.ceil(TWO_PI / check_step))
    return n, _added_angles(tuple(np.asarray(getattr(law, "breaks", np.zeros(0)), dtype=float).tolist()), n)


@lru_cache(maxsize=_GRID_CACHE_SIZE)
def _added_angles(brk: tuple[float, ...], n: int) -> np.ndarray:
    """The sorted angles :func:`_grid_layout` adds to the uniform grid of ``n`` angles for the
    breaks ``brk`` (rad), read-only (kept across designs: a sweep's designs share their breaks)."""
    if not brk:
        return _read_only(np.zeros(0))
    # a few angles, as Python floats (Python's % is np.mod)
    extra = sorted({(b + d) % TWO_PI for b in brk for d in (0.0, -1e-9, 1e-9)})
    d = TWO_PI / n
    # an angle on the grid is k 2 pi / n exactly for its nearest index k
    return _read_only(np.array([a for a in extra if round(a / d) * d != a or round(a / d) == n]))


def _insert_added(uniform: np.ndarray, added: np.ndarray, added_values: np.ndarray | None = None) -> np.ndarray:
    """Values on the sorted check grid from those on its uniform part (n,) (angles ``k 2 pi / n``)
    and at the ``added`` angles (sorted; ``added_values``: the values there, default the angles)."""
    if not added.size:
        return uniform
    n = uniform.size
    at = np.searchsorted(np.arange(n) * (TWO_PI / n), added)
    return np.insert(uniform, at, added if added_values is None else added_values)


def _law_on_grid(law: Displacement, n: int, added: np.ndarray) -> _LawValues:
    """``law`` (the displacement and its three derivatives) at the angles of the check grid in
    :class:`CheckGrid` order: the uniform part ``k 2 pi / n`` (k = 0 .. n - 1), then the ``added``
    angles; from the law's ``on_uniform_grid`` when it has one (a motion program: its sines and
    cosines by angle addition)."""
    uniform = getattr(law, "on_uniform_grid", None)
    if uniform is not None:
        s, ds, d2s, d3s = uniform(n, added)
        return s, ds, d2s, d3s
    theta = np.concatenate([np.arange(n) * (TWO_PI / n), added])
    s, ds, d2s, d3s = (np.asarray(x, dtype=float).ravel() for x in law(theta))
    return s, ds, d2s, d3s


#: Length of the short table of unit phasors of a uniform grid (:func:`_sorted_grid_to_cam`).
_PHASOR_BLOCK = 128


def _rows_of(values: _LawValues) -> np.ndarray | None:
    """The (4, n) float block whose rows 0 .. 3 are ``values`` in turn (a motion program's
    :meth:`~camgen.synthesis.laws.MotionProgram.on_uniform_grid` returns the rows of one block),
    else None: :attr:`CheckGrid.values` sorts the block in one ``take`` instead of stacking first."""
    base = values[0].base
    if not isinstance(base, np.ndarray) or base.dtype != np.float64 or base.shape != (4, values[0].size) \
            or not base.flags.c_contiguous:
        return None
    start, step = base.__array_interface__["data"][0], base.strides[0]
    for k, v in enumerate(values):
        if v.base is not base or v.ndim != 1 or v.strides[0] != base.strides[1] \
                or v.__array_interface__["data"][0] != start + k * step:
            return None
    return base


@lru_cache(maxsize=_GRID_CACHE_SIZE)
def _kept_rotation_to_cam(sigma: float, angles: bytes) -> np.ndarray:
    """:func:`_rotation_to_cam` at the cam angles ``angles`` (float64 bytes), read-only (kept
    across designs: the coarse grid and the spline's knots and probes stay while the law's breaks
    and the piece counts do)."""
    return _read_only(_rotation_to_cam(sigma, np.frombuffer(angles, dtype=float)))


@lru_cache(maxsize=_GRID_CACHE_SIZE)
def _grid_order(n: int, added: bytes) -> tuple[np.ndarray, np.ndarray]:
    """The sorted check grid of :class:`CheckGrid` (``n`` uniform angles ``k 2 pi / n``, the sorted
    ``added`` angles as float64 bytes) and its order: ``theta = grid[order]`` with ``grid`` the
    angles in the grid's own order (uniform part, then the added ones), as :func:`_insert_added`
    places them.  Both read-only (kept across designs: a pure function of its arguments)."""
    extra = np.frombuffer(added, dtype=float)
    order = _insert_added(np.arange(n), extra, np.arange(n, n + extra.size))
    return _read_only(_insert_added(np.arange(n) * (TWO_PI / n), extra)), _read_only(order)


@lru_cache(maxsize=_GRID_CACHE_SIZE)
def _sorted_grid_to_cam(sigma: float, n: int, added: bytes) -> np.ndarray:
    """:func:`_to_cam` of a cam turning in the direction ``sigma`` on the check grid (``n`` uniform
    angles ``k d``, ``d = 2 pi / n``, and the sorted ``added`` angles as float64 bytes), in the order
    of the sorted grid (``theta`` of :class:`CheckGrid`), read-only (kept across designs): on the
    uniform part ``exp(-i sigma k d)`` as the products ``exp(-i sigma B j d) exp(-i sigma l d)``
    (``k = B j + l``) of two short tables (angle addition: within a few ulps of the cosine and sine
    of the grid angles), at the added angles directly."""
    extra = np.frombuffer(added, dtype=float)
    d = TWO_PI / n
    rows = -(-n // _PHASOR_BLOCK)
    big = _rotation_to_cam(sigma, np.arange(rows) * (_PHASOR_BLOCK * d))
    small = _rotation_to_cam(sigma, np.arange(_PHASOR_BLOCK) * d)
    out = np.empty(n + extra.size, dtype=complex)
    out[:n] = np.multiply.outer(big, small).ravel()[:n]
    out[n:] = _rotation_to_cam(sigma, extra)
    return _read_only(out[_grid_order(n, added)[1]] if extra.size else out)


# --------------------------------------------------------------------------------------------
# The spline representation
# --------------------------------------------------------------------------------------------
_PROBES = np.array([0.25, 0.5, 0.75])
#: Rows ``s^0 .. s^5`` at the probes and at the piece end ``s = 1``: the quintic pieces there from
#: their scaled coefficients (:func:`camgen.contour.quintic_hermite_scaled`) in one product.
_PROBE_POWERS = np.append(_PROBES, 1.0)[:, None] ** np.arange(6.0)
#: Error constant of the first piece count: a quintic Hermite interpolant (values, first and
#: second derivatives at both ends of a piece of length ``h``) is within
#: ``max|f^(6)| / 6! max|(t - a)^3 (t - b)^3| = h^6 max|f^(6)| / 46080`` of ``f`` (the Hermite
#: interpolation remainder, e.g. Stoer & Bulirsch, *Introduction to Numerical Analysis*, thm. 2.1.5.9).
_SPLINE_ERROR_CONSTANT = 1.0 / 46080.0
#: Share of ``fit_tol`` the first piece count aims at (the sixth derivative is estimated from
#: differences: a margin so that one round is enough).
_FIRST_COUNT_SHARE = 0.8


def _uniform_knots(lo: np.ndarray, hi: np.ndarray, count: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Knots of several segments, concatenated: segment k has ``count[k]`` uniform pieces on
    ``[lo[k], hi[k]]`` (what ``np.linspace(lo, hi, count + 1)`` computes, its last knot ``hi``
    exactly).  Returns the knots (sum(count + 1),), the index of every segment's first knot and of its last."""
    n_t = count + 1
    seg = np.repeat(np.arange(count.size), n_t)
    first = np.concatenate([[0], np.cumsum(n_t)[:-1]])
    j = np.arange(int(n_t.sum())) - first[seg]
    x = j * ((hi - lo) / count)[seg] + lo[seg]
    last = first + count
    x[last] = hi
    return x, first, last


def _breaks_of(law: Displacement) -> tuple[np.ndarray, np.ndarray]:
    brk = np.mod(np.asarray(getattr(law, "breaks", np.zeros(0)), dtype=float), TWO_PI)
    cont = np.asarray(getattr(law, "break_continuity", np.full(brk.size, 2)), dtype=int)
    if brk.shape != cont.shape:
        raise ParameterError("break_continuity", f"{cont.size} values", f"one per break ({brk.size})")
    return brk, cont


#: Spacing (rad) of the coarse grid: the cam angles of the sixth-derivative estimate
#: (:func:`_sixth_derivatives`) and of the screening of a roller or knife cam (:func:`_pitch_clear`).
BOUND_SPACING = math.radians(1.0)


def _sixth_derivatives(theta: np.ndarray, d2: np.ndarray, brk: np.ndarray) -> np.ndarray:
    """Largest ``|d6Q/dtheta6|`` (mm/rad^6) of the curves whose exact ``d2Q/dtheta2`` (complex
    ``x + i y``, (curves, n)) are given at the uniformly spaced, increasing cam angles ``theta`` (n,)
    (the uniform part of the coarse grid, :data:`BOUND_SPACING`), per interval between the sorted
    breaks ``brk`` (interval k from ``brk[k]`` to the next break, the last one round to the first;
    one interval when there are none): fourth differences of ``d2Q`` over five consecutive angles
    (a window) that no break splits (the law is analytic inside an interval; a break on the first
    angle of a window belongs to the interval it starts), divided by the spacing^4.  An interval
    that holds no whole window (breaks closer than the windows) takes the value of the window at its
    start (its neighbour's; the fit measures what that count gives)."""
    worst = np.abs(np.diff(d2, 4, axis=1)).max(axis=0)
    worst *= (theta[1] - theta[0]) ** -4
    if not brk.size:
        return worst.max(initial=0.0, keepdims=True)
    whole, start, before = _break_windows(np.asarray(theta, dtype=float).tobytes(), np.asarray(brk, dtype=float).tobytes())
    worst *= whole
    out = np.maximum.reduceat(worst, start)
    if before > 0:
        out[-1] = max(out[-1], worst[:before].max())
    return out


@lru_cache(maxsize=_GRID_CACHE_SIZE)
def _break_windows(theta: bytes, brk: bytes) -> tuple[np.ndarray, np.ndarray, int]:
    """How :func:`_sixth_derivatives` splits the windows of five consecutive cam angles ``theta``
    (increasing, float64 bytes) by the sorted breaks ``brk`` (float64 bytes, at least one): whether
    each window lies inside one interval (bool, read-only), the index of the first window of every
    interval (the reduceat indices, read-only) and the number of windows before the first break
    (they belong to the last interval).  Kept across designs (a sweep's designs share their breaks
    and the coarse grid)."""
    at, b = np.frombuffer(theta, dtype=float), np.frombuffer(brk, dtype=float)
    # window i (angles i .. i + 4) is split iff the number of breaks <= theta differs at its ends
    below = np.searchsorted(b, at, side="right")
    whole = below[:-4] == below[4:]
    # interval k holds the windows from the first angle >= brk[k] on; the last one also those before brk[0]
    start = np.searchsorted(at, b, side="left")
    return _read_only(whole), _read_only(np.minimum(start, at.size - 5)), int(start[0])


#: rad: law breaks closer than this are fitted as one joint (a constant-velocity blend of 0.5 less
#: an ulp leaves a middle piece of 4e-16 rad, too short for a spline knot).
BREAK_MERGE = 1e-12
#: Weights of the one-sided extrapolation of the derivatives at a break from 1, 2, 3 steps away
#: (quadratic, error O(step^3)), and those steps (rad of cam angle).
_ONE_SIDED_WEIGHTS = np.array([3.0, -3.0, 1.0])
_ONE_SIDED_STEPS = _ONE_SIDED_STEP * np.array([1.0, 2.0, 3.0])


@lru_cache(maxsize=_GRID_CACHE_SIZE)
def _segments_of(brk: tuple[float, ...], sigma: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The spline segments of :func:`_spline_contours` for a law with the breaks ``brk`` (rad, in
    [0, 2 pi)) and a cam turning in the direction ``sigma``: the sorted distinct breaks, every
    segment's start ``lo`` and end ``hi`` in t = -sigma theta (breaks closer than
    :data:`BREAK_MERGE` one joint; one segment from 0 without breaks), ``hi - lo``, and the law
    interval (:func:`_sixth_derivatives`' index) holding every segment's middle.  Read-only (kept
    across designs: a sweep's designs share their breaks)."""
    sorted_brk = sorted(set(brk))
    tb: list[float] = []
    for t in sorted({(-sigma * b) % TWO_PI for b in sorted_brk}) or [0.0]:
        if not tb or t - tb[-1] > BREAK_MERGE:  # breaks closer than rounding are one joint
            tb.append(t)
    if len(tb) > 1 and tb[0] + TWO_PI - tb[-1] <= BREAK_MERGE:
        tb.pop()
    lo, hi = np.array(tb), np.array(tb[1:] + [tb[0] + TWO_PI])
    # the law interval of every segment (t = -sigma theta): the one holding its middle (one interval without breaks)
    mid = np.mod(-sigma * 0.5 * (lo + hi), TWO_PI)
    interval = (np.searchsorted(sorted_brk, mid, side="right") - 1) % max(1, len(sorted_brk))
    return (_read_only(np.array(sorted_brk, dtype=float)), _read_only(lo), _read_only(hi), _read_only(hi - lo),
            _read_only(interval))


@lru_cache(maxsize=_GRID_CACHE_SIZE)
def _round_angles(lo: tuple[float, ...], hi: tuple[float, ...], count: tuple[int, ...], sigma: float, lead: bool
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """The knots and cam angles of a round of :func:`_spline_contours` for the segments ``[lo[k],
    hi[k]]`` (t = -sigma theta) of ``count[k]`` uniform pieces each: the knots and the indices of
    every segment's first and last knot (:func:`_uniform_knots`), the pieces' spans (1 from one
    segment's end to the next one's start), and the cam angles ``-sigma t`` of (``lead``: the
    one-sided steps inside every segment's two ends, :data:`_ONE_SIDED_STEPS`, then) the knots and
    the probes of every piece.  None when a span is not > 0 (breaks too close for knots).
    Read-only (kept across designs: a sweep's designs share their breaks and mostly their piece counts)."""
    lo_a, hi_a = np.array(lo), np.array(hi)
    x, first, last = _uniform_knots(lo_a, hi_a, np.array(count))
    span = x[1:] - x[:-1]
    span[last[:-1]] = 1.0  # from one segment's end to the next one's start (the same angle)
    if not (span > 0.0).all():
        return None
    probes = x[:-1, None] + _PROBES * span[:, None]  # (knots - 1, 3)
    parts = [x, probes.ravel()]
    if lead:
        parts.insert(0, (np.stack([lo_a, hi_a])[:, :, None] + np.array([1.0, -1.0])[:, None, None] * _ONE_SIDED_STEPS).ravel())
    angles = -sigma * np.concatenate(parts)
    return _read_only(x), _read_only(first), _read_only(last), _read_only(span), _read_only(angles)


def _spline_contours(exact: Callable, dims: int, sigma: float, law: Displacement, fit_tol: float,
                     bound: tuple[np.ndarray, np.ndarray] | None = None, initial_step: float = math.radians(5.0),
                     max_rounds: int = 12, max_pieces: int = 100_000) -> tuple[list[Contour], list[float]]:
    """Contours of ``dims`` exact curves at once, one quintic spline segment per interval between
    the law's breaks (one segment from cam angle 0 when there are none); the curves share their knots.
    ``exact(theta)`` -> ``(Q, dQ/dtheta, d2Q/dtheta2)`` at the cam angles ``theta``, each complex
    (n, dims) (the curves side by side).

    The spline parameter is ``t = -sigma theta`` (the contour runs counter-clockwise).  Every
    segment has ``count`` uniform pieces, each the quintic Hermite interpolant of the exact curve's
    point, tangent and second derivative at both its ends (:meth:`camgen.contour.Spline.hermite5`):
    C2 inside the segment, and at the segment's ends the exact one-sided tangent and second
    derivative, so neighbours join with the exact curve's own continuity: G2 where the law's
    ``s''`` is continuous, G1 (the exact curvature jump) where it jumps, G0 where ``s'`` jumps.  The
    first count follows from the error bound ``h^6 max|Q^(6)| / 46080`` with ``Q^(6)`` from
    ``bound = (theta, d2Q/dtheta2 of the curves, complex (dims, n))`` (:func:`_sixth_derivatives`;
    else one piece per ``initial_step``); a segment gets more pieces (its error falls as h^6) until the distance of
    every curve from its exact points at the quarter and mid points of every piece is <= ``fit_tol``
    mm.  The exact curves are evaluated for all segments in one call per round.
    Returns the contours and the largest measured distance of each.
    """
    brk, _ = _breaks_of(law)
    sorted_brk, lo, hi, width, interval = _segments_of(tuple(brk.tolist()), sigma)
    nseg = lo.size
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if bound is None:
            want = width / initial_step
        else:
            sixth = _sixth_derivatives(bound[0], bound[1], sorted_brk)
            sixth = sixth[interval]
            want = width * (_SPLINE_ERROR_CONSTANT * sixth / (_FIRST_COUNT_SHARE * fit_tol)) ** (1.0 / 6.0)
            want = np.where(np.isfinite(want), want, width / initial_step)  # no usable bound: one piece per initial_step
        count = np.ceil(want.clip(2, max_pieces)).astype(int)

    # one-sided dQ/dt and d2Q/dt2 at every segment's two ends, evaluated with the first round
    ends: tuple[np.ndarray, np.ndarray] | None = None  # (dQ/dt, d2Q/dt2): (2 [start, end], nseg, dims) complex each
    fits: list[tuple[np.ndarray, np.ndarray] | None] = [None] * nseg
    errors = np.zeros((nseg, dims))
    # per segment and curve: its start and end point and its Green area (the contours' closure and
    # orientation, checked for all curves at once when every segment is made)
    seg_start = np.zeros((nseg, dims), dtype=complex)
    seg_end = np.zeros((nseg, dims), dtype=complex)
    seg_area = np.zeros((nseg, dims))
    todo = np.arange(nseg)
    for _ in range(max_rounds):
        layout = _round_angles(tuple(lo[todo].tolist()), tuple(hi[todo].tolist()), tuple(count[todo].tolist()), sigma, ends is None)
        if layout is None:
            raise GeometryError(f"the law's breaks are too close for spline knots between them (fit_tol {fit_tol:g} mm)")
        x, first, last, span, angles = layout
        nlead = 0 if ends is not None else 6 * nseg  # (the first round: todo is every segment)
        q, q1, q2 = exact(angles)
        q1 *= -sigma  # d/dt = -sigma d/dtheta
        if ends is None:  # quadratic extrapolation from 1, 2, 3 steps inside the segment
            lead1 = _ONE_SIDED_WEIGHTS @ q1[:nlead].reshape(2 * nseg, 3, dims).transpose(1, 0, 2).reshape(3, -1)
            lead2 = _ONE_SIDED_WEIGHTS @ q2[:nlead].reshape(2 * nseg, 3, dims).transpose(1, 0, 2).reshape(3, -1)
            ends = lead1.reshape(2, nseg, dims), lead2.reshape(2, nseg, dims)
        ends1, ends2 = ends
        knots = slice(nlead, nlead + x.size)
        qk, q1k, q2k = q[knots], q1[knots], q2[knots]
        q1k[first], q2k[first] = ends1[0, todo], ends2[0, todo]
        q1k[last], q2k[last] = ends1[1, todo], ends2[1, todo]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # the pieces between two segments are meaningless
            # (6, pieces, dims) complex: each piece in s = (t - x_i) / h_i on [0, 1], lowest power first
            scaled = quintic_hermite_scaled(quintic_hermite_data(qk, q1k, q2k, span))
            # the splines at the probes (rows 0-2) and at the end of every piece (row 3)
            at = (_PROBE_POWERS @ scaled.reshape(6, -1)).reshape(_PROBE_POWERS.shape[0], -1, dims)
            dist = np.abs(at[:-1] - q[nlead + x.size:].reshape(-1, _PROBES.size, dims).transpose(1, 0, 2)).max(axis=0)  # (pieces, dims)
            area = piece_green_areas(scaled)  # (pieces, dims)
        dist[last[:-1]] = 0.0  # between two segments (meaningless there)
        err = np.maximum.reduceat(dist, first, axis=0)
        errors[todo] = err
        worst = err.max(axis=1)
        coeffs = np.ascontiguousarray(power_coefficients(scaled, span).transpose(2, 0, 1))  # (dims, 6, pieces): in t, highest power first
        for j, k in enumerate(todo.tolist()):
            fits[k] = (x[first[j]: last[j] + 1], coeffs[:, :, first[j]: last[j]])
        seg_start[todo], seg_end[todo] = qk[first], at[-1, last - 1]
        area[last[:-1]] = 0.0
        seg_area[todo] = np.add.reduceat(area, first, axis=0)
        bad = worst > fit_tol
        if not bad.any():
            todo = todo[:0]
            break
        for j in np.flatnonzero(bad).tolist():
            k = int(todo[j])
            if count[k] >= max_pieces:
                raise _fit_failure(fit_tol, float(worst[j]), int(count[k]))
            count[k] = min(max_pieces, math.ceil(count[k] * min(16.0, max(1.25, (float(worst[j]) / (0.5 * fit_tol)) ** (1.0 / 6.0)))))
        todo = todo[bad]
    if todo.size:
        raise _fit_failure(fit_tol, float(errors[todo].max()), int(count[todo].max()))
    if not np.isfinite(errors).all():  # a NaN coefficient gives a NaN distance at its probes
        raise GeometryError("the exact curve is not finite at some spline knots or probes (a cusp the checks did not see)")
    closed = (np.abs(seg_end - np.concatenate([seg_start[1:], seg_start[:1]])) <= DEFAULT_CLOSURE_TOL).all(axis=0)
    area = seg_area.sum(axis=0)
    made = [fit for fit in fits if fit is not None]
    assert len(made) == nseg  # every segment is fitted once none is left to do
    contours = []
    for c in range(dims):  # the knots increase (uniform in each segment) and the distances are finite
        # coefficients (6, pieces) complex of curve c -> (6, pieces, 2) float (a view where the fit's block allows it)
        segments = [Spline._checked_by_caller(x, coeffs[c].view(np.float64).reshape(6, -1, 2)) for x, coeffs in made]
        # closed and counter-clockwise: checked above; else the constructor raises the message naming the failure
        contours.append(Contour._checked_by_caller(segments, float(area[c])) if closed[c] and area[c] > 0.0 else Contour(segments))
    return contours, [float(v) for v in errors.max(axis=0)]


# --------------------------------------------------------------------------------------------
# The cam
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CheckGrid:
    """The dense check grid of a cam (:func:`check_grid`) and the law's values on it.

    The law's values are made on first use (a roller or knife cam that the coarse screening of
    :func:`_pitch_clear` finds clear of every limit never needs them) and kept in the order they
    are made: the uniform grid ``k 2 pi / n`` (k = 0 .. n - 1) first, then the ``added`` angles
    (the breaks and their one-sided neighbours); the sorted grid and the values on it (``theta``,
    ``s``, ...) are made from them on first use.

    Attributes
    ----------
    law : the :class:`Displacement`.
    uniform_size : size ``n`` of the uniform grid ``k 2 pi / n``.
    added : the sorted angles added to the uniform grid (breaks and their neighbours), rad.
    raw : the law's displacement and its three derivatives (mm or rad of swing, per rad^k) at the
        uniform grid, then at ``added`` ((n + added.size,) each).
    theta : sorted cam angles, rad (one turn).
    added_at : positions of the added angles in ``theta``.
    values : ``(s, ds, d2s, d3s)``, the law's displacement and its derivatives at ``theta``
        (also as the attributes ``s``, ``ds``, ``d2s``, ``d3s``).
    """

    law: Displacement
    uniform_size: int
    added: np.ndarray

    @cached_property
    def raw(self) -> _LawValues:
        return _law_on_grid(self.law, self.uniform_size, self.added)

    @cached_property
    def _layout(self) -> tuple[np.ndarray, np.ndarray]:
        """(``theta``, the order taking the grid's own order to ``theta``): :func:`_grid_order`."""
        return _grid_order(self.uniform_size, self.added.tobytes())

    def sorted(self, values: np.ndarray) -> np.ndarray:
        """``values`` given in the grid's own order (uniform part, then the added angles) in the
        order of ``theta`` (``values`` itself when no angle is added)."""
        return values.take(self._layout[1]) if self.added.size else values

    @property
    def theta(self) -> np.ndarray:
        """The sorted cam angles, rad (read-only)."""
        return self._layout[0]

    @cached_property
    def added_at(self) -> np.ndarray:
        return np.searchsorted(self.theta, self.added)

    @cached_property
    def values(self) -> _LawValues:
        """``(s, ds, d2s, d3s)`` at ``theta`` (a motion program's: read-only, kept by the program
        for the grid: :meth:`~camgen.synthesis.laws.MotionProgram.on_uniform_grid_in_order`)."""
        in_order = getattr(self.law, "on_uniform_grid_in_order", None)
        if in_order is not None and self.added.size:
            block = in_order(self.uniform_size, self.added, self._layout[1])
            return block[0], block[1], block[2], block[3]
        raw = self.raw
        rows = _rows_of(raw)
        if rows is None:  # four separate arrays: stacked first (a copy: the raw values may be the law's kept ones)
            rows = np.stack(raw)
        elif not self.added.size:
            rows = rows.copy()  # (a copy: the raw values may be the law's kept ones)
        block = rows.take(self._layout[1], axis=1) if self.added.size else rows  # (take: a fresh array)
        return block[0], block[1], block[2], block[3]

    def to_cam(self, sigma: float) -> np.ndarray:
        """:func:`_to_cam` at ``theta`` for a cam turning in the direction ``sigma`` (read-only)."""
        return _sorted_grid_to_cam(sigma, self.uniform_size, self.added.tobytes())

    s = property(lambda self: self.values[0])
    ds = property(lambda self: self.values[1])
    d2s = property(lambda self: self.values[2])
    d3s = property(lambda self: self.values[3])


@dataclass(frozen=True)
class CamEnvelope:
    """A cam for a follower and a law: the curves, the dense curvature data and the failures.

    Attributes
    ----------
    follower : the :class:`FollowerSpec`.
    profile : the cam profile (:class:`Contour`), or None when it cannot be made (report-only).
    pitch : roller / knife: the pitch curve (roller-centre path; the knife's is the profile);
        flat: None.
    grid : the :class:`CheckGrid` (cam angles and the law's values there).
    failures : one entry per failed condition: ``{"reason": str, "ranges_deg": [(start, end), ...],
        "worst_deg": float}`` (empty when the cam can be made).
    fit_tol : the requested tolerance of the spline representation, mm.
    fit_error : the largest measured distance of ``profile`` (else ``pitch``) from the exact
        curve at the probe points, mm (NaN when neither was built).
    data : :class:`Kinematics` on the check grid, made on first use (the profile does not need
        it: rollers and knives are checked for undercuts and cusps from the pitch curve's speed
        and curvature alone).
    """

    follower: FollowerSpec
    profile: Contour | None
    pitch: Contour | None
    grid: CheckGrid
    failures: list[dict] = field(default_factory=list)
    fit_tol: float = DEFAULT_FIT_TOL
    fit_error: float = float("nan")

    @property
    def ok(self) -> bool:
        return not self.failures

    @cached_property
    def data(self) -> Kinematics:
        g = self.grid
        return _kinematics_from(self.follower, g.theta, *g.values, g.to_cam(self.follower.sigma))


def _failure_message(f: FollowerSpec, failures: list[dict]) -> str:
    parts = []
    for item in failures:
        ranges = ", ".join(f"{a:.3f}..{b:.3f}" for a, b in item["ranges_deg"][:6])
        parts.append(f"{item['reason']} at cam angles {ranges} deg")
    return (f"{f.kind} follower ({f.motion}, base_radius {f.base_radius:g} mm) cannot ride this law: " + "; ".join(parts)
            + "; increase base_radius (camgen.synthesis.sizing.min_base_radius gives the smallest that works)"
            + (" or reduce the roller radius" if f.has_radius else ""))


def _fit_failure(fit_tol: float, reached: float, pieces: int) -> FitToleranceError:
    return FitToleranceError(
        f"the spline representation does not reach fit_tol = {fit_tol:g} mm (error {reached:.3g} mm with {pieces} pieces): the "
        "curve changes on a finer scale than that many pieces follow (a curve close to a cusp, or a lift table of very many rows); "
        "increase fit_tol or the base radius", fit_tol, reached, pieces)


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
    if not f.edge and np.any(cont <= 0):
        where = ", ".join(f"{math.degrees(b):.3f}" for b in brk[cont <= 0])
        raise GeometryError(f"the law's velocity jumps at cam angles {where} deg: a {f.kind} follower cannot follow "
                            "a corner of the pitch curve exactly; use laws with continuous velocity there (or a knife follower)")
    n_uniform, added = _grid_layout(law, check_step)
    grid = CheckGrid(law, n_uniform, added)
    # the coarse grid (BOUND_SPACING, the breaks and their neighbours added): the law's values there
    # screen a roller or knife cam for its limits and give the sixth-derivative bound of the fit
    n_coarse, added_coarse = _grid_layout(law, BOUND_SPACING)
    coarse = _law_on_grid(law, n_coarse, added_coarse)
    flat_data = None
    terms = None if f.contact == "face" else _pitch_terms(f, *coarse)
    if terms is None:  # a flat face: its checks need most of its kinematics: made now, kept for `data`
        flat_data = _kinematics_from(f, grid.theta, *grid.values, grid.to_cam(f.sigma))
        masks = profile_failures(f, flat_data)
    elif _pitch_clear(f, terms, TWO_PI / n_coarse):
        masks = []
    else:  # the dense check, in the grid's own order (uniform part, then the added angles)
        masks = [(reason, grid.sorted(mask)) for reason, mask in _pitch_failures(f, *grid.raw[:3]) if mask.any()]
    failures: list[dict[str, Any]] = []
    for reason, mask in masks:
        if mask.any():
            theta = grid.theta
            worst = float(theta[np.argmax(mask)])
            failures.append({"reason": reason, "ranges_deg": _run_ranges(mask, theta), "worst_deg": math.degrees(worst)})
    if failures and not report_only:
        raise GeometryError(_failure_message(f, failures))

    sigma = f.sigma
    pitch = profile = None
    error = float("nan")
    pitch_ok = f.contact == "point" and not any(item["reason"].startswith(("cusp", "the follower passes")) for item in failures)
    # the curves to represent: roller: pitch and profile (pitch only when the profile cannot be made);
    # knife: its pitch curve is its profile; flat: the profile
    want = [] if failures else ["profile"]
    if pitch_ok and f.has_radius:
        want.insert(0, "pitch")

    def exact(th: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The wanted curves and their first two derivatives (d/dtheta) at cam angles ``th`` (n,)
        from one evaluation of the law: (Q, dQ, d2Q), complex (n, len(want)) each (the curves side by side)."""
        s, ds, d2s, d3s = (np.asarray(x, dtype=float).ravel() for x in law(th))
        block = np.empty((3, th.size, len(want)), dtype=complex)
        back = _kept_rotation_to_cam(sigma, th.tobytes())  # (th: a fresh float64 array)
        if f.contact == "face":
            block[:, :, 0] = _flat(f, th, s, ds, d2s, d3s, False, back)[0]
        else:
            _roller(f, th, s, ds, d2s, d3s, False, tuple(want), back=back, out=block)
        return block[0], block[1], block[2]

    if want:
        # d2Q/dtheta2 of the wanted curves on the uniform part of the coarse grid: the sixth-derivative bound
        at = np.arange(n_coarse) * (TWO_PI / n_coarse)
        if terms is None:
            s_c, ds_c, d2s_c, d3s_c = coarse
            d2 = _flat(f, at, s_c[:n_coarse], ds_c[:n_coarse], d2s_c[:n_coarse], d3s_c[:n_coarse], False)[0][2][None]
        else:
            d2 = _pitch_second_derivatives(f, at, terms, want)
        try:
            curves, errors = _spline_contours(exact, len(want), sigma, law, fit_tol, (at, d2))
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
            if f.edge:
                pitch = profile
    envelope = CamEnvelope(f, profile, pitch, grid, failures, fit_tol, error)
    if flat_data is not None:
        envelope.__dict__["data"] = flat_data  # the cache of the `data` property, already made
    return envelope


def pitch_offsets(follower: FollowerSpec, law: Displacement, distances: Sequence[float], *,
                  fit_tol: float = DEFAULT_FIT_TOL) -> tuple[list[Contour], list[float]]:
    """Exact parallel curves of the pitch curve (roller-centre path) of ``follower`` driven by ``law``.

    Curve ``i`` is ``Q = P - d_i n`` with ``d_i = distances[i]`` (mm) and ``n`` the pitch curve's
    outward normal: ``d > 0`` towards the cam axis (a roller's profile is ``d = r``), ``d < 0``
    away from it (a groove's outer wall is ``d = -(r + clearance / 2)``).  From the closed forms
    of :func:`_roller` with ``r -> d``: ``Q' = P' (1 - d kappa)``, ``Q'' = P'' (1 - d kappa) -
    d kappa' P'`` (kappa the pitch curve's signed curvature); represented as the envelopes are
    (:func:`_spline_contours`, within ``fit_tol`` mm at the probes; knots at the law's breaks).
    The caller checks the curves can be made (|radius of the pitch curve| > |d| where it bends
    towards the offset side: :func:`pitch_offset_failures`).

    Returns the contours (counter-clockwise, cam frame) and the largest measured distance of each
    from its exact curve (mm).
    """
    fit_tol = require_positive("fit_tol", fit_tol)
    if follower.contact != "point":
        raise ParameterError("follower", follower.kind, "a follower with a point contact (a pitch curve)")
    f = follower
    sigma = f.sigma
    d = np.asarray([require_finite("distance", float(v)) for v in distances], dtype=float)

    def exact(th: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        s, ds, d2s, d3s = (np.asarray(x, dtype=float).ravel() for x in law(th))
        (cx, cy), (vx, vy), (ax, ay), (bx, by), _, _ = _centre(f, s, ds, d2s, d3s)
        back = _to_cam(f, th)
        pitch, p1, p2 = _in_cam(back, cx, cy), _in_cam(back, vx, vy), _in_cam(back, ax, ay)
        speed, _, _, kappa, kappa1 = _pitch_curvature(sigma, vx, vy, ax, ay, bx, by)
        with np.errstate(divide="ignore", invalid="ignore"):
            k = (sigma * d[None, :]) / speed[:, None]  # Q = P - d n = P - i k P' (as in _roller)
        factor = 1.0 - d[None, :] * kappa[:, None]
        q = pitch[:, None] - 1j * k * p1[:, None]
        q1 = p1[:, None] * factor
        q2 = p2[:, None] * factor - (d[None, :] * kappa1[:, None]) * p1[:, None]
        return q, q1, q2

    n_coarse, added_coarse = _grid_layout(law, BOUND_SPACING)
    s_c, ds_c, d2s_c, d3s_c = _law_on_grid(law, n_coarse, added_coarse)
    at = np.arange(n_coarse) * (TWO_PI / n_coarse)
    (_, _), (vx, vy), (ax, ay), (bx, by), _, _ = _centre(f, s_c[:n_coarse], ds_c[:n_coarse], d2s_c[:n_coarse], d3s_c[:n_coarse])
    _, _, _, kappa, kappa1 = _pitch_curvature(sigma, vx, vy, ax, ay, bx, by)
    back = _to_cam(f, at)
    d2 = np.stack([_in_cam(back, ax * (1.0 - di * kappa) - di * kappa1 * vx, ay * (1.0 - di * kappa) - di * kappa1 * vy)
                   for di in d])
    return _spline_contours(exact, d.size, sigma, law, fit_tol, (at, d2))


def pitch_offset_failures(k: Kinematics, distance: float) -> np.ndarray:
    """Where the parallel curve at ``distance`` (mm, signed as in :func:`pitch_offsets`) of the
    pitch curve in ``k`` cannot be made: the pitch curve bends towards that side with a radius of
    curvature at most ``|distance|`` (the offset curve has a cusp or loops back: an undercut).
    Boolean (n,) over ``k.theta``."""
    assert k.pitch_curvature is not None, "a pitch curve's kinematics"
    return k.pitch_curvature * distance >= 1.0
