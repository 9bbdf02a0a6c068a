"""The caps on file size (planning.MAX_FLAT_POINTS, gcode.MAX_PASSES, gcode.MAX_PROGRAM_MOVES,
fea.MAX_FILE_BYTES and fea.MAX_MESHER_BYTES):
each refusal names the key and a least value that is itself accepted, and what is written at
that value holds no more than the cap (counted in the file, not taken from the code).

The caps are lowered with monkeypatch so that the cases stay small; the arithmetic that picks the
suggested value is the same at any cap.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from camgen.cli import main
from test_fea import require_module

PLATE = """
[output]
formats = {formats}
chord_tol_mm = {tol}
{machining}
[cams.plate]
kind = "motion_law"
base_radius_mm = 40.0
roller_radius_mm = 10.0
thickness_mm = {thickness}
bore_diameter_mm = 12.0
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


def _run(tmp_path: Path, capsys, name: str, formats: str = '["points"]', tol: float = 1e-3, step: float = 2.0,
         mode: str = "biarcs", thickness: float = 10.0) -> tuple[int, str, Path]:
    scene = tmp_path / f"{name}.toml"
    machining = f'[machining]\ntool_diameter_mm = 6.0\nstep_down_mm = {step!r}\nspline_mode = "{mode}"' if "ngc" in formats else ""
    scene.write_text(PLATE.format(formats=formats, tol=repr(tol), machining=machining, thickness=repr(thickness)))
    out = tmp_path / f"out_{name}"
    status = main(["run", str(scene), "-o", str(out), "--quiet"])
    return status, capsys.readouterr().err, out / name


def _least(err: str, key: str) -> float:
    match = re.search(rf"parameter '{re.escape(key)}' = \S+ is invalid: valid range is >= ([0-9.e+-]+) mm", err)
    assert match, err
    return float(match.group(1))


def test_suggested_chord_tolerance_is_accepted_and_the_file_fits(tmp_path, capsys, monkeypatch):
    import pandas

    import camgen.planning as pipeline

    cap = 3000
    monkeypatch.setattr(pipeline, "MAX_FLAT_POINTS", cap)
    status, err, folder = _run(tmp_path, capsys, "fine", tol=1e-5)
    assert status == 2 and err.count("\n") == 1 and not folder.exists(), err
    least = _least(err, "output.chord_tol_mm")
    status, err, folder = _run(tmp_path, capsys, "least", tol=least)
    assert status == 0, err
    rows = pandas.read_csv(folder / "plate_points.csv")
    assert list(rows.columns) == ["x_mm", "y_mm"] and len(rows) <= cap
    # the suggestion is the least with two significant digits: 5 % below it does not fit
    assert _run(tmp_path, capsys, "below", tol=least * 0.95)[0] == 2


def test_dxf_alone_is_not_capped_by_the_flattened_count(tmp_path, capsys, monkeypatch):
    """The DXF writes arcs exactly and splines as biarcs or exact SPLINEs: a tolerance at which the
    point list is refused writes a DXF of few entities (counted by ezdxf)."""
    import ezdxf

    import camgen.planning as pipeline

    monkeypatch.setattr(pipeline, "MAX_FLAT_POINTS", 3000)
    assert _run(tmp_path, capsys, "points", tol=1e-5)[0] == 2
    status, err, folder = _run(tmp_path, capsys, "dxf", formats='["dxf"]', tol=1e-5)
    assert status == 0, err
    profile = [e for e in ezdxf.readfile(folder / "plate.dxf").modelspace() if e.dxf.layer == "PROFILE"]
    assert 0 < len(profile) <= 3000


def test_least_step_down_is_accepted(tmp_path, capsys):
    """10.0345 mm + 0.2 mm breakthrough over at most 1000 passes: 0.0102345 mm, quoted rounded up."""
    import camgen.export.gcode as gcode

    status, err, folder = _run(tmp_path, capsys, "steps", formats='["ngc"]', step=0.001, thickness=10.0345)
    assert status == 2 and not folder.exists(), err
    least = _least(err, "machining.step_down_mm")
    assert least == pytest.approx(0.0103) and (10.0345 + 0.2) / least <= gcode.MAX_PASSES


