"""The joints of a closed chain of splines of one degree in Python floats (:meth:`Contour.joints
<camgen.contour.Contour.joints>`, which a disk cam's continuity check calls per design on a
handful of splines).

The values are those of :func:`camgen.contour.ends.spline_end_values` (on the contour's tables)
and the joint loop of :meth:`Contour.joints <camgen.contour.Contour.joints>` to the last bit: every product and sum of
the Horner steps is one IEEE operation in the same order (Python floats round as numpy's
elementwise float64 arithmetic does); what numpy computes otherwise stays numpy's: the speeds
(``np.hypot``, libm's) and their cubes and the curvatures' quotients on one array each, the gaps
by one ``np.hypot``, and each joint's tangent dot product by ``@`` on two rows (BLAS's ``ddot``,
which may fuse the multiply and add).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Sequence

import numpy as np

from camgen.numerics.polynomial import derivative_factors

if TYPE_CHECKING:
    from camgen.contour.spline import Spline

__all__ = ["JointValues", "spline_joint_values"]

#: A joint's end point (x, y), mm, gap (mm), tangent angle (rad) and curvature jump (1/mm).
JointValues = tuple[tuple[float, float], float, float, float]


def spline_joint_values(splines: "Sequence[Spline]") -> list[JointValues] | None:
    """Per joint ``i`` (the end of spline ``i`` -> the start of spline ``i + 1``, cyclic): its
    end point, gap, tangent angle and curvature jump (:data:`JointValues`); None when the
    splines have two degrees or an end is not on its end piece (the general path then)."""
    degree = splines[0].degree
    if any(s.degree != degree for s in splines):
        return None
    f1, f2 = derivative_factors(degree, 1).tolist(), derivative_factors(degree, 2).tolist()
    d1x: list[float] = []
    d1y: list[float] = []
    crosses: list[float] = []
    spans: list[float] = []
    ends: list[tuple[float, float]] = []
    starts: list[tuple[float, float]] = []
    for s in splines:
        b = s.breaks
        t0, b_last, b_end = float(b[0]), float(b[-2]), float(b[-1])
        span = b_end - t0  # Spline.span
        t_first, t_last = t0 + 0.0 * span, t0 + 1.0 * span  # Spline._t(0), Spline._t(1)
        if not (t_first == t0 and t_last >= b_last):
            return None
        spans.append(span)
        rows = s.coeffs[:, [0, -1]].tolist()  # (degree + 1, 2 [first, last piece], 2)
        for k, tau in ((0, t_first - t0), (1, t_last - b_last)):
            (ax, ay) = rows[0][k]
            # the first and second derivatives' Horner steps (ends._first_second, horner's order 1 and 2)
            px, py = ax * f1[0], ay * f1[0]
            qx, qy = ax * f2[0], ay * f2[0]
            for m in range(1, degree - 1):
                cx, cy = rows[m][k]
                px, py = px * tau + cx * f1[m], py * tau + cy * f1[m]
                qx, qy = qx * tau + cx * f2[m], qy * tau + cy * f2[m]
            cx, cy = rows[degree - 1][k]
            px, py = px * tau + cx * f1[degree - 1], py * tau + cy * f1[degree - 1]
            d1x.append(px)
            d1y.append(py)
            crosses.append(px * qy - py * qx)  # geometry.cross
        # the start point (Spline.start_point) and the end point (Spline.end_point: Horner at the last piece's end)
        starts.append((rows[degree][0][0], rows[degree][0][1]))
        (x, y) = rows[0][1]
        tau_end = b_end - b_last
        for m in range(1, degree + 1):
            x = x * tau_end + rows[m][1][0]
            y = y * tau_end + rows[m][1][1]
        ends.append((x, y))
    speed = np.hypot(np.array(d1x), np.array(d1y))  # geometry.signed_curvature
    curvature = (np.array(crosses) / speed**3).tolist()
    tangents = np.array([[px * span, py * span] for px, py, span in zip(d1x, d1y, [v for v in spans for _ in (0, 1)])])
    n = len(splines)
    nxt = [(i + 1) % n for i in range(n)]
    gaps = np.hypot(np.array([ends[i][0] - starts[j][0] for i, j in enumerate(nxt)]),
                    np.array([ends[i][1] - starts[j][1] for i, j in enumerate(nxt)])).tolist()
    t = tangents.tolist()
    out: list[JointValues] = []
    for i, j in enumerate(nxt):
        (ex, ey), (sx, sy) = t[2 * i + 1], t[2 * j]
        cross = ex * sy - ey * sx
        dot = float(tangents[2 * i + 1] @ tangents[2 * j])
        out.append((ends[i], gaps[i], abs(math.atan2(cross, dot)), curvature[2 * j] - curvature[2 * i + 1]))
    return out
