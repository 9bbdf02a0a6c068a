"""The wall, continuity and undercut checks of a plate cam, made with fewer array passes (issue 28
item 6), against the computations they replaced.

* :func:`camgen.body.wall_left` flattens only the pieces of the profile whose Bezier hull can
  come as near the bore or keyway as the wall (:mod:`camgen.wall_polygon`): the wall and its cam
  angle are bit for bit those measured on the whole polygon (the code before this work, kept here
  verbatim as the reference) over plate cams of many base radii, offsets, bores and keyways
  (through the profile too), and over a contour with arcs (which is flattened whole);
* the vertices of a part of the polygon (:func:`camgen.contour.partial.polygon_part`) are the
  whole polygon's, bit for bit, for random sets of pieces;
* the joints of a contour (:meth:`camgen.contour.Contour.joints`) take the splines' end tangents
  and curvatures in one pass: bit for bit the joints from each segment's own ``derivative`` and
  ``curvature`` (the code before, verbatim), on cubic, quintic and mixed contours and with arcs;
* the undercut check's least convex radius of the pitch curve from the largest curvature
  (:func:`camgen.kinds.least_radius.least_convex_radius`): bit for bit the least of every
  sample's reciprocal, ties within the last place included.

No clock: the time is measured in benchmarks/bench_evaluate.py.
"""
from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest


def _plate(change: dict):
    """The contour and body of templates/plate_cam.toml with ``change`` in its cam table."""
    from camgen.kinds import get_kind
    from camgen.scene import parse_scene, template_path

    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    data["cams"]["plate"].update(copy.deepcopy(change))
    (spec,) = parse_scene(data, "plate").cams
    built = get_kind(spec.kind, spec.form).build(spec, frozenset())
    return built.contour, spec.body


def _whole_polygon_wall(contour, body, chord_tol):
    """camgen.body.wall_left before this work (commit 9151046), verbatim: the whole polygon."""
    if body.bore_diameter <= 0:
        return math.inf, 0.0
    poly = contour.flatten(chord_tol)
    radius = np.hypot(poly[:, 0], poly[:, 1])
    i = int(np.argmin(radius))
    wall, where = float(radius[i]) - body.bore_diameter / 2, poly[i]
    if body.keyway_width > 0:
        c, s = math.cos(body.keyway_angle), math.sin(body.keyway_angle)
        along = poly @ np.array([c, s])
        across = poly @ np.array([-s, c])
        out = body.keyway_reach
        dx = np.maximum(np.maximum(-along, along - out), 0.0)
        dy = np.maximum(np.abs(across) - body.keyway_width / 2, 0.0)
        dist = np.hypot(dx, dy)
        inside = (along >= 0) & (along <= out) & (np.abs(across) <= body.keyway_width / 2)
        dist = np.where(inside, -1.0, dist)
        corners = body.keyway_corners()[1:3]
        j = int(np.argmin(dist))
        k_wall = float(dist[j])
        edge = np.roll(poly, -1, axis=0) - poly
        for corner in corners:
            rel = corner - poly
            u = np.clip(np.einsum("ij,ij->i", rel, edge) / np.maximum(np.einsum("ij,ij->i", edge, edge), 1e-300), 0.0, 1.0)
            gaps = np.hypot(*(rel - u[:, None] * edge).T)
            i_edge = int(np.argmin(gaps))
            if gaps[i_edge] < k_wall:
                k_wall, j = float(gaps[i_edge]), i_edge
        chords = np.hypot(*(np.roll(poly, -1, axis=0) - poly).T)
        nearest = float(np.min(radius)) - 0.5 * float(np.max(chords)) - chord_tol
        if bool(np.max(np.hypot(corners[:, 0], corners[:, 1])) >= nearest):
            reach = contour.polar_radius(np.arctan2(corners[:, 1], corners[:, 0]))
            if np.any(np.hypot(corners[:, 0], corners[:, 1]) >= reach):
                k_wall = min(k_wall, -1.0)
        if k_wall < wall:
            wall, where = k_wall, poly[j]
    return wall - chord_tol, math.degrees(math.atan2(where[1], where[0])) % 360.0


