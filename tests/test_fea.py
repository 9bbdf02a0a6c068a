"""FEA volume meshes (camgen.export.fea), read back and solved by independent programs:
CalculiX solves every template's .inp, gmsh and meshio read the .msh, meshio and VTK the .vtu;
the mesh quality (least angle, size grading) is measured from the files; a closed form (Lame's
ring) checks a displacement; nothing is written outside the run's folder."""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from helpers import require_tool
from test_solid import _shapely_section, wedge_volumes


def require_module(name: str):
    """The module ``name`` (a test extra); skip where missing, fail with CAMGEN_REQUIRE_VALIDATORS=1."""
    import importlib

    try:
        return importlib.import_module(name)
    except ImportError:
        why = f"python module {name} not installed (pip install '.[test]')"
        if os.environ.get("CAMGEN_REQUIRE_VALIDATORS") == "1":
            pytest.fail(why + ", but CAMGEN_REQUIRE_VALIDATORS=1: the validators must run")
        pytest.skip(why)


def _template_cams():
    """Every bundled template whose cams' forms mesh for FEA (the groove cam's body with its
    groove: tests/test_fea_pockets.py has the pocketed bodies' own tests; a barrel cam's form
    refuses the FEA formats, tests/test_barrel_form.py checks the refusal)."""
    from golden.regenerate import TEMPLATES

    from camgen.forms import get_form
    from camgen.scene import load_template

    def meshed(template: str) -> bool:
        return not any({"inp", "msh", "vtu"} & set(get_form(spec.form).formats_refused) for spec in load_template(template).cams)

    # packaging_machine's cams (a groove, an oscillating roller, a translating roller) are of the kinds the
    # groove_cam, oscillating_roller and plate_cam templates mesh: its run here would add time, not cover more
    return tuple(t for t in TEMPLATES if meshed(t) and t != "packaging_machine")


#: The pockets of each template cam (filled by the template_runs fixture).
POCKETS: dict = {}


@pytest.fixture(scope="module")
def template_runs(tmp_path_factory):
    """Every bundled template run with ``--only inp,msh,vtu`` (the files as a run writes them):
    {(template, cam): (folder, contour, body, chord_tol, figures)}; the cams' pockets in POCKETS."""
    require_module("gmsh")
    from camgen.cli import main
    from camgen.kinds import get_kind
    from camgen.scene import load_template, template_path

    out = tmp_path_factory.mktemp("fea")
    runs = {}
    for template in _template_cams():
        assert main(["run", str(template_path(template)), "-o", str(out), "--only", "inp,msh,vtu", "--quiet"]) == 0, template
        folder = out / template
        report = json.loads((folder / "report.json").read_text())
        scene = load_template(template)
        for spec in scene.cams:
            if not (folder / f"{spec.name}.inp").exists():
                continue
            cam = get_kind(spec.kind, spec.form).build(spec, frozenset())
            runs[(template, spec.name)] = (folder, cam.contour, cam.body, scene.output.chord_tol,
                                           report["cams"][spec.name]["figures"]["fea_mesh"])
            POCKETS[(template, spec.name)] = cam.pockets
    return runs


def _section_area(contour, body, tol) -> float:
    """GEOS's area of the profile polygon minus the bore polygon and keyway (independent boolean)."""
    from shapely.geometry import Polygon

    if body.bore_diameter > 0:
        return _shapely_section(contour, body, tol).area
    return Polygon(contour.flatten(tol)).area


def _body_volume(contour, body, tol, pockets=()) -> float:
    """GEOS's section area x thickness less each pocket's (inside its first wall's polygon,
    outside the others) area x depth."""
    from shapely.geometry import Polygon

    cut = sum(Polygon(p.walls[0].contour.flatten(tol), [w.contour.flatten(tol) for w in p.walls[1:]]).area * p.depth for p in pockets)
    return _section_area(contour, body, tol) * body.thickness - cut


