"""Bad input never escapes (issue "Trust", item 9; "Trust, round 2", items 3-5): generated bad
scenes over every key of every kind, of [output], [machining] and of every mechanism, plus
names, structure, sizes and files.

Each case is a real scene file run by ``camgen run``: exit status 2, exactly one stderr line
``camgen: error: ...`` naming the key at fault, no traceback, and nothing written anywhere (the
folder above OUTDIR included).  The cases are generated from the schema with a fixed seed, so a
new key is covered the day it is added.  Every key also gets integer literals no float can hold
(4000 hexadecimal digits, 5000 decimal digits, octal and binary), a string with a NUL character
and (for text keys and a sample of the others) a string of a million characters; the text of a
scene gets keys, tables and brackets nested thousands deep, more items than a scene may hold,
and expressions too deep or too costly to differentiate.  That these are refused in bounded
memory is shown by construction: the heaviest run in processes whose address space is capped
(``RLIMIT_AS``, :data:`MEMORY_LIMIT`), with a timeout that only guards against a hang.
"""
from __future__ import annotations

import collections
import copy
import datetime
import json
import math
import os
import random
import re
import subprocess
import sys

import pytest

from camgen.cli import main
from camgen.jobs import get_job, job_names
from camgen.kinds import get_kind, kind_names
from camgen.outputs import machining_keys, output_keys
from camgen.scene import template_dir
from camgen.schema import Choice, ChoiceList, Count, Flag, Key, Number, NumberList, TableList, Text

SEED = 20261123
#: Cases per key (types that have fewer kinds of wrong value give fewer).
PER_KEY = 12


# --------------------------------------------------------------------------------------------
# A small TOML writer (the test writes real scene files)
# --------------------------------------------------------------------------------------------
class Raw(str):
    """TOML text written as it is (integer literals a Python value cannot stand for: hex, octal)."""


def toml_value(value) -> str:
    if isinstance(value, Raw):
        return str(value)
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


def mechanism_scene(where: str) -> dict:
    """A valid scene for the mechanism table ``where`` (``mechanisms.<job>``)."""
    if where != "mechanisms.machine":
        return leg_scene()
    scene = leg_scene()  # the two three-arc cams on one shaft (no dynamics: no torque)
    scene["mechanisms"] = {"machine": {"rpm": 100.0, "cams": [{"name": "s"}, {"name": "h", "phase_deg": 90.0}]}}
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


#: Integer literals beyond the float range (issue "Trust, round 2", item 3): tomllib stops on
#: the 5000-digit decimal (Python's 4300-digit limit); the others parse, and their text is too
#: long for Python's int-to-str conversion in an error message.
HUGE_INTEGERS = {
    "hex": Raw("0x" + "f" * 4000),
    "decimal": Raw("9" * 5000),
    "negative": Raw("-" + "9" * 5000),
    "octal": Raw("0o" + "7" * 3000),
    "binary": Raw("0b" + "1" * 4400),
}
#: A string of a million characters (the scene stays under its 1 MiB limit).
MEGA_STRING = "x" * 1_000_000


def literal_values(key: Key, index: int) -> list[tuple[str, object]]:
    """(label, value) of the literal cases of ``key``: hex and huge decimal integers, octal or
    binary (by turns), a string holding a NUL character, and a million-character string for
    text keys and every eighth other key (``index`` counts the keys)."""
    out = [("hex", HUGE_INTEGERS["hex"]), ("decimal", HUGE_INTEGERS["decimal" if index % 2 else "negative"]),
           ("octal" if index % 2 else "binary", HUGE_INTEGERS["octal" if index % 2 else "binary"]),
           ("nul", "cam\x00.csv")]
    if isinstance(key.type, (Text, Choice, ChoiceList)) or index % 8 == 0:
        out.append(("mega", MEGA_STRING))
    return out


def _cases():
    rng = random.Random(SEED)
    cases = []

    def add(scene, key_text, label):
        cases.append(pytest.param(scene, key_text, id=f"{label}-{len(cases)}"))

    groups = [("cams.x", kind, get_kind(kind).keys) for kind in kind_names() if kind in CAMS]
    groups += [("output", None, output_keys()), ("machining", None, machining_keys())]
    groups += [(f"mechanisms.{j}", "leg", get_job(j).keys) for j in job_names()]
    count = 0
    for where, kind, keys in groups:
        for key in keys:
            for label, value in literal_values(key, count):  # every key: huge integers, NUL, long strings
                scene = mechanism_scene(where) if kind == "leg" else base_scene(kind or "three_arc")
                table = scene
                for part in where.split("."):
                    table = table[part]
                table[key.name] = value
                add(scene, key.name, f"{where}.{key.name}-{label}")
            count += 1
            if isinstance(key.type, TableList) and isinstance(CAMS.get(kind or "", {}).get(key.name), list):
                for sub in key.type.keys:  # and the keys of its tables ([[cams.x.segments]])
                    for label, value in literal_values(sub, count):
                        scene = copy.deepcopy(base_scene(kind or "three_arc"))  # CAMS' lists are shared
                        scene["cams"]["x"][key.name][0][sub.name] = value
                        add(scene, sub.name, f"{where}.{key.name}.{sub.name}-{label}")
                    count += 1
            values = wrong_values(key, rng)
            rng.shuffle(values)
            for value in values[:PER_KEY]:
                scene = mechanism_scene(where) if kind == "leg" else base_scene(kind or "three_arc")
                table = scene
                for part in where.split("."):
                    table = table[part]
                table[key.name] = value
                add(scene, key.name, f"{where}.{key.name}")
            if key.required:  # left out
                scene = mechanism_scene(where) if kind == "leg" else base_scene(kind or "three_arc")
                table = scene
                for part in where.split("."):
                    table = table[part]
                del table[key.name]
                add(scene, key.name, f"{where}.{key.name}-missing")
        for _ in range(3):  # unknown keys
            scene = mechanism_scene(where) if kind == "leg" else base_scene(kind or "three_arc")
            table = scene
            for part in where.split("."):
                table = table[part]
            name = rng.choice(["colour", "a_m", "thickness", "FORMAT", "x" * 70, "kind2"])
            table[name] = 1.0
            add(scene, name[:60], f"{where}.unknown")
    for label, value in literal_values(Key("name", Text(64), "", ()), 0):  # the scene's name and a cam's kind
        scene = base_scene()
        scene["name"] = value
        add(scene, "name", f"name-{label}")
        scene = base_scene()
        scene["cams"]["x"]["kind"] = value
        add(scene, "kind", f"kind-{label}")
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


