"""Linear (translating-plate) cams: conventions, closed-form kinematics and the exact edge and
slot walls.

Conventions
-----------
**Frames.** The *plate frame* is fixed to the plate, the *fixed frame* to the machine; they
coincide at travel 0.  The plate moves along the fixed ``-x`` direction: after a travel ``x``
(mm, ``0 <= x <= travel``) the plate point ``(X, Y)`` is at ``(X - x, Y)`` in the fixed frame, so
the follower reads the plate from left to right.  **x = 0 on the plate** is where the follower's
reference point (roller centre, knife tip) is at travel 0 and zero lift: the plate frame's
origin; ``y = 0`` is the *pitch line* (that point's height at zero lift).

**The abscissa.** The program is written in plate travel (a motion program's ``span_mm``, a lift
table's x in mm); the motion reads it onto one turn of ``theta``
(:class:`~camgen.synthesis.followers.Displacement`), ``theta = 2 pi x / travel``, so
``ds/dx = s'(theta) 2 pi / travel`` and so on.

**Translating follower**: moves along the fixed ``+y`` axis (the line ``x = 0`` of the fixed
frame); its reference point is ``(x, s(x))`` in the plate frame: the pitch curve is the graph of
the lift.  **Oscillating follower**: an arm of length ``L`` about a pivot fixed at ``p = (px, py)``
(fixed frame), ``L = |p|`` (the arm reaches the origin at zero swing); the swing ``s`` (rad) turns
it by ``tau s`` (``tau = +1`` ccw, ``-1`` cw) from its rest angle ``psi0 = arg(-p)``, so the
reference point is ``C = (x, 0) + p + L e^(i psi)``, ``psi = psi0 + tau s``.  A positive swing
must lift it (``tau cos(psi0) > 0``, i.e. ``-tau px > 0``).

**Offsets.** With the unit tangent ``t = C'/|C'|`` of the pitch curve (increasing x) and its
left normal ``n = i t`` (up, away from the plate below it), the curve at signed distance ``d``
is ``Q = C + d n``: the edge profile is ``d = -r`` (the roller rests on it), a slot's walls
``d = -(r + c/2)`` (lower) and ``d = +(r + c/2)`` (upper).  With the signed curvature
``k = Im(conj(C') C'') / |C'|^3`` (> 0 turning left: a valley seen from above),
``Q' = t |C'| (1 - d k)`` (the offset runs the pitch curve's way while ``1 - d k > 0``: where
``1 - d k <= 0`` it loops, the undercut) and ``Q''`` follows from ``t' = i k |C'| t`` and
``k' = Im(conj(C') C''') / |C'|^3 - 3 Im(conj(C') C'') Re(conj(C') C'') / |C'|^5`` (the
classical offset-curve formulas: e.g. Farouki and Neff, "Analytic properties of plane offset
curves", CAGD 7, 1990).  The offset's radius of curvature is ``1/k - d``.

**Pressure angle**: the angle between the common normal (the pitch curve's normal) and the
direction ``e`` the follower point moves in (translating ``e = i``; oscillating
``e = tau i e^(i psi)``), signed like the component of ``e`` along the pitch tangent:
``tan(alpha) = Re(conj(C') e) / Im(conj(C') e)``.  Translating: ``tan(alpha) = ds/dx``
(Rothbart, *Cam Design Handbook*, 2004, sec. 2: the translating cam).  Oscillating, derived here
from that definition: ``tan(alpha) = (L ds/dx - tau sin(psi)) / (tau cos(psi))``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camgen.errors import FitToleranceError, GeometryError

__all__ = [
    "EdgeOutline", "LinearCurves", "LinearFollower", "SlotWalls", "curves", "edge_fillets", "edge_outline", "end_arcs", "fit_offset",
    "law_in_x",
    "offset_curve", "offset_failures", "pressure_angle", "rounded_rectangle", "slot_walls",
]

TWO_PI = 2.0 * math.pi
#: Largest number of pieces of one spline segment of a fitted offset.
MAX_PIECES = 1 << 14
#: Quarter, mid and three-quarter points of a piece where a fit is measured.
_PROBES = np.array([0.25, 0.5, 0.75])


@dataclass(frozen=True)
class LinearFollower:
    """The follower of a linear cam (mm, rad): ``kind`` (its registered name), ``motion``
    (``"translating"`` | ``"oscillating"``), ``roller_radius`` (0: a knife), ``pivot`` (oscillating:
    the pivot relative to the follower point at zero swing and travel 0) and ``lift_turn``
    (``"ccw"`` | ``"cw"``: the way a positive swing turns the arm).

    ``edge``, ``kind`` and ``abscissa`` are what a motion asks of its follower (a knife edge may
    follow a velocity jump; nothing else can; a linear cam's program runs over the plate travel)."""

    kind: str
    motion: str = "translating"
    roller_radius: float = 0.0
    pivot: tuple[float, float] | None = None
    lift_turn: str = "ccw"

    def __post_init__(self) -> None:
        if self.motion == "oscillating":
            if self.pivot is None:
                raise GeometryError("an oscillating follower needs its pivot")
            if -self.tau * self.pivot[0] <= 0.0:
                raise GeometryError(f"a positive swing must lift the follower: with the pivot at x = {self.pivot[0]:g} mm the arm "
                                    f"turns {'cw' if self.pivot[0] > 0 else 'ccw'} to lift it (pivot_x_mm != 0)")

    @property
    def abscissa(self) -> str:
        """What the motion's program runs over: the plate travel (mm), not a cam angle
        (:mod:`camgen.motions.motion_law`: segments give ``span_mm``)."""
        return "travel"

    @property
    def edge(self) -> bool:
        """A knife edge (no radius)."""
        return self.roller_radius == 0.0

    @property
    def tau(self) -> float:
        return 1.0 if self.lift_turn == "ccw" else -1.0

    @property
    def arm_length(self) -> float:
        assert self.pivot is not None
        return math.hypot(*self.pivot)

    @property
    def rest_angle(self) -> float:
        """Arm angle at zero swing, rad (from the pivot to the follower point)."""
        assert self.pivot is not None
        return math.atan2(-self.pivot[1], -self.pivot[0])


def law_in_x(law: Any, travel: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """s and its first three derivatives by the travel x (mm; per mm^k) of ``law`` (a function of
    the cam angle over one turn) mapped onto ``travel`` mm: ``theta = 2 pi x / travel``."""
    k = TWO_PI / travel
    s, d1, d2, d3 = law(np.asarray(x, dtype=float) * k)
    return s, d1 * k, d2 * (k * k), d3 * (k * k * k)


@dataclass(frozen=True)
class LinearCurves:
    """The pitch curve at travels ``x`` (n,): point ``c``, derivatives ``c1``, ``c2``, ``c3`` by x
    (complex, plate frame), the follower's direction of motion ``e`` (unit, complex) and the law
    ``s``, ``s1`` (per mm)."""

    x: np.ndarray
    c: np.ndarray
    c1: np.ndarray
    c2: np.ndarray
    c3: np.ndarray
    e: np.ndarray
    s: np.ndarray
    s1: np.ndarray

    @property
    def speed(self) -> np.ndarray:
        return np.abs(self.c1)

    @property
    def curvature(self) -> np.ndarray:
        """Signed curvature of the pitch curve (1/mm, > 0 turning left: a valley seen from above)."""
        return np.imag(np.conj(self.c1) * self.c2) / self.speed**3

    @property
    def normal(self) -> np.ndarray:
        """Unit left normal (up, away from the plate below the pitch curve)."""
        return 1j * self.c1 / self.speed


def curves(f: LinearFollower, law: Any, travel: float, x: np.ndarray) -> LinearCurves:
    """The pitch curve of ``f`` on ``law`` over ``travel`` at travels ``x`` (closed forms of the
    module notes)."""
    x = np.asarray(x, dtype=float)
    s, s1, s2, s3 = law_in_x(law, travel, x)
    if f.motion == "translating":
        c = x + 1j * s
        c1 = 1.0 + 1j * s1
        c2 = 1j * s2
        c3 = 1j * s3
        e = np.full(x.shape, 1j)
    else:
        px, py = f.pivot  # type: ignore[misc]
        arm, tau = f.arm_length, f.tau
        rot = np.exp(1j * (f.rest_angle + tau * s))
        c = x + complex(px, py) + arm * rot
        c1 = 1.0 + 1j * tau * arm * s1 * rot
        c2 = arm * rot * (1j * tau * s2 - s1 * s1)
        c3 = arm * rot * (1j * tau * (s3 - s1**3) - 3.0 * s1 * s2)
        e = tau * 1j * rot
    return LinearCurves(x, c, c1, c2, c3, e, s, s1)


def pressure_angle(k: LinearCurves) -> np.ndarray:
    """Signed pressure angle (rad) at each travel: ``atan2(Re(conj(C') e), Im(conj(C') e))``."""
    z = np.conj(k.c1) * k.e
    return np.arctan2(z.real, z.imag)


def offset_curve(k: LinearCurves, d: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pitch curve offset by ``d`` (mm, along the left normal): point, first and second
    derivative by x (complex), from the closed forms of the module notes."""
    speed = k.speed
    t = k.c1 / speed
    dot = np.real(np.conj(k.c1) * k.c2)
    crs = np.imag(np.conj(k.c1) * k.c2)
    kappa = crs / speed**3
    dspeed = dot / speed
    dkappa = np.imag(np.conj(k.c1) * k.c3) / speed**3 - 3.0 * crs * dot / speed**5
    grow = 1.0 - d * kappa
    q = k.c + d * 1j * t
    q1 = t * speed * grow
    q2 = t * (1j * kappa * speed * speed * grow + dspeed * grow - d * dkappa * speed)
    return q, q1, q2


def offset_failures(k: LinearCurves, d: float) -> np.ndarray:
    """Where the offset by ``d`` loops (``1 - d k <= 0``: the pitch curve's radius on that side is
    not above ``|d|``), a boolean mask over ``k.x``; a knife (``d = 0``) never loops."""
    if d == 0.0:
        return np.zeros(k.x.shape, dtype=bool)
    return 1.0 - d * k.curvature <= 0.0


def _xy(z: np.ndarray) -> np.ndarray:
    return np.stack([z.real, z.imag], axis=-1)


def fit_offset(f: LinearFollower, law: Any, travel: float, d: float, x0: float, x1: float, fit_tol: float,
               reverse: bool = False) -> tuple[list, float]:
    """Quintic Hermite spline segments of the pitch curve's offset by ``d`` from travel ``x0`` to
    ``x1`` (mm), one segment per interval between the law's breaks (repeated every ``travel``),
    each within ``fit_tol`` mm of the exact curve at the quarter, mid and three-quarter points of
    every piece (pieces doubled until it is).  ``reverse``: run from ``x1`` to ``x0`` (the spline
    parameter is then ``-x``).  Returns the segments in order and the largest deviation met (mm).
    """
    from camgen.contour import Spline

    brk = np.asarray(law.breaks, dtype=float) * travel / TWO_PI
    cont = np.asarray(getattr(law, "break_continuity", np.zeros(brk.size)), dtype=int)
    from camgen.synthesis.laws import SMOOTH

    brk = brk[cont < SMOOTH]
    first, last = math.floor(x0 / travel) - 1, math.ceil(x1 / travel) + 1
    knots = (brk[None, :] + travel * np.arange(first, last + 1)[:, None]).ravel()
    eps = 1e-9 * max(1.0, travel)
    knots = np.unique(np.concatenate([[x0, x1], knots[(knots > x0 + eps) & (knots < x1 - eps)]]))
    segments = []
    worst = 0.0
    for a, b in zip(knots[:-1], knots[1:]):  # one segment per smooth interval (a handful)
        n = max(2, int(math.ceil((b - a) / max(travel / 64.0, 1e-6))))
        while True:
            x = np.linspace(a, b, n + 1)
            shrink = (b - a) * 1e-12
            x_eval = x.copy()
            x_eval[0] += shrink
            x_eval[-1] -= shrink
            # the points at the knots themselves (the curve is continuous there: neighbouring segments
            # share their end points), the derivatives one-sided (the law's right and left limits)
            q = offset_curve(curves(f, law, travel, x), d)[0]
            _, q1, q2 = offset_curve(curves(f, law, travel, x_eval), d)
            if reverse:
                t, pts, d1, d2 = -x[::-1], _xy(q[::-1]), -_xy(q1[::-1]), _xy(q2[::-1])
            else:
                t, pts, d1, d2 = x, _xy(q), _xy(q1), _xy(q2)
            spline = Spline.hermite5(t, pts, d1, d2)
            probe = (x[:-1, None] + (x[1:] - x[:-1])[:, None] * _PROBES[None, :]).ravel()
            exact = offset_curve(curves(f, law, travel, probe), d)[0]
            got = spline.eval_t(-probe if reverse else probe)
            error = float(np.max(np.abs(got[:, 0] + 1j * got[:, 1] - exact)))
            if error <= fit_tol:
                worst = max(worst, error)
                break
            if n >= MAX_PIECES:
                raise FitToleranceError(f"the spline of the linear cam's curve does not reach fit_tol_mm = {fit_tol:g} mm with "
                                        f"{n} pieces between x = {a:.6g} and {b:.6g} mm (reached {error:.3g} mm)", fit_tol, error, n)
            n *= 2
        segments.append(spline)
    if reverse:
        segments.reverse()
    return segments, worst


# --------------------------------------------------------------------------------------------
# The plate: an edge cam's outline, a slot's walls
# --------------------------------------------------------------------------------------------
#: Bisection steps of a fillet's tangent point (the bracket shrinks below 1e-15 of its width).
_BISECTIONS = 60


def _line(p: tuple[float, float], q: tuple[float, float]):
    """A straight segment from p to q as a cubic spline (a contour has arcs and splines)."""
    from camgen.contour import Spline

    p_, q_ = np.array(p, dtype=float), np.array(q, dtype=float)
    length = float(np.hypot(*(q_ - p_)))
    if length <= 0.0:
        raise GeometryError("a side of the plate has no length")
    direction = (q_ - p_) / length
    return Spline.hermite(np.array([0.0, length]), np.stack([p_, q_]), np.stack([direction, direction]))


def _fillet_point(f: LinearFollower, law: Any, travel: float, d: float, target: float, near: float, reach: float) -> float:
    """The travel x where the pitch curve's offset by ``d`` (the centre of a fillet) has abscissa
    ``target``: the sign change of ``Re(offset) - target`` on a grid over ``near +- reach``
    nearest to ``near``, refined by bisection."""
    grid = np.linspace(near - reach, near + reach, 4001)
    g = offset_curve(curves(f, law, travel, grid), d)[0].real - target
    above = g >= 0.0
    change = np.flatnonzero(above[:-1] != above[1:])
    if change.size == 0:
        raise GeometryError(f"no point of the plate's edge meets its end at x = {target:.6g} mm")
    i = int(change[np.argmin(np.abs(grid[change] - near))])
    lo, hi, lo_above = float(grid[i]), float(grid[i + 1]), bool(above[i])
    for _ in range(_BISECTIONS):  # a scalar root: 60 halvings
        mid = 0.5 * (lo + hi)
        gm = float(offset_curve(curves(f, law, travel, np.array([mid])), d)[0].real[0] - target)
        if (gm >= 0.0) == lo_above:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def edge_fillets(f: LinearFollower, law: Any, travel: float, x_left: float, x_right: float, corner: float) -> tuple[np.ndarray, np.ndarray]:
    """The travels (2,) where an edge cam's profile meets its two top corner fillets (radius
    ``corner``, tangent to the profile and to the ends ``x_left``, ``x_right``) and the fillets'
    centres (2,) complex: on the pitch curve offset by ``-(r + corner)``."""
    r, rc = f.roller_radius, corner
    reach = r + 2.0 * rc + (f.arm_length if f.motion == "oscillating" else 0.0) + 1.0
    xs = np.array([_fillet_point(f, law, travel, -(r + rc), x_left + rc, x_left + rc, reach),
                   _fillet_point(f, law, travel, -(r + rc), x_right - rc, x_right - rc, reach)])
    return xs, offset_curve(curves(f, law, travel, xs), -(r + rc))[0]


@dataclass(frozen=True)
class EdgeOutline:
    """An edge cam's plate outline (the contour), the travels ``x_start``, ``x_end`` (mm) between
    which it is the profile (beyond: the corner fillets) and the largest fit deviation (mm)."""

    contour: Any
    x_start: float
    x_end: float
    fit_error: float


def edge_outline(f: LinearFollower, law: Any, travel: float, x_left: float, x_right: float, y_bottom: float, corner: float,
                 fit_tol: float) -> EdgeOutline:
    """The closed counter-clockwise outline of an edge cam's plate: its bottom ``y = y_bottom``,
    its ends ``x = x_left``, ``x = x_right``, the profile (the pitch curve offset by ``-r``)
    between, every corner rounded by an arc of radius ``corner`` (the top corners: the arc tangent
    to the end and to the profile, its centre on the pitch curve offset by ``-(r + corner)``)."""
    from camgen.contour import Arc, Contour

    r, rc = f.roller_radius, corner
    xs, centres = edge_fillets(f, law, travel, x_left, x_right, corner)
    ups = curves(f, law, travel, xs).normal
    for centre, side in zip(centres, ("start", "end")):
        if centre.imag - rc <= y_bottom + rc:
            raise GeometryError(f"the plate's {side} is too low for its corners: the edge's fillet reaches y = "
                                f"{centre.imag - rc:.6g} mm, the bottom's corner y = {y_bottom + rc:.6g} mm")
    if xs[1] <= xs[0]:
        raise GeometryError("the plate is too short for its corners")
    profile, worst = fit_offset(f, law, travel, -r, float(xs[0]), float(xs[1]), fit_tol, reverse=True)
    left, right = centres[0], centres[1]
    a_right = float(np.angle(ups[1]))
    a_left = float(np.angle(ups[0]))
    segments = [
        _line((x_left + rc, y_bottom), (x_right - rc, y_bottom)),
        Arc((x_right - rc, y_bottom + rc), rc, -0.5 * math.pi, 0.5 * math.pi),
        _line((x_right, y_bottom + rc), (x_right, right.imag)),
        Arc((right.real, right.imag), rc, 0.0, a_right),
        *profile,
        Arc((left.real, left.imag), rc, a_left, math.pi - a_left),
        _line((x_left, left.imag), (x_left, y_bottom + rc)),
        Arc((x_left + rc, y_bottom + rc), rc, math.pi, 0.5 * math.pi),
    ]
    return EdgeOutline(Contour(segments), float(xs[0]), float(xs[1]), worst)


def rounded_rectangle(x_left: float, x_right: float, y_bottom: float, y_top: float, corner: float):
    """The closed counter-clockwise outline of a slot cam's plate: a rectangle, corners rounded."""
    from camgen.contour import Arc, Contour

    rc = corner
    return Contour([
        _line((x_left + rc, y_bottom), (x_right - rc, y_bottom)),
        Arc((x_right - rc, y_bottom + rc), rc, -0.5 * math.pi, 0.5 * math.pi),
        _line((x_right, y_bottom + rc), (x_right, y_top - rc)),
        Arc((x_right - rc, y_top - rc), rc, 0.0, 0.5 * math.pi),
        _line((x_right - rc, y_top), (x_left + rc, y_top)),
        Arc((x_left + rc, y_top - rc), rc, 0.5 * math.pi, 0.5 * math.pi),
        _line((x_left, y_top - rc), (x_left, y_bottom + rc)),
        Arc((x_left + rc, y_bottom + rc), rc, math.pi, 0.5 * math.pi),
    ])


@dataclass(frozen=True)
class SlotWalls:
    """A slot's closed wall (the pocket's boundary, counter-clockwise): the lower wall from travel
    ``x_start`` (0) to ``x_end`` (the travel), a half circle about the pitch curve's point at the
    end, the upper wall back, a half circle about its point at the start; ``centre``: the pitch
    curve between the two ends (an open chain of spline segments, the path of a cutter as wide as
    the slot); the largest fit deviation (mm)."""

    contour: Any
    centre: tuple
    x_start: float
    x_end: float
    fit_error: float


def end_arcs(f: LinearFollower, law: Any, travel: float, half: float) -> tuple[np.ndarray, np.ndarray]:
    """The centres (2,) complex and start angles (2,) rad of a slot's end half circles (radius
    ``half``, sweep pi counter-clockwise): about the pitch curve's point at the travel's end, from
    the lower wall (angle of the normal - pi) to the upper one; about its point at the start, from
    the upper wall (the normal's angle) to the lower one."""
    k = curves(f, law, travel, np.array([0.0, travel]))
    up = np.angle(k.normal)
    return k.c[::-1], np.array([float(up[1]) - math.pi, float(up[0])])


def slot_walls(f: LinearFollower, law: Any, travel: float, half: float, fit_tol: float) -> SlotWalls:
    """The boundary of a slot of width ``2 half`` along the pitch curve over the travel, closed
    inside the plate: the walls are the pitch curve's offsets by ``-half`` (lower) and ``+half``
    (upper) from travel 0 to ``travel``, each within ``fit_tol``; the ends are half circles of
    radius ``half`` about the pitch curve's points at 0 and ``travel`` (tangent to both walls:
    what a cutter of the slot's width leaves at the ends of its pass along the pitch curve)."""
    from camgen.contour import Arc, Contour

    lower, e1 = fit_offset(f, law, travel, -half, 0.0, travel, fit_tol)
    upper, e2 = fit_offset(f, law, travel, half, 0.0, travel, fit_tol, reverse=True)
    centre, e3 = fit_offset(f, law, travel, 0.0, 0.0, travel, fit_tol)
    centres, starts = end_arcs(f, law, travel, half)
    segments = [*lower, Arc((centres[0].real, centres[0].imag), half, float(starts[0]), math.pi), *upper,
                Arc((centres[1].real, centres[1].imag), half, float(starts[1]), math.pi)]
    return SlotWalls(Contour(segments), tuple(centre), 0.0, travel, max(e1, e2, e3))
