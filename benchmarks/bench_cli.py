"""Whole-process run time of `camgen run`: every bundled template, and `--only` jobs.

Each job is run ``REPEATS`` times as a fresh process (`python -m camgen run ... --quiet`), after
one warm-up run (the OS file cache, matplotlib's font cache); the table gives the median wall
time and the median CPU time (user + system of the child), in seconds.  Run it with camgen
installed:  python benchmarks/bench_cli.py
"""
from __future__ import annotations

import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import print_table

REPEATS = 5


def machine() -> str:
    model = ""
    try:
        model = next(line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines() if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{platform.node() or 'machine'}: {model or platform.processor()}, {os.cpu_count()} cores, Python {platform.python_version()}"


def timed(args: list[str]) -> tuple[float, float]:
    """(wall s, CPU s) of one process running ``camgen run`` with ``args``."""
    with tempfile.TemporaryDirectory() as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "camgen", "run", *args, "-o", out, "--quiet"], capture_output=True, text=True)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode not in (0, 1):
        raise SystemExit(f"camgen run {' '.join(args)} failed: {proc.stderr}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    from camgen.scene import template_names, template_path

    jobs = [(f"{name} (all outputs)", [str(template_path(name))]) for name in template_names()]
    jobs += [("default --only dxf", ["--only", "dxf"]), ("default --only ngc", ["--only", "ngc"]),
             ("default --only stl", ["--only", "stl"]), ("default --only json", ["--only", "json"])]
    print(f"camgen run, whole process; medians of {REPEATS} runs after one warm-up; {machine()}\n")
    rows = []
    for label, args in jobs:
        timed(args)
        samples = [timed(args) for _ in range(REPEATS)]
        rows.append([label, f"{statistics.median(s[0] for s in samples):.2f}", f"{statistics.median(s[1] for s in samples):.2f}"])
    print_table(["job", "wall_s", "cpu_s"], rows)


if __name__ == "__main__":
    main()
