"""The planned pipeline: scene -> synthesis -> checks -> mechanism jobs -> stages -> files.

:func:`plan_run` decides, from the requested outputs, which stages run (:mod:`camgen.outputs`);
:func:`execute` runs them and renders every file in memory; :func:`run_scene` then writes the
run atomically (:mod:`camgen.staging`).  Synthesis and the design checks always run: they decide
the exit status.  Everything else (ride simulations, fits, sweeps, meshes, plot data) runs only
when an output needs it, and its libraries are imported only then.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

from camgen.errors import GeometryError, ParameterError

if TYPE_CHECKING:
    from camgen.checks import CheckResult
    from camgen.jobs.base import JobResult
    from camgen.kinds.base import BuiltCam, CamSpec
    from camgen.outputs import OutputSpec
    from camgen.scene import Scene
    from camgen.writers import RunSettings

#: Called with a short description before each step of a run (progress display).
Progress = Callable[[str], None]


def _quiet(step: str) -> None:
    return None


@dataclass(frozen=True)
class Plan:
    """What a run writes and which stages it runs.

    ``formats``: the outputs written (registered names); ``stages``: the stages run besides
    synthesis and checks; ``full_report``: report.json carries the analysis figures (every run
    but one restricted by ``--only`` without ``json``).
    """

    formats: tuple[str, ...]
    stages: frozenset[str]
    full_report: bool = True


def plan_run(scene: "Scene", only: Sequence[str] | None = None) -> Plan:
    """The outputs and stages of a run of ``scene``; ``only`` restricts the outputs to those
    formats (whether or not the scene lists them; report.json is always written)."""
    from camgen.outputs import OUTPUTS

    if only is None:
        wanted = list(scene.output.formats) + [f.name for f in OUTPUTS.values() if f.implied]
        full = True
    else:
        unknown = [f for f in only if f not in OUTPUTS]
        if unknown or not only:
            raise ParameterError("--only", ",".join(only), "a comma-separated list of formats from " + ", ".join(OUTPUTS))
        wanted = list(only) + ["json"]
        full = "json" in only
    formats = tuple(f for f in OUTPUTS if f in wanted)
    if "follower" in formats:  # the follower table is the motion at the cam's speed
        for spec in scene.cams:
            if spec.checks.rpm is None:
                raise ParameterError(f"cams.{spec.name}.rpm", None, "a cam speed in rev/min (> 0)",
                                     'the "follower" output (<cam>_follower.csv) tabulates the follower motion at the cam speed')
    if "ngc" in formats:
        _check_machining(scene)
    planned: dict[str, str] = {}
    for name in formats:
        output = OUTPUTS[name]
        if output.scope == "cam":
            for spec in scene.cams:
                claim_file(planned, output.files.format(cam=spec.name), f"cams.{spec.name} ({name})")
        elif output.scope == "run":
            claim_file(planned, output.files, f"the run ({name})")
    stages: set[str] = set()
    for name in formats:
        if name != "json" or full:
            stages |= OUTPUTS[name].stages
    return Plan(formats, frozenset(stages), full)


def claim_file(files: "dict[str, str]", name: str, owner: str) -> None:
    """Record that ``owner`` (a scene key and format) writes the file ``name``; refuse a name
    another output of the run writes already, or one that differs from it only in letter case
    (one file on the case-insensitive file systems of macOS and Windows).

    Raises
    ------
    SceneError
        Naming both outputs and the file.
    """
    from camgen.errors import SceneError

    key = name.casefold()
    for other_name, other in files.items():
        if other_name.casefold() == key:
            same = "the same file" if other_name == name else f"one file on case-insensitive file systems ('{other_name}')"
            raise SceneError(f"{other} and {owner} would both write '{name}' ({same}): rename one of the cams "
                             "(each output of a run needs a file of its own)")
    files[name] = owner


def _check_machining(scene: "Scene") -> None:
    """The G-code settings against the run's chord tolerance, before any cam is built: the
    printed decimals must resolve a share of ``output.chord_tol_mm``
    (:class:`camgen.export.gcode.MachiningSpec`); the error names the key to change."""
    from camgen.outputs import machining_keys

    tol = scene.output.chord_tol
    try:
        dataclasses.replace(scene.machining, chord_tol=tol)
    except ParameterError as exc:
        try:
            dataclasses.replace(scene.machining, chord_tol=tol, decimals=6)
        except ParameterError:  # not even 6 decimals resolve this tolerance
            from camgen.export.gcode import ROUNDING_SHARE, rounding_error

            raise ParameterError("output.chord_tol_mm", tol, f'>= {rounding_error(6) / ROUNDING_SHARE:.2g} mm with "ngc" in '
                                 "output.formats and machining.decimals = 6 (G-code is printed with at most 6 decimals)", exc.why) from None
        key = {k.field: k.name for k in machining_keys()}.get(exc.name, exc.name)
        raise ParameterError(f"machining.{key}", exc.value, exc.valid, exc.why) from None
    step = scene.machining.step_down
    for spec in scene.cams:
        depth = spec.body.thickness + scene.machining.breakthrough
        if _passes(depth, step) > MAX_PASSES:
            from camgen.errors import ceil_significant

            least = ceil_significant(depth / MAX_PASSES, 3)
            while _passes(depth, least) > MAX_PASSES:  # the quoted least is tried: depth / least may round above
                least = float(f"{least + 10.0 ** (math.floor(math.log10(least)) - 2):.3g}")  # one unit of the 3rd digit up
            passes = _passes(depth, step)
            raise ParameterError("machining.step_down_mm", step, f">= {least:.3g} mm for cam '{spec.name}'",
                                 f"its {depth:g} mm (thickness + breakthrough) would take "
                                 f"{passes if passes < 1e9 else 'more than 10^9'} passes, more than "
                                 f"the {MAX_PASSES} a program may hold")


def _passes(depth: float, step: float) -> float:
    """Depth passes of a G-code program, as :func:`camgen.export.gcode.gcode_program` counts them
    (inf for a step so small that the count overflows)."""
    ratio = depth / step
    return max(1, math.ceil(ratio - 1e-9)) if math.isfinite(ratio) else math.inf


#: Most depth passes of a G-code program (thickness + breakthrough over step_down_mm).
MAX_PASSES = 1000


#: Largest number of vertices of one flattened contour in the point list and the surface meshes
#: (STL, 3MF, OBJ, PLY): about 16 MB of coordinates in the point list.  The FEA meshes have caps
#: of their own on each file's bytes and the mesher's memory (:func:`camgen.export.fea.check_caps`);
#: the DXF writes arcs and splines exactly or as few biarcs; the G-code has its own cap on the
#: program's moves (:data:`camgen.export.gcode.MAX_PROGRAM_MOVES`).
MAX_FLAT_POINTS = 500_000
#: Formats that flatten the whole profile (besides the surface meshes).
_FLAT_ALL = ("points",)
def _flat_count(cam: "BuiltCam", chord_tol: float) -> int:
    """Vertices of ``cam``'s flattened profile (and bore circle) at ``chord_tol`` mm."""
    count = sum(int(seg.flatten_params(chord_tol).size) for seg in cam.contour.segments)
    if cam.body.bore_diameter > 0:  # the bore circle of the mesh
        r = cam.body.bore_diameter / 2.0
        count += math.ceil(2.0 * math.pi / (2.0 * math.acos(max(-1.0, 1.0 - chord_tol / r))))
    return count


