"""Sizing against brute-force searches that use their own textbook formulas (polar-curve curvature,
Norton's pressure angle, Rb + s + s'' of a flat face, finite differences of the oscillating geometry)."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from camgen.errors import GeometryError, ParameterError
from camgen.synthesis.followers import FollowerSpec
from camgen.synthesis.laws import MotionProgram
from camgen.synthesis.laws import Segment as MotionSegment
from camgen.synthesis.sizing import DesignLimits, face_width, min_base_radius, min_base_radius_and_offset, require_design
import ride
from test_followers import rest_arm_angle

D = math.radians
TWO_PI = 2 * math.pi
THETA = np.linspace(0.0, TWO_PI, 7200, endpoint=False)  # the code checks a 0.05 deg grid too, plus the breaks
LAW = MotionProgram([MotionSegment("cycloidal", D(100), 20.0), MotionSegment("dwell", D(60), 0.0),
               MotionSegment("poly345", D(120), -20.0), MotionSegment("dwell", D(80), 0.0)])


def _centred_roller_ok(bases: np.ndarray, roller: float, limits: DesignLimits) -> np.ndarray:
    """Feasibility of a centred translating roller for every base radius: the pitch curve is the polar
    curve r = Rp + s; pressure angle atan(r' / r) (angle between radius and normal of a polar curve),
    radius of curvature (r^2 + r'^2)^1.5 / (r^2 + 2 r'^2 - r r'')."""
    s, v, a, _ = (x[None, :] for x in LAW(THETA))
    r = bases[:, None] + roller + s
    alpha = np.arctan(np.abs(v) / r)
    denom = r**2 + 2 * v**2 - r * a
    rho = (r**2 + v**2) ** 1.5 / denom  # > 0 convex, < 0 concave
    convex_profile = np.where(denom > 0, rho - roller, np.inf)
    concave_profile = np.where(denom < 0, -rho + roller, np.inf)
    return ((alpha.max(axis=1) <= limits.max_pressure_angle) & (convex_profile.min(axis=1) >= limits.min_convex_radius)
            & (convex_profile.min(axis=1) > 0) & (concave_profile.min(axis=1) >= limits.min_concave_radius))


def _smallest(grid: np.ndarray, ok: np.ndarray) -> float:
    assert ok.any() and not ok[0]
    return float(grid[np.argmax(ok)])


@pytest.mark.parametrize("limits, binding", [
    (DesignLimits(max_pressure_angle=D(30)), "pressure"),
    (DesignLimits(max_pressure_angle=D(45), min_convex_radius=25.0), "curvature"),
])
def test_centred_roller_base_radius_against_brute_force(limits, binding):
    result = min_base_radius(FollowerSpec("roller", 50.0, roller_radius=10.0), LAW, limits)
    coarse = np.arange(0.5, 80.0, 0.5)
    brute = _smallest(coarse, _centred_roller_ok(coarse, 10.0, limits))  # the whole range, coarsely
    grid = np.arange(brute - 0.5, brute + 0.005, 0.01)  # then 0.01 mm steps below the first coarse success
    brute = _smallest(grid, _centred_roller_ok(grid, 10.0, limits))
    assert brute - 0.01 - 1e-9 <= result.base_radius <= brute + 1e-9
    assert _centred_roller_ok(np.array([result.base_radius]), 10.0, limits)[0]
    m = result.measures  # which limit binds at the optimum
    if binding == "pressure":
        assert m.max_pressure_angle == pytest.approx(limits.max_pressure_angle, abs=1e-6)
    else:
        assert m.min_convex_radius == pytest.approx(25.0, abs=1e-3) and m.max_pressure_angle < limits.max_pressure_angle - D(1)


def test_flat_face_base_radius_against_rb_plus_s_plus_s2():
    limits = DesignLimits(min_convex_radius=5.0)
    result = min_base_radius(FollowerSpec("flat", 50.0), LAW, limits)
    s, _, a, _ = LAW(THETA)
    grid = np.arange(0.01, 60.0, 0.005)
    rho = grid[:, None] + s[None, :] + a[None, :]  # radius of curvature of a flat follower's cam (textbook)
    brute = _smallest(grid, rho.min(axis=1) >= 5.0)
    assert brute - 0.005 - 1e-9 <= result.base_radius <= brute + 1e-9
    assert result.measures.max_pressure_angle == 0.0


def test_offset_and_base_radius_against_a_grid():
    """Norton: tan(alpha) = (s' - e) / (s + sqrt(Rp^2 - e^2)) (ccw, e = offset); the smallest Rb over (e, Rb)."""
    limits = DesignLimits(max_pressure_angle=D(25))
    result = min_base_radius_and_offset(FollowerSpec("roller", 50.0, roller_radius=8.0), LAW, limits)
    s, v, _, _ = (x[None, None, :] for x in LAW(THETA[::2]))

    def smallest(offsets, bases):
        e = offsets[:, None, None]
        rp = bases[None, :, None] + 8.0
        with np.errstate(invalid="ignore", divide="ignore"):
            d0 = np.sqrt(rp**2 - e**2)
            ok = np.all(np.abs(np.arctan((v - e) / (s + d0))) <= limits.max_pressure_angle, axis=2) & (rp[..., 0] > np.abs(e[..., 0]))
        best = np.where(ok.any(axis=1), bases[np.argmax(ok, axis=1)], np.inf)
        k = int(np.argmin(best))
        return best[k], offsets[k]

    coarse, _ = smallest(np.arange(-20.0, 20.01, 0.5), np.arange(1.0, 80.0, 0.25))
    fine, fine_e = smallest(result.offset + np.arange(-0.3, 0.301, 0.01), result.base_radius + np.arange(-0.1, 0.1, 0.002))
    assert result.base_radius <= coarse + 1e-9  # nothing on the global grid is better
    assert fine - 0.002 - 1e-6 <= result.base_radius <= fine + 1e-9
    assert abs(result.offset - fine_e) <= 0.02
    # and the offset is worth it: the centred follower needs more
    assert min_base_radius(FollowerSpec("roller", 50.0, roller_radius=8.0), LAW, limits).base_radius > result.base_radius + 1.0
    # cw: the mirrored offset
    mirrored = min_base_radius_and_offset(FollowerSpec("roller", 50.0, roller_radius=8.0, rotation="cw"), LAW, limits)
    assert mirrored.offset == pytest.approx(-result.offset, abs=2e-3)
    assert mirrored.base_radius == pytest.approx(result.base_radius, abs=2e-4)


def test_oscillating_roller_against_finite_differences_of_the_geometry():
    law = MotionProgram([MotionSegment("cycloidal", D(100), 0.3), MotionSegment("dwell", D(60), 0.0),
                   MotionSegment("poly345", D(120), -0.3), MotionSegment("dwell", D(80), 0.0)])
    template = FollowerSpec("roller", 40.0, motion="oscillating", roller_radius=8.0, pivot=(110.0, 0.0), arm_length=90.0)
    limits = DesignLimits(max_pressure_angle=D(35), min_convex_radius=3.0)
    result = min_base_radius(template, law, limits)
    theta = THETA[::2]
    h = 1e-4

    def ok(base: float) -> bool:
        f = FollowerSpec("roller", base, motion="oscillating", roller_radius=8.0, pivot=(110.0, 0.0), arm_length=90.0)
        g0 = rest_arm_angle(f)  # the convention, computed in the tests on their own
        samples = theta[:, None] + np.array([-h, 0.0, h])[None, :]
        g = g0 + law(samples.ravel())[0].reshape(samples.shape)
        centre = np.array([110.0, 0.0]) + 90.0 * np.stack([np.cos(g), np.sin(g)], -1)
        c, s_ = np.cos(-samples), np.sin(-samples)  # seen from the cam (ccw)
        p = np.stack([c * centre[..., 0] - s_ * centre[..., 1], s_ * centre[..., 0] + c * centre[..., 1]], -1)
        d1 = (p[:, 2] - p[:, 0]) / (2 * h)
        d2 = (p[:, 2] - 2 * p[:, 1] + p[:, 0]) / h**2
        kappa = -(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
        # normal of the pitch curve back in the fixed frame, against the roller centre's motion (normal to the arm)
        cb, sb = np.cos(theta), np.sin(theta)
        tangent = np.stack([cb * d1[:, 0] - sb * d1[:, 1], sb * d1[:, 0] + cb * d1[:, 1]], -1)
        arm = centre[:, 1] - np.array([110.0, 0.0])
        motion = np.stack([-arm[:, 1], arm[:, 0]], -1)
        cos_t = np.abs(np.sum(tangent * motion, 1)) / (np.hypot(*tangent.T) * 90.0)
        alpha = np.arcsin(np.clip(cos_t, 0, 1))  # the normal's angle to the motion = the tangent's angle to its normal
        convex = np.where(kappa > 0, 1 / np.where(kappa > 0, kappa, 1) - 8.0, np.inf)
        return bool(alpha.max() <= limits.max_pressure_angle and convex.min() >= 3.0)

    assert ok(result.base_radius + 1e-3)
    assert not ok(result.base_radius - 0.02)
    grid = np.arange(result.base_radius - 2.0, result.base_radius - 0.019, 0.1)
    assert not any(ok(b) for b in grid)  # nothing smaller works either


def test_require_design_says_what_to_change():
    f = FollowerSpec("roller", 20.0, roller_radius=10.0)
    limits = DesignLimits(max_pressure_angle=D(30))
    with pytest.raises(GeometryError, match=r"pressure angle .* > 30 deg .*increase base_radius_mm to at least (\d+\.\d{3})$") as err:
        require_design(f, LAW, limits)
    need = float(re.search(r"at least (\d+\.\d+)", str(err.value)).group(1))
    grid = np.array([need, need - 0.001])
    assert _centred_roller_ok(grid, 10.0, limits).tolist() == [True, False]
    assert require_design(FollowerSpec("roller", need, roller_radius=10.0), LAW, limits).max_pressure_angle <= D(30)
    # no base radius can work: the pivot is too close for a 10 deg pressure-angle limit
    osc = FollowerSpec("roller", 40.0, motion="oscillating", roller_radius=8.0, pivot=(110.0, 0.0), arm_length=90.0)
    swing = MotionProgram([MotionSegment("cycloidal", D(100), 0.3), MotionSegment("cycloidal", D(260), -0.3)])
    with pytest.raises(GeometryError, match="move the pivot"):
        require_design(osc, swing, DesignLimits(max_pressure_angle=D(10)))


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_face_width_against_the_ride(rotation):
    """Where the ride finds the contact on the face.  Centred ccw translating face: the contact is at
    x = s' (Norton: the face must reach the largest velocity on each side)."""
    from camgen.synthesis.followers import cam_envelope

    theta = THETA[::4]
    flat = FollowerSpec("flat", 50.0, offset=3.0, rotation=rotation)
    cam = cam_envelope(flat, LAW).profile
    _, t = ride.translating_flat(cam, theta, flat.sigma, return_param=True)
    q = cam.evaluate(t)
    x = np.cos(flat.sigma * theta) * q[:, 0] - np.sin(flat.sigma * theta) * q[:, 1]  # contact x in the fixed frame
    width = face_width(flat, LAW)
    assert width.right == pytest.approx(np.max(x - 3.0), abs=1e-3)
    assert width.left == pytest.approx(np.max(3.0 - x), abs=1e-3)
    v = LAW(THETA)[1]
    if rotation == "ccw":
        assert width.right == pytest.approx(v.max() - 3.0, abs=1e-9) and width.left == pytest.approx(3.0 - v.min(), abs=1e-9)
    osc = FollowerSpec("flat", 60.0, motion="oscillating", pivot=(130.0, 50.0), face_offset=20.0, lift_turn="cw", rotation=rotation)
    swing = MotionProgram([MotionSegment("harmonic", D(100), 0.15), MotionSegment("dwell", D(60), 0.0),
                     MotionSegment("cycloidal", D(120), -0.15), MotionSegment("dwell", D(80), 0.0)])
    cam = cam_envelope(osc, swing).profile
    from test_followers import rest_face_angle

    psi, t = ride.oscillating_flat(cam, theta, osc.pivot, 20.0, rest_face_angle(osc), osc.tau, osc.sigma, return_param=True)
    q = cam.evaluate(t)
    c, s_ = np.cos(osc.sigma * theta), np.sin(osc.sigma * theta)
    contact = np.stack([c * q[:, 0] - s_ * q[:, 1], s_ * q[:, 0] + c * q[:, 1]], -1) - np.array(osc.pivot)
    xi = -contact[:, 0] * np.sin(psi) + contact[:, 1] * np.cos(psi)
    width = face_width(osc, swing)
    assert width.left == pytest.approx(xi.min(), abs=1e-3) and width.right == pytest.approx(xi.max(), abs=1e-3)
    with pytest.raises(ParameterError, match="flat follower"):
        face_width(FollowerSpec("knife", 40.0), LAW)


def test_limits_are_validated():
    with pytest.raises(ParameterError, match="'max_pressure_angle'.*0 < max_pressure_angle < pi/2"):
        DesignLimits(max_pressure_angle=D(90))
    with pytest.raises(ParameterError, match="'min_convex_radius'.*>= 0"):
        DesignLimits(min_convex_radius=-1.0)
    with pytest.raises(ParameterError, match="'follower'.*translating roller or knife"):
        min_base_radius_and_offset(FollowerSpec("flat", 40.0), LAW)
