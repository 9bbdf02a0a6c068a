"""The scene readers' caches (issue 28 item 6): a study's designs share what does not change
between them, and every design still reads as ``camgen check`` reads it.

* designs evaluated in a row in this process (the motion program, the body, the follower train
  and the base radius changed and changed back) each have the checks, values and verdict that
  ``camgen check`` prints for the same scene written to a file and checked in a child process
  (fresh caches: an independent path);
* a design whose ``[output]`` or ``[machining]`` value is refused, or whose machining cannot cut
  the cam (a check across the tables), is refused with the line ``camgen check`` prints, between
  designs that pass;
* the cache keys tell apart what Python's ``==`` does not: ``1``, ``1.0`` and ``True`` (a whole
  number, a number and a flag are read differently: the key reference's types), ``0.0`` and
  ``-0.0`` (IEEE 754: the sign of a zero survives a product), a table's order and which keys a
  parsed table was given;
* a design that keeps the motion gets the same law object back (read once), with read-only arrays;
  one that changes it gets its own law.
"""
from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

from camgen.errors import ParameterError
from camgen.frozen import frozen
from camgen.scene import parse_scene, template_path
from camgen.scene_edit import edit_scene_text
from camgen.schema import Parsed
from camgen.study.design import StudyScene, evaluate_point, point_scene_data
from camgen.study.keys import KeyPath, resolve_key


def _study(tmp_path: Path, formats: str) -> StudyScene:
    """templates/plate_cam.toml with ``output.formats`` = ``formats`` (a TOML list), as a study."""
    text = template_path("plate_cam").read_text(encoding="utf-8")
    old = 'formats = ["dxf", "points", "follower", "stl", "ngc", "html"]'
    assert old in text
    path = tmp_path / "plate.toml"
    path.write_text(text.replace(old, f"formats = {formats}"), encoding="utf-8")
    return StudyScene.load(str(path))


def _check(study: StudyScene, values: dict, tmp_path: Path, name: str) -> tuple[int, dict[str, tuple[str, str]], str]:
    """``camgen check`` as a program on the design's scene: exit status, check -> (result, value), stderr."""
    scene = tmp_path / f"{name}.toml"
    scene.write_text(edit_scene_text(study.text, point_scene_data(study.data, values)), encoding="utf-8")
    proc = subprocess.run([sys.executable, "-P", "-m", "camgen", "check", str(scene)], capture_output=True, text=True, timeout=300)
    table = {}
    for line in proc.stdout.splitlines()[1:]:
        cells = line.split()
        if len(cells) >= 4 and cells[2] in ("pass", "FAIL", "info"):
            table[cells[1]] = (cells[2].lower(), cells[3])
    return proc.returncode, table, proc.stderr


def _row(study: StudyScene, names: dict[str, object]) -> tuple[dict, dict]:
    """The row of the design setting ``names`` (study keys) and its values by path."""
    keys = [resolve_key(study.data, name) for name in names]
    return evaluate_point(study, keys, list(names.values())), {k.path: v for k, v in zip(keys, names.values())}


#: Designs evaluated in this order in one process: the law changed and changed back, the base
#: radius, the body and the follower train changed.
IN_A_ROW = [
    {"base_radius_mm": 40.0},
    {"base_radius_mm": 40.0, "cams.plate.segments[0].lift_mm": 14.0, "cams.plate.segments[2].lift_mm": -14.0},
    {"base_radius_mm": 44.0},
    {"base_radius_mm": 44.0, "cams.plate.segments[0].law": "poly345", "cams.plate.segments[2].law": "cycloidal"},
    {"base_radius_mm": 44.0, "bore_diameter_mm": 20.0, "spring_rate_n_per_mm": 0.2, "spring_preload_n": 5.0},
    {"base_radius_mm": 40.0},
]


def test_designs_in_a_row_each_read_as_camgen_check_reads_them(tmp_path):
    study = _study(tmp_path, '["dxf"]')
    rows = []
    for i, names in enumerate(IN_A_ROW):
        row, values = _row(study, names)
        assert row["status"] in ("pass", "fail"), row["error"]
        status, table, stderr = _check(study, values, tmp_path, f"design{i}")
        assert status == (1 if row["status"] == "fail" else 0), stderr
        assert set(table) == {name.split(".")[2] for name in row if name.startswith("check.") and not name.endswith(".status")}
        for check, (result, shown) in table.items():
            assert row[f"check.plate.{check}.status"] == result, (i, check)
            value = row[f"check.plate.{check}"]
            if value is not None:  # the table prints 6 significant digits
                assert math.isclose(value, float(shown.rstrip(",")), rel_tol=1e-5, abs_tol=1e-9), (i, check, value, shown)
        rows.append(row)
    pressure = [r["check.plate.pressure_angle"] for r in rows]
    assert len({round(p, 6) for p in pressure[:4]}) == 4  # each change of the law or the radius changed the design
    assert rows[5]["check.plate.pressure_angle"] == rows[0]["check.plate.pressure_angle"]  # back to the first design
    assert rows[4]["check.plate.wall_thickness"] < rows[2]["check.plate.wall_thickness"]  # the larger bore
    assert rows[4]["check.plate.jump"] < rows[2]["check.plate.jump"]  # the weaker spring


