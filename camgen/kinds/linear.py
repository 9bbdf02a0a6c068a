"""Linear (translating-plate) cams: keys, reading, building and the checks.

A plate moving in a straight line (along x) drives a translating (along +y) or oscillating
roller or knife.  The conventions (where x = 0 is, the pitch line, the offsets, the pressure
angle) are those of :mod:`camgen.synthesis.linear`; the README repeats them in user terms.
The motion's program is written in plate travel (segments' ``span_mm``, polynomial conditions per
mm; a lift table's x in mm): the follower tells the motion so (``LinearFollower.abscissa``), and
the motion reads it onto one turn, ``theta = 2 pi x / travel``.

``linear_form = "edge"``: the body is the closed outline (bottom, ends, the profile edge; corners
rounded), which every plate-cam output takes.  ``"slot"``: the body is a rectangle (corners
rounded) with a :class:`~camgen.kinds.base.Pocket`: the slot of width ``2 r + clearance`` between
the pitch curve's two offsets over the travel, closed by half circles about the pitch curve's
points at travel 0 and ``travel_mm`` (the ends a cutter of the slot's width leaves; the
pocket's ``centre_path`` is that cutter's path, the pitch curve between them), cut
``slot_depth_mm`` deep; the plate's margins must hold it with ``min_wall_mm`` to spare (check
``plate_length``).

x = 0 on the plate is the plate frame's origin (the DXF's CENTER cross with
``dxf_construction``; the report's section draws the line x = 0): a linear cam has no cam angle
0 and no rotation, so it gives no :class:`~camgen.kinds.base.ZeroMark` (whose arrow shows one).

Every check comes from the closed forms on a dense travel grid (``CHECK_STEP_MM``), never from
sampling a contour; the checks' ``where`` lists are plate travels in mm (their notes say so).
"""
from __future__ import annotations

import dataclasses

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from camgen.errors import GeometryError, ParameterError
from camgen.kinds.base import BuiltCam, CamSpec, CheckSettings, field_default, with_cam
from camgen.schema import Angle, Choice, Key, Length, Number, Text

if TYPE_CHECKING:
    from camgen.checks import CamEvaluation, CheckResult
    from camgen.synthesis.linear import LinearCurves, LinearFollower

__all__ = ["LinearCam", "LinearParams", "build_linear", "evaluate_linear", "linear_keys", "read_linear"]

#: Spacing (mm) of the dense travel grid of the checks and the report's curves (at most; the
#: grid has at least ``MIN_CHECK_SAMPLES`` points over the travel).
CHECK_STEP_MM = 0.01
MIN_CHECK_SAMPLES = 20001
#: Most samples of the travel grid (a cap before the work: a longer travel is checked coarser).
MAX_CHECK_SAMPLES = 200001
#: Longest end margin allowed, mm, when the travel is shorter (a margin is otherwise at most the
#: travel): the edge repeats the motion over the margins, one spline segment per law segment, so
#: the margins bound the profile's size.
MARGIN_FLOOR_MM = 500.0
#: Default of ``fit_tol_mm`` (mm).
DEFAULT_FIT_TOL = 1e-7
#: Default pressure-angle limits, rad: translating and oscillating followers.
DEFAULT_LIMITS = {"translating": math.radians(30.0), "oscillating": math.radians(45.0)}
#: Frames of the report's animation over the travel.
ANIMATION_FRAMES = 120
#: Seconds one pass over the travel takes in the report's animation.
ANIMATION_SECONDS = 6.0
LINEAR_FORMS = ("edge", "slot")
_OSC = {"follower_motion": ("oscillating",)}
_SLOT = {"linear_form": ("slot",)}


