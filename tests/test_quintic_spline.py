"""Quintic (degree-5) Spline pieces and contours mixing quintic splines, cubic splines and arcs.

Every number is checked against something outside camgen's spline code: scipy's ``PPoly`` built
from the same coefficients (values, derivatives, roots), dense brute-force sampling refined by
``scipy.optimize``, or closed forms (ellipse area, curvature and support function, the quintic
Hermite interpolation remainder ``P^(6)(xi) / 6! (t - a)^3 (t - b)^3``).
"""
from __future__ import annotations

import math

from fractions import Fraction

import numpy as np
import pytest
from scipy.interpolate import PPoly
from scipy.optimize import brentq, minimize_scalar

from camgen.contour import Arc, Contour, Spline
from helpers import brute_support, segmentwise

#: Relative agreement of camgen's evaluation with scipy's PPoly on the same coefficients.
RTOL_EVAL = 1e-12
#: Ellipse semi-axes, mm.
A_ELL, B_ELL = 50.0, 30.0
#: Radius of the arc half of the mixed contour, mm (its left half is a half ellipse a = A_ELL, b = R_MIX).
R_MIX = 30.0


def _ppoly(spline: Spline) -> PPoly:
    return PPoly(np.array(spline.coeffs), np.array(spline.breaks))


def _random_quintic(seed: int = 3, pieces: int = 40) -> Spline:
    """A wiggly C2 quintic spline: random points, slopes and second derivatives at random breaks."""
    rng = np.random.default_rng(seed)
    t = np.cumsum(np.r_[0.0, rng.uniform(0.2, 1.0, pieces)])
    return Spline.hermite5(t, rng.normal(0, 10, (pieces + 1, 2)), rng.normal(0, 20, (pieces + 1, 2)), rng.normal(0, 60, (pieces + 1, 2)))


def _ellipse_data(t: np.ndarray, a: float = A_ELL, b: float = B_ELL):
    p = np.c_[a * np.cos(t), b * np.sin(t)]
    return p, np.c_[-a * np.sin(t), b * np.cos(t)], -p


def _ellipse(pieces: int) -> Spline:
    t = np.linspace(0.0, 2.0 * math.pi, pieces + 1)
    p, d1, d2 = _ellipse_data(t)
    p[-1] = p[0]
    return Spline.hermite5(t, p, d1, d2)


def _ellipse_fit_bound(pieces: int, a: float = A_ELL, b: float = B_ELL) -> float:
    """Distance bound of the quintic Hermite fit: h^6 / 46080 max|P^(6)| per coordinate (a and b)."""
    return (2.0 * math.pi / pieces) ** 6 / 46080.0 * math.hypot(a, b)


def _star(pieces: int = 60, radius: float = 40.0, ripple: float = 8.0, lobes: int = 5) -> Spline:
    """r = radius + ripple cos(lobes theta) fitted by hermite5 from its exact derivatives (non-convex: ripple lobes^2 > radius)."""
    th = np.linspace(0.0, 2.0 * math.pi, pieces + 1)
    r = radius + ripple * np.cos(lobes * th)
    r1 = -ripple * lobes * np.sin(lobes * th)
    r2 = -ripple * lobes**2 * np.cos(lobes * th)
    c, s = np.cos(th), np.sin(th)
    p = np.c_[r * c, r * s]
    d1 = np.c_[r1 * c - r * s, r1 * s + r * c]
    d2 = np.c_[(r2 - r) * c - 2 * r1 * s, (r2 - r) * s + 2 * r1 * c]
    p[-1] = p[0]
    return Spline.hermite5(th, p, d1, d2)


def _half_ellipse(s: np.ndarray, a: float = A_ELL, b: float = R_MIX):
    """x = -a sin s, y = b cos s: the left half of an ellipse from (0, b) (s = 0) to (0, -b) (s = pi)."""
    return (np.c_[-a * np.sin(s), b * np.cos(s)], np.c_[-a * np.cos(s), -b * np.sin(s)], np.c_[a * np.sin(s), -b * np.cos(s)])


#: Pieces of the quintic (s in [0, pi/2]) and cubic (s in [pi/2, pi]) parts of the mixed contour.
MIX_QUINTIC, MIX_CUBIC = 6, 24


def _mixed() -> Contour:
    """Right half: an arc of radius R_MIX about the axis; left half: a half ellipse, its upper
    quarter a quintic Hermite spline, its lower quarter a cubic Hermite spline."""
    s5 = np.linspace(0.0, math.pi / 2, MIX_QUINTIC + 1)
    p, d1, d2 = _half_ellipse(s5)
    quintic = Spline.hermite5(s5, p, d1, d2)
    s3 = np.linspace(math.pi / 2, math.pi, MIX_CUBIC + 1)
    p, d1, _ = _half_ellipse(s3)
    cubic = Spline.hermite(s3, p, d1)
    return Contour([Arc((0.0, 0.0), R_MIX, -math.pi / 2, math.pi), quintic, cubic])


