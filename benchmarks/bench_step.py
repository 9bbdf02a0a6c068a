"""STEP of every bundled template's cams: size, B-spline control points and OCCT's volume error.

Run from the repository root: ``python benchmarks/bench_step.py``.
"before": every spline segment written exactly with its own pieces as one edge (the earlier
writer); "after": the compact form within bspline_tol = 1e-8 mm (camgen.export.dxf.compact_spline)
in edges of at most 64 knot spans (camgen.export.step.EDGE_SPANS).  Volume error: OCCT's default
mass properties (what FreeCAD shows) of the file read back, relative to the exact area x thickness.
Target (issue "Accuracy and numerical stability", item 2): within 1e-6 relative for every cam.
"""
from __future__ import annotations

import math
import re

import _common  # noqa: F401  (puts the repository root on sys.path)
from _common import median_time, print_table

from camgen.export.step import step_bytes, step_volume
from camgen.pipeline import Plan, compute
from camgen.scene import load_template, template_names


def exact_volume(contour, body) -> float:
    r, h = body.bore_diameter / 2, body.keyway_width / 2
    area = contour.area - math.pi * r * r
    if h > 0:
        area -= 2 * h * (r + body.keyway_depth) - (h * math.sqrt(r * r - h * h) + r * r * math.asin(h / r))
    return area * body.thickness


def poles(data: bytes) -> int:
    """Control points of the cubic B-spline curves of the file (each edge curve counted once per
    occurrence in the file: the 3-D edges, not OCCT's degree-1 parameter-space curves)."""
    text = data.decode("ascii")
    return sum(len(m.split(",")) for m in re.findall(r"B_SPLINE_CURVE_WITH_KNOTS\('',3,\(([^)]*)\)", text))


def main() -> None:
    rows = []
    for name in template_names():
        for cam in compute(load_template(name), Plan((), frozenset())).cams:
            if not cam.manufacturable or not any(seg.kind == "spline" for seg in cam.contour.segments):
                continue
            exact = exact_volume(cam.contour, cam.body)
            row = [name, cam.name, sum(seg.n_pieces for seg in cam.contour.segments if seg.kind == "spline")]
            for kw in ({"exact": True, "edge_spans": None}, {}):
                data = step_bytes(cam.contour, cam.body, cam.name, **kw)
                t = median_time(lambda: step_bytes(cam.contour, cam.body, cam.name, **kw), repeats=3)
                row += [len(data), poles(data), f"{(step_volume(data) - exact) / exact:.2e}", f"{t * 1e3:.0f}"]
            rows.append(row)
    print_table(["template", "cam", "pieces", "before_bytes", "before_poles", "before_volume_rel_err", "before_ms",
                 "after_bytes", "after_poles", "after_volume_rel_err", "after_ms"], rows)


if __name__ == "__main__":
    main()
