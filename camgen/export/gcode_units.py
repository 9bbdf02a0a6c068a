"""Inch programs (``machining.units = "inch"``): the one place where lengths become inches.

The scene keys stay in mm and mm/min.  An inch program is the program of the same writers
(:func:`camgen.export.gcode.gcode_program`, :func:`camgen.export.wire_edm.wire_edm_program`)
run on the geometry scaled by ``1 / 25.4`` (arcs: centre and radius; splines: their
coefficients; pockets: walls, centres, width and depth) and on a copy of the spec whose lengths
(tool, thickness, steps, safe Z, lead, breakthrough, chord tolerance; the wire's diameter, gap,
allowances, start hole and tab) and feeds (mm/min -> in/min) are divided by 25.4
(:func:`program_spec`, ``converted = True``).  A similarity keeps every relation the writers rely
on (tangency, offsets by the tool radius, the error budget's shares of ``chord_tol``, the G64 P
blend, all in inches), so only the units word (``G20``), the feed decimals
(:data:`camgen.export.gcode_spec.FEED_DECIMALS_INCH`) and the header's units note differ.

A barrel cam's groove (:func:`camgen.export.gcode_barrel.barrel_program`) is scaled the same
way (:class:`ScaledGroove`: its roller axis' height and offset, radii and half width); A stays
in degrees and the inverse-time feeds (feed over a move's length, 1/min) do not change.  A
barrel cam's rib (:func:`camgen.export.gcode_barrel_rib.rib_program`) is scaled as a whole
(:func:`scaled_rib`: a real :class:`~camgen.synthesis.barrel.BarrelRib` whose every length is
times ``s``, a translating follower's lift too, :class:`ScaledLift`), so whatever the rib writer
reads of it, nested or derived (the rollers' grooves and offset, the pitch line's extremes), is
in inches.

Decimals count inches: ``decimals`` rounds each printed value by up to ``0.5 10^-decimals`` in,
so the spec (in mm) checks ``rounding_error(decimals) x 25.4 <= ROUNDING_SHARE x chord_tol``
(:class:`camgen.export.gcode_spec.MachiningSpec`).  A refusal raised while writing the inch
program (a tool too wide for a pocket, a program too long) is raised again from the mm program,
so that its values are the scene's mm.
"""
from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING, Any, Callable, NoReturn, Sequence

import numpy as np

from camgen.contour import Arc, Contour, Spline
from camgen.errors import GeometryError, ParameterError
from camgen.export.gcode_moves import comment
from camgen.export.gcode_spec import MM_PER_INCH, MachiningSpec

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.kinds.base import Pocket

__all__ = ["ScaledGroove", "ScaledLift", "Writer", "groove_in_program_units", "in_program_units", "program_spec", "scaled_body", "scaled_contour",
           "scaled_pocket", "scaled_rib", "units_line", "units_note"]

#: A program writer: (contour, spec, cam, scene, thickness, pockets, cam body) -> program text.
Writer = Callable[[Contour, MachiningSpec, str, str, "float | None", "Sequence[Pocket]", "BodySpec | None"], str]

#: The spec's lengths (mm) and feeds (mm/min) that an inch program has in inches (and in/min).
_LENGTHS = ("tool_diameter", "thickness", "step_down", "safe_z", "feed", "plunge_feed", "chord_tol", "breakthrough", "stock_allowance")
#: Lengths (mm) that may be left out (None: a default the writers derive from the converted ones).
_OPTIONAL_LENGTHS = ("bore_tool_diameter", "holding_tab_width", "holding_tab_height")
_WIRE_LENGTHS = ("wire_diameter", "spark_gap", "start_hole_diameter", "start_hole_offset", "tab_width", "wire_feed")


def program_spec(spec: MachiningSpec) -> MachiningSpec:
    """``spec`` with its lengths and feeds in program units (``converted``): divided by 25.4 for
    an inch program; the lead and the lead arcs' radius given explicitly (their defaults, tool radius + 3 mm, is in mm)."""
    if spec.program_unit == 1.0:
        return spec
    s = 1.0 / spec.program_unit
    changes: dict[str, Any] = {name: getattr(spec, name) * s for name in _LENGTHS}
    if spec.wire_edm is not None:
        wire = spec.wire_edm
        assert wire.cut_allowances is not None
        changes["wire_edm"] = dataclasses.replace(wire, cut_allowances=tuple(a * s for a in wire.cut_allowances),
                                                  **{name: getattr(wire, name) * s for name in _WIRE_LENGTHS})
    else:
        changes["lead"] = spec.lead_length * s
        # the bore's own tool (camgen.export.gcode_bore), the holding tabs' size (camgen.export.gcode_tabs)
        changes.update({name: getattr(spec, name) * s for name in _OPTIONAL_LENGTHS if getattr(spec, name) is not None})
        changes["lead_radius"] = spec.lead_arc_radius * s  # the lead arcs' radius (camgen.export.gcode_leads), default in mm too
    return dataclasses.replace(spec, converted=True, **changes)


