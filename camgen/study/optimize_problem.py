"""The problem an optimisation solves: one figure of a design, every check with a limit a constraint.

:func:`parse_objective` reads ``--minimize/--maximize FIGURE``: a main figure of
:data:`camgen.study.design.FIGURES` (bare for a one-cam scene, or ``fig.<cam>.<figure>``) or a
check's value (``check.<cam>.<check>``).  :class:`Evaluator` evaluates a design (the base scene
with the varied keys set, read through the scene schema, built and checked by
:func:`camgen.pipeline.compute` with no files) into a :class:`Trial`: the figure and one
*margin* per check with a limit, how far the design is inside (>= 0) or outside (< 0) it,
normalised by the limit's size (:func:`check_margin`), so an optimiser sees how far a design is
from feasible.  A design the scene refuses is infeasible by :data:`PENALTY` on every check.
The evaluator remembers every design (an optimiser asking twice gets the same trial, counted
once) and stops the optimisation when its budget of evaluations is spent (:class:`BudgetSpent`).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Mapping, Sequence

from camgen.errors import CamgenError, ParameterError
from camgen.study.design import FIGURES, design_plan, finite_number, main_figures

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.results import CamResult, RunResult
    from camgen.study.design import StudyScene
    from camgen.study.space import Variable

__all__ = ["BudgetSpent", "Evaluator", "MARGIN_FLOOR", "Objective", "PENALTY", "SENSES", "STRICT_MARGIN", "Trial",
           "VALUE_DIGITS", "check_margin", "parse_objective", "trial_values"]

#: A limit smaller than this in size (in its own unit) normalises a margin by this instead.
MARGIN_FLOOR = 1.0
#: The margin of every check of a design the scene refuses (a value out of range, a geometry
#: that cannot be built): far worse than any design that builds.
PENALTY = 1e3
#: The margin of a failed check whose value equals its strict limit (``<``, ``>``): just below 0.
STRICT_MARGIN = 1e-12
#: A varied value is rounded to this many significant digits before it is evaluated, so the
#: optimum written into the scene file is exactly the design that was evaluated.
VALUE_DIGITS = 10
#: Whether the figure is minimised or maximised.
SENSES = ("minimize", "maximize")
#: The constraint slots after the base scene's checks: checks a design has that the base scene
#: has not (their least margin), and whether the figure has a value at the design.
OTHER_CHECKS, FIGURE_DEFINED = "other checks", "figure defined"


@dataclass(frozen=True)
class Objective:
    """What is optimised: ``column`` as a study row names it (``fig.<cam>.<figure>`` or
    ``check.<cam>.<check>``), its parts, and ``sense`` (:data:`SENSES`)."""

    column: str
    kind: str
    cam: str
    name: str
    sense: str

    def signed(self, value: float) -> float:
        """The value the optimiser minimises: ``value`` itself, or its negative when maximised."""
        return value if self.sense == "minimize" else -value


def _figure_rule(cams: Sequence[str]) -> str:
    example = cams[0] if cams else "CAM"
    return (f"a main figure ({', '.join(FIGURES)}; bare for a one-cam scene, or 'fig.{example}.<figure>') or a check's "
            f"value 'check.{example}.<check>' (camgen check lists the checks)")


def parse_objective(data: Mapping[str, Any], text: str, sense: str) -> Objective:
    """The objective ``--minimize/--maximize text`` of the decoded scene ``data``.

    A check's name is checked against the base scene's checks by :class:`Evaluator` (they are
    known only once a design is built).  Raises :class:`ParameterError` naming the option.
    """
    option = f"--{sense}"
    cams_table = data.get("cams")
    cams = list(cams_table) if isinstance(cams_table, dict) else []
    parts = text.strip().split(".") if isinstance(text, str) else []
    if len(parts) == 1 and parts[0] in FIGURES:
        if len(cams) != 1:
            raise ParameterError(option, text, _figure_rule(cams), f"the scene has {len(cams)} cams: name one")
        return Objective(f"fig.{cams[0]}.{parts[0]}", "fig", cams[0], parts[0], sense)
    if len(parts) == 3 and parts[0] in ("fig", "check") and parts[1] in cams and parts[2]:
        if parts[0] == "fig" and parts[2] not in FIGURES:
            raise ParameterError(option, text, _figure_rule(cams))
        return Objective(".".join(parts), parts[0], parts[1], parts[2], sense)
    raise ParameterError(option, text, _figure_rule(cams))


def check_margin(check: "CheckResult") -> float | None:
    """How far ``check`` is inside its limit (>= 0 exactly when it passed), None for information.

    A number against a number limit: ``(limit - value) / scale`` for ``<=``/``<`` and
    ``(value - limit) / scale`` for ``>=``/``>``, ``scale = max(|limit|, MARGIN_FLOOR)`` in the
    check's unit; anything else (a continuity level, "no concave part", a value that is not
    finite) is +1 when passed and -1 when failed.
    """
    if check.passed is None:
        return None
    value, limit = check.value, check.limit
    numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in (value, limit))
    if not numbers or check.comparison not in ("<=", "<", ">=", ">"):
        return 1.0 if check.passed else -1.0
    scale = max(abs(float(limit)), MARGIN_FLOOR)
    margin = (float(limit) - float(value)) / scale if check.comparison in ("<=", "<") else (float(value) - float(limit)) / scale
    return max(margin, 0.0) if check.passed else min(margin, -STRICT_MARGIN)


@dataclass(frozen=True)
class Trial:
    """One evaluated design.

    ``number`` (0, 1, ... in the order evaluated); ``values`` (the varied keys' values, in the
    variables' order); ``status`` (pass: every check with a limit passed; fail; error: the scene
    refused it, ``error`` is the one ``camgen: error:`` line); ``objective`` (the figure's value
    in its unit, None when it has none here); ``margins`` (one per constraint name of the
    :class:`Evaluator`); ``eval_ms`` (the evaluation's time).
    """

    number: int
    values: tuple[float | int, ...]
    status: str
    error: str
    objective: float | None
    margins: tuple[float, ...]
    eval_ms: float

    @property
    def feasible(self) -> bool:
        """Every check with a limit passed and the figure has a value."""
        return self.status == "pass" and self.objective is not None


class BudgetSpent(Exception):
    """The evaluator's budget of evaluations is spent: the optimiser is stopped."""


def _figure(cam: "CamResult", name: str) -> float | None:
    """The main figure ``name`` (:data:`FIGURES`) of a built and checked cam."""
    return main_figures(cam)[name]


def trial_values(variables: "Sequence[Variable]", unit: Sequence[float]) -> tuple[float | int, ...]:
    """The keys' values at the unit-cube point ``unit`` (0: a key's low end, 1: its high end),
    clipped to the bounds, rounded to :data:`VALUE_DIGITS` significant digits (an integer key to
    the nearest integer)."""
    out: list[float | int] = []
    for v, u in zip(variables, unit):
        assert v.low is not None and v.high is not None
        value = min(max(v.low + (v.high - v.low) * min(max(float(u), 0.0), 1.0), v.low), v.high)
        out.append(int(round(value)) if v.integer else float(f"{value:.{VALUE_DIGITS}g}"))
    return tuple(out)


class Evaluator:
    """Designs of ``study`` with ``variables`` set, evaluated once each, at most ``budget`` of them.

    The constraint names (:attr:`names`) are ``cams.<cam>.<check>`` of every check with a limit
    of the base scene, then :data:`OTHER_CHECKS` and :data:`FIGURE_DEFINED`.  Building the
    evaluator evaluates the base scene as it is (not counted): a base scene that cannot be built,
    a check objective the scene has not, or a figure with no value there, is refused.
    ``on_trial`` is called with each new trial (a progress display).
    """

    def __init__(self, study: "StudyScene", variables: "Sequence[Variable]", objective: Objective, budget: int,
                 on_trial: "Callable[[Trial], None] | None" = None) -> None:
        self.study = study
        self.on_trial = on_trial
        self.variables = tuple(variables)
        self.objective = objective
        self.budget = budget
        self.trials: list[Trial] = []
        self._seen: dict[tuple[float | int, ...], Trial] = {}
        try:
            base = self._compute({})
        except CamgenError as exc:
            raise ParameterError("SCENE", study.source, "a scene camgen check builds (the optimisation starts from it)",
                                 " ".join(str(exc).split())) from None
        self.names: tuple[str, ...] = tuple(f"cams.{cam.name}.{c.name}" for cam in base.cams for c in cam.checks
                                            if c.passed is not None) + (OTHER_CHECKS, FIGURE_DEFINED)
        cam = next((c for c in base.cams if c.name == objective.cam), None)
        option = f"--{objective.sense}"
        if cam is not None and objective.kind == "check" and objective.name not in {c.name for c in cam.checks}:
            raise ParameterError(option, objective.column, f"a check of cam '{objective.cam}': "
                                 + ", ".join(f"check.{cam.name}.{c.name}" for c in cam.checks))
        if cam is None or self._value(base) is None:
            check = next((c for c in (cam.checks if cam is not None else ()) if c.name == objective.name), None)
            why = (f"the base scene's {objective.name} is {check.value!r}, not a number" if check is not None
                   else "the base scene has none (no dynamics: no torque, stress or jump speed)")
            raise ParameterError(option, objective.column, "a figure with a number for this scene", why)

    def _compute(self, values: Mapping[tuple[str | int, ...], float | int]) -> "RunResult":
        from camgen.pipeline import compute

        scene = self.study.scene(values)
        return compute(scene, design_plan(scene))

    def _value(self, result: "RunResult") -> float | None:
        cam = next((c for c in result.cams if c.name == self.objective.cam), None)
        if cam is None:
            return None
        if self.objective.kind == "fig":
            return _figure(cam, self.objective.name)
        check = next((c for c in cam.checks if c.name == self.objective.name), None)
        return None if check is None else finite_number(check.value)

    def __call__(self, values: tuple[float | int, ...]) -> Trial:
        """The trial of the design with ``values`` (evaluated now, or remembered)."""
        known = self._seen.get(values)
        if known is not None:
            return known
        if len(self.trials) >= self.budget:
            raise BudgetSpent()
        from camgen.interrupt import checkpoint

        checkpoint()  # Ctrl-C between two designs stops the optimisation
        started = time.perf_counter()
        status, error, objective = "error", "", None
        margins = [-PENALTY] * len(self.names)
        try:
            result = self._compute({v.key.path: x for v, x in zip(self.variables, values)})
        except CamgenError as exc:
            error = "camgen: error: " + " ".join(str(exc).split())
        else:
            found: dict[str, float] = {}
            for cam in result.cams:
                for check in cam.checks:
                    m = check_margin(check)
                    if m is not None:
                        found[f"cams.{cam.name}.{check.name}"] = m
            objective = self._value(result)
            other = [m for name, m in found.items() if name not in self.names]
            margins = [found.get(name, 1.0) for name in self.names[:-2]] + [min(other, default=1.0),
                                                                           1.0 if objective is not None else -1.0]
            status = "pass" if all(m >= 0.0 for m in found.values()) else "fail"
        trial = Trial(len(self.trials), values, status, error, objective, tuple(margins), (time.perf_counter() - started) * 1e3)
        self.trials.append(trial)
        self._seen[values] = trial
        if self.on_trial is not None:
            self.on_trial(trial)
        return trial
