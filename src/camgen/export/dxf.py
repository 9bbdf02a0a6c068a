"""2-D DXF export: R2010, units mm, ARC and LINE entities every reader takes.

The file is written by camgen's own DXF writer (:mod:`camgen.export.dxfwriter`): no third-party
library is imported at run time, numbers are the exact doubles (``repr``), and the same drawing
always gives the same bytes (no time stamps or GUIDs).

Spline segments are written in one of two ways (:class:`DxfOptions` ``splines``):

* ``"biarc"`` (default): G1 chains of circular ARCs (and LINEs where the curve is straight)
  within ``biarc_tol`` mm of the exact curve (:mod:`camgen.biarc`).  OpenSCAD, laser and CAM
  programs import these; many of them ignore or reject SPLINE entities.
* ``"bspline"``: clamped cubic B-splines for CAD programs (fit-point-only or raw periodic-knot
  SPLINEs are misread by independent readers, see ``shared/research/ecosystem.md`` section 3):
  the compact form of every spline segment (:func:`compact_spline`: the fewest C2 pieces within
  ``bspline_tol`` mm of the contour, with its ends and joints kept exactly; the segment itself,
  exactly, where that has no fewer pieces), written exactly with simple interior knots.

Arc segments (three-arc cams) are exact ARCs in both modes.  Cams that know their cam angle 0
(disk cams) get a ``ZERO`` layer: a LINE from the rotation axis to the point of the profile the
follower touches at cam angle 0, and an ARC about the axis (half that radius, 40 deg) ending in
an arrow head (two LINEs) in the direction the cam turns.  The header extents ($EXTMIN,
$EXTMAX, and $LIMMIN/$LIMMAX) are the exact bounding box of everything drawn; the spline mode
and tolerance are stated in the header's custom properties (``camgen_splines`` and
``camgen_biarc_tol_mm`` or ``camgen_bspline_tol_mm``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from camgen.contour import DEFAULT_CHORD_TOL, Arc, Contour, Spline
from camgen.errors import ParameterError, require_finite, require_positive
from camgen.export.atomic import write_atomic
from camgen.export.dxfwriter import DxfDocument

PROFILE_LAYER = "PROFILE"


def spline_bezier_controls(spline: Spline) -> tuple[np.ndarray, np.ndarray]:
    """Exact clamped B-spline form of a piecewise cubic: knots (3K + 5,) and control points (3K + 1, 2).

    Each cubic piece on ``[t_i, t_i + h]`` becomes its four Bezier control points; interior
    breaks get knot multiplicity 3, the ends multiplicity 4.
    """
    a = spline.coeffs[::-1]  # ascending powers in tau: (4, K, 2)
    h = np.diff(spline.breaks)[:, None]
    # power basis in s = tau / h: p(s) = a0 + a1 h s + a2 h^2 s^2 + a3 h^3 s^3
    b0 = a[0]
    b1 = a[1] * h
    b2 = a[2] * h**2
    b3 = a[3] * h**3
    p0 = b0
    p1 = b0 + b1 / 3.0
    p2 = b0 + 2.0 * b1 / 3.0 + b2 / 3.0
    p3 = b0 + b1 + b2 + b3
    controls = np.concatenate([p0[:1], np.stack([p1, p2, p3], axis=1).reshape(-1, 2)])
    t = spline.breaks
    knots = np.concatenate([[t[0]] * 4, np.repeat(t[1:-1], 3), [t[-1]] * 4])
    return knots, controls


def spline_bspline(spline: Spline, tol: float = 1e-9) -> tuple[np.ndarray, np.ndarray]:
    """The clamped cubic B-spline of ``spline`` with the fewest knots: knot multiplicity 1 at
    C2 breaks, 2 at C1 breaks, 3 elsewhere (knots (n + 4,), control points (n, 2)).

    The control points come from interpolation at the Greville abscissae in that spline space,
    which holds the piecewise cubic exactly; the result is checked against the spline at the
    quarter points of every piece and replaced by :func:`spline_bezier_controls` if it is more
    than ``tol`` mm off.
    """
    from scipy.interpolate import make_interp_spline

    t = spline.breaks
    inner = t[1:-1]
    scale = max(1.0, float(np.max(np.abs(spline.coeffs[3]))))
    mult = np.full(inner.size, 3)
    if inner.size:
        d1l, d1r = spline.eval_piece(np.arange(inner.size), np.diff(t)[:-1], 1), spline.eval_piece(np.arange(1, inner.size + 1), np.zeros(inner.size), 1)
        d2l, d2r = spline.eval_piece(np.arange(inner.size), np.diff(t)[:-1], 2), spline.eval_piece(np.arange(1, inner.size + 1), np.zeros(inner.size), 2)
        c1 = np.max(np.abs(d1l - d1r), axis=1) <= 1e-10 * scale
        c2 = c1 & (np.max(np.abs(d2l - d2r), axis=1) <= 1e-8 * scale)
        mult = np.where(c2, 1, np.where(c1, 2, 3))
    knots = np.concatenate([[t[0]] * 4, np.repeat(inner, mult), [t[-1]] * 4])
    count = knots.size - 4
    greville = (knots[1 : count + 1] + knots[2 : count + 2] + knots[3 : count + 3]) / 3.0
    greville[0], greville[-1] = t[0], t[-1]  # (3 a) / 3 may round to just outside [a, b]: make_interp_spline refuses that
    try:
        fit = make_interp_spline(greville, spline.eval_t(greville), k=3, t=knots)
    except (ValueError, np.linalg.LinAlgError):
        return spline_bezier_controls(spline)
    probe = (t[:-1, None] + np.array([0.25, 0.5, 0.75])[None, :] * np.diff(t)[:, None]).ravel()
    if np.max(np.abs(fit(probe) - spline.eval_t(probe))) > tol:
        return spline_bezier_controls(spline)
    return knots, np.asarray(fit.c)


#: Default tolerance (mm) of the compact B-spline form of spline segments (:func:`compact_spline`)
#: in DXF (``splines = "bspline"``) and STEP files.
DEFAULT_BSPLINE_TOL = 1e-8


def _c2_breaks(spline: Spline) -> np.ndarray:
    """Which interior breaks (K - 1,) of ``spline`` are C2 (the test of :func:`spline_bspline`)."""
    t = spline.breaks
    inner = t[1:-1].size
    if not inner:
        return np.zeros(0, dtype=bool)
    scale = max(1.0, float(np.max(np.abs(spline.coeffs[3]))))
    left, right = np.arange(inner), np.arange(1, inner + 1)
    h = np.diff(t)[:-1]
    d1 = spline.eval_piece(left, h, 1) - spline.eval_piece(right, np.zeros(inner), 1)
    d2 = spline.eval_piece(left, h, 2) - spline.eval_piece(right, np.zeros(inner), 2)
    return (np.max(np.abs(d1), axis=1) <= 1e-10 * scale) & (np.max(np.abs(d2), axis=1) <= 1e-8 * scale)


def compact_spline(spline: Spline, tol: float = DEFAULT_BSPLINE_TOL) -> Spline:
    """``spline`` with as few cubic pieces as ``tol`` (mm) allows: C2 inside, same ends.

    Every run of pieces between breaks where ``spline`` is not C2 is refitted by a clamped C2
    cubic spline that keeps the run's end points, first and second derivatives exactly (so the
    joints keep their continuity: G2 stays G2) and lies within ``tol`` mm of the run at the
    probe points of every new piece (least squares with knots placed by the error,
    :func:`camgen.splinefit.fit_clamped`); a run keeps its own pieces where the refit would not
    have fewer.  The parameter range is unchanged (the parameter along the new pieces is not
    the old one: compare curves by distance, not at equal parameters).
    """
    from camgen.errors import GeometryError
    from camgen.splinefit import fit_clamped

    tol = require_positive("bspline_tol", tol, "mm")
    c2 = _c2_breaks(spline)
    cuts = np.concatenate([[0], np.flatnonzero(~c2) + 1, [spline.n_pieces]])
    breaks: list[np.ndarray] = []
    coeffs: list[np.ndarray] = []
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        run = Spline(spline.breaks[lo : hi + 1], spline.coeffs[:, lo:hi])
        a, b = float(run.breaks[0]), float(run.breaks[-1])
        ends = [run.eval_piece(np.array([i]), np.array([tau]), order)[0]
                for i, tau in ((0, 0.0), (run.n_pieces - 1, float(np.diff(run.breaks)[-1]))) for order in (0, 1, 2)]
        fit = None
        if run.n_pieces > 3:
            try:
                fit = fit_clamped(run.eval_t, a, b, tol, tuple(ends), initial_pieces=max(3, run.n_pieces // 8),
                                  max_pieces=run.n_pieces - 1, what="compact B-spline")
            except GeometryError:
                fit = None  # no fewer pieces within tol: keep the run as it is
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
        ``biarc_tol`` mm (every DXF reader takes them); ``"bspline"``: clamped cubic B-spline
        SPLINEs within ``bspline_tol`` mm (for CAD programs).
    biarc_tol : float
        Largest distance between a spline segment and its biarcs, mm (the pipeline passes the
        scene's ``chord_tol_mm``).
    bspline_tol : float
        Largest distance between a spline segment and its written B-spline (``"bspline"``), mm.
    center_mark : float
        Half-length of the centre cross on the rotation axis, mm (0: no centre mark).
    """

    splines: str = "biarc"
    biarc_tol: float = DEFAULT_CHORD_TOL
    center_mark: float = 5.0
    bspline_tol: float = DEFAULT_BSPLINE_TOL

    def __post_init__(self) -> None:
        if self.splines not in SPLINE_MODES:
            raise ParameterError("dxf_splines", self.splines, f"one of {', '.join(SPLINE_MODES)}")
        require_positive("biarc_tol", self.biarc_tol)
        require_positive("bspline_tol", self.bspline_tol)
        if require_finite("center_mark", self.center_mark) < 0:
            raise ParameterError("center_mark", self.center_mark, "center_mark >= 0 mm")


