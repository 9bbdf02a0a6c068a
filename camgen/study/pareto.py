"""The Pareto front of two figures, both minimised, in O(n log n).

A design is on the front when no other design is at least as good in both figures and better in
one (a design with the same two values as another is on the front with it).  A figure to be
maximised is passed negated.
"""
from __future__ import annotations

import numpy as np

from camgen.errors import ParameterError

__all__ = ["pareto_front"]


def pareto_front(a: "np.ndarray | list[float]", b: "np.ndarray | list[float]") -> np.ndarray:
    """A boolean mask of the designs on the Pareto front of ``(a, b)``, both minimised.

    Parameters
    ----------
    a, b : the two figures of each design (1-D, same length, finite; any unit).

    Returns
    -------
    numpy.ndarray of bool, one per design: True when no other design ``q`` has
    ``q.a <= a``, ``q.b <= b`` and is better in one of them.
    """
    x, y = np.asarray(a, dtype=float).ravel(), np.asarray(b, dtype=float).ravel()
    if x.shape != y.shape or not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise ParameterError("pareto figures", f"{x.size} and {y.size} values", "two arrays of finite numbers of one length")
    out = np.zeros(x.size, dtype=bool)
    if x.size == 0:
        return out
    order = np.lexsort((y, x))  # by a, then b: the first of each run of equal a has the run's least b
    xs, ys = x[order], y[order]
    first = np.empty(xs.size, dtype=bool)
    first[0] = True
    first[1:] = xs[1:] != xs[:-1]
    group = np.cumsum(first) - 1
    group_min = ys[first]
    # the least b of all designs with a strictly smaller a (inf for the first run)
    before = np.concatenate([[np.inf], np.minimum.accumulate(group_min)[:-1]])
    out[order] = (ys == group_min[group]) & (before[group] > ys)
    return out
