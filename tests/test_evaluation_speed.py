"""The evaluation a sweep makes of one design (issue 28 item 6), and the faster pieces under it.

* :func:`camgen.evaluation.evaluation_plan`: on a sample of plate-cam designs (base radii, offsets,
  laws, rollers, a failing pressure angle, a failing torque) every check it makes has the name,
  status and value ``camgen check`` prints for the same scene written to a file and checked in
  a child process (the full plan: an independent path; its table parsed by column);
* the exact extreme points of all of a contour's spline pieces in one grouped pass
  (:func:`camgen.contour.spline.extreme_points_of`): bit for bit those of the per-spline,
  per-axis root finding it replaced (kept here as the reference); the bounding box from the
  pieces that can reach out of the break points' box only (:func:`camgen.contour.spline.bounding_box_of`)
  bit for bit the box of every extreme point, and against a brute-force sampling of 10^6 points
  per spline; the perimeter against the dense polyline.

No clock: the time is measured in benchmarks/bench_evaluate.py.
"""
from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
import tomllib

import numpy as np
import pytest

from helpers import scene_toml

#: The design of templates/plate_cam.toml, with its machining table, and the changes of the sample.
DESIGNS = {
    "template": {},
    "small_base_radius": {"base_radius_mm": 20.0},  # the pressure angle fails (and the advice appears)
    "no_offset_small_roller": {"follower_offset_mm": 0.0, "roller_radius_mm": 6.0},
    "negative_offset_big_roller": {"follower_offset_mm": -6.0, "roller_radius_mm": 14.0, "base_radius_mm": 55.0},
    "low_torque_limit": {"torque_limit_n_m": 0.5, "rpm": 600.0},  # the camshaft torque fails
    "other_laws": {"segments": [{"law": "poly345", "span_deg": 100.0, "lift_mm": 15.0}, {"law": "dwell", "span_deg": 80.0},
                                {"law": "cycloidal", "span_deg": 140.0, "lift_mm": -15.0}, {"law": "dwell", "span_deg": 40.0}]},
}
#: ``camgen check``'s result column -> CheckResult.status
STATUS = {"pass": "pass", "FAIL": "fail", "info": "info"}


def _scene(change: dict) -> dict:
    from camgen.scene import template_path

    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    data["output"]["formats"] = ["dxf"]  # the same scene both ways; the check runs no mesh or G-code
    data["cams"]["plate"].update(copy.deepcopy(change))
    return data


def _check_table(stdout: str) -> list[dict[str, str]]:
    """The rows of ``camgen check``'s table, cut at the header's column starts."""
    lines = stdout.splitlines()
    header = next(i for i, line in enumerate(lines) if line.split()[:3] == ["cam", "check", "result"])
    names = lines[header].split()
    starts = [lines[header].index(name) for name in names]
    rows = []
    for line in lines[header + 1:]:
        if line.startswith("camgen:") or not line.strip():
            break
        cells = [line[a:b].strip() for a, b in zip(starts, starts[1:] + [len(line) + 1])]
        rows.append(dict(zip(names, cells)))
    return rows


def _same_value(printed: str, value: object) -> bool:
    """``printed`` (6 significant digits for a float) is ``value``."""
    if isinstance(value, float):
        return abs(float(printed) - value) <= 5e-6 * abs(value) + 1e-300
    if value is None:
        return printed == "-"
    return printed == str(value)


