"""STEP (AP214, mm) of the cam body with exact geometry, through OpenCASCADE (OCP).

Arcs become circles (``GC_MakeArcOfCircle`` through start, middle and end points).  Spline
segments become clamped cubic B-spline curves: the segment in its compact form
(:func:`camgen.export.dxf.compact_spline`: the fewest C2 pieces within ``bspline_tol`` mm of the
contour, ends and joints kept exactly; the segment itself where that has no fewer pieces), cut
into edges of at most :data:`EDGE_SPANS` knot spans, each written exactly (simple knots inside).
The face (profile minus bore) is extruded to the thickness and the keyway's prism (camgen.body's
one keyway shape) is cut.  The header's FILE_DESCRIPTION states the tolerance.

Why edges of a few spans: OCCT's (and so FreeCAD's) default mass properties integrate every face
with one Gauss rule of at most 61 points over the face's whole parameter range
(``BRepGProp_Gauss::Compute``, no subdivision at the knots), so a side wall over one edge of
hundreds of spans came out up to ~1e-3 relative off in volume (~1e-6 for a smooth cam); over
edges of at most 64 spans it is within ~1e-8 (``test_step.py``, ``benchmarks/bench_step.py``).

Optional: ``pip install "camgen[step]"`` (cadquery-ocp-novtk, Apache-2.0 bindings of OCCT).  The
file's time stamp is fixed so the same cam gives the same bytes.
"""
from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from camgen.contour import Arc, Contour, Spline
from camgen.errors import ExportError

#: Most knot spans of one B-spline edge (see the module notes: OCCT's volume integration).
EDGE_SPANS = 64


def _ocp():
    try:
        import OCP  # noqa: F401
    except ImportError:  # pragma: no cover - depends on the install
        raise ExportError('STEP export needs OpenCASCADE bindings: pip install ".[step]" (cadquery-ocp-novtk)') from None


def _edge_parts(seg: Spline, bspline_tol: float | None, edge_spans: int | None) -> list[Spline]:
    """The compact form of ``seg`` (``bspline_tol`` None: ``seg`` itself) cut into near-equal runs
    of at most ``edge_spans`` pieces (None: one run)."""
    from camgen.export.dxf import compact_spline

    compact = seg if bspline_tol is None else compact_spline(seg, bspline_tol)
    k = compact.n_pieces
    count = 1 if edge_spans is None else -(-k // edge_spans)
    cuts = (np.arange(count + 1) * k) // count
    return [Spline(compact.breaks[lo : hi + 1], compact.coeffs[:, lo:hi]) for lo, hi in zip(cuts[:-1], cuts[1:])]


def _edges(contour: Contour, bspline_tol: float | None, edge_spans: int | None) -> list[Any]:
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.collections import Array1_double, Array1_gp_Pnt, Array1_int
    from OCP.GC import GC_MakeArcOfCircle
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt

    from camgen.export.dxf import spline_bspline

    edges = []
    for seg in contour.segments:
        if isinstance(seg, Arc):
            a, m, b = (seg.point([u])[0] for u in (0.0, 0.5, 1.0))
            curve = GC_MakeArcOfCircle(gp_Pnt(a[0], a[1], 0.0), gp_Pnt(m[0], m[1], 0.0), gp_Pnt(b[0], b[1], 0.0)).Value()
            edges.append(BRepBuilderAPI_MakeEdge(curve).Edge())
            continue
        for part in _edge_parts(seg, bspline_tol, edge_spans):
            knots, controls = spline_bspline(part)
            unique = sorted(set(knots.tolist()))
            poles = Array1_gp_Pnt(1, len(controls))
            for i, (x, y) in enumerate(controls, 1):
                poles.SetValue(i, gp_Pnt(float(x), float(y), 0.0))
            kn = Array1_double(1, len(unique))
            mu = Array1_int(1, len(unique))
            for i, k in enumerate(unique, 1):
                kn.SetValue(i, k)
                mu.SetValue(i, int((knots == k).sum()))
            edges.append(BRepBuilderAPI_MakeEdge(Geom_BSplineCurve(poles, kn, mu, 3)).Edge())
    return edges


def step_bytes(contour: Contour, body: Any, name: str = "cam", bspline_tol: float | None = None, *, exact: bool = False,
               edge_spans: int | None = EDGE_SPANS) -> bytes:
    """STEP file content of the extruded cam body (``body``: :class:`camgen.export.solid.SolidSpec`).

    Spline segments are written within ``bspline_tol`` mm of the contour (default
    :data:`camgen.export.dxf.DEFAULT_BSPLINE_TOL`), stated in the header's FILE_DESCRIPTION, as
    edges of at most ``edge_spans`` knot spans.  ``exact=True`` writes every segment's own
    pieces (no compact form) and ``edge_spans=None`` one edge per segment: together the earlier
    form (benchmarks/bench_step.py compares them).
    """
    from camgen.errors import ParameterError, require_positive
    from camgen.export.dxf import DEFAULT_BSPLINE_TOL

    tol = require_positive("bspline_tol", DEFAULT_BSPLINE_TOL if bspline_tol is None else bspline_tol, "mm")
    if edge_spans is not None and (isinstance(edge_spans, bool) or not isinstance(edge_spans, int) or edge_spans < 1):
        raise ParameterError("edge_spans", edge_spans, "a whole number >= 1, or None")
    _ocp()
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepBuilderAPI import (
        BRepBuilderAPI_MakeEdge,
        BRepBuilderAPI_MakeFace,
        BRepBuilderAPI_MakePolygon,
        BRepBuilderAPI_MakeWire,
    )
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Ax2, gp_Circ, gp_Dir, gp_Pnt, gp_Vec
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    from OCP.TopoDS import TopoDS

    wire = BRepBuilderAPI_MakeWire()
    for edge in _edges(contour, None if exact else tol, edge_spans):
        wire.Add(edge)
    if not wire.IsDone():
        raise ExportError(f"cam '{name}': the profile edges do not form a closed wire for STEP")
    face = BRepBuilderAPI_MakeFace(wire.Wire())
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
        solid = BRepAlgoAPI_Cut(solid, box).Shape()
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    writer = STEPControl_Writer()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{name}.step"
        saved = os.dup(1)  # OCCT prints transfer statistics on stdout: keep the CLI quiet
        with open(os.devnull, "w") as devnull:
            os.dup2(devnull.fileno(), 1)
            try:
                writer.Transfer(solid, STEPControl_AsIs)
                status = writer.Write(str(path))
            finally:
                os.dup2(saved, 1)
                os.close(saved)
        if not path.exists() or int(status) != 1:  # IFSelect_RetDone
            raise ExportError(f"cam '{name}': OpenCASCADE could not write the STEP file (status {status})")
        text = path.read_text(encoding="ascii", errors="replace")
    # the tolerance of the spline edges in the header (FILE_DESCRIPTION)
    splines = any(isinstance(seg, Spline) for seg in contour.segments)
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

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "read.step"
        path.write_bytes(data)
        reader = STEPControl_Reader()
        saved = os.dup(1)
        with open(os.devnull, "w") as devnull:
            os.dup2(devnull.fileno(), 1)
            try:
                reader.ReadFile(str(path))
                reader.TransferRoots()
            finally:
                os.dup2(saved, 1)
                os.close(saved)
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(reader.OneShape(), props)
        return float(props.Mass())

