"""Exact cam profiles for every follower, checked by riding them (tests/ride.py) and against
closed forms from outside the code: the eccentric circular cam, Rb + s + s'' of a flat face,
the polar-curve curvature of a centred pitch curve, the contact normal of the simulated ride."""
from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from camgen.errors import GeometryError, ParameterError
from camgen.synthesis.followers import FollowerSpec, cam_envelope, kinematics
from camgen.synthesis.laws import MotionProgram
from camgen.synthesis.laws import Segment as MotionSegment
import ride

D = math.radians
TWO_PI = 2 * math.pi
#: The laws of this module's ride matrix (the motion-law library's every law rides the exported
#: cams of the scene-level tests in test_disk_cams.py).
LAWS = ("cycloidal", "harmonic", "poly345", "poly4567")


def program(law: str, lift: float, rise=D(100), ret=D(110), dwell=D(80)) -> MotionProgram:
    return MotionProgram([MotionSegment(law, rise, lift), MotionSegment("dwell", dwell, 0.0), MotionSegment(law, ret, -lift),
                          MotionSegment("dwell", TWO_PI - rise - ret - dwell, 0.0)])


FOLLOWERS = {
    "roller": dict(kind="roller", base_radius=40.0, roller_radius=10.0),
    "roller_offset": dict(kind="roller", base_radius=40.0, roller_radius=10.0, offset=12.0),
    "flat": dict(kind="flat", base_radius=45.0, offset=3.0),
    "knife": dict(kind="knife", base_radius=40.0, offset=-6.0),
    "osc_roller": dict(kind="roller", base_radius=40.0, motion="oscillating", roller_radius=8.0, pivot=(110.0, 40.0), arm_length=95.0),
    "osc_flat": dict(kind="flat", base_radius=60.0, motion="oscillating", pivot=(130.0, 50.0), face_offset=20.0, lift_turn="cw"),
    "osc_knife": dict(kind="knife", base_radius=40.0, motion="oscillating", pivot=(-90.0, 60.0), arm_length=80.0, lift_turn="cw"),
}


def spec(name: str, rotation: str = "ccw", **changes) -> FollowerSpec:
    return FollowerSpec(**{**FOLLOWERS[name], "rotation": rotation, **changes})


def lift_of(name: str) -> float:
    if FOLLOWERS[name].get("motion", "translating") == "translating":
        return 18.0
    return 0.15 if name == "osc_flat" else 0.2


@functools.lru_cache(maxsize=None)
def built(name: str, law: str, rotation: str, fit_tol: float = 1e-7):
    f = spec(name, rotation)
    motion = program(law, lift_of(name))
    return f, motion, cam_envelope(f, motion, fit_tol=fit_tol)


# -- the follower's rest position from the conventions, computed here on its own ---------------
def rest_arm_angle(f: FollowerSpec) -> float:
    """The crossing of the arm circle with the prime circle where a positive swing moves outward."""
    o = np.asarray(f.pivot)
    for g in ride.arm_circle_crossings(f.pivot, f.arm_length, f.base_radius + f.roller_radius):
        ahead = o + f.arm_length * np.array([math.cos(g + 1e-6 * f.tau), math.sin(g + 1e-6 * f.tau)])
        if np.hypot(*ahead) > f.base_radius + f.roller_radius:
            return float(g)
    raise AssertionError("no rest position")


def rest_face_angle(f: FollowerSpec) -> float:
    """The face normal at rest: the face line (X - pivot) . w = -f tangent to the base circle, lifting for a positive swing."""
    o = np.asarray(f.pivot)
    d = np.hypot(*o)
    for sign in (1, -1):
        psi = math.atan2(o[1], o[0]) + sign * math.acos((f.base_radius + f.face_offset) / d)
        ahead = psi + 1e-6 * f.tau
        if o @ np.array([math.cos(ahead), math.sin(ahead)]) - f.face_offset > f.base_radius:
            return psi
    raise AssertionError("no rest position")


def ride_position(f: FollowerSpec, cam, theta, return_param=False):
    """The follower position the ride simulator finds (mm: roller centre / tip / face height; rad: arm or face angle)."""
    if f.motion == "translating":
        if f.kind == "roller":
            return ride.translating_roller(cam, theta, f.offset, f.roller_radius, f.sigma, return_param)
        if f.kind == "knife":
            return ride.translating_knife(cam, theta, f.offset, f.sigma, return_param)
        return ride.translating_flat(cam, theta, f.sigma, return_param)
    if f.kind == "flat":
        return ride.oscillating_flat(cam, theta, f.pivot, f.face_offset, rest_face_angle(f), f.tau, f.sigma, return_param=return_param)
    return ride.oscillating_roller(cam, theta, f.pivot, f.arm_length, f.roller_radius, rest_arm_angle(f), f.tau, f.sigma,
                                   return_param=return_param)