# --------------------------------------------------------------------------------------------
# More cases (issue "Accuracy and numerical stability", item 3): the lift_table kind's keys,
# malformed tables, hostile expressions, mechanisms beyond their assembly, file sizes
# --------------------------------------------------------------------------------------------
MORE_SEED = 20261124
#: A valid lift table (the template's), absolute: the scenes are written to temporary folders.
LIFT_CSV = str(template_dir() / "lift_table.csv")
LIFT_CAM = {"kind": "lift_table", "lift_table_csv": LIFT_CSV, "base_radius_mm": 40.0, "roller_radius_mm": 10.0}

#: Table file contents that are not tables (written by the test; name -> text or bytes).
_TRAJ_ROWS = [(2000.0 * i / 40, 202.4396 * math.sin(math.pi * i / 20)) for i in range(41)]
_LIFT_ROWS = [(5.0 * i, 10.0 * (1 - math.cos(math.radians(5.0 * i)))) for i in range(72)]


def _csv(rows) -> str:
    return "".join(f"{a!r},{b!r}\n" for a, b in rows)


def malformed_tables(rows: list[tuple[float, float]]) -> dict[str, str | bytes]:
    """Contents of a table file (x or angle, y or lift) that camgen must refuse."""
    good = _csv(rows)
    swapped = rows[:]
    swapped[3], swapped[4] = swapped[4], swapped[3]
    return {
        "empty": "",
        "header-only": "x,y\n",
        "comments-only": "# nothing\n# here\n",
        "garbage": "lorem ipsum\ndolor, sit, amet\n" * 10,
        "binary": bytes(range(256)) * 4,
        "latin1": "x,y\n" + good.replace("0,", "\u00e9,").encode("latin-1", "replace").decode("latin-1") + "\u00ff",
        "nul": good[:40] + "\x00" + good[40:],
        "nan": good + "nan,nan\n",
        "nan-in-row": _csv(rows[:5]) + f"{rows[5][0]!r},nan\n" + _csv(rows[6:]),
        "inf": _csv(rows[:5]) + f"{rows[5][0]!r},inf\n" + _csv(rows[6:]),
        "huge-number": _csv(rows[:5]) + f"{rows[5][0]!r},1e400\n" + _csv(rows[6:]),
        "unsorted": _csv(swapped),
        "duplicate": _csv(rows[:6] + rows[5:]),
        "three-columns": "".join(f"{a!r},{b!r},1\n" for a, b in rows),
        "one-column": "".join(f"{a!r}\n" for a, _ in rows),
        "decimal-commas": "".join(f"{a!r},{b!r}\n".replace(".", ",") for a, b in rows),
        "too-few": _csv(rows[:4]),
        "too-many-rows": "".join(f"{i * 1e-4!r},0\n" for i in range(200_001)),
        "too-large": "# " + "x" * (9 << 20) + "\n" + good,
    }


#: Cases that fail today in files this test's owner may not edit (the fix is described in each reason).
KNOWN_BUGS = {
}


