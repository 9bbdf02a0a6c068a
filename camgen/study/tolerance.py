"""``camgen tolerance SCENE``: a Monte Carlo study of manufacturing and assembly errors.

Every sample is one cam as made and one follower as assembled, the errors drawn from their
distributions (:mod:`camgen.study.tolerance_errors`); the ride is re-simulated on that geometry
(a plate cam: :mod:`camgen.study.tolerance_plate`, all samples in a few numpy passes; the
tricycle: :mod:`camgen.study.tolerance_tricycle`).  The result: the follower motion error's
percentiles with their sampling error (:mod:`camgen.study.tolerance_stats`), its envelope over
the cam angle, the pressure angle's percentiles against its limit, and the first-order
sensitivity index of every error.

Files, in ``OUTDIR/<scene>-tolerance/`` (written as one folder, atomically:
:func:`camgen.staging.write_run`): ``tolerance.json`` (everything above, the inputs, seed and
camgen version), ``tolerance.csv`` (one row per sample: its errors and results) and
``report.json`` (an index of the folder, which marks it as a camgen run the next study may replace).

Verdict (exit status): 1 when a check fails at the asked percentile (the pressure angle's
``percentile``-th percentile above its limit), else 0.
"""
from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping

import numpy as np

from camgen.errors import ParameterError
from camgen.study.tolerance_errors import draw
from camgen.study.tolerance_settings import ToleranceOptions, ToleranceSettings, errors_of, read_settings
from camgen.study.tolerance_stats import CONFIDENCE, Percentile, first_order_indices, noise_floor, percentile

if TYPE_CHECKING:
    from camgen.kinds.base import CamSpec
    from camgen.scene import Scene

__all__ = ["ENVELOPE_PERCENTILES", "ENVELOPE_STEP", "REPORTED_PERCENTILES", "CheckSpread", "ToleranceResult", "scene_table",
           "study", "study_files"]

#: Percentiles of every result in tolerance.json (the asked percentile is added).
REPORTED_PERCENTILES = (50.0, 95.0, 99.0)
#: Percentiles of the signed motion error at every cam angle (the envelope).
ENVELOPE_PERCENTILES = (1.0, 5.0, 50.0, 95.0, 99.0)
#: Every how many output angles (0.1 deg apart) the envelope is given: 1 deg.
ENVELOPE_STEP = 10


@dataclass(frozen=True)
class CheckSpread:
    """A check over the samples: ``name``, ``unit``, the ``limit`` (value <= limit passes), the
    nominal cam's ``nominal`` value, the ``percentiles`` of the samples' values and
    ``at_percentile`` (the asked one), ``passed`` when that is within the limit."""

    name: str
    unit: str
    limit: float
    nominal: float
    percentiles: tuple[Percentile, ...]
    at_percentile: Percentile
    passed: bool


@dataclass(frozen=True)
class ToleranceResult:
    """A finished study: the scene, its file's SHA-256, the cam and its kind, the settings, the
    drawn ``inputs`` (samples, errors), ``measure`` (what the motion error is) and its ``unit``
    (mm, or deg of an oscillating follower's swing), ``max_error`` (samples,) and ``nominal_error`` (the nominal cam's, the computation's floor), the
    ``envelope`` (cam angles in deg and the signed error's percentiles there; None for the
    tricycle), the checks, and the first-order ``indices`` of every error for the largest
    motion error and for each check's value."""

    scene: "Scene"
    scene_sha256: str
    cam: str
    kind: str
    settings: ToleranceSettings
    inputs: np.ndarray
    measure: str
    unit: str
    max_error: np.ndarray
    nominal_error: float
    envelope: tuple[np.ndarray, tuple[np.ndarray, ...]] | None
    checks: tuple[CheckSpread, ...]
    check_values: tuple[np.ndarray, ...]
    indices: dict[str, np.ndarray]

    @property
    def failed(self) -> tuple[CheckSpread, ...]:
        """The checks that fail at the asked percentile."""
        return tuple(c for c in self.checks if not c.passed)


def scene_table(path: str | Path) -> Mapping[str, Any]:
    """The ``[tolerance]`` table of the scene file at ``path`` ({} when it has none), decoded as
    :func:`camgen.scene.load_scene` decodes the scene (which has read and checked it)."""
    from camgen.scene import decode_scene_file

    _, data = decode_scene_file(Path(path))
    table = data.get("tolerance", {})
    return table if isinstance(table, dict) else {}


def _percentiles(values: np.ndarray, asked: float) -> tuple[Percentile, ...]:
    ps = sorted(set(REPORTED_PERCENTILES) | {asked})
    return tuple(percentile(values, p) for p in ps)


def _quiet(step: str) -> None:
    """No progress shown."""


