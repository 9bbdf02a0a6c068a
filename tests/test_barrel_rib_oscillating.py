"""A barrel cam's rib driving an oscillating follower (track = "rib", follower_motion = "oscillating").

The geometry stated in camgen.synthesis.barrel.BarrelRib, rebuilt here from scratch: both rollers
on the arm's end, their axes parallel to x, ``o = rib_width / 2 + w`` either side of the arm's end
along the arm's normal ``n = (-sin psi, cos psi)`` in the tangent plane (y, z); the pivot at
``(y, z) = (-L, z_p)``; so the roller on side ``k`` (+1 upper, -1 lower) has its axis at

    y_k = -L + L cos psi - k o sin psi,    z_k = z_p + L sin psi + k o cos psi.

Every expected number comes from outside camgen's barrel code:

* the faces: the issue's brute force, the union of the two roller solids (a cam point is cut when
  some cam angle puts it inside a roller), its edge on the rib's side found on a dense cam-angle
  grid and polished by scipy's bounded Brent minimiser (test_barrel_geometry's method);
* the laws in closed form (Norton, *Design of Machinery*, ch. 8; test_barrel_geometry's and
  test_barrel_dynamics' cycloids);
* the pressure angle from its definition: the contact normal on the roller's section is
  perpendicular to the velocity of the roller's axis relative to the cam (test_barrel_dynamics'
  construction), its angle with the axis' velocity, here for each roller with its own velocity.
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from test_barrel_dynamics import cycloid, segments, table
from test_barrel_geometry import ARM, DEG, PIVOT_Z, R_I, R_M, R_O, REST, SWING, WALL_TOL, groove, norton_program

RIB_W = 12.0
TWO_PI = 2.0 * math.pi


def rib_of(sigma: int, width: float = RIB_W, clearance: float = 0.1):
    from camgen.synthesis.barrel import BarrelRib

    return BarrelRib(groove("oscillating", sigma, 4.0, clearance=clearance), width)


class ArmRollers:
    """The two rollers on the arm (module notes), the swing ``swing(theta) -> psi - psi0`` in closed form."""

    def __init__(self, sigma: int, w: float, offset: float, arm: float, pivot_z: float, rest: float, swing):
        self.sigma, self.w, self.o, self.arm, self.zp, self.rest, self.swing = sigma, w, offset, arm, pivot_z, rest, swing

    def axis(self, side: int, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        psi = self.rest + self.swing(theta)
        y = -self.arm + self.arm * np.cos(psi) - side * self.o * np.sin(psi)
        z = self.zp + self.arm * np.sin(psi) + side * self.o * np.cos(psi)
        return y, z

    def edge(self, face: int, r: float, phi: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """The cut of the roller on the rib's ``face`` side at cam point (r, phi) for each theta:
        the upper roller's lower edge (face +1), the lower roller's upper edge (face -1); NaN where
        the point's line along z misses that roller."""
        y, z = self.axis(face, theta)
        u = phi + self.sigma * theta
        half = self.w**2 - (r * np.sin(u) - y) ** 2
        return np.where((r * np.cos(u) > 0.0) & (half >= 0.0), z - face * np.sqrt(np.abs(half)), np.nan)

    def face(self, face: int, r: float, phi: np.ndarray, polish: bool = True) -> np.ndarray:
        """The rib's face ``face`` at (r, phi): min over theta of the upper roller's lower edge
        (face +1), max of the lower roller's upper edge (face -1); a grid of 1e-4 rad, then Brent
        (``polish`` False: a grid of 1e-3 rad only, within about 1e-4 mm, to locate the least width)."""
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        offsets = np.linspace(-0.6, 0.6, 12001 if polish else 1201)
        out = np.empty(phi.size)
        for lo in range(0, phi.size, 64):
            p = phi[lo : lo + 64, None]
            grid = -self.sigma * p + offsets[None, :]
            h = -face * self.edge(face, r, p, grid)  # maximise
            k = np.nanargmax(h, axis=1)
            best = h[np.arange(p.shape[0]), k]
            if polish:
                step = offsets[1] - offsets[0]
                for i in range(p.shape[0]):
                    t0 = grid[i, k[i]]
                    res = minimize_scalar(lambda t: face * float(self.edge(face, r, p[i], np.array([t]))[0]),
                                          bounds=(t0 - step, t0 + step), method="bounded", options={"xatol": 1e-13})
                    best[i] = max(best[i], -float(res.fun))
            out[lo : lo + 64] = -face * best
        return out


