"""G-code (RS274/NGC) for milling the cam profile: LinuxCNC dialect by default, GRBL on request.

The program cuts the outside of the profile in step-down passes to the stock bottom and
``breakthrough`` below it:

* header ``G21 G90 G17 G40 G49 G80 G94`` (+ ``G64 P<blend>`` path blending tolerance for LinuxCNC);
* by default the **tool-centre path**: the profile offset outward by the tool radius (exact
  arcs stay ``G2/G3``; spline segments become biarcs ``G2/G3`` or ``G1`` chords);
* optionally **cutter compensation** (LinuxCNC only): the profile itself with ``G41.1/G42.1
  D<diameter>``, switched on along the lead-in and off (``G40``) along the lead-out;
* climb milling (clockwise around the outside with a clockwise spindle, ``M3``) or conventional.

Lead-in and lead-out (the same geometry in both modes).  The tool enters and leaves along the
tangent of the tool-centre path at its start ``S' = S + r n`` (``S`` on the profile, ``n`` the
outward normal, ``t`` the travel direction, ``L`` the lead length): it plunges at
``P0 = S' - L t`` and runs straight to ``S'``; after the closed contour it runs on to
``Q = S' + L t``.  ``S`` is a **support point** of the profile: its tangent line touches the
profile and has all of it on one side (a point of the convex hull where the curvature is > 0;
the sharpest such point is taken).  The lead line lies at distance ``r`` outside that tangent
line, so every point of the lead-in, the lead-out and the plunge is at least ``r`` from every
point of the profile: the tool disc swept along them never touches the part.

Cutter compensation.  LinuxCNC's interpreter (``convert_straight_comp1``) ends the entry move
at ``A' = A + r u_perp`` (``A`` the programmed point, ``u`` the direction from the tool to
``A``); a following line that turns the other way is a concave corner and moves that end to
the intersection of the two offset lines.  camgen therefore programs the entry on the
profile's tangent line: ``G41.1`` to ``A = S - a t`` from ``P0``, then a line ``A -> S``.  With
``L' = min(sqrt(L^2 - r^2) / 2, r / tan(COMP_ENTRY_ANGLE))`` the length of the entry move along
the tangent (``a = L - L'``; its angle to the tangent stays above LinuxCNC's 0.05 rad, below
which a corner is run straight on), the
interpreter ends the entry move on the offset line at ``S' - (L - sqrt(L'^2 + r^2)) t``,
before ``S'``: the tool runs along the tangent from ``P0`` to ``S'`` and into the contour with
no corner.  The exit programs a line ``S -> B = S + (L / 2) t`` (tool on the offset line),
then ``G40`` with a straight move to ``Q``, again along the tangent.  A concave arc whose
radius is not above the tool radius is refused (LinuxCNC's own rule); arcs too short to print
safely are written as lines, never as arcs that the control could read as full circles.

Error budget.  The program follows the ideal tool path within ``chord_tol``:
``FIT_SHARE`` for the biarc / chord fit of spline segments, ``REFIT_SHARE`` for the offset
refit of spline segments, ``ROUNDING_SHARE`` for the printed decimals (a printed point is
within ``sqrt(2)/2 * 10^-decimals`` of its value; an arc, whose centre and both ends are
printed, within three times that) and ``BLEND_SHARE`` for LinuxCNC's path blending
(``G64 P``).  ``decimals`` too coarse for ``chord_tol`` is a :class:`ParameterError`.

Pockets.  A cam with pockets (a groove cam's groove, :class:`camgen.kinds.base.Pocket`) has them
milled first, to their depth, while the stock still holds the part; then its outline as above
(:mod:`camgen.export.gcode_pockets`: one pass along the pitch curve with a tool of the groove's
width, or two wall passes and the slot cleared with a smaller one; the header says which).

A concave radius of the profile smaller than the tool radius would be gouged: that is a
:class:`GeometryError` naming the cam angle.  Z = 0 is the top face of the stock.
"""
from __future__ import annotations

import io
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Sequence

import numpy as np

