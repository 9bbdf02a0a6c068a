"""The best designs of a study: ranked by a figure among the passing ones, each written back as
a scene file (the base scene's text with the design's values, comments kept) and, when asked
(``camgen sweep --keep-files N``), run as ``camgen run`` would run that scene.
"""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from camgen.errors import ParameterError
from camgen.study.columns import FigureColumn, number, resolve_figure

if TYPE_CHECKING:
    from camgen.results import RunResult
    from camgen.study.design import StudyScene
    from camgen.study.space import Value, Variable

__all__ = ["MAX_BEST", "best_rows", "best_scene_text", "check_best", "default_rank", "keep_files", "point_values"]

#: The most best designs a report lists or a sweep keeps files of.
MAX_BEST = 1000


def default_rank(data: Mapping[str, Any]) -> str:
    """The figure that ranks designs unless told: the first cam's outer radius."""
    from camgen.study.columns import cam_names

    cams = cam_names(data)
    return f"fig.{cams[0]}.outer_radius_mm" if cams else "outer_radius_mm"


def check_best(best: object, option: str = "--best") -> int:
    """``best`` as a count of designs (0 to :data:`MAX_BEST`), else a ParameterError."""
    if isinstance(best, bool) or not isinstance(best, int) or not 0 <= best <= MAX_BEST:
        raise ParameterError(option, best, f"an integer from 0 to {MAX_BEST}")
    return best


def best_rows(rows: Sequence[Mapping[str, object]], figure: FigureColumn, count: int) -> list[Mapping[str, object]]:
    """The ``count`` passing rows with the best value of ``figure`` (smallest, or largest when the
    figure says so; ties by the design's key), best first; rows without the figure left out."""
    ranked = [(figure.sign() * value, str(row.get("key")), i) for i, row in enumerate(rows)
              if row.get("status") == "pass" and (value := number(row.get(figure.column))) is not None]
    ranked.sort()
    return [rows[i] for _, _, i in ranked[:count]]


def point_values(variables: "Sequence[Variable]", row: Mapping[str, object]) -> "dict[tuple[str | int, ...], Value]":
    """The design's values by scene path (a numpy scalar of a row read back from Parquet made
    plain; an integer key's value an int)."""
    out: dict[tuple[str | int, ...], Value] = {}
    for v in variables:
        value = row[v.name]
        item = getattr(value, "item", None)
        plain = item() if callable(item) else value
        if v.integer and isinstance(plain, float) and plain.is_integer():
            plain = int(plain)
        if not isinstance(plain, (int, float, str, bool)):
            raise ParameterError(v.name, plain, "a number, word or true/false (a design's value)")
        out[v.key.path] = plain
    return out


def best_scene_text(study: "StudyScene", variables: "Sequence[Variable]", row: Mapping[str, object]) -> str:
    """The scene of the design ``row``: the base scene's text with its values set, comments kept
    (the study's ``[sweep]`` table left out; ``camgen run`` accepts it)."""
    from camgen.scene_edit import edit_scene_text
    from camgen.study.design import point_scene_data

    return edit_scene_text(study.text, point_scene_data(study.data, point_values(variables, row)))


def keep_files(study: "StudyScene", variables: "Sequence[Variable]", rows: Sequence[Mapping[str, object]], best: int,
               rank: str | None, outdir: "str | Path") -> "list[RunResult]":
    """Run each of the ``best`` designs (ranked by ``rank``, default :func:`default_rank`) as
    ``camgen run`` runs its scene, into ``outdir/best/<key>/`` (the files of the scene's
    ``output.formats``, report.json included), best first.

    Raises the scene reader's and the run's errors (a passing design's scene is valid).
    """
    from camgen.pipeline import run_scene
    from camgen.scene import parse_scene
    from camgen.study.design import point_scene_data

    figure = resolve_figure(study.data, default_rank(study.data) if rank is None else rank, "--rank")
    results = []
    for row in best_rows(rows, figure, check_best(best, "--keep-files")):
        data = point_scene_data(study.data, point_values(variables, row))
        scene = parse_scene(data, study.name, study.source, study.base_dir)
        results.append(run_scene(replace(scene, name=str(row["key"])), Path(outdir) / "best"))
    return results