#: Plate cams: the template, small and large base radii, offsets, the other direction, a knife's corners.
PLATES = {
    "template": {},
    "small": {"base_radius_mm": 20.0, "bore_diameter_mm": 20.0, "keyway_width_mm": 6.0, "keyway_depth_mm": 2.0},
    "large_offset": {"base_radius_mm": 55.0, "follower_offset_mm": -12.0, "keyway_angle_deg": 200.0},
    "clockwise": {"rotation": "cw", "keyway_angle_deg": 10.0, "roller_radius_mm": 6.0},
    "no_keyway": {"keyway_width_mm": 0.0, "keyway_depth_mm": 0.0, "bore_diameter_mm": 30.0},
}


@pytest.mark.parametrize("plate", sorted(PLATES))
def test_the_wall_is_the_whole_polygons_bit_for_bit(plate):
    """The scene's body, then bodies drawn at random about the profile: bores from well inside
    to beyond it, keyways of every width, depth and direction (some reaching through it)."""
    from camgen.body import WALL_TOL, BodySpec, wall_left

    contour, body = _plate(PLATES[plate])
    assert wall_left(contour, body) == _whole_polygon_wall(contour, body, WALL_TOL)
    near = float(np.min(np.hypot(*contour.flatten(1e-2).T)))
    rng = np.random.default_rng(sum(map(ord, plate)))
    for _ in range(24):
        bore = float(rng.uniform(0.2, 2.1)) * near
        if rng.random() < 0.75:
            body = BodySpec(bore_diameter=bore, keyway_width=float(rng.uniform(0.05, 0.9)) * bore,
                            keyway_depth=float(rng.uniform(0.02, 1.0)) * near, keyway_angle=float(rng.uniform(-7.0, 7.0)))
        else:
            body = BodySpec(bore_diameter=bore)
        for tol in (WALL_TOL, 1e-2):
            try:
                expected = _whole_polygon_wall(contour, body, tol)
            except Exception as exc:  # a ray through a keyway corner finds a profile that is not star-shaped
                with pytest.raises(type(exc)):
                    wall_left(contour, body, tol)
                continue
            assert wall_left(contour, body, tol) == expected, (body, tol)


def test_every_templates_walls_are_the_whole_polygons_bit_for_bit():
    """Every planar cam of every bundled template (plate, groove, conjugate, constant breadth,
    linear, lift table ...): its own body, a bore with a keyway toward the profile's nearest
    vertex, and a keyway reaching beyond the profile."""
    from camgen.body import WALL_TOL, BodySpec, wall_left
    from camgen.kinds import get_kind
    from camgen.scene import load_template
    from golden.regenerate import TEMPLATES

    for name in TEMPLATES:
        for spec in load_template(name).cams:
            cam = get_kind(spec.kind, spec.form).build(spec, frozenset())
            if not cam.planar or cam.contour is None:
                continue
            poly = cam.contour.flatten(1e-2)
            radius = np.hypot(poly[:, 0], poly[:, 1])
            near, toward = float(radius.min()), float(np.arctan2(*poly[int(np.argmin(radius))][::-1]))
            bodies = [cam.body, BodySpec(bore_diameter=0.8 * near, keyway_width=0.2 * near, keyway_depth=0.3 * near, keyway_angle=toward),
                      BodySpec(bore_diameter=0.5 * near, keyway_width=0.1 * near, keyway_depth=0.9 * near, keyway_angle=toward + 0.05)]
            for body in bodies:
                try:
                    expected = _whole_polygon_wall(cam.contour, body, WALL_TOL)
                except Exception as exc:  # not star-shaped where a keyway corner's ray meets it
                    with pytest.raises(type(exc)):
                        wall_left(cam.contour, body)
                    continue
                assert wall_left(cam.contour, body) == expected, (name, spec.name, body)


