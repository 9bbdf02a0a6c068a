"""Three-arc cam: chord tolerance -> points, flatten time (median), measured max deviation.

Run from the repository root: ``python benchmarks/bench_three_arc.py``.
Target (issue #2): 1 um tolerance in under 1 ms for the stride cam.
"""
from __future__ import annotations

import _common  # noqa: F401  (shared helpers: median_time, print_table)
from _common import median_time, print_table

import camgen
from helpers import chord_deviation  # tests/helpers.py (on the path through _common)

CAMS = {"stride_length (220, 160, 25)": (220.0, 160.0, 25.0), "stride_height (220, 220, 10)": (220.0, 220.0, 10.0)}


def main() -> None:
    for label, abc in CAMS.items():
        build_time = median_time(lambda: camgen.three_arc_cam(*abc))
        cam = camgen.three_arc_cam(*abc)
        rows = []
        for tol in (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6):
            pts = cam.flatten(tol)
            seconds = median_time(lambda: cam.flatten(tol))
            deviation = chord_deviation(cam, tol)
            rows.append([f"{tol:g}", len(pts), f"{seconds * 1e3:.3f}", f"{deviation:.3e}", f"{deviation / tol:.4f}"])
        print(f"\n{label}: build {build_time * 1e6:.1f} us (median)")
        print_table(["chord_tol_mm", "points", "flatten_ms", "max_deviation_mm", "deviation/tol"], rows)


if __name__ == "__main__":
    main()
