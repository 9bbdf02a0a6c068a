"""What each CSV of a run holds: report.json's ``tables`` object.

camgen's CSV files are a header row and numbers only (:mod:`camgen.export.tables`), so that
every reader opens them with its default settings; their description lives here, one entry per
CSV written, keyed by the file name::

    {"<file>.csv": {"content": str, "columns": {column: "meaning, unit"},
                    "cam": str | "mechanism": str, <the table's settings>}}

The settings are each table's own (:func:`camgen.export.points.points_metadata`,
:func:`~camgen.export.points.lift_metadata`, :func:`camgen.export.motion.follower_metadata`,
:func:`camgen.motions.trajectory.ride_metadata`, :func:`camgen.jobs.horse_leg.leg_path_metadata`):
the chord tolerance of a point list, the angle step and base radius of a lift table, the cam
speed, follower motion and acceleration jumps of a follower table, the target path of a ride,
the inclination and ground line of a leg path.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, Sequence

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.scene import Scene

__all__ = ["LEG_PATH_PREFIX", "LEG_PATH_SUFFIX", "tables_metadata"]

#: File name prefix and suffix of the horse leg's path tables.
LEG_PATH_PREFIX, LEG_PATH_SUFFIX = "leg_path_alpha_", ".csv"


def _cam_tables(cam: "CamResult", scene: "Scene", written: set[str]) -> dict[str, dict[str, Any]]:
    from camgen.outputs import OUTPUTS

    out: dict[str, dict[str, Any]] = {}

    def add(name: str, build: Any) -> None:
        if name in written:
            out[name] = {"cam": cam.name, **build()}

    own = _own_points_writer(cam)
    if own is not None:  # a form that writes its own point list describes it beside its writer: points_metadata(cam, chord_tol)
        import importlib

        describe = getattr(importlib.import_module(own.split(":")[0]), "points_metadata")
        add(OUTPUTS["points"].files.format(cam=cam.name), lambda: describe(cam, scene.output.chord_tol))
    elif cam.contour is not None:
        from camgen.export.points import lift_metadata, points_metadata

        add(OUTPUTS["points"].files.format(cam=cam.name), lambda: points_metadata(scene.output.chord_tol, cam.pockets))
        add(OUTPUTS["lift"].files.format(cam=cam.name), lambda: lift_metadata(cam.contour, scene.output.lift_step, cam.pockets))
    if OUTPUTS["inspection"].files.format(cam=cam.name) in written:  # the drawing's inspection table (camgen.export.drawing_writers)
        from camgen.export.drawing_writers import inspection_description

        add(OUTPUTS["inspection"].files.format(cam=cam.name), lambda: inspection_description(cam, scene.output.drawing))
    motion = cam.evaluation.motion if cam.evaluation is not None else None
    if motion is not None and cam.rpm is not None:
        from camgen.export.motion import follower_metadata

        add(OUTPUTS["follower"].files.format(cam=cam.name), lambda: follower_metadata(motion, cam.rpm))
    if cam.kind == "trajectory":
        from camgen.motions.trajectory import ride_metadata

        add(OUTPUTS["ride"].files.format(cam=cam.name), lambda: ride_metadata(str(cam.figures["trajectory"])))
    return out


def _own_points_writer(cam: "CamResult") -> str | None:
    """The ``"module:function"`` writing ``cam``'s point list for its form (CamForm.writers), or None."""
    from camgen.forms import form_names, get_form

    return get_form(cam.spec.form).writers.get("points") if cam.spec.form in form_names() else None


def _leg_tables(report: Mapping[str, Any], written: set[str]) -> dict[str, dict[str, Any]]:
    from camgen.jobs.horse_leg import leg_path_metadata

    out = {}
    for name in sorted(written):
        if name.startswith(LEG_PATH_PREFIX) and name.endswith(LEG_PATH_SUFFIX):
            figures = report[f"alpha_{name[len(LEG_PATH_PREFIX):-len(LEG_PATH_SUFFIX)]}"]
            out[name] = {"mechanism": "horse_leg", **leg_path_metadata(figures["alpha1_deg"], report["ground_y_mm"])}
    return out


def tables_metadata(scene: "Scene", cams: "Sequence[CamResult]", files: Sequence[str],
                    mechanisms: Mapping[str, Any] | None = None) -> dict[str, dict[str, Any]]:
    """The ``tables`` object of report.json: for every CSV among ``files`` (the names a run
    writes) what it holds; ``mechanisms`` are the jobs' report sections (the horse leg's
    inclinations and ground line)."""
    written = {name for name in files if name.endswith(".csv")}
    out: dict[str, dict[str, Any]] = {}
    for cam in cams:
        out.update(_cam_tables(cam, scene, written))
    if mechanisms and "horse_leg" in mechanisms:
        out.update(_leg_tables(mechanisms["horse_leg"], written))
    missing = sorted(written - set(out))
    if missing:  # a CSV without its description: a writer added without its metadata (a bug, not an input error)
        raise RuntimeError(f"no description of the table(s) {', '.join(missing)} for report.json")
    return dict(sorted(out.items()))