from camgen.contour import Arc, Contour, Spline
from camgen.errors import CornerError, GeometryError, ParameterError, ceil_significant, require_finite, require_positive
from camgen.export.tables import format_rows

if TYPE_CHECKING:
    from camgen.kinds.base import Pocket

DIALECTS = ("linuxcnc", "grbl")
DIRECTIONS = ("climb", "conventional")
SPLINE_MODES = ("lines", "biarcs")

#: Shares of ``chord_tol`` (they sum to 1): fit of spline segments by biarcs or chords,
#: offset refit of spline segments, printed decimals, LinuxCNC path blending (G64 P).
FIT_SHARE = 0.6
REFIT_SHARE = 0.05
ROUNDING_SHARE = 0.25
BLEND_SHARE = 0.1
#: LinuxCNC's TOLERANCE_CONCAVE_CORNER (rad): compensated corners flatter than this are run
#: straight on (interp_internal.hh).
COMP_STRAIGHT = 0.05
#: Angle (rad) between the compensation entry move and the tangent lead line, above COMP_STRAIGHT
#: so that LinuxCNC treats the corner as concave and moves the entry's end onto the offset line.
COMP_ENTRY_ANGLE = 0.1
#: Largest distance (mm) the profile may reach beyond the tangent line at the start point.
SUPPORT_TOL = 1e-7
#: Sagitta of the coarse polygon whose chord midpoints are the start-point candidates, as a
#: fraction of the contour size.
START_SAMPLING = 1e-3
#: Candidates of the start point whose support is tested at once (in order of falling curvature).
START_BATCH = 32


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

    def __post_init__(self) -> None:
        for name in ("tool_diameter", "thickness", "step_down", "safe_z", "feed", "plunge_feed", "spindle_rpm", "chord_tol"):
            require_positive(name, getattr(self, name), "")
        if require_finite("breakthrough", self.breakthrough) < 0.0:
            raise ParameterError("breakthrough", self.breakthrough, "breakthrough >= 0 mm")
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
        return self.tool_diameter / 2

    @property
    def lead_length(self) -> float:
        return self.lead if self.lead is not None else self.tool_radius + 3.0

    @property
    def depth(self) -> float:
        """Depth of the last pass below the stock top, mm: thickness + breakthrough."""
        return self.thickness + self.breakthrough


def tool_path(contour: Contour, spec: MachiningSpec) -> Contour:
    """The contour the tool centre follows: ``contour`` offset outward by the tool radius.

    Spline segments are refitted within ``REFIT_SHARE * chord_tol`` (at most 1e-6 mm).
    Raises :class:`GeometryError` where a concave radius is smaller than the tool radius.
    """
    try:
        return contour.offset(spec.tool_radius, spline_tol=min(1e-6, REFIT_SHARE * spec.chord_tol))
    except CornerError as exc:  # no tool radius follows a corner exactly
        raise CornerError(f"a tool of diameter {spec.tool_diameter:g} mm cannot follow the profile: {exc}") from None
    except GeometryError as exc:
        raise GeometryError(
            f"a tool of diameter {spec.tool_diameter:g} mm would gouge the profile ({exc}); "
            "use a tool whose radius is below the smallest concave radius"
        ) from None


# ------------------------------------------------------------------------------------------
# start point and contour rotation
# ------------------------------------------------------------------------------------------
def start_parameter(path: Contour, what: str = "lead") -> float:
    """Global parameter of the start point on ``path``: a support point (the tangent line has
    the whole path on one side, within ``SUPPORT_TOL`` mm) with positive curvature, the sharpest one.

    Candidates are the chord midpoints of a coarse flattening (never a segment end).  Raises
    :class:`GeometryError` naming ``what`` when no candidate qualifies (a hull made of corners).
    """
    params = path.flatten_params(START_SAMPLING * max(path.size, 1.0))
    mid = 0.5 * (params + np.append(params[1:], path.n_segments))
    points = path.evaluate(mid)
    normals = path.normal(mid)
    kappa = path.curvature(mid)
    psi = np.arctan2(normals[:, 1], normals[:, 0])
    # the sharpest convex candidate on the hull: test the support in order of falling curvature,
    # a batch at a time (the support costs pieces x directions; the first batches decide)
    order = np.argsort(-kappa, kind="stable")
    order = order[kappa[order] > 0.0]
    for lo in range(0, order.size, START_BATCH):
        batch = order[lo:lo + START_BATCH]
        gap = path.support(psi[batch]) - np.einsum("ij,ij->i", points[batch], normals[batch])
        ok = gap <= SUPPORT_TOL
        if ok.any():
            return float(mid[batch[np.argmax(ok)]])
    raise GeometryError(
        f"no safe start for the {what}: no point of the contour's convex hull has a tangent "
        "(the hull is made of corners); the tangent lead-in needs a smooth convex stretch"
        + ("; set cutter_compensation = false" if what == "cutter_compensation" else "")
    )


