"""README.md says what the installed program does: its examples parse, its tables list what the
registries hold, and its plate-cam example is the bundled template.

README.md is not part of the installed package: these tests read it in the checkout beside them.
"""
from __future__ import annotations

import re
import tomllib

import pytest

from camgen.cli import build_parser
from camgen.errors import CamgenError
from camgen.outputs import OUTPUTS
from camgen.scene import load_template, parse_scene, template_names, template_path
from helpers import tree  # noqa: F401  (fixture)


def _readme(tree) -> str:
    return (tree / "README.md").read_text(encoding="utf-8")


def _blocks(text: str, language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", text, re.S)


def _section(text: str, title: str) -> str:
    match = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert match, f"README.md has no section '## {title}'"
    return match.group(1)


def test_the_first_block_is_the_two_commands_ci_runs(tree):
    first = _blocks(_readme(tree), "sh")[0].strip().splitlines()
    assert first == ['python3 -m pip install . && camgen run',
                     'python3 -m pip install ".[test]" && python3 -P -m pytest -q -n auto tests']


CAM_KEYS_MARK = "# keys of a cam table"


def test_every_toml_example_is_a_valid_scene(tree):
    """Whole scenes parse; a fragment marked as keys of a cam table parses inside the plate cam's table."""
    examples = _blocks(_readme(tree), "toml")
    assert len(examples) >= 3
    for number, text in enumerate(examples):
        data = tomllib.loads(text)
        if text.startswith(CAM_KEYS_MARK):
            scene_data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
            scene_data["cams"]["plate"].update(data)
            data = scene_data
        try:
            scene = parse_scene(data, name=f"readme_{number}")
        except CamgenError as error:  # pragma: no cover - the message is the diagnosis
            pytest.fail(f"README toml example {number} is refused: {error}")
        assert scene.cams


def test_the_plate_cam_example_is_the_template(tree):
    example = next(t for t in _blocks(_readme(tree), "toml") if "[cams.plate]" in t)
    assert tomllib.loads(example) == tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))


def test_the_outputs_table_lists_every_registered_format(tree):
    table = _section(_readme(tree), "Outputs")
    first_column = " ".join(row.split("|")[1] for row in table.splitlines() if row.startswith("| "))
    named = set(re.findall(r"`([a-z0-9_]+)`", first_column))
    listed = {name for name, fmt in OUTPUTS.items() if not fmt.implied}
    assert listed - named == set(), "formats missing from README's Outputs table"
    assert named - set(OUTPUTS) == set(), "README lists formats camgen does not have"
    for fmt in OUTPUTS.values():
        if not fmt.implied:
            assert fmt.files.replace("{cam}", "<cam>") in table, fmt.files


def test_every_template_and_command_is_named(tree):
    text = _readme(tree)
    scenes = _section(text, "Scene files")
    assert [name for name in template_names() if f"`{name}`" not in scenes] == []
    parser = build_parser()
    commands = next(a for a in parser._subparsers._group_actions).choices  # noqa: SLF001
    usage = _section(text, "Command line and exit status")
    assert [name for name in commands if f"camgen {name}" not in usage] == []
    for status in ("| 0 |", "| 1 |", "| 2 |"):
        assert status in usage


def test_the_plate_cam_figures_quoted_are_the_programs(tree):
    """The README quotes the plate cam's pressure angle and pitch radius: they must be current."""
    from camgen.pipeline import Plan, compute

    text = _section(_readme(tree), "Example: a plate cam")
    quoted_angle = float(re.search(r"pressure angle ([0-9.]+) deg", text).group(1))
    quoted_radius = float(re.search(r"pitch curve ([0-9.]+) mm", text).group(1))
    result = compute(load_template("plate_cam"), Plan((), frozenset(), full_report=False))
    checks = {c.name: c for cam in result.cams for c in cam.checks}
    assert abs(checks["pressure_angle"].value - quoted_angle) < 0.01
    assert abs(checks["undercut"].value - quoted_radius) < 0.1  # smallest convex pitch radius


def test_the_limits_quoted_are_the_codes(tree):
    """The README's Limits section quotes camgen's caps and tolerances: each must be the value the
    code enforces (the behaviour at each limit is tested in test_limits.py and its neighbours)."""
    from camgen.export.gcode import MAX_PASSES, MAX_PROGRAM_MOVES, MIN_GCODE_CHORD_TOL
    from camgen.export.solid import MANIFOLD_SNAP
    from camgen.export.step import FOLD_TOL
    from camgen.kinds.base import MIN_RPM
    from camgen.motions.trajectory import MAX_SAMPLES
    from camgen.mechanisms.tricycle_fit import FIT_MAX_CONDITION
    from camgen.planning import MAX_FLAT_POINTS
    from camgen.synthesis import trajectory

    def short(x: float) -> str:  # 8.5e-6, 1e6: as written by hand
        return f"{x:.2g}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")

    text = " ".join(_section(_readme(tree), "Limits").split())
    quoted = {
        f"at most {MAX_FLAT_POINTS:,} vertices": True,
        f"at most {MAX_PASSES:,} depth passes and {MAX_PROGRAM_MOVES:,} moves": True,
        f">= {short(MIN_GCODE_CHORD_TOL)} mm": True,
        f"at most {trajectory.MAX_ROWS:,} rows and {trajectory.MAX_TABLE_BYTES >> 20} MiB": True,
        f"`samples` 16 to {MAX_SAMPLES:,}": True,
        f"shorter than {short(FOLD_TOL)} mm": True,
        f"`rpm >= {short(MIN_RPM)}`": True,
        f"exceeds {short(FIT_MAX_CONDITION)}": True,
        f"at most {short(MANIFOLD_SNAP)} mm off": True,
    }
    assert [phrase for phrase in quoted if phrase not in text] == []
