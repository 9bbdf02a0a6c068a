"""Scaling: time (median of repeats) against point count, with the fitted exponent.

Run from the repository root: ``python benchmarks/bench_scaling.py`` (about 3 minutes).

For each operation the size N runs from 1e3 to 1e5 and the exponent is the slope of a
least-squares line through (log N, log time).  What N counts:

* flatten, mesh: points of the flattened stride-length cam (six exact arcs; the chord
  tolerance is chosen to give N points); mesh: ``cam_solid`` with bore 20 mm and a 6 x 2.8
  keyway, the linear-time ring fill against manifold3d's triangulation (the previous mesh, run
  up to 3e4 points: it takes about 40 s per cam at 1e5);
* offset: knots of a periodic spline r = 40 + 8 cos(3 theta) (non-convex: the offset checks
  itself for crossings); self-intersection: chords of the offset's check, x sweep against the
  all-pairs scan of before (up to 3e4 chords);
* DXF: knots of the same spline written as an exact B-spline (``contour_to_dxf``);
* G-code: G1 moves of a 720-knot trefoil milled in "lines" mode at 2 um, scaled up for N;
* evaluate, polar_radius: parameters / rays on the tricycle steering cam as 572 arcs
  (``to_arc_spline`` within 1e-6 mm) and on the 720-piece steering spline; the per-segment
  loop and the rays x pieces table of before run alongside (the latter up to 1e4 rays; its
  peak memory is listed).
"""
from __future__ import annotations

import math
import tracemalloc

import _common  # noqa: F401  (shared helpers: median_time, print_table)
import numpy as np
from _common import machine, median_time, print_table

import camgen
from camgen.body import BodySpec
from camgen.contour import Contour, Spline

SIZES = (1000, 3000, 10000, 30000, 100000)
#: Chord tolerance of the G-code runs (mm); N grows with the size of the cam instead.
GCODE_TOL = 2e-3


def exponent(sizes: list[int], seconds: list[float]) -> float:
    """Slope of the least-squares line through (log N, log t)."""
    return float(np.polyfit(np.log(sizes), np.log(seconds), 1)[0])


def tol_for_points(contour: Contour, points: int, tol0: float = 1e-3) -> float:
    """Chord tolerance giving about ``points`` vertices (the count goes as tol^-1/2)."""
    tol = tol0 * (len(contour.flatten(tol0)) / points) ** 2
    return tol * (len(contour.flatten(tol)) / points) ** 2


def trefoil(knots: int, scale: float = 1.0) -> Contour:
    theta = np.linspace(0.0, 2 * math.pi, knots + 1)
    r = scale * (40.0 + 8.0 * np.cos(3.0 * theta))
    return Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])


def old_dispatch(contour: Contour, t: np.ndarray) -> np.ndarray:
    """Contour.evaluate as it was: one mask per segment."""
    flat = np.mod(t, contour.n_segments)
    idx = np.minimum(np.floor(flat).astype(int), contour.n_segments - 1)
    u = flat - idx
    out = np.empty((flat.size, 2))
    for i, seg in enumerate(contour.segments):
        mask = idx == i
        if mask.any():
            out[mask] = seg.point(u[mask])
    return out


def old_self_intersection(a: np.ndarray, block: int = 512) -> np.ndarray | None:
    """Contour.self_intersection's all-pairs scan as it was (on a flattened polygon)."""
    b = np.roll(a, -1, axis=0)
    n = len(a)
    d = b - a
    for lo in range(0, n, block):
        i = np.arange(lo, min(lo + block, n))[:, None]
        j = np.arange(n)[None, :]
        ai, di = a[i[:, 0]][:, None, :], d[i[:, 0]][:, None, :]
        aj, dj = a[None], d[None]

        def cross(u, v):
            return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

        hit = (cross(di, aj - ai) * cross(di, aj + dj - ai) < 0) & (cross(dj, ai - aj) * cross(dj, ai + di - aj) < 0)
        hit &= (np.abs(i - j) > 1) & (np.abs(i - j) < n - 1)
        if hit.any():
            k, m = np.argwhere(hit)[0]
            return a[i[k, 0]]
    return None


def peak_mb(func) -> float:
    tracemalloc.start()
    func()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak / 1e6


def timed(func, size: int) -> float:
    return median_time(func, repeats=5 if size <= 10000 else 3, min_total=0.02)


