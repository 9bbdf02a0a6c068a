"""Horse leg: full cycle at 3600 positions, vectorised solver against a per-angle Newton loop.

Run from the repository root: ``python benchmarks/bench_horse_leg.py``.
The per-angle loop is the paper's method (Section 4: "using the Newton iteration method" at
every input angle): each loop solved by Newton's method from the previous angle's solution,
one position after another.  Target (issue #4): <= 15 ms for 3600 positions.
"""
from __future__ import annotations

import math

import _common  # noqa: F401  (shared helpers: median_time, print_table)
import numpy as np
from _common import median_time, print_table

from camgen.mechanisms import horse_leg as hl


def per_angle_loop(leg: hl.HorseLeg, alpha1: float, theta1: np.ndarray, cams) -> np.ndarray:
    """Foot path W by scalar Newton iterations, position by position (the paper's approach)."""
    stride, height = cams
    first = hl.solve_leg(leg, alpha1, theta1[:2], cams=cams)  # start values of every loop
    psi, theta4, psi4, theta8, length = first.psi[0], first.theta4[0], first.psi4[0], first.theta8[0], first.slider[0]
    o4, o5, o6 = leg.point("o4"), leg.point("o5"), leg.point("o6")
    out = np.empty((theta1.size, 2))
    for i, t in enumerate(theta1):
        tt = np.array([t])
        for _ in range(30):  # stride loop, eq. (5) + (8) reduced to F(psi) = 0
            f, df, *_ = hl._stride_residual(leg, stride, np.array([psi]), tt, alpha1)
            step = f[0] / df[0]
            psi -= step
            if abs(step) < 1e-13:
                break
        _, _, q, r, _, _ = hl._stride_residual(leg, stride, np.array([psi]), tt, alpha1, derivative=False)
        theta6 = math.atan2(r[0, 1] - o6[1], r[0, 0] - o6[0])
        a = leg.r1 * np.array([math.cos(t + leg.gamma1), math.sin(t + leg.gamma1)])
        for _ in range(30):  # four-bar, eq. (11): |O4 + r4 e^{j(theta4+gamma4)} - A| = r_AB
            b = o4 + leg.r4 * np.array([math.cos(theta4 + leg.gamma4), math.sin(theta4 + leg.gamma4)])
            g = (b - a) @ (b - a) - leg.r_ab**2
            dg = 2 * (b - a) @ (leg.r4 * np.array([-math.sin(theta4 + leg.gamma4), math.cos(theta4 + leg.gamma4)]))
            theta4 -= g / dg
            if abs(g / dg) < 1e-13:
                break
        for _ in range(30):  # lifting loop, eq. (14) projected on the fork normal
            h, dh, _ = height.support_derivatives(np.array([psi4 - theta4]))
            n = np.array([math.cos(psi4), math.sin(psi4)])
            g = n @ (o5 - o4) - h[0] + leg.e5
            dg = np.array([-math.sin(psi4), math.cos(psi4)]) @ (o5 - o4) - dh[0]
            psi4 -= g / dg
            if abs(g / dg) < 1e-13:
                break
        theta5 = 1.5 * math.pi + psi4 - leg.gamma5
        s = o5 + leg.r5 * np.array([math.cos(theta5), math.sin(theta5)])
        tp = o6 + leg.r7 * np.array([math.cos(theta6 + leg.gamma6), math.sin(theta6 + leg.gamma6)])
        for _ in range(30):  # leg loop, eq. (17): two unknowns theta8, l
            e8 = np.array([math.cos(theta8), math.sin(theta8)])
            eu = np.array([math.cos(leg.theta_u + theta8 - math.pi), math.sin(leg.theta_u + theta8 - math.pi)])
            res = tp + leg.r8 * e8 + length * eu - s
            jac = np.column_stack([leg.r8 * np.array([-e8[1], e8[0]]) + length * np.array([-eu[1], eu[0]]), eu])
            step = np.linalg.solve(jac, res)
            theta8, length = theta8 - step[0], length - step[1]
            if np.max(np.abs(step)) < 1e-12:
                break
        u = tp + leg.r8 * np.array([math.cos(theta8), math.sin(theta8)])
        out[i] = u + leg.s8 * np.array([math.cos(math.pi + theta8 - leg.theta_p), math.sin(math.pi + theta8 - leg.theta_p)])
    return out


def main() -> None:
    leg = hl.HorseLeg()
    cams = hl.leg_cams(leg)
    theta1 = hl.cycle(3600)
    rows = []
    for alpha_deg in (12.5, 14.5, 18.5):
        alpha = math.radians(alpha_deg)
        vec = median_time(lambda: hl.solve_leg(leg, alpha, theta1, cams=cams), repeats=11)
        loop = median_time(lambda: per_angle_loop(leg, alpha, theta1, cams), repeats=3, min_total=0.0)
        w_vec = hl.solve_leg(leg, alpha, theta1, cams=cams).w
        w_loop = per_angle_loop(leg, alpha, theta1, cams)
        diff = float(np.max(np.linalg.norm(w_vec - w_loop, axis=1)))
        rows.append([alpha_deg, 3600, f"{vec * 1e3:.2f}", f"{loop * 1e3:.1f}", f"{loop / vec:.0f}", f"{diff:.2e}"])
    print_table(["alpha1_deg", "positions", "vectorised_ms", "per_angle_loop_ms", "speed-up", "max_|W_vec - W_loop|_mm"], rows)


if __name__ == "__main__":
    main()
