"""Peers side by side: a roller follower riding the cam each tool exports, in one run.

Run from the repository root: ``python benchmarks/bench_peers.py``.
The case of shared/research/peers.md section 3 in millimetres: cycloidal rise 25.4 mm over
180 deg and fall over 180 deg, base radius 76.2 mm, roller radius 12.7 mm, radial translating
follower.  Accuracy: the roller's lift on the exported profile (brute force over the polygon's
vertices and edges, at cam angles between the tools' samples) against the required motion.

What each timed call computes, from the motion description to the profile in memory:

* camgen (``cam_envelope``): the undercut, cusp and axis checks (the law on the 1 deg coarse grid
  plus every break and its neighbours; the pitch curve's curvature, speed and height there, each
  extrapolated by its largest slope, must stay 10% clear of its limit, else the dense 0.05 deg
  check runs; the dense kinematics, ``CamEnvelope.data``, are made when a report asks), then the
  exact envelope as two C2 quintic splines (pitch curve and profile), each verified within
  ``fit_tol`` = 1e-7 mm at three probes per piece.
* mechanism (PyPI, MIT; ``pip install mechanism`` -- not a camgen dependency, skipped when
  missing): ``Cam()`` tabulates S, V, A, J of its three motion families at 3600 angles and
  ``get_profile`` exports ``r = Rb + s`` at every angle (no envelope, no checks).
* the radial shortcut ``r = Rb + s`` computed with numpy (what mechanism and MOTUS NOVA's
  "Approximate" profile export): a floor for the time of any polygon of 3600 points.
"""
from __future__ import annotations

import math

import _common  # noqa: F401  (shared helpers: median_time, print_table)
import numpy as np
from _common import median_time, orientations, print_table

from camgen.synthesis.followers import DEFAULT_FIT_TOL, FollowerSpec, cam_envelope
from camgen.synthesis.laws import MotionProgram, Segment

BASE, ROLLER, LIFT = 76.2, 12.7, 25.4
N = 3600


def motion(theta: np.ndarray) -> np.ndarray:
    t = np.mod(theta, 2 * math.pi)
    rise = LIFT * (t / math.pi - np.sin(2 * t) / (2 * math.pi))
    fall = LIFT * (1 - ((t - math.pi) / math.pi - np.sin(2 * (t - math.pi)) / (2 * math.pi)))
    return np.where(t < math.pi, rise, fall)


def roller_lift(points: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Lift of a radial roller along +y riding the closed counter-clockwise polygon ``points``
    turned by ``theta`` (CCW): the highest roller centre on the axis x = 0 touching a vertex or
    the inside of an edge (between vertices the roller rests on the chord, not on a vertex)."""
    out = np.empty(theta.size)
    for k, t in enumerate(theta):  # brute-force reference, per angle on purpose
        c, s = math.cos(t), math.sin(t)
        x = c * points[:, 0] - s * points[:, 1]
        y = s * points[:, 0] + c * points[:, 1]
        near = np.abs(x) <= ROLLER
        best = np.max(y[near] + np.sqrt(ROLLER**2 - x[near] ** 2))
        # edge i -> i + 1 with outward normal n = (dy, -dx) / L: centre F + r n on x = 0, F on the edge
        dx, dy = np.roll(x, -1) - x, np.roll(y, -1) - y
        length = np.hypot(dx, dy)
        nx, ny = dy / length, -dx / length
        with np.errstate(divide="ignore", invalid="ignore"):
            lam = (-ROLLER * nx - x) / dx
        ok = (ny > 0) & (lam >= 0) & (lam <= 1)
        if ok.any():
            best = max(best, float(np.max(y[ok] + lam[ok] * dy[ok] + ROLLER * ny[ok])))
        out[k] = best
    return out


def ride_error(points: np.ndarray) -> float:
    theta = np.linspace(0, 2 * math.pi, 720, endpoint=False) + math.radians(0.05)
    wanted = BASE + ROLLER + motion(theta)
    # a tool may use another sense of rotation or angle origin: take its best reading
    best = math.inf
    for p in orientations(points):
        best = min(best, float(np.max(np.abs(roller_lift(p, theta[::8]) - wanted[::8]))))
        if best < 1.0:  # the right reading: measure it at every angle
            return float(np.max(np.abs(roller_lift(p, theta) - wanted)))
    return best


def program() -> MotionProgram:
    return MotionProgram([Segment("cycloidal", math.pi, LIFT), Segment("cycloidal", math.pi, -LIFT)])


def camgen_profile():
    """The exact envelope (camgen.synthesis.followers) of the motion program (camgen.synthesis.laws)."""
    return cam_envelope(FollowerSpec("roller", BASE, roller_radius=ROLLER), program()).profile


def main() -> None:
    rows = []
    seconds = median_time(camgen_profile, repeats=7)
    profile = camgen_profile()
    # the ride is measured on a 1e-7 mm polygon of the exported curve (vertices on the curve, chords within 1e-7 mm)
    pieces = sum(seg.n_pieces for seg in profile.segments)
    label = "camgen cam_envelope: undercut, cusp and axis checks + pitch and profile quintic splines"
    rows.append([f"{label} ({pieces} pieces, {DEFAULT_FIT_TOL:g} mm)", f"{seconds * 1e3:.2f}", f"{ride_error(profile.flatten(1e-7)):.2e}"])

    theta = 2 * math.pi * np.arange(N) / N  # radial shortcut: radius Rb + s at the polar angle of the follower
    def shortcut() -> np.ndarray:
        r = BASE + motion(-theta)
        return np.stack([r * np.cos(theta + math.pi / 2), r * np.sin(theta + math.pi / 2)], axis=1)
    seconds = median_time(shortcut, repeats=7)
    rows.append([f"radial shortcut r = Rb + s ({N} points, numpy)", f"{seconds * 1e3:.2f}", f"{ride_error(shortcut()):.2e}"])

    try:
        import matplotlib

        matplotlib.use("Agg")
        from mechanism import Cam
    except ImportError:
        rows.append(["mechanism (PyPI)", "not installed", "-"])
    else:
        def peer() -> np.ndarray:
            cam = Cam(motion=[("Rise", LIFT, 180), ("Fall", LIFT, 180)], degrees=True, omega=2 * math.pi, rotation="cw", h=2 * math.pi / N)
            x, y = cam.cycloidal.get_profile(BASE, cam.thetas_r)
            return np.column_stack([x, y])
        seconds = median_time(peer, repeats=5, min_total=0.0)
        rows.append([f"mechanism {__import__('importlib.metadata').metadata.version('mechanism')} Cam() + get_profile: r = Rb + s ({N} points)",
                     f"{seconds * 1e3:.2f}", f"{ride_error(peer()):.2e}"])
    print_table(["tool", "profile_ms", "max_roller_ride_error_mm"], rows)
    if len(rows) == 3 and rows[2][2] != "-":
        print(f"\ncamgen / mechanism in this run: time {float(rows[0][1]) / float(rows[2][1]):.2f}, "
              f"ride error {float(rows[0][2]) / float(rows[2][2]):.1e}")


if __name__ == "__main__":
    main()
