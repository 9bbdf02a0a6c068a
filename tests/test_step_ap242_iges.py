"""STEP AP242 and IGES of the cam body (issue 27, item 5), read back by OpenCASCADE and FreeCAD.

Each file must hold one valid solid (OCCT's BRepCheck_Analyzer; FreeCAD's ``isValid``) of the
volume of the AP214 STEP file's solid within 1e-6 relative, and the stride cam's also of its
closed-form volume (the three-arc profile's area less bore and keyway, times the thickness).
The IGES file is read by OCCT's IGES reader (its own parser of the fixed-column IGES text, not
the writer's model) and by FreeCAD's ``Part.read``.
"""
from __future__ import annotations

import dataclasses
import math
import re
import subprocess

import pytest

from cams import BODIES
from helpers import occt_shape, require_tool

pytest.importorskip("OCP")


def _read(data: bytes, suffix: str, tmp_path):
    """OCCT's reading of a STEP or IGES file: (number of solids, all valid, volume mm^3)."""
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    shape = occt_shape(data, tmp_path / f"cam{suffix}")
    solids, explorer = 0, TopExp_Explorer(shape, TopAbs_SOLID)
    while explorer.More():
        solids += 1
        explorer.Next()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    return solids, bool(BRepCheck_Analyzer(shape).IsValid()), float(props.Mass())


def _stride_volume() -> float:
    """The stride cam's body in closed form: the three-arc area (shoelace of its arcs, exact) less
    the bore circle and the keyway's part outside it (a rectangle less the circular segment), times
    the thickness (as tests/test_step.py)."""
    import camgen
    from cams import STRIDE

    body = BODIES["stride"]
    r, h = body.bore_diameter / 2, body.keyway_width / 2
    keyway = 2 * h * (r + body.keyway_depth) - (h * math.sqrt(r * r - h * h) + r * r * math.asin(h / r))
    return (camgen.three_arc_cam(*STRIDE).area - math.pi * r * r - keyway) * body.thickness


@pytest.fixture(scope="module")
def solids(contours):
    """The stride (exact arcs) and steering (B-splines) cams: AP214, AP242 and IGES bytes."""
    from camgen.export.iges import iges_bytes
    from camgen.export.step import step_bytes

    out = {}
    for name in ("stride", "steering"):
        contour, body = contours[name], BODIES[name]
        out[name] = (step_bytes(contour, body, name), step_bytes(contour, body, name, schema="AP242"), iges_bytes(contour, body, name))
    return out


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_ap242_is_the_ap214_solid_under_the_ap242_schema(name, solids, contours, tmp_path):
    from camgen.export.step import step_bytes

    ap214, ap242, _ = solids[name]
    text = ap242.decode("ascii")
    schema = re.search(r"FILE_SCHEMA\(\(\s*'([^']*)'", text).group(1)
    assert schema.startswith("AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF")  # ISO 10303-442's schema name
    assert "AUTOMOTIVE_DESIGN" not in text and "SI_UNIT(.MILLI.,.METRE.)" in text
    assert "AUTOMOTIVE_DESIGN" in ap214.decode("ascii")  # the default stays AP214
    assert step_bytes(contours[name], BODIES[name], name, schema="AP242") == ap242  # deterministic
    n214, ok214, v214 = _read(ap214, ".step", tmp_path)
    n242, ok242, v242 = _read(ap242, ".step", tmp_path)
    assert (n214, ok214, n242, ok242) == (1, True, 1, True)
    assert v242 == pytest.approx(v214, rel=1e-6)
    if name == "stride":
        assert v242 == pytest.approx(_stride_volume(), rel=1e-9)


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_iges_is_one_valid_solid_of_the_step_volume(name, solids, contours, tmp_path):
    from camgen.export.iges import IGES_DATE, iges_bytes

    ap214, _, iges = solids[name]
    text = iges.decode("ascii")
    lines = text.splitlines()
    assert all(len(line) == 80 for line in lines)  # IGES 5.3: 80-column records
    assert {line[72] for line in lines} == {"S", "G", "D", "P", "T"}
    glob = "".join(line[:72] for line in lines if line[72] == "G")
    assert ",2,2HMM," in glob and f"15H{IGES_DATE}" in glob  # units flag 2 (mm), the fixed date
    directory = [line for line in lines if line[72] == "D"][0::2]
    assert {int(line[:8]) for line in directory} >= {186, 514, 510}  # a manifold solid B-rep, its shell and faces
    assert iges_bytes(contours[name], BODIES[name], name) == iges  # deterministic
    _, _, v214 = _read(ap214, ".step", tmp_path)
    count, valid, volume = _read(iges, ".igs", tmp_path)
    assert (count, valid) == (1, True)
    assert volume == pytest.approx(v214, rel=1e-6)
    if name == "stride":
        assert volume == pytest.approx(_stride_volume(), rel=1e-9)


def test_freecad_reads_ap242_and_iges_as_the_step_solid(solids, tmp_path):
    """FreeCAD's Part.read (its own import of STEP and IGES) finds one valid solid in each, of the
    AP214 file's volume within 1e-6 (the steering cam: B-spline faces)."""
    freecad = require_tool("freecadcmd")
    ap214, ap242, iges = solids["steering"]
    paths = {}
    for key, data, suffix in (("ap214", ap214, ".step"), ("ap242", ap242, ".stp"), ("iges", iges, ".igs")):
        paths[key] = tmp_path / f"{key}{suffix}"
        paths[key].write_bytes(data)
    script = tmp_path / "check.py"
    script.write_text("import Part\n" + "".join(
        f"shape = Part.read({str(p)!r})\nprint('CHECK', {k!r}, shape.isValid(), len(shape.Solids), repr(shape.Volume))\n"
        for k, p in paths.items()))
    done = subprocess.run([freecad, str(script)], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    found = {ln.split()[1]: ln.split()[2:] for ln in done.stdout.splitlines() if ln.startswith("CHECK")}
    assert set(found) == {"ap214", "ap242", "iges"}, done.stdout + done.stderr
    reference = float(found["ap214"][2])
    for key in ("ap242", "iges"):
        valid, count, volume = found[key]
        assert (valid, count) == ("True", "1"), key
        assert float(volume) == pytest.approx(reference, rel=1e-6), key


def test_a_groove_scene_writes_ap242_and_iges(tmp_path):
    """Through the pipeline: the groove cam (a pocket cut from the top face) with
    ``output.step_schema = "AP242"`` and the ``iges`` format: both one valid solid of the AP214
    solid's volume."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template

    scene = load_template("groove_cam")
    volumes = {}
    for schema in ("AP214", "AP242"):
        run = dataclasses.replace(scene, output=dataclasses.replace(scene.output, formats=("step", "iges"), step_schema=schema))
        result = execute(run, plan_run(run))
        (cam,) = result.cams
        step = result.files[f"{cam.name}.step"]
        assert ("AP242_MANAGED" in step.decode("ascii")) == (schema == "AP242")
        volumes[schema] = _read(step, ".step", tmp_path)
        volumes[f"iges-{schema}"] = _read(result.files[f"{cam.name}.igs"], ".igs", tmp_path)
    reference = volumes["AP214"][2]
    for key, (count, valid, volume) in volumes.items():
        assert (count, valid) == (1, True), key
        assert volume == pytest.approx(reference, rel=1e-6), key
