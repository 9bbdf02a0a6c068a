"""``camgen sweep``: evaluate a scene over many values of its keys, each design a row.

The varied keys come from ``--vary KEY=SPEC`` options, a ``--points`` file, or the scene's
``[sweep]`` table (the command line overrides it).  Before anything runs, every key is resolved
and its range read through the scene schema (:func:`validate_variables`: a value the scene refuses
for that key is bad input, exit 2, naming it) and the results folder is checked
(:class:`camgen.study.store.ResultsFolder`).  The points are then evaluated
(:func:`camgen.study.execute.run_points`), each batch written as a Parquet part as it arrives;
at the end ``summary.csv`` and ``sweep.json`` are written and the sweep report hook is called.

A design that fails a check or that the scene refuses (a geometry that cannot be built) is a
row with status ``fail`` or ``error``; the sweep's exit status is 0 once every point has a row.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from camgen.errors import CamgenError, ParameterError
from camgen.study.execute import Execution

if TYPE_CHECKING:
    from camgen.study.design import Row, StudyScene
    from camgen.study.space import Value, Variable
    from camgen.study.store import ResultsFolder

__all__ = ["CLUSTER_ENV", "DEFAULT_SEED", "ReportRequest", "SweepOutcome", "SweepPlan", "SweepRequest", "plan_sweep", "run_sweep",
           "sweep_command", "validate_variables", "write_sweep_report"]

#: The environment variable naming a Dask scheduler when neither --cluster nor --workers is given.
CLUSTER_ENV = "DASK_SCHEDULER_ADDRESS"
#: The seed of a sampled design (lhs, sobol) when none is given: the same command, the same points
#: (and --resume finds them again).
DEFAULT_SEED = 0


@dataclass(frozen=True)
class SweepRequest:
    """What ``camgen sweep`` was asked (its options, unchecked)."""

    scene: str | None = None
    vary: tuple[str, ...] = ()
    method: str | None = None
    samples: int | None = None
    seed: int | None = None
    points_file: str | None = None
    execution: Execution = field(default_factory=Execution)
    resume: bool = False
    outdir: str = "outputs"
    quiet: bool = False
    report: "ReportRequest" = field(default_factory=lambda: ReportRequest())


@dataclass(frozen=True)
class ReportRequest:
    """What the sweep's report was asked (``--map``, ``--pareto``, ``--rank``, ``--best``,
    ``--keep-files``), unchecked: :func:`plan_sweep` checks it before any design runs."""

    map_keys: tuple[str, ...] | None = None
    pareto: tuple[str, ...] | None = None
    rank: str | None = None
    best: int = 10
    keep_files: int = 0


@dataclass(frozen=True)
class SweepPlan:
    """A checked sweep: the base scene, the variables, how the points were chosen and the
    distinct points (each a tuple of values in the variables' order) with their keys."""

    study: "StudyScene"
    variables: "tuple[Variable, ...]"
    method: str
    samples: int | None
    seed: int | None
    points: "tuple[tuple[Value, ...], ...]"
    keys: tuple[str, ...]
    duplicates: int


@dataclass(frozen=True)
class SweepOutcome:
    """A finished sweep: its plan, results folder, rows in point order, counts per status and the
    facts written to ``sweep.json``."""

    plan: SweepPlan
    folder: "ResultsFolder"
    rows: tuple[Mapping[str, Any], ...]
    counts: Mapping[str, int]
    facts: Mapping[str, Any]


def _variables(request: SweepRequest, study: "StudyScene") -> "tuple[tuple[Variable, ...], str | None, int | None, int | None, list[tuple[Value, ...]] | None]":
    """The variables, method, samples, seed and (from a file) points, the command line over the
    scene's [sweep] table."""
    from camgen.study.space import parse_vary, read_points, sweep_table

    table = sweep_table(study.data)
    method = request.method or table.method
    samples = request.samples if request.samples is not None else table.samples
    seed = request.seed if request.seed is not None else table.seed
    if request.points_file is not None:
        if request.vary:
            raise ParameterError("--vary", list(request.vary), "not with --points (the file's columns are the varied keys)")
        if request.method is not None or request.samples is not None or request.seed is not None:
            raise ParameterError("--method/--samples/--seed", request.method or request.samples or request.seed,
                                 "none with --points (the file gives the points)")
        variables, points = read_points(Path(request.points_file), study.data)
        return variables, "file", None, None, points
    variables = parse_vary(study.data, request.vary) if request.vary else table.variables
    return variables, method, samples, seed, None


def validate_variables(study: "StudyScene", variables: "Sequence[Variable]") -> None:
    """Every variable's values read through the scene schema, before anything runs: the base scene
    with its low and high end, or each listed value, set.

    Raises
    ------
    ParameterError, SceneError
        The scene's own refusal when it names the varied key (a value out of its range, a key the
        table does not have).  Any other refusal (another key, a geometry that cannot be built)
        belongs to that design: it becomes the row's ``error`` status.
    """
    import numpy as np

    for variable in variables:
        values = variable.values or tuple(variable.scaled(np.array([0.0, 1.0])))
        last = str(variable.key.path[-1])
        absent = _absent(study.data, variable.key.path)
        for value in values:
            try:
                study.scene({variable.key.path: value})
            except ParameterError as exc:
                if exc.name == variable.name:
                    raise
            except CamgenError as exc:
                if absent and f"'{last}'" in str(exc) and "unknown" in str(exc):
                    raise
                # another refusal: this design's error row


def _absent(data: Mapping[str, Any], path: tuple[str | int, ...]) -> bool:
    node: Any = data
    for step in path:
        try:
            node = node[step]
        except (KeyError, IndexError, TypeError):
            return True
    return False


def plan_sweep(request: SweepRequest) -> SweepPlan:
    """The checked sweep of ``request`` (raises the one-line refusals of bad input)."""
    from camgen.study.design import StudyScene, point_key
    from camgen.study.space import design_points

    study = StudyScene.load(request.scene)
    variables, method, samples, seed, points = _variables(request, study)
    if points is None:
        if not variables:
            raise ParameterError("--vary", "", "at least one varied key (--vary KEY=SPEC, a [sweep.vary] table, or --points FILE)")
        if method is None:
            if not all(v.values or v.step is not None for v in variables):
                raise ParameterError("--method", None, "lhs or sobol with --samples N (a range without a step is no grid), "
                                     "or a step for every range (low:high:step)")
            method = "grid"
        if method == "grid" and (samples is not None or seed is not None):
            raise ParameterError("--samples/--seed", samples if samples is not None else seed,
                                 "none for a grid (it has every combination; --method lhs or sobol samples)")
        if method != "grid" and seed is None:
            seed = DEFAULT_SEED
        points = design_points(variables, method, samples, seed)
    assert method is not None  # a file's, or given, or grid
    validate_variables(study, variables)
    from camgen.study.best import check_best
    from camgen.study.report import report_options

    asked = request.report
    report_options(study, variables, asked.map_keys, asked.pareto, asked.best, asked.rank)  # refused now, not after the designs
    check_best(asked.keep_files, "--keep-files")
    names = [v.name for v in variables]
    unique: dict[str, tuple[Value, ...]] = {}
    for p in points:
        unique.setdefault(point_key(names, p), p)
    return SweepPlan(study, tuple(variables), method, samples, seed, tuple(unique.values()), tuple(unique),
                     len(points) - len(unique))


def write_sweep_report(outcome: SweepOutcome, asked: ReportRequest) -> list[Path]:
    """The sweep report's files written into the results folder (:mod:`camgen.study.report`:
    ``report.html``, the best designs' scenes ``best/<key>.toml``) and, with ``--keep-files N``,
    the best N designs run into ``best/<key>/``; the paths written."""
    from camgen.study.best import keep_files
    from camgen.study.report import sweep_report_files, write_report_files

    plan = outcome.plan
    files = sweep_report_files(plan.study, plan.variables, outcome.rows, map_keys=asked.map_keys, pareto=asked.pareto,
                               best=asked.best, rank=asked.rank, method=plan.method)
    written = write_report_files(outcome.folder.root, files)
    if asked.keep_files:
        kept = keep_files(plan.study, plan.variables, outcome.rows, asked.keep_files, asked.rank, outcome.folder.root)
        written += [outcome.folder.root / "best" / str(r.scene.name) for r in kept]
    return written


def _variable_facts(variable: "Variable") -> dict[str, Any]:
    facts: dict[str, Any] = {"key": variable.name}
    if variable.values:
        facts["values"] = list(variable.values)
    else:
        facts.update(low=variable.low, high=variable.high, step=variable.step)
    facts["integer"] = variable.integer
    return facts


def run_sweep(request: SweepRequest) -> SweepOutcome:
    """Plan, run and write the sweep of ``request`` (its results folder: :attr:`SweepOutcome.folder`)."""
    from camgen import __version__
    from camgen.study.design import evaluate_point
    from camgen.study.execute import Runner
    from camgen.study.keys import KeyPath
    from camgen.study.monitor import SweepProgress
    from camgen.study.store import ResultsFolder, folder_for

    started = time.perf_counter()
    plan = plan_sweep(request)
    folder = ResultsFolder.prepare(folder_for(request.outdir, plan.study.name), request.resume)
    finished: set[str] = set()
    if request.resume:
        folder.clean()
        finished = folder.finished(plan.study.scene_hash)
    todo = [p for p, k in zip(plan.points, plan.keys) if k not in finished]
    keys: list[KeyPath] = [v.key for v in plan.variables]
    progress = SweepProgress(len(plan.points), len(plan.points) - len(todo), enabled=not request.quiet)

    def sink(rows: "list[Row]") -> None:
        folder.write_part(rows, plan.variables)
        progress.add(rows)

    workers = 0
    eval_s = 0.0
    if todo:
        with Runner(request.execution) as runner:  # connected, every worker's version checked: then the designs
            workers = runner.workers
            try:  # the first design here: its time sizes the batches (the second evaluation: imports done)
                first = evaluate_point(plan.study, keys, todo[0])
                again = evaluate_point(plan.study, keys, todo[0])
                eval_s = min(float(first["eval_ms"] or 0.0), float(again["eval_ms"] or 0.0)) / 1e3
                sink([first])
                runner.run(plan.study, keys, todo[1:], eval_s, sink)
            finally:
                progress.close()
    by_key = {str(r["key"]): r for r in folder.read_rows()}
    missing = [k for k in plan.keys if k not in by_key]
    if missing:
        raise RuntimeError(f"{len(missing)} points of the sweep have no row (first key {missing[0]})")
    rows = tuple(by_key[k] for k in plan.keys)
    counts = Counter(str(r["status"]) for r in rows)
    facts = {
        "scene": plan.study.source, "scene_name": plan.study.name, "scene_hash": plan.study.scene_hash,
        "camgen_version": __version__, "method": plan.method, "seed": plan.seed, "samples": plan.samples,
        "points_file": request.points_file, "variables": [_variable_facts(v) for v in plan.variables],
        "points": len(plan.points), "duplicate_points": plan.duplicates, "evaluated": len(todo),
        "resumed": len(plan.points) - len(todo),
        "counts": {s: counts.get(s, 0) for s in ("pass", "fail", "error", "crashed")},
        "execution": request.execution.describe(), "workers": workers,
        "eval_ms": round(eval_s * 1e3, 3), "elapsed_s": round(time.perf_counter() - started, 3),
    }
    folder.write_summary(rows)
    folder.write_json(facts)
    outcome = SweepOutcome(plan, folder, rows, {s: counts.get(s, 0) for s in ("pass", "fail", "error", "crashed")}, facts)
    write_sweep_report(outcome, request.report)
    return outcome


def _execution(args: argparse.Namespace) -> Execution:
    cluster = args.cluster if args.cluster is not None else (os.environ.get(CLUSTER_ENV) or None if args.workers is None else None)
    if cluster is not None and args.workers is not None:
        raise ParameterError("--workers", args.workers, "not with --cluster (the cluster's workers run the sweep)")
    if cluster is not None and not cluster.strip():
        raise ParameterError("--cluster", cluster, "a Dask scheduler's address, e.g. tcp://10.0.0.5:8786 or tls://host:8786")
    workers = 1 if args.workers is None else args.workers
    if workers < 1:
        raise ParameterError("--workers", workers, "an integer >= 1 (1: in this process)")
    if args.batch is not None and args.batch < 1:
        raise ParameterError("--batch", args.batch, "an integer >= 1 (points per task)")
    return Execution(workers, cluster, args.batch, args.dashboard)


def sweep_command(args: argparse.Namespace) -> int:
    """``camgen sweep``'s handler: the sweep run, its folder and counts printed (unless -q); 0."""
    def names(text: str | None) -> tuple[str, ...] | None:
        return None if text is None else tuple(n.strip() for n in text.split(","))

    report = ReportRequest(names(args.map), names(args.pareto), args.rank, args.best, args.keep_files)
    request = SweepRequest(args.scene, tuple(args.vary or ()), args.method, args.samples, args.seed, args.points,
                           _execution(args), args.resume, args.outdir, args.quiet, report)
    outcome = run_sweep(request)
    if not args.quiet:
        counts = ", ".join(f"{n} {s}" for s, n in outcome.counts.items() if n or s != "crashed")
        print(f"{outcome.folder.root}/report.html")
        print(f"{outcome.folder.root}/summary.csv")
        print(f"{outcome.folder.root}/sweep.json")
        print(f"camgen: sweep: {len(outcome.rows)} designs ({counts}); {outcome.facts['evaluated']} evaluated "
              f"{outcome.facts['execution']} in {outcome.facts['elapsed_s']:.1f} s", file=sys.stdout)
    return 0
