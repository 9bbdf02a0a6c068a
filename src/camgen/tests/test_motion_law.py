"""Motion-law disk cams: the laws, the exact envelopes, riding followers on the cams as made."""
from __future__ import annotations

import math

import numpy as np
import pytest

from camgen.checks import Follower, evaluate_cam
from camgen.errors import GeometryError, ParameterError
from camgen.synthesis.motion_law import (
    LAWS,
    MotionProgram,
    MotionSegment,
    flat_cam,
    roller_cam,
)

D = math.radians
PROGRAM = [MotionSegment("cycloidal", D(120), 20.0), MotionSegment("dwell", D(60), 0.0),
           MotionSegment("poly345", D(120), -20.0), MotionSegment("dwell", D(60), 0.0)]


@pytest.mark.parametrize("name", sorted(LAWS))
def test_laws_rise_from_zero_to_one_and_their_derivatives(name):
    tau = np.linspace(0, 1, 2001)
    s, v, a, j = LAWS[name](tau)
    assert s[0] == pytest.approx(0, abs=1e-15) and s[-1] == pytest.approx(1, abs=1e-14)
    assert v[0] == pytest.approx(0, abs=1e-12) and v[-1] == pytest.approx(0, abs=1e-12)
    step = tau[1] - tau[0]
    for lower, higher in ((s, v), (v, a), (a, j)):
        central = (lower[2:] - lower[:-2]) / (2 * step)
        assert np.max(np.abs(central - higher[1:-1])) <= 1e-4 * (1 + np.max(np.abs(higher)))
    if name == "cycloidal":  # zero acceleration at the ends; harmonic: pi^2 / 2; 4-5-6-7: zero jerk
        assert a[0] == pytest.approx(0, abs=1e-12) and a[-1] == pytest.approx(0, abs=1e-9)
    if name == "harmonic":
        assert a[0] == pytest.approx(math.pi**2 / 2)
    if name == "poly4567":
        assert j[0] == pytest.approx(0, abs=1e-12) and j[-1] == pytest.approx(0, abs=1e-9)


def test_program_validation():
    with pytest.raises(ParameterError, match="360 deg"):
        MotionProgram(PROGRAM[:3])
    with pytest.raises(ParameterError, match="lifts adding up to 0"):
        MotionProgram([MotionSegment("cycloidal", D(180), 20.0), MotionSegment("harmonic", D(180), -10.0)])
    with pytest.raises(ParameterError, match="law"):
        MotionSegment("sine-ish", D(90), 5.0)


def _roller_lift(profile, theta, offset, radius):
    """Brute force: lift of a roller on the axis x = -offset riding the polygon of the profile."""
    poly = profile.flatten(1e-6)
    out = np.empty(theta.size)
    for k, t in enumerate(theta):  # reference computation, per angle on purpose
        c, s = math.cos(t), math.sin(t)
        x = c * poly[:, 0] - s * poly[:, 1]
        y = s * poly[:, 0] + c * poly[:, 1]
        lateral = x + offset
        near = np.abs(lateral) <= radius
        out[k] = np.max(y[near] + np.sqrt(radius * radius - lateral[near] ** 2))
    return out


def test_roller_rides_the_exact_envelope():
    program = MotionProgram(PROGRAM)
    base, roller, offset = 40.0, 10.0, 8.0
    profile, pitch = roller_cam(program, base, roller, offset)
    theta = np.linspace(0, 2 * math.pi, 360, endpoint=False) + D(0.25)  # between the 0.5 deg samples
    s, ds, _, _ = program(theta)
    d0 = math.sqrt((base + roller) ** 2 - offset**2)
    lift = _roller_lift(profile, theta, offset, roller)
    assert np.max(np.abs(lift - (d0 + s))) <= 2e-5
    # and the radial shortcut r = Rb + s that some peers export is far off for the same roller
    shortcut = np.stack([(base + program(-t)[0]) * np.array([math.cos(t + math.pi / 2), math.sin(t + math.pi / 2)])
                         for t in np.linspace(0, 2 * math.pi, 2880, endpoint=False)])
    from camgen.contour import Contour, Spline

    phi = np.linspace(0, 2 * math.pi, 2881)
    shortcut_contour = Contour([Spline.interpolate(phi, np.vstack([shortcut, shortcut[:1]]))])
    err_shortcut = np.max(np.abs(_roller_lift(shortcut_contour, theta, 0.0, roller) - (base + roller + program(theta)[0])))
    assert err_shortcut > 0.1
    # pressure angle against the closed form tan(alpha) = (s' + e) / (d0 + s)
    ev = evaluate_cam(profile, Follower("roller", roller_radius=roller, offset=offset, direction=math.pi / 2), pitch=pitch)
    angle, alpha = ev.pressure_angle
    s2, ds2, _, _ = program(angle)
    assert np.max(np.abs(alpha - np.arctan((ds2 + offset) / (d0 + s2)))) <= 1e-6


def test_flat_follower_exact_envelope_and_undercut():
    program = MotionProgram(PROGRAM)
    cam = flat_cam(program, 60.0)
    theta = np.linspace(0, 2 * math.pi, 1000, endpoint=False) + 0.001
    psi = math.pi / 2 - theta
    brute = (cam.flatten(1e-7) @ np.stack([np.cos(psi), np.sin(psi)])).max(axis=0)
    assert np.max(np.abs(brute - (60.0 + program(theta)[0]))) <= 2e-6
    # Rb + s + s'' must stay > 0: the cycloidal rise needs s'' = 20 * 2 pi / (2 pi/3)^2 = 28.6 mm/rad^2
    with pytest.raises(GeometryError, match=r"undercuts the cam at cam angle .* use a larger base radius"):
        flat_cam(program, 5.0)


def test_bad_roller_parameters():
    program = MotionProgram(PROGRAM)
    with pytest.raises(ParameterError, match="offset"):
        roller_cam(program, 40.0, 10.0, offset=60.0)
    with pytest.raises(ParameterError, match="roller_radius"):
        roller_cam(program, 40.0, 0.0)
