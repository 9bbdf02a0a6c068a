"""The exact circular arc segment of a :class:`~camgen.contour.Contour`.

Lengths in mm, angles in rad, curvature in 1/mm, positive on a counter-clockwise arc (convex on
a counter-clockwise contour).  A segment's local parameter ``u`` runs over [0, 1].
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.errors import GeometryError, ParameterError, require_positive
from camgen.geometry import angle_in_sweep, unit_vectors

__all__ = ["Arc"]


def _as_array(values: object) -> np.ndarray:
    return np.asarray(values, dtype=float)


_unit = unit_vectors
_angle_in_sweep = angle_in_sweep


@dataclass(frozen=True)
class Arc:
    """An exact circular arc.

    Parameters
    ----------
    center : tuple of float
        Centre (x, y), mm.
    radius : float
        Radius, mm, > 0.
    start_angle : float
        Polar angle of the start point about the centre, rad.
    sweep : float
        Signed sweep, rad: > 0 counter-clockwise about the centre (convex on a CCW contour),
        < 0 clockwise (concave).
    """

    center: tuple[float, float]
    radius: float
    start_angle: float
    sweep: float

    kind = "arc"

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", (float(self.center[0]), float(self.center[1])))
        require_positive("radius", self.radius)
        if not math.isfinite(self.start_angle) or not math.isfinite(self.sweep) or self.sweep == 0:
            raise ParameterError("sweep", self.sweep, "a finite non-zero angle in rad")

    # -- pointwise --------------------------------------------------------------------------
    def angle(self, u: np.ndarray) -> np.ndarray:
        """Polar angle about the centre (rad) at local parameters ``u`` in [0, 1]."""
        return self.start_angle + self.sweep * _as_array(u)

    def point(self, u: np.ndarray) -> np.ndarray:
        """Points (n, 2), mm, at local parameters ``u``."""
        return np.asarray(self.center) + self.radius * _unit(self.angle(u))

    def derivative(self, u: np.ndarray) -> np.ndarray:
        """dP/du (n, 2), mm."""
        a = self.angle(u)
        return self.radius * self.sweep * np.stack([-np.sin(a), np.cos(a)], axis=-1)

    def second_derivative(self, u: np.ndarray) -> np.ndarray:
        """d2P/du2 (n, 2), mm."""
        return -(self.radius * self.sweep**2) * _unit(self.angle(u))

    def curvature(self, u: np.ndarray) -> np.ndarray:
        """Signed curvature (1/mm): +1/r on a counter-clockwise arc, -1/r on a clockwise one."""
        return np.full(np.shape(u), math.copysign(1.0 / self.radius, self.sweep))

    @property
    def start_point(self) -> np.ndarray:
        return self.point(np.array([0.0]))[0]

    @property
    def end_point(self) -> np.ndarray:
        return self.point(np.array([1.0]))[0]

    @property
    def length(self) -> float:
        """Arc length, mm (exact)."""
        return self.radius * abs(self.sweep)

    # -- whole-segment operations ----------------------------------------------------------
    def flatten_params(self, chord_tol: float) -> np.ndarray:
        """Local parameters of a chord polygon with sagitta <= ``chord_tol`` (start included, end excluded).

        The sagitta of a chord spanning the angle ``delta`` is ``r (1 - cos(delta / 2))``, so
        ``delta = 2 acos(1 - chord_tol / r)`` is the widest allowed step.
        """
        ratio = min(chord_tol / self.radius, 2.0)
        max_step = 2.0 * math.acos(1.0 - ratio)
        count = max(1, math.ceil(abs(self.sweep) / max_step - 1e-12))
        return np.arange(count) / count

    def green_area(self) -> float:
        """(1/2) integral of (x dy - y dx) along the arc, mm^2 (exact)."""
        cx, cy = self.center
        r, s = self.radius, self.start_angle
        e = s + self.sweep
        return 0.5 * (r * cx * (math.sin(e) - math.sin(s)) - r * cy * (math.cos(e) - math.cos(s)) + r * r * self.sweep)

    def extreme_points(self) -> np.ndarray:
        """End points and axis-extreme points (k, 2) of the arc: its exact bounding box."""
        axis_angles = np.arange(4) * (math.pi / 2)
        inside = axis_angles[_angle_in_sweep(axis_angles, self.start_angle, self.sweep)]
        pts = [self.start_point[None], self.end_point[None]]
        if inside.size:
            pts.append(np.asarray(self.center) + self.radius * _unit(inside))
        return np.concatenate(pts)

    def offset(self, distance: float, index: int = 0) -> "Arc":
        """The arc offset by ``distance`` along the outward normal of a CCW contour (exact)."""
        new_radius = self.radius + (distance if self.sweep > 0 else -distance)
        if new_radius <= 0.0:
            mid = self.point(np.array([0.5]))[0]
            polar = math.degrees(math.atan2(mid[1], mid[0])) % 360.0
            raise GeometryError(
                f"offset {distance:g} mm of segment {index} (arc of radius {self.radius:g} mm, "
                f"{'concave' if self.sweep < 0 else 'convex'}, around cam angle {polar:.3f} deg) "
                f"would make its radius {new_radius:g} mm <= 0 (undercut): "
                f"use |offset| < {self.radius:g} mm there"
            )
        return Arc(self.center, new_radius, self.start_angle, self.sweep)

    def support_candidates(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Interior support values (M,), contact points (M, 2) and radii of curvature (M,).

        For outward normal angles ``psi`` inside the sweep of a convex arc the contact is
        ``center + r u(psi)`` and ``h = center . u + r``; concave arcs have no interior maxima
        of ``p . u`` (value -inf).
        """
        u = _unit(psi)
        pts = np.asarray(self.center) + self.radius * u
        vals = np.einsum("ij,ij->i", pts, u)
        if self.sweep > 0:
            vals = np.where(_angle_in_sweep(psi, self.start_angle, self.sweep), vals, -np.inf)
        else:
            vals = np.full(psi.shape, -np.inf)
        return vals, pts, np.full(psi.shape, self.radius)

    def ray_hits(self, phi: np.ndarray) -> np.ndarray:
        """Distances (M, 2) along rays from the origin at polar angles ``phi`` to this arc (NaN: no hit)."""
        u = _unit(phi)
        uc = u @ np.asarray(self.center)
        disc = uc * uc - float(np.dot(self.center, self.center)) + self.radius**2
        root = np.sqrt(np.where(disc >= 0, disc, np.nan))
        dist = np.stack([uc - root, uc + root], axis=1)
        pts = dist[..., None] * u[:, None, :] - np.asarray(self.center)
        ang = np.arctan2(pts[..., 1], pts[..., 0])
        on_arc = _angle_in_sweep(ang, self.start_angle, self.sweep) & (dist > 0)
        return np.where(on_arc, dist, np.nan)