@pytest.mark.parametrize("design", sorted(DESIGNS))
def test_the_evaluation_plan_makes_the_checks_camgen_check_makes(design, tmp_path):
    from camgen.evaluation import evaluation_plan
    from camgen.pipeline import compute
    from camgen.scene import parse_scene

    data = _scene(DESIGNS[design])
    scene = parse_scene(data, "plate")
    (cam,) = compute(scene, evaluation_plan(scene)).cams
    mine = list(cam.checks)
    text = scene_toml(data) + "[machining]\n" + "".join(f"{k} = {v!r}\n" for k, v in data["machining"].items())
    path = tmp_path / "plate.toml"
    path.write_text(text, encoding="utf-8")
    proc = subprocess.run([sys.executable, "-P", "-m", "camgen", "check", str(path)], capture_output=True, text=True, timeout=300)
    assert proc.returncode in (0, 1), proc.stderr
    table = _check_table(proc.stdout)
    assert [r["check"] for r in table] == [c.name for c in mine]
    for row, check in zip(table, mine):
        assert STATUS[row["result"]] == check.status, (row, check)
        assert _same_value(row["value"], check.value), (row, check.value)
    # the sample has both verdicts, as camgen check's exit status says
    assert proc.returncode == (1 if any(c.failed for c in mine) else 0)
    if design in ("small_base_radius", "low_torque_limit"):
        assert proc.returncode == 1
    assert "acceleration_harmonics" not in cam.figures  # a report-only figure, not made
    assert "dynamics" in cam.figures  # the dynamics figures are (the row's torque, stress, jump speed)
    # the shape's report-only figures (the row's size is camgen.contour.reach's outer radius) are not made
    assert not {"area_mm2", "perimeter_mm", "bounds_mm"} & set(cam.figures)


def _random_spline(rng: np.random.Generator, degree: int, pieces: int):
    from camgen.contour import Spline

    breaks = np.cumsum(np.concatenate([[rng.uniform(-1.0, 1.0)], rng.uniform(0.05, 0.6, pieces)]))
    coeffs = rng.normal(0.0, 3.0, (degree + 1, pieces, 2))
    powers = np.arange(degree, -1, -1)[:, None]
    for i in range(1, pieces):  # continuous (a contour's splines are): each piece starts where the one before ends
        coeffs[-1, i] = np.sum(coeffs[:, i - 1] * (breaks[i] - breaks[i - 1]) ** powers, axis=0)
    return Spline(breaks, coeffs)