def geometry_rollers(sigma: int, rib) -> ArmRollers:
    return ArmRollers(sigma, 4.05, RIB_W / 2 + 4.05, ARM, PIVOT_Z, REST, lambda t: norton_program(SWING, t)[0])


@pytest.mark.parametrize("sigma", [1, -1])
def test_oscillating_rib_faces_match_the_union_of_the_two_roller_solids(sigma):
    """Both faces at the root, mean and rim radius on polar angles through the rise, the dwells and
    the return, within the issue's 1e-6 mm of the brute force, for both rotations."""
    rib = rib_of(sigma)
    assert rib.roller_offset == pytest.approx(RIB_W / 2 + 4.05, abs=1e-15)
    rollers = geometry_rollers(sigma, rib)
    phi = np.array([0.1, 35.0, 60.0, 100.0, 150.0, 200.0, 240.0, 275.0, 330.0]) * DEG
    worst = 0.0
    for r in (R_I, R_M, R_O):
        for side in (1, -1):
            got = rib.wall_height(side, np.asarray(r), phi)
            worst = max(worst, float(np.max(np.abs(got - rollers.face(side, r, phi)))))
    assert worst < WALL_TOL, worst


def test_oscillating_rib_faces_in_a_dwell_are_the_rollers_edges():
    """Where the arm dwells at psi the faces are flat: the upper roller's axis height less w and the
    lower's plus w, (rib_width + 2 w) cos(psi) - 2 w apart (the docstring's statement), here at the
    rise's top (psi = psi0 + swing) and the return's bottom (psi = psi0)."""
    rib, w = rib_of(1), 4.05
    o = RIB_W / 2 + w
    for phi, psi in ((-150.0 * DEG, REST + SWING), (-330.0 * DEG, REST)):  # sigma = +1: theta = -phi
        top = PIVOT_Z + ARM * math.sin(psi) + o * math.cos(psi) - w
        bottom = PIVOT_Z + ARM * math.sin(psi) - o * math.cos(psi) + w
        for r in (R_I, R_O):
            assert rib.wall_height(1, np.asarray(r), np.asarray(phi)) == pytest.approx(top, abs=1e-9)
            assert rib.wall_height(-1, np.asarray(r), np.asarray(phi)) == pytest.approx(bottom, abs=1e-9)
            assert float(rib.thickness(np.asarray(r), np.asarray(phi))) == pytest.approx((RIB_W + 2 * w) * math.cos(psi) - 2 * w,
                                                                                        abs=1e-9)


# --------------------------------------------------------------------------------------------
# The pipeline: the template's barrel with a rib on an oscillating arm
# --------------------------------------------------------------------------------------------
OSC_ARM, OSC_SWING, SCENE_W = 60.0, math.radians(20.0), 8.025
LENGTH = 90.0


def osc_rib(**extra) -> dict:
    return table(**{"follower_motion": "oscillating", "arm_length_mm": OSC_ARM, "rotation": "cw", "segments": segments("swing_deg", 20.0),
                    "pressure_angle_limit_deg": 60.0, "track": "rib", "rib_width_mm": 10.0, "cylinder_length_mm": LENGTH, **extra})


def scene_rollers(width: float = 10.0) -> ArmRollers:
    """The scene's rollers (default rest angle -swing / 2, pivot at half the length, clockwise)."""
    return ArmRollers(-1, SCENE_W, width / 2 + SCENE_W, OSC_ARM, LENGTH / 2, -OSC_SWING / 2, lambda t: cycloid(t, OSC_SWING)[0])


