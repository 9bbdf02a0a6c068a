"""Measured lift data: the smoothest periodic spline within a stated tolerance of every reading.

A lift table read with an instrument carries the instrument's noise and the rounding of its last
digit; interpolating it (:class:`~camgen.synthesis.lift_table.LiftTable`) puts that noise into the
cam's curvature (issue 26 item 3).  :func:`smooth_readings` fits instead:

* **What is smoothest.** The integral of the squared jerk over the turn, ``J(f) = int (f''')^2
  dtheta``.  Its minimiser among periodic functions taking given values at the readings is the
  periodic *quintic* spline with knots at the readings, continuous through the 4th derivative
  (the natural-spline property of ``int (f^(m))^2``, m = 3: degree 2m - 1, C^(2m-2); de Boor,
  *A Practical Guide to Splines*, ch. XIV; Wahba, *Spline Models for Observational Data*,
  1990, ch. 1).  So the smoothed cam is the lift table's own representation (the quintic
  interpolant of the fitted values) and every check, envelope and export takes it unchanged; the
  jerk stays continuous.  The 4th derivative's integral would give a C6 spline of degree 7 that
  camgen has no representation for, and the jerk is the derivative a cam's vibration answers.
* **The fit.** The penalised periodic smoothing spline: for a penalty lam, the f minimising
  ``sum_i (y_i - f(theta_i))^2 + lam J(f)`` (Reinsch 1967, Numer. Math. 10, for its cubic
  form).  Over piecewise quintics in Hermite form (value, slope and 2nd derivative at every
  reading, C2 by construction) the objective is a quadratic form whose normal equations are a
  cyclic block-tridiagonal system with 3 x 3 blocks, symmetric positive definite (solved
  sparse by scipy, imported only when a table is smoothed); its minimiser is
  C4 by the property above (tests/test_smoothing.py measures it).  The penalty is written as a
  bandwidth b (rad), lam = b^6 / h_mean (the smoothing spline's equivalent kernel width,
  Silverman 1984, Ann. Statist. 12), and raised by bisection on log b until the largest
  residual reaches the tolerance; the bisection keeps the feasible end, so the bound holds
  whatever the residual does between the ends.
* **Verified.** The fitted values are then interpolated by the quintic periodic spline
  (:class:`~camgen.synthesis.lift_table.LiftTable`), evaluated back at every reading and every
  residual compared with the tolerance: a fit that misses it by more than
  :data:`VERIFY_SLACK` raises (never happens by construction; it guards the arithmetic).

Cost: each trial is one sparse solve of 3 n unknowns (n readings), O(n); the bisection stops
after at most :data:`MAX_STEPS` trials (bounded before the work starts).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from camgen.errors import GeometryError, ParameterError
from camgen.synthesis.lift_table import LiftTable

__all__ = ["BANDWIDTH_RATIO", "MAX_STEPS", "MIN_BANDWIDTH", "SmoothedLiftTable", "SmoothingFit", "VERIFY_SLACK", "jerk_penalty", "smooth_readings", "smoothing_spline"]

TWO_PI = 2.0 * math.pi
#: The bisection on the bandwidth stops when its ends are within this ratio.
BANDWIDTH_RATIO = 1.0 + 1e-4
#: Most trial fits of the bisection (a cap applied before the work).
MAX_STEPS = 64
#: Smallest bandwidth tried, relative to the smallest spacing of the readings (below: the interpolation).
MIN_BANDWIDTH = 1e-3
#: Residuals may exceed the tolerance by at most this (mm or rad, absolute) after the fit: rounding only.
VERIFY_SLACK = 1e-12


@dataclass(frozen=True)
class SmoothingFit:
    """The smoothed readings.

    Attributes
    ----------
    angles : (n,) cam angles of the readings, rad (as read, closing row dropped).
    readings : (n,) the readings (mm, or rad of swing).
    fitted : (n,) the smooth curve at the readings (same unit): the quintic periodic spline through
        them is the fit.
    tolerance : the stated tolerance (same unit).
    bandwidth : b (rad) of the penalty lam = b^6 / h_mean; 0: the readings are interpolated.
    jerk_integral : int (s''')^2 dtheta of the fit (unit^2 / rad^5).
    jerk_integral_interpolated : the same of the interpolation of the readings.
    """

    angles: np.ndarray
    readings: np.ndarray
    fitted: np.ndarray
    tolerance: float
    bandwidth: float
    jerk_integral: float
    jerk_integral_interpolated: float

    @property
    def residuals(self) -> np.ndarray:
        """Reading minus fit at every reading (same unit)."""
        return self.readings - self.fitted

    @property
    def largest(self) -> float:
        """Largest |residual|."""
        return float(np.max(np.abs(self.residuals)))

    @property
    def rms(self) -> float:
        """Root mean square residual."""
        return float(np.sqrt(np.mean(self.residuals**2)))


@lru_cache(maxsize=1)
def _piece_form() -> np.ndarray:
    """Q (6, 6): int_0^1 (p''')^2 du of the quintic p on [0, 1] with Hermite data d = (p, p',
    p'' at 0, then at 1) is d^T Q d."""
    a = np.zeros((6, 6))  # rows: derivatives 0..2 at u = 0, then at u = 1; columns: coefficients of u^0 .. u^5
    for j in range(3):
        a[j, j] = math.factorial(j)
        for p in range(j, 6):
            a[3 + j, p] = math.factorial(p) / math.factorial(p - j)
    hinv = np.linalg.inv(a)
    power = np.arange(3, 6)  # d^3/du^3 of u^p = p (p - 1) (p - 2) u^(p - 3); lower powers vanish
    falling = power * (power - 1) * (power - 2)
    g = np.zeros((6, 6))
    g[3:, 3:] = np.outer(falling, falling) / (power[:, None] + power[None, :] - 5)
    return hinv.T @ g @ hinv


def _piece_matrices(h: np.ndarray) -> np.ndarray:
    """(n, 6, 6): int (f''')^2 over piece i as z^T L_i z, z = (f, f', f'' at its left break, then
    at its right), h the pieces' spans (rad)."""
    powers = h[:, None] ** np.array([0, 1, 2, 0, 1, 2])[None, :]  # Hermite data = powers * derivatives
    return _piece_form()[None] * powers[:, :, None] * powers[:, None, :] / h[:, None, None] ** 5


def jerk_penalty(angles: np.ndarray, derivatives: np.ndarray) -> float:
    """int (s''')^2 dtheta over the turn of the piecewise quintic with ``derivatives`` (n, 3)
    (s, s', s'' at every reading ``angles``, rad; the turn closes periodically)."""
    h = np.diff(np.append(angles, angles[0] + TWO_PI))
    z = np.concatenate([derivatives, np.roll(derivatives, -1, axis=0)], axis=1)
    return float(np.einsum("ni,nij,nj->", z, _piece_matrices(h), z))


def smoothing_spline(angles: np.ndarray, readings: np.ndarray, bandwidth: float) -> np.ndarray:
    """(n, 3): s, s', s'' at the readings of the periodic penalised smoothing spline with
    bandwidth ``bandwidth`` (rad; lam = b^6 / h_mean, module notes) through ``readings`` at
    ``angles`` (rad, strictly increasing, within one turn)."""
    n = angles.size
    h = np.diff(np.append(angles, angles[0] + TWO_PI))
    lam = bandwidth**6 / float(np.mean(h))
    # unknowns scaled w = (s, hbar s', hbar^2 s'') with hbar the mean span beside each reading
    hbar = 0.5 * (h + np.roll(h, 1))
    scale = hbar[:, None] ** -np.arange(3)[None, :]  # z = scale * w
    pair = np.concatenate([scale, np.roll(scale, -1, axis=0)], axis=1)  # (n, 6)
    local = lam * _piece_matrices(h) * pair[:, :, None] * pair[:, None, :]  # piece i couples readings i and i + 1
    diag = local[:, :3, :3] + np.roll(local[:, 3:, 3:], 1, axis=0)
    diag[:, 0, 0] += 1.0  # the data term
    upper = local[:, :3, 3:]
    lower = np.roll(local[:, 3:, :3], 1, axis=0)
    rhs = np.zeros((n, 3))
    rhs[:, 0] = readings
    w = _solve_cyclic(lower, diag, upper, rhs)
    if not np.all(np.isfinite(w)):
        raise GeometryError(f"the smoothing fit of {n} readings is singular at bandwidth {bandwidth:.6g} rad")
    return w * scale


def _solve_cyclic(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """The cyclic block-tridiagonal system (blocks (n, b, b), rhs (n, b)), symmetric positive
    definite, equilibrated by its diagonal (Jacobi scaling) and solved sparse (scipy's SuperLU):
    O(n) whatever the couplings (a cyclic block reduction needs them to die out first)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import spsolve

    n, b, _ = diag.shape
    first = np.arange(n)[:, None, None] * b + np.arange(b)[None, :, None]  # (n, b, 1) unknowns of each row block
    blocks = [(diag, first, first), (upper, first, np.roll(first, -1, axis=0)), (lower, first, np.roll(first, 1, axis=0))]
    rows = np.concatenate([np.broadcast_to(r, m.shape).ravel() for m, r, _ in blocks])
    cols = np.concatenate([np.broadcast_to(c.transpose(0, 2, 1), m.shape).ravel() for m, _, c in blocks])
    values = np.concatenate([m.ravel() for m, _, _ in blocks])
    d = np.sqrt(np.abs(np.einsum("nii->ni", diag).ravel()))
    matrix = coo_matrix((values / (d[rows] * d[cols]), (rows, cols)), shape=(n * b, n * b)).tocsc()
    return (np.asarray(spsolve(matrix, rhs.ravel() / d)) / d).reshape(n, b)


def _interpolated(angles: np.ndarray, readings: np.ndarray) -> np.ndarray:
    """(n, 3): s, s', s'' at the readings of the periodic quintic interpolating them (bandwidth 0)."""
    from camgen.numerics.interpolate import periodic_spline

    x = np.append(angles, angles[0] + TWO_PI)
    pp = periodic_spline(x, np.append(readings, readings[0]), 5)
    return np.stack([readings, pp.derivative(1)(angles), pp.derivative(2)(angles)], axis=1)


def smooth_readings(angles: np.ndarray, readings: np.ndarray, tolerance: float) -> SmoothingFit:
    """The smoothest periodic quintic spline (least int (s''')^2) of the penalised family within
    ``tolerance`` of every reading (module notes).

    Parameters
    ----------
    angles : (n,) cam angles, rad, strictly increasing within one turn (a LiftTable's ``angles``).
    readings : (n,) lifts (mm) or swings (rad).
    tolerance : > 0, same unit as the readings.

    Returns
    -------
    SmoothingFit
        Its ``fitted`` values within ``tolerance`` of the readings (verified on the spline built
        through them by :class:`SmoothedLiftTable`).
    """
    if not (math.isfinite(tolerance) and tolerance > 0):
        raise ParameterError("smoothing_mm", tolerance, "> 0")
    angles = np.asarray(angles, dtype=float)
    readings = np.asarray(readings, dtype=float)
    h = np.diff(np.append(angles, angles[0] + TWO_PI))

    def trial(b: float) -> tuple[np.ndarray, float]:
        z = smoothing_spline(angles, readings, b)
        return z, float(np.max(np.abs(readings - z[:, 0])))

    interpolated = _interpolated(angles, readings)
    best_b, best = 0.0, interpolated  # bandwidth 0: the readings themselves, always within
    # bracket: from the mean spacing, doubling (or halving) to a feasible lo and an infeasible hi
    lo, hi = 0.0, math.inf
    b = float(np.mean(h))
    for _ in range(MAX_STEPS):
        z, largest = trial(b)
        if largest <= tolerance:
            lo, best_b, best = b, b, z
            if b >= TWO_PI:  # smooth over the whole turn and still within: the smoothest trial
                return _fit(angles, readings, tolerance, best_b, best, interpolated)
            b *= 2.0
        else:
            hi = b
            b *= 0.5
        if math.isfinite(hi) and (lo > 0 or b < MIN_BANDWIDTH * float(np.min(h))):
            break
    if lo == 0.0:  # no trial within: the interpolation
        return _fit(angles, readings, tolerance, 0.0, interpolated, interpolated)
    for _ in range(MAX_STEPS):  # bisection on log b, keeping the feasible end
        if hi / lo <= BANDWIDTH_RATIO:
            break
        mid = math.sqrt(lo * hi)
        z, largest = trial(mid)
        if largest <= tolerance:
            lo, best_b, best = mid, mid, z
        else:
            hi = mid
    return _fit(angles, readings, tolerance, best_b, best, interpolated)


def _fit(angles: np.ndarray, readings: np.ndarray, tolerance: float, bandwidth: float, best: np.ndarray,
         interpolated: np.ndarray) -> SmoothingFit:
    return SmoothingFit(angles, readings, best[:, 0].copy(), float(tolerance), bandwidth, jerk_penalty(angles, best),
                        jerk_penalty(angles, interpolated))


class SmoothedLiftTable(LiftTable):
    """A lift table smoothed within a tolerance: the periodic quintic spline through the fitted
    values of :func:`smooth_readings` (the smoothing spline itself, module notes), verified within
    the tolerance at every reading.

    Attributes (besides :class:`~camgen.synthesis.lift_table.LiftTable`'s)
    ----------------------------------------------------------------------
    raw : the table as read: the interpolation of the readings (the checks compare with it).
    fit : the :class:`SmoothingFit`.
    residuals : (n,) reading minus the smoothed spline evaluated at each reading (unit).
    """

    def __init__(self, raw: LiftTable, tolerance: float, key: str = "smoothing_mm") -> None:
        fit = smooth_readings(raw.angles, raw.lifts, tolerance)
        super().__init__(np.degrees(raw.angles), fit.fitted, degree=raw.degree, unit=raw.unit, key=key)
        self.raw = raw
        self.fit = fit
        self.residuals = raw.lifts - self(raw.angles)[0]  # the spline itself, read back at every reading
        worst = int(np.argmax(np.abs(self.residuals)))
        if abs(self.residuals[worst]) > tolerance + VERIFY_SLACK:
            raise GeometryError(f"the smoothed lift misses reading {worst + 1} by {self.residuals[worst]:.6g} {raw.unit}, beyond "
                                f"{key} = {tolerance:g}")
