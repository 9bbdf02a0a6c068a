"""camgen's own numerical code, one module per job, on numpy arrays (no scipy import at run time
except where a module says so).  It imports nothing of camgen but :mod:`camgen.errors` and
:mod:`camgen.geometry`; the geometry of cams (:mod:`camgen.contour`) and everything above build
on it.

=================  ===========================================================================
``tridiagonal``    tridiagonal and block-tridiagonal systems, cyclic or not (parallel cyclic
                   reduction)
``polynomial``     kernels on polynomial pieces: Horner evaluation of derivatives, scaled bases
``bernstein``      Bezier control values of polynomial pieces and the bounds they give
``roots``          sign changes of many polynomials at once (derivative chain, safeguarded Newton)
``hermite``        Hermite interpolation on pieces (cubic C1, quintic C2)
``interpolate``    interpolating splines: periodic of odd degree, clamped cubic
``ppoly``          :class:`~camgen.numerics.ppoly.PiecewisePolynomial`, a function of one variable
``splinefit``      least-squares cubic B-spline fits within a tolerance (scipy in the clamped fit)
``biarc``          biarcs within a tolerance of a parametric curve
``least_squares``  Levenberg-Marquardt for small nonlinear least-squares problems
``order``          the median from one partition (numpy's imports numpy.ma on first use)
``minimise``       golden-section search for a scalar function's least value on an interval
=================  ===========================================================================

The package namespace imports none of them: import the module you need.
"""
from __future__ import annotations

__all__: list[str] = []
