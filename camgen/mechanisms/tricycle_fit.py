"""Fit the tricycle error model to a measured trajectory and turn it into adjustment advice.

Paper 004, Section 4.2 and Appendix A.  The error model (:class:`ErrorModel`) has five
parameters: steering offset ``delta`` (type I), steering gain ``g`` (type II), drive-distance
scale ``sigma``, start phase ``theta0`` and start-heading offset.  They are fitted by
nonlinear least squares (:func:`camgen.numerics.least_squares.levenberg_marquardt`): the residual at every measured
point is the simulated ride's ``y`` at the measured ``x`` minus the measured ``y``; the ride
is simulated on the cam as made (:func:`camgen.mechanisms.tricycle.ride`).

Uncertainties are one standard deviation from the Gauss-Newton covariance
``s^2 (J^T J)^-1`` with ``s^2 = RSS / (n - p)`` (the measurement noise is not given in the
paper; the residuals estimate it).

A fit the table does not determine is refused (:class:`FitNotDetermined`), never reported with
infinite, zero or meaningless uncertainties and adjustment advice: when the model's ride does
not reach the table's x at the solution (it falls short or turns back: e.g. the paper's tables,
measured to x = 2296 and 2063 mm, fitted to a cam of a 20 mm period), or when the Jacobian, its columns scaled by
:data:`PARAMETER_SCALE`, has a condition number above ``max_condition``
(:data:`FIT_MAX_CONDITION`): its forward differences carry a relative error of about
``sqrt(eps) = 1.5e-8`` of its largest singular value, so a direction whose singular value is
within a factor 100 of that noise is not determined by the data (the paper's path fitted to
Tables A1/A2: condition numbers 55 and 69).

Adjustments (paper 004, eqs. 16-17 and Fig. 8):

* the worm knob turns the steering by ``1 / Z3`` deg per knob degree: removing ``delta``
  takes ``-delta Z3`` knob degrees;
* the micro-indexing head moves the cam axially and so changes the active rod length ``d``;
  a gain ``g = d_design / d_actual`` is undone by changing ``d`` by ``d (1 - 1/g)``;
* ``sigma`` (distance per cam turn) is set by the drive wheel and the gears; neither
  mechanism corrects it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camgen.errors import GeometryError, ParameterError
from camgen.mechanisms.tricycle import (
    ErrorModel,
    MeasuredTable,
    TricycleCam,
    design_start,
    ride,
    ride_geometry,
)
from camgen.numerics.least_squares import LeastSquares, levenberg_marquardt

__all__ = [
    "FIT_FTOL", "FIT_MAX_CONDITION", "FitNotDetermined", "FitResult", "PARAMETERS", "PARAMETER_SCALE",
    "START_PHASES_DEG", "adjustment_advice", "fit_error_model", "model_y",
]

PARAMETERS = ("steering_offset_deg", "steering_gain", "drive_scale", "start_phase_deg", "start_heading_deg")


def _errors(p: np.ndarray) -> ErrorModel:
    return ErrorModel(math.radians(p[0]), p[1], p[2], math.radians(p[3]) % (2.0 * math.pi), math.radians(p[4]))


def model_y(cam: TricycleCam, geom: Any, p: np.ndarray, x: np.ndarray, periods: int = 2) -> np.ndarray:
    """Simulated ``y`` (mm) at abscissae ``x`` for parameters ``p`` (see PARAMETERS), path started at the origin."""
    errors = _errors(p)
    _, _, heading0 = design_start(cam, errors.start_phase)
    path = ride(geom, cam.device, cam.synthesis.arc_length, errors, periods).moved(0.0, 0.0, heading0)
    if not np.all(np.diff(path.x) > 0) or path.x[-1] < x.max():
        return np.full(x.shape, 1e3)  # the path turns back or falls short: a large residual
    return np.interp(x, path.x, path.y)


@dataclass(frozen=True)
class FitResult:
    """Fitted error model for one measured table (units in the keys)."""

    table: str
    values: dict[str, float]
    uncertainty: dict[str, float]
    residual_rms_mm: float
    n_points: int
    advice: dict[str, Any]

    def as_dict(self) -> dict[str, Any]:
        return {
            "parameters": self.values,
            "uncertainty_1sigma": self.uncertainty,
            "residual_rms_mm": self.residual_rms_mm,
            "points": self.n_points,
            "advice": self.advice,
            "finding": self.finding,
        }

    @property
    def finding(self) -> str:
        """What the fit says about the paper's explanation of the measured path."""
        sigma, ds = self.values["drive_scale"], self.uncertainty["drive_scale"]
        gain = self.values["steering_gain"]
        text = f"steering gain {gain:.3f}" + (" (steering too large)" if gain > 1 else " (steering too small)")
        if sigma - 1 > 3 * ds:
            text += (
                f"; the vehicle travels {sigma:.3f} x S per cam turn ({(sigma - 1) * 100:.1f} % +- {ds * 100:.1f} % more than designed): "
                "a steering error changes the shape of the path, not its length per cam turn, so this, not a too-large "
                "steering angle as the paper says, is what lengthens the measured period"
            )
        return text


