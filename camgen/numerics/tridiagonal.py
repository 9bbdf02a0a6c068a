"""Tridiagonal and block-tridiagonal linear systems, cyclic or not, in numpy (no scipy import).

:func:`solve_block_tridiagonal` solves

    A[i] x[i-1] + B[i] x[i] + C[i] x[i+1] = d[i]        (i = 0 .. n-1)

with (b, b) blocks, by block parallel cyclic reduction (Hockney 1965; Heller 1976 for the block
form): every step eliminates, in every row at once, the neighbours at distance s with the rows
i -+ s and doubles s.  The couplings shrink geometrically where the inverse matrix decays
away from its diagonal (spline interpolation systems, diagonally dominant systems: with
``|A| + |C| <= q |B|``, q < 1, each step squares q, Heller 1976, SIAM J. Numer. Anal. 13,
thm. 2.1), so a handful of vectorised steps suffice whatever n: the loop runs over those steps,
never over rows.  Small systems, and any system whose couplings do not die out before the
reduction would wrap around a cyclic system, are solved densely (``numpy.linalg.solve``) up to
:data:`DENSE_LIMIT` unknowns; beyond it a :class:`~camgen.errors.GeometryError` says so.

Scalar systems (b = 1: the cubic splines' moment systems) take the same steps with the 1 x 1
blocks' products and inverses as elementwise products and divisions instead of a LAPACK call per
row (:func:`_reduce_scalar`); :func:`solve_tridiagonal` is that case with scalar diagonals.  This
module replaces two solvers (issue 22): the block solver, and a scalar one that
``camgen.contour`` had for the cubic splines.  Measured on cubic-spline moment systems with
uneven knots (two right-hand sides; errors against scipy's ``solve_banded`` or a dense LU, all
within 6e-16): cyclic, 0.26 ms at n = 720 and 29 ms at 1e5, as the former scalar solver (0.29
and 26 ms) and 2.8 times faster than the (n, 1, 1) block form; not cyclic (no caller outside
the tests), 0.14 ms and 15 ms against the former scalar solver's 0.10 and 7.7 ms (it knew its
step count in advance and reused its buffers).
"""
from __future__ import annotations

import numpy as np

from camgen.errors import GeometryError

__all__ = ["COUPLING_TOL", "DENSE_LIMIT", "SMALL", "solve_block_tridiagonal", "solve_tridiagonal"]

#: Size of the couplings, relative to the diagonal blocks, below which they count as eliminated.
COUPLING_TOL = 1e-17
#: Systems of at most this many unknowns (rows x block size) are solved densely.
DENSE_LIMIT = 3000
#: Systems of at most this many unknowns are always solved densely (faster than the reduction).
SMALL = 96


def _assemble(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray, cyclic: bool) -> np.ndarray:
    """The dense (n b, n b) matrix of the block system."""
    n, b, _ = diag.shape
    dense = np.zeros((n, b, n, b))
    rows = np.arange(n)
    dense[rows, :, rows, :] = diag
    if n > 1:
        below, above = rows - 1, rows + 1
        ok_b = below >= 0 if not cyclic else np.ones(n, bool)
        ok_a = above < n if not cyclic else np.ones(n, bool)
        dense[rows[ok_b], :, below[ok_b] % n, :] += lower[ok_b]
        dense[rows[ok_a], :, above[ok_a] % n, :] += upper[ok_a]
    return dense.reshape(n * b, n * b)


def _size(blocks: np.ndarray) -> np.ndarray:
    """Largest absolute entry of each block (n,)."""
    return np.max(np.abs(blocks), axis=(1, 2))


