"""CSV tables as camgen writes them: ``#`` comment lines (units, tolerance, source), one header
row, then the rows; plain decimal numbers, '\\n' line ends, deterministic."""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np


def csv_table(comments: Sequence[str], columns: Mapping[str, np.ndarray], decimals: int = 9) -> str:
    """CSV text with ``comments`` (without the ``#``), header ``columns`` keys and their values.

    Values are rounded to ``decimals`` places; -0.0 is written as 0.
    """
    head = "".join(f"# {line}\n" for line in comments) + ",".join(columns) + "\n"
    data = np.column_stack([np.asarray(v, dtype=float) for v in columns.values()])
    if not np.all(np.isfinite(data)):
        from camgen.errors import ExportError

        raise ExportError(f"table with columns {list(columns)} holds non-finite values")
    return head + format_rows(np.round(data, decimals) + 0.0, ",".join([f"%.{decimals}f"] * data.shape[1]))


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