def _mixed_fit_bound() -> float:
    """Distance bound of the two spline parts to the exact half ellipse: quintic Hermite h^6/46080,
    cubic Hermite h^4/384 (de Boor, *A Practical Guide to Splines*, ch. 2), times max|P^(k)| <= hypot(a, b)."""
    h5, h3 = (math.pi / 2) / MIX_QUINTIC, (math.pi / 2) / MIX_CUBIC
    return max(h5**6 / 46080.0, h3**4 / 384.0) * math.hypot(A_ELL, R_MIX)


def _dense(spline: Spline, per_piece: int) -> np.ndarray:
    """Points of the spline from scipy's PPoly, ``per_piece`` per piece."""
    frac = np.arange(per_piece) / per_piece
    t = (spline.breaks[:-1, None] + frac * np.diff(spline.breaks)[:, None]).ravel()
    return _ppoly(spline)(t)


def _dense_mixed(per_piece: int = 400) -> np.ndarray:
    arc, quintic, cubic = _mixed().segments
    ang = arc.start_angle + arc.sweep * np.arange(per_piece * 8) / (per_piece * 8)
    return np.concatenate([arc.radius * np.c_[np.cos(ang), np.sin(ang)], _dense(quintic, per_piece), _dense(cubic, per_piece)])


# --------------------------------------------------------------------------------------------
# Evaluation
# --------------------------------------------------------------------------------------------
def test_values_and_derivatives_equal_scipy_ppoly():
    """eval_t (orders 0..5), derivatives, point / derivative / second_derivative and the end points
    of a wiggly quintic spline against scipy's PPoly on the same coefficients; the length of a
    quintic star against scipy.integrate.quad of |P'| on every piece."""
    from scipy.integrate import quad

    spline = _random_quintic()
    pp = _ppoly(spline)
    rng = np.random.default_rng(0)
    t = np.concatenate([rng.uniform(spline.breaks[0], spline.breaks[-1], 5000), spline.breaks])
    scale = np.max(np.abs(pp(t)))
    for order in range(6):
        ref = pp.derivative(order)(t) if order else pp(t)
        assert np.max(np.abs(spline.eval_t(t, order) - ref)) <= RTOL_EVAL * np.max(np.abs(ref)), order
    p, d1, d2 = spline.derivatives(t)
    for got, order in ((p, 0), (d1, 1), (d2, 2)):
        ref = pp.derivative(order)(t) if order else pp(t)
        assert np.max(np.abs(got - ref)) <= RTOL_EVAL * np.max(np.abs(ref))
    u = (t - spline.breaks[0]) / spline.span
    assert np.max(np.abs(spline.point(u) - pp(t))) <= RTOL_EVAL * scale
    ref1 = pp.derivative(1)(t) * spline.span
    assert np.max(np.abs(spline.derivative(u) - ref1)) <= RTOL_EVAL * np.max(np.abs(ref1))
    ref2 = pp.derivative(2)(t) * spline.span**2
    assert np.max(np.abs(spline.second_derivative(u) - ref2)) <= RTOL_EVAL * np.max(np.abs(ref2))
    assert np.allclose(spline.start_point, pp(spline.breaks[0]), rtol=0, atol=RTOL_EVAL * scale)
    assert np.allclose(spline.end_point, pp(spline.breaks[-1]), rtol=0, atol=RTOL_EVAL * scale)
    star = _star(20)  # length: Gauss-Legendre per piece is exact to rounding on smooth pieces (no near-stationary point)
    dpp = _ppoly(star).derivative()
    length = sum(quad(lambda x: float(np.hypot(*dpp(x))), lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
                 for lo, hi in zip(star.breaks[:-1], star.breaks[1:]))
    assert abs(star.length - length) <= 1e-12 * length


def test_hermite5_reproduces_a_quintic_polynomial():
    """A random quintic polynomial (each coordinate) sampled with its exact first and second
    derivatives at uneven breaks is reproduced to rounding by every piece (the Hermite
    interpolant of a polynomial of degree <= 5 is the polynomial itself)."""
    rng = np.random.default_rng(11)
    poly = [np.polynomial.Polynomial(rng.normal(0, 1, 6)) for _ in range(2)]
    t = np.sort(np.r_[-2.0, 3.0, rng.uniform(-2.0, 3.0, 7)])
    value = np.c_[poly[0](t), poly[1](t)]
    first = np.c_[poly[0].deriv()(t), poly[1].deriv()(t)]
    second = np.c_[poly[0].deriv(2)(t), poly[1].deriv(2)(t)]
    spline = Spline.hermite5(t, value, first, second)
    x = np.linspace(-2.0, 3.0, 2001)
    exact = np.c_[poly[0](x), poly[1](x)]
    assert np.max(np.abs(spline.eval_t(x) - exact)) <= 1e-12 * np.max(np.abs(exact))
    exact2 = np.c_[poly[0].deriv(2)(x), poly[1].deriv(2)(x)]
    assert np.max(np.abs(spline.eval_t(x, 2) - exact2)) <= 1e-11 * np.max(np.abs(exact2))


def test_hermite5_error_bound_and_sixth_order_convergence():
    """On (cos t, sin 2t) the error of every coordinate stays below h^6 max|P^(6)| / 46080 (1 and
    64), comes within 10 % of it (the remainder's bound is attained as pieces shrink), and falls by
    2^6 when the pieces halve (observed order 5.8 .. 6.2)."""
    def curve(t):
        return (np.c_[np.cos(t), np.sin(2 * t)], np.c_[-np.sin(t), 2 * np.cos(2 * t)], np.c_[-np.cos(t), -4 * np.sin(2 * t)])

    x = np.linspace(0.0, 2.0 * math.pi, 100001)
    errors = []
    for pieces in (16, 32):
        t = np.linspace(0.0, 2.0 * math.pi, pieces + 1)
        spline = Spline.hermite5(t, *curve(t))
        err = np.max(np.abs(spline.eval_t(x) - curve(x)[0]), axis=0)
        bound = (2.0 * math.pi / pieces) ** 6 / 46080.0 * np.array([1.0, 64.0])
        assert np.all(err <= bound) and np.all(err >= 0.9 * bound), (pieces, err / bound)
        errors.append(err)
    order = np.log2(errors[0] / errors[1])
    assert np.all((order > 5.8) & (order < 6.2)), order


# --------------------------------------------------------------------------------------------
# Exact extremes: bounding box, turning, support
# --------------------------------------------------------------------------------------------
def test_extreme_points_give_the_bounding_box_of_ppoly_roots():
    """extreme_points of a wiggly quintic spline: its box equals the box of the breaks and of
    PPoly.roots of x'(t) and y'(t) (scipy), every such root where x' (y') changes sign is among
    the returned points, and no dense sample leaves the box."""
    spline = _random_quintic(seed=5)
    pp = _ppoly(spline)
    pts = spline.extreme_points()
    scale = np.max(np.abs(pts))
    dense = pp(np.linspace(spline.breaks[0], spline.breaks[-1], 200001))
    for axis in range(2):
        d = PPoly(np.array(spline.coeffs[..., axis]), np.array(spline.breaks)).derivative()
        roots = d.roots(extrapolate=False)
        eps = 1e-7
        flips = roots[np.sign(d(roots - eps)) != np.sign(d(roots + eps))]
        assert flips.size > 2 * spline.n_pieces // 3  # the test curve really wiggles
        ref = np.concatenate([pp(spline.breaks)[:, axis], pp(roots)[:, axis]])
        assert abs(pts[:, axis].min() - ref.min()) <= RTOL_EVAL * scale
        assert abs(pts[:, axis].max() - ref.max()) <= RTOL_EVAL * scale
        gap = np.min(np.hypot(*(pp(flips)[:, None, :] - pts[None, :, :]).transpose(2, 0, 1)), axis=1)
        assert np.max(gap) <= 1e-9 * scale
        assert dense[:, axis].min() >= pts[:, axis].min() - RTOL_EVAL * scale
        assert dense[:, axis].max() <= pts[:, axis].max() + RTOL_EVAL * scale


def test_bezier_control_points_equal_scipy_bpoly():
    """The Bezier control points behind the support pre-filter (of Q'(s), s in [0, 1] per piece)
    and the flattening bound (largest control-point norm of P'') equal scipy's
    BPoly.from_power_basis of the same derivative (1e-12 relative)."""
    from scipy.interpolate import BPoly

    from camgen.numerics.bernstein import bernstein_max_norm as _bernstein_max_norm, power_to_bezier as _power_to_bezier
    from camgen.numerics.polynomial import derivative_factors as _derivative_factors, scaled_ascending as _scaled_ascending

    spline = _random_quintic(seed=9)
    h = np.diff(spline.breaks)
    for order in (1, 2):
        bp = BPoly.from_power_basis(_ppoly(spline).derivative(order))  # control points (6 - order, K, 2), in tau units
        q = _scaled_ascending(spline.coeffs, h)[:, order:] * _derivative_factors(spline.degree, order)[::-1][None, :, None]
        ours = _power_to_bezier(q).transpose(1, 0, 2) / (h ** order)[None, :, None]  # back from s to tau derivatives
        assert np.max(np.abs(ours - bp.c)) <= 1e-12 * np.max(np.abs(bp.c))
    bp2 = BPoly.from_power_basis(_ppoly(spline).derivative(2))
    second = spline.coeffs[:-2] * _derivative_factors(spline.degree, 2)[:, None, None]
    assert np.allclose(_bernstein_max_norm(second, h), np.max(np.hypot(bp2.c[..., 0], bp2.c[..., 1]), axis=0), rtol=1e-12, atol=0)


def _turning(pp: PPoly, t: np.ndarray) -> np.ndarray:
    d1, d2 = pp.derivative(1)(t), pp.derivative(2)(t)
    return d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]