#: The starts of the multi-start fit (drive scale: 1 or the measured period ratio; phase, deg).
START_PHASES_DEG = (0.0, 10.0, -10.0)
#: Typical size of each parameter (the scale of its finite-difference step and of the damping).
PARAMETER_SCALE = np.array([0.1, 0.05, 0.02, 5.0, 1.0])
#: Levenberg-Marquardt stops when the cost falls by less than this fraction in an accepted step.
FIT_FTOL = 1e-12
#: Largest condition number of the scaled Jacobian of a fit that is reported (module notes).
FIT_MAX_CONDITION = 1e6


class FitNotDetermined(GeometryError):
    """The measured table does not determine the error model for this cam (module notes).

    Attributes
    ----------
    table : the table's name.
    reason : why, in words (for the message naming the scene key).
    """

    def __init__(self, table: str, reason: str) -> None:
        super().__init__(f"the error model fitted to table {table} is not determined: {reason}")
        self.table = table
        self.reason = reason


def fit_error_model(cam: TricycleCam, table: MeasuredTable, nodes: int = 4, starts: str = "one",
                    max_condition: float = FIT_MAX_CONDITION) -> FitResult:
    """Least-squares fit of the five error-model parameters to ``table``.

    ``starts="one"``: Levenberg-Marquardt from the design (no errors, drive scale 1, phase 0);
    ``"all"``: also from the measured period ratio and phases +-10 deg (:data:`START_PHASES_DEG`),
    keeping the lowest cost.  On Tables A1 and A2 every start reaches the same minimum (tested;
    benchmarks/bench_tricycle.py shows it), so one start is the default.

    Raises
    ------
    FitNotDetermined
        When the model's ride does not reach the table at the solution, or the scaled Jacobian's
        condition number exceeds ``max_condition`` (module notes).
    """
    if starts not in ("one", "all"):
        raise ParameterError("starts", starts, '"one" or "all"')
    if not max_condition > 1.0:
        raise ParameterError("max_condition", max_condition, "> 1")

    geom = ride_geometry(cam.profile, cam.device.rod_radius, nodes)
    x, y = table.x[1:], table.measured[1:]  # row 1 is the start (0, 0)

    def residual(p: np.ndarray) -> np.ndarray:
        try:
            return model_y(cam, geom, p, x) - y
        except GeometryError:
            return np.full(x.shape, 1e3)

    best = None
    x_period = table.x[-1]
    sigmas = (1.0,) if starts == "one" else (1.0, x_period / cam.trajectory.period)
    phases = (0.0,) if starts == "one" else START_PHASES_DEG
    for sigma0 in sigmas:
        for phase0 in phases:
            p0 = np.array([0.0, 1.0, sigma0, phase0 % 360.0, 0.0])
            fit = levenberg_marquardt(residual, p0, PARAMETER_SCALE, ftol=FIT_FTOL)
            if best is None or fit.cost < best.cost:
                best = fit
    assert best is not None
    _require_determined(cam, geom, best, x, table.name, max_condition)
    n, k = x.size, best.x.size
    rss = float(np.sum(best.fun**2))
    jac = best.jac
    try:
        cov = np.linalg.inv(jac.T @ jac) * rss / max(n - k, 1)
        sigma = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    except np.linalg.LinAlgError:
        sigma = np.full(k, math.inf)
    values = dict(zip(PARAMETERS, (float(v) for v in best.x)))
    values["start_phase_deg"] %= 360.0
    uncertainty = dict(zip(PARAMETERS, (float(s) for s in sigma)))
    return FitResult(table.name, values, uncertainty, math.sqrt(rss / n), n, adjustment_advice(cam, values))


