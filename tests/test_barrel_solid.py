"""The barrel cam's surface mesh and STEP (camgen.export.barrel_solid, camgen.export.barrel_step)
against the issue's brute force: the groove as the union of the (widened) roller's positions,
its walls found by a dense search over the cam angle, never by camgen's contact formulas.

* the volume: ``pi (R_o^2 - R_bore^2) L`` less the integral of ``(z_upper - z_lower) r`` over the
  groove (Gauss-Legendre in r, the trapezoid rule over the periodic phi) of the brute-force walls;
* the mesh's walls, read back by vertical rays through its triangles (no camgen code), within the
  chord tolerance of the brute-force walls;
* the follower simulated in the exported mesh: the roller's highest and lowest axis height that
  the mesh's walls allow at a cam angle, against ``z0 + s(theta) +- c / 2``;
* STEP: one solid that OCCT (and FreeCAD where installed) finds valid, its volume by OCCT's mass
  properties, its walls (vertical lines intersected with its faces by OCCT) within fit_tol.
"""
from __future__ import annotations

import importlib.util
import io
import math
import os
import subprocess
from dataclasses import replace

import numpy as np
import pytest

from camgen.errors import GeometryError
from camgen.export.barrel_solid import barrel_solid
from camgen.synthesis.barrel import BarrelGroove, BarrelLayout
from camgen.synthesis.laws import MotionProgram, Segment
from helpers import require_tool

D = math.radians
RIM, ROOT, LENGTH, BORE, RR, CLEARANCE = 55.0, 45.0, 80.0, 10.0, 4.0, 0.2
#: The issue's example: a 40 mm cycloidal rise over 120 deg on a 50 mm mean radius, 10 mm deep,
#: an 8 mm roller; here with a dwell, the return and a dwell to close the turn.
LIFT, Z0 = 40.0, 20.0
#: An oscillating follower: 30 deg cycloidal swing of a 60 mm arm, pivot at z = 40 mm.
SWING, ARM, PIVOT_Z, REST = D(30.0), 60.0, 40.0, -D(15.0)


def program(lift: float, unit: str = "mm") -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(120), lift), Segment("dwell", D(60), 0.0), Segment("cycloidal", D(120), -lift),
                          Segment("dwell", D(60), 0.0)], unit=unit)


def make_groove(motion: str = "translating", sigma: int = 1, shape: str = "cylindrical", bore: float = BORE,
                fit_tol: float = 1e-5, length: float = LENGTH) -> BarrelGroove:
    mean = 0.5 * (RIM + ROOT)
    if motion == "translating":
        layout = BarrelLayout("translating", sigma, RR, shape, mean, Z0)
        return BarrelGroove(layout, program(LIFT), RIM, ROOT, length, bore, CLEARANCE, fit_tol)
    layout = BarrelLayout("oscillating", sigma, RR, "cylindrical", mean, PIVOT_Z, ARM, REST)
    return BarrelGroove(layout, program(SWING, "rad"), RIM, ROOT, length, bore, CLEARANCE, fit_tol)


