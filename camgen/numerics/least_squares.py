"""Nonlinear least squares for small problems: Levenberg-Marquardt with a forward-difference Jacobian.

:func:`levenberg_marquardt` minimises ``|r(p)|^2 / 2`` over a handful of parameters (Marquardt
1963, with Nielsen's damping update: H. B. Nielsen, *Damping parameter in Marquardt's method*,
IMM-REP-1999-05, DTU).  camgen fits the tricycle's error model with it
(:mod:`camgen.mechanisms.tricycle_fit`) without importing ``scipy.optimize``; the tests compare it
with scipy's MINPACK-based ``least_squares(method="lm")`` and with NIST's certified values.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["FTOL", "LeastSquares", "levenberg_marquardt"]

#: Default relative fall of the cost below which an accepted step ends the iteration.
FTOL = 1e-12


@dataclass(frozen=True)
class LeastSquares:
    """A Levenberg-Marquardt solution: parameters, residuals and Jacobian there, cost (half the
    residual sum of squares) and the number of residual evaluations."""

    x: np.ndarray
    fun: np.ndarray
    jac: np.ndarray
    cost: float
    nfev: int


def levenberg_marquardt(residual: Callable[[np.ndarray], np.ndarray], p0: np.ndarray, scale: np.ndarray,
                        max_nfev: int = 400, ftol: float = FTOL) -> LeastSquares:
    """Minimise ``|residual(p)|^2 / 2`` from ``p0`` (Marquardt 1963, with Nielsen's damping update).

    Forward-difference Jacobian with steps ``sqrt(eps) * max(|p|, scale)``; the damping
    ``mu * diag(scale^-2)`` makes the steps scale-aware, as ``x_scale`` does in MINPACK.  Stops
    when an accepted step lowers the cost by less than ``ftol`` of it, or after ``max_nfev``
    evaluations.  Small problems only (a handful of parameters): the normal equations are solved directly.
    """
    p = np.asarray(p0, dtype=float).copy()
    scale = np.asarray(scale, dtype=float)
    r = residual(p)
    nfev = 1

    def jacobian(p: np.ndarray, r: np.ndarray) -> np.ndarray:
        nonlocal nfev
        h = math.sqrt(np.finfo(float).eps) * np.maximum(np.abs(p), scale)
        nfev += p.size
        return np.stack([(residual(p + h[j] * np.eye(p.size)[j]) - r) / h[j] for j in range(p.size)], axis=1)

    cost = 0.5 * float(r @ r)
    jac = jacobian(p, r)
    weight = 1.0 / scale**2
    mu, nu = 1e-3 * float(np.max(np.diag(jac.T @ jac) / weight)), 2.0
    while nfev < max_nfev and cost > 0.0:
        a, g = jac.T @ jac, jac.T @ r
        if not mu * float(np.min(weight)) < 1e16 * max(float(np.max(np.diag(a))), np.finfo(float).tiny):
            break  # no step lowers the cost however short: a minimum (to rounding)
        try:
            delta = np.linalg.solve(a + mu * np.diag(weight), -g)
        except np.linalg.LinAlgError:
            mu *= nu
            nu *= 2.0
            continue
        trial = p + delta
        r_trial = residual(trial)
        nfev += 1
        cost_trial = 0.5 * float(r_trial @ r_trial)
        predicted = -(delta @ g) - 0.5 * delta @ (a @ delta)
        rho = (cost - cost_trial) / predicted if predicted > 0 else -1.0
        if rho > 0:  # accepted
            done = cost - cost_trial <= ftol * cost
            p, r, cost = trial, r_trial, cost_trial
            jac = jacobian(p, r)
            mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            nu = 2.0
            if done:
                break
        else:
            mu *= nu
            nu *= 2.0
    return LeastSquares(p, r, jac, cost, nfev)