@pytest.mark.parametrize("mode", ["biarcs", "lines"])
def test_a_program_too_long_names_step_down_and_its_least_value_fits(tmp_path, capsys, monkeypatch, mode):
    import camgen.export.gcode as gcode

    cap = 4000
    monkeypatch.setattr(gcode, "MAX_PROGRAM_MOVES", cap)
    status, err, folder = _run(tmp_path, capsys, "long", formats='["ngc"]', tol=1e-2, step=0.05, mode=mode)
    assert status == 2 and err.count("\n") == 1 and not folder.exists(), err
    least = _least(err, "machining.step_down_mm")
    status, err, folder = _run(tmp_path, capsys, "fits", formats='["ngc"]', tol=1e-2, step=least, mode=mode)
    assert status == 0, err
    moves = [line for line in (folder / "plate.ngc").read_text().splitlines() if re.match(r"G[0-3]\b|G4[12]\.1|G40", line)]
    assert len(moves) <= cap


def test_one_pass_too_long_names_the_path_setting(tmp_path, capsys, monkeypatch):
    import camgen.export.gcode as gcode

    monkeypatch.setattr(gcode, "MAX_PROGRAM_MOVES", 50)
    status, err, _ = _run(tmp_path, capsys, "lines", formats='["ngc"]', tol=1e-3, mode="lines")
    assert status == 2 and "parameter 'machining.spline_mode' = 'lines'" in err, err
    status, err, _ = _run(tmp_path, capsys, "arcs", formats='["ngc"]', tol=1e-3, mode="biarcs")
    assert status == 2 and "parameter 'output.chord_tol_mm' = 0.001" in err, err


def test_a_fit_tolerance_out_of_reach_names_fit_tol_mm_and_its_least_value_fits(tmp_path, capsys, monkeypatch):
    """With the pieces of a segment capped at 16, the plate cam cannot reach fit_tol_mm = 1e-10 (its
    rise needs more: the h^6 / 46080 bound of quintic pieces); the error names the key and a least
    value, which is accepted, its fit error (report.json) within it."""
    import functools
    import json

    import camgen.synthesis.followers as followers

    monkeypatch.setattr(followers, "_spline_contours", functools.partial(followers._spline_contours, max_pieces=16))

    def run(name: str, fit_tol: float) -> tuple[int, str, Path]:
        scene = tmp_path / f"{name}.toml"
        scene.write_text(PLATE.format(formats='["dxf"]', tol="0.001", machining="", thickness="10.0")
                         .replace("[cams.plate]\n", f"[cams.plate]\nfit_tol_mm = {fit_tol!r}\n"))
        status = main(["run", str(scene), "-o", str(tmp_path / f"out_{name}"), "--quiet"])
        return status, capsys.readouterr().err, tmp_path / f"out_{name}" / name

    status, err, folder = run("tight", 1e-10)
    assert status == 2 and err.count("\n") == 1 and not folder.exists(), err
    least = _least(err, "cams.plate.fit_tol_mm")
    assert "16 pieces" in err and 1e-10 < least < 1e-4
    status, err, folder = run("least", least)
    assert status == 0, err
    figures = json.loads((folder / "report.json").read_text())["cams"]["plate"]["figures"]
    assert figures["fit_error_mm"] <= least and figures["profile_pieces"] <= 4 * 16


# --------------------------------------------------------------------------------------------
# FEA meshes: each file at most fea.MAX_FILE_BYTES, the mesher at most fea.MAX_MESHER_BYTES
# --------------------------------------------------------------------------------------------
def _fea_scene(tmp_path: Path, name: str, base_radius: float, tol: float, formats: str, extra: str = "") -> Path:
    scene = tmp_path / f"{name}.toml"
    text = PLATE.format(formats=formats, tol=repr(tol), machining="", thickness="10.0").replace("base_radius_mm = 40.0",
                                                                                              f"base_radius_mm = {base_radius!r}")
    scene.write_text(text.replace("[cams.plate]", extra + "\n[cams.plate]"))
    return scene


