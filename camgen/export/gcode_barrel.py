"""4th-axis G-code (RS274/NGC, LinuxCNC) milling a barrel cam's groove with a rotary A axis.

Machine setup (the program's header states it):

* the cam's axis on the A axis, which lies along machine X; ``X = 0`` at the cam's bottom face
  (cam z = 0), +X towards its top face: ``X = z``;
* ``Z`` radial: the distance of the tool tip from the A axis; the tool's axis is parallel to Z,
  at ``Y = 0`` through the A axis for a translating follower;
* ``A`` (degrees): the cam turned about its axis by ``A``, counter-clockwise seen from +X (the
  right-hand rule about +X).  The tool stands where the follower does (world polar angle 0), so
  at ``A`` it is over cam polar angle ``-A`` and the station is the cam angle ``theta = sigma A``
  (:mod:`camgen.synthesis.barrel`: the follower meets cam polar angle ``-sigma theta``): the
  program turns the cam as it turns in use for ``rotation = "ccw"`` and the other way for "cw".
  The machine frame is the follower's world frame (x radial towards the follower, y, z the cam
  axis) as ``(X, Y, Z) = (z, -y, x)`` (right-handed).

Why one pass along the pitch curve is exact.  The groove is the union, over the cam angles, of
the follower's roller widened by half the clearance: a cylinder of radius ``w = Rr + c / 2``
about the roller's axis (``camgen.synthesis.barrel``'s brute force).  A cylindrical roller's
axis at cam angle theta is a straight line perpendicular to the cam axis: radial through the
axis at height ``z_c(theta)`` for a translating follower; for an oscillating follower the line
``{(t, e(theta), z_c(theta))}``, parallel to the radial line through the station and offset
tangentially by ``e`` (the arm swings in the plane tangent to the cylinder).  An end mill of
diameter ``2 w`` whose axis lies on that line is the same cylinder (down to its tip): so the
tool is placed with its axis on the roller's axis, ``X = z_c``, ``Y = -e``, at every station,
and the union of its poses is the exact groove, both walls at every radius.  A conical roller
would need a tapered cutter (refused); a smaller cutter a wall-offset strategy (refused: not
built).

The tip.  A flat tip at distance ``Z`` from the axis reaches radius ``sqrt(Z^2 + y^2)`` at the
tangential offset ``y`` from the axis; a wall's point at radius ``r`` meets the tool at an offset
up to ``|e| + D/2``.  The finishing pass therefore runs the tip at
``Z_f(theta) = sqrt(R_i^2 - (|e(theta)| + D/2)^2)``: the walls are cut down to the root radius
``R_i``, and the floor meets them there; midway between them it lies below the root by up to
``R_i - Z_f`` (stated in the header: the floor is not a running surface).

Passes.  The stock is the cylinder turned to the rim radius ``R_o``.  The tool approaches the
rim at the start station (``G94`` plunge feed to ``Z = R_o``), then runs whole turns of the
groove: ``n`` roughing turns, each a helical ramp along the groove whose tip falls linearly
with A by at most ``step_down`` per turn (no plunge into uncut stock), from the rim to the
floor, then one finishing turn on the floor.  A is not unwound (it ends at ``(n + 1) 360``).
Direction (spindle M3): with A increasing the tool travels +Y over the part, the upper wall
(+X) on its right: climb milling of the upper wall (``direction = "climb"``, A increasing);
``"conventional"`` runs A decreasing.  A tool of the groove's width cuts the other wall the
other way.

Feed.  Inverse time (``G93``): each move's ``F`` is ``feed / L`` (1/min), ``L`` the move's length
at the rim, ``sqrt((R_o dA)^2 + dX^2 + dY^2 + dZ^2)`` (dA in rad, printed values): the cutter
meets the stock at ``feed_mm_per_min`` at the rim, slower below it.

Error budget (shares of ``chord_tol`` as for the plate cams, :mod:`camgen.export.gcode_spec`).
Between stations the control interpolates X, Y, Z and A linearly (joint interpolation): the tool
relative to the part runs a helix, so the only path error is the stations' linear
interpolation of ``z_c``, ``e`` and ``Z_f``: within ``FIT_SHARE chord_tol`` (each step's error
sampled at its quarter points and held to half that; the law's breaks are stations).  The angle
step also keeps the chord of the rim circle (sagitta ``R_o (1 - cos(dA / 2))``) within the same
share, for a control that moves the tool centre point in straight lines (tool-centre-point
kinematics).  Printed decimals: X, Y, Z with ``decimals``, A with enough more that the rim moves
by no more than a unit of the last decimal: within ``ROUNDING_SHARE chord_tol`` (the spec
checked it).  ``G64 P`` blending: ``BLEND_SHARE chord_tol``.  The tool's mismatch with the width:
within ``one_pass_tol`` (2 x ``REFIT_SHARE chord_tol``), each wall within half of it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError, ParameterError, ceil_significant
from camgen.export.gcode_moves import comment
from camgen.synthesis.barrel import floor_radius
from camgen.export.gcode_spec import BLEND_SHARE, FIT_SHARE, ROUNDING_SHARE, MachiningSpec, depth_passes, rounding_error

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["GROOVE_ONE_PASS", "GROOVE_WIDTH", "MAX_REFINEMENTS", "MAX_STATIONS", "BarrelToolPath", "a_decimals", "barrel_program", "framed",
           "check_tool", "floor_radius", "named_program", "station_angles", "tool_path", "turn_blocks", "width_tol", "writer"]

#: Most stations of one turn (a program of a few turns stays within what controllers load).
MAX_STATIONS = 400_000
#: Most halvings of a station step while fitting the path (each halves the step's error 4 times).
MAX_REFINEMENTS = 40


def width_tol(spec: MachiningSpec) -> float:
    """Largest ``|tool diameter - groove width|`` (mm): the one-pass tolerance of the plate cams'
    grooves (:func:`camgen.export.gcode_pockets.one_pass_tol`); each wall within half of it."""
    from camgen.export.gcode_pockets import one_pass_tol

    return one_pass_tol(spec)


def a_decimals(decimals: int, rim_radius: float) -> int:
    """Decimals of A (deg) so that a printed A moves the rim (radius mm) by at most a unit of the
    ``decimals``-th decimal of mm: ``R_o pi / 180 x 10^-dA <= 10^-decimals``."""
    return decimals + max(0, math.ceil(math.log10(rim_radius * math.pi / 180.0) - 1e-12))


def _axis_path(groove: Any, theta: np.ndarray, tool_radius: float) -> np.ndarray:
    """Columns X = z_c, Y = -e, Z = the floor radius at cam angles ``theta`` (n, 3), mm."""
    z_c, e = groove.axis(theta)
    z_c, e = np.broadcast_to(z_c, theta.shape), np.broadcast_to(e, theta.shape)
    return np.column_stack([z_c, -e, floor_radius(groove.root_radius, e, tool_radius)])


def station_angles(groove: Any, travel: int, tool_radius: float, fit: float) -> np.ndarray:
    """Stations of one turn as the travel ``u`` in [0, 2 pi] (rad; ``A = travel u``, ``theta =
    sigma A``), increasing, both ends included: the law's breaks, then each interval split evenly
    with a step whose rim chord is within ``fit`` (mm), then every step whose linear interpolation
    of (X, Y) or Z misses the exact path by more than ``fit / 2`` at its quarter points halved,
    until none does.

    Raises
    ------
    GeometryError
        More than :data:`MAX_STATIONS` stations (a path the tolerance cannot follow: a law with a
        jump in the lift).
    """
    sigma = groove.layout.sigma
    two_pi = 2.0 * math.pi
    breaks = np.asarray(getattr(groove.law, "breaks", ()), dtype=float)
    knots = np.unique(np.concatenate([[0.0, two_pi], np.mod(sigma * travel * breaks, two_pi)]))
    knots = knots[np.concatenate([[True], np.diff(knots) > 1e-12])]
    knots[-1] = two_pi
    # the rim chord: sagitta R_o (1 - cos(h / 2)) <= fit
    h = 2.0 * math.acos(max(-1.0, 1.0 - fit / groove.rim_radius))
    lengths = np.diff(knots)
    steps = np.maximum(1, np.ceil(lengths / h - 1e-9)).astype(int)
    u = np.concatenate([np.repeat(knots[:-1], steps) + lengths.repeat(steps) * (np.arange(steps.sum()) - np.repeat(np.cumsum(steps) - steps, steps))
                        / steps.repeat(steps), [two_pi]])
    quarter = np.array([0.25, 0.5, 0.75])
    for _ in range(MAX_REFINEMENTS):
        if u.size > MAX_STATIONS:
            break
        a, b = u[:-1], u[1:]
        q = a[:, None] + (b - a)[:, None] * quarter  # (m, 3)
        ends = _axis_path(groove, sigma * travel * u, tool_radius)
        mid = _axis_path(groove, sigma * travel * q.ravel(), tool_radius).reshape(q.shape + (3,))
        lerp = ends[:-1, None, :] + (ends[1:] - ends[:-1])[:, None, :] * quarter[None, :, None]
        miss = mid - lerp
        err = np.maximum(np.hypot(miss[..., 0], miss[..., 1]), np.abs(miss[..., 2])).max(axis=1)
        bad = err > 0.5 * fit
        if not bad.any():
            return u
        u = np.sort(np.concatenate([u, 0.5 * (a[bad] + b[bad])]))
    raise GeometryError(f"the groove's path cannot be followed within {fit:.3g} mm with {MAX_STATIONS} stations a turn "
                        "(a lift that jumps?): raise output.chord_tol_mm")


@dataclass(frozen=True)
class BarrelToolPath:
    """The tool's poses of one turn at the stations: ``a`` (deg, 0 -> +-360), X, Y (mm), the
    floor radius ``floor`` (mm, the finishing tip) and the number of roughing turns ``turns``
    from the rim ``rim`` (mm) down to the floor in steps of at most ``step`` (mm)."""

    a: np.ndarray
    x: np.ndarray
    y: np.ndarray
    floor: np.ndarray
    rim: float
    step: float
    turns: int

    def tip(self, turn: int) -> np.ndarray:
        """Tip radius along roughing turn ``turn`` (1..turns; turns + 1: the finishing turn), mm:
        falling linearly with A from the level of the turn before to this turn's level
        ``max(rim - turn step, floor)``."""
        if turn > self.turns:
            return self.floor
        frac = np.abs(self.a) / 360.0
        start = np.maximum(self.rim - (turn - 1) * self.step, self.floor)
        end = np.maximum(self.rim - turn * self.step, self.floor)
        return start + (end - start) * frac


def tool_path(groove: Any, spec: MachiningSpec) -> BarrelToolPath:
    """The tool's poses for ``groove`` (a :class:`camgen.synthesis.barrel.BarrelGroove`) and the
    tool of ``spec`` (module docstring); the spec is checked first (:func:`barrel_program`)."""
    travel = 1 if spec.direction == "climb" else -1
    r = spec.tool_radius
    u = station_angles(groove, travel, r, FIT_SHARE * spec.chord_tol)
    theta = groove.layout.sigma * travel * u
    pose = _axis_path(groove, theta, r)
    depth = groove.rim_radius - float(pose[:, 2].min())
    turns = int(depth_passes(depth, spec.step_down))
    return BarrelToolPath(np.degrees(travel * u), pose[:, 0], pose[:, 1], pose[:, 2], groove.rim_radius, spec.step_down, turns)


#: What the groove's tool must match, as a refusal names it (:func:`check_tool`).
GROOVE_WIDTH = "the groove's width 2 x roller radius + clearance"
#: Why another tool is refused for a groove (:func:`check_tool`).
GROOVE_ONE_PASS = "a barrel cam's groove is cut in one pass along its pitch curve by a tool of its width; a wall-offset strategy for another tool is not built"


def check_tool(groove: Any, spec: MachiningSpec, cam: str, width_is: str = GROOVE_WIDTH, why: str = GROOVE_ONE_PASS) -> None:
    """Refuse what a barrel cam's program cannot cut (ParameterError naming the key): a conical
    roller, a tool whose diameter is not ``2 w`` (``groove.half_width``) within :func:`width_tol`
    (``width_is`` says what that width is, ``why`` why another tool is refused), the grbl dialect,
    cutter compensation, a bore milled."""
    layout = groove.layout
    if layout.roller_shape != "cylindrical":
        raise ParameterError(f"cams.{cam}.roller_shape", layout.roller_shape, '"cylindrical" with "ngc" in output.formats',
                             "the groove of a conical roller needs a tapered cutter: its G-code is not built")
    width = 2.0 * groove.half_width
    tol = width_tol(spec)
    if abs(spec.tool_diameter - width) > tol:
        raise ParameterError("tool_diameter", spec.tool_diameter, f"{width:.10g} mm ({width_is}, within {tol:.3g} mm)", why)
    if spec.dialect != "linuxcnc":
        raise ParameterError("dialect", spec.dialect, '"linuxcnc" for a barrel cam', "its program needs a rotary A axis and G93")
    if spec.cutter_compensation:
        raise ParameterError("cutter_compensation", True, "false for a barrel cam", "its program is a tool-centre path on a rotary axis")
    for name in ("bore_tool_diameter", "bore_operation"):  # the bore settings (camgen.export.gcode_bore) mill a plate cam's bore
        if getattr(spec, name) not in (None, "none"):
            raise ParameterError(name, getattr(spec, name), "left out for a barrel cam", "its program cuts the groove only")


def turn_blocks(path: BarrelToolPath, xs: np.ndarray, ys: np.ndarray, d: int, da: int, feed: float, rim: float, a_start: float = 0.0,
                oscillating: bool | None = None, label: str = "", floor_what: str = "finishing turn on the floor") -> list[str]:
    """The G93 moves of one pass's turns (``path.turns`` roughing turns, then one on the floor), a
    block of text per turn headed by a comment: ``xs``, ``ys`` the printed X, Y at the stations
    (mm, ``d`` decimals), A (deg, ``da`` decimals) from ``a_start`` (a multiple of 360: A is not
    unwound between passes) turning the way ``path.a`` does, the tip from ``rim`` (the level the
    pass starts at) down by :meth:`BarrelToolPath.tip`; ``F`` the inverse time of ``feed`` (mm/min)
    over each move's length at the ``rim`` radius (mm).  ``oscillating``: print Y (default: where
    any ``ys`` is not 0); ``label`` heads each turn's comment; ``floor_what`` names the last turn."""
    from camgen.export.tables import format_rows

    if oscillating is None:
        oscillating = bool(np.any(ys != 0.0))
    n_turns = path.turns + 1
    blocks: list[str] = []
    prev_z = rim
    for turn in range(1, n_turns + 1):
        a = np.round(path.a + (a_start + (turn - 1) * np.sign(path.a[-1]) * 360.0), da) + 0.0
        z = np.round(path.tip(turn), d) + 0.0
        z[0] = prev_z
        prev_z = float(z[-1])
        # a step finer than the printed decimals (a refined step at a sharp turn of the law) is dropped
        keep = np.concatenate([[True], (np.diff(a) != 0.0) | (np.diff(xs) != 0.0) | (np.diff(ys) != 0.0) | (np.diff(z) != 0.0)])
        a, xt, yt, z = a[keep], xs[keep], ys[keep], z[keep]
        # inverse time: feed over the move's length at the rim (printed values)
        length = np.sqrt((rim * np.radians(np.diff(a))) ** 2 + np.diff(xt) ** 2 + np.diff(yt) ** 2 + np.diff(z) ** 2)
        inverse = np.floor(feed / length * 1e4) / 1e4  # rounded down: never faster than the feed
        cols = [xt[1:]] + ([yt[1:]] if oscillating else []) + [z[1:], a[1:], inverse]
        row = f"G1 X%.{d}f" + (f" Y%.{d}f" if oscillating else "") + f" Z%.{d}f A%.{da}f F%.4f"
        what = floor_what if turn == n_turns else f"roughing turn {turn} of {path.turns}: ramp to Z{float(z[-1]):.{d}f}"
        blocks.append(f"({label}{what})\n" + format_rows(np.column_stack(cols), row))
    return blocks