def required_position(f: FollowerSpec, s: np.ndarray) -> np.ndarray:
    """Where the conventions put the follower at lift or swing s (mm; rad)."""
    if f.motion == "translating":
        if f.kind == "flat":
            return f.base_radius + s
        return math.sqrt((f.base_radius + f.roller_radius) ** 2 - f.offset**2) + s
    return (rest_face_angle(f) if f.kind == "flat" else rest_arm_angle(f)) + f.tau * s


RIDE_THETA = np.linspace(0.0, TWO_PI, 181)[:-1] + D(0.37)


# --------------------------------------------------------------------------------------------
# Ride tests: every law x every follower x both rotation directions
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("name", sorted(FOLLOWERS))
@pytest.mark.parametrize("law", sorted(LAWS))
def test_follower_rides_the_law(law, name, rotation):
    f, motion, cam = built(name, law, rotation)
    theta = np.concatenate([RIDE_THETA, motion.breaks, motion.breaks + 1e-4])
    s = motion(theta)[0]
    error = np.max(np.abs(ride_position(f, cam.profile, theta) - required_position(f, s)))
    assert error <= 1e-6  # mm (translating) or rad (oscillating)
    assert cam.fit_error <= cam.fit_tol == 1e-7
    # the kinematics' own position of the follower is the law's (SVAJ from the law, not from geometry)
    k = kinematics(f, motion, theta)
    assert np.array_equal(k.s, s) and np.array_equal(k.d3s, motion(theta)[3])
    if f.motion == "oscillating":
        diff = np.mod(k.arm_angle - required_position(f, s) + math.pi, TWO_PI) - math.pi
        assert np.max(np.abs(diff)) <= 1e-12


@pytest.mark.parametrize("name, offset", [("roller", 0.0), ("flat", 3.0), ("knife", 0.0), ("roller_offset", 12.0), ("knife", -6.0)])
def test_cw_cam_is_the_mirror_image_of_the_ccw_cam(name, offset):
    """Mirror x -> -x (polar angle phi -> pi - phi): a cw cam is the mirror image of the ccw cam of
    the mirrored follower (offset -> -offset; a flat face's offset does not change the cam).  The
    rides in both directions are in test_follower_rides_the_law."""
    motion = program("poly345", 18.0)
    mirrored = -offset if name != "flat" else offset
    ccw = cam_envelope(spec(name, "ccw", offset=offset), motion).profile
    cw = cam_envelope(spec(name, "cw", offset=mirrored), motion).profile
    phi = np.linspace(0, TWO_PI, 997, endpoint=False)
    assert np.max(np.abs(cw.polar_radius(phi) - ccw.polar_radius(math.pi - phi))) <= 2e-7
    # and not trivially: the ccw cam is not symmetric itself, and the offset's sign matters
    assert np.max(np.abs(ccw.polar_radius(phi) - ccw.polar_radius(math.pi - phi))) > 1.0
    if name != "flat" and offset:
        other = cam_envelope(spec(name, "cw", offset=offset), motion).profile
        assert np.max(np.abs(other.polar_radius(phi) - ccw.polar_radius(math.pi - phi))) > 0.1


def test_fit_tol_sets_the_accuracy_and_bounds_the_piece_count():
    f = spec("roller_offset")
    motion = program("cycloidal", 18.0)
    theta = RIDE_THETA
    required = required_position(f, motion(theta)[0])
    pieces, errors = [], []
    for tol in (1e-4, 1e-8):
        cam = cam_envelope(f, motion, fit_tol=tol)
        pieces.append(sum(seg.n_pieces for seg in cam.profile.segments))
        errors.append(np.max(np.abs(ride_position(f, cam.profile, theta) - required)))
        assert cam.fit_error <= tol and errors[-1] <= tol
    assert errors[0] > 100 * errors[1]  # the coarse one is really coarser
    # a cubic's error falls as h^4: 1e4 times tighter asks ~10 times the pieces, not more than 25
    assert 4 < pieces[1] / pieces[0] < 25
    with pytest.raises(ParameterError, match="fit_tol"):
        cam_envelope(f, motion, fit_tol=0.0)