def test_the_10_m_cam_at_the_least_chord_tolerance_fits_the_fea_caps(tmp_path):
    """Issue 21's case: a plate cam of base radius 10,000 mm at chord_tol_mm = 1e-7 (the least the
    key takes) with msh and inp: refused (exit 2, one line) naming output.chord_tol_mm and a least
    value; at that value the run is accepted and each file holds at most 100 MB, counted on
    disk, and the process's peak memory stays under the README's 1.5 GB (resource.getrusage of
    the child: it is the cap, applied before meshing, that bounds it)."""
    import subprocess
    import sys

    require_module("gmsh")
    from camgen.export import fea

    scene = _fea_scene(tmp_path, "big", 10000.0, 1e-7, '["msh", "inp"]')
    proc = subprocess.run([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(tmp_path / "out")], capture_output=True,
                          text=True, timeout=900)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and not (tmp_path / "out" / "big").exists(), proc.stderr
    least = _least(proc.stderr, "output.chord_tol_mm")
    assert "MB" in proc.stderr and 1e-7 < least < 1.0
    scene = _fea_scene(tmp_path, "least", 10000.0, least, '["msh", "inp"]')
    status, stderr, peak_kib = _run_measured([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(tmp_path / "out"),
                                              "--quiet"], timeout=1800)
    assert status == 0, stderr
    for suffix in (".msh", ".inp"):
        assert 0 < (tmp_path / "out" / "least" / f"plate{suffix}").stat().st_size <= fea.MAX_FILE_BYTES
    assert peak_kib * 1024 <= 1.5e9


def _run_measured(args: list[str], timeout: float) -> tuple[int, str, int]:
    """Exit status, stderr and peak resident memory (KiB) of one child process: ``os.wait4`` gives
    that child's own rusage (RUSAGE_CHILDREN would hold the largest of every child this test
    worker ever waited for: a browser or a Dask worker of another test)."""
    import os
    import subprocess
    import threading

    proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    try:
        assert proc.stderr is not None
        with proc.stderr:
            stderr = proc.stderr.read()
        _, wait_status, usage = os.wait4(proc.pid, 0)
    finally:
        timer.cancel()
    proc.returncode = os.waitstatus_to_exitcode(wait_status)
    return proc.returncode, stderr, usage.ru_maxrss


@pytest.mark.parametrize("elements", ["wedge", "tetra"])
def test_an_element_size_too_small_for_any_tolerance_names_the_least_size(tmp_path, capsys, monkeypatch, elements):
    """Caps lowered to 2 MB per file (4 MB for tetrahedra, whose boundary alone takes 2.6 MB here):
    with fea_element_size_mm = 0.2 mm the section's bulk alone is too big at any chord
    tolerance, so the error names output.fea_element_size_mm and a least size; at that size the
    run is accepted and the .inp (counted on disk) fits."""
    from camgen.cli import main
    from camgen.export import fea

    require_module("gmsh")
    cap = 2_000_000 if elements == "wedge" else 4_000_000
    monkeypatch.setattr(fea, "MAX_FILE_BYTES", cap)
    extra = f'fea_elements = "{elements}"\n'

    def run(name: str, size: float):
        scene = _fea_scene(tmp_path, name, 40.0, 0.01, '["inp"]', extra + f"fea_element_size_mm = {size!r}")
        status = main(["run", str(scene), "-o", str(tmp_path / "out"), "--quiet"])
        return status, capsys.readouterr().err, tmp_path / "out" / name

    status, err, folder = run("small", 0.2)
    assert status == 2 and err.count("\n") == 1 and not folder.exists(), err
    least = _least(err, "output.fea_element_size_mm")
    status, err, folder = run("fits", least)
    assert status == 0, err
    assert (folder / "plate.inp").stat().st_size <= cap


