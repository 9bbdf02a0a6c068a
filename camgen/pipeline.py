"""The planned pipeline: scene -> synthesis -> checks -> mechanism jobs -> stages -> files.

:func:`plan_run` decides, from the requested outputs, which stages run (:mod:`camgen.outputs`);
:func:`execute` runs them and renders every file in memory; :func:`run_scene` then writes the
run atomically (:mod:`camgen.staging`).  Synthesis and the design checks always run: they decide
the exit status.  Everything else (ride simulations, fits, sweeps, meshes, plot data) runs only
when an output needs it, and its libraries are imported only then.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping, Sequence

from camgen.errors import GeometryError
from camgen.outputs import CAM_STAGES
from camgen.planning import Plan, check_flat_size, claim_file, plan_run

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.forms.base import CamForm
    from camgen.jobs.base import JobResult
    from camgen.outputs import OutputSpec
    from camgen.results import CamResult, MadeFiles, RunResult
    from camgen.scene import Scene
    from camgen.writers import RunSettings

__all__ = ["Plan", "Progress", "compute", "execute", "fea_stage", "mesh_stage", "plan_run", "render", "run_scene"]

#: Called with a short description before each step of a run (progress display).
Progress = Callable[[str], None]


def _quiet(step: str) -> None:
    return None


def _export_failure(what: str, exc: Exception, blocks_manufacture: bool = True) -> "CheckResult":
    """An output that cannot be made (a tool path that would gouge, a solid that cannot be built)
    as a failed check; one of a manufacturing output withholds the cam's manufacturing files."""
    from camgen.checks import CheckResult

    return CheckResult(f"{what}_export", "failed", "made as designed", "", "", False, [], " ".join(str(exc).split()),
                       blocks_manufacture=blocks_manufacture)


def _overlay(cam: "CamResult", job: "JobResult") -> "CamResult":
    """``cam`` with what a mechanism job decided for it: checks replacing the cam's own of the same
    name, and the pressure-angle curve report.html draws instead of the cam's own."""
    from camgen.results import JobOverlay

    checks = tuple(job.checks.get(cam.name, ()))
    if checks:
        replaced = {c.name for c in checks}
        cam = cam.with_(overlay=JobOverlay(tuple(c for c in cam.overlay.checks if c.name not in replaced) + checks))
    curve = job.curves.get(cam.name)
    if curve is not None and cam.evaluation is not None:
        theta, angle, label = curve
        cam = cam.with_(evaluation=dataclasses.replace(cam.evaluation, pressure_angle=(theta, angle), pressure_angle_label=label))
    return cam


def compute(scene: "Scene", plan: Plan, progress: Progress = _quiet) -> "RunResult":
    """Synthesis, design checks, dynamics, mechanism jobs and the planned stages of ``scene``
    (no files): each stage's result a frozen value (:mod:`camgen.results`)."""
    from camgen.checking import evaluate
    from camgen.jobs import get_job
    from camgen.kinds import get_kind
    from camgen.kinds.base import with_cam
    from camgen.results import CamResult, RunResult, frozen_mapping

    tool_radius = scene.machining.tool_radius  # a limit where the cam's checks say so (the scene reader decided)
    cams: list[CamResult] = []
    for spec in scene.cams:
        where = f"cams.{spec.name}"
        progress(f"building cam '{spec.name}' ({spec.kind})")
        built = get_kind(spec.kind, spec.form).build(spec, plan.build_stages)
        progress(f"checking cam '{spec.name}'")
        cam = CamResult(spec, built, with_cam(where, lambda: evaluate(built, spec, tool_radius, spec.checks.tool_is_limit,
                                                                        plan.report_figures)))
        if spec.dynamics is not None:  # forces, jump, torque, contact stress: checks like the geometric ones
            from camgen.kinds.dynamics import run_dynamics

            progress(f"dynamics of cam '{spec.name}'")
            cam = cam.with_(dynamics_stage=with_cam(where, lambda: run_dynamics(built, spec, plan.stages, plan.report_figures)))
        cams.append(cam)
    for cam in cams:
        if cam.manufacturable and cam.contour is not None:
            check_flat_size(cam.name, cam.contour, cam.body, plan.formats, scene.output, cam.pockets)
    by_name = {c.name: c for c in cams}
    jobs = {}
    for mech in scene.mechanisms:
        progress(f"mechanism '{mech.name}'")
        job = get_job(mech.name).run(mech.settings, by_name, plan.stages, scene.name)
        jobs[mech.name] = job
        by_name = {name: _overlay(cam, job) for name, cam in by_name.items()}
    cams = list(by_name.values())
    for stage in CAM_STAGES:  # the per-cam stages the planned outputs need (camgen.outputs)
        if stage.name in plan.stages:  # a form may run a stage its own way (CamForm.stages)
            cams = [_load(_form_of(cam).stages.get(stage.name, stage.runner))(cam, scene.output, progress) if cam.manufacturable
                    else cam for cam in cams]
    return RunResult(scene, plan, tuple(cams), frozen_mapping(jobs))


