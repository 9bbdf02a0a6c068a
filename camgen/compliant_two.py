"""A two-degree compliant follower train: its periodic steady-state response to the cam.

The one-degree model (:mod:`camgen.compliant`) lumps the moving parts into one mass on the
train's stiffness.  A follower with a return spring and a stiff train (a roller on a rod
driving a tool, a valve train) has two: a cam-side mass ``m1`` (roller, follower rod end)
behind the train's stiffness ``k1`` from the cam contact, and the tool-side mass ``m2``
joined to it by the follower's own stiffness ``k2`` (translating follower; Koster, *Vibrations
of cam mechanisms*, 1974, ch. 4; Norton, *Cam Design and Manufacturing Handbook*, ch. 10,
the two-mass model).  ``mass_kg`` stays the whole moving mass ``M = m1 + m2`` (the rigid model's
and the weight's), ``tool_mass_kg`` is ``m2``.  The return spring ``K`` (with its preload and
the follower's own viscous damping ``C``) acts on ``m2`` by default, on ``m1`` when the scene
says so; the external load presses on the tool (``m2``); the weight is shared by the masses.

The model, with ``x1, x2`` the masses' positions, ``y(t) = s(w t)`` the cam's::

    m1 x1'' = k1 (y - x1) + c1 (y' - x1') + k2 (x2 - x1) + c2 (x2' - x1') - e1 S - G m1 / M
    m2 x2'' = k2 (x1 - x2) + c2 (x1' - x2')                               - e2 S - G m2 / M - L
    S = K (x_j - q_min) + P0 + C x_j'      (the spring's force, on mass j: e_j = 1, the other 0)

a viscous damper across each spring: ``c1 = 2 zeta sqrt((k1 + K) M)`` (the one-degree train's,
so that the model becomes it exactly as ``k2`` grows) and ``c2 = 2 zeta sqrt(k2 m1 m2 / M)``
(the follower's own spring on the masses' reduced mass), ``zeta`` the scene's damping ratio.
The cam pushes with ``F_c = k1 (y - x1) + c1 (y' - x1')``.  In the errors ``r_i = x_i - y``:

    Mm r'' + Cm r' + Km r = -m y'' - e (K y + C y') + f,   f = e (K q_min - P0) - G m / M - (0, L)

with ``Km = [[k1 + k2 + e1 K, -k2], [-k2, k2 + e2 K]]``, ``Cm`` the same in ``c1, c2, C``.

The periodic state is found as the one-degree model's (exact for the linear model): the law
between samples its quintic Hermite interpolant, each step by the matrix exponential of the
4-state matrix augmented by the forcing's derivative chain (Van Loan 1978), the recursion
summed by :func:`camgen.compliant.prefix_scan`, the turn closed by ``(I - Phi^N) z0 = S_N``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.compliant import (turn_steps, RESONANCE_TOL, TWO_PI, CompliantResult, acceleration_spectrum, angular_speed,
                              contact_projection, dwell_starts, prefix_scan, quintic_chain,
                              spectrum_harmonics)
from camgen.errors import GeometryError, ParameterError, require_finite

if TYPE_CHECKING:
    from camgen.compliant import TrainCompliance
    from camgen.dynamics import FollowerTrain, Kinematics

__all__ = ["SPRING_PLACES", "FollowerCompliance", "TwoMassTrain", "TwoDegreeResult", "natural_frequencies",
           "two_degree_response", "two_degree_states", "two_mass_train"]

#: Where the return spring (with its preload and the follower's own damping) acts.
SPRING_PLACES = ("tool", "cam_side")


@dataclass(frozen=True)
class FollowerCompliance:
    """The follower's own elasticity between its cam-side and tool-side masses: ``stiffness``
    N/mm (k2), ``tool_mass`` kg (m2, the part of the train's mass beyond it), ``spring_at``
    the mass the return spring acts on (one of :data:`SPRING_PLACES`)."""

    stiffness: float
    tool_mass: float
    spring_at: str = "tool"

    def __post_init__(self) -> None:
        if not require_finite("follower_stiffness", self.stiffness) > 0:
            raise ParameterError("follower_stiffness", self.stiffness, "follower_stiffness > 0 N/mm")
        if not require_finite("tool_mass", self.tool_mass) > 0:
            raise ParameterError("tool_mass", self.tool_mass, "tool_mass > 0 kg")
        if self.spring_at not in SPRING_PLACES:
            raise ParameterError("return_spring_on", self.spring_at, "one of " + ", ".join(f'"{p}"' for p in SPRING_PLACES))


@dataclass(frozen=True)
class TwoMassTrain:
    """The two-mass train's matrices in generalised units (N, mm, s): ``mass`` (m1, m2) in N per
    mm/s^2, ``stiffness`` and ``damping`` the 2 x 2 ``Km`` and ``Cm``, the contact spring ``k1``
    and damper ``c1``, the return spring's ``k_return`` and ``c_follower`` and the 0/1 vector
    ``spring`` of the mass they act on."""

    mass: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    k1: float
    c1: float
    k_return: float
    c_follower: float
    spring: np.ndarray

    def state_matrix(self) -> np.ndarray:
        """``A`` of ``z = (r1, r2, r1', r2')``: ``z' = A z`` in free vibration."""
        inv = 1.0 / self.mass
        a = np.zeros((4, 4))
        a[0, 2] = a[1, 3] = 1.0
        a[2:, :2] = -inv[:, None] * self.stiffness
        a[2:, 2:] = -inv[:, None] * self.damping
        return a


def two_mass_train(train: "FollowerTrain", compliance: "TrainCompliance") -> TwoMassTrain:
    """The :class:`TwoMassTrain` of a translating, force-closed ``train`` with ``compliance``
    (whose ``follower`` is a :class:`FollowerCompliance`)."""
    from camgen import dynamics as dy

    follower = compliance.follower
    assert follower is not None
    if train.closure != "force":
        raise ParameterError("train_stiffness", compliance.stiffness, "left out for a form-closed train",
                             "the compliant model is of a spring-loaded (force-closed) train")
    if train.motion != "translating":
        raise ParameterError("follower_stiffness", follower.stiffness, "left out for an oscillating follower",
                             "the two-mass train is modelled for a translating follower")
    total = train.mass * dy.KG_MM_PER_S2_TO_N
    m2 = follower.tool_mass * dy.KG_MM_PER_S2_TO_N
    if not follower.tool_mass < train.mass:
        raise ParameterError("tool_mass", follower.tool_mass, f"0 < tool_mass < mass ({train.mass:g} kg)",
                             "mass_kg is the whole moving mass, the tool's part of it beyond the follower's stiffness")
    m1 = total - m2
    k1, k2, big_k = float(compliance.stiffness), float(follower.stiffness), float(train.spring_rate)
    zeta = compliance.damping_ratio
    c1 = 2.0 * zeta * math.sqrt((k1 + big_k) * total)
    c2 = 2.0 * zeta * math.sqrt(k2 * m1 * m2 / total)
    c_follower = train.damping * dy.N_S_PER_M_TIMES_MM_PER_S_TO_N
    e = np.array([1.0, 0.0]) if follower.spring_at == "cam_side" else np.array([0.0, 1.0])
    stiff = np.array([[k1 + k2, -k2], [-k2, k2]]) + np.diag(e * big_k)
    damp = np.array([[c1 + c2, -c2], [-c2, c2]]) + np.diag(e * c_follower)
    return TwoMassTrain(np.array([m1, m2]), stiff, damp, k1, c1, big_k, c_follower, e)


def natural_frequencies(system: TwoMassTrain) -> tuple[np.ndarray, np.ndarray]:
    """The undamped natural frequencies (Hz, ascending: ``Km v = w^2 Mm v``) and the damping
    ratio of each mode from the damped eigenvalues ``lambda`` of the state matrix, paired by
    modulus (``zeta = -(l_a + l_b) / (2 sqrt(l_a l_b))``: ``-Re l / |l|`` for a complex pair)."""
    root = 1.0 / np.sqrt(system.mass)
    omega2 = np.linalg.eigvalsh(root[:, None] * system.stiffness * root[None, :])
    lam = np.linalg.eigvals(system.state_matrix())
    lam = lam[np.argsort(np.abs(lam), kind="stable")]
    pairs = lam.reshape(2, 2)
    wn = np.sqrt(np.abs(pairs[:, 0] * pairs[:, 1]))
    zeta = -(pairs[:, 0] + pairs[:, 1]).real / (2.0 * wn)
    return np.sqrt(omega2) / TWO_PI, zeta


def augmented_matrix(system: TwoMassTrain) -> np.ndarray:
    """The 14 x 14 matrix of ``z = (r1, r2, r1', r2')`` augmented by the forcing's derivative
    chain ``u = (y, y', ..., y^(5), f1, f1', f2, f2')`` (law a quintic, loads linear in a step):
    ``expm(H dt)`` holds the step's ``Phi`` (4 x 4) top-left, ``Gamma`` (4 x 10) top-right."""
    h = np.zeros((14, 14))
    h[:4, :4] = system.state_matrix()
    inv = 1.0 / system.mass
    # r_j'' += -(e_j K y + e_j C y') / m_j - y'' + f_j / m_j
    h[2:4, 4] = -system.spring * system.k_return * inv
    h[2:4, 5] = -system.spring * system.c_follower * inv
    h[2:4, 6] = -1.0
    h[2, 10] = inv[0]
    h[3, 12] = inv[1]
    for i in range(4, 9):
        h[i, i + 1] = 1.0
    h[10, 11] = h[12, 13] = 1.0
    return h


def _loads(kin: "Kinematics", train: "FollowerTrain", system: TwoMassTrain) -> np.ndarray:
    """``f`` of each mass at every sample, shape (N, 2): the spring's preload side on its mass,
    the weight shared by mass, the external load on the tool (N)."""
    from camgen import dynamics as dy

    a_coef, _, _ = dy.force_coefficients(kin, train)
    load = np.broadcast_to(train.load_at(kin.theta), kin.theta.shape)
    static = a_coef - train.spring_rate * (kin.s - kin.s.min())  # P0 + L + G
    weight = static - train.spring_preload - load
    share = system.mass / float(np.sum(system.mass))
    spring_side = train.spring_rate * kin.s.min() - train.spring_preload
    return system.spring[None, :] * spring_side - weight[:, None] * share[None, :] - np.outer(load, [0.0, 1.0])


def two_degree_states(kin: "Kinematics", train: "FollowerTrain", compliance: "TrainCompliance", rpm: float,
                      z0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The state ``z = (r1, r2, r1', r2')`` (mm, mm/s) at every sample over one turn from ``z0``
    at ``theta[0]`` (None: the periodic state), shape (N, 4), and the state after the turn.

    Raises :class:`GeometryError` when the undamped train is resonant with the turn."""
    theta = kin.theta
    n = theta.size
    omega, moving, dt = turn_steps(theta, rpm)
    system = two_mass_train(train, compliance)
    f = _loads(kin, train, system)
    slope = (np.roll(f, -1, axis=0) - f) / dt[:, None]
    chain = np.concatenate([quintic_chain(kin.s, omega * kin.ds, omega**2 * kin.d2s, dt),
                            np.stack([f[:, 0], slope[:, 0], f[:, 1], slope[:, 1]], axis=1)], axis=1)
    phi = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
    g = np.zeros((n, 4))
    if moving.any():
        from scipy.linalg import expm

        lengths, which = np.unique(dt[moving], return_inverse=True)
        e = expm(augmented_matrix(system)[None, :, :] * lengths[:, None, None])[which]
        phi[moving] = e[:, :4, :4]
        g[moving] = np.einsum("nij,nj->ni", e[:, :4, 4:], chain[moving])
    prod, acc = prefix_scan(phi, g)
    if z0 is None:
        closing = np.eye(4) - prod[-1]
        if abs(np.linalg.det(closing)) < RESONANCE_TOL:
            freqs, _ = natural_frequencies(system)
            raise GeometryError(f"the undamped train (natural frequencies {freqs[0]:.6g} and {freqs[1]:.6g} Hz) is in "
                                f"resonance with the turn ({rpm / 60.0:.6g} Hz): it has no periodic state; give a "
                                "damping_ratio > 0")
        z0 = np.linalg.solve(closing, acc[-1])
    z0 = np.asarray(z0, dtype=float)
    z = np.empty((n, 4))
    z[0] = z0
    z[1:] = prod[:-1] @ z0 + acc[:-1]
    return z, prod[-1] @ z0 + acc[-1]


def residual_amplitudes(system: TwoMassTrain, z: np.ndarray, static: np.ndarray) -> np.ndarray:
    """The tool mass's free-vibration amplitude from states ``z`` (S, 4) about the static
    deflections ``static`` (S, 2): the sum over the modes of each one's amplitude at the tool,
    ``sum_j |V[1, j] (V^-1 u)_j|`` over the eigenvectors ``V`` of the state matrix (a complex
    pair's two terms add to its real amplitude; the largest the free vibration can reach)."""
    lam, vec = np.linalg.eig(system.state_matrix())
    u = z - np.concatenate([static, np.zeros_like(static)], axis=1)
    coef = np.linalg.solve(vec, u.T)  # (4, S)
    return np.sum(np.abs(vec[1, :, None] * coef), axis=0)


@dataclass(frozen=True, eq=False)
class TwoDegreeResult(CompliantResult):
    """:class:`camgen.compliant.CompliantResult` of the two-mass train: ``error``, ``error_rate``
    and ``residual`` are the tool mass's; ``cam_side_error`` the cam-side mass's (mm);
    ``natural_frequencies`` (Hz) and ``damping_ratios`` of both modes, ascending
    (``natural_frequency`` and ``damping_ratio`` are the first's); ``follower_stiffness`` N/mm,
    ``tool_mass`` kg and ``spring_at`` as given."""

    cam_side_error: np.ndarray = None  # type: ignore[assignment]
    natural_frequencies: tuple[float, float] = (0.0, 0.0)
    damping_ratios: tuple[float, float] = (0.0, 0.0)
    follower_stiffness: float = 0.0
    tool_mass: float = 0.0
    spring_at: str = "tool"

    def figures(self) -> dict[str, Any]:
        """The one-degree figures (the tool's error and residual, the first mode) and the two-mass ones."""
        out = super().figures()
        first, second = self.natural_frequencies
        out.update({
            "model": "two masses",
            "follower_stiffness_N_per_mm": self.follower_stiffness,
            "tool_mass_kg": self.tool_mass,
            "return_spring_on": self.spring_at,
            "natural_frequencies_Hz": [first, second],
            "natural_frequency_harmonics": [first / self.turn_frequency, second / self.turn_frequency],
            "mode_damping_ratios": [float(v) for v in self.damping_ratios],
            "max_cam_side_dynamic_error_mm": float(np.max(np.abs(self.cam_side_error))),
        })
        return out


def two_degree_response(kin: "Kinematics", train: "FollowerTrain", compliance: "TrainCompliance",
                        rpm: float) -> TwoDegreeResult:
    """The periodic steady state of the two-mass train at ``rpm`` (:class:`TwoDegreeResult`)."""
    from camgen import dynamics as dy
    from camgen.checks import run_ends

    z, _ = two_degree_states(kin, train, compliance, rpm)
    system = two_mass_train(train, compliance)
    omega = angular_speed(rpm)
    projection = contact_projection(kin, train)
    force = -(system.k1 * z[:, 0] + system.c1 * z[:, 2]) / projection
    a, b, c = dy.force_coefficients(kin, train)
    rigid = (a + b * omega + c * omega**2) / projection
    # residual vibration: the free vibration of the tool about the dwell's static deflection Km r = f - e K y
    starts = dwell_starts(kin)
    f = _loads(kin, train, system)[starts]
    static = np.linalg.solve(system.stiffness, (f - np.outer(kin.s[starts], system.spring * system.k_return)).T).T
    amplitude = residual_amplitudes(system, z[starts], static)
    freqs, zetas = natural_frequencies(system)
    spectrum = acceleration_spectrum(kin, rpm, spectrum_harmonics(float(freqs[1]), rpm / 60.0, kin.theta.size))
    follower = compliance.follower
    return TwoDegreeResult(rpm, kin.theta, z[:, 1], z[:, 3], force, rigid, float(freqs[0]), rpm / 60.0, float(zetas[0]),
                           spectrum, starts, amplitude, run_ends(force < 0, kin.theta), 1.0, train.motion,
                           cam_side_error=z[:, 0], natural_frequencies=(float(freqs[0]), float(freqs[1])),
                           damping_ratios=(float(zetas[0]), float(zetas[1])), follower_stiffness=follower.stiffness,
                           tool_mass=follower.tool_mass, spring_at=follower.spring_at)