def _shift_piece(c: np.ndarray, delta: float) -> np.ndarray:
    """Coefficients (p + 1, 2) of the degree-p polynomial piece ``c`` (highest power first)
    re-expanded at ``tau = delta`` (Taylor shift: the coefficient of ``tau^k`` becomes
    ``P^(k)(delta) / k!``), by repeated synthetic division (Horner's scheme applied p times:
    Knuth, TAOCP vol. 2, sec. 4.6.4)."""
    out = np.array(c, dtype=float)
    p = out.shape[0] - 1
    for i in range(p):  # pass i leaves the coefficient of tau^i (row p - i) final
        for j in range(1, p + 1 - i):
            out[j] = out[j] + delta * out[j - 1]
    return out


def _split(seg: Arc | Spline, u: float) -> tuple[Arc | Spline | None, Arc | Spline | None]:
    """``seg`` split at local parameter ``u`` in (0, 1): (head, tail); None for an empty part."""
    if isinstance(seg, Arc):
        return (Arc(seg.center, seg.radius, seg.start_angle, seg.sweep * u),
                Arc(seg.center, seg.radius, seg.start_angle + seg.sweep * u, seg.sweep * (1.0 - u)))
    t = seg.breaks[0] + u * seg.span
    j = int(np.clip(np.searchsorted(seg.breaks, t, side="right") - 1, 0, seg.n_pieces - 1))
    delta = t - seg.breaks[j]
    if delta <= 1e-12 * seg.span:  # on a break: no piece to cut
        head = Spline(seg.breaks[: j + 1], seg.coeffs[:, :j]) if j > 0 else None
        return head, Spline(seg.breaks[j:], seg.coeffs[:, j:])
    tail_coeffs = np.concatenate([_shift_piece(seg.coeffs[:, j], delta)[:, None], seg.coeffs[:, j + 1 :]], axis=1)
    tail = Spline(np.concatenate([[t], seg.breaks[j + 1 :]]), tail_coeffs)
    head = Spline(np.concatenate([seg.breaks[: j + 1], [t]]), seg.coeffs[:, : j + 1])
    return head, tail


def rotate(path: Contour, t: float) -> Contour:
    """The same closed path starting at global parameter ``t`` (the segment there is split)."""
    i = int(math.floor(t)) % path.n_segments
    u = t - math.floor(t)
    segs = list(path.segments)
    if u <= 0.0:
        order = segs[i:] + segs[:i]
    else:
        head, tail = _split(segs[i], u)
        assert tail is not None  # u < 1: the tail is never empty
        order = [tail] + segs[i + 1 :] + segs[:i] + ([head] if head is not None else [])
    return Contour(order, closure_tol=1e-5)