def linear_keys() -> tuple[Key, ...]:
    """The keys of a linear cam: follower, travel and plate, slot, checks."""
    from camgen.followers import follower_names, get_follower
    from camgen.kinds.disk import own_keys

    points = follower_names(("point",))
    return (
        Key("travel_mm", Length(high=1e5), "Plate travel over which the motion runs (0..travel_mm): the motion program is written "
            "in it (each segment's span_mm; their sum is the travel: travel_mm may be left out, and given must equal it), a lift "
            "table's first column is x in mm within it (travel_mm required); x = 0 on the plate is where the follower's point "
            "(roller centre, knife tip) is at the start, on the pitch line y = 0.", ("profile",), example=250.0),
        Key("linear_form", Choice(LINEAR_FORMS), "edge: the follower rides the plate's top edge (the body is the outline: bottom, "
            "ends, profile); slot: a roller runs in a slot along the pitch curve over the travel, closed by half circles about "
            "its ends (the roller's centre at travel 0 and travel_mm), cut slot_depth_mm into a rectangular plate whose margins "
            "hold it with min_wall_mm to spare.", ("profile",), default="edge"),
        Key("follower", Choice(points), "Follower (camgen.followers; a flat face cannot ride a linear cam: a face normal to its "
            "motion has no envelope on a plate moving across it): " + "; ".join(f"{n}, {get_follower(n).summary}" for n in points)
            + ".", ("profile",), default="roller", feeds=("kind",)),
        Key("follower_motion", Choice(("translating", "oscillating")), "Translating along +y (perpendicular to the travel), or "
            "oscillating about a fixed pivot (pivot_x_mm, pivot_y_mm).", ("profile",), default="translating", feeds=("motion",)),
    ) + own_keys(("point",)) + (
        Key("pivot_x_mm", Length(-1e5, 1e5, low_open=False), "Oscillating follower: x of the fixed pivot relative to the follower's "
            "point at zero swing and travel 0 (the plate frame's origin); the arm's length is the pivot's distance from it; != 0.",
            ("profile",), requires=_OSC, feeds=("pivot",)),
        Key("pivot_y_mm", Length(-1e5, 1e5, low_open=False), "Oscillating follower: y of the fixed pivot (> 0: above the plate's "
            "pitch line).", ("profile",), requires=_OSC, feeds=("pivot",)),
        Key("swing_turn", Choice(("ccw", "cw")), "Oscillating follower: the way the arm turns about its pivot for a positive swing, "
            "which must lift the follower (ccw with the pivot left of it, pivot_x_mm < 0; cw with it right, > 0).", ("profile",),
            default="ccw", requires=_OSC, feeds=("lift_turn",)),
        Key("margin_start_mm", Length(0.0, 1e5, low_open=False), "Plate beyond x = 0 at the start (the plate's left end is at "
            "x = -margin_start_mm); the edge there continues the motion periodically; at most travel_mm (or 500 mm).", ("profile",),
            default=25.0),
        Key("margin_end_mm", Length(0.0, 1e5, low_open=False), "Plate beyond x = travel_mm at the end (its right end is at "
            "x = travel_mm + margin_end_mm); at most travel_mm (or 500 mm).", ("profile",), default=25.0),
        Key("below_pitch_mm", Length(high=1e5), "Height of the plate below the pitch line y = 0 (its bottom is at "
            "y = -below_pitch_mm).", ("profile",), default=40.0),
        Key("above_pitch_mm", Length(high=1e5), "Slot: height of the plate above the pitch line (its top is at y = above_pitch_mm).",
            ("profile",), requires=_SLOT),
        Key("corner_radius_mm", Length(high=1e3), "Radius of the plate's rounded corners (the edge's top corners: an arc tangent to "
            "the end and the profile).", ("profile",), default=2.0),
        Key("slot_clearance_mm", Length(0.0, 1e3, low_open=False), "Slot: what the slot's width exceeds the roller's diameter by "
            "(each wall at roller radius + half of it from the pitch curve).", ("profile",), default=0.1, requires=_SLOT),
        Key("slot_depth_mm", Length(high=1e4), "Slot: depth of the slot from the plate's top face (< thickness_mm).", ("profile",),
            requires=_SLOT),
        Key("thickness_mm", Length(high=1e4), "Thickness of the plate.", ("thickness",), default=field_default(_body(), "thickness")),
        Key("min_wall_mm", Length(0.0, 1e4, low_open=False), "Least material allowed between the profile (slot) and the plate's "
            "bottom (and top).", ("report",), default=field_default(_body(), "min_wall")),
        Key("fit_tol_mm", Number("mm", 1e-10, 1e-2), "Largest distance of the profile's (walls') spline representation from the "
            "exact offset of the pitch curve (measured at the quarter, mid and three-quarter points of every piece).", ("profile",),
            default=DEFAULT_FIT_TOL),
        Key("pressure_angle_limit_deg", Angle(0.01, 90.0, high_open=True), "Largest pressure angle allowed (default: 30 deg "
            "translating followers, 45 deg oscillating ones).", ("report",)),
        Key("source", Text(), "Where the numbers come from (a note copied into the report).", ("report",)),
    )


def _body() -> type:
    from camgen.body import BodySpec

    return BodySpec


@dataclass(frozen=True)
class LinearParams:
    """A linear cam: its law (over one turn), follower, travel and plate (mm), slot, fit
    tolerance (mm), the law's figures and a source note."""

    law: Any
    follower: "LinearFollower"
    travel: float
    form: str
    margin_start: float
    margin_end: float
    below: float
    above: float | None
    corner: float
    clearance: float
    slot_depth: float | None
    fit_tol: float
    law_figures: Mapping[str, Any] = field(default_factory=dict)
    source: str | None = None

    @property
    def x_left(self) -> float:
        return -self.margin_start

    @property
    def x_right(self) -> float:
        return self.travel + self.margin_end

    @property
    def half_width(self) -> float:
        """A slot's half width: roller radius + half the clearance (mm)."""
        return self.follower.roller_radius + 0.5 * self.clearance


