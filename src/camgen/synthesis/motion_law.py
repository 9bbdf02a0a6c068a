"""Disk cams from classic motion laws: exact envelopes for translating roller and flat followers.

A motion program is a sequence of segments (rise, dwell, return) covering one cam turn; each
segment follows a normalised law ``S(tau)`` on ``tau in [0, 1]`` with ``S(0) = 0``,
``S(1) = 1`` and zero velocity at both ends (the standard double-dwell laws):

* ``cycloidal``: ``tau - sin(2 pi tau) / (2 pi)`` (zero acceleration at the ends);
* ``harmonic``: ``(1 - cos(pi tau)) / 2`` (acceleration jumps at the ends);
* ``poly345``: ``10 tau^3 - 15 tau^4 + 6 tau^5``;
* ``poly4567``: ``35 tau^4 - 84 tau^5 + 70 tau^6 - 20 tau^7`` (zero jerk at the ends).

Followers (the cam turns counter-clockwise by ``theta``; the follower moves along ``+y``):

* translating roller of radius ``r`` on an axis offset by ``e`` (along ``d_perp``, the motion
  direction turned by +90 deg, i.e. ``x = -e``): the roller centre is
  ``C(theta) = e d_perp + (sqrt(Rp^2 - e^2) + s) d`` with the prime radius ``Rp = Rb + r``; the
  pitch curve is ``Rot(-theta) C(theta)`` (a periodic C2 spline through N samples) and the cam
  is its inward offset by ``r`` -- the exact envelope, not the radial shortcut ``Rb + s``
  (which is what several peers export, see shared/research/peers.md);
* translating flat face normal to its motion: the support function of the cam is
  ``h(psi) = Rb + s(theta)`` at ``psi = pi/2 - theta``, so the contact point is
  ``h u(psi) + h'(psi) u_perp(psi)`` exactly; undercut where ``Rb + s + s'' <= 0``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from camgen.contour import Contour, Spline
from camgen.errors import (
    GeometryError,
    ParameterError,
    UndercutError,
    require_finite,
    require_positive,
)

TWO_PI = 2.0 * math.pi


def _cycloidal(t: np.ndarray) -> tuple[np.ndarray, ...]:
    w = TWO_PI
    return (t - np.sin(w * t) / w, 1 - np.cos(w * t), w * np.sin(w * t), w * w * np.cos(w * t))


def _harmonic(t: np.ndarray) -> tuple[np.ndarray, ...]:
    p = math.pi
    return ((1 - np.cos(p * t)) / 2, p / 2 * np.sin(p * t), p * p / 2 * np.cos(p * t), -(p**3) / 2 * np.sin(p * t))


def _polynomial(coeffs: dict[int, float]):
    def law(t: np.ndarray) -> tuple[np.ndarray, ...]:
        out = []
        for order in range(4):
            total = np.zeros_like(t)
            for power, c in coeffs.items():
                if power >= order:
                    factor = math.prod(range(power - order + 1, power + 1))
                    total = total + c * factor * t ** (power - order)
            out.append(total)
        return tuple(out)

    return law


LAWS = {
    "cycloidal": _cycloidal,
    "harmonic": _harmonic,
    "poly345": _polynomial({3: 10.0, 4: -15.0, 5: 6.0}),
    "poly4567": _polynomial({4: 35.0, 5: -84.0, 6: 70.0, 7: -20.0}),
}


@dataclass(frozen=True)
class MotionSegment:
    """One segment: ``law`` (see LAWS; ignored for a dwell), ``span`` (rad), ``lift`` (mm;
    > 0 rise, < 0 return, 0 dwell)."""

    law: str
    span: float
    lift: float

    def __post_init__(self) -> None:
        if self.lift != 0 and self.law not in LAWS:
            raise ParameterError("law", self.law, f"one of {sorted(LAWS)}")
        require_positive("span", self.span, "rad")
        require_finite("lift", self.lift)


class MotionProgram:
    """Follower displacement over one cam turn, from consecutive segments.

    Raises :class:`ParameterError` unless the spans add up to 360 deg and the lifts to zero.
    """

    def __init__(self, segments: Sequence[MotionSegment]) -> None:
        self.segments = tuple(segments)
        if not self.segments:
            raise ParameterError("segments", [], "at least one segment")
        total = sum(s.span for s in self.segments)
        if abs(total - TWO_PI) > 1e-9:
            raise ParameterError("segments", f"spans adding up to {math.degrees(total):.6g} deg", "spans adding up to 360 deg")
        net = sum(s.lift for s in self.segments)
        if abs(net) > 1e-9 * max(1.0, max(abs(s.lift) for s in self.segments)):
            raise ParameterError("segments", f"lifts adding up to {net:.6g} mm", "lifts adding up to 0 mm (the follower returns)")
        self.starts = np.concatenate([[0.0], np.cumsum([s.span for s in self.segments])[:-1]])
        self.levels = np.concatenate([[0.0], np.cumsum([s.lift for s in self.segments])[:-1]])

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """s (mm), ds/dtheta (mm/rad), d2s (mm/rad^2), d3s (mm/rad^3) at cam angles ``theta`` (rad)."""
        theta = np.mod(np.asarray(theta, dtype=float), TWO_PI)
        out = [np.zeros_like(theta) for _ in range(4)]
        index = np.clip(np.searchsorted(self.starts, theta, side="right") - 1, 0, len(self.segments) - 1)
        for k, seg in enumerate(self.segments):
            mask = index == k
            if not mask.any():
                continue
            out[0][mask] = self.levels[k]
            if seg.lift == 0:
                continue
            tau = (theta[mask] - self.starts[k]) / seg.span
            values = LAWS[seg.law](tau)
            for order in range(4):
                out[order][mask] += seg.lift * values[order] / seg.span**order
        return out[0], out[1], out[2], out[3]

    @property
    def stroke(self) -> float:
        levels = np.append(self.levels, 0.0)
        return float(levels.max() - levels.min())


def roller_cam(program: MotionProgram, base_radius: float, roller_radius: float, offset: float = 0.0,
               samples: int = 720, offset_tol: float = 1e-9) -> tuple[Contour, Contour]:
    """Cam profile and pitch curve (both :class:`Contour`) for a translating roller follower.

    ``base_radius`` (mm) is the smallest cam radius on the follower axis side (prime radius
    minus the roller); ``offset`` (mm) as in the module docstring.
    """
    base_radius = require_positive("base_radius", base_radius)
    roller_radius = require_positive("roller_radius", roller_radius)
    prime = base_radius + roller_radius
    offset = require_finite("offset", offset)
    if abs(offset) >= prime:
        raise ParameterError("offset", offset, f"|offset| < prime radius = {prime:g} mm")
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 36:
        raise ParameterError("samples", samples, "an integer >= 36")
    phi = TWO_PI * np.arange(samples + 1) / samples  # counter-clockwise parameter; cam angle -phi
    theta = -phi
    s, _, _, _ = program(theta)
    d0 = math.sqrt(prime * prime - offset * offset)
    # motion direction d = +y, d_perp = -x: C = (-e, d0 + s), seen from the cam: Rot(-theta) C
    cx, cy = -offset, d0 + s
    c, sn = np.cos(-theta), np.sin(-theta)
    pts = np.stack([c * cx - sn * cy, sn * cx + c * cy], axis=1)
    pts[-1] = pts[0]
    pitch = Contour([Spline.interpolate(phi, pts, periodic=True)])
    try:
        profile = pitch.offset(-roller_radius, spline_tol=offset_tol)
    except GeometryError as exc:
        raise UndercutError(f"roller of radius {roller_radius:g} mm undercuts this cam: {exc}", pitch=pitch,
                            limit=roller_radius) from None
    return profile, pitch


def flat_cam(program: MotionProgram, base_radius: float, samples: int = 720) -> Contour:
    """Cam profile (exact envelope) for a translating flat-faced follower normal to its motion."""
    base_radius = require_positive("base_radius", base_radius)
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 36:
        raise ParameterError("samples", samples, "an integer >= 36")
    psi = math.pi / 2 + TWO_PI * np.arange(samples + 1) / samples  # face normal in the cam frame
    theta = math.pi / 2 - psi
    s, ds, d2s, _ = program(theta)
    rho = base_radius + s + d2s  # radius of curvature of the envelope: h + h''
    if np.any(rho <= 0):
        worst = float(np.mod(theta[np.argmin(rho)], TWO_PI))
        from camgen.checks import run_ends

        cam_angle = np.mod(theta[:-1], TWO_PI)
        order = np.argsort(cam_angle)
        raise UndercutError(
            f"the flat follower undercuts the cam at cam angle {math.degrees(worst):.3f} deg "
            f"(radius of curvature Rb + s + s'' = {float(rho.min()):.4g} mm <= 0): use a larger base radius",
            curve=(cam_angle[order], rho[:-1][order]), limit=0.0, where_deg=run_ends(rho[:-1][order] <= 0, cam_angle[order]),
        )
    h = base_radius + s
    dh = -ds  # dh/dpsi = -ds/dtheta
    u = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    u_perp = np.stack([-np.sin(psi), np.cos(psi)], axis=1)
    pts = h[:, None] * u + dh[:, None] * u_perp
    pts[-1] = pts[0]
    return Contour([Spline.interpolate(psi - psi[0], pts, periodic=True)])
