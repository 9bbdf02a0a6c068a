"""camgen.numerics.bernstein.bernstein_max_norm sums each Bezier point in place from its first
term (issue 28 item 6: fewer array passes per design, the wall check's chord counts): bit for bit
the bound of the code before (kept here verbatim as the reference) on random pieces of degrees 0
to 5 with zeros of both signs, ties and huge and tiny values, and against the exact maximum of
the control points' norms from :func:`camgen.numerics.bernstein.power_to_bezier`.
"""
from __future__ import annotations

import math

import numpy as np
import pytest


def _before(c: np.ndarray, h: np.ndarray) -> np.ndarray:
    """bernstein_max_norm before this change (commit 62e49be), verbatim."""
    degree = c.shape[0] - 1
    a = np.stack([c[degree - i] * (h ** i)[:, None] for i in range(degree + 1)])
    best = np.zeros(h.size)
    for j in range(degree + 1):
        b = sum(math.comb(j, i) / math.comb(degree, i) * a[i] for i in range(j + 1))
        np.maximum(best, np.hypot(b[:, 0], b[:, 1]), out=best)
    return best


@pytest.mark.parametrize("degree", range(6))
def test_the_fused_bound_is_the_one_before_bit_for_bit(degree):
    from camgen.numerics.bernstein import bernstein_max_norm, power_to_bezier

    rng = np.random.default_rng(degree)
    for scale in (1e-12, 1.0, 1e9):
        c = rng.normal(size=(degree + 1, 200, 2)) * scale
        c[:, ::7] = 0.0
        c[:, 3::11] = -0.0
        c[:, 5::13, 0] *= -1.0
        c[0, 4::9] = -c[-1, 4::9]  # terms that cancel
        h = rng.uniform(0.0, 3.0, size=200)
        h[::17] = 0.0
        got = bernstein_max_norm(c, h)
        assert np.array_equal(got, _before(c, h))
        # the bound is the largest norm of the Bezier control points (lowest power first in s = tau / h)
        a = np.stack([c[degree - i] * (h ** i)[:, None] for i in range(degree + 1)], axis=1)
        points = power_to_bezier(a)
        assert np.allclose(got, np.hypot(points[..., 0], points[..., 1]).max(axis=1), rtol=1e-13, atol=0)