@pytest.mark.parametrize("seed", [5, 8])
def test_min_turning_against_dense_sampling(seed):
    """min_turning (the exact smallest P' x P'') of a wiggly quintic spline against a 2000-per-piece
    sampling of P' x P'' from PPoly, refined by scipy's bounded scalar minimiser in the best sample's
    neighbourhood (1e-10 relative)."""
    spline = _random_quintic(seed=seed)
    pp = _ppoly(spline)
    t = np.linspace(spline.breaks[0], spline.breaks[-1], 2000 * spline.n_pieces + 1)
    w = _turning(pp, t)
    k = int(np.argmin(w))
    lo, hi = t[max(k - 1, 0)], t[min(k + 1, t.size - 1)]
    ref = min(float(w[k]), minimize_scalar(lambda x: float(_turning(pp, np.array([x]))[0]), bounds=(lo, hi),
                                           method="bounded", options={"xatol": 1e-14}).fun)
    got = spline.min_turning()
    assert abs(got - ref) <= 1e-10 * np.max(np.abs(w))
    assert got <= ref + 1e-12 * np.max(np.abs(w))


def test_ellipse_closed_forms():
    """An ellipse (50 cos t, 30 sin t) fitted by hermite5 from its exact derivatives (30 pieces: its
    y extremes fall inside pieces): area pi a b within perimeter x the fit bound, bounding box
    (-a, -b, a, b) within the fit bound, curvature a b / (a^2 sin^2 + b^2 cos^2)^(3/2) and
    min_turning = a b (P' x P'' of the ellipse) within h^4 relative (the fit's second derivative
    error is O(h^4)), convex, and the support function sqrt(a^2 cos^2 psi + b^2 sin^2 psi), its
    derivative and h'' = rho - h from the closed form."""
    pieces = 30
    spline = _ellipse(pieces)
    contour = Contour([spline])
    e = _ellipse_fit_bound(pieces)
    h = 2.0 * math.pi / pieces
    a, b = A_ELL, B_ELL
    perimeter = 2 * math.pi * math.sqrt((a * a + b * b) / 2)
    assert abs(contour.area - math.pi * a * b) <= perimeter * e
    assert np.allclose(contour.bounds, (-a, -b, a, b), rtol=0, atol=e)
    t = np.linspace(0.0, 2.0 * math.pi, 5001)
    kappa = a * b / (a * a * np.sin(t) ** 2 + b * b * np.cos(t) ** 2) ** 1.5
    assert np.max(np.abs(contour.curvature(t / (2 * math.pi)) / kappa - 1)) <= h**4
    assert abs(spline.min_turning() / (a * b) - 1) <= h**4
    assert contour.is_convex()
    psi = np.linspace(-math.pi, math.pi, 2048, endpoint=False)
    g = a * a * np.cos(psi) ** 2 + b * b * np.sin(psi) ** 2
    support = np.sqrt(g)
    g1 = -(a * a - b * b) * np.sin(2 * psi)
    g2 = -2.0 * (a * a - b * b) * np.cos(2 * psi)
    h1 = g1 / (2 * support)
    h2 = g2 / (2 * support) - g1**2 / (4 * support**3)
    got, got1, got2 = contour.support_derivatives(psi)
    assert np.max(np.abs(got - support)) <= e
    assert np.max(np.abs(got1 - h1)) <= 1e-4  # contact point along the face: within the fit's O(h^5) slope error
    assert np.max(np.abs(got2 - h2) / support) <= h**4  # radius of curvature: O(h^4)


