"""The vertices of a profile's polygon that can decide the wall left between bore/keyway and
profile (:func:`camgen.body.wall_left`), without flattening the whole profile.

The wall is the least, over the vertices of ``contour.flatten(chord_tol)``, of three distances:
a vertex's from the axis less the bore radius, a vertex's from the keyway rectangle (-1 inside
it), and a keyway's outer corner's from a chord.  Each piece of a spline profile lies inside
the convex hull of its Bezier control points (Farin, *Curves and Surfaces for CAGD*, ch. 4), so
those points bound each distance from below over the piece's vertices and chords (a chord runs
to the next piece's first vertex: that point too; :func:`_keep`).  The first vertex of every
piece is at its first control point, so the least distance there bounds the wall from above.  A
piece whose lower bound exceeds that upper bound (by more than :data:`WALL_SLACK_MM` and
:data:`WALL_SLACK_REL`, far above the rounding of the control points and vertices) cannot hold
the wall, nor tie with it: only the other pieces are flattened
(:func:`camgen.contour.partial.polygon_part`, the same vertices in the same order), and the wall,
its vertex and so the cam angle reported are the whole polygon's (tests/test_wall.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camgen.contour.partial import contour_pieces, polygon_part

if TYPE_CHECKING:
    from camgen.contour import Contour
    from camgen.contour.partial import ContourPieces

__all__ = ["KeywayTerms", "WALL_SLACK_MM", "WALL_SLACK_REL", "WallPolygon", "keyway_terms", "wall_polygon"]

#: Absolute slack (mm) by which a piece's lower bound must exceed the upper bound of the wall for
#: the piece to be left out.
WALL_SLACK_MM = 1e-6
#: Relative slack (of the largest control-point coordinate) added to :data:`WALL_SLACK_MM`.
WALL_SLACK_REL = 1e-9


@dataclass(frozen=True)
class WallPolygon:
    """Vertices of the profile's polygon, a subsequence in its order: ``points`` (m, 2), mm;
    ``successor`` (m,): where the next vertex of the whole polygon is in ``points`` (-1: the chord
    from this vertex is left out); ``near_axis``: a lower bound (mm) of the profile's distance from
    the axis."""

    points: np.ndarray
    successor: np.ndarray
    near_axis: float


@dataclass(frozen=True)
class KeywayTerms:
    """What the wall's bounds and distances take of a keyway rectangle alone (read-only arrays):
    its ``corners`` (4, 2), mm (:meth:`camgen.body.BodySpec.keyway_corners`); the unit
    directions along (``side``) and across (``across``) it, its length ``out`` and ``width``
    (mm), the middle ``mid`` of its axis side; ``along``, ``across_dir``: ``(cos, sin)`` and
    ``(-sin, cos)`` of ``angle`` (the keyway's direction, rad; :func:`camgen.body.wall_left`'s
    frame); ``corner_reach``: the outer corners' largest distance from the axis (mm)."""

    corners: np.ndarray
    side: np.ndarray
    across: np.ndarray
    out: float
    width: float
    mid: np.ndarray
    along: np.ndarray
    across_dir: np.ndarray
    corner_reach: float


def keyway_terms(keyway: np.ndarray, angle: float) -> KeywayTerms:
    """:class:`KeywayTerms` of the keyway rectangle ``keyway`` (corners (4, 2), as
    :meth:`camgen.body.BodySpec.keyway_corners` gives them; copied) in the direction ``angle`` (rad)."""
    keyway = np.array(keyway, dtype=float)
    side, across = keyway[1] - keyway[0], keyway[3] - keyway[0]
    out, width = math.hypot(*side), math.hypot(*across)
    c, s = math.cos(angle), math.sin(angle)
    outer = keyway[1:3]
    terms = KeywayTerms(keyway, side / out, across / width, out, width, 0.5 * (keyway[0] + keyway[3]), np.array([c, s]),
                        np.array([-s, c]), float(np.hypot(outer[:, 0], outer[:, 1]).max()))
    for a in (terms.corners, terms.side, terms.across, terms.mid, terms.along, terms.across_dir):
        a.flags.writeable = False
    return terms