def _old_sign_change_roots(a: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """camgen.numerics.roots.sign_change_roots as it was before this work (commit 634d245), verbatim:
    the reference of the grouped and the scalar root finding."""
    n, degree = a.shape[0], a.shape[1] - 1
    if degree <= 0:
        return np.empty((n, 0))
    crit = np.sort(_old_sign_change_roots(a[:, 1:] * np.arange(1, degree + 1), lo, hi), axis=1)
    bounds = np.concatenate([np.full((n, 1), lo), np.where(np.isnan(crit), hi, crit), np.full((n, 1), hi)], axis=1)
    left, right = bounds[:, :-1], bounds[:, 1:]
    f_left, f_right = _old_horner(a, left), _old_horner(a, right)
    out = np.full((n, degree), np.nan)
    row, col = np.nonzero(((f_left < 0) & (f_right > 0)) | ((f_left > 0) & (f_right < 0)))
    if row.size:
        coef = a[row]
        slope = coef[:, 1:] * np.arange(1, degree + 1)
        l, r = left[row, col], right[row, col]
        rising = f_left[row, col] < 0
        x = 0.5 * (l + r)
        for _ in range(64):
            f = _old_horner(coef, x[:, None])[:, 0]
            up = (f < 0) == rising
            l = np.where(up, x, l)
            r = np.where(up, r, x)
            with np.errstate(divide="ignore", invalid="ignore"):
                new = x - f / _old_horner(slope, x[:, None])[:, 0]
            tol = 4.0 * np.finfo(float).eps * np.maximum(1.0, np.abs(x))
            step = np.abs(new - x)
            new = np.where(((new > l) & (new < r)) | (step <= tol), new, 0.5 * (l + r))
            new = np.where(f == 0, x, new)
            moved = np.abs(new - x) > tol
            x = new
            if not np.any(moved):
                break
        out[row, col] = x
    return out


def _old_horner(a: np.ndarray, x: np.ndarray) -> np.ndarray:
    acc = np.broadcast_to(a[:, -1:], x.shape).copy()
    for i in range(a.shape[1] - 2, -1, -1):
        acc *= x
        acc += a[:, i : i + 1]
    return acc


def _per_spline_reference(spline) -> np.ndarray:
    """The extreme points as the code before this work found them: per axis, one root finding per
    spline (the old root finder, :func:`_old_sign_change_roots`; roots_in_pieces' clipping)."""
    q = spline._scaled()
    h = np.diff(spline.breaks)
    pts = [spline.eval_t(spline.breaks)]
    for axis in range(2):
        s = _old_sign_change_roots(q[:, 1:, axis] * np.arange(1, spline.degree + 1), -1e-9, 1.0 + 1e-9)
        piece, col = np.nonzero(np.isfinite(s))
        pts.append(spline.eval_piece(piece, np.clip(s[piece, col], 0.0, 1.0) * h[piece]))
    return np.concatenate(pts)


def test_the_root_finder_is_bit_for_bit_the_old_one_for_few_and_many_roots():
    """Scalar steps for a few polynomials, vectorised ones for many, grouped sets: every root
    bit for bit what the old finder returns for its set alone."""
    from camgen.numerics.roots import SCALAR_ROWS, grouped_sign_change_roots, sign_change_roots

    rng = np.random.default_rng(4)
    for rows in (1, 3, SCALAR_ROWS, SCALAR_ROWS + 1, 200):
        for degree in (1, 2, 4, 5):
            a = rng.normal(size=(rows, degree + 1))
            expected = _old_sign_change_roots(a, 0.0, 1.0)
            assert np.array_equal(sign_change_roots(a, 0.0, 1.0), expected, equal_nan=True)
            group = rng.integers(0, 3, rows)
            got = grouped_sign_change_roots(a, 0.0, 1.0, group, 3)
            for g in range(3):
                assert np.array_equal(got[group == g], _old_sign_change_roots(a[group == g], 0.0, 1.0), equal_nan=True)


def test_grouped_extreme_points_are_bit_for_bit_the_per_spline_ones():
    from camgen.contour.spline import extreme_points_of

    rng = np.random.default_rng(28)
    for _ in range(20):
        splines = [_random_spline(rng, 5, int(rng.integers(1, 40))) for _ in range(int(rng.integers(1, 6)))]
        grouped = extreme_points_of(splines)
        for spline, got in zip(splines, grouped):
            assert np.array_equal(got, _per_spline_reference(spline))


def test_the_pruned_bounding_box_is_bit_for_bit_the_box_of_every_extreme_point():
    """bounding_box_of looks for the extremes of only the pieces whose Bezier hull reaches out of
    the box of the break points: the box is still the min and max of every extreme point."""
    from camgen.contour.spline import bounding_box_of

    rng = np.random.default_rng(29)
    for _ in range(60):
        splines = [_random_spline(rng, int(rng.choice([3, 5])), int(rng.integers(1, 40))) for _ in range(int(rng.integers(1, 5)))]
        every = np.concatenate([_per_spline_reference(s) if s.degree != 3 else s.extreme_points() for s in splines])
        lo, hi = bounding_box_of(splines)
        assert np.array_equal(lo, every.min(axis=0)) and np.array_equal(hi, every.max(axis=0))


def test_the_bounding_box_against_a_dense_sampling():
    from camgen.contour.spline import bounding_box_of, extreme_points_of

    rng = np.random.default_rng(6)
    for degree in (3, 5):
        splines = [_random_spline(rng, degree, int(rng.integers(2, 30))) for _ in range(3)]
        for spline, pts in zip(splines, extreme_points_of(splines)):
            assert all(np.array_equal(a, b) for a, b in zip(bounding_box_of([spline]), (pts.min(axis=0), pts.max(axis=0))))
            t = np.linspace(spline.breaks[0], spline.breaks[-1], 1_000_001)
            dense = np.concatenate([spline.eval_t(t), spline.eval_t(spline.breaks)])  # a side may be at a kink (a break)
            # every sample lies in the exact box; the box's sides are reached within the sampling's
            # error, (dt / 2)^2 / 2 * max |P''| (a side off the breaks is an extreme: P' = 0 there)
            d2 = np.max(np.abs(spline.eval_t(t[::100], 2)))
            slack = 0.5 * (0.5 * (t[1] - t[0])) ** 2 * d2 * 2.0 + 1e-12
            assert np.all(dense.min(axis=0) >= pts.min(axis=0) - 1e-12)
            assert np.all(dense.max(axis=0) <= pts.max(axis=0) + 1e-12)
            assert np.all(dense.min(axis=0) - pts.min(axis=0) <= slack)
            assert np.all(pts.max(axis=0) - dense.max(axis=0) <= slack)


def test_the_template_profile_length_against_its_dense_polyline():
    """The perimeter (Gauss-Legendre, its nodes computed once) against the chords of 10^6 points:
    the polyline is shorter, by at most (dt^2 / 24) max |P''|^2 / |P'| per unit length."""
    from camgen.pipeline import compute
    from camgen.planning import plan_run
    from camgen.scene import parse_scene

    scene = parse_scene(_scene({}), "plate")
    (cam,) = compute(scene, plan_run(scene)).cams  # the full plan: the report's perimeter figure
    polyline = 0.0
    for spline in cam.contour.segments:
        t = np.union1d(np.linspace(spline.breaks[0], spline.breaks[-1], 250_001), spline.breaks)
        polyline += float(np.sum(np.hypot(*np.diff(spline.eval_t(t), axis=0).T)))
    assert 0.0 <= cam.contour.length - polyline <= 1e-9 * cam.contour.length
    assert cam.figures["perimeter_mm"] == cam.contour.length


@pytest.mark.parametrize("depth", [5.0, 20.0, 24.0, 30.0, 45.0])
def test_the_wall_check_sees_a_keyway_through_the_profile(depth):
    """A keyway cut deeper and deeper from a 12 mm bore: the wall check passes while its outer
    corners stay inside the profile and says the keyway breaks through (a wall <= -1 mm) once one
    lies beyond it; inside or beyond from the profile's polar radius at the corner's angle,
    interpolated from 10^6 points of the profile (independent of the check's polygon and rays)."""
    from camgen.checking import wall_check
    from camgen.kinds import get_kind
    from camgen.scene import parse_scene

    scene = parse_scene(_scene({"keyway_depth_mm": depth, "keyway_width_mm": 8.0, "base_radius_mm": 30.0}), "plate")
    (spec,) = scene.cams
    built = get_kind(spec.kind, spec.form).build(spec, frozenset())
    contour = built.contour
    t = np.linspace(0.0, contour.n_segments, 1_000_000, endpoint=False)
    pts = contour.evaluate(t)
    angle, radius = np.arctan2(pts[:, 1], pts[:, 0]), np.hypot(pts[:, 0], pts[:, 1])
    order = np.argsort(angle)
    corners = spec.body.keyway_corners()[1:3]
    reach = np.interp(np.arctan2(corners[:, 1], corners[:, 0]), angle[order], radius[order], period=2 * np.pi)
    beyond = np.hypot(corners[:, 0], corners[:, 1]) - reach
    assert np.all(np.abs(beyond) > 1e-3)  # no case on the edge
    check = wall_check(built)
    if np.any(beyond > 0):
        assert check.value <= -1.0 and check.failed
    else:
        assert check.value > -1.0


def test_a_narrow_keyway_poking_through_between_the_polygon_vertices_fails_the_wall_check():
    """A keyway 0.02 mm wide whose end lies 0.01 mm beyond the profile: narrower than the wall
    polygon's chords there (no vertex inside it), the rays through its outer corners find it (the
    profile's polar radius there from 10^6 points, as above)."""
    from camgen.checking import wall_check
    from camgen.kinds import get_kind
    from camgen.scene import parse_scene

    change = {"keyway_width_mm": 0.02, "keyway_depth_mm": 1.0, "keyway_angle_deg": 270.0, "base_radius_mm": 30.0}
    scene = parse_scene(_scene(change), "plate")
    (spec,) = scene.cams
    contour = get_kind(spec.kind, spec.form).build(spec, frozenset()).contour
    pts = contour.evaluate(np.linspace(0.0, contour.n_segments, 1_000_000, endpoint=False))
    angle = np.arctan2(pts[:, 1], pts[:, 0])
    order = np.argsort(angle)
    reach = float(np.interp(-0.5 * np.pi, angle[order], np.hypot(pts[:, 0], pts[:, 1])[order]))
    for beyond, broken in ((0.01, True), (-0.01, False)):
        depth = math.sqrt((reach + beyond) ** 2 - 0.01**2) - 6.0  # the corner (depth + bore radius, +-0.01) at reach + beyond
        scene = parse_scene(_scene({**change, "keyway_depth_mm": depth}), "plate")
        (spec,) = scene.cams
        check = wall_check(get_kind(spec.kind, spec.form).build(spec, frozenset()))
        assert (check.value <= -1.0) == broken, (beyond, check.value)


def test_the_chord_parameters_of_several_splines_at_once_are_each_splines_own():
    """flatten_params_of bounds |P''| on the pieces of all the splines of a degree in one pass:
    the parameters are bit for bit each spline's alone, and every chord is within the tolerance
    of the curve (measured at 65 points per chord)."""
    from camgen.contour import Contour
    from camgen.contour.spline import flatten_params_of
    from camgen.kinds import get_kind
    from camgen.scene import parse_scene
    from helpers import chord_deviation

    rng = np.random.default_rng(27)
    splines = [_random_spline(rng, int(rng.choice([3, 5])), int(rng.integers(1, 30))) for _ in range(6)]
    together = flatten_params_of(splines, 1e-3)
    for spline, params in zip(splines, together):
        assert np.array_equal(params, flatten_params_of([spline], 1e-3)[0])
    (spec,) = parse_scene(_scene({}), "plate").cams
    contour = get_kind(spec.kind, spec.form).build(spec, frozenset()).contour
    assert isinstance(contour, Contour)
    assert chord_deviation(contour, 1e-4) <= 1e-4  # the wall check's polygon


def _sampled_farthest(points_of, knots: np.ndarray, samples: int = 400_001) -> float:
    """The largest |P| of a curve on [knots[0], knots[-1]]: a dense sampling with the knots (where
    a piecewise curve may have a corner), then a bounded scalar search (scipy's Brent) about the
    best sample: an independent computation."""
    from scipy.optimize import minimize_scalar

    t = np.union1d(np.linspace(knots[0], knots[-1], samples), knots)
    samples = t.size
    r = np.hypot(*points_of(t).T)
    k = int(np.argmax(r))
    a, b = t[max(k - 1, 0)], t[min(k + 1, samples - 1)]
    found = minimize_scalar(lambda x: -float(np.hypot(*points_of(np.array([x]))[0])), bounds=(a, b), method="bounded",
                            options={"xatol": 1e-13})
    return max(float(r.max()), -float(found.fun))


@pytest.mark.parametrize("degree", [3, 5])
def test_the_farthest_distance_of_splines_against_a_dense_sampling(degree):
    from camgen.contour.reach import splines_farthest_distance

    rng = np.random.default_rng(28 + degree)
    for _ in range(6):
        spline = _random_spline(rng, degree, int(rng.integers(1, 9)))
        exact = splines_farthest_distance([spline])
        sampled = _sampled_farthest(spline.eval_t, spline.breaks)
        assert sampled <= exact * (1.0 + 1e-12)  # never a point beyond it
        assert exact - sampled <= 1e-9 * exact  # and it is reached
    several = [_random_spline(rng, d, 4) for d in (3, 5, 5)]  # pieces of both degrees at once
    assert splines_farthest_distance(several) == max(splines_farthest_distance([s]) for s in several)


def test_the_farthest_distance_of_arcs_is_the_closed_form():
    from camgen.contour import Arc
    from camgen.contour.reach import arc_farthest_distance

    # the direction of the centre (atan2(3, 4)) inside the sweep: |centre| + radius = 5 + 2
    assert arc_farthest_distance(Arc((4.0, 3.0), 2.0, 0.0, 1.5)) == pytest.approx(7.0, rel=1e-15)
    assert arc_farthest_distance(Arc((4.0, 3.0), 2.0, 2.0, -1.5)) == pytest.approx(7.0, rel=1e-15)  # clockwise through it
    # outside the sweep (from pi/2 to pi): the farther end, at angle pi/2: hypot(4, 5)
    assert arc_farthest_distance(Arc((4.0, 3.0), 2.0, math.pi / 2, math.pi / 2)) == pytest.approx(math.hypot(4.0, 5.0), rel=1e-15)
    assert arc_farthest_distance(Arc((0.0, 0.0), 3.0, 0.3, 0.2)) == pytest.approx(3.0, rel=1e-15)  # about the axis


@pytest.mark.parametrize("template", ["plate_cam", "default"])
def test_the_outer_radius_against_a_dense_sampling_and_the_flattened_outline(template):
    from camgen.contour.reach import farthest_distance
    from camgen.evaluation import evaluation_plan
    from camgen.pipeline import compute
    from camgen.scene import parse_scene, template_path
    from camgen.study.design import OUTER_RADIUS_TOL, main_figures

    scene = parse_scene(tomllib.loads(template_path(template).read_text(encoding="utf-8")), template)
    for cam in compute(scene, evaluation_plan(scene)).cams:
        if cam.contour is None:
            continue
        contour = cam.contour
        exact = main_figures(cam)["outer_radius_mm"]
        assert exact == farthest_distance(contour)
        sampled = max(_sampled_farthest(lambda u, seg=seg: seg.point(u), np.array([0.0, 1.0]), 100_001) for seg in contour.segments)
        assert sampled <= exact * (1.0 + 1e-12) and exact - sampled <= 1e-9 * exact, (cam.name, exact, sampled)
        flat = contour.flatten(OUTER_RADIUS_TOL)  # the old figure: at most the chord tolerance too small
        old = float(np.hypot(*flat.T).max())
        assert old <= exact * (1.0 + 1e-12) and exact - old <= OUTER_RADIUS_TOL



_HEAP_SCRIPT = """
import json, sys, tomllib
from camgen.evaluation import evaluation_plan
from camgen.pipeline import compute
from camgen.scene import parse_scene, template_path
from camgen.study.heap import keep_heap

def results():
    out = []
    for radius in (20.0, 40.0, 55.0):
        data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
        data["cams"]["plate"]["base_radius_mm"] = radius
        scene = parse_scene(data, "plate")
        (cam,) = compute(scene, evaluation_plan(scene)).cams
        out.append([repr(c) for c in cam.checks] + [repr(dict(cam.figures))])
    return out

before = results()
kept = keep_heap()
print(json.dumps({"kept": kept, "same": results() == before, "checks": len(before[0])}))
"""


def test_keeping_the_heap_changes_no_value():
    """camgen.study.heap.keep_heap (glibc's mmap and trim thresholds, set once per study process)
    changes where arrays live, never a value: in a fresh process the checks (value, limit, where,
    note) and figures of three designs, one failing, are the same before and after it."""
    proc = subprocess.run([sys.executable, "-P", "-c", _HEAP_SCRIPT], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["same"] and out["checks"] > 5
    assert out["kept"] == sys.platform.startswith("linux")  # this machine's C library is glibc


@pytest.mark.parametrize("degree", [3, 5, 7])
def test_the_outer_radius_s_scaled_pieces_are_scaled_ascending_s(degree):
    """reach._scaled_pieces (one block, no stack) against camgen.numerics.polynomial.scaled_ascending,
    bit for bit, on random plane pieces of several lengths."""
    from camgen.contour.reach import _scaled_pieces
    from camgen.numerics.polynomial import scaled_ascending

    rng = np.random.default_rng(degree)
    coeffs = rng.normal(size=(degree + 1, 37, 2)) * 40.0
    h = rng.uniform(1e-3, 0.3, 37)
    got, want = _scaled_pieces(coeffs, h), scaled_ascending(coeffs, h)
    assert got.shape == want.shape == (37, degree + 1, 2)
    assert np.array_equal(got, want) and np.array_equal(np.signbit(got), np.signbit(want))