def _scaled_segment(seg: Arc | Spline, s: float) -> Arc | Spline:
    if isinstance(seg, Arc):
        return Arc((seg.center[0] * s, seg.center[1] * s), seg.radius * s, seg.start_angle, seg.sweep)
    return Spline(seg.breaks, np.asarray(seg.coeffs) * s)  # P(t) scaled: every coefficient


def scaled_contour(contour: Contour, s: float) -> Contour:
    """``contour`` scaled by ``s`` about the origin (the cam axis): the same parameters."""
    return Contour([_scaled_segment(seg, s) for seg in contour.segments])


def scaled_pocket(pocket: "Pocket", s: float) -> "Pocket":
    """``pocket`` scaled by ``s``: walls, centre (closed or open), width, depth, clearance."""
    walls = tuple(dataclasses.replace(w, contour=scaled_contour(w.contour, s)) for w in pocket.walls)
    return dataclasses.replace(
        pocket, walls=walls, depth=pocket.depth * s, clearance=pocket.clearance * s,
        width=None if pocket.width is None else pocket.width * s,
        centre=None if pocket.centre is None else scaled_contour(pocket.centre, s),
        centre_path=None if pocket.centre_path is None else tuple(_scaled_segment(seg, s) for seg in pocket.centre_path))


def scaled_body(body: "BodySpec | None", s: float) -> "BodySpec | None":
    """``body`` (bore and keyway) scaled by ``s``: thickness, bore, keyway width and depth, least
    wall; the keyway's angle unchanged."""
    if body is None:
        return None
    return dataclasses.replace(body, thickness=body.thickness * s, bore_diameter=body.bore_diameter * s,
                               keyway_width=body.keyway_width * s, keyway_depth=body.keyway_depth * s, min_wall=body.min_wall * s)


def units_note(spec: MachiningSpec) -> str:
    """The header's units word of a program written from ``spec``: ``units mm`` or ``units inch``
    (an inch program also has :func:`units_line` after that header line)."""
    return f"units {spec.units}"


def units_line(spec: MachiningSpec) -> str:
    """The comment line an inch program's header has after its units: lengths, feeds and the
    path tolerance in both units (``spec`` in program units)."""
    return comment(f"units inch [G20]: every length in inches, feeds in in/min [{spec.feed_decimals} decimals]: the scene's mm / "
                   f"{MM_PER_INCH:g}; path tolerance {spec.chord_tol:.6g} in = {spec.chord_tol * MM_PER_INCH:.6g} mm; "
                   f"{spec.decimals} decimals of an inch")


def _with_units_line(program: str, spec: MachiningSpec) -> str:
    """``program`` with :func:`units_line` after the first header line that says ``units inch``
    (Fanuc-safe in a Fanuc program)."""
    line = units_line(spec)
    if spec.dialect == "fanuc":
        from camgen.export.gcode_fanuc import fanuc_comment

        line = f"({fanuc_comment(line[1:-1])})"
    lines = program.split("\n")
    k = next(i for i, text in enumerate(lines) if text.startswith("(") and "units inch" in text.lower())
    return "\n".join(lines[:k + 1] + [line] + lines[k + 1:])


def _in_mm(spec: MachiningSpec) -> MachiningSpec:
    """``spec`` writing a mm program, with 6 decimals (finer than any inch program's in mm)."""
    return dataclasses.replace(spec, units="mm", decimals=6)


def _refuse_in_mm(write_mm: Callable[[], str], exc: Exception) -> NoReturn:
    """Raise the refusal of the mm program (``write_mm``), whose values are the scene's mm; where
    it writes, ``exc`` (the inch program's), a ParameterError saying its values are in inches."""
    write_mm()
    if isinstance(exc, ParameterError):
        raise ParameterError(exc.name, exc.value, exc.valid, "; ".join(filter(None, [exc.why, "values of the inch program, in inches"])))
    raise exc


