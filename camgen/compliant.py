"""A compliant follower train: its periodic steady-state response to the cam over one turn.

The rigid model (:mod:`camgen.dynamics`) holds the follower on the law, ``q = y(theta)``.
Here the train between the cam contact and the follower's mass is a spring ``k`` with a
viscous damper ``c`` (one degree of freedom, the lumped model of Koster, *Vibrations of cam
mechanisms*, Macmillan 1974, ch. 3, and of Norton, *Cam Design and Manufacturing Handbook*,
ch. 10): the cam drives the train's end along the law ``y(t) = s(w t)`` at the constant speed
``w``; the mass ``M`` moves ``x(t)``; the return spring ``K``, its preload, the external load,
the weight and the follower's own viscous damping ``C`` act on the mass as in the rigid model::

    M x'' + C x' + c (x' - y') + k (x - y) + K (x - q_min) + P0 + L + G = 0

and the cam pushes with ``F_c = k (y - x) + c (y' - x')`` (generalised: N, or N*mm about the
pivot).  With the dynamic error ``r = x - y`` this is

    M r'' + (C + c) r' + (k + K) r = -Q_rigid(t),    F_c = -(k r + c r')

``Q_rigid = M y'' + C y' + K (y - q_min) + P0 + L + G`` being the rigid model's generalised
force (:func:`camgen.dynamics.force_coefficients`): as ``k`` grows ``F_c`` tends to it.
``c = 2 zeta sqrt((k + K) M)``: ``zeta`` is the damping ratio of the train's mode, whose
natural frequency is ``f_n = sqrt((k + K) / M) / (2 pi)``.

How the periodic state is found (exactly for the linear model, no time stepping error):

* between two cam samples the law is the quintic Hermite interpolant of its samples
  ``(y, y', y'')`` at both ends (error O(h^6) in ``y``), the loads the linear one of theirs;
* each step's response to such a polynomial forcing is exact: the matrix exponential of the
  state matrix augmented by the forcing's derivative chain (Van Loan, IEEE TAC 23, 1978,
  "Computing integrals involving the matrix exponential"), one exponential for the uniform step;
* the step recursion ``z[i+1] = Phi z[i] + g[i]`` is summed by a prefix scan in
  ``ceil(log2 N)`` vectorised rounds (no loop over time steps), the powers ``Phi^i`` by doubling;
* the turn closes on itself: ``(I - Phi^N) z[0] = sum_j Phi^(N-1-j) g[j]`` (one 2x2 solve).

Where ``F_c`` would go negative the follower leaves the cam: the linear model no longer holds
there; the runs are reported (the dynamic jump), not modelled past.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError, ParameterError, require_finite

if TYPE_CHECKING:
    from camgen.dynamics import FollowerTrain, Kinematics

__all__ = ["CompliantResult", "TrainCompliance", "UNIFORM_TOL", "DWELL_TOL", "RESONANCE_TOL", "acceleration_spectrum",
           "compliant_response", "dwell_starts", "response_from", "step_matrices"]

TWO_PI = 2.0 * math.pi
#: Relative tolerance on the spacing of the cam samples (the exact step needs one step length).
UNIFORM_TOL = 1e-9
#: A sample is in a dwell where |s'| and |s''| are at most this fraction of their largest values.
DWELL_TOL = 1e-12
#: |det(I - Phi^N)| below this: an undamped train resonant with the turn has no periodic state.
RESONANCE_TOL = 1e-10
#: Harmonics of the acceleration spectrum reported: at least this many ...
SPECTRUM_MIN_HARMONICS = 40
#: ... and at most this many (and never past the samples' Nyquist limit).
SPECTRUM_MAX_HARMONICS = 400


@dataclass(frozen=True)
class TrainCompliance:
    """The train's elasticity: ``stiffness`` between the cam contact and the follower's mass
    (translating N/mm; oscillating N*mm/rad about the pivot), ``damping_ratio`` of its mode
    (0 <= zeta < 1), ``residual_limit`` mm (at the roller for an arm; None: information)."""

    stiffness: float
    damping_ratio: float = 0.0
    residual_limit: float | None = None

    def __post_init__(self) -> None:
        if not require_finite("train_stiffness", self.stiffness) > 0:
            raise ParameterError("train_stiffness", self.stiffness, "train_stiffness > 0 (N/mm or N*mm/rad)")
        zeta = require_finite("damping_ratio", self.damping_ratio)
        if not 0.0 <= zeta < 1.0:
            raise ParameterError("damping_ratio", zeta, "0 <= damping_ratio < 1 (an underdamped train)")
        if self.residual_limit is not None and not require_finite("residual_vibration_limit", self.residual_limit) > 0:
            raise ParameterError("residual_vibration_limit", self.residual_limit, "residual_vibration_limit > 0 mm")


@dataclass(frozen=True)
class Oscillator:
    """The train's modal constants in generalised units: inertia ``m`` (N per mm/s^2, or N*mm
    per rad/s^2), stiffness ``k`` (train) and ``k_return`` (spring), damping ``c`` (train,
    from the ratio) and ``c_follower`` (the follower's own), per mm/s or rad/s."""

    m: float
    k: float
    k_return: float
    c: float
    c_follower: float

    @property
    def omega_n(self) -> float:
        """rad/s, ``sqrt((k + K) / M)``."""
        return math.sqrt((self.k + self.k_return) / self.m)

    @property
    def zeta_total(self) -> float:
        """The mode's damping ratio with the follower's own damping, ``(c + C) / (2 sqrt((k + K) M))``."""
        return (self.c + self.c_follower) / (2.0 * math.sqrt((self.k + self.k_return) * self.m))


def oscillator(train: "FollowerTrain", compliance: TrainCompliance) -> Oscillator:
    """The :class:`Oscillator` of ``train`` with ``compliance`` (units as :mod:`camgen.dynamics`)."""
    from camgen import dynamics as dy

    if train.closure != "force":
        raise ParameterError("train_stiffness", compliance.stiffness, "left out for a form-closed train",
                             "the compliant model is of a spring-loaded (force-closed) train")
    if train.motion == "translating":
        m, c_follower = train.mass * dy.KG_MM_PER_S2_TO_N, train.damping * dy.N_S_PER_M_TIMES_MM_PER_S_TO_N
    else:
        m, c_follower = train.inertia * dy.KG_M2_PER_S2_TO_N_MM, train.damping * dy.N_M_TO_N_MM
    if not m > 0:
        name = "mass" if train.motion == "translating" else "inertia"
        raise ParameterError(name, 0.0, f"{name} > 0 with a train stiffness (the compliant train's mass vibrates on it)")
    k = float(compliance.stiffness)
    c = 2.0 * compliance.damping_ratio * math.sqrt((k + train.spring_rate) * m)
    return Oscillator(m, k, float(train.spring_rate), c, c_follower)


def _omega(rpm: float) -> float:
    """rad/s of ``rpm`` (> 0)."""
    from camgen.dynamics import RPM_TO_RAD_PER_S

    if not require_finite("rpm", rpm) > 0:
        raise ParameterError("rpm", rpm, "rpm > 0")
    return float(rpm) * RPM_TO_RAD_PER_S


def contact_projection(kin: "Kinematics", train: "FollowerTrain") -> np.ndarray:
    """The generalised force per newton along the contact normal, ``lever cos(phi)`` (as the
    rigid model: 1 translating, the arm or ``kin.lever`` for an oscillating follower)."""
    lever: Any = 1.0 if train.motion == "translating" else (kin.lever if kin.lever is not None else float(train.arm_length))
    return lever * np.cos(kin.pressure_angle)


# --------------------------------------------------------------------------------------------
# The exact step
# --------------------------------------------------------------------------------------------
def step_matrices(osc: Oscillator, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """``(Phi, Gamma)`` of one step ``dt`` (s): the state ``z = (r mm, r' mm/s)`` moves to
    ``Phi z + Gamma u`` under the forcing whose derivative chain at the step's start is
    ``u = (y, y', ..., y^(5), f, f')`` (the law a quintic, the load part ``f`` linear).

    Van Loan's augmented exponential: ``expm([[A, B], [0, N]] dt)`` with ``N`` the chain's
    shift matrix; its top-right block is ``int_0^dt e^(A (dt - s)) B e^(N s) ds``."""
    from scipy.linalg import expm

    m = osc.m
    h = np.zeros((10, 10))
    h[0, 1] = 1.0
    h[1, 0] = -(osc.k + osc.k_return) / m
    h[1, 1] = -(osc.c + osc.c_follower) / m
    # -Q_rigid / M = -(M y'' + C y' + K y - f) / M, f = K q_min - P0 - L - G
    h[1, 2] = -osc.k_return / m
    h[1, 3] = -osc.c_follower / m
    h[1, 4] = -1.0
    h[1, 8] = 1.0 / m
    for i in range(2, 7):
        h[i, i + 1] = 1.0
    h[8, 9] = 1.0
    e = expm(h * dt)
    return e[:2, :2], e[:2, 2:]


def quintic_chain(y: np.ndarray, v: np.ndarray, a: np.ndarray, dt: float) -> np.ndarray:
    """The derivatives ``(y, y', ..., y^(5))`` at the start of each step of the quintic Hermite
    interpolant of ``(y, y', y'')`` at both its ends (shape (N, 6); samples periodic)."""
    y1, v1, a1 = np.roll(y, -1), np.roll(v, -1), np.roll(a, -1)
    d = y1 - y - v * dt - 0.5 * a * dt**2
    e = v1 - v - a * dt
    f = a1 - a
    c3 = (10.0 * d - 4.0 * e * dt + 0.5 * f * dt**2) / dt**3
    c4 = (-15.0 * d + 7.0 * e * dt - f * dt**2) / dt**4
    c5 = (6.0 * d - 3.0 * e * dt + 0.5 * f * dt**2) / dt**5
    return np.stack([y, v, a, 6.0 * c3, 24.0 * c4, 120.0 * c5], axis=1)


def _powers(phi: np.ndarray, n: int) -> np.ndarray:
    """``Phi^i`` for i = 0 .. n (shape (n + 1, 2, 2)) by doubling."""
    out = np.empty((n + 1, 2, 2))
    out[0] = np.eye(2)
    filled, block = 1, phi
    while filled <= n:
        take = min(filled, n + 1 - filled)
        out[filled:filled + take] = block @ out[:take]
        filled += take
        block = block @ block
    return out


def _scan(phi: np.ndarray, g: np.ndarray) -> np.ndarray:
    """``S[i] = sum_{j <= i} Phi^(i - j) g[j]`` (shape (N, 2)): Hillis-Steele prefix scan."""
    acc = g.copy()
    power, shift = phi, 1
    while shift < len(acc):
        acc[shift:] += acc[:-shift] @ power.T
        power = power @ power
        shift *= 2
    return acc


def response_from(kin: "Kinematics", train: "FollowerTrain", compliance: TrainCompliance, rpm: float,
                  z0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The dynamic error over one turn from the state ``z0`` = (r mm, r' mm/s) at ``theta[0]``
    (None: the periodic state, the one the turn returns to).

    Returns ``(r, r_dot, z_end)``: the error and its rate at every sample (mm, mm/s; an arm:
    rad, rad/s) and the state after the turn."""
    from camgen import dynamics as dy

    theta = kin.theta
    n = theta.size
    h = TWO_PI / n
    steps = np.diff(np.append(theta, theta[0] + TWO_PI))
    if np.any(np.abs(steps - h) > UNIFORM_TOL * h):
        raise ParameterError("theta", "cam angles", "uniformly spaced cam angles over the turn (the exact step)")
    omega = _omega(rpm)
    dt = h / omega
    osc = oscillator(train, compliance)
    phi, gamma = step_matrices(osc, dt)
    a_coef, _, _ = dy.force_coefficients(kin, train)
    f = train.spring_rate * kin.s - a_coef  # K q_min - P0 - L - G
    chain = np.concatenate([quintic_chain(kin.s, omega * kin.ds, omega**2 * kin.d2s, dt),
                            np.stack([f, (np.roll(f, -1) - f) / dt], axis=1)], axis=1)
    g = chain @ gamma.T
    acc = _scan(phi, g)
    powers = _powers(phi, n)
    if z0 is None:
        system = np.eye(2) - powers[n]
        if abs(np.linalg.det(system)) < RESONANCE_TOL:
            raise GeometryError(f"the undamped train (natural frequency {osc.omega_n / TWO_PI:.6g} Hz) is in resonance with "
                                f"the turn ({rpm / 60.0:.6g} Hz): it has no periodic state; give a damping_ratio > 0")
        z0 = np.linalg.solve(system, acc[-1])
    z0 = np.asarray(z0, dtype=float)
    z = np.empty((n, 2))
    z[0] = z0
    z[1:] = powers[1:n] @ z0 + acc[:-1]
    z_end = powers[n] @ z0 + acc[-1]
    return z[:, 0], z[:, 1], z_end


def dwell_starts(kin: "Kinematics", tol: float = DWELL_TOL) -> np.ndarray:
    """Indices of the first sample of every dwell that follows a motion (``s'`` and ``s''``
    within ``tol`` of 0 relative to their largest values; periodic)."""
    scale_v = float(np.max(np.abs(kin.ds))) or 1.0
    scale_a = float(np.max(np.abs(kin.d2s))) or 1.0
    still = (np.abs(kin.ds) <= tol * scale_v) & (np.abs(kin.d2s) <= tol * scale_a)
    if still.all() or not still.any():
        return np.zeros(0, dtype=int)
    return np.nonzero(still & ~np.roll(still, 1))[0]


def acceleration_spectrum(kin: "Kinematics", rpm: float) -> np.ndarray:
    """Amplitudes of the law's acceleration at speed, harmonics 0 .. N/2 of the turn (FFT of the
    uniform samples; translating mm/s^2, an arm rad/s^2): ``a(t) = sum A_n cos(n w t + p_n)``."""
    omega = _omega(rpm)
    coef = np.fft.rfft(omega**2 * kin.d2s) / kin.theta.size
    amp = 2.0 * np.abs(coef)
    amp[0] = abs(coef[0].real)
    if kin.theta.size % 2 == 0:
        amp[-1] = abs(coef[-1].real)
    return amp


@dataclass(frozen=True, eq=False)
class CompliantResult:
    """The compliant train's periodic response at ``rpm`` (arrays of shape (N,) over ``theta``).

    Attributes
    ----------
    error, error_rate : ``x - y``, the dynamic displacement error (mm; an arm rad) and its rate.
    contact_force : N along the contact normal (the dynamic one; < 0: the follower leaves the cam).
    rigid_force : N, the rigid model's contact force, for comparison.
    natural_frequency : Hz.  turn_frequency : Hz (rpm / 60).
    damping_ratio : of the mode, the follower's own damping included.
    spectrum : the law's acceleration amplitudes by harmonic (index n: n x the turn frequency).
    dwell_start : sample indices where a dwell follows a rise or return.
    residual : the free-vibration amplitude at each dwell start (mm; an arm: mm at the roller).
    jump_ranges_deg : start/end cam angles of the runs where the dynamic force < 0.
    lever : mm per unit of the coordinate (1 translating; the arm length).
    """

    rpm: float
    theta: np.ndarray
    error: np.ndarray
    error_rate: np.ndarray
    contact_force: np.ndarray
    rigid_force: np.ndarray
    natural_frequency: float
    turn_frequency: float
    damping_ratio: float
    spectrum: np.ndarray
    dwell_start: np.ndarray
    residual: np.ndarray
    jump_ranges_deg: list[float]
    lever: float
    motion: str

    @property
    def amplification(self) -> float:
        """Peak dynamic over peak rigid contact force."""
        return float(np.max(self.contact_force) / np.max(self.rigid_force))

    @property
    def residual_peak(self) -> float:
        """Largest residual vibration amplitude over the dwells (mm), 0 without dwells."""
        return float(np.max(self.residual)) if self.residual.size else 0.0

    def harmonics(self) -> np.ndarray:
        """The spectrum's harmonics 1 .. H reported: at least 40, past twice ``f_n``, at most 400."""
        ratio = self.natural_frequency / self.turn_frequency
        count = int(min(max(SPECTRUM_MIN_HARMONICS, math.ceil(2.0 * ratio)), SPECTRUM_MAX_HARMONICS, self.spectrum.size - 1))
        return self.spectrum[1:count + 1]

    def figures(self) -> dict[str, Any]:
        """report.json's ``figures.dynamics.compliant`` (units in the keys)."""
        length = "mm" if self.motion == "translating" else "rad"
        accel = "m_per_s2" if self.motion == "translating" else "rad_per_s2"
        scale = 1e-3 if self.motion == "translating" else 1.0  # mm/s^2 -> m/s^2
        ratio = self.natural_frequency / self.turn_frequency
        nearest = max(1, int(round(ratio)))
        harmonics = self.harmonics() * scale
        i = int(np.argmin(self.contact_force))
        out: dict[str, Any] = {
            "natural_frequency_Hz": self.natural_frequency,
            "turn_frequency_Hz": self.turn_frequency,
            "natural_frequency_harmonic": ratio,
            "damping_ratio": self.damping_ratio,
            f"max_dynamic_error_{length}": float(np.max(np.abs(self.error))),
            "min_dynamic_contact_force_N": float(self.contact_force[i]),
            "min_dynamic_contact_force_deg": round(math.degrees(float(self.theta[i])), 6),
            "max_dynamic_contact_force_N": float(np.max(self.contact_force)),
            "max_rigid_contact_force_N": float(np.max(self.rigid_force)),
            "dynamic_amplification": self.amplification,
            "dynamic_jump_ranges_deg": self.jump_ranges_deg,
            "residual_vibration_mm": [float(v) for v in self.residual],
            "residual_vibration_deg": [round(math.degrees(float(self.theta[j])), 6) for j in self.dwell_start],
            "residual_vibration_peak_mm": self.residual_peak,
            f"acceleration_harmonics_{accel}": [float(v) for v in harmonics],
        }
        if nearest < self.spectrum.size:
            out[f"acceleration_at_nearest_harmonic_{accel}"] = float(self.spectrum[nearest] * scale)
            out["nearest_harmonic"] = nearest
        return out


def compliant_response(kin: "Kinematics", train: "FollowerTrain", compliance: TrainCompliance, rpm: float) -> CompliantResult:
    """The periodic steady state of the compliant train at ``rpm`` (:class:`CompliantResult`).

    Raises :class:`GeometryError` for an undamped train exactly resonant with the turn."""
    from camgen import dynamics as dy
    from camgen.checks import run_ends

    r, r_dot, _ = response_from(kin, train, compliance, rpm)
    osc = oscillator(train, compliance)
    omega = _omega(rpm)
    projection = contact_projection(kin, train)
    force = -(osc.k * r + osc.c * r_dot) / projection
    a, b, c = dy.force_coefficients(kin, train)
    rigid = (a + b * omega + c * omega**2) / projection
    # residual vibration: the free vibration about the dwell's static equilibrium r_eq = -Q / (k + K)
    starts = dwell_starts(kin)
    stiff = osc.k + osc.k_return
    u = r[starts] + a[starts] / stiff
    wn, zt = osc.omega_n, osc.zeta_total
    if zt < 1.0:
        wd = wn * math.sqrt(1.0 - zt * zt)
        amplitude = np.hypot(u, (r_dot[starts] + zt * wn * u) / wd)  # Duhamel: the envelope of the free response
    else:  # overdamped by the follower's own damping: no vibration, the offset decays
        amplitude = np.abs(u)
    lever = 1.0 if train.motion == "translating" else float(train.arm_length)
    return CompliantResult(rpm, kin.theta, r, r_dot, force, rigid, wn / TWO_PI, rpm / 60.0, zt, acceleration_spectrum(kin, rpm),
                           starts, amplitude * lever, run_ends(force < 0, kin.theta), lever, train.motion)
