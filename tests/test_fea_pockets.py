"""FEA volume meshes of a body with pockets (camgen.export.fea_pockets): the plate less bore and
keyway less each pocket from the top face down its depth, as wedges and as tetrahedra.

The bodies are tests/test_pocket_files.py's (a rim circle, a bore with keyway; grooves between
circles, concentric and eccentric, closed forms pi r^2; a groove between the offsets of a spline
pitch curve, a dense shoelace; a blind slot, a through slot, a groove and a slot), the bundled
groove cam (Steiner's formula on the closed-form pitch curve) and a linear cam with a slot (a
rounded rectangle less the disc of the slot's half width swept along the pitch curve
(x, s(x)): 2 w L + pi w^2).  Every file is read back by meshio; the volumes, the node sets and
the elements' orientation are measured there; CalculiX solves the .inp and gmsh reads the .msh.
"""
from __future__ import annotations

import json
import math
import re
import subprocess

import numpy as np
import pytest

from helpers import require_tool
from test_fea import _inp_sets, _run_ccx, _totals, require_module
from test_pocket_files import BODY, CASES, RIM_CONTOUR, THICKNESS, exact_volume, pocket_area, volume_bound
from test_solid import wedge_volumes

TOL = 0.01  # chord tolerance of the meshes built here (mm): coarse, the tetrahedra stay few