def test_breaks_an_ulp_apart_are_one_joint():
    """A constant-velocity segment whose blends take the whole span but an ulp (blend = 0.5 - 2^-54,
    within the documented 0 <= blend <= 0.5) has two breaks 4e-16 rad apart: the cam is made (it
    was refused: "breaks too close for spline knots") and rides the law (tests/ride.py)."""
    segments = [MotionSegment("cycloidal", D(55.49132947976879), 1.0), MotionSegment("dwell", D(55.49132947976879), 0.0),
                MotionSegment("cycloidal", D(41.61849710982659), -0.5), MotionSegment("dwell", D(24.277456647398843), 0.0),
                MotionSegment("constant_velocity", D(55.49132947976879), 0.5, 0.5 - 2.0**-54),
                MotionSegment("dwell", D(55.49132947976879), 0.0), MotionSegment("cycloidal", D(55.49132947976879), -1.0),
                MotionSegment("dwell", D(16.647398843930603), 0.0)]
    motion = MotionProgram(segments)
    assert np.min(np.diff(np.sort(motion.breaks))) < 1e-15
    f = FollowerSpec("knife", 1.0)
    cam = cam_envelope(f, motion, fit_tol=1e-7)
    theta = np.concatenate([RIDE_THETA, motion.breaks + 1e-4])
    assert np.max(np.abs(ride_position(f, cam.profile, theta) - required_position(f, motion(theta)[0]))) <= 1e-6


# --------------------------------------------------------------------------------------------
# Continuity: G1 exactly where the law's acceleration jumps, the jerk is the law's
# --------------------------------------------------------------------------------------------
MIXED = [MotionSegment("harmonic", D(90), 15.0), MotionSegment("dwell", D(50), 0.0), MotionSegment("cycloidal", D(110), -15.0),
         MotionSegment("poly4567", D(60), 4.0), MotionSegment("poly345", D(50), -4.0)]


@pytest.mark.parametrize("name", ["roller_offset", "flat", "knife", "osc_roller", "osc_flat"])
@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_joints_are_g1_exactly_where_the_acceleration_jumps(name, rotation):
    segments = MIXED if FOLLOWERS[name].get("motion") != "oscillating" else [
        MotionSegment(s.law, s.span, s.lift / 75.0) for s in MIXED]
    motion = MotionProgram(segments)
    f = spec(name, rotation)
    cam = cam_envelope(f, motion).profile
    brk = motion.breaks
    # where the law's acceleration jumps, from the law itself on both sides of each break
    jump = np.abs(motion(brk + 1e-9)[2] - motion(brk - 1e-9)[2]) > 1e-3
    assert jump.tolist() == [True, True, False, False, False]  # the harmonic rise's two ends
    # where the ride touches the cam at the break angles: the joints
    _, t = ride_position(f, cam, brk, return_param=True)
    contact = cam.evaluate(t)
    joints = cam.joints()
    points = np.array([j.point for j in joints])
    level = []
    for p in contact:
        dist = np.hypot(*(points - p).T)
        assert dist.min() <= 1e-6
        level.append(joints[int(np.argmin(dist))].continuity)
    assert level == ["G1" if j else "G2" for j in jump]
    assert len(joints) == brk.size
    if name == "flat":  # curvature jump = the jump of 1 / (Rb + s + s'') (radius of curvature of a flat follower's cam)
        s, _, a_right, _ = motion(brk + 1e-12)
        a_left = motion(brk - 1e-12)[2]
        expected = np.abs(1 / (f.base_radius + s + a_right) - 1 / (f.base_radius + s + a_left))
        got = [abs(joints[int(np.argmin(np.hypot(*(points - p).T)))].curvature_jump_per_mm) for p in contact]
        assert np.allclose(got, expected, rtol=1e-6, atol=1e-9)


def _derivatives_of_ride(f, cam, centre, step):
    """Central differences (1st..3rd) of the ride position at ``centre +- k step``."""
    k = np.arange(-2, 3)
    y = ride_position(f, cam, (centre[:, None] + k[None, :] * step).ravel()).reshape(-1, 5)
    first = (y[:, 3] - y[:, 1]) / (2 * step)
    second = (y[:, 3] - 2 * y[:, 2] + y[:, 1]) / step**2
    third = (y[:, 4] - 2 * y[:, 3] + 2 * y[:, 1] - y[:, 0]) / (2 * step**3)
    return first, second, third


