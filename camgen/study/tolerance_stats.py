"""Percentiles with their sampling error, and first-order sensitivity indices from the same samples.

**Percentiles.**  The p-th percentile of n samples is numpy's default (linear interpolation
between order statistics).  Its sampling error is stated as the distribution-free confidence
interval of the population quantile from the order statistics (the binomial interval: the
quantile lies between the l-th and u-th smallest samples with probability at least
``CONFIDENCE``, where ``l``, ``u`` are the ``(1 - CONFIDENCE) / 2`` and ``(1 + CONFIDENCE) / 2``
quantiles of Binomial(n, p); Conover, *Practical Nonparametric Statistics*, 3rd ed., 1999,
Section 3.2; David & Nagaraja, *Order Statistics*, 3rd ed., 2003, Section 7.1).  An interval
whose rank falls outside 1..n is open on that side (the sample minimum or maximum is given and
``bounded`` says so).

**Sensitivity.**  First-order indices ``S_i = Var(E[Y | X_i]) / Var(Y)`` estimated from the given
samples by the correlation ratio over equal-count bins of ``X_i`` (McKay, "Evaluating
prediction uncertainty", NUREG/CR-6311, 1995; Plischke, Borgonovo & Smith, "Global sensitivity
measures from given data", Eur. J. Oper. Res. 226 (2013) 536-550): ``B = round(sqrt(n))`` bins,
the between-bin variance of the bin means over the total variance.  With independent inputs the
estimate of an input that does not matter is about ``(B - 1) / n`` (the bias of the estimator):
it is given as ``noise_floor``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CONFIDENCE", "Percentile", "first_order_indices", "noise_floor", "percentile"]

#: Confidence level of the stated interval of every percentile.
CONFIDENCE = 0.95


@dataclass(frozen=True)
class Percentile:
    """The ``p``-th percentile (0-100) of a sample, ``value``, and the distribution-free
    ``CONFIDENCE`` interval ``[low, high]`` of the population's percentile; ``bounded``: False
    when too few samples bound the interval on one side (then it ends at the sample extreme)."""

    p: float
    value: float
    low: float
    high: float
    bounded: bool


def percentile(values: np.ndarray, p: float, confidence: float = CONFIDENCE) -> Percentile:
    """The ``p``-th percentile of ``values`` (n,) with its order-statistic confidence interval."""
    from scipy.stats import binom

    ordered = np.sort(np.asarray(values, dtype=float))
    n = ordered.size
    q = p / 100.0
    lo_rank = int(binom.ppf((1.0 - confidence) / 2.0, n, q))  # P(B < l) <= (1 - c) / 2: x_(l) <= quantile
    hi_rank = int(binom.ppf((1.0 + confidence) / 2.0, n, q)) + 1
    bounded = lo_rank >= 1 and hi_rank <= n
    low = float(ordered[max(lo_rank, 1) - 1])
    high = float(ordered[min(hi_rank, n) - 1])
    return Percentile(p, float(np.percentile(ordered, p)), low, high, bounded)


def noise_floor(samples: int) -> float:
    """The expected first-order index (correlation ratio) of an input that does not matter, ``(B - 1) / n``."""
    bins = _bins(samples)
    return (bins - 1) / samples


def _bins(samples: int) -> int:
    return max(2, int(round(math.sqrt(samples))))


def first_order_indices(inputs: np.ndarray, output: np.ndarray) -> np.ndarray:
    """The first-order index of every column of ``inputs`` (n, k) for ``output`` (n,): the
    correlation ratio over ``round(sqrt(n))`` equal-count bins of the column (0 for a constant
    output or a constant column)."""
    inputs = np.asarray(inputs, dtype=float)
    output = np.asarray(output, dtype=float)
    n, k = inputs.shape
    total = float(np.var(output))
    out = np.zeros(k)
    if total == 0.0 or n < 4:
        return out
    edges = np.linspace(0, n, _bins(n) + 1).round().astype(int)
    for j in range(k):
        if np.ptp(inputs[:, j]) == 0.0:
            continue
        ranked = output[np.argsort(inputs[:, j], kind="stable")]
        means = np.array([ranked[a:b].mean() for a, b in zip(edges[:-1], edges[1:])])
        counts = np.diff(edges)
        out[j] = float(np.sum(counts * (means - output.mean()) ** 2) / n / total)
    return out
