"""IGES of a barrel cam (groove and rib): the STEP file's solid, read back by OCCT's IGES reader
(its own parser of the fixed-column IGES text) as one valid solid of the STEP solid's volume
within 1e-6 relative (the STEP file read by OCCT's STEP reader), and through the pipeline for
the barrel_cam template; FreeCAD's Part.read finds the same solid where it is installed.
"""
from __future__ import annotations

import dataclasses
import subprocess

import pytest

from helpers import require_tool

pytest.importorskip("OCP")

from test_barrel_rib_files import make_rib  # noqa: E402
from test_barrel_solid import make_groove  # noqa: E402
from test_step_ap242_iges import _read  # noqa: E402

#: Fit tolerance of the walls (mm): the STEP tests' (a tighter one only makes more poles).
FIT_TOL = 1e-5


@pytest.fixture(scope="module")
def files():
    """(STEP, IGES) bytes of the groove and of the rib barrel cam."""
    from camgen.export.barrel_iges import barrel_iges_bytes
    from camgen.export.barrel_rib_step import rib_step_bytes
    from camgen.export.barrel_step import barrel_step_bytes

    groove, rib = make_groove(fit_tol=FIT_TOL), make_rib(fit_tol=FIT_TOL)
    return {"groove": (barrel_step_bytes(groove, "barrel"), barrel_iges_bytes(groove, name="barrel")),
            "rib": (rib_step_bytes(rib, "rib"), barrel_iges_bytes(None, rib, "rib"))}


@pytest.mark.parametrize("track", ["groove", "rib"])
def test_iges_is_one_valid_solid_of_the_step_volume(track, files, tmp_path):
    step, iges = files[track]
    lines = iges.decode("ascii").splitlines()
    assert all(len(line) == 80 for line in lines) and {line[72] for line in lines} == {"S", "G", "D", "P", "T"}  # IGES 5.3 records
    directory = [line for line in lines if line[72] == "D"][0::2]
    assert {int(line[:8]) for line in directory} >= {186, 514, 510}  # a manifold solid B-rep, its shell and faces
    n_step, ok_step, v_step = _read(step, ".step", tmp_path)
    n_iges, ok_iges, v_iges = _read(iges, ".igs", tmp_path)
    assert (n_step, ok_step, n_iges, ok_iges) == (1, True, 1, True)
    assert v_iges == pytest.approx(v_step, rel=1e-6)


def test_freecad_reads_the_barrel_iges_as_the_step_solid(files, tmp_path):
    freecad = require_tool("freecadcmd")
    step, iges = files["groove"]
    (tmp_path / "b.step").write_bytes(step)
    (tmp_path / "b.igs").write_bytes(iges)
    script = tmp_path / "check.py"
    script.write_text("import Part\n" + "".join(
        f"shape = Part.read({str(tmp_path / p)!r})\nprint('CHECK', {p!r}, shape.isValid(), len(shape.Solids), repr(shape.Volume))\n"
        for p in ("b.step", "b.igs")))
    done = subprocess.run([freecad, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    found = {ln.split()[1]: ln.split()[2:] for ln in done.stdout.splitlines() if ln.startswith("CHECK")}
    assert set(found) == {"b.step", "b.igs"}, done.stdout + done.stderr
    (valid_s, count_s, vol_s), (valid_i, count_i, vol_i) = found["b.step"], found["b.igs"]
    assert (valid_s, count_s, valid_i, count_i) == ("True", "1", "True", "1")
    assert float(vol_i) == pytest.approx(float(vol_s), rel=1e-6)


def test_the_barrel_template_writes_iges(tmp_path):
    """Through the pipeline (the form's writer): the barrel_cam template's IGES is the solid of its STEP."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template

    scene = load_template("barrel_cam")
    run = dataclasses.replace(scene, output=dataclasses.replace(scene.output, formats=("step", "iges")))
    result = execute(run, plan_run(run))
    (cam,) = result.cams
    n_step, ok_step, v_step = _read(result.files[f"{cam.name}.step"], ".step", tmp_path)
    n_iges, ok_iges, v_iges = _read(result.files[f"{cam.name}.igs"], ".igs", tmp_path)
    assert (n_step, ok_step, n_iges, ok_iges) == (1, True, 1, True)
    assert v_iges == pytest.approx(v_step, rel=1e-6)
