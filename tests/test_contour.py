"""Contour core: flattening bound, area, length, bounds, support, offset, joints."""
from __future__ import annotations

import math

import numpy as np
import pytest

import camgen
from camgen.contour import Arc, Contour, Spline
from camgen.errors import GeometryError, ParameterError
from helpers import (
    brute_support,
    chord_deviation,
    distance_to_arcs,
    segmentwise,
    shoelace,
)


def mixed_contour() -> Contour:
    """Right half circle (r = 30) + a spline through a half ellipse (semi-axes 45, 30): G1, not G2."""
    arc = Arc((0.0, 0.0), 30.0, -math.pi / 2, math.pi)
    s = np.linspace(0.0, math.pi, 13)
    pts = np.stack([-45.0 * np.sin(s), 30.0 * np.cos(s)], axis=1)
    spline = Spline.interpolate(s, pts, periodic=False, end_derivatives=(np.array([-45.0, 0.0]), np.array([45.0, 0.0])))
    return Contour([arc, spline])


def periodic_contour() -> Contour:
    """A periodic C2 spline through a trefoil-like polar curve r = 40 + 8 cos(3 theta) (convex: no)."""
    theta = np.linspace(0.0, 2 * math.pi, 49)
    r = 40.0 + 8.0 * np.cos(3.0 * theta)
    pts = np.stack([r * np.cos(theta), r * np.sin(theta)], axis=1)
    return Contour([Spline.interpolate(theta, pts, periodic=True)])


CONTOURS = {
    "stride": lambda: camgen.three_arc_cam(220, 160, 25),
    "height": lambda: camgen.three_arc_cam(220, 220, 10),
    "mixed": mixed_contour,
    "periodic": periodic_contour,
}


@pytest.mark.parametrize("name", CONTOURS)
@pytest.mark.parametrize("tol", [1e-1, 1e-2, 1e-3, 1e-4, 1e-5])
def test_flatten_deviation_never_exceeds_chord_tol(name, tol):
    contour = CONTOURS[name]()
    deviation = chord_deviation(contour, tol)
    assert deviation <= tol * (1 + 1e-9)
    # and the bound is not wildly conservative: the sagitta formula is tight for arcs, and the
    # second-derivative bound of a cubic piece (|P''| is linear on it) comes within a factor of 2
    assert deviation >= 0.5 * tol
    pts = contour.flatten(tol)
    assert pts.ndim == 2 and pts.shape[1] == 2 and len(pts) >= 3


@pytest.mark.parametrize("name", CONTOURS)
def test_area_matches_shoelace_of_fine_flattening(name):
    contour = CONTOURS[name]()
    tol = 1e-7
    poly = contour.flatten(tol)
    # the region between a chord and its arc has area <= chord length * chord_tol
    assert abs(contour.area - shoelace(poly)) <= contour.length * tol
    assert contour.area > shoelace(poly) - 1e-9 or name == "periodic"


def test_three_arc_area_from_table_1():
    """Area = (1/2) integral of R(phi)^2 d phi, with the polar radius R(phi) of paper 000's
    Table 1 typed in literally (helpers.table1_paper), integrated region by region with
    scipy's adaptive quadrature: an area from the paper's formulas, not from the arcs."""
    from scipy.integrate import quad

    from helpers import table1_paper

    for a, b, c in ((220.0, 160.0, 25.0), (220.0, 220.0, 10.0), (100.0, 40.0, 30.0)):
        cam = camgen.three_arc_cam(a, b, c)
        b1 = math.asin(b / (2 * a))
        b2 = math.pi / 2 + math.atan(math.sqrt(a * a - b * b / 4) / (a + c - b / 2))
        b3 = math.pi - b1
        edges = [0.0, b1, b2, b3, math.pi]

        def r2(phi: float) -> float:
            return float(table1_paper(a, b, c, np.array([phi]))[1][0]) ** 2

        half = sum(quad(r2, lo + 1e-12, hi - 1e-12, epsabs=1e-12, epsrel=1e-13)[0] for lo, hi in zip(edges[:-1], edges[1:]))
        assert cam.area == pytest.approx(half, rel=1e-9)  # symmetric about the x axis: 2 x (1/2) x half


@pytest.mark.parametrize("name", CONTOURS)
def test_length_and_bounds_against_dense_sampling(name):
    contour = CONTOURS[name]()
    poly = contour.flatten(1e-7)
    closed = np.vstack([poly, poly[:1]])
    perimeter = np.sum(np.linalg.norm(np.diff(closed, axis=0), axis=1))
    assert contour.length == pytest.approx(perimeter, rel=1e-8)
    assert contour.length >= perimeter - 1e-9
    xmin, ymin, xmax, ymax = contour.bounds
    assert xmin == pytest.approx(poly[:, 0].min(), abs=1e-6) and xmin <= poly[:, 0].min() + 1e-12
    assert ymin == pytest.approx(poly[:, 1].min(), abs=1e-6)
    assert xmax == pytest.approx(poly[:, 0].max(), abs=1e-6)
    assert ymax == pytest.approx(poly[:, 1].max(), abs=1e-6) and ymax >= poly[:, 1].max() - 1e-12