def _check_flat_size(cam: "BuiltCam", formats: Sequence[str], chord_tol: float, output: "OutputSpec | None" = None) -> None:
    """Refuse a chord tolerance that would flatten ``cam`` into more than :data:`MAX_FLAT_POINTS`
    vertices in a planned point list or surface mesh, or a surface mesh file beyond 100 MB
    (:func:`camgen.export.solid.vertex_limit`; a 200 m cam at 1e-7 mm: 3 million vertices),
    naming ``output.chord_tol_mm`` and the smallest tolerance, as printed, that fits; and FEA
    meshes beyond their caps (:func:`camgen.export.fea.check_caps`, which needs gmsh)."""
    from camgen.errors import ceil_significant
    from camgen.outputs import FEA_FORMATS, MAX_CHORD_TOL, MESH_FORMATS

    if cam.contour is None:
        return
    if output is not None and any(f in FEA_FORMATS for f in formats):
        from camgen.export.fea import check_caps, require_gmsh

        require_gmsh(formats)
        check_caps(cam.contour, cam.body, formats, chord_tol, output.fea_element_size, output.fea_elements, cam.name, MAX_CHORD_TOL)
    flat = [f for f in formats if f in _FLAT_ALL or (f in MESH_FORMATS and f not in FEA_FORMATS)]
    if not flat:
        return
    limit, holder = MAX_FLAT_POINTS, "a file"
    surfaces = [f for f in flat if f not in _FLAT_ALL]
    if surfaces:  # each surface mesh file at most solid.MAX_FILE_BYTES (bytes per outline vertex)
        from camgen.export.solid import vertex_limit

        limit, holder = min([(limit, holder)] + [(vertex_limit(f), f"a {f} file") for f in surfaces])
    count = _flat_count(cam, chord_tol)
    if count <= limit:
        return
    # chords of arcs and splines: the vertex count grows as chord_tol^-1/2 (at least one per piece)
    need = ceil_significant(min(MAX_CHORD_TOL, chord_tol * (count / limit) ** 2), 2)
    while need < MAX_CHORD_TOL and _flat_count(cam, need) > limit:
        need = ceil_significant(min(MAX_CHORD_TOL, need * 1.05), 2)
    why = f"at {chord_tol:g} mm its flattened profile would have {count} vertices, more than the {limit} {holder} may hold"
    if _flat_count(cam, need) > limit:
        raise ParameterError("output.formats", list(formats), f"formats without the point list and surface meshes for cam '{cam.name}'",
                             why + f", and still more at the largest chord_tol_mm ({MAX_CHORD_TOL:g} mm)")
    raise ParameterError("output.chord_tol_mm", chord_tol, f">= {need:.2g} mm for cam '{cam.name}'", why)


