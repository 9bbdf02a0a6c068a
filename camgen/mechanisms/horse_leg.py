"""Single leg of the quadruped horse robot: cam-linkage kinematics (paper 000, Sections 3-6).

Loops (all in the paper's frame: origin O1 at the stride-cam centre, x right, y up, mm, rad):

* stride-length loop O1 N N' Q P O7 (eqs. 3-5) and O1 O7 P Q R O6 (eqs. 6-8): the stride cam
  (three-arc, turning by ``theta1``) drives a yoke (fork) of half-width ``e2`` whose centre Q
  rides a slide block along the rectangular swing rod: ``Q = O7 + r_p e^{j(alpha1 + pi/2)}
  + S e^{j alpha1}`` (eq. 4's right side).  The fork carries the arm QR (``l1``) at
  ``theta2 = psi + pi/2 + gamma2`` (psi: the face normal, ``theta1 + phi1 + beta10``), and R
  hangs on the rocker O6R (``r6``).  Projecting eq. 5 on the face normal gives
  ``n . Q = h(psi - theta1) - e2`` with ``h`` the cam's support function, so S follows from
  psi and the loop reduces to one scalar equation ``|R(psi) - O6| = r6``, solved by a
  vectorised Newton iteration with continuation;
* four-bar O1 A B O4 (eqs. 9-11): crank ``r1`` at ``theta1 + gamma1``, coupler ``r_AB``,
  rocker ``r4``; the stride-height cam is fixed to the rocker and turns by ``theta4``
  (``B = O4 + r4 e^{j(theta4 + gamma4)}``).  Closed form (circle intersection);
* lifting loop O1 O4 K K' O5 (eqs. 12-14): the height fork (half-width ``e5``) swings about
  O5, so its centre line passes through O5: ``n4 . (O5 - C_k) = r_k - e5`` on the active arc
  (centre ``C_k``, radius ``r_k``) of the height cam.  Closed form per arc;
* leg loop O1 O5 S U T O6 (eqs. 15-17): ``S = O5 + r5 e^{j theta5}``,
  ``theta5 = 3 pi/2 + psi4 - gamma5``; ``T = O6 + r7 e^{j(theta6 + gamma6)}``; the leg carries
  TU (``r8``) and a slideway through U at ``theta_U`` to TU along which S slides (``l``).
  Closed form (a quadratic in l);
* leg end point W (eq. 18): ``W = U + S8 e^{j(pi + theta8 - theta_P)}``.

Decisions where Figure 3 is missing (each checked by the tests against Section 6's numbers):

* branches: fork normal ``psi`` near 206.5 deg at theta1 = 0 (the other root of the stride loop
  puts the foot 1.7 m higher, beside the body); four-bar with B on the left of A->O4;
  height-fork normal within 90 deg of its value at theta1 = 0 (the other choice swings the
  arm O5S to the other side of O5).  :func:`branch_table` shows what the other branches do;
* alpha1 enters only through the swing rod: ``P = O7 + r_p e^{j(alpha1 + pi/2)}`` and the
  slide direction ``e^{j alpha1}`` (eq. 4); eq. (2) relates alpha1 to the lead screw;
* misprints: eq. (7) lacks a ``j`` (``l1 e^{j theta2}``); eqs. (20)-(21) write the slide term
  as ``S e^{j(alpha1 + pi)}`` while eq. (4) has ``S e^{j alpha1}`` -- read literally they put the
  instant centre on the wrong side and give 60-90 deg pressure angles (see
  :func:`pressure_angle`, ``literal=True``); "l7" in Section 4.7 is the slider length ``l``;
  ``theta_P`` and ``theta_p`` are one angle (125 deg);
* the ground: the foot path is split into swing (above) and stance (below) by a horizontal
  ground line ``y = ground_y``.  Figures 10-12 that show it are missing; each of the paper's
  three cases implies the same line (lowest foot point + the paper's body height change:
  -2074.8, -2075.4 and -2074.1 mm), so it is a property of the robot, not of alpha1:
  ``ground_y = -2074`` mm (configurable).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from camgen.contour import Arc, Contour
from camgen.errors import GeometryError, ParameterError, require_finite
from camgen.geometry import unit_vectors as _unit
from camgen.geometry import wrap_pi

__all__ = [
    "ASSEMBLY_SCAN", "ASSEMBLY_SCAN_POSITIONS", "ASSEMBLY_STEP", "ASSEMBLY_TOL", "Branches", "HorseLeg",
    "LegSolution", "PARALLEL_TOL", "assembly_range", "body_path", "branch_table", "cycle", "four_bar", "gait_figures",
    "gait_range", "grashof_margin", "ground_crossings", "ground_lines", "height_fork_pressure_angle",
    "lead_screw_length", "leg_cams", "leg_loop", "lifting_loop", "pressure_angle", "solve_leg", "solve_stride_loop",
]

D = math.radians


@dataclass(frozen=True)
class HorseLeg:
    """Dimensions of the single-leg system (paper 000, Section 6), mm and rad."""

    o7: tuple[float, float] = (-360.0, -753.0)
    o2: tuple[float, float] = (-460.0, -720.0)
    o6: tuple[float, float] = (383.0, -531.0)
    o4: tuple[float, float] = (-114.0, -654.0)
    o5: tuple[float, float] = (-433.0, -923.0)
    r_p: float = 185.0
    l1: float = 240.0
    e2: float = 165.0
    r4: float = 44.0
    r1: float = 35.0
    r_ab: float = 655.0
    r7: float = 474.0
    r6: float = 95.0
    r8: float = 100.0
    s8: float = 1081.0
    r5: float = 356.0
    e5: float = 120.0
    gamma1: float = D(180.0)
    gamma2: float = D(40.0)
    gamma5: float = D(62.0)
    gamma6: float = D(40.0)
    gamma4: float = D(-8.0)
    theta_u: float = D(120.0)
    theta_p: float = D(125.0)
    stride_cam: tuple[float, float, float] = (220.0, 160.0, 25.0)
    height_cam: tuple[float, float, float] = (220.0, 220.0, 10.0)
    ground_y: float = -2074.0

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            for v in value if isinstance(value, tuple) else (value,):
                require_finite(f.name, v)

    def point(self, name: str) -> np.ndarray:
        return np.asarray(getattr(self, name), dtype=float)


@dataclass(frozen=True)
class Branches:
    """Assembly branches: stride-loop fork normal near ``stride_psi0`` at theta1 = 0 (rad),
    four-bar ``four_bar`` = +1 or -1, height fork normal on the side ``height_side`` = +1 or -1."""

    stride_psi0: float = D(206.5)
    four_bar: int = 1
    height_side: int = 1


def _rotate(v: np.ndarray, angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.sum(a * b, axis=-1)


_wrap = wrap_pi


def grashof_margin(leg: HorseLeg) -> float:
    """Grashof margin of the four-bar O1 A B O4, mm: (sum of the two middle links) - (shortest + longest).

    > 0: the shortest link (the crank r1) turns fully (crank-rocker).  For Section 6 it is
    ``(655 + 44) - (35 + |O1O4|) = 0.14`` mm: a crank-rocker by a hair.
    """
    ground = float(np.hypot(*leg.o4))
    links = sorted([ground, leg.r1, leg.r_ab, leg.r4])
    return links[1] + links[2] - (links[0] + links[3])


def lead_screw_length(leg: HorseLeg, alpha1: float) -> float:
    """Eq. (2): ``(X_O7 - X_O2) cos alpha1 + (Y_O7 - Y_O2) sin alpha1``, mm (= l0 +- s theta3 / 2 pi)."""
    d = leg.point("o7") - leg.point("o2")
    return float(d[0] * math.cos(alpha1) + d[1] * math.sin(alpha1))


# --------------------------------------------------------------------------------------------
# Stride-length loop (eqs. 3-8)
# --------------------------------------------------------------------------------------------
#: |n . d| below which the stride fork's face counts as parallel to the slide (no slide position).
PARALLEL_TOL = 1e-9


def _stride_residual(leg: HorseLeg, cam: Contour, psi: np.ndarray, theta1: np.ndarray, alpha1: float, derivative: bool = True):
    """F(psi) = |R - O6|^2 - r6^2 and dF/dpsi, with Q, R, S, h for fork normals ``psi``."""
    n = _unit(psi)
    n_perp = np.stack([-n[..., 1], n[..., 0]], axis=-1)
    d = np.array([math.cos(alpha1), math.sin(alpha1)])
    p = leg.point("o7") + leg.r_p * np.array([math.cos(alpha1 + math.pi / 2), math.sin(alpha1 + math.pi / 2)])
    h, dh, _ = cam.support_derivatives(psi - theta1)
    nd = n @ d
    parallel = np.abs(nd) < PARALLEL_TOL
    if not derivative:  # the bracketing grid: no position there (NaN), the branch search goes around it
        nd = np.where(parallel, np.nan, nd)
    elif np.any(parallel):
        raise GeometryError("stride-length loop: the fork face is parallel to the slide (n . d = 0)")
    num = h - leg.e2 - n @ p
    s = num / nd
    q = p + s[..., None] * d
    arm = psi + math.pi / 2 + leg.gamma2
    r = q + leg.l1 * _unit(arm)
    rel = r - leg.point("o6")
    f = _dot(rel, rel) - leg.r6**2
    if not derivative:
        return f, None, q, r, s, h
    ds = ((dh - n_perp @ p) * nd - num * (n_perp @ d)) / nd**2
    dr = ds[..., None] * d + leg.l1 * _unit(arm + math.pi / 2)
    return f, 2.0 * _dot(rel, dr), q, r, s, h


def _newton(leg, cam, psi, theta1, alpha1, tol=1e-13, max_iter=30):
    for _ in range(max_iter):
        f, df, *_ = _stride_residual(leg, cam, psi, theta1, alpha1)
        step = f / df
        step = np.clip(step, -0.2, 0.2)  # stay on the branch
        psi = psi - step
        if np.max(np.abs(step)) <= tol:
            return psi, True
    return psi, False


def solve_stride_loop(leg: HorseLeg, cam: Contour, theta1: np.ndarray, alpha1: float, psi0: float,
                      coarse_steps: int = 36, window: float = D(60.0), tol: float = 1e-13) -> np.ndarray:
    """Fork normal psi (rad) at every ``theta1``, by a vectorised Newton with continuation.

    ``psi0`` selects the branch at theta1 = 0.  Continuation without a per-angle loop:
    ``F(psi)`` is evaluated at once on a grid of ``coarse_steps`` cam angles times psi values
    within ``window`` of ``psi0``; its sign changes bracket every root; the branch is followed
    through the coarse angles by taking, at each, the root nearest the previous one among the
    roots where F crosses zero in the same direction (the sign of dF/dpsi is constant along a
    branch: at an assembly limit the branch meets a root of the other sign and ends there,
    and following the nearest root of any sign would jump onto the other assembly, the foot
    1.7 m higher); then all positions are solved together by Newton from the interpolated
    coarse roots (tolerance ``tol`` rad) and each solution is checked to lie on the branch (the
    sign of dF/dpsi) and the branch to close after a turn.  Raises :class:`GeometryError`
    naming the loop and cam angle where the branch ends (beyond the assembly limit).
    """
    def beyond(where: float) -> GeometryError:
        return GeometryError(f"stride-length loop cannot close at cam angle theta1 = {math.degrees(where):.2f} deg for "
                             f"alpha1 = {math.degrees(alpha1):.3f} deg (beyond the assembly limit of this branch)")

    coarse = np.linspace(0.0, 2.0 * math.pi, coarse_steps + 1)
    grid = psi0 + np.linspace(-window, window, 241)
    tt, pp = np.meshgrid(coarse, grid, indexing="ij")
    f, *_ = _stride_residual(leg, cam, pp, tt, alpha1, derivative=False)
    change = np.signbit(f[:, :-1]) != np.signbit(f[:, 1:])
    rising = f[:, 1:] > f[:, :-1]
    with np.errstate(invalid="ignore", divide="ignore"):
        roots = pp[:, :-1] - f[:, :-1] * (pp[:, 1:] - pp[:, :-1]) / (f[:, 1:] - f[:, :-1])
    roots = np.where(change, roots, np.nan)
    psi_c = np.empty(coarse.size)
    current = psi0
    direction = None  # F rising (True) or falling through the branch's root
    for i in range(coarse.size):  # branch following over the coarse angles (not per position)
        candidates = roots[i] if direction is None else np.where(rising[i] == direction, roots[i], np.nan)
        distance = np.abs(candidates - current)
        if np.all(np.isnan(distance)) or np.nanmin(distance) > 0.35:
            raise beyond(coarse[i])
        k = int(np.nanargmin(distance))
        if direction is None:
            direction = bool(rising[i, k])
        current = roots[i, k]
        psi_c[i] = current
    if abs(_wrap(psi_c[-1] - psi_c[0])) > 0.35:  # after a turn the branch must come back to where it started
        raise beyond(coarse[-1])
    guess = np.interp(np.mod(theta1, 2.0 * math.pi), coarse, psi_c)
    psi, ok = _newton(leg, cam, guess, theta1, alpha1, tol)
    f, df, *_ = _stride_residual(leg, cam, psi, theta1, alpha1)
    bad = ~np.isfinite(f) | (np.abs(f) > 1e-6) | (np.abs(_wrap(psi - guess)) > 0.1)
    if not ok or np.any(bad):
        where = float(theta1[np.argmax(bad)]) if np.any(bad) else float(theta1[0])
        raise GeometryError(f"stride-length loop: Newton did not converge at theta1 = {math.degrees(where):.2f} deg, alpha1 = {math.degrees(alpha1):.3f} deg")
    off = (df > 0) != direction  # a root of the other sign: the other assembly (or the fold between them)
    if np.any(off):
        raise beyond(float(theta1[np.argmax(off)]))
    return psi


# --------------------------------------------------------------------------------------------
# Four-bar (eqs. 9-11), lifting loop (eqs. 12-14), leg loop (eqs. 15-17)
# --------------------------------------------------------------------------------------------
def four_bar(leg: HorseLeg, theta1: np.ndarray, branch: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Joint A, joint B and the height-cam angle theta4 (rad) in closed form (circle intersection)."""
    a = leg.r1 * _unit(theta1 + leg.gamma1)
    o4 = leg.point("o4")
    dv = o4 - a
    dist = np.hypot(dv[..., 0], dv[..., 1])
    along = (leg.r_ab**2 - leg.r4**2 + dist**2) / (2.0 * dist)
    across2 = leg.r_ab**2 - along**2
    if np.any(across2 < 0):
        worst = float(theta1[np.argmin(across2)])
        raise GeometryError(f"four-bar O1ABO4 cannot close at theta1 = {math.degrees(worst):.2f} deg")
    perp = np.stack([-dv[..., 1], dv[..., 0]], axis=-1) / dist[..., None]
    b = a + (along / dist)[..., None] * dv + branch * np.sqrt(across2)[..., None] * perp
    theta4 = np.arctan2(b[..., 1] - o4[1], b[..., 0] - o4[0]) - leg.gamma4
    return a, b, theta4