def study(scene_path: str, options: ToleranceOptions, progress: Callable[[str], None] = _quiet) -> ToleranceResult:
    """Read the scene and the study, draw the samples and ride every made cam; ``progress`` is
    called with a line at every chunk of samples (a signal stops the study there:
    :func:`camgen.interrupt.checkpoint`).

    Raises ParameterError / SceneError (exit 2) for bad input (the scene, the study, errors too
    large for a made cam to be ridden); nothing is written then.
    """
    from camgen.errors import GeometryError, SceneError
    from camgen.kinds import get_kind
    from camgen.scene import load_scene

    if not scene_path.strip():
        raise ParameterError("SCENE", scene_path, "the path of a scene file (TOML)")
    scene = load_scene(scene_path)
    names_of = {spec.name: names for spec in scene.cams if (names := errors_of(spec)) is not None}
    settings = read_settings(scene_table(scene_path), options, [c.name for c in scene.cams], names_of)
    spec = next(c for c in scene.cams if c.name == settings.cam)
    built: Any = get_kind(spec.kind, spec.form).build(spec, frozenset())
    if built.contour is None:
        raise SceneError(f"cams.{spec.name}: the nominal cam cannot be made ({built.undercut}); camgen check shows why")
    inputs = draw(tuple(d for _, d in settings.errors), settings.samples, settings.seed)
    columns = {name: inputs[:, j] for j, (name, _) in enumerate(settings.errors)}
    n = settings.samples
    try:
        if spec.kind == "trajectory":
            from camgen.study.tolerance_tricycle import ride_tricycle

            periods = spec.params.ride_periods
            max_error = ride_tricycle(built.tricycle, periods, columns, n, progress)
            nominal_error = float(ride_tricycle(built.tricycle, periods, {}, 1)[0])
            measure = f"the largest |lateral error| of the ride from the target path over {periods} cam turns (ride_periods), mm"
            unit = "mm"
            envelope = None
            checks: tuple[CheckSpread, ...] = ()
            values: tuple[np.ndarray, ...] = ()
        else:
            max_error, nominal_error, envelope, checks, values, unit = _plate(spec, built, columns, settings, progress)
            what = "position rest + s(theta)" if unit == "mm" else "swing s(theta)"
            measure = f"the largest |follower riding the made cam - nominal {what}| over the turn (0.1 deg apart), {unit}"
    except GeometryError as exc:
        raise ParameterError("--error" if options.errors else "tolerance.errors", ", ".join(f"{k}={d.describe()}" for k, d in settings.errors),
                             "errors small enough that every made cam can be ridden", str(exc)) from None
    indices = {f"max_abs_error_{unit}": first_order_indices(inputs, max_error)}
    for check, v in zip(checks, values):
        indices[f"{check.name}_{check.unit}"] = first_order_indices(inputs, v)
    digest = hashlib.sha256(Path(scene_path).read_bytes()).hexdigest()
    return ToleranceResult(scene, digest, spec.name, spec.kind, settings, inputs, measure, unit, max_error, nominal_error, envelope,
                           checks, values, indices)


