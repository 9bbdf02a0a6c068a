"""``camgen optimize``: the optimum against a bisection written here, the scene it writes, the
refusals (issue 28 item 5).

The problem with a known answer: the plate_cam template's outer radius grows with its base
radius, and its pressure angle falls with it, so the smallest plate cam whose every check passes
has the least base radius at which the pressure-angle check passes; a bisection on that check
(each step :func:`camgen.pipeline.compute` on the scene, not the optimiser's code) finds it.
"""
from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from camgen.checks import CheckResult, limited
from camgen.cli import main
from camgen.pipeline import compute
from camgen.planning import plan_run
from camgen.scene import parse_scene, template_path
from camgen.study.design import OUTER_RADIUS_TOL, StudyScene, evaluate_point
from camgen.study.keys import resolve_key
from camgen.study.optimize import X_TOL
from camgen.study.optimize_problem import STRICT_MARGIN, Evaluator, check_margin, parse_objective

TEMPLATE = template_path("plate_cam")
LOW, HIGH = 25.0, 45.0
#: The bisection stops when its bracket is this narrow, mm (far below the optimiser's tolerance).
BISECTION_TOL = 1e-7


def _check_results(base_radius: float) -> dict[str, CheckResult]:
    data = tomllib.loads(TEMPLATE.read_text(encoding="utf-8"))
    data["cams"]["plate"]["base_radius_mm"] = base_radius
    scene = parse_scene(data, "plate_cam", str(TEMPLATE), TEMPLATE.parent)
    result = compute(scene, plan_run(scene, ["json"]))
    return {c.name: c for c in result.cams[0].checks}


def _checks(base_radius: float) -> dict[str, bool | None]:
    return {name: c.passed for name, c in _check_results(base_radius).items()}


@pytest.fixture(scope="module")
def least_base_radius() -> float:
    """The least base radius (mm) at which the pressure-angle check passes, by bisection."""
    low, high = LOW, HIGH
    assert _checks(low)["pressure_angle"] is False and _checks(high)["pressure_angle"] is True
    while high - low > BISECTION_TOL:
        mid = 0.5 * (low + high)
        low, high = (low, mid) if _checks(mid)["pressure_angle"] else (mid, high)
    # the pressure angle is the check that binds: every other check passes just above it
    assert all(p is not False for p in _checks(high).values())
    return high


def _optimize(tmp: Path, *extra: str, goal: tuple[str, str] = ("--minimize", "outer_radius_mm")) -> tuple[int, Path]:
    status = main(["optimize", str(TEMPLATE), "--vary", f"base_radius_mm={LOW:g}:{HIGH:g}", *goal, "-o", str(tmp), "-q", *extra])
    return status, tmp / "plate_cam-optimum"


@pytest.fixture(scope="module")
def optimum(tmp_path_factory: pytest.TempPathFactory) -> Path:
    status, folder = _optimize(tmp_path_factory.mktemp("de"), "--max-evaluations", "80", "--seed", "3")
    assert status == 0
    return folder


@pytest.mark.parametrize("method, goal", [("de", "--minimize"), ("cobyla", "--minimize"), ("cobyla", "--maximize")])
def test_the_smallest_cam_is_at_the_pressure_angle_limit(method, goal, optimum, least_base_radius, tmp_path):
    """Minimising the outer radius, or maximising the pressure angle (the largest that passes is
    the limit's), both end at the least base radius that passes."""
    if method == "de":
        folder = optimum
    else:
        figure = "outer_radius_mm" if goal == "--minimize" else "pressure_angle_deg"
        status, folder = _optimize(tmp_path, "--method", "cobyla", "--max-evaluations", "60", goal=(goal, figure))
        assert status == 0
    history = json.loads((folder / "optimize.json").read_text(encoding="utf-8"))
    best = history["best"]["values"]["cams.plate.base_radius_mm"]
    # feasible (at or above the limit), and within the optimiser's stated tolerance of it
    assert least_base_radius - BISECTION_TOL <= best <= least_base_radius + X_TOL * (HIGH - LOW)
    assert history["method"] == method and history["best"]["feasible"]
    assert 0 < history["evaluations_done"] <= history["max_evaluations"]
    report = json.loads((folder / "report.json").read_text(encoding="utf-8"))
    assert report["status"] == "pass"
    assert [c["name"] for c in report["cams"]["plate"]["checks"] if c["status"] == "fail"] == []
    assert report["cams"]["plate"]["figures"]["base_radius_mm"] == best
    if goal == "--maximize":
        limit = next(c["limit"] for c in report["cams"]["plate"]["checks"] if c["name"] == "pressure_angle")
        assert history["objective"] == {"figure": "fig.plate.pressure_angle_deg", "sense": "maximize"}
        # the pressure angle falls as the base radius grows: at most the limit, at least its value
        # at the far end of the optimiser's tolerance
        far = _check_results(least_base_radius + X_TOL * (HIGH - LOW))["pressure_angle"].value
        assert far <= history["best"]["objective"] <= limit


