"""The wire-EDM settings of a program (``dialect = "wire_edm"`` in ``[machining]``), mm and mm/min.

:class:`WireEdmSpec` is the wire, its spark gap and the cuts: one first cut and ``skim_cuts``
skims, each leaving an allowance, the last one none.  The wire offset of cut ``k`` (the
distance from the wire's centre to the profile the cut leaves) is

    offset_k = wire radius + spark gap + allowance_k            (allowance of the last cut = 0)

and is held in the control's register ``D<k>`` (the program's header lists the values).
:func:`wire_edm_table` turns the parsed ``[machining]`` table into the spec the machining spec
carries, refusing the milling keys that have no meaning for a wire (a spindle, depth passes).
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from functools import lru_cache
from typing import Any

from camgen.errors import ParameterError, require_finite
from camgen.keynames import renamed
from camgen.schema import Count, Flag, Key, Number, NumberList, Parsed

__all__ = ["ALLOWANCE_RATIO", "FIRST_ALLOWANCE", "MAX_SKIM_CUTS", "MILLING_KEYS", "WIRE_EDM", "WireEdmSpec", "default_allowances",
           "wire_edm_keys", "wire_edm_table"]

#: The dialect's name in ``machining.dialect``.
WIRE_EDM = "wire_edm"
#: Most skim cuts after the first cut (one register each: D1 .. D10).
MAX_SKIM_CUTS = 9
#: Default allowance (mm) the first cut leaves when skims follow, and the ratio of each next
#: cut's allowance to the one before (0.1, 0.02, 0.004, ... mm).
FIRST_ALLOWANCE = 0.1
ALLOWANCE_RATIO = 0.2
#: The [machining] keys of milling that a wire program has no use for (refused with wire_edm).
#: (scene key -> the machining spec's field)
MILLING_KEYS = {"tool_diameter_mm": "tool_diameter", "step_down_mm": "step_down", "safe_z_mm": "safe_z", "feed_mm_per_min": "feed",
                "plunge_feed_mm_per_min": "plunge_feed", "spindle_rpm": "spindle_rpm", "direction": "direction",
                "cutter_compensation": "cutter_compensation", "lead_mm": "lead", "breakthrough_mm": "breakthrough",
                "lead_style": "lead_style", "lead_radius_mm": "lead_radius",

                "entry": "entry", "ramp_angle_deg": "ramp_angle", "stock_allowance_mm": "stock_allowance", "holding_tabs": "holding_tabs",
                "holding_tab_width_mm": "holding_tab_width", "holding_tab_height_mm": "holding_tab_height"}


def default_allowances(skim_cuts: int) -> tuple[float, ...]:
    """Allowances (mm) of the cuts before the last: ``FIRST_ALLOWANCE * ALLOWANCE_RATIO^(k-1)``."""
    return tuple(FIRST_ALLOWANCE * ALLOWANCE_RATIO**k for k in range(skim_cuts))


@dataclass(frozen=True)
class WireEdmSpec:
    """The wire and its cuts (mm, mm/min).

    ``cut_allowances``: the allowance each cut before the last leaves (``skim_cuts`` values,
    falling, > 0); the last cut leaves none.  ``start_hole_offset``: the start hole's centre lies
    this far outside the profile's tangent line at the start point and this far back along it;
    ``tab_width``: the stretch of the profile (measured along it) that every cut leaves uncut
    until the last cut, after its stop, cuts it off.  ``wire_compensation``: program the profile
    with ``G41 D<k>`` (True) or the wire-centre path of every cut (False,
    :mod:`camgen.export.wire_edm_centre`).
    """

    wire_diameter: float = 0.25
    spark_gap: float = 0.02
    skim_cuts: int = 2
    cut_allowances: tuple[float, ...] | None = None
    start_hole_diameter: float = 2.0
    start_hole_offset: float = 5.0
    tab_width: float = 3.0
    wire_feed: float = 3.0
    wire_compensation: bool = True

    def __post_init__(self) -> None:
        if self.cut_allowances is None:
            object.__setattr__(self, "cut_allowances", default_allowances(self.skim_cuts))
        allowances = self.allowances[:-1]
        if len(allowances) != self.skim_cuts:
            raise ParameterError("cut_allowances", list(allowances), f"a list of skim_cuts = {self.skim_cuts} allowances",
                                 "one allowance per cut before the last (the last leaves none)")
        if any(not require_finite("cut_allowances", a) > 0.0 for a in allowances) or any(b >= a for a, b in zip(allowances, allowances[1:])):
            raise ParameterError("cut_allowances", list(allowances), "positive and falling (each cut leaves less than the one before)")
        least = self.start_hole_diameter / 2.0 + self.offsets[0]
        if not self.start_hole_offset > least:
            raise ParameterError("start_hole_offset", self.start_hole_offset,
                                 f"> start hole radius + first cut's offset = {least:.4g} mm",
                                 "the hole must stay clear of the part and the compensation's entry move longer than the offset")

    @property
    def allowances(self) -> tuple[float, ...]:
        """Allowance of every cut (mm), the last one 0."""
        assert self.cut_allowances is not None
        return tuple(self.cut_allowances) + (0.0,)

    @property
    def cuts(self) -> int:
        return self.skim_cuts + 1

    @property
    def offsets(self) -> tuple[float, ...]:
        """Wire offset of every cut (mm): wire radius + spark gap + allowance."""
        base = self.wire_diameter / 2.0 + self.spark_gap
        return tuple(base + a for a in self.allowances)

    @property
    def kerf_radius(self) -> float:
        """Half the kerf width (mm): wire radius + spark gap."""
        return self.wire_diameter / 2.0 + self.spark_gap


def _d(name: str) -> Any:
    """The default of field ``name`` of :class:`WireEdmSpec` (one owner for every default)."""
    return {f.name: f.default for f in fields(WireEdmSpec)}[name]


@lru_cache(maxsize=None)  # constants only: made once
def wire_edm_keys() -> tuple[Key, ...]:
    """The ``[machining]`` keys of the wire-EDM dialect (each only with ``dialect = "wire_edm"``)."""
    only = {"dialect": (WIRE_EDM,)}
    return (
        Key("wire_diameter_mm", Number("mm", 0.02, 1.0), "Wire-EDM: diameter of the wire.", ("gcode",),
            default=_d("wire_diameter"), requires=only),
        Key("spark_gap_mm", Number("mm", 0.0, 0.2), "Wire-EDM: spark gap (overcut) on each side of the wire; the wire offset of "
            "cut k is wire radius + spark gap + allowance of cut k, in register D<k>.", ("gcode",), default=_d("spark_gap"), requires=only),
        Key("skim_cuts", Count(0, MAX_SKIM_CUTS), "Wire-EDM: skim cuts after the first cut (registers D1 .. D<skim_cuts + 1>).",
            ("gcode",), default=_d("skim_cuts"), requires=only),
        Key("cut_allowances_mm", NumberList(Number("mm", 1e-4, 2.0), min_items=1, max_items=MAX_SKIM_CUTS),
            "Wire-EDM: the allowance each cut before the last leaves (skim_cuts values, falling; the last cut leaves none; "
            f"default {FIRST_ALLOWANCE:g} mm for the first cut and {ALLOWANCE_RATIO:g} of the one before for each next).", ("gcode",),
            requires=only),
        Key("start_hole_diameter_mm", Number("mm", 0.1, 20.0), "Wire-EDM: diameter of the start hole the wire is "
            "threaded in (drilled before; its centre is in the header); with the bore cut by the wire, its start hole at the axis too, "
            "so below the bore radius.", ("gcode",), default=_d("start_hole_diameter"), requires=only),
        Key("start_hole_offset_mm", Number("mm", 1.0, 1000.0), "Wire-EDM: the start hole's centre lies this far "
            "outside the profile's tangent line at the start point and this far back along it; the wire enters along the normal, "
            "then along the tangent (> hole radius + first cut's offset).", ("gcode",), default=_d("start_hole_offset"), requires=only),
        Key("tab_width_mm", Number("mm", 0.1, 100.0), "Wire-EDM: length of the profile (measured along it, ending at "
            "the start point) every cut leaves uncut; the last cut stops before it (M00) and then cuts it off: the part drops. With "
            "the bore cut by the wire, its slug's tab too: shorter than the bore wall from the keyway to the start point.",
            ("gcode",), default=_d("tab_width"), requires=only),
        Key("wire_feed_mm_per_min", Number("mm/min", 0.01, 1e4), "Wire-EDM: feed of the cuts (the control's servo "
            "may cut slower).", ("gcode",), default=_d("wire_feed"), attr="wire_feed", requires=only),
        Key("wire_compensation", Flag(), "Wire-EDM: program the profile with the control's wire offset G41 D<k> (true), or "
            "(false) the wire-centre path of every cut: the profile offset by its wire offset, exact arcs, no G41/G42 and no "
            "register (the header says which).", ("gcode",), default=_d("wire_compensation"), requires=only),
    )


def wire_edm_table(parsed: Parsed) -> Parsed:
    """The parsed ``[machining]`` table for :class:`camgen.export.gcode_spec.MachiningSpec`: the
    wire keys taken out and, for ``dialect = "wire_edm"``, made into its ``wire_edm`` spec; a
    milling key given with that dialect is refused naming it."""
    keys = wire_edm_keys()
    wire_fields = {k.field for k in keys}
    out = Parsed({name: value for name, value in parsed.items() if name not in wire_fields})
    out.given, out.tool_limit = parsed.given, parsed.tool_limit
    if parsed.get("dialect") != WIRE_EDM:
        return out
    given = parsed.given
    for name, attr in MILLING_KEYS.items():
        if name in given:
            raise ParameterError(f"machining.{name}", parsed.get(attr), 'left out with dialect = "wire_edm"',
                                 "it is a milling setting: a wire has no tool, spindle, depth passes or Z moves")
    wire = {k.field: parsed[k.field] for k in keys if k.field in parsed}
    if "cut_allowances" in wire:
        wire["cut_allowances"] = tuple(wire["cut_allowances"])
    out["wire_edm"] = renamed("machining", keys, lambda: WireEdmSpec(**wire))  # errors name the scene key
    return out


