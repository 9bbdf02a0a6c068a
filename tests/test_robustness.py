"""Stress and fuzz tests: extreme valid geometry stays exact; arbitrary user text never escapes
as anything but a CamgenError."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import camgen
from camgen.errors import CamgenError, ParameterError
from camgen.synthesis.expression import parse_expression
from helpers import chord_deviation


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


#: Fragments of expressions, whitelisted and not, to make text that parses often and fails in many ways.
_SOUP = ["x", "pi", "1", "2.5", "0", "1e3", "0x1f", "(", ")", "+", "-", "*", "/", "**", " ", "sin(", "cos(", "tan(", "exp(",
         "log(", "sqrt(", "abs(", "y", "^", "@", "[", "]", ",", "import", "lambda", "__", "1j", "e", ".", "%", "<"]
_WHITELIST_NAMES = {"x", "pi", "sin", "cos", "tan", "exp", "log", "sqrt", "abs"}
_WHITELIST_OPS = {"+", "-", "*", "/", "**", "(", ")"}


def _reference(text: str, x: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """CPython's own evaluation of ``text`` with numpy's functions and every number a float64
    (as camgen's are: 1/0 is inf, not ZeroDivisionError), independent of camgen's tree; with
    every number and x times ``scale`` (to measure how much rounding the text amplifies)."""
    import io
    import tokenize

    def to_float(value):
        try:
            return np.float64(value) * scale
        except OverflowError:  # an integer beyond the floats: camgen reads it as inf
            return np.float64(math.inf)

    tokens = [(tok.type, f"_f({tok.string})" if tok.type == tokenize.NUMBER else tok.string)
              for tok in tokenize.generate_tokens(io.StringIO(text.strip()).readline)]
    code = tokenize.untokenize(tokens)
    names = {"_f": to_float, "x": x * scale, "pi": np.float64(math.pi) * scale, "sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp,
             "log": np.log, "sqrt": np.sqrt, "abs": np.abs}
    with np.errstate(all="ignore"):
        return np.broadcast_to(eval(code, {"__builtins__": {}}, names), x.shape)  # noqa: S307 - whitelisted text only


_GRAMMAR = st.recursive(
    st.sampled_from(["x", "-x", "pi", "1", "-2.5", "0", "1e3", "0x1f", "7_0"]),
    lambda inner: st.one_of(
        st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "**"]), inner).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        st.tuples(st.sampled_from(["sin", "cos", "exp", "sqrt", "abs", "log", "tan", "-", "+"]), inner).map(lambda t: f"{t[0]}({t[1]})"),
    ),
    max_leaves=6,
)


@settings(max_examples=300, deadline=None, derandomize=True, database=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.text(max_size=60), st.lists(st.sampled_from(_SOUP), max_size=12).map("".join), _GRAMMAR, _LONG_TEXTS))
@example("abs(-x) + abs(x - 0.5)")
@example("sin(-x) * cos(2*x) / tan(x/2)")
@example("exp(-x) + log(x) - sqrt(x) + pi")
@example("-x**2 + 2**-x - x/(1 - x) + 0x1f - 1e3")
def test_arbitrary_expression_text_is_a_parameter_error_or_a_function(text):
    """Refused: a ParameterError of the key 'expression' (which the cam kinds rename
    cams.<name>.expression) in one line.  Accepted: a function whose value and two derivatives are
    arrays of the input's shape; every name in the text is whitelisted and every operator one of
    + - * / ** (Python's tokenizer, not camgen's parser); and, for texts CPython itself compiles
    (up to 200 characters: the long ones probe the parser's limits), the function's values at x
    in [0.1, 1] are CPython's evaluation of the same text (where that is finite), to 1e-12 relative
    plus what the text makes of a 1e-12 relative change of its numbers (numpy's and libm's sine
    may differ by an ulp, which sin(pi**5.66) amplifies)."""
    import io
    import tokenize

    try:
        expr = parse_expression(text)
    except ParameterError as exc:
        assert exc.name == "expression" and str(exc).startswith("parameter 'expression' = ") and "\n" not in str(exc)
        return
    x = np.linspace(0.1, 1.0, 5)
    with np.errstate(all="ignore"):  # parsed text evaluates without touching Python
        assert all(np.shape(g(x)) == x.shape for g in (expr.f, expr.df, expr.d2f))
    tokens = list(tokenize.generate_tokens(io.StringIO(text.strip()).readline))
    assert {t.string for t in tokens if t.type == tokenize.NAME} <= _WHITELIST_NAMES, text
    assert {t.string for t in tokens if t.type == tokenize.OP} <= _WHITELIST_OPS, text
    if len(text) > 200:
        return
    with np.errstate(all="ignore"):
        got = np.broadcast_to(expr.f(x), x.shape)
    want = _reference(text, x)
    with np.errstate(all="ignore"):
        spread = np.maximum(np.abs(_reference(text, x, 1 + 1e-12) - want), np.abs(_reference(text, x, 1 - 1e-12) - want))
        error = np.abs(got - want)
    finite = np.isfinite(want) & np.isfinite(spread)
    assert np.all(error[finite] <= (1e-12 * np.abs(want) + 10 * spread + 1e-300)[finite]), (text, got, want)


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


_FUZZ_VALUES = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.floats(1e-3, 1e3), st.integers(-5, 500),
                        st.text(max_size=8), st.booleans(), st.sampled_from(["yoke", "flat", "roller", "knife"]))
#: The documented ranges of the three-arc keys (camgen keys, docs/scene-keys.md): lowest, highest.
_RANGES = {"a_mm": (1e-6, 1e5), "b_mm": (1e-6, 1e5), "c_mm": (1e-6, 1e5), "thickness_mm": (1e-6, 1e4),
           "bore_diameter_mm": (0.0, 1e4), "rpm": (1e-3, 1e6)}


def _invalid_keys(table: dict) -> set[str]:
    """The keys a three-arc table breaks by the documented rules (scene-keys.md, README): the kind,
    a number in range for each numeric key (not a boolean), the follower one of yoke, flat, roller
    (a roller needs its radius), a, b, c required with 0 < b < min(2a, a + c)."""
    if table.get("kind") != "three_arc":
        return {"kind"}
    bad = set()
    for key, (lo, hi) in _RANGES.items():
        value = table.get(key)
        if key in table and (isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= value <= hi):
            bad.add(key)
    bad |= {key for key in ("a_mm", "b_mm", "c_mm") if key not in table}
    follower = table.get("follower", "yoke")
    if follower not in ("yoke", "flat", "roller"):
        bad.add("follower")
    elif follower == "roller":
        bad.add("roller_radius_mm")  # not among the fuzzed keys: always missing
    if not bad & {"a_mm", "b_mm", "c_mm"}:
        a, b, c = table["a_mm"], table["b_mm"], table["c_mm"]
        if not b < min(2 * a, a + c):
            bad.add("b_mm")
    return bad


_FUZZ_KEYS = ["a_mm", "b_mm", "c_mm", "thickness_mm", "bore_diameter_mm", "follower", "rpm"]
#: Paper 000's stride cam: fuzzed keys over a valid cam.
_PAPER_CAM = {"a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0}


@st.composite
def _near_valid_tables(draw) -> dict:
    """A three-arc table (b anywhere in its range, at its end or up to half as much again beyond
    it, a bore of any size, a follower and a speed or not) with up to two of its keys dropped or
    given a fuzzed value."""
    a = draw(st.floats(1e-2, 1e3))
    c = a * draw(st.floats(0.05, 3.0))
    b = min(2 * a, a + c) * draw(st.one_of(st.floats(0.01, 1.5), st.just(1.0)))
    table = {"a_mm": a, "b_mm": b, "c_mm": c}
    near_wall = max(0.0, 2.0 * (c - 2.0)) * draw(st.floats(0.9, 1.1))  # the bore that leaves the 2 mm default wall, +-10 %
    bores = st.one_of(st.floats(0.0, 3.0 * c), st.just(near_wall))
    for key, values in (("thickness_mm", st.floats(0.1, 100.0)), ("bore_diameter_mm", bores),
                        ("follower", st.sampled_from(["yoke", "flat"])), ("rpm", st.floats(1.0, 1000.0))):
        if draw(st.booleans()):
            table[key] = draw(values)
    for key in draw(st.lists(st.sampled_from(_FUZZ_KEYS), max_size=2)):
        if draw(st.booleans()):
            table.pop(key, None)
        else:
            table[key] = draw(_FUZZ_VALUES)
    return table


@settings(max_examples=300, deadline=None, derandomize=True, database=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.one_of(st.just("three_arc"), st.just("three_arc"),
                 st.text(max_size=10).filter(lambda k: k not in ("lift_table", "motion_law", "trajectory"))),
       st.one_of(st.dictionaries(st.sampled_from(_FUZZ_KEYS), _FUZZ_VALUES, max_size=7), _near_valid_tables(), _near_valid_tables(),
                 st.dictionaries(st.sampled_from(_FUZZ_KEYS), _FUZZ_VALUES, max_size=4).map(lambda t: {**_PAPER_CAM, **t})))
@example("three_arc", {"a_mm": 20.0, "b_mm": 10.0, "c_mm": 21.5, "bore_diameter_mm": 39.6})  # wall 1.7 mm: fails
@example("three_arc", {"a_mm": 20.0, "b_mm": 10.0, "c_mm": 21.5, "bore_diameter_mm": 38.8})  # wall 2.1 mm: passes
@example("three_arc", {"a_mm": 20.0, "b_mm": 10.0, "c_mm": 21.5, "bore_diameter_mm": 46.0})  # the bore breaks through
@example("three_arc", {"a_mm": 20.0, "b_mm": 40.0, "c_mm": 21.5})  # b = 2a: the end of b's range, refused
def test_fuzzed_cam_tables_end_in_a_camgen_error_or_a_cam(kind, table):
    """A table the documented rules refuse (_invalid_keys) ends in a CamgenError naming one of the
    keys it breaks; any other builds a cam of constant breadth 2a + 2c - b (paper 000) whose
    wall check fails exactly where the bore leaves less than the 2 mm default wall to the base
    circle of radius c (the nearest profile point to the axis; measured to 1e-4 mm)."""
    from camgen.pipeline import Plan, compute
    from camgen.scene import parse_scene

    table = {"kind": kind, **table}
    invalid = _invalid_keys(table)
    try:
        scene = parse_scene({"cams": {"x": table}}, "fuzz")
        cam = compute(scene, Plan((), frozenset())).cams[0]
    except CamgenError as exc:
        text = str(exc)  # "parameter 'cams.x.<key>' ..." or "[cams.x]: missing key(s) '<key>', ..."
        named = re.findall(r"'(\w+)'", text.split("missing key(s)")[1]) if "missing key(s)" in text else re.findall(r"cams\.x\.(\w+)", text)
        assert invalid and named and named[0] in invalid, (table, text)
        return
    assert not invalid, (table, invalid)
    assert cam.name == "x" and math.isfinite(cam.contour.area) and cam.contour.area > 0
    a, b, c = table["a_mm"], table["b_mm"], table["c_mm"]
    psi = np.linspace(0.0, math.pi, 90)
    assert np.allclose(cam.contour.support(psi) + cam.contour.support(psi + math.pi), 2 * a + 2 * c - b, rtol=1e-12,
                       atol=1e-12 * (2 * a + c))
    bore = table.get("bore_diameter_mm", 0.0)
    wall = c - bore / 2 - 2.0
    if bore > 0 and abs(wall) > 1e-3:
        check = next(ch for ch in cam.checks if ch.name == "wall_thickness")
        assert check.failed == (wall < 0), (table, check)


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
