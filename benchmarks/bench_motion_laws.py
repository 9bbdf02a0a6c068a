"""camgen against the `mechanism` package on the same motion-law cam, in one run.

Run from the repository root: ``python benchmarks/bench_motion_laws.py``.
The case of shared/research/peers.md section 3 in millimetres: cycloidal rise 25.4 mm over
180 deg and fall over 180 deg, base radius 76.2 mm, roller radius 12.7 mm, radial translating
follower.  For each tool: the median time to make the profile from the motion description (law,
follower, profile in memory) and the ride error: the roller riding the profile (the independent
simulator tests/ride.py, on the exact curve where the tool gives one, else on its points)
against the required lift, at 720 cam angles between the tools' samples.

`mechanism` (PyPI, MIT) is installed by hand for this run (``pip install mechanism``); it is not
a camgen dependency and the script says so when it is missing.
"""
from __future__ import annotations

import importlib.metadata
import math

import _common  # noqa: F401  (shared helpers: median_time, print_table)
import numpy as np
from _common import machine, median_time, orientations, print_table

from camgen.synthesis.followers import DEFAULT_FIT_TOL, FollowerSpec, cam_envelope
from camgen.synthesis.laws import MotionProgram, Segment
import ride  # tests/ride.py (on the path through _common)

BASE, ROLLER, LIFT = 76.2, 12.7, 25.4
N = 3600  # mechanism's samples per turn
THETA = np.linspace(0.0, 2.0 * math.pi, 720, endpoint=False) + math.radians(0.05)


def required(theta: np.ndarray) -> np.ndarray:
    """Roller-centre height of the radial follower: Rb + r + s, the cycloidal law written out here."""
    t = np.mod(theta, 2.0 * math.pi)
    rise = LIFT * (t / math.pi - np.sin(2.0 * t) / (2.0 * math.pi))
    fall = LIFT * (1.0 - ((t - math.pi) / math.pi - np.sin(2.0 * (t - math.pi)) / (2.0 * math.pi)))
    return BASE + ROLLER + np.where(t < math.pi, rise, fall)


def camgen_profile():
    """From the motion description to the exact envelope (camgen.synthesis: laws, followers)."""
    program = MotionProgram([Segment("cycloidal", math.pi, LIFT), Segment("cycloidal", math.pi, -LIFT)])
    return cam_envelope(FollowerSpec("roller", BASE, roller_radius=ROLLER), program).profile


def best_reading(points: np.ndarray) -> float:
    """Ride error of a polygon from a tool whose rotation sense and angle origin may differ from
    camgen's: the smallest over its readings (the right reading is far better)."""
    return min(float(np.max(np.abs(ride.translating_roller(p, THETA, 0.0, ROLLER) - required(THETA))))
               for p in orientations(points))


def main() -> None:
    print(f"machine: {machine()}")
    rows = []
    t_camgen = median_time(camgen_profile, repeats=21)
    profile = camgen_profile()
    e_camgen = float(np.max(np.abs(ride.translating_roller(profile, THETA, 0.0, ROLLER) - required(THETA))))
    pieces = sum(seg.n_pieces for seg in profile.segments)
    import camgen

    rows.append([f"camgen {camgen.__version__}: exact envelope "
                 f"(quintic spline, {pieces} pieces, fit_tol {DEFAULT_FIT_TOL:g} mm)", f"{t_camgen * 1e3:.3f}", f"{e_camgen:.2e}"])
    # the same exact envelope as N points at uniform cam angles, ridden as a polygon like the peer's points
    params = np.linspace(0.0, profile.n_segments, N, endpoint=False)
    e_points = float(np.max(np.abs(ride.translating_roller(profile.evaluate(params), THETA, 0.0, ROLLER) - required(THETA))))
    rows.append([f"camgen: the same profile as {N} points (polygon ride)", "-", f"{e_points:.2e}"])
    try:
        import matplotlib

        matplotlib.use("Agg")
        from mechanism import Cam
    except ImportError:
        rows.append(["mechanism (PyPI): not installed (pip install mechanism)", "-", "-"])
        print_table(["tool", "profile_ms", "max_ride_error_mm"], rows)
        return

    def peer() -> np.ndarray:
        cam = Cam(motion=[("Rise", LIFT, 180), ("Fall", LIFT, 180)], degrees=True, omega=2 * math.pi, rotation="cw", h=2 * math.pi / N)
        x, y = cam.cycloidal.get_profile(BASE, cam.thetas_r)
        return np.column_stack([x, y])

    t_peer = median_time(peer, repeats=21)
    e_peer = best_reading(peer())
    rows.append([f"mechanism {importlib.metadata.version('mechanism')}: Cam() + get_profile ({N} points)",
                 f"{t_peer * 1e3:.3f}", f"{e_peer:.2e}"])
    print_table(["tool", "profile_ms", "max_ride_error_mm"], rows)
    print()
    print_table(["ratio", "value"], [["time camgen / mechanism", f"{t_camgen / t_peer:.2f}"],
                                     ["ride error mechanism / camgen", f"{e_peer / e_camgen:.3g}"]])


if __name__ == "__main__":
    main()