def test_support_on_every_break_of_an_ellipse():
    """Directions whose contact point is exactly a break of the quintic (the exact normal there):
    the support value is that break's P . u (1e-12 relative), not a nearby root or the far side."""
    spline = _ellipse(30)
    contour = Contour([spline])
    pp = _ppoly(spline)
    t = spline.breaks[:-1]
    p, d1 = pp(t), pp.derivative()(t)
    psi = np.arctan2(-d1[:, 0], d1[:, 1])  # outward normal: tangent rotated by -90 deg
    h, pts = contour.support_point(psi)
    ref = p[:, 0] * np.cos(psi) + p[:, 1] * np.sin(psi)
    assert np.max(np.abs(h / ref - 1)) <= 1e-12
    assert np.max(np.hypot(*(pts - p).T)) <= 1e-6  # the contact point is the break (flat direction: sqrt of rounding)


def _refined_support(points_of, psi: np.ndarray, t_dense: np.ndarray, pts_dense: np.ndarray) -> np.ndarray:
    """max of P(t) . u by dense sampling refined with a bounded scalar maximiser around the best sample."""
    out = np.empty(psi.size)
    for k, angle in enumerate(psi):
        u = np.array([math.cos(angle), math.sin(angle)])
        vals = pts_dense @ u
        j = int(np.argmax(vals))
        lo, hi = t_dense[max(j - 1, 0)], t_dense[min(j + 1, t_dense.size - 1)]
        res = minimize_scalar(lambda x: -float(points_of(np.array([x]))[0] @ u), bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-13})
        out[k] = max(float(vals[j]), -res.fun)
    return out


