"""What every part of report.html shares: numbers and values as the page writes them, the
thinning of dense curves before they are drawn, and the page's maker of numbered figures.

The report's modules (:mod:`camgen.report.html`, :mod:`~camgen.report.design`,
:mod:`~camgen.report.dynamics`, :mod:`~camgen.report.sections`) take these from here, never
from each other's private names.
"""
from __future__ import annotations

import html
import itertools
import math
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from camgen.report.model import JsonValue
    from camgen.report.svgplot import Figure

__all__ = ["FigureMaker", "figure_factory", "fmt", "number", "thin", "value_text"]

#: Most values of a list written into a table cell (the rest shown as "...").
LIST_SHOWN = 12


class FigureMaker(Protocol):
    """Makes the next :class:`camgen.report.svgplot.Figure` of the page (``figsize`` in inches)."""

    def __call__(self, figsize: tuple[float, float]) -> "Figure": ...


def figure_factory() -> FigureMaker:
    """A maker of :class:`camgen.report.svgplot.Figure`s numbered in page order, so every
    figure's clip-path ids are unique on the page and the same run gives the same bytes."""
    from camgen.report.svgplot import Figure

    ids = itertools.count(1)

    def make(figsize: tuple[float, float]) -> Figure:
        return Figure(figsize=figsize, id_prefix=f"f{next(ids)}")

    return make


def thin(n: int, most: int = 900) -> slice:
    """A slice that keeps at most about ``most`` of ``n`` evenly spaced samples (plots only)."""
    return slice(None, None, max(1, math.ceil(n / most)))


def fmt(value: "JsonValue") -> str:
    """A check's value, limit or cam angles in a table cell (HTML-escaped): floats to 6
    significant digits, lists as the first :data:`LIST_SHOWN` values."""
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, tuple)):
        return ", ".join(fmt(v) for v in value[:LIST_SHOWN]) + (" ..." if len(value) > LIST_SHOWN else "")
    return html.escape(str(value))


def number(value: float) -> str:
    """A number as the report writes it: 6 significant digits, no exponent noise for integers."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return str(value)
    if not math.isfinite(value):  # report figures are finite (report.json refuses others); drawn as words all the same
        return "infinite" if value > 0 else "-infinite" if value < 0 else "not a number"
    return f"{value:.6g}"


def value_text(value: "JsonValue") -> str:
    """A figure's value as text (HTML-escaped): numbers, lists of them, words."""
    if isinstance(value, (bool, int, float)):
        return number(value)
    if value is None:
        return "-"
    if isinstance(value, (list, tuple)):
        if not value:
            return "none"
        shown = ", ".join(value_text(v) for v in value[:LIST_SHOWN])
        return shown + (f", ... ({len(value)} values)" if len(value) > LIST_SHOWN else "")
    return html.escape(str(value))