@pytest.mark.parametrize("name", CONTOURS)
def test_support_against_brute_force(name):
    contour = CONTOURS[name]()
    psi = np.linspace(-math.pi, math.pi, 3600, endpoint=False)
    brute = brute_support(contour.flatten(1e-7), psi)
    h, pts = contour.support_point(psi)
    assert np.max(np.abs(h - brute)) <= 1e-6
    assert np.all(h >= brute - 1e-9)
    # the contact point realises the support value
    assert np.max(np.abs(np.einsum("ij,ij->i", pts, np.stack([np.cos(psi), np.sin(psi)], 1)) - h)) <= 1e-9


def test_spline_curvature_tangent_normal_against_finite_differences():
    contour = periodic_contour()
    t = np.linspace(0.0, 1.0, 400, endpoint=False) + 1e-3
    step = 1e-5
    p_m, p_0, p_p = contour.evaluate(t - step), contour.evaluate(t), contour.evaluate(t + step)
    d1 = (p_p - p_m) / (2 * step)
    d2 = (p_p - 2 * p_0 + p_m) / step**2
    kappa_fd = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
    assert np.max(np.abs(contour.curvature(t) - kappa_fd)) <= 1e-5
    tan = contour.tangent(t)
    assert np.max(np.abs(tan - d1 / np.hypot(*d1.T)[:, None])) <= 1e-8
    normal = contour.normal(t)
    assert np.max(np.abs(np.einsum("ij,ij->i", normal, tan))) <= 1e-12
    # outward: moving along the normal leaves the curve's inside (the polar radius grows on average)
    assert np.mean(np.einsum("ij,ij->i", normal, p_0)) > 0


def test_joints_report_g1_with_curvature_jumps():
    cam = camgen.three_arc_cam(220, 160, 25)
    joints = cam.joints()
    assert [j.continuity for j in joints] == ["G1"] * 6
    # curvature jumps from 1/c to 1/(a + c) at B: known size
    assert joints[0].curvature_jump_per_mm == pytest.approx(1 / 245 - 1 / 25, rel=1e-12)
    mixed = mixed_contour().joints()
    assert [j.continuity for j in mixed] == ["G1", "G1"]
    # half-ellipse ends have curvature b/a^2 = 30/45^2, the circle 1/30; the 12-piece spline
    # reproduces the ellipse's end curvature to about 1 % (interpolation error, not joint error)
    assert abs(mixed[0].curvature_jump_per_mm) == pytest.approx(1 / 30 - 30 / 45**2, rel=1e-2)
    periodic = periodic_contour().joints()
    assert [j.continuity for j in periodic] == ["G2"]


def test_corner_is_g0():
    # a lens: two arcs meeting at corners
    # circles of radius 20 about (0, -10) and (0, 10) meet at (+-20 cos 30deg, 0)
    half = math.pi / 6
    lens = Contour([Arc((0.0, -10.0), 20.0, half, 4 * half), Arc((0.0, 10.0), 20.0, math.pi + half, 4 * half)])
    assert {j.continuity for j in lens.joints()} == {"G0"}
    # the support function picks the corner for directions between the arcs' normal ranges
    h = lens.support(np.array([0.0, math.pi]))
    assert h == pytest.approx([20 * math.cos(half), 20 * math.cos(half)], abs=1e-12)


def test_offset_is_exact_for_arcs_and_checks_undercut():
    a, b, c = 220.0, 160.0, 25.0
    cam = camgen.three_arc_cam(a, b, c)
    out = cam.offset(6.0)
    psi = np.linspace(0, math.pi, 360, endpoint=False)
    assert np.max(np.abs(out.support(psi) + out.support(psi + math.pi) - (2 * a + 2 * c - b + 12))) <= 1e-9
    # every offset point lies 6 mm from the original arcs
    dist = distance_to_arcs(out.flatten(1e-3), cam.segments)
    assert np.max(np.abs(dist - 6.0)) <= 1e-9
    inner = cam.offset(-20.0)
    assert inner.segments[0].radius == pytest.approx(5.0)
    with pytest.raises(GeometryError, match=r"segment 0 .*radius 25 mm.*cam angle 0\.000 deg.*undercut"):
        cam.offset(-25.0)