def _more_cases():
    rng = random.Random(MORE_SEED)
    cases = []

    def add(scene, key_text, label):
        marks = [pytest.mark.xfail(strict=True, reason=KNOWN_BUGS[label])] if label in KNOWN_BUGS else []
        cases.append(pytest.param(scene, key_text, id=f"more-{label}-{len(cases)}", marks=marks))

    def lift_scene():
        scene = base_scene()
        scene["cams"] = {"x": dict(LIFT_CAM)}
        return scene

    for index, key in enumerate(get_kind("lift_table").keys):  # the lift_table kind's keys, as _cases() does the others'
        for label, value in literal_values(key, index):
            scene = lift_scene()
            scene["cams"]["x"][key.name] = value
            add(scene, key.name, f"cams.x.{key.name}-{label}")
        values = wrong_values(key, rng)
        rng.shuffle(values)
        for value in values[:PER_KEY]:
            scene = lift_scene()
            scene["cams"]["x"][key.name] = value
            add(scene, key.name, f"cams.x.{key.name}")
        if key.required:
            scene = lift_scene()
            del scene["cams"]["x"][key.name]
            add(scene, key.name, f"cams.x.{key.name}-missing")
    # malformed table files (written at run time: a "table:<name>" value)
    for name in malformed_tables(_LIFT_ROWS):
        scene = lift_scene()
        scene["cams"]["x"]["lift_table_csv"] = f"table:{name}"
        add(scene, "lift_table_csv", f"lift-table-{name}")
    for name in malformed_tables(_TRAJ_ROWS):
        scene = base_scene("trajectory")
        del scene["cams"]["x"]["expression"], scene["cams"]["x"]["period_mm"]
        scene["cams"]["x"]["trajectory_csv"] = f"table:{name}"
        add(scene, "trajectory_csv", f"trajectory-table-{name}")
    for path in ("/dev/zero", "/dev/urandom", "/", "/nonexistent/table.csv", "/proc/self/status", LIFT_CSV + "\x00", "\x00"):
        scene = lift_scene()
        scene["cams"]["x"]["lift_table_csv"] = path
        add(scene, "lift_table_csv", "lift-table-file")
    for path in (LIFT_CSV + "\x00.csv", "table\x00.csv"):  # NUL in the other file keys' paths
        scene = base_scene("trajectory")
        del scene["cams"]["x"]["expression"], scene["cams"]["x"]["period_mm"]
        scene["cams"]["x"]["trajectory_csv"] = path
        add(scene, "trajectory_csv", "trajectory-table-nul")
        scene = base_scene("motion_law")
        scene["cams"]["x"].update(rpm=100.0, mass_kg=0.5, spring_rate_n_per_mm=1.0, external_load_csv=path)
        add(scene, "external_load_csv", "load-table-nul")
    # the scene's text: nesting, items and literals the TOML parser cannot take in bounded time and memory
    for label, key, value in STRUCTURE_VALUES:
        scene = base_scene()
        scene["cams"]["x"]["a_mm"] = value
        add(scene, key, f"text-{label}")
    for label, (key, text) in STRUCTURE_TEXTS.items():
        add(toml_scene(base_scene()) + text, key, f"text-{label}")
    # hostile and impossible expressions (the path: never evaluated as Python, never NaN)
    for text in ("x**1e308", "exp(exp(exp(x)))", "1/0", "0/0", "x/0", "log(0*x)", "sqrt(-1-x*x)", "abs(x-1000)", "sqrt(x)",
                 "(x-1000)**2", "1e308*sin(x)", "sin(x)**-1", "exp(710+0*x)", "x if x else 1", "x[0]", "{x}", "x;x", "x@x",
                 "x^2", "x % 3", "x // 2", "not x", "x < 1", "f'{x}'", "'a'", "b'x'", "True", "None", "...", "x.real",
                 "sin", "sin()", "sin(x=1)", "sin(*x)", "\u0445", "1_000*x", "0x10*x", "1j*x", "\x00", "x\n+1",
                 "1e308*sin(2*pi*x/2000)", "cos(pi*x/1000)**(1/3)",
                 # round 2, item 3: recursion, derivatives of O(n^3) operations, numbers beyond the float range
                 "x" + "+x" * 999, "x" + "*x" * 600, "x" + "*x" * 60, "x" + "/x" * 40, "sin(" * 150 + "x" + ")" * 150,
                 "-" * 1999 + "x", "x" + "**x" * 600, "exp(" * 60 + "x" + ")" * 60, "1" + "0" * 400 + "*x",
                 "0x" + "f" * 1000 + "*x", "x*" + "9" * 1990):
        scene = base_scene("trajectory")
        scene["cams"]["x"]["expression"] = text
        add(scene, "expression", "expression")
    # numbers at the edge of the float range and of each type
    for key, value in (("a_mm", 5e-324), ("a_mm", 1.7976931348623157e308), ("c_mm", -0.0), ("b_mm", 9.999999999e-7),
                       ("thickness_mm", 1e4 * (1 + 1e-15) + 1e-9), ("rpm", 0.0), ("rpm", -1e-300),
                       ("rpm", 5e-324), ("rpm", 9.99e-4)):
        scene = base_scene()
        scene["cams"]["x"][key] = value
        add(scene, key, "edge-number")
    for key, value in (("samples", 20001), ("samples", 15), ("samples", 1_000_000), ("period_mm", 1e-300), ("period_mm", 5e-7),
                       ("ride_periods", 1001), ("worm_teeth", 0)):
        scene = base_scene("trajectory")
        scene["cams"]["x"][key] = value
        add(scene, key, "edge-trajectory")
    # the three-arc domain 0 < b < min(2a, a + c): on and beyond both bounds
    for a, b, c, key in ((220.0, 440.0, 500.0, "b_mm"), (220.0, 245.0, 25.0, "b_mm"), (220.0, 440.0 * (1 + 1e-12), 500.0, "b_mm"),
                         (1e-3, 1e-3 + 1e-6, 1e-6, "b_mm")):
        scene = base_scene()
        scene["cams"]["x"].update(a_mm=a, b_mm=b, c_mm=c, bore_diameter_mm=0.0, keyway_width_mm=0.0, keyway_depth_mm=0.0)
        add(scene, key, "three-arc-domain")
    # the leg beyond its assembly (alpha1 9.38 .. 20.11 deg for the paper's leg) and ground line
    for alphas, key in (([25.0], "inclinations_deg[0]"), ([12.5, 60.0], "inclinations_deg[1]"), ([-90.0], "inclinations_deg[0]"),
                        ([9.0], "inclinations_deg[0]"), ([12.5, 12.5000001], "inclinations_deg"), ([12.4999996, 12.5000004], "inclinations_deg")):
        scene = leg_scene()
        scene["mechanisms"]["horse_leg"]["inclinations_deg"] = alphas
        add(scene, key, "leg-inclination")
    for ground in (0.0, -5000.0, 1e5):
        scene = leg_scene()
        scene["mechanisms"]["horse_leg"]["ground_y_mm"] = ground
        add(scene, "ground_y_mm", "leg-ground")
    scene = leg_scene()  # a height cam the fork cannot ride
    scene["cams"]["h"] = {"kind": "three_arc", "a_mm": 400.0, "b_mm": 300.0, "c_mm": 200.0}
    add(scene, "height_cam", "leg-height-cam")
    scene = leg_scene()  # a stride cam with which the leg assembles nowhere
    scene["cams"]["s"] = {"kind": "three_arc", "a_mm": 500.0, "b_mm": 100.0, "c_mm": 300.0}
    add(scene, "stride_cam", "leg-stride-cam")
    # G-code settings the chord tolerance cannot hold, and flattened files too large
    for output, machining, key in (({"formats": ["ngc"], "chord_tol_mm": 1e-7}, {}, "chord_tol_mm"),
                                   ({"formats": ["ngc"], "chord_tol_mm": 5e-4}, {"decimals": 4}, "decimals"),
                                   ({"formats": ["points"], "chord_tol_mm": 1e-7}, None, "chord_tol_mm")):
        scene = base_scene()
        scene["output"] = output
        if machining is None:
            del scene["machining"]
        else:
            scene["machining"] = {"tool_diameter_mm": 6.0, **machining}
        scene["cams"]["x"].update(a_mm=1e5, b_mm=1e5, c_mm=10.0, bore_diameter_mm=0.0, keyway_width_mm=0.0, keyway_depth_mm=0.0)
        add(scene, key, "output-size")
    return cases


#: Values of cams.x.a_mm nested or long beyond what a scene may hold: (label, the key the error
#: names, value).
STRUCTURE_VALUES = [
    ("deep-arrays", "a_mm", Raw("[" * 5000 + "]" * 5000)),
    ("deep-arrays-9", "a_mm", Raw("[" * 7 + "]" * 7)),  # cams.x.a_mm is level 3: the 7th bracket's items are level 10
    ("deep-inline-tables", "a_mm", Raw("{a = " * 3000 + "1" + "}" * 3000)),
    ("many-items", "a_mm", Raw("[" + "1," * 30_000 + "]")),
    ("million-items", "a_mm", Raw("[" + "1," * 520_000 + "]")),
]
#: Scene text appended after the cam's table: (the key the error names, text).
STRUCTURE_TEXTS = {
    "deep-dotted-key": ("a.a.a.a", "a." * 20_000 + "b = 1\n"),
    "dotted-key-9": ("p.q.r.s.t.u.v", "p.q.r.s.t.u.v = 1\n"),  # under [cams.x]: level 9
    "deep-header": ("t.t.t.t", "[" + "t." * 20_000 + "u]\nv = 1\n"),
    "deep-array-header": ("t.t.t.t", "[[" + "t." * 20_000 + "u]]\nv = 1\n"),
    "deep-quoted-key": ('"a"."a"', '"a".' * 10_000 + "b = 1\n"),
    "many-keys": ("more than 20000 keys", "".join(f"k{i} = 1\n" for i in range(25_000))),
    "many-tables": ("more than 20000 keys", "".join(f"[[cams.x.segments]]\n" for i in range(25_000))),
}

