"""Part of a contour's flattened polygon: the vertices :meth:`Contour.flatten
<camgen.contour.Contour.flatten>` gives on some of its pieces only, the same values, and the
Bezier control points of the pieces that say which pieces can matter.

A check that needs the polygon only where it comes near something (the wall between the bore
and the profile: :func:`camgen.body.wall_left`) bounds every piece by the convex hull of its
Bezier control points (the piece lies inside it: Farin, *Curves and Surfaces for CAGD*, ch. 4),
and flattens only the pieces whose bound can reach its answer.  The vertices of a piece come from
the arithmetic of :meth:`Contour.flatten_params <camgen.contour.Contour.flatten_params>` (the
chord count of the piece from the Bezier bound of ``|P''|``, its parameters, the contour's
global parameter), evaluated by :meth:`Contour.evaluate <camgen.contour.Contour.evaluate>`, every
step elementwise: each vertex is the one the whole polygon has (tests/test_wall.py compares them).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from camgen.contour.contour import Contour
from camgen.contour.spline import Spline, acceleration_bound
from camgen.errors import require_positive
from camgen.numerics.bernstein import bezier_matrix

__all__ = ["ContourPieces", "PolygonPart", "contour_pieces", "evaluate_on", "polygon_part"]


@dataclass(frozen=True)
class ContourPieces:
    """The pieces of a contour made of splines of one degree, in order along it (P pieces).

    ``control``: Bezier control points (P, degree + 1, 2), mm (rounded: a bound built on them
    needs a slack); ``counts``: the chords :meth:`Contour.flatten` gives each piece at its chord
    tolerance (P,); ``segment``: each piece's segment (P,); ``start``, ``end``: its first and last
    spline parameter, ``t0``, ``span``: its spline's first parameter and span (P,); ``coeffs``: the
    pieces' power coefficients (degree + 1, P, 2), highest first (the splines' own, concatenated);
    ``first``, ``last``: whether the piece is its spline's first, last (P,).
    """

    contour: Contour
    control: np.ndarray
    counts: np.ndarray
    segment: np.ndarray
    start: np.ndarray
    end: np.ndarray
    t0: np.ndarray
    span: np.ndarray
    coeffs: np.ndarray
    first: np.ndarray
    last: np.ndarray

    @property
    def size(self) -> int:
        """The number of pieces."""
        return int(self.counts.size)


@dataclass(frozen=True)
class PolygonPart:
    """Vertices of ``contour.flatten(chord_tol)``, a subsequence in its order: ``points`` (m, 2),
    mm, and ``successor`` (m,): where the vertex after each in the whole polygon is in
    ``points``, -1 where it is not there (the chord from it is not in the part)."""

    points: np.ndarray
    successor: np.ndarray


def contour_pieces(contour: Contour, chord_tol: float) -> ContourPieces | None:
    """The :class:`ContourPieces` of ``contour`` at chord tolerance ``chord_tol`` (mm), or None for
    a contour with an arc or with splines of two degrees (flatten it whole)."""
    require_positive("chord_tol", chord_tol)
    splines = [seg for seg in contour.segments if isinstance(seg, Spline)]
    if len(splines) != len(contour.segments) or len({s.degree for s in splines}) != 1:
        return None
    degree = splines[0].degree
    pieces = tuple(s.n_pieces for s in splines)
    breaks = np.concatenate([s.breaks for s in splines])  # each spline's K + 1 breaks
    first, at, segment, first_piece, last_piece = _layout(pieces)
    start, end = breaks[at], breaks[at + 1]
    h = end - start  # np.diff of each spline's breaks
    c = np.concatenate([s.coeffs for s in splines], axis=1)  # (degree + 1, P, 2)
    # the chord counts of Spline._chord_params, from the bound of flatten_params_of (elementwise per piece)
    max_acc = acceleration_bound(c, h, degree)
    counts = np.maximum(1, np.ceil(h * np.sqrt(max_acc / (8.0 * chord_tol)) - 1e-12)).astype(int)
    # the pieces in s = tau / h on [0, 1], lowest power first (P, degree + 1, 2), then their Bezier points
    scaled = c[::-1] * (h ** np.arange(degree + 1.0)[:, None])[:, :, None]
    control = np.einsum("ji,ikc->kjc", bezier_matrix(degree), scaled)
    span = np.array([s.span for s in splines])[segment]  # each piece's spline's span (np.repeat's values, one gather)
    return ContourPieces(contour, control, counts, segment, start, end, breaks[first], span, c, first_piece, last_piece)


@functools.lru_cache(maxsize=8)
def _layout(pieces: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Where the pieces of splines of ``pieces`` pieces each (in order) are, all (P,), read-only:
    the index of a piece's spline's first break and of its own first break in the splines'
    concatenated breaks (each spline's K + 1), its spline's number, and whether it is its spline's
    first, last piece.  Kept per piece counts: a study's designs share them (pure integer indices)."""
    first = np.repeat(np.cumsum([0] + [k + 1 for k in pieces[:-1]]), pieces)  # where a piece's spline's breaks start
    at = first + np.arange(sum(pieces)) - np.repeat(np.cumsum([0] + list(pieces[:-1])), pieces)  # a piece's first break
    local = at - first  # the piece's number within its spline
    out = (first, at, np.repeat(np.arange(len(pieces)), pieces), local == 0, local == np.repeat(pieces, pieces) - 1)
    for a in out:
        a.flags.writeable = False
    return out


