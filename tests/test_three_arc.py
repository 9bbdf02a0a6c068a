"""Three-arc constant-breadth cams against paper 000 and brute-force references."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import camgen
from camgen.errors import ParameterError
from camgen.synthesis import three_arc
from helpers import brute_support, distance_to_arcs, table1_paper

# paper 000, Section 6: cam parameters and the yoke single-side widths e2, e5
STRIDE = (220.0, 160.0, 25.0)
HEIGHT = (220.0, 220.0, 10.0)
E2, E5 = 165.0, 120.0
PAPER_CAMS = [pytest.param(STRIDE, 2 * E2, id="stride_length"), pytest.param(HEIGHT, 2 * E5, id="stride_height")]


@pytest.mark.parametrize("abc, yoke_width", PAPER_CAMS)
def test_breadth_equals_yoke_width_of_section_6(abc, yoke_width):
    cam = camgen.three_arc_cam(*abc)
    psi = np.linspace(0, math.pi, 3600, endpoint=False)
    # brute force on a dense polygon (vertices lie on the curve, so this can only under-estimate)
    dense = cam.flatten(1e-6)
    brute = brute_support(dense, psi) + brute_support(dense, psi + math.pi)
    assert np.max(np.abs(brute - yoke_width)) <= 2e-6
    analytic = cam.support(psi) + cam.support(psi + math.pi)
    assert np.max(np.abs(analytic - yoke_width)) <= 1e-9
    assert three_arc.breadth(*abc) == yoke_width


@pytest.mark.parametrize("abc, yoke_width", PAPER_CAMS)
def test_table1_matches_brute_force_support(abc, yoke_width):
    a, b, c = abc
    cam = camgen.three_arc_cam(a, b, c)
    phi = np.linspace(-math.pi, math.pi, 3600, endpoint=False) + 1e-4  # avoid 0/0 at region ends
    beta, radius = table1_paper(a, b, c, phi)
    psi = phi - beta * np.where(phi >= 0, 1.0, -1.0)  # psi = phi + beta10, paper 000 section 4.3
    h_table = radius * np.cos(beta)  # face distance: projection of ON on the face normal
    brute = brute_support(cam.flatten(1e-7), psi)
    assert np.max(np.abs(h_table - brute)) <= 1e-6
    # camgen's (singularity-free) implementation agrees with the literal table
    beta_c, radius_c = three_arc.yoke_law(a, b, c, phi)
    assert np.max(np.abs(beta_c - beta)) <= 1e-9
    assert np.max(np.abs(radius_c - radius)) <= 1e-7
    # and the contact point of Table 1 lies on the six arcs
    contact = radius[:, None] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    assert np.max(distance_to_arcs(contact, cam.segments)) <= 1e-7


@pytest.mark.parametrize("abc", [STRIDE, HEIGHT])
def test_table1_continuous_across_its_four_regions(abc):
    a, b, c = abc
    eps = 1e-9
    for bound in three_arc.region_bounds(a, b, c):
        for sgn in (1.0, -1.0):
            phi = sgn * np.array([bound - eps, bound + eps])
            beta, radius = three_arc.yoke_law(a, b, c, phi)
            assert abs(beta[1] - beta[0]) <= 1e-6
            assert abs(radius[1] - radius[0]) <= 1e-6
    # the region ends: R = c at B, R = 2a + c - b at D, beta is 0 there
    half, phi_c, phi_d = three_arc.region_bounds(a, b, c)
    beta, radius = three_arc.yoke_law(a, b, c, np.array([half, phi_d]))
    assert radius == pytest.approx([c, 2 * a + c - b], abs=1e-9)
    assert beta == pytest.approx([0.0, 0.0], abs=1e-12)
    # at C the normal is vertical (tangent point of arcs BC and CD on the line O'O'')
    beta_c, _ = three_arc.yoke_law(a, b, c, np.array([phi_c]))
    assert phi_c - beta_c[0] == pytest.approx(math.pi / 2, abs=1e-12)


@pytest.mark.parametrize("abc", [STRIDE, HEIGHT])
def test_inverse_law_returns_the_contact(abc):
    cam = camgen.three_arc_cam(*abc)
    psi = np.linspace(-math.pi, math.pi, 721)
    phi, beta, radius = three_arc.contact_from_normal(cam, psi)
    beta_t, radius_t = three_arc.yoke_law(*abc, phi)
    assert np.max(np.abs(radius - radius_t)) <= 1e-9
    on_dwell = np.isclose(radius, abc[2]) | np.isclose(radius, 2 * abc[0] + abc[2] - abc[1])
    # on the dwell arcs the contact is where the normal points; elsewhere beta follows Table 1
    assert np.max(np.abs(beta - beta_t)[~on_dwell]) <= 1e-9
    back = three_arc.normal_angle(phi, beta)
    assert np.max(np.abs(np.angle(np.exp(1j * (back - psi))))[~on_dwell]) <= 1e-9


def test_yoke_motion_derivatives_match_finite_differences():
    cam = camgen.three_arc_cam(*STRIDE)
    theta = np.linspace(0, 2 * math.pi, 1441)[:-1] + 1e-3
    motion = camgen.yoke_motion(cam, theta)
    step = 1e-4
    dense = cam.flatten(1e-7)
    s = lambda th: brute_support(dense, 0.0 - th)  # noqa: E731 (face normal along +x)
    assert np.max(np.abs(motion.displacement - s(theta))) <= 2e-7  # polygon under-estimates by <= chord_tol
    fd_v = (s(theta + step) - s(theta - step)) / (2 * step)
    assert np.max(np.abs(motion.velocity - fd_v)) <= 2e-3
    # acceleration (rho - h) against the second difference of the support values; step 1e-3
    # keeps the truncation error (fourth derivative * step^2 / 12) below 1e-4 mm
    step = 1e-3
    h = lambda th: cam.support(0.0 - th)  # noqa: E731
    fd_a = (h(theta + step) - 2 * h(theta) + h(theta - step)) / step**2
    _, _, rho = cam._support(-theta)
    # contact on the same arc at theta +- step: same radius of curvature
    _, _, rho_p = cam._support(-(theta + step))
    _, _, rho_m = cam._support(-(theta - step))
    smooth = (rho == rho_p) & (rho == rho_m)
    assert smooth.sum() > 1400
    assert np.max(np.abs(motion.acceleration - fd_a)[smooth]) <= 1e-3
    # stroke of the yoke: max - min displacement = (2a + c - b) - c
    assert motion.displacement.max() - motion.displacement.min() == pytest.approx(2 * 220 - 160, abs=1e-6)


# --- parameter validation -----------------------------------------------------------------------
@pytest.mark.parametrize(
    "a, b, c, name",
    [
        (-220, 160, 25, "a"),
        (0, 160, 25, "a"),
        (float("nan"), 160, 25, "a"),
        (float("inf"), 160, 25, "a"),
        (220, -1, 25, "b"),
        (220, 0, 25, "b"),
        (220, float("nan"), 25, "b"),
        (220, 160, 0, "c"),
        (220, 160, -5, "c"),
        (220, 160, float("inf"), "c"),
        (220, 440, 500, "b"),  # b = 2a: theta_x = pi, flank arcs vanish
        (220, 250, 25, "b"),  # b >= a + c: radius a + c - b <= 0
        ("220", 160, 25, "a"),
    ],
)
def test_invalid_parameters_name_the_parameter(a, b, c, name):
    with pytest.raises(ParameterError) as info:
        camgen.three_arc_cam(a, b, c)
    assert info.value.name == name
    assert f"parameter '{name}'" in str(info.value)
    assert "valid range" in str(info.value)


def test_domain_message_gives_the_bound():
    with pytest.raises(ParameterError, match=r"0 < b < min\(2a, a \+ c\) = 245 mm"):
        camgen.three_arc_cam(220, 250, 25)
    with pytest.raises(ParameterError, match=r"b < 2a"):
        camgen.three_arc_cam(100, 200, 500)


# --- hypothesis over the valid domain ---------------------------------------------------------------
valid_abc = st.tuples(
    st.floats(1.0, 1000.0), st.floats(0.01, 0.99), st.floats(0.1, 500.0)
).map(lambda t: (t[0], t[1] * min(2 * t[0], t[0] + t[2]), t[2]))


@settings(max_examples=60, deadline=None)
@given(valid_abc)
def test_valid_domain_closed_g1_constant_breadth(abc):
    a, b, c = abc
    cam = camgen.three_arc_cam(a, b, c)
    size = 2 * a + c
    for joint in cam.joints():
        assert joint.gap_mm <= 1e-12 * size + 1e-12
        assert joint.tangent_jump_rad <= 1e-9
        assert joint.continuity in ("G1", "G2")
    psi = np.linspace(0, math.pi, 720, endpoint=False)
    assert np.max(np.abs(cam.support(psi) + cam.support(psi + math.pi) - (2 * a + 2 * c - b))) <= 1e-9
    assert sum(abs(s.sweep) for s in cam.segments) == pytest.approx(2 * math.pi, abs=1e-12)
