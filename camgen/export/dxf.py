"""2-D DXF export: R2010 (or R12), units mm, ARC and LINE entities every reader takes.

The file is written by camgen's own DXF writer (:mod:`camgen.export.dxfwriter`): no third-party
library is imported at run time, numbers are the exact doubles (``repr``), and the same drawing
always gives the same bytes (no time stamps or GUIDs).

Spline segments are written in one of two ways (:class:`DxfOptions` ``splines``):

* ``"biarc"`` (default): G1 chains of circular ARCs (and LINEs where the curve is straight)
  within ``chord_tol`` mm of the exact curve (:mod:`camgen.numerics.biarc`).  OpenSCAD, laser and CAM
  programs import these; many of them ignore or reject SPLINE entities.
* ``"bspline"``: clamped cubic B-splines (always cubic, whatever the segment's degree: LibreCAD
  and most CAM readers take SPLINEs of degree <= 3 only) for CAD programs (fit-point-only or raw periodic-knot
  SPLINEs are misread by independent readers, see ``shared/research/ecosystem.md`` section 3):
  the compact form of every spline segment (:func:`compact_spline`: the fewest C2 pieces within
  ``bspline_tol`` mm of the contour, with its ends and joints kept exactly; a cubic segment
  itself, exactly, where that has no fewer pieces; a quintic segment always refitted), written
  exactly with simple interior knots.

Arc segments (three-arc cams) are exact ARCs in both modes; a segment that is a whole circle
(a groove cam's rim, a circular groove wall) is a CIRCLE.

What is cut and what is construction: the layers ``PROFILE`` (the outline), ``BORE`` and
``KEYWAY`` (the hole: one closed loop of the bore ARC, or CIRCLE, and the keyway's three sides)
are the part; programs that import a whole file (OpenSCAD's ``import()``, laser and CAM
programs) cut or extrude every curve they find, so a drawing holds only these unless it is given
construction geometry.  A body with pockets (a groove, a slot: :class:`camgen.kinds.base.Pocket`)
has each pocket wall cut on a layer of its own, named after the wall (``GROOVE_OUTER``,
``GROOVE_INNER``, ...), drawn as PROFILE is; each pocket's depth is a header custom property.
Construction: ``PITCH`` (the follower-centre path), ``CENTER`` (a cross on the rotation
axis, :class:`DxfOptions` ``center_mark``) and ``ZERO`` (cams that know their cam angle 0: a LINE
from the rotation axis to the point of the profile the follower touches at cam angle 0, and an
ARC about the axis, half that radius, 40 deg, ending in an arrow head of two LINEs in the
direction the cam turns).  Only the layers drawn are defined.  The header extents ($EXTMIN,
$EXTMAX, and $LIMMIN/$LIMMAX) are the exact bounding box of everything drawn; the spline mode
and tolerance are stated in the header's custom properties (``camgen_splines`` and
``camgen_biarc_tol_mm`` or ``camgen_bspline_tol_mm``).

``DxfOptions(version="R12")`` writes the same drawing as an R12 (AC1009) file for legacy CAM
programs (:mod:`camgen.export.dxfwriter`): LINE, ARC, CIRCLE and POLYLINE only, spline segments
as biarcs (R12 has no SPLINE: ``splines = "bspline"`` is refused), the custom properties and the
units as comments.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from camgen.contour import DEFAULT_CHORD_TOL, SPLINE_DEGREES, Arc, Contour, Spline
from camgen.errors import ExportError, ParameterError, require_finite, require_positive
from camgen.export.atomic import write_atomic
from camgen.export.dxfwriter import DXF_VERSIONS, DxfDocument

__all__ = [
    "C1_JUMP", "C2_JUMP", "CONSTRUCTION_LAYERS", "CUT_LAYERS", "DEFAULT_BSPLINE_TOL", "DxfOptions", "FULL_TURN", "PROFILE_LAYER",
    "SPLINE_MODES", "ZERO_ARROW_RADIUS", "arc_contour", "ZERO_ARROW_SWEEP", "compact_spline", "contour_to_dxf", "drawing_bounds",
    "spline_bezier_controls", "spline_bspline", "write_dxf", "zero_mark_geometry",
]

PROFILE_LAYER = "PROFILE"
#: Layers of what is cut (the part) and of construction geometry (drawn only when given), with
#: their ACI colours.
CUT_LAYERS = {PROFILE_LAYER: 7, "BORE": 2, "KEYWAY": 3}
CONSTRUCTION_LAYERS = {"PITCH": 4, "CENTER": 1, "ZERO": 6}


def _degree_of(spline: Spline) -> int:
    degree = int(spline.degree)
    if degree not in SPLINE_DEGREES:  # Spline refuses other shapes; a guard for look-alikes
        raise ParameterError("spline degree", degree, f"one of {SPLINE_DEGREES}")
    return degree


def spline_bezier_controls(spline: Spline) -> tuple[np.ndarray, np.ndarray]:
    """Exact clamped B-spline form of a piecewise polynomial of degree ``p`` (``spline.degree``,
    3 or 5): knots (pK + p + 2,) and control points (pK + 1, 2).

    Each piece on ``[t_i, t_i + h]`` becomes its ``p + 1`` Bezier control points (power basis in
    ``s = tau / h``, ``b_i = a_i h^i``, then ``P_j = sum_{i <= j} C(j, i) / C(p, i) b_i``: Farin,
    *Curves and Surfaces for CAGD*, ch. 5); interior breaks get knot multiplicity ``p``, the ends
    ``p + 1``.  The degree of the result is ``knots.size - len(controls) - 1`` (= ``p``): a
    writer that only takes cubics must check it (the DXF writer writes only cubic SPLINEs).
    """
    p = _degree_of(spline)
    a = spline.coeffs[::-1]  # ascending powers in tau: (p + 1, K, 2)
    h = np.diff(spline.breaks)[:, None]
    b = [a[i] * h**i for i in range(p + 1)]  # power basis in s = tau / h
    points = [sum(math.comb(j, i) / math.comb(p, i) * b[i] for i in range(j + 1)) for j in range(p + 1)]
    controls = np.concatenate([points[0][:1], np.stack(points[1:], axis=1).reshape(-1, 2)])
    t = spline.breaks
    knots = np.concatenate([[t[0]] * (p + 1), np.repeat(t[1:-1], p), [t[-1]] * (p + 1)])
    return knots, controls


#: Relative jumps (of the end points' scale) of the first and second derivatives below which an
#: interior break counts as C1 and C2 (:func:`_break_continuity`).
C1_JUMP = 1e-10
C2_JUMP = 1e-8


def _break_continuity(spline: Spline) -> np.ndarray:
    """Order of continuity (K - 1,) at the interior breaks of ``spline``: 2 where value, first and
    second derivatives agree (within :data:`C1_JUMP`, :data:`C2_JUMP` of the curve's scale), 1
    where the first does, 0 elsewhere."""
    t = spline.breaks
    inner = t[1:-1].size
    if not inner:
        return np.zeros(0, dtype=int)
    scale = max(1.0, float(np.max(np.abs(spline.coeffs[-1]))))  # the pieces' start points
    left, right = np.arange(inner), np.arange(1, inner + 1)
    h = np.diff(t)[:-1]
    d1 = spline.eval_piece(left, h, 1) - spline.eval_piece(right, np.zeros(inner), 1)
    d2 = spline.eval_piece(left, h, 2) - spline.eval_piece(right, np.zeros(inner), 2)
    c1 = np.max(np.abs(d1), axis=1) <= C1_JUMP * scale
    c2 = c1 & (np.max(np.abs(d2), axis=1) <= C2_JUMP * scale)
    return np.where(c2, 2, np.where(c1, 1, 0))


def spline_bspline(spline: Spline, tol: float = 1e-9) -> tuple[np.ndarray, np.ndarray]:
    """The clamped B-spline of degree ``p = spline.degree`` holding ``spline`` with the fewest
    knots: interior knot multiplicity ``p - 2`` at C2 breaks, ``p - 1`` at C1 breaks, ``p``
    elsewhere (cubic: 1, 2, 3; quintic: 3, 4, 5), knots (n + p + 1,), control points (n, 2).

    The control points come from interpolation at the Greville abscissae in that spline space,
    which holds the piecewise polynomial exactly; the result is checked against the spline at
    the quarter points of every piece and replaced by :func:`spline_bezier_controls` if it is
    more than ``tol`` mm off.  The degree of the result is ``knots.size - len(controls) - 1``.
    """
    from scipy.interpolate import make_interp_spline

    p = _degree_of(spline)
    t = spline.breaks
    inner = t[1:-1]
    mult = p - _break_continuity(spline)
    knots = np.concatenate([[t[0]] * (p + 1), np.repeat(inner, mult), [t[-1]] * (p + 1)])
    count = knots.size - p - 1
    greville = np.mean([knots[j : count + j] for j in range(1, p + 1)], axis=0)
    greville[0], greville[-1] = t[0], t[-1]  # (p a) / p may round to just outside [a, b]: make_interp_spline refuses that
    try:
        fit = make_interp_spline(greville, spline.eval_t(greville), k=p, t=knots)
    except (ValueError, np.linalg.LinAlgError):
        return spline_bezier_controls(spline)
    probe = (t[:-1, None] + np.array([0.25, 0.5, 0.75])[None, :] * np.diff(t)[:, None]).ravel()
    if not np.max(np.abs(fit(probe) - spline.eval_t(probe))) <= tol:
        return spline_bezier_controls(spline)
    return knots, np.asarray(fit.c)


#: Default tolerance (mm) of the compact B-spline form of spline segments (:func:`compact_spline`)
#: in DXF (``splines = "bspline"``) and STEP files.
DEFAULT_BSPLINE_TOL = 1e-8


def compact_spline(spline: Spline, tol: float = DEFAULT_BSPLINE_TOL) -> Spline:
    """``spline`` as a piecewise CUBIC with as few pieces as ``tol`` (mm) allows: C2 inside, same ends.

    Every run of pieces between breaks where ``spline`` is not C2 is refitted by a clamped C2
    cubic spline that keeps the run's end points, first and second derivatives exactly (so the
    joints keep their continuity: G2 stays G2) and lies within ``tol`` mm of the run at the
    probe points of every new piece (least squares with knots placed by the error,
    :func:`camgen.numerics.splinefit.fit_clamped`).  A cubic run keeps its own pieces where the refit
    would not have fewer; a run of higher degree (quintic) is always refitted, with as many
    cubic pieces as ``tol`` needs (a cubic's error falls as h^4, a quintic's as h^6: usually
    more pieces than the run), and :class:`GeometryError` when no cubic within ``tol`` exists
    (:data:`camgen.numerics.splinefit.MAX_PIECES`).  The parameter range is unchanged (the parameter
    along the new pieces is not the old one: compare curves by distance, not at equal parameters).
    """
    from camgen.errors import GeometryError
    from camgen.numerics.splinefit import MAX_PIECES, fit_clamped

    tol = require_positive("bspline_tol", tol, "mm")
    cubic = _degree_of(spline) == 3
    c2 = _break_continuity(spline) == 2
    cuts = np.concatenate([[0], np.flatnonzero(~c2) + 1, [spline.n_pieces]])
    breaks: list[np.ndarray] = []
    coeffs: list[np.ndarray] = []
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        run = Spline(spline.breaks[lo : hi + 1], spline.coeffs[:, lo:hi])
        a, b = float(run.breaks[0]), float(run.breaks[-1])
        ends = [run.eval_piece(np.array([i]), np.array([tau]), order)[0]
                for i, tau in ((0, 0.0), (run.n_pieces - 1, float(np.diff(run.breaks)[-1]))) for order in (0, 1, 2)]
        fit = None
        if not cubic:
            fit = fit_clamped(run.eval_t, a, b, tol, tuple(ends), initial_pieces=max(3, run.n_pieces),
                              max_pieces=MAX_PIECES, what=f"cubic form of a degree-{spline.degree} spline (bspline_tol)")
        elif run.n_pieces > 3:
            try:
                fit = fit_clamped(run.eval_t, a, b, tol, tuple(ends), initial_pieces=max(3, run.n_pieces // 8),
                                  max_pieces=run.n_pieces - 1, what="compact B-spline")
            except GeometryError:
                fit = None  # no fewer pieces within tol: keep the (cubic) run as it is
        if fit is None:
            breaks.append(run.breaks[:-1])
            coeffs.append(run.coeffs)
        else:
            breaks.append(fit.breaks[:-1])
            coeffs.append(fit.coeffs)
    return Spline(np.append(np.concatenate(breaks), spline.breaks[-1]), np.concatenate(coeffs, axis=1))


#: Spline modes of :class:`DxfOptions`.
SPLINE_MODES = ("biarc", "bspline")


@dataclass(frozen=True)
class DxfOptions:
    """DXF drawing options.

    Parameters
    ----------
    splines : {"biarc", "bspline"}
        ``"biarc"`` (default): spline segments of PROFILE and PITCH become ARCs and LINEs within
        ``chord_tol`` mm (every DXF reader takes them); ``"bspline"``: clamped cubic B-spline
        SPLINEs within ``bspline_tol`` mm (for CAD programs).
    chord_tol : float
        Largest distance between a spline segment and its biarcs, mm: the run's chord tolerance
        (``output.chord_tol_mm``, under the one name it has from the scene to every writer).
    bspline_tol : float
        Largest distance between a spline segment and its written B-spline (``"bspline"``), mm.
    center_mark : float
        Half-length of the centre cross on the rotation axis (CENTER layer, construction), mm;
        0 (default): no centre mark.
    version : {"R2010", "R12"}
        The file's DXF version (R12: LINE, ARC, CIRCLE and POLYLINE only; ``splines`` must be
        ``"biarc"``).
    """

    splines: str = "biarc"
    chord_tol: float = DEFAULT_CHORD_TOL
    center_mark: float = 0.0
    bspline_tol: float = DEFAULT_BSPLINE_TOL
    version: str = "R2010"

    def __post_init__(self) -> None:
        if self.splines not in SPLINE_MODES:
            raise ParameterError("dxf_splines", self.splines, f"one of {', '.join(SPLINE_MODES)}")
        if self.version not in DXF_VERSIONS:
            raise ParameterError("dxf_version", self.version, f"one of {', '.join(DXF_VERSIONS)}")
        if self.version == "R12" and self.splines != "biarc":
            raise ParameterError("dxf_splines", self.splines, 'biarc with dxf_version = "R12"', "R12 has no SPLINE entity")
        require_positive("chord_tol", self.chord_tol)
        require_positive("bspline_tol", self.bspline_tol)
        if require_finite("center_mark", self.center_mark) < 0:
            raise ParameterError("center_mark", self.center_mark, "center_mark >= 0 mm")


def _is_line(seg: Spline) -> bool:
    """One piece of degree <= 1 (every coefficient above the linear one is 0)."""
    return seg.n_pieces == 1 and not np.any(seg.coeffs[:-2])


def arc_contour(contour: Contour, tol: float) -> Contour:
    """``contour`` as the DXF draws it in biarc mode: every curved spline segment replaced by
    biarcs within ``tol`` mm, arcs and straight pieces (one piece of degree <= 1) kept as they are."""
    from camgen.contour.arcspline import spline_to_biarcs

    if all(isinstance(seg, Arc) or _is_line(seg) for seg in contour.segments):
        return contour
    segments: list[Arc | Spline] = []
    for seg in contour.segments:
        segments.extend([seg] if isinstance(seg, Arc) or _is_line(seg) else spline_to_biarcs(seg, tol))
    return Contour(segments, closure_tol=1e-6)


def _cubic_contour(contour: Contour, tol: float) -> Contour:
    """``contour`` with every curved spline segment replaced by its compact cubic form within
    ``tol`` mm (:func:`compact_spline`: quintic segments always become cubic; ends kept exactly)."""
    if all(isinstance(seg, Arc) or _is_line(seg) for seg in contour.segments):
        return contour
    segments = [seg if isinstance(seg, Arc) or _is_line(seg) else compact_spline(seg, tol) for seg in contour.segments]
    # the ends are kept exactly: the joints' gaps are the contour's own
    gap = max(float(np.hypot(*(a.end_point - b.start_point))) for a, b in zip(contour.segments, contour.segments[1:] + contour.segments[:1]))
    return Contour(segments, closure_tol=max(1e-6, 2.0 * gap))


#: An arc segment sweeping this much (rad) is a whole circle: written as a CIRCLE (an ARC from 0
#: to 360 deg reads back as a zero sweep in some readers).
FULL_TURN = 2.0 * math.pi * (1.0 - 1e-12)


def _add_contour(msp: DxfDocument, contour: Contour, layer: str) -> None:
    """ARCs, LINEs and cubic SPLINEs of ``contour`` as drawn (spline segments already biarcs or
    cubic: :func:`arc_contour`, :func:`_cubic_contour`)."""
    for seg in contour.segments:
        if isinstance(seg, Arc) and abs(seg.sweep) >= FULL_TURN:  # a whole circle (a rim, a circular wall): ARC 0-360 is ambiguous
            msp.add_circle(seg.center, seg.radius, layer)
        elif isinstance(seg, Arc):
            start = math.degrees(seg.start_angle)
            end = math.degrees(seg.start_angle + seg.sweep)
            if seg.sweep < 0:  # DXF arcs always run counter-clockwise from start to end
                start, end = end, start
            msp.add_arc(seg.center, seg.radius, start, end, layer)
        elif _is_line(seg):
            msp.add_line(tuple(seg.start_point), tuple(seg.end_point), layer)
        else:
            if seg.degree != 3:  # LibreCAD and most CAM readers take SPLINEs of degree <= 3 only
                raise ExportError(f"cannot write DXF: a degree-{seg.degree} spline segment on layer {layer} "
                                  "(DXF SPLINEs are written cubic: compact_spline first)")
            knots, controls = spline_bspline(seg)
            msp.add_spline(controls, knots, 3, layer)


#: Sweep of the ZERO layer's rotation arrow (rad) and its radius as a fraction of the mark's length.
ZERO_ARROW_SWEEP = math.radians(40.0)
ZERO_ARROW_RADIUS = 0.5


def zero_mark_geometry(mark: Any) -> tuple[list[tuple[np.ndarray, np.ndarray]], tuple[float, float, float]]:
    """The ZERO layer of ``mark`` (a :class:`camgen.kinds.base.ZeroMark`): LINEs (start, end) and
    the arrow's ARC (radius, start angle, signed sweep in rad; centre on the axis)."""
    p = np.asarray(mark.point, dtype=float)
    length = float(np.hypot(*p))
    a0 = math.atan2(p[1], p[0])
    r = ZERO_ARROW_RADIUS * length
    sweep = mark.sigma * ZERO_ARROW_SWEEP
    end_angle = a0 + sweep
    tip = r * np.array([math.cos(end_angle), math.sin(end_angle)])
    along = mark.sigma * np.array([-math.sin(end_angle), math.cos(end_angle)])  # direction of travel at the tip
    out = np.array([math.cos(end_angle), math.sin(end_angle)])
    head = 0.12 * length
    wings = [tip - head * along + 0.5 * head * out, tip - head * along - 0.5 * head * out]
    lines = [(np.zeros(2), p)] + [(w, tip) for w in wings]
    return lines, (r, a0, sweep)


