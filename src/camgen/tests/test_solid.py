"""Extruded solids and mesh files, read back by trimesh, meshio and admesh."""
from __future__ import annotations

import math
import re
import subprocess

import numpy as np
import pytest

from camgen.errors import GeometryError
from camgen.export.solid import SolidSpec, cam_solid, mesh_bytes
from camgen.tests.cams import BODIES
from camgen.tests.helpers import require_tool


def _shapely_section(contour, body, tol):
    from shapely.geometry import Polygon, box
    from shapely import affinity

    outer = Polygon(contour.flatten(tol))
    r = body.bore_diameter / 2
    n = max(8, math.ceil(2 * math.pi / (2 * math.acos(1 - tol / r))))
    a = 2 * math.pi * np.arange(n) / n
    hole = Polygon(np.stack([r * np.cos(a), r * np.sin(a)], 1))
    key = box(0, -body.keyway_width / 2, r + body.keyway_depth, body.keyway_width / 2)
    key = affinity.rotate(key, body.keyway_angle, origin=(0, 0), use_radians=True)
    return outer.difference(hole.union(key))


@pytest.mark.parametrize("name", ["stride", "height", "steering"])
def test_solid_is_watertight_genus_one_with_the_right_volume(name, contours):
    import trimesh
    contour, body, tol = contours[name], BODIES[name], 1e-3
    solid = cam_solid(contour, body, tol)
    mesh = trimesh.Trimesh(solid.vertices, solid.triangles, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume
    assert mesh.euler_number == 0 and solid.genus == 1  # one hole through the body
    section = _shapely_section(contour, body, tol)  # independent 2-D boolean (GEOS)
    assert solid.volume == pytest.approx(section.area * body.thickness, rel=1e-9)
    assert mesh.volume == pytest.approx(solid.volume, rel=1e-12)
    # against the exact profile area: the chords cut off at most perimeter x chord_tol
    r, h = body.bore_diameter / 2, body.keyway_width / 2
    # keyway area outside the bore: strip |y| <= h, 0 <= x <= r + depth, minus the disc part
    keyway = 2 * h * (r + body.keyway_depth) - (h * math.sqrt(r * r - h * h) + r * r * math.asin(h / r))
    exact = (contour.area - math.pi * r * r - keyway) * body.thickness
    assert abs(solid.volume - exact) <= (contour.length + math.pi * body.bore_diameter + 4 * body.keyway_depth) * tol * body.thickness


@pytest.mark.parametrize("fmt", ["stl", "stl_ascii", "3mf", "obj", "ply", "vtu", "msh", "inp"])
def test_mesh_formats_read_back(fmt, contours, tmp_path):
    contour, body = contours["stride"], BODIES["stride"]
    solid = cam_solid(contour, body, 1e-3)
    data = mesh_bytes(solid, fmt, "stride")
    assert data == mesh_bytes(solid, fmt, "stride")  # deterministic
    suffix = {"stl_ascii": "stl"}.get(fmt, fmt)
    path = tmp_path / f"cam.{suffix}"
    path.write_bytes(data)
    if fmt in ("vtu", "msh", "inp"):
        import meshio

        mesh = meshio.read(path)
        tri = mesh.points[mesh.cells_dict["triangle"]]
        volume = np.sum(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))) / 6
        assert volume == pytest.approx(solid.volume, rel=1e-12)
        return
    import trimesh

    mesh = trimesh.load(path, force="mesh")
    assert mesh.is_watertight and mesh.is_winding_consistent
    rel = 1e-6 if fmt in ("stl", "ply", "3mf") else 1e-9  # float32 in binary STL/PLY, 3MF text precision
    assert mesh.volume == pytest.approx(solid.volume, rel=rel)
    if fmt == "3mf":
        assert mesh.units in ("millimeter", "millimeters", "mm")


def test_binary_stl_passes_admesh(contours, tmp_path):
    admesh = require_tool("admesh")
    path = tmp_path / "cam.stl"
    solid = cam_solid(contours["height"], BODIES["height"], 1e-3)
    path.write_bytes(mesh_bytes(solid, "stl"))
    # admesh always exits 0 and echoes the 80-byte header's raw bytes: decode leniently, parse the figures
    out = subprocess.run([admesh, "-e", str(path)], capture_output=True, timeout=60).stdout.decode("utf-8", "replace")
    figures = {k.strip(): v for k, v in re.findall(r"^([A-Za-z ]+?)\s*:\s*(\d+)", out, re.M)}
    for key in ("Degenerate facets", "Edges fixed", "Facets removed", "Facets added", "Facets reversed", "Backwards edges", "Normals fixed"):
        assert int(figures[key]) == 0, (key, out)
    assert re.search(r"Total disconnected facets\s*:\s*0\s+0", out), out
    assert re.search(r"Number of facets\s*:\s*(\d+)", out).group(1) == str(len(solid.triangles))
    assert float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1)) == pytest.approx(solid.volume, rel=1e-6)


@pytest.mark.parametrize(
    "body, fragment",
    [
        (SolidSpec(bore_diameter=21.0, min_wall=0.5), "breaks through"),
        (SolidSpec(bore_diameter=16.0, min_wall=3.0), "wall of only"),
        (SolidSpec(bore_diameter=8.0, keyway_width=2.0, keyway_depth=6.0, keyway_angle=0.0, min_wall=0.5), "breaks through"),
    ],
)
def test_bore_or_keyway_breaking_the_wall_is_an_error(body, fragment, contours):
    with pytest.raises(GeometryError, match=fragment):
        cam_solid(contours["height"], body)  # base radius c = 10 mm


def test_wall_is_measured_where_it_is_thinnest(contours):
    from camgen.export.solid import wall_left

    wall, where = wall_left(contours["height"], SolidSpec(bore_diameter=8.0))
    # the whole base arc (+-30 deg for b = a) is 10 mm from the axis
    assert wall == pytest.approx(10.0 - 4.0, abs=2e-4) and (where <= 30.01 or where >= 329.99)
    wall, where = wall_left(contours["height"], SolidSpec(bore_diameter=8.0, keyway_width=2.0, keyway_depth=5.5, keyway_angle=0.0))
    # thinnest at the keyway's outer corners (9.5, +-1): 10 - hypot(9.5, 1) from the base circle
    assert wall == pytest.approx(10.0 - math.hypot(9.5, 1.0), abs=2e-4) and (where < 15 or where > 345)