def report_of(cam: dict, formats=("html",)):
    import json

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": list(formats)}, "cams": {"c": cam}}, "t")
    return json.loads(execute(scene, plan_run(scene)).files["report.json"])["cams"]["c"]


def check(report: dict, name: str) -> dict:
    return next(c for c in report["checks"] if c["name"] == name)


def brute_least_width(rollers: ArmRollers) -> float:
    """The rib's least width along z on the check's grid (9 radii from root to rim, 3600 polar
    angles), by the brute force: every 10th polar angle at each radius on a coarse cam-angle grid,
    then, at the radii within 0.01 mm of the least, the 21 grid angles around their least polished."""
    from camgen.kinds.barrel import RIB_THICKNESS_SAMPLES, UNDERCUT_RADII

    step = TWO_PI / RIB_THICKNESS_SAMPLES
    coarse = np.arange(0, RIB_THICKNESS_SAMPLES, 10) * step
    radii = np.linspace(R_O - 10.0, R_O, UNDERCUT_RADII)
    widths = [rollers.face(1, r, coarse, polish=False) - rollers.face(-1, r, coarse, polish=False) for r in radii]
    floor = min(float(np.min(w)) for w in widths)
    least = math.inf
    for r, width in zip(radii, widths):
        if np.min(width) > floor + 0.01:
            continue
        fine = coarse[int(np.argmin(width))] + np.arange(-10, 11) * step
        least = min(least, float(np.min(rollers.face(1, r, fine) - rollers.face(-1, r, fine))))
    return least


def test_oscillating_rib_thickness_at_its_threshold(tmp_path, capsys):
    """The rib_thickness check's value is the brute force's least width (1e-6 mm); with min_wall_mm
    1e-4 mm below it the run exits 0 and writes the drawing, 1e-4 mm above it exits 1 and withholds it."""
    from camgen.cli import main
    from helpers import scene_toml

    least = brute_least_width(scene_rollers())
    assert check(report_of(osc_rib(min_wall_mm=1.0)), "rib_thickness")["value"] == pytest.approx(least, abs=1e-6)
    for delta, status in ((-1e-4, 0), (1e-4, 1)):
        path, out = tmp_path / f"s{status}.toml", tmp_path / f"out{status}"
        path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"c": osc_rib(min_wall_mm=least + delta)}}))
        assert main(["run", str(path), "-o", str(out)]) == status
        assert bool(list(out.rglob("c.dxf"))) == (status == 0)
    capsys.readouterr()


def test_oscillating_rib_width_hint_is_verified_by_using_it():
    """A rib too thin for min_wall_mm: the check's hint quotes a rib_width_mm; a rib that wide passes
    (its least width, the brute force's, >= min_wall_mm) and one unit less in the hint's sixth digit
    fails (the least such width); the width does not grow one to one with rib_width_mm here, so the
    translating rule's hint would miss."""
    min_wall = 9.0
    thin = check(report_of(osc_rib(min_wall_mm=min_wall)), "rib_thickness")
    assert thin["status"] == "fail"
    quoted = float(re.search(r"a rib_width_mm of ([0-9.]+) mm gives", thin["note"]).group(1))
    one_to_one = 10.0 + min_wall - thin["value"]
    assert abs(quoted - one_to_one) > 1e-3  # not the translating rule
    wide = check(report_of(osc_rib(min_wall_mm=min_wall, rib_width_mm=quoted)), "rib_thickness")
    assert wide["status"] == "pass"
    assert min_wall <= brute_least_width(scene_rollers(quoted)) + 1e-9
    last_digit = 10.0 ** (math.floor(math.log10(quoted)) - 5)  # the hint's 6 significant digits: the least such width
    assert brute_least_width(scene_rollers(quoted - last_digit)) < min_wall