def test_offset_of_concave_arcs_is_exact():
    """Four convex lobes (radius 15) joined by concave arcs (radius 10): offsetting by +4 mm makes
    the concave arcs radius 6 about the same centres, every point 4 mm from the original
    (distances from the circle equations); +10 mm is the concave arcs' undercut."""
    from camgen.contour import Arc

    n, distance, lobe, valley = 4, 30.0, 15.0, 10.0
    centres = [distance * np.array([math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)]) for k in range(n)]
    segments = []
    for k in range(n):
        u = np.array([math.cos(2 * math.pi * (k + 0.5) / n), math.sin(2 * math.pi * (k + 0.5) / n)])
        bq, cq = -2 * u @ centres[k], centres[k] @ centres[k] - (valley + lobe) ** 2
        valley_centre = (-bq + math.sqrt(bq * bq - 4 * cq)) / 2 * u  # tangent to lobes k and k + 1
        nxt = centres[(k + 1) % n]
        a_in = math.atan2(*(valley_centre - centres[k])[::-1])
        a_out = math.atan2(*(valley_centre - nxt)[::-1])
        segments.append((k, a_in, a_out, valley_centre))
    arcs = []
    for k, a_in, a_out, vc in segments:
        prev_out = segments[k - 1][2]
        start = prev_out
        sweep = (a_in - start) % (2 * math.pi)
        arcs.append(Arc(tuple(centres[k]), lobe, start, sweep))
        v_start = math.atan2(*(centres[k] - vc)[::-1])
        v_end = math.atan2(*(centres[(k + 1) % n] - vc)[::-1])
        arcs.append(Arc(tuple(vc), valley, v_start, -((v_start - v_end) % (2 * math.pi))))
    contour = Contour(arcs, closure_tol=1e-9)
    out = contour.offset(4.0)
    concave = [s for s in out.segments if s.sweep < 0]
    assert len(concave) == n and all(s.radius == pytest.approx(valley - 4.0, abs=1e-12) for s in concave)
    dist = distance_to_arcs(out.flatten(1e-4), contour.segments)
    assert np.max(np.abs(dist - 4.0)) <= 1e-9
    with pytest.raises(GeometryError, match=r"concave.*undercut"):
        contour.offset(10.0)


def _assert_parallel(contour, offset, distance: float, tol: float) -> None:
    """``offset`` is the parallel curve of ``contour`` at ``distance`` (> 0 outward): 20,000 of its
    points are |distance| from the original's polygon (flattened at 1e-8 mm; GEOS distances to the
    nearest of its edges, found by an STR tree) within ``tol``, on the outside (> 0) or inside; it
    does not cross itself, and its area is Steiner's A + L d + pi d^2 (no cusps: 1 + d kappa > 0)."""
    import shapely
    from shapely.geometry import LinearRing, Polygon

    poly = contour.flatten(1e-8)
    edges = shapely.linestrings(np.stack([poly, np.roll(poly, -1, axis=0)], axis=1))
    pts = offset.evaluate(np.linspace(0.0, offset.n_segments, 20_000, endpoint=False))
    points = shapely.points(pts)
    which, edge = shapely.STRtree(edges).query_nearest(points, all_matches=False)
    gap = shapely.distance(points[which], edges[edge])
    assert which.size == pts.shape[0] and np.max(np.abs(gap - abs(distance))) <= tol + 1e-7
    inside = shapely.contains_xy(Polygon(poly), pts[:, 0], pts[:, 1])
    assert np.all(inside) if distance < 0 else not np.any(inside)
    assert LinearRing(offset.flatten(1e-4)).is_simple
    steiner = contour.area + contour.length * distance + math.pi * distance**2
    assert abs(offset.area - steiner) <= offset.length * tol


def test_offset_of_spline_within_tolerance_and_undercut_error():
    contour = periodic_contour()
    out = contour.offset(2.0, spline_tol=1e-7)
    # the refit keeps the parameter of the original spline: compare with P + d n pointwise,
    # at parameters that are not the refit's own sample points
    t = np.linspace(0, 1, 4001, endpoint=False) + 1.234e-5
    exact = contour.evaluate(t) + 2.0 * contour.normal(t)
    assert np.max(np.linalg.norm(out.evaluate(t) - exact, axis=1)) <= 1e-7
    # the refit keeps the area of an offset curve: A + L d + pi d^2 (Steiner, closed convex-or-not curve
    # with total turning 2 pi and no cusps)
    assert out.area == pytest.approx(contour.area + contour.length * 2.0 + math.pi * 4.0, rel=1e-8)
    # r = 40 + 8 cos 3t is concave at t = 60 deg with radius of curvature
    # (r^2 + r'^2)^1.5 / |r^2 + 2 r'^2 - r r''| = 32^3 / |32^2 - 32 * 72| = 25.6 mm
    near = contour.offset(24.0, spline_tol=1e-5)  # the 48-point spline has 24.68 mm there: just made
    _assert_parallel(contour, near, 24.0, 1e-5)
    with pytest.raises(GeometryError, match=r"segment 0 \(spline\) reverses at cam angle (59|60)\.\d+ deg.*undercut"):
        contour.offset(26.0)


def test_contour_validation():
    with pytest.raises(GeometryError, match="not closed"):
        Contour([Arc((0, 0), 10, 0, math.pi)])
    with pytest.raises(GeometryError, match="counter-clockwise"):
        Contour([Arc((0, 0), 10, 0, -2 * math.pi)])
    with pytest.raises(ParameterError, match="radius"):
        Arc((0, 0), -1.0, 0.0, 1.0)
    with pytest.raises(ParameterError, match="chord_tol"):
        camgen.three_arc_cam(220, 160, 25).flatten(0.0)


