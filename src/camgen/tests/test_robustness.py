"""Stress and fuzz tests: extreme valid geometry stays exact; arbitrary user text never escapes
as anything but a CamgenError."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import camgen
from camgen.errors import CamgenError, ParameterError
from camgen.synthesis.expression import parse_expression
from camgen.tests.helpers import chord_deviation


@pytest.mark.parametrize(
    "a, b, c",
    [
        (220.0, 1e-6, 25.0),  # b -> 0: nearly an eccentric circle, dwell arcs of 5e-9 rad
        (220.0, 440.0 * (1 - 1e-9), 500.0),  # b -> 2a: flank arcs of ~4e-5 rad
        (220.0, 245.0 * (1 - 1e-9), 25.0),  # b -> a + c: concave-free but radius a + c - b -> 2.5e-7
        (1e-3, 1e-3, 1e-3),  # a 1 um cam
        (1e5, 1e5, 10.0),  # a 200 m cam with a 10 mm base circle
    ],
)
def test_extreme_three_arc_cams_stay_exact(a, b, c):
    cam = camgen.three_arc_cam(a, b, c)
    size = 2 * a + c
    psi = np.linspace(0, math.pi, 720, endpoint=False)
    breadth = cam.support(psi) + cam.support(psi + math.pi)
    assert np.max(np.abs(breadth - (2 * a + 2 * c - b))) <= 1e-12 * size + 1e-15
    assert all(j.gap_mm <= 1e-12 * size + 1e-15 for j in cam.joints())
    tol = 1e-6 * size
    assert chord_deviation(cam, tol) <= tol * (1 + 1e-9)
    assert cam.area > 0 and np.isfinite(cam.length)


_TERMS = st.sampled_from(["x", "pi", "1", "2.5", "sin(x)", "x**2", "1e308", "0x" + "f" * 300, "1" + "0" * 400])
#: Texts built to reach the parser's limits: long sums and products (recursion, O(n^3)
#: derivatives), deep parentheses and calls, huge literals (beyond the float range).
_LONG_TEXTS = st.one_of(
    st.builds(lambda terms, op: op.join(terms), st.lists(_TERMS, min_size=50, max_size=700), st.sampled_from(["+", "-", "*", "/", "**"])),
    st.builds(lambda n, op: op.join(["x"] * n), st.integers(900, 1000), st.sampled_from(["+", "-", "*", "/"])),  # ~1000 levels
    st.builds(lambda n, inner: "(" * n + inner + ")" * n, st.integers(1, 400), _TERMS),
    st.builds(lambda n, f, inner: f"{f}(" * n + inner + ")" * n, st.integers(1, 300), st.sampled_from(["sin", "exp", "log", "abs"]), _TERMS),
    st.builds(lambda n, inner: "-" * n + inner, st.integers(1, 1999), st.sampled_from(["x", "1", "sin(x)"])),
    st.builds(lambda digits, prefix: prefix + digits + "*x", st.text("0123456789abcdef", min_size=300, max_size=1990), st.sampled_from(["0x", "1"])),
)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.text(max_size=60), _LONG_TEXTS))
def test_arbitrary_expression_text_is_a_parameter_error_or_a_function(text):
    """Any text is either refused naming the key (a ParameterError of 'expression', which the
    cam kinds rename cams.<name>.expression) or a function whose value and two derivatives are
    arrays of the input's shape."""
    try:
        expr = parse_expression(text)
    except ParameterError as exc:
        assert exc.name == "expression" and str(exc).startswith("parameter 'expression' = ")
        return
    x = np.linspace(0.1, 1.0, 5)
    with np.errstate(all="ignore"):  # parsed text evaluates without touching Python
        assert all(np.shape(g(x)) == x.shape for g in (expr.f, expr.df, expr.d2f))


@pytest.mark.parametrize("build", [
    lambda n: "+".join(["x"] * n),  # n terms: n levels (n - 1 sums and the leaf)
    lambda n: "x+(" * (n - 1) + "x" + ")" * (n - 1),  # nested to the right
    lambda n: "sin(" + "+".join(["x"] * (n - 1)) + ")",  # a call around n - 1 levels
    lambda n: "-" * (n - 1) + "x",  # n - 1 signs
])
def test_expressions_nest_at_most_max_depth_levels(build):
    """The documented limit, counted by construction: MAX_DEPTH levels parse, one more is refused
    naming the key (evaluating and differentiating recurse once per level)."""
    from camgen.synthesis.expression import MAX_DEPTH

    x = np.linspace(0.1, 1.0, 5)
    assert np.shape(parse_expression(build(MAX_DEPTH)).d2f(x)) == x.shape
    with pytest.raises(ParameterError, match=f"nested {MAX_DEPTH + 1} levels deep") as refused:
        parse_expression(build(MAX_DEPTH + 1))
    assert refused.value.name == "expression"


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.recursive(
    st.one_of(st.sampled_from(["x", "pi", "1", "2.5", "0"])),
    lambda inner: st.one_of(
        st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "**"]), inner).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        st.tuples(st.sampled_from(["sin", "cos", "exp", "sqrt", "abs", "log", "tan"]), inner).map(lambda t: f"{t[0]}({t[1]})"),
    ),
    max_leaves=8,
))
def test_whitelisted_expressions_have_consistent_derivatives(text):
    """The symbolic derivative against the complex-step derivative Im f(x + i h) / h, exact to
    rounding for analytic expressions (abs is not analytic: those are skipped)."""
    if "abs" in text:
        return
    expr = parse_expression(text)
    x = np.linspace(0.7, 1.3, 7)
    h = 1e-30
    with np.errstate(all="ignore"):
        reference = expr.f(x + 1j * h).imag / h
        d1 = expr.df(x)
        f0 = expr.f(x)
    ok = np.isfinite(f0) & np.isfinite(reference) & np.isfinite(d1) & (np.abs(d1) < 1e12)
    assert np.all(np.abs(reference[ok] - d1[ok]) <= 1e-9 * (1 + np.abs(d1[ok])))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.dictionaries(st.sampled_from(["a_mm", "b_mm", "c_mm", "kind", "thickness_mm", "bore_diameter_mm", "follower", "rpm"]),
                       st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-5, 500), st.text(max_size=8), st.booleans()),
                       max_size=8))
