"""The polynomial curve segment of a :class:`~camgen.contour.Contour`: :class:`Spline`, a planar
piecewise cubic or quintic ``P(t) = (x(t), y(t))``.

It is the *curve* (the geometry a contour needs: tangents, curvature, chord bounds, offsets,
support, ray hits); :class:`camgen.numerics.ppoly.PiecewisePolynomial` is the *function* of one
variable.  Both hold scipy ``PPoly``'s layout and evaluate with the kernels of
:mod:`camgen.numerics.polynomial`; the interpolating constructors come from
:mod:`camgen.numerics.interpolate` and :mod:`camgen.numerics.hermite`, the root finding from
:mod:`camgen.numerics.roots`, the Bezier bounds from :mod:`camgen.numerics.bernstein`.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from camgen.errors import GeometryError, ParameterError
from camgen.geometry import outward_normal, signed_curvature, unit_vectors
from camgen.numerics.bernstein import bernstein_max_norm, bezier_matrix, power_to_bezier
from camgen.numerics.hermite import cubic_hermite_coefficients, quintic_hermite_coefficients
from camgen.numerics.interpolate import clamped_cubic, periodic_spline
from camgen.numerics.polynomial import derivative_factors, exponents, horner, scaled_ascending
from camgen.numerics.roots import ROOT_TOL, grouped_sign_change_roots, roots_in_pieces, sign_change_roots

__all__ = ["BOX_SLACK", "SPLINE_DEGREES", "Spline", "acceleration_bound", "bounding_box_of", "extreme_points_of", "flatten_params_of", "piece_green_areas"]

#: Polynomial degrees a :class:`Spline` piece may have.
SPLINE_DEGREES = (3, 5)
#: Relative slack (of the largest coordinate) by which a piece's Bezier hull must reach beyond the
#: box of the break points for :func:`bounding_box_of` to look for its extremes (rounding of the
#: control points kept on the safe side: a piece kept in vain only costs its roots).
BOX_SLACK = 1e-9


def _as_array(values: object) -> np.ndarray:
    return np.asarray(values, dtype=float)


_unit = unit_vectors


@functools.lru_cache(maxsize=None)
def _area_weights(degree: int) -> np.ndarray:
    """The (degree + 1, degree + 1) matrix ``W[i, m] = (m - i) / (i + m)`` for ``i < m`` (0 elsewhere)
    of :func:`piece_green_areas` (read-only; complex, as it multiplies complex coefficients)."""
    i, m = np.triu_indices(degree + 1, 1)
    w = np.zeros((degree + 1, degree + 1), dtype=complex)
    w[i, m] = (m - i) / (i + m)
    w.flags.writeable = False
    return w


@functools.lru_cache(maxsize=None)
def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``n``-point Gauss-Legendre nodes and weights on [-1, 1] (numpy's, computed once; read-only)."""
    nodes, weights = np.polynomial.legendre.leggauss(n)
    nodes.flags.writeable = False
    weights.flags.writeable = False
    return nodes, weights


def piece_green_areas(q: np.ndarray) -> np.ndarray:
    """``(1/2) integral of (x dy - y dx)`` (mm^2, exact) over every piece of polynomial curves
    given by their scaled coefficients ``q`` (degree + 1, K, ...), complex ``x + i y``, lowest power
    first: piece k is ``sum_i q[i, k] s^i`` for ``s`` in [0, 1] (``q_i = p_i h^i`` of a piece
    ``sum_i p_i tau^i`` on ``[0, h]``); returns (K, ...).

    ``x y' - y x' = sum_{i<m} (m - i) (q_i x q_m) s^(i+m-1)`` integrates to ``sum_{i<m} (m - i) /
    (i + m) (q_i x q_m)``; with ``q_i x q_m = Im(conj(q_i) q_m)`` that is ``Im(sum_i conj(q_i) (W q)_i)``
    (:func:`_area_weights`)."""
    d = q.shape[0] - 1
    wq = _area_weights(d) @ q.reshape(d + 1, -1)
    wq *= np.conj(q).reshape(wq.shape)
    return 0.5 * wq.sum(axis=0).imag.reshape(q.shape[1:])


