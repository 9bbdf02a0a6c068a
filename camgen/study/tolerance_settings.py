"""What a ``camgen tolerance`` study is asked: the scene's ``[tolerance]`` table and the command line.

The ``[tolerance]`` table (``camgen run`` and ``camgen check`` ignore it)::

    [tolerance]
    cam = "plate"            # the cam to study (needed when the scene has more than one)
    samples = 2000           # Monte Carlo samples (default 1000)
    seed = 1                 # numpy PCG64 seed (default 0)
    percentile = 95.0        # the checks must pass at this percentile (default 95)

    [tolerance.errors]       # error name = distribution (camgen.study.tolerance_errors)
    roller_radius_mm = "normal:0.01"
    phase_deg = "uniform:-0.2:0.2"

Every command reading the scene checks the table (:func:`check_scene_table`, called by
:func:`camgen.scene.parse_scene`): ``camgen check`` refuses what ``camgen tolerance`` would.
The command line's ``--cam``, ``--samples``, ``--seed`` and ``--percentile`` replace the
table's; every ``--error NAME=DIST`` replaces the table's distribution of NAME or adds one.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from camgen.errors import ParameterError
from camgen.schema import Count, Key, Number, Text, parse_table
from camgen.study.tolerance_errors import (
    PLATE_ERRORS,
    TRICYCLE_ERRORS,
    Distribution,
    ErrorName,
    check_name,
    parse_distribution,
    parse_error_option,
)

if TYPE_CHECKING:
    from camgen.kinds.base import CamSpec

__all__ = ["DEFAULT_PERCENTILE", "DEFAULT_SAMPLES", "MAX_SAMPLES", "STUDIED", "TABLE_KEYS", "TOLERANCE_REFERENCE", "ToleranceOptions", "ToleranceSettings",
           "check_scene_table", "errors_of", "read_settings"]

#: Monte Carlo samples when none are asked.
DEFAULT_SAMPLES = 1000
#: Most samples a study takes (memory: every sample's error curve is kept at 1 deg, 360 floats: 58 MB;
#: the order-statistic interval of the 99th percentile is then about +-0.15 percentile points wide).
MAX_SAMPLES = 20_000
#: The cams a study can take.
STUDIED = ("a plate cam (motion_law or lift_table) with a translating roller, knife or flat follower or an oscillating "
           "roller or knife, or the tricycle's steering cam (trajectory)")
#: The percentile at which the checks must pass when none is asked.
DEFAULT_PERCENTILE = 95.0

TABLE_KEYS = (
    Key("cam", Text(64), "The cam to study (needed when the scene has more than one).", ()),
    Key("samples", Count(10, MAX_SAMPLES), "Monte Carlo samples.", (), default=DEFAULT_SAMPLES),
    Key("seed", Count(0, 2**63 - 1), "Seed of numpy's PCG64 generator.", (), default=0),
    Key("percentile", Number("", 50.0, 100.0, high_open=True), "The checks must pass at this percentile of the samples.", (),
        default=DEFAULT_PERCENTILE),
)




def _reference() -> str:
    rows = "\n".join(f"| `{k.name}` | {k.type.describe()} | {'-' if k.default is None else k.default} | tolerance | {k.doc} |"
                     for k in TABLE_KEYS)
    errors = "\n".join(f"| `{e.name}` | {e.unit} | {e.help} |" for e in PLATE_ERRORS + TRICYCLE_ERRORS)
    return f"""## [tolerance]

Read by `camgen tolerance` only (`camgen run` and `camgen check` check it and change nothing for it);
the command line's `--cam`, `--samples`, `--seed`, `--percentile` take precedence and each
`--error NAME=DIST` replaces or adds one error.

| key | value | default | changes | what it is |
| --- | --- | --- | --- | --- |
{rows}

Each key of the `[tolerance.errors]` table is an error of the studied cam and its value a
distribution: `"normal:SIGMA"`, `"normal:MEAN:SIGMA"` (SIGMA >= 0) or `"uniform:A:B"` (A <= B), in the
error's unit.  Plate cams take the first six: a translating follower all but
`centre_distance_mm` (a knife no `roller_radius_mm`, a flat face neither it nor
`follower_offset_mm`), an oscillating roller or knife all but `follower_offset_mm`; the
tricycle's steering cam (`trajectory`) the last three.

| error | unit | what it is |
| --- | --- | --- |
{errors}
"""


#: The ``[tolerance]`` section of the key reference (``camgen keys tolerance``).
TOLERANCE_REFERENCE = _reference()


@dataclass(frozen=True)
class ToleranceOptions:
    """The command line's settings (None: not given): ``errors`` the ``--error NAME=DIST`` texts."""

    cam: str | None = None
    samples: int | None = None
    seed: int | None = None
    percentile: float | None = None
    errors: tuple[str, ...] = ()


@dataclass(frozen=True)
class ToleranceSettings:
    """A study, validated: the cam's name, the errors (name, distribution) in the order given,
    the number of samples, the seed and the percentile (50 <= p < 100) the checks must pass at."""

    cam: str
    errors: tuple[tuple[str, Distribution], ...]
    samples: int
    seed: int
    percentile: float