def test_a_chord_tolerance_too_fine_for_the_fea_caps_names_the_least_and_it_fits(tmp_path, capsys, monkeypatch):
    """Caps lowered to 3 MB per file: the plate cam at chord_tol_mm = 1e-5 with vtu, msh, inp is
    refused naming output.chord_tol_mm; at the quoted value each file (on disk) fits."""
    from camgen.cli import main
    from camgen.export import fea

    require_module("gmsh")
    monkeypatch.setattr(fea, "MAX_FILE_BYTES", 3_000_000)

    def run(name: str, tol: float):
        scene = _fea_scene(tmp_path, name, 40.0, tol, '["vtu", "msh", "inp"]')
        status = main(["run", str(scene), "-o", str(tmp_path / "out"), "--quiet"])
        return status, capsys.readouterr().err, tmp_path / "out" / name

    status, err, folder = run("fine", 1e-5)
    assert status == 2 and err.count("\n") == 1 and not folder.exists(), err
    least = _least(err, "output.chord_tol_mm")
    status, err, folder = run("least", least)
    assert status == 0, err
    for fmt in ("vtu", "msh", "inp"):
        assert (folder / f"plate.{fmt}").stat().st_size <= 3_000_000


# --------------------------------------------------------------------------------------------
# Surface meshes: each file at most solid.MAX_FILE_BYTES (solid.BYTES_PER_VERTEX)
# --------------------------------------------------------------------------------------------
def _random_star_cam(rng):
    import math

    import numpy as np

    from camgen.body import BodySpec
    from camgen.contour import Contour, Spline

    theta = np.linspace(0.0, 2 * math.pi, 65)
    k = np.arange(1, 6)
    a, b = rng.normal(size=(2, 5)) / k**2
    r = (1 + 0.15 * (np.cos(np.outer(theta, k)) @ a + np.sin(np.outer(theta, k)) @ b)) * rng.uniform(20, 400)
    r[-1] = r[0]
    contour = Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])
    bore = float(rng.uniform(0.1, 0.5) * r.min())
    return contour, BodySpec(thickness=float(rng.uniform(2, 50)), bore_diameter=bore, keyway_width=0.3 * bore, keyway_depth=0.1 * bore,
                             min_wall=0.0)


@pytest.mark.parametrize("tol", [1e-3, 1e-5])
def test_surface_mesh_bytes_per_outline_vertex_are_bounded(tol):
    """The bytes of every surface format (counted in the written content) stay within
    solid.BYTES_PER_VERTEX x (outline vertices + solid.EXTRA_VERTICES) for every template cam
    and random cams."""
    import numpy as np

    from camgen.export.solid import BYTES_PER_VERTEX, EXTRA_VERTICES, bore_polygon, cam_solid, mesh_bytes
    from camgen.kinds import get_kind
    from camgen.scene import load_template
    from golden.regenerate import TEMPLATES

    cases = []
    for template in TEMPLATES:
        scene = load_template(template)
        for spec in scene.cams:
            cam = get_kind(spec.kind, spec.form).build(spec, frozenset())
            if cam.planar:  # a barrel's mesh has its own cap (tests/test_barrel_solid.py)
                cases.append((cam.contour, cam.body))
    rng = np.random.default_rng(21)
    cases += [_random_star_cam(rng) for _ in range(4)]
    for contour, body in cases:
        solid = cam_solid(contour, body, tol)
        hole = bore_polygon(body, tol)
        outline = len(contour.flatten(tol)) + (0 if hole is None else len(hole))
        for fmt, bound in BYTES_PER_VERTEX.items():
            assert len(mesh_bytes(solid, fmt)) <= bound * (outline + EXTRA_VERTICES), (fmt, outline)


def test_an_ascii_stl_beyond_its_cap_names_the_least_chord_tolerance_and_it_fits(tmp_path, capsys, monkeypatch):
    """Surface files capped at 3 MB: the plate cam's ASCII STL at 1e-5 mm is refused naming
    output.chord_tol_mm; at the quoted value the file on disk holds at most 3 MB."""
    import camgen.export.solid as solid

    monkeypatch.setattr(solid, "MAX_FILE_BYTES", 3_000_000)
    status, err, folder = _run(tmp_path, capsys, "fine", formats='["stl_ascii"]', tol=1e-5)
    assert status == 2 and err.count("\n") == 1 and "stl_ascii" in err and not folder.exists(), err
    least = _least(err, "output.chord_tol_mm")
    status, err, folder = _run(tmp_path, capsys, "least", formats='["stl_ascii"]', tol=least)
    assert status == 0, err
    assert (folder / "plate_ascii.stl").stat().st_size <= 3_000_000
