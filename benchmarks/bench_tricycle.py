"""Tricycle steering cam: N x curvature scheme -> synthesis time, ride time, max path error.

Run from the repository root: ``python benchmarks/bench_tricycle.py``.
Path error: largest lateral distance of the drive wheel's simulated path (on the cam as made)
from the target y = 202.4396 sin(pi x / 1000), over 1 and 10 periods.
Target (issue #3): exact curvature <= 1e-6 mm over one period at N = 720, synthesis + ride <= 5 ms.
"""
from __future__ import annotations

import _common  # noqa: F401  (shared helpers: median_time, print_table)
import numpy as np
from _common import median_time, print_table

from camgen.mechanisms import tricycle as tc
from camgen.synthesis.trajectory import trajectory_from_expression


def main() -> None:
    traj = trajectory_from_expression("202.4396*sin(pi*x/1000)", 2000.0)
    rows = []
    for scheme in ("forward", "central", "exact"):
        for n in (90, 180, 360, 720, 1440, 2880, 5760):
            cam = tc.tricycle_cam(traj, n_samples=n, scheme=scheme)
            synth = median_time(lambda: tc.tricycle_cam(traj, n_samples=n, scheme=scheme), repeats=11)
            ride_t = median_time(lambda: tc.simulate_cam(cam), repeats=11)
            one = tc.simulate_cam(cam)
            ten = tc.simulate_cam(cam, periods=10)
            e1 = np.max(np.abs(tc.lateral_error(traj, one.x, one.y)))
            e10 = np.max(np.abs(tc.lateral_error(traj, ten.x, ten.y)))
            rows.append([scheme, n, f"{synth * 1e3:.2f}", f"{ride_t * 1e3:.2f}", f"{(synth + ride_t) * 1e3:.2f}", f"{e1:.3e}", f"{e10:.3e}"])
    print_table(["scheme", "N", "synthesis_ms", "ride_ms", "total_ms", "max_error_1_period_mm", "max_error_10_periods_mm"], rows)
    fits(traj)


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