def test_the_figure_is_the_outline_s_largest_radius(optimum):
    """The optimised figure against the run's own profile points (plate_points.csv)."""
    history = json.loads((optimum / "optimize.json").read_text(encoding="utf-8"))
    with (optimum / "plate_points.csv").open(newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    largest = max(math.hypot(float(r["x_mm"]), float(r["y_mm"])) for r in rows)
    chord_tol = tomllib.loads(TEMPLATE.read_text(encoding="utf-8"))["output"]["chord_tol_mm"]
    assert abs(history["best"]["objective"] - largest) <= OUTER_RADIUS_TOL + chord_tol


def test_the_written_scene_is_the_base_with_the_optimum(optimum):
    text = (optimum / "plate_cam-optimum.toml").read_text(encoding="utf-8")
    best = json.loads((optimum / "optimize.json").read_text(encoding="utf-8"))["best"]["values"]
    expected = tomllib.loads(TEMPLATE.read_text(encoding="utf-8"))
    expected["cams"]["plate"]["base_radius_mm"] = best["cams.plate.base_radius_mm"]
    assert tomllib.loads(text) == expected
    comments = [line[line.index("#"):] for line in TEMPLATE.read_text(encoding="utf-8").splitlines() if "#" in line]
    assert [c for c in comments if c not in text] == []
    check = subprocess.run([sys.executable, "-m", "camgen", "check", str(optimum / "plate_cam-optimum.toml")],
                           capture_output=True, text=True, timeout=120)
    assert check.returncode == 0, check.stderr


def test_no_feasible_design_is_one_line_naming_the_check(tmp_path, capsys):
    status = main(["optimize", str(TEMPLATE), "--vary", "base_radius_mm=15:24", "--minimize", "outer_radius_mm",
                   "--max-evaluations", "12", "-o", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 1
    assert len(err) == 1 and "no feasible design" in err[0] and "cams.plate.pressure_angle never passed" in err[0]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, named", [
    (["--vary", "base_radius_mm=30,40", "--minimize", "outer_radius_mm"], "--vary cams.plate.base_radius_mm"),
    (["--vary", "base_radius_mm=30:40:1", "--minimize", "outer_radius_mm"], "--vary cams.plate.base_radius_mm"),
    (["--vary", "base_radius_mm=40:30", "--minimize", "outer_radius_mm"], "--vary cams.plate.base_radius_mm"),
    (["--vary", "base_radius_mm=40:40", "--minimize", "outer_radius_mm"], "--vary cams.plate.base_radius_mm"),
    (["--vary", "rotation=0:1", "--minimize", "outer_radius_mm"], "--vary cams.plate.rotation"),
    (["--vary", "no_such_table.x=0:1", "--minimize", "outer_radius_mm"], "--vary"),
    (["--vary", "base_radius_mm=30:40", "--minimize", "size_mm"], "--minimize"),
    (["--vary", "base_radius_mm=30:40", "--maximize", "fig.other.outer_radius_mm"], "--maximize"),
    (["--vary", "base_radius_mm=30:40", "--minimize", "check.plate.no_such_check"], "--minimize"),
    (["--vary", "base_radius_mm=30:40"], "--minimize"),
    (["--minimize", "outer_radius_mm"], "--vary"),
    (["--vary", "base_radius_mm=30:40", "--minimize", "outer_radius_mm", "--method", "nelder"], "--method"),
    (["--vary", "base_radius_mm=30:40", "--minimize", "outer_radius_mm", "--max-evaluations", "0"], "--max-evaluations"),
])
def test_bad_input_is_one_line_and_nothing_written(args, named, tmp_path, capsys):
    status = main(["optimize", str(TEMPLATE), *args, "-o", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2
    assert len(err) == 1 and err[0].startswith("camgen: error:") and named in err[0], err
    assert list(tmp_path.iterdir()) == []


def test_a_margin_is_the_distance_to_the_limit_over_its_size():
    assert check_margin(limited("p", 24.0, "<=", 30.0, "deg", [], "")) == pytest.approx(6.0 / 30.0)
    assert check_margin(limited("p", 33.0, "<=", 30.0, "deg", [], "")) == pytest.approx(-3.0 / 30.0)
    assert check_margin(limited("w", 5.0, ">=", 2.0, "mm", [], "")) == pytest.approx(3.0 / 2.0)
    assert check_margin(limited("t", 0.25, "<=", 0.5, "N*m", [], "")) == pytest.approx(0.25)  # |limit| < 1: over 1
    assert check_margin(limited("u", 10.0, ">", 10.0, "mm", [], "")) == -STRICT_MARGIN  # equal to a strict limit: failed
    for value in (-3.0, 0.0, 1.5, 2.0, 2.5, 40.0):  # inside the limit exactly when the check passed
        for comparison in ("<=", "<", ">=", ">"):
            check = limited("c", value, comparison, 2.0, "mm", [], "")
            margin = check_margin(check)
            assert margin is not None and (margin >= 0.0) == check.passed


def test_the_evaluator_agrees_with_a_sweep_row():
    """The figure and the pass/fail the optimiser sees are those of the study's own row."""
    study = StudyScene.load(str(TEMPLATE))
    from camgen.study.optimize import parse_variables

    variables = parse_variables(study.data, ["base_radius_mm=20:45"])
    evaluator = Evaluator(study, variables, parse_objective(study.data, "outer_radius_mm", "minimize"), budget=2)
    by_check = Evaluator(study, variables, parse_objective(study.data, "check.plate.pressure_angle", "maximize"), budget=2)
    assert by_check.objective.column == "check.plate.pressure_angle"
    key = resolve_key(study.data, "base_radius_mm")
    for radius in (22.0, 36.0):
        trial, checked = evaluator((radius,)), by_check((radius,))
        row = evaluate_point(study, [key], [radius])
        assert trial.status == row["status"] and trial.objective == row["fig.plate.outer_radius_mm"]
        assert checked.objective == row["check.plate.pressure_angle"]
        failed = {n for n, m in zip(evaluator.names, trial.margins) if m < 0}
        assert failed == {"cams." + column.removeprefix("check.").removesuffix(".status") for column, value in row.items()
                          if column.endswith(".status") and value == "fail"}
    assert [t.status for t in evaluator.trials] == ["fail", "pass"]  # 22 mm fails the pressure angle, 36 mm passes


def test_the_same_seed_gives_the_same_designs():
    from camgen.study.optimize import optimize, parse_variables

    study = StudyScene.load(str(TEMPLATE))
    variables = parse_variables(study.data, ["base_radius_mm=25:45", "follower_offset_mm=0:10"])
    objective = parse_objective(study.data, "outer_radius_mm", "minimize")
    runs = [optimize(study, variables, objective, "de", seed, 10) for seed in (5, 5, 6)]
    designs = [[(t.values, t.status, t.objective, t.margins) for t in r.trials] for r in runs]
    assert len(designs[0]) == 10 and designs[0] == designs[1] and designs[0] != designs[2]
