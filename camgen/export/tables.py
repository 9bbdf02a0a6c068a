"""CSV tables as camgen writes them: one header row of column names that carry their unit
(``x_mm``, ``time_s``), then the rows: plain decimal numbers, ',' between them, '\\n' line ends,
deterministic.  No comment lines: every CSV opens with a reader's default settings
(``pandas.read_csv(path)``, a spreadsheet).  What a table holds, its columns' meaning and the
settings it was made with are in report.json's ``tables`` object (:mod:`camgen.export.tablemeta`)."""
from __future__ import annotations

import re
from typing import Mapping

import numpy as np

__all__ = ["COLUMN_NAME", "csv_table", "format_rows"]

#: A column name: a lower-case identifier (letters, digits, '_'), its unit as the last part.
COLUMN_NAME = re.compile(r"^[a-z][a-z0-9_]*$")


def csv_table(columns: Mapping[str, np.ndarray], decimals: int = 9) -> str:
    """CSV text: the header (``columns``' keys) and their values, one row per element.

    Values are rounded to ``decimals`` places; -0.0 is written as 0.
    """
    from camgen.errors import ExportError

    names = list(columns)
    if not names or not all(COLUMN_NAME.match(n) for n in names) or len(set(names)) != len(names):
        raise ExportError(f"table columns {names} must be distinct lower-case names (letters, digits, '_')")
    data = np.column_stack([np.asarray(v, dtype=float) for v in columns.values()])
    if not np.all(np.isfinite(data)):
        raise ExportError(f"table with columns {names} holds non-finite values")
    return ",".join(names) + "\n" + format_rows(np.round(data, decimals) + 0.0, ",".join([f"%.{decimals}f"] * data.shape[1]))


def format_rows(rows: np.ndarray, row_format: str) -> str:
    """Text of ``rows`` (n, k), each formatted by the printf-style ``row_format`` (k conversions)
    and ended by '\\n': the same text as ``numpy.savetxt``, formatted in one operation instead of
    one Python call per row."""
    rows = np.asarray(rows)
    if rows.ndim == 1:
        rows = rows[:, None]
    if rows.shape[0] == 0:
        return ""
    return ((row_format + "\n") * rows.shape[0]) % tuple(rows.ravel().tolist())