def _is_line(seg: Spline) -> bool:
    return seg.n_pieces == 1 and not np.any(seg.coeffs[:2])


def _arc_spline(contour: Contour, tol: float) -> Contour:
    """``contour`` with every curved spline segment replaced by biarcs within ``tol`` mm (arcs
    and straight pieces kept as they are)."""
    from camgen.biarc import spline_to_biarcs

    if all(isinstance(seg, Arc) or _is_line(seg) for seg in contour.segments):
        return contour
    segments: list[Arc | Spline] = []
    for seg in contour.segments:
        segments.extend([seg] if isinstance(seg, Arc) or _is_line(seg) else spline_to_biarcs(seg, tol))
    return Contour(segments, closure_tol=1e-6)


def _add_contour(msp: DxfDocument, contour: Contour, layer: str, bspline_tol: float = DEFAULT_BSPLINE_TOL) -> None:
    for seg in contour.segments:
        if isinstance(seg, Arc):
            start = math.degrees(seg.start_angle)
            end = math.degrees(seg.start_angle + seg.sweep)
            if seg.sweep < 0:  # DXF arcs always run counter-clockwise from start to end
                start, end = end, start
            msp.add_arc(seg.center, seg.radius, start, end, layer)
        elif _is_line(seg):
            msp.add_line(tuple(seg.start_point), tuple(seg.end_point), layer)
        else:
            knots, controls = spline_bspline(compact_spline(seg, bspline_tol))
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
                   zero_mark: Any = None) -> str:
    """DXF text (R2010, $INSUNITS = 4 mm) of a cam drawing.

    Layers: ``PROFILE`` (the contour), ``BORE`` (circle, or the arc outside the keyway) and
    ``KEYWAY`` (its three sides outside the bore) from ``body`` (a
    :class:`camgen.export.solid.SolidSpec`), ``PITCH`` (the follower-centre path, when given),
    ``CENTER`` (a centre mark on the rotation axis) and ``ZERO`` (cam angle 0 and the direction
    of rotation, when ``zero_mark`` is given: see the module notes).  Spline segments follow
    ``options.splines`` (default: biarcs within ``options.biarc_tol`` mm).
    """
    return _contour_to_dxf(contour, body, pitch, options, zero_mark)


