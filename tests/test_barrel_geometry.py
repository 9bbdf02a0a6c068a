"""Barrel (cylindrical) cams: the exact groove walls of camgen.synthesis.barrel against references
computed here without camgen's contact formulas.

* The walls: the issue's brute force, the groove as the union of the roller solids (api.md):
  ``z_upper(r, phi) = max over theta of [z_c + sqrt(w^2 - (r sin(phi + sigma theta) - e)^2)]`` and
  its lower twin; the cone's (apex on the axis at the roller axis' height, slope ``k = w / R_m``):
  a point is inside when its distance from the roller axis line is below ``k`` times its distance
  along it.  The maximum over a dense grid of theta is polished by scipy's bounded Brent
  minimiser.  The follower's motion comes from the laws in closed form (Norton, *Design of
  Machinery*, ch. 8: cycloidal ``S = u - sin(2 pi u) / (2 pi)``, 3-4-5 ``S = 10 u^3 - 15 u^4 +
  6 u^5``) and the arm geometry of api.md, not from camgen.
* The pressure angle: the issue's figures (40.3 deg at the root, 37.4 deg at the mean radius);
  ``atan(s' / r)`` for a translating roller (the developed cam: e.g. Rothbart, *Cam Design
  Handbook*, 2004, the cylindrical cam); for both followers, its definition computed by brute
  force: the contact found on the roller section as the point of the circle the union of the
  other roller positions does not cover, the velocity by a finite difference of the roller axis.
* The wrapped-groove approximation: the issue's figures (0.436 mm, 0.324 mm, 0.87 mm) and a
  developed offset polyline built here.
* The undercut: where camgen says the section folds, a neighbouring roller position cuts the
  contact away (brute force over theta near it); elsewhere none does.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from camgen.synthesis.barrel import BarrelGroove, BarrelLayout
from camgen.synthesis.laws import MotionProgram, Segment

#: The walls agree with the brute force within this (mm): the issue's requirement.
WALL_TOL = 1e-6
#: The brute-force pressure angle (contact by a polished grid, velocity by a central difference).
ANGLE_TOL = 1e-6
DEG = math.pi / 180.0

# the issue's example: R_m 50 mm, groove depth 10 mm, a 40 mm cycloidal rise over 120 deg
R_O, R_I, R_M = 55.0, 45.0, 50.0
RISE, RISE_SPAN = 40.0, 120.0 * DEG
SWING = 25.0 * DEG
ARM, PIVOT_Z, REST = 80.0, 35.0, -12.5 * DEG


def norton_program(h: float, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """s and ds/dtheta of: cycloidal rise h over 120 deg, dwell 60 deg, 3-4-5 return over 120 deg,
    dwell 60 deg (Norton, ch. 8, closed forms), periodic."""
    th = np.mod(theta, 2.0 * math.pi)
    u = np.clip(th / RISE_SPAN, 0.0, 1.0)
    v = np.clip((th - 180.0 * DEG) / RISE_SPAN, 0.0, 1.0)
    rising, falling = (th < RISE_SPAN), (th >= 180.0 * DEG) & (th < 300.0 * DEG)
    s = h * (u - np.sin(2 * math.pi * u) / (2 * math.pi)) - h * (10 * v**3 - 15 * v**4 + 6 * v**5)
    ds = np.where(rising, h * (1 - np.cos(2 * math.pi * u)) / RISE_SPAN, 0.0)
    ds = ds - np.where(falling, h * (30 * v**2 - 60 * v**3 + 30 * v**4) / RISE_SPAN, 0.0)
    return s, ds


def camgen_program(h: float, unit: str = "mm") -> MotionProgram:
    """The same program from camgen's law machinery (what the groove is built from)."""
    return MotionProgram([Segment("cycloidal", RISE_SPAN, h), Segment("dwell", 60 * DEG),
                          Segment("poly345", RISE_SPAN, -h), Segment("dwell", 60 * DEG)], unit=unit)