def test_flat_follower_jerk_and_acceleration_are_the_laws():
    """Riding the cam as made: the flat follower's jerk is the law's s''' (e.g. the cycloidal
    return's peak 4 pi^2 L / beta^3 = 4 pi^2 15 / (110 deg)^3 = 83.68 mm/rad^3), and the
    harmonic rise's acceleration steps from pi^2 L / (2 beta^2) to 0 at its end without overshoot."""
    motion = MotionProgram(MIXED)
    f = FollowerSpec("flat", 50.0)
    cam = cam_envelope(f, motion, fit_tol=1e-10).profile
    centre = np.linspace(D(145), D(245), 21)  # inside the cycloidal return (140..250 deg)
    _, acc, jerk = _derivatives_of_ride(f, cam, centre, 0.01)  # truncation step^2 s^(5) / 4: 3e-4 relative
    tau = (centre - D(140)) / D(110)
    closed = -15.0 * 4 * math.pi**2 * np.cos(2 * math.pi * tau) / D(110) ** 3  # cycloidal S''' = 4 pi^2 cos(2 pi tau)
    assert abs(closed).max() == pytest.approx(83.68, rel=1e-3)
    assert np.max(np.abs(jerk - closed)) <= 1e-3 * 83.68
    # the harmonic rise's end at 90 deg: acceleration -pi^2 L / (2 beta^2) before, 0 after (dwell)
    step = 2e-4
    left = np.linspace(D(80), D(90) - 3 * step, 8)
    right = np.linspace(D(90) + 3 * step, D(100), 8)
    a_end = -(math.pi**2) * 15.0 / (2 * D(90) ** 2)
    _, acc_left, _ = _derivatives_of_ride(f, cam, left, step)
    _, acc_right, _ = _derivatives_of_ride(f, cam, right, step)
    assert np.max(np.abs(acc_left - motion(left)[2])) <= 1e-3 * abs(a_end)
    assert np.max(np.abs(acc_right)) <= 1e-3 * abs(a_end)
    assert np.min(acc_left) >= a_end * (1 + 1e-3)  # no overshoot beyond the law's own step


# --------------------------------------------------------------------------------------------
# Closed forms against outside numbers
# --------------------------------------------------------------------------------------------
class FourierLaw:
    """A smooth periodic law from samples of ``func`` on one turn, evaluated and differentiated as
    its trigonometric interpolant (spectrally exact for these analytic, fast-decaying laws)."""

    def __init__(self, func, n: int = 256):
        theta = TWO_PI * np.arange(n) / n
        self.coef = np.fft.rfft(func(theta)) / n
        self.coef[1:] *= 2.0
        if n % 2 == 0:
            self.coef[-1] /= 2.0
        self.k = np.arange(self.coef.size)
        self.breaks = np.zeros(0)
        self.break_continuity = np.zeros(0, dtype=int)

    def __call__(self, theta):
        theta = np.asarray(theta, dtype=float)
        wave = np.exp(1j * np.multiply.outer(theta, self.k)) * self.coef
        return tuple(np.real(wave @ (1j * self.k) ** m) for m in range(4))


A, R_DISK = 6.0, 30.0  # the eccentric circular cam: a disk of radius 30 mm whose centre is 6 mm from the axis
CENTRE = np.array([0.0, -A])  # in the cam frame: at cam angle 0 the follower rests on the disk's nearest point


def _disk_centre(theta, sigma):
    return np.stack([sigma * A * np.sin(theta), -A * np.cos(theta)], axis=-1)  # R(sigma theta) CENTRE


def eccentric_law(f: FollowerSpec) -> FourierLaw:
    """The law of ``f`` riding the eccentric disk, from plane geometry (circle-circle / circle-line contacts)."""
    sigma, reach = f.sigma, R_DISK + f.roller_radius

    def s(theta):
        c = _disk_centre(theta, sigma)
        if f.motion == "translating":
            if f.kind == "flat":
                return c[:, 1] + R_DISK - f.base_radius  # the face rests on top of the disk
            return c[:, 1] + np.sqrt(reach**2 - (f.offset - c[:, 0]) ** 2) - math.sqrt((f.base_radius + f.roller_radius) ** 2 - f.offset**2)
        o = np.asarray(f.pivot)
        oc = c - o
        dist = np.hypot(*oc.T)
        base = np.arctan2(oc[:, 1], oc[:, 0])
        if f.kind == "flat":  # the face line (X - o) . w = -f tangent to the disk: (o - c) . w = f + R
            g0 = rest_face_angle(f)
            cand = np.stack([base + math.pi + np.arccos((f.face_offset + R_DISK) / dist) * k for k in (1, -1)])
        else:  # roller centre at distance L from the pivot and R + r from the disk centre
            g0 = rest_arm_angle(f)
            cand = np.stack([base + np.arccos((f.arm_length**2 + dist**2 - reach**2) / (2 * f.arm_length * dist)) * k for k in (1, -1)])
        wrapped = np.mod(cand - g0 + math.pi, TWO_PI) - math.pi
        pick = np.argmin(np.abs(wrapped), axis=0)
        return f.tau * wrapped[pick, np.arange(theta.size)]

    return FourierLaw(s)