def _tet_volumes(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    p = points[cells]
    return np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0


def _read_back(mesh, tmp_path, name: str = "cam") -> dict:
    """Every format of ``mesh`` written and read back by meshio: {fmt: (points, cells of the kind)}."""
    import meshio

    from camgen.export.fea import fea_bytes

    kind = "wedge" if mesh.elements == "wedge" else "tetra"
    out = {}
    for fmt in ("vtu", "msh", "inp"):
        path = tmp_path / f"{name}.{fmt}"
        path.write_bytes(fea_bytes(mesh, fmt, name))
        read = meshio.read(path)
        assert list(read.cells_dict) == [kind], (fmt, list(read.cells_dict))
        cells = read.cells_dict[kind]
        if fmt == "vtu" and kind == "wedge":  # meshio turns a VTK wedge's base round on reading (see test_fea)
            cells = cells[:, [0, 2, 1, 3, 5, 4]]
        out[fmt] = (read.points, cells)
    return out


def _wall_distance(contour, points: np.ndarray) -> np.ndarray:
    """Distance (mm) of ``points`` (n, 2) to the exact wall ``contour``: a circle's closed form,
    else the dense chain of tests/test_dxf.py (chords of 1/1024 piece)."""
    from camgen.contour import Arc
    from test_dxf import exact_chain

    seg = contour.segments[0]
    if contour.n_segments == 1 and isinstance(seg, Arc):
        return np.abs(np.hypot(points[:, 0] - seg.center[0], points[:, 1] - seg.center[1]) - seg.radius)
    return exact_chain(contour, per_piece=1024).distance(points)


def _on_polygon(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Whether each point (n, 2) lies on the closed polygon's boundary (GEOS, 1e-9 mm)."""
    import shapely
    from shapely.geometry import LinearRing

    return shapely.distance(LinearRing(polygon), shapely.points(points)) <= 1e-9


def assert_sets_on_their_faces(mesh, pockets, points: np.ndarray, tol: float, thickness: float) -> None:
    """Every node of a wall's set lies on that wall (within ``tol`` of the exact curve) between its
    floor and the top; every node on the wall's polygon at those heights is in the set; the
    floor set at the floor's height, inside the pocket; BOTTOM and TOP at 0 and the thickness."""
    import shapely
    from shapely.geometry import Polygon

    sets = mesh.node_sets
    for pocket in pockets:
        floor = thickness - pocket.depth
        for wall in pocket.walls:
            members = sets[wall.layer]
            p = points[members]
            assert len(members) > 0
            assert np.max(_wall_distance(wall.contour, p[:, :2])) <= tol + 1e-9
            assert np.all(p[:, 2] >= floor - 1e-12) and np.all(p[:, 2] <= thickness + 1e-12)
            polygon = wall.contour.flatten(tol)
            on = np.flatnonzero(_on_polygon(points[:, :2], polygon) & (points[:, 2] >= floor - 1e-9))
            assert set(on.tolist()) == set(members.tolist()), wall.layer
        name = f"{pocket.name.upper()}_FLOOR"
        if floor <= 0:
            assert name not in sets
            continue
        p = points[sets[name]]
        assert np.all(p[:, 2] == floor)
        region = Polygon(pocket.walls[0].contour.flatten(tol), [w.contour.flatten(tol) for w in pocket.walls[1:]])
        assert np.all(shapely.distance(region, shapely.points(p[:, :2])) <= 1e-9)
        # and every node at the floor's height inside the pocket is on the floor
        inside = (points[:, 2] == floor) & shapely.contains_xy(region, points[:, 0], points[:, 1])
        assert set(np.flatnonzero(inside).tolist()) <= set(sets[name].tolist())
    assert np.all(points[sets["BOTTOM"], 2] == 0.0) and np.all(points[sets["TOP"], 2] == thickness)
    assert set(np.flatnonzero(points[:, 2] == 0.0).tolist()) == set(sets["BOTTOM"].tolist())
    assert set(np.flatnonzero(points[:, 2] == thickness).tolist()) == set(sets["TOP"].tolist())


@pytest.fixture(scope="module")
def meshes():
    """The FEA meshes of every body of test_pocket_files.py's CASES, wedges and tetrahedra, at TOL."""
    require_module("gmsh")
    from camgen.export.fea_pockets import body_volume_mesh as volume_mesh

    return {(case, elements): volume_mesh(RIM_CONTOUR, BODY, TOL, None, elements, pockets, case)
            for case, pockets in CASES.items() for elements in ("wedge", "tetra")}


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
@pytest.mark.parametrize("case", list(CASES))
def test_pocketed_body_read_back_has_the_closed_form_volume(case, elements, meshes, tmp_path):
    """meshio reads the vtu, msh and inp: the same points and elements; no element inverted (the
    wedge as three tetrahedra, the tetrahedron's determinant); their volumes add up to the
    closed form (plate less hole less pocket area x depth) within the chord tolerance's bound;
    the node sets lie on their faces."""
    mesh = meshes[(case, elements)]
    pockets = CASES[case]
    files = _read_back(mesh, tmp_path, case)
    points, cells = files["msh"]
    for fmt, (p, c) in files.items():
        assert np.allclose(p, points, rtol=0, atol=1e-12 * 50) and np.array_equal(c, cells), fmt
    volumes = wedge_volumes(points, cells) if elements == "wedge" else _tet_volumes(points, cells)
    assert np.all(volumes > 0)
    exact = exact_volume(pockets)
    bound = volume_bound(pockets, TOL)
    assert abs(volumes.sum() - exact) <= bound
    assert bound < 0.2 * min(pocket_area(p) * p.depth for p in pockets)  # a pocket left out (or cut twice) cannot pass
    assert_sets_on_their_faces(mesh, pockets, points, TOL, THICKNESS)
    if elements == "wedge":  # a layer boundary at every floor, the wedges vertical
        levels = np.unique(points[:, 2])
        for pocket in pockets:
            assert THICKNESS - pocket.depth in levels or pocket.depth == THICKNESS
        assert np.all(points[cells[:, 3:], :2] == points[cells[:, :3], :2])


def test_wedges_conform_and_leave_the_pockets_empty(meshes):
    """The wedge mesh is conforming (every interior face shared by exactly two wedges, read from
    the cells: a face of a wedge stacked on no other, or a side face met by one, would show as a
    boundary face not on the body's boundary) and no wedge lies inside a pocket above its floor."""
    import shapely
    from shapely.geometry import Polygon

    mesh = meshes[("groove_and_slot", "wedge")]
    pockets = CASES["groove_and_slot"]
    p = mesh.nodes[mesh.cells]
    centroid = p.mean(axis=1)
    for pocket in pockets:
        region = Polygon(pocket.walls[0].contour.flatten(TOL), [w.contour.flatten(TOL) for w in pocket.walls[1:]])
        inside = shapely.contains_xy(region, centroid[:, 0], centroid[:, 1])
        assert np.any(inside) and np.all(centroid[inside, 2] < THICKNESS - pocket.depth)
    # boundary faces: triangles (ends) and quads (sides) met by one wedge only
    tri = np.sort(np.concatenate([mesh.cells[:, :3], mesh.cells[:, 3:]]), axis=1)
    quads = np.concatenate([mesh.cells[:, [a, b, b + 3, a + 3]] for a, b in ((0, 1), (1, 2), (2, 0))])
    quads = np.sort(quads, axis=1)
    for faces in (tri, quads):
        _, counts = np.unique(faces, axis=0, return_counts=True)
        assert counts.max() <= 2
    # the boundary's area: the surface of the body (closed form of its loops, in the polygons)
    keys, counts = np.unique(tri, axis=0, return_counts=True)
    once = keys[counts == 1]
    q = mesh.nodes[once]
    area = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    from helpers import shoelace
    from camgen.export.solid import bore_polygon

    section = shoelace(RIM_CONTOUR.flatten(TOL)) - shoelace(bore_polygon(BODY, TOL))
    # horizontal boundary: bottom = section; top = section less the pockets; floors = the pockets
    assert area.sum() == pytest.approx(2 * section, rel=1e-12)


def test_a_wall_across_the_outline_is_refused():
    """A slot reaching past the rim: a GeometryError naming the cam (the run makes it a failed check)."""
    require_module("gmsh")
    from camgen.errors import GeometryError
    from camgen.export.fea_pockets import body_volume_mesh as volume_mesh
    from camgen.kinds.base import Pocket, Wall
    from test_pocket_files import circle

    across = (Pocket("slot", (Wall("SLOT", circle((47.0, 0.0), 6.0)),), 3.0),)
    for elements in ("wedge", "tetra"):
        with pytest.raises(GeometryError, match="cam 'x'"):
            volume_mesh(RIM_CONTOUR, BODY, TOL, None, elements, across, "x")


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
def test_gmsh_measures_the_pocketed_mesh(elements, meshes, tmp_path):
    """The gmsh program reads the groove's .msh: every element's Jacobian positive
    (AnalyseMeshQuality, as tests/test_fea.py), written back as the same elements."""
    from camgen.export.fea import fea_bytes

    gmsh = require_tool("gmsh")
    mesh = meshes[("spline", elements)]
    (tmp_path / "cam.msh").write_bytes(fea_bytes(mesh, "msh"))
    (tmp_path / "check.geo").write_text('Merge "cam.msh";\nPlugin(AnalyseMeshQuality).JacobianDeterminant = 1;\n'
                                        "Plugin(AnalyseMeshQuality).CreateView = 0;\nPlugin(AnalyseMeshQuality).Run;\n")
    proc = subprocess.run([gmsh, "check.geo", "-0", "-o", "out.msh", "-format", "msh22"], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0 and "Error" not in proc.stdout + proc.stderr, proc.stdout + proc.stderr
    checked = int(re.search(r"checking the Jacobian of (\d+) elements", proc.stdout).group(1))
    assert checked == len(mesh.cells)
    assert float(re.search(r"minJ\s*=\s*(\S+),", proc.stdout).group(1)) > 0


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
def test_calculix_solves_the_groove_with_a_load_on_a_wall(elements, meshes, tmp_path):
    """CalculiX reads the .inp, BOTTOM fixed, 1 N along x on every node of GROOVE_OUTER: it
    converges, the reaction is minus the load, its element volumes (EVOL) add up to the closed
    form within the bound; the header lists the sets."""
    ccx = require_tool("ccx")
    from camgen.export.fea import fea_bytes

    mesh = meshes[("eccentric", elements)]
    data = fea_bytes(mesh, "inp", "groove")
    text = data.decode()
    sets = _inp_sets(text)
    assert list(sets) == ["PROFILE", "BORE", "BOTTOM", "TOP", "GROOVE_OUTER", "GROOVE_INNER", "GROOVE_FLOOR"]
    header = re.search(r"^\*\* node sets: (.*)$", text, re.M).group(1)
    assert re.findall(r"\b([A-Z][A-Z_]*) \(", header) == list(sets)
    loaded = len(set(sets["GROOVE_OUTER"]) - set(sets["BOTTOM"]))
    assert loaded == len(sets["GROOVE_OUTER"])  # the wall is above the floor, off the bottom
    dat = _run_ccx(ccx, tmp_path, data, """*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=CAM, MATERIAL=STEEL
*STEP
*STATIC
*BOUNDARY
BOTTOM, 1, 3, 0.
*CLOAD
GROOVE_OUTER, 1, 1.0
*NODE PRINT, NSET=BOTTOM, TOTALS=ONLY
RF
*EL PRINT, ELSET=CAM, TOTALS=ONLY
EVOL
*END STEP
""")
    force = _totals(dat, "force", "BOTTOM")
    assert force[0] == pytest.approx(-loaded, rel=1e-6) and abs(force[1]) <= 1e-6 * loaded
    pockets = CASES["eccentric"]
    assert abs(_totals(dat, "volume", "CAM")[0] - exact_volume(pockets)) <= volume_bound(pockets, TOL) + 1e-6 * exact_volume(pockets)


# --------------------------------------------------------------------------------------------
# Through the run: the groove cam template, a linear cam with a slot
# --------------------------------------------------------------------------------------------
def test_groove_cam_template_fea_files(tmp_path):
    """`camgen run groove_cam.toml --only vtu,msh,inp` writes the three files (exit 0); meshio
    reads them; the volume is Steiner's closed form (test_pocket_files) within the bound; the
    sets lie on their faces; report.json states the mesh."""
    require_module("gmsh")
    from camgen.cli import main
    from camgen.kinds import get_kind
    from camgen.scene import load_template, template_path
    from test_dxf import hole_area
    from test_pocket_files import _cycloidal_pitch_length

    out = tmp_path / "out"
    assert main(["run", str(template_path("groove_cam")), "-o", str(out), "--only", "vtu,msh,inp", "--quiet"]) == 0
    folder = out / "groove_cam"
    scene = load_template("groove_cam")
    (spec,) = scene.cams
    cam = get_kind(spec.kind, spec.form).build(spec, frozenset())
    (groove,) = cam.pockets
    body, tol = cam.body, scene.output.chord_tol
    (rim,) = cam.contour.segments
    w = 10.0 + 0.05 / 2  # roller radius + clearance / 2 (the template)
    length = _cycloidal_pitch_length(60.0, 20.0)
    exact = (math.pi * rim.radius**2 - hole_area(body)) * body.thickness - 2 * w * length * groove.depth
    hole_perimeter = math.pi * body.bore_diameter + 2 * (body.keyway_depth + body.keyway_width)
    bound = tol * ((2 * math.pi * rim.radius + hole_perimeter) * body.thickness + 2 * length * groove.depth) + 1e-7 * exact
    import meshio

    read = {fmt: meshio.read(folder / f"track.{fmt}") for fmt in ("vtu", "msh", "inp")}
    points, cells = read["msh"].points, read["msh"].cells_dict["wedge"]
    for r in read.values():
        assert np.array_equal(r.points, points) or np.allclose(r.points, points, rtol=0, atol=1e-12)
    volumes = wedge_volumes(points, cells)
    assert np.all(volumes > 0) and abs(volumes.sum() - exact) <= bound
    text = (folder / "track.inp").read_text()
    sets = {name: np.array(ids) - 1 for name, ids in _inp_sets(text).items()}

    class Mesh:
        node_sets = sets

    assert_sets_on_their_faces(Mesh, cam.pockets, points, tol, body.thickness)
    report = json.loads((folder / "report.json").read_text())
    assert report["cams"]["track"]["figures"]["fea_mesh"]["element_count"] == len(cells)


LINEAR_SLOT = """
[output]
formats = ["inp", "msh", "vtu"]
chord_tol_mm = {tol}
{extra}
[cams.slider]
kind = "motion_law"
form = "linear"
linear_form = "slot"
travel_mm = 200.0
margin_start_mm = 30.0
margin_end_mm = 30.0
below_pitch_mm = 30.0
above_pitch_mm = 45.0
corner_radius_mm = 5.0
follower = "roller"
roller_radius_mm = 8.0
slot_clearance_mm = 0.2
slot_depth_mm = 6.0
thickness_mm = 15.0

[[cams.slider.segments]]
law = "cycloidal"
span_mm = 100.0
lift_mm = 15.0

[[cams.slider.segments]]
law = "cycloidal"
span_mm = 100.0
lift_mm = -15.0
"""


def _cycloidal_graph_length(travel: float, lift: float, samples: int = 400_000) -> float:
    """Length (mm) of the graph (x, s(x)): cycloidal rise of ``lift`` over the first half of
    ``travel``, cycloidal return over the second (Norton eq. 8.6), a dense polyline."""
    x = np.linspace(0.0, travel, samples + 1)
    half = travel / 2
    u = np.clip(x / half, 0, 1)
    v = np.clip((x - half) / half, 0, 1)
    s = lift * (u - np.sin(2 * math.pi * u) / (2 * math.pi)) - lift * (v - np.sin(2 * math.pi * v) / (2 * math.pi))
    return float(np.sum(np.hypot(np.diff(x), np.diff(s))))


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
def test_linear_cam_with_a_slot_fea_files(elements, tmp_path, capsys):
    """A linear cam with linear_form = "slot" through the run: exit 0; the volume is the rounded
    plate (W H - (4 - pi) c^2) x thickness less the slot (the disc of radius w swept along the
    pitch curve of length L: 2 w L + pi w^2, the pitch curve's radius of curvature above w) x
    depth, within the chord tolerance's bound; the SLOT and SLOT_FLOOR sets on their faces."""
    require_module("gmsh")
    import meshio

    from camgen.cli import main
    from camgen.scene import load_scene

    extra = 'fea_elements = "tetra"' if elements == "tetra" else ""
    tol = 0.05 if elements == "tetra" else 0.01  # the tetrahedra's caps want a coarser tolerance (they say so)
    scene = tmp_path / "slider.toml"
    scene.write_text(LINEAR_SLOT.format(extra=extra, tol=tol))
    assert main(["run", str(scene), "-o", str(tmp_path / "out"), "--quiet"]) == 0, capsys.readouterr().err
    folder = tmp_path / "out" / "slider"
    w = 8.0 + 0.2 / 2
    width, height, c, thickness, depth = 200.0 + 60.0, 30.0 + 45.0, 5.0, 15.0, 6.0
    length = _cycloidal_graph_length(200.0, 15.0)
    exact = (width * height - (4 - math.pi) * c * c) * thickness - (2 * w * length + math.pi * w * w) * depth
    bound = tol * (2 * (width + height) * thickness + 2 * (length + math.pi * w) * depth)
    read = meshio.read(folder / "slider.msh")
    kind = "wedge" if elements == "wedge" else "tetra"
    points, cells = read.points, read.cells_dict[kind]
    volumes = wedge_volumes(points, cells) if kind == "wedge" else _tet_volumes(points, cells)
    assert np.all(volumes > 0) and abs(volumes.sum() - exact) <= bound
    assert bound < 0.05 * (2 * w * length) * depth  # a slot left out cannot pass
    text = (folder / "slider.inp").read_text()
    sets = {name: np.array(ids) - 1 for name, ids in _inp_sets(text).items()}
    assert list(sets) == ["PROFILE", "BOTTOM", "TOP", "SLOT", "SLOT_FLOOR"]
    s = load_scene(scene)
    from camgen.kinds import get_kind

    cam = get_kind(s.cams[0].kind, s.cams[0].form).build(s.cams[0], frozenset())

    class Mesh:
        node_sets = sets

    assert_sets_on_their_faces(Mesh, cam.pockets, points, tol, thickness)


def test_fea_estimates_bound_the_pocketed_meshes(meshes):
    """The counts and bytes estimated before meshing (the caps, the walls counted) are at least
    those of the meshes made."""
    from camgen.export.fea import estimate, fea_bytes, file_bytes, section_outline

    for (case, elements), mesh in meshes.items():
        est = estimate(section_outline(RIM_CONTOUR, BODY, TOL, None, CASES[case]), THICKNESS, elements)
        assert est.elements >= len(mesh.cells) and est.nodes >= len(mesh.nodes), (case, elements)
        for fmt in ("inp", "msh", "vtu"):
            assert file_bytes(fmt, est, elements) >= len(fea_bytes(mesh, fmt)), (case, elements, fmt)