def test_support_of_a_non_convex_quintic_against_brute_force():
    """A five-lobed quintic star (non-convex): the support function at 2048 directions is never
    below the max over 60000 PPoly samples and above it by at most their sampling error; at 40
    directions it equals the sampled max refined by scipy's scalar maximiser (1e-9 mm), and the
    contact point lies on the curve and attains the value."""
    spline = _star()
    contour = Contour([spline])
    assert not contour.is_convex()
    pp = _ppoly(spline)
    t_dense = np.linspace(spline.breaks[0], spline.breaks[-1], 60001)
    dense = pp(t_dense)
    psi = np.linspace(-math.pi, math.pi, 2048, endpoint=False)
    h, pts = contour.support_point(psi)
    brute = brute_support(dense, psi, chunk=16)
    assert np.all(h >= brute - 1e-12) and np.max(h - brute) <= 1e-5
    few = psi[::51]
    ref = _refined_support(pp, few, t_dense, dense)
    assert np.max(np.abs(contour.support(few) - ref)) <= 1e-9
    u = np.c_[np.cos(psi), np.sin(psi)]
    assert np.max(np.abs(np.einsum("ij,ij->i", pts, u) - h)) <= 1e-9
    dpp = pp.derivative()
    for p in pts[::16]:  # on the curve: the foot of p on PPoly ((P - p) . P' = 0, scipy's brentq near the nearest sample)
        j = int(np.argmin(np.hypot(*(dense - p).T)))
        foot = brentq(lambda x: float((pp(x) - p) @ dpp(x)), t_dense[max(j - 1, 0)], t_dense[min(j + 1, t_dense.size - 1)], xtol=1e-15)
        assert np.hypot(*(pp(foot) - p)) <= 1e-11


# --------------------------------------------------------------------------------------------
# Mixed contours: arc + quintic + cubic
# --------------------------------------------------------------------------------------------
def test_mixed_contour_evaluates_like_its_segments_and_ppoly():
    """evaluate / tangent / curvature of an arc + quintic + cubic contour give bit for bit what
    each segment's own methods give (cubic pieces padded to degree 5 in the shared table do the
    cubic's arithmetic), and the spline parts equal scipy's PPoly (1e-12)."""
    contour = _mixed()
    rng = np.random.default_rng(2)
    t = np.concatenate([rng.uniform(0, 3, 30000), np.arange(12) / 4.0, [3 - 1e-12, 3.0]])
    point, deriv, kappa, idx, u = segmentwise(contour, t)
    assert np.array_equal(contour.evaluate(t), point)
    assert np.array_equal(contour.tangent(t), deriv / np.linalg.norm(deriv, axis=1, keepdims=True))
    assert np.array_equal(contour.curvature(t), kappa)
    for i in (1, 2):
        seg = contour.segments[i]
        at = idx == i
        ts = seg.breaks[0] + u[at] * seg.span
        pp = _ppoly(seg)
        assert np.max(np.abs(contour.evaluate(t[at]) - pp(ts))) <= RTOL_EVAL * 100
        d1, d2 = pp.derivative()(ts), pp.derivative(2)(ts)
        ref = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(d1[:, 0], d1[:, 1]) ** 3
        assert np.max(np.abs(contour.curvature(t[at]) - ref)) <= 1e-12


