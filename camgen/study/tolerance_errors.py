"""The manufacturing and assembly errors of ``camgen tolerance`` and their distributions.

An error is named (:data:`PLATE_ERRORS`, :data:`TRICYCLE_ERRORS`) and given a distribution as
text, on the command line (``--error roller_radius_mm=normal:0.01``) or in the scene's
``[tolerance.errors]`` table:

* ``normal:SIGMA`` (mean 0) or ``normal:MEAN:SIGMA``: a Gaussian, ``SIGMA >= 0``;
* ``uniform:A:B``: uniform on ``[A, B]``, ``A <= B``.

Values are in the error's unit (mm, deg, or a dimensionless ratio).  Samples are drawn by
:func:`draw` with numpy's PCG64 generator from the seed, one column per error in the order the
errors are given: the same seed and errors give the same samples.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camgen.errors import ParameterError

__all__ = ["DISTRIBUTIONS", "Distribution", "ErrorName", "PLATE_ERRORS", "TRICYCLE_ERRORS", "check_name", "draw",
           "parse_distribution", "parse_error_option"]

#: The distribution families and how each is written.
DISTRIBUTIONS = {"normal": "normal:SIGMA or normal:MEAN:SIGMA (SIGMA >= 0)", "uniform": "uniform:A:B (A <= B)"}


@dataclass(frozen=True)
class ErrorName:
    """One error a tolerance study can vary: its name, unit and one line saying what it is."""

    name: str
    unit: str
    help: str


#: Errors of a plate cam (the cam as made, the follower as assembled).
PLATE_ERRORS = (
    ErrorName("profile_offset_mm", "mm", "the cut profile offset along its outward normal (tool wear, cutter compensation)"),
    ErrorName("profile_scale", "1", "the cut profile scaled about the cam axis by (1 + error) (a relative error)"),
    ErrorName("follower_offset_mm", "mm", "the follower axis moved sideways from x = offset (the guide displaced; translating)"),
    ErrorName("centre_distance_mm", "mm", "the pivot moved away from the cam axis (the centre distance; oscillating)"),
    ErrorName("roller_radius_mm", "mm", "the roller radius made larger by the error (roller followers)"),
    ErrorName("phase_deg", "deg", "the cam keyed on the shaft turned back against the rotation: the motion is s(theta - phase)"),
)

#: Errors of the tricycle steering cam (paper 004, Section 4.2: camgen.mechanisms.tricycle.ErrorModel).
TRICYCLE_ERRORS = (
    ErrorName("steering_offset_deg", "deg", "type I: an angle added to the steering angle (left > 0)"),
    ErrorName("steering_gain", "1", "type II: tan(alpha) = (1 + error) Delta r / d (a relative error of the gain)"),
    ErrorName("drive_scale", "1", "the distance per cam turn scaled by (1 + error) (wheel diameter, slip)"),
)


@dataclass(frozen=True)
class Distribution:
    """A distribution of one error: ``family`` (``"normal"``: ``a`` mean, ``b`` standard
    deviation; ``"uniform"``: on ``[a, b]``), in the error's unit."""

    family: str
    a: float
    b: float

    def describe(self) -> str:
        """The distribution as it is written (``normal:0:0.01``)."""
        return f"{self.family}:{self.a!r}:{self.b!r}"  # the shortest text giving back the doubles

    @property
    def mean(self) -> float:
        """The distribution's mean."""
        return self.a if self.family == "normal" else 0.5 * (self.a + self.b)

    @property
    def std(self) -> float:
        """The distribution's standard deviation."""
        return self.b if self.family == "normal" else (self.b - self.a) / math.sqrt(12.0)


def _number(key: str, text: str, whole: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(key, whole, DISTRIBUTIONS["normal"] + " or " + DISTRIBUTIONS["uniform"],
                             f"'{text}' is not a number") from None
    if not math.isfinite(value):
        raise ParameterError(key, whole, "finite numbers", f"'{text}' is not finite")
    return value


def parse_distribution(key: str, text: object) -> Distribution:
    """The :class:`Distribution` written ``text`` for the error ``key``; a
    :class:`~camgen.errors.ParameterError` naming ``key`` when it is not one."""
    valid = " or ".join(DISTRIBUTIONS.values())
    if not isinstance(text, str):
        raise ParameterError(key, text, valid, "a distribution is written as text")
    family, _, rest = text.strip().partition(":")
    if family not in DISTRIBUTIONS:
        raise ParameterError(key, text, valid, f"unknown distribution '{family}': one of {', '.join(DISTRIBUTIONS)}")
    parts = [_number(key, p.strip(), text) for p in rest.split(":")] if rest else []
    if family == "normal":
        if len(parts) not in (1, 2):
            raise ParameterError(key, text, DISTRIBUTIONS["normal"])
        mean, sigma = (0.0, parts[0]) if len(parts) == 1 else (parts[0], parts[1])
        if sigma < 0:
            raise ParameterError(key, text, DISTRIBUTIONS["normal"], "a standard deviation is >= 0")
        return Distribution("normal", mean, sigma)
    if len(parts) != 2 or parts[0] > parts[1]:
        raise ParameterError(key, text, DISTRIBUTIONS["uniform"])
    return Distribution("uniform", parts[0], parts[1])


def parse_error_option(option: str, names: tuple[ErrorName, ...], where: str = "--error") -> tuple[str, Distribution]:
    """``NAME=DISTRIBUTION`` (the ``--error`` option) as the error's name and distribution."""
    name, eq, text = option.partition("=")
    name = name.strip()
    if not eq:
        raise ParameterError(where, option, "NAME=DISTRIBUTION, e.g. roller_radius_mm=normal:0.01")
    check_name(f"{where} {name}", name, names)
    return name, parse_distribution(f"{where} {name}", text)


def check_name(key: str, name: str, names: tuple[ErrorName, ...]) -> None:
    """Refuse an error name the cam does not have (a ParameterError listing the ones it has)."""
    if name not in {e.name for e in names}:
        raise ParameterError(key, name, "one of " + ", ".join(e.name for e in names), "not an error of this cam")


def draw(distributions: tuple[Distribution, ...], samples: int, seed: int) -> np.ndarray:
    """``samples`` draws of every distribution, (samples, len(distributions)), from numpy's
    PCG64 generator seeded with ``seed`` (one column after the other)."""
    rng = np.random.default_rng(seed)
    out = np.empty((samples, len(distributions)))
    for j, d in enumerate(distributions):
        if d.family == "normal":
            out[:, j] = d.a + d.b * rng.standard_normal(samples)
        else:
            out[:, j] = rng.uniform(d.a, d.b, samples)
    return out