# ------------------------------------------------------------------------------------------
# primitives
# ------------------------------------------------------------------------------------------
def _line_tolerance(contour: Contour, spec: MachiningSpec) -> float:
    """Chord tolerance of ``lines`` mode, mm.

    Without compensation it is the fit share of ``chord_tol``.  With compensation LinuxCNC
    treats a chord corner below ``COMP_STRAIGHT`` rad as straight and starts the next offset
    chord where the previous one ended (no arc, no intersection).  For chords of sagitta ``f``
    on a radius ``R`` the tool then reaches into the part by ``f (1 + 2 r/R - (r/R)^2) <= 2 f``
    on a convex stretch and by ``r f / (R - r)`` on a concave one (the offset point of each
    vertex is tilted by the chord angle ``sqrt(8 f / R)``): ``f`` is scaled by
    ``min(1/2, (R - r) / r)`` with R the smallest concave radius of the spline segments.
    """
    fit = FIT_SHARE * spec.chord_tol
    if not spec.cutter_compensation:
        return fit
    r = spec.tool_radius
    u = np.linspace(0.0, 1.0, 4097)
    kappa = [np.min(seg.curvature(u)) for seg in contour.segments if not isinstance(seg, Arc)]
    least = min(kappa, default=0.0)
    scale = 0.5 if least >= 0.0 else min(0.5, (1.0 / -least - r) / r)
    return fit * scale


def primitives(contour: Contour, spec: MachiningSpec) -> list[tuple]:
    """Counter-clockwise primitives: ('arc', Arc) or ('lines', points (n, 2) excluding the start)."""
    if spec.spline_mode == "biarcs" and any(not isinstance(s, Arc) for s in contour.segments):
        from camgen.contour.arcspline import to_arc_spline

        contour = to_arc_spline(contour, FIT_SHARE * spec.chord_tol)
    tol = _line_tolerance(contour, spec)
    out: list[tuple] = []
    for seg in contour.segments:
        if isinstance(seg, Arc):
            out.append(("arc", seg))
        else:
            u = np.append(seg.flatten_params(tol)[1:], 1.0)
            out.append(("lines", seg.point(u)))
    return out


def reverse_primitives(prims: list[tuple], start: np.ndarray) -> list[tuple]:
    """The same closed path travelled the other way round (clockwise), from the same start."""
    out: list[tuple] = []
    ends = [start] + [p[1].end_point if p[0] == "arc" else p[1][-1] for p in prims[:-1]]
    for (kind, item), begin in zip(reversed(prims), reversed(ends)):
        if kind == "arc":
            out.append(("arc", Arc(item.center, item.radius, item.start_angle + item.sweep, -item.sweep)))
        else:
            out.append(("lines", np.vstack([item[-2::-1], begin[None]])))
    return out


def _check_compensated_arcs(prims: list[tuple], spec: MachiningSpec) -> None:
    """Concave arcs of the counter-clockwise profile ``prims`` under cutter compensation.

    LinuxCNC refuses an arc with the tool inside whose radius is not above the tool radius, and
    an arc whose compensated chord is too short to print (< 100 units of the last decimal)
    could run as a full circle: both are a :class:`GeometryError` naming ``cutter_compensation``.
    """
    r = spec.tool_radius
    least = 100.0 * 10.0 ** (-spec.decimals)
    for kind, arc in prims:
        if kind != "arc" or arc.sweep > 0:  # convex: the tool runs outside the arc
            continue
        half = math.sin(min(abs(arc.sweep), math.pi) / 2.0)
        written_as_arc = 2.0 * arc.radius * half >= least
        if arc.radius <= r or (written_as_arc and 2.0 * (arc.radius - r) * half < least):
            mid = arc.point(np.array([0.5]))[0]
            polar = math.degrees(math.atan2(mid[1], mid[0])) % 360.0
            raise GeometryError(
                f"cutter_compensation: the concave arc of radius {arc.radius:.4g} mm near cam angle {polar:.3f} deg "
                f"leaves the tool (radius {r:g} mm) too little room for LinuxCNC's compensation; "
                "set cutter_compensation = false (camgen then writes the exact tool-centre path) or use a smaller tool"
            )