CASES = _cases() + _more_cases()


def test_there_are_enough_cases():
    assert len(CASES) >= 1000


#: Bad cases run, by family (the terminal summary prints them: test_properties.pytest_terminal_summary).
CASE_COUNTS: collections.Counter = collections.Counter()


@pytest.fixture(scope="module", autouse=True)
def _warm():
    """Import what the cases use once (the cases then share the imports)."""
    import scipy.interpolate  # noqa: F401

    import camgen.export.gcode  # noqa: F401
    import camgen.jobs.horse_leg  # noqa: F401
    import camgen.mechanisms.horse_leg  # noqa: F401
    import camgen.mechanisms.tricycle  # noqa: F401
    import camgen.pipeline  # noqa: F401
    import camgen.synthesis.lift_table  # noqa: F401

    for kind in kind_names():
        get_kind(kind)


def _write_tables(scene: dict | str, folder) -> list[str]:
    """Materialise ``table:<name>`` values (malformed_tables) as files in ``folder``; their names."""
    written: list[str] = []
    cams = scene.get("cams") if isinstance(scene, dict) else None
    for table in cams.values() if isinstance(cams, dict) else ():
        for key in ("lift_table_csv", "trajectory_csv"):
            value = table.get(key) if isinstance(table, dict) else None
            if isinstance(value, str) and value.startswith("table:"):
                name = value.split(":", 1)[1]
                content = malformed_tables(_LIFT_ROWS if key == "lift_table_csv" else _TRAJ_ROWS)[name]
                path = folder / "table.csv"
                path.write_bytes(content if isinstance(content, bytes) else content.encode("utf-8"))
                table[key] = str(path)
                written.append(path.name)
    return written


def _scene_text(scene: dict | str) -> str:
    return scene if isinstance(scene, str) else toml_scene(scene)


@pytest.mark.parametrize("scene, key", CASES)
def test_bad_scene_is_one_line_naming_the_key_and_writes_nothing(scene, key, tmp_path, capsys):
    """`camgen run` refuses with one line naming the key and writes nothing; `camgen check` refuses
    with the same line and status."""
    import copy

    scene = copy.deepcopy(scene)
    tables = _write_tables(scene, tmp_path)
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text(scene), encoding="utf-8")
    parent = tmp_path / "parent"
    parent.mkdir()
    status = main(["run", str(path), "-o", str(parent / "out")])
    err = capsys.readouterr().err
    assert status == 2, err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err
    assert key in err, f"the error does not name '{key}': {err}"
    assert list(parent.iterdir()) == []  # nothing written, not even OUTDIR
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["parent", "scene.toml"] + tables)
    # camgen check shares the reading and the planning: the same status and the same line
    assert main(["check", str(path)]) == status and capsys.readouterr().err == err
    CASE_COUNTS[("bad_input", key.split(".")[-1].split("[")[0] if key else "?")] += 1


#: Address space of the processes that run bad scenes, bytes: importing camgen, numpy and scipy
#: and refusing a scene takes under 200 MB; a 40 KB scene of 20,000-part dotted keys took 1.6 GB
#: before the scene text was bounded (a run over the limit ends in MemoryError, not exit 2).
MEMORY_LIMIT = 400 << 20
#: Threads of the numerical libraries in those processes (their per-thread buffers count in the
#: address space, and the machine's core count must not decide the test).
_ONE_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def _limited_memory() -> None:  # runs in the child, before it starts Python
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def _run_limited(args: list[str], timeout: float) -> subprocess.CompletedProcess:
    """``python args`` with its memory capped at MEMORY_LIMIT; ``timeout`` (s) only guards
    against a hang (no duration is asserted)."""
    import os

    return subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=timeout,
                          preexec_fn=_limited_memory, env={**os.environ, **_ONE_THREAD})


_PLAIN = [i for i, case in enumerate(CASES) if not case.marks]
#: The cases run in a process of capped memory, by family: every case of the scene's text and of
#: expressions, and a sample of the huge literals (the in-process test runs them all).
_HEAVY = {
    "text": [i for i in _PLAIN if "-text-" in CASES[i].id],
    "expression": [i for i in _PLAIN if CASES[i].id.split("-")[0] in ("expression", "more") and "-expression-" in f"-{CASES[i].id}"],
    "literal": [i for i in _PLAIN if any(f"-{label}-" in CASES[i].id for label in ("hex", "decimal", "octal", "binary", "mega", "nul"))][::9],
}