def main() -> None:
    from camgen.contour.arcspline import to_arc_spline
    from camgen.export.dxf import DxfOptions, contour_to_dxf
    from camgen.export.gcode import MachiningSpec, gcode_program
    from camgen.export.solid import cam_solid
    from camgen.mechanisms import tricycle as tc
    from camgen.synthesis.trajectory import trajectory_from_expression

    print(f"Machine: {machine()}\n")
    stride = camgen.three_arc_cam(220.0, 160.0, 25.0)
    body = BodySpec(20.0, 20.0, 6.0, 2.8, min_wall=3.0)
    steering = tc.tricycle_cam(trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0)).profile
    arcs = to_arc_spline(steering, 1e-6)
    gear = trefoil(720)  # G-code: scaled per N
    results: dict[str, tuple[list[int], list[float]]] = {}
    rows = []

    def record(name: str, size: int, seconds: float, note: str = "") -> None:
        results.setdefault(name, ([], []))
        results[name][0].append(size)
        results[name][1].append(seconds)
        rows.append([name, size, f"{seconds * 1e3:.2f}", note])

    for n in SIZES:
        tol = tol_for_points(stride, n)
        points = len(stride.flatten(tol))
        record("flatten (stride, arcs)", points, timed(lambda: stride.flatten(tol), n))
        solid = cam_solid(stride, body, tol)
        record("mesh: ring fill + manifold3d check", points, timed(lambda: cam_solid(stride, body, tol), n), f"{len(solid.triangles)} triangles")
        if n <= 30000:
            old = cam_solid(stride, body, tol, fill="manifold")
            record("mesh: manifold3d triangulation (before)", points, median_time(lambda: cam_solid(stride, body, tol, fill="manifold"), repeats=3 if n <= 3000 else 1, min_total=0.0), f"{len(old.triangles)} triangles")

        spline = trefoil(n)
        record("offset -2 mm (spline, with crossing check)", n, timed(lambda: spline.offset(-2.0), n))
        check = spline.offset(-2.0).flatten(max(1e-6, 1e-6 * spline.size))
        inner = spline.offset(-2.0)
        record("self_intersection: x sweep", len(check), timed(lambda: inner.self_intersection(), n))
        if len(check) <= 30000:
            record("self_intersection: all pairs (before)", len(check), median_time(lambda: old_self_intersection(check), repeats=1, min_total=0.0))
        record("DXF (exact B-spline)", n, timed(lambda: contour_to_dxf(spline, options=DxfOptions("bspline")), n))
        grow = (n / len(gear.flatten(GCODE_TOL))) ** 2  # points go as sqrt(size) at one tolerance
        big = trefoil(720, grow)
        spec = MachiningSpec(thickness=10.0, step_down=10.0, chord_tol=GCODE_TOL, spline_mode="lines")
        record("G-code (lines, one pass)", len(big.flatten(GCODE_TOL)), timed(lambda: gcode_program(big, spec), n), f"trefoil x {grow:.3g}")

        t = np.linspace(0.0, arcs.n_segments, n, endpoint=False) + 0.37
        record("evaluate: 572 arcs", n, timed(lambda: arcs.evaluate(t), n))
        record("evaluate: 572 arcs, one mask per segment (before)", n, timed(lambda: old_dispatch(arcs, t), n))
        record("evaluate: 720-piece spline", n, timed(lambda: steering.evaluate(t / arcs.n_segments), n))
        phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False) + 1e-3
        arcs.polar_radius(phi[:3])
        record("polar_radius: 572 arcs", n, timed(lambda: arcs.polar_radius(phi), n), f"peak {peak_mb(lambda: arcs.polar_radius(phi)):.1f} MB")
        record("polar_radius: 720-piece spline", n, timed(lambda: steering.polar_radius(phi), n), f"peak {peak_mb(lambda: steering.polar_radius(phi)):.1f} MB")
        if n <= 10000:
            record("polar_radius: 572 arcs, rays x pieces (before)", n, median_time(lambda: arcs._polar_radius_all_pieces(phi), repeats=1, min_total=0.0),
                   f"peak {peak_mb(lambda: arcs._polar_radius_all_pieces(phi)):.1f} MB")
        print(f"... N = {n} done", flush=True)

    print()
    print_table(["operation", "N", "time_ms", "note"], rows)
    print()
    summary = []
    for name, (sizes, seconds) in results.items():
        at = {s: t for s, t in zip(sizes, seconds)}
        largest = max(sizes)
        summary.append([name, f"{min(sizes)}..{largest}", f"{exponent(sizes, seconds):.2f}", f"{at[largest] * 1e3:.1f} ms at {largest}"])
    print_table(["operation", "N range", "fitted exponent", "largest"], summary)


if __name__ == "__main__":
    main()