class Spline:
    """A parametric piecewise polynomial ``P(t) = (x(t), y(t))`` on ``breaks[0] <= t <= breaks[-1]``,
    every piece of the same degree (3: cubic, 5: quintic; :data:`SPLINE_DEGREES`).

    Parameters
    ----------
    breaks : array (K + 1,)
        Strictly increasing break points of the parameter.
    coeffs : array (degree + 1, K, 2)
        Polynomial coefficients per piece, highest power first (scipy ``PPoly`` convention):
        ``P(t) = sum_m coeffs[m, i] (t - breaks[i]) ** (degree - m)`` on piece ``i``.

    Instances are immutable: the arrays are copied and made read-only.
    """

    kind = "spline"

    def __init__(self, breaks: np.ndarray, coeffs: np.ndarray) -> None:
        breaks = np.array(breaks, dtype=float)
        coeffs = np.array(coeffs, dtype=float)
        if breaks.ndim != 1 or breaks.size < 2 or not (breaks[1:] > breaks[:-1]).all():
            raise ParameterError("breaks", f"array of shape {breaks.shape}", "a strictly increasing 1-D array of >= 2 values")
        if (coeffs.ndim != 3 or coeffs.shape[0] - 1 not in SPLINE_DEGREES or coeffs.shape[1:] != (breaks.size - 1, 2)
                or not np.isfinite(coeffs).all()):
            raise ParameterError("coeffs", f"array of shape {coeffs.shape}",
                                 f"finite values of shape (degree + 1, {breaks.size - 1}, 2), degree one of {SPLINE_DEGREES}")
        breaks.flags.writeable = False
        coeffs.flags.writeable = False
        self.breaks = breaks
        self.coeffs = coeffs
        self.degree = coeffs.shape[0] - 1

    @classmethod
    def _checked_by_caller(cls, breaks: np.ndarray, coeffs: np.ndarray) -> "Spline":
        """A spline of arrays its caller has checked (float ``breaks`` strictly increasing, finite
        float ``coeffs`` of shape (degree + 1, K, 2), possibly a view into a larger block): made
        read-only, neither copied nor checked again (the envelope fit checks all its segments at once)."""
        spline = cls.__new__(cls)
        breaks.flags.writeable = False
        coeffs.flags.writeable = False
        spline.breaks = breaks
        spline.coeffs = coeffs
        spline.degree = coeffs.shape[0] - 1
        return spline

    @functools.cached_property
    def _rows(self) -> np.ndarray:
        """The coefficients as (K, degree + 1, 2), contiguous, for fast gathers of whole pieces."""
        return np.ascontiguousarray(self.coeffs.transpose(1, 0, 2))

    # -- constructors ------------------------------------------------------------------------
    @classmethod
    def interpolate(
        cls,
        t: np.ndarray,
        points: np.ndarray,
        periodic: bool = True,
        end_derivatives: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> "Spline":
        """Cubic spline through ``points`` (n, 2) at parameters ``t`` (n,).

        ``periodic=True`` gives the periodic C2 spline (``points[-1]`` must equal ``points[0]``);
        otherwise the ends are clamped to ``end_derivatives`` (dP/dt at both ends), or use the
        not-a-knot condition when those are not given.
        """
        t = _as_array(t)
        points = _as_array(points)
        if t.ndim != 1 or t.size < 3 or points.shape != (t.size, 2) or not np.all(np.diff(t) > 0):
            raise ParameterError("t", f"{t.size} parameters for points of shape {points.shape}",
                                 "strictly increasing parameters, one per point (n, 2), n >= 3")
        if periodic:
            if not np.allclose(points[0], points[-1], rtol=0, atol=1e-9):
                raise GeometryError("a periodic spline needs its last point equal to its first")
            points = points.copy()
            points[-1] = points[0]
            return cls(t, periodic_spline(t, points, 3).c)
        if end_derivatives is not None:
            return cls(t, clamped_cubic(t, points, *(np.asarray(d, dtype=float) for d in end_derivatives)))
        from scipy.interpolate import CubicSpline  # lazy: scipy.interpolate costs ~0.5 s to import

        spline = CubicSpline(t, points, bc_type="not-a-knot")
        return cls(spline.x, spline.c)

    @classmethod
    def hermite(cls, t: np.ndarray, points: np.ndarray, derivatives: np.ndarray) -> "Spline":
        """C1 piecewise cubic Hermite interpolant of ``points`` (n, 2) and ``derivatives`` dP/dt (n, 2) at ``t`` (n,)."""
        t = _as_array(t)
        return cls(t, cubic_hermite_coefficients(t, _as_array(points), _as_array(derivatives)))

    @classmethod
    def hermite5(cls, t: np.ndarray, points: np.ndarray, first: np.ndarray, second: np.ndarray) -> "Spline":
        """C2 piecewise quintic Hermite interpolant of ``points`` (n, 2) and their first and second
        derivatives ``first``, ``second`` (d/dt, d2/dt2, (n, 2) each) at ``t`` (n,): on every piece the
        one quintic with those values at both ends (its error on a piece of length ``h`` is at most
        ``h^6 max|P^(6)| / 46080``: the interpolation remainder ``P^(6)/6! (t - a)^3 (t - b)^3``)."""
        return cls(t, quintic_hermite_coefficients(_as_array(t), _as_array(points), _as_array(first), _as_array(second)))

    # -- pointwise ---------------------------------------------------------------------------
    @property
    def span(self) -> float:
        return float(self.breaks[-1] - self.breaks[0])

    @property
    def n_pieces(self) -> int:
        return self.breaks.size - 1

    def _locate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        idx = np.minimum(np.maximum(np.searchsorted(self.breaks, t, side="right") - 1, 0), self.n_pieces - 1)  # np.clip, fewer calls
        return idx, t - self.breaks[idx]

    def eval_t(self, t: np.ndarray, order: int = 0) -> np.ndarray:
        """d^order P / dt^order (n, 2) at spline parameters ``t``."""
        idx, tau = self._locate(_as_array(t))
        return self.eval_piece(idx, tau, order)

    def eval_piece(self, idx: np.ndarray, tau: np.ndarray, order: int = 0) -> np.ndarray:
        """d^order P / dt^order (n, 2) at offsets ``tau`` from the start of pieces ``idx``."""
        if not 0 <= order <= self.degree:
            raise ValueError(f"order must be 0..{self.degree}")
        c = self._rows[idx]  # (n, degree + 1, 2): one contiguous gather
        tau = tau[:, None]
        if self.degree != 3:
            return horner(c, tau, order)
        if order == 0:
            return ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3]
        if order == 1:
            return (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        if order == 2:
            return 6.0 * c[:, 0] * tau + 2.0 * c[:, 1]
        return 6.0 * c[:, 0]

    def derivatives(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """P, dP/dt and d2P/dt2 (each (n, 2)) at spline parameters ``t``, with one piece lookup."""
        idx, tau = self._locate(_as_array(t))
        c = self._rows[idx]
        tau = tau[:, None]
        if self.degree != 3:
            return horner(c, tau, 0), horner(c, tau, 1), horner(c, tau, 2)
        p = ((c[:, 0] * tau + c[:, 1]) * tau + c[:, 2]) * tau + c[:, 3]
        d1 = (3.0 * c[:, 0] * tau + 2.0 * c[:, 1]) * tau + c[:, 2]
        d2 = 6.0 * c[:, 0] * tau + 2.0 * c[:, 1]
        return p, d1, d2

    def _t(self, u: np.ndarray) -> np.ndarray:
        return self.breaks[0] + _as_array(u) * self.span

    def point(self, u: np.ndarray) -> np.ndarray:
        """Points (n, 2), mm, at local parameters ``u`` in [0, 1]."""
        return self.eval_t(self._t(u))

    def derivative(self, u: np.ndarray) -> np.ndarray:
        return self.eval_t(self._t(u), 1) * self.span

    def second_derivative(self, u: np.ndarray) -> np.ndarray:
        return self.eval_t(self._t(u), 2) * self.span**2

    def curvature(self, u: np.ndarray) -> np.ndarray:
        """Signed curvature, 1/mm."""
        _, d1, d2 = self.derivatives(self._t(u))
        return signed_curvature(d1, d2)

    @property
    def start_point(self) -> np.ndarray:
        return self.coeffs[-1, 0].copy()  # P at tau = 0 of the first piece (what eval_t gives there)

    @property
    def end_point(self) -> np.ndarray:
        (x, y), *rest = self._rows[-1].tolist()  # the last piece at its end, by the arithmetic of eval_piece (Horner)
        tau = float(self.breaks[-1] - self.breaks[-2])
        for cx, cy in rest:
            x = x * tau + cx
            y = y * tau + cy
        return np.array([x, y])

    def _ascending(self) -> np.ndarray:
        """Coefficients (degree + 1, K, 2), lowest power first."""
        return self.coeffs[::-1]

    @property
    def length(self) -> float:
        """Arc length, mm, by 16-point Gauss-Legendre quadrature on every piece (error < 1e-12 relative for smooth pieces)."""
        nodes, weights = _gauss_legendre(16)
        h = np.diff(self.breaks)
        tau = 0.5 * (nodes[:, None] + 1.0) * h[None, :]  # (16, K)
        d1 = self.eval_piece(np.tile(np.arange(self.n_pieces), 16), tau.ravel(), 1).reshape(16, -1, 2)
        speed = np.hypot(d1[..., 0], d1[..., 1])
        return float(np.sum(weights[:, None] * speed * 0.5 * h[None, :]))

    # -- whole-segment operations -------------------------------------------------------------
    def flatten_params(self, chord_tol: float) -> np.ndarray:
        """Local parameters of a chord polygon within ``chord_tol`` of the curve (end excluded).

        On a piece of parameter length ``h`` the chord deviates from the curve by at most
        ``h^2 / 8 * max |P''|`` (linear-interpolation error bound); ``P''`` is linear on a cubic
        piece, so its largest norm is at one of the piece's ends; on a quintic piece its largest
        norm is bounded by its Bezier control points (:func:`_bernstein_max_norm`).
        """
        return flatten_params_of([self], chord_tol)[0]

    def _chord_params(self, max_acc: np.ndarray, chord_tol: float) -> np.ndarray:
        """:meth:`flatten_params` given the bound ``max_acc`` (K,) of ``|P''|`` on every piece."""
        h = np.diff(self.breaks)
        counts = np.maximum(1, np.ceil(h * np.sqrt(max_acc / (8.0 * chord_tol)) - 1e-12)).astype(int)
        piece = np.repeat(np.arange(self.n_pieces), counts)
        first = np.repeat(np.cumsum(counts) - counts, counts)
        frac = (np.arange(counts.sum()) - first) / counts[piece]
        t = self.breaks[piece] + frac * h[piece]
        return (t - self.breaks[0]) / self.span

    def min_turning(self) -> float:
        """Smallest ``P' x P''`` over the spline (its sign is the sign of the curvature), exact.

        On a cubic piece ``P' x P''`` is the quadratic ``-6 (a x b) t^2 + 6 (c x a) t + 2 (c x b)``
        (``P = a t^3 + b t^2 + c t + d``); its minimum is at an end or at the vertex.  Other
        degrees: :meth:`_min_turning_generic` (degree 6 on a quintic piece).
        """
        if self.degree != 3:
            return self._min_turning_generic()
        a, b, c = self.coeffs[0], self.coeffs[1], self.coeffs[2]

        def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
            return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]

        qa, qb, qc = -6.0 * cross(a, b), 6.0 * cross(c, a), 2.0 * cross(c, b)
        h = np.diff(self.breaks)
        with np.errstate(divide="ignore", invalid="ignore"):
            vertex = np.clip(np.where(qa != 0, -qb / (2.0 * qa), 0.0), 0.0, h)
        values = [qc, (qa * h + qb) * h + qc, (qa * vertex + qb) * vertex + qc]
        return float(np.min(values))

    def _scaled(self) -> np.ndarray:
        """Coefficients (K, degree + 1, 2), lowest power first, of ``Q(s) = P(breaks[i] + h_i s)``, s in [0, 1]."""
        return scaled_ascending(self.coeffs, np.diff(self.breaks))

    def _min_turning_generic(self) -> float:
        """:meth:`min_turning` for any degree: with ``Q(s) = sum_i q_i s^i`` (``s = tau / h``),
        ``Q' x Q'' = sum_{k<m} k m (m - k) (q_k x q_m) s^(k+m-3)`` (degree ``2 degree - 4``; 6 for a
        quintic); its minimum on a piece is at an end or where its derivative changes sign."""
        q = self._scaled()  # (K, d + 1, 2)
        d = self.degree
        w = np.zeros((self.n_pieces, 2 * d - 3))
        for k in range(1, d + 1):
            for m in range(k + 1, d + 1):
                w[:, k + m - 3] += k * m * (m - k) * (q[:, k, 0] * q[:, m, 1] - q[:, k, 1] * q[:, m, 0])
        piece, tau = roots_in_pieces(w[:, 1:] * np.arange(1, w.shape[1]), np.diff(self.breaks))
        h = np.diff(self.breaks)
        everywhere = np.arange(self.n_pieces)
        idx = np.concatenate([everywhere, everywhere, piece])
        at = np.concatenate([np.zeros(self.n_pieces), h, tau])
        d1, d2 = self.eval_piece(idx, at, 1), self.eval_piece(idx, at, 2)
        return float(np.min(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]))

    def green_area(self) -> float:
        """(1/2) integral of (x dy - y dx) along the spline, mm^2 (exact polynomial integration,
        :func:`piece_green_areas` of the coefficients scaled to each piece)."""
        h = self.breaks[1:] - self.breaks[:-1]
        return float(piece_green_areas(self.coeffs.view(complex)[::-1, :, 0] * h ** exponents(self.degree)).sum())

    def _quadratic_roots(self, qa: np.ndarray, qb: np.ndarray, qc: np.ndarray) -> np.ndarray:
        """Real roots (2, ...) of qa tau^2 + qb tau + qc inside each piece, NaN elsewhere."""
        h = np.diff(self.breaks).reshape((-1,) + (1,) * (qa.ndim - 1))
        with np.errstate(divide="ignore", invalid="ignore"):
            disc = qb * qb - 4.0 * qa * qc
            sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
            # numerically stable pair of roots; linear case where qa is ~0
            q = -0.5 * (qb + np.copysign(sq, qb))
            r1 = np.where(np.abs(qa) > 1e-300, q / qa, -qc / qb)
            r2 = np.where(np.abs(q) > 1e-300, qc / q, np.nan)
        roots = np.stack([r1, r2])
        # a root on a knot may round to just outside [0, h]: accept it within ROOT_TOL of the piece
        slack = ROOT_TOL * h
        inside = (roots >= -slack) & (roots <= h + slack)
        return np.where(inside, np.clip(roots, 0.0, h), np.nan)

    def extreme_points(self) -> np.ndarray:
        """Break points and axis-extreme points (k, 2): the exact bounding box of the spline."""
        if self.degree != 3:
            # x'(s) and y'(s) (degree 4 for a quintic): the extremes are at their sign changes
            return extreme_points_of([self])[0]
        c = self.coeffs
        pts = [self.eval_t(self.breaks)]
        for axis in range(2):
            roots = self._quadratic_roots(3 * c[0][:, axis], 2 * c[1][:, axis], c[2][:, axis])
            piece = np.broadcast_to(np.arange(self.n_pieces), roots.shape)
            ok = np.isfinite(roots)
            if ok.any():
                pts.append(self.eval_t(self.breaks[piece[ok]] + roots[ok]))
        return np.concatenate(pts)

    def ray_hits(self, phi: np.ndarray, iterations: int = 60) -> np.ndarray:
        """Distances (M, 1) along rays from the origin at polar angles ``phi`` to this spline (NaN: no hit).

        The piece where ``u x P`` changes sign from - to + (with ``P . u > 0``) holds the hit;
        safeguarded Newton steps refine it to 1e-13 in the parameter.  One hit per ray is
        returned (the first such piece); :meth:`Contour.polar_radius` checks that there is one.
        """
        u = _unit(phi)
        pts = self.eval_t(self.breaks)  # (K + 1, 2)
        if np.allclose(pts[0], pts[-1], rtol=0, atol=1e-9):
            pts[-1] = pts[0]  # a closed spline: its two ends are one break, counted once
        g = np.outer(u[:, 0], pts[:, 1]) - np.outer(u[:, 1], pts[:, 0])  # (M, K + 1) = u x P
        ahead = (u @ pts.T) > 0
        crossing = (g[:, :-1] < 0) & (g[:, 1:] >= 0) & (ahead[:, :-1] | ahead[:, 1:])  # half-open: a break counts once
        count = crossing.sum(axis=1)
        piece = np.argmax(crossing, axis=1)
        lo = self.breaks[piece].copy()
        hi = self.breaks[piece + 1].copy()
        g0, g1 = g[np.arange(phi.size), piece], g[np.arange(phi.size), piece + 1]
        t = lo + (hi - lo) * np.clip(-g0 / np.where(g1 - g0 != 0, g1 - g0, 1.0), 0.0, 1.0)
        for _ in range(iterations):
            p = self.eval_t(t)
            dp = self.eval_t(t, 1)
            gt = u[:, 0] * p[:, 1] - u[:, 1] * p[:, 0]
            dg = u[:, 0] * dp[:, 1] - u[:, 1] * dp[:, 0]
            lo = np.where(gt < 0, t, lo)
            hi = np.where(gt > 0, t, hi)
            new = t - np.where(dg != 0, gt / np.where(dg != 0, dg, 1.0), 0.0)
            new = np.where((new <= lo) | (new >= hi) | ~np.isfinite(new), 0.5 * (lo + hi), new)
            converged = np.max(np.abs(new - t), initial=0.0) <= 1e-13 * max(1.0, self.span)
            t = new
            if converged:
                break
        dist = np.einsum("ij,ij->i", self.eval_t(t), u)
        out = np.where(count >= 1, dist, np.nan)
        if np.any(count > 1):
            out = np.where(count > 1, np.inf, out)  # several crossings: flagged for the caller
        return out[:, None]

    def support_candidates(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Largest interior value of ``P . u(psi)`` (M,) over all pieces, its point (M, 2) and radius of curvature (M,).

        Interior extrema of ``P(t) . u`` are roots of the quadratic ``P'(t) . u = 0`` on each piece
        (cubic pieces; other degrees: :meth:`_support_candidates_generic`).
        """
        if self.degree != 3:
            return self._support_candidates_generic(psi)
        u = _unit(psi)  # (M, 2)
        c = self.coeffs  # (4, K, 2)
        # coefficients of P'(tau).u per (piece, direction): (K, M)
        qa = 3.0 * (c[0] @ u.T)
        qb = 2.0 * (c[1] @ u.T)
        qc = c[2] @ u.T
        roots = self._quadratic_roots(qa, qb, qc)  # (2, K, M)
        tau = np.nan_to_num(roots, nan=0.0)
        vals = np.zeros_like(roots)
        for m in range(4):  # Horner on P(tau) . u
            vals = vals * tau + (c[m] @ u.T)[None]
        vals = np.where(np.isfinite(roots), vals, -np.inf)
        flat = vals.reshape(-1, psi.size)
        best = np.argmax(flat, axis=0)
        best_val = flat[best, np.arange(psi.size)]
        root_idx, piece = np.divmod(best, self.n_pieces)
        t = self.breaks[piece] + tau[root_idx, piece, np.arange(psi.size)]
        d1, d2 = self.eval_t(t, 1), self.eval_t(t, 2)
        with np.errstate(divide="ignore"):
            rho = np.hypot(d1[:, 0], d1[:, 1]) ** 3 / (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
        return best_val, self.eval_t(t), rho

    def _support_candidates_generic(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`support_candidates` for any degree.

        ``f(s) = Q'(s) . u`` (``Q(s) = P(breaks[i] + h s)``) is a polynomial of degree
        ``degree - 1`` whose Bezier control values on [0, 1] are ``B_j . u`` (``B_j`` the control
        points of ``Q'``): where they keep one sign ``f`` has no root on the piece (convex-hull
        property).  Only the (piece, direction) pairs where they change sign (within a slack
        covering the :data:`ROOT_TOL` extension of the piece) are solved, by :func:`sign_change_roots`.
        """
        u = _unit(psi)  # (M, 2)
        m_dirs = psi.size
        q = self._scaled()  # (K, d + 1, 2)
        d = self.degree
        bez = power_to_bezier(q[:, 1:] * np.arange(1, d + 1)[None, :, None])  # (K, d, 2): control points of Q'
        # |f| changes by at most |f'| ROOT_TOL <= 2 (d - 1) max|B| ROOT_TOL on the slack
        slack = 2.0 * (d - 1) * ROOT_TOL * np.max(np.hypot(bez[..., 0], bez[..., 1]), axis=1)  # (K,)
        lowest = np.full((self.n_pieces, m_dirs), np.inf)
        highest = np.full((self.n_pieces, m_dirs), -np.inf)
        for j in range(d):
            bj = bez[:, j] @ u.T  # (K, M)
            np.minimum(lowest, bj, out=lowest)
            np.maximum(highest, bj, out=highest)
        piece, direction = np.nonzero((lowest < slack[:, None]) & (highest > -slack[:, None]))
        best_val = np.full(m_dirs, -np.inf)
        best_piece = np.zeros(m_dirs, dtype=int)
        best_tau = np.zeros(m_dirs)
        if piece.size:
            uu = u[direction]
            f = (q[piece, 1:, 0] * uu[:, :1] + q[piece, 1:, 1] * uu[:, 1:]) * np.arange(1, d + 1)  # (n, d)
            s = sign_change_roots(f, -ROOT_TOL, 1.0 + ROOT_TOL)  # (n, d - 1)
            row, col = np.nonzero(np.isfinite(s))
            if row.size:
                h = np.diff(self.breaks)
                pc = piece[row]
                tau = np.clip(s[row, col], 0.0, 1.0) * h[pc]
                dr = direction[row]
                vals = np.einsum("ij,ij->i", self.eval_piece(pc, tau), u[dr])
                order = np.lexsort((vals, dr))  # by direction, then value: the last of each direction wins
                last = order[np.append(dr[order][1:] != dr[order][:-1], True)]
                best_val[dr[last]] = vals[last]
                best_piece[dr[last]] = pc[last]
                best_tau[dr[last]] = tau[last]
        pts = self.eval_piece(best_piece, best_tau)
        d1, d2 = self.eval_piece(best_piece, best_tau, 1), self.eval_piece(best_piece, best_tau, 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = np.hypot(d1[:, 0], d1[:, 1]) ** 3 / (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
        return best_val, pts, rho

    def offset(self, distance: float, index: int = 0, tol: float = 1e-6) -> "Spline":
        """Offset along the outward normal of a CCW contour, refitted as a piecewise cubic.

        The exact offset ``Q = P + d n`` has tangent ``Q' = P' (1 + d kappa)``; where
        ``1 + d kappa <= 0`` the offset reverses (cusp, undercut) and a :class:`GeometryError`
        names the segment and cam angle (sampled: 4 points per cubic piece, 32 per quintic
        piece).  ``Q`` is only C1 at the breaks of ``P`` (``kappa'``
        jumps there), so the refit is a cubic Hermite interpolant of the exact ``Q`` and ``Q'``
        on a subdivision of every piece (C1, error O(h^4)), refined until its distance to the
        exact offset at the quarter points of every new piece is <= ``tol`` mm.
        """
        # sampled reversal check: 4 points per cubic piece; quintic pieces are ~8x longer, so 32
        per_piece = 4 if self.degree == 3 else 32
        dense_u = np.linspace(0.0, 1.0, per_piece * self.n_pieces + 1)
        kappa = self.curvature(dense_u)
        factor = 1.0 + distance * kappa
        if np.any(factor <= 0.0):
            worst = int(np.argmin(factor))
            p = self.point(dense_u[worst : worst + 1])[0]
            polar = math.degrees(math.atan2(p[1], p[0])) % 360.0
            raise GeometryError(
                f"offset {distance:g} mm of segment {index} (spline) reverses at cam angle {polar:.3f} deg: "
                f"radius of curvature {1.0 / abs(kappa[worst]):.6g} mm <= |offset| (undercut)"
            )

        def exact(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            p, d1, d2 = self.derivatives(t)
            return p + distance * outward_normal(d1), d1 * (1.0 + distance * signed_curvature(d1, d2))[:, None]

        subdiv = 1
        h = np.diff(self.breaks)
        while True:
            frac = np.arange(subdiv) / subdiv
            t = np.append((self.breaks[:-1, None] + frac[None, :] * h[:, None]).ravel(), self.breaks[-1])
            q, dq = exact(t)
            fit = Spline.hermite(t, q, dq)
            probe = (t[:-1, None] + np.array([0.25, 0.5, 0.75])[None, :] * np.diff(t)[:, None]).ravel()
            err = float(np.max(np.hypot(*(fit.eval_t(probe) - exact(probe)[0]).T)))
            if err <= tol:
                return fit
            if subdiv >= 256:
                raise GeometryError(
                    f"offset {distance:g} mm of segment {index} (spline): refit error {err:.3g} mm "
                    f"stays above tol = {tol:g} mm; the offset is too close to a cusp"
                )
            # the Hermite error falls as (piece length)^4: jump to the subdivision that should do
            subdiv = min(256, max(subdiv + 1, math.ceil(1.1 * subdiv * (err / tol) ** 0.25)))


def extreme_points_of(splines: "list[Spline]") -> list[np.ndarray]:
    """:meth:`Spline.extreme_points` of every spline of ``splines``, bit for bit, the root finding
    of all the non-cubic ones (their ``x'`` and ``y'``, one set of polynomials per spline and
    axis) in one vectorised pass (:func:`camgen.numerics.roots.grouped_sign_change_roots`)."""
    general = [i for i, spline in enumerate(splines) if spline.degree != 3]
    out = [spline.extreme_points() if spline.degree == 3 else spline.eval_t(spline.breaks) for spline in splines]
    if not general:
        return out
    for degree in sorted({splines[i].degree for i in general}):  # one pass per degree (the rows of a pass share their length)
        members = [i for i in general if splines[i].degree == degree]
        scaled = [splines[i]._scaled() for i in members]
        rows = [q[:, 1:, axis] * np.arange(1, degree + 1) for q in scaled for axis in range(2)]
        sizes = [r.shape[0] for r in rows]
        group = np.repeat(np.arange(len(rows)), sizes)
        s = grouped_sign_change_roots(np.concatenate(rows), -ROOT_TOL, 1.0 + ROOT_TOL, group, len(rows))
        start = np.cumsum([0] + sizes)
        for m, i in enumerate(members):
            spline, h = splines[i], np.diff(splines[i].breaks)
            pts = [out[i]]
            for axis in range(2):  # as roots_in_pieces: the finite roots, clipped to the piece
                block = s[start[2 * m + axis]:start[2 * m + axis + 1]]
                piece, col = np.nonzero(np.isfinite(block))
                pts.append(spline.eval_piece(piece, np.clip(block[piece, col], 0.0, 1.0) * h[piece]))
            out[i] = np.concatenate(pts)
    return out


def bounding_box_of(splines: "list[Spline]") -> tuple[np.ndarray, np.ndarray]:
    """The exact bounding box ``(lo, hi)`` (each (2,), mm) of ``splines``: the min and max of
    their :func:`extreme_points_of`, with the roots of only the pieces that can reach beyond the
    box of the break points.  A piece lies in the convex hull of its Bezier control points (Farin,
    *Curves and Surfaces for CAGD*, ch. 4): a piece whose control points in an axis stay within
    that box (less :data:`BOX_SLACK`) has no extreme beyond it, and its roots are not needed."""
    ends = np.concatenate([spline.eval_t(spline.breaks) for spline in splines])
    lo, hi = ends.min(axis=0), ends.max(axis=0)
    slack = BOX_SLACK * float(np.max(np.abs(ends)))
    pts = [ends] + [spline.extreme_points() for spline in splines if spline.degree == 3]  # closed form: every extreme point
    for degree in sorted({spline.degree for spline in splines} - {3}):
        rows, which = [], []
        for spline in splines:
            if spline.degree != degree:
                continue
            q = spline._scaled()  # (K, degree + 1, 2)
            ctrl = np.einsum("ji,kic->kjc", bezier_matrix(degree), q)  # the Bezier control points (K, degree + 1, 2)
            reach = (ctrl.max(axis=1) > hi - slack) | (ctrl.min(axis=1) < lo + slack)  # (K, 2): pieces that may reach out
            for axis in range(2):
                pieces = np.flatnonzero(reach[:, axis])
                if pieces.size:
                    rows.append(q[pieces, 1:, axis] * np.arange(1, degree + 1))
                    which.append((spline, pieces))
        if not rows:
            continue
        sizes = [r.shape[0] for r in rows]
        s = grouped_sign_change_roots(np.concatenate(rows), -ROOT_TOL, 1.0 + ROOT_TOL, np.repeat(np.arange(len(rows)), sizes), len(rows))
        start = np.cumsum([0] + sizes)
        for g, (spline, pieces) in enumerate(which):
            block = s[start[g]:start[g + 1]]
            row, col = np.nonzero(np.isfinite(block))
            if row.size:
                piece = pieces[row]
                h = spline.breaks[piece + 1] - spline.breaks[piece]
                pts.append(spline.eval_piece(piece, np.clip(block[row, col], 0.0, 1.0) * h))
    every = np.concatenate(pts)
    return every.min(axis=0), every.max(axis=0)


def acceleration_bound(c: np.ndarray, h: np.ndarray, degree: int) -> np.ndarray:
    """A bound of ``|P''|`` (mm per parameter unit squared) over each piece of splines of ``degree``
    with coefficients ``c`` (degree + 1, P, 2; highest power first) on pieces of lengths ``h`` (P,):
    exact for a cubic (``|P''|`` is linear, largest at an end), the Bezier hull of ``P''`` otherwise."""
    if degree == 3:
        acc_start = np.hypot(*(2.0 * c[1]).T)
        acc_end = np.hypot(*(6.0 * c[0] * h[:, None] + 2.0 * c[1]).T)
        return np.maximum(acc_start, acc_end)
    return bernstein_max_norm(c[:-2] * derivative_factors(degree, 2)[:, None, None], h)


def flatten_params_of(splines: "list[Spline]", chord_tol: float) -> list[np.ndarray]:
    """:meth:`Spline.flatten_params` of every spline of ``splines`` (bit for bit), the bounds of
    ``|P''|`` of all the pieces of one degree in one vectorised pass (elementwise per piece)."""
    bound: dict[int, np.ndarray] = {}
    for degree in sorted({spline.degree for spline in splines}):
        members = [spline for spline in splines if spline.degree == degree]
        h = np.concatenate([np.diff(spline.breaks) for spline in members])
        c = np.concatenate([spline.coeffs for spline in members], axis=1)
        max_acc = acceleration_bound(c, h, degree)
        start = np.cumsum([0] + [spline.n_pieces for spline in members])
        for k, spline in enumerate(members):
            bound[id(spline)] = max_acc[start[k]:start[k + 1]]
    return [spline._chord_params(bound[id(spline)], chord_tol) for spline in splines]
