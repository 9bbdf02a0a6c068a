"""The least convex radius of curvature of a sampled curve from its curvature, without the
reciprocal of every sample (the undercut check of a roller's pitch curve, per design of a sweep).

The radius of curvature is ``1 / k`` where ``k != 0`` (``inf`` where ``k = 0``); the convex radii
are the positive ones.  A correctly rounded ``1 / k`` does not increase as ``k`` grows, so the
least convex radius is ``1 / max k`` over ``k > 0``; the samples whose reciprocal rounds to that
same value lie within two units in the last place of ``max k``, and the first of them is the
first sample where the radius is least (what ``argmin`` of every sample's radius gives).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["TIE_REL", "least_convex_radius"]

#: Relative distance below the largest curvature within which a sample's reciprocal may round to
#: the least radius (two units in the last place are 4.4e-16): those samples are compared exactly.
TIE_REL = 1e-12


def least_convex_radius(curvature: np.ndarray, top: float | None = None) -> tuple[float, int]:
    """The least positive radius of curvature (mm) of the samples ``curvature`` (1/mm) and the
    first sample where it is, bit for bit ``min`` and ``argmin`` of ``where(rho > 0, rho, inf)``
    with ``rho = where(k != 0, 1 / k, inf)``; ``(inf, 0)`` when no radius is positive and finite.
    ``top``: ``float(curvature.max())`` when the caller has it (a non-empty ``curvature``)."""
    if top is None:
        top = float(curvature.max()) if curvature.size else 0.0  # NaN if any sample is NaN
    if 0.0 < top < math.inf:
        # no NaN, no infinity, and a positive largest: the largest positive curvature, and the
        # samples near it (a threshold > 0: no sample <= 0 passes it) in one comparison
        largest, near_of = top, curvature
    else:
        # NaN is not > 0; an infinite curvature's radius 1 / inf = 0 is not positive either
        near_of = np.where((curvature > 0) & (curvature < math.inf), curvature, 0.0)
        largest = float(near_of.max()) if near_of.size else 0.0
    if not largest > 0 or math.isinf(1.0 / largest):
        return math.inf, 0
    near = np.flatnonzero(near_of >= largest * (1.0 - TIE_REL))
    with np.errstate(over="ignore"):
        radius = 1.0 / curvature[near]
    least = float(radius.min())
    return least, int(near[int((radius == least).argmax())])