def _keep(pieces: "ContourPieces", bore: float, keyway: np.ndarray | None,
          terms: KeywayTerms | None = None) -> tuple[np.ndarray, float]:
    """The pieces that may hold the wall to a bore of radius ``bore`` (mm) and the keyway
    rectangle ``keyway`` (its corners (4, 2): axis side, outer, outer, axis side; None: no
    keyway), (P,), and a lower bound of the profile's distance from the axis (mm).

    A piece's lower bounds come from the half-plane through its nearest control point across the
    direction ``n`` of the middle of its chord: a point ``p`` of its hull and ``r`` of the bore or
    keyway have ``|p - r| >= (p - r) . n >= min(control . n) - max(r . n)`` (tight along a base
    circle).  A piece's chords end on it or at the next piece's first vertex: its hull and that
    point."""
    control = pieces.control  # (P, degree + 1, 2)
    slack = WALL_SLACK_MM + WALL_SLACK_REL * float(np.abs(control).max())
    starts = control[:, 0]
    middle = starts + control[:, -1]
    length = np.hypot(middle[:, 0], middle[:, 1])
    n = middle / np.where(length > 0, length, 1.0)[:, None]  # (P, 2), 0 for a chord through the axis
    reach = np.einsum("pjc,pc->pj", control, n).min(axis=1)  # (P,): the least p . n over the piece's hull
    upper = float(np.hypot(starts[:, 0], starts[:, 1]).min()) - bore
    lower = reach - bore
    if keyway is not None:
        kt = keyway_terms(keyway, 0.0) if terms is None else terms  # (the angle's terms are wall_left's)
        keyway, out, width = kt.corners, kt.out, kt.width
        rel = starts - kt.mid  # from the middle of the axis side: the rectangle [0, out] x [-width / 2, width / 2]
        along, off = rel @ kt.side, rel @ kt.across
        gaps = np.hypot(np.maximum(np.maximum(-along, along - out), 0.0), np.maximum(np.abs(off) - 0.5 * width, 0.0))
        upper = min(upper, float(gaps.min()))
        to_keyway = reach - (n @ keyway.T).max(axis=1)
        to_keyway[to_keyway <= slack] = -np.inf  # the hull may meet the keyway: a vertex may be inside (-1)
        # a chord from the piece to the next piece's first vertex: the outer corners against both
        both = np.minimum(reach, np.einsum("pc,pc->p", np.concatenate((starts[1:], starts[:1])), n))
        to_corner = both - (n @ keyway[1:3].T).max(axis=1)
        lower = np.minimum(np.minimum(lower, to_keyway), to_corner)
    return lower <= upper + slack, float(reach.min()) - slack


def wall_polygon(contour: "Contour", chord_tol: float, bore: float, keyway: np.ndarray | None,
                 terms: KeywayTerms | None = None) -> WallPolygon:
    """The vertices of ``contour.flatten(chord_tol)`` that can decide the wall to a bore of radius
    ``bore`` (mm) and the keyway rectangle ``keyway`` (corners (4, 2) as
    :meth:`camgen.body.BodySpec.keyway_corners` gives them; None: no keyway): those of the pieces
    that may hold it (a profile of splines of one degree), else every vertex.  ``terms``: the
    keyway's :class:`KeywayTerms` when the caller has them (else made from ``keyway``)."""
    pieces = contour_pieces(contour, chord_tol)
    if pieces is not None:
        keep, near_axis = _keep(pieces, bore, keyway, terms)
        part = polygon_part(pieces, keep)
        if part is not None:
            return WallPolygon(part.points, part.successor, near_axis)
    poly = contour.flatten(chord_tol)
    successor = (np.arange(len(poly)) + 1) % len(poly)
    # every point of a chord is at least the nearer vertex's distance less half the chord from the
    # axis, and the profile is within chord_tol of its chords
    chords = np.hypot(*(poly[successor] - poly).T)
    near_axis = float(np.min(np.hypot(poly[:, 0], poly[:, 1]))) - 0.5 * float(np.max(chords)) - chord_tol
    return WallPolygon(poly, successor, near_axis)
