"""One map from internal parameter names back to scene keys (issue 22, item 5): the schema's keys.

A spec built from a scene table validates its parameters and names them as it knows them
(``offset``, ``bore_diameter``, ``spring_rate``); the error line must name the scene key.  Every
name a spec's :class:`~camgen.errors.ParameterError` can carry is read from the spec's own
source (its ``ParameterError(...)``, ``require_*``/``_choice`` calls, with the names of the
loops they run in), mapped by :func:`camgen.keynames.scene_key` over the keys the scene reader
hands that spec, and looked up in ``docs/scene-keys.md``: the independent list of keys
``camgen keys`` prints, parsed here from its index.  Then scenes that only a spec (not the
schema's ranges) can refuse, run by ``camgen run``, must name exactly the key at fault; the
generated bad-input corpus (tests/test_bad_input.py) covers the schema's own refusals, and
tests/test_disk_scenes.py and tests/test_dynamics_scenes.py the follower's and the train's.
"""
from __future__ import annotations

import ast
import inspect
import re
import textwrap
from pathlib import Path

import pytest

from camgen.cli import main

CHECKOUT = Path(__file__).resolve().parents[1]


def documented_keys() -> dict[str, set[str]]:
    """Section -> its keys, from the index at the head of docs/scene-keys.md (the
    ``[[cams.<name>.segments]]`` tables as section "segments")."""
    text = (CHECKOUT / "docs" / "scene-keys.md").read_text(encoding="utf-8")
    out: dict[str, set[str]] = {}
    for line in text.split("\n## ")[0].splitlines():  # the index, before the first section
        section = re.search(r"\(section (\w+)\)", line)
        sub = re.search(r"each `\[\[cams\.<name>\.(\w+)\]\]`", line)
        name = section.group(1) if section else sub.group(1) if sub else None
        if name is not None:
            out[name] = set(re.findall(r"`([a-z0-9_]+)`", line.split(":", 1)[1]))
    return out


#: Functions whose first argument is the parameter name a ParameterError will carry.
_NAMING = {"ParameterError", "require_finite", "require_positive", "_nonnegative", "_choice", "_name"}


def error_names(*objects) -> set[str]:
    """Every parameter name the ParameterErrors raised in ``objects`` (functions, classes) can
    carry: string constants given to :data:`_NAMING` calls, and for a loop variable the strings
    of the tuple the loop runs over."""
    names: set[str] = set()
    for obj in objects:
        tree = ast.parse(textwrap.dedent(inspect.getsource(obj)))
        loops: dict[str, set[str]] = {}
        for node in ast.walk(tree):
            if isinstance(node, ast.For) and isinstance(node.iter, ast.Tuple):
                targets = node.target.elts if isinstance(node.target, ast.Tuple) else [node.target]
                for i, target in enumerate(targets):
                    if isinstance(target, ast.Name):
                        items = [e.elts[i] if isinstance(e, ast.Tuple) else e for e in node.iter.elts]
                        loops.setdefault(target.id, set()).update(
                            e.value for e in items if isinstance(e, ast.Constant) and isinstance(e.value, str))
        for node in ast.walk(tree):
            if not isinstance(node, ast.Call) or not node.args:
                continue
            func = node.func.id if isinstance(node.func, ast.Name) else node.func.attr if isinstance(node.func, ast.Attribute) else ""
            if func not in _NAMING:
                continue
            first = node.args[0]
            if isinstance(first, ast.Constant) and isinstance(first.value, str):
                names.add(first.value)
            elif isinstance(first, ast.Name) and first.id in loops:
                names |= loops[first.id]
    return names


