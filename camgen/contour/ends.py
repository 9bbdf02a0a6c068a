"""The tangents and curvatures of a contour's splines at both their ends, in one vectorised pass
(:meth:`camgen.contour.Contour.joints`, which a disk cam's continuity check calls per design).

The arithmetic is that of :meth:`Spline.derivative <camgen.contour.Spline.derivative>` and
:meth:`Spline.curvature <camgen.contour.Spline.curvature>` at ``u = 0`` and ``u = 1`` (as
:meth:`SegmentTables.spline_values <camgen.contour.tables.SegmentTables.spline_values>` does it for
many segments), elementwise, so the values are the same to the last bit; only the piece lookup is
shorter: ``u = 0`` is the first piece at offset 0, ``u = 1`` the last piece (``t = t0 + span`` is at
or beyond the last piece's start, checked; else the general sorted search).
"""
from __future__ import annotations

import functools

import numpy as np

from camgen.contour.tables import SegmentTables
from camgen.geometry import signed_curvature
from camgen.numerics.polynomial import derivative_factors, horner

__all__ = ["spline_end_values"]


def spline_end_values(tables: SegmentTables, segments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit-parameter tangents ``dP/du`` (S, 2, 2), mm, and signed curvatures (S, 2), 1/mm, of the
    spline segments ``segments`` (S,) (indices into the contour's ``tables``) at ``u = 0`` and
    ``u = 1`` (axis 1)."""
    spline = tables.spline_of[segments]
    t0, span = tables.t0[spline], tables.span[spline]
    first = tables.break_start[spline]  # where each spline's breaks start in tables.breaks
    last = tables.break_start[spline + 1] - 2  # its last piece's start break
    row = np.stack([tables.piece_start[spline], tables.piece_start[spline] + tables.n_pieces[spline] - 1], axis=1).ravel()
    got = _end_values(t0, span, tables.breaks[first], tables.breaks[last], tables.rows[row], tables.degree)
    if got is not None:
        return got
    # a span so short that rounding moves an end into another piece: the general lookup
    t = _ends_t(t0, span)
    row, tau = tables.locate(np.repeat(spline, 2), t.ravel())
    return _derivatives(tables.rows[row], tau[:, None], span, tables.degree)


def _ends_t(t0: np.ndarray, span: np.ndarray) -> np.ndarray:
    """The spline parameters (S, 2) at u = 0 and u = 1 (Spline._t(u): breaks[0] + u span)."""
    t = np.empty((t0.size, 2))
    t[:, 0] = t0 + 0.0 * span
    t[:, 1] = t0 + 1.0 * span
    return t


def _end_values(t0: np.ndarray, span: np.ndarray, b_first: np.ndarray, b_last: np.ndarray, rows: np.ndarray,
                degree: int) -> tuple[np.ndarray, np.ndarray] | None:
    """The ends' values from the splines' first parameters ``t0``, spans, first and last pieces'
    start breaks ``b_first``, ``b_last`` (S,) and those pieces' coefficients ``rows`` (2 S, degree
    + 1, 2: first, last of each spline); None if an end is not on its end piece (the sorted search
    would find another)."""
    t = _ends_t(t0, span)
    if not ((t[:, 0] == b_first).all() and (t[:, 1] >= b_last).all()):
        return None
    tau = (t - np.stack([b_first, b_last], axis=1)).ravel()
    return _derivatives(rows, tau[:, None], span, degree)


def _derivatives(c: np.ndarray, tau: np.ndarray, span: np.ndarray, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Tangents (S, 2, 2) and curvatures (S, 2) of the pieces ``c`` (2 S, degree + 1, 2) at offsets
    ``tau`` (2 S, 1): SegmentTables.spline_values' arithmetic."""
    if degree > 3:
        d1, d2 = _first_second(c, tau, degree)
    elif degree != 3:
        d1, d2 = horner(c, tau, 1), horner(c, tau, 2)
    else:
        d1 = (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        d2 = 6.0 * c[:, 0] * tau + 2.0 * c[:, 1]
    tangents = d1 * span.repeat(2)[:, None]
    return tangents.reshape(-1, 2, 2), signed_curvature(d1, d2).reshape(-1, 2)


def _first_second(c: np.ndarray, tau: np.ndarray, degree: int) -> tuple[np.ndarray, np.ndarray]:
    """``horner(c, tau, 1)`` and ``horner(c, tau, 2)`` (:func:`camgen.numerics.polynomial.horner`)
    of a degree > 3, both in one array (2, n, 2): each element by the same products and sums in
    the same order (the second derivative's Horner steps are the first's but its last)."""
    f1, f2 = derivative_factors(degree, 1).tolist(), derivative_factors(degree, 2).tolist()
    acc = c[:, 0] * _factor_column(f1[0], f2[0])
    for m in range(1, degree - 1):
        acc = acc * tau + c[:, m] * _factor_column(f1[m], f2[m])
    return acc[0] * tau + c[:, degree - 1] * f1[degree - 1], acc[1]


@functools.lru_cache(maxsize=32)
def _factor_column(first: float, second: float) -> np.ndarray:
    """The two derivatives' factors of one coefficient as (2, 1, 1), read-only (kept: a few per degree)."""
    out = np.array([first, second]).reshape(2, 1, 1)
    out.flags.writeable = False
    return out
