"""Several cams on one shaft: their torques combined by phase, the flywheel, the motor.

Every cam turns with the machine: a cam with phase ``p`` is at cam angle ``theta = phi + p`` when
the machine (the shaft) is at angle ``phi``, both measured in the direction of rotation.  A cam's
camshaft torque ``T_c(theta)`` (from its dynamics, :mod:`camgen.dynamics`) sampled on its own
grid is resampled at ``phi + p`` by periodic linear interpolation and the machine's torque is the
sum over its cams.

The flywheel (energy method; Norton, Design of Machinery, ch. 11): at constant motor torque
``T_m = mean(T)`` the shaft's kinetic energy changes by ``E(phi) = int_0^phi (T_m - T) dphi``;
its largest swing over a turn ``dE = max E - min E`` sets the inertia that holds the coefficient
of speed fluctuation ``Cs = (w_max - w_min) / w_mean`` (``w_mean = (w_max + w_min) / 2``):
``I = dE / (Cs w_mean^2)``.  The speed it leaves follows from the energy exactly:
``I w(phi)^2 / 2 = I w_min^2 / 2 + E(phi) - min E``.

Units: angles rad, torque N*m, energy J, inertia kg*m^2, speed rad/s (rpm at the edges), power W.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

__all__ = ["Flywheel", "PhasedTorque", "combined_torque", "energy_excess", "flywheel", "machine_angles", "shifted", "turn_rms"]

TWO_PI = 2.0 * math.pi


def machine_angles(samples: int) -> np.ndarray:
    """``samples`` machine angles (rad) evenly over one turn, from 0."""
    return TWO_PI * np.arange(samples) / samples


def shifted(theta: np.ndarray, values: np.ndarray, phase: float, angles: np.ndarray) -> np.ndarray:
    """``values`` sampled at cam angles ``theta`` (rad, increasing in [0, 2 pi)) read at cam angle
    ``angles + phase``: periodic linear interpolation."""
    return np.interp(np.mod(angles + phase, TWO_PI), theta, values, period=TWO_PI)


@dataclass(frozen=True)
class PhasedTorque:
    """One cam's camshaft torque over its turn (cam angles rad, N*m) and its phase (rad)."""

    name: str
    theta: np.ndarray
    torque: np.ndarray
    phase: float


def combined_torque(cams: Sequence[PhasedTorque], angles: np.ndarray) -> np.ndarray:
    """The shaft torque (N*m) at machine angles ``angles``: the sum of every cam's torque read at
    its cam angle ``angles + phase``."""
    total = np.zeros_like(angles, dtype=float)
    for cam in cams:
        total = total + shifted(cam.theta, cam.torque, cam.phase, angles)
    return total


def turn_rms(values: np.ndarray) -> float:
    """RMS over one turn of samples at evenly spaced machine angles."""
    return float(np.sqrt(np.mean(np.square(values))))


def energy_excess(torque: np.ndarray) -> np.ndarray:
    """``E(phi_k) = int_0^phi_k (T_m - T) dphi`` (J) at evenly spaced machine angles from 0
    (periodic trapezoid rule, ``T_m`` the mean torque: ``E`` returns to 0 after a turn)."""
    n = torque.size
    h = TWO_PI / n
    excess = float(np.mean(torque)) - torque
    steps = 0.5 * h * (excess + np.roll(excess, -1))  # the trapezoid from phi_k to phi_{k+1}
    return np.concatenate(([0.0], np.cumsum(steps[:-1])))


@dataclass(frozen=True)
class Flywheel:
    """The flywheel holding a coefficient of speed fluctuation, and the speed it leaves.

    Attributes
    ----------
    inertia : kg*m^2 on the shaft (dE / (Cs w^2)); 0 when the torque is constant.
    energy_swing : J, the largest swing of ``E`` over a turn.
    mean_torque : N*m, the motor's constant torque (the mean shaft torque).
    omega : rad/s, the machine speed w_mean = (w_max + w_min) / 2.
    cs : the coefficient of speed fluctuation wanted.
    speed : rad/s at each machine angle.
    energy : J, ``E`` at each machine angle.
    """

    inertia: float
    energy_swing: float
    mean_torque: float
    omega: float
    cs: float
    speed: np.ndarray
    energy: np.ndarray

    @property
    def fluctuation(self) -> float:
        """``(w_max - w_min) / w_mean`` of :attr:`speed`."""
        return float((self.speed.max() - self.speed.min()) / self.omega)

    @property
    def time_mean_speed(self) -> float:
        """rad/s averaged over time: one turn over its duration ``int dphi / w``."""
        return float(TWO_PI / (TWO_PI * np.mean(1.0 / self.speed)))


def flywheel(torque: np.ndarray, rpm: float, cs: float) -> Flywheel:
    """The flywheel that holds ``cs`` (0 < cs < 1) against the shaft torque ``torque`` (N*m at
    evenly spaced machine angles) at ``rpm``, the motor giving the mean torque."""
    omega = rpm * TWO_PI / 60.0
    energy = energy_excess(torque)
    swing = float(energy.max() - energy.min())
    inertia = swing / (cs * omega**2)
    w_min = omega * (1.0 - cs / 2.0)
    if inertia > 0.0:
        speed = np.sqrt(w_min**2 + 2.0 * (energy - energy.min()) / inertia)
    else:
        speed = np.full(torque.shape, omega)
    return Flywheel(inertia, swing, float(np.mean(torque)), omega, cs, speed, energy)
