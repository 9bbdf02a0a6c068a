"""STEP (AP214, or AP242 on request; mm) of the cam body with exact geometry, through OpenCASCADE (OCP).

Arcs become circles built from their centre, radius and turning sense (the circle's axis +z for a
counter-clockwise arc, -z for a clockwise one) trimmed at their two end angles: never from three
points on them, which OCCT refuses as collinear within ``Precision::Confusion`` (1e-7 mm) for a
short arc on a large radius (a three-arc cam at b -> 2a: 4e-6 mm on 280 mm).  Spline
segments become clamped B-spline curves: by default the segment's compact CUBIC form
(:func:`camgen.export.dxf.compact_spline`: the fewest C2 cubic pieces within ``bspline_tol`` mm of
the contour, ends and joints kept exactly; a cubic segment itself where that has no fewer pieces,
a quintic one always refitted); with ``exact=True`` the segment's own pieces in their own degree
(cubic, or quintic: a degree-5 B-spline, knot multiplicity 3 at C2 breaks), no refit.  Either is
cut into edges of at most :data:`EDGE_SPANS` knot spans, each written exactly (the fewest knots
that hold it: :func:`camgen.export.dxf.spline_bspline`).
Consecutive edges share one vertex (the mean of the ends it joins), so the wire closes exactly;
a piece shorter than :data:`FOLD_TOL` (a three-arc cam at a + c - b -> 0 has arcs of radius
3e-14 mm) is folded into its neighbours' shared vertex.  The face (profile minus bore) is extruded to the thickness and the keyway's prism (camgen.body's
one keyway shape) is cut, then each pocket (a groove, a slot: the face between its walls, whose
edges are made as the profile's, swept from its floor to above the top face).  The header's FILE_DESCRIPTION states the tolerance.  Whatever
OCCT refuses while building the solid is a :class:`camgen.errors.GeometryError` naming the cam
(the run reports it as a failed export check), never an OCCT exception.

Why edges of a few spans: OCCT's (and so FreeCAD's) default mass properties integrate every face
with one Gauss rule of at most 61 points over the face's whole parameter range
(``BRepGProp_Gauss::Compute``, no subdivision at the knots), so a side wall over one edge of
hundreds of spans came out up to ~1e-3 relative off in volume (~1e-6 for a smooth cam); over
edges of at most 64 spans it is within ~1e-8 (``test_step.py``, ``benchmarks/bench_step.py``).

The schema (:data:`STEP_SCHEMAS`): AP214 (default, OCCT's ``AP214IS``) or AP242 (``AP242DIS``:
the same solid under the AP242 schema, ``FILE_SCHEMA(('AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF ...'))``).
:func:`cam_solid` is the solid itself (the IGES writer, :mod:`camgen.export.iges`, writes it too).

Optional: ``pip install "camgen[step]"`` (cadquery-ocp-novtk, Apache-2.0 bindings of OCCT).  The
file's time stamp is fixed so the same cam gives the same bytes.
"""
from __future__ import annotations

import io
import math
import os
import re
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from camgen.contour import Arc, Contour, Spline
from camgen.errors import ExportError, GeometryError

__all__ = ["EDGE_SPANS", "FOLD_TOL", "STEP_SCHEMAS", "cam_solid", "fold_short", "step_bytes", "step_text", "step_volume"]

#: Most knot spans of one B-spline edge (see the module notes: OCCT's volume integration).
EDGE_SPANS = 64
#: Pieces of the profile shorter than this (mm) are folded into their neighbours, and the least
#: tolerance of a vertex: OCCT's ``Precision::Confusion()``, the distance below which it takes two
#: points for one (an edge shorter than its vertices' tolerance is invalid).
FOLD_TOL = 1e-7
#: STEP schemas written: the ``step_schema`` name -> OCCT's ``write.step.schema``.
STEP_SCHEMAS = {"AP214": "AP214IS", "AP242": "AP242DIS"}


def _ocp():
    try:
        import OCP  # noqa: F401
    except ModuleNotFoundError as exc:  # pragma: no cover - depends on the install
        if (exc.name or "OCP").split(".")[0] != "OCP":
            raise ExportError(f"the OpenCASCADE bindings (OCP) are installed but did not load: {exc}") from None
        raise ExportError('STEP export needs OpenCASCADE bindings: pip install ".[step]" (cadquery-ocp-novtk)') from None
    except (ImportError, OSError) as exc:  # a library they link did not load (missing, or no memory to map it)
        raise ExportError(f"the OpenCASCADE bindings (OCP) are installed but did not load: {exc}") from None


