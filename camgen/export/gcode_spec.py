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
from camgen.export.fanuc_settings import check_fanuc_settings
from camgen.export.entry_settings import check_entry_settings, check_tab_settings

if TYPE_CHECKING:  # wire EDM (camgen.export.wire_edm_spec)
    from camgen.export.wire_edm_spec import WireEdmSpec

__all__ = ["BLEND_SHARE", "DIALECTS", "DIRECTIONS", "FIT_SHARE", "MIN_GCODE_CHORD_TOL", "MachiningSpec", "REFIT_SHARE",
           "ROUNDING_SHARE", "SPLINE_MODES", "depth_passes", "rounding_error"]

DIALECTS = ("linuxcnc", "grbl", "wire_edm", "fanuc")
DIRECTIONS = ("climb", "conventional")
SPLINE_MODES = ("lines", "biarcs")

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


@dataclass(frozen=True)
class MachiningSpec:
    """Cutting parameters (mm, mm/min, rev/min).

    ``breakthrough`` (mm, >= 0, default 0.2): the last pass runs this far below the stock
    bottom (Z = -thickness - breakthrough).  An end mill's corner is never perfectly sharp and
    the machine's Z zero is set by touching off, to a few hundredths of a millimetre: a last pass
    exactly at the stock bottom leaves a skin or burr that holds the part to the stock.  Going a
    little deeper (into a spoil board or a gap below the stock) cuts the part free.
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
    spline_mode: str = "biarcs"
    chord_tol: float = 1e-3
    decimals: int = 4
    breakthrough: float = 0.2
    # wire EDM (camgen.export.wire_edm_spec): the wire and its cuts, given with dialect = "wire_edm"
    wire_edm: "WireEdmSpec | None" = None
    # --- fanuc dialect only (camgen.export.fanuc_settings: None = its default) ---
    program_number: int | None = None
    tool_number: int | None = None
    radius_register: int | None = None
    # --- outline passes (camgen.export.gcode_entry, camgen.export.gcode_passes) ---
    entry: str = "helix"
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
        if require_finite("stock_allowance", self.stock_allowance) < 0.0:
            raise ParameterError("stock_allowance", self.stock_allowance, "stock_allowance >= 0 mm")
        check_tab_settings(self.holding_tabs, self.holding_tab_width, self.holding_tab_height)  # camgen.export.gcode_tabs
        if self.wire_edm is None:  # the way down to each pass (camgen.export.gcode_entry)
            check_entry_settings(self.entry, self.ramp_angle, self.tool_radius, self.step_down, self.lead_length)
        if self.spline_mode not in SPLINE_MODES:
            raise ParameterError("spline_mode", self.spline_mode, f"one of {SPLINE_MODES}")
        if self.cutter_compensation and self.dialect == "grbl":
            raise ParameterError("cutter_compensation", True, "false for the grbl dialect", "GRBL has no G41/G42: camgen writes the tool-centre path")
        if self.lead is not None and require_finite("lead", self.lead) <= self.tool_diameter / 2:
            raise ParameterError("lead", self.lead, f"lead > tool radius = {self.tool_diameter / 2:g} mm", "the cutter-compensation entry move must be longer than the tool radius")
        if isinstance(self.decimals, bool) or not isinstance(self.decimals, int) or not 3 <= self.decimals <= 6:
            raise ParameterError("decimals", self.decimals, "an integer 3..6")
        budget = ROUNDING_SHARE * self.chord_tol
        if rounding_error(self.decimals) > budget:
            lowest = next((d for d in range(3, 7) if rounding_error(d) <= budget), None)
            if lowest is None:
                raise ParameterError("chord_tol", self.chord_tol, f">= {MIN_GCODE_CHORD_TOL:.2g} mm for G-code (with machining.decimals = 6)",
                                     f"6 printed decimals may move an arc by {rounding_error(6):.2g} mm, more than "
                                     f"{ROUNDING_SHARE:g} x chord_tol = {budget:.2g} mm")
            valid = f"an integer {lowest}..6"
            raise ParameterError(
                "decimals", self.decimals, valid,
                f"printed coordinates may move an arc by {rounding_error(self.decimals):.2g} mm, more than "
                f"{ROUNDING_SHARE:g} x chord_tol = {budget:.2g} mm",
            )

    @property
    def tool_radius(self) -> float:
        if self.wire_edm is not None:  # wire EDM: the first cut's wire offset is the least concave radius it follows
            return self.wire_edm.offsets[0]
        return self.tool_diameter / 2

    @property
    def lead_length(self) -> float:
        return self.lead if self.lead is not None else self.tool_radius + 3.0

    @property
    def depth(self) -> float:
        """Depth of the last pass below the stock top, mm: thickness + breakthrough."""
        return self.thickness + self.breakthrough



def depth_passes(depth: float, step: float) -> float:
    """Depth passes of a program cutting ``depth`` mm in steps of ``step`` mm, as
    :func:`gcode_program` counts them (inf for a step so small that the count overflows)."""
    ratio = depth / step
    return max(1, math.ceil(ratio - 1e-9)) if math.isfinite(ratio) else math.inf
