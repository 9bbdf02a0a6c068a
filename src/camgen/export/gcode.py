"""G-code (RS274/NGC) for milling the cam profile: LinuxCNC dialect by default, GRBL on request.

The program cuts the outside of the profile in step-down passes to full thickness:

* header ``G21 G90 G17 G40 G49 G80 G94`` (+ ``G64 P<tol>`` path blending tolerance for LinuxCNC);
* by default the **tool-centre path**: the profile offset outward by the tool radius (exact
  arcs stay ``G2/G3``; spline segments become ``G1`` chords within ``chord_tol`` or biarcs
  within ``chord_tol``);
* optionally **cutter compensation** (LinuxCNC only): the profile itself with ``G41.1/G42.1
  D<diameter>`` switched on along the linear lead-in and off (``G40``) along the lead-out;
* climb milling (clockwise around the outside with a clockwise spindle, ``M3``) or conventional;
* a perpendicular linear lead-in and lead-out of length ``lead``, safe Z between passes.

A concave radius of the profile smaller than the tool radius would be gouged: that is a
:class:`GeometryError` naming the cam angle.  Z = 0 is the top face of the stock.
"""
from __future__ import annotations

import io
import math
from dataclasses import dataclass

import numpy as np

from camgen.contour import Arc, Contour
from camgen.errors import (
    GeometryError,
    ParameterError,
    require_finite,
    require_positive,
)

DIALECTS = ("linuxcnc", "grbl")
DIRECTIONS = ("climb", "conventional")
SPLINE_MODES = ("lines", "biarcs")


@dataclass(frozen=True)
class MachiningSpec:
    """Cutting parameters (mm, mm/min, rev/min)."""

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

    def __post_init__(self) -> None:
        for name in ("tool_diameter", "thickness", "step_down", "safe_z", "feed", "plunge_feed", "spindle_rpm", "chord_tol"):
            require_positive(name, getattr(self, name), "")
        if self.direction not in DIRECTIONS:
            raise ParameterError("direction", self.direction, f"one of {DIRECTIONS}")
        if self.dialect not in DIALECTS:
            raise ParameterError("dialect", self.dialect, f"one of {DIALECTS}")
        if self.spline_mode not in SPLINE_MODES:
            raise ParameterError("spline_mode", self.spline_mode, f"one of {SPLINE_MODES}")
        if self.cutter_compensation and self.dialect == "grbl":
            raise ParameterError("cutter_compensation", True, "false for the grbl dialect", "GRBL has no G41/G42: camgen writes the tool-centre path")
        if self.lead is not None and require_finite("lead", self.lead) <= self.tool_diameter / 2:
            raise ParameterError("lead", self.lead, f"lead > tool radius = {self.tool_diameter / 2:g} mm", "the cutter-compensation entry move must be longer than the tool radius")
        if isinstance(self.decimals, bool) or not isinstance(self.decimals, int) or not 3 <= self.decimals <= 6:
            raise ParameterError("decimals", self.decimals, "an integer 3..6")

    @property
    def tool_radius(self) -> float:
        return self.tool_diameter / 2

    @property
    def lead_length(self) -> float:
        return self.lead if self.lead is not None else self.tool_radius + 3.0


def tool_path(contour: Contour, spec: MachiningSpec) -> Contour:
    """The contour the tool centre follows: ``contour`` offset outward by the tool radius.

    Raises :class:`GeometryError` where a concave radius is smaller than the tool radius.
    """
    try:
        return contour.offset(spec.tool_radius, spline_tol=min(1e-6, spec.chord_tol / 10))
    except GeometryError as exc:
        raise GeometryError(
            f"a tool of diameter {spec.tool_diameter:g} mm would gouge the profile ({exc}); "
            "use a tool whose radius is below the smallest concave radius"
        ) from None


def _primitives(contour: Contour, spec: MachiningSpec) -> list[tuple]:
    """Counter-clockwise primitives: ('arc', Arc) or ('lines', points (n, 2) excluding the start)."""
    if spec.spline_mode == "biarcs" and any(not isinstance(s, Arc) for s in contour.segments):
        from camgen.biarc import to_arc_spline

        contour = to_arc_spline(contour, spec.chord_tol)
    out: list[tuple] = []
    for seg in contour.segments:
        if isinstance(seg, Arc):
            out.append(("arc", seg))
        else:
            u = np.append(seg.flatten_params(spec.chord_tol)[1:], 1.0)
            out.append(("lines", seg.point(u)))
    return out