@dataclass(frozen=True)
class _Piece:
    """One edge's curve: ``kind`` "arc" (data: centre (x, y), radius, +1 counter-clockwise or -1) or
    "bspline" (data: knots, controls (n, 2), degree), over parameters ``p1 < p2`` from ``start`` to ``end``
    ((2,), mm); ``length`` mm (a spline's: its control polygon's, an upper bound)."""

    kind: str
    data: tuple
    p1: float
    p2: float
    start: np.ndarray
    end: np.ndarray
    length: float


def _edge_parts(seg: Spline, bspline_tol: float | None, edge_spans: int | None) -> list[Spline]:
    """The compact form of ``seg`` (``bspline_tol`` None: ``seg`` itself) cut into near-equal runs
    of at most ``edge_spans`` pieces (None: one run)."""
    from camgen.export.dxf import compact_spline

    compact = seg if bspline_tol is None else compact_spline(seg, bspline_tol)
    k = compact.n_pieces
    count = 1 if edge_spans is None else -(-k // edge_spans)
    cuts = (np.arange(count + 1) * k) // count
    return [Spline(compact.breaks[lo : hi + 1], compact.coeffs[:, lo:hi]) for lo, hi in zip(cuts[:-1], cuts[1:])]


def _pieces(contour: Contour, bspline_tol: float | None, edge_spans: int | None) -> list[_Piece]:
    """The contour as the curves of its edges, in order: one per arc, one per run of spline pieces."""
    from camgen.export.dxf import spline_bspline

    pieces = []
    for seg in contour.segments:
        if isinstance(seg, Arc):
            # the circle turns the arc's way (axis +z counter-clockwise, -z clockwise), so the edge
            # runs over increasing parameters p1 < p2 = p1 + |sweep| (OCCT's circle parameter is the
            # angle from the x axis about the circle's own axis)
            sense = 1.0 if seg.sweep > 0 else -1.0
            p1 = (sense * seg.start_angle) % (2.0 * math.pi)
            ends = seg.point(np.array([0.0, 1.0]))
            pieces.append(_Piece("arc", (seg.center, seg.radius, sense), p1, p1 + abs(seg.sweep), ends[0], ends[1], seg.length))
            continue
        for part in _edge_parts(seg, bspline_tol, edge_spans):
            knots, controls = spline_bspline(part)
            reach = float(np.sum(np.hypot(*np.diff(controls, axis=0).T)))  # the control polygon: >= the curve's length
            pieces.append(_Piece("bspline", (knots, controls, part.degree), float(knots[0]), float(knots[-1]), controls[0], controls[-1], reach))
    return pieces


def _curve(piece: _Piece) -> Any:
    """The OCCT curve (Geom_Circle, or Geom_BSplineCurve of the piece's degree) of ``piece``."""
    from OCP.collections import Array1_double, Array1_gp_Pnt, Array1_int
    from OCP.Geom import Geom_BSplineCurve, Geom_Circle
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    if piece.kind == "arc":
        (cx, cy), radius, sense = piece.data
        return Geom_Circle(gp_Ax2(gp_Pnt(cx, cy, 0.0), gp_Dir(0.0, 0.0, sense), gp_Dir(1.0, 0.0, 0.0)), radius)
    knots, controls, degree = piece.data
    if knots.size != len(controls) + degree + 1:  # spline_bspline's form is of the spline's own degree
        raise GeometryError(f"B-spline edge of degree {degree} with {len(controls)} poles and {knots.size} knots")
    unique = sorted(set(knots.tolist()))
    poles = Array1_gp_Pnt(1, len(controls))
    for i, (x, y) in enumerate(controls, 1):
        poles.SetValue(i, gp_Pnt(float(x), float(y), 0.0))
    kn = Array1_double(1, len(unique))
    mu = Array1_int(1, len(unique))
    for i, k in enumerate(unique, 1):
        kn.SetValue(i, k)
        mu.SetValue(i, int((knots == k).sum()))
    return Geom_BSplineCurve(poles, kn, mu, int(degree))


def fold_short(pieces: list[_Piece], fold_tol: float = FOLD_TOL) -> tuple[list[_Piece], list[np.ndarray], list[float]]:
    """Drop the pieces shorter than ``fold_tol`` mm; the joints of the rest.

    Returns the kept pieces, the point (2,) of the vertex each kept piece starts at (the mean of
    every end met there: the previous kept piece's end, the folded pieces' ends, this piece's
    start) and each vertex' tolerance, mm: ``max(fold_tol, 2 * d)``, ``d`` the largest distance from
    the vertex to an end it joins (OCCT refuses an edge whose end is farther from its vertex than
    the vertex' tolerance).  GeometryError when every piece is shorter than ``fold_tol``.
    """
    keep = [i for i, piece in enumerate(pieces) if piece.length >= fold_tol]
    if not keep:
        total = sum(piece.length for piece in pieces)
        raise GeometryError(f"the contour is {total:.3g} mm long, below OpenCASCADE's confusion distance "
                            f"{fold_tol:g} mm: scale the cam up")
    points, tolerances = [], []
    for j, i in enumerate(keep):
        prev = keep[j - 1]
        between = range(prev + 1, i) if prev < i else [*range(prev + 1, len(pieces)), *range(i)]
        ends = np.array([pieces[prev].end] + [e for k in between for e in (pieces[k].start, pieces[k].end)] + [pieces[i].start])
        point = ends.mean(axis=0)
        points.append(point)
        tolerances.append(max(fold_tol, 2.0 * float(np.max(np.hypot(*(ends - point).T)))))
    return [pieces[i] for i in keep], points, tolerances


def _edges(contour: Contour, bspline_tol: float | None, edge_spans: int | None, fold_tol: float = FOLD_TOL) -> list[Any]:
    """The profile's edges, consecutive ones sharing one vertex (so the wire closes exactly)."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.gp import gp_Pnt
    from OCP.TopoDS import TopoDS_Vertex

    pieces, points, tolerances = fold_short(_pieces(contour, bspline_tol, edge_spans), fold_tol)
    builder = BRep_Builder()
    vertices = []
    for (x, y), tol in zip(points, tolerances):
        vertex = TopoDS_Vertex()
        builder.MakeVertex(vertex, gp_Pnt(float(x), float(y), 0.0), tol)
        vertices.append(vertex)
    edges = []
    for i, piece in enumerate(pieces):
        made = BRepBuilderAPI_MakeEdge(_curve(piece), vertices[i], vertices[(i + 1) % len(pieces)], piece.p1, piece.p2)
        if not made.IsDone():
            raise GeometryError(f"OpenCASCADE cannot make edge {i} ({piece.kind}, {piece.length:.6g} mm long) of the profile: "
                                f"{made.Error()}")
        edges.append(made.Edge())
    return edges


def _wire(contour: Contour, bspline_tol: float | None, edge_spans: int | None, what: str) -> Any:
    """The closed wire of ``contour``'s edges (z = 0)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeWire

    wire = BRepBuilderAPI_MakeWire()
    for edge in _edges(contour, bspline_tol, edge_spans):
        wire.Add(edge)
    if not wire.IsDone():
        raise GeometryError(f"the {what}'s edges do not form a wire ({wire.Error()})")
    return wire.Wire()


def _cut_pocket(solid: Any, pocket: Any, thickness: float, bspline_tol: float | None, edge_spans: int | None) -> Any:
    """``solid`` less ``pocket``: the face inside ``walls[0]`` and outside the other walls, swept
    from the pocket's floor (``thickness - depth``; below the body for a pocket through it) to
    above the top face, cut by OCCT's boolean."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    walls = [_wire(wall.contour, bspline_tol, edge_spans, f"wall {wall.layer}") for wall in pocket.walls]
    face = BRepBuilderAPI_MakeFace(walls[0])
    for inner in walls[1:]:
        face.Add(TopoDS.Wire(inner.Reversed()))
    if not face.IsDone():
        raise GeometryError(f"OpenCASCADE cannot make the face of pocket {pocket.name!r} ({face.Error()})")
    floor = thickness - pocket.depth
    start = floor if floor > 0.0 else -1.0  # a pocket through the body: start below it (no coplanar faces)
    height = thickness + max(1.0, pocket.depth) - start  # above the top face
    prism = BRepPrimAPI_MakePrism(face.Face(), gp_Vec(0, 0, height)).Shape()
    lift = gp_Trsf()
    lift.SetTranslation(gp_Vec(0, 0, start))
    cut = BRepAlgoAPI_Cut(solid, prism.Moved(TopLoc_Location(lift)))
    if not cut.IsDone():
        raise GeometryError(f"OpenCASCADE cannot cut pocket {pocket.name!r} from the body")
    return cut.Shape()


def _solid(contour: Contour, body: Any, bspline_tol: float | None, edge_spans: int | None, pockets: tuple[Any, ...] = ()) -> Any:
    """The OCCT solid: the profile face less the bore, extruded to ``body.thickness``, less the
    keyway, less each of ``pockets`` from the top face down its depth; GeometryError unless
    OCCT's checker (BRepCheck_Analyzer) finds it valid."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepBuilderAPI import (
        BRepBuilderAPI_MakeEdge,
        BRepBuilderAPI_MakeFace,
        BRepBuilderAPI_MakePolygon,
        BRepBuilderAPI_MakeWire,
    )
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pnt, gp_Vec
    from OCP.TopoDS import TopoDS

    face = BRepBuilderAPI_MakeFace(_wire(contour, bspline_tol, edge_spans, "profile"))
    if body.bore_diameter > 0:
        circle = gp_Circ(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), body.bore_diameter / 2)
        bore = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(circle).Edge()).Wire()
        face.Add(TopoDS.Wire(bore.Reversed()))
    solid = BRepPrimAPI_MakePrism(face.Face(), gp_Vec(0, 0, body.thickness)).Shape()
    if body.keyway_width > 0:  # the keyway's prism, from the one keyway shape (camgen.body)
        corners = body.keyway_corners()
        outline = BRepBuilderAPI_MakePolygon()
        for x, y in corners:
            outline.Add(gp_Pnt(float(x), float(y), -1.0))
        outline.Close()
        key_face = BRepBuilderAPI_MakeFace(outline.Wire()).Face()
        box = BRepPrimAPI_MakePrism(key_face, gp_Vec(0, 0, body.thickness + 2.0)).Shape()
        cut = BRepAlgoAPI_Cut(solid, box)
        if not cut.IsDone():
            raise GeometryError("OpenCASCADE cannot cut the keyway from the body")
        solid = cut.Shape()
    for pocket in pockets:
        solid = _cut_pocket(solid, pocket, body.thickness, bspline_tol, edge_spans)
    if not BRepCheck_Analyzer(solid).IsValid():
        raise GeometryError("OpenCASCADE finds the extruded profile invalid (BRepCheck_Analyzer)")
    return solid