def test_fuzzed_cam_tables_end_in_a_camgen_error_or_a_cam(table):
    """A fuzzed cam table is refused naming the cam or its key, or builds a cam whose profile is
    a closed curve of finite positive area."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import parse_scene

    table = {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0, **table}  # fuzzed keys over a valid cam
    try:
        scene = parse_scene({"cams": {"x": table}}, "fuzz")
        result = compute(scene, Plan((), frozenset()))
    except CamgenError as exc:
        assert "cams.x" in str(exc), str(exc)
        return
    (cam,) = result.cams
    assert cam.name == "x" and math.isfinite(cam.contour.area) and cam.contour.area > 0


# --------------------------------------------------------------------------------------------
# Nothing but camgen's own lines on stderr; never NaN in a file
# --------------------------------------------------------------------------------------------
_STDERR_SCENES = {
    # every kind and the leg, succeeding (exit 0 with --quiet: stderr empty)
    "ok": """
[output]
formats = ["dxf", "points", "lift", "ngc", "follower"]
[cams.s]
kind = "three_arc"
a_mm = 220.0
b_mm = 160.0
c_mm = 25.0
rpm = 30.0
[cams.h]
kind = "three_arc"
a_mm = 220.0
b_mm = 220.0
c_mm = 10.0
rpm = 30.0
[cams.t]
kind = "trajectory"
expression = "202.4396*sin(pi*x/1000)"
period_mm = 2000.0
rpm = 30.0
[cams.m]
kind = "motion_law"
base_radius_mm = 40.0
rpm = 300.0
[[cams.m.segments]]
law = "cycloidal"
span_deg = 180.0
lift_mm = 20.0
[[cams.m.segments]]
law = "poly345"
span_deg = 180.0
lift_mm = -20.0
[mechanisms.horse_leg]
stride_cam = "s"
height_cam = "h"
inclinations_deg = [12.5, 18.5]
""",
    # design checks that fail: an undercut trajectory cam, a disk cam too small, the leg near its toggle (exit 1)
    "checks": """
[output]
formats = ["dxf", "ngc"]
[cams.t]
kind = "trajectory"
expression = "1e-6*sin(2*pi*10000*x/2000)"
period_mm = 2000.0
[cams.m]
kind = "motion_law"
base_radius_mm = 5.0
follower = "flat"
[[cams.m.segments]]
law = "simple_harmonic"
span_deg = 90.0
lift_mm = 20.0
[[cams.m.segments]]
law = "cycloidal"
span_deg = 270.0
lift_mm = -20.0
[cams.s]
kind = "three_arc"
a_mm = 220.0
b_mm = 160.0
c_mm = 25.0
[cams.h]
kind = "three_arc"
a_mm = 220.0
b_mm = 220.0
c_mm = 10.0
[mechanisms.horse_leg]
stride_cam = "s"
height_cam = "h"
inclinations_deg = [20.1]
ground_y_mm = -2000.0
""",
    # bad input (exit 2): the leg beyond its assembly
    "bad": """
[cams.s]
kind = "three_arc"
a_mm = 220.0
b_mm = 160.0
c_mm = 25.0
[cams.h]
kind = "three_arc"
a_mm = 220.0
b_mm = 220.0
c_mm = 10.0
[mechanisms.horse_leg]
stride_cam = "s"
height_cam = "h"
inclinations_deg = [30.0]
""",
}


@pytest.mark.parametrize("name, status", [("ok", 0), ("checks", 1), ("bad", 2)])
def test_runs_print_nothing_but_camgen_lines_on_stderr(name, status, tmp_path):
    """Every warning shown (-W always): a successful run prints nothing on stderr with --quiet,
    a failed check only its 'camgen: check failed' lines, bad input its one error line."""
    import subprocess
    import sys

    path = tmp_path / f"{name}.toml"
    path.write_text(_STDERR_SCENES[name])
    proc = subprocess.run([sys.executable, "-W", "always", "-m", "camgen", "run", str(path), "-q", "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == status, proc.stderr
    lines = proc.stderr.splitlines()
    prefix = {0: None, 1: "camgen: check failed: ", 2: "camgen: error: "}[status]
    if prefix is None:
        assert proc.stderr == ""
    else:
        assert lines and all(line.startswith(prefix) for line in lines), proc.stderr
    assert status != 2 or len(lines) == 1


def test_a_file_that_would_hold_nan_is_never_written(tmp_path, capsys, monkeypatch):
    """The pipeline's last guard: a writer that produced NaN (a bug) makes the run fail naming the
    file and line; nothing is written."""
    from camgen import writers
    from camgen.cli import main

    monkeypatch.setattr(writers, "points", lambda cam, run, fmt: "x_mm,y_mm\n1.0,2.0\nNaN,3.0\n")
    path = tmp_path / "scene.toml"
    path.write_text('[output]\nformats = ["points"]\n[cams.x]\nkind = "three_arc"\na_mm = 2.0\nb_mm = 1.0\nc_mm = 1.0\n')
    assert main(["run", str(path), "-q", "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "x_points.csv" in err and "'NaN' at line 3" in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()
