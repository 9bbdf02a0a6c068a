"""A barrel cam's rib (track = "rib"): its files against the issue's brute force, computed here
from the two rollers (never from camgen's contact formulas or camgen.synthesis.barrel.BarrelRib).

The rib is straddled by two rollers whose axes ride ``o = rib_width / 2 + Rr + c / 2`` above and
below the pitch line ``z_c = z0 + s(theta)``.  Each roller, widened by half the clearance, is swept
through the turn (tests/test_barrel_solid.py's brute force: the extreme height of the union of its
solids, over the cam angle): the rib's upper face is the lower edge of the upper roller's union,
its lower face the upper edge of the lower roller's.

* STEP: one solid that OCCT and FreeCAD find valid; its volume (OCCT's mass properties, FreeCAD's
  Part workbench) against ``pi (R_i^2 - R_b^2) L`` plus the integral of the brute-force width
  ``z_up - z_lo`` times r over the rib (Gauss-Legendre in r, the trapezoid rule over the periodic
  polar angle); its faces, read by OCCT's line intersections, within fit_tol of the brute force;
  its top on the rim cylinder, its base on the root cylinder.
* The follower simulated through the exported mesh: the range of pitch heights the two rollers
  (radius Rr, not widened) can take astride the mesh's rib against the range the brute-force rib
  allows, and the required z_c(theta) inside it with the clearance's play.
* The developed DXF (ezdxf) and the point list (pandas): every vertex on the brute-force faces.
"""
from __future__ import annotations

import io
import math
import subprocess
from dataclasses import replace

import numpy as np
import pytest

from helpers import require_tool
from test_barrel_solid import (BORE, CLEARANCE, DWELLS, LENGTH, LIFT, RIDE, RIM, ROOT, RR, Z0, _read_step, axis, brute_wall,
                               make_groove, mesh_walls)

RIB_W = 12.0
#: The rollers' axes above and below the pitch line (mm): the rib's half width, the roller, half the clearance.
O = RIB_W / 2 + RR + CLEARANCE / 2
R_M = 0.5 * (RIM + ROOT)
STEP_TOL = 1e-5
MESH_TOL = 2e-3
CHORD = 1e-3


def make_rib(bore: float = BORE, fit_tol: float = STEP_TOL):
    from camgen.synthesis.barrel import BarrelRib

    return BarrelRib(make_groove("translating", 1, "cylindrical", bore, fit_tol), RIB_W)


def brute_face(side: int, r: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """The rib's face ``side`` (+1 upper, -1 lower) at radius ``r`` and polar angle ``phi`` (mm):
    the brute force of the roller on that side, its axis at ``Z0 + s(theta) + side O`` (the
    groove of its own axis height), its envelope on the rib's side (``-side``)."""
    groove = make_groove("translating", 1, "cylindrical", BORE, STEP_TOL)
    roller = replace(groove, layout=replace(groove.layout, z0=Z0 + side * O))
    return brute_wall(roller, -side, r, phi)


def rib_volume(n_phi: int = 2048, n_r: int = 6) -> float:
    """pi (R_i^2 - R_b^2) L plus the rib: the integral over r in [R_i, R_o] (Gauss-Legendre, n_r
    points) and phi (trapezoid rule over the period, n_phi points) of (z_up - z_lo) r."""
    x, weight = np.polynomial.legendre.leggauss(n_r)
    r = 0.5 * (RIM + ROOT) + 0.5 * (RIM - ROOT) * x
    phi = 2.0 * math.pi * np.arange(n_phi) / n_phi
    rr, pp = np.meshgrid(r, phi, indexing="ij")
    width = brute_face(1, rr, pp) - brute_face(-1, rr, pp)
    rib = float(np.sum(0.5 * (RIM - ROOT) * weight * r * width.sum(axis=1)) * 2.0 * math.pi / n_phi)
    return math.pi * (ROOT**2 - BORE**2) * LENGTH + rib


_VOLUME: list[float] = []


def reference_volume() -> float:
    if not _VOLUME:
        _VOLUME.append(rib_volume())
    return _VOLUME[0]


def test_reference_volume_converged():
    """The brute-force integral itself: doubling both rules moves it by less than 1e-9 relative
    (the STEP is held to 1e-6)."""
    coarse = rib_volume(1024, 4)
    assert abs(coarse - reference_volume()) <= 1e-9 * reference_volume()


# ----------------------------------------------------------------------------------- STEP
@pytest.fixture(scope="module")
def rib_run(tmp_path_factory) -> tuple[int, str, bytes]:
    """`camgen run` of the rib scene (rib_table(): make_rib()'s rib, z0 centred = 20 mm, ccw, the
    pressure-angle limit raised to 45 deg so that the design checks pass: 40.3 deg at the root)
    asking for STEP, its cam named "rib", once for the module: (exit status, stderr, the bytes of
    its rib.step).  The STEP tests below read this file: the one the command line writes, built by
    camgen.export.barrel_rib_step.rib_step_bytes from the scene's rib (the same bytes as
    ``rib_step_bytes(make_rib(), "rib")``: computed once, not once through the API and again
    through the command line)."""
    import contextlib
    import io

    pytest.importorskip("OCP")
    from camgen.cli import main
    from helpers import scene_toml

    folder = tmp_path_factory.mktemp("rib_run")
    path = folder / "s.toml"
    path.write_text(scene_toml({"output": {"formats": ["step"]}, "cams": {"rib": rib_table()}}))
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main(["run", str(path), "-o", str(folder / "out")])
    steps = list((folder / "out").rglob("rib.step"))
    return status, err.getvalue(), steps[0].read_bytes() if len(steps) == 1 else b""


@pytest.fixture(scope="module")
def stepped(rib_run) -> bytes:
    status, err, step = rib_run
    assert status == 0 and step, err
    return step


def test_step_one_valid_solid_and_its_volume(stepped):
    """Read back by OCCT: one solid, BRepCheck_Analyzer valid; its volume (mass properties,
    adaptive to 1e-9) within 1e-6 relative of the brute-force integral, and OCCT's default
    integration (FreeCAD's) the same to 1e-8.  The bound the faces' fit allows: fit_tol times the
    two faces' area (< 7000 mm^2) is 7e-2 mm^3, 1.4e-7 of the volume."""
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    assert b"FILE_DESCRIPTION(('camgen barrel cam rib: B-spline rib faces within 1e-05 mm" in stepped
    shape = _read_step(stepped)
    solids, explorer = 0, TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        solids += 1
        explorer.Next()
    assert solids == 1 and BRepCheck_Analyzer(shape).IsValid()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props, 1e-9)
    exact = reference_volume()
    assert abs(props.Mass() - exact) <= 1e-6 * exact, (props.Mass(), exact)
    default = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, default)
    assert abs(default.Mass() - props.Mass()) <= 1e-8 * exact