def test_offset_through_a_narrow_neck_is_an_error():
    """r = 30 + 25 cos(2 theta): a peanut whose waist at +-90 deg is 5 mm from the axis, i.e. a
    10 mm neck.  Every convex radius exceeds 11 mm, so an inward offset of 6 mm passes the local
    check, but the two sides of the neck cross: a global self-intersection."""
    theta = np.linspace(0.0, 2 * math.pi, 241)
    r = 30 + 25 * np.cos(2 * theta)
    peanut = Contour([Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))])
    assert not peanut.is_convex() and peanut.self_intersection() is None
    narrow = peanut.offset(-4.0)  # the neck (10 mm) still leaves 2 mm
    _assert_parallel(peanut, narrow, -4.0, 1e-6)
    waist = narrow.polar_radius(np.radians([90.0, 270.0]))
    assert np.allclose(waist, 1.0, atol=1e-3)  # 5 mm from the axis less 4: the 2 mm neck, 1 mm each side
    with pytest.raises(GeometryError, match=r"crosses itself near cam angle .* deg \(point \((?P<x>[-\d.e]+), (?P<y>[-\d.e]+)\) mm\)") as info:
        peanut.offset(-6.0)
    x, y = (float(v) for v in info.value.args[0].split("(point (")[1].split(") mm")[0].split(", "))
    assert abs(y) < 5 and abs(x) < 10  # the two sides of the neck meet inside the 10 mm waist
    assert camgen.three_arc_cam(220, 160, 25).is_convex()


def test_support_maximum_exactly_on_a_knot_is_found():
    """A periodic spline through a circle's points at 0, 10, ... 350 deg: in the direction of a
    knot the support point is that knot (symmetry), and its radius of curvature is the spline's
    there, not 0 (a corner).  Brute force over a dense sampling gives the support value."""
    phi = np.radians(np.arange(0, 361, 10.0))
    pts = 50.0 * np.stack([np.cos(phi), np.sin(phi)], 1)
    pts[-1] = pts[0]
    contour = Contour([Spline.interpolate(phi, pts)])
    psi = phi[:-1]
    h, dh, d2h = contour.support_derivatives(psi)
    dense = contour.evaluate(np.linspace(0, 1, 200001))
    assert np.allclose(h, (dense @ np.stack([np.cos(psi), np.sin(psi)])).max(axis=0), atol=1e-9)
    rho = d2h + h  # = radius of curvature at the contact point
    kappa = contour.curvature(psi / (2 * math.pi))
    assert np.allclose(rho, 1.0 / kappa, rtol=1e-9)


@pytest.mark.parametrize("n", [4, 37, 720, 5001])
def test_numpy_cubic_splines_equal_scipys(n):
    """camgen's periodic and clamped cubic splines (moments by cyclic reduction, no scipy import)
    have scipy.interpolate.CubicSpline's coefficients, for random uneven knots."""
    from scipy.interpolate import CubicSpline

    rng = np.random.default_rng(n)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.01, 3.0, n - 1))])
    y = rng.normal(size=(n, 2)) * 50
    y[-1] = y[0]
    mine, theirs = Spline.interpolate(t, y), CubicSpline(t, y, bc_type="periodic")
    assert np.max(np.abs(mine.coeffs - theirs.c)) <= 1e-12 * np.max(np.abs(theirs.c))
    d0, d1 = rng.normal(size=2) * 50, rng.normal(size=2) * 50
    mine = Spline.interpolate(t, y, periodic=False, end_derivatives=(d0, d1))
    theirs = CubicSpline(t, y, bc_type=((1, d0), (1, d1)))
    assert np.max(np.abs(mine.coeffs - theirs.c)) <= 1e-12 * np.max(np.abs(theirs.c))


@pytest.mark.parametrize("cyclic", [False, True])
def test_cyclic_reduction_against_a_dense_solve(cyclic):
    from camgen.numerics.tridiagonal import solve_tridiagonal

    rng = np.random.default_rng(3 + cyclic)
    n = 257
    lower, upper = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    diag = (np.abs(lower) + np.abs(upper)) * rng.uniform(1.1, 3.0, n) * rng.choice([-1, 1], n)
    if not cyclic:
        lower[0] = upper[-1] = 0.0
    dense = np.diag(diag) + np.diag(lower[1:], -1) + np.diag(upper[:-1], 1)
    if cyclic:
        dense[0, -1], dense[-1, 0] = lower[0], upper[-1]
    rhs = rng.normal(size=(n, 3))
    assert np.allclose(solve_tridiagonal(lower, diag, upper, rhs, cyclic), np.linalg.solve(dense, rhs), rtol=0, atol=1e-10)


# --------------------------------------------------------------------------------------------
# Vectorised evaluation, polar radius and self-intersection against per-segment and brute force
# --------------------------------------------------------------------------------------------
def many_splines_contour() -> Contour:
    """The trefoil r = 40 + 8 cos(3 theta) as 12 spline segments of 4 pieces each (breaks at
    t = 0, 1/4, 1/2, 3/4, 1: exact binary fractions, so parameters land exactly on breaks), each
    through 5 points of the curve with its exact end derivatives."""
    def curve(theta):
        r, dr = 40.0 + 8.0 * np.cos(3.0 * theta), -24.0 * np.sin(3.0 * theta)
        c, s_ = np.cos(theta), np.sin(theta)
        return np.stack([r * c, r * s_], -1), np.stack([dr * c - r * s_, dr * s_ + r * c], -1)

    span = 2 * math.pi / 12
    t = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    segments = []
    for k in range(12):
        pts, der = curve(k * span + t * span)
        segments.append(Spline.interpolate(t, pts, periodic=False, end_derivatives=(der[0] * span, der[-1] * span)))
    return Contour(segments, closure_tol=1e-9)


