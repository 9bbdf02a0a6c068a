"""Planning a run, once, for `camgen run` and `camgen check` alike: which outputs, which stages,
and every refusal that does not need the cams built (the follower table's speed, file names that
collide), then the size caps of the files that flatten a profile (checked per cam once it is
built, before anything is rendered).  The specs it plans from are final: the scene reader
validated them, the G-code's settings against the chord tolerance included (:mod:`camgen.scene`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

from camgen.errors import ParameterError

if TYPE_CHECKING:
    from camgen.outputs import OutputSpec
    from camgen.body import BodySpec
    from camgen.contour import Contour
    from camgen.kinds.base import Pocket
    from camgen.scene import Scene

__all__ = ["MAX_FLAT_POINTS", "Plan", "REPORT_FIGURES_STAGE", "check_flat_size", "claim_file", "plan_run"]

#: The build stage of the report's figures of a cam's shape (a disk cam's area, perimeter and bounds):
#: in :attr:`Plan.build_stages` when :attr:`Plan.report_figures` (a sweep's design evaluation leaves it out).
REPORT_FIGURES_STAGE = "report_figures"


@dataclass(frozen=True)
class Plan:
    """What a run writes and which stages it runs.

    ``formats``: the outputs written (registered names); ``stages``: the stages run besides
    synthesis and checks; ``full_report``: report.json carries the analysis figures (every run
    but one restricted by ``--only`` without ``json``); ``report_figures``: the report's figures
    beyond the checks and the main figures (the law's acceleration harmonics) are computed: every
    planned run; False in the evaluation of one design by a sweep (:mod:`camgen.evaluation`).
    A build is given :attr:`build_stages`: ``stages`` and, with ``report_figures``, the stage
    :data:`REPORT_FIGURES_STAGE` (a disk cam's ``area_mm2``, ``perimeter_mm``, ``bounds_mm``).
    """

    formats: tuple[str, ...]
    stages: frozenset[str]
    full_report: bool = True
    report_figures: bool = True

    @property
    def build_stages(self) -> frozenset[str]:
        """The stages a cam's build is given: :attr:`stages`, with :data:`REPORT_FIGURES_STAGE`
        when the plan computes the report's figures."""
        return self.stages | {REPORT_FIGURES_STAGE} if self.report_figures else self.stages


def _refuse_formats_of_forms(scene: "Scene", formats: Sequence[str]) -> None:
    """A format a cam's form cannot have (:attr:`camgen.forms.base.CamForm.formats_refused`) is
    refused naming ``output.formats``, the format, the cam and why."""
    from camgen.forms import form_names, get_form

    known = set(form_names())
    for spec in scene.cams:
        refused = dict(get_form(spec.form).formats_refused) if spec.form in known else {}
        refused.update(getattr(spec.params, "formats_refused", {}))  # what this cam's own parameters cannot have yet
        for name in formats:
            if name in refused:
                raise ParameterError("output.formats", name, "any format but " + ", ".join(f'"{f}"' for f in refused),
                                     f"cams.{spec.name} is a {spec.form} cam: {refused[name]}")


def plan_run(scene: "Scene", only: Sequence[str] | None = None) -> Plan:
    """The outputs and stages of a run of ``scene``; ``only`` restricts the outputs to those
    formats (whether or not the scene lists them; report.json is always written)."""
    from camgen.outputs import ALWAYS, MACHINING_FORMATS, OUTPUTS

    if only is None:
        wanted = list(scene.output.formats) + [f.name for f in OUTPUTS.values() if f.implied]
        full = True
    else:
        unknown = [f for f in only if f not in OUTPUTS]
        if unknown or not only:
            raise ParameterError("--only", ",".join(only), "a comma-separated list of formats from " + ", ".join(OUTPUTS))
        wanted = list(only) + list(ALWAYS)
        full = all(f in only for f in ALWAYS)  # the report carries the analysis figures when asked for by name
    formats = tuple(f for f in OUTPUTS if f in wanted)
    _refuse_formats_of_forms(scene, formats)
    for name in formats:
        why = OUTPUTS[name].needs_rpm
        for spec in scene.cams if why else ():
            if spec.checks.rpm is None:
                raise ParameterError(f"cams.{spec.name}.rpm", None, "a cam speed in rev/min (> 0)",
                                     f'the "{name}" output ({OUTPUTS[name].files.replace("{cam}", "<cam>")}) {why}')
    # the scene reader checked the machining settings for a run that writes G-code (the specs are final)
    assert scene.machined or not set(formats) & set(MACHINING_FORMATS), \
        "a run writing G-code needs a scene read with its --only formats (load_scene(only=...))"
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
        if not OUTPUTS[name].always or full:
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


#: Largest number of vertices of one flattened contour in the point list and the surface meshes
#: (STL, 3MF, OBJ, PLY): about 16 MB of coordinates in the point list.  The FEA meshes have caps
#: of their own on each file's bytes and the mesher's memory (:func:`camgen.export.fea.check_caps`);
#: the DXF writes arcs and splines exactly or as few biarcs; the G-code has its own cap on the
#: program's moves (:data:`camgen.export.gcode.MAX_PROGRAM_MOVES`).
MAX_FLAT_POINTS = 500_000


def _flat_count(contour: "Contour", body: "BodySpec", chord_tol: float, pockets: "Sequence[Pocket]" = ()) -> int:
    """Vertices of the flattened ``contour`` (and the bore circle of ``body``, and the walls of
    ``pockets``) at ``chord_tol`` mm."""
    count = sum(int(seg.flatten_params(chord_tol).size) for seg in contour.segments)
    if pockets:  # the walls are in the point list and the meshes too
        from camgen.export.pocket import wall_flat_count

        count += wall_flat_count(pockets, chord_tol)
    if body.bore_diameter > 0:  # the bore circle of the mesh
        r = body.bore_diameter / 2.0
        count += math.ceil(2.0 * math.pi / (2.0 * math.acos(max(-1.0, 1.0 - chord_tol / r))))
    return count


def check_flat_size(name: str, contour: "Contour", body: "BodySpec", formats: Sequence[str], output: "OutputSpec",
                    pockets: "Sequence[Pocket]" = ()) -> None:
    """Refuse a chord tolerance (``output.chord_tol``) that would flatten cam ``name`` into more than :data:`MAX_FLAT_POINTS`
    vertices in a planned point list or surface mesh, or a surface mesh file beyond 100 MB
    (:func:`camgen.export.solid.vertex_limit`; a 200 m cam at 1e-7 mm: 3 million vertices),
    naming ``output.chord_tol_mm`` and the smallest tolerance, as printed, that fits (the
    ``pockets``' walls counted with the outline); and FEA meshes beyond their caps (:func:`camgen.export.fea.check_caps`, which needs gmsh;
    the walls counted there too)."""
    from camgen.errors import ceil_significant
    from camgen.outputs import FEA_FORMATS, MAX_CHORD_TOL, MESH_FORMATS, OUTPUTS

    chord_tol = output.chord_tol
    flattened = tuple(f.name for f in OUTPUTS.values() if f.flattens)  # the whole profile, besides the surface meshes
    if any(f in FEA_FORMATS for f in formats):
        from camgen.export.fea import check_caps, require_gmsh

        require_gmsh(formats)
        check_caps(contour, body, formats, chord_tol, output.fea_element_size, output.fea_elements, name, MAX_CHORD_TOL, pockets)
    flat = [f for f in formats if f in flattened or f in MESH_FORMATS]
    if not flat:
        return
    limit, holder = MAX_FLAT_POINTS, "a file"
    surfaces = [f for f in flat if f not in flattened]
    if surfaces:  # each surface mesh file at most solid.MAX_FILE_BYTES (bytes per outline vertex)
        from camgen.export.solid import vertex_limit

        limit, holder = min([(limit, holder)] + [(vertex_limit(f), f"a {f} file") for f in surfaces])
    count = _flat_count(contour, body, chord_tol, pockets)
    if count <= limit:
        return
    # chords of arcs and splines: the vertex count grows as chord_tol^-1/2 (at least one per piece)
    need = ceil_significant(min(MAX_CHORD_TOL, chord_tol * (count / limit) ** 2), 2)
    while need < MAX_CHORD_TOL and _flat_count(contour, body, need, pockets) > limit:
        need = ceil_significant(min(MAX_CHORD_TOL, need * 1.05), 2)
    why = f"at {chord_tol:g} mm its flattened profile would have {count} vertices, more than the {limit} {holder} may hold"
    if _flat_count(contour, body, need, pockets) > limit:
        raise ParameterError("output.formats", list(formats), f"formats without the point list and surface meshes for cam '{name}'",
                             why + f", and still more at the largest chord_tol_mm ({MAX_CHORD_TOL:g} mm)")
    raise ParameterError("output.chord_tol_mm", chord_tol, f">= {need:.2g} mm for cam '{name}'", why)