def test_mixed_contour_global_measures():
    """Area pi R^2 / 2 + pi a R / 2 (half disk + half ellipse) within the perimeter x the fit
    bound and equal to the shoelace of 400-per-piece samples (to their O(1/N^2) error); bounding
    box (-a, -R, R, R) within the fit bound and containing every sample; convex; joints: arc ->
    quintic G1 with curvature jump R / a^2 - 1 / R (ellipse at its vertex), quintic -> cubic G1
    (the quintic's end curvature a / R^2 exactly: hermite5 matches second derivatives), cubic -> arc G1."""
    contour = _mixed()
    e = _mixed_fit_bound()
    a, r = A_ELL, R_MIX
    perimeter = math.pi * r + math.pi * math.sqrt((a * a + r * r) / 2)
    assert abs(contour.area - (math.pi * r * r / 2 + math.pi * a * r / 2)) <= perimeter * e
    dense = _dense_mixed()
    x, y = dense[:, 0], dense[:, 1]
    shoelace = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert abs(contour.area - shoelace) <= 1e-3
    box = contour.bounds
    assert np.allclose(box, (-a, -r, r, r), rtol=0, atol=e)
    assert box[0] <= x.min() + 1e-12 and box[2] >= x.max() - 1e-12 and box[1] <= y.min() + 1e-12 and box[3] >= y.max() - 1e-12
    assert contour.is_convex()
    joints = contour.joints(curvature_tol=1e-6)
    assert [j.continuity for j in joints] == ["G1", "G1", "G1"]
    assert abs(joints[0].curvature_jump_per_mm - (r / a**2 - 1 / r)) <= 1e-12
    assert abs(contour.segments[1].curvature(np.array([1.0]))[0] - a / r**2) <= 1e-12
    assert max(j.gap_mm for j in joints) <= 1e-12 and max(j.tangent_jump_rad for j in joints) <= 1e-9


def test_mixed_contour_support_and_polar_radius():
    """Support (2048 directions) never below the max over dense PPoly / arc samples and above it by
    at most their sampling error; polar radius by the sorted-table path and by every ray against
    every segment (the fallback) equal to bisection of u x P on PPoly (1e-10 mm) and to the
    closed forms (circle R, half ellipse a R / sqrt(R^2 cos^2 + a^2 sin^2)) within the fit bound."""
    contour = _mixed()
    psi = np.linspace(-math.pi, math.pi, 2048, endpoint=False)
    dense = _dense_mixed(2000)
    brute = brute_support(dense, psi, chunk=16)
    h = contour.support(psi)
    assert np.all(h >= brute - 1e-12) and np.max(h - brute) <= 1e-6
    phi = np.linspace(-math.pi, math.pi, 721)
    star = contour.polar_radius(phi)
    every = contour._polar_radius_all_pieces(phi)
    a, r = A_ELL, R_MIX
    exact = np.where(np.cos(phi) >= 0, r, a * r / np.sqrt((r * np.cos(phi)) ** 2 + (a * np.sin(phi)) ** 2))
    ref = _bisect_polar(contour, phi)
    for got in (star, every):
        assert np.max(np.abs(got - ref)) <= 1e-10
        assert np.max(np.abs(got - exact)) <= 2 * _mixed_fit_bound() * a / r  # ray oblique to the normal: <= a / R


def _bisect_polar(contour: Contour, phi: np.ndarray) -> np.ndarray:
    """Distance along each ray by bisection of u x P(t) on the spline (scipy PPoly) or the circle
    (arc half, |phi| <= pi/2) holding it; the half ellipse x <= 0 is split at y = 0 (s = pi/2)."""
    arc, quintic, cubic = contour.segments
    out = np.full(phi.size, arc.radius)
    u = np.c_[np.cos(phi), np.sin(phi)]
    left = np.cos(phi) < 0
    for seg, side in ((quintic, np.sin(phi) >= 0), (cubic, np.sin(phi) < 0)):
        sel = left & side
        pp = _ppoly(seg)
        lo = np.full(sel.sum(), seg.breaks[0])
        hi = np.full(sel.sum(), seg.breaks[-1])
        us = u[sel]

        def g(t):
            p = pp(t)
            return us[:, 0] * p[:, 1] - us[:, 1] * p[:, 0]

        g_lo = g(lo)
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            same = np.sign(g(mid)) == np.sign(g_lo)
            lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
        out[sel] = np.einsum("ij,ij->i", pp(0.5 * (lo + hi)), us)
    return out