def concave_arcs_contour() -> Contour:
    """Four convex lobes (radius 15, centres 30 mm out) joined by concave arcs (radius 10)
    tangent to both neighbours: the contour of test_offset_of_concave_arcs_is_exact."""
    n, distance, lobe, valley = 4, 30.0, 15.0, 10.0
    centres = [distance * np.array([math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)]) for k in range(n)]
    valleys = []
    for k in range(n):
        u = np.array([math.cos(2 * math.pi * (k + 0.5) / n), math.sin(2 * math.pi * (k + 0.5) / n)])
        bq, cq = -2 * u @ centres[k], centres[k] @ centres[k] - (valley + lobe) ** 2
        valleys.append((-bq + math.sqrt(bq * bq - 4 * cq)) / 2 * u)
    arcs = []
    for k in range(n):
        vc, prev = valleys[k], valleys[k - 1]
        start = math.atan2(*(prev - centres[k])[::-1])
        arcs.append(Arc(tuple(centres[k]), lobe, start, (math.atan2(*(vc - centres[k])[::-1]) - start) % (2 * math.pi)))
        v_start = math.atan2(*(centres[k] - vc)[::-1])
        v_end = math.atan2(*(centres[(k + 1) % n] - vc)[::-1])
        arcs.append(Arc(tuple(vc), valley, v_start, -((v_start - v_end) % (2 * math.pi))))
    return Contour(arcs, closure_tol=1e-9)


@pytest.fixture(scope="module")
def biarc_tricycle(steering):
    """The tricycle steering cam as arcs within 1 um (camgen.contour.arcspline.to_arc_spline): 572 arcs."""
    from camgen.contour.arcspline import to_arc_spline

    contour = to_arc_spline(steering.profile, 1e-6)
    assert contour.n_segments > 500 and all(isinstance(s, Arc) for s in contour.segments)
    return contour


def _evaluation_cases(biarc_tricycle, steering):
    return {**{k: f() for k, f in CONTOURS.items()}, "many_splines": many_splines_contour(), "concave_arcs": concave_arcs_contour(),
            "biarc_tricycle": biarc_tricycle, "steering": steering.profile,
            "mixed_offset": mixed_contour().offset(3.0)}


@pytest.mark.parametrize("name", list(CONTOURS) + ["many_splines", "concave_arcs", "biarc_tricycle", "steering", "mixed_offset"])
def test_evaluation_equals_each_segments_own_methods(name, biarc_tricycle, steering):
    """evaluate / tangent / curvature (one vectorised pass per kind of segment) give bit for bit
    what each segment's own point / derivative / curvature give for its points (the per-segment
    loop, computed here), at random parameters, at every segment start and quarter (the spline
    breaks of many_splines: a piece located by the grouped search) and just before the end."""
    contour = _evaluation_cases(biarc_tricycle, steering)[name]
    n = contour.n_segments
    rng = np.random.default_rng(7)
    quarters = np.arange(4 * n) / 4.0  # on the breaks of many_splines
    t = np.concatenate([rng.uniform(0, n, 20000), quarters, [n - 1e-12, n, -0.25, 2 * n + 0.5]])
    point, deriv, kappa, _, _ = segmentwise(contour, t)
    assert np.array_equal(contour.evaluate(t), point)
    assert np.array_equal(contour.tangent(t), deriv / np.linalg.norm(deriv, axis=1, keepdims=True))
    assert np.array_equal(contour.curvature(t), kappa)
    assert contour.evaluate(t[:20000].reshape(4, -1)).shape == (4, 5000, 2)


