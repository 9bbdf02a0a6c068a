"""How fast and in how much memory `camgen run` refuses bad input: the cases of issue 21 (a fuzz
campaign's scenes that took seconds and gigabytes, or crashed) and the unbounded files a scene may
name.  The tests check that each is refused with one line naming the key and that the caps apply
before the work (no test times anything); this table measures what that buys.

Each case is a fresh process (`python -m camgen run SCENE -o OUT --quiet`), median of ``REPEATS``
runs after one warm-up; wall and CPU time (user + system of the child) and the child's peak
resident memory (ru_maxrss).  Target: every refusal within 1 s and 200 MB on this machine
(issue 21, item 4: "refused or accepted within a second and bounded memory").
Run it with camgen installed:  python benchmarks/bench_refusals.py
"""
from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

from _common import machine, print_table

REPEATS = 5
TARGET_S = 1.0
TARGET_MB = 200.0

PLATE = """[output]
formats = ["dxf"]
[cams.c]
kind = "motion_law"
base_radius_mm = {radius}
roller_radius_mm = 10.0
segments = [{{law = "cycloidal", span_deg = 180.0, lift_mm = 10.0}}, {{law = "cycloidal", span_deg = 180.0, lift_mm = -10.0}}]
"""
LIFT = """[output]
formats = ["dxf"]
[cams.c]
kind = "lift_table"
base_radius_mm = 40.0
roller_radius_mm = 10.0
lift_table_csv = "{path}"
"""
TRAJECTORY = """[output]
formats = ["dxf"]
[cams.c]
kind = "trajectory"
period_mm = 2000.0
expression = "{expression}"
"""


def _scene(text: str) -> Callable[[Path], Path]:
    def make(folder: Path) -> Path:
        path = folder / "s.toml"
        path.write_text(text)
        return path
    return make


def _lift_table(make_file: Callable[[Path], str]) -> Callable[[Path], Path]:
    def make(folder: Path) -> Path:
        return _scene(LIFT.format(path=make_file(folder)))(folder)
    return make


def _sparse(folder: Path) -> str:
    path = folder / "huge.csv"
    with open(path, "wb") as handle:
        handle.truncate(10**12)  # 1 TB, sparse
    return str(path)


def _fifo(folder: Path) -> str:
    path = folder / "pipe.csv"
    if not path.exists():
        os.mkfifo(path)
    return str(path)


CASES: dict[str, Callable[[Path], Path]] = {
    "valid plate cam (for scale)": _scene(PLATE.format(radius=40.0)),
    "20,000-deep dotted key (40 KB)": _scene("a." * 20000 + "b = 1\n"),
    "20,000-deep table header": _scene("[" + "t." * 20000 + "u]\n"),
    "10,000-deep inline array": _scene("x = " + "[" * 10000 + "]" * 10000 + "\n"),
    "4000-digit hex integer in a key": _scene(PLATE.format(radius="0x" + "f" * 4000)),
    "5000-digit decimal integer in a key": _scene(PLATE.format(radius="9" * 5000)),
    "1 MiB scene of comments": _scene(PLATE.format(radius=40.0) + ("#" + "x" * 1022 + "\n") * 1020),
    "expression x+x+... (1000 terms)": _scene(TRAJECTORY.format(expression="+".join(["x"] * 1000))),
    "expression with a 401-digit integer": _scene(TRAJECTORY.format(expression="sin(x)*" + "9" * 401)),
    "lift table: a sparse 1 TB file": _lift_table(_sparse),
    "lift table: /dev/zero": _lift_table(lambda folder: "/dev/zero"),
    "lift table: a FIFO without a writer": _lift_table(_fifo),
}


def measure(make: Callable[[Path], Path]) -> tuple[float, float, float, int]:
    """(wall s, CPU s, peak MB, exit status) of one refusal, each a median over REPEATS runs."""
    walls, cpus, peaks, statuses = [], [], [], []
    with tempfile.TemporaryDirectory() as folder:
        scene = make(Path(folder))
        for i in range(REPEATS + 1):
            start = time.perf_counter()
            proc = subprocess.Popen([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(Path(folder) / "out"), "--quiet"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            _, status, usage = os.wait4(proc.pid, 0)
            wall = time.perf_counter() - start
            if i == 0:
                continue  # warm-up
            walls.append(wall)
            cpus.append(usage.ru_utime + usage.ru_stime)
            peaks.append(usage.ru_maxrss / 1024.0)
            statuses.append(os.waitstatus_to_exitcode(status))
    return statistics.median(walls), statistics.median(cpus), statistics.median(peaks), max(statuses)


def main() -> None:
    print(f"camgen run refusing bad input, whole process; medians of {REPEATS} runs after one warm-up; {machine()}\n")
    rows = []
    for name, make in CASES.items():
        wall, cpu, peak, status = measure(make)
        met = "yes" if wall <= TARGET_S and peak <= TARGET_MB else "no"
        rows.append([name, status, f"{wall:.2f}", f"{cpu:.2f}", f"{peak:.0f}", met])
    print_table(["case", "exit", "wall_s", "cpu_s", "peak_MB", f"met ({TARGET_S:g} s, {TARGET_MB:g} MB)"], rows)


if __name__ == "__main__":
    main()