def test_oscillating_rib_pressure_angle_and_reach_from_the_arm_geometry():
    """The pressure angle check: the larger of the two rollers' at the root, each from its own axis
    velocity (the arm's derivative, closed form here) and the contact normal perpendicular to the
    roller's velocity relative to the cam; its note's mean and rim values likewise.  The
    cylinder_length check: the least of the lowest roller edge (z - w) and the length less the
    highest (z + w) over the turn, from the rollers' axes here."""
    report = report_of(osc_rib())
    theta = TWO_PI * np.arange(3600) / 3600
    rollers = scene_rollers()
    psi_dot = cycloid(theta, OSC_SWING)[1]
    psi = -OSC_SWING / 2 + cycloid(theta, OSC_SWING)[0]
    largest = {}
    for name, r in (("root", R_O - 10.0), ("mean", R_O - 5.0), ("rim", R_O)):
        worst = np.zeros_like(theta)
        for side in (1, -1):
            o = side * rollers.o
            y, _ = rollers.axis(side, theta)
            # the axis moves at psi' d per rad, d = d/dpsi of the arm point (its direction also where psi' = 0)
            d = np.stack([-OSC_ARM * np.sin(psi) - o * np.cos(psi), OSC_ARM * np.cos(psi) - o * np.sin(psi)], axis=-1)
            t = np.sqrt(r * r - y * y)
            rel = psi_dot[:, None] * d - np.stack([-1 * t, np.zeros_like(t)], axis=-1)  # the cam moves the section at sigma t along y
            n = np.stack([-rel[:, 1], rel[:, 0]], axis=-1)
            n /= np.linalg.norm(n, axis=-1, keepdims=True)
            alpha = np.arccos(np.clip(np.abs(np.sum(n * d, axis=-1)) / np.linalg.norm(d, axis=-1), 0.0, 1.0))
            worst = np.maximum(worst, alpha)
        largest[name] = math.degrees(float(np.max(worst)))
    pressure = check(report, "pressure_angle")
    assert pressure["value"] == pytest.approx(largest["root"], abs=1e-6)
    for name in ("mean", "rim"):
        assert f"{largest[name]:.6g} deg" in pressure["note"]
    assert report["figures"]["pressure_angle_mean_deg"] == pytest.approx(largest["mean"], abs=1e-6)
    zs = [rollers.axis(side, theta)[1] for side in (1, -1)]
    low, high = min(float(z.min()) for z in zs) - SCENE_W, max(float(z.max()) for z in zs) + SCENE_W
    assert check(report, "cylinder_length")["value"] == pytest.approx(min(low, LENGTH - high), abs=1e-6)


def test_oscillating_rib_mesh_is_watertight_with_the_volume_of_an_independent_integral():
    """The rib's mesh (as the translating rib's test): manifold3d finds one closed piece; its volume
    against pi R_i^2 L plus the integral of the rib's width r dr dphi (Gauss-Legendre in r, trapezoid
    over the periodic polar angle; the faces checked against the brute force above) within chord_tol
    times the mesh's area."""
    import manifold3d

    from camgen.export.barrel_rib_solid import rib_solid

    tol = 0.01
    rib = rib_of(1)
    solid = rib_solid(rib, tol)
    m = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=solid.vertices, tri_verts=solid.triangles.astype(np.uint64)))
    assert m.status() == manifold3d.Error.NoError and len(m.decompose()) == 1
    x, wts = np.polynomial.legendre.leggauss(8)
    r = 0.5 * (R_O + R_I) + 0.5 * (R_O - R_I) * x
    phi = TWO_PI * np.arange(4096) / 4096
    width = rib.thickness(r[:, None], phi[None, :])
    want = math.pi * R_I**2 * 70.0 + 0.5 * (R_O - R_I) * float(np.sum(wts * r * width.mean(axis=1) * TWO_PI))
    v, t = solid.vertices, solid.triangles
    area = 0.5 * float(np.sum(np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1)))
    assert abs(solid.volume - want) <= tol * area, (solid.volume, want, tol * area)
    assert abs(float(m.volume()) - want) <= tol * area