def _inp_nodes(text: str) -> dict[int, np.ndarray]:
    block = text.split("*NODE, NSET=NALL\n")[1].split("*")[0]
    rows = np.array([[float(v) for v in line.split(",")] for line in block.splitlines() if line.strip()])
    return dict(zip(rows[:, 0].astype(int).tolist(), rows[:, 1:]))


def _inp_sets(text: str) -> dict[str, list[int]]:
    sets = {}
    for name, body in re.findall(r"\*NSET, NSET=(\w+)\n([^*]*)", text):
        sets[name] = [int(v) for v in re.findall(r"\d+", body)]
    return sets


def _run_ccx(ccx, folder, mesh: bytes, deck: str) -> str:
    (folder / "cam.inp").write_bytes(mesh)
    (folder / "job.inp").write_text("*INCLUDE, INPUT=cam.inp\n" + deck)
    proc = subprocess.run([ccx, "-i", "job"], cwd=folder, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0 and "ERROR" not in proc.stdout.upper().replace("ERROR ESTIMATOR", ""), proc.stdout[-3000:]
    assert (folder / "job.frd").stat().st_size > 0
    return (folder / "job.dat").read_text()


def _totals(dat: str, what: str, where: str) -> np.ndarray:
    block = re.search(rf"total {what} .*?for set {where} .*?\n\s*\n\s*(.*?)\n", dat, re.S | re.I)
    assert block, dat
    return np.array([float(v) for v in block.group(1).split()])


TEMPLATE_CAMS = [("default", "stride_length"), ("default", "stride_height"), ("default", "steering"), ("horse_leg", "stride_length"),
                 ("horse_leg", "stride_height"), ("motion_law", "rise_return"), ("tricycle", "steering"), ("plate_cam", "plate"),
                 ("flat_follower", "flat"), ("knife_follower", "knife"), ("oscillating_roller", "rocker"), ("oscillating_flat", "rocker"),
                 ("lift_table", "table"), ("conjugate_cam", "pair_a"), ("conjugate_cam", "pair_b"), ("constant_breadth", "yoke_cam"),
                 ("linear_cam", "lifter"), ("groove_cam", "track"), ("wire_edm_cam", "plate")]


def test_every_template_cam_has_fea_files(template_runs):
    """The list below is every cam of every template (so the parametrised tests cover them all)."""
    assert sorted(template_runs) == sorted(TEMPLATE_CAMS)


# (the groove cam's pocketed inp is solved by tests/test_fea_pockets.py, on a smaller body)
@pytest.mark.parametrize("template, cam", [c for c in TEMPLATE_CAMS if c[0] != "groove_cam"])
def test_calculix_solves_every_templates_inp(template, cam, template_runs, tmp_path):
    """CalculiX reads the .inp as written by the run and solves a static case: the bore fixed
    (the BOTTOM face where the cam has no bore), 0.5 N in x and -0.25 N in y on every PROFILE
    node: the reaction is minus the load (equilibrium), CalculiX's element volumes add up to
    GEOS's section area x thickness (less each pocket's area x depth).  The .inp names BORE
    exactly when the cam has a bore, a set per pocket wall and floor, and its header lists the
    sets it defines."""
    ccx = require_tool("ccx")
    folder, contour, body, tol, figures = template_runs[(template, cam)]
    pockets = POCKETS[(template, cam)]
    data = (folder / f"{cam}.inp").read_bytes()
    text = data.decode("ascii")
    sets = _inp_sets(text)
    expected = ["PROFILE", "BORE", "BOTTOM", "TOP"] if body.bore_diameter > 0 else ["PROFILE", "BOTTOM", "TOP"]
    for pocket in pockets:
        expected += [w.layer for w in pocket.walls] + [f"{pocket.name.upper()}_FLOOR"]
    assert list(sets) == expected
    header = re.search(r"^\*\* node sets: (.*)$", text, re.M).group(1)
    assert re.findall(r"\b([A-Z][A-Z_]*)\b(?: \(|,|$)", header) == ["NALL"] + list(sets)
    fixed = "BORE" if body.bore_diameter > 0 else "BOTTOM"
    n_profile = len(set(sets["PROFILE"]) - set(sets[fixed]))  # a load on a held node goes straight to the support
    dat = _run_ccx(ccx, tmp_path, data, f"""*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=CAM, MATERIAL=STEEL
*STEP
*STATIC
*BOUNDARY
{fixed}, 1, 3, 0.
*CLOAD
PROFILE, 1, 0.5
PROFILE, 2, -0.25
*NODE PRINT, NSET={fixed}, TOTALS=ONLY
RF
*EL PRINT, ELSET=CAM, TOTALS=ONLY
EVOL
*END STEP
""")
    force = _totals(dat, "force", fixed)
    assert force[:2] == pytest.approx([-0.5 * n_profile, 0.25 * n_profile], rel=1e-6)
    assert _totals(dat, "volume", "CAM")[0] == pytest.approx(_body_volume(contour, body, tol, pockets), rel=1e-6)  # .dat prints 7 digits
    elements = text.split("*ELEMENT, TYPE=C3D6, ELSET=CAM\n")[1].split("*")[0].splitlines()
    assert figures["element_count"] == len(elements) and all(len(line.split(",")) == 7 for line in elements)


def _lame_ring_outer_displacement(a: float, b: float, u0: float, nu: float) -> float:
    """Radial displacement of the free rim r = b of a ring a < r < b whose bore is pushed out by
    u0, plane stress (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., art. 28: u = A r + B / r,
    sigma_r = E / (1 - nu^2) ((1 + nu) A - (1 - nu) B / r^2) = 0 at r = b)."""
    k = (1.0 - nu) / ((1.0 + nu) * b * b)  # A = k B
    big_b = u0 / (k * a + 1.0 / a)
    return k * big_b * b + big_b / b


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
def test_ring_with_the_bore_pushed_out_matches_lame(elements, tmp_path):
    """A disc cam (radius 40 mm, 4 mm thick) with a 30 mm bore; every BORE node moved out
    radially by 0.01 mm (z held on the bottom edge only): the rim's mean radial displacement
    from CalculiX is Lame's plane-stress value within 1 %."""
    ccx = require_tool("ccx")
    require_module("gmsh")
    from camgen.body import BodySpec
    from camgen.contour import Arc, Contour
    from camgen.export.fea import fea_bytes, volume_mesh

    a, b, u0, nu = 15.0, 40.0, 0.01, 0.3
    contour = Contour([Arc((0.0, 0.0), b, 0.0, 2 * math.pi)])
    body = BodySpec(thickness=4.0, bore_diameter=2 * a, min_wall=1.0)
    text = fea_bytes(volume_mesh(contour, body, 1e-3, None, elements), "inp", "ring").decode()
    nodes, sets = _inp_nodes(text), _inp_sets(text)
    bottom = set(sets["BOTTOM"])
    lines = []
    for node in sets["BORE"]:
        x, y, z = nodes[node]
        r = math.hypot(x, y)
        lines += [f"{node}, 1, 1, {u0 * x / r:.12g}", f"{node}, 2, 2, {u0 * y / r:.12g}"] + ([f"{node}, 3, 3, 0."] if node in bottom else [])
    dat = _run_ccx(ccx, tmp_path, text.encode(), "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., " + repr(nu) + "\n"
                   "*SOLID SECTION, ELSET=CAM, MATERIAL=STEEL\n*STEP\n*STATIC\n*BOUNDARY\n" + "\n".join(lines) + "\n"
                   "*NODE PRINT, NSET=PROFILE\nU\n*END STEP\n")
    rows = re.findall(r"^\s*(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", dat.split("displacements")[1], re.M)
    assert len(rows) == len(sets["PROFILE"])
    radial = [(float(ux) * nodes[int(n)][0] + float(uy) * nodes[int(n)][1]) / math.hypot(*nodes[int(n)][:2]) for n, ux, uy, _ in rows]
    assert np.mean(radial) == pytest.approx(_lame_ring_outer_displacement(a, b, u0, nu), rel=0.01)


# --------------------------------------------------------------------------------------------
# Quality, measured from the files
# --------------------------------------------------------------------------------------------
def _triangle_angles(p: np.ndarray) -> np.ndarray:
    """Angles (deg) of triangles p (t, 3, 2 or 3), from the law of cosines on the edge lengths."""
    edge = np.stack([np.linalg.norm(p[:, (i + 1) % 3] - p[:, (i + 2) % 3], axis=1) for i in range(3)], axis=1)  # opposite vertex i
    out = []
    for i in range(3):
        a, b, c = edge[:, i], edge[:, (i + 1) % 3], edge[:, (i + 2) % 3]
        out.append(np.degrees(np.arccos(np.clip((b * b + c * c - a * a) / (2 * b * c), -1.0, 1.0))))
    return np.stack(out, axis=1)


def _distance_to_polygon(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Distance of each point to the closed polygon's boundary (GEOS)."""
    import shapely
    from shapely.geometry import LinearRing

    return shapely.distance(LinearRing(polygon), shapely.points(points))


@pytest.mark.parametrize("template, cam", TEMPLATE_CAMS)
def test_wedge_mesh_quality_from_the_msh(template, cam, template_runs):
    """From the .msh as meshio reads it: every bottom triangle's least angle >= 20 deg (law of
    cosines); neighbouring triangles differ in size (longest edge) by at most 2.5 x; no edge is
    longer than 1.5 x the element size stated in the .inp; every vertex of the profile polygon at
    chord_tol_mm is a node (exact coordinates) and every PROFILE node lies within chord_tol_mm
    of the exact profile; the layers are as high as stated; report.json's figures agree."""
    import meshio

    folder, contour, body, tol, figures = template_runs[(template, cam)]
    mesh = meshio.read(folder / f"{cam}.msh")
    wedges = mesh.cells_dict["wedge"]
    points = mesh.points
    bottom = wedges[np.all(points[wedges[:, :3], 2] == 0.0, axis=1), :3]
    p = points[bottom][:, :, :2]
    angles = _triangle_angles(p)
    assert angles.min() >= 20.0
    assert angles.min() == pytest.approx(figures["least_triangle_angle_deg"], abs=1e-9)
    longest = np.max(np.stack([np.linalg.norm(p[:, i] - p[:, (i + 1) % 3], axis=1) for i in range(3)], axis=1), axis=1)
    edges = np.sort(np.concatenate([bottom[:, [0, 1]], bottom[:, [1, 2]], bottom[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(bottom)), 3)
    order = np.lexsort(edges.T[::-1])
    e, o = edges[order], owner[order]
    shared = np.flatnonzero(np.all(e[1:] == e[:-1], axis=1))
    ratio = longest[o[shared]] / longest[o[shared + 1]]
    assert np.max(np.maximum(ratio, 1 / ratio)) <= 2.5
    text = (folder / f"{cam}.inp").read_text()
    size = float(re.search(r"element size (\S+) mm", text).group(1))
    assert longest.max() <= 1.5 * size
    polygon = contour.flatten(tol)
    polygon = np.where(np.abs(polygon) < 1e-9, 0.0, polygon)  # the files print sub-picometre values as 0
    at_bottom = points[points[:, 2] == 0.0][:, :2]
    assert {tuple(v) for v in polygon.tolist()} <= {tuple(v) for v in at_bottom.tolist()}
    nodes = _inp_nodes(text)
    profile = np.array([nodes[i][:2] for i in _inp_sets(text)["PROFILE"]])
    assert _distance_to_polygon(profile, polygon).max() <= 1e-9 * np.abs(polygon).max()
    levels = np.unique(points[:, 2])
    floors = sorted({body.thickness - p.depth for p in POCKETS[(template, cam)]} - {0.0})
    if not floors:
        assert levels == pytest.approx(np.linspace(0.0, body.thickness, figures["layers"] + 1), abs=1e-12)
        assert figures["layers"] == max(2, math.ceil(body.thickness / size - 1e-9))
    else:  # the README's rule: a layer boundary at each floor, ceil(length / size) equal layers between
        breaks = [0.0] + floors + [body.thickness]
        expected = np.concatenate([np.linspace(a, b, max(1, math.ceil((b - a) / size - 1e-9)) + 1)[:-1]
                                   for a, b in zip(breaks[:-1], breaks[1:])] + [[body.thickness]])
        assert levels == pytest.approx(expected, abs=1e-12) and figures["layers"] == len(expected) - 1


@pytest.fixture(scope="module")
def tetra_meshes(template_runs):
    """Tetrahedral meshes of two template cams (a bore with keyway; none), at their chord tolerance."""
    from camgen.export.fea import volume_mesh

    out = {}
    for key in (("plate_cam", "plate"), ("horse_leg", "stride_height")):
        folder, contour, body, tol, _ = template_runs[key]
        out[key] = (volume_mesh(contour, body, tol, None, "tetra"), contour, body, tol)
    return out


def _dihedral_angles(p: np.ndarray) -> np.ndarray:
    """The six dihedral angles (deg) of tetrahedra p (m, 4, 3): pi minus the angle between the
    outward normals of the two faces at each edge."""
    faces = {0: (1, 2, 3), 1: (0, 2, 3), 2: (0, 1, 3), 3: (0, 1, 2)}  # face opposite vertex i
    normals = {}
    for i, (a, b, c) in faces.items():
        n = np.cross(p[:, b] - p[:, a], p[:, c] - p[:, a])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        normals[i] = n * np.sign(np.einsum("ij,ij->i", n, p[:, a] - p[:, i]))[:, None]
    return np.stack([180.0 - np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", normals[i], normals[j]), -1, 1)))
                     for i in range(4) for j in range(i + 1, 4)], axis=1)


@pytest.mark.parametrize("key", [("plate_cam", "plate"), ("horse_leg", "stride_height")])
def test_tetra_mesh_read_back_and_measured(key, tetra_meshes, tmp_path):
    """Tetrahedra through the .msh (meshio): all of positive volume, adding up to GEOS's area x
    thickness; least dihedral angle >= 5 deg and as reported; BOTTOM/TOP on the faces, PROFILE
    nodes on the profile polygon, BORE only with a bore."""
    import meshio

    from camgen.export.fea import fea_bytes

    mesh, contour, body, tol = tetra_meshes[key]
    path = tmp_path / "cam.msh"
    path.write_bytes(fea_bytes(mesh, "msh"))
    read = meshio.read(path)
    tets = read.cells_dict["tetra"]
    p = read.points[tets]
    volume = np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0
    assert np.all(volume > 0)
    assert volume.sum() == pytest.approx(_section_area(contour, body, tol) * body.thickness, rel=1e-9)
    dihedral = _dihedral_angles(p)
    assert dihedral.min() >= 5.0 and dihedral.min() == pytest.approx(mesh.figures["least_dihedral_angle_deg"], abs=1e-9)
    assert ("BORE" in mesh.node_sets) == (body.bore_diameter > 0)
    assert np.all(read.points[mesh.node_sets["BOTTOM"], 2] == 0.0) and np.all(read.points[mesh.node_sets["TOP"], 2] == body.thickness)
    polygon = contour.flatten(tol)
    assert _distance_to_polygon(read.points[mesh.node_sets["PROFILE"], :2], polygon).max() <= 1e-9 * np.abs(polygon).max()
    text = fea_bytes(mesh, "inp").decode()
    assert "TYPE=C3D4" in text and f"{len(tets)} C3D4 tetrahedra" in text


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
def test_gmsh_reads_the_msh_as_volume_elements(elements, template_runs, tetra_meshes, tmp_path):
    """The gmsh program reads the .msh, finds every element's Jacobian positive (AnalyseMeshQuality)
    and writes it back as the same element type (6: prism, 4: tetrahedron) filling the volume."""
    import meshio

    from camgen.export.fea import fea_bytes

    gmsh = require_tool("gmsh")
    if elements == "wedge":
        folder, contour, body, tol, _ = template_runs[("default", "stride_length")]
        data = (folder / "stride_length.msh").read_bytes()
    else:
        mesh, contour, body, tol = tetra_meshes[("plate_cam", "plate")]
        data = fea_bytes(mesh, "msh")
    (tmp_path / "cam.msh").write_bytes(data)
    (tmp_path / "check.geo").write_text('Merge "cam.msh";\nPlugin(AnalyseMeshQuality).JacobianDeterminant = 1;\n'
                                        "Plugin(AnalyseMeshQuality).CreateView = 0;\nPlugin(AnalyseMeshQuality).Run;\n")
    proc = subprocess.run([gmsh, "check.geo", "-0", "-o", "out.msh", "-format", "msh22"], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0 and "Error" not in proc.stdout + proc.stderr, proc.stdout + proc.stderr
    checked = int(re.search(r"checking the Jacobian of (\d+) elements", proc.stdout).group(1))
    assert float(re.search(r"minJ\s*=\s*(\S+),", proc.stdout).group(1)) > 0
    out = meshio.read(tmp_path / "out.msh")
    kind = {"wedge": "wedge", "tetra": "tetra"}[elements]
    assert set(out.cells_dict) == {kind} and checked == len(out.cells_dict[kind])
    text = (tmp_path / "out.msh").read_text()
    types = {int(line.split()[1]) for line in text.split("$Elements\n")[1].split("$EndElements")[0].splitlines()[1:]}
    assert types == {6 if elements == "wedge" else 4}
    cells = out.cells_dict[kind]
    if elements == "wedge":
        total = wedge_volumes(out.points, cells).sum()
    else:
        p = out.points[cells]
        total = (np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0).sum()
    assert total == pytest.approx(_section_area(contour, body, tol) * body.thickness, rel=1e-9)


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
def test_vtu_read_by_meshio_and_vtk(elements, template_runs, tetra_meshes, tmp_path):
    """The in-memory VTU, read by meshio and by VTK's own XML reader: the .msh's points and cells,
    VTK_WEDGE 13 or VTK_TETRA 10 cells only, every cell of positive volume by VTK's own measure
    (vtkCellSizeFilter), adding up to the volume of the .msh's cells."""
    import meshio

    from camgen.export.fea import fea_bytes

    vtk = require_module("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    if elements == "wedge":
        folder, *_ = template_runs[("plate_cam", "plate")]
        vtu, msh = (folder / "plate.vtu").read_bytes(), (folder / "plate.msh").read_bytes()
    else:
        mesh = tetra_meshes[("horse_leg", "stride_height")][0]
        vtu, msh = fea_bytes(mesh, "vtu"), fea_bytes(mesh, "msh")
    (tmp_path / "cam.vtu").write_bytes(vtu)
    (tmp_path / "cam.msh").write_bytes(msh)
    reference = meshio.read(tmp_path / "cam.msh")
    kind = "wedge" if elements == "wedge" else "tetra"
    by_meshio = meshio.read(tmp_path / "cam.vtu")
    assert np.array_equal(by_meshio.points, reference.points)
    # meshio turns a VTK wedge's base round on reading (after an older text of vtkWedge's
    # documentation); VTK itself, below, finds the Gmsh order of positive volume
    turn = [0, 2, 1, 3, 5, 4] if elements == "wedge" else [0, 1, 2, 3]
    assert list(by_meshio.cells_dict) == [kind] and np.array_equal(by_meshio.cells_dict[kind], reference.cells_dict[kind][:, turn])
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "cam.vtu"))
    reader.Update()
    grid = reader.GetOutput()
    assert np.array_equal(vtk_to_numpy(grid.GetPoints().GetData()), reference.points)
    types = np.array([grid.GetCellType(i) for i in range(grid.GetNumberOfCells())])
    assert set(types.tolist()) == {13 if elements == "wedge" else 10}
    connectivity = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(len(types), -1)
    assert np.array_equal(connectivity, reference.cells_dict[kind])
    sizes = vtk.vtkCellSizeFilter()  # VTK's own cell volumes: all positive, adding up to the body's
    sizes.SetInputConnection(reader.GetOutputPort())
    sizes.Update()
    volume = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Volume"))
    assert np.all(volume > 0)
    cells = reference.cells_dict[kind]
    assert volume.sum() == pytest.approx(_reference_volume(reference.points, cells, kind), rel=1e-9)


def _reference_volume(points: np.ndarray, cells: np.ndarray, kind: str) -> float:
    if kind == "wedge":
        return float(wedge_volumes(points, cells).sum())
    p = points[cells]
    return float((np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0).sum())


# --------------------------------------------------------------------------------------------
# The estimates behind the caps
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("template, cam", TEMPLATE_CAMS)
def test_estimates_bound_what_is_written(template, cam, template_runs):
    """The counts and bytes estimated before meshing (the caps') are at least those of the
    files the run wrote (counted in the files)."""
    from camgen.export.fea import estimate, file_bytes, section_outline

    folder, contour, body, tol, figures = template_runs[(template, cam)]
    est = estimate(section_outline(contour, body, tol, None, POCKETS[(template, cam)]), body.thickness, "wedge")
    text = (folder / f"{cam}.inp").read_text()
    assert est.nodes >= len(_inp_nodes(text)) and est.elements >= figures["element_count"]
    for fmt in ("inp", "msh", "vtu"):
        assert file_bytes(fmt, est, "wedge") >= (folder / f"{cam}.{fmt}").stat().st_size


@pytest.mark.parametrize("key", [("plate_cam", "plate"), ("horse_leg", "stride_height")])
def test_tetra_estimates_bound_the_mesh(key, tetra_meshes):
    from camgen.export.fea import estimate, fea_bytes, file_bytes, section_outline

    mesh, contour, body, tol = tetra_meshes[key]
    est = estimate(section_outline(contour, body, tol), body.thickness, "tetra")
    assert est.elements >= len(mesh.cells) and est.nodes >= len(mesh.nodes)
    for fmt in ("inp", "msh", "vtu"):
        assert file_bytes(fmt, est, "tetra") >= len(fea_bytes(mesh, fmt))


# --------------------------------------------------------------------------------------------
# Keys, the missing extra, temporary files
# --------------------------------------------------------------------------------------------
PLATE = """
[output]
formats = {formats}
{extra}
[cams.plate]
kind = "motion_law"
base_radius_mm = 40.0
roller_radius_mm = 10.0
thickness_mm = 10.0
bore_diameter_mm = 12.0
keyway_width_mm = 4.0
keyway_depth_mm = 1.8
rpm = 300.0
[[cams.plate.segments]]
law = "cycloidal"
span_deg = 120.0
lift_mm = 20.0
[[cams.plate.segments]]
law = "dwell"
span_deg = 60.0
[[cams.plate.segments]]
law = "poly345"
span_deg = 120.0
lift_mm = -20.0
[[cams.plate.segments]]
law = "dwell"
span_deg = 60.0
"""


def _run(tmp_path, capsys, name: str, formats: str, extra: str = ""):
    from camgen.cli import main

    scene = tmp_path / f"{name}.toml"
    scene.write_text(PLATE.format(formats=formats, extra=extra))
    status = main(["run", str(scene), "-o", str(tmp_path / "out"), "--quiet"])
    return status, capsys.readouterr().err, tmp_path / "out" / name


def test_fea_keys_change_the_mesh_and_need_an_fea_format(tmp_path, capsys):
    """fea_element_size_mm = 4 mm: no section edge longer than 1.5 x 4 mm, and fewer elements
    than at 2 mm; fea_elements = "tetra": C3D4 elements; either key without vtu, msh or inp in
    output.formats is refused naming it."""
    require_module("gmsh")
    counts = {}
    for size in (2.0, 4.0):
        status, err, folder = _run(tmp_path, capsys, f"s{int(size)}", '["inp"]', f"fea_element_size_mm = {size}")
        assert status == 0, err
        text = (folder / "plate.inp").read_text()
        counts[size] = int(re.search(r"': (\d+) C3D6", text).group(1))
        nodes = _inp_nodes(text)
        ids = np.array([[int(v) for v in line.split(",")[1:4]] for line in
                        text.split("*ELEMENT, TYPE=C3D6, ELSET=CAM\n")[1].split("*")[0].splitlines()])
        p = np.array([[nodes[i][:2] for i in row] for row in ids])
        assert np.max(np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2)) <= 1.5 * size
    assert counts[4.0] < counts[2.0]
    status, err, folder = _run(tmp_path, capsys, "tet", '["msh", "inp"]', 'fea_elements = "tetra"\nchord_tol_mm = 0.02')
    assert status == 0, err
    assert "*ELEMENT, TYPE=C3D4, ELSET=CAM" in (folder / "plate.inp").read_text()
    report = json.loads((folder / "report.json").read_text())
    assert report["cams"]["plate"]["figures"]["fea_mesh"]["elements"] == "tetra"
    for key in ('fea_elements = "tetra"', "fea_element_size_mm = 3.0"):
        status, err, folder = _run(tmp_path, capsys, "nofea", '["stl"]', key)
        assert status == 2 and err.count("\n") == 1 and f"'output.{key.split()[0]}'" in err and "inp" in err, err


def test_without_gmsh_an_fea_format_is_one_line_naming_the_extra(tmp_path, capsys, monkeypatch):
    """gmsh not importable: exit 2, one line naming the format and the fea extra, nothing written."""
    monkeypatch.setitem(sys.modules, "gmsh", None)  # import gmsh raises ImportError
    status, err, folder = _run(tmp_path, capsys, "nogmsh", '["dxf", "msh"]')
    assert status == 2 and err.count("\n") == 1 and '"msh"' in err and "camgen[fea]" in err, err
    assert not folder.exists()


ALL_FORMATS = None  # every selectable format (filled from camgen.outputs)


def test_no_writer_touches_tmpdir(tmp_path, capsys, monkeypatch):
    """Every format written with TMPDIR (and HOME) pointing at empty folders, in a separate
    process (so that libraries in C and C++ see them too): TMPDIR stays empty (HOME gets only
    the empty preferences file of gmsh's FLTK library).  And in this process
    with Python's tempfile made to fail: the run still succeeds."""
    require_module("gmsh")
    require_module("OCP")
    import tempfile

    from camgen.outputs import SELECTABLE

    formats = json.dumps(list(SELECTABLE))
    scene = tmp_path / "all.toml"
    scene.write_text(PLATE.format(formats=formats, extra="chord_tol_mm = 0.01\n[machining]\ntool_diameter_mm = 6.0"))
    tmp, home = tmp_path / "tmp", tmp_path / "home"
    tmp.mkdir()
    home.mkdir()
    env = {**os.environ, "TMPDIR": str(tmp), "TEMP": str(tmp), "TMP": str(tmp), "HOME": str(home), "MPLCONFIGDIR": str(home)}
    proc = subprocess.run([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(tmp_path / "out"), "--quiet"], env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    written = {p.name for p in (tmp_path / "out" / "all").iterdir()}
    assert {"plate.step", "plate.vtu", "plate.msh", "plate.inp", "report.html"} <= written
    assert list(tmp.iterdir()) == []
    # the only file in HOME: the empty preferences file gmsh's FLTK library makes at start-up
    assert {str(p.relative_to(home)) for p in home.rglob("*") if p.is_file()} <= {".fltk/fltk.org/fltk.prefs"}

    def refuse(*args, **kwargs):
        raise AssertionError("a writer used tempfile")

    for name in ("mkstemp", "mkdtemp", "TemporaryDirectory", "NamedTemporaryFile", "TemporaryFile", "SpooledTemporaryFile"):
        monkeypatch.setattr(tempfile, name, refuse)
    from camgen.cli import main

    assert main(["run", str(scene), "-o", str(tmp_path / "out2"), "--quiet"]) == 0, capsys.readouterr().err
    assert {p.name for p in (tmp_path / "out2" / "all").iterdir()} == written