# ------------------------------------------------------------------------------------------
# writing
# ------------------------------------------------------------------------------------------
class MoveWriter:
    """Moves printed from the printed current point: I/J from printed values, zero-length moves
    dropped, arcs too short to print safely written as lines.  A move given ``z`` also prints its
    Z word (a ramp: lines with Z, helical G2/G3)."""

    def __init__(self, decimals: int, start: np.ndarray, z: float | None = None) -> None:
        self.d = decimals
        self.unit = 10.0 ** (-decimals)
        self.current = self.round(start)
        self.z = None if z is None else self.round_z(z)
        self.out = io.StringIO()

    def round(self, p: np.ndarray) -> np.ndarray:
        return np.round(np.asarray(p, dtype=float), self.d) + 0.0

    def round_z(self, z: float) -> float:
        return round(float(z), self.d) + 0.0

    def xy(self, p: np.ndarray) -> str:
        return f"X{p[0]:.{self.d}f} Y{p[1]:.{self.d}f}"

    def _z_word(self, z: float | None) -> str:
        if z is None:
            return ""
        self.z = self.round_z(z)
        return f" Z{self.z:.{self.d}f}"

    def line(self, p: np.ndarray, prefix: str = "", z: float | None = None) -> None:
        q = self.round(p)
        if np.array_equal(q, self.current) and not prefix and (z is None or self.round_z(z) == self.z):
            return
        self.out.write(f"{prefix}G1 {self.xy(q)}{self._z_word(z)}\n")
        self.current = q

    def lines(self, points: np.ndarray, z: np.ndarray | None = None) -> None:
        q = self.round(points)
        keep = np.any(q != np.vstack([self.current[None], q[:-1]]), axis=1)
        q = q[keep]
        if len(q):
            if z is None:
                self.out.write(format_rows(q, f"G1 X%.{self.d}f Y%.{self.d}f"))
            else:
                zq = np.round(np.asarray(z, dtype=float)[keep], self.d) + 0.0
                self.out.write(format_rows(np.column_stack([q, zq]), f"G1 X%.{self.d}f Y%.{self.d}f Z%.{self.d}f"))
                self.z = float(zq[-1])
            self.current = q[-1]

    def arc(self, arc: Arc, z: float | None = None) -> None:
        end = self.round(arc.end_point)
        centre = self.round(np.asarray(arc.center))
        chord = float(np.hypot(*(end - self.current)))
        sagitta = arc.radius * (1.0 - math.cos(min(abs(arc.sweep), math.pi) / 2.0))
        if chord < 100.0 * self.unit and sagitta <= math.sqrt(2.0) * self.unit:
            self.line(end, z=z)  # within the rounding budget, and never misread as a full circle
            return
        # the sweep the control will run: from the printed start to the printed end about the printed centre
        a0 = math.atan2(self.current[1] - centre[1], self.current[0] - centre[0])
        a1 = math.atan2(end[1] - centre[1], end[0] - centre[0])
        run = (a1 - a0) % (2 * math.pi) if arc.sweep > 0 else -((a0 - a1) % (2 * math.pi))
        if chord == 0.0 or abs(run - arc.sweep) > 1e-2 * max(1.0, abs(arc.sweep)):
            raise GeometryError(
                f"an arc of radius {arc.radius:.6g} mm and sweep {math.degrees(arc.sweep):.6g} deg cannot be "
                f"printed with {self.d} decimals; raise decimals"
            )
        ij = centre - self.current
        word = "G3" if arc.sweep > 0 else "G2"
        self.out.write(f"{word} {self.xy(end)}{self._z_word(z)} I{ij[0]:.{self.d}f} J{ij[1]:.{self.d}f}\n")
        self.current = end

    def text(self) -> str:
        return self.out.getvalue()


def loop_moves(prims: list[tuple], start: np.ndarray, decimals: int) -> str:
    """The moves of the closed path ``prims`` from ``start`` back to it (XY only: the Z of the
    pass is modal).  Raises :class:`GeometryError` when the written path does not close."""
    writer = MoveWriter(decimals, start)
    for kind, item in prims:
        if kind == "arc":
            writer.arc(item)
        else:
            writer.lines(item)
    gap = float(np.hypot(*(writer.current - writer.round(start))))
    if gap > 1e-4:
        raise GeometryError(f"the written contour does not close: it ends {gap:.3g} mm from its start")
    writer.line(start)  # a gap of the offset's closure tolerance, if any
    return writer.text()


def comment(text: str) -> str:
    """An RS274 comment: parentheses cannot nest, so they are replaced in the text."""
    return "(" + text.replace("(", "[").replace(")", "]") + ")"