ECCENTRIC = {
    "roller": dict(kind="roller", base_radius=R_DISK - A, roller_radius=8.0),
    "roller_offset": dict(kind="roller", base_radius=R_DISK - A, roller_radius=8.0, offset=5.0),
    "flat": dict(kind="flat", base_radius=R_DISK - A),
    "knife": dict(kind="knife", base_radius=R_DISK - A, offset=-4.0),
    "osc_roller": dict(kind="roller", base_radius=R_DISK - A, motion="oscillating", roller_radius=8.0, pivot=(70.0, 20.0), arm_length=60.0),
    "osc_knife": dict(kind="knife", base_radius=R_DISK - A, motion="oscillating", pivot=(-60.0, 30.0), arm_length=55.0, lift_turn="cw"),
    "osc_flat": dict(kind="flat", base_radius=R_DISK - A, motion="oscillating", pivot=(70.0, 40.0), face_offset=4.0),
}


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("name", sorted(ECCENTRIC))
def test_eccentric_circular_cam(name, rotation):
    """Every follower riding its law off an eccentric disk must give back the disk: profile radius
    R everywhere, pitch curvature 1 / (R + r), and the contact normal through the disk centre
    (pressure angle: sin(alpha) = a sin(theta) / (R + r) for a centred translating roller, the
    classic eccentric-cam result; flat face: s = a (1 - cos theta), simple harmonic motion)."""
    f = FollowerSpec(**ECCENTRIC[name], rotation=rotation)
    law = eccentric_law(f)
    cam = cam_envelope(f, law)
    pts = cam.profile.evaluate(np.linspace(0, cam.profile.n_segments, 2000, endpoint=False))
    assert np.max(np.abs(np.hypot(*(pts - CENTRE).T) - R_DISK)) <= 2e-7
    assert len(cam.profile.joints()) == 1 and cam.profile.continuity() == "G2"
    theta = np.linspace(0, TWO_PI, 721)
    k = kinematics(f, law, theta)
    assert np.max(np.abs(k.profile_radius - R_DISK)) <= 1e-8
    if f.kind != "flat":
        assert np.max(np.abs(k.pitch_curvature - 1 / (R_DISK + f.roller_radius))) <= 1e-11
        assert np.max(np.abs(k.pitch_radius - (R_DISK + f.roller_radius))) <= 1e-8
    else:
        assert k.pitch_radius is None and cam.pitch is None
    c = _disk_centre(theta, f.sigma)
    if f.kind == "flat":
        normal = np.stack([np.zeros_like(theta), np.ones_like(theta)], -1) if f.motion == "translating" else None
        if f.motion == "translating":
            assert np.max(np.abs(k.s - A * (1 - np.cos(theta)))) <= 1e-12
            assert np.max(np.abs(k.pressure_angle)) == 0.0
        else:  # contact normal w at the point where the disk touches the face; the face point moves about the pivot
            contact = k.follower_point
            normal = (contact - c) / R_DISK
            arm = contact - np.asarray(f.pivot)
            motion_dir = np.stack([-arm[:, 1], arm[:, 0]], -1) / np.hypot(*arm.T)[:, None]
            assert np.max(np.abs(np.abs(k.pressure_angle) - np.arccos(np.abs(np.sum(normal * motion_dir, 1))))) <= 1e-9
        return
    normal = (k.follower_point - c) / (R_DISK + f.roller_radius)
    assert np.max(np.abs(np.hypot(*normal.T) - 1)) <= 1e-12  # the follower point is where the geometry says
    if f.motion == "translating":
        motion_dir = np.tile([0.0, 1.0], (theta.size, 1))
    else:
        arm = k.follower_point - np.asarray(f.pivot)
        motion_dir = np.stack([-arm[:, 1], arm[:, 0]], -1) / f.arm_length
    alpha = np.arccos(np.clip(np.abs(np.sum(normal * motion_dir, 1)), 0, 1))
    assert np.max(np.abs(np.abs(k.pressure_angle) - alpha)) <= 1e-9
    if name == "roller":
        assert np.max(np.abs(np.abs(np.sin(k.pressure_angle)) - A * np.abs(np.sin(theta)) / (R_DISK + f.roller_radius))) <= 1e-12


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("name", ["roller_offset", "flat", "osc_roller", "osc_flat"])
def test_spline_parameter_is_the_cam_angle(name, rotation):
    """The spline's parameter is t = -sigma theta: at t it passes through the contact point of cam
    angle theta, and its second derivative at the segment ends is the exact curve's (which is what
    makes the joints G2 or exactly G1).  Contact points from the eccentric disk's plane geometry."""
    f = FollowerSpec(**ECCENTRIC[name], rotation=rotation)
    law = eccentric_law(f)
    spline = cam_envelope(f, law).profile.segments[0]
    sigma = f.sigma

    def contact(theta):
        s = law(theta)[0]
        c = _disk_centre(theta, sigma)
        if f.kind == "flat":  # the disk touches the face where its normal w points: c + R w
            psi = np.full_like(theta, math.pi / 2) if f.motion == "translating" else rest_face_angle(f) + f.tau * s
            x = c + R_DISK * np.stack([np.cos(psi), np.sin(psi)], -1)
        else:  # on the line from the disk centre to the roller centre
            if f.motion == "translating":
                centre = np.stack([np.full_like(theta, f.offset), math.sqrt((f.base_radius + f.roller_radius) ** 2 - f.offset**2) + s], -1)
            else:
                g = rest_arm_angle(f) + f.tau * s
                centre = np.asarray(f.pivot) + f.arm_length * np.stack([np.cos(g), np.sin(g)], -1)
            x = c + R_DISK * (centre - c) / (R_DISK + f.roller_radius)
        cb, sb = np.cos(-sigma * theta), np.sin(-sigma * theta)
        return np.stack([cb * x[:, 0] - sb * x[:, 1], sb * x[:, 0] + cb * x[:, 1]], -1)

    t = np.linspace(spline.breaks[0], spline.breaks[-1], 1001)
    assert np.max(np.hypot(*(spline.eval_t(t) - contact(-sigma * t)).T)) <= 1e-7
    h = 1e-3
    for end in (spline.breaks[0], spline.breaks[-1]):
        q = contact(-sigma * (end + h * np.arange(-2, 3)))
        second = (-q[0] + 16 * q[1] - 30 * q[2] + 16 * q[3] - q[4]) / (12 * h * h)
        assert np.max(np.abs(spline.eval_t(np.array([end - 1e-12 if end > 0 else end]), 2)[0] - second)) <= 1e-5 * np.max(np.abs(second))


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
@pytest.mark.parametrize("name", ["roller_offset", "osc_roller", "osc_flat", "knife"])
def test_pressure_angle_against_the_contact_normal_of_the_ride(name, rotation):
    """|pressure angle| = angle between the contact normal the ride finds and the follower point's direction of motion."""
    f, motion, cam = built(name, "cycloidal", rotation)
    theta = RIDE_THETA
    position, t = ride_position(f, cam.profile, theta, return_param=True)
    sigma = f.sigma
    c, s_ = np.cos(sigma * theta), np.sin(sigma * theta)
    q = cam.profile.evaluate(t)
    contact = np.stack([c * q[:, 0] - s_ * q[:, 1], s_ * q[:, 0] + c * q[:, 1]], -1)  # fixed frame
    tangent = cam.profile.tangent(t)
    tangent = np.stack([c * tangent[:, 0] - s_ * tangent[:, 1], s_ * tangent[:, 0] + c * tangent[:, 1]], -1)
    normal = np.stack([tangent[:, 1], -tangent[:, 0]], -1)
    if f.motion == "translating":
        direction = np.tile([0.0, 1.0], (theta.size, 1))
    else:
        point = contact if f.kind == "flat" else np.asarray(f.pivot) + f.arm_length * np.stack([np.cos(position), np.sin(position)], -1)
        arm = point - np.asarray(f.pivot)
        direction = np.stack([-arm[:, 1], arm[:, 0]], -1) / np.hypot(*arm.T)[:, None]
    alpha = np.arccos(np.clip(np.abs(np.sum(normal * direction, 1)), 0, 1))
    k = kinematics(f, motion, theta)
    assert np.max(np.abs(np.abs(k.pressure_angle) - alpha)) <= 2e-6
    assert np.max(alpha) > D(10)  # a real test: the pressure angle is not ~0
    if f.kind == "flat":  # the contact position along the face, from the pivot's foot
        w = np.stack([np.cos(position), np.sin(position)], -1)
        xi = np.sum((contact - np.asarray(f.pivot)) * np.stack([-w[:, 1], w[:, 0]], -1), 1)
        # the contact slides along the face by rho * (tangent error ~ fit error / piece length): ~1e-5 mm
        assert np.max(np.abs(k.face_position - xi)) <= 3e-5


