"""camgen.numerics against independent references: scipy's banded, circulant and dense solvers,
its spline constructors and piecewise-polynomial roots, exact rational arithmetic, and NIST's
certified values for nonlinear least squares (Statistical Reference Datasets)."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from camgen.errors import GeometryError
from camgen.numerics.hermite import cubic_hermite_coefficients, quintic_hermite_coefficients
from camgen.numerics.interpolate import periodic_spline
from camgen.numerics.least_squares import levenberg_marquardt
from camgen.numerics.ppoly import PiecewisePolynomial
from camgen.numerics.tridiagonal import DENSE_LIMIT, SMALL, solve_block_tridiagonal, solve_tridiagonal


def _dominant(rng: np.random.Generator, n: int, q: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Diagonals with (|lower| + |upper|) / |diag| between q / 2 and q, diagonal signs mixed."""
    lower, upper = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    diag = (np.abs(lower) + np.abs(upper)) / q * rng.uniform(1.0, 2.0, n) * rng.choice([-1.0, 1.0], n)
    return lower, diag, upper


# --------------------------------------------------------------------------------------------
# Tridiagonal systems
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("n", [SMALL + 1, 1000, 20000])
@pytest.mark.parametrize("q", [0.5, 0.99])
def test_tridiagonal_equals_scipys_banded_solve(n, q):
    """Systems that are not cyclic, beyond the dense size (the reduction runs), one and three
    right-hand sides: scipy.linalg.solve_banded's LU solution."""
    from scipy.linalg import solve_banded

    rng = np.random.default_rng(n + int(100 * q))
    lower, diag, upper = _dominant(rng, n, q)
    banded = np.zeros((3, n))
    banded[0, 1:], banded[1], banded[2, :-1] = upper[:-1], diag, lower[1:]
    for rhs in (rng.normal(size=n), rng.normal(size=(n, 3))):
        expected = solve_banded((1, 1), banded, rhs)
        got = solve_tridiagonal(lower, diag, upper, rhs, cyclic=False)
        assert got.shape == rhs.shape
        assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))


@pytest.mark.parametrize("n", [SMALL + 1, 1000, 20001])
def test_cyclic_tridiagonal_equals_scipys_circulant_solve(n):
    """A cyclic system with constant diagonals is circulant: scipy.linalg.solve_circulant (FFT)."""
    from scipy.linalg import solve_circulant

    rng = np.random.default_rng(n)
    a, b, c = -1.0, 3.3, 1.7  # row i: a x[i-1] + b x[i] + c x[i+1]
    column = np.zeros(n)
    column[0], column[1], column[-1] = b, a, c  # the matrix's first column
    rhs = rng.normal(size=(n, 2))
    expected = solve_circulant(column, rhs)
    got = solve_tridiagonal(np.full(n, a), np.full(n, b), np.full(n, c), rhs, cyclic=True)
    assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))


@pytest.mark.parametrize("q", [0.5, 0.9, 1.5])
def test_cyclic_tridiagonal_with_varying_diagonals_equals_scipys_dense_solve(q):
    """Varying diagonals, dominant (the reduction converges) or not (q = 1.5: the couplings would
    wrap around before they die out, and the system is solved densely): scipy.linalg.solve."""
    from scipy.linalg import solve

    rng = np.random.default_rng(int(10 * q))
    n = 700
    lower, diag, upper = _dominant(rng, n, q)
    dense = np.diag(diag) + np.diag(lower[1:], -1) + np.diag(upper[:-1], 1)
    dense[0, -1], dense[-1, 0] = lower[0], upper[-1]
    rhs = rng.normal(size=n)
    expected = solve(dense, rhs)
    got = solve_tridiagonal(lower, diag, upper, rhs, cyclic=True)
    assert np.max(np.abs(got - expected)) <= 1e-10 * np.max(np.abs(expected))


def test_a_cyclic_system_too_large_for_the_dense_solve_is_refused():
    n = DENSE_LIMIT + 1
    lower = upper = np.ones(n)
    with pytest.raises(GeometryError, match=f"{n} unknowns.*> {DENSE_LIMIT} unknowns"):
        solve_tridiagonal(lower, np.full(n, 1.5), upper, np.ones(n), cyclic=True)  # couplings 4/3 of the diagonal


