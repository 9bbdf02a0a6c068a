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

__all__ = ["CompliantResult", "TrainCompliance", "SAME_ANGLE", "DWELL_TOL", "RESONANCE_TOL", "acceleration_spectrum",
           "TWO_PI", "angular_speed", "contact_projection", "quintic_chain", "turn_steps", "compliant_response", "prefix_scan", "dwell_starts", "response_from", "sample_spectrum", "spectrum_harmonics", "step_matrices"]

TWO_PI = 2.0 * math.pi
#: Two samples closer than this fraction of the longest step are one cam angle (a break's two sides).
SAME_ANGLE = 1e-9
#: A sample is in a dwell where |s'| and |s''| are at most this fraction of their largest values.
DWELL_TOL = 1e-12
#: |det(I - Phi^N)| below this: an undamped train resonant with the turn has no periodic state.
RESONANCE_TOL = 1e-10
#: Harmonics of the acceleration spectrum reported: at least this many ...
SPECTRUM_MIN_HARMONICS = 40
#: ... and at most this many (and never past the samples' Nyquist limit).
SPECTRUM_MAX_HARMONICS = 400
#: Complex terms (harmonics x samples) the spectrum holds at once (64 MB): its memory is bounded.
SPECTRUM_CHUNK = 1 << 22


@dataclass(frozen=True)
class TrainCompliance:
    """The train's elasticity: ``stiffness`` between the cam contact and the follower's mass
    (translating N/mm; oscillating N*mm/rad about the pivot), ``damping_ratio`` of its mode
    (0 <= zeta < 1), ``residual_limit`` mm (at the roller for an arm; None: information);
    ``follower``: the follower's own stiffness and tool mass of a two-mass train
    (:class:`camgen.compliant_two.FollowerCompliance`; None: one degree of freedom)."""

    stiffness: float
    damping_ratio: float = 0.0
    residual_limit: float | None = None
    follower: Any = None

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


def angular_speed(rpm: float) -> float:
    """rad/s of ``rpm`` (> 0)."""
    from camgen.dynamics import RPM_TO_RAD_PER_S

    if not require_finite("rpm", rpm) > 0:
        raise ParameterError("rpm", rpm, "rpm > 0")
    return float(rpm) * RPM_TO_RAD_PER_S



def turn_steps(theta: np.ndarray, rpm: float) -> tuple[float, np.ndarray, np.ndarray]:
    """The shaft's angular speed (rad/s) at ``rpm`` and the time steps (s) from each sample of
    ``theta`` (rad, one turn) to the next: ``moving`` False where two samples share an angle (a
    break sampled twice: the state carries over, its step is a placeholder 1 / omega)."""
    omega = angular_speed(rpm)
    steps = np.diff(np.append(theta, theta[0] + TWO_PI))
    moving = steps > SAME_ANGLE * float(np.max(steps))
    return omega, moving, np.where(moving, steps, 1.0) / omega

def contact_projection(kin: "Kinematics", train: "FollowerTrain") -> np.ndarray:
    """The generalised force per newton along the contact normal, ``lever cos(phi)`` (as the
    rigid model: 1 translating, the arm or ``kin.lever`` for an oscillating follower)."""
    lever: Any = 1.0 if train.motion == "translating" else (kin.lever if kin.lever is not None else float(train.arm_length))
    return lever * np.cos(kin.pressure_angle)


# --------------------------------------------------------------------------------------------
# The exact step
# --------------------------------------------------------------------------------------------
def augmented_matrix(osc: Oscillator) -> np.ndarray:
    """The 10 x 10 state matrix of ``z = (r mm, r' mm/s)`` augmented by the forcing's derivative
    chain ``u = (y, y', ..., y^(5), f, f')`` (the law a quintic in time, the load part ``f``
    linear): ``expm(H dt)`` has the step's ``Phi`` top-left and ``Gamma`` top-right, ``z`` moving
    to ``Phi z + Gamma u`` (Van Loan: ``Gamma = int_0^dt e^(A (dt - s)) B e^(N s) ds``)."""
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
    return h


