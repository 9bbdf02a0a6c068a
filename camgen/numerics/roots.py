"""Sign changes of many polynomials at once, without eigenvalues.

:func:`sign_change_roots` finds, for every row of ascending power coefficients, the points of an
interval where the polynomial changes sign: the sign changes of its derivative (found the same
way, down to a constant) cut the interval into monotonic pieces, and safeguarded Newton steps
find the one root of each piece whose ends differ in sign.  Vectorised over the rows; the loop
runs over the degree and the Newton steps, never over the polynomials.
"""
from __future__ import annotations

import math

import numpy as np

from camgen.numerics.polynomial import horner_ascending

__all__ = ["ROOT_STEPS", "ROOT_TOL", "SCALAR_ROWS", "grouped_sign_change_roots", "roots_in_pieces", "sign_change_roots"]

#: Largest number of safeguarded Newton steps of :func:`sign_change_roots` (each step that
#: would leave the bracket is a bisection; Newton on a monotonic bracket converges in a few).
ROOT_STEPS = 64
#: Up to this many roots the Newton steps run on Python floats (:func:`_scalar_newton`), more
#: vectorised: a numpy call costs about a microsecond, a scalar step a tenth of one.
SCALAR_ROWS = 16
#: Relative slack (of a piece's parameter length) within which a root of a piece's polynomial
#: just outside the piece, by rounding, still counts as on its end (knot): :func:`roots_in_pieces`.
ROOT_TOL = 1e-9


def sign_change_roots(a: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Every point of ``(lo, hi)`` where the polynomial with ascending coefficients ``a`` (n, degree + 1)
    changes sign: (n, degree), sorted, NaN-padded.

    Derivative chain (no eigenvalues, no leading-coefficient division): the sign changes of the
    derivative (found the same way, down to a constant) cut ``[lo, hi]`` into intervals where the
    polynomial is monotonic; each holds one sign change iff its end values differ in sign, and
    Newton steps kept inside the shrinking bracket (a bisection where a step would leave it) find
    it to a few ulps.  A root of even multiplicity (no sign change) is not
    returned: the callers want the extrema of the polynomial's antiderivative, which sit exactly
    at the sign changes.  Identically zero polynomials have none.
    """
    return grouped_sign_change_roots(a, lo, hi, np.zeros(a.shape[0], dtype=np.intp), 1)


def grouped_sign_change_roots(a: np.ndarray, lo: float, hi: float, group: np.ndarray, groups: int) -> np.ndarray:
    """:func:`sign_change_roots` of several independent sets of polynomials in one vectorised
    pass: row ``i`` of ``a`` (n, degree + 1) belongs to set ``group[i]`` (ints in ``[0, groups)``).

    Each set's Newton iteration stops when none of its own roots moved (as a call of
    :func:`sign_change_roots` on that set alone stops), so every root is bit for bit what that
    call returns; the loops run once for all the sets (far fewer numpy calls on small arrays)."""
    n, degree = a.shape[0], a.shape[1] - 1
    if degree <= 0:
        return np.empty((n, 0))
    crit = np.sort(grouped_sign_change_roots(a[:, 1:] * np.arange(1, degree + 1), lo, hi, group, groups), axis=1)  # (n, degree - 1)
    bounds = np.concatenate([np.full((n, 1), lo), np.where(np.isnan(crit), hi, crit), np.full((n, 1), hi)], axis=1)
    left, right = bounds[:, :-1], bounds[:, 1:]  # (n, degree) monotonic intervals
    f_left, f_right = horner_ascending(a, left), horner_ascending(a, right)
    out = np.full((n, degree), np.nan)
    row, col = np.nonzero(((f_left < 0) & (f_right > 0)) | ((f_left > 0) & (f_right < 0)))
    if row.size:
        coef = a[row]
        slope = coef[:, 1:] * np.arange(1, degree + 1)
        l, r = left[row, col], right[row, col]
        rising = f_left[row, col] < 0
        x = 0.5 * (l + r)
        owner = group[row]
        if row.size <= SCALAR_ROWS:  # a few roots: the same steps on Python floats (no numpy call per step)
            out[row, col] = _scalar_newton(coef.tolist(), slope.tolist(), l.tolist(), r.tolist(), rising.tolist(), owner.tolist())
            return out
        single = groups == 1
        live = np.ones(row.size, dtype=bool)  # rows whose set still iterates
        for _ in range(ROOT_STEPS):
            f = horner_ascending(coef, x[:, None])[:, 0]
            up = (f < 0) == rising  # x on the left end's side
            l = np.where(up, x, l)
            r = np.where(up, r, x)
            with np.errstate(divide="ignore", invalid="ignore"):
                new = x - f / horner_ascending(slope, x[:, None])[:, 0]
            tol = 4.0 * np.finfo(float).eps * np.maximum(1.0, np.abs(x))
            step = np.abs(new - x)
            # a Newton step inside the bracket, or one that has converged (x may sit on the bracket's end)
            new = np.where(((new > l) & (new < r)) | (step <= tol), new, 0.5 * (l + r))
            new = np.where(f == 0, x, new)
            moved = np.abs(new - x) > tol
            if single:
                x = new
                if not np.any(moved):
                    break
                continue
            x = np.where(live, new, x)
            going = np.bincount(owner[live & moved], minlength=groups) > 0  # the sets with a root still moving
            live &= going[owner]
            if not np.any(live):
                break
        out[row, col] = x
    return out


def _scalar_newton(coef: list, slope: list, left: list, right: list, rising: list, owner: list) -> list[float]:
    """The safeguarded Newton steps of :func:`grouped_sign_change_roots` on Python floats, root
    by root within each set, each set until none of its roots moved: the same IEEE operations in
    the same order (Horner, the step, the bracket test, the bisection), so the same bits."""
    tiny = 4.0 * float(np.finfo(float).eps)
    x = [0.5 * (a + b) for a, b in zip(left, right)]
    l, r = list(left), list(right)
    sets: dict[int, list[int]] = {}
    for i, g in enumerate(owner):
        sets.setdefault(g, []).append(i)
    for members in sets.values():
        for _ in range(ROOT_STEPS):
            moved = False
            for i in members:
                xi, ci, si = x[i], coef[i], slope[i]
                f = ci[-1]
                for c in ci[-2::-1]:
                    f = f * xi + c
                d = si[-1]
                for c in si[-2::-1]:
                    d = d * xi + c
                if (f < 0) == rising[i]:  # x on the left end's side
                    l[i] = xi
                else:
                    r[i] = xi
                tol = tiny * max(1.0, abs(xi))
                if f == 0:
                    new = xi
                else:
                    new = xi - f / d if d != 0 else math.inf  # numpy: +-inf, then a bisection
                    step = abs(new - xi)
                    if not ((l[i] < new < r[i]) or step <= tol):
                        new = 0.5 * (l[i] + r[i])
                if abs(new - xi) > tol:
                    moved = True
                x[i] = new
            if not moved:
                break
    return x


def roots_in_pieces(a: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pieces (M,) and offsets ``tau`` (M,) from their starts of the sign changes of the pieces'
    polynomials, given by ascending coefficients ``a`` (K, m) in ``s = tau / h`` (``h`` (K,) the
    pieces' lengths) on ``[0, 1]``; one just outside (within :data:`ROOT_TOL`, by rounding at a
    knot) counts as on the end."""
    s = sign_change_roots(a, -ROOT_TOL, 1.0 + ROOT_TOL)  # (K, m - 1)
    piece, col = np.nonzero(np.isfinite(s))
    return piece, np.clip(s[piece, col], 0.0, 1.0) * h[piece]