def _hits(shape, origins: np.ndarray, direction: tuple[float, float, float], reach: float) -> list[list[float]]:
    """Parameters (mm along ``direction`` from each origin) where OCCT's intersector meets the
    solid's faces, sorted."""
    from OCP.gp import gp_Dir, gp_Lin, gp_Pnt
    from OCP.IntCurvesFace import IntCurvesFace_ShapeIntersector

    hit = IntCurvesFace_ShapeIntersector()
    hit.Load(shape, 1e-9)
    out = []
    for o in origins:
        hit.Perform(gp_Lin(gp_Pnt(*map(float, o)), gp_Dir(*direction)), 0.0, reach)
        out.append(sorted(hit.WParameter(i) for i in range(1, hit.NbPnt() + 1)))
    return out


def test_step_faces_within_fit_tol(stepped):
    """Vertical lines through 200 random points of the rib's annulus (outside the root cylinder)
    meet the solid twice: the lower and the upper face, each within fit_tol of the brute force."""
    shape = _read_step(stepped)
    rng = np.random.default_rng(11)
    r = rng.uniform(ROOT + 0.05, RIM - 0.05, 200)
    phi = rng.uniform(0.0, 2.0 * math.pi, 200)
    origins = np.column_stack([r * np.cos(phi), r * np.sin(phi), np.full(200, -1.0)])
    hits = _hits(shape, origins, (0.0, 0.0, 1.0), LENGTH + 2.0)
    assert all(len(h) == 2 for h in hits), hits
    lower, upper = (np.array(hits) - 1.0).T
    assert np.max(np.abs(upper - brute_face(1, r, phi))) <= STEP_TOL
    assert np.max(np.abs(lower - brute_face(-1, r, phi))) <= STEP_TOL


def test_step_rib_top_on_the_rim_and_base_on_the_root(stepped):
    """Radial lines from the bore outwards: at mid-rib height (between the brute-force faces) the
    solid ends at the rim radius; below the rib (z = 3 mm, under its lowest face) at the root
    radius; both start at the bore (exact cylinders: to 1e-9 mm)."""
    shape = _read_step(stepped)
    phi = 2.0 * math.pi * np.arange(24) / 24 + 0.01
    mid = 0.5 * (brute_face(1, np.full(24, R_M), phi) + brute_face(-1, np.full(24, R_M), phi))
    for z, outer in ((mid, RIM), (np.full(24, 3.0), ROOT)):
        origins = np.column_stack([np.zeros(24), np.zeros(24), z])
        for k, p in enumerate(phi):
            (h,) = _hits(shape, origins[k : k + 1], (math.cos(p), math.sin(p), 0.0), RIM + 5.0)
            assert len(h) == 2 and abs(h[0] - BORE) <= 1e-9 and abs(h[1] - outer) <= 1e-9, (z[k], h)


