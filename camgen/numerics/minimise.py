"""Golden-section search for the least value of a scalar function on an interval (a function
that is expensive or not smooth, called one point at a time: sizing's best base radius over the
offset, the least radius of a curve between two samples)."""
from __future__ import annotations

import math
from typing import Callable

__all__ = ["GOLDEN", "golden_section"]

#: (sqrt(5) - 1) / 2: each step keeps this fraction of the bracket (Kiefer 1953).
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def golden_section(f: Callable[[float], float], a: float, b: float, *, tol: float = 0.0,
                   max_steps: int = 200) -> tuple[tuple[float, float], tuple[float, float]]:
    """The two inner points ``(x, f(x))`` of the last bracket of a golden-section search for the
    least value of ``f`` on ``[a, b]``: it stops when the bracket is at most ``tol`` long or
    after ``max_steps`` steps (one evaluation each).  For a unimodal ``f`` the least value lies
    in the last bracket; for another, the search finds a local least value."""
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(max_steps):
        if b - a <= tol:
            break
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = f(d)
    return (c, fc), (d, fd)
