"""The cam body beside its profile: thickness, shaft bore and keyway, and the wall they leave.

One definition of the keyway shape for every writer (:meth:`BodySpec.keyway_corners`): a
rectangle of ``keyway_width`` centred on the direction ``keyway_angle`` (cam frame), reaching
from the axis to ``bore_diameter / 2 + keyway_depth``.  The mesh subtracts it from the profile
together with the bore; the DXF draws the part outside the bore; STEP cuts its prism.
"""
from __future__ import annotations

import functools
import math
import struct
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from camgen.contour import Contour
from camgen.errors import ParameterError, require_finite, require_positive

if TYPE_CHECKING:
    from camgen.wall_polygon import KeywayTerms

__all__ = ["BodySpec", "WALL_TOL", "kept_keyway_terms", "wall_left"]


@dataclass(frozen=True)
class BodySpec:
    """Cam body: thickness, shaft bore and keyway (mm, rad); ``min_wall`` is the smallest wall
    allowed between bore/keyway and profile.

    ``bore_diameter = 0`` means no bore; ``keyway_width = 0`` no keyway.
    """

    thickness: float = 10.0
    bore_diameter: float = 0.0
    keyway_width: float = 0.0
    keyway_depth: float = 0.0
    keyway_angle: float = math.pi / 2
    min_wall: float = 2.0

    def __post_init__(self) -> None:
        require_positive("thickness", self.thickness)
        for name in ("bore_diameter", "keyway_width", "keyway_depth", "min_wall"):
            if require_finite(name, getattr(self, name)) < 0:
                raise ParameterError(name, getattr(self, name), f"{name} >= 0 mm")
        require_finite("keyway_angle", self.keyway_angle)
        if self.keyway_width > 0 and (self.bore_diameter <= 0 or self.keyway_depth <= 0):
            raise ParameterError("keyway_width", self.keyway_width, "0 unless bore_diameter > 0 and keyway_depth > 0")
        if self.keyway_width >= self.bore_diameter > 0:
            raise ParameterError("keyway_width", self.keyway_width, f"0 <= keyway_width < bore_diameter = {self.bore_diameter:g} mm")
        if self.keyway_width == 0 and (self.keyway_depth > 0):
            raise ParameterError("keyway_depth", self.keyway_depth, "0 unless keyway_width > 0", "a keyway needs a width")

    @property
    def keyway_reach(self) -> float:
        """Distance of the keyway's bottom from the axis, mm."""
        return self.bore_diameter / 2 + self.keyway_depth

    def keyway_corners(self, from_radius: float = 0.0) -> np.ndarray:
        """Corners (4, 2) of the keyway rectangle, counter-clockwise, from ``from_radius`` along
        its centre line out to its bottom (0: from the axis; the bore radius' chord point
        ``sqrt(r^2 - (w/2)^2)``: the part outside the bore)."""
        half = self.keyway_width / 2
        out = self.keyway_reach
        local = np.array([[from_radius, -half], [out, -half], [out, half], [from_radius, half]])
        c, s = math.cos(self.keyway_angle), math.sin(self.keyway_angle)
        return local @ np.array([[c, s], [-s, c]])  # rotated by +keyway_angle

    def keyway_outside_bore(self) -> np.ndarray:
        """The keyway's three sides outside the bore circle: corners (4, 2) from where its sides
        meet the bore circle."""
        r, half = self.bore_diameter / 2, self.keyway_width / 2
        return self.keyway_corners(math.sqrt(r * r - half * half))


#: Chord tolerance (mm) of the profile polygon on which the wall is measured.
WALL_TOL = 1e-4


def kept_keyway_terms(body: BodySpec) -> "KeywayTerms":
    """:func:`camgen.wall_polygon.keyway_terms` of ``body``'s keyway (a body with a keyway), kept
    for bodies alike to the bit (a sweep's designs share their body): a bounded cache keyed by
    the keyway's numbers' bytes (-0.0 is not 0.0 there) and the body; read-only arrays."""
    key = struct.pack("<4d", body.bore_diameter, body.keyway_width, body.keyway_depth, body.keyway_angle)
    return _kept_terms(key, body)