def test_step_opens_in_freecad(stepped, tmp_path):
    """FreeCAD (an independent reader of STEP: its own import into its Part workbench) finds one
    valid solid of the brute-force volume within 1e-6 relative."""
    freecad = require_tool("freecadcmd")
    path = tmp_path / "rib.step"
    path.write_bytes(stepped)
    script = tmp_path / "check.py"
    script.write_text("import Part\nshape = Part.read(%r)\nprint('CHECK', shape.isValid(), len(shape.Solids), repr(shape.Volume))\n"
                      % str(path))
    done = subprocess.run([freecad, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    line = [ln for ln in done.stdout.splitlines() if ln.startswith("CHECK")]
    assert line, done.stdout + done.stderr
    _, valid, solids, volume = line[0].split()
    assert valid == "True" and solids == "1"
    assert abs(float(volume) - reference_volume()) <= 1e-6 * reference_volume()


def test_step_of_crossing_faces_is_refused():
    """A rib too narrow for its rollers' spacing (its faces cross during the rise) has no STEP: a
    GeometryError naming the cam, as its mesh."""
    pytest.importorskip("OCP")
    from camgen.errors import GeometryError
    from camgen.export.barrel_rib_step import rib_step_bytes
    from camgen.synthesis.barrel import BarrelRib

    narrow = BarrelRib(make_groove("translating", 1, "cylindrical", BORE, STEP_TOL), 0.5)
    with pytest.raises(GeometryError, match="narrow-rib.*cross"):
        rib_step_bytes(narrow, "narrow-rib")


# ----------------------------------------------------------------------------------- the run
def rib_table(**extra) -> dict:
    return {"kind": "motion_law", "form": "barrel", "track": "rib", "rib_width_mm": RIB_W, "roller_radius_mm": RR,
            "cylinder_radius_mm": RIM, "cylinder_length_mm": LENGTH, "groove_depth_mm": RIM - ROOT,
            "groove_clearance_mm": CLEARANCE, "bore_diameter_mm": 2 * BORE, "fit_tol_mm": STEP_TOL, "pressure_angle_limit_deg": 45.0,
            "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": LIFT}, {"law": "dwell", "span_deg": 60.0},
                         {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -LIFT}, {"law": "dwell", "span_deg": 60.0}], **extra}


def files_of(formats: list[str], chord: float = CHORD) -> dict:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": formats, "chord_tol_mm": chord}, "cams": {"b": rib_table()}}, "t")
    return execute(scene, plan_run(scene)).files


def test_a_rib_scene_writes_its_step(rib_run):
    """`camgen run` of a rib scene asking for STEP exits 0 (no longer refused) and writes one
    rib.step; that file is the one test_step_one_valid_solid_and_its_volume reads back (one valid
    solid of the brute-force volume) and the other STEP tests measure."""
    status, err, step = rib_run
    assert status == 0, err
    assert step.startswith(b"ISO-10303-21;") and b"FILE_DESCRIPTION(('camgen barrel cam rib: B-spline rib faces" in step


# ----------------------------------------------------------------------------------- the ride
@pytest.fixture(scope="module")
def meshed():
    from camgen.export.barrel_rib_solid import rib_solid

    return rib_solid(make_rib(), MESH_TOL, "rib")


def pitch_range(theta: np.ndarray, faces) -> tuple[np.ndarray, np.ndarray]:
    """The lowest and the highest pitch height z_p (mm) the two rollers (radius Rr, not widened;
    axes at z_p +- O) can take astride the rib at each cam angle: their sections at three radii,
    401 points across each, the upper roller held above the upper face (z_p >= z_up + half - O),
    the lower one below the lower face (z_p <= z_lo - half + O).  ``faces(x, y) -> (z_up, z_lo)``
    reads the rib."""
    low, high = np.full(len(theta), -np.inf), np.full(len(theta), np.inf)
    for r in (ROOT + 0.1, R_M, RIM - 0.1):
        reach = math.asin(min(1.0, RR / r))
        a = np.linspace(-reach, reach, 401)[None, :] + 0.0 * theta[:, None]
        y = r * np.sin(a)
        half = np.sqrt(np.maximum(RR * RR - y * y, 0.0))
        phi = a - theta[:, None]  # ccw: the follower at world angle a reads the cam at a - theta
        z_up, z_lo = faces(r * np.cos(phi), r * np.sin(phi))
        low = np.maximum(low, np.max(z_up + half - O, axis=1))
        high = np.minimum(high, np.min(z_lo - half + O, axis=1))
    return low, high