def lifting_loop(leg: HorseLeg, cam: Contour, theta4: np.ndarray, side: int = 1, reference: float | None = None) -> np.ndarray:
    """Height-fork normal psi4 (rad) in closed form: the fork's centre line through O5 stays
    ``r_k - e5`` from the centre ``C_k`` of the active arc k of the height cam.

    Of the two solutions (one per fork face, psi4 and psi4 + pi), the one within 90 deg of
    ``reference`` is kept (``reference``: the solution at the first position on ``side``).
    """
    o5 = leg.point("o5") - leg.point("o4")
    best = np.full(theta4.shape, np.nan)
    found = np.zeros(theta4.shape, dtype=int)
    for seg in cam.segments:
        assert isinstance(seg, Arc)  # the height cam is made of circular arcs (the paper's cam)
        centre = _rotate(np.broadcast_to(np.asarray(seg.center), theta4.shape + (2,)), theta4)
        dv = o5 - centre
        dist = np.hypot(dv[..., 0], dv[..., 1])
        ratio = (seg.radius - leg.e5) / dist
        ok = np.abs(ratio) <= 1.0
        delta = np.arctan2(dv[..., 1], dv[..., 0])
        for sgn in (1.0, -1.0):
            psi = delta + sgn * np.arccos(np.clip(ratio, -1.0, 1.0))
            local = np.mod(psi - theta4 - seg.start_angle, 2.0 * math.pi)
            on_arc = ok & ((local <= seg.sweep + 1e-12) | (local >= 2.0 * math.pi - 1e-12))
            if reference is None:
                ref = np.where(found == 0, np.nan, best)
            else:
                ref = np.full(theta4.shape, reference)
            keep = on_arc & (np.isnan(best) if reference is None else (np.cos(psi - ref) > 0))
            best = np.where(keep & np.isnan(best), psi, best)
            found = found + keep
    if np.any(np.isnan(best)):
        worst = float(theta4[np.argmax(np.isnan(best))])
        raise GeometryError(f"lifting loop O1O4KK'O5 cannot close at theta4 = {math.degrees(worst):.2f} deg")
    return best