@dataclass
class RunResult:
    """Everything a run computed: the cams, the mechanism jobs' results, the files (name ->
    content, report.json included) and the plan."""

    scene: "Scene"
    plan: Plan
    cams: "list[BuiltCam]"
    jobs: "dict[str, JobResult]" = field(default_factory=dict)
    files: dict[str, str | bytes] = field(default_factory=dict)

    def failed_checks(self) -> "list[tuple[str, CheckResult]]":
        """(cam name, check) of every check that failed (information is never a failure)."""
        return [(cam.name, check) for cam in self.cams for check in cam.checks if check.failed]

    def settings(self) -> "RunSettings":
        from camgen.writers import RunSettings

        return RunSettings(self.scene.name, self.scene.output, self.scene.machining)


def check_cam(cam: "BuiltCam", spec: "CamSpec", tool_radius: float, tool_is_limit: bool) -> None:
    """The design checks of one cam (:func:`camgen.checks.evaluate_cam`) and its wall check.

    A cam whose profile could not be made (``cam.contour`` None: an undercut) gets the checks
    of its pitch curve, or its undercut as a failed check with the curvature curve to plot.
    """
    from camgen.checks import CheckResult, evaluate_cam
    from camgen.kinds import get_kind

    follower = cam.follower
    own = get_kind(spec.kind).evaluate
    if own is not None:  # the kind's own (closed-form) checks
        cam.evaluation = own(cam, spec, tool_radius, tool_is_limit)
    else:
        pitch = cam.pitch if follower.kind == "roller" else None
        cam.evaluation = evaluate_cam(cam.contour, follower, tool_radius, spec.checks.rpm, cam.breadth, pitch, tool_is_limit)
    if cam.contour is None and cam.undercut is not None and not any(c.name == "undercut" and c.failed for c in cam.evaluation.checks):
        exc = cam.undercut  # the synthesis found the undercut: a failed check, with its curvature curve when it has one
        value = float(exc.curve[1].min()) if exc.curve is not None else "undercut"
        cam.evaluation.checks = [c for c in cam.evaluation.checks if c.name != "undercut"]
        cam.evaluation.checks.insert(0, CheckResult("undercut", value, exc.limit, ">", "mm", False, exc.where_deg,
                                                    " ".join(str(exc).split()), blocks_manufacture=True))
        if exc.curve is not None:
            cam.evaluation.curvature_radius = exc.curve
            cam.evaluation.curvature_label = "radius of curvature of the envelope (mm)"
            cam.evaluation.curvature_limit = exc.limit
    cam.checks.extend(cam.evaluation.checks)
    cam.rpm = spec.checks.rpm
    if own is None:  # a kind with its own checks reports its follower itself
        cam.figures["follower"] = {"kind": follower.kind, "motion": follower.motion, "roller_radius_mm": follower.roller_radius,
                                   "offset_mm": follower.offset, "pressure_angle_limit_deg": math.degrees(follower.limit)}
    if spec.checks.rpm and cam.evaluation.motion is not None:
        cam.figures["motion_at_rpm"] = {"rpm": spec.checks.rpm, **cam.evaluation.motion.at_rpm(spec.checks.rpm)}
    if cam.body.bore_diameter > 0 and cam.contour is not None:
        cam.checks.append(_wall_check(cam))


