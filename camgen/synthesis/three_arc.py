"""Constant-breadth three-center cam and its flat-faced double (yoke) follower law.

Paper 000 (Wang et al. 2019), Section 4.1, Figure 5, Table 1 and eq. (1).

Construction (cam frame, origin on the pivot O, angles counter-clockwise):

* O' and O'' lie at distance ``a`` from O with ``|O'O''| = b``, symmetric about the -x axis:
  O' at polar angle ``pi + theta_x / 2``, O'' at ``pi - theta_x / 2``, with
  ``theta_x = 2 asin(b / 2a)`` (eq. 1), the angle O'OO''.
* Six arcs HB, BC, CD, DF, FG, GH with centres O, O', O'', O, O', O'' and radii
  ``c, a+c, a+c-b, 2a+c-b, a+c-b, a+c``.  HB (the dwell nearest the axis, the base circle)
  is centred on the +x axis and spans ``theta_x``; DF spans ``theta_x`` around the -x axis;
  the four flank arcs each span ``pi/2 - theta_x/2``.
* Opposite arcs share a centre and their radii add up to ``2a + 2c - b``: that is the breadth,
  the same in every direction.

Domain where the construction holds (each bound is a radius or sweep that must stay > 0):

* ``a > 0``;
* ``c > 0``: the base arc HB has radius ``c``;
* ``b > 0``: the base and outer arcs HB and DF sweep ``theta_x``, zero at ``b = 0``;
* ``b < 2a``: ``theta_x = 2 asin(b / 2a)`` needs ``b / 2a < 1``; at ``b = 2a`` the flank arcs
  sweep ``pi/2 - theta_x/2 = 0``;
* ``b < a + c``: the arcs CD and FG have radius ``a + c - b``.

Table 1 of the paper gives, for the contact point N of polar angle ``phi`` (input angle),
the output angle ``beta`` between ON and the contact normal, and the radius vector
``R = |ON|``.  The face normal points along ``psi = phi + beta10`` with
``beta10 = -beta SIGN(phi)`` (paper 000, Section 4.3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from camgen.contour import Arc, Contour
from camgen.errors import ParameterError, require_positive
from camgen.geometry import wrap_pi

__all__ = [
    "YokeMotion", "breadth", "contact_from_normal", "normal_angle", "region_bounds", "sign", "theta_x",
    "three_arc_cam", "validate_three_arc", "yoke_law", "yoke_motion",
]


def validate_three_arc(a: float, b: float, c: float) -> tuple[float, float, float]:
    """Check ``(a, b, c)`` (mm) against the domain in the module docstring; return them as floats.

    Raises
    ------
    ParameterError
        Naming the first parameter outside the domain, its value and the valid range.
    """
    a = require_positive("a", a)
    c = require_positive("c", c)
    b = require_positive("b", b)
    upper = min(2.0 * a, a + c)
    if b >= upper:
        if 2.0 * a <= a + c:
            why = "theta_x = 2 asin(b / 2a) needs b < 2a, and the flank arcs sweep pi/2 - theta_x/2 > 0"
        else:
            why = "the arcs CD and FG have radius a + c - b, which must be > 0"
        raise ParameterError("b", b, f"0 < b < min(2a, a + c) = {upper:g} mm for a = {a:g} mm, c = {c:g} mm", why)
    return a, b, c


def theta_x(a: float, b: float) -> float:
    """Angle O'OO'' between the two off-axis centres, rad (paper 000, eq. 1)."""
    return 2.0 * math.asin(b / (2.0 * a))


def breadth(a: float, b: float, c: float) -> float:
    """Constant breadth of the cam, mm: the distance between the two parallel yoke faces."""
    return 2.0 * a + 2.0 * c - b


def three_arc_cam(a: float, b: float, c: float) -> Contour:
    """The exact six-arc constant-breadth three-center cam (paper 000, Fig. 5).

    Parameters
    ----------
    a : float
        Distance of the off-axis centres O', O'' from the pivot O, mm.
    b : float
        Distance between O' and O'', mm.
    c : float
        Base-circle radius (radius of the dwell arc HB about O), mm.

    Returns
    -------
    Contour
        Six arcs HB, BC, CD, DF, FG, GH, counter-clockwise, starting at H.
    """
    a, b, c = validate_three_arc(a, b, c)
    half = 0.5 * theta_x(a, b)
    flank = 0.5 * math.pi - half
    o = (0.0, 0.0)
    o1 = (-a * math.cos(half), -a * math.sin(half))  # O', polar angle pi + theta_x/2
    o2 = (-a * math.cos(half), a * math.sin(half))  # O'', polar angle pi - theta_x/2
    arcs = [
        Arc(o, c, -half, 2.0 * half),  # HB: base dwell
        Arc(o1, a + c, half, flank),  # BC
        Arc(o2, a + c - b, 0.5 * math.pi, flank),  # CD
        Arc(o, 2.0 * a + c - b, math.pi - half, 2.0 * half),  # DF: outer dwell
        Arc(o1, a + c - b, math.pi + half, flank),  # FG
        Arc(o2, a + c, 1.5 * math.pi, flank),  # GH
    ]
    return Contour(arcs)


