"""What a study varies and the points it evaluates.

A :class:`Variable` is a scene key (:mod:`camgen.study.keys`) with either listed values
(``--vary KEY=v1,v2,...``) or a range (``--vary KEY=low:high`` for sampling, ``low:high:step``
for a grid).  :func:`design_points` turns the variables into points: the full grid (the
product of every variable's values), a Latin hypercube or a scrambled Sobol sequence
(:mod:`scipy.stats.qmc`, seeded: the same seed gives the same points), or the rows of a
CSV/Parquet file whose columns are keys (so designs from SALib or chaospy plug in).  A sampled
variable with listed values takes one of them with equal probability; an integer key is rounded.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping, Sequence

from camgen.errors import ParameterError
from camgen.study.keys import KeyPath, resolve_key

__all__ = ["MAX_POINTS", "METHODS", "SWEEP_REFERENCE", "SweepTable", "Value", "Variable", "design_points", "parse_vary", "read_points",
           "sweep_table"]

#: A scalar a study gives a key.
Value = float | int | str | bool
#: The most points one study evaluates (a larger grid is refused before anything runs).
MAX_POINTS = 10_000_000
#: How the points are chosen.
METHODS = ("grid", "lhs", "sobol", "file")
#: Points of a grid step range may exceed the high end by this fraction of a step (rounding of
#: a decimal step such as 0.1), relative.
_STEP_SLACK = 1e-9


@dataclass(frozen=True)
class Variable:
    """One varied scene key: ``values`` (listed) or ``low``/``high`` with an optional ``step``
    (a grid's spacing), in the key's own unit (degrees where the key says deg)."""

    key: KeyPath
    values: tuple[Value, ...] = ()
    low: float | None = None
    high: float | None = None
    step: float | None = None
    integer: bool = False

    @property
    def name(self) -> str:
        return self.key.name

    def grid(self) -> tuple[Value, ...]:
        """The grid values: the listed ones, or low, low + step, ... up to high (both ends in)."""
        if self.values:
            return self.values
        if self.step is None or self.low is None or self.high is None:
            raise ParameterError(f"--vary {self.name}", f"{self.low}:{self.high}", "low:high:step for a grid (a range "
                                 "without a step is for --method lhs or sobol)")
        count = int(math.floor((self.high - self.low) / self.step * (1 + _STEP_SLACK) + _STEP_SLACK)) + 1
        if count > MAX_POINTS:
            raise ParameterError(f"--vary {self.name}", f"{self.low}:{self.high}:{self.step}", f"at most {MAX_POINTS} values")
        import numpy as np

        values = self.low + self.step * np.arange(count)
        return tuple(self._typed(float(v)) for v in values)

    def scaled(self, unit: "Any") -> list[Value]:
        """The values at the unit-interval samples ``unit`` (a 1-D array in [0, 1))."""
        import numpy as np

        if self.values:
            index = np.minimum((np.asarray(unit) * len(self.values)).astype(int), len(self.values) - 1)
            return [self.values[i] for i in index.tolist()]
        assert self.low is not None and self.high is not None
        return [self._typed(v) for v in (self.low + (self.high - self.low) * np.asarray(unit)).tolist()]

    def _typed(self, value: float) -> Value:
        return int(round(value)) if self.integer else value


def _number(text: str) -> Value:
    """A listed value as TOML would type it: an integer, a float, true/false, else a string."""
    stripped = text.strip()
    if stripped in ("true", "false"):
        return stripped == "true"
    try:
        return int(stripped)
    except ValueError:
        pass
    try:
        value = float(stripped)
    except ValueError:
        return stripped.strip("'\"")
    if not math.isfinite(value):
        raise ValueError(stripped)
    return value


def _variable(data: Mapping[str, Any], key: str, spec: object, option: str) -> Variable:
    """The variable ``key`` = ``spec`` (text ``a:b[:step]`` or ``v1,v2``; in a [sweep] table also a
    list of values or a table {low, high, step})."""
    path = resolve_key(data, key, option)
    where = f"{option} {path.name}"
    integer = _base_is_int(data, path)
    valid = "low:high (sampled), low:high:step (a grid, step > 0), or values v1,v2,..."
    if isinstance(spec, list):
        if not spec or not all(isinstance(v, (int, float, str, bool)) for v in spec):
            raise ParameterError(where, spec, "a non-empty list of values")
        return Variable(path, tuple(spec), integer=integer)
    if isinstance(spec, dict):
        unknown = set(spec) - {"low", "high", "step"}
        if unknown or not {"low", "high"} <= set(spec):
            raise ParameterError(where, spec, "a table {low = ..., high = ..., step = ...} (step optional)")
        spec = ":".join(str(spec[k]) for k in ("low", "high", "step") if k in spec)
    if not isinstance(spec, str) or not spec.strip():
        raise ParameterError(where, spec, valid)
    try:
        if ":" in spec:
            parts = [float(p) for p in spec.split(":")]
            if len(parts) not in (2, 3) or not all(math.isfinite(p) for p in parts):
                raise ValueError(spec)
            low, high = parts[0], parts[1]
            step = parts[2] if len(parts) == 3 else None
            if high < low or (step is not None and step <= 0.0) or (step is None and high == low):
                raise ValueError(spec)
            return Variable(path, (), low, high, step, integer)
        return Variable(path, tuple(_number(v) for v in spec.split(",")), integer=integer)
    except ValueError:
        raise ParameterError(where, spec, valid + "; low < high, all finite") from None


def _base_is_int(data: Mapping[str, Any], key: KeyPath) -> bool:
    node: Any = data
    for step in key.path:
        try:
            node = node[step]
        except (KeyError, IndexError, TypeError):
            return False
    return isinstance(node, int) and not isinstance(node, bool)


def parse_vary(data: Mapping[str, Any], items: Sequence[str]) -> tuple[Variable, ...]:
    """The variables of ``--vary KEY=SPEC`` options (the decoded scene ``data`` resolves the keys)."""
    out = []
    for item in items:
        key, sep, spec = item.partition("=")
        if not sep:
            raise ParameterError("--vary", item, "KEY=low:high, KEY=low:high:step or KEY=v1,v2,...")
        out.append(_variable(data, key, spec, "--vary"))
    return _unique(out)


def _unique(variables: Sequence[Variable]) -> tuple[Variable, ...]:
    seen: set[str] = set()
    for v in variables:
        if v.name in seen:
            raise ParameterError("--vary", v.name, "each key once")
        seen.add(v.name)
    return tuple(variables)


#: The ``[sweep]`` table in the key reference (``camgen keys sweep``).
SWEEP_REFERENCE = """## [sweep]

Read by `camgen sweep` only (`camgen run` and `camgen check` check it and change nothing for it);
the command line's `--vary`, `--method`, `--samples`, `--seed` take precedence.

| key | value | default | changes | what it is |
| --- | --- | --- | --- | --- |
| `method` | one of grid, lhs, sobol | grid when every varied key has a step or values | sweep | how the points are chosen: the full grid, a Latin hypercube, a scrambled Sobol sequence |
| `samples` | integer >= 1 | required for lhs, sobol | sweep | the points of a sampled design |
| `seed` | integer >= 0 | none (fresh entropy) | sweep | the sampler's seed: the same seed, the same points |

Each key of the `[sweep.vary]` table is a scene key's path (`"cams.plate.base_radius_mm"`,
`"cams.plate.segments[0].lift_mm"`, or a bare key of the scene's only cam) and its value one of:
`"low:high:step"` (a grid from low to high, both in), `"low:high"` (a range to sample), a list of
values (`[5.0, 10.0]`, `["cycloidal", "poly345"]`), or a table `{low = 30.0, high = 60.0, step = 5.0}`.
"""


@dataclass(frozen=True)
class SweepTable:
    """A scene's ``[sweep]`` table: ``method``, ``samples``, ``seed`` and the ``vary`` table."""

    variables: tuple[Variable, ...]
    method: str | None = None
    samples: int | None = None
    seed: int | None = None


def sweep_table(data: Mapping[str, Any]) -> SweepTable:
    """The ``[sweep]`` table of the decoded scene (absent: no variables)."""
    table = data.get("sweep")
    if table is None:
        return SweepTable(())
    if not isinstance(table, dict):
        raise ParameterError("sweep", table, "a table: [sweep] with method, samples, seed and a [sweep.vary] table")
    unknown = sorted(set(table) - {"method", "samples", "seed", "vary"})
    if unknown:
        raise ParameterError(f"sweep.{unknown[0]}", table[unknown[0]], "one of method, samples, seed, vary")
    vary = table.get("vary", {})
    if not isinstance(vary, dict):
        raise ParameterError("sweep.vary", vary, "a table of KEY = \"low:high[:step]\" or [values]")
    method = table.get("method")
    if method is not None and method not in METHODS[:3]:
        raise ParameterError("sweep.method", method, "one of grid, lhs, sobol")
    samples, seed = table.get("samples"), table.get("seed")
    for name, value in (("samples", samples), ("seed", seed)):
        if value is not None and (not isinstance(value, int) or isinstance(value, bool) or value < (1 if name == "samples" else 0)):
            raise ParameterError(f"sweep.{name}", value, "an integer >= 1" if name == "samples" else "an integer >= 0")
    variables = _unique([_variable(data, key, spec, "sweep.vary") for key, spec in vary.items()])
    return SweepTable(variables, method, samples, seed)


def read_points(path: Path, data: Mapping[str, Any]) -> tuple[tuple[Variable, ...], list[tuple[Value, ...]]]:
    """The points of a CSV or Parquet file: one column per key, one row per point.

    Returns the variables (listed values: each column's distinct values) and the points in file
    order."""
    suffix = path.suffix.lower()
    if suffix not in (".csv", ".parquet"):
        raise ParameterError("--points", str(path), "a .csv or .parquet file of one column per scene key")
    if not path.is_file():
        raise ParameterError("--points", str(path), "an existing .csv or .parquet file")
    if suffix == ".parquet":
        from camgen.study.optional import require

        pq = require("pyarrow.parquet", "reading a Parquet file of points")
        table = pq.read_table(path).to_pydict()
        columns = list(table)
        rows = list(zip(*(table[c] for c in columns)))
    else:
        import csv

        with path.open(newline="", encoding="utf-8") as handle:
            reader = csv.reader(handle)
            columns = next(reader, [])
            try:
                rows = [tuple(_number(v) for v in row) for row in reader if row]
            except ValueError as exc:
                raise ParameterError("--points", str(path), "finite numbers or words in every cell") from exc
    if not columns or not rows:
        raise ParameterError("--points", str(path), "a header of scene keys and at least one row")
    if any(len(r) != len(columns) for r in rows):
        raise ParameterError("--points", str(path), f"{len(columns)} cells in every row (the header's)")
    keys = [resolve_key(data, c, "--points") for c in columns]
    variables = _unique([Variable(k, tuple(dict.fromkeys(r[i] for r in rows)), integer=_base_is_int(data, k))
                         for i, k in enumerate(keys)])
    if len(rows) > MAX_POINTS:
        raise ParameterError("--points", str(path), f"at most {MAX_POINTS} rows")
    return variables, [tuple(r) for r in rows]


def design_points(variables: Sequence[Variable], method: str, samples: int | None = None,
                  seed: int | None = None) -> list[tuple[Value, ...]]:
    """The points of a study, each a tuple of values in the order of ``variables``.

    Parameters
    ----------
    method : ``grid`` (every combination of the variables' grid values), ``lhs`` (Latin hypercube,
        McKay et al. 1979) or ``sobol`` (scrambled Sobol sequence, Owen scrambling; scipy.stats.qmc).
    samples : points of a sampled design (``lhs``, ``sobol``).
    seed : the sampler's seed (the same seed, the same points).
    """
    if not variables:
        raise ParameterError("--vary", "", "at least one varied key (--vary KEY=... or a [sweep.vary] table)")
    if method == "grid":
        sizes = [len(v.grid()) for v in variables]
        if math.prod(sizes) > MAX_POINTS:
            raise ParameterError("--vary", " x ".join(map(str, sizes)), f"a grid of at most {MAX_POINTS} points")
        import itertools

        return [tuple(p) for p in itertools.product(*(v.grid() for v in variables))]
    if method not in ("lhs", "sobol"):
        raise ParameterError("--method", method, "one of grid, lhs, sobol")
    if samples is None or samples < 1 or samples > MAX_POINTS:
        raise ParameterError("--samples", samples, f"an integer from 1 to {MAX_POINTS} (the points of an {method} design)")
    import warnings

    from scipy.stats import qmc

    sampler = (qmc.LatinHypercube(d=len(variables), seed=seed) if method == "lhs"
               else qmc.Sobol(d=len(variables), scramble=True, seed=seed))
    with warnings.catch_warnings():  # Sobol's balance wants a power of 2 points: the README says so
        warnings.simplefilter("ignore", UserWarning)
        unit = sampler.random(samples)
    columns = [v.scaled(unit[:, i]) for i, v in enumerate(variables)]
    return [tuple(p) for p in zip(*columns)]