def step_matrices(osc: Oscillator, dt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(Phi, Gamma)`` of steps of lengths ``dt`` (s, shape (S,)): shapes (S, 2, 2) and (S, 2, 8);
    one matrix exponential per distinct length (a check grid has a few), batched."""
    from scipy.linalg import expm

    lengths, which = np.unique(dt, return_inverse=True)
    e = expm(augmented_matrix(osc)[None, :, :] * lengths[:, None, None])
    return e[which, :2, :2], e[which, :2, 2:]


def quintic_chain(y: np.ndarray, v: np.ndarray, a: np.ndarray, dt: np.ndarray | float) -> np.ndarray:
    """The derivatives ``(y, y', ..., y^(5))`` at the start of each step of the quintic Hermite
    interpolant of ``(y, y', y'')`` at both its ends (shape (N, 6); samples periodic, step
    ``i`` from sample ``i`` to ``i + 1`` of length ``dt[i]``)."""
    y1, v1, a1 = np.roll(y, -1), np.roll(v, -1), np.roll(a, -1)
    d = y1 - y - v * dt - 0.5 * a * dt**2
    e = v1 - v - a * dt
    f = a1 - a
    c3 = (10.0 * d - 4.0 * e * dt + 0.5 * f * dt**2) / dt**3
    c4 = (-15.0 * d + 7.0 * e * dt - f * dt**2) / dt**4
    c5 = (6.0 * d - 3.0 * e * dt + 0.5 * f * dt**2) / dt**5
    return np.stack([y, v, a, 6.0 * c3, 24.0 * c4, 120.0 * c5], axis=1)


def prefix_scan(phi: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The recursion ``z[i+1] = Phi[i] z[i] + g[i]`` summed for every step at once: returns
    ``(P, G)`` with ``P[i] = Phi[i] ... Phi[0]`` and ``G[i]`` the state after step ``i`` from
    ``z[0] = 0`` (so ``z[i+1] = P[i] z[0] + G[i]``).  Hillis-Steele prefix scan of the
    associative composition ``(Phi_b, g_b) o (Phi_a, g_a) = (Phi_b Phi_a, Phi_b g_a + g_b)``:
    ``ceil(log2 N)`` vectorised rounds."""
    prod, acc = phi.copy(), g.copy()
    shift = 1
    while shift < len(acc):
        acc[shift:] = acc[shift:] + np.einsum("nij,nj->ni", prod[shift:], acc[:-shift])
        prod[shift:] = prod[shift:] @ prod[:-shift]
        shift *= 2
    return prod, acc


def response_from(kin: "Kinematics", train: "FollowerTrain", compliance: TrainCompliance, rpm: float,
                  z0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The dynamic error over one turn from the state ``z0`` = (r mm, r' mm/s) at ``theta[0]``
    (None: the periodic state, the one the turn returns to).  Any sample spacing: a step shorter
    than :data:`SAME_ANGLE` of the longest joins the one-sided values of a break (the state
    carries over it).

    Returns ``(r, r_dot, z_end)``: the error and its rate at every sample (mm, mm/s; an arm:
    rad, rad/s) and the state after the turn."""
    from camgen import dynamics as dy

    theta = kin.theta
    n = theta.size
    omega, moving, dt = turn_steps(theta, rpm)
    osc = oscillator(train, compliance)
    a_coef, _, _ = dy.force_coefficients(kin, train)
    f = train.spring_rate * kin.s - a_coef  # K q_min - P0 - L - G
    chain = np.concatenate([quintic_chain(kin.s, omega * kin.ds, omega**2 * kin.d2s, dt),
                            np.stack([f, (np.roll(f, -1) - f) / dt], axis=1)], axis=1)
    phi = np.broadcast_to(np.eye(2), (n, 2, 2)).copy()
    g = np.zeros((n, 2))
    if moving.any():
        phi_m, gamma_m = step_matrices(osc, dt[moving])
        phi[moving] = phi_m
        g[moving] = np.einsum("nij,nj->ni", gamma_m, chain[moving])
    prod, acc = prefix_scan(phi, g)
    if z0 is None:
        system = np.eye(2) - prod[-1]
        if abs(np.linalg.det(system)) < RESONANCE_TOL:
            raise GeometryError(f"the undamped train (natural frequency {osc.omega_n / TWO_PI:.6g} Hz) is in resonance with "
                                f"the turn ({rpm / 60.0:.6g} Hz): it has no periodic state; give a damping_ratio > 0")
        z0 = np.linalg.solve(system, acc[-1])
    z0 = np.asarray(z0, dtype=float)
    z = np.empty((n, 2))
    z[0] = z0
    z[1:] = prod[:-1] @ z0 + acc[:-1]
    return z[:, 0], z[:, 1], prod[-1] @ z0 + acc[-1]


def dwell_starts(kin: "Kinematics", tol: float = DWELL_TOL) -> np.ndarray:
    """Indices of the first sample of every dwell that follows a motion (``s'`` and ``s''``
    within ``tol`` of 0 relative to their largest values; periodic)."""
    scale_v = float(np.max(np.abs(kin.ds))) or 1.0
    scale_a = float(np.max(np.abs(kin.d2s))) or 1.0
    still = (np.abs(kin.ds) <= tol * scale_v) & (np.abs(kin.d2s) <= tol * scale_a)
    if still.all() or not still.any():
        return np.zeros(0, dtype=int)
    return np.nonzero(still & ~np.roll(still, 1))[0]


def acceleration_spectrum(kin: "Kinematics", rpm: float, harmonics: int) -> np.ndarray:
    """Amplitudes ``A_n`` of the law's acceleration at speed, ``a(t) = sum A_n cos(n w t + p_n)``,
    harmonics n = 0 .. ``harmonics`` of the turn (translating mm/s^2, an arm rad/s^2): the
    Fourier integrals of the piecewise-linear interpolant of the samples (any spacing; on a
    uniform grid the FFT's coefficients up to the linear interpolant's sinc factor)."""
    omega = angular_speed(rpm)
    return sample_spectrum(kin.theta, omega**2 * np.append(kin.d2s, kin.d2s[0]), harmonics)


def sample_spectrum(angles: np.ndarray, values: np.ndarray, harmonics: int) -> np.ndarray:
    """Amplitudes ``A_n`` (n = 0 .. ``harmonics``) of a periodic signal over one turn,
    ``f(theta) = sum A_n cos(n theta + p_n)``, from its samples ``values`` at the cam angles
    ``angles`` (rad, sorted, one turn) with the first sample repeated at the end (``values`` one
    longer than ``angles``): the Fourier integrals of their piecewise-linear interpolant (the
    shared core of :func:`acceleration_spectrum`, in the samples' own unit)."""
    theta = np.append(angles, angles[0] + TWO_PI)
    acc = np.asarray(values, dtype=float)
    n = np.arange(1, harmonics + 1)[:, None]
    width = np.diff(theta)
    keep = width > 0
    t0, t1, a0, a1, w = theta[:-1][keep], theta[1:][keep], acc[:-1][keep], acc[1:][keep], width[keep]
    slope = (a1 - a0) / w
    part = np.zeros(harmonics, dtype=complex)
    chunk = max(1, SPECTRUM_CHUNK // harmonics)  # pieces per block: at most SPECTRUM_CHUNK complex terms at once
    for lo in range(0, t0.size, chunk):
        piece = slice(lo, lo + chunk)
        # int_t0^t1 (a0 + slope (t - t0)) e^(-i n t) dt, in closed form per piece
        e0, e1 = np.exp(-1j * n * t0[piece]), np.exp(-1j * n * t1[piece])
        part += ((a0[piece] * e0 - a1[piece] * e1) / (1j * n) + slope[piece] * (e1 - e0) / n**2).sum(axis=1)
    mean = float(np.sum(0.5 * (a0 + a1) * w)) / TWO_PI
    return np.concatenate([[abs(mean)], np.abs(part) / math.pi])


@dataclass(frozen=True, eq=False)
class CompliantResult:
    """The compliant train's periodic response at ``rpm`` (arrays of shape (N,) over ``theta``).

    Attributes
    ----------
    error, error_rate : ``x - y``, the dynamic displacement error (mm; an arm rad) and its rate.
    contact_force : N along the contact normal (the dynamic one; < 0: the follower leaves the cam).
    rigid_force : N, the rigid model's contact force, for comparison.
    natural_frequency : Hz.  turn_frequency : Hz (rpm / 60).
    damping_ratio : of the mode, the follower's own damping (``damping_n_s_per_m``) included.
    spectrum : the law's acceleration amplitudes by harmonic 0 .. H (index n: n x the turn frequency).
    dwell_start : sample indices where a dwell follows a rise or return.
    residual : the free-vibration amplitude at each dwell start (mm; an arm: mm at the roller).
    jump_ranges_deg : start/end cam angles of the runs where the dynamic force < 0.
    lever : mm per unit of the coordinate (1 translating; the arm length).
    motion : ``"translating"`` or ``"oscillating"``.
    residual_limit : mm, the residual-vibration limit it is checked against (None: not given).
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
    residual_limit: float | None = None

    @property
    def amplification(self) -> float:
        """Peak dynamic over peak rigid contact force."""
        return float(np.max(self.contact_force) / np.max(self.rigid_force))

    @property
    def residual_peak(self) -> float:
        """Largest residual vibration amplitude over the dwells (mm), 0 without dwells."""
        return float(np.max(self.residual)) if self.residual.size else 0.0

    def harmonics(self) -> np.ndarray:
        """The spectrum's harmonics 1 .. H."""
        return self.spectrum[1:]

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
            "mode_damping_ratio": self.damping_ratio,
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


def spectrum_harmonics(natural: float, turn: float, samples: int) -> int:
    """How many harmonics the spectrum shows: past twice the natural frequency, at least
    :data:`SPECTRUM_MIN_HARMONICS`, at most :data:`SPECTRUM_MAX_HARMONICS` and half the samples."""
    return int(min(max(SPECTRUM_MIN_HARMONICS, math.ceil(2.0 * natural / turn)), SPECTRUM_MAX_HARMONICS, samples // 2))


def compliant_response(kin: "Kinematics", train: "FollowerTrain", compliance: TrainCompliance, rpm: float) -> CompliantResult:
    """The periodic steady state of the compliant train at ``rpm`` (:class:`CompliantResult`).

    Raises :class:`GeometryError` for an undamped train exactly resonant with the turn."""
    from camgen import dynamics as dy
    from camgen.checks import run_ends

    r, r_dot, _ = response_from(kin, train, compliance, rpm)
    osc = oscillator(train, compliance)
    omega = angular_speed(rpm)
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
    spectrum = acceleration_spectrum(kin, rpm, spectrum_harmonics(wn / TWO_PI, rpm / 60.0, kin.theta.size))
    return CompliantResult(rpm, kin.theta, r, r_dot, force, rigid, wn / TWO_PI, rpm / 60.0, zt, spectrum,
                           starts, amplitude * lever, run_ends(force < 0, kin.theta), lever, train.motion)