def _count(name: str, value: int | None, key: Key) -> int | None:
    return None if value is None else int(key.type.parse(name, value))


def errors_of(spec: "CamSpec") -> tuple[ErrorName, ...] | None:
    """The errors a tolerance study of the cam ``spec`` can vary (None: it cannot be studied)."""
    if spec.kind == "trajectory" and spec.form == "plate":
        return TRICYCLE_ERRORS
    follower = getattr(spec.params, "follower", None)
    if follower is None or spec.form != "plate" or not hasattr(spec.params, "law"):
        return None
    oscillating = follower.motion == "oscillating"
    if oscillating and follower.contact == "face":
        return None
    drop = {"follower_offset_mm"} if oscillating else {"centre_distance_mm"}
    if follower.contact == "face":  # a face's lift does not depend on where along it the axis is
        drop |= {"roller_radius_mm", "follower_offset_mm"}
    elif not follower.has_radius:
        drop |= {"roller_radius_mm"}
    return tuple(e for e in PLATE_ERRORS if e.name not in drop)


def check_scene_table(table: object, cams: "Sequence[CamSpec]") -> None:
    """Refuse a ``[tolerance]`` table ``camgen tolerance`` would refuse (its errors may come from the
    command line, its cam too when the scene has several it can study)."""
    if not isinstance(table, dict):
        raise ParameterError("tolerance", table, "a table [tolerance]")
    names_of = {c.name: names for c in cams if (names := errors_of(c)) is not None}
    _read(table, ToleranceOptions(), [c.name for c in cams], names_of, complete=False)


def read_settings(table: Mapping[str, Any], options: ToleranceOptions, cams: Sequence[str],
                  names_of: "Mapping[str, tuple[ErrorName, ...]]") -> ToleranceSettings:
    """The study from the scene's ``[tolerance]`` table and the command line.

    ``cams``: the scene's cam names; ``names_of``: the errors each cam that can be studied has
    (a cam not in it cannot be studied).  Every refusal is a ParameterError naming the key.
    """
    settings = _read(table, options, cams, names_of, complete=True)
    assert settings is not None  # complete: a study or a refusal
    return settings


def _read(table: Mapping[str, Any], options: ToleranceOptions, cams: Sequence[str],
          names_of: "Mapping[str, tuple[ErrorName, ...]]", complete: bool) -> ToleranceSettings | None:
    """The study (``complete``: every part given, else None once the table is checked)."""
    table = dict(table)
    errors_table = table.pop("errors", {})
    parsed = parse_table("tolerance", table, TABLE_KEYS)
    keys = {k.name: k for k in TABLE_KEYS}
    cam = options.cam if options.cam is not None else parsed.get("cam")
    where = "--cam" if options.cam is not None else "tolerance.cam"
    studied = [c for c in cams if c in names_of]
    if not studied:
        raise ParameterError("cams" if complete else "tolerance", ", ".join(cams), STUDIED,
                             "camgen tolerance can study none of this scene's cams")
    if cam is None and len(studied) == 1:
        cam = studied[0]
    if cam is None:
        if complete:
            raise ParameterError("--cam", None, "one of " + ", ".join(studied),
                                 f"the scene has {len(studied)} cams camgen tolerance can study: name one (--cam or tolerance.cam)")
        names = tuple({e.name: e for c in studied for e in names_of[c]}.values())  # the cam is the command line's
    else:
        if cam not in cams:
            raise ParameterError(where, cam, "one of the scene's cams: " + ", ".join(cams))
        if cam not in names_of:
            raise ParameterError(where, cam, STUDIED, "camgen tolerance cannot study this cam")
        names = names_of[cam]
    errors: dict[str, Distribution] = {}
    if not isinstance(errors_table, dict):
        raise ParameterError("tolerance.errors", errors_table, "a table of error name = \"distribution\"")
    for name, text in errors_table.items():
        check_name(f"tolerance.errors.{name}", str(name), names)
        errors[str(name)] = parse_distribution(f"tolerance.errors.{name}", text)
    if not complete or cam is None:
        return None
    for option in options.errors:
        name, dist = parse_error_option(option, names)
        errors[name] = dist
    if not errors:
        raise ParameterError("--error", None, "at least one error, NAME=DISTRIBUTION (or a [tolerance.errors] table); names: "
                             + ", ".join(e.name for e in names))
    samples = _count("--samples", options.samples, keys["samples"])
    seed = _count("--seed", options.seed, keys["seed"])
    percentile = parsed["percentile"] if options.percentile is None else keys["percentile"].type.parse("--percentile", options.percentile)
    if not math.isfinite(percentile):  # pragma: no cover - Number refuses it
        raise ParameterError("--percentile", percentile, "50 <= p < 100")
    return ToleranceSettings(cam, tuple(errors.items()), parsed["samples"] if samples is None else samples,
                             parsed["seed"] if seed is None else seed, float(percentile))
