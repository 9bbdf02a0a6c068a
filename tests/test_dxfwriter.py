"""camgen's own DXF R2010 writer (camgen.export.dxfwriter), checked by independent readers.

* **ezdxf** (``readfile``, ``audit``, ``recover``) reads the files with no error and nothing to
  fix, and gets back exactly the doubles that were written (the writer prints ``repr`` floats).
* **GDAL** ``ogrinfo`` reads every feature on its layer, the extent is the closed-form bounding
  box, and its vertices lie on the closed-form arcs, circles, lines and (scipy-evaluated) splines.
* **LibreCAD** ``dxf2pdf`` (Debian package ``librecad``) converts the file headless; the paths of
  its PDF, mapped back to millimetres, lie on the closed-form geometry and cover it.
* A **structural check written from the DXF Reference** (group-code pairs parsed here): sections
  in order, every object one unique handle, owners and pointers at existing handles, $HANDSEED
  above every handle, table counts, subclass markers, layouts linked to their block records.
* NaN and infinite values raise ExportError and write nothing.

The test drawing is bounded by a closed LWPOLYLINE rectangle (-20, -20) ... (40, 20): every
other entity lies inside it, so that rectangle is the drawing's exact bounding box.
"""
from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import zlib

import numpy as np
import pytest

from camgen.errors import ExportError
from camgen.export.dxfwriter import DxfDocument
from helpers import require_tool

BOX = (-20.0, -20.0, 40.0, 20.0)
RECT = [(-20.0, -20.0), (40.0, -20.0), (40.0, 20.0), (-20.0, 20.0)]
LINE = ((0.1, 1.0 / 3.0), (30.0, -0.0))
ARC = ((1.0 / 3.0, -2.0 / 7.0), math.sqrt(2.0), 10.0, 250.0)  # centre, radius, start and end deg (CCW)
CIRCLE = ((10.0, 5.0), 5.0)
BEZIER = ([(0.0, 10.0), (5.0, 18.0), (15.0, 18.0), (20.0, 10.0)], [0.0] * 4 + [1.0] * 4)  # one cubic Bezier span
SPLINE2 = ([(-15.0, -15.0), (-10.0, -5.0), (0.0, -18.0), (10.0, -5.0), (30.0, -15.0)],
           [0.0] * 4 + [0.4] + [1.0] * 4)  # two spans, interior knot 0.4
LAYERS = {"EDGE": 1, "CURVES": 5, "FREE": 3}


def drawing() -> DxfDocument:
    doc = DxfDocument()
    for name, color in LAYERS.items():
        doc.add_layer(name, color)
    doc.add_lwpolyline(RECT, True, "EDGE")
    doc.add_line(*LINE, "EDGE")
    doc.add_arc(ARC[0], ARC[1], ARC[2], ARC[3], "CURVES")
    doc.add_circle(*CIRCLE, "CURVES")
    doc.add_spline(BEZIER[0], BEZIER[1], 3, "FREE")
    doc.add_spline(SPLINE2[0], SPLINE2[1], 3, "FREE")
    doc.set_extents(*BOX)
    doc.add_custom_property("camgen_test", "value 1")
    return doc


KINDS = ["LWPOLYLINE", "LINE", "ARC", "CIRCLE", "SPLINE", "SPLINE"]
ENTITY_LAYERS = ["EDGE", "EDGE", "CURVES", "CURVES", "FREE", "FREE"]


@pytest.fixture(scope="module")
def dxf_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("dxfw") / "drawing.dxf"
    path.write_text(drawing().to_text(), encoding="utf-8", newline="\n")
    return path


# --------------------------------------------------------------------------------------------
# Closed-form geometry of the test drawing (scipy's BSpline evaluates the splines)
# --------------------------------------------------------------------------------------------
def _spline(controls, knots):
    from scipy.interpolate import BSpline

    return BSpline(np.asarray(knots), np.asarray(controls), 3)