def test_polar_radius_of_a_quintic_star_both_paths():
    """The non-convex quintic star: polar radius by the table path and by the every-piece path
    equal bisection of u x P on PPoly (1e-10 mm), on random rays and on the rays through every break."""
    spline = _star()
    contour = Contour([spline])
    pp = _ppoly(spline)
    rng = np.random.default_rng(4)
    phi = np.concatenate([rng.uniform(-math.pi, math.pi, 500), np.arctan2(*pp(spline.breaks[:-1]).T[::-1])])
    # theta is the polar angle of the exact star; the fit's polar angle differs by the fit error:
    # bracket each ray within theta +- 0.05 rad
    u = np.c_[np.cos(phi), np.sin(phi)]
    lo, hi = phi - 0.05, phi + 0.05

    def g(t):
        p = pp(np.mod(t, 2 * math.pi))
        return u[:, 0] * p[:, 1] - u[:, 1] * p[:, 0]

    assert np.all(g(lo) < 0) and np.all(g(hi) > 0)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        neg = g(mid) < 0
        lo, hi = np.where(neg, mid, lo), np.where(neg, hi, mid)
    ref = np.einsum("ij,ij->i", pp(np.mod(0.5 * (lo + hi), 2 * math.pi)), u)
    assert np.max(np.abs(contour.polar_radius(phi) - ref)) <= 1e-10
    assert np.max(np.abs(contour._polar_radius_all_pieces(phi) - ref)) <= 1e-10


# --------------------------------------------------------------------------------------------
# Flattening and offsets
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("tol", [1e-2, 1e-4])
def test_flatten_chord_error_of_quintic_and_mixed_contours(tol):
    """Every chord of flatten(tol) stays within tol of the curve between its ends, measured on 64
    PPoly / circle points per chord; and the bound is not wasteful: the largest deviation is at
    least tol / 8 (the chord count is within a few times the minimum)."""
    for contour in (Contour([_star()]), _mixed()):
        params = contour.flatten_params(tol)
        t1 = np.append(params[1:], contour.n_segments)
        worst = 0.0
        for i, seg in enumerate(contour.segments):
            at = np.floor(params).astype(int) == i
            a, b = params[at] - i, t1[at] - i
            frac = np.linspace(0.0, 1.0, 66)[1:-1]
            uu = a[:, None] + frac * (b - a)[:, None]
            if isinstance(seg, Arc):
                ang = seg.start_angle + seg.sweep * np.r_[uu.ravel(), a, b]
                pts = seg.center + seg.radius * np.c_[np.cos(ang), np.sin(ang)]
            else:
                pts = _ppoly(seg)(seg.breaks[0] + np.r_[uu.ravel(), a, b] * seg.span)
            n = a.size
            curve = pts[: uu.size].reshape(uu.shape + (2,))
            pa, pb = pts[uu.size : uu.size + n, None], pts[uu.size + n :, None]
            ab = pb - pa
            w = np.clip(np.sum((curve - pa) * ab, -1) / np.sum(ab * ab, -1), 0.0, 1.0)
            worst = max(worst, float(np.max(np.hypot(*(curve - pa - w[..., None] * ab).transpose(2, 0, 1)))))
        assert tol / 8 <= worst <= tol, worst / tol


def test_offset_of_a_mixed_contour_is_at_the_offset_distance():
    """Offsetting arc + quintic + cubic by 3 mm: every vertex of a fine flattening of the offset
    lies 3 mm from the original (nearest of 2000-per-piece PPoly / arc samples, whose spacing error
    is below 1e-6 mm) within spline_tol, and the offset's area is A + 3 L + pi 9 (parallel-curve
    area of a convex curve, Steiner's formula) within perimeter x spline_tol."""
    contour = _mixed()
    d, tol = 3.0, 1e-6
    out = contour.offset(d, spline_tol=tol)
    pts = out.flatten(1e-5)[::7]
    dense = _dense_mixed(2000)
    near = np.array([np.min(np.hypot(*(dense - p).T)) for p in pts])
    assert np.max(np.abs(near - d)) <= tol + 1e-6
    steiner = contour.area + d * contour.length + math.pi * d * d
    assert abs(out.area - steiner) <= out.length * tol * 2


def test_offset_of_a_quintic_ellipse_reverses_past_its_smallest_radius():
    """The quintic ellipse (shifted by half a piece: its sharpest points lie inside pieces) offset
    inward by less than its smallest radius of curvature b^2 / a = 18 mm is valid; by more, the
    offset reverses there and is a GeometryError naming the spline."""
    from camgen.errors import GeometryError

    pieces = 30
    t = np.linspace(0.0, 2.0 * math.pi, pieces + 1) + math.pi / pieces
    p, d1, d2 = _ellipse_data(t)
    p[-1] = p[0]
    contour = Contour([Spline.hermite5(t, p, d1, d2)])
    rho_min = B_ELL**2 / A_ELL
    inner = contour.offset(-(rho_min - 0.05))
    assert abs(inner.bounds[2] - (A_ELL - rho_min + 0.05)) <= 1e-5  # the vertex moves in along the x axis
    with pytest.raises(GeometryError, match="segment 0 .spline. reverses"):
        contour.offset(-(rho_min + 0.05))


