"""The harmonic content of a cam's law: the amplitudes of the first :data:`ACCELERATION_HARMONICS`
harmonics of the follower's acceleration over one turn (issue 26 item 5).

The acceleration ``s''(theta)`` over a turn is ``sum_n A_n cos(n theta + p_n)``; at a cam speed
``w`` (rad/s) harmonic ``n`` is a vibration at ``n`` times the turn frequency with amplitude
``w^2 A_n`` (what a train whose natural frequency lies near it feels: Koster, *Vibrations of cam
mechanisms*, 1974, ch. 3).  The amplitudes are those the machine job's compliant train reports,
from the same code (:func:`camgen.compliant.sample_spectrum`): the Fourier integrals of the
piecewise-linear interpolant ``I_h a`` of the acceleration at the cam's motion samples (a uniform
grid of ``m`` cam angles, stated in report.json).  Each amplitude is within ``(1/pi) int |a - I_h
a| dtheta`` of the law's own (the triangle inequality on the Fourier integral): ``O(h^2)``, ``h =
2 pi / m``, for a law whose acceleration is continuous, ``O(h)`` where it jumps.  On a pure
harmonic ``cos(n theta)`` the interpolant's amplitude is exactly ``sinc^2(n h / 2)`` times it.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from camgen.checks import Motion

__all__ = ["ACCELERATION_HARMONICS", "acceleration_harmonics", "harmonic_figures"]

#: Harmonics of the turn reported per cam (n = 1 .. this).
ACCELERATION_HARMONICS = 20


def acceleration_harmonics(motion: "Motion", harmonics: int = ACCELERATION_HARMONICS) -> np.ndarray:
    """Amplitudes ``A_1 .. A_harmonics`` of the follower's acceleration per unit cam speed
    (``motion.unit``/rad^2: mm or rad of swing) over one turn."""
    from camgen.compliant import sample_spectrum

    theta = np.asarray(motion.cam_angle, dtype=float)
    acc = np.asarray(motion.acceleration, dtype=float)
    return sample_spectrum(theta, np.append(acc, acc[0]), harmonics)[1:]


def harmonic_figures(motion: "Motion | None", rpm: float | None) -> dict[str, Any]:
    """report.json's ``figures.acceleration_harmonics`` of a cam's motion (``{}`` without one): the
    amplitudes per unit cam speed and, with ``rpm``, at speed (m/s^2 translating, rad/s^2 an arm)."""
    if motion is None or motion.cam_angle.size < 2 * ACCELERATION_HARMONICS + 1:
        return {}
    amplitudes = acceleration_harmonics(motion)
    unit = motion.unit
    samples = int(motion.cam_angle.size)
    out: dict[str, Any] = {
        "harmonics": ACCELERATION_HARMONICS,
        "method": f"Fourier integrals of the piecewise-linear interpolant of the acceleration at {samples} cam angles "
                  "(camgen.compliant.sample_spectrum, as the compliant train's spectrum)",
        "samples": samples,
        f"amplitude_{unit}_per_rad2": amplitudes.tolist(),
    }
    if rpm:
        omega = 2.0 * math.pi * rpm / 60.0
        if unit == "mm":
            out["amplitude_m_per_s2"] = (amplitudes * (omega**2 * 1e-3)).tolist()
        else:
            out[f"amplitude_{unit}_per_s2"] = (amplitudes * omega**2).tolist()
    return out
