"""What a sweep reuses from one design to the next (issue 28 item 6) gives each design the answer
a fresh ``camgen check`` of its own scene gives.

* The base-radius advice of a failing design (``min_base_radius``: a search over trial base
  radii) is kept for the next designs (:mod:`camgen.synthesis.advice_cache`): asked again with
  an equal law (the same object, or the law of another parse of the same segments) and another
  base radius it is taken from the cache (the cache's hit count says so), and it is the value
  ``camgen check`` prints for that design's scene, run as a program (a fresh process: nothing
  kept); a follower that differs in another parameter (the roller radius) is searched again and
  gets its own scene's value.
* Rows of :func:`camgen.study.design.evaluate_point` made one after the other with the base
  radius (the advice reused), the roller, the lifts (another law: searched again) and the spring
  changing, the same design twice, each equal to ``camgen check`` of its own scene (every
  check's status and printed value).
"""
from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

from camgen.scene import parse_scene, template_path
from camgen.scene_edit import edit_scene_text
from camgen.study.design import StudyScene, evaluate_point, point_scene_data
from camgen.study.keys import resolve_key

PLATE = template_path("plate_cam")

#: The designs, in the order they are evaluated: scene key -> value (the template's plate cam otherwise).
DESIGNS = {
    "base20": {"base_radius_mm": 20.0},  # the pressure angle fails: the advice is searched
    "base24": {"base_radius_mm": 24.0},  # the same law: the advice is reused
    "base24_roller6": {"base_radius_mm": 24.0, "roller_radius_mm": 6.0},  # another follower: searched again
    "base20_lift26": {"base_radius_mm": 20.0, "cams.plate.segments[0].lift_mm": 26.0, "cams.plate.segments[2].lift_mm": -26.0},  # another law
    "weak_spring_fast": {"spring_preload_n": 2.0, "rpm": 700.0},  # the jump check fails: its spring hints
    "base20_again": {"base_radius_mm": 20.0},
}


@pytest.fixture(scope="module")
def study() -> StudyScene:
    return StudyScene.load(str(PLATE))


def _values(study: StudyScene, change: dict[str, float]) -> tuple[list, list[float]]:
    keys = [resolve_key(study.data, name) for name in change]
    return keys, list(change.values())


@pytest.fixture(scope="module")
def checked(study, tmp_path_factory) -> dict[str, tuple[int, dict[str, tuple[str, str]]]]:
    """``camgen check`` of every design's scene, as programs (run side by side): exit status and
    check -> (result, printed value)."""
    folder = tmp_path_factory.mktemp("designs")
    procs = {}
    for name, change in DESIGNS.items():
        keys, values = _values(study, change)
        scene = folder / f"{name}.toml"
        scene.write_text(edit_scene_text(study.text, point_scene_data(study.data, {k.path: v for k, v in zip(keys, values)})),
                         encoding="utf-8")
        procs[name] = subprocess.Popen([sys.executable, "-m", "camgen", "check", str(scene)], stdout=subprocess.PIPE,
                                       stderr=subprocess.PIPE, text=True)
    out = {}
    for name, proc in procs.items():
        stdout, _ = proc.communicate(timeout=300)
        table = {}
        for line in stdout.splitlines()[1:]:
            cells = line.split()
            if len(cells) >= 4 and cells[0] == "plate" and cells[2] in ("pass", "FAIL", "info"):
                table[cells[1]] = (cells[2].lower(), cells[3].rstrip(","))
        out[name] = (proc.returncode, table)
    return out


def test_rows_in_a_row_equal_camgen_check_of_each_scene(study, checked):
    from camgen.synthesis import advice_cache

    advice_cache._outcome.cache_clear()  # nothing kept from another test
    seen, hits = set(), {}
    for name, change in DESIGNS.items():
        keys, values = _values(study, change)
        before = advice_cache._outcome.cache_info().hits
        row = evaluate_point(study, keys, values)
        hits[name] = advice_cache._outcome.cache_info().hits - before
        status, table = checked[name]
        assert status == (1 if row["status"] == "fail" else 0), name
        for check, (result, shown) in table.items():
            if check.endswith("_export"):
                continue
            assert row[f"check.plate.{check}.status"] == result, (name, check)
            value = row[f"check.plate.{check}"]
            if value is not None:  # the table prints 6 significant digits
                assert float(shown) == float(f"{value:.6g}"), (name, check, value, shown)
            seen.add((check, result))
    # the sample reaches what it is for: the advice searched, reused and searched again, the jump failing
    assert ("min_base_radius", "info") in seen and ("jump", "fail") in seen and ("pressure_angle", "fail") in seen
    assert hits["base24"] == 1 and hits["base24_roller6"] == 0 and hits["base20_lift26"] == 0 and hits["base20_again"] == 1


