"""Reading a study's rows: figure columns named as a user names them, a row's first failing
check, and a cell's number (a row read back from Parquet may hold numpy scalars, NaN or None).

A figure is named ``fig.<cam>.<figure>``, ``<cam>.<figure>`` or, for a scene of one cam, the bare
``<figure>`` (:data:`camgen.study.design.FIGURES`); a leading ``-`` asks for the largest value
instead of the smallest (``-jump_rpm``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

from camgen.errors import ParameterError

__all__ = ["FigureColumn", "cam_names", "check_label", "first_failure", "number", "resolve_figure", "row_category"]


@dataclass(frozen=True)
class FigureColumn:
    """A figure chosen by an option: its row column (``fig.<cam>.<figure>``), its label as shown
    (``<cam>.<figure>``, or ``<figure>`` for a scene of one cam) and whether larger is better."""

    column: str
    label: str
    maximise: bool = False

    def sign(self) -> float:
        """+1 when the smallest value is best, -1 when the largest is."""
        return -1.0 if self.maximise else 1.0


def cam_names(data: Mapping[str, Any]) -> list[str]:
    """The cams of a decoded scene, in scene order."""
    cams = data.get("cams")
    return list(cams) if isinstance(cams, dict) else []


def resolve_figure(data: Mapping[str, Any], name: object, option: str) -> FigureColumn:
    """The figure column ``name`` (see the module's doc) names in a study of the scene ``data``.

    Raises
    ------
    ParameterError
        Naming ``option`` and ``name``, with the valid names, when it names no figure of a cam.
    """
    from camgen.study.design import FIGURES

    cams = cam_names(data)
    valid = [f"fig.{cam}.{figure}" for cam in cams for figure in FIGURES]
    shown = list(FIGURES) if len(cams) == 1 else [v[4:] for v in valid]
    if not isinstance(name, str) or not name.strip():
        raise ParameterError(option, name, "a figure: " + ", ".join(shown) + " ('-' first: the largest is best)")
    text = name.strip()
    maximise = text.startswith("-")
    text = text[1:] if maximise else text
    candidates = [text, f"fig.{text}"] + ([f"fig.{cams[0]}.{text}"] if len(cams) == 1 else [])
    column = next((c for c in candidates if c in valid), None)
    if column is None:
        raise ParameterError(option, name, "a figure: " + ", ".join(shown) + " ('-' first: the largest is best)")
    label = column.split(".", 2)[2] if len(cams) == 1 else column[4:]
    return FigureColumn(column, label, maximise)


def number(value: object) -> float | None:
    """A cell as a finite float (None: empty, not a number, NaN or infinite)."""
    if value is None or isinstance(value, (bool, str)):
        return None
    try:
        out = float(value)  # type: ignore[arg-type]  # numpy scalars and ints
    except (TypeError, ValueError):
        return None
    return out if math.isfinite(out) else None


def first_failure(row: Mapping[str, object]) -> str | None:
    """The first failing check of a row as ``<cam>.<check>`` (columns in row order), or None."""
    for column, value in row.items():
        if value == "fail" and column.startswith("check.") and column.endswith(".status"):
            return column[len("check."):-len(".status")]
    return None


def check_label(check: str, cams: Sequence[str]) -> str:
    """A check ``<cam>.<check>`` as a legend names it (the bare check for a scene of one cam)."""
    return check.split(".", 1)[1] if len(cams) == 1 and "." in check else check


def row_category(row: Mapping[str, object], cams: Sequence[str]) -> str:
    """What colours a design: ``pass``, ``error``, ``crashed``, or its first failing check's label
    (``fail`` when a failing row names none)."""
    status = str(row.get("status"))
    if status != "fail":
        return status if status in ("pass", "error", "crashed") else "error"
    check = first_failure(row)
    return "fail" if check is None else check_label(check, cams)
