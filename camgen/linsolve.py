"""Block-tridiagonal linear systems, cyclic or not, in numpy (no scipy import at run time).

:func:`solve_block_tridiagonal` solves

    A[i] x[i-1] + B[i] x[i] + C[i] x[i+1] = d[i]        (i = 0 .. n-1)

with (b, b) blocks, by block parallel cyclic reduction (Hockney 1965; Heller 1976 for the block
form): every step eliminates, in every row at once, the neighbours at distance s with the rows
i -+ s and doubles s.  The couplings shrink geometrically where the inverse matrix decays
away from its diagonal (spline interpolation systems, diagonally dominant systems), so a
handful of vectorised steps suffice whatever n: the loop runs over those steps, never over
rows.  Small systems, and any system whose couplings do not die out before the reduction would
wrap around a cyclic system, are solved densely (``numpy.linalg.solve``) up to
:data:`DENSE_LIMIT` unknowns; beyond it a :class:`~camgen.errors.GeometryError` says so.
"""
from __future__ import annotations

import numpy as np

from camgen.errors import GeometryError

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
    rows = np.arange(n)
    step = 1
    scale = _size(bb)
    while np.max((_size(a) + _size(c)) / scale) > COUPLING_TOL:
        if cyclic and 2 * step >= n:  # the couplings would wrap around onto the row itself
            return _dense_fallback(lower, diag, upper, rhs, cyclic, "the reduction did not converge")
        below, above = rows - step, rows + step
        if cyclic:
            below, above = below % n, above % n
            ok_b = ok_a = np.ones(n, bool)
        else:
            ok_b, ok_a = below >= 0, above < n
            below, above = np.clip(below, 0, n - 1), np.clip(above, 0, n - 1)
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
