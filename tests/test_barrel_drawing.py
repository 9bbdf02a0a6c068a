"""A barrel cam's developed drawing (DXF) and the walls' point list against independent references.

* The DXF is read back by ezdxf.
* The developed pitch curve of a translating roller is ``(R_m phi, z0 + s(-sigma phi))`` with ``s``
  the cycloidal law in closed form (Norton, *Design of Machinery*, eq. 8.6).
* The walls come from the issue's brute force (the groove as the union of the roller's solids):
  ``z_upper(r, phi) = max over theta of [z_c + sqrt(w^2 - (r sin(phi + sigma theta) - e)^2)]``
  (``r cos(phi + sigma theta) > 0``), the lower wall its twin (min, minus the root), maximised over
  a dense cam-angle grid and refined by scipy's bounded scalar minimiser.
"""
from __future__ import annotations

import io
import math

import numpy as np
import pytest

from test_barrel_form import BETA, CLEAR, DEPTH, H, R_O, RR, W, cam, cycloidal, segments

R_M, R_I = R_O - DEPTH / 2, R_O - DEPTH
CHORD = 1e-3
#: The oscillating follower of these tests: arm 60 mm, a 20 deg cycloidal swing, the rest angle
#: centring it (-10 deg), the pivot at mid-length.
ARM, SWING, LENGTH_OSC = 60.0, 20.0, 60.0


def files_of(table: dict, formats=("dxf", "points"), chord=CHORD) -> dict:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": list(formats), "chord_tol_mm": chord}, "cams": {"c": table}}, "t")
    return execute(scene, plan_run(scene)).files


def oscillating(**extra) -> dict:
    return cam(follower_motion="oscillating", arm_length_mm=ARM, cylinder_length_mm=LENGTH_OSC,
               segments=segments("swing_deg", SWING), **extra)


def axis_of(table: dict):
    """The roller axis (z_c, e) against the cam angle, from the scene's values and the law's
    closed form (api.md's conventions)."""
    if table.get("follower_motion") == "oscillating":
        psi0 = -math.radians(SWING) / 2

        def axis(theta):
            psi = psi0 + cycloidal(theta, math.radians(SWING))
            return LENGTH_OSC / 2 + ARM * np.sin(psi), ARM * (np.cos(psi) - 1.0)
    else:
        z0 = table.get("pitch_z_mm", (table["cylinder_length_mm"] - H) / 2)

        def axis(theta):
            return z0 + cycloidal(theta), np.zeros_like(theta)
    return axis


def brute_wall(table: dict, side: int, r: float, phi: np.ndarray) -> np.ndarray:
    """The issue's brute force: the wall ``side`` (+1 upper, -1 lower) at radius ``r`` and polar
    angles ``phi`` as the extreme height of the union of the widened roller's solids."""
    from scipy.optimize import minimize_scalar

    sigma = -1 if table.get("rotation") == "cw" else 1
    axis = axis_of(table)
    step = 2e-5
    offsets = np.arange(-0.45, 0.45, step)
    out = np.empty(len(phi))

    def height(theta):
        z_c, e = axis(theta)
        u = phi_k + sigma * theta
        g = r * np.sin(u) - e
        inside = (w * w - g * g >= 0.0) & (r * np.cos(u) > 0.0)
        return np.where(inside, z_c + side * np.sqrt(np.where(inside, w * w - g * g, 0.0)), -side * np.inf)

    w = W
    for k, phi_k in enumerate(phi):
        theta = -sigma * phi_k + offsets
        f = side * height(theta)
        i = int(np.argmax(f))
        best = minimize_scalar(lambda t: -side * float(height(np.array([t]))[0]), bounds=(theta[i] - 2 * step, theta[i] + 2 * step),
                               method="bounded", options={"xatol": 1e-13})
        out[k] = max(f[i], -best.fun) * side
    return out


def read_dxf(text: str):
    import ezdxf

    return ezdxf.read(io.StringIO(text))