def step_text(shape: Any, name: str, schema: str = "AP214") -> str:
    """The STEP text (mm) of an OCCT ``shape`` under ``schema`` (:data:`STEP_SCHEMAS`: AP214 or
    AP242), written in memory (no file outside the run's staging folder) with OCCT's transfer
    statistics kept off stdout; :class:`ExportError` naming cam ``name`` when OCCT cannot write it."""
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Controller, STEPControl_Writer

    if schema not in STEP_SCHEMAS:
        raise ExportError(f"cam '{name}': STEP schema {schema!r} is not one of {', '.join(STEP_SCHEMAS)}")
    STEPControl_Controller.Init_s()  # defines the write.step.* settings (before it, setting them does nothing)
    if not (Interface_Static.SetCVal_s("write.step.unit", "MM") and Interface_Static.SetCVal_s("write.step.schema", STEP_SCHEMAS[schema])):
        raise ExportError(f"cam '{name}': OpenCASCADE refused the STEP settings (unit MM, schema {STEP_SCHEMAS[schema]})")
    writer = STEPControl_Writer()
    stream = io.BytesIO()
    saved = os.dup(1)  # OCCT prints transfer statistics on stdout: keep the CLI quiet
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
        try:
            writer.Transfer(shape, STEPControl_AsIs)
            status = writer.WriteStream(stream)
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    if int(status) != 1 or not stream.getvalue():  # IFSelect_RetDone
        raise ExportError(f"cam '{name}': OpenCASCADE could not write the STEP file (status {status})")
    return stream.getvalue().decode("ascii", errors="replace")


