"""The one shared value of camgen: a closed counter-clockwise chain of exact segments.

A :class:`Contour` is a closed, planar, counter-clockwise curve in the cam frame (origin on
the rotation axis), in millimetres.  It is a chain of two kinds of segment:

* :class:`Arc`, an exact circular arc (centre, radius, start angle, signed sweep);
* :class:`Spline`, a parametric piecewise cubic or quintic ``x(t), y(t)`` (C2 inside the
  segment when built by interpolation or quintic Hermite fit; C1 when it is a refitted offset).

Every check and export in camgen works through the operations defined here, so they work for
every cam.  The package imports nothing of camgen but :mod:`camgen.errors`,
:mod:`camgen.geometry` and :mod:`camgen.numerics`.

Parameterisation: a contour with ``n`` segments has the global parameter ``t`` in ``[0, n)``;
``floor(t)`` is the segment index and ``t - floor(t)`` the local parameter ``u`` in ``[0, 1)``.

Conventions: lengths in mm, angles in rad, curvature in 1/mm, positive where the curve turns
left (convex parts of a counter-clockwise contour).  The outward normal is the unit tangent
rotated by -90 deg.

Modules: ``arc`` (:class:`Arc`), ``spline`` (:class:`Spline`, the exact Green area of polynomial
pieces), ``contour`` (:class:`Contour`, :class:`Joint`, the tolerances), ``tables`` (the
per-contour tables of the vectorised queries: evaluation over many segments, polar radius),
``arcspline`` (spline segments as biarcs), ``reach`` (the exact largest distance from the axis), ``ends``
(the splines' end tangents and curvatures at the joints).  The polynomial kernels, interpolation and fits they
use live in :mod:`camgen.numerics`; the Hermite helpers the envelope fit calls are re-exported
here for it.
"""
from __future__ import annotations

from camgen.contour.arc import Arc
from camgen.contour.arcspline import spline_to_biarcs, to_arc_spline
from camgen.contour.contour import DEFAULT_CHORD_TOL, DEFAULT_CLOSURE_TOL, Contour, Joint, Segment
from camgen.contour.spline import SPLINE_DEGREES, Spline, piece_green_areas
from camgen.numerics.hermite import quintic_hermite_coefficients, quintic_hermite_data, quintic_hermite_scaled
from camgen.numerics.polynomial import power_coefficients

__all__ = [
    "DEFAULT_CHORD_TOL",
    "DEFAULT_CLOSURE_TOL",
    "SPLINE_DEGREES",
    "Arc",
    "Contour",
    "Joint",
    "Segment",
    "Spline",
    "piece_green_areas",
    "power_coefficients",
    "quintic_hermite_coefficients",
    "quintic_hermite_data",
    "quintic_hermite_scaled",
    "spline_to_biarcs",
    "to_arc_spline",
]
