"""One design of a study, evaluated as a pure function: the base scene and a point in, a row out.

:class:`StudyScene` is the base scene decoded once; :func:`evaluate_point` sets the point's values
into a copy of the decoded table, reads it through the scene schema (:func:`camgen.scene.parse_scene`:
the same refusals as ``camgen check``), builds every cam and runs every design check and the
dynamics (:func:`camgen.pipeline.compute` with the evaluation plan), and returns a flat row
(:data:`Row`): the inputs, the point's key, its status, every check's value and status and the
main figures.  No file is written and nothing outside the arguments is read or changed, so a row
depends on the scene and the point alone (a cluster worker computes the same row as this process).

The export checks (a tool path that would gouge, a solid that cannot be meshed) are not part of a
design's evaluation: they need the files (``camgen sweep --keep-files`` makes them for the best
designs, and ``camgen check`` on a design's scene runs them).
"""
from __future__ import annotations

import hashlib
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from camgen.errors import CamgenError

if TYPE_CHECKING:
    from camgen.planning import Plan
    from camgen.results import CamResult
    from camgen.scene import Scene
    from camgen.study.keys import KeyPath
    from camgen.study.space import Value

__all__ = ["FIGURES", "OUTER_RADIUS_TOL", "Row", "STATUSES", "StudyScene", "design_plan", "evaluate_batch", "evaluate_point", "finite_number",
           "main_figures", "point_key", "point_scene_data"]

#: A row of a study: column name -> a JSON scalar (str, int, float, bool or None; never NaN).
Row = dict[str, "str | int | float | bool | None"]
#: A design's status: every check with a limit passed, one failed, the scene refused it (a value
#: out of range, a geometry that cannot be built), or its evaluation killed the worker repeatedly.
STATUSES = ("pass", "fail", "error", "crashed")
#: A bound of the outer radius's error, mm: it is the exact largest distance of the outline's
#: pieces (:func:`camgen.contour.reach.farthest_distance`: their ends and the roots of ``P . P'``,
#: exact to rounding, far within this bound; tests/test_evaluation_speed.py against dense sampling).
OUTER_RADIUS_TOL = 1e-3
#: The main figures of every cam (column ``fig.<cam>.<figure>``) and what each is.
FIGURES = {
    "outer_radius_mm": "largest distance from the cam axis to the outline, mm (within OUTER_RADIUS_TOL)",
    "pressure_angle_deg": "largest pressure angle, deg (the pressure_angle check's value)",
    "least_radius_mm": "smallest radius of curvature of the profile, convex or concave, mm",
    "torque_peak_n_m": "peak camshaft torque at rpm, N*m (dynamics)",
    "contact_stress_mpa": "peak Hertz contact stress, MPa (dynamics)",
    "jump_rpm": "speed at which the follower would leave the cam, rpm (dynamics; force-closed trains)",
}


@dataclass(frozen=True)
class StudyScene:
    """The base scene of a study: its decoded table, text and where it was read from.

    ``scene_hash``: the first 16 hex digits of the SHA-256 of the scene's text (a row names the
    scene it came from).
    """

    data: Mapping[str, Any]
    text: str
    name: str
    source: str
    base_dir: Path | None
    scene_hash: str

    @classmethod
    def load(cls, path: "str | None") -> "StudyScene":
        """The scene file at ``path`` (None: the bundled default scene), read through the scene's
        limits and checked by :func:`camgen.scene.parse_scene` (a bad base scene is refused now)."""
        from camgen.scene import decode_scene_file, template_path

        file = template_path("default") if path is None else Path(path)
        text, data = decode_scene_file(file)
        study = cls(data, text, file.stem, str(file) if path is not None else "templates/default.toml", file.parent,
                    hashlib.sha256(text.encode("utf-8")).hexdigest()[:16])
        study.scene({})
        return study

    def scene(self, values: "Mapping[tuple[str | int, ...], Value]") -> "Scene":
        """The validated scene with ``values`` (path -> value) set (raises the scene reader's errors).
        The process keeps its freed memory for the next design from now on (:func:`camgen.study.heap.keep_heap`)."""
        from camgen.scene import parse_scene
        from camgen.study.heap import keep_heap

        keep_heap()  # once per process: every design's large arrays from the heap, not fresh mmaps
        return parse_scene(point_scene_data(self.data, values), self.name, self.source, self.base_dir)