def cam_solid(contour: Contour, body: Any, name: str = "cam", bspline_tol: float | None = None, *, exact: bool = False,
              edge_spans: int | None = EDGE_SPANS, pockets: Sequence[Any] = ()) -> Any:
    """The OCCT solid of the extruded cam body that :func:`step_bytes` writes (same arguments),
    valid by OCCT's checker; :class:`GeometryError` naming cam ``name`` when OCCT cannot build it."""
    from camgen.errors import ParameterError, require_positive
    from camgen.export.dxf import DEFAULT_BSPLINE_TOL

    tol = require_positive("bspline_tol", DEFAULT_BSPLINE_TOL if bspline_tol is None else bspline_tol, "mm")
    if edge_spans is not None and (isinstance(edge_spans, bool) or not isinstance(edge_spans, int) or edge_spans < 1):
        raise ParameterError("edge_spans", edge_spans, "a whole number >= 1, or None")
    _ocp()

    pockets = tuple(pockets)
    if pockets:
        from camgen.export.pocket import check_pockets

        check_pockets(pockets, body.thickness)
    try:
        return _solid(contour, body, None if exact else tol, edge_spans, pockets)
    except GeometryError as exc:
        raise GeometryError(f"cam '{name}': STEP: {exc}") from None
    except Exception as exc:  # OCCT's exceptions (Standard_Failure, StdFail_NotDone, ...) share no Python base
        if not type(exc).__module__.startswith("OCP"):
            raise
        raise GeometryError(f"cam '{name}': OpenCASCADE cannot build the STEP solid ({type(exc).__name__}: {exc}); "
                            "check the profile for arcs or splines shorter than "
                            f"{FOLD_TOL:g} mm or nearly touching itself") from None


