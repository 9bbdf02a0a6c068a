"""The lazy pipeline: scene -> synthesis -> contour -> checks -> report and exports.

Only the stages a scene's outputs need are run, and their libraries are imported only then
(ezdxf for DXF; nothing heavier is touched by a DXF/CSV job).  Everything is computed before
the first file is written, so a user error leaves no partial output behind.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from camgen.scene import CamSpec, Scene


@dataclass
class BuiltCam:
    """A synthesised cam with its figures (report numbers) and checks."""

    name: str
    kind: str
    contour: Any
    figures: dict[str, Any]
    checks: list[Any] = field(default_factory=list)


def _build_three_arc(spec: CamSpec) -> BuiltCam:
    from camgen import checks
    from camgen.synthesis import three_arc

    p = spec.params
    a, b, c = (p.get(k) for k in ("a", "b", "c"))
    try:
        a, b, c = three_arc.validate_three_arc(a, b, c)
    except Exception as exc:  # re-raise with the scene key so the user finds it
        from camgen.errors import ParameterError

        if isinstance(exc, ParameterError):
            raise ParameterError(f"cams.{spec.name}.{exc.name}_mm", exc.value, exc.valid) from None
        raise
    contour = three_arc.three_arc_cam(a, b, c)
    width = three_arc.breadth(a, b, c)
    breadth_check = checks.constant_breadth_check(contour, width)
    figures = {
        "a_mm": a,
        "b_mm": b,
        "c_mm": c,
        "theta_x_deg": math.degrees(three_arc.theta_x(a, b)),
        "breadth_mm": width,
        "breadth_error_mm": breadth_check.value,
        "base_radius_mm": c,
        "max_radius_mm": 2.0 * a + c - b,
        "area_mm2": contour.area,
        "perimeter_mm": contour.length,
        "bounds_mm": list(contour.bounds),
        "arc_radii_mm": [seg.radius for seg in contour.segments],
    }
    if "source" in p:
        figures["source"] = p["source"]
    return BuiltCam(
        spec.name,
        spec.kind,
        contour,
        figures,
        [breadth_check, checks.continuity_check(contour), checks.convexity_check(contour)],
    )


BUILDERS: dict[str, Callable[[CamSpec], BuiltCam]] = {"three_arc": _build_three_arc}


def build_cams(scene: Scene) -> list[BuiltCam]:
    """Synthesise and check every cam of ``scene``."""
    return [BUILDERS[spec.kind](spec) for spec in scene.cams]


def run_scene(scene: Scene, outdir: str | Path = "outputs") -> list[Path]:
    """Run ``scene`` and write its outputs into ``outdir/<scene name>/``; return the paths written."""
    from camgen.report import report_json, report_dict

    target = Path(outdir) / scene.name
    cams = build_cams(scene)
    tol = scene.output.chord_tol
    # render everything in memory first: nothing is written unless all of it succeeded
    files: dict[str, str | bytes] = {}
    for cam in cams:
        if "dxf" in scene.output.formats:
            from camgen.export.dxf import contour_to_dxf

            files[f"{cam.name}.dxf"] = contour_to_dxf(cam.contour)
        if "points" in scene.output.formats:
            from camgen.export.points import points_csv

            files[f"{cam.name}_points.csv"] = points_csv(cam.contour, tol, cam.name, scene.name)
    files["report.json"] = report_json(report_dict(scene, cams, sorted(files) + ["report.json"]))

    from camgen.export.atomic import write_atomic

    return [write_atomic(target / name, data) for name, data in files.items()]