def polygon_part(pieces: ContourPieces, keep: np.ndarray) -> PolygonPart | None:
    """The vertices of the pieces where ``keep`` (P,) is True, each followed by the first vertex of
    the next piece (the end of its last chord); None when the whole polygon has fewer than 3
    vertices (:meth:`Contour.flatten_params` then takes 3 of its own: flatten it whole)."""
    counts = pieces.counts
    if int(counts.sum()) < 3:
        return None
    after_kept = np.concatenate((keep[-1:], keep[:-1]))
    take = np.where(keep, counts, after_kept.astype(int))  # a piece not kept: its first vertex after a kept one
    piece = np.arange(counts.size).repeat(take)
    first = (take.cumsum() - take).repeat(take)
    j = np.arange(piece.size) - first  # the vertex's number within its piece
    start, end, t0, span, segment = (pieces.start[piece], pieces.end[piece], pieces.t0[piece], pieces.span[piece],
                                     pieces.segment[piece])
    # Spline._chord_params and Contour.flatten_params, vertex by vertex
    frac = j / counts[piece]
    t = start + frac * (end - start)
    params = segment + (t - t0) / span
    points = _evaluate_gathered(pieces, piece, params, (start, end, t0, span, segment))
    successor = np.where(keep[piece], (np.arange(piece.size) + 1) % piece.size, -1)
    return PolygonPart(points, successor)


def evaluate_on(pieces: ContourPieces, piece: np.ndarray, params: np.ndarray) -> np.ndarray:
    """``pieces.contour.evaluate(params)`` (n, 2), mm, for global parameters ``params`` (n,) of
    vertices made on the pieces ``piece`` (n,): the arithmetic of :meth:`Contour.evaluate
    <camgen.contour.Contour.evaluate>` (the segment and spline parameter from the global one, the
    piece's polynomial at the offset from its first break) step by step, without its sorted search
    for the piece: each vertex's own piece is taken where the search would find it (its segment
    is the piece's, and its spline parameter ``t`` has ``start <= t < end``, open at the spline's
    ends as the search's clip is); any other vertex (rounding at a break) by ``evaluate`` itself."""
    return _evaluate_gathered(pieces, piece, params, (pieces.start[piece], pieces.end[piece], pieces.t0[piece], pieces.span[piece],
                                                      pieces.segment[piece]))


def _evaluate_gathered(pieces: ContourPieces, piece: np.ndarray, params: np.ndarray,
                       gathered: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]) -> np.ndarray:
    """:func:`evaluate_on` with the vertices' pieces' ``start``, ``end``, ``t0``, ``span`` and
    ``segment`` (n,) already gathered (:func:`polygon_part` has them)."""
    start, end, t0, span, segment = gathered
    contour = pieces.contour
    n = contour.n_segments
    flat = np.mod(params, n)
    idx = np.minimum(np.floor(flat).astype(int), n - 1)
    u = flat - idx
    t = t0 + u * span  # Spline._t of the vertex's segment, where it is the piece's
    found = (idx == segment) & (pieces.first[piece] | (start <= t)) & (pieces.last[piece] | (t < end))
    tau = (t - start)[:, None]
    c = pieces.coeffs[:, piece]  # (degree + 1, n, 2)
    if c.shape[0] == 4:
        points = ((c[0] * tau + c[1]) * tau + c[2]) * tau + c[3]
    else:  # numerics.polynomial.horner's order 0, on the coefficients' rows
        points = c[0] * 1.0
        for m in range(1, c.shape[0]):
            points = points * tau + c[m]
    if not found.all():
        miss = np.flatnonzero(~found)
        points[miss] = contour.evaluate(params[miss])
    return points
