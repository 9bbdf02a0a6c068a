"""One plate-cam design evaluated as a sweep evaluates it (issue 28 item 6): the time per design
and where it goes, against the target of 3 ms.

A sweep decodes the scene's TOML once; per point (``camgen.study.design.evaluate_point``) it
changes some values of the decoded table, validates it (``camgen.scene.parse_scene``), runs
``camgen.pipeline.compute(scene, camgen.evaluation.evaluation_plan(scene))``: synthesis, every
design check, the dynamics, no file, and makes the row (the checks and the main figures).  Here
templates/plate_cam.toml with its base radius stepped over 40 values (every design a new one: no
cache of a design's values is reused), split into its stages, each timed per design
(``time.process_time``: the CPU time of this process, which the other processes of a shared
machine disturb far less than the wall time), the median over the designs of several rounds:

* validate: the point's table (``point_scene_data``) and ``parse_scene`` of it (schema, every key, the law);
* build: the kind's synthesis (exact envelope of the roller, its spline fit, size, perimeter);
* checks: every design check (``camgen.checking.evaluate`` without the report-only figures);
* dynamics: the follower train's forces, jump, torque, contact stress and their checks;
* row: the row's main figures (``camgen.study.design.main_figures``: the exact outer radius).

Then ``evaluate_point`` as a whole, on passing designs and on a range half of which fails (base radii from
18 mm: the pressure angle fails, and the ``min_base_radius`` check, the value in the row,
searches the smallest base radius that passes: a failing design costs more), and on a range of
rises (the rise and the return of the motion changed together, 10 .. 29.5 mm): a sweep over the
base radius keeps one motion law, whose values a design may reuse (a cache of a pure function of
the motion's keys); a sweep over the motion makes a new law at every point.

The "before" row is the same split measured on commit 634d245 (before this work) with the
same scene and designs, on the same machine, alternating three runs of each with this script's
"now" (the medians; load average about 5 on 2 cores: six other sessions ran); its ``evaluate``
computed the report-only acceleration harmonics too (it had no evaluation plan).
Run:  python benchmarks/bench_evaluate.py
"""
from __future__ import annotations

import os
import statistics
import time

from _common import machine, print_table

#: Target time of one design with every check, in process (issue 28 item 6), ms.
TARGET_MS = 3.0
#: Designs per round (base radii 36 .. 55.5 mm) and rounds.
DESIGNS, ROUNDS = 40, 5
#: The stages of ``evaluate_point``: the point's table and its validation, the synthesis, the
#: design checks, the dynamics, the row's main figures (the outer radius: camgen.contour.reach).
STAGES = ("validate", "build", "checks", "dynamics", "row")
#: The split measured on commit 634d245 (CPU ms; validate, build, checks, dynamics), same script logic.
BEFORE = {"validate": 2.50, "build": 9.09, "checks": 12.92, "dynamics": 2.64}


def _points():
    """The study of templates/plate_cam.toml varying its base radius, and the key."""
    from camgen.scene import template_path
    from camgen.study.design import StudyScene
    from camgen.study.keys import resolve_key

    study = StudyScene.load(str(template_path("plate_cam")))
    return study, resolve_key(study.data, "base_radius_mm")