def read_linear(where: str, name: str, parsed: Mapping[str, Any], motion: Any, base_dir: Path | None = None) -> CamSpec:
    """The typed spec of a linear cam table; errors name the scene keys."""
    from camgen.body import BodySpec
    from camgen.followers import get_follower
    from camgen.synthesis.linear import LinearFollower

    kind, moves = parsed["follower"], parsed["follower_motion"]
    radius = get_follower(kind).radius(parsed)
    form = parsed["linear_form"]
    pivot = None
    if moves == "oscillating":
        for key in ("pivot_x", "pivot_y"):
            if key not in parsed:
                raise ParameterError(f"{where}.{key}_mm", None, "a length in mm", "required for an oscillating follower")
        pivot = (parsed["pivot_x"], parsed["pivot_y"])
        tau = 1.0 if parsed["swing_turn"] == "ccw" else -1.0
        if -tau * pivot[0] <= 0.0:
            raise ParameterError(f"{where}.pivot_x_mm", pivot[0], "< 0 with swing_turn = \"ccw\", > 0 with \"cw\"",
                                 "a positive swing must lift the follower away from the plate")
    if form == "slot":
        if radius <= 0.0:
            raise ParameterError(f"{where}.follower", kind, "a roller (a follower with a radius) for a slot",
                                 "a slot holds a roller on both sides")
        for key in ("above_pitch", "slot_depth"):
            if key not in parsed:
                raise ParameterError(f"{where}.{key}_mm", None, "a length in mm", 'required with linear_form = "slot"')
        if parsed["slot_depth"] >= parsed["thickness"]:
            raise ParameterError(f"{where}.slot_depth_mm", parsed["slot_depth"], f"< thickness_mm = {parsed['thickness']:g} mm",
                                 "a slot through the plate would cut it in two")
    if 2.0 * parsed["corner_radius"] >= parsed["below_pitch"] + parsed.get("above_pitch", 0.0):
        raise ParameterError(f"{where}.corner_radius_mm", parsed["corner_radius"], "less than half the plate's height")
    follower = LinearFollower(kind, moves, radius, pivot, parsed.get("swing_turn", "ccw"))
    reading = motion.read_law(where, parsed, follower, base_dir)
    travel = _travel(where, parsed.get("travel"), reading.figures.get("travel_mm"))
    for key in ("margin_start", "margin_end"):
        most = max(travel, MARGIN_FLOOR_MM)
        if parsed[key] > most:
            raise ParameterError(f"{where}.{key}_mm", parsed[key], f"<= {most:g} mm (travel_mm, or {MARGIN_FLOOR_MM:g} mm for a "
                                 "shorter travel)", "the edge beyond the travel repeats the motion; a longer plate end is not a cam")
    params = LinearParams(reading.law, follower, travel, form, parsed["margin_start"], parsed["margin_end"],
                          parsed["below_pitch"], parsed.get("above_pitch"), parsed["corner_radius"], parsed.get("slot_clearance", 0.0),
                          parsed.get("slot_depth"), parsed["fit_tol"], dict(reading.figures), parsed.get("source"))
    body = BodySpec(thickness=parsed["thickness"], min_wall=parsed["min_wall"])
    checks = CheckSettings(parsed.get("pressure_angle_limit"), None, getattr(parsed, "tool_limit", None))
    return CamSpec(name, motion.name, params, body, checks, None, None, form="linear")


#: Largest relative difference between travel_mm and the sum of a program's span_mm.
TRAVEL_MATCH_REL = 1e-12


def _travel(where: str, given: float | None, program: float | None) -> float:
    """The plate travel (mm): ``travel_mm`` (``given``) or the program's (the sum of its span_mm),
    equal when both are there; a motion without one (a lift table) needs ``travel_mm``."""
    if program is None:
        if given is None:
            raise ParameterError(f"{where}.travel_mm", None, "a length in mm > 0",
                                 "required: the motion gives no travel of its own (a lift table's x column runs within it)")
        return given
    if given is not None and abs(given - program) > TRAVEL_MATCH_REL * program:
        raise ParameterError(f"{where}.travel_mm", given, f"{program:.12g} mm, the sum of the segments' span_mm (or leave it out)",
                             "the program runs over the whole travel")
    return program


# --------------------------------------------------------------------------------------------
# Building
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class LinearCam(BuiltCam):
    """A built linear cam: its spec, the closed-form curves on the check grid, the travels between
    which the edge is the profile (the slot's walls run), and the report's section data."""

    params: LinearParams
    grid: "LinearCurves"
    x_start: float
    x_end: float
    fit_error: float


def check_grid(travel: float) -> np.ndarray:
    """The dense travel grid of the checks (mm): 0..travel every ``CHECK_STEP_MM`` or finer, at
    most ``MAX_CHECK_SAMPLES`` samples."""
    n = min(MAX_CHECK_SAMPLES, max(MIN_CHECK_SAMPLES, int(math.ceil(travel / CHECK_STEP_MM)) + 1))
    return np.linspace(0.0, travel, n)


def build_linear(spec: CamSpec, stages: frozenset[str]) -> BuiltCam:
    """Build a linear cam: the edge outline or the plate and its slot (the pitch curve's exact
    offsets within ``fit_tol_mm``); an offset that loops (undercut) leaves the cam unmade."""
    return with_cam(f"cams.{spec.name}", lambda: _build(spec, stages))