def test_advice_kept_for_the_same_law_and_searched_again_for_another_follower(study, checked):
    from camgen.kinds.disk import pressure_limit
    from camgen.kinds.disk_margins import design_limits
    from camgen.synthesis import advice_cache
    from camgen.synthesis.sizing import DesignLimits, base_radius_advice

    def design(name: str):
        keys, values = _values(study, DESIGNS[name])
        scene = parse_scene(point_scene_data(study.data, {k.path: v for k, v in zip(keys, values)}), study.name, study.source,
                            study.base_dir)
        (spec,) = scene.cams
        tool = scene.machining.tool_radius if spec.checks.tool_is_limit else 0.0
        limits = design_limits(spec, DesignLimits(max_pressure_angle=pressure_limit(spec), min_concave_radius=tool))
        return spec.params.follower, spec.params.law, limits

    advice_cache._outcome.cache_clear()  # nothing kept from another test
    follower, law, limits = design("base20")  # this law object is given to every follower below
    first = base_radius_advice(follower, law, limits)
    printed = {name: float(checked[name][1]["min_base_radius"][1]) for name in ("base20", "base24", "base24_roller6")}
    assert first.low == printed["base20"]
    hits = advice_cache._outcome.cache_info().hits
    follower, _, limits = design("base24")
    kept = base_radius_advice(follower, law, limits)
    assert advice_cache._outcome.cache_info().hits == hits + 1  # reused, not searched
    assert kept.low == printed["base24"]
    from camgen.motions.motion_law import _cached_law

    _cached_law.cache_clear()  # a fresh program: the scene reader keeps its last ones (camgen.motions.motion_law)
    follower, own_law, limits = design("base24")  # the law of another parse: equal segments
    assert own_law is not law
    assert base_radius_advice(follower, own_law, limits).low == printed["base24"]
    assert advice_cache._outcome.cache_info().hits == hits + 2
    follower, _, limits = design("base24_roller6")
    other = base_radius_advice(follower, law, limits)
    assert advice_cache._outcome.cache_info().hits == hits + 2  # another roller: searched
    assert other.low == printed["base24_roller6"] != printed["base24"]


def test_a_follower_registered_again_with_another_contact_is_searched_again():
    """The search reads the follower's contact (point or face) and whether it has a radius, which
    a FollowerSpec takes from the follower registry: a follower registered again under the same
    name with another contact is another search (its answer the uncached search's), not the
    kept answer of the first."""
    from camgen.followers import FollowerKind, register, unregister
    from camgen.synthesis import advice_cache, sizing
    from camgen.synthesis.followers import FollowerSpec
    from camgen.synthesis.laws import MotionProgram, Segment

    law = MotionProgram([Segment("cycloidal", math.radians(120), 20.0), Segment("dwell", math.radians(60)),
                         Segment("poly345", math.radians(120), -20.0), Segment("dwell", math.radians(60))])
    limits = sizing.DesignLimits(max_pressure_angle=math.radians(30.0), min_convex_radius=15.0)
    advice_cache._outcome.cache_clear()
    answers = {}
    for contact in ("point", "face"):
        register(FollowerKind("probe", "a follower registered twice", contact))
        try:
            follower = FollowerSpec("probe", 10.0)
            answers[contact] = (sizing.base_radius_advice(follower, law, limits).low,
                                sizing._advice_search(follower, law, limits, sizing.DEFAULT_SIZE_TOL, 32, 3).low)
        finally:
            unregister("probe")
    assert answers["point"][0] == answers["point"][1] and answers["face"][0] == answers["face"][1], answers
    assert answers["point"][0] != answers["face"][0]  # the two contacts need different base radii