def test_block_systems_of_two_by_two_blocks_equal_scipys_banded_solve():
    """(n, 2, 2) blocks, not cyclic: the same matrix as a banded one of half-width 3."""
    from scipy.linalg import solve_banded

    rng = np.random.default_rng(2)
    n, b = 400, 2
    lower, upper = rng.normal(size=(n, b, b)), rng.normal(size=(n, b, b))
    diag = rng.normal(size=(n, b, b)) * 0.5 + np.eye(b) * 8.0
    dense = np.zeros((n * b, n * b))
    for i in range(n):  # the reference assembles the matrix block by block
        dense[b * i:b * i + b, b * i:b * i + b] = diag[i]
        if i > 0:
            dense[b * i:b * i + b, b * i - b:b * i] = lower[i]
        if i < n - 1:
            dense[b * i:b * i + b, b * i + b:b * i + 2 * b] = upper[i]
    width = 2 * b - 1
    banded = np.zeros((2 * width + 1, n * b))
    for k in range(-width, width + 1):
        diagonal = np.diagonal(dense, k)
        banded[width - k, max(k, 0):max(k, 0) + diagonal.size] = diagonal
    rhs = rng.normal(size=(n, b))
    expected = solve_banded((width, width), banded, rhs.ravel()).reshape(n, b)
    got = solve_block_tridiagonal(lower, diag, upper, rhs, cyclic=False)
    assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))


# --------------------------------------------------------------------------------------------
# Interpolating splines
# --------------------------------------------------------------------------------------------
def _exact_periodic_cubic(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Coefficients (4, n, d), highest power first, of the periodic C2 cubic through ``y`` at
    ``t`` in exact rational arithmetic: the cyclic moment system (de Boor, ch. IV) eliminated
    without pivoting (it is diagonally dominant), then the pieces from the moments."""
    tt = [Fraction(v) for v in t]
    n = len(tt) - 1
    h = [tt[i + 1] - tt[i] for i in range(n)]
    out = np.empty((4, n, y.shape[1]))
    for col in range(y.shape[1]):
        yy = [Fraction(v) for v in y[:, col]]
        s = [(yy[i + 1] - yy[i]) / h[i] for i in range(n)]
        rows = [{(i - 1) % n: h[i - 1], i: 2 * (h[i - 1] + h[i]), (i + 1) % n: h[i]} for i in range(n)]
        rhs = [6 * (s[i] - s[i - 1]) for i in range(n)]
        for k in range(n):
            for i in range(k + 1, n):
                if rows[i].get(k):
                    f = rows[i][k] / rows[k][k]
                    for j, v in rows[k].items():
                        if j >= k:
                            rows[i][j] = rows[i].get(j, 0) - f * v
                    rhs[i] -= f * rhs[k]
        m = [Fraction(0)] * n
        for i in range(n - 1, -1, -1):
            m[i] = (rhs[i] - sum(v * m[j] for j, v in rows[i].items() if j > i)) / rows[i][i]
        m.append(m[0])
        for i in range(n):
            out[:, i, col] = [float((m[i + 1] - m[i]) / (6 * h[i])), float(m[i] / 2),
                              float(s[i] - h[i] * (2 * m[i] + m[i + 1]) / 6), float(yy[i])]
    return out


def test_periodic_cubic_is_the_exact_rational_spline_to_rounding():
    """Knot spacing varying 300-fold, 120 pieces: the coefficients within 4e-15 (relative) of the
    spline solved in exact rational arithmetic (the moments keep that; the Hermite form of the
    quintic, used for a cubic, errs by 1e-14 .. 4e-14 here)."""
    rng = np.random.default_rng(5)
    n = 120
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.01, 3.0, n))])
    y = rng.normal(size=(n + 1, 2)) * 50
    y[-1] = y[0]
    exact = _exact_periodic_cubic(t, y)
    assert np.max(np.abs(periodic_spline(t, y, 3).c - exact)) <= 4e-15 * np.max(np.abs(exact))


@pytest.mark.parametrize("degree", [3, 5])
def test_periodic_spline_through_points_equals_scipys(degree):
    """Two columns at once (the points of a closed curve): scipy's periodic interpolating spline
    (CubicSpline for k = 3, make_interp_spline for k = 5) of the same points."""
    from scipy.interpolate import CubicSpline, make_interp_spline

    rng = np.random.default_rng(degree)
    n = 300
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.2, 1.8, n))])
    y = rng.normal(size=(n + 1, 2)) * 20
    y[-1] = y[0]
    theirs = CubicSpline(t, y, bc_type="periodic") if degree == 3 else make_interp_spline(t, y, k=degree, bc_type="periodic")
    mine = periodic_spline(t, y, degree)
    assert mine.c.shape == (degree + 1, n, 2)
    probe = np.concatenate([t, rng.uniform(t[0], t[-1], 5000)])
    for order in range(3):
        expected = theirs(probe, order)
        got = mine.derivative(order)(probe) if order else mine(probe)
        assert np.max(np.abs(got - expected)) <= 1e-11 * np.max(np.abs(expected)), order


def test_hermite_pieces_equal_scipys():
    """Cubic pieces from values and slopes: scipy's CubicHermiteSpline; quintic pieces from
    values, first and second derivatives: scipy's BPoly.from_derivatives (Bernstein form)."""
    from scipy.interpolate import BPoly, CubicHermiteSpline, PPoly

    rng = np.random.default_rng(8)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 2.0, 40))])
    p, d1, d2 = (rng.normal(size=(t.size, 2)) * s for s in (10.0, 5.0, 3.0))
    cubic = CubicHermiteSpline(t, p, d1).c
    assert np.max(np.abs(cubic_hermite_coefficients(t, p, d1) - cubic)) <= 1e-12 * np.max(np.abs(cubic))
    for axis in range(2):
        quintic = PPoly.from_bernstein_basis(BPoly.from_derivatives(t, np.stack([p[:, axis], d1[:, axis], d2[:, axis]], axis=1))).c
        got = quintic_hermite_coefficients(t, p, d1, d2)[..., axis]
        assert np.max(np.abs(got - quintic)) <= 1e-11 * np.max(np.abs(quintic)), axis


