"""The evaluation of one design, as a sweep makes it: the plan of a run that writes nothing.

A sweep (issue 28) evaluates each design point as ``compute(scene, evaluation_plan(scene))``
(:func:`camgen.pipeline.compute`): synthesis, every design check and the dynamics checks, the
figures those checks and the main figures need (size, peak pressure angle, least radius, peak
torque, contact stress, jump speed), and nothing else: no output format, no mesh, no analysis or
plot stage, no figure only the report shows (the law's acceleration harmonics:
:attr:`camgen.planning.Plan.report_figures`).  Every check it makes is the check ``camgen
check`` makes on the same scene, with the same value and status (tests/test_evaluation_speed.py
compares them); ``camgen check`` also runs the export checks of the files a run would write (a
tool path that would gouge, a mesh that cannot be built), which this plan does not make.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from camgen.planning import Plan

if TYPE_CHECKING:
    from camgen.scene import Scene

__all__ = ["evaluation_plan"]


def evaluation_plan(scene: "Scene") -> Plan:
    """The plan of one design's evaluation: no file, no stage beyond synthesis and the checks,
    no report-only figure.  The same for every scene (the argument keeps the planner's shape)."""
    del scene  # the checks are planned the same for every scene: synthesis and checks always run
    return Plan((), frozenset(), full_report=False, report_figures=False)
