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


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(max_size=60))
def test_arbitrary_expression_text_is_a_parameter_error_or_a_function(text):
    try:
        expr = parse_expression(text)
    except ParameterError:
        return
    with np.errstate(all="ignore"):
        expr.f(np.linspace(0.1, 1.0, 5))  # parsed text evaluates without touching Python


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
    from camgen.pipeline import Plan, compute
    from camgen.scene import parse_scene

    try:
        scene = parse_scene({"cams": {"x": table}}, "fuzz")
        compute(scene, Plan((), frozenset()))
    except CamgenError:
        pass