def _form_of(cam: "CamResult") -> "CamForm":
    """The registered form of ``cam`` (its own writers and stage runners)."""
    from camgen.forms import get_form

    return get_form(cam.spec.form)


def _load(reference: str) -> Callable[..., Any]:
    """The function a registry names as ``"module:function"`` (its module imported now)."""
    import importlib

    module, function = reference.split(":")
    return getattr(importlib.import_module(module), function)


def mesh_stage(cam: "CamResult", output: "OutputSpec", progress: Progress) -> "CamResult":
    """``cam`` with its extruded solid at the chord tolerance (with its pockets cut), or the failure
    that stopped it (a failed check)."""
    from camgen.export.solid import cam_solid

    progress(f"meshing cam '{cam.name}'")
    assert cam.contour is not None
    try:
        if cam.pockets:  # the outline less bore and keyway, less each pocket from the top face down
            from camgen.export.pocket_solid import pocket_solid

            return cam.with_(solid=pocket_solid(cam.contour, cam.body, cam.pockets, output.chord_tol, cam.name))
        return cam.with_(solid=cam_solid(cam.contour, cam.body, output.chord_tol, cam.name))
    except GeometryError as exc:
        return cam.with_(mesh_failures=cam.mesh_failures + (_export_failure("solid", exc),))


def fea_stage(cam: "CamResult", output: "OutputSpec", progress: Progress) -> "CamResult":
    """``cam`` with its FEA volume mesh (gmsh), made once for every FEA format: the body with its
    pockets cut (:mod:`camgen.export.fea_pockets`), or the failure that stopped it."""
    from camgen.export.fea_pockets import body_volume_mesh

    assert cam.contour is not None
    progress(f"FEA mesh of cam '{cam.name}'")
    try:
        return cam.with_(fea=body_volume_mesh(cam.contour, cam.body, output.chord_tol, output.fea_element_size, output.fea_elements,
                                              cam.pockets, cam.name))
    except GeometryError as exc:
        return cam.with_(mesh_failures=cam.mesh_failures + (_export_failure("fea", exc),))


def execute(scene: "Scene", plan: Plan, progress: Progress = _quiet) -> "RunResult":
    """Run the planned stages of ``scene`` and render every file in memory (nothing written)."""
    return render(compute(scene, plan, progress), progress)


