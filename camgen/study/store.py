"""The results folder of a sweep: Parquet part files as batches arrive, a summary and the counts.

``OUTDIR/<scene>-sweep/`` holds ``parts/part-NNNNN.parquet`` (one per batch of rows, each written
atomically: a temporary file in the same folder, then ``os.replace``, so a killed client loses at
most the batches in flight and never leaves a half-written part), ``summary.csv`` (every row of the
sweep in point order, for spreadsheets: None as an empty cell, never NaN) and ``sweep.json`` (what
was swept and the counts per status).  ``--resume`` reads the parts' keys and evaluates only the
points that have none.

Every part has the same column types whatever its rows (:func:`column_type`), so the parts of a
serial and of a parallel sweep read back equal.
"""
from __future__ import annotations

import csv
import io
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Mapping, Sequence

from camgen.errors import ParameterError

if TYPE_CHECKING:
    from camgen.study.design import Row
    from camgen.study.space import Variable

__all__ = ["PART_GLOB", "ResultsFolder", "column_type", "folder_for"]

#: The part files of a results folder (in ``parts/``).
PART_GLOB = "part-*.parquet"
_PART = re.compile(r"^part-(\d+)\.parquet$")
#: Columns that hold text (besides ``check.<cam>.<check>.status``).
_TEXT = frozenset({"key", "status", "error", "camgen_version", "scene_hash"})
#: The pyarrow type of each column type.
_ARROW = {"string": "string", "float64": "float64", "int64": "int64", "bool": "bool_"}


def folder_for(outdir: str, scene_name: str) -> Path:
    """The results folder of a sweep of scene ``scene_name``: ``OUTDIR/<scene>-sweep``."""
    if not outdir.strip():
        raise ParameterError("-o/--outdir", outdir, "a folder path (default: outputs)")
    return Path(outdir) / f"{scene_name}-sweep"


def column_type(name: str, variables: "Sequence[Variable]") -> str:
    """The type of a column: ``string``, ``float64``, ``int64`` or ``bool``.

    A varied key is an integer when its base value is, a bool when every listed value is, a
    float when every value is a number, else text; the check values, figures and ``eval_ms`` are
    floats; the rest is text.
    """
    for v in variables:
        if v.name == name:
            if v.values and all(isinstance(x, bool) for x in v.values):
                return "bool"
            if v.integer or (v.values and all(isinstance(x, int) and not isinstance(x, bool) for x in v.values)):
                return "int64"
            if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v.values):
                return "float64"
            return "string"
    if name in _TEXT or name.endswith(".status"):
        return "string"
    return "float64"


def _cast(value: object, kind: str) -> object:
    if value is None:
        return None
    if kind == "string":
        return value if isinstance(value, str) else str(value)
    if kind == "int64":
        return int(value)  # type: ignore[call-overload]  # a varied integer key's value (int, or a float of one)
    if kind == "float64":
        return float(value)  # type: ignore[arg-type]  # a number column (the row's float, or an input int)
    return bool(value)


def _columns(rows: "Iterable[Mapping[str, object]]") -> list[str]:
    """Every column of ``rows`` in the order of first appearance."""
    seen: dict[str, None] = {}
    for row in rows:
        seen.update(dict.fromkeys(row))
    return list(seen)


def _cell(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)  # the shortest text that reads back as the same float
    return str(value)


@dataclass(frozen=True)
class ResultsFolder:
    """A sweep's results folder (:func:`folder_for`) and the Parquet module that writes it."""

    root: Path
    parquet: Any

    @property
    def parts(self) -> Path:
        return self.root / "parts"

    @classmethod
    def prepare(cls, root: Path, resume: bool) -> "ResultsFolder":
        """The folder ``root``, checked before anything is computed.

        Raises
        ------
        ParameterError
            ``--resume`` when ``root`` holds parts and ``resume`` is False (the sweep would mix
            two studies); ``-o/--outdir`` when ``root`` is a file.
        """
        from camgen.study.optional import require

        parquet = require("pyarrow.parquet", "camgen sweep (its results are Parquet files)")
        if root.exists() and not root.is_dir():
            raise ParameterError("-o/--outdir", str(root), "a folder (a file of that name is in the way)")
        folder = cls(root, parquet)
        if not resume and folder.part_files():
            raise ParameterError("--resume", False, f"given to continue the sweep in '{root}' (it holds results), or "
                                 "another -o/--outdir, or that folder removed")
        return folder

    def part_files(self) -> list[Path]:
        """The part files, in the order they were written."""
        if not self.parts.is_dir():
            return []
        return sorted((p for p in self.parts.iterdir() if _PART.match(p.name)), key=lambda p: p.name)

    def clean(self) -> None:
        """Remove the temporary files a killed sweep left in ``parts/`` (never a whole part)."""
        if self.parts.is_dir():
            for stray in self.parts.glob(".part-*.tmp"):
                stray.unlink(missing_ok=True)

    def finished(self, scene_hash: str) -> set[str]:
        """The keys of the points the parts hold.

        Raises
        ------
        ParameterError
            ``--resume`` when a part comes from another scene (its ``scene_hash`` differs).
        """
        keys: set[str] = set()
        for part in self.part_files():
            table = self.parquet.read_table(part, columns=["key", "scene_hash"]).to_pydict()
            other = set(table["scene_hash"]) - {scene_hash}
            if other:
                raise ParameterError("--resume", str(self.root), "the results of this scene file as it is now (its parts "
                                     f"come from a scene of hash {sorted(other)[0]}, this one is {scene_hash})")
            keys.update(table["key"])
        return keys

    def write_part(self, rows: "Sequence[Row]", variables: "Sequence[Variable]") -> Path:
        """Write ``rows`` as the next part file, atomically; return its path."""
        from camgen.export.atomic import atomic_path
        from camgen.study.optional import require

        pa = require("pyarrow", "camgen sweep (its results are Parquet files)")

        files = self.part_files()
        number = int(_PART.match(files[-1].name).group(1)) + 1 if files else 0  # type: ignore[union-attr]  # matched in part_files
        path = self.parts / f"part-{number:05d}.parquet"
        columns = _columns(rows)
        arrays = {}
        for name in columns:
            kind = column_type(name, variables)
            arrays[name] = pa.array([_cast(r.get(name), kind) for r in rows], type=getattr(pa, _ARROW[kind])())
        table = pa.table(arrays)
        with atomic_path(path) as tmp:
            self.parquet.write_table(table, tmp)
        return path

    def read_rows(self) -> list[dict[str, Any]]:
        """Every row of every part, in the order written (a point evaluated twice: its last row)."""
        out: dict[str, dict[str, Any]] = {}
        for part in self.part_files():
            for row in self.parquet.read_table(part).to_pylist():
                out[row["key"]] = row
        return list(out.values())

    def write_summary(self, rows: "Sequence[Mapping[str, Any]]") -> Path:
        """``summary.csv``: ``rows`` (in point order) with every column any of them has, atomically."""
        from camgen.export.atomic import write_atomic

        columns = _columns(rows)
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(columns)
        for row in rows:
            writer.writerow([_cell(row.get(c)) for c in columns])
        return write_atomic(self.root / "summary.csv", buffer.getvalue())

    def write_json(self, facts: Mapping[str, Any]) -> Path:
        """``sweep.json``: the facts of the sweep, atomically."""
        from camgen.export.atomic import write_atomic

        return write_atomic(self.root / "sweep.json", json.dumps(facts, indent=2, allow_nan=False) + "\n")