def test_follower_rides_the_rib_mesh(meshed):
    """The follower simulated on the exported mesh: the range of pitch heights the two rollers can
    take astride the mesh's rib (read by vertical lines) is the range the brute-force rib allows,
    within the chord tolerance; the required z_c(theta) = z0 + s(theta) lies in it with at least
    c / 2 - tol of play either way, exactly c / 2 in the dwells: the motion read back from the
    file is the law's."""
    theta = np.radians(RIDE)
    zc, _ = axis(make_groove(), theta)

    def mesh(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        lower, upper = mesh_walls(meshed.vertices, meshed.triangles, LENGTH, x, y)  # facing down: the lower face
        return upper, lower

    def exact(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r, phi = np.hypot(x, y), np.arctan2(y, x)
        return brute_face(1, r, phi), brute_face(-1, r, phi)

    low, high = pitch_range(theta, mesh)
    low_exact, high_exact = pitch_range(theta, exact)
    assert np.max(np.abs(low - low_exact)) <= MESH_TOL
    assert np.max(np.abs(high - high_exact)) <= MESH_TOL
    play = CLEARANCE / 2
    assert np.min(zc - low) >= play - MESH_TOL and np.min(high - zc) >= play - MESH_TOL
    assert np.max(np.abs(zc - low - play)[DWELLS]) <= MESH_TOL
    assert np.max(np.abs(high - zc - play)[DWELLS]) <= MESH_TOL


# ----------------------------------------------------------------------------------- drawing, points
def test_developed_dxf_faces_on_the_brute_force():
    """ezdxf reads the developed drawing: the rib's layers (no groove wall layers), each face one
    polyline over x = 0 .. 2 pi R_m whose vertices lie on the brute-force face at R_m (z at
    phi = x / R_m within 1e-6 mm) and whose chords' midpoints lie within the chord tolerance of it
    (the distance from the face's point at the midpoint's x to the chord: its height difference
    times the chord's cosine)."""
    import ezdxf

    doc = ezdxf.read(io.StringIO(files_of(["dxf"])["b.dxf"]))
    layers = {layer.dxf.name for layer in doc.layers}
    assert {"RIB_UPPER_DEVELOPED", "RIB_LOWER_DEVELOPED"} <= layers
    assert not {"WALL_UPPER_DEVELOPED", "WALL_LOWER_DEVELOPED"} & layers
    for side, layer in ((1, "RIB_UPPER_DEVELOPED"), (-1, "RIB_LOWER_DEVELOPED")):
        (poly,) = [e for e in doc.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == layer]
        pts = np.array([(p[0], p[1]) for p in poly.get_points("xy")])
        assert pts[0, 0] == pytest.approx(0.0, abs=1e-9) and pts[-1, 0] == pytest.approx(2 * math.pi * R_M, abs=1e-9)
        assert np.all(np.diff(pts[:, 0]) > 0.0)
        assert np.max(np.abs(pts[:, 1] - brute_face(side, np.full(len(pts), R_M), pts[:, 0] / R_M))) <= 1e-6
        mid = 0.5 * (pts[:-1] + pts[1:])
        d = np.diff(pts, axis=0)
        gap = np.abs(brute_face(side, np.full(len(mid), R_M), mid[:, 0] / R_M) - mid[:, 1]) * d[:, 0] / np.hypot(d[:, 0], d[:, 1])
        assert np.max(gap) <= CHORD


def test_point_list_on_the_brute_force():
    """pandas reads the point list: only the rib's faces (RIB_UPPER, RIB_LOWER) at the root, mean
    and rim radius, x and y the radius at the polar angle, z on the brute-force face within 1e-6 mm
    (the points are exact, written with 9 decimals; the stated tolerances are coarser)."""
    import pandas as pd

    table = pd.read_csv(io.StringIO(files_of(["points"])["b_points.csv"]))
    assert set(table["wall"]) == {"RIB_UPPER", "RIB_LOWER"}
    assert set(np.round(table["radius_mm"], 9)) == {ROOT, R_M, RIM}
    r, phi = table["radius_mm"].to_numpy(), np.radians(table["phi_deg"].to_numpy())
    assert np.max(np.abs(table["x_mm"] - r * np.cos(phi))) <= 1e-8 and np.max(np.abs(table["y_mm"] - r * np.sin(phi))) <= 1e-8
    for side, name in ((1, "RIB_UPPER"), (-1, "RIB_LOWER")):
        rows = (table["wall"] == name).to_numpy()
        assert np.max(np.abs(table["z_mm"].to_numpy()[rows] - brute_face(side, r[rows], phi[rows]))) <= 1e-6

