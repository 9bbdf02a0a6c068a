"""Tricycle steering cam: spline form x curvature scheme x N -> synthesis time, ride time, ride error.

Run from the repository root: ``python benchmarks/bench_tricycle.py``.
Path error: largest lateral distance of the drive wheel's simulated path (on the cam as made)
from the target y = 202.4396 sin(pi x / 1000), over 1 and 10 periods.

Spline forms (:func:`camgen.mechanisms.tricycle.tricycle_cam`): ``cartesian`` (the earlier form:
a parametric C2 cubic through the sample points, offset refitted as C1 Hermite cubics) and
``polar`` (the default: a periodic quintic rho(phi) through the samples, its exact pitch and
profile fitted by least-squares C2 cubics within fit_tol = 1e-9 mm).
Targets (issue "Accuracy and numerical stability"): at N = 720 the ride error <= 2e-8 mm over one
period and <= 1e-6 mm over ten; the convergence order stated and measured.
"""
from __future__ import annotations

import _common  # noqa: F401  (shared helpers: median_time, print_table)
import numpy as np
from _common import median_time, print_table

from camgen.mechanisms import tricycle as tc
from camgen.synthesis.trajectory import trajectory_from_expression

NS = (90, 180, 360, 720, 1440, 2880, 5760)


def _errors(traj, cam) -> tuple[float, float]:
    one = tc.simulate_cam(cam)
    ten = tc.simulate_cam(cam, periods=10)
    return (float(np.max(np.abs(tc.lateral_error(traj, one.x, one.y)))), float(np.max(np.abs(tc.lateral_error(traj, ten.x, ten.y)))))


def main() -> None:
    traj = trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0)
    rows = []
    for scheme in ("exact", "central", "forward"):
        for n in NS:
            for form in ("cartesian", "polar"):
                cam = tc.tricycle_cam(traj, n_samples=n, scheme=scheme, form=form)
                synth = median_time(lambda: tc.tricycle_cam(traj, n_samples=n, scheme=scheme, form=form), repeats=7)
                ride_t = median_time(lambda: tc.simulate_cam(cam), repeats=7)
                e1, e10 = _errors(traj, cam)
                rows.append([scheme, n, form, cam.profile.segments[0].n_pieces, f"{synth * 1e3:.2f}", f"{ride_t * 1e3:.2f}",
                             f"{(synth + ride_t) * 1e3:.2f}", f"{e1:.3e}", f"{e10:.3e}"])
    print_table(["scheme", "N", "form", "pieces", "synthesis_ms", "ride_ms", "total_ms", "max_error_1_period_mm",
                 "max_error_10_periods_mm"], rows)
    convergence(traj)
    fits(traj)


def convergence(traj) -> None:
    """Ride error against N and the fitted slope (exact curvature), the representation far below
    the interpolation error (cartesian: offset_tol 1e-11 mm; polar: fit_tol 1e-11 / 1e-9 mm)."""
    cases = [
        ("cartesian", {"form": "cartesian", "offset_tol": 1e-11}, (90, 180, 360, 720)),
        ("polar, cubic rho", {"rho_degree": 3, "fit_tol": 1e-9}, (90, 180, 360, 720)),
        ("polar, quintic rho", {"rho_degree": 5, "fit_tol": 1e-11}, (45, 64, 90, 128)),
    ]
    rows = []
    for name, kw, ns in cases:
        errors = np.array([_errors(traj, tc.tricycle_cam(traj, n_samples=n, **kw))[0] for n in ns])
        slope = -np.polyfit(np.log(ns), np.log(errors), 1)[0]
        rows.append([name, " ".join(str(n) for n in ns), " ".join(f"{e:.2e}" for e in errors), f"{slope:.2f}"])
    print("\nConvergence of the one-period ride error (exact curvature): fitted slope of log error against log N\n")
    print_table(["form", "N", "max_error_1_period_mm", "order"], rows)


def fits(traj) -> None:
    """The error-model fit: one start (default) against six starts, on Tables A1 and A2."""
    from camgen.mechanisms.tricycle_fit import PARAMETERS, fit_error_model

    cam = tc.tricycle_cam(traj)
    rows = []
    for name in ("A1", "A2"):
        table = tc.load_measured_table(name)
        one, every = fit_error_model(cam, table), fit_error_model(cam, table, starts="all")
        t_one = median_time(lambda: fit_error_model(cam, table), repeats=5)
        t_all = median_time(lambda: fit_error_model(cam, table, starts="all"), repeats=5)
        worst = 0.0
        for key in PARAMETERS:
            diff = abs(one.values[key] - every.values[key])
            diff = min(diff, 360.0 - diff) if key == "start_phase_deg" else diff
            worst = max(worst, diff / every.uncertainty[key])
        rows.append([name, f"{t_one * 1e3:.0f}", f"{t_all * 1e3:.0f}", f"{t_all / t_one:.1f}", f"{worst:.2e}",
                     f"{one.residual_rms_mm:.6f}", f"{every.residual_rms_mm:.6f}"])
    print("\nError-model fit: one start against six (difference of the parameters in units of their 1-sigma uncertainty)\n")
    print_table(["table", "one_start_ms", "six_starts_ms", "ratio", "max_diff_sigma", "rms_one_mm", "rms_six_mm"], rows)


if __name__ == "__main__":
    main()
