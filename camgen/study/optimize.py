"""``camgen optimize``: the design that minimises (or maximises) a figure with every check passing.

The varied keys are continuous within their bounds (``--vary KEY=low:high``); the optimiser works
in the unit cube of those bounds (:func:`camgen.study.optimize_problem.trial_values`) and sees
every check with a limit as a constraint ``margin >= 0`` (:mod:`camgen.study.optimize_problem`).

Methods (:data:`METHODS`): ``de``, scipy's differential evolution (Storn & Price 1997; seeded,
the base scene's values in its first population when they are within the bounds) on
:data:`DE_SHARE` of the evaluations, then a COBYLA refinement from its best design with the
rest; ``cobyla``, COBYLA alone (Powell 1994; a local method) from the base scene's values.
COBYLA stops when its trust region is :data:`X_TOL` of every key's range, so the optimum lies
within about ``X_TOL * (high - low)`` of a constrained optimum it converged to.  The best design
is the best *feasible* one evaluated (every check passed), whatever the optimiser reports.

Outputs, in ``OUTDIR/<scene>-optimum/`` as one atomic run (:func:`camgen.staging.write_run`):
the best design's scene ``<scene>-optimum.toml`` (the base scene's text with the new values, its
comments kept: :func:`camgen.scene_edit.edit_scene_text`), the files of its run (as ``camgen run``
of that scene writes them) and ``optimize.json`` (:func:`history`).  No feasible design: nothing
is written and the status is 1, with one line naming the check that never passed.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Sequence

from camgen.errors import ParameterError
from camgen.study.optimize_problem import BudgetSpent, Evaluator, Objective, Trial, parse_objective, trial_values

if TYPE_CHECKING:
    from camgen.study.design import StudyScene
    from camgen.study.space import Variable

__all__ = ["DEFAULT_EVALUATIONS", "DE_SHARE", "INSIDE_MARGIN", "MAX_EVALUATIONS", "METHODS", "OptimizeResult", "X_TOL", "best_trial",
           "history", "optimize", "optimize_command", "parse_variables"]

METHODS = ("de", "cobyla")
#: The designs evaluated when ``--max-evaluations`` is not given, and the most it accepts.
DEFAULT_EVALUATIONS, MAX_EVALUATIONS = 400, 1_000_000
#: The share of the evaluations differential evolution may use before the COBYLA refinement.
DE_SHARE = 0.75
#: COBYLA's final trust-region radius, a fraction of each key's range (unit cube).
X_TOL = 1e-4
#: COBYLA's first trust-region radius, a fraction of each key's range.
COBYLA_START = 0.1
#: The optimiser is asked for margins of at least this (normalised, :func:`check_margin`), not 0:
#: COBYLA converges to a constraint's boundary from either side and accepts a tiny violation, so
#: the design it ends on is still inside every check's limit (a pressure angle of 30 deg: 3e-5 deg).
INSIDE_MARGIN = 1e-6


@dataclass(frozen=True)
class OptimizeResult:
    """An optimisation: every trial in order, the best feasible one (None: none was feasible)."""

    objective: Objective
    variables: tuple["Variable", ...]
    names: tuple[str, ...]
    trials: tuple[Trial, ...]
    best: Trial | None
    method: str
    seed: int


def _base_value(data: Any, path: tuple[str | int, ...]) -> Any:
    """The base scene's value at ``path`` (None when absent: the key is at its default)."""
    node: Any = data
    for step in path:
        if isinstance(node, dict) and isinstance(step, str):
            node = node.get(step)
        elif isinstance(node, list) and isinstance(step, int) and 0 <= step < len(node):
            node = node[step]
        else:
            return None
    return node