@functools.lru_cache(maxsize=8)
def _kept_terms(key: bytes, body: BodySpec) -> "KeywayTerms":
    from camgen.wall_polygon import keyway_terms

    return keyway_terms(body.keyway_corners(), body.keyway_angle)


def wall_left(contour: Contour, body: BodySpec, chord_tol: float = WALL_TOL) -> tuple[float, float]:
    """Thinnest wall (mm) between bore/keyway and the profile, and the cam angle (deg) where it is.

    Measured on the profile flattened at ``chord_tol`` (every chord within ``chord_tol`` of the
    curve, so the true wall is within ``chord_tol`` of the value; ``chord_tol`` is subtracted
    to stay on the safe side).  Negative: the bore or keyway breaks through.
    """
    if body.bore_diameter <= 0:
        return math.inf, 0.0
    from camgen.wall_polygon import wall_polygon

    terms = kept_keyway_terms(body) if body.keyway_width > 0 else None  # the keyway's own numbers, kept per body
    keyway = terms.corners if terms is not None else None
    part = wall_polygon(contour, chord_tol, body.bore_diameter / 2, keyway, terms)  # the vertices that can decide it (the whole polygon's)
    poly = part.points
    radius = np.hypot(poly[:, 0], poly[:, 1])
    i = int(radius.argmin())
    wall, where = float(radius[i]) - body.bore_diameter / 2, poly[i]
    if body.keyway_width > 0:
        # distance of the profile vertices to the keyway rectangle, in the keyway's frame (the part
        # has >= 2 vertices: OpenBLAS computes each row of an (n >= 2, 2) @ (2,) product as it does in
        # the whole polygon's, not a lone row's; tests/test_wall.py compares with the whole polygon)
        assert terms is not None
        along = poly @ terms.along
        across = poly @ terms.across_dir
        out = body.keyway_reach
        dx = np.maximum(np.maximum(-along, along - out), 0.0)
        dy = np.maximum(np.abs(across) - body.keyway_width / 2, 0.0)
        dist = np.hypot(dx, dy)  # 0 exactly where the vertex is inside the rectangle (dx = dy = 0), else > 0
        # the rectangle's outer corners must lie inside the profile (star-shaped cams)
        assert keyway is not None
        corners = keyway[1:3]
        j = int(dist.argmin())  # the first vertex inside (-1), else the nearest
        k_wall = -1.0 if dist[j] == 0.0 else float(dist[j])
        # two polygons are nearest at a vertex of one and an edge of the other: the profile's
        # vertices against the rectangle (above), and the rectangle's outer corners against the
        # profile's edges (a corner facing the middle of a chord is nearer than both its ends);
        # both corners at once (2, chords), elementwise: each dot product x0 y0 + x1 y1, the sum
        # np.einsum("ij,ij->i") gives (tests/test_wall.py compares with the whole polygon)
        chord = np.flatnonzero(part.successor >= 0)
        start = poly[chord]
        edge = poly[part.successor[chord]] - start
        ex, ey = edge[:, 0], edge[:, 1]
        rx, ry = corners[:, :1] - start[:, 0], corners[:, 1:] - start[:, 1]
        u = ((rx * ex + ry * ey) / np.maximum(ex * ex + ey * ey, 1e-300)).clip(0.0, 1.0)
        gaps = np.hypot(rx - u * ex, ry - u * ey)
        for row, i_edge in enumerate(gaps.argmin(axis=1).tolist()):
            if gaps[row, i_edge] < k_wall:
                k_wall, j = float(gaps[row, i_edge]), int(chord[i_edge])
        # no ray from the axis meets the profile nearer than part.near_axis
        if terms.corner_reach >= part.near_axis:
            reach = contour.polar_radius(np.arctan2(corners[:, 1], corners[:, 0]))
            if np.any(np.hypot(corners[:, 0], corners[:, 1]) >= reach):
                k_wall = min(k_wall, -1.0)
        if k_wall < wall:
            wall, where = k_wall, poly[j]
    return wall - chord_tol, math.degrees(math.atan2(where[1], where[0])) % 360.0
