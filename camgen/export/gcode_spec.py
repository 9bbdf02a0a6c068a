"""The machining settings of a G-code program and its error budget (mm, mm/min, rev/min).

:class:`MachiningSpec` is the ``[machining]`` table read (plus the run's chord tolerance); the
shares of ``chord_tol`` split the path tolerance between the fit of spline segments, the
offset refit, the printed decimals and LinuxCNC's path blending (:mod:`camgen.export.gcode`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from camgen.errors import ParameterError, require_finite, require_positive
from camgen.export.bore_settings import check_bore_settings
from camgen.export.fanuc_settings import check_fanuc_settings
from camgen.export.entry_settings import check_entry_settings, check_tab_settings

if TYPE_CHECKING:  # wire EDM (camgen.export.wire_edm_spec)
    from camgen.export.wire_edm_spec import WireEdmSpec

__all__ = ["AUTO_DECIMALS", "BLEND_SHARE", "DEFAULT_DECIMALS", "DIALECTS", "DIRECTIONS", "FEED_DECIMALS_INCH", "FIT_SHARE", "LEAD_STYLES",
           "MIN_GCODE_CHORD_TOL", "MIN_LEAD_RADIUS", "MM_PER_INCH", "MachiningSpec", "REFIT_SHARE", "ROUNDING_SHARE", "SPLINE_MODES", "UNITS",
           "depth_passes", "least_decimals", "rounding_error"]

DIALECTS = ("linuxcnc", "grbl", "wire_edm", "fanuc")
DIRECTIONS = ("climb", "conventional")
SPLINE_MODES = ("lines", "biarcs")
#: Lead-in and lead-out: tangent quarter arcs after straight moves, or straight tangent lines
#: (camgen.export.gcode_leads).
LEAD_STYLES = ("arc", "line")
#: Least lead-arc radius (mm): 100 units of the last decimal at the coarsest 3 decimals, so the
#: quarter arc's chord is >= 141 printed units, an arc no control can read as a full circle
#: (the rule of the contour's arcs).
MIN_LEAD_RADIUS = 0.1
#: Units of the program (``machining.units``; the scene keys stay in mm): mm (G21) or inch (G20).
UNITS = ("mm", "inch")
#: Millimetres per inch (exact, by definition: 1959 international yard and pound agreement).
MM_PER_INCH = 25.4
#: ``decimals`` left to its default: 4 in a mm program; in an inch program the least that keeps
#: the rounding share of the budget (:func:`least_decimals`; 6 with the default chord_tol 1e-3 mm).
AUTO_DECIMALS = 0
DEFAULT_DECIMALS = 4
#: Decimals of the feeds (F, in/min) of an inch program: 0.005 in/min = 0.127 mm/min, finer than
#: the whole mm/min of a mm program.
FEED_DECIMALS_INCH = 2

#: Shares of ``chord_tol`` (they sum to 1): fit of spline segments by biarcs or chords,
#: offset refit of spline segments, printed decimals, LinuxCNC path blending (G64 P).
FIT_SHARE = 0.6
REFIT_SHARE = 0.05
ROUNDING_SHARE = 0.25
BLEND_SHARE = 0.1


def rounding_error(decimals: int) -> float:
    """Largest distance (mm) between a printed arc and the exact one: centre and both ends are
    each rounded by up to ``sqrt(2)/2 * 10^-decimals``, so every point of the arc moves by up to
    three times that (radius error from the ends and centre, plus the centre shift)."""
    return 3.0 * math.sqrt(2.0) / 2.0 * 10.0 ** (-decimals)


#: The finest chord tolerance (mm) the G-code's error budget allows: 6 printed decimals.
MIN_GCODE_CHORD_TOL = rounding_error(6) / ROUNDING_SHARE


def least_decimals(budget: float, unit: float = 1.0) -> int | None:
    """The least printed decimals 3..6 whose rounding (:func:`rounding_error`, in program units
    of ``unit`` mm each) is within ``budget`` mm; None when 6 are not enough."""
    return next((d for d in range(3, 7) if rounding_error(d) * unit <= budget), None)


@dataclass(frozen=True)
class MachiningSpec:
    """Cutting parameters (mm, mm/min, rev/min).

    ``breakthrough`` (mm, >= 0, default 0.2): the last pass runs this far below the stock
    bottom (Z = -thickness - breakthrough).  An end mill's corner is never perfectly sharp and
    the machine's Z zero is set by touching off, to a few hundredths of a millimetre: a last pass
    exactly at the stock bottom leaves a skin or burr that holds the part to the stock.  Going a
    little deeper (into a spoil board or a gap below the stock) cuts the part free.

    ``units`` (``"mm"`` or ``"inch"``): the program's units; the spec's lengths and feeds stay in
    mm and mm/min (the scene's), an inch program is written from a converted copy
    (:mod:`camgen.export.gcode_units`).  ``decimals`` counts the program's decimals (of mm or of
    inches): its rounding (:func:`rounding_error`, times 25.4 mm for an inch) must stay within
    ``ROUNDING_SHARE * chord_tol``; left out (:data:`AUTO_DECIMALS`) it is 4 in mm and in inches
    the least that keeps that budget (6 with the default chord_tol 1e-3 mm).
    """

    tool_diameter: float = 6.0
    thickness: float = 10.0
    step_down: float = 2.0
    safe_z: float = 5.0
    feed: float = 400.0
    plunge_feed: float = 100.0
    spindle_rpm: float = 8000.0
    direction: str = "climb"
    dialect: str = "linuxcnc"
    cutter_compensation: bool = False
    lead: float | None = None
    lead_style: str = "arc"
    lead_radius: float | None = None
    spline_mode: str = "biarcs"
    chord_tol: float = 1e-3
    decimals: int = AUTO_DECIMALS
    breakthrough: float = 0.2
    # wire EDM (camgen.export.wire_edm_spec): the wire and its cuts, given with dialect = "wire_edm"
    wire_edm: "WireEdmSpec | None" = None
    # --- fanuc dialect only (camgen.export.fanuc_settings: None = its default) ---
    program_number: int | None = None
    tool_number: int | None = None
    radius_register: int | None = None
    # --- the bore and keyway (camgen.export.gcode_bore: None = its default) ---
    bore_operation: str | None = None
    bore_tool_diameter: float | None = None
    bore_tool_number: int | None = None
    # --- program units (camgen.export.gcode_units): "inch" writes G20 and every length in inches ---
    units: str = "mm"
    #: True: the lengths and feeds are already in the program's units (a copy made by
    #: camgen.export.gcode_units.program_spec for the writers; not a scene key)
    converted: bool = False
    # --- outline passes (camgen.export.gcode_entry, camgen.export.gcode_passes) ---
    entry: str | None = None  # None: the helix, else a ramp, else the plunge (camgen.export.entry_settings)
    ramp_angle: float = math.radians(3.0)
    stock_allowance: float = 0.0
    holding_tabs: int = 0
    holding_tab_width: float | None = None
    holding_tab_height: float | None = None

    def __post_init__(self) -> None:
        for name in ("tool_diameter", "thickness", "step_down", "safe_z", "feed", "plunge_feed", "spindle_rpm", "chord_tol"):
            require_positive(name, getattr(self, name), "")
        if require_finite("breakthrough", self.breakthrough) < 0.0:
            raise ParameterError("breakthrough", self.breakthrough, "breakthrough >= 0 mm")
        if self.direction not in DIRECTIONS:
            raise ParameterError("direction", self.direction, f"one of {DIRECTIONS}")
        if self.dialect not in DIALECTS:
            raise ParameterError("dialect", self.dialect, f"one of {DIALECTS}")
        if (self.dialect == "wire_edm") != (self.wire_edm is not None):  # wire EDM: its spec exactly with its dialect
            if self.wire_edm is not None:
                raise ParameterError("dialect", self.dialect, '"wire_edm" for a wire spec')
            from camgen.export.wire_edm_spec import WireEdmSpec

            object.__setattr__(self, "wire_edm", WireEdmSpec())
        check_fanuc_settings(self.dialect, self.program_number, self.tool_number, self.radius_register)  # fanuc dialect
        check_bore_settings(self.dialect, self.tool_number, self.bore_operation, self.bore_tool_diameter,
                            self.bore_tool_number, self.wire_edm is None or self.wire_edm.wire_compensation)  # the bore and keyway (camgen.export.bore_settings)
        if require_finite("stock_allowance", self.stock_allowance) < 0.0:
            raise ParameterError("stock_allowance", self.stock_allowance, "stock_allowance >= 0 mm")
        check_tab_settings(self.holding_tabs, self.holding_tab_width, self.holding_tab_height)  # camgen.export.gcode_tabs
        if self.wire_edm is None:  # the way down to each pass (camgen.export.gcode_entry)
            object.__setattr__(self, "entry", check_entry_settings(self.entry, self.ramp_angle, self.tool_radius, self.step_down,
                                                                   self.lead_length))
        if self.spline_mode not in SPLINE_MODES:
            raise ParameterError("spline_mode", self.spline_mode, f"one of {SPLINE_MODES}")
        if self.cutter_compensation and self.dialect == "grbl":
            raise ParameterError("cutter_compensation", True, "false for the grbl dialect", "GRBL has no G41/G42: camgen writes the tool-centre path")
        if self.lead is not None and require_finite("lead", self.lead) <= self.tool_diameter / 2:
            raise ParameterError("lead", self.lead, f"lead > tool radius = {self.tool_diameter / 2:g} mm", "the cutter-compensation entry move must be longer than the tool radius")
        if self.units not in UNITS:
            raise ParameterError("units", self.units, f"one of {UNITS}")
        if isinstance(self.decimals, bool) or not isinstance(self.decimals, int) or not (3 <= self.decimals <= 6 or self.decimals == AUTO_DECIMALS):
            raise ParameterError("decimals", self.decimals, "an integer 3..6")
        if self.lead_style not in LEAD_STYLES:  # the leads (camgen.export.gcode_leads)
            raise ParameterError("lead_style", self.lead_style, f"one of {LEAD_STYLES}")
        if self.lead_radius is not None and not self.converted and not require_finite("lead_radius", self.lead_radius) >= MIN_LEAD_RADIUS:
            raise ParameterError("lead_radius", self.lead_radius, f"{MIN_LEAD_RADIUS:g} <= lead_radius mm",
                                 "a shorter lead arc could be read as a full circle once printed")
        unit = self.program_unit  # a program unit in the spec's length unit
        budget = ROUNDING_SHARE * self.chord_tol
        if self.decimals == AUTO_DECIMALS:  # 4 in mm; in inches the least that keeps the budget
            auto = DEFAULT_DECIMALS if self.units == "mm" else least_decimals(budget, unit)
            object.__setattr__(self, "decimals", 6 if auto is None else auto)
        if rounding_error(self.decimals) * unit > budget and not self.converted:
            lowest = least_decimals(budget, unit)
            inch = " in inches" if unit != 1.0 else ""
            if lowest is None:
                least_tol = rounding_error(6) * unit / ROUNDING_SHARE
                raise ParameterError("chord_tol", self.chord_tol, f">= {least_tol:.2g} mm for G-code{inch} (with machining.decimals = 6)",
                                     f"6 printed decimals{inch} may move an arc by {rounding_error(6) * unit:.2g} mm, more than "
                                     f"{ROUNDING_SHARE:g} x chord_tol = {budget:.2g} mm")
            valid = f"an integer {lowest}..6"
            raise ParameterError(
                "decimals", self.decimals, valid,
                f"printed coordinates{inch} may move an arc by {rounding_error(self.decimals) * unit:.2g} mm, more than "
                f"{ROUNDING_SHARE:g} x chord_tol = {budget:.2g} mm",
            )

    @property
    def program_unit(self) -> float:
        """A unit of the program in the spec's length unit: 25.4 for an inch program of a spec in
        mm (the scene's), else 1 (a mm program, or a spec already converted to inches)."""
        return MM_PER_INCH if self.units == "inch" and not self.converted else 1.0

    @property
    def units_word(self) -> str:
        """The program's units word: G20 (inch) or G21 (mm)."""
        return "G20" if self.units == "inch" else "G21"

    @property
    def feed_decimals(self) -> int:
        """Decimals of the printed feeds: whole mm/min, or :data:`FEED_DECIMALS_INCH` in/min."""
        return FEED_DECIMALS_INCH if self.units == "inch" else 0

    @property
    def tool_radius(self) -> float:
        if self.wire_edm is not None:  # wire EDM: the first cut's wire offset is the least concave radius it follows
            return self.wire_edm.offsets[0]
        return self.tool_diameter / 2

    @property
    def lead_length(self) -> float:
        return self.lead if self.lead is not None else self.tool_radius + 3.0

    @property
    def lead_arc_radius(self) -> float:
        """Radius (mm) of the tool centre's lead arcs (``lead_style = "arc"``): ``lead_radius``,
        by default the tool radius + 3 mm."""
        return self.lead_radius if self.lead_radius is not None else self.tool_radius + 3.0

    @property
    def depth(self) -> float:
        """Depth of the last pass below the stock top, mm: thickness + breakthrough."""
        return self.thickness + self.breakthrough



def depth_passes(depth: float, step: float) -> float:
    """Depth passes of a program cutting ``depth`` mm in steps of ``step`` mm, as
    :func:`gcode_program` counts them (inf for a step so small that the count overflows)."""
    ratio = depth / step
    return max(1, math.ceil(ratio - 1e-9)) if math.isfinite(ratio) else math.inf