def _bore_and_keyway(body: Any) -> tuple[float, np.ndarray | None]:
    """Bore radius (mm, 0: none) and the keyway's corners (4, 2) outside the bore circle
    (``None``: no keyway), in the cam frame (:meth:`camgen.body.BodySpec.keyway_outside_bore`)."""
    if body is None or body.bore_diameter <= 0:
        return 0.0, None
    r = body.bore_diameter / 2
    return r, (body.keyway_outside_bore() if body.keyway_width > 0 else None)


def drawing_bounds(contour: Contour, body: Any = None, pitch: Contour | None = None, center_mark: float = 0.0,
                   zero_mark: Any = None) -> tuple[float, float, float, float]:
    """Exact bounding box ``(xmin, ymin, xmax, ymax)``, mm, of the entities of a drawing.

    ``contour`` and ``pitch`` are the contours as drawn (after any biarc conversion); arcs
    (the bore arc too) count with their end points and the axis-extreme points inside their sweep.
    """
    boxes = [np.array(contour.bounds).reshape(2, 2)]
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


def _contour_to_dxf(contour: Contour, body: Any, pitch: Contour | None, options: DxfOptions, zero_mark: Any = None) -> str:
    if options.splines == "biarc":
        contour = _arc_spline(contour, options.biarc_tol)
        pitch = _arc_spline(pitch, options.biarc_tol) if pitch is not None else None
    msp = DxfDocument(insunits=4, measurement=1, lunits=2, luprec=6)  # mm, metric, decimal, 6 places
    # readers zoom to $EXTMIN/$EXTMAX: the exact bounds; the limits are the same box
    msp.set_extents(*drawing_bounds(contour, body, pitch, options.center_mark, zero_mark))
    msp.add_custom_property("camgen_splines", options.splines)
    if options.splines == "biarc":
        msp.add_custom_property("camgen_biarc_tol_mm", repr(float(options.biarc_tol)))
    else:
        msp.add_custom_property("camgen_bspline_tol_mm", repr(float(options.bspline_tol)))
    for name, color in ((PROFILE_LAYER, 7), ("BORE", 2), ("KEYWAY", 3), ("PITCH", 4), ("CENTER", 1)):
        msp.add_layer(name, color)
    if zero_mark is not None:
        msp.add_layer("ZERO", 6)
    _add_contour(msp, contour, PROFILE_LAYER, options.bspline_tol)
    if pitch is not None:
        _add_contour(msp, pitch, "PITCH", options.bspline_tol)
    r, keyway = _bore_and_keyway(body)
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