def parse_variables(data: Any, items: Sequence[str] | None) -> tuple["Variable", ...]:
    """The ``--vary KEY=low:high`` ranges: continuous keys of numbers (listed values and grid steps
    are a sweep's, refused here)."""
    from camgen.study.space import parse_vary

    if not items:
        raise ParameterError("--vary", "", "at least one KEY=low:high (a scene key and its bounds)")
    variables = parse_vary(data, list(items))
    for v in variables:
        spec = ",".join(map(str, v.values)) if v.values else f"{v.low}:{v.high}:{v.step}"
        if v.values or v.step is not None:
            raise ParameterError(f"--vary {v.name}", spec, "low:high, a continuous range (listed values and grid steps "
                                 "are for camgen sweep)")
        node = _base_value(data, v.key.path)
        if node is not None and (isinstance(node, bool) or not isinstance(node, (int, float))):
            raise ParameterError(f"--vary {v.name}", f"{v.low}:{v.high}", "a key whose value is a number",
                                 f"the scene gives it {node!r}")
    return variables


def best_trial(trials: Sequence[Trial], objective: Objective) -> Trial | None:
    """The feasible trial with the best figure (the first of equals), None when none is feasible."""
    feasible = [t for t in trials if t.feasible]
    if not feasible:
        return None
    return min(feasible, key=lambda t: (objective.signed(t.objective or 0.0), t.number))


def _closest(trials: Sequence[Trial]) -> Trial | None:
    """The built design nearest to passing (the largest least margin), None when none was built."""
    built = [t for t in trials if t.status != "error"]
    return max(built, key=lambda t: (min(t.margins), -t.number)) if built else None


def _unit(variables: Sequence["Variable"], values: Sequence[float | int]) -> list[float]:
    out = []
    for v, x in zip(variables, values):
        assert v.low is not None and v.high is not None
        out.append((float(x) - v.low) / (v.high - v.low))
    return out


def _start(study: "StudyScene", variables: Sequence["Variable"]) -> list[float] | None:
    """The base scene's values in the unit cube (None when one is absent or out of the bounds)."""
    values = []
    for v in variables:
        node = _base_value(study.data, v.key.path)
        if not isinstance(node, (int, float)) or isinstance(node, bool):
            return None
        values.append(node)
    unit = _unit(variables, values)
    return unit if all(0.0 <= u <= 1.0 for u in unit) else None


def _objective_value(evaluator: Evaluator, trial: Trial) -> float:
    """What the optimiser minimises at a trial: the signed figure; a design with no figure (the
    scene refused it) is given the worst signed figure seen plus 1 (the constraints say why)."""
    if trial.objective is not None:
        return evaluator.objective.signed(trial.objective)
    seen = [evaluator.objective.signed(t.objective) for t in evaluator.trials if t.objective is not None]
    return (max(seen) if seen else 0.0) + 1.0


def _cobyla(evaluator: Evaluator, start: Sequence[float]) -> None:
    import numpy as np
    from scipy.optimize import NonlinearConstraint, minimize

    d = len(evaluator.variables)

    def trial(x: Any) -> Trial:
        return evaluator(trial_values(evaluator.variables, x))

    constraint = NonlinearConstraint(lambda x: np.array(trial(x).margins), INSIDE_MARGIN, np.inf)
    minimize(lambda x: _objective_value(evaluator, trial(x)), np.asarray(start, dtype=float), method="COBYLA",
             bounds=[(0.0, 1.0)] * d, constraints=[constraint],
             options={"rhobeg": COBYLA_START, "tol": X_TOL, "maxiter": max(evaluator.budget, 1)})


def _differential_evolution(evaluator: Evaluator, start: Sequence[float] | None, seed: int) -> None:
    import numpy as np
    from scipy.optimize import NonlinearConstraint, differential_evolution

    d = len(evaluator.variables)

    def trial(x: Any) -> Trial:
        return evaluator(trial_values(evaluator.variables, x))

    constraint = NonlinearConstraint(lambda x: np.array(trial(x).margins), INSIDE_MARGIN, np.inf)
    differential_evolution(lambda x: _objective_value(evaluator, trial(x)), [(0.0, 1.0)] * d, constraints=constraint,
                           rng=np.random.default_rng(seed), polish=False, x0=None if start is None else np.asarray(start),
                           maxiter=evaluator.budget, updating="immediate")