def contour_to_dxf(contour: Contour, body: Any = None, pitch: Contour | None = None, options: DxfOptions = DxfOptions(),
                   zero_mark: Any = None, pockets: Sequence[Any] = ()) -> str:
    """DXF text (R2010, $INSUNITS = 4 mm) of a cam drawing.

    What is cut: ``PROFILE`` (the contour), ``BORE`` (circle, or the arc outside the keyway)
    and ``KEYWAY`` (its three sides outside the bore) from ``body`` (a
    :class:`camgen.body.BodySpec`): the bore and keyway form one closed loop.  Construction,
    each only when asked for: ``PITCH`` (``pitch``, the follower-centre path), ``CENTER``
    (``options.center_mark`` > 0) and ``ZERO`` (``zero_mark``: cam angle 0 and the direction of
    rotation, see the module notes).  Only the layers drawn are defined.  Spline segments follow
    ``options.splines`` (default: biarcs within ``options.chord_tol`` mm).

    ``pockets`` (:class:`camgen.kinds.base.Pocket`, a body with a groove or a slot): each wall is
    cut too, on its own layer (the wall's ``layer``, after KEYWAY, colours
    :data:`camgen.export.pocket.POCKET_LAYER_COLORS`), drawn as PROFILE is; the header's custom
    property ``camgen_pocket_<name>_depth_mm`` states each pocket's depth below the top face.
    """
    return _contour_to_dxf(contour, body, pitch, options, zero_mark, tuple(pockets))