def test_sign_change_roots_against_numpys_eigenvalue_roots():
    """Every sign change on (0, 1) of 3000 random polynomials of degree 1 to 6 (and two that once
    stopped the Newton steps on a bracket end, from a knife cam's x'(t)) against numpy.roots
    (companion-matrix eigenvalues): as many as the real simple roots inside, each within 1e-6 of one
    (eigenvalues of clustered roots are themselves that uncertain) and each a true sign change: the
    polynomial, evaluated here in exact rational arithmetic, has opposite signs either side at the
    distance its float evaluation allows (64 ulps of sum |a_i| over the slope, at least 1e-12)."""
    from camgen.numerics.roots import sign_change_roots as _sign_change_roots

    rng = np.random.default_rng(2026)
    polys = [np.array([-0.00509335, 0.20612288, 0.02145751, 0.00346926, -0.00023837]),
             np.array([1.64456116e+00, -2.25108493e+00, 2.66159062e-02, 1.46031548e-02, -3.06683857e-04])]
    for degree in range(1, 7):
        # roots placed in (0, 1) and outside, times a random scale: polynomials with known sign changes
        for _ in range(500):
            inside = rng.uniform(0.02, 0.98, rng.integers(0, degree + 1))
            outside = rng.uniform(1.2, 4.0, degree - inside.size) * rng.choice([-1, 1], degree - inside.size)
            polys.append(np.polynomial.polynomial.polyfromroots(np.concatenate([inside, outside])) * rng.uniform(0.1, 100))
    for a in polys:
        found = _sign_change_roots(a[None, :], 0.0, 1.0)[0]
        found = np.sort(found[np.isfinite(found)])
        roots = np.roots(a[::-1])
        real = np.sort(roots.real[(np.abs(roots.imag) < 1e-9) & (roots.real > 0) & (roots.real < 1)])
        close = np.abs(real[:, None] - real[None, :]) < 1e-6  # near-double roots: no sign change to find
        if np.any(close & ~np.eye(real.size, dtype=bool)):
            continue
        assert found.size == real.size and np.allclose(found, real, rtol=0, atol=1e-6), (a, found, real)
        slope = np.polynomial.polynomial.polyval(found, a[1:] * np.arange(1, a.size))
        for x, dx in zip(found, np.maximum(1e-12, 64 * np.finfo(float).eps * np.sum(np.abs(a)) / np.abs(slope))):
            sides = [sum(Fraction(float(c)) * Fraction(float(x + d)) ** i for i, c in enumerate(a)) for d in (-dx, dx)]
            assert sides[0] * sides[1] <= 0, (a, x)


def _dense_polygon_turning(contour: Contour, per_segment: int = 20_000) -> float:
    """Smallest sine of the turning angle at the vertices of a dense polygon on the contour (every
    segment sampled on [0, 1), so each joint is a vertex once): < 0 where the contour turns right."""
    t = (np.arange(contour.n_segments)[:, None] + np.arange(per_segment)[None, :] / per_segment).ravel()
    edges = np.diff(contour.evaluate(t), axis=0, append=contour.evaluate(t[:1]))
    nxt = np.roll(edges, -1, axis=0)
    cross = edges[:, 0] * nxt[:, 1] - edges[:, 1] * nxt[:, 0]
    return float(np.min(cross / (np.hypot(*edges.T) * np.hypot(*nxt.T))))


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_is_convex_sees_the_concave_corner_of_a_knife_cam(rotation):
    """A knife cam whose law's velocity jumps (constant velocity after a cycloidal return) has
    quintic flanks that all turn left but a concave corner where the rise starts (the tangent turns
    right there by ~6 deg): is_convex() must agree with the dense polygon's turning (it used to
    look at the segments' curvature only and said True); a cam of smooth laws stays convex."""
    from camgen.synthesis.followers import FollowerSpec, cam_envelope
    from camgen.synthesis.laws import MotionProgram, Segment as LawSegment

    knife = FollowerSpec("knife", 40.0, offset=-6.0, rotation=rotation)
    jumps = MotionProgram([LawSegment("constant_velocity", math.radians(150), 12.0), LawSegment("dwell", math.radians(60)),
                           LawSegment("cycloidal", math.radians(150), -12.0)])
    smooth = MotionProgram([LawSegment("cycloidal", math.radians(150), 12.0), LawSegment("dwell", math.radians(60)),
                            LawSegment("cycloidal", math.radians(150), -12.0)])
    for law in (jumps, smooth):
        contour = cam_envelope(knife, law).profile
        turning = _dense_polygon_turning(contour)
        assert abs(turning) > 1e-6  # clearly one way or the other
        assert contour.is_convex() == (turning > 0), (law is jumps, turning)
    assert _dense_polygon_turning(cam_envelope(knife, jumps).profile) < -0.05  # the corner: sin(-6 deg)