def _plate(spec: "CamSpec", built: Any, columns: dict[str, np.ndarray], settings: ToleranceSettings,
           progress: Callable[[str], None]) -> tuple[
        np.ndarray, float, tuple[np.ndarray, tuple[np.ndarray, ...]], tuple[CheckSpread, ...], tuple[np.ndarray, ...], str]:
    from camgen.interrupt import checkpoint
    from camgen.kinds.disk import pressure_limit
    from camgen.study.tolerance_plate import CHUNK, OUTPUT_ANGLES, plate_nominal, ride_plate

    nominal = plate_nominal(built.spec_follower, built.law)
    n = settings.samples
    max_error, coarse = np.empty(n), np.empty((n, OUTPUT_ANGLES // ENVELOPE_STEP))
    peaks: list[np.ndarray] = []
    theta = np.empty(0)
    for lo in range(0, n, CHUNK):  # memory: one chunk's error curves at a time
        checkpoint()
        progress(f"made cams ridden: {lo} of {n}")
        hi = min(lo + CHUNK, n)
        ride = ride_plate(nominal, {k: v[lo:hi] for k, v in columns.items()}, hi - lo)
        max_error[lo:hi] = np.max(np.abs(ride.error), axis=1)
        coarse[lo:hi] = ride.error[:, ::ENVELOPE_STEP]
        theta = ride.theta
        if ride.pressure_peak is not None:
            peaks.append(ride.pressure_peak)
    base = ride_plate(nominal, {}, 1)
    nominal_error = float(np.max(np.abs(base.error)))
    envelope = (np.degrees(theta[::ENVELOPE_STEP]), tuple(np.percentile(coarse, p, axis=0) for p in ENVELOPE_PERCENTILES))
    checks: list[CheckSpread] = []
    values: list[np.ndarray] = []
    if peaks and base.pressure_peak is not None:
        peak = np.degrees(np.concatenate(peaks))
        limit = round(math.degrees(pressure_limit(spec)), 9)  # the scene gave degrees
        at = percentile(peak, settings.percentile)
        checks.append(CheckSpread("pressure_angle", "deg", limit, float(np.degrees(base.pressure_peak[0])),
                                  _percentiles(peak, settings.percentile), at, at.value <= limit))
        values.append(peak)
    return max_error, nominal_error, envelope, tuple(checks), tuple(values), nominal.unit


def _pct(p: Percentile) -> dict[str, Any]:
    return {"p": p.p, "value": p.value, "low": p.low, "high": p.high, "bounded": p.bounded}


def _ranking(names: list[str], indices: np.ndarray) -> list[dict[str, Any]]:
    order = np.argsort(-indices, kind="stable")
    return [{"error": names[i], "first_order_index": float(indices[i])} for i in order]


def study_files(result: ToleranceResult) -> dict[str, str]:
    """The files of a study: ``tolerance.json``, ``tolerance.csv`` and ``report.json`` (text)."""
    from camgen import __version__
    from camgen.study.tolerance_errors import PLATE_ERRORS as plate, TRICYCLE_ERRORS as tricycle

    s = result.settings
    names = [name for name, _ in s.errors]
    units = {e.name: e.unit for e in plate + tricycle}
    n = s.samples
    data: dict[str, Any] = {
        "camgen_version": __version__,
        "command": "tolerance",
        "scene": result.scene.source,
        "scene_sha256": result.scene_sha256,
        "cam": result.cam,
        "kind": result.kind,
        "samples": n,
        "seed": s.seed,
        "generator": "numpy.random.default_rng(seed) (PCG64), one column per error in this order",
        "errors": [{"name": name, "unit": units[name], "distribution": d.describe(), "mean": d.mean, "std": d.std}
                   for name, d in s.errors],
        "percentile_method": "numpy.percentile (linear); [low, high]: the distribution-free order-statistic interval of the "
                             f"population percentile at confidence {CONFIDENCE} (binomial ranks; bounded false: open on a side, "
                             "given as the sample extreme)",
        "confidence": CONFIDENCE,
        "motion_error": {
            "measure": result.measure,
            "unit": result.unit,
            "nominal": result.nominal_error,
            "percentiles": [_pct(p) for p in _percentiles(result.max_error, s.percentile)],
            "max": float(np.max(result.max_error)),
        },
        "envelope": None if result.envelope is None else {
            "what": f"percentiles of the signed follower motion error ({result.unit}) over the samples at every cam angle",
            "theta_deg": [round(float(t), 9) for t in result.envelope[0]],
            **{f"p{p:g}": [float(v) for v in values] for p, values in zip(ENVELOPE_PERCENTILES, result.envelope[1])},
        },
        "checks": [{"name": c.name, "unit": c.unit, "limit": c.limit, "comparison": "<=", "nominal": c.nominal,
                    "percentiles": [_pct(p) for p in c.percentiles], "at_percentile": _pct(c.at_percentile), "passed": c.passed}
                   for c in result.checks],
        "verdict_percentile": s.percentile,
        "sensitivity": {
            "method": "first-order indices Var(E[Y|X_i]) / Var(Y), the correlation ratio over round(sqrt(n)) equal-count bins "
                      "of each error (McKay 1995, NUREG/CR-6311; Plischke, Borgonovo & Smith 2013, EJOR 226:536-550)",
            "noise_floor": noise_floor(n),
            "rankings": {output: _ranking(names, idx) for output, idx in result.indices.items()},
        },
        "passed": not result.failed,
    }
    header = ["sample", *names, f"max_abs_error_{result.unit}", *(f"{c.name}_{c.unit}" for c in result.checks)]
    rows = [",".join(header)]
    table = np.column_stack([result.inputs, result.max_error, *result.check_values])
    for i, row in enumerate(table):
        rows.append(",".join([str(i), *(f"{v:.17g}" for v in row)]))  # 17 digits: the doubles themselves
    index = {"camgen_version": __version__, "command": "tolerance", "scene": result.scene.source, "cam": result.cam,
             "files": ["tolerance.json", "tolerance.csv"], "passed": not result.failed}
    return {"tolerance.json": json.dumps(data, indent=1, allow_nan=False) + "\n", "tolerance.csv": "\n".join(rows) + "\n",
            "report.json": json.dumps(index, indent=1, allow_nan=False) + "\n"}