def _wall_check(cam: "BuiltCam") -> "CheckResult":
    """Wall left between bore/keyway and profile against ``min_wall`` (blocks manufacture)."""
    from camgen.body import wall_left
    from camgen.checks import limited

    wall, where = wall_left(cam.contour, cam.body)
    what = "the bore/keyway breaks through the profile" if wall <= 0 else f"thinnest wall between the bore/keyway and the profile, {wall:.3f} mm"
    note = what if wall >= cam.body.min_wall else what + ": use a smaller bore or keyway, or a smaller min_wall_mm"
    return limited("wall_thickness", wall, ">=", cam.body.min_wall, "mm", [round(where, 6)], note, blocks_manufacture=True)


def _export_failure(cam: "BuiltCam", what: str, exc: Exception, blocks_manufacture: bool = True) -> "CheckResult":
    """An output that cannot be made (a tool path that would gouge, a solid that cannot be built)
    as a failed check; one of a manufacturing output withholds the cam's manufacturing files."""
    from camgen.checks import CheckResult

    return CheckResult(f"{what}_export", "failed", "made as designed", "", "", False, [], " ".join(str(exc).split()),
                       blocks_manufacture=blocks_manufacture)


def _merge_job(cams: "dict[str, BuiltCam]", result: "JobResult") -> None:
    """A mechanism's checks replace the cams' checks of the same name; its curves replace the
    pressure-angle curves report.html draws."""
    for name, checks in result.checks.items():
        replaced = {c.name for c in checks}
        cams[name].checks[:] = [c for c in cams[name].checks if c.name not in replaced] + list(checks)
    for name, (theta, angle, label) in result.curves.items():
        evaluation = cams[name].evaluation
        if evaluation is not None:
            evaluation.pressure_angle = (theta, angle)
            evaluation.pressure_angle_label = label


def compute(scene: "Scene", plan: Plan, progress: Progress = _quiet) -> RunResult:
    """Synthesis, design checks, mechanism jobs and the planned stages of ``scene`` (no files)."""
    from camgen.jobs import get_job
    from camgen.kinds import get_kind
    from camgen.kinds.base import with_cam

    tool_radius = scene.machining.tool_radius
    # the tool is a limit where the scene names it or machines the cam
    tool_is_limit = scene.machining_given or "ngc" in scene.output.formats or "ngc" in plan.formats
    cams: list[BuiltCam] = []
    for spec in scene.cams:
        if tool_is_limit:  # a kind that sizes its cam holds the concave radii to the named tool
            spec = dataclasses.replace(spec, checks=dataclasses.replace(spec.checks, tool_radius=tool_radius))
        progress(f"building cam '{spec.name}' ({spec.kind})")
        cam = get_kind(spec.kind).build(spec, plan.stages)
        progress(f"checking cam '{spec.name}'")
        with_cam(f"cams.{spec.name}", lambda: check_cam(cam, spec, tool_radius, tool_is_limit))
        if spec.dynamics is not None:  # forces, jump, torque, contact stress: checks like the geometric ones
            from camgen.kinds.dynamics import run_dynamics

            progress(f"dynamics of cam '{spec.name}'")
            with_cam(f"cams.{spec.name}", lambda: run_dynamics(cam, spec, plan.stages))
        cams.append(cam)
    for cam in cams:
        if cam.manufacturable:
            _check_flat_size(cam, plan.formats, scene.output.chord_tol, scene.output)
    by_name = {c.name: c for c in cams}
    result = RunResult(scene, plan, cams)
    for mech in scene.mechanisms:
        progress(f"mechanism '{mech.name}'")
        job = get_job(mech.name)
        result.jobs[mech.name] = job.run(mech.settings, by_name, plan.stages, scene.name)
        _merge_job(by_name, result.jobs[mech.name])
    if "mesh" in plan.stages:
        from camgen.export.solid import cam_solid

        for cam in cams:
            if not cam.manufacturable:
                continue
            progress(f"meshing cam '{cam.name}'")
            try:
                cam.solid = cam_solid(cam.contour, cam.body, scene.output.chord_tol, cam.name)
            except GeometryError as exc:
                cam.checks.append(_export_failure(cam, "solid", exc))
                continue
            cam.figures["solid_volume_mm3"] = cam.solid.volume
            cam.figures["solid_triangles"] = int(len(cam.solid.triangles))
            if cam.solid.snapped > 0.0:  # manifold3d's vertices kept (export/solid.py, unsnap): say how far off
                cam.figures["solid_vertex_snap_mm"] = cam.solid.snapped
    return result