@pytest.mark.parametrize("index", _PLAIN[:: max(1, len(_PLAIN) // 12)])
def test_bad_scenes_in_a_process_exit_2_without_traceback(index, tmp_path):
    import copy

    scene, key = CASES[index].values
    scene = copy.deepcopy(scene)
    _write_tables(scene, tmp_path)
    path = tmp_path / "scene.toml"
    path.write_text(_scene_text(scene), encoding="utf-8")
    proc = _run_limited(["-m", "camgen", "run", str(path), "-o", str(tmp_path / "out")], timeout=300)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1, proc.stderr
    assert key in proc.stderr
    assert not (tmp_path / "out").exists()


#: Runs camgen's command line on each scene of a JSON list [[scene, outdir], ...] in this one
#: process, printing {"status", "err"} per scene as a JSON line.
_DRIVER = """
import contextlib, io, json, sys
from camgen.cli import main
for scene, outdir in json.load(open(sys.argv[1])):
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main(["run", scene, "-o", outdir])
    print(json.dumps({"status": status, "err": err.getvalue()}), flush=True)
"""


@pytest.mark.parametrize("family", ["text", "expression", "literal"])
def test_heavy_bad_scenes_are_refused_in_bounded_memory(family, tmp_path):
    """The scene texts, expressions and literals that took gigabytes, recursed or hit Python's
    digit limit, run by camgen's command line in one process capped at MEMORY_LIMIT: each is
    the one-line exit-2 error naming its key, and nothing is written."""
    import copy
    import json

    jobs, keys = [], []
    for n, index in enumerate(_HEAVY[family]):
        scene, key = CASES[index].values
        scene = copy.deepcopy(scene)
        folder = tmp_path / str(n)
        folder.mkdir()
        _write_tables(scene, folder)
        (folder / "scene.toml").write_text(_scene_text(scene), encoding="utf-8")
        jobs.append([str(folder / "scene.toml"), str(folder / "out")])
        keys.append((CASES[index].id, key))
    (tmp_path / "jobs.json").write_text(json.dumps(jobs))
    proc = _run_limited(["-c", _DRIVER, str(tmp_path / "jobs.json")], timeout=1200)
    results = [json.loads(line) for line in proc.stdout.splitlines()]
    assert proc.returncode == 0 and len(results) == len(jobs), f"stopped after {keys[len(results)][0]}: {proc.stderr[-2000:]}"
    for (case, key), result, (_, outdir) in zip(keys, results, jobs):
        err = result["err"]
        assert result["status"] == 2 and err.startswith("camgen: error: ") and err.count("\n") == 1, (case, err[:500])
        assert key in err and "Traceback" not in err, (case, err[:500])
        assert not os.path.exists(outdir), case
    assert len(jobs) >= 10


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


# --------------------------------------------------------------------------------------------
# Valid scenes at the edges of every range (issue "Trust, round 2", item 15): each is accepted
# (exit 0, or 1 with a failed check), writes the files it asks for (or withholds a cam's
# manufacturing files naming the failed check that blocks them), and what it writes is right:
# the files are the report's list, every number finite, every table readable, the point list
# the profile's area within its chord tolerance, the report stating the value given.
# --------------------------------------------------------------------------------------------
#: A number that is not finite as a writer prints it, standing alone (the scene's names are
#: "fuzz" and "x": no name holds these letters).
_NONFINITE = re.compile(rb"(?<![A-Za-z_])[+-]?(nan|inf|infinity)(?![A-Za-z_])", re.IGNORECASE)


def _edges(key: Key) -> list:
    """The valid values at both ends of ``key``'s range (scene units)."""
    kind = key.type
    if isinstance(kind, Count):
        return [kind.low, kind.high]
    if not isinstance(kind, Number):
        return []
    out = []
    for end, is_open, toward in ((kind.low, kind.low_open, math.inf), (kind.high, kind.high_open, -math.inf)):
        if math.isfinite(end):
            value = end  # bounds are in scene units (Number.parse compares before scaling)
            if is_open:
                value = math.nextafter(value, toward) if value == 0 else value + (1e-9 if toward > 0 else -1e-9) * max(1.0, abs(value))
            out.append(value)
    return out


_OSCILLATING_ROLLER = {"follower": "roller", "follower_motion": "oscillating", "base_radius_mm": 40.0, "roller_radius_mm": 8.0,
                       "pivot_x_mm": 90.0, "pivot_y_mm": 50.0, "arm_length_mm": 80.0}
_OSCILLATING_FLAT = {"follower": "flat", "follower_motion": "oscillating", "base_radius_mm": 45.0, "pivot_x_mm": 100.0,
                     "pivot_y_mm": 60.0, "face_offset_mm": 10.0, "swing_turn": "cw"}


def _swing_segments(swing_deg: float) -> list[dict]:
    return [{"law": "cycloidal", "span_deg": 100.0, "swing_deg": swing_deg}, {"law": "dwell", "span_deg": 60.0},
            {"law": "poly4567", "span_deg": 120.0, "swing_deg": -swing_deg}, {"law": "dwell", "span_deg": 80.0}]


def _clip(x: float) -> float:
    return min(max(x, 1e-6), 1e5)


def _three_arc_scaled(cam: dict, key: str, value: float) -> None:
    """a, b, c in the ratio of the base cam (220 : 160 : 25) with ``key`` = ``value``, kept in
    their ranges and in the domain 0 < b < min(2a, a + c); no body features."""
    base = {"a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0}
    scale = value / base[key]
    abc = {k: _clip(v * scale) for k, v in base.items()}
    abc[key] = value
    if not abc["b_mm"] < min(2 * abc["a_mm"], abc["a_mm"] + abc["c_mm"]):
        others = [k for k in base if k != key]
        for k in others:  # the other two as large as the key needs
            abc[k] = _clip(max(abc[k], value))
        if key == "b_mm":
            abc["a_mm"] = _clip(max(abc["a_mm"], value))
            abc["c_mm"] = _clip(max(abc["c_mm"], value))
    cam.update(abc, bore_diameter_mm=0.0, keyway_width_mm=0.0, keyway_depth_mm=0.0)


def _size(scene: dict) -> float:
    """A length of the cam (mm) to scale the chord tolerance and the machining by."""
    cam = scene["cams"]["x"]
    if cam["kind"] == "three_arc":
        return 2 * cam["a_mm"] + cam["c_mm"]
    if cam["kind"] == "trajectory":
        return 2000.0
    return 2 * (cam.get("base_radius_mm", 40.0) + 20.0) + 2 * cam.get("roller_radius_mm", 0.0)


def _edge_scene(where: str, kind: str | None, key: Key, value: float) -> tuple[dict, list[str]]:
    """A scene in which ``value`` of ``key`` is valid: the key's own needs given (follower,
    motion, mass and speed), the other lengths scaled to it, the outputs it changes asked for.
    Returns the scene and the formats asked for."""
    if kind == "leg":
        scene = mechanism_scene(where)
    elif kind == "lift_table":
        scene = base_scene()
        scene["cams"] = {"x": dict(LIFT_CAM)}
    elif where == "output" and "drawing" in key.affects:  # the drawing's keys: a disk cam (it has a zero mark)
        scene = copy.deepcopy(base_scene("motion_law"))
    else:
        scene = copy.deepcopy(base_scene(kind or "three_arc"))
    cams = scene["cams"]
    cam = cams["x"] if "x" in cams else None
    if kind == "three_arc":  # the cam of paper 000 with its yoke (the default follower), a bore and a keyway
        cam.update(follower="yoke")
        del cam["roller_radius_mm"]
    table = scene
    for part in where.split("."):
        table = table[part]
    name = key.name
    for other, allowed in key.requires.items():
        table[other] = allowed[0]
    if cam is not None and where == "cams.x":
        oscillating = cam.get("follower_motion") == "oscillating"
        if oscillating and kind in ("motion_law", "lift_table"):
            cam.update(_OSCILLATING_FLAT if cam.get("follower") == "flat" else _OSCILLATING_ROLLER)
            cam.pop("roller_radius_mm", None) if cam.get("follower") == "flat" else None
            if kind == "motion_law":
                cam["segments"] = _swing_segments(10.0)
        if oscillating and kind == "three_arc":  # pitch radii 35 .. 315 mm: the arm's circle meets them all
            cam.update(follower="roller", roller_radius_mm=10.0, pivot_x_mm=350.0, pivot_y_mm=0.0, arm_length_mm=330.0)
        if cam.get("follower") == "flat" and kind in ("motion_law", "lift_table"):
            cam.pop("roller_radius_mm", None)
        if cam.get("follower") in ("roller",) and kind == "three_arc":
            cam.setdefault("roller_radius_mm", 10.0)
        dynamics = {k.name for k in __import__("camgen.kinds.dynamics", fromlist=["dynamics_keys"]).dynamics_keys()}
        if name in dynamics:
            cam["rpm"] = 100.0
            if kind == "three_arc":  # a flat face (a yoke is form-closed: no spring, no jump)
                cam["follower"] = "flat"
                cam.pop("roller_radius_mm", None)
            cam["inertia_kg_m2" if oscillating else "mass_kg"] = cam.get("inertia_kg_m2" if oscillating else "mass_kg", 0.5)
            if name == "cg_distance_mm":
                cam["mass_kg"] = 0.25
            if name in ("spring_free_length_mm", "spring_installed_length_mm"):
                cam.update(spring_rate_n_per_mm=1.0, spring_free_length_mm=value, spring_installed_length_mm=value)
            if name in ("damping_ratio", "residual_vibration_limit_mm"):  # the compliant train's: with its stiffness
                cam["train_stiffness_n_mm_per_rad" if oscillating else "train_stiffness_n_per_mm"] = 1e3
            if name in ("follower_stiffness_n_per_mm", "tool_mass_kg", "return_spring_on"):  # the two-mass train's: together
                valid = name == "tool_mass_kg" and isinstance(value, (int, float)) and 0.1 < value <= 1e4  # its edges' mass
                tool = value if valid else 0.1
                cam.update(follower_stiffness_n_per_mm=1e3, tool_mass_kg=tool, train_stiffness_n_per_mm=1e3, mass_kg=2.0 * tool + 0.5)
            # FATIGUE (issue 25 items 3, 4): the friction and life keys given with the keys they need
            fatigue = {"guide_length_mm": {"guide_overhang_mm": 20.0}, "guide_overhang_mm": {"guide_length_mm": 40.0},
                       "guide_friction": {"guide_length_mm": 40.0, "guide_overhang_mm": 20.0},
                       "roller_pin_friction": {"roller_pin_radius_mm": 3.0}, "contact_friction": {"roller_pin_radius_mm": 3.0},
                       "roller_bearing": {"roller_dynamic_load_rating_n": 8000.0},
                       "min_bearing_life_h": {"roller_dynamic_load_rating_n": 8000.0}}
            sn = {"sn_stress_mpa": 1500.0, "sn_cycles": 1e7, "sn_exponent": 6.6, "contact_design_cycles": 1e8}
            if name in sn:
                cam.update({k: v for k, v in sn.items() if k != name})
            if cam.get("follower", "roller") == "roller" or name not in ("roller_pin_friction", "contact_friction"):
                cam.update(fatigue.get(name, {}))
        # lengths scaled to the value
        if kind == "three_arc" and name in ("a_mm", "b_mm", "c_mm"):
            _three_arc_scaled(cam, name, value)
        big = abs(value) >= 1e3
        if name == "bore_diameter_mm":
            cam.update(keyway_width_mm=0.0, keyway_depth_mm=0.0)
            if big:
                _grow(cam, kind, value / 2 + 10.0)
        if name == "keyway_width_mm":
            cam.update(bore_diameter_mm=max(cam.get("bore_diameter_mm", 0.0), 20.0), keyway_depth_mm=2.0 if value else 0.0)
        if name == "keyway_depth_mm":
            cam.update(bore_diameter_mm=20.0, keyway_width_mm=6.0 if value else 0.0)
            if big:
                _grow(cam, kind, value + 20.0)
        if name == "follower_offset_mm" and big:
            if kind == "three_arc":
                cam.update(a_mm=1e5, b_mm=1e5, c_mm=1e5, roller_radius_mm=1e3, bore_diameter_mm=0.0, keyway_width_mm=0.0, keyway_depth_mm=0.0)
            else:
                cam.update(base_radius_mm=1e5, bore_diameter_mm=0.0)
        if name in ("pivot_x_mm", "pivot_y_mm", "arm_length_mm") and oscillating and kind in ("motion_law", "lift_table") and (big or value < 1):
            reach = abs(value)
            if name == "arm_length_mm":
                cam.update(pivot_x_mm=value, pivot_y_mm=0.0, base_radius_mm=40.0) if big else cam.update(
                    pivot_x_mm=48.0 + value / 2, pivot_y_mm=0.0, roller_radius_mm=8.0)  # the arm's circle grazes the prime circle
                reach = value if big else 8e4  # a tiny arm: a tiny swing
            else:
                other = "pivot_y_mm" if name == "pivot_x_mm" else "pivot_x_mm"
                cam[other] = 0.0
                cam["arm_length_mm"] = reach
            _scale_swing(cam, kind, 80.0 / max(reach, 1e-6) if reach > 80 else 1.0)
        if name in ("pivot_x_mm", "pivot_y_mm", "arm_length_mm") and kind == "three_arc":
            if value < 1 and name == "arm_length_mm":  # a cam of 1e-6 mm: pitch radii 2e-6 .. 2.002e-6 mm, the pivot 2e-6 mm from the axis
                cam.update(a_mm=1e-6, b_mm=1.998e-6, c_mm=1e-6, roller_radius_mm=1e-6, pivot_x_mm=2e-6, pivot_y_mm=0.0,
                           arm_length_mm=1e-6, bore_diameter_mm=0.0, keyway_width_mm=0.0, keyway_depth_mm=0.0)
            elif name == "arm_length_mm":  # the pivot far away: its arm's circle passes 20 mm from the axis, inside the smallest pitch radius 35
                cam.update(pivot_x_mm=value - 20.0, pivot_y_mm=0.0, arm_length_mm=value)
            else:  # the pivot at the edge value on its axis, the other coordinate 0: the arm's circle passes 20 mm from the cam axis
                cam.update({name: value, ("pivot_y_mm" if name == "pivot_x_mm" else "pivot_x_mm"): 0.0, "arm_length_mm": abs(value) - 20.0})
        if kind == "trajectory" and name in ("half_track_mm", "lever_mm", "wheelbase_mm", "period_mm"):
            # a gentle path (right-turn radius 1e6 / (A pi^2) for y = A sin(pi x / 1000)), not the paper's: no fits
            cam.pop("fit_tables", None), cam.pop("worm_teeth", None)
            period = value if name == "period_mm" else 2000.0
            amplitude = period**2 / (4 * math.pi**2 * 1e7)  # right-turn radius 1e7 mm
            cam.update(expression=f"{amplitude!r}*sin(2*pi*x/{period!r})", period_mm=period)
        if name == "face_offset_mm" and big:  # the pivot 1.41e5 mm away: |face offset + base radius| < its distance
            cam.update(pivot_x_mm=1e5, pivot_y_mm=1e5, base_radius_mm=45.0)
            _scale_swing(cam, kind, 100.0 / 1.4e5)
        if name == "roller_radius_mm" and big:
            _grow(cam, kind, value + 100.0)
        if name == "base_radius_mm" and value < 1.0:
            cam["roller_radius_mm"] = min(cam.get("roller_radius_mm", 10.0), 10.0)
    formats = ["dxf", "points", "lift", "ngc", "follower"] if where == "cams.x" else ["dxf", "points", "lift", "ngc"]
    if where not in ("mechanisms.horse_leg", "mechanisms.machine"):  # a machine's cams turn at its speed
        for other in scene["cams"].values():
            other["rpm"] = other.get("rpm", 100.0)
    size = _size(scene) if "x" in cams else 500.0
    if cam is not None and cam["kind"] == "three_arc":
        size = 2 * cam["a_mm"] + cam["c_mm"]
    output = scene["output"]
    output["chord_tol_mm"] = min(max(size * 2e-6, 1e-7), 1.0) if where != "output" or name != "chord_tol_mm" else value
    machining = scene.setdefault("machining", {"tool_diameter_mm": 6.0})
    machining.setdefault("decimals", 6)  # printed coordinates resolve a quarter of chord tolerances down to 8.5e-6 mm
    thickness = cam.get("thickness_mm", 10.0) if cam is not None else 10.0
    if where == "cams.x" and name == "thickness_mm":
        thickness = value
    machining.setdefault("step_down_mm", max(2.0, thickness / 500.0))
    if output["chord_tol_mm"] < 8.5e-6 or size < 1e-2:  # G-code cannot resolve it (README, "Limits")
        formats.remove("ngc")
        del scene["machining"]
    if where == "machining" and name == "lead_mm" and value < 1:
        machining["tool_diameter_mm"] = value  # the lead must exceed the tool radius (export/gcode.py)
    if where == "machining" and name == "decimals":
        output["chord_tol_mm"] = 0.01  # 3 printed decimals resolve a quarter of 0.01 mm
    if where == "machining" and key.requires.get("dialect") == ("wire_edm",):  # WIRE EDM: its dialect refuses the milling keys
        for milling in ("tool_diameter_mm", "step_down_mm"):
            machining.pop(milling, None)
        machining.update(start_hole_offset_mm=50.0, start_hole_diameter_mm=1.0)  # room for any hole and allowance
        if name == "cut_allowances_mm" and isinstance(value, list):
            machining["skim_cuts"] = len(value)
    if where == "machining" and name.startswith("holding_tab_"):  # a tab's size needs a tab
        machining["holding_tabs"] = 1
    if where in ("machining",) and "ngc" not in formats:
        formats.append("ngc")
    if where == "output" and "fea" in key.affects:  # an FEA key needs an FEA mesh; a coarse tolerance keeps it small
        formats.append("msh")
        output["chord_tol_mm"] = 0.05
    if where == "output" and "drawing" in key.affects:  # the drawing's keys need its formats
        formats += ["drawing", "drawing_pdf", "inspection"]
    output["formats"] = formats
    output.pop("lift_step_deg", None) if "lift" not in formats else None
    table[name] = value
    return scene, formats


def _grow(cam: dict, kind: str | None, radius: float) -> None:
    """Make the cam's smallest radius at least ``radius`` (mm), for a large body feature."""
    if kind == "trajectory":
        return  # its size follows from the device
    if kind == "three_arc":
        c = _clip(radius)
        cam.update(c_mm=c, a_mm=_clip(max(cam["a_mm"], 2 * c)), b_mm=_clip(max(cam["a_mm"], 2 * c)) * 0.8)
    else:
        cam["base_radius_mm"] = _clip(max(cam.get("base_radius_mm", 40.0), radius))


def _scale_swing(cam: dict, kind: str | None, factor: float) -> None:
    """The oscillating follower's swing times ``factor`` (a long arm swings less for the same travel)."""
    if kind == "motion_law":
        cam["segments"] = _swing_segments(10.0 * factor)
    else:
        cam["lift_table_csv"] = f"swing:{factor!r}"


#: Edge values refused today by files this test's owner may not edit (the fix in each reason):
#: strict, so the day one is fixed its entry must go.
EDGE_BUGS: dict[str, str] = {}
#: Edge values no scene can use, refused as README.md's "Limits" or the key's own text documents
#: (a combination with another key): the phrase of the documented refusal (the test checks the
#: error is that one, naming the key).
EDGE_DOCUMENTED: dict[str, str] = {
    # "a G-code program holds at most 1,000 depth passes (the error gives the least machining.step_down_mm)"
    "machining.step_down_mm=4.94066e-324": "more than the 1000 a program may hold",
    # keyway_width_mm: "(< bore_diameter_mm)"; the edge scenes' bore is 20 mm
    **{f"cams.x.keyway_width_mm=10000-{kind}": "keyway_width < bore_diameter" for kind in ("three_arc", "trajectory", "motion_law",
                                                                                        "lift_table")},
    # wheelbase_mm: "> rod_radius_mm"; rod_radius_mm: "< wheelbase_mm"
    "cams.x.wheelbase_mm=1e-06-trajectory": "r_b = L - r_d must be > 0",
    "cams.x.rod_radius_mm=100000-trajectory": "r_b = L - r_d must be > 0",
    # "the error gives ... the smallest output.fea_element_size_mm where no tolerance does" (README, Limits)
    "output.fea_element_size_mm=1e-06": "output.fea_element_size_mm",
    # ground_y_mm: "the foot path must cross it twice at every inclination ... (the error gives the band)"
    "mechanisms.horse_leg.ground_y_mm=-100000": "a ground line the foot path crosses twice",
    "mechanisms.horse_leg.ground_y_mm=100000": "a ground line the foot path crosses twice",
    # bore_tool_diameter_mm: "at most the bore diameter - 0.2 mm"; the edge scenes' bore is 20 mm
    "machining.bore_tool_diameter_mm=1000": "bore diameter - 0.2",
    # bore_tool_number: "needs bore_tool_diameter_mm or bore_operation = "drill""
    **{f"machining.bore_tool_number={n}": "only with bore_tool_diameter_mm" for n in (1, 99)},
    # holding_tabs: "as many as fit: each tab's width, a tool radius on both sides and a tool diameter of full cut between two"
    "machining.holding_tabs=100": "do not fit on the",
    # the wire-EDM bore (cut by the wire in the edge scenes' 20 mm bore): start_hole_diameter_mm "below the bore radius",
    # tab_width_mm "shorter than the bore wall from the keyway to the start point"
    "machining.start_hole_diameter_mm=20": "< bore diameter / 2",
    "machining.tab_width_mm=100": "for the bore",
    # holding_tab_height_mm: "below the stock thickness"
    "machining.holding_tab_height_mm=1000": "< the stock thickness",
}


def _edge_cases():
    cases = []
    groups = [("cams.x", kind, get_kind(kind).keys) for kind in ("three_arc", "trajectory", "motion_law", "lift_table")]
    groups += [("output", None, output_keys()), ("machining", None, machining_keys())]
    groups += [(f"mechanisms.{j}", "leg", get_job(j).keys) for j in job_names()]
    for where, kind, keys in groups:
        for key in keys:
            for value in _edges(key):
                scene, formats = _edge_scene(where, kind, key, value)
                label = f"{where}.{key.name}={value:g}" + (f"-{kind}" if where == "cams.x" else "")
                marks = [pytest.mark.xfail(strict=True, reason=EDGE_BUGS[label])] if label in EDGE_BUGS else []
                cases.append(pytest.param(scene, formats, key.name, value, EDGE_DOCUMENTED.get(label), id=label, marks=marks))
    return cases


EDGE_CASES = _edge_cases()


def _read_numbers(path) -> "np.ndarray":
    """The numeric rows of a camgen CSV (comment lines and the header row skipped), read by numpy."""
    import numpy as np

    lines = [line for line in path.read_text().splitlines() if line and not line.startswith("#")]
    return np.loadtxt(lines[1:], delimiter=",", ndmin=2)


def test_edge_exceptions_are_edge_cases():
    labels = {case.id for case in EDGE_CASES}
    assert set(EDGE_BUGS) <= labels and set(EDGE_DOCUMENTED) <= labels


@pytest.mark.parametrize("scene, formats, key, value, documented", EDGE_CASES)
def test_valid_edge_value_is_accepted_and_written_right(scene, formats, key, value, documented, tmp_path, capsys):
    import numpy as np

    scene = copy.deepcopy(scene)
    for table in scene["cams"].values():  # an oscillating lift table: the template's lifts as swings, scaled
        if str(table.get("lift_table_csv", "")).startswith("swing:"):
            factor = float(table["lift_table_csv"].split(":", 1)[1])
            (tmp_path / "swing.csv").write_text(_csv([(a, lift * factor) for a, lift in _LIFT_ROWS]))
            table["lift_table_csv"] = str(tmp_path / "swing.csv")
    path = tmp_path / "scene.toml"
    path.write_text(toml_scene(scene), encoding="utf-8")
    status = main(["run", str(path), "-q", "-o", str(tmp_path / "out")])
    err = capsys.readouterr().err
    if documented is not None:  # a documented limit of the whole scene: its one-line refusal naming the key
        assert status == 2 and err.count("\n") == 1 and key in err and documented in err, err
        assert not (tmp_path / "out").exists()
        CASE_COUNTS[("edge_value", "refused as documented")] += 1
        return
    assert status in (0, 1), f"a valid value refused: {err}"  # a refusal of a valid value is a failure
    assert "Traceback" not in err and "Warning" not in err
    folder = tmp_path / "out" / "fuzz"
    report = json.loads((folder / "report.json").read_text(), parse_constant=lambda c: pytest.fail(f"report.json holds {c}"))
    assert report["status"] == ("pass" if status == 0 else "fail")
    written = sorted(p.name for p in folder.iterdir())
    assert written == sorted(report["files"])
    for name, cam in report["cams"].items():
        for fmt in formats:
            file = {"dxf": f"{name}.dxf", "points": f"{name}_points.csv", "lift": f"{name}_lift.csv", "ngc": f"{name}.ngc",
                    "follower": f"{name}_follower.csv", "msh": f"{name}.msh", "drawing": f"{name}_drawing.svg",
                    "drawing_pdf": f"{name}_drawing.pdf", "inspection": f"{name}_inspection.csv"}[fmt]
            if file not in written:  # withheld: the cam cannot be made, and a failed check says so
                assert file in cam["withheld_files"] and not cam["manufacturable"], file
                assert any(c["status"] == "fail" and c["blocks_manufacture"] for c in cam["checks"]), file
    for file in folder.iterdir():
        data = file.read_bytes()
        assert not _NONFINITE.search(data), (file.name, _NONFINITE.search(data))
        if file.suffix == ".csv":
            assert np.all(np.isfinite(_read_numbers(file)))
    if "x_points.csv" in written:  # the flattened profile against the exact area (chord error: at most perimeter x tol)
        xy = _read_numbers(folder / "x_points.csv")
        shoelace = 0.5 * abs(np.dot(xy[:, 0], np.roll(xy[:, 1], -1)) - np.dot(xy[:, 1], np.roll(xy[:, 0], -1)))
        figures = report["cams"]["x"]["figures"]
        if "area_mm2" in figures:
            assert abs(shoelace - figures["area_mm2"]) <= figures["perimeter_mm"] * report["chord_tol_mm"] * (1 + 1e-9) + 1e-12 * figures["area_mm2"]
    figures = report["cams"].get("x", {}).get("figures", {})
    if key in figures and isinstance(figures[key], (int, float)):  # the report states the value given
        assert figures[key] == pytest.approx(value, rel=1e-12, abs=0.0)
    CASE_COUNTS[("edge_value", "ran" if status == 0 else "ran, a check failed")] += 1