def leg_loop(leg: HorseLeg, s_point: np.ndarray, t_point: np.ndarray, theta1: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Slider length l (mm) and leg angle theta8 (rad): ``S - T = e^{j theta8} (r8 - l e^{j theta_U})``.

    ``|S - T|^2 = r8^2 + l^2 - 2 r8 l cos(theta_U)``: the positive root of this quadratic.
    """
    rel = s_point - t_point
    d2 = _dot(rel, rel)
    disc = d2 - (leg.r8 * math.sin(leg.theta_u)) ** 2

    def where(bad: np.ndarray) -> str:
        return "" if theta1 is None else f" at theta1 = {math.degrees(float(np.asarray(theta1)[np.argmax(bad)])):.2f} deg"

    if np.any(disc < 0):
        raise GeometryError(f"leg loop O1O5SUTO6 cannot close{where(disc < 0)}: S is too close to T")
    length = leg.r8 * math.cos(leg.theta_u) + np.sqrt(disc)
    if np.any(length <= 0):
        raise GeometryError(f"leg loop O1O5SUTO6{where(length <= 0)}: the slider S would leave the leg's slideway (l <= 0)")
    zeta = np.arctan2(rel[..., 1], rel[..., 0])
    theta8 = zeta - np.angle(leg.r8 - length * np.exp(1j * leg.theta_u))
    return length, theta8


# --------------------------------------------------------------------------------------------
# Whole leg
# --------------------------------------------------------------------------------------------
@dataclass
class LegSolution:
    """Every solved quantity at the cam angles ``theta1`` (arrays, mm and rad)."""

    alpha1: float
    theta1: np.ndarray
    psi: np.ndarray  # stride fork normal (fixed frame)
    q: np.ndarray
    r: np.ndarray
    s: np.ndarray  # slide position along the swing rod
    h: np.ndarray  # contact offset along the stride fork face
    contact: np.ndarray  # N
    phi1: np.ndarray
    beta1: np.ndarray
    radius1: np.ndarray  # R1 = |ON|
    theta6: np.ndarray
    a: np.ndarray
    b: np.ndarray
    theta4: np.ndarray
    psi4: np.ndarray
    contact4: np.ndarray  # K
    phi4: np.ndarray
    beta4: np.ndarray
    radius4: np.ndarray
    h4: np.ndarray  # h'
    theta5: np.ndarray
    s_point: np.ndarray
    t_point: np.ndarray
    u_point: np.ndarray
    slider: np.ndarray  # l
    theta8: np.ndarray
    w: np.ndarray
    pressure_angle: np.ndarray = field(default_factory=lambda: np.zeros(0))


def leg_cams(leg: HorseLeg) -> tuple[Contour, Contour]:
    """The leg's stride and height cams (paper 000's three-arc cams of ``leg``)."""
    from camgen.synthesis.three_arc import three_arc_cam

    return three_arc_cam(*leg.stride_cam), three_arc_cam(*leg.height_cam)


@dataclass(frozen=True)
class _HeightSide:
    """The parts of the leg that do not depend on alpha1: the four-bar, the lifting loop and
    the point S of the leg loop, at the cam angles ``theta1`` (mm, rad)."""

    a: np.ndarray
    b: np.ndarray
    theta4: np.ndarray
    psi4: np.ndarray
    k_cam: np.ndarray
    theta5: np.ndarray
    s_point: np.ndarray


def _height_side(leg: HorseLeg, height: Contour, theta1: np.ndarray, branches: Branches) -> _HeightSide:
    a, b, theta4 = four_bar(leg, theta1, branches.four_bar)
    first = lifting_loop(leg, height, theta4[:1], branches.height_side)
    ref = float(first[0]) if branches.height_side > 0 else float(first[0]) + math.pi
    psi4 = lifting_loop(leg, height, theta4, reference=ref)
    _, k_cam = height.support_point(psi4 - theta4)
    theta5 = 1.5 * math.pi + psi4 - leg.gamma5
    s_point = leg.point("o5") + leg.r5 * _unit(theta5)
    return _HeightSide(a, b, theta4, psi4, k_cam, theta5, s_point)


def _rocker_angle(leg: HorseLeg, r: np.ndarray) -> np.ndarray:
    return np.arctan2(r[..., 1] - leg.o6[1], r[..., 0] - leg.o6[0])


def solve_leg(leg: HorseLeg, alpha1: float, theta1: np.ndarray, branches: Branches = Branches(),
              cams: tuple[Contour, Contour] | None = None) -> LegSolution:
    """Solve all loops at the cam angles ``theta1`` (rad) for the inclination ``alpha1`` (rad)."""
    alpha1 = require_finite("alpha1", alpha1)
    theta1 = np.asarray(theta1, dtype=float)
    stride, height = cams if cams is not None else leg_cams(leg)
    psi = solve_stride_loop(leg, stride, theta1, alpha1, branches.stride_psi0)
    _, _, q, r, s, _ = _stride_residual(leg, stride, psi, theta1, alpha1, derivative=False)
    _, contact_cam = stride.support_point(psi - theta1)
    contact = _rotate(contact_cam, theta1)
    tangent = _unit(psi + math.pi / 2)
    h = _dot(q + leg.e2 * _unit(psi) - contact, tangent)  # eq. (4): N + h t - e2 n = Q
    phi1 = _wrap(np.arctan2(contact_cam[..., 1], contact_cam[..., 0]))
    beta1 = np.abs(_wrap(psi - theta1 - phi1))
    theta6 = _rocker_angle(leg, r)
    side = _height_side(leg, height, theta1, branches)
    a, b, theta4, psi4, k_cam = side.a, side.b, side.theta4, side.psi4, side.k_cam
    contact4 = leg.point("o4") + _rotate(k_cam, theta4)
    h4 = _dot(leg.point("o5") + leg.e5 * _unit(psi4) - contact4, _unit(psi4 + math.pi / 2))
    phi4 = _wrap(np.arctan2(k_cam[..., 1], k_cam[..., 0]))
    beta4 = np.abs(_wrap(psi4 - theta4 - phi4))
    theta5, s_point = side.theta5, side.s_point
    t_point = leg.point("o6") + leg.r7 * _unit(theta6 + leg.gamma6)
    slider, theta8 = leg_loop(leg, s_point, t_point, theta1)
    u_point = t_point + leg.r8 * _unit(theta8)
    w = u_point + leg.s8 * _unit(math.pi + theta8 - leg.theta_p)  # eq. (18)
    sol = LegSolution(
        alpha1, theta1, psi, q, r, s, h, contact, phi1, beta1, np.hypot(contact[..., 0], contact[..., 1]),
        theta6, a, b, theta4, psi4, contact4, phi4, beta4, np.hypot(*(contact4 - leg.point("o4")).T), h4,
        theta5, s_point, t_point, u_point, slider, theta8, w,
    )
    sol.pressure_angle = pressure_angle(leg, sol)
    return sol


#: Scan of :func:`assembly_range`: the inclinations tried (rad), the step (rad) and the positions
#: per turn of the scan; the ends found are refined by bisection to ``ASSEMBLY_TOL`` (rad).
ASSEMBLY_SCAN = (D(-90.0), D(90.0))
ASSEMBLY_STEP = D(1.0)
ASSEMBLY_SCAN_POSITIONS = 72
ASSEMBLY_TOL = D(1e-3)


def assembly_range(leg: HorseLeg, positions: int = 3600, branches: Branches = Branches(),
                   cams: tuple[Contour, Contour] | None = None, scan: tuple[float, float] = ASSEMBLY_SCAN,
                   step: float = ASSEMBLY_STEP, tol: float = ASSEMBLY_TOL) -> list[tuple[float, float]]:
    """The intervals of alpha1 (rad) at which every loop of the leg closes on the branch
    ``branches`` at ``positions`` cam angles per turn.

    The inclinations ``scan[0], scan[0] + step, ...`` are tried at ``ASSEMBLY_SCAN_POSITIONS``
    cam angles (an interval narrower than ``step`` may be missed); each end found is refined by
    bisection to ``tol`` at ``positions`` cam angles, and returned on the side where the leg
    assembles.  The alpha1-independent loops (four-bar, lifting loop) are solved once: when
    they cannot close, their :class:`GeometryError` is raised (no inclination helps).
    For the paper's leg and cams (Section 6): 9.382 to 20.111 deg (3600 positions; test_limits.py
    checks both ends against an independent root count of the paper's eqs. 4-8).
    """
    stride, height = cams if cams is not None else leg_cams(leg)
    grids = {n: cycle(n) for n in (ASSEMBLY_SCAN_POSITIONS, positions)}
    sides = {n: _height_side(leg, height, theta1, branches) for n, theta1 in grids.items()}

    def closes(alpha: float, n: int) -> bool:
        theta1 = grids[n]
        try:
            psi = solve_stride_loop(leg, stride, theta1, alpha, branches.stride_psi0)
            _, _, _, r, _, _ = _stride_residual(leg, stride, psi, theta1, alpha, derivative=False)
            t_point = leg.point("o6") + leg.r7 * _unit(_rocker_angle(leg, r) + leg.gamma6)
            leg_loop(leg, sides[n].s_point, t_point)
        except GeometryError:
            return False
        return True

    alphas = np.arange(scan[0], scan[1] + 0.5 * step, step)
    ok = np.array([closes(float(a), ASSEMBLY_SCAN_POSITIONS) for a in alphas])
    return _refined_runs(alphas, ok, lambda alpha: closes(alpha, positions), tol)


def _refined_runs(alphas: np.ndarray, ok: np.ndarray, holds: Any, tol: float) -> list[tuple[float, float]]:
    """The runs of ``ok`` over the increasing inclinations ``alphas`` (rad) as intervals whose
    inner ends (not the first or last of ``alphas``) are refined by bisection with ``holds``
    to ``tol``; each end is returned on the side where ``holds`` is true."""

    def refine(inside: float, outside: float) -> float:
        for _ in range(60):
            if abs(outside - inside) <= tol:
                break
            mid = 0.5 * (inside + outside)
            inside, outside = (mid, outside) if holds(mid) else (inside, mid)
        return inside

    out = []
    i = 0
    while i < alphas.size:
        if not ok[i]:
            i += 1
            continue
        j = i
        while j + 1 < alphas.size and ok[j + 1]:
            j += 1
        lo = float(alphas[i]) if i == 0 else refine(float(alphas[i]), float(alphas[i - 1]))
        hi = float(alphas[j]) if j == alphas.size - 1 else refine(float(alphas[j]), float(alphas[j + 1]))
        out.append((lo, hi))
        i = j + 1
    return out


def ground_crossings(y: np.ndarray, ground: float) -> np.ndarray:
    """Indices ``i`` of the closed foot path's samples where it crosses the ground line
    ``y = ground`` between sample ``i`` and the next (above: ``y > ground``)."""
    above = y > ground
    return np.nonzero(above != np.roll(above, -1))[0]


def ground_lines(y: np.ndarray) -> list[tuple[float, float]]:
    """The ground lines ``g`` (mm) that the closed foot path of heights ``y`` (mm, samples in
    order) crosses exactly twice (one swing, one stance): a list of half-open intervals
    ``[low, high)``, as :func:`ground_crossings` counts crossings.

    The sample pair (i, i + 1) is crossed by every ``g`` with ``min <= g < max`` of the two
    heights; the count over ``g`` is a running sum of +1 at each pair's lower height and -1 at
    its upper one (exact for the samples, no scan over ``g``)."""
    y = np.asarray(y, dtype=float)
    nxt = np.roll(y, -1)
    lo, hi = np.minimum(y, nxt), np.maximum(y, nxt)
    moving = lo < hi
    events = np.concatenate([lo[moving], hi[moving]])
    steps = np.concatenate([np.ones(int(moving.sum()), dtype=int), -np.ones(int(moving.sum()), dtype=int)])
    order = np.argsort(events, kind="stable")
    events, steps = events[order], steps[order]
    levels, first = np.unique(events, return_index=True)
    count = np.cumsum(steps)[np.append(first[1:] - 1, events.size - 1)]  # crossings on [levels[k], levels[k + 1])
    two = np.append(count[:-1] == 2, False)
    out = []
    k = 0
    while k < levels.size - 1:
        if two[k]:
            start = k
            while two[k + 1]:
                k += 1
            out.append((float(levels[start]), float(levels[k + 1])))
        k += 1
    return out


def gait_range(leg: HorseLeg, positions: int = 3600, branches: Branches = Branches(),
               cams: tuple[Contour, Contour] | None = None, assembly: list[tuple[float, float]] | None = None,
               step: float = ASSEMBLY_STEP, tol: float = ASSEMBLY_TOL) -> list[tuple[float, float]]:
    """The intervals of alpha1 (rad) at which the leg assembles (:func:`assembly_range`, or
    ``assembly``) and its foot path at ``positions`` cam angles crosses the ground line
    ``leg.ground_y`` exactly twice: one swing above it and one stance on it.

    Each assembly interval is tried at its ends and every ``step`` between; each end found is
    refined by bisection to ``tol`` and returned on the side where the foot walks.  For the
    paper's leg, cams and ground line (-2074 mm): 9.382 to 19.717 deg (3600 positions): above,
    the foot path's lowest point rises above the ground line (-2060.2 mm at 20.111 deg), so the
    foot never reaches the ground although the leg still assembles.
    """
    stride, height = cams if cams is not None else leg_cams(leg)
    if assembly is None:
        assembly = assembly_range(leg, positions, branches, (stride, height), step=step, tol=tol)
    theta1 = cycle(positions)

    def walks(alpha: float) -> bool:
        try:
            sol = solve_leg(leg, alpha, theta1, branches, (stride, height))
        except GeometryError:
            return False
        return ground_crossings(sol.w[:, 1], leg.ground_y).size == 2

    out: list[tuple[float, float]] = []
    for lo, hi in assembly:
        inner = np.arange(lo + step, hi, step)
        alphas = np.concatenate([[lo], inner[inner < hi - 0.5 * tol], [hi]])
        ok = np.array([walks(float(a)) for a in alphas])
        out.extend(_refined_runs(alphas, ok, walks, tol))
    return out


def pressure_angle(leg: HorseLeg, sol: LegSolution, literal: bool = False) -> np.ndarray:
    """Stride-cam pressure angle (rad, acute) by eqs. (19)-(25).

    P' (the fork's instant centre) is where the rocker line O6R meets the line through Q
    perpendicular to the slide: eq. (20) with the slide term ``S e^{j alpha1}`` of eq. (4).
    ``literal=True`` uses eq. (20) as printed, ``S e^{j(alpha1 + pi)}``.  Then
    ``alpha = theta_N + pi/2 - psi`` with theta_N the direction P' -> N (eq. 25), folded to
    the acute angle between the contact normal and the contact point's velocity.
    """
    a1 = sol.alpha1
    slide = -sol.s if literal else sol.s
    q_used = leg.point("o7") + leg.r_p * np.array([math.cos(a1 + math.pi / 2), math.sin(a1 + math.pi / 2)]) + slide[..., None] * np.array([math.cos(a1), math.sin(a1)])
    e6 = _unit(sol.theta6)
    ep = np.broadcast_to(np.array([math.cos(a1 - math.pi / 2), math.sin(a1 - math.pi / 2)]), e6.shape)
    # O6 + l4 e6 = Q + l3 ep  ->  [e6, -ep] [l4, l3] = Q - O6
    rhs = q_used - leg.point("o6")
    det = e6[..., 0] * (-ep[..., 1]) - e6[..., 1] * (-ep[..., 0])
    num = rhs[..., 0] * (-ep[..., 1]) - rhs[..., 1] * (-ep[..., 0])
    parallel = det == 0.0  # the rocker line parallel to the slide's normal: P' at infinity
    l4 = num / np.where(parallel, 1.0, det)
    centre = leg.point("o6") + l4[..., None] * e6
    to_contact = sol.contact - centre
    if np.any(parallel):  # N - P' is then along -num e6 (only its direction counts: the angle is folded below)
        to_contact = np.where(parallel[..., None], -num[..., None] * e6, to_contact)
    theta_n = np.arctan2(to_contact[..., 1], to_contact[..., 0])
    alpha = np.abs(_wrap(theta_n + math.pi / 2 - sol.psi))
    return np.minimum(alpha, math.pi - alpha)


def height_fork_pressure_angle(leg: HorseLeg, sol: LegSolution) -> np.ndarray:
    """Pressure angle (rad, acute) of the stride-height cam on its fork, which swings about O5:
    the fork point at the contact K moves perpendicular to O5K."""
    rel = sol.contact4 - leg.point("o5")
    velocity = np.arctan2(rel[..., 1], rel[..., 0]) + math.pi / 2
    alpha = np.abs(_wrap(sol.psi4 - velocity))
    return np.minimum(alpha, math.pi - alpha)


# --------------------------------------------------------------------------------------------
# Gait figures (Section 6.1)
# --------------------------------------------------------------------------------------------
def gait_figures(leg: HorseLeg, sol: LegSolution) -> dict[str, Any]:
    """Section 6.1's figures for one inclination (mm, deg).

    The ground line ``y = ground_y`` crosses the closed foot path at W1 (lift-off, the path
    rising through it) and W4 (touch-down).  Swing: the part above the line; stance: the part
    below, during which the foot stays on the ground and the body moves along the point
    reflection of the foot path (Section 3: W40-W50-W60-W10 antisymmetric to W4-W5-W6-W1).
    """
    x, y = sol.w[:, 0], sol.w[:, 1]
    ground = leg.ground_y
    above = y > ground
    crossings = ground_crossings(y, ground)
    if crossings.size != 2:
        where = ("its lowest point is above the line: the foot does not reach the ground" if y.min() > ground
                 else "its highest point is below the line: the foot never lifts" if y.max() <= ground
                 else "it dips below the line more than once")
        raise GeometryError(
            f"alpha1 = {math.degrees(sol.alpha1):.3f} deg: the foot path (y from {float(y.min()):.1f} to {float(y.max()):.1f} mm) "
            f"crosses the ground line y = {ground:g} mm {crossings.size} times (need 2: one swing, one stance): {where}"
        )

    def cross(i: int) -> np.ndarray:  # linear interpolation between samples i and i + 1
        j = (i + 1) % y.size
        f = (ground - y[i]) / (y[j] - y[i])
        return sol.w[i] + f * (sol.w[j] - sol.w[i])

    points = [cross(i) for i in crossings]
    rising = [not above[i] for i in crossings]
    w1 = points[rising.index(True)]
    w4 = points[rising.index(False)]
    swing_x = np.concatenate([x[above], [w1[0], w4[0]]])
    stance_x = np.concatenate([x[~above], [w1[0], w4[0]]])
    return {
        "alpha1_deg": math.degrees(sol.alpha1),
        "lift_mm": float(y.max() - ground),
        "leg_horizontal_mm": float(np.ptp(swing_x)),
        "body_height_change_mm": float(ground - y.min()),
        "body_horizontal_mm": float(np.ptp(stance_x)),
        "stride_mm": float(abs(w4[0] - w1[0])),
        "max_pressure_angle_deg": float(np.degrees(sol.pressure_angle.max())),
        "max_pressure_angle_at_theta1_deg": float(np.degrees(sol.theta1[np.argmax(sol.pressure_angle)])),
        "grashof_margin_mm": grashof_margin(leg),
        "w1_mm": [float(w1[0]), float(w1[1])],
        "w4_mm": [float(w4[0]), float(w4[1])],
        "ground_y_mm": ground,
        "lead_screw_length_mm": lead_screw_length(leg, sol.alpha1),
    }


def body_path(leg: HorseLeg, sol: LegSolution) -> np.ndarray:
    """Body (O1) positions (mm) during stance, in a ground frame where the foot stands at W4:
    the foot is fixed, so the body moves by minus the foot's motion relative to the body."""
    stance = sol.w[:, 1] <= leg.ground_y
    figures = gait_figures(leg, sol)
    w4 = np.asarray(figures["w4_mm"])
    return w4 - sol.w[stance]