def solve_block_tridiagonal(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray, rhs: np.ndarray,
                            cyclic: bool) -> np.ndarray:
    """Solve the block-tridiagonal system (see the module notes).

    Parameters
    ----------
    lower, diag, upper : arrays (n, b, b)
        ``A``, ``B``, ``C``; without ``cyclic``, ``lower[0]`` and ``upper[-1]`` are ignored.
    rhs : array (n, b) or (n, b, k)
        Right-hand side(s).
    cyclic : bool
        Row 0 couples to row n-1 through ``lower[0]`` and row n-1 to row 0 through ``upper[-1]``.

    Returns
    -------
    array of the shape of ``rhs``
    """
    a, bb, c = (np.array(v, dtype=float) for v in (lower, diag, upper))
    d = np.array(rhs, dtype=float)
    vector = d.ndim == 2
    if vector:
        d = d[:, :, None]
    n, b, _ = bb.shape
    if not cyclic:
        a[0] = 0.0
        c[-1] = 0.0
    if n * b <= SMALL or (cyclic and n < 4):
        x = np.linalg.solve(_assemble(a, bb, c, cyclic), d.reshape(n * b, -1)).reshape(d.shape)
        return x[:, :, 0] if vector else x
    if b == 1:
        scalar = _reduce_scalar(a[:, 0, 0], bb[:, 0, 0], c[:, 0, 0], d[:, 0, :], cyclic)
        if scalar is None:
            return _dense_fallback(lower, diag, upper, rhs, cyclic, "the reduction did not converge")
        return scalar if vector else scalar[:, None, :]
    rows = np.arange(n)
    step = 1
    scale = _size(bb)
    while np.max((_size(a) + _size(c)) / scale) > COUPLING_TOL:
        if cyclic and 2 * step >= n:  # the couplings would wrap around onto the row itself
            return _dense_fallback(lower, diag, upper, rhs, cyclic, "the reduction did not converge")
        below, above = _neighbours(rows, step, n, cyclic)
        ok_b, ok_a = _inside(rows, step, n, cyclic)
        try:
            inv = np.linalg.inv(bb)
        except np.linalg.LinAlgError:
            return _dense_fallback(lower, diag, upper, rhs, cyclic, "a diagonal block became singular")
        alpha = np.where(ok_b[:, None, None], -a @ inv[below], 0.0)
        gamma = np.where(ok_a[:, None, None], -c @ inv[above], 0.0)
        bb, d, a, c = (bb + alpha @ c[below] + gamma @ a[above],
                       d + alpha @ d[below] + gamma @ d[above],
                       alpha @ a[below], gamma @ c[above])
        step *= 2
        if not cyclic and step >= n:  # every coupling points outside the system: done
            break
    x = np.linalg.solve(bb, d)
    return x[:, :, 0] if vector else x