def _build(spec: CamSpec, stages: frozenset[str]) -> BuiltCam:
    from camgen.kinds.base import Pocket, Wall
    from camgen.synthesis import linear as lin

    p: LinearParams = spec.params
    f = p.follower
    grid = lin.curves(f, p.law, p.travel, check_grid(p.travel))
    figures: dict[str, Any] = {
        "follower": {"kind": f.kind, "motion": f.motion, **({"roller_radius_mm": f.roller_radius} if f.roller_radius else {}),
                     **({"pivot_mm": list(f.pivot), "arm_length_mm": f.arm_length, "swing_turn": f.lift_turn} if f.pivot else {})},
        "travel_mm": p.travel, "linear_form": p.form, "plate_x_mm": [p.x_left, p.x_right],
        "plate_y_mm": [-p.below, p.above if p.above is not None else None],
        "x_zero": "x = 0 on the plate is where the follower's point is at travel 0 (zero lift), y = 0 the pitch line",
        "fit_tol_mm": p.fit_tol, **dict(p.law_figures),
    }
    if p.source is not None:
        figures["source"] = p.source
    d = -f.roller_radius if p.form == "edge" else -p.half_width
    failed = lin.offset_failures(grid, d) | (lin.offset_failures(grid, p.half_width) if p.form == "slot" else False)
    contour: Any = None
    pockets: tuple[Pocket, ...] = ()
    x_start, x_end, error = p.x_left, p.x_right, 0.0
    if not np.any(failed):
        if p.form == "edge":  # the plate deep enough for the top corners' fillets to meet its ends above the bottom's
            least = 2.0 * p.corner - float(np.min(lin.edge_fillets(f, p.law, p.travel, p.x_left, p.x_right, p.corner)[1].imag))
            if p.below <= least:
                raise ParameterError(f"cams.{spec.name}.below_pitch_mm", p.below, f"> {least:.6g} mm",
                                     f"the profile's corner fillets (corner_radius_mm = {p.corner:g}) reach {least - p.corner:.6g} mm "
                                     "below the pitch line: the plate's ends would have no straight side")
        try:
            if p.form == "edge":
                outline = lin.edge_outline(f, p.law, p.travel, p.x_left, p.x_right, -p.below, p.corner, p.fit_tol)
                contour, x_start, x_end, error = outline.contour, outline.x_start, outline.x_end, outline.fit_error
            else:
                assert p.above is not None and p.slot_depth is not None
                contour = lin.rounded_rectangle(p.x_left, p.x_right, -p.below, p.above, p.corner)
                walls = lin.slot_walls(f, p.law, p.travel, p.half_width, p.fit_tol)
                x_start, x_end, error = walls.x_start, walls.x_end, walls.fit_error
                pockets = (Pocket("slot", (Wall("SLOT", walls.contour),), p.slot_depth, 2.0 * p.half_width, None, p.clearance,
                                  f"slot {2.0 * p.half_width:g} mm wide (roller {2.0 * f.roller_radius:g} mm + clearance "
                                  f"{p.clearance:g} mm), {p.slot_depth:g} mm deep, closed by half circles about the pitch curve "
                                  f"at travel 0 and {p.travel:g} mm", centre_path=walls.centre),)
        except GeometryError as exc:
            raise GeometryError(f"the plate cannot be made: {exc}") from None
    figures["fit_error_mm"] = error
    section = _section(spec, grid, contour, pockets[0].walls[0].contour if pockets else None) if "plots" in stages else None
    return LinearCam(spec.name, spec.kind, contour, figures, spec.body, None, zero_mark=None, pockets=pockets, section=section,
                     params=p, grid=grid, x_start=x_start, x_end=x_end, fit_error=error)


@functools.cache
def _section_class() -> type:
    """The frozen data of a linear cam's report section (made on first use: the report model is
    imported only by runs that draw)."""
    from camgen.report.model import SectionData

    @dataclass(frozen=True)
    class LinearSection(SectionData):
        """Curves against travel (mm), the plate, slot and pitch polylines (mm), the follower at
        travel 0, the animation's frames (travel, mm) and moves (lift mm or swing deg), the
        arm's turn sense, the pressure-angle limit (deg)."""

        x: np.ndarray
        s: np.ndarray
        v: np.ndarray
        a: np.ndarray
        pressure: np.ndarray
        radius: np.ndarray
        unit: str
        plate: np.ndarray | None
        walls: np.ndarray | None
        pitch: np.ndarray
        follower: tuple[tuple[str, np.ndarray], ...]
        frames: np.ndarray
        moves: np.ndarray
        travel: float
        pivot: tuple[float, float] | None
        turn: float
        limit: float

    return LinearSection