def test_a_profile_with_arcs_is_flattened_whole_with_the_same_wall():
    """A contour of arcs (the fallback: no Bezier hulls) gives the whole polygon's wall."""
    from camgen.body import WALL_TOL, BodySpec, wall_left
    from camgen.contour import Arc, Contour
    from camgen.contour.partial import contour_pieces

    # an arc of 20 mm about the axis over +-0.5 rad, closed by an arc about (-12, 0) through its ends
    x, y = 20.0 * math.cos(0.5), 20.0 * math.sin(0.5)
    start = math.atan2(y, x + 12.0)
    contour = Contour([Arc((0.0, 0.0), 20.0, -0.5, 1.0), Arc((-12.0, 0.0), math.hypot(x + 12.0, y), start, 2.0 * math.pi - 2.0 * start)])
    assert contour_pieces(contour, WALL_TOL) is None
    for body in (BodySpec(bore_diameter=10.0), BodySpec(bore_diameter=10.0, keyway_width=3.0, keyway_depth=4.0, keyway_angle=0.3)):
        assert wall_left(contour, body) == _whole_polygon_wall(contour, body, WALL_TOL)


def test_the_template_wall_flattens_a_part_of_the_profile():
    """What makes the wall cheaper: of the template's profile only the pieces near the keyway
    are flattened (a fifth of the vertices or fewer), and they are the whole polygon's."""
    from camgen.body import WALL_TOL
    from camgen.wall_polygon import wall_polygon

    contour, body = _plate({})
    whole = contour.flatten(WALL_TOL)
    part = wall_polygon(contour, WALL_TOL, body.bore_diameter / 2, body.keyway_corners())
    assert len(part.points) <= len(whole) // 5
    assert all(any(np.array_equal(p, q) for q in whole) for p in part.points[:: max(1, len(part.points) // 10)])


@pytest.mark.parametrize("plate", ["template", "clockwise"])
def test_the_vertices_of_a_part_are_the_whole_polygons(plate):
    """Random sets of pieces: their vertices, each followed by the next piece's first vertex, are
    the whole polygon's at the same places, and each vertex's successor is the polygon's next."""
    from camgen.contour.partial import contour_pieces, polygon_part

    contour, _ = _plate(PLATES[plate])
    rng = np.random.default_rng(7)
    for tol in (1e-4, 1e-3, 0.05):
        whole = contour.flatten(tol)
        pieces = contour_pieces(contour, tol)
        assert pieces is not None and int(pieces.counts.sum()) == len(whole)
        first = np.cumsum(pieces.counts) - pieces.counts  # each piece's first vertex in the whole polygon
        for _ in range(6):
            keep = rng.random(pieces.size) < rng.uniform(0.05, 0.9)
            keep[int(rng.integers(pieces.size))] = True
            part = polygon_part(pieces, keep)
            index = np.concatenate([first[p] + np.arange(pieces.counts[p] if keep[p] else int(keep[p - 1]))
                                    for p in range(pieces.size)])
            assert np.array_equal(part.points, whole[index])
            inner = part.successor >= 0
            assert np.array_equal(inner, keep[np.searchsorted(first, index, side="right") - 1])
            assert np.array_equal(index[part.successor[inner]], (index[inner] + 1) % len(whole))


@pytest.mark.parametrize("plate", ["template", "clockwise", "large_offset"])
def test_points_on_known_pieces_are_the_contours_evaluation(plate):
    """evaluate_on (the vertices' points with their pieces known, no sorted search) gives
    Contour.evaluate's points bit for bit: every vertex of the whole polygon with its own piece, and
    with a wrong piece named for some (the other way: evaluate itself), at three tolerances."""
    from camgen.contour.partial import contour_pieces, evaluate_on

    contour, _ = _plate(PLATES[plate])
    rng = np.random.default_rng(11)
    for tol in (1e-4, 1e-3, 0.05):
        params = contour.flatten_params(tol)
        pieces = contour_pieces(contour, tol)
        assert pieces is not None and int(pieces.counts.sum()) == params.size
        piece = np.repeat(np.arange(pieces.size), pieces.counts)
        want = contour.evaluate(params)
        assert np.array_equal(evaluate_on(pieces, piece, params), want)
        wrong = piece.copy()
        moved = rng.random(piece.size) < 0.2
        wrong[moved] = (wrong[moved] + rng.integers(1, pieces.size, moved.sum())) % pieces.size
        assert np.array_equal(evaluate_on(pieces, wrong, params), want)
        # a piece's last break (the next piece's start) as a parameter: the next piece's point
        ends = pieces.segment + (pieces.end - pieces.t0) / pieces.span
        assert np.array_equal(evaluate_on(pieces, np.arange(pieces.size), ends), contour.evaluate(ends))


def _segment_joints(contour, curvature_tol):
    """camgen.contour.Contour.joints before this work (commit 4cd56c6), verbatim: each segment's
    own end tangents and curvatures."""
    from camgen.contour import Joint, Spline

    def end_values(seg):
        if isinstance(seg, Spline):
            both = np.array([0.0, 1.0])
            return seg.derivative(both), seg.curvature(both)
        start, end = np.array([0.0]), np.array([1.0])
        return (np.concatenate([seg.derivative(start), seg.derivative(end)]),
                np.concatenate([seg.curvature(start), seg.curvature(end)]))

    out = []
    n = contour.n_segments
    ends = [end_values(seg) for seg in contour.segments]
    for i, seg in enumerate(contour.segments):
        nxt = contour.segments[(i + 1) % n]
        end = seg.end_point
        gap = float(np.hypot(*(end - nxt.start_point)))
        t_end = ends[i][0][1]
        t_start = ends[(i + 1) % n][0][0]
        cross = t_end[0] * t_start[1] - t_end[1] * t_start[0]
        dot = float(t_end @ t_start)
        angle = abs(math.atan2(cross, dot))
        k_jump = float(ends[(i + 1) % n][1][0] - ends[i][1][1])
        level = "none" if gap > 1e-9 else "G0" if angle > 1e-9 else "G1" if abs(k_jump) > curvature_tol else "G2"
        out.append(Joint(i, (float(end[0]), float(end[1])), gap, angle, k_jump, level))
    return tuple(out)


def _spline_loop(rng, degrees, closure=True):
    """A closed counter-clockwise chain of random splines (of the given degrees) about the axis."""
    from camgen.contour import Spline

    n = len(degrees)
    angles = np.linspace(0.0, 2.0 * math.pi, n + 1)
    segments = []
    for k, degree in enumerate(degrees):
        pieces = int(rng.integers(1, 6))
        t = np.linspace(angles[k], angles[k + 1], pieces + 1)
        t[1:-1] += rng.uniform(-0.2, 0.2, pieces - 1) * (t[1] - t[0])
        r = 30.0 + rng.uniform(-3.0, 3.0, pieces + 1)
        r[0], r[-1] = 30.0, 30.0  # the segments meet on the circle
        points = np.stack([r * np.cos(t), r * np.sin(t)], axis=1)
        first = np.stack([-r * np.sin(t), r * np.cos(t)], axis=1) * rng.uniform(0.8, 1.2, (pieces + 1, 1))
        if degree == 3:
            segments.append(Spline.hermite(t, points, first))
        else:
            second = -np.stack([r * np.cos(t), r * np.sin(t)], axis=1) * rng.uniform(0.8, 1.2, (pieces + 1, 1))
            segments.append(Spline.hermite5(t, points, first, second))
    return segments


@pytest.mark.parametrize("degrees", [(5, 5, 5, 5), (3, 3, 3), (3, 5, 3, 5, 5)])
def test_the_joints_are_each_segments_own_bit_for_bit(degrees):
    from camgen.contour import Arc, Contour

    rng = np.random.default_rng(len(degrees) * 11 + sum(degrees))
    for _ in range(5):
        segments = _spline_loop(rng, degrees)
        contour = Contour(segments, closure_tol=1e-6)
        for tol in (1e-9, 1e-6):
            assert contour.joints(curvature_tol=tol) == _segment_joints(contour, tol)
        # an arc in the chain: its ends from its own methods, the splines' in one pass
        with_arc = Contour(segments[:-1] + [Arc((0.0, 0.0), 30.0, float(segments[-1].breaks[0]),
                                                2.0 * math.pi - float(segments[-1].breaks[0]))], closure_tol=1e-6)
        assert with_arc.joints(curvature_tol=1e-6) == _segment_joints(with_arc, 1e-6)


def test_the_plate_cams_joints_are_each_segments_own_bit_for_bit():
    for plate in PLATES:
        contour, _ = _plate(PLATES[plate])
        assert contour.joints(curvature_tol=1e-6) == _segment_joints(contour, 1e-6)


def test_joints_from_the_splines_alone_are_the_tables_and_each_segments_bit_for_bit():
    """A fresh contour of splines (no segment tables: the joints from the splines themselves,
    camgen.contour.spline_joints.spline_joint_values), the same contour after an evaluation built its tables
    (the tables' path), and each segment's own values (the code before) give the same joints."""
    from camgen.contour import Contour

    for plate in PLATES:
        contour, _ = _plate(PLATES[plate])
        fresh = Contour(contour.segments)
        assert "_segment_tables" not in fresh.__dict__
        direct = fresh.joints(curvature_tol=1e-6)
        assert "_segment_tables" not in fresh.__dict__  # the splines' path taken
        tabled = Contour(contour.segments)
        tabled.evaluate(np.array([0.5]))
        assert "_segment_tables" in tabled.__dict__
        assert direct == tabled.joints(curvature_tol=1e-6) == _segment_joints(contour, 1e-6)


def test_the_least_convex_radius_is_the_least_reciprocal_bit_for_bit():
    """camgen.kinds.least_radius against every sample's radius ``1 / k`` (the pitch curve's radius
    of curvature before this work): curvatures equal but for a few units in the last place (a
    dwell's base circle: distinct curvatures whose reciprocals round alike), zeros, negatives, NaN, and one so small its
    radius overflows."""
    from camgen.kinds.least_radius import least_convex_radius

    def every_sample(k):
        with np.errstate(divide="ignore", over="ignore"):
            rho = np.where(k != 0, 1.0 / np.where(k != 0, k, 1.0), np.inf)
        convex = np.where(rho > 0, rho, np.inf)
        i = int(np.argmin(convex))
        return float(convex[i]), i

    rng = np.random.default_rng(28)
    for _ in range(3000):
        n = int(rng.integers(1, 40))
        base = float(rng.choice([1 / 40, 1.99 / 64, 1.99, 1e-3, 3.0, 1e-310]))  # 1.99 2^e: reciprocals closer than k
        k = (base + rng.integers(-3, 4, n) * np.spacing(base)) * rng.choice([1.0, -1.0], n, p=[0.7, 0.3])  # a few ulps apart
        if rng.random() < 0.3:
            k[rng.integers(n)] = 0.0
        if rng.random() < 0.1:
            k[rng.integers(n)] = np.nan
        if rng.random() < 0.1:  # an infinite curvature: radius 1 / inf = 0, not a positive radius
            k[rng.integers(n)] = np.inf
        if rng.random() < 0.3:
            k = np.concatenate([k, rng.normal(0.0, base, 5)])
        assert least_convex_radius(k) == every_sample(k), k
    assert least_convex_radius(np.array([0.01, np.inf, 0.02, -0.5])) == every_sample(np.array([0.01, np.inf, 0.02, -0.5])) == (50.0, 2)


def test_the_pieces_layout_kept_across_designs_is_each_contours_own():
    """The pieces' indices kept per piece counts (``partial._layout``, shared by a study's designs)
    against a loop over each contour's splines and pieces, for designs in a row with the same
    piece counts (base radii) and others (a lift, a quintic law); the kept arrays are read-only."""
    from camgen.body import WALL_TOL
    from camgen.contour.partial import contour_pieces

    changes = [{}, {"base_radius_mm": 47.5}, {"base_radius_mm": 23.0}, PLATES["clockwise"], PLATES["large_offset"], {}]
    for change in changes:
        contour, _ = _plate(change)
        pieces = contour_pieces(contour, WALL_TOL)
        assert pieces is not None
        segment, start, end, t0, first, last = [], [], [], [], [], []
        for number, spline in enumerate(contour.segments):
            for k in range(spline.n_pieces):
                segment.append(number)
                start.append(spline.breaks[k])
                end.append(spline.breaks[k + 1])
                t0.append(spline.breaks[0])
                first.append(k == 0)
                last.append(k == spline.n_pieces - 1)
        for got, want in ((pieces.segment, segment), (pieces.start, start), (pieces.end, end), (pieces.t0, t0),
                          (pieces.first, first), (pieces.last, last)):
            assert got.tolist() == want, change
        for kept in (pieces.segment, pieces.first, pieces.last):
            assert not kept.flags.writeable
