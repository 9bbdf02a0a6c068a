"""The synthesis's reuse across designs (issue 28 item 6) and its cheaper paths, each against a
computation that shares no state with it.

* designs evaluated in a row in one process (the base radius, the lift, a law with other breaks,
  a failing design, back to the first) give rows bit for bit those of each design evaluated alone
  in a fresh process (no grid, rotation or law value kept from another design);
* one motion program reused by builds of other base radii (what a sweep that keeps the law gets):
  every check bit for bit that of a freshly read scene (its own program); a program's kept grid
  values are read-only and bit for bit a fresh program's, for every grid asked in turn;
* the sorted check grid (angles, the law's values) bit for bit its definition (``np.insert`` of
  the added angles into the uniform grid, written here); the rotation into the cam frame of a
  ``cw`` cam the complex conjugate of the ``ccw`` one's, whichever is asked first;
* :func:`camgen.synthesis.followers.contact_points` bit for bit the contact points of
  :func:`~camgen.synthesis.followers.kinematics`, for every follower;
* a program's values at angles asked again bit for bit a fresh program's, the caller's own arrays;
  a pickled program carries none of its kept values (its size that of an unused one).

No clock: the time is measured in benchmarks/bench_evaluate.py.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from camgen.scene import template_path
from camgen.study.design import StudyScene, evaluate_point, point_scene_data
from camgen.study.keys import resolve_key
from camgen.synthesis.followers import CheckGrid, FollowerSpec, _grid_layout, contact_points, kinematics, profile_curvature
from camgen.synthesis.laws import MotionProgram, Segment

D = math.radians
TWO_PI = 2.0 * math.pi
PLATE = template_path("plate_cam")
KEYS = ("cams.plate.base_radius_mm", "cams.plate.segments[0].lift_mm", "cams.plate.segments[2].lift_mm",
        "cams.plate.segments[0].span_deg", "cams.plate.segments[1].span_deg", "cams.plate.segments[0].law")
#: A design and the changes of the sequence: the base radius (the same law), the lift (another
#: law on the same grid), the spans and a law (other breaks: another check grid), a failing
#: pressure angle (the sizing advice's trial envelopes).
POINTS = {
    "first": [40.0, 20.0, -20.0, 120.0, 60.0, "cycloidal"],
    "base_radius": [46.0, 20.0, -20.0, 120.0, 60.0, "cycloidal"],
    "lift": [46.0, 15.0, -15.0, 120.0, 60.0, "cycloidal"],
    "breaks": [46.0, 15.0, -15.0, 100.0, 80.0, "poly345"],
    "failing": [22.0, 20.0, -20.0, 120.0, 60.0, "cycloidal"],
}
_CHILD = """
import json, sys
from camgen.study.design import StudyScene, evaluate_point
from camgen.study.keys import resolve_key
study = StudyScene.load(sys.argv[1])
names, values = json.loads(sys.argv[2])
row = evaluate_point(study, [resolve_key(study.data, n) for n in names], values)
row.pop("eval_ms")
print(json.dumps(row))
"""


def _row(study: StudyScene, values: list) -> dict:
    row = evaluate_point(study, [resolve_key(study.data, n) for n in KEYS], values)
    row.pop("eval_ms")  # the only column that differs between runs
    return row


def test_designs_in_a_row_equal_each_design_alone_in_a_fresh_process():
    alone = {name: subprocess.Popen([sys.executable, "-P", "-c", _CHILD, str(PLATE), json.dumps([KEYS, values])],
                                    stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for name, values in POINTS.items()}
    study = StudyScene.load(str(PLATE))
    order = ["first", "base_radius", "lift", "breaks", "first", "failing", "base_radius"]
    in_a_row = [(name, _row(study, POINTS[name])) for name in order]
    fresh = {}
    for name, proc in alone.items():
        out, err = proc.communicate(timeout=300)
        assert proc.returncode == 0, err
        fresh[name] = json.loads(out)  # floats by their shortest repr: read back exactly
    assert {fresh[name]["status"] for name in POINTS} == {"pass", "fail"}  # both verdicts in the sample
    assert fresh["failing"]["check.plate.pressure_angle.status"] == "fail"
    for name, row in in_a_row:
        assert json.loads(json.dumps(row)) == fresh[name], name


def test_a_program_reused_by_other_base_radii_gives_a_fresh_scene_s_checks():
    from camgen.evaluation import evaluation_plan
    from camgen.pipeline import compute
    from camgen.scene import parse_scene

    study = StudyScene.load(str(PLATE))
    path = resolve_key(study.data, "base_radius_mm").path
    shared = parse_scene(point_scene_data(study.data, {}), "plate")
    spec = shared.cams[0]
    for radius in (40.0, 46.0, 23.0, 40.0):  # 23 mm fails the pressure angle
        params = replace(spec.params, follower=replace(spec.params.follower, base_radius=radius))
        scene = replace(shared, cams=(replace(spec, params=params),))
        (mine,) = compute(scene, evaluation_plan(scene)).cams
        from camgen.motions.motion_law import _cached_law

        _cached_law.cache_clear()  # a fresh program: the scene reader keeps its last ones (camgen.motions.motion_law)
        own = parse_scene(point_scene_data(study.data, {path: radius}), "plate")
        assert own.cams[0].params.law is not spec.params.law
        (theirs,) = compute(own, evaluation_plan(own)).cams
        assert [(c.name, c.status, repr(c.value), c.where_deg) for c in mine.checks] == \
               [(c.name, c.status, repr(c.value), c.where_deg) for c in theirs.checks], radius
        assert repr(mine.figures) == repr(theirs.figures)


def _program(unit: str = "mm", lift: float = 20.0) -> MotionProgram:
    return MotionProgram([Segment("cycloidal", D(120), lift), Segment("dwell", D(40)), Segment("poly345", D(130), -lift),
                          Segment("dwell", D(70))], unit=unit)


def test_a_program_s_kept_grid_values_are_a_fresh_program_s_and_read_only():
    program = _program()
    asked = [(7200, 0.05, 1), (360, 1.0, 1), (7200, 0.05, 1), (100, 3.6, 1), (7200, 0.05, 2), (361, 1.0, 1), (7200, 0.05, 1)]
    for n, step, every in asked:  # (every other added angle: the same uniform grid, other added angles)
        added = _grid_layout(program, D(step))[1][::every]
        got = program.on_uniform_grid(n, added)
        again = program.on_uniform_grid(n, added)
        want = _program().on_uniform_grid(n, added)  # a program of its own: nothing kept
        for a, b, c in zip(got, again, want):
            assert np.array_equal(a, c) and np.array_equal(b, c), n
            assert not a.flags.writeable
            with pytest.raises(ValueError):
                a[0] = 1.0


def test_sorted_check_grid_is_the_insertion_of_the_added_angles():
    """theta and the law's values on it against np.insert of the added angles (and of the values
    there) into the uniform grid; random breaks on and off the grid, none."""
    rng = np.random.default_rng(5)
    for trial in range(20):
        spans = rng.uniform(0.3, 1.0, int(rng.integers(2, 6)))
        spans *= 360.0 / spans.sum()
        lifts = rng.uniform(-5.0, 5.0, spans.size)
        lifts[-1] = -lifts[:-1].sum()
        law = MotionProgram([Segment(str(rng.choice(["cycloidal", "poly345", "harmonic"])), D(a), h) for a, h in zip(spans, lifts)])
        step = D(float(rng.choice([0.05, 0.3, 1.0])))
        n, added = _grid_layout(law, step)
        grid = CheckGrid(law, n, added)
        uniform = np.arange(n) * (TWO_PI / n)
        at = np.searchsorted(uniform, added)
        assert np.array_equal(grid.theta, np.insert(uniform, at, added)), trial
        direct = law(np.concatenate([uniform, added]))  # the law at the grid's own order, evaluated here
        for got, raw, value in zip(grid.values, grid.raw, direct):
            assert np.array_equal(got, np.insert(raw[:n], at, raw[n:])), trial
            assert np.allclose(raw, value, rtol=1e-12, atol=1e-12 * np.abs(value).max())
        mask = rng.random(n + added.size) < 0.3
        assert np.array_equal(grid.sorted(mask), np.insert(mask[:n], at, mask[n:]))
    empty = CheckGrid(law, 720, np.zeros(0))  # no angle added: the values are the raw ones, the caller's own arrays
    assert np.array_equal(empty.theta, np.arange(720) * (TWO_PI / 720))
    for got, raw in zip(empty.values, empty.raw):
        assert np.array_equal(got, raw) and got.flags.writeable


@pytest.mark.parametrize("first", [1.0, -1.0])
def test_cw_rotation_into_the_cam_frame_is_the_conjugate_of_the_ccw_one(first):
    law = _program()
    n, added = _grid_layout(law, D(0.05))
    grid = CheckGrid(law, n, added)
    a = grid.to_cam(first)
    b = CheckGrid(law, n, added).to_cam(-first)
    assert np.array_equal(b, np.conj(a)) and not np.array_equal(a, b)
    assert np.max(np.abs(a - (np.cos(grid.theta) - 1j * first * np.sin(grid.theta)))) <= 2e-15
    assert not a.flags.writeable


FOLLOWERS = {
    "roller": (dict(kind="roller", base_radius=40.0, roller_radius=10.0, offset=12.0), "mm"),
    "knife": (dict(kind="knife", base_radius=40.0, offset=-6.0, rotation="cw"), "mm"),
    "flat": (dict(kind="flat", base_radius=45.0, offset=3.0), "mm"),
    "osc_roller": (dict(kind="roller", base_radius=40.0, motion="oscillating", roller_radius=8.0, pivot=(110.0, 40.0), arm_length=95.0), "rad"),
    "osc_flat": (dict(kind="flat", base_radius=60.0, motion="oscillating", pivot=(130.0, 50.0), face_offset=20.0, lift_turn="cw"), "rad"),
}


@pytest.mark.parametrize("name", FOLLOWERS)
def test_contact_points_are_those_of_the_kinematics(name):
    changes, unit = FOLLOWERS[name]
    follower = FollowerSpec(**changes)
    law = _program(unit, 20.0 if unit == "mm" else 0.2)
    theta = np.concatenate([[0.0], np.random.default_rng(3).uniform(0.0, TWO_PI, 40), law.breaks])
    want = kinematics(follower, law, theta).contact_point
    got = contact_points(follower, law, theta)
    assert got.shape == (theta.size, 2) and np.array_equal(got, want)
    assert np.array_equal(contact_points(follower, law, 0.0), want[:1])


def test_a_program_s_kept_values_at_angles_are_a_fresh_program_s_and_the_caller_s_own():
    """Calls asked again (the motion samples, one angle, unsorted and negative angles, a 2-D
    array) among others: each answer bit for bit a fresh program's, and a caller that writes
    into its arrays changes no later answer."""
    program = _program()
    rng = np.random.default_rng(11)
    asks = [2.0 * math.pi * np.arange(3600) / 3600, np.zeros(1), rng.uniform(-TWO_PI, TWO_PI, 7),
            rng.uniform(0.0, 3.0 * TWO_PI, (3, 4)), np.linspace(0.0, 1.0, 5000)]
    for turn in range(4):
        for k in rng.permutation(len(asks) + 3).tolist():
            theta = asks[k] if k < len(asks) else rng.uniform(0.0, TWO_PI, 50)  # (angles asked once)
            got = program(theta)
            want = _program()(theta)
            for a, b in zip(got, want):
                assert a.shape == theta.shape and np.array_equal(a, b), (turn, k)
                a[...] = np.nan  # the caller's own array


def test_a_pickled_program_carries_no_kept_values_and_answers_the_same():
    import pickle

    program, fresh = _program(), _program()
    fresh(np.zeros(1))  # (its evaluation plan made, as the used program's)
    fresh_size = len(pickle.dumps(fresh))
    theta = 2.0 * math.pi * np.arange(3600) / 3600
    for _ in range(3):
        program(theta)
    program.on_uniform_grid(7200, _grid_layout(program, D(0.05))[1])
    text = pickle.dumps(program)
    assert len(text) <= fresh_size + 64  # (a 3600-angle call alone keeps ~115 kB)
    back = pickle.loads(text)
    for a, b in zip(back(theta), _program()(theta)):
        assert np.array_equal(a, b)


@pytest.mark.parametrize("name", FOLLOWERS)
def test_profile_curvature_is_that_of_the_kinematics(name):
    """At random angles, the breaks and 1e-9 rad either side of them (where the curvature jumps)."""
    changes, unit = FOLLOWERS[name]
    follower = FollowerSpec(**changes)
    law = _program(unit, 20.0 if unit == "mm" else 0.2)
    theta = np.concatenate([np.random.default_rng(4).uniform(0.0, TWO_PI, 30), law.breaks, law.breaks - 1e-9, law.breaks + 1e-9])
    want = kinematics(follower, law, theta).profile_curvature
    got = profile_curvature(follower, law, theta)
    assert got.shape == theta.shape and np.array_equal(got, want)


@pytest.mark.parametrize("name", FOLLOWERS)
def test_profile_curvatures_in_one_pass_are_each_arrays_own(name):
    """The continuity check's one pass over both sides of the joints (profile_curvatures): each
    array's curvatures are its own kinematics', for arrays of 1, 2 and many angles in one call."""
    from camgen.synthesis.followers import profile_curvatures

    changes, unit = FOLLOWERS[name]
    follower = FollowerSpec(**changes)
    law = _program(unit, 20.0 if unit == "mm" else 0.2)
    thetas = [law.breaks + 1e-9, law.breaks - 1e-9, np.array([1.0]), np.random.default_rng(5).uniform(0.0, TWO_PI, 40),
              law.breaks[:2]]
    got = profile_curvatures(follower, law, *thetas)
    assert len(got) == len(thetas)
    for theta, value in zip(thetas, got):
        assert value.shape == theta.shape and np.array_equal(value, kinematics(follower, law, theta).profile_curvature)


class _Plain:
    """A law without ``on_uniform_grid`` (its four values separate arrays), or whose values are the
    rows of one block in another order (``rows``): the check grid's values must still be the law's."""

    def __init__(self, law, rows=(0, 1, 2, 3)):
        self.law, self.rows = law, rows
        self.breaks, self.break_continuity = law.breaks, law.break_continuity

    def on_uniform_grid(self, n, extra):
        block = np.stack(self.law(np.concatenate([np.arange(n) * (TWO_PI / n), extra])))[list(self.rows)]
        return tuple(block[k] for k in np.argsort(self.rows))  # the law's (s, ds, d2s, d3s), rows of `block` in another order


@pytest.mark.parametrize("rows", [(0, 1, 2, 3), (1, 0, 2, 3), (3, 2, 1, 0)])
def test_check_grid_values_whatever_block_the_law_values_share(rows):
    """CheckGrid.values (sorted in one take when the raw values are the rows of one block) against
    np.insert of the law's own values (a fresh program evaluated here), for raw values that are a
    block's rows in order, in another order, and (a motion program) its kept read-only ones (then the
    values are the program's kept block in the grid's order: read-only)."""
    law = _program()
    n, added = _grid_layout(law, D(0.3))
    uniform = np.arange(n) * (TWO_PI / n)
    at = np.searchsorted(uniform, added)
    direct = law(np.concatenate([uniform, added]))
    fresh = _program()  # the program's kept grid values: those of a fresh program's grid
    for source, values in ((_Plain(law, rows), direct), (law, fresh.on_uniform_grid(n, added))):
        grid = CheckGrid(source, n, added)
        for got, value in zip(grid.values, values):
            assert np.array_equal(got, np.insert(value[:n], at, value[n:]))
            assert got.flags.writeable == (source is not law)  # a motion program's: its kept, read-only block
        assert all(not np.shares_memory(got, raw) for got in grid.values for raw in grid.raw)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_dwell_s_values_are_its_level_and_the_matrix_product_s(sign):
    """A dwell's values (no basis, no product: the plan matrix's column) on every path that
    evaluates a program (a direct call, a uniform grid with and without added angles): ``s`` the
    dwell's level (the lifts before it, closed form) and the three derivatives +0.0, bit for bit
    what the product of the plan matrix with the row of ones gives (the code before, written
    here), also for a matrix with negative zeros."""
    lifts = (sign * 20.0, sign * 7.5, -sign * 27.5)
    program = MotionProgram([Segment("cycloidal", D(100), lifts[0]), Segment("dwell", D(40)), Segment("poly345", D(60), lifts[1]),
                             Segment("dwell", D(50)), Segment("harmonic", D(70), lifts[2]), Segment("dwell", D(40))])
    dwells = [(D(100), D(140), lifts[0]), (D(200), D(250), lifts[0] + lifts[1]), (D(320), TWO_PI, 0.0)]
    n, added = _grid_layout(program, D(0.05))
    uniform = np.arange(n) * (TWO_PI / n)
    rng = np.random.default_rng(3)
    odd = np.sort(rng.uniform(0.0, TWO_PI, 500))
    for theta, values in ((odd, program(odd)), (uniform, program.on_uniform_grid(n)),
                          (np.concatenate([uniform, added]), program.on_uniform_grid(n, added)),
                          (np.arange(360) * (TWO_PI / 360), program.on_uniform_grid(360))):
        for lo, hi, level in dwells:
            inside = (theta > lo + 1e-9) & (theta < hi - 1e-9)
            assert inside.sum() > 2
            assert np.all(values[0][inside] == values[0][inside][0])
            assert abs(values[0][inside][0] - level) <= 1e-12 * 30.0
            for d in values[1:]:
                assert np.all(d[inside] == 0.0) and not np.signbit(d[inside]).any()
    for column in ([3.5, -0.0, 0.0, -0.0], [-0.0, -0.0, -0.0, -0.0], [-2.0, 0.0, 0.0, 0.0]):
        matrix = np.array(column)[:, None]
        got = np.empty((4, 7))
        MotionProgram._fill((0.0, 1.0, 0.0, True, 0.0, (), matrix, None), np.linspace(0.1, 0.9, 7), got, None)
        want = np.matmul(matrix, np.ones((1, 7)))
        assert np.array_equal(got, want) and np.array_equal(np.signbit(got), np.signbit(want))


def test_kept_rotations_are_the_direct_ones_for_each_direction():
    """The rotation into the cam frame kept per angles (the coarse grid, the spline's knots and
    probes) against cos - i sigma sin of the same angles computed here, for a ccw and a cw cam asked
    in turn with the same angles (neither answer the other's), read-only."""
    from camgen.synthesis.followers import _kept_rotation_to_cam

    rng = np.random.default_rng(11)
    for size in (1, 7, 285, 360):
        theta = rng.uniform(-TWO_PI, TWO_PI, size)
        for sigma in (1.0, -1.0, 1.0):
            got = _kept_rotation_to_cam(sigma, theta.tobytes())
            want = np.empty(size, dtype=complex)
            want.real, want.imag = np.cos(theta), -sigma * np.sin(theta)
            assert np.array_equal(got, want) and not got.flags.writeable


@pytest.mark.parametrize("lift", [20.0, -12.5])
def test_a_program_s_kept_peaks_are_a_fresh_program_s_and_the_sampled_ones(lift):
    """peak_values asked again (kept on the program) against a fresh program's and against the
    largest |s'|, |s''|, |s'''| of the law sampled every 0.01 deg (within the sampling's reach);
    two programs with other lifts asked in turn keep their own; a pickled one answers the same."""
    import pickle

    program, other = _program(lift=lift), _program(lift=2.0 * lift)
    for _ in range(3):
        got, got_other = program.peak_values(), other.peak_values()
        assert got == _program(lift=lift).peak_values() and got_other == _program(lift=2.0 * lift).peak_values()
        # twice the lift, twice every peak (a factor 2 is exact), at the same angles
        assert (got_other.velocity, got_other.acceleration, got_other.jerk) == (2.0 * got.velocity, 2.0 * got.acceleration, 2.0 * got.jerk)
        assert (got_other.velocity_at, got_other.acceleration_at, got_other.jerk_at) == (got.velocity_at, got.acceleration_at, got.jerk_at)
    theta = np.arange(36000) * (TWO_PI / 36000)
    _, ds, d2s, d3s = _program(lift=lift)(theta)
    for sampled, peak in zip((ds, d2s, d3s), (got.velocity, got.acceleration, got.jerk)):
        assert np.abs(sampled).max() <= peak * (1 + 1e-12) and np.abs(sampled).max() >= peak * (1 - 1e-4)
    assert pickle.loads(pickle.dumps(program)).peak_values() == got
    assert "_peaks" not in pickle.loads(pickle.dumps(program)).__dict__