def branch_table(leg: HorseLeg, alpha1: float, theta1: np.ndarray) -> list[dict[str, Any]]:
    """Every assembly branch at ``alpha1``: where the foot goes (or why the branch fails)."""
    stride, height = leg_cams(leg)
    rows = []
    for psi0 in (D(206.5), D(221.5)):
        for fb in (1, -1):
            for side in (1, -1):
                row: dict[str, Any] = {"stride_psi0_deg": math.degrees(psi0), "four_bar": fb, "height_side": side}
                try:
                    sol = solve_leg(leg, alpha1, theta1, Branches(psi0, fb, side), (stride, height))
                    row.update(
                        foot_y_range_mm=[float(sol.w[:, 1].min()), float(sol.w[:, 1].max())],
                        foot_x_range_mm=[float(sol.w[:, 0].min()), float(sol.w[:, 0].max())],
                        max_pressure_angle_deg=float(np.degrees(sol.pressure_angle.max())),
                    )
                except GeometryError as exc:
                    row["error"] = str(exc)
                rows.append(row)
    return rows


def cycle(n: int = 3600) -> np.ndarray:
    """theta1 = 0, 360/n, ..., 360 - 360/n deg, in rad."""
    if isinstance(n, bool) or not isinstance(n, int) or n < 36:
        raise ParameterError("positions", n, "an integer >= 36")
    return 2.0 * math.pi * np.arange(n) / n