@pytest.mark.parametrize("key, value", [("output.chord_tol_mm", 0.0), ("machining.tool_diameter_mm", -1.0),
                                        ("machining.step_down_mm", 1e-5), ("output.dxf_splines", "nurbs")],
                         ids=["output", "machining", "passes-across-tables", "choice"])
def test_a_refused_output_or_machining_value_between_good_designs(tmp_path, key, value):
    study = _study(tmp_path, '["dxf", "ngc"]')
    good, _ = _row(study, {"base_radius_mm": 41.0})
    assert good["status"] in ("pass", "fail"), good["error"]
    path = tuple(key.split("."))
    keys = [resolve_key(study.data, "base_radius_mm")]
    bad = evaluate_point(study, [keys[0], KeyPath(key, path)], [41.0, value])
    status, _, stderr = _check(study, {keys[0].path: 41.0, path: value}, tmp_path, "refused")
    assert status == 2 and bad["status"] == "error"
    assert bad["error"] == stderr.strip()
    again, _ = _row(study, {"base_radius_mm": 41.0})
    assert {k: v for k, v in again.items() if k != "eval_ms"} == {k: v for k, v in good.items() if k != "eval_ms"}


def test_the_cache_keys_tell_apart_what_equality_does_not():
    assert 1 == 1.0 == True  # noqa: E712  (what a dict key would conflate)
    assert len({frozen(1), frozen(1.0), frozen(True)}) == 3
    assert frozen(0.0) != frozen(-0.0)
    assert frozen({"a": 1.0, "b": 2.0}) != frozen({"b": 2.0, "a": 1.0})  # a table's order
    assert frozen({"x": [1.0, 2.0]}) != frozen({"x": (1.0, 2.0)})
    assert frozen({"a": [0.5, "dwell"]}) == frozen({"a": [0.5, "dwell"]})
    one, two = Parsed(a=1.0), Parsed(a=1.0)
    one.given, two.given = frozenset({"a_mm"}), frozenset()
    assert one == two and frozen(one) != frozen(two)  # equal items, not the same table (a default is not given)
    assert frozen((one,)) != frozen((two,))


def _plate_data(**cam) -> dict:
    from camgen.scene import decode_scene_file

    _, data = decode_scene_file(template_path("plate_cam"))
    data["cams"]["plate"].update(cam)
    return data


def test_a_cached_table_still_refuses_a_value_of_another_type():
    data = _plate_data()
    data["output"]["dxf_construction"] = True
    assert parse_scene(data, "plate").output.dxf_construction is True
    data["output"]["dxf_construction"] = 1  # a flag is true or false (the key reference), 1 == True notwithstanding
    with pytest.raises(ParameterError, match="output.dxf_construction"):
        parse_scene(data, "plate")
    data["output"]["dxf_construction"] = False
    data["machining"]["holding_tabs"] = 2
    assert parse_scene(data, "plate").machining.holding_tabs == 2
    data["machining"]["holding_tabs"] = 2.0  # a whole number is an integer, 2 == 2.0 notwithstanding
    with pytest.raises(ParameterError, match="machining.holding_tabs"):
        parse_scene(data, "plate")


def test_the_sign_of_a_zero_reaches_the_follower_train():
    for degrees in (0.0, -0.0, 0.0):  # gravity_deg * pi / 180 keeps the sign of the zero (IEEE 754)
        train = parse_scene(_plate_data(gravity_deg=degrees), "plate").cams[0].dynamics.train
        assert train.gravity_angle == 0.0 and math.copysign(1.0, train.gravity_angle) == math.copysign(1.0, degrees)


def test_a_design_keeping_the_motion_gets_the_same_law_and_a_new_motion_its_own():
    first = parse_scene(_plate_data(base_radius_mm=41.0), "plate").cams[0].params
    second = parse_scene(_plate_data(base_radius_mm=47.0), "plate").cams[0].params
    assert second.law is first.law and second.follower.base_radius == 47.0
    assert not first.law.breaks.flags.writeable and not first.law.starts.flags.writeable
    first.law_figures["segments"][0]["law"] = "changed by its reader"  # the figures are each reader's own
    assert second.law_figures["segments"][0]["law"] == "cycloidal"
    segments = [dict(s) for s in _plate_data()["cams"]["plate"]["segments"]]
    segments[0]["lift_mm"], segments[2]["lift_mm"] = 12.0, -12.0
    third = parse_scene(_plate_data(base_radius_mm=47.0, segments=segments), "plate").cams[0].params
    assert third.law is not first.law
    assert third.law(math.radians(120.0))[0] == pytest.approx(12.0) and first.law(math.radians(120.0))[0] == pytest.approx(20.0)