def point_scene_data(data: Mapping[str, Any], values: "Mapping[tuple[str | int, ...], Value]") -> dict[str, Any]:
    """The decoded scene ``data`` with ``values`` (path -> value) set; ``data`` is not changed."""
    from camgen.scene_edit import set_value

    out = dict(data)
    for path, value in values.items():
        out = set_value(out, path, value)
    out.pop("sweep", None)  # the study's own table is not part of a design
    return out


def point_key(names: Sequence[str], values: "Sequence[Value]") -> str:
    """The key of a point: the first 16 hex digits of the SHA-256 of its inputs as canonical JSON
    (the same inputs, the same key, in any process; a float by its shortest repr)."""
    text = json.dumps(sorted(zip(names, values)), separators=(",", ":"))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def finite_number(value: object) -> float | None:
    """A check's value as a float column (None: not a number, or not finite)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _outer_radius(cam: "CamResult") -> float | None:
    if cam.contour is None:
        return None
    from camgen.contour.reach import farthest_distance

    return farthest_distance(cam.contour)


def main_figures(cam: "CamResult") -> dict[str, float | None]:
    """The :data:`FIGURES` of a built and checked cam (None where the cam has none)."""
    checks = {c.name: c for c in cam.checks}
    radii = [v for v in (finite_number(checks[n].value) for n in ("min_convex_radius", "min_concave_radius") if n in checks)
             if v is not None]
    dynamics = cam.figures.get("dynamics") or {}
    return {
        "outer_radius_mm": _outer_radius(cam),
        "pressure_angle_deg": finite_number(checks["pressure_angle"].value) if "pressure_angle" in checks else None,
        "least_radius_mm": min(radii) if radii else None,
        "torque_peak_n_m": finite_number(dynamics.get("torque_peak_Nm")),
        "contact_stress_mpa": finite_number(dynamics.get("hertz_stress_peak_MPa")),
        "jump_rpm": finite_number(dynamics.get("jump_rpm")),
    }


def design_plan(scene: "Scene") -> "Plan":
    """The plan of a design's evaluation: synthesis, every design check and the dynamics, no
    files and no figure only the report draws (:func:`camgen.evaluation.evaluation_plan`)."""
    from camgen.evaluation import evaluation_plan

    return evaluation_plan(scene)


def evaluate_point(study: StudyScene, keys: "Sequence[KeyPath]", values: "Sequence[Value]") -> Row:
    """The row of one design: ``study``'s scene with ``values`` set at ``keys``.

    Columns: each key's name with its value; ``key`` (:func:`point_key`); ``status`` (:data:`STATUSES`);
    ``error`` (the one line ``camgen check`` would print, "" when none); per cam and check
    ``check.<cam>.<check>`` (its value, None when not a number) and ``check.<cam>.<check>.status``
    (pass, fail, info); per cam the :data:`FIGURES` as ``fig.<cam>.<figure>``; ``camgen_version``,
    ``scene_hash``; ``eval_ms`` (the evaluation's time, the only column that differs between runs).
    """
    from camgen import __version__

    started = time.perf_counter()
    names = [k.name for k in keys]
    row: Row = dict(zip(names, values))
    row.update(key=point_key(names, values), status="error", error="", camgen_version=__version__, scene_hash=study.scene_hash)
    try:
        from camgen.pipeline import compute

        scene = study.scene({k.path: v for k, v in zip(keys, values)})
        result = compute(scene, design_plan(scene))
        failed = False
        for cam in result.cams:
            for check in cam.checks:
                row[f"check.{cam.name}.{check.name}"] = finite_number(check.value)
                row[f"check.{cam.name}.{check.name}.status"] = check.status
                failed = failed or check.failed
            for figure, value in main_figures(cam).items():
                row[f"fig.{cam.name}.{figure}"] = value
        row["status"] = "fail" if failed else "pass"
    except CamgenError as exc:
        row["error"] = "camgen: error: " + " ".join(str(exc).split())
    except Exception as exc:  # a bug in camgen on this design: recorded, the study goes on
        row["error"] = f"camgen: internal error: {type(exc).__name__}: {' '.join(str(exc).split())[:200]}"
    row["eval_ms"] = (time.perf_counter() - started) * 1e3
    return row


def evaluate_batch(study: StudyScene, keys: "Sequence[KeyPath]", points: "Sequence[Sequence[Value]]") -> list[Row]:
    """The rows of ``points`` in order (one task of a parallel study: a batch keeps the per-task
    overhead small against the designs' evaluation)."""
    return [evaluate_point(study, keys, p) for p in points]