def test_centred_roller_pressure_angle_sign_and_norton_formula():
    """Positive during the rise of a centred follower; with an offset, Norton's
    tan(alpha) = (s' - eps) / (s + sqrt(Rp^2 - eps^2)) with eps = offset for ccw, -offset for cw."""
    for rotation, eps_sign in (("ccw", 1.0), ("cw", -1.0)):
        f, motion, _ = built("roller_offset", "harmonic", rotation)
        theta = np.linspace(0, TWO_PI, 3601)
        s, v, _, _ = motion(theta)
        eps = eps_sign * f.offset
        norton = np.arctan((v - eps) / (s + math.sqrt(50.0**2 - eps**2)))
        assert np.max(np.abs(kinematics(f, motion, theta).pressure_angle - norton)) <= 1e-13
    f, motion, _ = built("roller", "harmonic", "ccw")
    rising = (RIDE_THETA > D(5)) & (RIDE_THETA < D(95))
    assert np.all(kinematics(f, motion, RIDE_THETA[rising]).pressure_angle > 0)


@pytest.mark.parametrize("rotation", ["ccw", "cw"])
def test_radius_of_curvature_against_the_ride(rotation):
    """Roller: curvature of the pitch curve = curvature of the roller-centre path the ride finds,
    seen from the cam (finite differences); flat: radius of curvature = h + h'' of the ride height
    (the support function of the cam)."""
    f, motion, cam = built("roller_offset", "poly345", rotation)
    theta = np.linspace(D(2), D(358), 90)
    step = 1e-3
    sample = (theta[:, None] + np.array([-1, 0, 1])[None, :] * step).ravel()
    y = ride_position(f, cam.profile, sample)
    sigma = f.sigma
    centre = np.stack([np.full_like(y, f.offset), y], -1)
    c, s_ = np.cos(-sigma * sample), np.sin(-sigma * sample)
    p = np.stack([c * centre[:, 0] - s_ * centre[:, 1], s_ * centre[:, 0] + c * centre[:, 1]], -1).reshape(-1, 3, 2)
    d1 = (p[:, 2] - p[:, 0]) / (2 * step)
    d2 = (p[:, 2] - 2 * p[:, 1] + p[:, 0]) / step**2
    kappa = -sigma * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3  # the contour runs against theta for ccw
    k = kinematics(f, motion, theta)
    assert np.max(np.abs(kappa - k.pitch_curvature)) <= 1e-5
    assert np.ptp(k.pitch_curvature) > 0.01  # not a circle
    f, motion, cam = built("flat", "poly345", rotation)
    step = 0.02  # five-point second difference: truncation ~ step^4 h^(6) / 90, ride noise ~ 1e-8 / step^2
    sample = (theta[:, None] + np.arange(-2, 3)[None, :] * step).ravel()
    h = ride_position(f, cam.profile, sample).reshape(-1, 5)
    rho = h[:, 2] + (-h[:, 0] + 16 * h[:, 1] - 30 * h[:, 2] + 16 * h[:, 3] - h[:, 4]) / (12 * step**2)
    # away from the breaks, where the stencil would straddle the jerk's jump
    away = np.min(np.abs(np.mod(theta[:, None] - motion.breaks[None, :] + math.pi, TWO_PI) - math.pi), axis=1) > 3 * step
    assert np.max(np.abs(rho - kinematics(f, motion, theta).profile_radius)[away]) <= 1e-4
    assert away.sum() > 70