def optimize(study: "StudyScene", variables: Sequence["Variable"], objective: Objective, method: str = "de",
             seed: int = 0, max_evaluations: int = DEFAULT_EVALUATIONS,
             progress: Callable[[str], None] | None = None) -> OptimizeResult:
    """Optimise ``objective`` over ``variables`` of ``study`` subject to every check passing.

    Evaluates at most ``max_evaluations`` designs (the base scene's own evaluation not counted);
    the same seed gives the same trials.  ``progress`` is called after each design with a line
    (designs done, feasible, the best figure so far).
    """
    best: list[float] = []
    feasible = [0]

    def report(trial: Trial) -> None:
        if trial.feasible and trial.objective is not None:
            feasible[0] += 1
            if not best or objective.signed(trial.objective) < objective.signed(best[0]):
                best[:] = [trial.objective]
        if progress is not None:
            shown = f", best {best[0]:.6g}" if best else ""
            progress(f"optimising: {trial.number + 1}/{max_evaluations} designs, {feasible[0]} feasible{shown}")

    if method not in METHODS:
        raise ParameterError("--method", method, "one of " + ", ".join(METHODS))
    if not 1 <= max_evaluations <= MAX_EVALUATIONS:
        raise ParameterError("--max-evaluations", max_evaluations, f"an integer from 1 to {MAX_EVALUATIONS}")
    evaluator = Evaluator(study, variables, objective, max_evaluations if method == "cobyla"
                          else max(1, int(max_evaluations * DE_SHARE)), report)
    start = _start(study, variables)
    try:
        if method == "de":
            _differential_evolution(evaluator, start, seed)
        else:
            _cobyla(evaluator, start if start is not None else [0.5] * len(variables))
    except BudgetSpent:
        pass
    if method == "de":  # a local refinement of the best design with the evaluations left
        evaluator.budget = max_evaluations
        found = best_trial(evaluator.trials, objective) or _closest(evaluator.trials)
        if found is not None and len(evaluator.trials) < max_evaluations:
            try:
                _cobyla(evaluator, _unit(variables, found.values))
            except BudgetSpent:
                pass
    trials = tuple(evaluator.trials)
    return OptimizeResult(objective, tuple(variables), evaluator.names, trials, best_trial(trials, objective), method, seed)


def history(result: OptimizeResult, study: "StudyScene", max_evaluations: int) -> dict[str, Any]:
    """``optimize.json``: the problem, the optimiser, every evaluation and the best design.

    ``evaluations``: each trial's ``values`` (key -> value), ``status``, ``error``, ``objective``
    (the figure, null when none), ``feasible`` and ``margins`` (constraint name -> margin, >= 0
    inside the limit); ``best``: the best feasible trial (null when none).
    """
    from camgen import __version__

    def entry(t: Trial) -> dict[str, Any]:
        return {"number": t.number, "values": {v.name: x for v, x in zip(result.variables, t.values)}, "status": t.status,
                "error": t.error, "objective": t.objective, "feasible": t.feasible,
                "margins": dict(zip(result.names, t.margins))}

    return {
        "camgen_version": __version__, "scene": study.source, "scene_hash": study.scene_hash,
        "objective": {"figure": result.objective.column, "sense": result.objective.sense},
        "variables": [{"key": v.name, "low": v.low, "high": v.high, "integer": v.integer} for v in result.variables],
        "constraints": list(result.names), "method": result.method, "seed": result.seed,
        "max_evaluations": max_evaluations, "evaluations_done": len(result.trials), "x_tol": X_TOL,
        "feasible_evaluations": sum(t.feasible for t in result.trials),
        "best": None if result.best is None else entry(result.best),
        "evaluations": [entry(t) for t in result.trials],
    }


