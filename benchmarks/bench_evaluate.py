"""One plate-cam design evaluated as a sweep evaluates it (issue 28 item 6): the time per design
and where it goes, against the target of 3 ms.

A sweep decodes the scene's TOML once; per point it changes some values of the decoded table,
validates it (``camgen.scene.parse_scene``) and runs ``camgen.pipeline.compute(scene,
camgen.evaluation.evaluation_plan(scene))``: synthesis, every design check, the dynamics, no
file.  Here templates/plate_cam.toml with its base radius stepped over 40 values (every design a
new one: no cache of a design's values is reused), split into its stages, each timed per design
(``time.process_time``: the CPU time of this process, which the other processes of a shared machine disturb far less than the wall time), the median over the designs of several rounds:

* validate: ``parse_scene`` of the changed table (schema, every key, the law);
* build: the kind's synthesis (exact envelope of the roller, its spline fit, size, perimeter);
* checks: every design check (``camgen.checking.evaluate`` without the report-only figures);
* dynamics: the follower train's forces, jump, torque, contact stress and their checks.

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
import tomllib

from _common import machine, print_table

#: Target time of one design with every check, in process (issue 28 item 6), ms.
TARGET_MS = 3.0
#: Designs per round (base radii 36 .. 55.5 mm) and rounds.
DESIGNS, ROUNDS = 40, 5
#: The split measured on commit 634d245 (CPU ms; validate, build, checks, dynamics), same script logic.
BEFORE = {"validate": 2.50, "build": 9.09, "checks": 12.92, "dynamics": 2.64}


def _split() -> dict[str, list[float]]:
    from camgen.checking import evaluate
    from camgen.evaluation import evaluation_plan
    from camgen.kinds import get_kind
    from camgen.kinds.dynamics import run_dynamics
    from camgen.scene import parse_scene, template_path

    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    cam = data["cams"]["plate"]
    times: dict[str, list[float]] = {"validate": [], "build": [], "checks": [], "dynamics": []}
    for round_ in range(ROUNDS + 1):  # the first round warms up (imports, the composed kinds)
        for i in range(DESIGNS):
            point = {**data, "cams": {"plate": {**cam, "base_radius_mm": 36.0 + 0.5 * i + 0.01 * round_}}}
            t0 = time.process_time()
            scene = parse_scene(point, "plate_cam")
            plan = evaluation_plan(scene)
            (spec,) = scene.cams
            t1 = time.process_time()
            built = get_kind(spec.kind, spec.form).build(spec, plan.stages)
            t2 = time.process_time()
            evaluate(built, spec, scene.machining.tool_radius, spec.checks.tool_is_limit, plan.report_figures)
            t3 = time.process_time()
            run_dynamics(built, spec, plan.stages)
            t4 = time.process_time()
            if round_:
                for name, took in zip(times, (t1 - t0, t2 - t1, t3 - t2, t4 - t3)):
                    times[name].append(took * 1e3)
    return times


def _whole() -> tuple[float, float]:
    """Median ms of the whole evaluation (validate + compute with the evaluation plan), and of
    compute with the plan of `camgen run --only json` (the report's figures too) for comparison."""
    from camgen.evaluation import evaluation_plan
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene, template_path

    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    cam = data["cams"]["plate"]
    evaluation, report = [], []
    for round_ in range(ROUNDS + 1):
        for i in range(DESIGNS):
            point = {**data, "cams": {"plate": {**cam, "base_radius_mm": 36.0 + 0.5 * i + 0.01 * round_}}}
            t0 = time.process_time()
            scene = parse_scene(point, "plate_cam")
            compute(scene, evaluation_plan(scene))
            t1 = time.process_time()
            compute(scene, plan_run(scene, ["json"]))
            t2 = time.process_time()
            if round_:
                evaluation.append((t1 - t0) * 1e3)
                report.append((t2 - t1) * 1e3)
    return statistics.median(evaluation), statistics.median(report)


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
        rows.append([label] + [f"{split[n]:.2f}" for n in times] + [f"{total:.2f}", f"{TARGET_MS:g}", "yes" if total <= TARGET_MS else "no"])
    print_table(["code", "validate", "build", "checks", "dynamics", "total_ms", "target_ms", "met"], rows)
    print()
    total = sum(now.values())
    print("share of the total now: " + ", ".join(f"{n} {100 * v / total:.0f} %" for n, v in now.items()))
    evaluation, report = _whole()
    print()
    print(f"whole evaluation (validate + compute with evaluation_plan): {evaluation:.2f} ms per design, "
          f"{1000.0 / evaluation:.0f} designs/s on one core ({1e5 * evaluation / 6e4:.1f} min for 10^5 designs); "
          f"compute with the plan of `camgen run --only json` (the report's figures too): {report:.2f} ms")


if __name__ == "__main__":
    main()
