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

import numpy as np

from camgen.contour.tables import SegmentTables
from camgen.geometry import signed_curvature
from camgen.numerics.polynomial import horner

__all__ = ["spline_end_values"]


def spline_end_values(tables: SegmentTables, segments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit-parameter tangents ``dP/du`` (S, 2, 2), mm, and signed curvatures (S, 2), 1/mm, of the
    spline segments ``segments`` (S,) (indices into the contour's ``tables``) at ``u = 0`` and
    ``u = 1`` (axis 1)."""
    spline = tables.spline_of[segments]
    t0, span = tables.t0[spline], tables.span[spline]
    t = np.empty((spline.size, 2))
    t[:, 0] = t0 + 0.0 * span  # Spline._t(u): breaks[0] + u span
    t[:, 1] = t0 + 1.0 * span
    first = tables.break_start[spline]  # where each spline's breaks start in tables.breaks
    last = tables.break_start[spline + 1] - 2  # its last piece's start break
    if np.all(t[:, 0] == tables.breaks[first]) and np.all(t[:, 1] >= tables.breaks[last]):
        row = np.stack([tables.piece_start[spline], tables.piece_start[spline] + tables.n_pieces[spline] - 1], axis=1).ravel()
        tau = (t - np.stack([tables.breaks[first], tables.breaks[last]], axis=1)).ravel()
    else:  # a span so short that rounding moves an end into another piece: the general lookup
        row, tau = tables.locate(np.repeat(spline, 2), t.ravel())
    c = tables.rows[row]
    tau = tau[:, None]
    if tables.degree != 3:
        d1, d2 = horner(c, tau, 1), horner(c, tau, 2)
    else:
        d1 = (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        d2 = 6.0 * c[:, 0] * tau + 2.0 * c[:, 1]
    tangents = d1 * np.repeat(span, 2)[:, None]
    return tangents.reshape(-1, 2, 2), signed_curvature(d1, d2).reshape(-1, 2)