def _neighbours(rows: np.ndarray, step: int, n: int, cyclic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Rows ``i - step`` and ``i + step`` (wrapped, or clipped into the system)."""
    below, above = rows - step, rows + step
    if cyclic:
        return below % n, above % n
    return np.clip(below, 0, n - 1), np.clip(above, 0, n - 1)


def _inside(rows: np.ndarray, step: int, n: int, cyclic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Whether rows ``i - step`` and ``i + step`` exist (always, in a cyclic system)."""
    if cyclic:
        every = np.ones(n, bool)
        return every, every
    return rows - step >= 0, rows + step < n


def _reduce_scalar(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray, cyclic: bool) -> np.ndarray | None:
    """The reduction of :func:`solve_block_tridiagonal` for 1 x 1 blocks: ``a``, ``b``, ``c`` (n,),
    ``d`` (n, k); None where a cyclic system's couplings would wrap around before they die out.

    Step for step the block form (the inverse of a 1 x 1 block is ``1 / b``, its products are
    scalar products), on vectors instead of (n, 1, 1) stacks; it agrees with the block form to
    rounding (a few 1e-17 relative: LAPACK divides by multiplying with the reciprocal)."""
    n = b.size
    if not cyclic:
        return _reduce_scalar_open(a, b, c, d)
    rows = np.arange(n)
    step = 1
    scale = np.abs(b)
    while np.max((np.abs(a) + np.abs(c)) / scale) > COUPLING_TOL:
        if cyclic and 2 * step >= n:
            return None
        below, above = _neighbours(rows, step, n, cyclic)
        ok_b, ok_a = _inside(rows, step, n, cyclic)
        inv = 1.0 / b
        alpha = np.where(ok_b, -a * inv[below], 0.0)
        gamma = np.where(ok_a, -c * inv[above], 0.0)
        b, d, a, c = (b + alpha * c[below] + gamma * a[above],
                      d + alpha[:, None] * d[below] + gamma[:, None] * d[above],
                      alpha * a[below], gamma * c[above])
        step *= 2
        if not cyclic and step >= n:
            break
    return d / b[:, None]


def _reduce_scalar_open(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """:func:`_reduce_scalar` of a system that is not cyclic (``a[0] = c[-1] = 0``): the rows sit
    between ``n`` rows of the identity on either side (no couplings, no right-hand side), so the
    neighbours at distance ``s < n`` are slices, not gathers, and need no mask (a coupling to a
    padding row eliminates nothing and vanishes)."""
    n, k = d.shape
    size = 3 * n
    mid = slice(n, 2 * n)
    a_pad, b_pad, c_pad, d_pad = np.zeros(size), np.ones(size), np.zeros(size), np.zeros((size, k))
    a_pad[mid], b_pad[mid], c_pad[mid], d_pad[mid] = a, b, c, d
    scale = np.abs(b)
    step = 1
    while step < n and np.max((np.abs(a_pad[mid]) + np.abs(c_pad[mid])) / scale) > COUPLING_TOL:
        lo, hi = slice(n - step, 2 * n - step), slice(n + step, 2 * n + step)
        alpha = -a_pad[mid] * (1.0 / b_pad[lo])
        gamma = -c_pad[mid] * (1.0 / b_pad[hi])
        b_new = b_pad[mid] + alpha * c_pad[lo] + gamma * a_pad[hi]
        d_new = d_pad[mid] + alpha[:, None] * d_pad[lo] + gamma[:, None] * d_pad[hi]
        a_pad[mid], c_pad[mid] = alpha * a_pad[lo], gamma * c_pad[hi]
        b_pad[mid], d_pad[mid] = b_new, d_new
        step *= 2
    return d_pad[mid] / b_pad[mid, None]


def solve_tridiagonal(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray, rhs: np.ndarray, cyclic: bool) -> np.ndarray:
    """Solve ``lower[i] x[i-1] + diag[i] x[i] + upper[i] x[i+1] = rhs[i]``: the scalar case of
    :func:`solve_block_tridiagonal` (``lower``, ``diag``, ``upper`` (n,), ``rhs`` (n,) or (n, k);
    ``cyclic``: row 0 couples to row n-1 and back; else ``lower[0]`` and ``upper[-1]`` are ignored).

    Returns an array of the shape of ``rhs``."""
    a, b, c = (np.asarray(v, dtype=float)[:, None, None] for v in (lower, diag, upper))
    d = np.asarray(rhs, dtype=float)
    x = solve_block_tridiagonal(a, b, c, d[:, None] if d.ndim == 1 else d[:, None, :], cyclic)
    return x[:, 0] if d.ndim == 1 else x[:, 0, :]


def _dense_fallback(lower, diag, upper, rhs, cyclic: bool, why: str) -> np.ndarray:
    n, b, _ = np.shape(diag)
    if n * b > DENSE_LIMIT:
        raise GeometryError(f"block-tridiagonal system of {n * b} unknowns: {why} and it is too large to solve densely "
                            f"(> {DENSE_LIMIT} unknowns); the spacing of the data is too uneven")
    a, bb, c = (np.array(v, dtype=float) for v in (lower, diag, upper))
    if not cyclic:
        a[0] = 0.0
        c[-1] = 0.0
    d = np.asarray(rhs, dtype=float)
    x = np.linalg.solve(_assemble(a, bb, c, cyclic), d.reshape(n * b, -1))
    return x.reshape(d.shape)
