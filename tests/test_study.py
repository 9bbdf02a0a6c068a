"""The study foundation (issue 28): scene keys by path, the points of a design space, one design's
row, and scenes edited with their comments kept.

References: the grid's arithmetic; the Latin hypercube's defining property (McKay, Beckman and
Conover 1979: one point in each of the n equal strata of every coordinate); the scrambled Sobol
sequence's (0, m, 1)-net property in each coordinate (Owen 1995: each of the 2^m intervals of
length 2^-m holds exactly one of 2^m points); ``camgen check`` run as a program on the design's
scene written to a file; tomllib reading the edited scene back.
"""
from __future__ import annotations

import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from camgen.errors import ParameterError
from camgen.scene import template_path
from camgen.scene_edit import edit_scene_text
from camgen.study.design import StudyScene, evaluate_point, point_scene_data
from camgen.study.keys import resolve_key
from camgen.study.space import design_points, parse_vary, read_points, sweep_table

PLATE = template_path("plate_cam")


@pytest.fixture(scope="module")
def plate() -> StudyScene:
    return StudyScene.load(str(PLATE))


def test_keys_resolve_bare_dotted_and_indexed(plate):
    assert resolve_key(plate.data, "base_radius_mm").path == ("cams", "plate", "base_radius_mm")
    key = resolve_key(plate.data, "cams.plate.segments[2].lift_mm")
    assert key.path == ("cams", "plate", "segments", 2, "lift_mm") and key.name == "cams.plate.segments[2].lift_mm"
    assert resolve_key(plate.data, "machining.tool_diameter_mm").path == ("machining", "tool_diameter_mm")


@pytest.mark.parametrize("key, why", [
    ("cams.plate.segments[4].lift_mm", "has 4 entries"),
    ("cams.nope.base_radius_mm", "no table 'cams.nope'"),
    ("cams.plate.segments", "a table or list"),
    ("cams..x", "path"),
])
def test_keys_refused_with_the_reason(plate, key, why):
    with pytest.raises(ParameterError, match="--vary") as info:
        resolve_key(plate.data, key)
    assert why in str(info.value)


def test_bare_key_of_a_scene_of_several_cams_is_refused():
    study = StudyScene.load(None)  # the default scene: three cams
    with pytest.raises(ParameterError, match="name one"):
        resolve_key(study.data, "base_radius_mm")


def test_grid_values_are_the_arithmetic_progression_with_both_ends(plate):
    (radius, step01) = parse_vary(plate.data, ["base_radius_mm=30:40:2.5", "follower_offset_mm=0:1:0.1"])
    assert radius.grid() == (30.0, 32.5, 35.0, 37.5, 40.0)
    values = step01.grid()
    assert len(values) == 11 and values[0] == 0.0 and abs(values[-1] - 1.0) < 1e-12  # 0.1 is not exact in binary
    points = design_points((radius, step01), "grid")
    assert len(points) == 55 and points[0] == (30.0, 0.0) and points[-1][0] == 40.0


def test_latin_hypercube_has_one_point_in_every_stratum(plate):
    variables = parse_vary(plate.data, ["base_radius_mm=30:60", "follower_offset_mm=-5:5", "roller_radius_mm=5:12"])
    n = 50
    points = np.array(design_points(variables, "lhs", n, seed=7), dtype=float)
    lows = np.array([30.0, -5.0, 5.0])
    highs = np.array([60.0, 5.0, 12.0])
    strata = np.floor((points - lows) / (highs - lows) * n).astype(int)
    for column in strata.T:  # McKay et al. 1979: every stratum of every coordinate exactly once
        assert sorted(column.tolist()) == list(range(n))


def test_sobol_points_form_a_net_in_each_coordinate(plate):
    variables = parse_vary(plate.data, ["base_radius_mm=30:62", "follower_offset_mm=0:16"])
    n = 64
    points = np.array(design_points(variables, "sobol", n, seed=3), dtype=float)
    unit = (points - [30.0, 0.0]) / [32.0, 16.0]
    for column in unit.T:  # Owen 1995: 2^m points, one in each interval of length 2^-m
        assert sorted(np.floor(column * n).astype(int).tolist()) == list(range(n))


def test_listed_values_in_a_sampled_design_are_taken_equally_often(plate):
    variables = parse_vary(plate.data, ["cams.plate.segments[0].law=cycloidal,poly345,simple_harmonic", "base_radius_mm=30:60"])
    points = design_points(variables, "lhs", 30, seed=1)
    laws = [p[0] for p in points]
    assert {law: laws.count(law) for law in set(laws)} == {"cycloidal": 10, "poly345": 10, "simple_harmonic": 10}


