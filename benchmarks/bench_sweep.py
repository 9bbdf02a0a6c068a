"""Design sweeps (issue 28): designs per second per core against the number of workers, Dask's
per-task overhead measured, and the throughput expected on N machines from those figures.

1. ``camgen sweep`` as a whole process on the plate_cam template (a grid of base radius x roller
   radius, ``POINTS`` designs), in process (``--workers 1``) and on a local Dask cluster of 2
   workers: wall time, designs per second, per core; the cluster's start-up measured apart (a
   sweep of 2 designs) so the steady rate is (N - 2) / (t_N - t_2).
2. Dask's per-task overhead on this machine: a local cluster of 2 process workers runs ``TASKS``
   tasks that do nothing; the overhead per task is the wall time over the tasks (2 workers in
   parallel: the scheduler's cost per task, what bounds a cluster's task rate).
3. On paper: with a design's time t (median from step 1 in process), a batch of b designs and the
   overhead o per task, one core evaluates b / (b t + o) designs per second; N machines of c
   cores, c N b / (b t + o), until the scheduler's task rate 1 / o_s caps it at b / o_s designs
   per second (o_s: the scheduler's share, step 2).
Run it with camgen and its sweep extra installed:  python benchmarks/bench_sweep.py
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

from _common import machine, print_table

#: Designs of the timed sweep (a grid of base radius x roller radius) and repeats of each run.
RADII = "30:69.5:0.5"  # 80 base radii
ROLLERS = "6,8,10,12,14"  # 5 roller radii
POINTS = 80 * 5
REPEATS = 3
#: Empty tasks of the overhead measurement.
TASKS = 2000


def _sweep(args: list[str]) -> tuple[float, dict]:
    """Wall time of one ``camgen sweep`` process and its sweep.json."""
    with tempfile.TemporaryDirectory() as out:
        start = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "camgen", "sweep", "-q", "-o", out, *args], capture_output=True, text=True)
        wall = time.perf_counter() - start
        if proc.returncode != 0:
            raise SystemExit(f"camgen sweep {' '.join(args)} failed: {proc.stderr}")
        summary = next(p for p in os.scandir(out) if p.is_dir())
        with open(os.path.join(summary.path, "sweep.json"), encoding="utf-8") as handle:
            return wall, json.load(handle)


def _template() -> str:
    from camgen.scene import template_path

    return str(template_path("plate_cam"))


def throughput() -> tuple[list[list[object]], float]:
    rows = []
    per_design = 0.0
    for workers in (1, 2):
        common = [_template(), "--workers", str(workers)]
        full = statistics.median(_sweep(common + ["--vary", f"base_radius_mm={RADII}", "--vary", f"roller_radius_mm={ROLLERS}"])[0]
                                 for _ in range(REPEATS))
        small = statistics.median(_sweep(common + ["--vary", "base_radius_mm=30,31"])[0] for _ in range(REPEATS))
        rate = (POINTS - 2) / (full - small)
        if workers == 1:
            per_design = 1.0 / rate
        rows.append([workers, POINTS, f"{full:.2f}", f"{small:.2f}", f"{rate:.0f}", f"{rate / workers:.0f}",
                     f"{1e3 / rate * workers:.2f}"])
    return rows, per_design


def task_overhead() -> float:
    """Seconds per empty task on a local cluster of 2 process workers (median of 3)."""
    import logging

    import distributed

    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None,
                                       silence_logs=logging.CRITICAL)
    client = distributed.Client(cluster)
    try:
        client.gather(client.map(int, range(100)))  # warm up
        samples = []
        for r in range(3):
            start = time.perf_counter()
            client.gather(client.map(abs, range(r * TASKS, (r + 1) * TASKS), pure=False))
            samples.append((time.perf_counter() - start) / TASKS)
        return statistics.median(samples)
    finally:
        client.close()
        cluster.close()


def main() -> None:
    print(f"camgen sweep of the plate_cam template, whole process, medians of {REPEATS}; {machine()}")
    print()
    rows, t = throughput()
    print_table(["workers", "designs", "wall_s", "wall_2_designs_s", "designs_per_s", "per_core", "ms_per_design_core"], rows)
    print()
    o = task_overhead()
    print(f"Dask overhead per task (local cluster, 2 process workers, {TASKS} empty tasks, median of 3): {o * 1e3:.2f} ms")
    print()
    batch = max(1, round(0.005 / (0.1 * t)))  # camgen.study.execute.batch_size: overhead <= 10 % of a batch
    print(f"On paper, a design at t = {t * 1e3:.2f} ms (in process above), batches of b = {batch} designs "
          f"(overhead <= 10 % of a batch at 5 ms a task), overhead o = {o * 1e3:.2f} ms a task:")
    print()
    rows = []
    for machines, cores in ((1, 2), (4, 8), (16, 16), (64, 32)):
        cores_total = machines * cores
        compute = cores_total * batch / (batch * t + o)
        cap = batch / o  # the scheduler hands out at most 1 / o tasks a second
        rows.append([machines, cores, cores_total, f"{compute:.0f}", f"{cap:.0f}", f"{min(compute, cap):.0f}",
                     f"{1e5 / min(compute, cap) / 60:.1f}", f"{1e7 / min(compute, cap) / 3600:.2f}"])
    print_table(["machines", "cores_each", "cores", "compute_bound_per_s", "scheduler_bound_per_s", "expected_per_s",
                 "min_for_1e5", "h_for_1e7"], rows)


if __name__ == "__main__":
    main()