def layer_points(doc, layer: str) -> np.ndarray:
    (poly,) = [e for e in doc.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == layer]
    return np.array([(p[0], p[1]) for p in poly.get_points("xy")])


def distance_to_polyline(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of each point (n, k) from the polyline (m, k) whose first coordinate increases
    (each point against the segments about its abscissa)."""
    i = np.clip(np.searchsorted(poly[:, 0], points[:, 0]) - 1, 0, len(poly) - 2)
    best = np.full(len(points), np.inf)
    for j in (i - 1, i, i + 1):
        j = np.clip(j, 0, len(poly) - 2)
        a, b = poly[j], poly[j + 1]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", points - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(points - a - t[:, None] * ab, axis=1))
    return best


# --------------------------------------------------------------------------------------------
# The developed drawing
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_developed_pitch_curve_is_the_closed_form_within_the_chord_tolerance(rotation):
    table = cam(rotation=rotation, cylinder_length_mm=80.0)
    chord = 1e-5  # fine enough that the drawing's sampling must refine (720 points give 1e-3 mm)
    doc = read_dxf(files_of(table, ("dxf",), chord)["c.dxf"])
    assert {"PITCH_DEVELOPED", "WALL_UPPER_DEVELOPED", "WALL_LOWER_DEVELOPED", "OUTLINE_DEVELOPED"} <= {l.dxf.name for l in doc.layers}
    pitch = layer_points(doc, "PITCH_DEVELOPED")
    sigma = -1 if rotation == "cw" else 1
    z0 = (80.0 - H) / 2

    def closed(x):
        return z0 + cycloidal(-sigma * x / R_M)

    assert pitch[0, 0] == pytest.approx(0.0, abs=1e-12) and pitch[-1, 0] == pytest.approx(2 * math.pi * R_M, abs=1e-9)
    assert np.max(np.abs(pitch[:, 1] - closed(pitch[:, 0]))) < 1e-9  # every vertex on the curve
    x = np.linspace(0.0, 2 * math.pi * R_M, 400001)
    dense = np.column_stack([x, closed(x)])
    assert np.max(distance_to_polyline(dense, pitch)) <= chord  # the curve within the chord tolerance of its polyline
    # the mid-points of the chords within it of the curve (the polyline is no coarser than it must be... nor off it)
    mid = 0.5 * (pitch[1:] + pitch[:-1])
    assert np.max(distance_to_polyline(mid, dense)) <= chord + 1e-7
    outline = layer_points(doc, "OUTLINE_DEVELOPED")
    assert np.allclose(sorted(map(tuple, outline)), sorted([(0, 0), (2 * math.pi * R_M, 0), (2 * math.pi * R_M, 80), (0, 80)]))
    texts = [e.dxf.text for e in doc.modelspace() if e.dxftype() == "TEXT"]
    assert len(texts) == 1 and "developed at mean radius R_m = 50 mm" in texts[0]


@pytest.mark.parametrize("table", [cam(cylinder_length_mm=80.0), cam(rotation="cw", cylinder_length_mm=80.0), oscillating()],
                         ids=["translating", "translating-cw", "oscillating"])
def test_developed_walls_are_the_brute_force_at_the_mean_radius(table):
    doc = read_dxf(files_of(table, ("dxf",))["c.dxf"])
    for side, layer in ((1, "WALL_UPPER_DEVELOPED"), (-1, "WALL_LOWER_DEVELOPED")):
        pts = layer_points(doc, layer)
        assert pts[0, 0] == pytest.approx(0.0, abs=1e-12) and pts[-1, 0] == pytest.approx(2 * math.pi * R_M, abs=1e-9)
        pick = np.linspace(0, len(pts) - 2, 41).astype(int)
        vertices = pts[pick]
        assert np.max(np.abs(brute_wall(table, side, R_M, vertices[:, 0] / R_M) - vertices[:, 1])) < 1e-6, layer
        # the chords: the wall at each picked chord's middle within the chord tolerance of it
        x_mid = 0.5 * (pts[pick, 0] + pts[pick + 1, 0])
        z_mid = brute_wall(table, side, R_M, x_mid / R_M)
        a, b = pts[pick], pts[pick + 1]
        ab = b - a
        q = np.column_stack([x_mid, z_mid]) - a
        t = np.clip(np.einsum("ij,ij->i", q, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        assert np.max(np.linalg.norm(q - t[:, None] * ab, axis=1)) <= CHORD, layer


# --------------------------------------------------------------------------------------------
# The point list
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("table", [cam(cylinder_length_mm=80.0), oscillating(rotation="cw")], ids=["translating", "oscillating-cw"])
def test_point_list_is_the_brute_force_at_root_mean_and_rim(table):
    import csv
    import json

    chord = 1e-4
    files = files_of(table, ("points",), chord)
    rows = list(csv.reader(io.StringIO(files["c_points.csv"])))
    assert rows[0] == ["wall", "radius_mm", "phi_deg", "x_mm", "y_mm", "z_mm"]
    body = rows[1:]
    walls = np.array([r[0] for r in body])
    data = np.array([[float(v) for v in r[1:]] for r in body])
    groups = [(w, r) for w, r in dict.fromkeys(zip(walls, data[:, 0]))]
    assert groups == [(w, r) for r in (R_I, R_M, R_O) for w in ("UPPER", "LOWER")]
    meta = json.loads(files["report.json"])["tables"]["c_points.csv"]
    assert meta["chord_tol_mm"] == chord and set(meta["columns"]) == {"wall", "radius_mm", "phi_deg", "x_mm", "y_mm", "z_mm"}
    for wall, r in groups:
        sel = (walls == wall) & (data[:, 0] == r)
        pts = data[sel]
        phi = np.radians(pts[:, 1])
        assert np.all(np.diff(phi) > 0) and phi[0] == 0.0 and phi[-1] < 2 * math.pi  # one closed section, counter-clockwise
        assert np.max(np.abs(pts[:, 2] - r * np.cos(phi))) < 1e-8 and np.max(np.abs(pts[:, 3] - r * np.sin(phi))) < 1e-8
        side = 1 if wall == "UPPER" else -1
        pick = np.linspace(0, len(pts) - 2, 17).astype(int)
        assert np.max(np.abs(brute_wall(table, side, r, phi[pick]) - pts[pick, 4])) < 1e-6, (wall, r)
        # the chord to the next row within the chord tolerance of the wall at its middle angle
        mid = 0.5 * (phi[pick] + phi[pick + 1])
        p = np.column_stack([r * np.cos(mid), r * np.sin(mid), brute_wall(table, side, r, mid)])
        a, b = pts[pick, 2:5], pts[pick + 1, 2:5]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        assert np.max(np.linalg.norm(p - a - t[:, None] * ab, axis=1)) <= chord, (wall, r)


def test_developed_drawing_writes_no_heavy_library():
    """A DXF-only barrel run imports none of the heavy libraries (a subprocess, fresh imports)."""
    import subprocess
    import sys

    from helpers import scene_toml

    code = ("import sys, tempfile, pathlib\n"
            "from camgen.cli import main\n"
            "d = pathlib.Path(tempfile.mkdtemp()); p = d / 's.toml'\n"
            f"p.write_text({scene_toml({'output': {'formats': ['dxf']}, 'cams': {'c': cam(cylinder_length_mm=80.0, pressure_angle_limit_deg=45.0)}})!r})\n"
            "rc = main(['run', str(p), '-o', str(d / 'o'), '--quiet', '--only', 'dxf'])\n"
            "heavy = [m for m in ('scipy', 'trimesh', 'OCP', 'gmsh', 'manifold3d', 'meshio') if m in sys.modules]\n"
            "print(rc, heavy)\n")
    out = subprocess.run([sys.executable, "-P", "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "0 []", out