def _split() -> dict[str, list[float]]:
    """Each stage of ``evaluate_point`` timed by itself on the same designs (CPU ms per design)."""
    from camgen.checking import evaluate
    from camgen.evaluation import evaluation_plan
    from camgen.kinds import get_kind
    from camgen.kinds.dynamics import run_dynamics
    from camgen.pipeline import compute
    from camgen.scene import parse_scene
    from camgen.study.design import main_figures, point_scene_data
    from camgen.study.heap import keep_heap

    keep_heap()  # as a study's scenes do (camgen.study.heap)
    study, key = _points()
    times: dict[str, list[float]] = {name: [] for name in STAGES}
    for round_ in range(ROUNDS + 1):  # the first round warms up (imports, the composed kinds)
        for i in range(DESIGNS):
            t0 = time.process_time()
            data = point_scene_data(study.data, {key.path: 36.0 + 0.5 * i + 0.01 * round_})
            scene = parse_scene(data, study.name, study.source, study.base_dir)
            plan = evaluation_plan(scene)
            (spec,) = scene.cams
            t1 = time.process_time()
            built = get_kind(spec.kind, spec.form).build(spec, plan.build_stages)
            t2 = time.process_time()
            evaluate(built, spec, scene.machining.tool_radius, spec.checks.tool_is_limit, plan.report_figures)
            t3 = time.process_time()
            run_dynamics(built, spec, plan.stages, plan.report_figures)
            t4 = time.process_time()
            (cam,) = compute(scene, plan).cams  # the same cam as a CamResult (not timed): its row's figures
            t5 = time.process_time()
            main_figures(cam)
            t6 = time.process_time()
            if round_:
                for name, took in zip(times, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t6 - t5)):
                    times[name].append(took * 1e3)
    return times


def _whole(start: float, vary: str = "base_radius") -> tuple[float, float]:
    """Median CPU ms of ``camgen.study.design.evaluate_point`` (what a sweep calls per point) and
    the share of its designs that failed a check: ``vary`` "base_radius": base radii from
    ``start`` mm (the motion law the same at every point); "lift": the rise and the return from
    ``start`` mm (segments 1 and 3; a new motion law at every point)."""
    from camgen.study.design import evaluate_point
    from camgen.study.keys import resolve_key

    study, key = _points()
    keys = [key] if vary == "base_radius" else [resolve_key(study.data, f"cams.plate.segments[{i}].lift_mm") for i in (0, 2)]
    took, failed = [], 0
    for round_ in range(ROUNDS + 1):
        for i in range(DESIGNS):
            value = start + 0.5 * i + 0.01 * round_
            t0 = time.process_time()
            row = evaluate_point(study, keys, [value] if vary == "base_radius" else [value, -value])
            t1 = time.process_time()
            if round_:
                took.append((t1 - t0) * 1e3)
                failed += row["status"] == "fail"
    return statistics.median(took), failed / (DESIGNS * ROUNDS)


def main() -> None:
    times = _split()
    now = {name: statistics.median(values) for name, values in times.items()}
    load = " ".join(f"{v:.2f}" for v in os.getloadavg())
    print(f"One plate-cam design (templates/plate_cam.toml, {DESIGNS} base radii x {ROUNDS} rounds), in process, no files; "
          f"median CPU ms per design; {machine()}; load average {load} at the end")
    print()
    rows = []
    for label, split in (("before (634d245)", BEFORE), ("now", now)):
        total = sum(split.values())
        rows.append([label] + [f"{split[n]:.2f}" if n in split else "-" for n in STAGES]
                    + [f"{total:.2f}", f"{TARGET_MS:g}", "yes" if total <= TARGET_MS else "no"])
    print_table(["code"] + list(STAGES) + ["total_ms", "target_ms", "met"], rows)
    print()
    total = sum(now.values())
    print("share of the total now: " + ", ".join(f"{n} {100 * v / total:.0f} %" for n, v in now.items()))
    print()
    rows = []
    for label, start, vary in (("base radius 36 .. 55.5 mm", 36.0, "base_radius"), ("base radius 18 .. 37.5 mm", 18.0, "base_radius"),
                               ("rise and return 10 .. 29.5 mm", 10.0, "lift")):
        whole, failed = _whole(start, vary)
        rows.append([label, f"{100 * failed:.0f} %", f"{whole:.2f}", f"{1000.0 / whole:.0f}", f"{1e5 * whole / 6e4:.1f}",
                     "yes" if whole <= TARGET_MS else "no"])
    print("camgen.study.design.evaluate_point as a whole (what a sweep calls per point; a failing design's "
          "min_base_radius check searches the smallest base radius that passes):")
    print()
    print_table(["designs", "failing_share", "ms_per_design", "designs_per_s_core", "min_per_1e5", "met"], rows)


if __name__ == "__main__":
    main()
