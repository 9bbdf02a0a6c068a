"""Row-list segment keys: a bspline's ``points`` and a polynomial's ``interior`` conditions.

A row starts with a *position* along the segment, measured from the segment's start in the
program's abscissa (deg of cam angle; a linear cam: mm of plate travel), strictly inside the span
and increasing from row to row; the rest of the row is in the units of the segment's other keys
(:mod:`camgen.motions.motion_law`).  :class:`Rows` reads the scene value; :func:`rows_per_rad`
checks the positions against the span (naming the row in scene units) and converts a row to the
units of :class:`camgen.synthesis.laws.Segment` (rad of the turn; mm or rad of swing; per rad^k).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from camgen.errors import ParameterError
from camgen.schema import Number, NumberList, ValueType

__all__ = ["Rows", "rows_per_rad"]


@dataclass(frozen=True)
class Rows(ValueType):
    """A list of ``1 .. max_rows`` rows, each a list of ``min_width .. max_width`` finite numbers."""

    min_width: int
    max_width: int
    max_rows: int = 100

    def _row(self) -> NumberList:
        return NumberList(Number(""), self.min_width, self.max_width)

    def describe(self) -> str:
        width = f"{self.min_width}" if self.min_width == self.max_width else f"{self.min_width} to {self.max_width}"
        return f"a list of 1 to {self.max_rows} rows, each a list of {width} numbers"

    def parse(self, path: str, value: object) -> tuple[tuple[float, ...], ...]:
        if not isinstance(value, list) or not 1 <= len(value) <= self.max_rows:
            shown = value if not isinstance(value, list) or len(value) < 20 else f"<list of {len(value)}>"
            raise ParameterError(path, shown, self.describe())
        return tuple(self._row().parse(f"{path}[{i}]", row) for i, row in enumerate(value))

    def to_scene(self, value: Any) -> Any:
        return None if value is None else [list(row) for row in value]


def rows_per_rad(path: str, rows: tuple[tuple[float, ...], ...], span: float, span_unit: str, per_unit: float,
                 oscillating: bool) -> tuple[tuple[float, ...], ...]:
    """Rows ``[position, value, d value, d2 value]`` in scene units -> the segment's units.

    Parameters
    ----------
    path : str
        The key's scene path (``cams.c.segments[0].points``), for refusals.
    rows : tuple of tuples
        As :class:`Rows` read them.
    span : float
        The segment's span in scene units (deg or mm), ``span_unit`` its unit.
    per_unit : float
        The abscissa's units in one rad of the turn (a degree: 180/pi; a travel of T mm: T/(2 pi)).
    oscillating : bool
        The values are deg of swing (converted to rad), else mm.

    Returns
    -------
    tuple of tuples
        Position in rad from the segment's start, the value in mm or rad, the k-th derivative per
        rad^k.

    Raises
    ------
    ParameterError
        A position not strictly inside ``(0, span)`` or not after the previous row's.
    """
    from camgen.synthesis.laws_spline import MIN_SPACING

    gap = MIN_SPACING * span
    for k, row in enumerate(rows):
        if not 0.0 < row[0] < span:
            raise ParameterError(f"{path}[{k}]", list(row), f"a position strictly inside the segment's span: 0 < position < {span:g} "
                                 f"{span_unit} (from the segment's start)")
        if not gap <= row[0] <= span - gap:
            raise ParameterError(f"{path}[{k}]", list(row), f"a position at least {gap:g} {span_unit} ({MIN_SPACING:g} of the span) "
                                 "from the segment's ends", "closer, the conditions are too ill-conditioned to meet")
        if k and not row[0] > rows[k - 1][0]:
            raise ParameterError(f"{path}[{k}]", list(row), f"a position after {rows[k - 1][0]:g} {span_unit} ({path}[{k - 1}]'s)",
                                 "rows in increasing order of position")
        if k and not row[0] - rows[k - 1][0] >= gap:
            raise ParameterError(f"{path}[{k}]", list(row), f"a position at least {gap:g} {span_unit} ({MIN_SPACING:g} of the span) "
                                 f"after {rows[k - 1][0]:g} {span_unit} ({path}[{k - 1}]'s)",
                                 "closer, the conditions are too ill-conditioned to meet")
    factor = math.pi / 180.0 if oscillating else 1.0  # deg of swing -> rad
    return tuple((row[0] / per_unit,) + tuple(v * factor * per_unit**k for k, v in enumerate(row[1:])) for row in rows)