def _reverse(prims: list[tuple], start: np.ndarray) -> list[tuple]:
    """The same closed path travelled the other way round (clockwise), from the same start."""
    out: list[tuple] = []
    ends = [start] + [p[1].end_point if p[0] == "arc" else p[1][-1] for p in prims[:-1]]
    for (kind, item), begin in zip(reversed(prims), reversed(ends)):
        if kind == "arc":
            out.append(("arc", Arc(item.center, item.radius, item.start_angle + item.sweep, -item.sweep)))
        else:
            out.append(("lines", np.vstack([item[-2::-1], begin[None]])))
    return out


def _comment(text: str) -> str:
    """An RS274 comment: parentheses cannot nest, so they are replaced in the text."""
    return "(" + text.replace("(", "[").replace(")", "]") + ")"


def gcode_program(contour: Contour, spec: MachiningSpec, cam: str = "cam", scene: str = "") -> str:
    """RS274/NGC program text that mills ``contour`` (the cam profile) to ``spec.thickness``."""
    from camgen import __version__

    path = contour if spec.cutter_compensation else tool_path(contour, spec)
    if spec.cutter_compensation:
        tool_path(contour, spec)  # the controller offsets the path: still refuse a gouge
    prims = _primitives(path, spec)
    start = path.evaluate(np.array([0.0]))[0]
    normal = path.normal(np.array([0.0]))[0]
    climb = spec.direction == "climb"
    if climb:
        prims = _reverse(prims, start)
    lead_point = start + spec.lead_length * normal
    d = spec.decimals
    num = f"%.{d}f"

    def xy(p: np.ndarray) -> str:
        return f"X{p[0]:.{d}f} Y{p[1]:.{d}f}"

    moves = io.StringIO()
    current = start
    for kind, item in prims:
        if kind == "arc":
            end = item.end_point
            ij = np.asarray(item.center) - current
            word = "G3" if item.sweep > 0 else "G2"
            moves.write(f"{word} {xy(end)} I{ij[0]:.{d}f} J{ij[1]:.{d}f}\n")
            current = end
        else:
            np.savetxt(moves, item + 0.0, fmt=f"G1 X{num} Y{num}")
            current = item[-1]
    contour_moves = moves.getvalue()

    n_passes = max(1, math.ceil(spec.thickness / spec.step_down - 1e-9))
    depths = -np.minimum(spec.step_down * np.arange(1, n_passes + 1), spec.thickness)
    # G41: tool left of the travel direction = outside of a clockwise (climb) path
    comp = ("G41.1" if climb else "G42.1") + f" D{spec.tool_diameter:.{d}f} " if spec.cutter_compensation else ""
    uncomp = "G40 " if spec.cutter_compensation else ""
    mode = "cutter compensation G41.1/G42.1 on the profile" if spec.cutter_compensation else "tool-centre path = profile offset by the tool radius"
    lines = [
        _comment(f"camgen {__version__}: cam '{cam}'" + (f", scene '{scene}'" if scene else "")),
        _comment(f"units mm; tool diameter {spec.tool_diameter:g}; {mode}; {spec.direction} milling, outside contour"),
        _comment(f"stock top Z0; depth {spec.thickness:g} in {n_passes} passes of <= {spec.step_down:g}; chord/biarc tolerance {spec.chord_tol:g}"),
        "G21 G90 G17 G40 G49 G80 G94",
    ]
    if spec.dialect == "linuxcnc":
        lines.append(f"G64 P{spec.chord_tol:.{d}f}")
    lines += [f"G0 Z{spec.safe_z:.{d}f}", f"M3 S{spec.spindle_rpm:.0f}"]
    body = ["\n".join(lines) + "\n"]
    for k, z in enumerate(depths, 1):
        body.append(
            f"(pass {k} of {n_passes}: Z{z:.{d}f})\n"
            f"G0 {xy(lead_point)}\n"
            f"G1 Z{z:.{d}f} F{spec.plunge_feed:.0f}\n"
            f"{comp}G1 {xy(start)} F{spec.feed:.0f}\n"
            f"{contour_moves}"
            f"{uncomp}G1 {xy(lead_point)}\n"
            f"G0 Z{spec.safe_z:.{d}f}\n"
        )
    body.append("M5\nM2\n")
    return "".join(body)
