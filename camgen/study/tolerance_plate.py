"""The follower's motion riding a plate cam as made: the ride re-simulated on perturbed geometry.

A plate cam (any displacement law) with a translating follower (roller, knife or flat face) or
an oscillating roller or knife (conventions: :mod:`camgen.synthesis.followers`).  Every sample is one cam as made and one
follower as assembled (:data:`camgen.study.tolerance_errors.PLATE_ERRORS`):

* the nominal profile ``Q`` (exact, from the law: :func:`camgen.synthesis.followers.kinematics`)
  with its outward unit normal ``N``, made as ``(1 + k) Q + delta N`` (scale ``k``, normal offset
  ``delta``; a uniform scale keeps the normals), turned back against the rotation by the phase
  error ``phi``: the cam frame's ``R(-sigma phi)``;
* a roller of radius ``r + dr`` (a knife: ``r = 0``) on the line ``x = e + de``, or on an arm of
  length ``L`` about the pivot ``p`` moved away from the cam axis by ``dc`` (the centre distance).

**Contact (exact, no root finding).**  The roller centre riding the made cam is the made pitch
curve ``P = (1 + k) Q + (delta + r + dr) N`` (the made profile offset by the roller radius,
turned): every point ``P_i`` of it reaches the follower line ``x = e'`` at the one cam angle
where ``R(sigma theta) P_i`` lies on the line above the axis,
``theta_i = sigma (acos(e' / |P_i|) - arg P_i)``, with the follower at ``y_i = sqrt(|P_i|^2 - e'^2)``.
On an oscillating arm the point reaches the arm's circle ``|X - p'| = L`` where
``cos(arg P_i + sigma theta - arg p') = (|P_i|^2 + |p'|^2 - L^2) / (2 |P_i| |p'|)`` (the root on the
nominal cam's side of the line from the axis to the pivot), and the swing is the arm's angle
from its nominal rest angle.  A flat face touches the point whose fixed-frame normal is ``+y``:
``theta_i = sigma (pi / 2 - arg N_i) + phi`` and ``y_i = (1 + k) Q_i . N_i + delta`` (the support
function).  The follower position at the output angles is the linear interpolation of
``(theta_i, y_i)`` over :data:`PROFILE_POINTS` points a turn (periodic; its error is below
``h^2 max|y''| / 8`` with ``h = 2 pi / PROFILE_POINTS``: 2e-6 mm for the plate_cam template).  The
motion error is that position minus the nominal ``rest_height + s(theta)``.

The pressure angle of the made cam (roller, knife) is the angle between the made normal at the
contact and the follower's direction of motion (``+y``; an arm: perpendicular to it), at every
profile point.  The error is in mm (translating) or deg of swing (oscillating).

All samples of a chunk are one numpy pass (arrays (samples, points)).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camgen.errors import GeometryError, ParameterError

__all__ = ["CHUNK", "OUTPUT_ANGLES", "PROFILE_POINTS", "PlateNominal", "PlateRide", "plate_nominal", "ride_plate"]

#: Profile points a turn at which the made cam is rebuilt (the contact's interpolation grid).
PROFILE_POINTS = 8192
#: Cam angles a turn at which the follower motion error is given (0.1 deg apart).
OUTPUT_ANGLES = 3600
#: Samples computed in one numpy pass (memory: a few arrays of CHUNK x PROFILE_POINTS floats).
CHUNK = 128


@dataclass(frozen=True)
class PlateNominal:
    """The nominal plate cam at :data:`PROFILE_POINTS` cam angles: ``theta`` (rad), the contact
    ``profile`` and its outward unit ``normal`` (cam frame, complex ``x + i y``, mm), the follower
    (``contact`` ``"point"`` or ``"face"``, ``roller`` radius mm, ``offset`` mm, ``sigma`` +1 ccw /
    -1 cw, ``rest`` the follower's y at zero lift, mm) and ``law`` (the displacement law, mm; an
    oscillating follower's swing, rad).  Oscillating (``pivot`` not None): the ``pivot`` (complex,
    mm), ``arm`` length (mm), ``tau`` (+1: a positive swing turns the arm ccw), ``rest`` the arm's
    angle at zero swing (rad) and ``branch`` (+-1 per point: the side of the line from the axis to
    the pivot where the nominal contact reaches the arm's circle)."""

    theta: np.ndarray
    profile: np.ndarray
    normal: np.ndarray
    contact: str
    roller: float
    offset: float
    sigma: float
    rest: float
    law: Any  # camgen.synthesis.followers.Displacement
    pivot: complex | None = None
    arm: float = 0.0
    tau: float = 1.0
    branch: np.ndarray | None = None

    @property
    def unit(self) -> str:
        """The unit of the motion error: ``"mm"`` (translating) or ``"deg"`` (an oscillating swing)."""
        return "mm" if self.pivot is None else "deg"

    def nominal_position(self, theta: np.ndarray) -> np.ndarray:
        """The nominal follower position at cam angles ``theta`` (rad): ``rest + s(theta)`` (mm), or
        an oscillating follower's swing ``s(theta)`` (rad)."""
        s = np.asarray(self.law(np.ravel(theta))[0], dtype=float).reshape(np.shape(theta))
        return s if self.pivot is not None else self.rest + s


@dataclass(frozen=True)
class PlateRide:
    """The rides of a set of samples: ``theta`` the output cam angles (rad, (M,)), ``error`` the
    follower motion error there ((S, M), mm or deg of swing) and ``pressure_peak`` the peak |pressure angle| of
    each made cam ((S,), rad; None for a flat face, whose pressure angle is 0)."""

    theta: np.ndarray
    error: np.ndarray
    pressure_peak: np.ndarray | None


def plate_nominal(follower: Any, law: Any, points: int = PROFILE_POINTS) -> PlateNominal:
    """The nominal cam of ``follower`` (a :class:`~camgen.synthesis.followers.FollowerSpec`:
    translating, or an oscillating roller or knife) and ``law``, sampled at ``points`` uniform cam angles."""
    from camgen.synthesis.followers import kinematics

    if follower.motion != "translating" and follower.contact == "face":
        raise ParameterError("follower", follower.kind, "a roller or knife on an oscillating arm (camgen tolerance)",
                             "the oscillating face's perturbed ride is not modelled yet")
    theta = 2.0 * math.pi * np.arange(points) / points
    k = kinematics(follower, law, theta)
    profile = k.contact_point[:, 0] + 1j * k.contact_point[:, 1]
    if follower.contact == "point" and follower.has_radius and k.pitch_point is not None:
        pitch = k.pitch_point[:, 0] + 1j * k.pitch_point[:, 1]
        normal = (pitch - profile) / follower.roller_radius
    else:  # the tangent along the contour (t = -sigma theta runs counter-clockwise), turned clockwise
        assert k.contact_d1 is not None  # kinematics() gives the exact derivative of the contact
        tangent = -follower.sigma * (k.contact_d1[:, 0] + 1j * k.contact_d1[:, 1])
        normal = -1j * tangent / np.abs(tangent)
    if follower.motion == "oscillating":
        assert k.pitch_point is not None  # a roller or knife has a pitch curve
        pitch = k.pitch_point[:, 0] + 1j * k.pitch_point[:, 1]
        pivot = complex(*follower.pivot_xy)
        branch = np.where(_wrap(np.angle(pitch) + follower.sigma * theta - np.angle(pivot)) >= 0.0, 1.0, -1.0)
        return PlateNominal(theta, profile, normal, follower.contact, follower.roller_radius, 0.0, follower.sigma,
                            follower.rest_arm_angle, law, pivot, follower.arm_length, follower.tau, branch)
    rest = follower.base_radius if follower.contact == "face" else follower.rest_height
    return PlateNominal(theta, profile, normal, follower.contact, follower.roller_radius, follower.offset, follower.sigma, rest, law)


def _wrap(angle: np.ndarray) -> np.ndarray:
    """Angles (rad) wrapped into [-pi, pi] (the nearest multiple of 2 pi taken off)."""
    return angle - (2.0 * math.pi) * np.round(angle / (2.0 * math.pi))


def ride_plate(nominal: PlateNominal, errors: dict[str, np.ndarray], samples: int, angles: int = OUTPUT_ANGLES) -> PlateRide:
    """The follower motion error of ``samples`` made cams at ``angles`` cam angles a turn (mm, or
    deg of swing for an oscillating follower).

    ``errors``: error name -> (samples,) values in the error's unit (names of
    :data:`~camgen.study.tolerance_errors.PLATE_ERRORS`; a missing name is no error).
    """
    out_theta = 2.0 * math.pi * np.arange(angles) / angles
    nominal_out = nominal.nominal_position(out_theta)
    zero = np.zeros(samples)
    delta = errors.get("profile_offset_mm", zero)
    scale = 1.0 + errors.get("profile_scale", zero)
    de = errors.get("follower_offset_mm", zero)
    dc = errors.get("centre_distance_mm", zero)
    dr = errors.get("roller_radius_mm", zero)
    phase = np.radians(errors.get("phase_deg", zero))
    if nominal.contact == "face" and np.any(dr != 0):
        raise ParameterError("roller_radius_mm", "an error", "no roller-radius error: a flat face has no roller")
    if nominal.roller == 0.0 and nominal.contact == "point" and np.any(dr != 0):
        raise ParameterError("roller_radius_mm", "an error", "no roller-radius error: a knife edge has no roller")
    if np.any(scale <= 0.0):
        raise GeometryError("a profile scale error <= -1 leaves no cam")
    if nominal.contact == "point" and np.any(nominal.roller + dr <= 0.0) and nominal.roller > 0.0:
        raise GeometryError(f"a roller-radius error makes the roller radius <= 0 (nominal {nominal.roller:g} mm)")
    sigma = nominal.sigma
    error = np.empty((samples, angles))
    peak = None if nominal.contact == "face" else np.empty(samples)
    for lo in range(0, samples, CHUNK):
        sl = slice(lo, min(lo + CHUNK, samples))
        turn = np.exp(-1j * sigma * phase[sl])[:, None]
        normal = turn * nominal.normal[None, :]
        if nominal.contact == "face":
            theta = sigma * (0.5 * math.pi - np.angle(normal))
            y = scale[sl, None] * (nominal.profile.real * nominal.normal.real + nominal.profile.imag * nominal.normal.imag)[None, :]
            y = y + delta[sl, None]
        else:
            pitch = turn * (scale[sl, None] * nominal.profile[None, :] + (delta[sl] + nominal.roller + dr[sl])[:, None] * nominal.normal[None, :])
            radius = np.abs(pitch)
            if nominal.pivot is None:
                e = (nominal.offset + de[sl])[:, None]
                if np.any(np.abs(e) >= radius):
                    raise GeometryError("a made cam does not reach the follower line (|offset| >= the pitch radius): the errors are too large")
                theta = sigma * (np.arccos(e / radius) - np.angle(pitch))
                y = np.sqrt(radius * radius - e * e)
                motion = np.full((1, 1), 0.5 * math.pi)
            else:
                theta, y, motion = _on_arm(nominal, pitch, radius, dc[sl])
        # every point reaches the follower about `phase` later than on the nominal cam: unwrapped about that
        shift = phase[sl, None]
        theta = nominal.theta[None, :] + shift + _wrap(theta - nominal.theta[None, :] - shift)
        if np.any(np.diff(theta, axis=1) <= 0):
            raise GeometryError("a made cam's contact runs back along the profile (an undercut of the made cam): the errors are too large")
        turn_theta = np.concatenate([theta - 2.0 * math.pi, theta, theta + 2.0 * math.pi], axis=1)  # periodic, still sorted
        turn_y = np.concatenate([y, y, y], axis=1)
        for row in range(theta.shape[0]):
            error[lo + row] = np.interp(out_theta, turn_theta[row], turn_y[row]) - nominal_out
        if peak is not None:  # the made normal at the contact against the follower's direction of motion
            fixed = np.angle(normal) + sigma * theta
            peak[sl] = np.max(np.abs(_wrap(fixed - motion)), axis=1)
    if nominal.pivot is not None:
        error = np.degrees(error)
    return PlateRide(out_theta, error, peak)


def _on_arm(nominal: PlateNominal, pitch: np.ndarray, radius: np.ndarray, dc: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where each made pitch point (samples, points) reaches the arm's circle about the pivot moved
    away from the axis by ``dc`` (samples,): the cam angle, the swing (rad) and the direction of
    the roller centre's motion there (rad, fixed frame)."""
    assert nominal.pivot is not None and nominal.branch is not None
    pivot = nominal.pivot * ((abs(nominal.pivot) + dc) / abs(nominal.pivot))[:, None]  # (samples, 1)
    distance, towards = np.abs(pivot), np.angle(pivot)
    cosine = (radius * radius + distance * distance - nominal.arm**2) / (2.0 * radius * distance)
    if np.any(np.abs(cosine) > 1.0):
        raise GeometryError("a made cam does not reach the arm's circle about the pivot: the errors are too large")
    polar = towards + nominal.branch[None, :] * np.arccos(cosine)  # the point's polar angle in the fixed frame
    theta = nominal.sigma * (polar - np.angle(pitch))
    arm = np.angle(radius * np.exp(1j * polar) - pivot)
    swing = nominal.tau * _wrap(arm - nominal.rest)
    return theta, swing, arm + nominal.tau * 0.5 * math.pi
