"""What a run computed, as frozen values: one :class:`CamResult` per cam composed of its stages'
results, and the :class:`RunResult` of the run.

Each stage hands the next a value and never writes into an earlier one (``dataclasses.replace``
makes the next value): synthesis gives the kind's :class:`~camgen.kinds.base.BuiltCam`, the
checks a :class:`~camgen.checks.CamEvaluation`, the dynamics a
:class:`~camgen.kinds.dynamics.DynamicsStage`, a mechanism job the checks and curves it decides
(:class:`JobOverlay`), meshing a :class:`~camgen.export.solid.CamSolid` (or the failure that
stopped it) and the FEA mesh, rendering the :class:`MadeFiles`.  :class:`CamResult` reads them
together: its ``checks``, ``figures``, ``withheld`` and ``manufacturable`` are what the report,
the command line and the exit status see.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.checks import CamEvaluation, CheckResult, Follower
    from camgen.contour import Contour
    from camgen.export.fea import VolumeMesh
    from camgen.export.solid import CamSolid
    from camgen.jobs.base import JobResult
    from camgen.kinds.base import BuiltCam, CamSpec, Pocket, ZeroMark
    from camgen.kinds.dynamics import DynamicsOutcome, DynamicsStage
    from camgen.planning import Plan
    from camgen.scene import Scene

__all__ = ["CamResult", "JobOverlay", "MadeFiles", "RunResult", "frozen_mapping"]


def frozen_mapping(values: Mapping[str, Any] | None = None) -> Mapping[str, Any]:
    """A read-only view of a copy of ``values`` (a stage's figures or files: never written later)."""
    return MappingProxyType(dict(values or {}))


@dataclass(frozen=True)
class JobOverlay:
    """The checks a mechanism job decides for one cam: they replace the cam's own of the same
    name (the pressure angle in the mechanism instead of on a bare face)."""

    checks: "tuple[CheckResult, ...]" = ()


@dataclass(frozen=True)
class MadeFiles:
    """The files rendered for one cam: ``files`` (name -> content), the manufacturing files
    ``withheld`` (not written: the cam cannot be made as designed) and the ``failures`` of
    outputs that could not be made (failed ``<format>_export`` checks)."""

    files: Mapping[str, str | bytes] = field(default_factory=frozen_mapping)
    withheld: tuple[str, ...] = ()
    failures: "tuple[CheckResult, ...]" = ()


@dataclass(frozen=True)
class CamResult:
    """One cam through every stage that ran.

    ``spec`` the cam as the scene gave it (final: tool radius included); ``built`` its synthesis
    (a kind's subclass of :class:`~camgen.kinds.base.BuiltCam`: ``built.law``, ``built.tricycle``
    ...); ``evaluation`` its design checks and the curves they drew; ``dynamics_stage`` the
    follower train at speed; ``overlay`` what a mechanism job decided; ``solid`` and ``fea`` the
    surface and FEA meshes, ``mesh_failures`` the meshing that failed (failed checks); ``made``
    the rendered files.
    """

    spec: "CamSpec"
    built: "BuiltCam"
    evaluation: "CamEvaluation | None" = None
    dynamics_stage: "DynamicsStage | None" = None
    overlay: JobOverlay = JobOverlay()
    solid: "CamSolid | None" = None
    fea: "VolumeMesh | None" = None
    mesh_failures: "tuple[CheckResult, ...]" = ()
    made: MadeFiles | None = None

    # what the synthesis made, read through
    @property
    def name(self) -> str:
        return self.built.name

    @property
    def kind(self) -> str:
        return self.built.kind

    @property
    def contour(self) -> "Contour | None":
        return self.built.contour

    @property
    def body(self) -> "BodySpec":
        return self.built.body

    @property
    def follower(self) -> "Follower | None":
        return self.built.follower

    @property
    def pitch(self) -> "Contour | None":
        return self.built.pitch

    @property
    def pockets(self) -> "tuple[Pocket, ...]":
        """Regions cut into the body's top face (a groove cam's groove); () for a prismatic body."""
        return self.built.pockets

    @property
    def breadth(self) -> float | None:
        return self.built.breadth

    @property
    def zero_mark(self) -> "ZeroMark | None":
        return self.built.zero_mark

    @property
    def files(self) -> Mapping[str, str]:
        """The kind's own files (a trajectory cam's ride table)."""
        return self.built.files

    @property
    def rpm(self) -> float | None:
        return self.spec.checks.rpm

    # the stages together
    @property
    def checks(self) -> "tuple[CheckResult, ...]":
        """Every check in report order: the design checks (a job's replace those of the same
        name), the dynamics', a failed meshing and failed exports."""
        own: list[CheckResult] = list(self.evaluation.checks) if self.evaluation is not None else []
        if self.dynamics_stage is not None:
            own += self.dynamics_stage.checks
        replaced = {c.name for c in self.overlay.checks}
        out = [c for c in own if c.name not in replaced] + list(self.overlay.checks)
        out += self.mesh_failures
        if self.made is not None:
            out += self.made.failures
        return tuple(out)

    @property
    def figures(self) -> Mapping[str, Any]:
        """report.json's figures of the cam: the synthesis', the checks', the dynamics', the meshes'."""
        out = dict(self.built.figures)
        if self.evaluation is not None:
            out.update(self.evaluation.figures)
        if self.dynamics_stage is not None and self.dynamics_stage.figures:
            out["dynamics"] = dict(self.dynamics_stage.figures)
        if self.solid is not None:
            out["solid_volume_mm3"] = self.solid.volume
            out["solid_triangles"] = int(len(self.solid.triangles))
            if self.solid.snapped > 0.0:  # manifold3d's vertices kept (export/solid.py, unsnap): say how far off
                out["solid_vertex_snap_mm"] = self.solid.snapped
        if self.fea is not None:
            out["fea_mesh"] = dict(self.fea.figures)
        return MappingProxyType(out)

    @property
    def dynamics(self) -> "DynamicsOutcome | None":
        """The forces, torque and stress at speed the report draws (None: no follower train)."""
        return self.dynamics_stage.outcome if self.dynamics_stage is not None else None

    @property
    def withheld(self) -> tuple[str, ...]:
        return self.made.withheld if self.made is not None else ()

    @property
    def undercut(self) -> Any:
        return self.built.undercut

    @property
    def manufacturable(self) -> bool:
        """False when the profile could not be made (a plate without its contour) or a check that
        blocks manufacture failed."""
        made = self.contour is not None or not self.built.planar  # a body that is no plate has no contour to lack
        return made and not any(c.failed and c.blocks_manufacture for c in self.checks)

    def with_(self, **changes: Any) -> "CamResult":
        """This result with the next stage's values (``dataclasses.replace``)."""
        return dataclasses.replace(self, **changes)


@dataclass(frozen=True)
class RunResult:
    """Everything a run computed: the scene, the plan, the cams, the mechanism jobs' results and
    the files (name -> content, report.json included) once rendered."""

    scene: "Scene"
    plan: "Plan"
    cams: tuple[CamResult, ...]
    jobs: "Mapping[str, JobResult]" = field(default_factory=frozen_mapping)
    files: Mapping[str, str | bytes] = field(default_factory=frozen_mapping)

    def failed_checks(self) -> "list[tuple[str, CheckResult]]":
        """(cam name, check) of every check that failed (information is never a failure)."""
        return [(cam.name, check) for cam in self.cams for check in cam.checks if check.failed]
