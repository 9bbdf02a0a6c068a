"""Bad input never escapes (issue "Trust", item 9): generated bad scenes over every key of every
kind, of [output], [machining] and of every mechanism, plus names, structure, sizes and files.

Each case is a real scene file run by ``camgen run``: exit status 2, exactly one stderr line
``camgen: error: ...`` naming the key at fault, no traceback, and nothing written anywhere (the
folder above OUTDIR included).  The cases are generated from the schema with a fixed seed, so a
new key is covered the day it is added.
"""
from __future__ import annotations

import datetime
import json
import math
import random
import subprocess
import sys

import pytest

from camgen.cli import main
from camgen.jobs import get_job, job_names
from camgen.kinds import get_kind, kind_names
from camgen.outputs import machining_keys, output_keys
from camgen.schema import Choice, ChoiceList, Count, Flag, Key, Number, NumberList, TableList, Text

SEED = 20261123
#: Cases per key (types that have fewer kinds of wrong value give fewer).
PER_KEY = 12


# --------------------------------------------------------------------------------------------
# A small TOML writer (the test writes real scene files)
# --------------------------------------------------------------------------------------------
def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # JSON's escapes are TOML basic-string escapes
    if isinstance(value, (datetime.date, datetime.datetime)):
        return value.isoformat()
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(type(value))


def toml_scene(scene: dict) -> str:
    lines = []
    for key, value in scene.items():
        if not isinstance(value, dict):
            lines.append(f"{json.dumps(key)} = {toml_value(value)}")
    for section in ("output", "machining"):
        if isinstance(scene.get(section), dict):
            lines.append(f"[{section}]")
            lines += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in scene[section].items()]
    for section in ("cams", "mechanisms"):
        if isinstance(scene.get(section), dict):
            for name, table in scene[section].items():
                if isinstance(table, dict):
                    lines.append(f"[{section}.{json.dumps(name)}]")
                    lines += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in table.items()]
                else:
                    lines.append(f"[{section}]\n{json.dumps(name)} = {toml_value(table)}")
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------------------------
# Valid bases
# --------------------------------------------------------------------------------------------
CAMS = {
    "three_arc": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0, "bore_diameter_mm": 20.0,
                  "keyway_width_mm": 6.0, "keyway_depth_mm": 2.8, "follower": "roller", "roller_radius_mm": 10.0},
    "trajectory": {"kind": "trajectory", "expression": "202.4396*sin(pi*x/1000)", "period_mm": 2000.0, "samples": 180,
                   "fit_tables": ["A1"], "worm_teeth": 50},
    "motion_law": {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0,
                   "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                                {"law": "poly345", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]},
}


def base_scene(kind: str = "three_arc") -> dict:
    cam = dict(CAMS.get(kind, CAMS["three_arc"]))
    return {"name": "fuzz", "output": {"formats": ["dxf", "lift", "ngc"], "lift_step_deg": 1.0}, "machining": {"tool_diameter_mm": 6.0},
            "cams": {"x": cam}}


def leg_scene() -> dict:
    scene = base_scene()
    scene["cams"] = {"s": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0},
                     "h": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 220.0, "c_mm": 10.0}}
    scene["mechanisms"] = {"horse_leg": {"stride_cam": "s", "height_cam": "h", "inclinations_deg": [12.5]}}
    return scene


# --------------------------------------------------------------------------------------------
# Wrong values by type
# --------------------------------------------------------------------------------------------
def wrong_values(key: Key, rng: random.Random) -> list:
    """Values of the wrong type or outside the range of ``key``."""
    common = [[1], {"a": 1}, datetime.date(2026, 11, 23), [[[1]]]]
    kind = key.type
    if isinstance(kind, Number):
        out = ["12", True, float("nan"), float("inf"), -float("inf"), 10**400, -(10**400)]
        if math.isfinite(kind.low):
            out.append(kind.low / kind.scale - (1.0 if kind.low else 1e-3) * rng.uniform(1, 5) * max(1.0, abs(kind.low)))
        if math.isfinite(kind.high):
            out.append(kind.high / kind.scale * rng.uniform(1.5, 10) + 1.0)
        return out + common
    if isinstance(kind, Count):
        return [1.5, "7", True, kind.low - 1, kind.high + 1, 10**400, -(10**30)] + common
    if isinstance(kind, Flag):
        return ["true", 1, 0, 1.0] + common
    if isinstance(kind, Choice):
        return ["no_such_value", "", kind.values[0].upper() + "X", 3, True] + common
    if isinstance(kind, Text):
        return [3, True, "x" * (kind.max_length + 1), "   "] + common
    if isinstance(kind, ChoiceList):
        return ["dxf", [], [3], ["no_such_value"], [kind.values[0], kind.values[0]], [[kind.values[0]]], {"a": 1}]
    if isinstance(kind, NumberList):
        return [3.0, [], ["a"] * kind.min_items, [float("nan")] * kind.min_items, [1.0] * (kind.max_items + 1), [[1.0]], {"a": 1}]
    if isinstance(kind, TableList):
        return [3, [], [1, 2], [{"unknown_key": 1}], [{"law": "no_such_law", "span_deg": 360.0}], [[{}]],
                [{"law": "dwell", "span_deg": 360.0}] * (kind.max_items + 1)]
    raise AssertionError(f"no wrong values for {type(kind).__name__} (key {key.name})")


