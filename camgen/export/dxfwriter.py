"""A small, exact, deterministic DXF R2010 (AC1024) or R12 (AC1009) ASCII writer for 2-D drawings.

It writes the structure an R2000-and-later file needs (Autodesk, *AutoCAD 2012 DXF Reference*:
chapter 2 HEADER, 3 CLASSES, 4 TABLES, 5 BLOCKS, 6 ENTITIES, 7 OBJECTS; chapter 10 for handles
and ownership):

* HEADER: ``$ACADVER`` AC1024, ``$DWGCODEPAGE``, the custom properties
  (``$CUSTOMPROPERTYTAG`` / ``$CUSTOMPROPERTY`` pairs), ``$INSBASE``, ``$EXTMIN``/``$EXTMAX``,
  ``$LIMMIN``/``$LIMMAX``, ``$LUNITS``, ``$LUPREC``, ``$HANDSEED`` (the next free handle, above
  every handle in the file), ``$MEASUREMENT`` and ``$INSUNITS``;
* CLASSES: LAYOUT (its objects are instances of a registered class, not built-in types);
* TABLES, LTYPE before LAYER as the reference requires: VPORT ``*Active`` (zoomed to the
  extents), LTYPE ByBlock/ByLayer/Continuous, LAYER ``0`` and the drawing's layers, STYLE
  Standard, VIEW and UCS (empty), APPID ACAD, DIMSTYLE Standard (handle in group 105),
  BLOCK_RECORD ``*Model_Space`` and ``*Paper_Space`` (each pointing at its LAYOUT, group 340);
* BLOCKS: the two empty layout blocks; ENTITIES: LINE, ARC, CIRCLE, LWPOLYLINE, SPLINE, TEXT, all in
  model space;
* OBJECTS: the root dictionary (owner 0) with ``ACAD_GROUP`` (empty) and ``ACAD_LAYOUT``, which
  holds the ``Model`` and ``Layout1`` LAYOUT objects (each pointing back at its block record).

Every object has a unique hexadecimal handle (group 5; 105 for DIMSTYLE), its owner (330) and
its subclass markers (100).  Numbers are written with ``repr(float)``, the shortest text that
reads back as the same double, so a reader gets the exact coordinates; NaN and infinities raise
:class:`camgen.errors.ExportError` before anything is returned.  There are no time stamps or
GUIDs: the same drawing always gives the same text.

**R12** (``DxfDocument(version="R12")``, for legacy CAM programs; Autodesk, *AutoCAD Release 12
DXF Reference*, chapter 11): HEADER (``$ACADVER`` AC1009, ``$DWGCODEPAGE``, ``$INSBASE``,
``$EXTMIN``/``$EXTMAX``, ``$LIMMIN``/``$LIMMAX``, ``$LUNITS``, ``$LUPREC``, ``$HANDLING`` 0: no
handles), TABLES (LTYPE CONTINUOUS, LAYER), an empty BLOCKS section and ENTITIES of the R12
kinds only: LINE, ARC, CIRCLE, TEXT, and POLYLINE (with its VERTEX and SEQEND) for what R2010
writes as an LWPOLYLINE; no subclass markers (group 100), no OBJECTS.  R12 has no SPLINE (adding
one raises :class:`camgen.errors.ExportError`), no ``$INSUNITS`` and no custom properties: the
units (mm) and the custom properties are stated in comments (group 999) before the HEADER.
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from camgen.errors import ExportError

__all__ = ["ACADVER", "ACADVER_R12", "DXF_VERSIONS", "DxfDocument", "INSUNITS_MM", "PAPER_MM", "R12_ENTITIES", "ZOOM_MARGIN"]

#: DXF version written by default: R2010.
ACADVER = "AC1024"
#: ``$ACADVER`` of an R12 file.
ACADVER_R12 = "AC1009"
#: The versions :class:`DxfDocument` writes: name -> ``$ACADVER``.
DXF_VERSIONS = {"R2010": ACADVER, "R12": ACADVER_R12}
#: The entities an R12 file holds (the R12 reference's ENTITIES section; camgen writes these).
R12_ENTITIES = ("LINE", "ARC", "CIRCLE", "TEXT", "POLYLINE", "VERTEX", "SEQEND")
#: Characters a DXF symbol-table name may not contain (AutoCAD's naming rules).
_FORBIDDEN_NAME = set('<>/\\":;?*|=`')
#: $INSUNITS of millimetres (DXF Reference, HEADER: 4 = Millimeters).
INSUNITS_MM = 4
#: Paper of the paper-space layout, mm (ISO A4 landscape).
PAPER_MM = (297.0, 210.0)
#: Margin around the extents when the active viewport is zoomed to them (fraction of their size).
ZOOM_MARGIN = 0.05


def _num(value: float, what: str) -> str:
    """``repr`` of ``value`` as a float (exact round trip); ExportError if it is not finite."""
    x = float(value)
    if not math.isfinite(x):
        raise ExportError(f"cannot write DXF: {what} is {x!r} (not a finite number)")
    return repr(x)


def _points(points: object, what: str, width: int = 2) -> np.ndarray:
    """``points`` as a finite float array (n, width)."""
    try:
        arr = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise ExportError(f"cannot write DXF: {what} is not an array of numbers") from None
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != width:
        raise ExportError(f"cannot write DXF: {what} must have shape (n, {width}), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ExportError(f"cannot write DXF: {what} holds NaN or infinite values")
    return arr


def _text(value: str, what: str) -> str:
    """A string value: one line, no control characters (a line break would end the group)."""
    if not isinstance(value, str) or any(ord(c) < 32 or ord(c) == 127 for c in value):
        raise ExportError(f"cannot write DXF: {what} {value!r} must be a one-line string without control characters")
    return value


def _name(value: str, what: str) -> str:
    _text(value, what)
    if not value or value != value.strip() or _FORBIDDEN_NAME & set(value):
        raise ExportError(f"cannot write DXF: {what} {value!r} must be non-empty, without surrounding spaces and "
                          f"without any of {''.join(sorted(_FORBIDDEN_NAME))}")
    return value


@dataclass(frozen=True)
class _Entity:
    kind: str
    layer: str
    groups: tuple[tuple[int, str], ...]  # the entity's own subclass groups, values already formatted


class DxfDocument:
    """A 2-D drawing in model space, written as DXF R2010 text by :meth:`to_text`.

    Coordinates are in drawing units (``insunits``, default 4 = mm); angles of arcs in degrees,
    counter-clockwise from start to end as DXF defines them.  Every value is checked when it is
    added: a NaN or infinite coordinate raises :class:`camgen.errors.ExportError`.

    Parameters
    ----------
    insunits : int
        ``$INSUNITS`` (4: millimetres).
    measurement : int
        ``$MEASUREMENT`` (0: imperial, 1: metric).
    lunits, luprec : int
        ``$LUNITS`` (2: decimal) and ``$LUPREC`` (decimal places shown by CAD programs).
    version : {"R2010", "R12"}
        The file's DXF version (:data:`DXF_VERSIONS`; R12: see the module notes).
    """

    def __init__(self, insunits: int = INSUNITS_MM, measurement: int = 1, lunits: int = 2, luprec: int = 6,
                 version: str = "R2010") -> None:
        if version not in DXF_VERSIONS:
            raise ExportError(f"cannot write DXF: version {version!r} is not one of {', '.join(DXF_VERSIONS)}")
        self.version = version
        self._header_ints = {"$LUNITS": int(lunits), "$LUPREC": int(luprec), "$MEASUREMENT": int(measurement),
                             "$INSUNITS": int(insunits)}
        self._layers: dict[str, int] = {"0": 7}
        self._entities: list[_Entity] = []
        self._custom: list[tuple[str, str]] = []
        self._extents: tuple[float, float, float, float] | None = None
        self._limits: tuple[float, float, float, float] | None = None

    # ------------------------------------------------------------------ content
    def add_layer(self, name: str, color: int = 7) -> None:
        """A layer ``name`` drawn in ACI colour ``color`` (1 red, 2 yellow, 3 green, 4 cyan,
        5 blue, 6 magenta, 7 white/black ... 255), linetype Continuous."""
        _name(name, "layer name")
        if name.upper() in (n.upper() for n in self._layers):
            raise ExportError(f"cannot write DXF: layer {name!r} is defined twice (DXF names ignore case)")
        if isinstance(color, bool) or not isinstance(color, (int, np.integer)) or not 1 <= int(color) <= 255:
            raise ExportError(f"cannot write DXF: colour {color!r} of layer {name!r} must be an ACI number 1 ... 255")
        self._layers[name] = int(color)

    def _layer(self, layer: str) -> str:
        if layer not in self._layers:
            raise ExportError(f"cannot write DXF: layer {layer!r} is not defined (add_layer first)")
        return layer

    def add_line(self, start: Sequence[float], end: Sequence[float], layer: str = "0") -> None:
        """A LINE from ``start`` to ``end`` (x, y)."""
        p = _points([start, end], "LINE end points")
        self._add("LINE", layer, (100, "AcDbLine"), *_xyz(10, p[0]), *_xyz(11, p[1]))

    def add_arc(self, center: Sequence[float], radius: float, start_deg: float, end_deg: float, layer: str = "0") -> None:
        """An ARC about ``center`` (x, y) of ``radius`` > 0, counter-clockwise from ``start_deg``
        to ``end_deg`` (degrees)."""
        c = _points(center, "ARC centre")[0]
        r = self._radius(radius, "ARC")
        self._add("ARC", layer, (100, "AcDbCircle"), *_xyz(10, c), (40, r), (100, "AcDbArc"),
                  (50, _num(start_deg, "ARC start angle")), (51, _num(end_deg, "ARC end angle")))

    def add_circle(self, center: Sequence[float], radius: float, layer: str = "0") -> None:
        """A CIRCLE about ``center`` (x, y) of ``radius`` > 0."""
        c = _points(center, "CIRCLE centre")[0]
        self._add("CIRCLE", layer, (100, "AcDbCircle"), *_xyz(10, c), (40, self._radius(radius, "CIRCLE")))

    def add_lwpolyline(self, points: npt.ArrayLike, closed: bool = False, layer: str = "0") -> None:
        """An LWPOLYLINE through ``points`` (n >= 2, 2) with straight segments; ``closed`` joins
        the last point to the first."""
        p = _points(points, "LWPOLYLINE vertices")
        if len(p) < 2:
            raise ExportError(f"cannot write DXF: an LWPOLYLINE needs at least 2 vertices, got {len(p)}")
        flat = p.tolist()
        vertices = [g for x, y in flat for g in ((10, repr(x)), (20, repr(y)))]
        self._add("LWPOLYLINE", layer, (100, "AcDbPolyline"), (90, str(len(p))), (70, "1" if closed else "0"),
                  (43, "0.0"), *vertices)

    def add_spline(self, control_points: npt.ArrayLike, knots: npt.ArrayLike, degree: int = 3,
                   layer: str = "0") -> None:
        """A non-rational B-spline SPLINE in the x-y plane: control points (n, 2), knots
        (n + degree + 1,), non-decreasing (clamped: the first and last ``degree + 1`` equal)."""
        if self.version == "R12":
            raise ExportError("cannot write DXF: R12 has no SPLINE entity (write the curve as ARCs and LINEs)")
        p = _points(control_points, "SPLINE control points")
        k = _points(np.asarray(knots, dtype=float).reshape(-1, 1), "SPLINE knots", width=1)[:, 0]
        if isinstance(degree, bool) or not isinstance(degree, (int, np.integer)) or degree < 1:
            raise ExportError(f"cannot write DXF: SPLINE degree {degree!r} must be an integer >= 1")
        degree = int(degree)
        if len(p) < degree + 1 or len(k) != len(p) + degree + 1:
            raise ExportError(f"cannot write DXF: a degree-{degree} SPLINE with {len(p)} control points needs "
                              f"{len(p) + degree + 1} knots and at least {degree + 1} points, got {len(k)} knots")
        if np.any(np.diff(k) < 0) or not k[-1] > k[0]:
            raise ExportError("cannot write DXF: SPLINE knots must be non-decreasing and span a non-empty interval")
        groups = [(100, "AcDbSpline"), (210, "0.0"), (220, "0.0"), (230, "1.0"),
                  (70, "8"),  # planar (the normal above), not closed, not periodic, not rational
                  (71, str(degree)), (72, str(len(k))), (73, str(len(p))), (74, "0"),
                  (42, "1e-10"), (43, "1e-10")]
        groups += [(40, repr(t)) for t in k.tolist()]
        groups += [g for x, y in p.tolist() for g in ((10, repr(x)), (20, repr(y)), (30, "0.0"))]
        self._add("SPLINE", layer, *groups)

    def add_text(self, insert: Sequence[float], height: float, text: str, layer: str = "0") -> None:
        """A one-line TEXT (style Standard) whose baseline starts at ``insert`` (x, y), its
        characters ``height`` > 0 high (DXF Reference, ENTITIES: TEXT, groups 10, 40, 1)."""
        p = _points(insert, "TEXT insertion point")[0]
        h = _num(height, "TEXT height")
        if not float(h) > 0:
            raise ExportError(f"cannot write DXF: TEXT height {height!r} must be > 0")
        self._add("TEXT", layer, (100, "AcDbText"), *_xyz(10, p), (40, h),
                  (1, _text(text, "TEXT string")), (100, "AcDbText"))

    def set_extents(self, xmin: float, ymin: float, xmax: float, ymax: float) -> None:
        """The drawing's bounding box: ``$EXTMIN``/``$EXTMAX`` (z = 0), the limits
        ``$LIMMIN``/``$LIMMAX`` (unless :meth:`set_limits` gives others), the model layout's
        extents and the zoom of the active viewport."""
        x0, y0, x1, y1 = (float(_num(v, f"extent {n}")) for v, n in zip((xmin, ymin, xmax, ymax), ("xmin", "ymin", "xmax", "ymax")))
        box = (x0, y0, x1, y1)
        if box[2] < box[0] or box[3] < box[1]:
            raise ExportError(f"cannot write DXF: extents {box} have max < min")
        self._extents = box

    def set_limits(self, xmin: float, ymin: float, xmax: float, ymax: float) -> None:
        """``$LIMMIN``/``$LIMMAX`` (the drawing limits), when they differ from the extents."""
        x0, y0, x1, y1 = (float(_num(v, "limit")) for v in (xmin, ymin, xmax, ymax))
        self._limits = (x0, y0, x1, y1)

    def add_custom_property(self, tag: str, value: str) -> None:
        """A custom drawing property (``$CUSTOMPROPERTYTAG`` / ``$CUSTOMPROPERTY``)."""
        _text(tag, "custom property tag")
        if not tag:
            raise ExportError("cannot write DXF: a custom property tag must not be empty")
        self._custom.append((tag, _text(value, f"custom property {tag!r} value")))

    @property
    def entity_count(self) -> int:
        return len(self._entities)

    # ------------------------------------------------------------------ helpers
    @staticmethod
    def _radius(radius: float, kind: str) -> str:
        text = _num(radius, f"{kind} radius")
        if not float(text) > 0:
            raise ExportError(f"cannot write DXF: {kind} radius {radius!r} must be > 0")
        return text

    def _add(self, kind: str, layer: str, *groups: tuple[int, str]) -> None:
        self._entities.append(_Entity(kind, self._layer(layer), tuple(groups)))

    # ------------------------------------------------------------------ output
    def to_text(self) -> str:
        """The whole file as text ('\\n' line ends; write it UTF-8 encoded, as R2007+ files are)."""
        return _R12Writer(self).text() if self.version == "R12" else _Writer(self).text()


def _xyz(code: int, p: np.ndarray) -> tuple[tuple[int, str], ...]:
    return (code, repr(float(p[0]))), (code + 10, repr(float(p[1]))), (code + 20, "0.0")


def _extents_and_limits(doc: DxfDocument) -> tuple[tuple[float, float, float, float], tuple[float, float, float, float]]:
    """The header's extents and limits of ``doc`` (AutoCAD's "empty drawing" values without extents)."""
    ext = doc._extents
    extents = ext if ext is not None else (1e20, 1e20, -1e20, -1e20)
    limits = doc._limits or (ext if ext is not None else (0.0, 0.0, 420.0, 297.0))
    return extents, limits


class _Handles:
    """Consecutive handles from 1, as upper-case hexadecimal strings."""

    def __init__(self) -> None:
        self.next = 1

    def __call__(self) -> str:
        value = self.next
        self.next += 1
        return f"{value:X}"


class _Writer:
    """Allocates every handle first (owners and pointers must be known before they are written),
    then writes the sections in order."""

    TABLES = ("VPORT", "LTYPE", "LAYER", "STYLE", "VIEW", "UCS", "APPID", "DIMSTYLE", "BLOCK_RECORD")

    def __init__(self, doc: DxfDocument) -> None:
        self.doc = doc
        h = _Handles()
        self.table = {name: h() for name in self.TABLES}
        self.vport = h()
        self.ltypes = {name: h() for name in ("ByBlock", "ByLayer", "Continuous")}
        self.layers = {name: h() for name in doc._layers}
        self.style = h()
        self.appid = h()
        self.dimstyle = h()
        self.record = {"*Model_Space": h(), "*Paper_Space": h()}
        self.block = {name: (h(), h()) for name in self.record}  # BLOCK, ENDBLK
        self.root, self.groups, self.layout_dict = h(), h(), h()
        self.layout = {"*Model_Space": h(), "*Paper_Space": h()}
        self.entities = [h() for _ in doc._entities]
        self.handseed = f"{h.next:X}"
        self.out: list[str] = []

    def g(self, *pairs: tuple[int, str]) -> None:
        out = self.out
        for code, value in pairs:
            out.append(f"{code:>3}")
            out.append(value)

    def text(self) -> str:
        self.header()
        self.classes()
        self.tables()
        self.blocks()
        self.entities_section()
        self.objects()
        self.g((0, "EOF"))
        return "\n".join(self.out) + "\n"

    # ------------------------------------------------------------------ HEADER
    def _box(self) -> tuple[tuple[float, float, float, float], tuple[float, float, float, float]]:
        return _extents_and_limits(self.doc)

    def header(self) -> None:
        (ex0, ey0, ex1, ey1), (lx0, ly0, lx1, ly1) = self._box()
        self.g((0, "SECTION"), (2, "HEADER"), (9, "$ACADVER"), (1, ACADVER), (9, "$DWGCODEPAGE"), (3, "ANSI_1252"))
        for tag, value in self.doc._custom:
            self.g((9, "$CUSTOMPROPERTYTAG"), (1, tag), (9, "$CUSTOMPROPERTY"), (1, value))
        self.g((9, "$INSBASE"), (10, "0.0"), (20, "0.0"), (30, "0.0"),
               (9, "$EXTMIN"), (10, repr(ex0)), (20, repr(ey0)), (30, "0.0"),
               (9, "$EXTMAX"), (10, repr(ex1)), (20, repr(ey1)), (30, "0.0"),
               (9, "$LIMMIN"), (10, repr(lx0)), (20, repr(ly0)),
               (9, "$LIMMAX"), (10, repr(lx1)), (20, repr(ly1)))
        ints = self.doc._header_ints
        self.g((9, "$LUNITS"), (70, str(ints["$LUNITS"])), (9, "$LUPREC"), (70, str(ints["$LUPREC"])),
               (9, "$HANDSEED"), (5, self.handseed),
               (9, "$MEASUREMENT"), (70, str(ints["$MEASUREMENT"])), (9, "$INSUNITS"), (70, str(ints["$INSUNITS"])),
               (0, "ENDSEC"))

    def classes(self) -> None:
        # LAYOUT: C++ class AcDbLayout, application "ObjectDBX Classes", proxy flags 0, 2 instances,
        # was-a-proxy 0, is-an-entity 0 (DXF Reference, "Default Class Values")
        self.g((0, "SECTION"), (2, "CLASSES"),
               (0, "CLASS"), (1, "LAYOUT"), (2, "AcDbLayout"), (3, "ObjectDBX Classes"), (90, "0"), (91, "2"),
               (280, "0"), (281, "0"),
               (0, "ENDSEC"))

    # ------------------------------------------------------------------ TABLES
    def _table(self, name: str, count: int) -> None:
        self.g((0, "TABLE"), (2, name), (5, self.table[name]), (330, "0"), (100, "AcDbSymbolTable"), (70, str(count)))

    def _record(self, kind: str, handle: str, subclass: str, name: str, flags: bool = True) -> None:
        code = 105 if kind == "DIMSTYLE" else 5
        self.g((0, kind), (code, handle), (330, self.table[kind]), (100, "AcDbSymbolTableRecord"), (100, subclass), (2, name))
        if flags:  # standard flags (a block record's 70 is its insertion units instead)
            self.g((70, "0"))

    def _view(self) -> tuple[float, float, float, float]:
        """Centre (x, y), height and width/height of the active viewport: the extents plus a margin."""
        ext = self.doc._extents
        if ext is None:
            return 0.0, 0.0, 100.0, 1.5
        w, hgt = ext[2] - ext[0], ext[3] - ext[1]
        size = max(w, hgt, 1e-6) * (1.0 + 2.0 * ZOOM_MARGIN)
        height = max(hgt * (1.0 + 2.0 * ZOOM_MARGIN), size / 4.0)
        width = max(w * (1.0 + 2.0 * ZOOM_MARGIN), size / 4.0)
        return (ext[0] + ext[2]) / 2.0, (ext[1] + ext[3]) / 2.0, height, width / height

    def tables(self) -> None:
        self.g((0, "SECTION"), (2, "TABLES"))
        cx, cy, height, aspect = self._view()
        self._table("VPORT", 1)
        self._record("VPORT", self.vport, "AcDbViewportTableRecord", "*Active")
        self.g((10, "0.0"), (20, "0.0"), (11, "1.0"), (21, "1.0"), (12, repr(cx)), (22, repr(cy)), (13, "0.0"), (23, "0.0"),
               (14, "1.0"), (24, "1.0"), (15, "10.0"), (25, "10.0"), (16, "0.0"), (26, "0.0"), (36, "1.0"),
               (17, "0.0"), (27, "0.0"), (37, "0.0"), (40, repr(height)), (41, repr(aspect)), (42, "50.0"), (43, "0.0"),
               (44, "0.0"), (50, "0.0"), (51, "0.0"), (71, "0"), (72, "1000"), (73, "1"), (74, "3"), (75, "0"), (76, "0"),
               (77, "0"), (78, "0"), (281, "0"), (65, "1"), (110, "0.0"), (120, "0.0"), (130, "0.0"),
               (111, "1.0"), (121, "0.0"), (131, "0.0"), (112, "0.0"), (122, "1.0"), (132, "0.0"), (79, "0"), (146, "0.0"),
               (0, "ENDTAB"))
        self._table("LTYPE", 3)
        for name, handle in self.ltypes.items():
            self._record("LTYPE", handle, "AcDbLinetypeTableRecord", name)
            self.g((3, "Solid line" if name == "Continuous" else ""), (72, "65"), (73, "0"), (40, "0.0"))
        self.g((0, "ENDTAB"))
        self._table("LAYER", len(self.layers))
        for name, handle in self.layers.items():
            self._record("LAYER", handle, "AcDbLayerTableRecord", name)
            self.g((62, str(self.doc._layers[name])), (6, "Continuous"), (370, "-3"))
        self.g((0, "ENDTAB"))
        self._table("STYLE", 1)
        self._record("STYLE", self.style, "AcDbTextStyleTableRecord", "Standard")
        self.g((40, "0.0"), (41, "1.0"), (50, "0.0"), (71, "0"), (42, "2.5"), (3, "txt"), (4, ""), (0, "ENDTAB"))
        self._table("VIEW", 0)
        self.g((0, "ENDTAB"))
        self._table("UCS", 0)
        self.g((0, "ENDTAB"))
        self._table("APPID", 1)
        self._record("APPID", self.appid, "AcDbRegAppTableRecord", "ACAD")
        self.g((0, "ENDTAB"))
        self._table("DIMSTYLE", 1)
        self.g((100, "AcDbDimStyleTable"))
        self._record("DIMSTYLE", self.dimstyle, "AcDbDimStyleTableRecord", "Standard")
        self.g((0, "ENDTAB"))
        self._table("BLOCK_RECORD", 2)
        for name, handle in self.record.items():
            self._record("BLOCK_RECORD", handle, "AcDbBlockTableRecord", name, flags=False)
            self.g((340, self.layout[name]), (70, "0"), (280, "1"), (281, "0"))
        self.g((0, "ENDTAB"), (0, "ENDSEC"))

    # ------------------------------------------------------------------ BLOCKS, ENTITIES
    def blocks(self) -> None:
        self.g((0, "SECTION"), (2, "BLOCKS"))
        for name, (begin, end) in self.block.items():
            paper = ((67, "1"),) if name == "*Paper_Space" else ()
            owner = self.record[name]
            self.g((0, "BLOCK"), (5, begin), (330, owner), (100, "AcDbEntity"), *paper, (8, "0"), (100, "AcDbBlockBegin"),
                   (2, name), (70, "0"), (10, "0.0"), (20, "0.0"), (30, "0.0"), (3, name), (1, ""),
                   (0, "ENDBLK"), (5, end), (330, owner), (100, "AcDbEntity"), *paper, (8, "0"), (100, "AcDbBlockEnd"))
        self.g((0, "ENDSEC"))

    def entities_section(self) -> None:
        self.g((0, "SECTION"), (2, "ENTITIES"))
        owner = self.record["*Model_Space"]
        for handle, e in zip(self.entities, self.doc._entities):
            self.g((0, e.kind), (5, handle), (330, owner), (100, "AcDbEntity"), (8, e.layer), *e.groups)
        self.g((0, "ENDSEC"))

    # ------------------------------------------------------------------ OBJECTS
    def _dictionary(self, handle: str, owner: str, entries: Iterable[tuple[str, str]]) -> None:
        self.g((0, "DICTIONARY"), (5, handle))
        if owner != "0":
            self.g((102, "{ACAD_REACTORS"), (330, owner), (102, "}"))
        self.g((330, owner), (100, "AcDbDictionary"), (281, "1"))
        for name, target in entries:
            self.g((3, name), (350, target))

    def _layout(self, block: str, name: str, tab: int) -> None:
        model = block == "*Model_Space"
        extents, limits = self._box()
        if not model:
            extents, limits = (1e20, 1e20, -1e20, -1e20), (0.0, 0.0) + PAPER_MM
        paper_w, paper_h = PAPER_MM
        handle, owner = self.layout[block], self.layout_dict
        self.g((0, "LAYOUT"), (5, handle), (102, "{ACAD_REACTORS"), (330, owner), (102, "}"), (330, owner),
               (100, "AcDbPlotSettings"), (1, ""), (2, "none_device"), (4, "ISO_A4_(210.00_x_297.00_MM)"), (6, ""),
               (40, "7.5"), (41, "20.0"), (42, "7.5"), (43, "20.0"), (44, repr(paper_h)), (45, repr(paper_w)),  # portrait sheet
               (46, "0.0"), (47, "0.0"), (48, "0.0"), (49, "0.0"), (140, "0.0"), (141, "0.0"), (142, "1.0"), (143, "1.0"),
               # flags: 16 use standard scale, 32 plot plot styles, 128 print lineweights, 512 draw
               # viewports first, 1024 model type; paper in mm; plot rotation 90 deg counter-clockwise
               # (A4 portrait paper, landscape plot); plot type 1 (extents) for the model, 5 (layout)
               (70, str(1712 if model else 688)), (72, "1"), (73, "1"), (74, "1" if model else "5"), (7, ""),
               (75, "0" if model else "16"), (147, "1.0"), (76, "0"), (77, "2"), (78, "300"), (148, "0.0"), (149, "0.0"),
               (100, "AcDbLayout"), (1, name), (70, "1"), (71, str(tab)),
               (10, repr(limits[0])), (20, repr(limits[1])), (11, repr(limits[2])), (21, repr(limits[3])),
               (12, "0.0"), (22, "0.0"), (32, "0.0"),
               (14, repr(extents[0])), (24, repr(extents[1])), (34, "0.0"),
               (15, repr(extents[2])), (25, repr(extents[3])), (35, "0.0"),
               (146, "0.0"), (13, "0.0"), (23, "0.0"), (33, "0.0"), (16, "1.0"), (26, "0.0"), (36, "0.0"),
               (17, "0.0"), (27, "1.0"), (37, "0.0"), (76, "0"), (330, self.record[block]))
        if model:
            self.g((331, self.vport))

    def objects(self) -> None:
        self.g((0, "SECTION"), (2, "OBJECTS"))
        self._dictionary(self.root, "0", [("ACAD_GROUP", self.groups), ("ACAD_LAYOUT", self.layout_dict)])
        self._dictionary(self.groups, self.root, [])
        self._dictionary(self.layout_dict, self.root, [("Layout1", self.layout["*Paper_Space"]),
                                                       ("Model", self.layout["*Model_Space"])])
        self._layout("*Model_Space", "Model", 0)
        self._layout("*Paper_Space", "Layout1", 1)
        self.g((0, "ENDSEC"))


class _R12Writer:
    """The R12 file (module notes): no handles, no subclass markers, an LWPOLYLINE as a
    POLYLINE with its VERTEX entities and SEQEND."""

    def __init__(self, doc: DxfDocument) -> None:
        self.doc = doc
        self.out: list[str] = []

    def g(self, *pairs: tuple[int, str]) -> None:
        for code, value in pairs:
            self.out.append(f"{code:>3}")
            self.out.append(value)

    def text(self) -> str:
        doc = self.doc
        units = {INSUNITS_MM: "millimetres"}.get(doc._header_ints["$INSUNITS"], f"$INSUNITS {doc._header_ints['$INSUNITS']}")
        self.g((999, f"units: {units} (R12 has no $INSUNITS)"))
        for tag, value in doc._custom:
            self.g((999, f"{tag} = {value}"))
        (ex0, ey0, ex1, ey1), (lx0, ly0, lx1, ly1) = _extents_and_limits(doc)
        ints = doc._header_ints
        self.g((0, "SECTION"), (2, "HEADER"), (9, "$ACADVER"), (1, ACADVER_R12), (9, "$DWGCODEPAGE"), (3, "ANSI_1252"),
               (9, "$INSBASE"), (10, "0.0"), (20, "0.0"), (30, "0.0"),
               (9, "$EXTMIN"), (10, repr(ex0)), (20, repr(ey0)), (30, "0.0"),
               (9, "$EXTMAX"), (10, repr(ex1)), (20, repr(ey1)), (30, "0.0"),
               (9, "$LIMMIN"), (10, repr(lx0)), (20, repr(ly0)),
               (9, "$LIMMAX"), (10, repr(lx1)), (20, repr(ly1)),
               (9, "$LUNITS"), (70, str(ints["$LUNITS"])), (9, "$LUPREC"), (70, str(ints["$LUPREC"])),
               (9, "$HANDLING"), (70, "0"), (0, "ENDSEC"))
        self.g((0, "SECTION"), (2, "TABLES"),
               (0, "TABLE"), (2, "LTYPE"), (70, "1"),
               (0, "LTYPE"), (2, "CONTINUOUS"), (70, "0"), (3, "Solid line"), (72, "65"), (73, "0"), (40, "0.0"),
               (0, "ENDTAB"), (0, "TABLE"), (2, "LAYER"), (70, str(len(doc._layers))))
        for name, colour in doc._layers.items():
            self.g((0, "LAYER"), (2, name), (70, "0"), (62, str(colour)), (6, "CONTINUOUS"))
        self.g((0, "ENDTAB"), (0, "ENDSEC"), (0, "SECTION"), (2, "BLOCKS"), (0, "ENDSEC"), (0, "SECTION"), (2, "ENTITIES"))
        for e in doc._entities:
            if e.kind == "LWPOLYLINE":
                self._polyline(e)
            else:  # LINE, ARC, CIRCLE, TEXT: the R2010 groups less the subclass markers
                self.g((0, e.kind), (8, e.layer), *(pair for pair in e.groups if pair[0] != 100))
        self.g((0, "ENDSEC"), (0, "EOF"))
        return "\n".join(self.out) + "\n"

    def _polyline(self, e: _Entity) -> None:
        """An LWPOLYLINE's vertices (its groups 10/20) as a POLYLINE (group 66: vertices follow;
        70: 1 closed), a VERTEX each, and SEQEND."""
        closed = dict(pair for pair in e.groups if pair[0] == 70)[70]
        xs = [v for code, v in e.groups if code == 10]
        ys = [v for code, v in e.groups if code == 20]
        self.g((0, "POLYLINE"), (8, e.layer), (66, "1"), (10, "0.0"), (20, "0.0"), (30, "0.0"), (70, closed))
        for x, y in zip(xs, ys):
            self.g((0, "VERTEX"), (8, e.layer), (10, x), (20, y), (30, "0.0"), (70, "0"))
        self.g((0, "SEQEND"), (8, e.layer))
