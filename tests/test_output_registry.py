"""Adding an output format is a writer and one registry line (issue 22, item 5).

Toy formats are registered here, from the test, in :data:`camgen.outputs.OUTPUTS` only: a file per
cam, a file per run drawn from the report input, and one that needs the cam speed.  The planner,
the pipeline and the report take them with no other change: they are planned, written, listed
in report.json, and a cam without a speed is refused for the one that needs it, naming the key.
"""
from __future__ import annotations

import json
import tomllib

import pytest

from camgen import outputs
from camgen.errors import ParameterError
from camgen.outputs import OUTPUTS, OutputFormat
from camgen.pipeline import execute, plan_run
from camgen.scene import load_template, parse_scene, template_path


def segment_count(cam, run, fmt: str) -> str:
    """A toy per-cam writer: the profile's segment count and the run's chord tolerance."""
    return f"{fmt}: {len(cam.contour.segments)} segments at {run.output.chord_tol:g} mm\n"


def cam_names(report) -> str:
    """A toy per-run writer: the names of the report's cams, one a line."""
    return "".join(f"{cam.name}\n" for cam in report.cams)


@pytest.fixture
def toys(monkeypatch):
    registry = dict(OUTPUTS)
    registry["toy"] = OutputFormat("toy", "{cam}_toy.txt", "a toy per-cam file", f"{__name__}:segment_count")
    registry["toy_run"] = OutputFormat("toy_run", "toy_run.txt", "a toy per-run file", f"{__name__}:cam_names", manufacturing=False,
                                       scope="run")
    registry["toy_speed"] = OutputFormat("toy_speed", "{cam}_speed.txt", "a toy file at the cam speed", f"{__name__}:segment_count",
                                         manufacturing=False, needs_rpm="tabulates the toy at the cam speed")
    monkeypatch.setattr(outputs, "OUTPUTS", registry)


def test_a_registered_format_is_planned_written_and_listed(toys):
    scene = load_template("plate_cam")
    result = execute(scene, plan_run(scene, ["toy", "toy_run"]))
    names = list(tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))["cams"])  # the scene file itself
    assert sorted(result.files) == sorted([f"{name}_toy.txt" for name in names] + ["toy_run.txt", "report.json"])
    assert result.files["toy_run.txt"] == "".join(f"{name}\n" for name in names)
    for name in names:
        assert result.files[f"{name}_toy.txt"].startswith(f"toy: ") and result.files[f"{name}_toy.txt"].endswith(
            f" at {scene.output.chord_tol:g} mm\n")
    listed = json.loads(result.files["report.json"])["files"]
    assert listed == sorted(f"{name}_toy.txt" for name in names) + ["report.json", "toy_run.txt"]  # the report first


def test_a_format_that_needs_the_cam_speed_refuses_a_cam_without_one(toys):
    data = tomllib.loads(template_path("knife_follower").read_text(encoding="utf-8"))
    (name,) = data["cams"]
    del data["cams"][name]["rpm"]
    for key in [k for k in data["cams"][name] if k.startswith(("mass", "spring", "damping", "jump", "torque", "external"))]:
        del data["cams"][name][key]  # the dynamics keys need the speed too
    scene = parse_scene(data, "knife", base_dir=template_path("knife_follower").parent)
    with pytest.raises(ParameterError) as info:
        plan_run(scene, ["toy_speed"])
    assert info.value.name == f"cams.{name}.rpm"
    assert info.value.why == 'the "toy_speed" output (<cam>_speed.txt) tabulates the toy at the cam speed'
    plan_run(scene, ["toy"])  # a format that does not need it is planned


def test_every_key_a_format_owns_is_an_output_key_refused_without_the_format():
    """OutputFormat.keys: each names an [output] key, and the key given with none of its formats
    is refused naming it and the formats (the plain plate scene of the default template, its
    formats replaced by one that owns none of the keys)."""
    from camgen.outputs import output_keys

    names = {k.name for k in output_keys()}
    owned = {key: [f.name for f in OUTPUTS.values() if key in f.keys] for f in OUTPUTS.values() for key in f.keys}
    assert owned and set(owned) <= names
    cams = {"c": {"kind": "three_arc", "a_mm": 100.0, "b_mm": 100.0, "c_mm": 35.0}}
    value = {"dxf_splines": "bspline", "dxf_construction": True, "lift_step_deg": 2.0, "fea_element_size_mm": 2.0, "fea_elements": "tetra",
             "dxf_version": "R12", "step_schema": "AP242"}
    from camgen.export.drawing_spec import drawing_keys

    value.update({k.name: k.example for k in drawing_keys()})  # the drawing's keys (issue 27 item 4)
    for key, formats in owned.items():
        with pytest.raises(ParameterError) as caught:
            parse_scene({"output": {"formats": ["points"], key: value[key]}, "cams": cams}, "t")
        assert caught.value.name == f"output.{key}" and all(f in str(caught.value) for f in formats), str(caught.value)
        parse_scene({"output": {"formats": [formats[-1]], key: value[key]}, "cams": cams}, "t")  # with one of them: taken