def barrel_program(groove: Any, spec: MachiningSpec, cam: str = "cam", scene: str = "") -> str:
    """RS274/NGC program text milling ``groove`` (a :class:`camgen.synthesis.barrel.BarrelGroove`)
    on a 4th axis with the tool of ``spec`` (module docstring).  ``spec`` is final (the scene
    reader checked its decimals against its chord tolerance).

    Raises
    ------
    ParameterError
        A conical roller (``cams.<cam>.roller_shape``); a tool that is not the groove's width
        within :func:`width_tol` (``tool_diameter``); the grbl dialect; cutter compensation; a
        program of more than :data:`camgen.export.gcode.MAX_PROGRAM_MOVES` moves (``step_down``).
    GeometryError
        A tool whose reach (tangential offset + radius) is not inside the root radius.
    """
    from camgen import __version__
    from camgen.export.gcode import MAX_PROGRAM_MOVES, blend_word

    if spec.program_unit != 1.0:  # inch: the same program of the scaled groove and spec (camgen.export.gcode_units)
        from camgen.export.gcode_units import groove_in_program_units

        return groove_in_program_units(barrel_program, groove, spec, cam, scene)
    check_tool(groove, spec, cam)
    path = tool_path(groove, spec)
    d = spec.decimals
    da = a_decimals(d, groove.rim_radius)
    n_turns = path.turns + 1
    moves = n_turns * (path.a.size - 1)  # at most: steps finer than the decimals are dropped
    if moves > MAX_PROGRAM_MOVES:
        per_turn = path.a.size - 1
        turns = MAX_PROGRAM_MOVES // per_turn - 1
        why = f"{n_turns} turns of {per_turn} moves would make {moves} lines, more than the {MAX_PROGRAM_MOVES} a program may hold"
        if turns >= 1:
            raise ParameterError("step_down", spec.step_down, f">= {ceil_significant((path.rim - float(path.floor.min())) / turns, 3):.3g} mm", why)
        raise ParameterError("chord_tol", spec.chord_tol, "a larger chord_tol", why)
    sigma = groove.layout.sigma
    oscillating = bool(np.any(np.abs(path.y) > 0.0))
    unit = 10.0 ** (-d)
    xs, ys = np.round(path.x, d) + 0.0, np.round(path.y, d) + 0.0

    # one block of moves per turn: the turns run on from A = 360 k (A is not unwound)
    feed = spec.feed
    rim = groove.rim_radius
    blocks = turn_blocks(path, xs, ys, d, da, feed, rim, oscillating=oscillating)

    chord_tol = spec.chord_tol
    blend = blend_word(BLEND_SHARE * chord_tol, d)
    rounding = math.hypot(0.5 * unit, 0.5 * unit + rim * math.radians(0.5 * 10.0 ** (-da)))
    depth_below = groove.root_radius - float(path.floor.min())
    step_deg = float(np.max(np.abs(np.diff(path.a))))
    rotation = "ccw" if sigma > 0 else "cw"
    lines = [
        comment(f"camgen {__version__}: barrel cam '{cam}'" + (f", scene '{scene}'" if scene else "") + "; LinuxCNC, 4th axis"),
        comment("machine: the cam's axis on the A axis along X; X0 at the cam's bottom face [cam z = 0], +X to its top face; "
                "Z radial: the tool tip's distance from the A axis; Y0 through the axis"
                + ("; the tool's axis at Y = -e, the roller axis's tangential offset" if oscillating else "")),
        comment(f"units {spec.units}, A in degrees: the cam turned by A counter-clockwise seen from +X [right-hand rule]; at A the tool is over cam "
                f"polar angle -A, cam angle theta = {'+' if sigma > 0 else '-'}A [rotation {rotation}]"),
        comment(f"tool: end mill diameter {spec.tool_diameter:g} = groove width {2.0 * groove.half_width:.10g} within "
                f"{width_tol(spec):.3g}, axis radial, on the roller's axis at every station: it sweeps the exact groove"),
        comment(f"stock: cylinder turned to the rim radius {rim:g}; tip from Z{rim:g} down to the floor Z{float(path.floor.min()):.{d}f}"
                f" where the flat tip reaches the walls at the root radius {groove.root_radius:g}; the floor lies up to "
                f"{depth_below:.4g} below the root radius midway between the walls"),
        comment(f"passes: {path.turns} roughing turns, each a helical ramp along the groove down <= {spec.step_down:g} a turn, "
                f"then a finishing turn on the floor; {spec.direction} milling of the upper wall [+X]: A "
                f"{'increasing' if spec.direction == 'climb' else 'decreasing'}, not unwound"),
        comment(f"feed: G93 inverse time, F = {feed:g} / [move length at the rim radius: sqrt[[R dA]^2 + dX^2 + dY^2 + dZ^2]]"),
        comment(f"path tolerance {chord_tol:g} = stations {FIT_SHARE * chord_tol:.3g} [{path.a.size - 1} a turn, A step <= {step_deg:.4g} deg, "
                f"X Y Z between stations and the rim chord] + {d} and {da} printed decimals {rounding:.3g} + G64 blending {blend} "
                f"+ tool width mismatch {0.5 * width_tol(spec):.3g}"),
        comment("not used by this program: machining.lead_mm, lead_style, lead_radius_mm, breakthrough_mm, spline_mode, entry, ramp_angle_deg, stock_allowance_mm, holding_tabs"),
    ]
    assert rounding <= rounding_error(d) <= ROUNDING_SHARE * chord_tol * (1 + 1e-12)  # the spec's decimals check covers the barrel's
    safe = rim + spec.safe_z
    return framed("\n".join(lines), blocks, spec, blend, safe, rim, (float(xs[0]), float(ys[0])), d, da)


