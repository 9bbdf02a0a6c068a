"""The surface mesh of a barrel cam with a rib: the root cylinder less the bore, with the rib on it.

The body is ``{R_bore <= r <= R_i, 0 <= z <= length}`` plus the rib ``{R_i <= r <= R_o,
z_lower(r, phi) <= z <= z_upper(r, phi)}`` (cam frame of :mod:`camgen.synthesis.barrel`; the faces
those of :class:`~camgen.synthesis.barrel.BarrelRib`).  Built as :mod:`camgen.export.barrel_solid`
builds the groove, with the same steps from the chord tolerance and the same measured wall grid
(:func:`~camgen.export.barrel_solid.wall_grid`: every face within ``chord_tol`` of the exact one,
a folded face refused): the two faces on one (r, psi) grid; the rib's top (``r = R_o``) between
the faces' rim rows and the root cylinder (``r = R_i``) from a ring at ``z = 0`` to the lower
face's root row and from the upper face's to a ring at ``z = length``, joined by angle
(:func:`~camgen.export.barrel_solid.zipper`); the bore and the two end faces (annuli from the bore
to the root, or discs).  manifold3d validates it (one closed piece, genus 1 with a bore, 0
without); faces that cross (a rib too thin for its rollers) fail there.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError
from camgen.export.barrel_solid import band, closed_body, half_chord_step, triangle_cap, wall_grid, zipper

if TYPE_CHECKING:
    from camgen.export.solid import CamSolid

__all__ = ["rib_solid"]


def rib_solid(rib: Any, chord_tol: float, cam: str = "cam", formats: tuple[str, ...] | None = None) -> "CamSolid":
    """The :class:`~camgen.export.solid.CamSolid` of the barrel cam with the rib ``rib``
    (:class:`camgen.synthesis.barrel.BarrelRib`): every surface within ``chord_tol`` mm of the exact
    one (module notes), validated by manifold3d; ``formats`` as :func:`~camgen.export.barrel_solid.barrel_solid`'s."""

    rim, root, length, bore = (float(rib.rim_radius), float(rib.root_radius), float(rib.length), float(rib.bore_radius))
    if not 0.0 <= bore < root < rim:
        raise GeometryError(f"cam '{cam}': the barrel needs 0 <= bore radius < root radius < rim radius (bore {bore:g} mm, root "
                            f"{root:g} mm, rim {rim:g} mm)")
    r, psi, (upper, lower), (phi_up, phi_lo) = wall_grid(rib, chord_tol, triangle_cap(formats), cam)
    # manifold3d does not see faces that cross: the lower face's height under each upper-face vertex
    below = rib.wall_height(-1, np.broadcast_to(r[:, None], phi_up.shape), phi_up)
    if not np.all(upper[..., 2] > below):
        raise GeometryError(f"cam '{cam}': the rib's faces cross (its least width along z on the mesh's grid is "
                            f"{float(np.min(upper[..., 2] - below)):.4g} mm): the rollers cut the rib away")
    low, high = float(np.min(lower[..., 2])), float(np.max(upper[..., 2]))
    if not (low > 0.0 and high < length):
        raise GeometryError(f"cam '{cam}': the rib runs from z = {low:.4g} mm to z = {high:.4g} mm, through an end face of the "
                            f"cylinder (length {length:g} mm)")
    rows, n = upper.shape[:2]
    ring_count = max(16, math.ceil(2.0 * math.pi / half_chord_step(rim, chord_tol)))  # the rim's step: finer than the root's
    ring_angle = 2.0 * math.pi * np.arange(ring_count) / ring_count
    c, s = np.cos(ring_angle), np.sin(ring_angle)

    def ring(radius: float, z: float) -> np.ndarray:
        return np.column_stack([radius * c, radius * s, np.full(ring_count, z)])

    blocks = [upper.reshape(-1, 3), lower.reshape(-1, 3), ring(root, 0.0), ring(root, length)]
    up = np.arange(rows * n).reshape(rows, n)
    lo = up + rows * n
    root0 = 2 * rows * n + np.arange(ring_count)
    root1 = root0 + ring_count
    faces = [band(up[i + 1], up[i]) for i in range(rows - 1)]  # the upper face, facing +z: the rib below it
    faces += [band(lo[i], lo[i + 1]) for i in range(rows - 1)]  # the lower face, facing -z
    faces += [zipper(lo[-1], phi_lo[-1], up[-1], phi_up[-1]),  # the rib's top at the rim, facing +r
              zipper(root0, ring_angle, lo[0], phi_lo[0]), zipper(up[0], phi_up[0], root1, ring_angle)]  # the root cylinder
    return closed_body(blocks, faces, root0, root1, ring, bore, length, rim, f"cam '{cam}': the rib", "its faces cross", chord_tol)