def _never_passed(result: OptimizeResult) -> str:
    """Why no design was feasible, in a few words naming the check."""
    built = [t for t in result.trials if t.status != "error"]
    if not built:
        first = next((t.error for t in result.trials if t.error), "")
        return f"every design was refused by the scene ({first.removeprefix('camgen: error: ')})"
    never = [name for i, name in enumerate(result.names) if all(t.margins[i] < 0.0 for t in built)]
    if never:
        closest = max(built, key=lambda t: t.margins[result.names.index(never[0])])
        shown = ", ".join(f"{v.name} = {x:g}" for v, x in zip(result.variables, closest.values))
        return f"{never[0]} never passed (closest at {shown})"
    return "no design passed every check at once"


def optimize_command(scene: str | None, vary: Sequence[str] | None, minimize: str | None, maximize: str | None,
                     method: str, seed: int, max_evaluations: int, outdir: str, quiet: bool) -> int:
    """``camgen optimize``: returns the exit status (0 an optimum whose run passed every check,
    1 no feasible design or the optimum's run failed a check; bad input raises)."""
    import sys

    from camgen.study.design import StudyScene

    if not outdir.strip():
        raise ParameterError("-o/--outdir", outdir, "a folder path (default: outputs)")
    if method not in METHODS:
        raise ParameterError("--method", method, "one of " + ", ".join(METHODS))
    if not 1 <= max_evaluations <= MAX_EVALUATIONS:
        raise ParameterError("--max-evaluations", max_evaluations, f"an integer from 1 to {MAX_EVALUATIONS}")
    if seed < 0:
        raise ParameterError("--seed", seed, "an integer >= 0")
    study = StudyScene.load(scene)
    variables = parse_variables(study.data, vary)
    sense, figure = ("maximize", maximize) if maximize is not None else ("minimize", minimize)
    if figure is None:
        raise ParameterError("--minimize", "", "a figure to minimise (or --maximize FIGURE)")
    objective = parse_objective(study.data, figure, sense)
    target = Path(outdir) / f"{study.name}-optimum"
    from camgen.staging import preflight

    preflight(target)
    from camgen.progress import TerminalProgress

    display = TerminalProgress(enabled=not quiet)
    try:
        result = optimize(study, variables, objective, method, seed, max_evaluations, display)
    finally:
        display.close()
    if result.best is None:
        print(f"camgen: no feasible design in {len(result.trials)} evaluations: {_never_passed(result)}", file=sys.stderr)
        return 1
    return _write_optimum(study, result, target, max_evaluations, quiet)


def _write_optimum(study: "StudyScene", result: OptimizeResult, target: Path, max_evaluations: int, quiet: bool) -> int:
    """The best design's scene, run and history written into ``target`` in one atomic swap."""
    import sys

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene
    from camgen.scene_edit import edit_scene_text
    from camgen.staging import write_run
    from camgen.study.design import point_scene_data

    best = result.best
    assert best is not None
    data = point_scene_data(study.data, {v.key.path: x for v, x in zip(result.variables, best.values)})
    text = edit_scene_text(study.text, data)
    scene = parse_scene(data, target.name, study.source, study.base_dir)
    run = execute(scene, plan_run(scene))
    files = dict(run.files)
    files[f"{target.name}.toml"] = text
    files["optimize.json"] = json.dumps(history(result, study, max_evaluations), indent=1, allow_nan=False) + "\n"
    write_run(target, files)
    failed = run.failed_checks()
    for cam, check in failed:
        print(f"camgen: check failed: cams.{cam}: {check.name} in the optimum's run ({check.note})", file=sys.stderr)
    if not quiet:
        shown = ", ".join(f"{v.name} = {x:g}" for v, x in zip(result.variables, best.values))
        print(f"{target}/{target.name}.toml")
        print(f"{target}/optimize.json")
        print(f"camgen: optimum: {result.objective.column} = {best.objective:.6g} at {shown} ({len(result.trials)} "
              f"evaluations, {sum(t.feasible for t in result.trials)} feasible)")
    return 1 if failed else 0
