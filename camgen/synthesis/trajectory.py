"""Trajectory -> disk cam by arc length, curvature and a periodic cubic spline.

Paper 004 (Jiang et al. 2022), Sections 2.3 and 3, eqs. (8)-(13).

A periodic trajectory ``y = f(x)`` over one period ``[0, l]`` is followed by a point of the
vehicle (the drive wheel A, see :mod:`camgen.mechanisms.tricycle`).  The cam turns once per
period, so the travelled arc length is proportional to the cam angle (eq. 10):
``s = S theta / 2 pi`` with ``S`` the arc length of one period (eq. 9).  For a uniform grid
``theta_i`` camgen inverts ``s -> x`` (Newton on the arc-length integral), evaluates the
path curvature ``k`` and turns it into the cam radius (eq. 13)

    rho = d L k / (1 + D k) + r_b.

Curvature schemes (``scheme``):

* ``"exact"``: ``k = f'' / (1 + f'^2)^1.5`` from the exact derivatives of ``f`` (symbolic
  for expressions, of a periodic quintic spline fit for tables);
* ``"forward"`` / ``"central"``: the paper's eq. (12), first and second finite differences of
  the sequences ``X_i = x(theta_i)``, ``Y_i = f(X_i)``, kept for comparison (benchmark).

Tolerances: the arc length is converged to ``1e-12`` relative (panel doubling) and the
Newton inversion to ``newton_tol`` mm (default ``1e-10``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from camgen.errors import GeometryError, ParameterError, ceil_significant, quoted, require_positive

__all__ = [
    "ArcLength", "CHECK_GRID", "CamSynthesis", "Func", "MAX_ROWS", "MAX_TABLE_BYTES", "PathError", "SCHEMES",
    "Trajectory", "arc_length", "cam_radius", "path_curvature", "read_trajectory_csv", "sample_path",
    "steerable_paths", "steerable_radius", "synthesize_rho", "trajectory_from_expression", "trajectory_from_table",
]

Func = Callable[[np.ndarray], np.ndarray]

SCHEMES = ("exact", "forward", "central")
#: Largest trajectory table read, bytes.
MAX_TABLE_BYTES = 8 << 20
#: Largest number of rows of a trajectory table (the lift table's cap).
MAX_ROWS = 100_000
_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(20)
#: Points of the uniform grid (one period) at which the exact curvature is checked besides the
#: arc-length quadrature nodes.
CHECK_GRID = 4001


class PathError(GeometryError):
    """The device is valid but the path cannot be steered (or resolved) with it.

    ``valid`` states which paths can, for the scene key that gave the path (the cam kind turns
    this into a :class:`~camgen.errors.ParameterError` naming ``expression`` or ``trajectory_csv``).
    """

    def __init__(self, message: str, valid: str = "a path the device can steer") -> None:
        super().__init__(message)
        self.valid = valid


def steerable_radius(d: float, wheelbase: float, half_track: float, base_radius: float) -> float:
    """Smallest radius (mm) of a right turn the device can steer: ``D + d L / r_b``.

    Eq. (13), ``rho = d L k / (1 + D k) + r_b``, needs ``1 + D k > 0`` (a right turn, ``k < 0``,
    of radius ``R = 1/|k| > D``) and ``rho > 0``; for ``k < 0`` the latter is
    ``r_b > d L / (R - D)``, i.e. ``R > D + d L / r_b``, the stronger of the two.  Left turns
    (``k > 0``) keep ``rho`` between ``r_b`` and ``r_b + d L / D`` at any radius.
    """
    return half_track + d * wheelbase / base_radius


def steerable_paths(d: float, wheelbase: float, half_track: float, base_radius: float) -> str:
    """The valid range of a path for the device, as the error messages state it."""
    r_min = ceil_significant(steerable_radius(d, wheelbase, half_track, base_radius), 6)  # rounded up: any radius above it steers
    return (f"a path whose right turns keep a radius > {r_min:g} mm = half_track_mm + lever_mm * wheelbase_mm / r_b "
            f"(D = {half_track:g}, d = {d:g}, L = {wheelbase:g}, r_b = L - rod_radius_mm = {base_radius:g} mm), "
            "features resolved by the arc-length quadrature (one period in at most 16384 panels)")


@dataclass(frozen=True)
class Trajectory:
    """A periodic path ``y = f(x)``, ``0 <= x <= period`` (mm), with exact derivatives."""

    period: float
    f: Func
    df: Func
    d2f: Func
    source: str

    def curvature(self, x: np.ndarray) -> np.ndarray:
        """Signed curvature of the path, 1/mm (> 0 turning left when travelling in +x)."""
        slope = self.df(x)
        return self.d2f(x) / (1.0 + slope * slope) ** 1.5

    def wrapped(self, x: np.ndarray) -> np.ndarray:
        """``f`` extended periodically beyond one period."""
        return self.f(np.mod(x, self.period))


def _check_periodic(traj: Trajectory, tol: float = 1e-6) -> Trajectory:
    """Reject a trajectory that is not periodic (value, slope, curvature) or not finite."""
    grid = np.linspace(0.0, traj.period, 4001)
    with np.errstate(all="ignore"):
        values = [traj.f(grid), traj.df(grid), traj.d2f(grid)]
    for name, arr in zip(("f", "f'", "f''"), values):
        if not np.all(np.isfinite(arr)):
            bad = grid[~np.isfinite(arr)][0]
            raise ParameterError("trajectory", traj.source, f"a function finite on 0 <= x <= {traj.period:g} mm", f"{name} is not finite at x = {bad:g} mm")
    scale = max(1.0, float(np.max(np.abs(values[0]))))
    ends = [(values[0], tol * scale, "f(0) = f(period)"), (values[1], tol, "f'(0) = f'(period)"), (values[2], tol / scale * 10, "f''(0) = f''(period)")]
    for arr, limit, what in ends:
        if abs(arr[-1] - arr[0]) > limit:
            raise ParameterError(
                "trajectory", traj.source, f"a periodic path with {what}",
                f"over the period {traj.period:g} mm it changes by {arr[-1] - arr[0]:.6g}; the cam turns once per period",
            )
    return traj


def trajectory_from_expression(text: str, period: float) -> Trajectory:
    """Trajectory from a whitelisted expression of ``x`` (see :mod:`camgen.synthesis.expression`)."""
    from camgen.synthesis.expression import parse_expression

    period = require_positive("period", period)
    expr = parse_expression(text)
    return _check_periodic(Trajectory(period, expr.f, expr.df, expr.d2f, text))


def trajectory_from_table(x: np.ndarray, y: np.ndarray, source: str = "table") -> Trajectory:
    """Trajectory from a table of points (one period, first and last ``y`` equal).

    The table is fitted by a periodic quintic interpolating spline (C4), whose derivatives
    give the curvature; the period is ``x[-1] - x[0]``.
    """
    from scipy.interpolate import make_interp_spline

    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.ndim != 1 or x.shape != y.shape or x.size < 8:
        raise ParameterError("trajectory table", f"{x.size} points", "at least 8 (x, y) points over one period")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ParameterError("trajectory table", "non-finite values", "finite numbers")
    if not np.all(np.diff(x) > 0):
        raise ParameterError("trajectory table", "x column", "strictly increasing x")
    if abs(y[-1] - y[0]) > 1e-9 * max(1.0, float(np.max(np.abs(y)))):
        raise ParameterError("trajectory table", f"y[0] = {y[0]:g}, y[-1] = {y[-1]:g}", "a periodic table: last y equal to first y")
    x0 = x[0]
    spline = make_interp_spline(x - x0, np.append(y[:-1], y[0]), k=5, bc_type="periodic")
    d1, d2 = spline.derivative(1), spline.derivative(2)
    period = float(x[-1] - x0)
    traj = Trajectory(period, lambda t: spline(t), lambda t: d1(t), lambda t: d2(t), source)
    return _check_periodic(traj, tol=1e-6)


# --------------------------------------------------------------------------------------------
# Arc length and its inverse
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ArcLength:
    """Arc length ``s(x) = integral_0^x sqrt(1 + f'^2)`` (eq. 9) on Gauss-Legendre panels."""

    trajectory: Trajectory
    edges: np.ndarray  # panel boundaries (M + 1,)
    cumulative: np.ndarray  # s at the boundaries (M + 1,)

    @property
    def total(self) -> float:
        """S, the arc length of one period, mm."""
        return float(self.cumulative[-1])

    def speed(self, x: np.ndarray) -> np.ndarray:
        slope = self.trajectory.df(x)
        return np.sqrt(1.0 + slope * slope)

    def nodes(self) -> np.ndarray:
        """The Gauss-Legendre nodes of every panel (M, 20), mm."""
        half = 0.5 * np.diff(self.edges)
        return self.edges[:-1, None] + half[:, None] * (_GL_NODES + 1.0)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """s(x), mm, for 0 <= x <= period (vectorised)."""
        x = np.asarray(x, dtype=float)
        k = np.clip(np.searchsorted(self.edges, x, side="right") - 1, 0, self.edges.size - 2)
        lo = self.edges[k]
        half = 0.5 * (x - lo)
        nodes = lo[..., None] + half[..., None] * (_GL_NODES + 1.0)
        return self.cumulative[k] + half * np.sum(_GL_WEIGHTS * self.speed(nodes), axis=-1)

    def inverse(self, s: np.ndarray, newton_tol: float = 1e-10, max_iter: int = 50) -> np.ndarray:
        """x(s) by Newton's method (``ds/dx = sqrt(1 + f'^2) >= 1``), to ``newton_tol`` mm in s."""
        s = np.asarray(s, dtype=float)
        x = np.interp(s, self.cumulative, self.edges)
        for _ in range(max_iter):
            residual = self(x) - s
            if np.max(np.abs(residual), initial=0.0) <= newton_tol:
                return x
            x = np.clip(x - residual / self.speed(x), 0.0, self.trajectory.period)
        raise PathError(f"arc-length inversion did not converge to {newton_tol:g} mm in {max_iter} Newton steps: the path has "
                        "features finer than the arc-length quadrature resolves",
                        "a path whose features the arc-length quadrature resolves (one period in at most 16384 panels)")


def arc_length(trajectory: Trajectory, rel_tol: float = 1e-12, max_panels: int = 1 << 14) -> ArcLength:
    """Build :class:`ArcLength`, doubling the panel count until S changes by < ``rel_tol``."""
    panels = 16
    previous = None
    while True:
        edges = np.linspace(0.0, trajectory.period, panels + 1)
        half = 0.5 * np.diff(edges)
        nodes = edges[:-1, None] + half[:, None] * (_GL_NODES + 1.0)
        slope = trajectory.df(nodes)
        pieces = half * np.sum(_GL_WEIGHTS * np.sqrt(1.0 + slope * slope), axis=1)
        cumulative = np.concatenate([[0.0], np.cumsum(pieces)])
        if previous is not None and abs(cumulative[-1] - previous) <= rel_tol * cumulative[-1]:
            return ArcLength(trajectory, edges, cumulative)
        if panels >= max_panels:
            raise PathError(f"arc length of {quoted(trajectory.source)} did not converge to {rel_tol:g} relative in {max_panels} panels",
                            f"a path whose features the arc-length quadrature resolves (one period in at most {max_panels} panels)")
        previous = cumulative[-1]
        panels *= 2


# --------------------------------------------------------------------------------------------
# Curvature schemes and the cam radius
# --------------------------------------------------------------------------------------------
def sample_path(trajectory: Trajectory, n_samples: int, newton_tol: float = 1e-10,
                length: ArcLength | None = None) -> tuple[np.ndarray, np.ndarray, ArcLength]:
    """Cam angles ``theta_i = 2 pi i / N`` (rad), path abscissae ``x_i = x(S theta_i / 2 pi)`` (mm), and the arc length
    (``length`` if given, else computed)."""
    length = arc_length(trajectory) if length is None else length
    theta = 2.0 * math.pi * np.arange(n_samples) / n_samples
    x = length.inverse(length.total * theta / (2.0 * math.pi), newton_tol)
    return theta, x, length


def path_curvature(trajectory: Trajectory, x: np.ndarray, scheme: str = "exact") -> np.ndarray:
    """Path curvature (1/mm) at the samples ``x_i`` (uniform in cam angle), by ``scheme``."""
    if scheme == "exact":
        return trajectory.curvature(x)
    if scheme not in SCHEMES:
        raise ParameterError("scheme", scheme, f"one of {SCHEMES}")
    # paper 004, eq. (12): differences of the sequences X_i, Y_i; x advances by one period per turn
    n = x.size
    ext = np.concatenate([x[-2:] - trajectory.period, x, x[:2] + trajectory.period])
    y = trajectory.wrapped(ext)
    i = np.arange(n) + 2
    if scheme == "forward":
        dx, dy = ext[i + 1] - ext[i], y[i + 1] - y[i]
        d2x, d2y = ext[i + 2] - 2 * ext[i + 1] + ext[i], y[i + 2] - 2 * y[i + 1] + y[i]
    else:
        dx, dy = 0.5 * (ext[i + 1] - ext[i - 1]), 0.5 * (y[i + 1] - y[i - 1])
        d2x, d2y = ext[i + 1] - 2 * ext[i] + ext[i - 1], y[i + 1] - 2 * y[i] + y[i - 1]
    return (dx * d2y - d2x * dy) / (dx * dx + dy * dy) ** 1.5


def cam_radius(k: np.ndarray, d: float, wheelbase: float, half_track: float, base_radius: float) -> np.ndarray:
    """Paper 004, eq. (13): ``rho = d L k / (1 + D k) + r_b`` (mm), for path curvature ``k`` (1/mm).

    Raises :class:`PathError` where ``1 + D k <= 0`` or ``rho <= 0`` (:func:`steerable_radius`).
    """
    valid = steerable_paths(d, wheelbase, half_track, base_radius)
    denom = 1.0 + half_track * k
    if np.any(denom <= 0.0):
        worst = float(k[np.argmin(denom)])
        raise PathError(
            f"path curvature k = {worst:.6g} 1/mm makes 1 + D k = {1.0 + half_track * worst:.6g} <= 0 "
            f"(D = {half_track:g} mm): a right turn of radius {1.0 / abs(worst):.6g} mm <= D cannot be steered "
            "(the rear-axle centre would have to turn about the drive wheel)", valid)
    rho = d * wheelbase * k / denom + base_radius
    if np.any(rho <= 0.0):
        worst = int(np.argmin(rho))
        raise PathError(
            f"a right turn of radius {1.0 / abs(float(k[worst])):.6g} mm makes the cam radius rho = {float(rho[worst]):.6g} mm "
            f"<= 0 (eq. 13): the path turns too sharply for r_b = {base_radius:g} mm", valid)
    return rho


@dataclass(frozen=True)
class CamSynthesis:
    """Result of trajectory -> cam synthesis.

    Attributes
    ----------
    theta : array (N,)
        Cam angles, rad.
    x : array (N,)
        Path abscissae of the tracked point at those angles, mm.
    curvature : array (N,)
        Path curvature by the chosen scheme, 1/mm.
    rho : array (N,)
        Paper's cam radius (eq. 13), mm.
    arc_length : float
        S, mm.
    scheme : str
    """

    theta: np.ndarray
    x: np.ndarray
    curvature: np.ndarray
    rho: np.ndarray
    arc_length: float
    scheme: str
    length: ArcLength = field(repr=False)


def synthesize_rho(
    trajectory: Trajectory,
    n_samples: int,
    d: float,
    wheelbase: float,
    half_track: float,
    base_radius: float,
    scheme: str = "exact",
    newton_tol: float = 1e-10,
) -> CamSynthesis:
    """Eqs. (9)-(13): the cam radius ``rho_i`` on a uniform grid of ``n_samples`` cam angles."""
    if isinstance(n_samples, bool) or not isinstance(n_samples, (int, np.integer)) or not 16 <= n_samples <= 1_000_000:
        raise ParameterError("samples", n_samples, "an integer 16 <= N <= 1000000", "the cam spline needs enough points per turn")
    if scheme not in SCHEMES:
        raise ParameterError("scheme", scheme, f"one of {SCHEMES}")
    length = arc_length(trajectory)
    # the exact curvature must also keep 1 + D k > 0 and rho > 0 between the samples: on a uniform
    # grid and at the arc-length quadrature's nodes (as fine as the quadrature resolves the path)
    dense = np.concatenate([np.linspace(0.0, trajectory.period, CHECK_GRID), length.nodes().ravel()])
    cam_radius(trajectory.curvature(dense), d, wheelbase, half_track, base_radius)
    theta, x, length = sample_path(trajectory, int(n_samples), newton_tol, length)
    k = path_curvature(trajectory, x, scheme)
    rho = cam_radius(k, d, wheelbase, half_track, base_radius)
    return CamSynthesis(theta, x, k, rho, length.total, scheme, length)


def read_trajectory_csv(path: str, max_rows: int = MAX_ROWS, max_bytes: int = MAX_TABLE_BYTES) -> Trajectory:
    """Trajectory from a CSV file of ``x, y`` rows (mm) over one period, the last ``y`` equal to
    the first.

    The format is the lift table's (:func:`camgen.synthesis.lift_table.parse_two_column_table`,
    one reader for both): exactly two fields a row, separated by a comma, a semicolon or blanks
    (no decimal commas: ``50,0,1,23`` is four fields, refused); ``#`` comments and blank lines
    skipped; one optional header row of two non-numeric fields; at most ``max_rows`` rows and
    ``max_bytes`` bytes.

    Raises
    ------
    ParameterError
        Naming ``trajectory_csv``, the file, and for a bad row its line number and text.
    """
    from pathlib import Path

    from camgen.synthesis.lift_table import read_two_column_table

    x, y, labels = read_two_column_table(path, "trajectory_csv", ("x", "y"), max_rows, max_bytes)
    if x.size < 8:
        raise ParameterError("trajectory_csv", str(path), "at least 8 rows of x, y (mm)", f"{x.size} rows")
    bad = np.flatnonzero(np.diff(x) <= 0.0)
    if bad.size:
        i = int(bad[0]) + 1
        raise ParameterError("trajectory_csv", f"{labels[i]}: x = {float(x[i])!r} after {float(x[i - 1])!r}", "strictly increasing x (mm)")
    return trajectory_from_table(x, y, source=Path(path).name)