def region_bounds(a: float, b: float, c: float) -> tuple[float, float, float]:
    """The three values of ``|phi|`` (rad) that separate the four rows of Table 1.

    ``theta_x / 2`` (point B), ``pi/2 + atan(sqrt(a^2 - b^2/4) / (a + c - b/2))`` (point C),
    ``pi - theta_x / 2`` (point D).
    """
    a, b, c = validate_three_arc(a, b, c)
    half = 0.5 * theta_x(a, b)
    phi_c = 0.5 * math.pi + math.atan(math.sqrt(a * a - 0.25 * b * b) / (a + c - 0.5 * b))
    return half, phi_c, math.pi - half


def sign(phi: np.ndarray) -> np.ndarray:
    """SIGN of paper 000, eq. (1): +1 for phi >= 0, -1 for phi < 0."""
    return np.where(np.asarray(phi) >= 0.0, 1.0, -1.0)


def yoke_law(a: float, b: float, c: float, phi: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Table 1: output angle ``beta`` (rad) and radius vector ``R`` (mm) for input angles ``phi``.

    ``phi`` is the polar angle of the contact point N (rad, wrapped to [-pi, pi)).  ``R`` is
    computed by projecting the triangle O-centre-N on ON,
    ``R = r cos(beta) - a cos(|phi| -/+ theta_x / 2)``, which equals Table 1's sine-rule form
    ``a sin(|phi| - beta -/+ theta_x/2) / sin(beta)`` but stays finite where ``beta -> 0``
    at the region boundaries B and D.
    """
    a, b, c = validate_three_arc(a, b, c)
    phi = wrap_pi(phi)
    ap = np.abs(phi)
    half, phi_c, phi_d = region_bounds(a, b, c)
    in2 = (ap > half) & (ap <= phi_c)
    in3 = (ap > phi_c) & (ap <= phi_d)
    beta2 = np.arcsin(np.clip(a / (a + c) * np.sin(ap - half), -1.0, 1.0))
    beta3 = np.arcsin(np.clip(a / (a + c - b) * np.sin(ap + half), -1.0, 1.0))
    r2 = (a + c) * np.cos(beta2) - a * np.cos(ap - half)
    r3 = (a + c - b) * np.cos(beta3) - a * np.cos(ap + half)
    beta = np.where(in2, beta2, np.where(in3, beta3, 0.0))
    radius = np.where(ap <= half, c, np.where(in2, r2, np.where(in3, r3, 2.0 * a + c - b)))
    return beta, radius


def normal_angle(phi: object, beta: object) -> np.ndarray:
    """Follower face normal direction ``psi = phi + beta10``, ``beta10 = -beta SIGN(phi)`` (rad)."""
    phi = np.asarray(phi, dtype=float)
    return phi - np.asarray(beta, dtype=float) * sign(phi)


def contact_from_normal(contour: Contour, psi: object) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Inverse of Table 1: for face normal directions ``psi`` (rad) the contact point's
    input angle ``phi`` (rad, in [-pi, pi)), output angle ``beta`` (rad) and radius vector ``R`` (mm)."""
    psi = np.asarray(psi, dtype=float)
    _, point = contour.support_point(psi)
    phi = np.arctan2(point[..., 1], point[..., 0])
    radius = np.hypot(point[..., 0], point[..., 1])
    beta = np.abs(wrap_pi(psi - phi))
    return phi, beta, radius


@dataclass(frozen=True)
class YokeMotion:
    """Translating yoke motion per unit cam speed.

    Attributes
    ----------
    cam_angle : array
        Cam rotation angle theta, rad (counter-clockwise).
    displacement : array
        Distance from the cam axis to the face touching the cam, mm.
    velocity : array
        d(displacement)/d(theta), mm/rad (multiply by omega in rad/s for mm/s).
    acceleration : array
        d2(displacement)/d(theta)2, mm/rad^2 (multiply by omega^2 for mm/s^2).
    """

    cam_angle: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


def yoke_motion(contour: Contour, cam_angle: object, face_normal: float = 0.0) -> YokeMotion:
    """Motion of a translating flat-faced yoke driven by ``contour``.

    The yoke slides along the fixed direction ``face_normal`` (rad); the cam turns
    counter-clockwise by ``cam_angle``, so the face normal seen in the cam frame is
    ``psi = face_normal - cam_angle`` and the displacement is the support function
    ``s = h(psi)``, ``ds/dtheta = -h'(psi)``, ``d2s/dtheta2 = h''(psi) = rho - h``.
    The opposite face sits at ``s - breadth`` for a constant-breadth cam.
    """
    theta = np.asarray(cam_angle, dtype=float)
    h, dh, d2h = contour.support_derivatives(face_normal - theta)
    return YokeMotion(theta, h, -dh, d2h)