def _brute_polar_radius(points: np.ndarray, phi: np.ndarray, chunk: int = 16) -> np.ndarray:
    """Distance along each ray to the closed polygon ``points``: every ray against every chord
    (u x a + s u x d = 0 with 0 <= s <= 1, distance along u > 0); the nearest hit."""
    a = points
    d = np.roll(points, -1, axis=0) - points
    out = np.empty(phi.size)
    for lo in range(0, phi.size, chunk):
        u = np.stack([np.cos(phi[lo : lo + chunk]), np.sin(phi[lo : lo + chunk])], 1)[:, None, :]
        ua = u[..., 0] * a[None, :, 1] - u[..., 1] * a[None, :, 0]
        ud = u[..., 0] * d[None, :, 1] - u[..., 1] * d[None, :, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = -ua / ud
            dist = np.einsum("rck,rk->rc", a[None] + s[..., None] * d[None], u[:, 0, :])
        ok = (s >= 0) & (s <= 1) & (dist > 0)
        out[lo : lo + chunk] = np.where(ok, dist, np.inf).min(axis=1)
    return out


@pytest.mark.parametrize("name", list(CONTOURS) + ["many_splines", "concave_arcs", "biarc_tricycle", "steering"])
def test_polar_radius_against_brute_force_and_at_every_joint(name, biarc_tricycle, steering):
    """polar_radius (sorted search, one piece per ray) against every ray intersected with every
    chord of a 1e-6 mm flattening (within 1e-5 mm: the chords are within 1e-6 of the curve, the
    rays cross it at angles far from grazing), and on rays exactly through every segment joint
    and every spline break (1e-11 relative to the point's own distance from the axis)."""
    contour = _evaluation_cases(biarc_tricycle, steering)[name]
    phi = np.linspace(-math.pi, math.pi, 721)
    brute = _brute_polar_radius(contour.flatten(1e-6), phi)
    assert np.max(np.abs(contour.polar_radius(phi) - brute)) <= 1e-5
    joints = [seg.start_point for seg in contour.segments]
    joints += [p for seg in contour.segments if isinstance(seg, Spline) for p in seg.eval_t(seg.breaks)]
    joints = np.array(joints)
    radius = contour.polar_radius(np.arctan2(joints[:, 1], joints[:, 0]))
    assert np.max(np.abs(radius / np.hypot(joints[:, 0], joints[:, 1]) - 1)) <= 1e-11
    assert contour.polar_radius(phi.reshape(7, 103)).shape == (7, 103)


def test_polar_radius_memory_is_linear_in_the_rays(biarc_tricycle):
    """2e5 rays on the 572-arc contour: the peak of new allocations (tracemalloc, numpy's arrays
    included) stays under 1 kB per ray, where a table of rays x pieces would take 9 kB per ray
    (572 arcs x 2 roots x 8 bytes)."""
    import tracemalloc

    phi = np.linspace(0.0, 2 * math.pi, 200000, endpoint=False)
    biarc_tricycle.polar_radius(phi[:10])  # the contour's tables, built once
    tracemalloc.start()
    biarc_tricycle.polar_radius(phi)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 1000 * phi.size


def test_polar_radius_of_a_contour_not_star_shaped_is_an_error():
    disc = Contour([Arc((30.0, 0.0), 10.0, 0.0, 2 * math.pi)])  # rays miss it or meet it twice
    with pytest.raises(GeometryError, match="not star-shaped about the rotation axis: the ray at cam angle"):
        disc.polar_radius(np.array([0.0]))
    # a disc of radius 40 with a rectangular notch [15, 40] x [-10, 10] cut in: the ray at 20 deg
    # leaves through the notch's bottom, re-enters through its side and leaves at the circle
    def line(p, q):
        p, q = np.asarray(p, float), np.asarray(q, float)
        return Spline([0.0, 1.0], np.stack([np.zeros(2), np.zeros(2), q - p, p])[:, None, :])

    start = math.asin(10 / 40)
    corner = 40 * math.cos(start)
    notched = Contour([Arc((0.0, 0.0), 40.0, start, 2 * math.pi - 2 * start), line((corner, -10), (15, -10)),
                       line((15, -10), (15, 10)), line((15, 10), (corner, 10))], closure_tol=1e-9)
    assert notched.polar_radius(np.radians([90.0, 180.0])) == pytest.approx([40.0, 40.0], abs=1e-12)  # rays meeting it once
    with pytest.raises(GeometryError, match="not star-shaped.*cam angle 20.000 deg"):
        notched.polar_radius(np.radians([90.0, 20.0]))


@pytest.mark.parametrize("gap", [0.0, 1e-12, -1e-12, 1e-9, -1e-9])
def test_a_ray_through_a_joint_meets_it_once_whatever_the_rounding_there(gap):
    """A circle of radius 50 from four cubic Hermite quarters whose second one ends ``gap`` mm off
    (within closure_tol): the ray at 180 deg runs through that joint (its direction's sine is
    1.2e-16, not 0, so it can pass between the two ends); both the sorted-table path and the
    every-piece path give the radius there (50 mm up to the gap), and 1e-13 rad either side."""
    radius = 50.0

    def quarter(a0, a1, off):
        t = np.linspace(a0, a1, 9)
        p = np.c_[radius * np.cos(t), radius * np.sin(t)]
        p[-1, 1] += off
        return Spline.hermite(t, p, np.c_[-radius * np.sin(t), radius * np.cos(t)])

    circle = Contour([quarter(0.0, math.pi / 2, 0.0), quarter(math.pi / 2, math.pi, gap), quarter(math.pi, 1.5 * math.pi, 0.0),
                      quarter(1.5 * math.pi, 2 * math.pi, 0.0)])
    phi = np.array([math.pi, math.pi - 1e-13, math.pi + 1e-13])
    for got in (circle.polar_radius(phi), circle._polar_radius_all_pieces(phi)):
        assert np.max(np.abs(got - radius)) <= abs(gap) + 1e-12


def _brute_crossing(points: np.ndarray):
    """All pairs of non-adjacent chords of the closed polygon: the crossing with the smallest
    (i, j), i < j, as the point on chord i; None without one."""
    n = len(points)
    a, d = points, np.roll(points, -1, axis=0) - points

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    for i in range(n):
        j = np.arange(i + 2, n - (1 if i == 0 else 0))
        if not j.size:
            continue
        o1, o2 = cross(d[i], a[j] - a[i]), cross(d[i], a[j] + d[j] - a[i])
        o3, o4 = cross(d[j], a[i] - a[j]), cross(d[j], a[i] + d[i] - a[j])
        hit = (o1 * o2 < 0) & (o3 * o4 < 0)
        if hit.any():
            k = np.argmax(hit)
            return a[i] + o3[k] / (o3[k] - o4[k]) * d[i]
    return None


@pytest.mark.parametrize("distance", [-4.0, -6.0, -9.0, 0.2])
def test_self_intersection_equals_all_pairs(distance):
    """The x sweep finds the crossing of the all-pairs scan (the same pair, the same point) on
    the peanut's offsets: none at -4 and +0.2 mm, the neck crossing at -6 and -9 mm."""
    theta = np.linspace(0.0, 2 * math.pi, 121)
    r = 30 + 25 * np.cos(2 * theta)
    peanut = Spline.interpolate(theta, np.stack([r * np.cos(theta), r * np.sin(theta)], 1))
    offset = Contour([peanut.offset(distance, tol=1e-5)], closure_tol=1e-4)
    tol = 1e-3
    expected = _brute_crossing(offset.flatten(tol))
    found = offset.self_intersection(tol)
    assert (expected is None) == (distance in (-4.0, 0.2))
    if expected is None:
        assert found is None
    else:
        assert np.array_equal(found, expected)


# --------------------------------------------------------------------------------------------
# Least-squares fits within a tolerance (camgen.numerics.splinefit)
# --------------------------------------------------------------------------------------------
def _ellipse(a: float = 50.0, b: float = 30.0):
    def curve(t):
        return np.stack([a * np.cos(t), b * np.sin(t)], axis=1)

    return curve


def _ellipse_distance(points: np.ndarray, a: float = 50.0, b: float = 30.0) -> np.ndarray:
    """Distance of points to the ellipse x^2/a^2 + y^2/b^2 = 1 by Newton on the foot point's
    parameter (closed-form curve, independent of the fit)."""
    t = np.arctan2(points[:, 1] / b, points[:, 0] / a)
    for _ in range(30):
        p = np.stack([a * np.cos(t), b * np.sin(t)], 1)
        d1 = np.stack([-a * np.sin(t), b * np.cos(t)], 1)
        d2 = -p
        g = np.einsum("ij,ij->i", p - points, d1)
        dg = np.einsum("ij,ij->i", d1, d1) + np.einsum("ij,ij->i", p - points, d2)
        t = t - g / dg
    p = np.stack([a * np.cos(t), b * np.sin(t)], 1)
    return np.hypot(*(p - points).T)


@pytest.mark.parametrize("tol", [1e-5, 1e-7, 1e-9])
def test_periodic_fit_is_within_tol_between_the_probes_and_c2(tol):
    from camgen.numerics.splinefit import fit_periodic

    fit = fit_periodic(_ellipse(), 0.0, 2 * math.pi, tol)
    spline = Spline(fit.breaks, fit.coeffs)
    t = np.random.default_rng(7).uniform(0, 2 * math.pi, 200_000)
    assert np.max(_ellipse_distance(spline.eval_t(t))) <= tol
    assert fit.error <= tol
    contour = Contour([spline])
    assert contour.continuity() == "G2"
    # the B-spline form holds the pieces exactly (scipy evaluates it independently)
    from scipy.interpolate import BSpline

    assert np.max(np.abs(BSpline(fit.knots, fit.controls, 3)(t) - spline.eval_t(t))) <= 1e-10


def test_periodic_fit_pieces_scale_as_tol_to_the_minus_quarter():
    """A cubic's error falls as h^4, so the fewest pieces within tol grow as tol^(-1/4)."""
    from camgen.numerics.splinefit import fit_periodic

    tols = np.array([1e-4, 1e-6, 1e-8, 1e-10])
    pieces = np.array([fit_periodic(_ellipse(), 0.0, 2 * math.pi, tol).breaks.size - 1 for tol in tols])
    slope = np.polyfit(np.log(tols), np.log(pieces), 1)[0]
    assert -0.28 <= slope <= -0.22, (pieces, slope)


def test_least_squares_fit_has_no_one_signed_radial_error():
    """Why the fits are least squares: a cubic spline interpolating a circle at its knots lies
    inside it between them (radial error one-signed, mean about -half its extreme); the L2 fit's
    error changes sign, its mean is ~1e-3 of its extreme (circle of radius 50 mm, closed form)."""
    from camgen.numerics.splinefit import fit_periodic

    r = 50.0
    fit = fit_periodic(lambda t: np.stack([r * np.cos(t), r * np.sin(t)], 1), 0.0, 2 * math.pi, 1e-7)
    lsq = Spline(fit.breaks, fit.coeffs)
    pts = r * np.stack([np.cos(fit.breaks), np.sin(fit.breaks)], 1)
    pts[-1] = pts[0]
    interp = Spline.interpolate(fit.breaks, pts, periodic=True)
    t = np.linspace(0.0, 2 * math.pi, 400_001)[:-1]
    radial_lsq = np.hypot(*lsq.eval_t(t).T) - r
    radial_int = np.hypot(*interp.eval_t(t).T) - r
    assert np.max(radial_int) <= 1e-12 and np.mean(radial_int) < -0.4 * np.max(np.abs(radial_int))
    assert np.min(radial_lsq) < 0 < np.max(radial_lsq)
    assert abs(np.mean(radial_lsq)) <= 1e-3 * np.max(np.abs(radial_lsq))


def test_clamped_fit_keeps_the_end_conditions_exactly():
    """A quarter of the ellipse (closed-form point, first and second derivative at both ends)."""
    from camgen.numerics.splinefit import fit_clamped

    a, b = 50.0, 30.0
    lo, hi = 0.2, 1.9

    def ends(t):
        return (np.array([a * math.cos(t), b * math.sin(t)]), np.array([-a * math.sin(t), b * math.cos(t)]),
                np.array([-a * math.cos(t), -b * math.sin(t)]))

    fit = fit_clamped(_ellipse(a, b), lo, hi, 1e-8, ends(lo) + ends(hi))
    spline = Spline(fit.breaks, fit.coeffs)
    h = float(np.diff(fit.breaks)[-1])
    for (piece, tau, t) in ((0, 0.0, lo), (spline.n_pieces - 1, h, hi)):
        for order, want in enumerate(ends(t)):
            got = spline.eval_piece(np.array([piece]), np.array([tau]), order)[0]
            assert np.allclose(got, want, rtol=0, atol=1e-9 * (1 + np.max(np.abs(want))))
    t = np.random.default_rng(8).uniform(lo, hi, 100_000)
    assert np.max(_ellipse_distance(spline.eval_t(t), a, b)) <= 1e-8
    inner = np.arange(1, spline.n_pieces)
    for order in (0, 1, 2):  # C2 at every inner break
        left = spline.eval_piece(inner - 1, np.diff(fit.breaks)[:-1], order)
        right = spline.eval_piece(inner, np.zeros(inner.size), order)
        assert np.max(np.abs(left - right)) <= 1e-7 * 10**order


def test_fits_reject_bad_tolerances_and_give_up_with_a_clear_error():
    from camgen.numerics.splinefit import fit_clamped, fit_periodic

    with pytest.raises(ParameterError, match="tol"):
        fit_periodic(_ellipse(), 0.0, 2 * math.pi, 1e-15)
    with pytest.raises(ParameterError, match="tol"):
        fit_periodic(_ellipse(), 0.0, 2 * math.pi, -1.0)
    # a corner (|t|) cannot be fitted within 1e-9 by a C2 cubic with at most 50 pieces
    z = np.zeros(2)
    with pytest.raises(GeometryError, match="does not reach tol"):
        fit_clamped(lambda t: np.stack([t, np.abs(t)], 1), -1.0, 1.0, 1e-9, (np.array([-1.0, 1.0]), np.array([1.0, -1.0]), z,
                    np.array([1.0, 1.0]), np.array([1.0, 1.0]), z), max_pieces=50)


def test_spline_green_area_against_gauss_legendre_quadrature():
    """Random cubic pieces: (1/2) integral of x y' - y x' by 8-point Gauss-Legendre on every piece
    (exact for the degree-5 integrand), evaluated here from the power form with numpy.polynomial."""
    rng = np.random.default_rng(21)
    nodes, weights = np.polynomial.legendre.leggauss(8)
    for trial in range(20):
        k = int(rng.integers(1, 40))
        breaks = np.cumsum(rng.uniform(0.01, 3.0, k + 1)) - 5.0
        coeffs = rng.normal(size=(4, k, 2)) * rng.choice([1e-3, 1.0, 50.0])
        expected = 0.0
        for i in range(k):
            h = breaks[i + 1] - breaks[i]
            tau = 0.5 * h * (nodes + 1.0)
            x, y = (np.polynomial.Polynomial(coeffs[::-1, i, j]) for j in range(2))
            integrand = x(tau) * y.deriv()(tau) - y(tau) * x.deriv()(tau)
            expected += 0.5 * float(np.sum(weights * integrand)) * 0.5 * h
        scale = np.sum(np.abs(coeffs)) ** 2 * (breaks[-1] - breaks[0] + 1.0) ** 6
        assert abs(Spline(breaks, coeffs).green_area() - expected) <= 1e-13 * scale, trial


@pytest.mark.parametrize("n", [1, 2, 3, 7, 64, 1500])
@pytest.mark.parametrize("q", [0.0, 0.5, 0.9, 0.999])
def test_cyclic_reduction_step_count_against_a_dense_solve(n, q):
    """Non-cyclic systems whose dominance ratio max (|lower| + |upper|) / |diag| is q: the reduction
    stops once the couplings are eliminated (q^(2^k), Heller's bound) or the distance reaches n
    (every coupling outside the system); the solution is numpy's dense solve's."""
    from camgen.numerics.tridiagonal import solve_tridiagonal

    rng = np.random.default_rng(int(1000 * q) + n)
    lower, upper = rng.uniform(-1, 1, n) * (q > 0), rng.uniform(-1, 1, n) * (q > 0)  # q = 0: a diagonal system
    lower[0] = upper[-1] = 0.0
    diag = (np.abs(lower) + np.abs(upper)) / max(q, 1e-300) * rng.uniform(1.0, 1.0 + (1.0 - q), n)
    diag[(np.abs(lower) + np.abs(upper)) == 0] = 1.0
    diag *= rng.choice([-1, 1], n)
    dense = np.diag(diag) + np.diag(lower[1:], -1) + np.diag(upper[:-1], 1)
    rhs = rng.normal(size=(n, 3))
    exact = np.linalg.solve(dense, rhs)
    got = solve_tridiagonal(lower, diag, upper, rhs, cyclic=False)
    assert got.shape == rhs.shape
    assert np.max(np.abs(got - exact)) <= 1e-10 * max(1.0, np.max(np.abs(exact)))