# --------------------------------------------------------------------------------------------
# Undercut, velocity jumps, parameters
# --------------------------------------------------------------------------------------------
def _ranges(mask, theta):
    edges = np.flatnonzero(np.diff(mask.astype(int)))
    return np.degrees(theta[edges])


def test_flat_undercut_names_the_angles_of_rb_plus_s_plus_s2_below_zero():
    motion = program("cycloidal", 18.0)
    f = FollowerSpec("flat", 12.0)
    theta = np.linspace(0, TWO_PI, 72001)
    s, _, a, _ = motion(theta)
    bad = 12.0 + s + a <= 0  # textbook radius of curvature of a flat follower's cam: rho = Rb + s + s'' (Norton, Design of Machinery, ch. 8)
    edges = _ranges(bad, theta)
    assert edges.size == 4  # two failing stretches
    with pytest.raises(GeometryError, match="undercut.*cam angles") as err:
        cam_envelope(f, motion)
    numbers = [float(x) for part in str(err.value).split("cam angles ")[1].split(" deg")[0].split(", ") for x in part.split("..")]
    assert np.allclose(sorted(numbers), sorted(edges), atol=0.06)
    report = cam_envelope(f, motion, report_only=True)
    assert report.profile is None and report.pitch is None and not report.ok
    assert np.allclose(sorted(v for r in report.failures[0]["ranges_deg"] for v in r), sorted(edges), atol=0.06)


