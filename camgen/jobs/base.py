"""What a mechanism job is: its keys, how to read them, how to run, what it returns."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from camgen.schema import Key

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.report.model import SectionData

__all__ = ["JobResult", "MechanismJob"]


@dataclass(frozen=True)
class JobResult:
    """What a mechanism job returns.

    Attributes
    ----------
    report : its section of report.json (``mechanisms.<job>``).
    files : file name -> text.
    checks : cam name -> checks the mechanism decides (they replace the cam's own checks of
        the same name: e.g. the pressure angle in the mechanism instead of on a bare face).
    curves : cam name -> (cam angle rad, pressure angle rad, label) report.html draws instead
        of the cam's own pressure-angle curve.
    plots : the data the job's report section draws (:class:`camgen.report.model.SectionData`;
        None unless the ``plots`` stage ran).
    """

    report: dict[str, Any]
    files: dict[str, str] = field(default_factory=dict)
    checks: "dict[str, list[CheckResult]]" = field(default_factory=dict)
    curves: dict[str, tuple[np.ndarray, np.ndarray, str]] = field(default_factory=dict)
    plots: "SectionData | None" = None


@dataclass(frozen=True)
class MechanismJob:
    """A registered mechanism: ``[mechanisms.<name>]`` keys, ``read(where, parsed, cam_specs)``
    -> its typed spec, ``run(spec, built_cams, stages, scene_name)`` -> :class:`JobResult`, and
    the ``"module:function"`` drawing its report section (called with the page's figure maker and
    the job's :class:`camgen.report.model.MechanismReport`, whose ``section`` is
    :attr:`JobResult.plots`)."""

    name: str
    summary: str
    keys: tuple[Key, ...]
    read: Callable[..., Any]
    run: Callable[..., JobResult]
    report_section: str = ""
