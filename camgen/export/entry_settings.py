"""Settings of the outline's passes: the way down to each pass depth (``machining.entry``,
``ramp_angle_deg``: their names, limits and the check of a tool and angle that cannot work;
:mod:`camgen.export.gcode_entry` writes the moves) and the holding tabs' (``holding_tabs``,
``holding_tab_width_mm``, ``holding_tab_height_mm``; :mod:`camgen.export.gcode_tabs`)."""
from __future__ import annotations

import math

from camgen.errors import ParameterError

__all__ = ["DEFAULT_TAB_HEIGHT", "ENTRIES", "HELIX_SHARE", "MAX_ENTRY_TURNS", "MAX_RAMP_ANGLE_DEG", "check_entry_settings",
           "check_tab_settings", "ramp_length", "tab_size", "turn_length"]

#: The ways down to a pass depth (``machining.entry``).
ENTRIES = ("helix", "ramp", "plunge")
#: Radius of the helix over the tool radius: below 1, so the tool covers the helix axis (no core).
HELIX_SHARE = 0.5
#: Steepest ramp angle a scene may give, deg (an end mill's ramp is a few degrees).
MAX_RAMP_ANGLE_DEG = 30.0
#: Most helix turns (ramp round trips) of one pass's entry: more is a ramp angle too shallow for the tool.
MAX_ENTRY_TURNS = 200
#: Height of a tab (mm) when none is given, at most half the stock.
DEFAULT_TAB_HEIGHT = 1.0


def turn_length(entry: str, tool_radius: float, lead: float) -> float:
    """Horizontal length (mm) of one helix turn, or of one ramp round trip."""
    return 2.0 * math.pi * HELIX_SHARE * tool_radius if entry == "helix" else 2.0 * ramp_length(tool_radius, lead)


def ramp_length(tool_radius: float, lead: float) -> float:
    """Length of one straight ramp (mm): the lead length, at least the tool diameter."""
    return max(lead, 2.0 * tool_radius)


def _fits(entry: str, ramp_angle: float, tool_radius: float, step_down: float, lead: float) -> bool:
    """Whether ``entry`` descends one ``step_down`` in at most :data:`MAX_ENTRY_TURNS` turns (no
    division: a vanishing tool gives a turn of length 0, which never fits)."""
    if entry == "plunge":
        return True
    return step_down <= MAX_ENTRY_TURNS * turn_length(entry, tool_radius, lead) * math.tan(ramp_angle)


def check_entry_settings(entry: str | None, ramp_angle: float, tool_radius: float, step_down: float, lead: float) -> str:
    """The way down, resolved: ``entry`` as given, or (None, the default) the helix, else a ramp
    where the helix of this tool (radius, mm) would need more than :data:`MAX_ENTRY_TURNS` turns
    to descend one ``step_down`` at ``ramp_angle`` (rad), else the plunge.  Refuse an unknown
    ``entry`` or angle, and a given helix or ramp that needs more turns: naming ``ramp_angle_deg``
    with the least angle that works where it is within the limit, else ``entry``."""
    if entry is not None and entry not in ENTRIES:
        raise ParameterError("entry", entry, f"one of {ENTRIES}")
    if not 0.0 <= ramp_angle <= math.radians(MAX_RAMP_ANGLE_DEG):  # (0: a positive angle in deg lost below rad's least float)
        raise ParameterError("ramp_angle_deg", math.degrees(ramp_angle), f"0 < x <= {MAX_RAMP_ANGLE_DEG:g} deg")
    if entry is None:  # the default: the first that fits
        return next(kind for kind in ENTRIES if _fits(kind, ramp_angle, tool_radius, step_down, lead))
    if _fits(entry, ramp_angle, tool_radius, step_down, lead):
        return entry
    per_turn = turn_length(entry, tool_radius, lead)
    why = (f"the {entry} of a tool of radius {tool_radius:g} mm would need more than {MAX_ENTRY_TURNS} "
           f"{'turns' if entry == 'helix' else 'ramps'} to descend step_down_mm = {step_down:g}")
    least = math.degrees(math.atan2(step_down, MAX_ENTRY_TURNS * per_turn))
    if least <= MAX_RAMP_ANGLE_DEG - 1e-3:
        raise ParameterError("ramp_angle_deg", math.degrees(ramp_angle), f">= {math.ceil(least * 1000) / 1000:g} deg", why)
    other = [kind for kind in ENTRIES if kind != entry and _fits(kind, ramp_angle, tool_radius, step_down, lead)]
    raise ParameterError("entry", entry, " or ".join(f'"{kind}"' for kind in other), why)


def check_tab_settings(tabs: int, width: float | None, height: float | None) -> None:
    """Refuse a tab count below 0, a width or height <= 0, or either given without tabs."""
    if isinstance(tabs, bool) or not isinstance(tabs, int) or tabs < 0:
        raise ParameterError("holding_tabs", tabs, "an integer >= 0")
    for name, value in (("holding_tab_width", width), ("holding_tab_height", height)):
        if value is None:
            continue
        if tabs == 0:
            raise ParameterError(name, value, "left out with holding_tabs = 0", "there are no tabs")
        if not (math.isfinite(value) and value > 0.0):
            raise ParameterError(name, value, "> 0 mm")


def tab_size(width: float | None, height: float | None, tool_diameter: float, stock: float, mm: float = 1.0) -> tuple[float, float]:
    """Width and height of the tabs (in the lengths' unit; ``mm``: one mm in it, 1/25.4 in an
    inch program's converted spec): as given, else the tool diameter and
    min(:data:`DEFAULT_TAB_HEIGHT` mm, half the stock)."""
    return (tool_diameter if width is None else width, min(DEFAULT_TAB_HEIGHT * mm, 0.5 * stock) if height is None else height)