def execute(scene: "Scene", plan: Plan, progress: Progress = _quiet) -> RunResult:
    """Run the planned stages of ``scene`` and render every file in memory (nothing written)."""
    result = compute(scene, plan, progress)
    render(result, progress)
    return result


def render(result: RunResult, progress: Progress = _quiet) -> None:
    """Every planned file of ``result`` into ``result.files``: per-cam writers, the kinds' and
    jobs' files, report.json and report.html."""
    import importlib

    from camgen.outputs import OUTPUTS
    from camgen.report import report_dict, report_json
    from camgen.report_data import report_input

    settings = result.settings()
    files = result.files
    owners: dict[str, str] = {}

    def add(new: "dict[str, str | bytes]", owner: str) -> None:
        for path in new:
            claim_file(owners, path, owner)
        files.update(new)

    for cam in result.cams:
        planned = {name: OUTPUTS[name].files.format(cam=cam.name) for name in result.plan.formats if OUTPUTS[name].scope == "cam"}
        made = {name: path for name, path in planned.items() if cam.manufacturable or not OUTPUTS[name].manufacturing}
        cam.withheld = [path for name, path in planned.items() if name not in made]
        cam_files: dict[str, str | bytes] = {}
        blocked = False  # a manufacturing output failed: no manufacturing file of this cam, the others still written
        for name, path in made.items():
            if blocked and OUTPUTS[name].manufacturing:
                continue
            progress(f"writing {path}")
            module, function = OUTPUTS[name].writer.split(":")
            try:
                cam_files[path] = getattr(importlib.import_module(module), function)(cam, settings, name)
            except GeometryError as exc:  # the cam cannot be made this way: a failed check
                manufacturing = OUTPUTS[name].manufacturing
                cam.checks.append(_export_failure(cam, name, exc, blocks_manufacture=manufacturing))
                if manufacturing:
                    blocked = True
                    cam.withheld = [p for n, p in planned.items() if OUTPUTS[n].manufacturing or p in cam.withheld]
                    cam_files = {p: data for p, data in cam_files.items() if p not in cam.withheld}
                else:
                    cam.withheld.append(path)
        add(cam_files, f"cams.{cam.name}")
        if "ride" in result.plan.formats:
            add(cam.files, f"cams.{cam.name}")
    if "legs" in result.plan.formats:
        for name, job in result.jobs.items():
            add(job.files, f"mechanisms.{name}")
    html = "html" in result.plan.formats
    _check_finite(files)
    for name in ("report.json",) + (("report.html",) if html else ()):
        claim_file(owners, name, "the run's report")
    names = sorted(files) + ["report.json"] + (["report.html"] if html else [])
    report = report_input(result.scene, result.cams, result.jobs, result.plan.stages, names, drawn=html)
    files["report.json"] = report_json(report_dict(report))
    if html:
        progress("writing report.html")
        module, function = OUTPUTS["html"].writer.split(":")
        files["report.html"] = getattr(importlib.import_module(module), function)(report)


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