def _bore_and_keyway(body: Any) -> tuple[float, np.ndarray | None]:
    """Bore radius (mm, 0: none) and the keyway's corners (4, 2) outside the bore circle
    (``None``: no keyway), in the cam frame (:meth:`camgen.body.BodySpec.keyway_outside_bore`)."""
    if body is None or body.bore_diameter <= 0:
        return 0.0, None
    r = body.bore_diameter / 2
    return r, (body.keyway_outside_bore() if body.keyway_width > 0 else None)


def drawing_bounds(contour: Contour, body: Any = None, pitch: Contour | None = None, center_mark: float = 0.0,
                   zero_mark: Any = None, walls: Sequence[Contour] = ()) -> tuple[float, float, float, float]:
    """Exact bounding box ``(xmin, ymin, xmax, ymax)``, mm, of the entities of a drawing.

    ``contour``, ``pitch`` and the pockets' ``walls`` are the contours as drawn (after any biarc
    conversion); arcs (the bore arc too) count with their end points and the axis-extreme points
    inside their sweep.
    """
    boxes = [np.array(contour.bounds).reshape(2, 2)] + [np.array(wall.bounds).reshape(2, 2) for wall in walls]
    if pitch is not None:
        boxes.append(np.array(pitch.bounds).reshape(2, 2))
    r, keyway = _bore_and_keyway(body)
    if r > 0:
        if keyway is None:
            boxes.append(np.array([[-r, -r], [r, r]]))
        else:
            boxes.append(np.array([keyway.min(axis=0), keyway.max(axis=0)]))
            gap = math.asin(body.keyway_width / 2 / r)
            arc = Arc((0.0, 0.0), r, body.keyway_angle + gap, 2.0 * math.pi - 2.0 * gap)
            pts = arc.extreme_points()
            boxes.append(np.array([pts.min(axis=0), pts.max(axis=0)]))
    if center_mark > 0:
        boxes.append(np.array([[-center_mark, -center_mark], [center_mark, center_mark]]))
    if zero_mark is not None:
        lines, (r, a0, sweep) = zero_mark_geometry(zero_mark)
        boxes.append(np.concatenate([np.stack(pair) for pair in lines]))
        pts = Arc((0.0, 0.0), r, a0, sweep).extreme_points()
        boxes.append(np.array([pts.min(axis=0), pts.max(axis=0)]))
    stack = np.concatenate(boxes)
    lo, hi = stack.min(axis=0), stack.max(axis=0)
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])