def blend_word(tol: float, decimals: int) -> str:
    """``P`` value of ``G64`` printed rounded down (P0 would mean no tolerance at all)."""
    for k in range(decimals, decimals + 6):
        value = math.floor(tol * 10**k) / 10**k
        if value >= 0.5 * tol:
            return f"{value:.{k}f}"
    return f"{tol:.3e}"


#: Most moves (lines) of one G-code program: about 60 MB of text, what controllers and CAM
#: viewers still load (the contour is repeated in every depth pass).
MAX_PROGRAM_MOVES = 2_000_000


#: Most depth passes of a G-code program (thickness + breakthrough over step_down_mm).
MAX_PASSES = 1000


def depth_passes(depth: float, step: float) -> float:
    """Depth passes of a program cutting ``depth`` mm in steps of ``step`` mm, as
    :func:`gcode_program` counts them (inf for a step so small that the count overflows)."""
    ratio = depth / step
    return max(1, math.ceil(ratio - 1e-9)) if math.isfinite(ratio) else math.inf


def _refuse_long_program(spec: MachiningSpec, depth: float, n_passes: int, moves: int) -> None:
    """Raise the :class:`ParameterError` for a program of more than :data:`MAX_PROGRAM_MOVES`
    moves: fewer passes (``step_down_mm``) where one pass fits, else a coarser path."""
    why = f"{n_passes} passes of {moves} moves would make {n_passes * moves} lines, more than the {MAX_PROGRAM_MOVES} a program may hold"
    passes = MAX_PROGRAM_MOVES // moves
    if passes >= 1:
        raise ParameterError("step_down_mm", spec.step_down, f">= {ceil_significant(depth / passes, 3):.3g} mm", why)
    coarser = '"biarcs" or a larger chord_tol' if spec.spline_mode == "lines" else "a larger chord_tol"
    raise ParameterError("spline_mode" if spec.spline_mode == "lines" else "chord_tol", spec.spline_mode if spec.spline_mode == "lines" else spec.chord_tol,
                         coarser, why)


