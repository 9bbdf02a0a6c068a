"""Order statistics without numpy's masked-array import.

:func:`numpy.median` imports :mod:`numpy.ma` on its first call (about 8 ms of a run's start on the
machine of benchmarks/RESULTS.md, where a DXF-only run takes about 0.3 s); :func:`median` gives
the same number from one partition.
"""
from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = ["median"]


def median(values: npt.ArrayLike) -> float:
    """The median of ``values`` (flattened; the mean of the two middle values for an even count),
    NaN if any value is NaN or there are none, as :func:`numpy.median`."""
    flat = np.asarray(values, dtype=float).ravel()
    n = flat.size
    if n == 0 or np.isnan(flat).any():
        return math.nan
    k = n // 2
    if n % 2:
        return float(np.partition(flat, k)[k])
    part = np.partition(flat, (k - 1, k))
    return float((part[k - 1] + part[k]) / 2.0)