def framed(header: str, blocks: list[str], spec: "MachiningSpec", blend: str, safe: float, rim: float,
           first: tuple[float, float], d: int, da: int) -> str:
    """A 4th-axis program: the ``header`` comments, the modal start (G21 metric, G90, G17, G64
    blending ``blend``), a rapid to ``first`` = (X, Y) at A 0 above the rim (``safe`` mm), the
    spindle, the plunge to the ``rim`` radius, G93 inverse time, the cutting ``blocks``, and back
    to G94, the safe height, M5 and M2; ``d``, ``da``: decimals of mm and deg."""
    head = header + "\n" + (
        f"{spec.units_word} G90 G17 G40 G49 G80 G94\n"
        f"G64 P{blend}\n"
        f"G0 Z{safe:.{d}f}\n"
        f"G0 X{first[0]:.{d}f} Y{first[1]:.{d}f} A{0.0:.{da}f}\n"
        f"M3 S{spec.spindle_rpm:.0f}\n"
        f"G1 Z{rim:.{d}f} F{spec.plunge_feed:.{spec.feed_decimals}f}\n"
        "G93\n"
    )
    return head + "".join(blocks) + f"G94\nG0 Z{safe:.{d}f}\nM5\nM2\n"


def writer(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """The barrel cam's ``ngc`` for a groove (a rib's: :func:`camgen.export.gcode_barrel_rib.writer`):
    its groove (``cam.built.groove``) milled on a 4th axis; errors name the scene keys."""
    groove = getattr(cam.built, "groove")
    return named_program(cam, run, lambda: barrel_program(groove, run.machining, cam.name, run.scene_name))


def named_program(cam: "CamResult", run: "RunSettings", make: Callable[[], str]) -> str:
    """``make()``, a barrel cam's program from ``run.machining``: a :class:`ParameterError` naming
    a machining or output parameter is re-raised naming its scene key, its valid range said for
    the cam ``cam.name``; one naming the cam's own key (``cams.``) passes unchanged."""
    from camgen.keynames import renamed
    from camgen.outputs import machining_keys, output_keys

    assert run.machining.chord_tol == run.output.chord_tol, "the scene reader gives a G-code run its chord tolerance"
    try:
        return renamed("machining", machining_keys(), make, also=(("output", output_keys()),))
    except ParameterError as exc:
        if exc.name.startswith("cams."):
            raise
        raise ParameterError(exc.name, exc.value, f"{exc.valid} for cam '{cam.name}'", exc.why) from None