def gcode_program(contour: Contour, spec: MachiningSpec, cam: str = "cam", scene: str = "", thickness: float | None = None,
                  pockets: "Sequence[Pocket]" = ()) -> str:
    """RS274/NGC program text that mills ``contour`` (the cam profile) to ``thickness`` (mm; the
    cam's, default ``spec.thickness``) plus ``spec.breakthrough``, with tangent lead-in and
    lead-out (see the module docstring).  ``spec`` is final (the scene reader checked it against
    its chord tolerance and the cam's depth): it is used as it is.

    ``pockets`` (a groove cam's groove) are milled first, to their depth, while the stock still
    holds the part (:mod:`camgen.export.gcode_pockets`: one pass along the pitch curve, or two
    wall passes and the slot cleared); then the outline as without them."""
    from camgen import __version__

    pocketed = None
    if pockets:
        from camgen.export.gcode_pockets import pocket_program

        pocketed = pocket_program(pockets, spec)

    comp = spec.cutter_compensation
    # the start is chosen on the profile; the offset keeps the parameter (arcs: same angles,
    # splines: refitted at the same parameter values), so it starts at the same global parameter
    t_start = start_parameter(contour, "cutter_compensation" if comp else "lead")
    offset = tool_path(contour, spec)  # in compensation mode still refuses a gouging tool
    path = rotate(contour if comp else offset, t_start)
    prims = primitives(path, spec)
    if comp:
        _check_compensated_arcs(prims, spec)
    start = path.segments[0].start_point
    tangent = path.tangent(np.array([0.0]))[0]  # counter-clockwise
    normal = np.array([tangent[1], -tangent[0]])  # outward
    climb = spec.direction == "climb"
    if climb:
        prims = reverse_primitives(prims, start)
    travel = -tangent if climb else tangent
    r, lead = spec.tool_radius, spec.lead_length
    centre_start = start + r * normal if comp else start  # S': the tool centre at the start
    plunge = centre_start - lead * travel
    leave = centre_start + lead * travel
    if comp:
        # L': length of the entry move along the tangent; its angle atan(r / L') to the tangent
        # stays above COMP_STRAIGHT so that LinuxCNC takes the corner as concave
        entry = min(math.sqrt(lead * lead - r * r) / 2.0, r / math.tan(COMP_ENTRY_ANGLE))
        a_point = start - (lead - entry) * travel
        b_point = start + 0.5 * lead * travel

    contour_moves = loop_moves(prims, start, spec.decimals)

    d = spec.decimals

    def xy(p: np.ndarray) -> str:
        return f"X{p[0]:.{d}f} Y{p[1]:.{d}f}"

    stock = spec.thickness if thickness is None else require_positive("thickness", thickness, "mm")
    depth = stock + spec.breakthrough
    n_passes = max(1, math.ceil(depth / spec.step_down - 1e-9))
    moves = contour_moves.count("\n") + 6  # + plunge, feed down, lead-in (2), lead-out (2)
    if pocketed is not None:  # the pockets' levels count as passes of the same length on average
        moves += -(-pocketed.count // n_passes)
    if n_passes * moves > MAX_PROGRAM_MOVES:
        _refuse_long_program(spec, depth, n_passes, moves)
    depths = -np.minimum(spec.step_down * np.arange(1, n_passes + 1), depth)
    chord_tol = spec.chord_tol
    blend = blend_word(BLEND_SHARE * chord_tol, d)
    if comp:
        # G41: tool left of the travel direction = outside of a clockwise (climb) path
        side = "G41.1" if climb else "G42.1"
        lead_in = f"{side} D{spec.tool_diameter:.{d}f} G1 {xy(a_point)} F{spec.feed:.0f}\nG1 {xy(start)}\n"
        lead_out = f"G1 {xy(b_point)}\nG40 G1 {xy(leave)}\n"
        mode = f"cutter compensation {side} on the profile"
    else:
        lead_in = f"G1 {xy(start)} F{spec.feed:.0f}\n"
        lead_out = f"G1 {xy(leave)}\n"
        mode = "tool-centre path = profile offset by the tool radius"
    fit_what = "biarc" if spec.spline_mode == "biarcs" else "chord"
    lines = [
        comment(f"camgen {__version__}: cam '{cam}'" + (f", scene '{scene}'" if scene else "")),
        comment(f"units mm; tool diameter {spec.tool_diameter:g}; {mode}; {spec.direction} milling, outside contour"),
        comment(f"stock top Z0, bottom Z{-stock:g}; last pass Z{-depth:g} = {spec.breakthrough:g} below the stock bottom "
                 f"(breakthrough); {n_passes} passes of <= {spec.step_down:g}"),
        comment(f"path tolerance {chord_tol:g} = {fit_what} fit {FIT_SHARE * chord_tol:.3g} + offset refit "
                 f"{min(1e-6, REFIT_SHARE * chord_tol):.3g} "
                 f"+ {d} printed decimals {rounding_error(d):.3g}"
                 + (f" + G64 blending {blend}" if spec.dialect == "linuxcnc" else "")),
        comment(f"tangent lead-in and lead-out of {lead:g} at tool-centre point {xy(centre_start)}, plunge at {xy(plunge)}"),
    ]
    if pocketed is not None:
        lines += list(pocketed.header)
    lines.append("G21 G90 G17 G40 G49 G80 G94")
    if spec.dialect == "linuxcnc":
        lines.append(f"G64 P{blend}")
    lines += [f"G0 Z{spec.safe_z:.{d}f}", f"M3 S{spec.spindle_rpm:.0f}"]
    body = ["\n".join(lines) + "\n"]
    if pocketed is not None:
        body.append(pocketed.moves)
    for k, z in enumerate(depths, 1):
        body.append(
            f"(pass {k} of {n_passes}: Z{z:.{d}f})\n"
            f"G0 {xy(plunge)}\n"
            f"G1 Z{z:.{d}f} F{spec.plunge_feed:.0f}\n"
            f"{lead_in}"
            f"{contour_moves}"
            f"{lead_out}"
            f"G0 Z{spec.safe_z:.{d}f}\n"
        )
    body.append("M5\nM2\n")
    return "".join(body)
