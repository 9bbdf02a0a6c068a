"""report.html's figures: camgen.report.svgplot against matplotlib (Figure + savefig SVG).

The default scene's page draws 15 figures (3 cams x profile, curves, motion; the tricycle's
ride, error types and fits; the horse leg's paths, pressure angles and sweep).  This script
synthesises figures of the same layout with the same number of curves and points (recorded
from an instrumented `camgen run` of the default scene) and times drawing all 15 to SVG
strings: svgplot; matplotlib savefig(format="svg"); matplotlib with bbox_inches="tight" (what
report.html did: every figure drawn twice).  Also: the import time of each, in a fresh process.
Medians of repeated runs in one process.  Run:  python benchmarks/bench_report.py
"""
from __future__ import annotations

import io
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from _common import machine, median_time, print_table

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))


# --------------------------------------------------------------- backend-neutral figure specs

def _ring(n: int, r: float, wobble: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    t = np.linspace(0, 2 * math.pi, n)
    rr = r + wobble * np.sin(t) ** 2
    return rr * np.cos(t), rr * np.sin(t)


def _axes(**kw):
    base = {"lines": [], "hlines": [], "vlines": [], "equal": False, "title": None, "xlabel": None, "ylabel": None, "legend": None}
    base.update(kw)
    return base


def _line(x, y, **kw):
    return (np.asarray(x, float), np.asarray(y, float), kw)


def default_scene_figures() -> list[dict]:
    """15 figures with the default page's layout and point counts."""
    rng = np.random.default_rng(0)
    figs = []
    for cam, (n_profile, n_rho, pitch) in enumerate(((275, 1024, False), (208, 1024, False), (721, 1152, True))):
        lines = [_line(*_ring(n_profile, 60 + 10 * cam, 20), color="k", width=1.2, label="profile")]
        if pitch:
            lines.append(_line(*_ring(721, 75, 20), color="tab:blue", width=0.8, dash="--", label="pitch curve (roller centre)"))
        lines += [_line(*_ring(181, 10), color="tab:orange", width=0.8, label="bore"),
                  _line([-3, 3, 3, -3, -3], [9, 9, 12, 12, 9], color="tab:green", width=0.8, label="keyway")]
        if pitch:
            lines.append(_line(*(_ring(91, 12.7)[0] + 80, _ring(91, 12.7)[1]), color="tab:red", width=1.0, label="follower at cam angle 0"))
        else:
            lines += [_line([80, 80], [-60, 60], color="tab:red", width=1.0, label="follower face at cam angle 0"),
                      _line([-80, -80], [-60, 60], color="tab:red", width=1.0)]
        lines.append(_line([0], [0], color="k", marker="+", marker_size=10, dash="none"))
        figs.append({"figsize": (5.2, 5.2), "grid": (1, 1), "axes": [_axes(lines=lines, equal=True, xlabel="x (mm)", ylabel="y (mm)",
                                                                         title=f"cam{cam}: profile to scale (cam frame)", legend=("upper right", 7, 1))]})
        deg = np.linspace(0, 360, 900)
        rho_deg = np.sort(rng.uniform(0, 360, n_rho))
        figs.append({"figsize": (10, 3.2), "grid": (1, 2), "axes": [
            _axes(lines=[_line(deg, 25 * np.sin(np.radians(deg)), color="tab:blue", width=1)],
                  hlines=[(30, {"color": "tab:red", "dash": "--", "width": 0.8}), (-30, {"color": "tab:red", "dash": "--", "width": 0.8})],
                  xlabel="cam angle (deg)", ylabel="pressure angle (deg)", title=("pressure angle, limit dashed", 8)),
            _axes(lines=[_line(rho_deg, 60 + 40 * np.cos(np.radians(3 * rho_deg)), color="tab:blue", marker=".", marker_size=1.5, dash="none")],
                  hlines=[(6.0, {"color": "tab:red", "dash": "--", "width": 0.8}), (-6.0, {"color": "tab:red", "dash": "--", "width": 0.8})],
                  xlabel="cam angle (deg)", ylabel="radius of curvature (mm)", title=("radius of curvature; tool radius 6 mm dashed", 8))]})
        th = np.linspace(0, 360, 720)
        motion = []
        for k, label in enumerate(("displacement (mm)", "velocity (mm/rad)", "acceleration (mm/rad^2)", "jerk (mm/rad^3)")):
            motion.append(_axes(lines=[_line(th, 25 * np.sin(np.radians(th) + k) * 10**k, color="tab:purple", width=1)],
                                ylabel=(label, 8), xlabel="cam angle (deg)" if k >= 2 else None,
                                vlines=[(a, {"color": "tab:red", "width": 0.6, "dash": ":"}) for a in (60, 120, 180, 240, 300, 330)] if k == 3 and cam < 2 else []))
        figs.append({"figsize": (10, 4.2), "grid": (2, 2), "suptitle": (f"cam{cam}: follower motion per unit cam speed", 9), "axes": motion})
    # tricycle: ride, error types, fits
    x = np.linspace(0, 2000, 801)
    xr = np.linspace(0, 2000, 841)
    figs.append({"figsize": (10, 3.4), "grid": (1, 2), "axes": [
        _axes(lines=[_line(x, 200 * np.sin(np.pi * x / 1000), color="k", width=2.5, alpha=0.4, label="target y = f(x)"),
                     _line(xr, 200 * np.sin(np.pi * xr / 1000), color="tab:blue", width=1, label="ride simulation")],
              xlabel="x (mm)", ylabel="y (mm)", legend=("best", 7, 1), title=("drive wheel A: target and simulated path", 9)),
        _axes(lines=[_line(np.linspace(0, 360, 841), 1e-3 * np.sin(np.linspace(0, 20, 841)), width=1)],
              xlabel="cam angle (deg)", ylabel="lateral error (um)", title=("distance from the target path", 9))]})
    xs = np.linspace(0, 4000, 841)
    figs.append({"figsize": (10, 3.4), "grid": (1, 1), "axes": [
        _axes(lines=[_line(xs, 200 * np.sin(np.pi * xs / 1000) * (1 + 0.02 * k), width=1, label=f"type {k}") for k in range(5)],
              xlabel="x (mm)", ylabel="y (mm)", legend=("best", 7, 3), title=("error types over two periods", 9))]})
    fits = []
    for _ in range(2):
        xm, xf = np.linspace(0, 2000, 41), np.linspace(0, 2000, 400)
        fits.append(_axes(lines=[_line(xm, 200 * np.sin(np.pi * xm / 1000) + rng.normal(0, 3, 41), marker="o", marker_size=3, dash="none", label="measured"),
                                 _line(xf, 200 * np.sin(np.pi * xf / 1000), color="k", alpha=0.4, width=2, label="ideal"),
                                 _line(xf[1:], 199 * np.sin(np.pi * xf[1:] / 1000), color="tab:red", width=1, label="fitted model")],
                          xlabel="x (mm)", ylabel="y (mm)", legend=("best", 7, 1), title=("Table: rms residual 2.00 mm", 9)))
    figs.append({"figsize": (10, 3.4), "grid": (1, 2), "axes": fits})
    # horse leg: paths, pressure angles, sweep
    paths, bodies = [], []
    for k, (n_body, alpha) in enumerate(((2311, 12.5), (1325, 14.5), (771, 18.5))):
        paths.append(_line(*_ring(721, 300 + 10 * k, 60), width=1, color=f"C{k}", label=f"alpha1 = {alpha:g} deg"))
        t = np.linspace(0, 1, n_body)
        bodies.append(_line(300 * t, 5 * np.sin(7 * t) + k, width=1, color=f"C{k}", label=f"alpha1 = {alpha:g} deg"))
    figs.append({"figsize": (10, 4.6), "grid": (1, 2), "axes": [
        _axes(lines=paths, hlines=[(-420, {"color": "k", "width": 0.8, "dash": "--", "label": "ground line"})], equal=True,
              xlabel="x (mm)", ylabel="y (mm)", title=("leg end point W relative to the body", 9), legend=("best", 7, 1)),
        _axes(lines=bodies, xlabel="x (mm)", ylabel="y (mm)", title=("body (O1) during stance", 9), legend=("best", 7, 1))]})
    theta = np.linspace(0, 360, 720)
    sweep = [19.0 + 0.2 * k for k in range(19)]
    figs.append({"figsize": (10, 3.4), "grid": (1, 2), "axes": [
        _axes(lines=[_line(theta, 20 * np.sin(np.radians(theta)) + k, width=1, color=f"C{k}", label=f"alpha1 = {a} deg") for k, a in enumerate((12.5, 14.5, 18.5))],
              hlines=[(26, {"color": "tab:red", "dash": "--", "width": 0.8})], xlabel="stride-cam angle theta1 (deg)",
              ylabel="pressure angle (deg)", title=("stride-cam pressure angle", 9), legend=("best", 7, 1)),
        _axes(lines=[_line(np.arange(19) + 10.0, sweep, marker="o", marker_size=3, color="C0")],
              hlines=[(26, {"color": "tab:red", "dash": "--", "width": 0.8, "label": "limit"})], xlabel="inclination alpha1 (deg)",
              ylabel="max pressure angle (deg)", title=("inclination sweep", 9), legend=("best", 7, 1))]})
    cluster_w, cluster_p = [], []
    for k in range(19):
        cluster_w.append(_line(*_ring(721, 300 + k, 60), color="tab:green", width=0.7, alpha=0.8))
        cluster_p.append(_line(theta, 20 * np.sin(np.radians(theta)) + 0.2 * k, color="tab:green", width=0.7, alpha=0.8))
    figs.append({"figsize": (10, 4.2), "grid": (1, 2), "axes": [
        _axes(lines=cluster_w, hlines=[(-420, {"color": "k", "width": 0.8, "dash": "--"})], equal=True, xlabel="x (mm)", ylabel="y (mm)",
              title=("trajectory cluster over the sweep", 9)),
        _axes(lines=cluster_p, hlines=[(26, {"color": "tab:red", "dash": "--", "width": 0.8})], xlabel="stride-cam angle theta1 (deg)",
              ylabel="pressure angle (deg)", title=("pressure angle over the sweep", 9))]})
    assert len(figs) == 15
    return figs


def _pair(v):
    return v if isinstance(v, tuple) else (v, None)


# ------------------------------------------------------------------------------- backends

def draw_svgplot(figs: list[dict]) -> list[str]:
    from camgen.report.svgplot import Figure

    out = []
    for i, spec in enumerate(figs):
        fig = Figure(figsize=spec["figsize"], id_prefix=f"f{i}")
        axes = np.atleast_1d(fig.subplots(*spec["grid"])).ravel()
        if "suptitle" in spec:
            fig.suptitle(spec["suptitle"][0], font_size=spec["suptitle"][1])
        for ax, a in zip(axes, spec["axes"]):
            for x, y, kw in a["lines"]:
                ax.plot(x, y, **kw)
            for v, kw in a["hlines"]:
                ax.hline(v, **kw)
            for v, kw in a["vlines"]:
                ax.vline(v, **kw)
            if a["equal"]:
                ax.equal_aspect()
            for name in ("title", "xlabel", "ylabel"):
                if a[name]:
                    s, size = _pair(a[name])
                    getattr(ax, name)(s, font_size=size)
            if a["legend"]:
                loc, size, ncol = a["legend"]
                ax.legend(loc, font_size=size, ncol=ncol)
        out.append(fig.to_svg())
    return out


def _mpl_kw(kw: dict) -> dict:
    names = {"width": "lw", "dash": "ls", "marker_size": "ms"}
    return {names.get(k, k): v for k, v in kw.items()}


def draw_matplotlib(figs: list[dict], tight: bool) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    matplotlib.rcParams.update({"svg.hashsalt": "camgen", "svg.fonttype": "none", "font.size": 9, "axes.grid": True, "grid.alpha": 0.3})
    from matplotlib.figure import Figure

    out = []
    for spec in figs:
        fig = Figure(figsize=spec["figsize"])
        axes = np.atleast_1d(fig.subplots(*spec["grid"])).ravel()
        if "suptitle" in spec:
            fig.suptitle(spec["suptitle"][0], fontsize=spec["suptitle"][1])
        for ax, a in zip(axes, spec["axes"]):
            for x, y, kw in a["lines"]:
                ax.plot(x, y, **_mpl_kw(kw))
            for v, kw in a["hlines"]:
                ax.axhline(v, **_mpl_kw(kw))
            for v, kw in a["vlines"]:
                ax.axvline(v, **_mpl_kw(kw))
            if a["equal"]:
                ax.set_aspect("equal")
            for name in ("title", "xlabel", "ylabel"):
                if a[name]:
                    s, size = _pair(a[name])
                    getattr(ax, "set_" + name)(s, fontsize=size)
            if a["legend"]:
                loc, size, ncol = a["legend"]
                ax.legend(loc=loc, fontsize=size, ncol=ncol)
        buf = io.StringIO()
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": None}, **({"bbox_inches": "tight"} if tight else {}))
        out.append(buf.getvalue())
    return out


def import_time(module: str, repeats: int = 5) -> float:
    """Median wall time (s) of ``import module`` in a fresh interpreter, minus the bare start-up."""
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}

    def run(code: str) -> float:
        samples = []
        for _ in range(repeats):
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", code], check=True, env=env)
            samples.append(time.perf_counter() - start)
        return statistics.median(samples)

    return run(f"import numpy, {module}") - run("import numpy")