def _specs():
    """(what, the spec's validating code, the key tables the reader hands it (each must name
    every parameter: one table per follower motion), the doc sections each name must be a key of ("a|b": of either), names no
    scene value reaches: the reader passes them from elsewhere)."""
    from camgen import dynamics as dy
    from camgen.body import BodySpec
    from camgen.checks import Follower
    from camgen.export import gcode
    from camgen.kinds import disk
    from camgen.kinds.base import body_keys
    from camgen.kinds.dynamics import dynamics_keys
    from camgen.mechanisms.tricycle import Tricycle
    from camgen.motions import motion_law, three_arc, trajectory
    from camgen.outputs import machining_keys, output_keys
    from camgen.synthesis import followers, laws
    from camgen.synthesis import trajectory as tr
    from camgen.synthesis.three_arc import validate_three_arc

    def by_motion(motion):
        return tuple(k for k in dynamics_keys() if motion in k.requires.get("follower_motion", (motion,)))

    disk_sections = ("lift_table", "motion_law")
    return [
        ("FollowerSpec", (followers.FollowerSpec, followers._choice), [disk.follower_keys()], disk_sections, set()),
        ("BodySpec", (BodySpec,), [body_keys()], disk_sections + ("three_arc", "trajectory"), set()),
        # closure: from the follower kind; arm_length: from the follower geometry (the stage); an arm's keys are refused
        # for a slider and a slider's spring lengths for an arm by the schema (the reader passes 0 or None)
        ("FollowerTrain (translating)", (dy.FollowerTrain, dy._nonnegative), [by_motion("translating")], disk_sections,
         {"closure", "arm_length", "inertia", "cg_distance"}),
        ("FollowerTrain (oscillating)", (dy.FollowerTrain, dy._nonnegative), [by_motion("oscillating")], disk_sections,
         {"closure", "arm_length", "spring_free_length", "spring_installed_length"}),
        ("ContactMaterial", (dy.ContactMaterial,), [dynamics_keys()], disk_sections + ("three_arc",), set()),
        ("MachiningSpec", (gcode.MachiningSpec, gcode._refuse_long_program), [machining_keys() + output_keys()],
         ("machining|output",), {"thickness"}),  # the cam's thickness_mm, validated by its body
        ("Follower (three_arc)", (Follower,), [three_arc.KEYS], ("three_arc",), set()),
        ("validate_three_arc", (validate_three_arc,), [three_arc.KEYS], ("three_arc",), set()),
        ("Tricycle", (Tricycle,), [trajectory.KEYS], ("trajectory",), set()),
        ("the expression's path", (tr.trajectory_from_expression, tr._check_periodic),
         [tuple(k for k in trajectory.KEYS if k.name != "trajectory_csv")], ("trajectory",), set()),
        ("the table's path", (tr.read_trajectory_csv, tr.trajectory_from_table, tr._check_periodic),
         [tuple(k for k in trajectory.KEYS if k.name != "expression")], ("trajectory",), set()),
        ("Segment", (laws.Segment,), [tuple(k for k in motion_law.SEGMENT_KEYS if k.name != "swing_deg"),
                                      tuple(k for k in motion_law.SEGMENT_KEYS if k.name != "lift_mm")], ("segments",),
         {"ends"}),  # a velocity_blend's ends: MotionProgram gives them from its neighbours, no scene key
    ]


@pytest.mark.parametrize("what, code, tables, sections, elsewhere", _specs(), ids=[s[0] for s in _specs()])
def test_every_name_a_spec_can_raise_maps_to_a_documented_key(what, code, tables, sections, elsewhere):
    from camgen.keynames import scene_key

    documented = documented_keys()
    names = error_names(*code) - elsewhere
    assert names, f"no ParameterError names found in {what}: the source walk is broken"
    for name in sorted(names):
        mapped = {scene_key(keys, name) for keys in tables}
        for section in sections:  # "a|b": a key of either table
            keys = set().union(*(documented[s] for s in section.split("|")))
            bad = [m for m in mapped if not all(part in keys for part in m.split("/"))]
            assert not bad, f"{what}: a ParameterError naming {name!r} becomes {bad}, no key of [{section}] in docs/scene-keys.md"


