"""Design studies: sweeps of scene keys, tolerance Monte Carlo and optimisation.

:mod:`camgen.study.space` reads which keys vary and samples the points; :mod:`camgen.study.design`
evaluates one design as a pure function of the base scene and the point (no files), giving a
flat row of inputs, statuses, check values and main figures.  :mod:`camgen.study.tolerance`
(``camgen tolerance``) rides cams as made under manufacturing and assembly errors.
"""
from __future__ import annotations

__all__: list[str] = []