def main() -> None:
    figs = default_scene_figures()
    points = sum(x.size for f in figs for a in f["axes"] for x, _, _ in a["lines"])
    curves = sum(len(a["lines"]) for f in figs for a in f["axes"])
    print(f"report figures of the default scene (synthesised): {len(figs)} figures, {curves} curves, {points} points; {machine()}\n")
    rows = []
    t_svg = median_time(lambda: draw_svgplot(figs), repeats=15)
    t_mpl = median_time(lambda: draw_matplotlib(figs, tight=False), repeats=5)
    t_tight = median_time(lambda: draw_matplotlib(figs, tight=True), repeats=5)
    sizes = [sum(map(len, draw_svgplot(figs))), sum(map(len, draw_matplotlib(figs, False))), sum(map(len, draw_matplotlib(figs, True)))]
    imports = [import_time("camgen.report.svgplot"), import_time("matplotlib.figure")]
    for label, t, size, imp in (("svgplot", t_svg, sizes[0], imports[0]), ("matplotlib savefig svg", t_mpl, sizes[1], imports[1]),
                                ("matplotlib savefig svg, bbox_inches='tight'", t_tight, sizes[2], imports[1])):
        rows.append([label, f"{t * 1e3:.1f}", f"{t / t_svg:.1f}", f"{imp * 1e3:.0f}", f"{size / 1024:.0f}"])
    print_table(["backend", "15_figures_ms", "x_svgplot", "import_ms", "svg_kib"], rows)


if __name__ == "__main__":
    main()