# --------------------------------------------------------------------------------------------
# Roots of piecewise polynomials
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("order", [1, 2, 3])
def test_roots_equal_scipys_ppoly_roots(order):
    """The sign changes of derivatives of a periodic quintic through random values (simple roots):
    scipy's PPoly.roots (companion matrices), inside the breaks, as many and each within 1e-10."""
    from scipy.interpolate import PPoly

    rng = np.random.default_rng(order)
    x = np.concatenate([[0.0], np.cumsum(rng.uniform(0.3, 1.7, 200))])
    y = rng.normal(size=x.size)
    y[-1] = y[0]
    d = periodic_spline(x, y, 5).derivative(order)
    expected = np.unique(PPoly(d.c, d.x).roots(discontinuity=False, extrapolate=False))
    expected = expected[np.concatenate([[True], np.diff(expected) > 1e-9])]  # a root on a break: once
    got = d.roots()
    assert expected.size > 100 and got.size == expected.size
    assert np.max(np.abs(got - expected)) <= 1e-10


def test_roots_list_sign_changes_once_and_no_touching_zero():
    """On one piece [0, 3]: (t - 1)^2 (t - 2) changes sign at 2 only; (t - 1)^3 at 1; on two
    pieces meeting at 1 where t - 1 changes sign, the root on the break is listed once."""
    touching = PiecewisePolynomial(np.array([0.0, 3.0]), np.array([[1.0], [-4.0], [5.0], [-2.0]]))  # t^3 - 4t^2 + 5t - 2
    assert np.allclose(touching.roots(), [2.0], rtol=0, atol=1e-12)
    cube = PiecewisePolynomial(np.array([0.0, 3.0]), np.array([[1.0], [-3.0], [3.0], [-1.0]]))  # (t - 1)^3
    assert cube.roots().size == 1 and abs(cube.roots()[0] - 1.0) <= 1e-5  # a triple root: 1e-16 ** (1/3)
    line = PiecewisePolynomial(np.array([0.0, 1.0, 2.0]), np.array([[1.0, 1.0], [-1.0, 0.0]]))  # t - 1 on both pieces
    assert line.roots().tolist() == [1.0]