def _contour_to_dxf(contour: Contour, body: Any, pitch: Contour | None, options: DxfOptions, zero_mark: Any = None,
                    pockets: tuple[Any, ...] = ()) -> str:
    from camgen.export.pocket import POCKET_LAYER_COLORS, check_pockets

    if pockets:
        check_pockets(pockets, body.thickness if body is not None else float("inf"), (*CUT_LAYERS, *CONSTRUCTION_LAYERS))

    # the curves as drawn: biarcs, or the compact cubic form of every spline segment
    def drawn(c: Contour) -> Contour:
        return arc_contour(c, options.chord_tol) if options.splines == "biarc" else _cubic_contour(c, options.bspline_tol)

    contour = drawn(contour)
    pitch = drawn(pitch) if pitch is not None else None
    walls = [(wall.layer, drawn(wall.contour)) for pocket in pockets for wall in pocket.walls]
    msp = DxfDocument(insunits=4, measurement=1, lunits=2, luprec=6, version=options.version)  # mm, metric, decimal, 6 places
    # readers zoom to $EXTMIN/$EXTMAX: the exact bounds; the limits are the same box
    msp.set_extents(*drawing_bounds(contour, body, pitch, options.center_mark, zero_mark, [wall for _, wall in walls]))
    msp.add_custom_property("camgen_splines", options.splines)
    if options.splines == "biarc":
        msp.add_custom_property("camgen_biarc_tol_mm", repr(float(options.chord_tol)))
    else:
        msp.add_custom_property("camgen_bspline_tol_mm", repr(float(options.bspline_tol)))
    for pocket in pockets:
        msp.add_custom_property(f"camgen_pocket_{pocket.name}_depth_mm", repr(float(pocket.depth)))
    r, keyway = _bore_and_keyway(body)
    drawn_layers = {PROFILE_LAYER: True, "BORE": r > 0, "KEYWAY": keyway is not None, "PITCH": pitch is not None,
                    "CENTER": options.center_mark > 0, "ZERO": zero_mark is not None}
    wall_colors = {layer: POCKET_LAYER_COLORS[i % len(POCKET_LAYER_COLORS)] for i, (layer, _) in enumerate(walls)}
    for name, color in {**CUT_LAYERS, **wall_colors, **CONSTRUCTION_LAYERS}.items():
        if drawn_layers.get(name, True):  # every wall's layer is drawn
            msp.add_layer(name, color)
    _add_contour(msp, contour, PROFILE_LAYER)
    for layer, wall in walls:  # each wall as PROFILE is: arcs, biarcs or cubic B-splines
        _add_contour(msp, wall, layer)
    if pitch is not None:
        _add_contour(msp, pitch, "PITCH")
    if r > 0 and keyway is not None:
        # keyway: two sides from the bore circle out to the keyway bottom, and the bottom; the
        # bore arc closes the loop outside the keyway
        msp.add_lwpolyline([tuple(p) for p in keyway], False, "KEYWAY")
        gap = math.degrees(math.asin(body.keyway_width / 2 / r))
        key = math.degrees(body.keyway_angle)
        msp.add_arc((0.0, 0.0), r, key + gap, key + 360.0 - gap, "BORE")
    elif r > 0:
        msp.add_circle((0.0, 0.0), r, "BORE")
    m = options.center_mark
    if m > 0:
        msp.add_line((-m, 0.0), (m, 0.0), "CENTER")
        msp.add_line((0.0, -m), (0.0, m), "CENTER")
    if zero_mark is not None:
        lines, (r, a0, sweep) = zero_mark_geometry(zero_mark)
        for a, b in lines:
            msp.add_line(tuple(a), tuple(b), "ZERO")
        start, end = (a0, a0 + sweep) if sweep > 0 else (a0 + sweep, a0)  # DXF arcs run counter-clockwise
        msp.add_arc((0.0, 0.0), r, math.degrees(start), math.degrees(end), "ZERO")
    return msp.to_text()


def write_dxf(contour: Contour, path: str | Path, **kwargs: Any) -> Path:
    """Write :func:`contour_to_dxf` to ``path`` atomically."""
    return write_atomic(path, contour_to_dxf(contour, **kwargs))