def step_bytes(contour: Contour, body: Any, name: str = "cam", bspline_tol: float | None = None, *, exact: bool = False,
               edge_spans: int | None = EDGE_SPANS, pockets: Sequence[Any] = (), schema: str = "AP214") -> bytes:
    """STEP file content of the extruded cam body (``body``: :class:`camgen.export.solid.SolidSpec`).

    Spline segments are written within ``bspline_tol`` mm of the contour (default
    :data:`camgen.export.dxf.DEFAULT_BSPLINE_TOL`), stated in the header's FILE_DESCRIPTION, as
    edges of at most ``edge_spans`` knot spans: cubic B-splines (:func:`camgen.export.dxf.compact_spline`;
    a quintic segment is refitted).  ``exact=True`` writes every segment's own pieces in their own
    degree (no compact form: a quintic segment becomes a degree-5 B-spline) and ``edge_spans=None``
    one edge per segment: together the earlier form (benchmarks/bench_step.py compares them).

    ``pockets`` (:class:`camgen.kinds.base.Pocket`: a groove, a slot): ``contour`` is the body's
    outline and each pocket is cut from the top face down its depth, its walls written as the
    profile is.  ``schema``: AP214 (default) or AP242 (:data:`STEP_SCHEMAS`).
    """
    from camgen.errors import require_positive
    from camgen.export.dxf import DEFAULT_BSPLINE_TOL

    pockets = tuple(pockets)
    solid = cam_solid(contour, body, name, bspline_tol, exact=exact, edge_spans=edge_spans, pockets=pockets)
    tol = require_positive("bspline_tol", DEFAULT_BSPLINE_TOL if bspline_tol is None else bspline_tol, "mm")
    text = step_text(solid, name, schema)
    # the tolerance of the spline edges in the header (FILE_DESCRIPTION)
    curves = [contour] + [wall.contour for pocket in pockets for wall in pocket.walls]
    splines = any(isinstance(seg, Spline) for curve in curves for seg in curve.segments)
    what = (f"camgen cam {name}: B-spline edges within {tol!r} mm of the contour" if splines and not exact
            else f"camgen cam {name}: exact arcs, lines and B-splines")
    text = re.sub(r"FILE_DESCRIPTION\(\('[^']*'\)", f"FILE_DESCRIPTION(('{what}')", text, count=1)
    # fixed time stamp and names in the header (FILE_NAME): the same cam gives the same bytes
    text = re.sub(r"FILE_NAME\('[^']*','[^']*'", f"FILE_NAME('{name}.step','2000-01-01T00:00:00'", text, count=1)
    # the product is named after a per-process counter of OCCT's translator: name it after the cam
    text = re.sub(r"PRODUCT\('[^']*',\s*'[^']*'", f"PRODUCT('{name}','{name}'", text, count=1)
    return text.encode("ascii")


def step_volume(data: bytes) -> float:
    """Volume (mm^3) of the solid in STEP ``data``, read back by OpenCASCADE (tests, benchmarks)."""
    _ocp()
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.STEPControl import STEPControl_Reader

    reader = STEPControl_Reader()
    saved = os.dup(1)
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
        try:
            reader.ReadStream("read.step", io.BytesIO(data))
            reader.TransferRoots()
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(reader.OneShape(), props)
    return float(props.Mass())