# --------------------------------------------------------------------------------------------
# Levenberg-Marquardt against NIST StRD (https://www.itl.nist.gov/div898/strd/nls/nls_main.shtml)
# --------------------------------------------------------------------------------------------
#: Misra1a (lower difficulty) and BoxBOD (higher difficulty): y = b1 (1 - exp(-b2 x)); data, both
#: NIST starting points, certified parameters and residual sum of squares.
NIST = {
    "Misra1a": (np.array([77.6, 114.9, 141.1, 190.8, 239.9, 289.0, 332.8, 378.4, 434.8, 477.3, 536.8, 593.1, 689.1, 760.0]),
                np.array([10.07, 14.73, 17.94, 23.93, 29.61, 35.18, 40.02, 44.82, 50.76, 55.05, 61.01, 66.40, 75.47, 81.78]),
                ((500.0, 1e-4), (250.0, 5e-4)), (2.3894212918e02, 5.5015643181e-04), 1.2455138894e-01, (100.0, 1e-4)),
    "BoxBOD": (np.array([1.0, 2.0, 3.0, 5.0, 7.0, 10.0]), np.array([109.0, 149.0, 149.0, 191.0, 213.0, 224.0]),
               ((1.0, 1.0), (100.0, 0.75)), (2.1380940889e02, 5.4723748542e-01), 1.1680088766e03, (100.0, 0.5)),
}


@pytest.mark.parametrize("name", sorted(NIST))
@pytest.mark.parametrize("start", [0, 1])
def test_levenberg_marquardt_reaches_nists_certified_values(name, start):
    x, y, starts, certified, rss, scale = NIST[name]

    def residual(b: np.ndarray) -> np.ndarray:
        return b[0] * (1.0 - np.exp(-b[1] * x)) - y

    fit = levenberg_marquardt(residual, np.array(starts[start]), np.array(scale))
    assert np.allclose(fit.x, certified, rtol=1e-6, atol=0)
    assert 2.0 * fit.cost == pytest.approx(rss, rel=1e-9)
    assert np.array_equal(fit.fun, residual(fit.x)) and fit.nfev <= 400
    jac = np.stack([1.0 - np.exp(-fit.x[1] * x), fit.x[0] * x * np.exp(-fit.x[1] * x)], axis=1)  # closed form
    assert np.allclose(fit.jac, jac, rtol=1e-5, atol=1e-8 * np.max(np.abs(jac)))


def test_median_is_numpys_bit_for_bit():
    """camgen.numerics.order.median against numpy.median (the library it stands in for): odd and
    even counts, ties, a 2-D input, and NaN anywhere giving NaN."""
    from camgen.numerics.order import median

    rng = np.random.default_rng(7)
    for n in (1, 2, 3, 10, 11, 3599, 3600):
        values = rng.normal(size=n) * 10.0 ** rng.integers(-8, 8)
        assert median(values) == float(np.median(values))
        rounded = np.round(values, 1)  # ties
        assert median(rounded) == float(np.median(rounded))
    grid = rng.random((7, 9))
    assert median(grid) == float(np.median(grid))
    with_nan = rng.random(101)
    with_nan[37] = np.nan
    assert np.isnan(median(with_nan)) and np.isnan(np.median(with_nan))
    assert np.isnan(median(np.array([])))


def test_golden_section_brackets_the_least_value():
    """f(x) = |x - 1/3| + 2 on [0, 1] has its least value 2 at 1/3 (a kink: resolved to the
    stopping length, where a smooth minimum is flat below sqrt(eps)); a step budget stops the
    search too (each step keeps 0.618 of the bracket)."""
    from camgen.numerics.minimise import GOLDEN, golden_section

    def f(x: float) -> float:
        return abs(x - 1.0 / 3.0) + 2.0

    (c, fc), (d, fd) = golden_section(f, 0.0, 1.0, tol=1e-12)
    assert abs(c - 1.0 / 3.0) <= 1e-12 and abs(d - 1.0 / 3.0) <= 1e-12 and min(fc, fd) == pytest.approx(2.0, abs=1e-12)
    (c, _), (d, _) = golden_section(f, 0.0, 1.0, max_steps=10)
    assert abs(0.5 * (c + d) - 1.0 / 3.0) <= GOLDEN**10 and abs(c - d) > 1e-3