def dense_samples(step: float = 1e-3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points on every entity of the drawing, at most ``step`` mm apart along each (n, 2); the
    index of the piece each lies on (n,); each piece's smallest radius of curvature, mm
    (inf: straight; the splines' from s' and s'': |s'|^3 / |s' x s''|)."""
    pts, rho = [], []
    closed = np.array(RECT + RECT[:1])
    segs = [closed[i:i + 2] for i in range(4)] + [np.array(LINE)]
    for a, b in segs:
        n = int(np.ceil(np.hypot(*(b - a)) / step)) + 1
        pts.append(a + np.linspace(0, 1, n)[:, None] * (b - a))
        rho.append(math.inf)
    (cx, cy), r, a0, a1 = ARC
    for centre, radius, start, sweep in (((cx, cy), r, math.radians(a0), math.radians(a1 - a0)),
                                         (CIRCLE[0], CIRCLE[1], 0.0, 2 * math.pi)):
        t = start + sweep * np.linspace(0, 1, int(abs(sweep) * radius / step) + 2)
        pts.append(np.stack([centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)], 1))
        rho.append(radius)
    for controls, knots in (BEZIER, SPLINE2):  # both shorter than 100 mm
        spline = _spline(controls, knots)
        t = np.linspace(0, 1, int(100.0 / step) + 1)
        pts.append(spline(t))
        d1, d2 = spline.derivative(1)(t), spline.derivative(2)(t)
        rho.append(float(np.min(np.hypot(*d1.T) ** 3 / np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]))))
    owner = np.concatenate([np.full(len(p), i) for i, p in enumerate(pts)])
    return np.concatenate(pts), owner, np.array(rho)


def spline_distance(points: np.ndarray, controls, knots) -> np.ndarray:
    """Distance of ``points`` (n, 2) to a spline: nearest of 20001 samples, then Newton steps on
    |s(t) - p|^2 (clamped to [0, 1])."""
    s = _spline(controls, knots)
    d1, d2 = s.derivative(1), s.derivative(2)
    grid = np.linspace(0, 1, 20001)
    curve = s(grid)
    t = grid[np.argmin(((points[:, None, :] - curve[None, :, :]) ** 2).sum(-1), axis=1)]
    for _ in range(8):
        e = s(t) - points
        g = np.einsum("ij,ij->i", e, d1(t))
        h = np.einsum("ij,ij->i", d1(t), d1(t)) + np.einsum("ij,ij->i", e, d2(t))
        t = np.clip(t - g / np.where(h > 0, h, 1.0), 0.0, 1.0)
    return np.hypot(*(s(t) - points).T)


# --------------------------------------------------------------------------------------------
# ezdxf: reads, audits and recovers clean; exact round trip
# --------------------------------------------------------------------------------------------
def test_ezdxf_reads_audits_and_recovers_without_errors_or_fixes(dxf_file):
    import ezdxf
    from ezdxf import recover

    doc = ezdxf.readfile(dxf_file)
    auditor = doc.audit()
    assert not auditor.has_errors and not auditor.has_fixes, [e.message for e in auditor.errors + auditor.fixes]
    doc2, auditor2 = recover.readfile(dxf_file)
    assert not auditor2.has_errors and not auditor2.has_fixes, [e.message for e in auditor2.errors + auditor2.fixes]
    assert doc.dxfversion == doc2.dxfversion == "AC1024"
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    assert doc.layout_names_in_taborder() == ["Model", "Layout1"]


def test_entities_read_back_by_ezdxf_are_exactly_what_was_written(dxf_file):
    import ezdxf

    doc = ezdxf.readfile(dxf_file)
    entities = list(doc.modelspace())
    assert [e.dxftype() for e in entities] == KINDS and [e.dxf.layer for e in entities] == ENTITY_LAYERS
    rect, line, arc, circle, bezier, spline2 = entities
    assert [tuple(p) for p in rect.get_points("xy")] == RECT and rect.closed
    assert tuple(line.dxf.start) == (*LINE[0], 0.0) and tuple(line.dxf.end) == (*LINE[1], 0.0)
    assert math.copysign(1.0, line.dxf.end.y) == -1.0  # even the sign of -0.0
    assert tuple(arc.dxf.center)[:2] == ARC[0] and arc.dxf.radius == ARC[1]
    assert (arc.dxf.start_angle, arc.dxf.end_angle) == (ARC[2], ARC[3])
    assert tuple(circle.dxf.center)[:2] == CIRCLE[0] and circle.dxf.radius == CIRCLE[1]
    for entity, (controls, knots) in ((bezier, BEZIER), (spline2, SPLINE2)):
        assert entity.dxf.degree == 3 and list(entity.knots) == knots and not entity.weights
        assert [tuple(p)[:2] for p in entity.control_points] == controls
        assert not entity.closed
    assert {layer.dxf.name: layer.color for layer in doc.layers if layer.dxf.name in LAYERS} == LAYERS
    assert doc.header["$EXTMIN"] == (-20.0, -20.0, 0.0) and doc.header["$EXTMAX"] == (40.0, 20.0, 0.0)
    assert doc.header["$LIMMIN"] == (-20.0, -20.0) and doc.header["$LIMMAX"] == (40.0, 20.0)
    assert dict(doc.header.custom_vars) == {"camgen_test": "value 1"}


@pytest.mark.parametrize("value", [0.1 + 0.2, 1.0 / 3.0, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
                                   -123456.78901234567, 1e-17, -0.0])
def test_every_double_survives_the_round_trip_bit_for_bit(value, tmp_path):
    import ezdxf

    doc = DxfDocument()
    doc.add_line((value, -value), (0.0, 1.0))
    path = tmp_path / "x.dxf"
    path.write_text(doc.to_text())
    start = ezdxf.readfile(path).modelspace()[0].dxf.start
    assert np.array([start.x, start.y]).tobytes() == np.array([value, -value]).tobytes()


# --------------------------------------------------------------------------------------------
# Structure, parsed here from the group-code pairs (DXF Reference chapters 2-7 and 10)
# --------------------------------------------------------------------------------------------
def group_pairs(text: str) -> list[tuple[int, str]]:
    lines = text.split("\n")
    assert lines[-1] == "" and len(lines) % 2 == 1, "group code / value lines must pair up"
    pairs = [(int(lines[i]), lines[i + 1]) for i in range(0, len(lines) - 1, 2)]
    for code, value in pairs:  # 10-59, 110-149, 210-239, 460-469, 1010-1059: doubles, finite
        if 10 <= code <= 59 or 110 <= code <= 149 or 210 <= code <= 239 or 460 <= code <= 469:
            assert math.isfinite(float(value)), (code, value)
    return pairs


def split_objects(pairs):
    """[(section, kind, groups)] for every record that starts with a 0 group."""
    out, section, current = [], None, None
    for i, (code, value) in enumerate(pairs):
        if code == 0:
            if value == "SECTION":
                section = pairs[i + 1][1]
            current = (section, value, [])
            out.append(current)
        else:
            assert current is not None, "a group before the first 0 group"
            current[2].append((code, value))
    return out


def owner_of(groups) -> str | None:
    """The owner (330) outside the 102 {...} application groups."""
    depth = 0
    for code, value in groups:
        if code == 102:
            depth += 1 if value.startswith("{") else -1
        elif code == 330 and depth == 0:
            return value
    return None


SUBCLASSES = {"LINE": ["AcDbEntity", "AcDbLine"], "ARC": ["AcDbEntity", "AcDbCircle", "AcDbArc"],
              "CIRCLE": ["AcDbEntity", "AcDbCircle"], "LWPOLYLINE": ["AcDbEntity", "AcDbPolyline"],
              "SPLINE": ["AcDbEntity", "AcDbSpline"]}
NO_HANDLE = {"SECTION", "ENDSEC", "ENDTAB", "EOF", "CLASS"}
#: Object types AutoCAD registers as classes (DXF Reference, chapter 3 "Default class values"):
#: an object of one of these types needs its CLASS record.
CLASS_TYPES = {"ACDBDICTIONARYWDFLT", "ACDBPLACEHOLDER", "DICTIONARYVAR", "IDBUFFER", "IMAGEDEF", "IMAGEDEF_REACTOR",
               "LAYER_INDEX", "LAYOUT", "OBJECT_PTR", "PLOTSETTINGS", "RASTERVARIABLES", "SORTENTSTABLE",
               "SPATIAL_INDEX", "SPATIAL_FILTER", "WIPEOUTVARIABLES"}


def check_structure(text: str) -> dict:
    pairs = group_pairs(text)
    objects = split_objects(pairs)
    sections = [g[0][1] for s, kind, g in objects if kind == "SECTION"]
    assert sections == ["HEADER", "CLASSES", "TABLES", "BLOCKS", "ENTITIES", "OBJECTS"]
    assert objects[-1][1] == "EOF" and pairs[-1] == (0, "EOF")
    header = objects[0][2]
    assert header[1:3] == [(9, "$ACADVER"), (1, "AC1024")]
    variables = {header[i][1]: header[i + 1][1] for i in range(1, len(header) - 1) if header[i][0] == 9}
    handles: dict[str, tuple] = {}
    for obj in objects:
        section, kind, groups = obj
        if kind in NO_HANDLE:
            continue
        own = [v for c, v in groups if c == (105 if kind == "DIMSTYLE" and section == "TABLES" else 5)]
        assert len(own) == 1 and re.fullmatch(r"[0-9A-F]+", own[0]), (kind, own)
        assert own[0] not in handles, f"handle {own[0]} used twice"
        handles[own[0]] = obj
    assert int(variables["$HANDSEED"], 16) > max(int(h, 16) for h in handles)
    records = {(kind, dict(g).get(2)): h for h, (s, kind, g) in handles.items()}
    objects_section = [o for o in objects if o[0] == "OBJECTS" and o[1] != "SECTION"]
    root = objects_section[0]
    assert root[1] == "DICTIONARY" and owner_of(root[2]) == "0"
    assert {v for c, v in root[2] if c == 3} >= {"ACAD_GROUP", "ACAD_LAYOUT"}
    classes = {dict(g)[1]: int(dict(g)[91]) for s, kind, g in objects if kind == "CLASS"}
    for kind in {k for s, k, g in objects_section} & CLASS_TYPES:  # registered, with the instance count
        assert classes.get(kind) == sum(k == kind for s, k, g in objects_section), kind
    for h, (section, kind, groups) in handles.items():
        owner = owner_of(groups)
        if kind == "TABLE" or (section, kind) == ("OBJECTS", "DICTIONARY") and groups is root[2]:
            assert owner == "0", (kind, h)
        else:
            assert owner in handles, f"{kind} {h}: owner {owner} is not a handle of the file"
        for code, value in groups:  # every pointer group points at an object of the file
            if 330 <= code <= 369 or 390 <= code <= 399:
                assert value in handles or (code == 330 and value == "0" and owner == "0"), (kind, h, code, value)
    # tables: LTYPE before LAYER, 70 counts, records owned by their table
    tables = [(h, dict(g)[2]) for h, (s, kind, g) in handles.items() if kind == "TABLE"]
    names = [n for _, n in tables]
    assert names.index("LTYPE") < names.index("LAYER")
    for h, name in tables:
        entries = [e for e, (s, kind, g) in handles.items() if kind == name and owner_of(g) == h]
        assert int(dict(handles[h][2])[70]) == len(entries), name
    assert {n for (k, n) in records if k == "LTYPE"} >= {"ByBlock", "ByLayer", "Continuous"}
    model = records[("BLOCK_RECORD", "*Model_Space")]
    layers = {n for (k, n) in records if k == "LAYER"}
    for h, (section, kind, groups) in handles.items():
        if section == "ENTITIES":
            assert owner_of(groups) == model
            assert [v for c, v in groups if c == 100] == SUBCLASSES[kind], kind
            assert dict(groups)[8] in layers
    # every block record points at a LAYOUT (340) that points back (its last 330)
    for name in ("*Model_Space", "*Paper_Space"):
        layout = handles[dict(handles[records[("BLOCK_RECORD", name)]][2])[340]]
        assert layout[1] == "LAYOUT" and [v for c, v in layout[2] if c == 330][-1] == records[("BLOCK_RECORD", name)]
        assert ("BLOCK", name) in {(k, dict(g).get(2)) for s, k, g in objects if s == "BLOCKS"}
    assert ("VPORT", "*Active") in records and ("APPID", "ACAD") in records and ("LAYER", "0") in records
    return {"variables": variables, "handles": handles}


def test_structure_handles_owners_and_handseed(dxf_file):
    info = check_structure(dxf_file.read_text())
    kinds = [kind for s, kind, g in info["handles"].values() if s == "ENTITIES"]
    assert kinds == KINDS


def _camgen_dxfs():
    """DXF text of camgen drawings: the default template (ZERO layer, keyway), both spline modes."""
    from camgen.export.dxf import DxfOptions, contour_to_dxf
    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template

    scene = load_template("default")
    cams = execute(scene, plan_run(scene, only=["dxf"])).cams
    return {f"{c.name}-{mode}": contour_to_dxf(c.contour, c.body, c.pitch, DxfOptions(splines=mode), c.zero_mark)
            for c in cams for mode in ("biarc", "bspline")}


def test_camgen_drawings_pass_the_structural_check_and_ezdxf_audit():
    import io

    import ezdxf

    texts = _camgen_dxfs()
    assert any("\nSPLINE\n" in t for t in texts.values()) and any("\nLWPOLYLINE\n" in t for t in texts.values())
    for name, text in texts.items():
        check_structure(text)
        auditor = ezdxf.read(io.StringIO(text)).audit()
        assert not auditor.has_errors and not auditor.has_fixes, name


def test_same_drawing_same_bytes_in_other_processes():
    from pathlib import Path

    code = "import sys; from test_dxfwriter import drawing; sys.stdout.write(drawing().to_text())"
    src = str(Path(__file__).resolve().parent)  # this test module's folder
    texts = {subprocess.run([sys.executable, "-c", code], check=False, capture_output=True, text=True, timeout=120,
                            env={**os.environ, "PYTHONHASHSEED": seed, "PYTHONPATH": src}).stdout for seed in ("1", "2")}
    assert texts == {drawing().to_text()}


# --------------------------------------------------------------------------------------------
# Bad values: ExportError, nothing written
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_values_raise_and_add_nothing(bad):
    doc = drawing()
    before = doc.to_text()
    calls = [lambda: doc.add_line((bad, 0.0), (1.0, 1.0), "EDGE"),
             lambda: doc.add_arc((0.0, 0.0), 1.0, 0.0, bad, "CURVES"),
             lambda: doc.add_arc((0.0, 0.0), bad, 0.0, 90.0, "CURVES"),
             lambda: doc.add_circle((0.0, bad), 1.0, "CURVES"),
             lambda: doc.add_lwpolyline([(0.0, 0.0), (bad, 1.0)], False, "EDGE"),
             lambda: doc.add_spline([(0.0, 0.0), (1.0, bad), (2.0, 0.0), (3.0, 0.0)], [0, 0, 0, 0, 1, 1, 1, 1], 3, "FREE"),
             lambda: doc.add_spline(BEZIER[0], [0, 0, 0, 0, bad, 1, 1, 1], 3, "FREE"),
             lambda: doc.set_extents(0.0, 0.0, bad, 1.0)]
    for call in calls:
        with pytest.raises(ExportError, match="finite|NaN"):
            call()
    assert doc.to_text() == before


def test_a_nan_contour_writes_no_file(tmp_path):
    from camgen.contour import Arc, Contour
    from camgen.export.dxf import write_dxf

    path = tmp_path / "cam.dxf"
    with pytest.raises(ExportError):
        write_dxf(Contour([Arc((math.nan, 0.0), 10.0, 0.0, 2 * math.pi)]), path)
    assert list(tmp_path.iterdir()) == []  # no file, no temporary left behind


@pytest.mark.parametrize("call, match", [
    (lambda d: d.add_line((0, 0), (1, 1), "NOPE"), "not defined"),
    (lambda d: d.add_layer("edge", 2), "twice"),
    (lambda d: d.add_layer("A/B", 2), "without any of"),
    (lambda d: d.add_layer("OK", 256), "ACI"),
    (lambda d: d.add_arc((0, 0), 0.0, 0, 90, "EDGE"), "> 0"),
    (lambda d: d.add_spline(BEZIER[0], [0, 0, 0, 1, 1, 1, 1], 3, "FREE"), "needs 8 knots"),
    (lambda d: d.add_spline(BEZIER[0], [0, 0, 0, 0, 1, 1, 1, 0.5], 3, "FREE"), "non-decreasing"),
    (lambda d: d.add_custom_property("k", "two\nlines"), "one-line"),
    (lambda d: d.add_lwpolyline([(0, 0)], False, "EDGE"), "at least 2"),
])
def test_invalid_input_raises_export_error(call, match):
    with pytest.raises(ExportError, match=match):
        call(drawing())


# --------------------------------------------------------------------------------------------
# GDAL ogrinfo
# --------------------------------------------------------------------------------------------
def _ogr_features(text: str) -> list[tuple[str, np.ndarray]]:
    """(layer, vertices (n, 2)) of every feature ogrinfo -al prints."""
    out, layer = [], None
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("Layer (String) = "):
            layer = line.split("= ", 1)[1]
        elif line.startswith(("LINESTRING", "POLYGON")):
            body = line[line.index("(") :].strip("()")
            pts = np.array([[float(v) for v in p.split()[:2]] for p in body.split(",")])
            out.append((layer, pts))
    return out


def test_gdal_reads_every_feature_on_its_layer_and_on_the_exact_geometry(dxf_file):
    ogrinfo = require_tool("ogrinfo")
    summary = subprocess.run([ogrinfo, "-ro", "-al", "-so", str(dxf_file)], check=False, capture_output=True, text=True,
                             timeout=60)
    assert summary.returncode == 0, summary.stderr
    assert "Feature Count: 6" in summary.stdout
    extent = re.search(r"Extent: \(([-\d.]+), ([-\d.]+)\) - \(([-\d.]+), ([-\d.]+)\)", summary.stdout)
    assert tuple(float(v) for v in extent.groups()) == BOX  # the rectangle bounds everything
    full = subprocess.run([ogrinfo, "-ro", "-al", str(dxf_file)], check=False, capture_output=True, text=True, timeout=60)
    assert full.returncode == 0 and "ERROR" not in full.stderr, full.stderr
    features = _ogr_features(full.stdout)
    assert [f[0] for f in features] == ENTITY_LAYERS
    (_, rect), (_, line), (_, arc), (_, circle), (_, bezier), (_, spline2) = features
    assert np.array_equal(rect, np.array(RECT + RECT[:1]))  # closed: back to the first vertex
    assert np.allclose(line, np.array(LINE), rtol=0, atol=1e-13)
    (cx, cy), r, a0, a1 = ARC
    assert np.max(np.abs(np.hypot(arc[:, 0] - cx, arc[:, 1] - cy) - r)) <= 1e-12
    angles = np.degrees(np.arctan2(arc[:, 1] - cy, arc[:, 0] - cx)) % 360.0
    assert np.all((angles >= a0 - 1e-9) & (angles <= a1 + 1e-9))
    assert np.isclose(angles.min(), a0) and np.isclose(angles.max(), a1)  # the whole sweep
    assert np.max(np.abs(np.hypot(circle[:, 0] - CIRCLE[0][0], circle[:, 1] - CIRCLE[0][1]) - CIRCLE[1])) <= 1e-12
    for pts, (controls, knots) in ((bezier, BEZIER), (spline2, SPLINE2)):
        assert len(pts) > 10 and np.max(spline_distance(pts, controls, knots)) <= 1e-9
        assert np.array_equal(pts[0], controls[0]) and np.array_equal(pts[-1], controls[-1])  # clamped ends


# --------------------------------------------------------------------------------------------
# LibreCAD dxf2pdf
# --------------------------------------------------------------------------------------------
#: Qt's PDF coordinates are whole device units: a vertex may be up to this many units off
#: (0.5 rounding on each axis, plus the rounding of the bounding box the scale comes from).
PDF_UNITS_TOL = 2.0


def _pdf_paths(pdf: bytes, per_curve: int = 16) -> list[np.ndarray]:
    """Sub-paths (n, 2) of the page content after its clip rectangle, in PDF device units; each
    cubic Bezier (``c``, Qt draws circles so) becomes ``per_curve`` points on it."""
    paths: list[list] = []
    s = np.linspace(0.0, 1.0, per_curve + 1)[1:, None]
    for raw in re.findall(rb"stream\r?\n(.*?)\r?\nendstream", pdf, re.DOTALL):
        try:
            content = zlib.decompress(raw).decode("latin-1")
        except zlib.error:
            content = raw.decode("latin-1", "replace")
        if "W* n" not in content:
            continue
        numbers: list[float] = []
        for token in content.split("W* n", 1)[1].split():
            if token == "m":
                paths.append([np.array([numbers[-2:]])])
            elif token == "l":
                paths[-1].append(np.array([numbers[-2:]]))
            elif token == "c":
                p0 = paths[-1][-1][-1]
                p1, p2, p3 = np.array(numbers[-6:]).reshape(3, 2)
                paths[-1].append((1 - s) ** 3 * p0 + 3 * (1 - s) ** 2 * s * p1 + 3 * (1 - s) * s**2 * p2 + s**3 * p3)
            else:
                try:
                    numbers.append(float(token))
                except ValueError:
                    numbers = []
                continue
            numbers = []
    return [np.concatenate(p) for p in paths if len(p) >= 2]


def librecad_pdf(librecad: str, path) -> bytes:
    """``librecad dxf2pdf -a`` of ``path`` (fit to page); a file it cannot read opens a message box
    that never closes headless: the timeout turns that into a failure."""
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    proc = subprocess.run([librecad, "dxf2pdf", "-a", path.name], cwd=path.parent, check=False, capture_output=True, text=True,
                          timeout=60, env=env)
    assert proc.returncode == 0, proc.stderr
    pdf = path.with_suffix(".pdf")
    assert pdf.exists(), proc.stdout + proc.stderr
    return pdf.read_bytes()


def test_librecad_converts_the_drawing_and_draws_it_where_it_is(dxf_file):
    from scipy.spatial import cKDTree

    librecad = require_tool("librecad")
    paths = _pdf_paths(librecad_pdf(librecad, dxf_file))
    vertices = np.concatenate(paths)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    # fit to page: the device box of the drawing has the aspect of BOX (60 x 40 mm)
    scale_x, scale_y = (hi[0] - lo[0]) / (BOX[2] - BOX[0]), (hi[1] - lo[1]) / (BOX[3] - BOX[1])
    assert scale_x == pytest.approx(scale_y, rel=2 * PDF_UNITS_TOL / (hi[1] - lo[1]))
    scale = (scale_x + scale_y) / 2
    mm = np.stack([BOX[0] + (vertices[:, 0] - lo[0]) / scale, BOX[3] - (vertices[:, 1] - lo[1]) / scale], 1)  # y down
    tol = PDF_UNITS_TOL / scale + 1e-3  # + the sample spacing of the exact geometry
    samples, owner, rho = dense_samples()
    tree = cKDTree(samples)
    assert np.max(tree.query(mm)[0]) <= tol, "a LibreCAD vertex is off the drawing"
    # and the drawing is covered: every exact point lies within tol of LibreCAD's segments, plus
    # the sagitta of its chords on that piece, L^2 / (8 rho) (L: its longest chord on the piece)
    segs = np.concatenate([np.stack([p[:-1], p[1:]], 1) for p in paths])
    segs = (segs - lo) / scale * [1, -1] + [BOX[0], BOX[3]]
    a, ab = segs[:, 0], segs[:, 1] - segs[:, 0]
    piece = owner[tree.query(a + ab / 2)[1]]
    longest = np.array([np.max(np.hypot(*ab[piece == k].T), initial=0.0) for k in range(len(rho))])
    probe, probe_owner, _ = dense_samples(step=0.5)
    bound = tol + np.where(np.isinf(rho), 0.0, longest**2 / (8 * rho))[probe_owner]
    best = np.full(len(probe), np.inf)
    for i in range(0, len(probe), 256):
        p = probe[i:i + 256, None, :]
        w = np.clip(np.einsum("pij,ij->pi", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
        best[i:i + 256] = np.min(np.hypot(*(p - a - w[..., None] * ab).transpose(2, 0, 1)), axis=1)
    assert np.all(best <= bound), "part of the drawing is missing from LibreCAD's PDF"


def test_librecad_converts_a_camgen_drawing(tmp_path):
    librecad = require_tool("librecad")
    text = _camgen_dxfs()["steering-bspline"]
    path = tmp_path / "steering.dxf"
    path.write_text(text)
    paths = _pdf_paths(librecad_pdf(librecad, path))
    assert len(paths) > 10


def test_librecad_draws_every_spline_of_a_quintic_disk_cam(tmp_path):
    """A motion-law roller cam (its envelope in C2 quintic pieces) written with B-spline SPLINEs:
    they are cubic (LibreCAD reads degree <= 3 only) and LibreCAD draws all of them where the
    profile is: every vertex of its PDF lies on the exact profile and every point of the profile
    lies near its paths (within the PDF's unit and half of LibreCAD's longest chord)."""
    from scipy.spatial import cKDTree

    from camgen.export.dxf import DxfOptions, contour_to_dxf
    from camgen.synthesis.followers import FollowerSpec, cam_envelope
    from camgen.synthesis.laws import MotionProgram, Segment

    librecad = require_tool("librecad")
    law = MotionProgram([Segment("cycloidal", math.radians(120), 12.0), Segment("dwell", math.radians(60)),
                         Segment("modified_sine", math.radians(100), -12.0), Segment("dwell", math.radians(80))])
    profile = cam_envelope(FollowerSpec("roller", 30.0, roller_radius=8.0), law).profile
    assert {seg.degree for seg in profile.segments} == {5}
    path = tmp_path / "cam.dxf"
    path.write_text(contour_to_dxf(profile, options=DxfOptions(splines="bspline", center_mark=0.0)))
    import ezdxf

    splines = [e for e in ezdxf.readfile(path).modelspace() if e.dxftype() == "SPLINE"]
    assert len(splines) == profile.n_segments and {e.dxf.degree for e in splines} == {3}
    paths = _pdf_paths(librecad_pdf(librecad, path))
    vertices = np.concatenate(paths)
    exact = profile.evaluate(np.linspace(0.0, profile.n_segments, 200_000, endpoint=False))  # ~1e-3 mm apart
    box_lo, box_hi = exact.min(axis=0), exact.max(axis=0)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    scale_x, scale_y = (hi - lo) / (box_hi - box_lo)
    assert scale_x == pytest.approx(scale_y, rel=2 * PDF_UNITS_TOL / (hi[1] - lo[1]))
    scale = (scale_x + scale_y) / 2
    mm = np.stack([box_lo[0] + (vertices[:, 0] - lo[0]) / scale, box_hi[1] - (vertices[:, 1] - lo[1]) / scale], 1)  # y down
    tol = PDF_UNITS_TOL / scale + 2e-3
    assert np.max(cKDTree(exact).query(mm)[0]) <= tol, "a LibreCAD vertex is off the profile"
    segs = np.concatenate([np.stack([p[:-1], p[1:]], 1) for p in paths])
    longest = float(np.max(np.hypot(*(segs[:, 1] - segs[:, 0]).T))) / scale
    assert np.max(cKDTree(mm).query(exact[::50])[0]) <= tol + longest / 2, "part of the profile is missing from LibreCAD's PDF"
