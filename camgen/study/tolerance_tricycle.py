"""The tricycle steering cam's ride under its error types I and II (paper 004, Section 4.2).

Every sample is the ride of the cam as made over the scene's ``ride_periods`` cam turns, started
on the designed path, with the sample's errors in
:class:`camgen.mechanisms.tricycle.ErrorModel`: ``steering_offset_deg`` (type I, added to the
steering angle), ``steering_gain`` (type II, the gain ``1 + error``) and ``drive_scale`` (the
distance per cam turn scaled by ``1 + error``).  The follower motion error of a sample is the
largest |lateral error| of its ride from the target path (mm;
:func:`camgen.mechanisms.tricycle.ride_max_lateral_error`, one sample after the other).
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np

__all__ = ["PROGRESS_EVERY", "ride_tricycle"]

#: Samples between two progress lines (and signal checks).
PROGRESS_EVERY = 16


def _quiet(step: str) -> None:
    """No progress shown."""


def ride_tricycle(cam: Any, periods: int, errors: dict[str, np.ndarray], samples: int,
                  progress: Callable[[str], None] = _quiet) -> np.ndarray:
    """The largest |lateral error| (mm) of the ride of ``cam`` (a
    :class:`~camgen.mechanisms.tricycle.TricycleCam`) over ``periods`` turns for every sample
    (``errors``: name -> (samples,) values; a missing name is no error); ``progress`` is called
    every :data:`PROGRESS_EVERY` samples, where a signal stops the study."""
    from camgen.interrupt import checkpoint
    from camgen.mechanisms.tricycle import ErrorModel, ride_max_lateral_error

    zero = np.zeros(samples)
    offset = np.radians(errors.get("steering_offset_deg", zero))
    gain = 1.0 + errors.get("steering_gain", zero)
    drive = 1.0 + errors.get("drive_scale", zero)
    out = np.empty(samples)
    for i in range(samples):
        if i % PROGRESS_EVERY == 0:
            checkpoint()
            progress(f"rides simulated: {i} of {samples}")
        model = ErrorModel(steering_offset=float(offset[i]), steering_gain=float(gain[i]), drive_scale=float(drive[i]))
        out[i] = ride_max_lateral_error(cam, periods, model)
    if not np.all(np.isfinite(out)):
        from camgen.errors import GeometryError

        raise GeometryError("a ride left the steerable range (a non-finite lateral error): the errors are too large")
    return out


