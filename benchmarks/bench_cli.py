"""Whole-process run time of `camgen run`: every bundled template with all its outputs and with
`--only dxf`, some `--only` jobs of the default scene, and where the default scene's time goes.

Each job is run ``REPEATS`` times as a fresh process (`python -m camgen run ... --quiet`), after
one warm-up run (the OS file cache, compiled .pyc files); the table gives the median wall time
and the median CPU time (user + system of the child), in seconds, against issue 13's targets
(every template <= 1.5 s, `--only dxf` <= 0.5 s).  Wall time on a loaded machine exceeds CPU
time by the waiting; the "met" column judges the wall time.  The per-stage table times the
default scene's steps in one process (imports excluded), medians of ``REPEATS`` runs.
Run it with camgen installed:  python benchmarks/bench_cli.py
"""
from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

from _common import machine, print_table

REPEATS = 5
#: Targets of issue 13 (whole process, s).
TARGET_ALL_S = 1.5
TARGET_DXF_S = 0.5


def _environment() -> dict[str, str]:
    """The children's environment: .pyc files written and used, as after `pip install`."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def timed(args: list[str]) -> tuple[float, float]:
    """(wall s, CPU s) of one process running ``camgen run`` with ``args``."""
    with tempfile.TemporaryDirectory() as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "camgen", "run", *args, "-o", out, "--quiet"], capture_output=True, text=True,
                              env=_environment())
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode not in (0, 1):
        raise SystemExit(f"camgen run {' '.join(args)} failed: {proc.stderr}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def load() -> str:
    try:
        return "load average " + " ".join(Path("/proc/loadavg").read_text().split()[:3])
    except OSError:
        return "load average unknown"


def stage_of(step: str) -> str:
    """The stage a progress message belongs to ("building cam 'x' (kind)" -> "build: kind")."""
    if step.startswith("building cam"):
        return "build " + step.rsplit("(", 1)[-1].rstrip(")")
    if step.startswith("writing ") and step != "writing files":
        name = step[len("writing "):]
        return "write " + (name if name.startswith("report") else name.rsplit(".", 1)[-1].rsplit("_", 1)[-1])
    return step.split(" '")[0]


def stages() -> list[list[str]]:
    """Median seconds per stage of the default scene in one process (after a warm-up run)."""
    from camgen.pipeline import run_scene
    from camgen.scene import load_template

    runs: list[dict[str, float]] = []
    for repeat in range(REPEATS + 1):
        marks: list[tuple[str, float]] = []
        with tempfile.TemporaryDirectory() as out:
            start = time.perf_counter()
            run_scene(load_template("default"), out, progress=lambda step: marks.append((step, time.perf_counter())))
            end = time.perf_counter()
        spent: dict[str, float] = defaultdict(float)
        spent["read scene, plan"] = marks[0][1] - start
        for (step, at), (_, until) in zip(marks, marks[1:] + [("end", end)]):
            spent[stage_of(step)] += until - at
        if repeat:
            runs.append(spent)
    total = statistics.median(sum(r.values()) for r in runs)
    names = sorted({k for r in runs for k in r}, key=lambda k: -statistics.median(r.get(k, 0.0) for r in runs))
    rows = [[name, f"{1e3 * statistics.median(r.get(name, 0.0) for r in runs):.1f}"] for name in names]
    rows.append(["total (in process, imports excluded)", f"{1e3 * total:.1f}"])
    return rows


def main() -> None:
    from camgen.scene import template_names, template_path

    jobs = []
    for name in template_names():
        jobs.append((f"{name}", [str(template_path(name))], TARGET_ALL_S))
        jobs.append((f"{name} --only dxf", [str(template_path(name)), "--only", "dxf"], TARGET_DXF_S))
    jobs += [("default --only ngc", ["--only", "ngc"], None), ("default --only stl", ["--only", "stl"], None),
             ("default --only json", ["--only", "json"], None)]
    print(f"camgen run, whole process; medians of {REPEATS} runs after one warm-up; {machine()}; {load()} at the start\n")
    rows = []
    for label, args, target in jobs:
        timed(args)
        samples = [timed(args) for _ in range(REPEATS)]
        wall, cpu = statistics.median(s[0] for s in samples), statistics.median(s[1] for s in samples)
        met = "-" if target is None else ("yes" if wall <= target else "NO")
        rows.append([label, f"{wall:.2f}", f"{cpu:.2f}", "-" if target is None else f"{target:g}", met])
    print_table(["job", "wall_s", "cpu_s", "target_s", "met"], rows)
    print(f"\nWhere the default scene's time goes (ms, medians of {REPEATS} in-process runs; {load()}):\n")
    print_table(["stage", "ms"], stages())


if __name__ == "__main__":
    main()