def _section(spec: CamSpec, grid: "LinearCurves", outline: Any, walls: Any) -> Any:
    """What the report's section draws: the law, pressure angle and radius against travel (mm,
    thinned), the plate (its outline and slot walls, flattened), the follower at travel 0 and
    per animation frame its lift (mm) or swing (deg)."""
    from camgen.synthesis.linear import law_in_x, pressure_angle

    p: LinearParams = spec.params
    f = p.follower
    keep = slice(None, None, max(1, grid.x.size // 1500))
    x = grid.x[keep]
    s, v, a, _ = law_in_x(p.law, p.travel, x)
    degrees = f.motion == "oscillating"
    conv = (180.0 / math.pi) if degrees else 1.0
    frames = np.linspace(0.0, p.travel, ANIMATION_FRAMES + 1)
    moves = law_in_x(p.law, p.travel, frames)[0] * conv
    kappa = grid.curvature[keep]
    shown = 1e3  # a straight pitch curve (a dwell) is drawn at the plot's edge, +-1000 mm
    radius = np.clip(np.divide(1.0, kappa, out=np.full(kappa.shape, shown), where=kappa != 0.0), -shown, shown)
    chord = 0.02
    return _section_class()(x, s * conv, v * conv, a * conv, np.degrees(pressure_angle(grid))[keep], radius,
                         "deg" if degrees else "mm", outline.flatten(chord) if outline is not None else None,
                         walls.flatten(chord) if walls is not None else None, np.stack([grid.c.real, grid.c.imag], axis=1)[keep],
                         _follower_shapes(p), frames, moves, p.travel, f.pivot, f.tau, math.degrees(pressure_limit(spec)))


def _follower_shapes(p: LinearParams) -> tuple[tuple[str, np.ndarray], ...]:
    """The follower at travel 0, zero lift (fixed frame, mm): roller circle (or knife point) and
    stem (translating) or arm to the pivot."""
    f = p.follower
    r = f.roller_radius
    phi = np.linspace(0.0, 2.0 * math.pi, 73)
    shapes: list[tuple[str, np.ndarray]] = []
    if r > 0:
        shapes.append(("roller", np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1)))
    else:
        shapes.append(("knife", np.array([[-3.0, 6.0], [0.0, 0.0], [3.0, 6.0]])))
    if f.pivot is None:
        shapes.append(("follower stem", np.array([[0.0, max(r, 0.0)], [0.0, max(r, 0.0) + 40.0]])))
    else:
        shapes.append(("arm", np.array([[0.0, 0.0], list(f.pivot)])))
    return tuple(shapes)


def _animation_svg(d: Any, title: str, width_px: int = 640) -> str:
    """The plate sliding left under the follower (SMIL, no script): the plate group translates by
    -travel over the animation, the follower by its lift (or turns by its swing) per frame."""
    plate = d.plate if d.plate is not None else d.pitch
    pts = [plate] + [s for _, s in d.follower]
    allp = np.concatenate(pts + [np.array([[plate[:, 0].min() - d.travel, 0.0]])])
    lo, hi = allp.min(axis=0) - 10.0, allp.max(axis=0) + 10.0 + (float(np.max(d.moves)) if d.pivot is None else 0.0)
    w, h = hi - lo
    height = int(round(width_px * h / w))

    def path(points: np.ndarray, closed: bool = False) -> str:
        return "M " + " ".join(f"{px:.3f},{py:.3f}" for px, py in points) + (" Z" if closed else "")

    dur = f"{ANIMATION_SECONDS:g}s"
    body = [f"<g><animateTransform attributeName='transform' type='translate' from='0 0' to='{-d.travel:.3f} 0' dur='{dur}' "
            "repeatCount='indefinite'/>", f"<path d='{path(plate, True)}' fill='#d6e4f0' stroke='#1f4e79' stroke-width='0.6'/>"]
    if d.walls is not None:
        body.append(f"<path d='{path(d.walls, True)}' fill='#ffffff' stroke='#1f4e79' stroke-width='0.6'/>")
    body.append(f"<line x1='0' y1='{lo[1]:.3f}' x2='0' y2='{hi[1]:.3f}' stroke='#888' stroke-dasharray='2,2' stroke-width='0.4'/></g>")
    if d.pivot is None:
        values = ";".join(f"0 {m:.4f}" for m in d.moves)
        move = f"<animateTransform attributeName='transform' type='translate' values='{values}' dur='{dur}' repeatCount='indefinite'/>"
    else:
        values = ";".join(f"{d.turn * m:.4f} {d.pivot[0]:.3f} {d.pivot[1]:.3f}" for m in d.moves)
        move = f"<animateTransform attributeName='transform' type='rotate' values='{values}' dur='{dur}' repeatCount='indefinite'/>"
    follower = "".join(f"<path d='{path(s)}' fill='none' stroke='#c0392b' stroke-width='0.8'/>" for _, s in d.follower)
    body.append(f"<g>{move}{follower}</g>")
    inner = "".join(body)
    return (f"<svg xmlns='http://www.w3.org/2000/svg' width='{width_px}' height='{height}' viewBox='0 0 {w:.3f} {h:.3f}' "
            f"role='img' aria-label='{title}'><g transform='translate({-lo[0]:.3f} {hi[1]:.3f}) scale(1 -1)'>{inner}</g></svg>")


def linear_section(Figure: Any, cam: Any) -> str:
    """A linear cam's part of report.html: the motion, pressure angle and pitch radius against the
    travel (mm), the plate and follower at travel 0, and the plate moving under the follower."""
    import html as _html

    d = cam.section
    name = _html.escape(cam.name)
    if d is None:
        return ""
    parts = [f"<h3>{name}: linear cam against plate travel</h3>"]
    fig = Figure(figsize=(10, 5.2))
    axes = fig.subplots(2, 2)
    ax = axes[0][0]
    ax.plot(d.x, d.s, width=1)
    ax.ylabel(f"lift ({d.unit})" if d.unit == "mm" else "swing (deg)")
    ax.xlabel("plate travel x (mm)")
    ax = axes[0][1]
    ax.plot(d.x, d.v, width=1, label=f"ds/dx ({d.unit}/mm)")
    ax.plot(d.x, d.a, width=1, label=f"d2s/dx2 ({d.unit}/mm^2)")
    ax.legend(font_size=7)
    ax.xlabel("plate travel x (mm)")
    ax = axes[1][0]
    ax.plot(d.x, d.pressure, width=1)
    ax.hline(d.limit, color="tab:red", dash="--")
    ax.hline(-d.limit, color="tab:red", dash="--")
    ax.ylabel("pressure angle (deg)")
    ax.xlabel("plate travel x (mm)")
    ax = axes[1][1]
    ax.plot(d.x, d.radius, width=1)
    ax.ylabel("pitch curve radius (mm, > 0 valley)")
    ax.xlabel("plate travel x (mm)")
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    fig = Figure(figsize=(10, 3.2))
    ax = fig.add_subplot()
    if d.plate is not None:
        ax.plot(np.append(d.plate[:, 0], d.plate[0, 0]), np.append(d.plate[:, 1], d.plate[0, 1]), color="tab:blue", width=1, label="plate")
    if d.walls is not None:
        ax.plot(np.append(d.walls[:, 0], d.walls[0, 0]), np.append(d.walls[:, 1], d.walls[0, 1]), color="tab:green", width=1, label="slot")
    ax.plot(d.pitch[:, 0], d.pitch[:, 1], color="k", width=0.6, dash="--", label="pitch curve")
    for label, shape in d.follower:
        ax.plot(shape[:, 0], shape[:, 1], color="tab:red", width=1)
    ax.vline(0.0, color="grey", dash=":", label="x = 0 (follower at travel 0)")
    ax.equal_aspect()
    ax.xlabel("x on the plate (mm)")
    ax.ylabel("y (mm)")
    ax.legend(font_size=7)
    ax.title("plate and follower at travel 0", font_size=9)
    parts.append(f"<div class='fig'>{fig.to_svg()}</div>")
    parts.append(f"<div class='fig'>{_animation_svg(d, _html.escape(cam.name) + ': the plate moving under the follower')}</div>")
    return "".join(parts)


# --------------------------------------------------------------------------------------------
# Checks
# --------------------------------------------------------------------------------------------
def _where(x: Any) -> list[float]:
    """Travels (mm) for a check's ``where`` list (a linear cam's are travels, not cam angles)."""
    return [round(float(v), 6) for v in np.atleast_1d(x)]


def _runs(mask: np.ndarray, x: np.ndarray) -> list[float]:
    """Start and end travels (mm) of every run of True in ``mask`` (not periodic: the travel has ends)."""
    edges = np.diff(np.concatenate([[False], mask, [False]]).astype(np.int8))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [v for s, e in zip(starts, ends) for v in _where(x[[s, e]])]


def pressure_limit(spec: CamSpec) -> float:
    limit = spec.checks.pressure_angle_limit
    return limit if limit is not None else DEFAULT_LIMITS[spec.params.follower.motion]


def _undercut(cam: "LinearCam") -> "CheckResult":
    from camgen.checks import CheckResult

    p, k = cam.params, cam.grid
    need = p.follower.roller_radius if p.form == "edge" else p.half_width
    rho = 1.0 / np.where(k.curvature == 0.0, 1e-300, k.curvature)  # signed radius of the pitch curve, > 0 valley
    side = -rho if p.form == "edge" else np.abs(rho)  # the edge: the convex side (peaks, rho < 0); a slot: both walls
    side = np.where(side > 0, side, np.inf)
    i = int(np.argmin(side))
    value: Any = float(side[i]) if np.isfinite(side[i]) else "none"
    if np.isfinite(side[i]) and need > 0:
        value = _least_radius(cam, float(k.x[max(i - 1, 0)]), float(k.x[min(i + 1, k.x.size - 1)]), float(side[i]))
    bad = side <= need if need > 0 else np.zeros(side.shape, dtype=bool)
    what = ("smallest convex radius of the pitch curve (the peaks) against the roller radius" if p.form == "edge" else
            "smallest radius of the pitch curve (either side: both walls) against the slot's half width (roller radius + half the "
            "clearance)") if need > 0 else "a knife rides its pitch curve: no undercut"
    where = _runs(bad, k.x) if bad.any() else _where(k.x[i])
    note = what + "; where: plate travel in mm" + ("; the offset loops there: the plate cannot be made" if bad.any() else "")
    passed = not bool(bad.any()) and (not isinstance(value, float) or value > need)
    return CheckResult("undercut", value, need, ">", "mm", passed, where, note, blocks_manufacture=True)


def _least_radius(cam: "LinearCam", lo: float, hi: float, found: float) -> float:
    """The least radius on the checked side between travels ``lo`` and ``hi`` around the grid's
    least (``found``): golden-section search on the closed form (a scalar minimum, 80 steps)."""
    from camgen.synthesis.linear import curves

    p = cam.params
    edge = p.form == "edge"

    def radius(x: float) -> float:
        kappa = float(curves(p.follower, p.law, p.travel, np.array([x])).curvature[0])
        value = -1.0 / kappa if edge else 1.0 / abs(kappa)
        return value if kappa != 0.0 and value > 0 else math.inf

    from camgen.numerics.minimise import golden_section

    (_, fc), (_, fd) = golden_section(radius, lo, hi, max_steps=80)
    return min(found, fc, fd)


def _plate_length(cam: "LinearCam", min_wall: float) -> "CheckResult":
    """Edge: over the travel, every contact point lies on the profile, between the edge's fillets.
    Slot: the slot (walls and end half circles) keeps ``min_wall`` from the plate's ends and their
    rounded corners (the least margins that would, when it does not)."""
    from camgen.checks import limited
    from camgen.synthesis.linear import offset_curve

    p, k = cam.params, cam.grid
    if p.form == "slot":
        return _slot_to_ends(cam, min_wall)
    lo_x, hi_x = cam.x_start, cam.x_end
    xs = offset_curve(k, -p.follower.roller_radius)[0].real
    room = min(float(np.min(xs)) - lo_x, hi_x - float(np.max(xs)))
    at = k.x[int(np.argmin(np.minimum(xs - lo_x, hi_x - xs)))]
    return limited("plate_length", room, ">=", 0.0, "mm", _where(at),
                   f"least room (mm) between the follower's contact over the travel 0..{p.travel:g} mm and where the plate's "
                   f"profile ends (x = {lo_x:.6g} .. {hi_x:.6g} mm: the plate from {p.x_left:g} to {p.x_right:g} mm less its "
                   "corner fillets); < 0: the follower runs off the profile (lengthen margin_start_mm / margin_end_mm); where: travel mm",
                   blocks_manufacture=True)


#: Samples of each end half circle of a slot in its checks (its extreme points are added exactly).
END_ARC_SAMPLES = 2001
#: Bisection steps of a least margin (the bracket shrinks below 1e-15 of its width).
_MARGIN_BISECTIONS = 60


def slot_boundary(cam: "LinearCam") -> np.ndarray:
    """Points (complex, mm) of a slot's boundary: both walls on the check grid (closed forms) and
    the end half circles, sampled with their extreme points in x and y."""
    from camgen.synthesis.linear import end_arcs, offset_curve

    p, k = cam.params, cam.grid
    h = p.half_width
    centres, starts = end_arcs(p.follower, p.law, p.travel, h)
    t = np.linspace(0.0, math.pi, END_ARC_SAMPLES)
    extreme = (np.arange(4.0) * 0.5 * math.pi - starts[:, None]) % (2.0 * math.pi)  # angles 0, 90, 180, 270 deg on each arc
    angles = starts[:, None] + np.concatenate([np.broadcast_to(t, (2, t.size)), np.where(extreme <= math.pi, extreme, 0.0)], axis=1)
    arcs = centres[:, None] + h * np.exp(1j * angles)
    return np.concatenate([offset_curve(k, -h)[0], offset_curve(k, h)[0], arcs.ravel()])


def plate_room(z: np.ndarray, x_left: float, x_right: float, y_bottom: float, y_top: float, corner: float) -> tuple[np.ndarray, np.ndarray]:
    """Distance (mm) of points ``z`` (complex, inside) from a rounded rectangle's outline, and
    whether the nearest outline point is on an end or a corner arc (True) or on the top or bottom
    (False): the rounded box's distance in closed form (``q = |p - c| - (half size - corner)``:
    in a corner's square ``corner - |q|``, else ``corner - max(q)``)."""
    cx, cy = 0.5 * (x_left + x_right), 0.5 * (y_bottom + y_top)
    qx = np.abs(z.real - cx) - (0.5 * (x_right - x_left) - corner)
    qy = np.abs(z.imag - cy) - (0.5 * (y_top - y_bottom) - corner)
    in_corner = (qx > 0.0) & (qy > 0.0)
    room = np.where(in_corner, corner - np.hypot(np.maximum(qx, 0.0), np.maximum(qy, 0.0)), corner - np.maximum(qx, qy))
    return room, in_corner | (qx >= qy)


def _slot_to_ends(cam: "LinearCam", min_wall: float) -> "CheckResult":
    """The slot's least distance from the plate's ends and corners against ``min_wall``; failing,
    the least ``margin_start_mm`` / ``margin_end_mm`` that hold it (bisection on the margin)."""
    from camgen.checks import limited

    p = cam.params
    assert p.above is not None
    above = p.above
    z = slot_boundary(cam)
    mid = 0.5 * (p.x_left + p.x_right)

    def room_at(start: float, end: float, left: bool) -> float:
        """Least distance of the slot's points on one side from that end (with margins start, end)."""
        room, at_end = plate_room(z, -start, p.travel + end, -p.below, above, p.corner)
        side = (z.real < mid) if left else (z.real >= mid)
        sel = at_end & side
        return float(np.min(room[sel])) if sel.any() else math.inf

    rooms = {"margin_start_mm": room_at(p.margin_start, p.margin_end, True), "margin_end_mm": room_at(p.margin_start, p.margin_end, False)}
    least = min(rooms.values())
    room, at_end = plate_room(z, p.x_left, p.x_right, -p.below, p.above, p.corner)
    i = int(np.argmin(np.where(at_end, room, np.inf)))
    note = (f"least material between the slot (walls and end half circles; its ends at travel 0 and {p.travel:g} mm) and the plate's "
            f"ends (x = {p.x_left:g}, {p.x_right:g} mm) with their corners, against min_wall_mm")
    hints = []
    for key, value in rooms.items():
        if value < min_wall:
            left = key == "margin_start_mm"
            own = p.margin_start if left else p.margin_end
            lo, hi = own, own + (min_wall - value) + 2.0 * p.corner + 1.0
            for _ in range(_MARGIN_BISECTIONS):  # the room grows with the margin: the least margin that holds min_wall
                m = 0.5 * (lo + hi)
                got = room_at(m, p.margin_end, True) if left else room_at(p.margin_start, m, False)
                lo, hi = (m, hi) if got < min_wall else (lo, m)
            hints.append(f"{key} >= {math.ceil(hi * 1e6) / 1e6:.6f}")
    if hints:
        note += "; the plate is too short for the slot: " + ", ".join(hints) + " mm holds it"
    return limited("plate_length", least, ">=", min_wall, "mm", [round(float(z[i].real), 6), round(float(z[i].imag), 6)],
                   note + "; where: the point (x, y) of the slot, mm", blocks_manufacture=True)


def _plate_height(cam: "LinearCam", min_wall: float) -> "CheckResult":
    from camgen.checks import limited
    from camgen.synthesis.linear import offset_curve

    p, k = cam.params, cam.grid
    if p.form == "slot":  # the slot's boundary (walls and end half circles) from the plate's top and bottom
        assert p.above is not None
        z = slot_boundary(cam)
        room, at_end = plate_room(z, p.x_left, p.x_right, -p.below, p.above, p.corner)
        room = np.where(at_end, np.inf, room)
        i = int(np.argmin(room))
        return limited("plate_height", float(room[i]), ">=", min_wall, "mm", [round(float(z[i].real), 6), round(float(z[i].imag), 6)],
                       f"least material between the slot (walls and end half circles) and the plate's bottom (y = {-p.below:g} mm) "
                       f"and top (y = {p.above:g} mm): below_pitch_mm, above_pitch_mm; where: the point (x, y) of the slot, mm",
                       blocks_manufacture=True)
    lower = offset_curve(k, -p.follower.roller_radius)[0].imag
    below = lower + p.below
    wall, i = float(np.min(below)), int(np.argmin(below))
    note = f"least material between the profile and the plate's bottom (y = {-p.below:g} mm)"
    return limited("plate_height", wall, ">=", min_wall, "mm", _where(k.x[i]), note + "; where: travel mm",
                   blocks_manufacture=True)


def profile_radii(cam: "LinearCam") -> tuple[np.ndarray, str]:
    """Signed radius of curvature (mm, < 0 concave seen from the cutter's side) of what is cut:
    the edge profile (the cutter above it) or a slot's walls (the cutter inside it, the smaller
    of the two walls' radii at each travel)."""
    p, k = cam.params, cam.grid
    kappa = k.curvature
    with np.errstate(divide="ignore"):
        rho = np.where(kappa == 0.0, np.inf, 1.0 / kappa)  # > 0: a valley
    if p.form == "edge":
        # the profile's radius is rho + r: a valley (rho > 0) is concave seen from above
        return -(rho + p.follower.roller_radius), "profile radius of curvature (mm, < 0 concave)"
    # seen from inside the slot every wall is concave where the pitch curve bends away from it: radius |rho| + w/2
    return -(np.abs(rho) + p.half_width), "slot walls' radius of curvature seen from the slot (mm, < 0 concave)"


def _machinability(cam: "LinearCam", tool_radius: float, tool_is_limit: bool) -> list["CheckResult"]:
    """The smallest concave radius of what is cut against the tool radius (a limit when a tool is
    named or G-code is written), and the smallest convex one (information)."""
    from camgen.checks import NO_CONCAVE_PART, CheckResult, information, limited

    rho, _ = profile_radii(cam)
    x = cam.grid.x
    out = []
    convex = rho > 0
    if convex.any():
        i = int(np.argmin(np.where(convex, rho, np.inf)))
        out.append(information("min_convex_radius", float(rho[i]), "mm", _where(x[i]), "smallest convex radius of what is cut (no "
                               f"limit; the tool radius is {tool_radius:g} mm); where: travel mm"))
    concave = rho < 0
    if not concave.any():
        note = "no concave parts: any tool radius cuts the profile"
        out.append(CheckResult("min_concave_radius", NO_CONCAVE_PART, tool_radius, ">", "mm", True, [], note) if tool_is_limit
                   else information("min_concave_radius", NO_CONCAVE_PART, "mm", [], note))
        return out
    i = int(np.argmax(np.where(concave, rho, -np.inf)))
    bad = concave & (-rho <= tool_radius)
    where = _runs(bad, x) if bad.any() else _where(x[i])
    note = "smallest concave radius of what is cut: a concave radius not above the tool radius cannot be cut without gouging; where: travel mm"
    if tool_is_limit:
        out.append(limited("min_concave_radius", float(-rho[i]), ">", tool_radius, "mm", where, note, blocks_manufacture=True))
    else:
        out.append(information("min_concave_radius", float(-rho[i]), "mm", where, note + f"; no tool is named "
                               f"(machining.tool_diameter_mm), {tool_radius:g} mm is the default radius"))
    return out


def evaluate_linear(cam: BuiltCam, spec: CamSpec, tool_radius: float, tool_is_limit: bool) -> "CamEvaluation":
    """The design checks of a linear cam from the closed forms on the dense travel grid."""
    from camgen.checks import CamEvaluation, CheckResult, information, limited
    from camgen.synthesis.linear import pressure_angle

    assert isinstance(cam, LinearCam), f"a linear cam's checks on a {type(cam).__name__}"
    p, k = cam.params, cam.grid
    checks: list[CheckResult] = [_undercut(cam)]
    alpha = np.abs(pressure_angle(k))
    limit = pressure_limit(spec)
    bad = alpha > limit
    i = int(np.argmax(alpha))
    what = f"{p.follower.motion} {p.follower.kind} follower on a linear cam"
    checks.append(CheckResult("pressure_angle", float(np.degrees(alpha[i])), round(math.degrees(limit), 9), "<=", "deg",
                              not bool(bad.any()), _runs(bad, k.x) if bad.any() else _where(k.x[i]),
                              f"largest pressure angle of the {what} (closed form"
                              + (", tan(alpha) = ds/dx" if p.follower.motion == "translating" else "")
                              + "); where: travel mm" + (" (above the limit between the listed pairs)" if bad.any() else "")))
    if cam.contour is not None:
        checks.append(_plate_length(cam, spec.body.min_wall))
        checks.append(_plate_height(cam, spec.body.min_wall))
        checks.extend(_machinability(cam, tool_radius, tool_is_limit))
        if p.form == "slot":
            checks.append(limited("slot_tool", 2.0 * p.half_width, ">=", 2.0 * tool_radius, "mm", [],
                                  "the slot's width against the cutter's diameter", blocks_manufacture=tool_is_limit))
        checks.append(information("fit_error", cam.fit_error, "mm", [], f"largest distance of the spline from the exact offset "
                                  f"(fit_tol_mm = {p.fit_tol:g})"))
    # every check points at the plate in mm (a travel, or a point (x, y)): report.json's where_mm
    checks = [dataclasses.replace(c, where_unit="mm") for c in checks]
    return CamEvaluation(tuple(checks), None, None, None, None, None, pressure_angle_label=f"{what}, closed form")