def test_roller_undercut_report_keeps_the_pitch_curve():
    """A roller larger than the pitch curve's convex radius: error naming the angles, or in
    report-only mode the pitch curve (checked against the polar curve Rp + s) and the data."""
    motion = program("harmonic", 18.0, rise=D(60), ret=D(60))
    f = FollowerSpec("roller", 14.0, roller_radius=22.0)
    theta = np.linspace(0, TWO_PI, 36001)
    s, v, a, _ = motion(theta)
    r = 36.0 + s  # centred follower: the pitch curve is the polar curve r(theta); textbook polar radius of curvature
    rho = (r**2 + v**2) ** 1.5 / (r**2 + 2 * v**2 - r * a)
    bad = (rho > 0) & (rho <= 22.0)
    assert bad.any()
    with pytest.raises(GeometryError, match="roller radius 22 mm at cam angles"):
        cam_envelope(f, motion)
    report = cam_envelope(f, motion, report_only=True)
    assert report.profile is None and report.pitch is not None
    found = sorted(v for item in report.failures for rg in item["ranges_deg"] for v in rg)
    assert np.allclose(found, sorted(_ranges(bad, theta)), atol=0.06)
    phi = np.linspace(0, TWO_PI, 500, endpoint=False) + 0.01  # (rays exactly through a joint are ambiguous to polar_radius)
    # ccw: the centre at cam angle theta is at polar angle pi/2 - theta of the cam frame
    assert np.max(np.abs(report.pitch.polar_radius(phi) - (36.0 + motion(math.pi / 2 - phi)[0]))) <= 1e-7


class ConstantVelocity:
    """A rise and return at constant velocity: the velocity jumps at every break."""

    breaks = np.array([0.0, D(120), D(180), D(300)])
    break_continuity = np.zeros(4, dtype=int)

    def __call__(self, theta):
        t = np.mod(np.asarray(theta, dtype=float), TWO_PI)
        v = np.select([t < D(120), t < D(180), t < D(300)], [10 / D(120), 0.0, -10 / D(120)], 0.0)
        s = np.select([t < D(120), t < D(180), t < D(300)], [t * 10 / D(120), 10.0, 10 - (t - D(180)) * 10 / D(120)], 0.0)
        return s, v, np.zeros_like(t), np.zeros_like(t)


def test_velocity_jumps_give_a_knife_corners_and_refuse_rollers():
    law = ConstantVelocity()
    f = FollowerSpec("knife", 40.0, offset=3.0)
    cam = cam_envelope(f, law).profile
    assert [j.continuity for j in cam.joints()] == ["G0"] * 4
    error = np.max(np.abs(ride.translating_knife(cam, RIDE_THETA, 3.0) - required_position(f, law(RIDE_THETA)[0])))
    assert error <= 1e-6
    with pytest.raises(GeometryError, match=r"velocity jumps at cam angles 0\.000, 120\.000, 180\.000, 300\.000 deg"):
        cam_envelope(FollowerSpec("roller", 40.0, roller_radius=5.0), law)


@pytest.mark.parametrize("changes, name, text", [
    (dict(kind="ball"), "kind", "roller"),
    (dict(rotation="clockwise"), "rotation", "ccw"),
    (dict(base_radius=0.0), "base_radius", "> 0"),
    (dict(roller_radius=0.0), "roller_radius", "> 0"),
    (dict(offset=50.0), "offset", "prime radius = 50"),
    (dict(offset=float("nan")), "offset", "finite"),
    (dict(pivot=(100.0, 0.0)), "pivot", "None for a translating"),
    (dict(motion="oscillating"), "offset", "0 for an oscillating"),
    (dict(motion="oscillating", offset=0.0), "pivot", r"\(x, y\)"),
    (dict(motion="oscillating", offset=0.0, pivot=(30.0, 0.0), arm_length=40.0), "pivot", "farther than the prime radius 50"),
    (dict(motion="oscillating", offset=0.0, pivot=(100.0, 0.0), arm_length=20.0), "arm_length", "50 < arm_length < 150"),
    (dict(motion="oscillating", offset=0.0, pivot=(100.0, 0.0), arm_length=60.0, lift_turn="up"), "lift_turn", "ccw"),
])
def test_parameters_are_validated(changes, name, text):
    with pytest.raises(ParameterError, match=f"'{name}'.*{text}"):
        FollowerSpec(**{"kind": "roller", "base_radius": 40.0, "roller_radius": 10.0, "offset": 5.0, **changes})


def test_flat_and_knife_parameters():
    with pytest.raises(ParameterError, match="'roller_radius'.*0 for a flat"):
        FollowerSpec("flat", 40.0, roller_radius=5.0)
    with pytest.raises(ParameterError, match="'face_offset'.*tangent to the base circle"):
        FollowerSpec("flat", 40.0, motion="oscillating", pivot=(60.0, 0.0), face_offset=30.0)
    with pytest.raises(ParameterError, match="'arm_length'.*0 for an oscillating flat"):
        FollowerSpec("flat", 40.0, motion="oscillating", pivot=(60.0, 0.0), arm_length=30.0)
    FollowerSpec("flat", 40.0, offset=500.0)  # a flat face's offset only moves the face centre