def test_the_source_walk_finds_the_names_it_should():
    """The walk is checked on known code: FollowerSpec's choices, a loop of BodySpec's names."""
    from camgen.body import BodySpec
    from camgen.synthesis import followers

    assert {"kind", "motion", "lift_turn", "rotation", "pivot", "offset"} <= error_names(followers.FollowerSpec)
    assert {"bore_diameter", "keyway_width", "keyway_depth", "min_wall", "thickness", "keyway_angle"} <= error_names(BodySpec)


def test_two_keys_feeding_one_parameter_are_named_together_and_an_unknown_name_stays():
    from camgen.keynames import scene_key
    from camgen.kinds.disk import follower_keys

    assert scene_key(follower_keys(), "pivot") == "pivot_x_mm/pivot_y_mm"
    assert scene_key(follower_keys(), "lift_turn") == "swing_turn"
    assert scene_key(follower_keys(), "no_such_parameter") == "no_such_parameter"


# --------------------------------------------------------------------------------------------
# Refusals only a spec makes: the error line names exactly the key at fault
# --------------------------------------------------------------------------------------------
_PLATE = """[cams.c]
kind = "motion_law"
base_radius_mm = 40.0
roller_radius_mm = 10.0
[[cams.c.segments]]
law = "cycloidal"
span_deg = 120.0
lift_mm = 15.0
[[cams.c.segments]]
law = "dwell"
span_deg = 60.0
[[cams.c.segments]]
law = "cycloidal"
span_deg = 120.0
lift_mm = -15.0
[[cams.c.segments]]
law = "dwell"
span_deg = 60.0
"""
_NGC = '[output]\nformats = ["ngc"]\n'
_TRICYCLE = '[cams.c]\nkind = "trajectory"\nexpression = "10 * sin(2 * pi * x / 400)"\nperiod_mm = 400.0\n'

REFUSED = {
    # case: (scene text, --only, the key named, a word of why)
    "lead inside the tool": (_NGC + "[machining]\ntool_diameter_mm = 6.0\nlead_mm = 2.0\n" + _PLATE, None, "machining.lead_mm",
                             "lead > tool radius"),
    "compensation on GRBL": (_NGC + '[machining]\ndialect = "grbl"\ncutter_compensation = true\n' + _PLATE, None,
                             "machining.cutter_compensation", "GRBL has no G41"),
    "decimals too coarse for the tolerance": ('[output]\nformats = ["ngc"]\nchord_tol_mm = 1e-4\n[machining]\ndecimals = 3\n' + _PLATE,
                                              None, "machining.decimals", "an integer 5..6"),
    "decimals too coarse, ngc by --only": ('[output]\nchord_tol_mm = 1e-4\n' + _PLATE, ["ngc"], "machining.decimals", "an integer 5..6"),
    "tolerance too fine for G-code, ngc by --only": ('[output]\nchord_tol_mm = 1e-6\n' + _PLATE, ["ngc"], "output.chord_tol_mm",
                                                     "machining.decimals = 6"),
    "too many passes, ngc by --only": (_PLATE.replace("roller_radius_mm = 10.0", "roller_radius_mm = 10.0\nthickness_mm = 2500.0"),
                                       ["ngc"], "machining.step_down_mm", "1251 passes"),
    "rod as long as the wheelbase": (_TRICYCLE + "wheelbase_mm = 20.0\nrod_radius_mm = 20.0\n", None, "cams.c.rod_radius_mm",
                                     "r_b = L - r_d"),
}


@pytest.mark.parametrize("case", REFUSED)
def test_a_refusal_of_a_spec_names_exactly_the_key(case, tmp_path, capsys):
    text, only, key, why = REFUSED[case]
    path = tmp_path / "bad.toml"
    path.write_text(text)
    args = ["run", str(path), "-o", str(tmp_path / "out")] + (["--only", ",".join(only)] if only else [])
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert re.search(r"parameter '([^']+)'", err).group(1) == key, err
    assert why in err, err
    assert not (tmp_path / "out").exists()