class Follower:
    """The roller axis from api.md's conventions: ``(e, z_c)`` at cam angles, and its shape."""

    def __init__(self, motion: str, sigma: int, w: float, shape: str = "cylindrical", z0: float = 10.0):
        self.motion, self.sigma, self.w, self.shape, self.z0 = motion, sigma, w, shape, z0

    def axis(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if self.motion == "translating":
            s, _ = norton_program(RISE, theta)
            return np.zeros_like(s), self.z0 + s
        psi = REST + norton_program(SWING, theta)[0]
        return ARM * (np.cos(psi) - 1.0), PIVOT_Z + ARM * np.sin(psi)

    def covered(self, r: float, phi: float, z: float, theta: np.ndarray) -> np.ndarray:
        """How far inside the roller at each theta the cam point (r, phi, z) is (mm; > 0 inside),
        NaN where it is behind the cam axis."""
        e, zc = self.axis(theta)
        x, y = r * np.cos(phi + self.sigma * theta), r * np.sin(phi + self.sigma * theta)
        radius = self.w * x / R_M if self.shape == "conical" else self.w
        return np.where(x > 0.0, radius - np.hypot(y - e, z - zc), np.nan)

    def cut_height(self, side: int, r: float, phi: float, theta: np.ndarray) -> np.ndarray:
        """``z_c + side * sqrt(radius^2 - offset^2)``: the cut's edge at each theta (NaN: misses)."""
        e, zc = self.axis(theta)
        x, y = r * np.cos(phi + self.sigma * theta), r * np.sin(phi + self.sigma * theta)
        radius = self.w * x / R_M if self.shape == "conical" else self.w
        half = radius * radius - (y - e) ** 2
        return np.where((x > 0.0) & (half >= 0.0), zc + side * np.sqrt(np.abs(half)), np.nan)

    def brute_wall(self, side: int, r: float, phi: float) -> float:
        """The issue's brute force: the extreme edge over theta (grid, then Brent on the bracket)."""
        centre = -self.sigma * phi
        grid = centre + np.linspace(-0.6, 0.6, 12001)
        h = side * self.cut_height(side, r, phi, grid)
        k = int(np.nanargmax(h))
        step = grid[1] - grid[0]
        res = minimize_scalar(lambda t: -side * float(self.cut_height(side, r, phi, np.array([t]))[0]),
                              bounds=(grid[k] - step, grid[k] + step), method="bounded", options={"xatol": 1e-13})
        return max(float(h[k]), -float(res.fun)) * side


def groove(motion: str, sigma: int, roller: float, shape: str = "cylindrical", clearance: float = 0.0) -> BarrelGroove:
    if motion == "translating":
        layout = BarrelLayout("translating", sigma, roller, shape, R_M, 10.0)
        law = camgen_program(RISE)
    else:
        layout = BarrelLayout("oscillating", sigma, roller, shape, R_M, PIVOT_Z, arm_length=ARM, rest_angle=REST)
        law = camgen_program(SWING, "rad")
    return BarrelGroove(layout, law, R_O, R_I, 70.0, 0.0, clearance, 1e-3)


# cam angles in the rise, the dwells, the return (both laws) and at its steepest points
THETAS = np.array([0.1, 35.0, 60.0, 100.0, 150.0, 200.0, 240.0, 275.0, 330.0]) * DEG
CASES = [(m, s, shape) for m, shape in (("translating", "cylindrical"), ("oscillating", "cylindrical"),
                                        ("translating", "conical")) for s in (1, -1)]


@pytest.mark.parametrize("motion, sigma, shape", CASES)
def test_walls_match_the_union_of_roller_solids(motion, sigma, shape):
    g = groove(motion, sigma, 4.0, shape, clearance=0.3)
    ref = Follower(motion, sigma, 4.15, shape)
    worst = 0.0
    for side in (1, -1):
        for r in (R_I, R_M, R_O):
            phi, z = g.wall(side, r, THETAS)
            # the contact point at theta lies on the wall there (max/min over every theta)
            bf = np.array([ref.brute_wall(side, r, p) for p in phi])
            worst = max(worst, float(np.max(np.abs(z - bf))))
            # and the wall at any angle: between the contacts, in the dwell, across the pitch
            anywhere = -sigma * np.array([13.0, 88.0, 163.0, 251.0, 299.0]) * DEG + 0.004
            zh = g.wall_height(side, r, anywhere)
            bf = np.array([ref.brute_wall(side, r, p) for p in anywhere])
            worst = max(worst, float(np.max(np.abs(zh - bf))))
    assert worst < WALL_TOL, f"largest distance from the brute-force wall: {worst:.3g} mm"


def brute_pressure_angle(ref: Follower, r: float, theta: float) -> float:
    """The pressure angle by its definition, without the envelope condition: the upper contact on
    the roller section whose centre is at distance r from the cam axis is the point of that circle
    no other roller position covers (it minimises the depth to which the other positions cover
    it); the wall normal there is the circle's; the roller axis' velocity is a central difference.
    Signed: the angle from the direction of a positive lift to the normal, counted the way the cam
    turns seen from +x (> 0 on a translating rise)."""
    e0, z0 = (float(v[0]) for v in ref.axis(np.array([theta])))
    t = math.sqrt(r * r - e0 * e0)
    sig = ref.sigma
    around = theta + np.linspace(-0.25, 0.25, 2501)

    def depth(b: float) -> float:
        # the circle's point at angle b (from +z), taken into the cam frame, then looked for in the
        # roller at every other cam angle
        y, z = e0 + ref.w * math.sin(b), z0 + ref.w * math.cos(b)
        rr, phi = math.hypot(t, y), math.atan2(y, t) - sig * theta
        k = ref.covered(rr, phi, z, around)
        i = int(np.nanargmax(k))
        res = minimize_scalar(lambda q: -float(ref.covered(rr, phi, z, np.array([q]))[0]),
                              bounds=(around[max(i - 1, 0)], around[min(i + 1, around.size - 1)]), method="bounded",
                              options={"xatol": 1e-12})
        return max(float(k[i]), -float(res.fun))

    bs = np.linspace(-1.4, 1.4, 141)
    j = int(np.argmin([depth(b) for b in bs]))
    b = minimize_scalar(depth, bounds=(bs[max(j - 1, 0)], bs[min(j + 1, bs.size - 1)]), method="bounded",
                        options={"xatol": 1e-10}).x
    h = 1e-6
    (ea, za), (eb, zb) = (tuple(float(v[0]) for v in ref.axis(np.array([theta + d]))) for d in (h, -h))
    vy, vz = (ea - eb) / (2 * h), (za - zb) / (2 * h)
    speed = math.copysign(math.hypot(vy, vz), vz)  # the direction of a positive lift points up
    dy, dz = vy / speed, vz / speed
    ny, nz = math.sin(b), math.cos(b)
    # the angle from the lift direction to the normal, counted the way the cam turns
    return math.atan2(sig * (ny * dz - nz * dy), ny * dy + nz * dz)


def test_pressure_angle_the_issue_figures():
    g = groove("translating", 1, 4.0)
    theta = np.linspace(0.0, RISE_SPAN, 4001)
    root = np.degrees(np.max(g.pressure_angle(R_I, theta)))
    mean = np.degrees(np.max(g.pressure_angle(R_M, theta)))
    rim = np.degrees(np.max(g.pressure_angle(R_O, theta)))
    assert (round(root, 1), round(mean, 1)) == (40.3, 37.4)
    assert root > mean > rim  # largest at the root


@pytest.mark.parametrize("sigma", [1, -1])
def test_pressure_angle_translating_closed_form(sigma):
    g = groove("translating", sigma, 4.0)
    theta = np.linspace(0.0, 2 * math.pi, 721)
    _, ds = norton_program(RISE, theta)
    for r in (R_I, R_M, R_O):
        assert np.max(np.abs(g.pressure_angle(r, theta) - np.arctan(ds / r))) < 1e-12


@pytest.mark.parametrize("motion, sigma", [("translating", 1), ("oscillating", 1), ("oscillating", -1)])
def test_pressure_angle_by_its_definition(motion, sigma):
    g = groove(motion, sigma, 4.0)
    ref = Follower(motion, sigma, 4.0)
    for theta in (35.0 * DEG, 60.0 * DEG, 215.0 * DEG):
        for r in (R_I, R_O):
            got = float(g.pressure_angle(r, theta))
            want = brute_pressure_angle(ref, r, theta)
            assert abs(got - want) < ANGLE_TOL, (theta, r, math.degrees(got), math.degrees(want))


def developed_offset_wall(side: int, w: float, phi: np.ndarray) -> np.ndarray:
    """The wrapped groove built here: the developed pitch curve (x = -R_m theta, z = z0 + s) as a
    dense polyline, offset by side * w along its normal, read at x = R_m phi by interpolation."""
    theta = np.linspace(-0.5, 2.5, 600001)
    s, ds = norton_program(RISE, theta)
    x, z = -R_M * theta, 10.0 + s
    dx, dz = -R_M * np.ones_like(theta), ds
    n = np.hypot(dx, dz)
    ox, oz = x + side * w * dz / n, z - side * w * dx / n  # the normal with +z: (dz, -dx) / n for dx < 0
    order = np.argsort(ox)
    return np.interp(R_M * phi, ox[order], oz[order])


def test_wrapped_groove_the_issue_figures():
    """The issue's figures come out with a roller of radius 8 mm (its "8 mm cylindrical roller" read
    as the radius; no clearance), the error being the largest over the angle on each wall, and the
    groove's narrowing at the bottom the two walls' largest errors added (2 x 0.436).  With a
    roller of 8 mm diameter the errors are about half."""
    g = groove("translating", 1, 8.0)
    phi = -np.linspace(20.0, 100.0, 2001) * DEG
    low_root = np.max(g.wall_height(1, R_I, phi) - g.wrapped_wall_height(1, R_I, phi))
    high_rim = np.max(g.wrapped_wall_height(1, R_O, phi) - g.wall_height(1, R_O, phi))
    lower_high_root = np.max(g.wrapped_wall_height(-1, R_I, phi) - g.wall_height(-1, R_I, phi))
    assert round(low_root, 3) == 0.436
    assert round(high_rim, 3) == 0.324
    assert round(low_root + lower_high_root, 2) == 0.87
    # the extremes confirmed on the brute-force wall and the wrapped groove built here
    ref = Follower("translating", 1, 8.0)
    k = int(np.argmax(g.wall_height(1, R_I, phi) - g.wrapped_wall_height(1, R_I, phi)))
    assert abs(ref.brute_wall(1, R_I, phi[k]) - developed_offset_wall(1, 8.0, phi[k:k + 1])[0] - low_root) < 1e-6
    assert np.max(np.abs(g.wrapped_wall_height(1, R_O, phi[::100]) - developed_offset_wall(1, 8.0, phi[::100]))) < 1e-6


def test_undercut_where_the_section_folds():
    """A steep rise at a small radius with a wide roller: where camgen says the upper wall's
    section folds, roller positions next to the contact cut it away (brute force over theta near
    it); where it says not, the contact is the highest cut nearby (a local maximum over theta)."""
    layout = BarrelLayout("translating", 1, 9.0, "cylindrical", 14.0, 10.0)
    law = MotionProgram([Segment("cycloidal", 40 * DEG, 40.0), Segment("dwell", 140 * DEG),
                         Segment("cycloidal", 40 * DEG, -40.0), Segment("dwell", 140 * DEG)])
    g = BarrelGroove(layout, law, 16.0, 12.0, 70.0, 0.0, 0.0, 1e-3)
    ref = Follower("translating", 1, 9.0)
    # the test's own law: the same cycloids (Norton, ch. 8)

    def axis(theta):
        th = np.mod(theta, 2 * math.pi)
        u = np.clip(th / (40 * DEG), 0, 1)
        v = np.clip((th - 180 * DEG) / (40 * DEG), 0, 1)
        s = 40 * (u - np.sin(2 * math.pi * u) / (2 * math.pi)) - 40 * (v - np.sin(2 * math.pi * v) / (2 * math.pi))
        return np.zeros_like(s), 10.0 + s

    ref.axis = axis
    r = 12.0
    theta = np.linspace(0.0, 40 * DEG, 401)
    folded = g.undercut(1, r, theta)
    phi, z = g.wall(1, r, theta)
    # the roller within 1e-3 rad of the contact's cam angle cuts above it (a fold: F has a local
    # minimum there, not a maximum); the wings beside the fold are cut by farther positions
    near = np.linspace(-1e-3, 1e-3, 201)
    cut_away = np.array([np.nanmax(ref.cut_height(1, r, p, t + near)) - zz > 1e-10 for p, t, zz in zip(phi, theta, z)])
    edges = np.flatnonzero(np.diff(folded.astype(int)))
    keep = np.ones(theta.size, dtype=bool)
    for i in edges:  # the fold's own points (dphi/dtheta = 0) are neither
        keep[max(i - 1, 0):i + 3] = False
    assert folded.any() and (~folded).any()
    assert np.array_equal(folded[keep], cut_away[keep])
    # a folded contact is not the wall: the brute force lies above it
    i = int(np.flatnonzero(folded)[folded.sum() // 2])
    assert ref.brute_wall(1, r, phi[i]) > z[i] + 1e-3
    # the issue's groove does not fold anywhere from the root to the rim
    big = groove("translating", 1, 4.0)
    every = np.linspace(0, 2 * math.pi, 1441)
    assert not any(big.undercut(side, rr, every).any() for side in (1, -1) for rr in (R_I, R_M, R_O))


def test_conical_contact_is_a_curve_during_a_rise():
    """The cone (apex on the axis) touches along a generator only in a dwell: during the rise the
    generator through the contact at the mean radius leaves the brute-force wall by over 1e-3 mm at
    the root and the rim (1000 times the walls' tolerance), while camgen's contact curve stays on it
    (test_walls_match_the_union_of_roller_solids)."""
    ref = Follower("translating", 1, 4.0, "conical")
    k = 4.0 / R_M

    def miss(theta: float, b: float, t: float) -> float:
        """Brute-force upper wall minus the cone's point at generator angle b, station t (>= 0)."""
        s = float(norton_program(RISE, np.array([theta]))[0][0])
        y, z = t * k * math.sin(b), 10.0 + s + t * k * math.cos(b)
        return ref.brute_wall(1, math.hypot(t, y), math.atan2(y, t) - theta) - z

    for theta in (30.0 * DEG, 60.0 * DEG):
        # the generator touching the wall at the mean radius (the cone's points elsewhere are cut)
        b = minimize_scalar(lambda q: miss(theta, q, R_M), bounds=(0.0, 1.2), method="bounded",
                            options={"xatol": 1e-10}).x
        assert abs(miss(theta, b, R_M)) < WALL_TOL
        for t in (R_I, R_O):
            assert miss(theta, b, t) > 1e-3
    # in the dwell at the top the top generator (b = 0) is the contact from the root to the rim
    assert max(abs(miss(150.0 * DEG, 0.0, t)) for t in (R_I, R_M, R_O)) < WALL_TOL