def _cases():
    rng = random.Random(SEED)
    cases = []

    def add(scene, key_text, label):
        cases.append(pytest.param(scene, key_text, id=f"{label}-{len(cases)}"))

    groups = [("cams.x", kind, get_kind(kind).keys) for kind in kind_names() if kind in CAMS]
    groups += [("output", None, output_keys()), ("machining", None, machining_keys())]
    groups += [(f"mechanisms.{j}", "leg", get_job(j).keys) for j in job_names()]
    for where, kind, keys in groups:
        for key in keys:
            values = wrong_values(key, rng)
            rng.shuffle(values)
            for value in values[:PER_KEY]:
                scene = leg_scene() if kind == "leg" else base_scene(kind or "three_arc")
                table = scene
                for part in where.split("."):
                    table = table[part]
                table[key.name] = value
                add(scene, key.name, f"{where}.{key.name}")
            if key.required:  # left out
                scene = leg_scene() if kind == "leg" else base_scene(kind or "three_arc")
                table = scene
                for part in where.split("."):
                    table = table[part]
                del table[key.name]
                add(scene, key.name, f"{where}.{key.name}-missing")
        for _ in range(3):  # unknown keys
            scene = leg_scene() if kind == "leg" else base_scene(kind or "three_arc")
            table = scene
            for part in where.split("."):
                table = table[part]
            name = rng.choice(["colour", "a_m", "thickness", "FORMAT", "x" * 70, "kind2"])
            table[name] = 1.0
            add(scene, name[:60], f"{where}.unknown")
    # names: of the scene and of cams (file names: nothing may resolve outside OUTDIR)
    for bad in ("..", ".", "../evil", "a/b", "/etc", "", " x", "x" * 65, "-x", "a\\b", "a\x00b", "\u00e9"):
        scene = base_scene()
        scene["name"] = bad
        add(scene, "name", "scene-name")
        scene = base_scene()
        scene["cams"] = {bad: scene["cams"]["x"]}
        add(scene, "cams.", "cam-name")
    # structure
    for section, value in (("cams", 3), ("cams", {}), ("output", [1]), ("machining", "fast"), ("mechanisms", {"walker": {}}),
                           ("mechanisms", [1]), ("extra", 1)):
        scene = base_scene()
        scene[section] = value
        add(scene, section, f"structure-{section}")
    scene = base_scene()
    del scene["cams"]
    add(scene, "cams", "structure-no-cams")
    scene = base_scene()
    scene["cams"]["x"]["kind"] = "no_such_kind"
    add(scene, "kind", "structure-kind")
    scene = base_scene()
    del scene["cams"]["x"]["kind"]
    add(scene, "kind", "structure-no-kind")
    deep: object = 1.0  # nesting beyond the limit
    for _ in range(40):
        deep = [deep]
    scene = base_scene()
    scene["cams"]["x"]["a_mm"] = deep
    add(scene, "a_mm", "nesting")
    # hostile expressions
    for text in ("__import__('os').system('true')", "x.__class__", "lambda: 1", "[x for x in ()]", "(" * 300 + "x" + ")" * 300,
                 "x" + "+x" * 1500, "sin(x, x)", "open('f')", "1e999*x", "x**x**x**x**x**x**x**x**x**x**x**x**x**x**x**x"):
        scene = base_scene("trajectory")
        scene["cams"]["x"]["expression"] = text
        add(scene, "expression", "expression")
    # files that are not tables
    for path in ("/dev/zero", "/nonexistent/table.csv", "/", "/etc/hostname"):
        scene = base_scene("trajectory")
        del scene["cams"]["x"]["expression"], scene["cams"]["x"]["period_mm"]
        scene["cams"]["x"]["trajectory_csv"] = path
        add(scene, "trajectory_csv", "table-file")
    return cases


CASES = _cases()


def test_there_are_enough_cases():
    assert len(CASES) >= 1000


@pytest.mark.parametrize("scene, key", CASES)
def test_bad_scene_is_one_line_naming_the_key_and_writes_nothing(scene, key, tmp_path, capsys):
    path = tmp_path / "scene.toml"
    path.write_text(toml_scene(scene), encoding="utf-8")
    parent = tmp_path / "parent"
    parent.mkdir()
    status = main(["run", str(path), "-o", str(parent / "out")])
    err = capsys.readouterr().err
    assert status == 2, err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err
    assert key in err, f"the error does not name '{key}': {err}"
    assert list(parent.iterdir()) == []  # nothing written, not even OUTDIR
    assert sorted(p.name for p in tmp_path.iterdir()) == ["parent", "scene.toml"]


@pytest.mark.parametrize("index", range(0, len(CASES), max(1, len(CASES) // 12)))
def test_bad_scenes_in_a_process_exit_2_without_traceback(index, tmp_path):
    scene, key = CASES[index].values
    path = tmp_path / "scene.toml"
    path.write_text(toml_scene(scene), encoding="utf-8")
    proc = subprocess.run([sys.executable, "-m", "camgen", "run", str(path), "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1, proc.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("path", ["/dev/zero", "/", "/nonexistent.toml"])
def test_scene_files_that_cannot_be_scenes(path, capsys):
    assert main(["run", path, "-o", "/nonexistent/out"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: cannot read scene file") and err.count("\n") == 1


def test_a_scene_file_named_dot_dot_cannot_write_outside(tmp_path, capsys):
    """A scene file `...toml` has the stem `..`: without a name = "..." it is refused."""
    path = tmp_path / "...toml"
    path.write_text(toml_scene({"cams": base_scene()["cams"]}))
    parent = tmp_path / "parent"
    parent.mkdir()
    assert main(["run", str(path), "-o", str(parent / "out")]) == 2
    assert "name" in capsys.readouterr().err and list(parent.iterdir()) == []
