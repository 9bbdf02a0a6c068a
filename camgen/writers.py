"""Writers of the registered outputs (:mod:`camgen.outputs`): the built cam and the run's typed
settings in, the file content out.  Each imports its export module when called."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from camgen.errors import ParameterError

if TYPE_CHECKING:
    from camgen.contour import Contour
    from camgen.export.gcode import MachiningSpec
    from camgen.outputs import OutputSpec
    from camgen.report.model import ReportInput
    from camgen.results import CamResult


@dataclass(frozen=True)
class RunSettings:
    """The run-wide settings the writers take: scene name, output and machining specs."""

    scene_name: str
    output: "OutputSpec"
    machining: "MachiningSpec"


#: Half-length (mm) of the centre cross on the DXF's CENTER layer (``output.dxf_construction``).
DXF_CENTER_MARK_MM = 5.0


def _profile(cam: "CamResult") -> "Contour":
    """The cam's profile: a manufacturing output is written only for a cam that has one (the
    pipeline withholds it otherwise)."""
    assert cam.contour is not None, f"cam {cam.name!r} has no profile to write"
    return cam.contour


def dxf(cam: "CamResult", run: RunSettings, fmt: str) -> str:
    """What is cut (profile, bore, keyway, each pocket wall on its own layer); with ``output.dxf_construction`` also the PITCH,
    CENTER and ZERO layers."""
    from camgen.export.dxf import DxfOptions, contour_to_dxf

    from camgen.export.dxf import DEFAULT_BSPLINE_TOL

    construction = run.output.dxf_construction
    # the B-splines as close to the profile as its own fit (fit_tol_mm) where that is tighter than the default
    fit = cam.figures.get("fit_tol_mm")
    bspline_tol = min(DEFAULT_BSPLINE_TOL, float(fit)) if isinstance(fit, (int, float)) else DEFAULT_BSPLINE_TOL
    options = DxfOptions(splines=run.output.dxf_splines, chord_tol=run.output.chord_tol,
                         center_mark=DXF_CENTER_MARK_MM if construction else 0.0, bspline_tol=bspline_tol,
                         version=run.output.dxf_version)
    if not construction:
        return contour_to_dxf(_profile(cam), cam.body, None, options, None, cam.pockets)
    # the synthesis' follower-centre path, else the roller checks' pitch curve
    pitch = cam.pitch if cam.pitch is not None else (cam.evaluation.pitch if cam.evaluation is not None else None)
    return contour_to_dxf(_profile(cam), cam.body, pitch, options, cam.zero_mark, cam.pockets)


def points(cam: "CamResult", run: RunSettings, fmt: str) -> str:
    from camgen.export.points import points_csv

    return points_csv(_profile(cam), run.output.chord_tol, cam.pockets)


def lift(cam: "CamResult", run: RunSettings, fmt: str) -> str:
    """The polar lift table of the profile (and of each pocket wall); a wall that a ray from the
    axis does not meet exactly once (a slot beside the axis) refuses it (``output.formats``)."""
    from camgen.errors import GeometryError
    from camgen.export.points import lift_csv

    if not cam.pockets:
        return lift_csv(_profile(cam), run.output.lift_step)
    try:
        return lift_csv(_profile(cam), run.output.lift_step, cam.pockets)
    except GeometryError as exc:
        from camgen.export.pocket import refuse_pocket_format

        refuse_pocket_format(cam.name, fmt, cam.pockets, f"the lift table needs every wall star-shaped about the axis ({exc})")


def follower(cam: "CamResult", run: RunSettings, fmt: str) -> str:
    from camgen.errors import GeometryError
    from camgen.export.motion import follower_csv

    motion = cam.evaluation.motion if cam.evaluation is not None else None
    if motion is None or cam.rpm is None:
        raise GeometryError("the follower motion of this cam is not known (its profile cannot be made): no follower table")
    return follower_csv(motion, cam.rpm)


def mesh(cam: "CamResult", run: RunSettings, fmt: str) -> bytes:
    from camgen.export.solid import mesh_bytes

    assert cam.solid is not None, f"cam {cam.name!r} has no solid (the mesh stage withholds its meshes)"
    return mesh_bytes(cam.solid, fmt, cam.name)


def step(cam: "CamResult", run: RunSettings, fmt: str) -> bytes:
    from camgen.export.step import step_bytes

    return step_bytes(_profile(cam), cam.body, cam.name, pockets=cam.pockets, schema=run.output.step_schema)


def gcode(cam: "CamResult", run: RunSettings, fmt: str) -> str:
    """The cam's G-code: the machining spec is final (the scene reader checked it against the
    chord tolerance and the cam's depth); the cam's thickness is the stock's; its pockets (a
    groove) are milled before its outline."""
    from camgen.export.gcode import gcode_program
    from camgen.keynames import renamed
    from camgen.outputs import machining_keys, output_keys

    assert run.machining.chord_tol == run.output.chord_tol, "the scene reader gives a G-code run its chord tolerance"
    if run.machining.wire_edm is not None:  # wire EDM: its own program (camgen.export.wire_edm)
        from camgen.export.wire_edm import wire_edm_program as gcode_program
    try:  # a program too long: the error names the scene key to change
        return renamed("machining", machining_keys(), lambda: gcode_program(_profile(cam), run.machining, cam.name, run.scene_name,
                                                                             cam.body.thickness, cam.pockets, cam_body=cam.body),
                       also=(("output", output_keys()),))
    except ParameterError as exc:
        raise ParameterError(exc.name, exc.value, f"{exc.valid} for cam '{cam.name}'", exc.why) from None


def json_report(report: "ReportInput") -> str:
    """report.json of the run's report input (:mod:`camgen.report_data`)."""
    from camgen.report import report_dict, report_json

    return report_json(report_dict(report))


def html(report: "ReportInput") -> str:
    """report.html of the run's report input (:mod:`camgen.report_data`)."""
    from camgen.report.html import report_html

    return report_html(report)
