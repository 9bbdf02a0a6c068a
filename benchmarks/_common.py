"""Shared helpers of the benchmark scripts (camgen installed, e.g. ``pip install -e ".[test]"``)."""
from __future__ import annotations

import math
import os
import platform
import statistics
import sys
import time
from pathlib import Path
from typing import Callable, Iterator

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
# the tests' independent references (tests/ride.py, tests/helpers.py) serve the benchmarks too
sys.path.append(str(ROOT / "tests"))


def median_time(func: Callable[[], object], repeats: int = 21, min_total: float = 0.05) -> float:
    """Median wall time of one call (s), over ``repeats`` timed batches of calls."""
    func()  # warm up (imports, caches)
    calls = 1
    while True:
        start = time.perf_counter()
        for _ in range(calls):
            func()
        if time.perf_counter() - start >= min_total / repeats or calls >= 1 << 16:
            break
        calls *= 2
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            func()
        samples.append((time.perf_counter() - start) / calls)
    return statistics.median(samples)


def print_table(headers: list[str], rows: list[list[object]]) -> None:
    """Print a Markdown table."""
    cells = [[str(c) for c in row] for row in rows]
    widths = [max(len(h), *(len(r[i]) for r in cells)) for i, h in enumerate(headers)]
    print("| " + " | ".join(h.rjust(w) for h, w in zip(headers, widths)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for row in cells:
        print("| " + " | ".join(c.rjust(w) for c, w in zip(row, widths)) + " |")


def machine() -> str:
    """The machine a table was measured on: host, CPU model, cores, Python and numpy versions."""
    model = ""
    try:
        model = next(line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines() if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{platform.node() or 'machine'}: {model or platform.processor()}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy {np.__version__}"


def orientations(points: np.ndarray) -> Iterator[np.ndarray]:
    """``points`` (n, 2) in the eight readings another tool's sense of rotation and angle origin
    may need (mirrored or not, turned by quarter turns): a peer's profile is scored in its best."""
    for mirror in (1.0, -1.0):
        p = points * np.array([mirror, 1.0])
        for quarter in range(4):
            c, s = math.cos(quarter * math.pi / 2), math.sin(quarter * math.pi / 2)
            yield np.column_stack([c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]])