def _require_determined(cam: TricycleCam, geom: Any, fit: LeastSquares, x: np.ndarray, table: str, max_condition: float) -> None:
    """Raise :class:`FitNotDetermined` unless the ride reaches ``x`` (mm) at the solution and the
    scaled Jacobian's condition number is at most ``max_condition``."""
    errors = _errors(fit.x)
    try:
        _, _, heading0 = design_start(cam, errors.start_phase)
        path = ride(geom, cam.device, cam.synthesis.arc_length, errors, 2).moved(0.0, 0.0, heading0)
    except GeometryError as exc:
        raise FitNotDetermined(table, f"the ride cannot be simulated at the solution ({exc})") from None
    if not np.all(np.diff(path.x) > 0) or path.x[-1] < x.max():
        raise FitNotDetermined(
            table, f"the model's ride over two cam turns ({float(path.x[-1]):.6g} mm, period {cam.trajectory.period:g} mm) does not "
            f"run forward through the table's x up to {float(x.max()):.6g} mm at the fitted parameters")
    _, singular, vt = np.linalg.svd(fit.jac * PARAMETER_SCALE)
    condition = float(singular[0] / singular[-1]) if singular[-1] > 0 else math.inf
    if not condition <= max_condition:
        weak = [name for name, c in zip(PARAMETERS, vt[-1]) if abs(c) >= 0.3]  # the least determined direction
        what = weak[0] if len(weak) == 1 else f"a combination of {', '.join(weak)}"
        raise FitNotDetermined(
            table, f"the scaled Jacobian's condition number is {condition:.3g} > {max_condition:g}: {what} barely changes "
            "the ride at the table's points")


def adjustment_advice(cam: TricycleCam, values: dict[str, float]) -> dict[str, Any]:
    """Worm knob turns, indexing-head change of ``d`` and what remains, for fitted ``values``."""
    device = cam.device
    delta = values["steering_offset_deg"]
    gain = values["steering_gain"]
    knob_deg = -delta * device.worm_teeth  # eq. (17): one knob degree = 1/Z3 deg of steering
    d_change = device.lever * (1.0 - 1.0 / gain)
    wheel = device.drive_wheel_diameter(cam.synthesis.arc_length)
    return {
        "worm_knob_deg": knob_deg,
        "worm_knob_turns": knob_deg / 360.0,
        "worm_direction": "right" if delta > 0 else "left",
        "indexing_head_change_of_d_mm": d_change,
        "d_after_mm": device.lever,
        "effective_drive_wheel_diameter_mm": values["drive_scale"] * wheel,
        "design_drive_wheel_diameter_mm": wheel,
        "note": (
            f"turn the worm knob {abs(knob_deg):.1f} deg ({abs(knob_deg) / 360.0:.3f} turns) to steer "
            f"{abs(delta):.3f} deg to the {'right' if delta > 0 else 'left'}; "
            f"{'lengthen' if d_change > 0 else 'shorten'} the active rod length d by {abs(d_change):.3f} mm "
            f"with the indexing head (gain {gain:.4f}); the distance per cam turn is "
            f"{values['drive_scale']:.4f} x design, which only the drive wheel or the gears can change"
        ),
    }
