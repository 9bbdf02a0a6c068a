"""CSV tables as camgen writes them: ``#`` comment lines (units, tolerance, source), one header
row, then the rows; plain decimal numbers, '\\n' line ends, deterministic."""
from __future__ import annotations

import io
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
    body = io.StringIO()
    np.savetxt(body, np.round(data, decimals) + 0.0, fmt=f"%.{decimals}f", delimiter=",")
    return head + body.getvalue()