def axis(groove: BarrelGroove, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The roller axis (height z_c, tangential offset e, mm) from the law and api.md's placement
    (the layout's inputs: z0, arm length, rest angle)."""
    lay = groove.layout
    s = groove.law(theta)[0]
    if lay.motion == "translating":
        return lay.z0 + s, np.zeros_like(s)
    psi = lay.rest_angle + s
    return lay.z0 + lay.arm_length * np.sin(psi), lay.arm_length * (np.cos(psi) - 1.0)


def brute_wall(groove: BarrelGroove, side: int, r: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """The issue's brute force: z_upper(r, phi) = max over theta of z_c + sqrt(w^2 - (r sin(phi + sigma theta) - e)^2)
    (the lower wall: min, minus), r cos(phi + sigma theta) > 0; for the conical roller (apex on the
    cam axis at the axis' height, radius w at R_m) the radius at the point's station t = r cos(a)
    along the roller axis is w t / R_m instead of w.  The search over the follower's
    angle a = phi + sigma theta: 129 samples over every a where the roller can reach radius r (at
    least 20 across the roller), then 12 zooms of 9 samples about the best (each 4x finer: a to
    ~1e-9 rad, z to ~1e-14 mm)."""
    r, phi = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(phi, dtype=float))
    shape, r, phi = r.shape, r.ravel(), phi.ravel()
    sigma, w = groove.layout.sigma, groove.half_width
    cone = groove.layout.roller_shape == "conical"
    reach = w + (ARM * (1.0 - math.cos(abs(REST) + SWING)) if groove.layout.motion == "oscillating" else 0.0)
    lo = np.full((len(r), 1), -1.0) * np.arcsin(np.minimum(1.0, reach / r))[:, None]
    hi = -lo
    rows = np.arange(len(r))
    best = np.empty(len(r))
    for zoom in range(13):
        a = lo + (hi - lo) * np.linspace(0.0, 1.0, 129 if zoom == 0 else 9)[None, :]
        zc, e = axis(groove, sigma * (a - phi[:, None]))
        radius = w * r[:, None] * np.cos(a) / groove.layout.mean_radius if cone else w
        q = radius * radius - (r[:, None] * np.sin(a) - e) ** 2
        inside = (q >= 0.0) & (np.cos(a) > 0.0)
        f = np.where(inside, zc + side * np.sqrt(np.where(inside, q, 0.0)), -side * np.inf)
        k = np.argmax(side * f, axis=1)
        best = f[rows, k]
        step = (hi - lo) / (a.shape[1] - 1)
        lo, hi = a[rows, k][:, None] - step, a[rows, k][:, None] + step
    return best.reshape(shape)


def groove_volume(groove: BarrelGroove, n_phi: int = 2048, n_r: int = 6) -> float:
    """pi (R_o^2 - R_bore^2) L less the groove: integral over r in [R_i, R_o] (Gauss-Legendre, n_r
    points) and phi (trapezoid rule over the period, n_phi points) of (z_upper - z_lower) r."""
    x, weight = np.polynomial.legendre.leggauss(n_r)
    r = 0.5 * (RIM + ROOT) + 0.5 * (RIM - ROOT) * x
    phi = 2.0 * math.pi * np.arange(n_phi) / n_phi
    rr, pp = np.meshgrid(r, phi, indexing="ij")
    height = brute_wall(groove, 1, rr, pp) - brute_wall(groove, -1, rr, pp)
    cut = float(np.sum(0.5 * (RIM - ROOT) * weight * r * height.sum(axis=1)) * 2.0 * math.pi / n_phi)
    return math.pi * (RIM**2 - groove.bore_radius**2) * groove.length - cut


_VOLUMES: dict[tuple, float] = {}


def reference_volume(motion: str, sigma: int, shape: str, bore: float) -> float:
    key = (motion, sigma, shape, bore)
    if key not in _VOLUMES:
        _VOLUMES[key] = groove_volume(make_groove(motion, sigma, shape, bore))
    return _VOLUMES[key]


def test_reference_volume_converged():
    """The brute-force integral itself: doubling both rules moves it by less than 1e-9 relative
    (the tests below hold the exports to 1e-6)."""
    groove = make_groove()
    coarse, fine = groove_volume(groove, 1024, 4), reference_volume("translating", 1, "cylindrical", BORE)
    assert abs(coarse - fine) <= 1e-9 * fine


# ----------------------------------------------------------------------------------- the mesh
def mesh_walls(vertices: np.ndarray, triangles: np.ndarray, length: float, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Heights (mm) of the upper and lower groove walls of a closed mesh where the vertical lines
    through (x, y) meet them: the triangles facing down (up) that are not on an end face, the one
    whose projection holds the point (its 48 nearest centroids searched), interpolated linearly."""
    from scipy.spatial import cKDTree

    tri = vertices[triangles]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    nz = normal[:, 2] / np.linalg.norm(normal, axis=1)
    on_end = np.all(tri[:, :, 2] == 0.0, axis=1) | np.all(tri[:, :, 2] == length, axis=1)
    query = np.column_stack([x.ravel(), y.ravel()])
    out = []
    for facing in (nz < -1e-3, nz > 1e-3):
        chosen = tri[facing & ~on_end]
        _, near = cKDTree(chosen[:, :, :2].mean(axis=1)).query(query, k=48)
        cand = chosen[near]  # (q, 48, 3, 3)
        p = query[:, None, :]
        a, b, c = cand[..., 0, :2], cand[..., 1, :2], cand[..., 2, :2]
        det = (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (c[..., 0] - a[..., 0]) * (b[..., 1] - a[..., 1])
        l1 = ((p[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (c[..., 0] - a[..., 0]) * (p[..., 1] - a[..., 1])) / det
        l2 = ((b[..., 0] - a[..., 0]) * (p[..., 1] - a[..., 1]) - (p[..., 0] - a[..., 0]) * (b[..., 1] - a[..., 1])) / det
        l0 = 1.0 - l1 - l2
        holds = (l0 >= -1e-12) & (l1 >= -1e-12) & (l2 >= -1e-12)
        assert np.all(holds.any(axis=1)), "a vertical line meets no wall triangle among its 48 nearest"
        k = np.argmax(holds, axis=1)
        rows = np.arange(len(query))
        z = l0[rows, k] * cand[rows, k, 0, 2] + l1[rows, k] * cand[rows, k, 1, 2] + l2[rows, k] * cand[rows, k, 2, 2]
        out.append(z.reshape(x.shape))
    return out[0], out[1]


CASES = [("translating", 1, "cylindrical", BORE), ("oscillating", -1, "cylindrical", BORE), ("translating", -1, "conical", 0.0)]
MESH_TOL = 2e-3


@pytest.fixture(scope="module", params=CASES, ids=["translating", "oscillating-cw", "conical-cw-nobore"])
def meshed(request):
    motion, sigma, shape, bore = request.param
    groove = make_groove(motion, sigma, shape, bore)
    return request.param, groove, barrel_solid(groove, MESH_TOL, "barrel")


def test_mesh_watertight_one_body_volume(meshed):
    """Watertight, consistently wound, one body; its volume within what the chord tolerance allows
    of the brute-force integral: every point of the mesh lies within tol of the exact surface, so
    the two regions differ by at most tol times the surface's area."""
    import trimesh

    case, groove, solid = meshed
    mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume
    assert mesh.body_count == 1
    assert mesh.euler_number == (0 if groove.bore_radius > 0 else 2)  # genus 1 with the bore, 0 without
    exact = reference_volume(*case)
    assert abs(mesh.volume - exact) <= MESH_TOL * mesh.area
    assert abs(solid.volume - mesh.volume) <= 1e-9 * exact  # the solid states the mesh's volume


def test_mesh_walls_within_chord_tolerance(meshed):
    """The mesh's walls, read by vertical lines at 3000 random points of the groove's annulus,
    within the chord tolerance of the brute-force walls (axially: the distance is at most that)."""
    case, groove, solid = meshed
    rng = np.random.default_rng(24)
    r = rng.uniform(ROOT + 0.05, RIM - 0.05, 3000)
    phi = rng.uniform(0.0, 2.0 * math.pi, 3000)
    upper, lower = mesh_walls(solid.vertices, solid.triangles, groove.length, r * np.cos(phi), r * np.sin(phi))
    assert np.max(np.abs(upper - brute_wall(groove, 1, r, phi))) <= MESH_TOL
    assert np.max(np.abs(lower - brute_wall(groove, -1, r, phi))) <= MESH_TOL


def test_mesh_vertices_on_the_exact_surfaces(meshed):
    """Every vertex lies on the body's surfaces: the rim, root, bore cylinders or an end face to
    rounding, else on a groove wall (3000 of them sampled) within 1e-8 mm of the brute force; every
    edge between two vertices of one cylinder has its midpoint within the chord tolerance of it."""
    case, groove, solid = meshed
    v = solid.vertices
    r = np.hypot(v[:, 0], v[:, 1])
    radii = [RIM, ROOT] + ([groove.bore_radius] if groove.bore_radius > 0 else [])
    on = {R: np.abs(r - R) <= 1e-9 * R for R in radii}
    end = (v[:, 2] == 0.0) | (v[:, 2] == groove.length)
    wall = ~end & ~np.logical_or.reduce(list(on.values())) & (r > ROOT) & (r < RIM)
    assert np.all(end | wall | np.logical_or.reduce(list(on.values())))
    # the walls' vertices at the root and rim are on those cylinders too: check them all the same way
    sample = np.random.default_rng(3).choice(np.flatnonzero(~end & (r >= ROOT - 1e-9) & (r <= RIM + 1e-9)), 3000, replace=False)
    phi = np.arctan2(v[sample, 1], v[sample, 0])
    gap = np.minimum(np.abs(v[sample, 2] - brute_wall(groove, 1, r[sample], phi)), np.abs(v[sample, 2] - brute_wall(groove, -1, r[sample], phi)))
    floor_or_rim = (np.abs(r[sample] - ROOT) <= 1e-9 * ROOT) | (np.abs(r[sample] - RIM) <= 1e-9 * RIM)
    assert np.all((gap <= 1e-8) | floor_or_rim)
    assert np.all(gap[~floor_or_rim] <= 1e-8)
    edges = np.concatenate([solid.triangles[:, [0, 1]], solid.triangles[:, [1, 2]], solid.triangles[:, [2, 0]]])
    for R, flags in on.items():
        both = edges[flags[edges[:, 0]] & flags[edges[:, 1]]]
        mid = 0.5 * (v[both[:, 0]] + v[both[:, 1]])
        assert len(both) and np.min(np.hypot(mid[:, 0], mid[:, 1])) >= R - MESH_TOL


def roller_range(groove: BarrelGroove, theta: np.ndarray, walls) -> tuple[np.ndarray, np.ndarray]:
    """The highest and the lowest height of the roller's axis (radius Rr, not widened, the cone's at
    R_m; its axis at the tangential offset e(theta)) that the walls allow at each cam angle: its sections at three
    radii, 401 points across each, held below the upper wall and above the lower one.
    ``walls(x, y) -> (z_upper, z_lower)`` reads the groove."""
    sigma = groove.layout.sigma
    _, e = axis(groove, theta)
    high, low = np.full(len(theta), np.inf), np.full(len(theta), -np.inf)
    for r in (ROOT + 0.1, 0.5 * (ROOT + RIM), RIM - 0.1):
        reach = math.asin(min(1.0, (RR + float(np.max(np.abs(e)))) / r))
        a = np.linspace(-reach, reach, 401)[None, :] + 0.0 * theta[:, None]
        y = r * np.sin(a) - e[:, None]
        radius = RR * r * np.cos(a) / groove.layout.mean_radius if groove.layout.roller_shape == "conical" else RR
        held = radius * radius - y * y > 0.0
        half = np.sqrt(np.where(held, radius * radius - y * y, 0.0))
        phi = a - sigma * theta[:, None]
        upper, lower = walls(r * np.cos(phi), r * np.sin(phi))
        high = np.minimum(high, np.min(np.where(held, upper - half, np.inf), axis=1))
        low = np.maximum(low, np.max(np.where(held, lower + half, -np.inf), axis=1))
    return high, low


#: Cam angles of the ride (deg): dwells (0, 130, 170, 310, 350), rises and returns.
RIDE = np.array([0.0, 20.0, 45.0, 60.0, 75.0, 100.0, 130.0, 170.0, 200.0, 240.0, 255.0, 280.0, 310.0, 350.0])
DWELLS = np.isin(RIDE, [0.0, 130.0, 170.0, 310.0, 350.0])


def test_follower_rides_the_mesh(meshed):
    """The follower simulated in the exported mesh: the range of axis heights the roller can take
    between the mesh's walls (read by vertical lines) at each cam angle is the range the exact
    groove (the brute force, read the same way) allows, within the chord tolerance; the required
    axis z_c(theta) lies in it with at least c / 2 - tol on either side (the roller neither jams
    nor rattles beyond its play), exactly c / 2 in the dwells (the contact at the top of the
    roller; the cone's play is c / 2 r / R_m at its section of radius r).  Sampling across a section is the same for both readings."""
    case, groove, solid = meshed
    theta = np.radians(RIDE)
    zc, _ = axis(groove, theta)
    high, low = roller_range(groove, theta, lambda x, y: mesh_walls(solid.vertices, solid.triangles, groove.length, x, y))

    def exact(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r, phi = np.hypot(x, y), np.arctan2(y, x)
        return brute_wall(groove, 1, r, phi), brute_wall(groove, -1, r, phi)

    high_exact, low_exact = roller_range(groove, theta, exact)
    assert np.max(np.abs(high - high_exact)) <= MESH_TOL
    assert np.max(np.abs(low - low_exact)) <= MESH_TOL
    # the play at the top of the roller: c / 2 (the cone: c / 2 r / R_m at its section of radius r,
    # the least at the innermost section read, ROOT + 0.1)
    play = CLEARANCE / 2 * ((ROOT + 0.1) / groove.layout.mean_radius if groove.layout.roller_shape == "conical" else 1.0)
    assert np.min(high - zc) >= play - MESH_TOL and np.min(zc - low) >= play - MESH_TOL
    assert np.max(np.abs(high - zc - play)[DWELLS]) <= MESH_TOL
    assert np.max(np.abs(zc - low - play)[DWELLS]) <= MESH_TOL


def test_mesh_beyond_the_file_cap_is_refused_before_the_walls_are_evaluated():
    """At 1e-7 mm the first grid (the rim at half its chord step: 1.0e5 columns) already makes an
    ASCII STL of more than 100 MB (300 bytes a triangle at most, measured 288): refused naming
    output.chord_tol_mm before a single wall point is computed (the cap comes before the work)."""
    groove = make_groove()
    calls = []

    class Counting:
        def __getattr__(self, name):
            return getattr(groove, name)

        def wall(self, *args):
            calls.append(args)
            return groove.wall(*args)

    with pytest.raises(GeometryError, match="output.chord_tol_mm"):
        barrel_solid(Counting(), 1e-7, "barrel", ("stl_ascii",))
    assert calls == []
    barrel_solid(Counting(), 1e-2, "barrel", ("stl_ascii",))
    assert calls  # the counting wrapper does see the work when there is some


def test_groove_through_an_end_face_is_refused():
    """A groove whose lower wall reaches below z = 0 (the axis at lift 0 at 2 mm, the roller 4.1 mm
    wide) is a GeometryError naming the cam, not a mesh nor a STEP."""
    groove = make_groove(length=LENGTH)
    short = replace(groove, layout=replace(groove.layout, z0=2.0))
    with pytest.raises(GeometryError, match="barrel-short.*end face"):
        barrel_solid(short, MESH_TOL, "barrel-short")
    if importlib.util.find_spec("OCP") is not None:
        from camgen.export.barrel_step import barrel_step_bytes

        with pytest.raises(GeometryError, match="barrel-short.*end face"):
            barrel_step_bytes(short, "barrel-short")


# ----------------------------------------------------------------------------------- STEP
STEP_TOL = 1e-5


@pytest.fixture(scope="module")
def stepped():
    pytest.importorskip("OCP")
    from camgen.export.barrel_step import barrel_step_bytes

    groove = make_groove(fit_tol=STEP_TOL)
    return groove, barrel_step_bytes(groove, "barrel")


def _read_step(data: bytes):
    from OCP.STEPControl import STEPControl_Reader

    reader = STEPControl_Reader()
    saved = os.dup(1)
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
        try:
            reader.ReadStream("barrel.step", io.BytesIO(data))
            reader.TransferRoots()
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    return reader.OneShape()


def test_step_one_valid_solid_and_its_volume(stepped):
    """Read back by OCCT: one solid, BRepCheck_Analyzer valid; its volume (OCCT's mass properties,
    adaptive to 1e-9) within 1e-6 relative of the brute-force integral, and its default integration
    (what FreeCAD shows) the same to 1e-8.  The bound the walls' fit
    allows: fit_tol times the two walls' area (< 8000 mm^2) is 8e-2 mm^3, 1.1e-7 of the volume."""
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    groove, data = stepped
    assert b"FILE_DESCRIPTION(('camgen barrel cam barrel: B-spline groove walls within 1e-05 mm" in data
    shape = _read_step(data)
    solids, explorer = 0, TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        solids += 1
        explorer.Next()
    assert solids == 1 and BRepCheck_Analyzer(shape).IsValid()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-9)
    exact = reference_volume("translating", 1, "cylindrical", BORE)
    assert abs(props.Mass() - exact) <= 1e-6 * exact
    # OCCT's default integration (FreeCAD's volume: one Gauss rule per face) agrees to 1e-8
    default = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, default)
    assert abs(default.Mass() - props.Mass()) <= 1e-8 * exact


def test_step_walls_within_fit_tol(stepped):
    """Vertical lines through 200 random points of the groove's annulus, intersected with the STEP
    solid's faces by OCCT: the two hits between the end faces are the walls, within fit_tol of the
    brute-force walls."""
    from OCP.gp import gp_Dir, gp_Lin, gp_Pnt
    from OCP.IntCurvesFace import IntCurvesFace_ShapeIntersector

    groove, data = stepped
    shape = _read_step(data)
    hit = IntCurvesFace_ShapeIntersector()
    hit.Load(shape, 1e-9)
    rng = np.random.default_rng(7)
    r = rng.uniform(ROOT + 0.05, RIM - 0.05, 200)
    phi = rng.uniform(0.0, 2.0 * math.pi, 200)
    walls = []
    for ri, pi in zip(r, phi):
        hit.Perform(gp_Lin(gp_Pnt(ri * math.cos(pi), ri * math.sin(pi), -1.0), gp_Dir(0.0, 0.0, 1.0)), 0.0, LENGTH + 2.0)
        z = sorted(hit.Pnt(i).Z() for i in range(1, hit.NbPnt() + 1))
        inner = [v for v in z if 1e-6 < v < LENGTH - 1e-6]
        assert len(inner) == 2, z
        walls.append(inner)
    lower, upper = np.array(walls).T
    assert np.max(np.abs(upper - brute_wall(groove, 1, r, phi))) <= STEP_TOL
    assert np.max(np.abs(lower - brute_wall(groove, -1, r, phi))) <= STEP_TOL


def test_step_opens_in_freecad(stepped, tmp_path):
    """FreeCAD (an independent reader of STEP: its own import into its Part workbench) finds one
    valid solid of the brute-force volume within 1e-6 relative."""
    freecad = require_tool("freecadcmd")
    groove, data = stepped
    path = tmp_path / "barrel.step"
    path.write_bytes(data)
    script = tmp_path / "check.py"
    script.write_text("import Part\nshape = Part.read(%r)\nprint('CHECK', shape.isValid(), len(shape.Solids), repr(shape.Volume))\n"
                      % str(path))
    done = subprocess.run([freecad, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    line = [ln for ln in done.stdout.splitlines() if ln.startswith("CHECK")]
    assert line, done.stdout + done.stderr
    _, valid, solids, volume = line[0].split()
    exact = reference_volume("translating", 1, "cylindrical", BORE)
    assert valid == "True" and solids == "1"
    assert abs(float(volume) - exact) <= 1e-6 * exact


# ----------------------------------------------------------------------------------- the run
def test_a_barrel_scene_writes_its_meshes_and_step(tmp_path):
    """A scene of the translating groove above through the pipeline (the form's mesh stage and
    STEP writer): the STL read by admesh (nothing to repair, one part) and by trimesh (watertight)
    with the brute-force volume within the chord tolerance times the area (and float32's
    rounding, admesh summing in float32: Higham's (n - 1) 2^-24); the 3MF the same mesh; the STEP
    one valid solid of that volume within 1e-6."""
    import re

    import trimesh

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene
    from test_solid import admesh_clean

    tol = 5e-3
    formats = ["stl", "3mf", "step"] if importlib.util.find_spec("OCP") is not None else ["stl", "3mf"]
    table = {"kind": "motion_law", "form": "barrel", "roller_radius_mm": RR, "cylinder_radius_mm": RIM, "cylinder_length_mm": LENGTH,
             "groove_depth_mm": RIM - ROOT, "groove_clearance_mm": CLEARANCE, "bore_diameter_mm": 2 * BORE, "fit_tol_mm": STEP_TOL,
             "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": LIFT}, {"law": "dwell", "span_deg": 60.0},
                          {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -LIFT}, {"law": "dwell", "span_deg": 60.0}]}
    scene = parse_scene({"output": {"formats": formats, "chord_tol_mm": tol}, "cams": {"b": table}}, "t", base_dir=tmp_path)
    files = execute(scene, plan_run(scene)).files
    exact = reference_volume("translating", 1, "cylindrical", BORE)  # the same groove: z0 centred = 20 mm, ccw
    mesh = trimesh.Trimesh(**trimesh.exchange.stl.load_stl(io.BytesIO(files["b.stl"])), process=False)
    mesh.merge_vertices()
    assert mesh.is_watertight and mesh.body_count == 1
    rounding = len(mesh.faces) * 2.0**-24 * exact
    assert abs(mesh.volume - exact) <= tol * mesh.area + rounding
    path = tmp_path / "b.stl"
    path.write_bytes(files["b.stl"])
    out = admesh_clean(require_tool("admesh"), path)
    assert abs(float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1)) - exact) <= tol * mesh.area + rounding
    three = trimesh.load(io.BytesIO(files["b.3mf"]), file_type="3mf", force="mesh")
    assert three.is_watertight and abs(three.volume - mesh.volume) <= rounding
    if "step" in formats:
        from OCP.BRepCheck import BRepCheck_Analyzer
        from OCP.BRepGProp import BRepGProp
        from OCP.GProp import GProp_GProps

        shape = _read_step(files["b.step"])
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(shape, props)
        assert BRepCheck_Analyzer(shape).IsValid() and abs(props.Mass() - exact) <= 1e-6 * exact