def in_program_units(write: Writer, contour: Contour, spec: MachiningSpec, cam: str, scene: str, thickness: float | None,
                     pockets: "Sequence[Pocket]", cam_body: "BodySpec | None" = None) -> str:
    """The program ``write`` makes of ``contour`` (mm) for ``spec`` (in mm, ``units = "inch"``):
    written in inches from the scaled geometry (the cam body's bore and keyway too) and :func:`program_spec`.  A refusal is that of
    the mm program (its values in the scene's mm)."""
    s = 1.0 / spec.program_unit
    try:
        inch = program_spec(spec)
        program = write(scaled_contour(contour, s), inch, cam, scene, None if thickness is None else thickness * s,
                        tuple(scaled_pocket(p, s) for p in pockets), scaled_body(cam_body, s))
    except (ParameterError, GeometryError) as exc:
        _refuse_in_mm(lambda: write(contour, _in_mm(spec), cam, scene, thickness, pockets, cam_body), exc)
    return _with_units_line(program, inch)


class ScaledGroove:
    """A barrel cam's groove (:class:`camgen.synthesis.barrel.BarrelGroove`) seen at scale ``s``:
    what :func:`camgen.export.gcode_barrel.barrel_program` reads of it, its lengths times ``s``
    (the roller axis' height ``z_c`` and tangential offset ``e``, rim and root radii, half width);
    the layout (shape, sense of rotation) and the law (its breaks are cam angles) unchanged."""

    def __init__(self, groove: Any, s: float) -> None:
        self.groove, self.s = groove, s
        self.layout, self.law = groove.layout, groove.law
        self.half_width = groove.half_width * s
        self.rim_radius = groove.rim_radius * s
        self.root_radius = groove.root_radius * s

    def axis(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Height and tangential offset of the roller's axis at cam angles ``theta``, scaled."""
        z_c, e = self.groove.axis(theta)
        return np.asarray(z_c) * self.s, np.asarray(e) * self.s


class ScaledLift:
    """A translating barrel follower's law (:class:`camgen.synthesis.laws.Displacement`, the lift
    in mm) at scale ``s``: the lift and its derivatives by the cam angle times ``s``, its bounds
    (``s_bounds``) too; the breaks (cam angles) unchanged."""

    def __init__(self, law: Any, s: float) -> None:
        self.law, self.s = law, s
        self.breaks: np.ndarray = law.breaks
        self.break_continuity: np.ndarray = law.break_continuity

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """s, s', s'', s''' at cam angles ``theta`` (rad), times ``s``."""
        s0, s1, s2, s3 = self.law(theta)
        return s0 * self.s, s1 * self.s, s2 * self.s, s3 * self.s

    @property
    def s_bounds(self) -> tuple[float, float]:
        """The least and the greatest lift, times ``s``."""
        lo, hi = self.law.s_bounds
        return lo * self.s, hi * self.s


def scaled_rib(rib: Any, s: float) -> Any:
    """``rib`` (a :class:`camgen.synthesis.barrel.BarrelRib`) scaled by ``s`` about the cam's
    axis: the same classes rebuilt from scaled lengths (the layout's roller and mean radii, ``z0``
    and arm length; the groove's rim, root and bore radii, length, clearance, fit tolerance and
    axis offset; the rib's width; a translating follower's lift, :class:`ScaledLift`), so every
    length they derive is scaled; angles (the sense, the rest angle, an oscillating follower's
    swing in rad) unchanged."""
    from camgen.synthesis.barrel import BarrelRib

    groove, lay = rib.groove, rib.groove.layout
    layout = dataclasses.replace(lay, roller_radius=lay.roller_radius * s, mean_radius=lay.mean_radius * s, z0=lay.z0 * s,
                                 arm_length=lay.arm_length * s)
    law = ScaledLift(groove.law, s) if lay.motion == "translating" else groove.law  # oscillating: the swing, rad
    scaled = dataclasses.replace(groove, layout=layout, law=law, rim_radius=groove.rim_radius * s, root_radius=groove.root_radius * s,
                                 length=groove.length * s, bore_radius=groove.bore_radius * s, clearance=groove.clearance * s,
                                 fit_tol=groove.fit_tol * s, axis_offset=groove.axis_offset * s)
    return BarrelRib(scaled, rib.width * s)


def groove_in_program_units(write: Callable[[Any, MachiningSpec, str, str], str], groove: Any, spec: MachiningSpec, cam: str,
                            scene: str, scale: Callable[[Any, float], Any] = ScaledGroove) -> str:
    """The barrel program ``write`` makes of ``groove`` for ``spec`` (in mm, ``units = "inch"``),
    written in inches (``groove`` seen through ``scale``: :class:`ScaledGroove`, or a rib's
    :func:`scaled_rib`; :func:`program_spec`); a refusal is the mm program's."""
    s = 1.0 / spec.program_unit
    inch = program_spec(spec)
    try:
        program = write(scale(groove, s), inch, cam, scene)
    except (ParameterError, GeometryError) as exc:
        _refuse_in_mm(lambda: write(groove, _in_mm(spec), cam, scene), exc)
    return _with_units_line(program, inch)