@pytest.mark.parametrize("spec, valid", [
    ("base_radius_mm=60:30", "low < high"),
    ("base_radius_mm=30:60:0", "step > 0"),
    ("base_radius_mm=30:nan", "finite"),
    ("base_radius_mm", "KEY=low:high"),
])
def test_bad_vary_refused_in_one_line(plate, spec, valid):
    with pytest.raises(ParameterError) as info:
        parse_vary(plate.data, [spec])
    assert valid in str(info.value) and "\n" not in str(info.value)


def test_a_range_without_a_step_is_no_grid(plate):
    with pytest.raises(ParameterError, match="low:high:step for a grid"):
        design_points(parse_vary(plate.data, ["base_radius_mm=30:60"]), "grid")


def test_points_file_read_in_order(plate, tmp_path):
    path = tmp_path / "points.csv"
    path.write_text("base_radius_mm,cams.plate.segments[0].law\n35,cycloidal\n42.5,poly345\n35,poly345\n", encoding="utf-8")
    variables, points = read_points(path, plate.data)
    assert [v.name for v in variables] == ["cams.plate.base_radius_mm", "cams.plate.segments[0].law"]
    assert points == [(35, "cycloidal"), (42.5, "poly345"), (35, "poly345")]


def _check_table(scene: Path) -> tuple[int, dict[tuple[str, str], tuple[str, str]], str]:
    """``camgen check`` as a program: exit status, (cam, check) -> (result, value), stderr."""
    proc = subprocess.run([sys.executable, "-m", "camgen", "check", str(scene)], capture_output=True, text=True, timeout=300)
    table = {}
    for line in proc.stdout.splitlines()[1:]:
        cells = line.split()
        if len(cells) >= 4 and cells[2] in ("pass", "FAIL", "info"):
            table[(cells[0], cells[1])] = (cells[2].lower(), cells[3])
    return proc.returncode, table, proc.stderr


@pytest.mark.parametrize("values", [(40.0, 10.0), (22.0, 10.0), (40.0, -1.0)], ids=["passes", "pressure-angle-fails", "refused"])
def test_row_equals_camgen_check_on_the_written_scene(plate, tmp_path, values):
    keys = [v.key for v in parse_vary(plate.data, ["base_radius_mm=1,2", "roller_radius_mm=1,2"])]
    row = evaluate_point(plate, keys, values)
    scene = tmp_path / "design.toml"
    scene.write_text(edit_scene_text(plate.text, point_scene_data(plate.data, {k.path: v for k, v in zip(keys, values)})),
                     encoding="utf-8")
    status, table, stderr = _check_table(scene)
    if row["status"] == "error":
        assert status == 2 and stderr.strip() == row["error"]
        return
    assert status == (1 if row["status"] == "fail" else 0)
    checks = {name.split(".")[2]: value for name, value in row.items() if name.startswith("check.") and not name.endswith(".status")}
    assert {(cam, c) for cam, c in table if not c.endswith("_export")} == {("plate", c) for c in checks}
    for (cam, name), (result, shown) in table.items():
        if name.endswith("_export"):
            continue
        assert row[f"check.plate.{name}.status"] == result
        if checks[name] is not None:  # the table prints 6 significant digits
            assert math.isclose(checks[name], float(shown.rstrip(",")), rel_tol=1e-5, abs_tol=1e-9)
    if values == (22.0, 10.0):
        assert row["check.plate.pressure_angle.status"] == "fail"


def test_edited_scene_keeps_its_comments_and_holds_the_values(plate):
    data = point_scene_data(plate.data, {("cams", "plate", "base_radius_mm"): 45.5, ("cams", "plate", "segments", 2, "law"): "cycloidal"})
    data["cams"]["plate"]["segments"] = data["cams"]["plate"]["segments"] + [{"law": "dwell", "span_deg": 0.5}]
    text = edit_scene_text(plate.text, data)
    assert tomllib.loads(text) == data
    comments = [line.split("#", 1)[1].strip() for line in plate.text.splitlines() if "#" in line]
    kept = [c for c in comments if c in text]
    assert kept == comments  # every comment of the template is still there (no key of theirs was removed)
    assert "base_radius_mm = 45.5" in text and "# the roller touches the cam 40 mm" in text


def test_sweep_table_read_and_its_errors_refused_by_check(plate, tmp_path):
    table = sweep_table({**plate.data, "sweep": {"method": "lhs", "samples": 8, "seed": 2,
                                                  "vary": {"base_radius_mm": "30:60", "roller_radius_mm": [5.0, 8.0]}}})
    assert (table.method, table.samples, table.seed) == ("lhs", 8, 2)
    assert [v.name for v in table.variables] == ["cams.plate.base_radius_mm", "cams.plate.roller_radius_mm"]
    bad = tmp_path / "bad.toml"
    bad.write_text(plate.text + '\n[sweep]\nmethod = "random"\n', encoding="utf-8")
    status, _, stderr = _check_table(bad)
    assert status == 2 and stderr.count("\n") == 1 and "sweep.method" in stderr and "grid, lhs, sobol" in stderr
