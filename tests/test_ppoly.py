"""numpy splines and solvers against independent implementations: scipy.interpolate's periodic
B-spline interpolant, numpy.linalg's dense solve, and polynomial roots by bisection."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.numerics.interpolate import periodic_spline
from camgen.numerics.ppoly import PiecewisePolynomial
from camgen.numerics.tridiagonal import solve_block_tridiagonal


@pytest.mark.parametrize("degree", [3, 5])
@pytest.mark.parametrize("n, uneven", [(8, 0.0), (41, 0.9), (360, 0.5), (5000, 0.9)])
def test_periodic_spline_is_scipys(degree, n, uneven):
    """Same spline (value and three derivatives) as scipy's make_interp_spline(bc_type='periodic'),
    on breaks whose spacing varies by up to a factor 19."""
    from scipy.interpolate import PPoly, make_interp_spline

    rng = np.random.default_rng(n + degree)
    x = np.concatenate([[0.0], np.cumsum(rng.uniform(1 - uneven, 1 + uneven, n))])
    x *= 2 * math.pi / x[-1]
    y = rng.normal(size=n + 1) * 10
    y[-1] = y[0]
    mine = periodic_spline(x, y, degree)
    theirs = PPoly.from_spline(make_interp_spline(x, y, k=degree, bc_type="periodic"))
    inside = (x[:-1, None] + np.linspace(0, 1, 7)[None, 1:-1] * np.diff(x)[:, None]).ravel()
    for order in range(4):
        # a cubic's third derivative jumps at every break: compare it inside the pieces only
        t = inside if order == degree else np.concatenate([np.linspace(0, 2 * math.pi, 20001), x])
        expected = theirs.derivative(order)(t) if order else theirs(t)
        got = mine.derivative(order)(t) if order else mine(t)
        assert np.max(np.abs(got - expected)) <= 1e-11 * max(1.0, np.max(np.abs(expected))), order


def test_periodic_spline_interpolates_and_is_smooth_across_the_seam():
    """Through the data, and continuous through derivative degree-1 at every break, the seam included
    (one-sided values of neighbouring pieces)."""
    rng = np.random.default_rng(7)
    x = np.concatenate([[0.0], np.cumsum(rng.uniform(0.5, 1.5, 30))])
    y = rng.normal(size=31)
    y[-1] = y[0]
    spline = periodic_spline(x, y, 5)
    assert np.allclose(spline(x[:-1]), y[:-1], rtol=0, atol=1e-12)
    for order in range(5):
        d = spline.derivative(order)
        h = np.diff(x)
        # right end of piece i-1 (evaluated with its own coefficients) against the left end of piece i
        right_end = np.array([np.polyval(d.c[:, i], h[i]) for i in range(30)])
        left_end = d.c[-1, :]
        assert np.allclose(np.roll(right_end, 1), left_end, rtol=0, atol=1e-9 * max(1.0, np.max(np.abs(left_end)))), order


@pytest.mark.parametrize("cyclic", [False, True])
@pytest.mark.parametrize("n, b", [(3, 2), (60, 1), (500, 2), (700, 3)])
def test_block_tridiagonal_against_a_dense_solve(cyclic, n, b):
    rng = np.random.default_rng(n * b + cyclic)
    lower, upper = rng.normal(size=(n, b, b)), rng.normal(size=(n, b, b))
    diag = rng.normal(size=(n, b, b)) * 0.5 + np.eye(b) * (2.5 * b + 2)
    rhs = rng.normal(size=(n, b))
    dense = np.zeros((n * b, n * b))
    for i in range(n):  # the reference assembles the matrix row by row
        dense[i * b:(i + 1) * b, i * b:(i + 1) * b] = diag[i]
        if i > 0 or cyclic:
            j = (i - 1) % n
            dense[i * b:(i + 1) * b, j * b:(j + 1) * b] += lower[i]
        if i < n - 1 or cyclic:
            j = (i + 1) % n
            dense[i * b:(i + 1) * b, j * b:(j + 1) * b] += upper[i]
    expected = np.linalg.solve(dense, rhs.ravel()).reshape(n, b)
    assert np.allclose(solve_block_tridiagonal(lower, diag, upper, rhs, cyclic), expected, rtol=0, atol=1e-11)


def test_roots_of_every_piece_against_bisection():
    """Real roots inside the pieces equal those found by sign changes on a fine grid refined by bisection."""
    rng = np.random.default_rng(11)
    x = np.concatenate([[0.0], np.cumsum(rng.uniform(0.5, 1.5, 25))])
    y = rng.normal(size=26)
    y[-1] = y[0]
    d = periodic_spline(x, y, 5).derivative(1)
    roots = d.roots()
    grid = np.linspace(x[0], x[-1], 400001)
    values = d(grid)
    change = np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)
    lo, hi = grid[change], grid[change + 1]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        left = np.sign(d(lo)) * np.sign(d(mid)) <= 0
        hi, lo = np.where(left, mid, hi), np.where(left, lo, mid)
    assert roots.size == lo.size
    assert np.allclose(roots, 0.5 * (lo + hi), rtol=0, atol=1e-9)


def test_derivative_of_a_single_polynomial():
    """d/dt of 2 t^3 - t + 4 on one piece starting at 1: 6 (t-1)^2 ... evaluated against the closed form."""
    p = PiecewisePolynomial(np.array([1.0, 3.0]), np.array([[2.0], [0.0], [-1.0], [4.0]]))
    t = np.linspace(1, 3, 7)
    assert np.allclose(p.derivative(1)(t), 6 * (t - 1) ** 2 - 1)
    assert np.allclose(p.derivative(2)(t), 12 * (t - 1))
    assert np.allclose(p.derivative(4)(t), 0.0)