def _made(cam: "CamResult", plan: Plan, settings: "RunSettings", progress: Progress) -> "MadeFiles":
    """The files of one cam's planned per-cam outputs: a manufacturing output that fails withholds
    every manufacturing file of the cam (a failed check says why); the others are still written."""
    from camgen.outputs import OUTPUTS
    from camgen.results import MadeFiles, frozen_mapping

    planned = {name: OUTPUTS[name].files.format(cam=cam.name) for name in plan.formats if OUTPUTS[name].scope == "cam"}
    made = {name: path for name, path in planned.items() if cam.manufacturable or not OUTPUTS[name].manufacturing}
    withheld = [path for name, path in planned.items() if name not in made]
    files: dict[str, str | bytes] = {}
    failures: list[CheckResult] = []
    blocked = False  # a manufacturing output failed: no manufacturing file of this cam, the others still written
    for name, path in made.items():
        output = OUTPUTS[name]
        if blocked and output.manufacturing:
            continue
        progress(f"writing {path}")
        writer = _form_of(cam).writers.get(name, output.writer)  # a form may write a format its own way (CamForm.writers)
        assert writer is not None, f"per-cam format {name!r} has no writer"
        try:
            files[path] = _load(writer)(cam, settings, name)
        except GeometryError as exc:  # the cam cannot be made this way: a failed check
            failures.append(_export_failure(name, exc, blocks_manufacture=output.manufacturing))
            if output.manufacturing:
                blocked = True
                withheld = [p for n, p in planned.items() if OUTPUTS[n].manufacturing or p in withheld]
                files = {p: data for p, data in files.items() if p not in withheld}
            else:
                withheld.append(path)
    return MadeFiles(frozen_mapping(files), tuple(withheld), tuple(failures))


def render(result: "RunResult", progress: Progress = _quiet) -> "RunResult":
    """``result`` with every planned file rendered in memory: per-cam writers, the kinds' and
    jobs' files, then the run's files (report.json, report.html) from the report input."""
    from camgen.outputs import OUTPUTS
    from camgen.report_data import report_input
    from camgen.results import frozen_mapping
    from camgen.writers import RunSettings

    settings = RunSettings(result.scene.name, result.scene.output, result.scene.machining)
    files: dict[str, str | bytes] = {}
    owners: dict[str, str] = {}

    def add(new: "Mapping[str, str | bytes]", owner: str) -> None:
        for path in new:
            claim_file(owners, path, owner)
        files.update(new)

    planned = [OUTPUTS[name] for name in result.plan.formats]
    cams = []
    for cam in result.cams:
        cam = cam.with_(made=_made(cam, result.plan, settings, progress))
        assert cam.made is not None
        add(cam.made.files, f"cams.{cam.name}")
        if any(f.scope == "kind" for f in planned):  # the files a kind's stages made (ride tables)
            add(cam.files, f"cams.{cam.name}")
        cams.append(cam)
    if any(f.scope == "job" for f in planned):  # the files the mechanism jobs made (leg paths)
        for name, job in result.jobs.items():
            add(job.files, f"mechanisms.{name}")
    _check_finite(files)
    run_files = sorted((f for f in planned if f.scope == "run"), key=lambda f: not f.always)  # the report first: it lists the others
    for output in run_files:
        claim_file(owners, output.files, "the run's report")
    names = sorted(files) + [f.files for f in run_files]
    result = dataclasses.replace(result, cams=tuple(cams))
    report = report_input(result.scene, result.cams, result.jobs, result.plan.stages, names, drawn="plots" in result.plan.stages)
    for output in run_files:
        assert output.writer is not None, f"run format {output.name!r} has no writer"
        if not output.always:  # the report is the run's last step, not a file of its own to wait for
            progress(f"writing {output.files}")
        files[output.files] = _load(output.writer)(report)
    return dataclasses.replace(result, files=frozen_mapping(files))


def _check_finite(files: dict[str, str | bytes]) -> None:
    """The last guard before anything is written: no text file may hold NaN or inf where a number
    stands (a machine or CAD reader would take it for a coordinate, or fail on it); names that
    hold the letters are not numbers (:mod:`camgen.nonfinite`).  Raises :class:`ExportError`
    naming the file and the line."""
    from camgen.nonfinite import check_files

    check_files(files)


def run_scene(scene: "Scene", outdir: str | Path = "outputs", only: Sequence[str] | None = None,
              progress: Progress = _quiet) -> RunResult:
    """Run ``scene`` and write its files into ``outdir/<scene name>/`` as one atomic swap (an
    output folder that cannot take the run is refused before anything is computed)."""
    from camgen.staging import preflight, write_run

    target = Path(outdir) / scene.name
    plan = plan_run(scene, only)
    preflight(target)
    result = execute(scene, plan, progress)
    progress("writing files")
    write_run(target, result.files)
    return result
