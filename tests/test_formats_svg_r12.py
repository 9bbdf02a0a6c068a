"""The SVG profile read by svgelements, the R12 DXF read by ezdxf and LibreCAD (issue 27, item 5).

Every distance is to the exact contour (its arcs as arcs, its spline pieces as fine polylines:
``test_dxf.Chain``), both ways: what the reader gets lies within the chord tolerance of the
contour, and every point of the contour lies within it of what the reader gets.  The SVG is read
by svgelements (an independent SVG library: its own path parser, its own centre of each ``A``
command from the end points, radius and flags, SVG 1.1 appendix F.6.5); the R12 file by ezdxf
(its own DXF parser, R12 mode) and LibreCAD (``dxf2pdf``, its own libdxfrw).
"""
from __future__ import annotations

import dataclasses
import io
import math
import re

import numpy as np
import pytest

from helpers import require_tool
from test_dxf import Chain, dxf_layer, exact_chain, exact_samples

#: templates covering the curves a profile has: exact arcs and a bore with a keyway (default: three-arc
#: cams), quintic envelopes (plate_cam), a groove's two walls and a rim circle (groove_cam), a slot
#: beside the axis (linear_cam), a yoke cam (constant_breadth), a conjugate pair
TEMPLATES = ("default", "plate_cam", "groove_cam", "linear_cam", "constant_breadth", "conjugate_cam")
#: R12's entities (AutoCAD Release 12 DXF reference, ENTITIES section) that camgen's drawings use
R12_KINDS = {"LINE", "ARC", "CIRCLE", "POLYLINE", "VERTEX", "SEQEND", "TEXT"}


def _render(template: str, **output) -> tuple:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template

    scene = load_template(template)
    scene = dataclasses.replace(scene, output=dataclasses.replace(scene.output, **output))
    result = execute(scene, plan_run(scene))
    return scene, result


@pytest.fixture(scope="module")
def svg_curves(rendered):
    """Each template's cams with svgelements' reading of their SVG: layer -> :func:`svg_curve`."""
    out = {}
    for name, (scene, cams) in rendered.items():
        out[name] = [(cam, {layer: svg_curve(segments) for layer, segments in read_svg(svg)[0].items()}) for cam, svg, _, _ in cams]
    return out


@pytest.fixture(scope="module")
def rendered():
    """Each template's cams with their SVG, R12 and R2010 DXF."""
    out = {}
    for name in TEMPLATES:
        scene, r12 = _render(name, formats=("svg", "dxf"), dxf_version="R12")
        _, r2010 = _render(name, formats=("dxf",))
        out[name] = (scene, [(cam, r12.files[f"{cam.name}.svg"], r12.files[f"{cam.name}.dxf"], r2010.files[f"{cam.name}.dxf"])
                             for cam in r12.cams])
    return out


def _loops(cam):
    """What is cut, by layer: the profile and every pocket wall (exact contours)."""
    return {"PROFILE": cam.contour, **{wall.layer: wall.contour for pocket in cam.pockets for wall in pocket.walls}}


# --------------------------------------------------------------------------------------------
# SVG
# --------------------------------------------------------------------------------------------
def read_svg(text: str) -> tuple[dict, object]:
    """svgelements' reading: layer (group id) -> list of its path's segments in user units, and the
    document (its width, height and viewBox)."""
    from svgelements import SVG, Group, Path

    doc = SVG.parse(io.StringIO(text), ppi=25.4)  # 25.4 px per inch: one px is one mm
    layers = {}
    for element in doc.elements():
        if isinstance(element, Group) and element.id is not None:
            paths = [e for e in element if isinstance(e, Path)]
            assert len(paths) == 1, f"layer {element.id}: one closed path"
            layers[element.id] = list(Path(paths[0].values["d"]))  # the path data itself, in user units
    return layers, doc


def svg_curve(segments, per_arc: int = 64):
    """A layer's segments as the cam-frame Chain of its arcs and lines (y = -SVG y) and points on
    them, with the arcs' centres and radii as svgelements finds them."""
    from svgelements import Arc, Close, Line, Move

    assert isinstance(segments[0], Move) and isinstance(segments[-1], Close), "one closed sub-path"
    assert not any(isinstance(s, Move) for s in segments[1:]), "one closed sub-path"
    arcs, lines, points = [], [], []
    flip = np.array([1.0, -1.0])
    for s in segments[1:-1]:
        if isinstance(s, Arc):
            assert s.rx == pytest.approx(s.ry, rel=1e-9), "a circular arc"
            pts = np.asarray(s.npoint(np.linspace(0.0, 1.0, per_arc)), dtype=float) * flip  # svgelements' own arc evaluation
            centre = np.array([s.center.x, s.center.y]) * flip
            start = math.atan2(*(pts[0] - centre)[::-1])
            arcs.append([*centre, s.rx, start, -s.sweep])  # the flip turns SVG's sweep the other way
            points.append(pts)
        elif isinstance(s, Line):
            a, b = np.array([s.start.x, s.start.y]) * flip, np.array([s.end.x, s.end.y]) * flip
            lines.append(np.concatenate([a, b]))
            points.append(a + np.linspace(0, 1, 50)[:, None] * (b - a))
        else:
            raise AssertionError(f"{type(s).__name__} in the path: only A and L commands")
    return Chain(arcs, np.array(lines) if lines else None), np.concatenate(points), np.array(arcs).reshape(-1, 5)


def test_svg_prints_at_one_to_one_and_frames_the_drawing(rendered):
    """width and height in mm equal the viewBox's size (one user unit one mm), and the viewBox is
    the exact bounds of what is cut (y flipped) grown by the stated margin."""
    from camgen.export.svg import MARGIN_MM

    for scene, cams in rendered.values():
        for cam, svg, _, _ in cams:
            text = svg
            width, height = (float(v) for v in re.search(r'width="([^"]+)mm" height="([^"]+)mm"', text).groups())
            _, doc = read_svg(text)
            box = doc.viewbox
            assert (box.width, box.height) == pytest.approx((width, height), rel=1e-12)
            # svgelements' own unit conversion: width 'mm' at 25.4 ppi in px is the viewBox width
            assert doc.width == pytest.approx(box.width, rel=1e-6) and doc.height == pytest.approx(box.height, rel=1e-6)
            lo, hi = (bound := cam.contour.flatten(1e-4)).min(axis=0), bound.max(axis=0)  # the profile holds what else is cut
            slack = scene.output.chord_tol + 1e-4  # the biarcs drawn, and the flattening's chords
            assert box.x == pytest.approx(lo[0] - MARGIN_MM, abs=slack) and box.x + box.width == pytest.approx(hi[0] + MARGIN_MM, abs=slack)
            # SVG y = -y: the top of the viewBox is the highest point of the profile
            assert box.y == pytest.approx(-hi[1] - MARGIN_MM, abs=slack) and box.y + box.height == pytest.approx(-lo[1] + MARGIN_MM, abs=slack)


def test_svg_profile_and_walls_are_arcs_within_chord_tol(rendered, svg_curves):
    """Every layer of what is cut is one closed path of A and L commands; svgelements' arcs (its
    own centres) lie within the chord tolerance of the exact contour and cover it."""
    for name, (scene, _) in rendered.items():
        tol = scene.output.chord_tol
        for cam, layers in svg_curves[name]:
            assert set(layers) >= set(_loops(cam))
            for layer, contour in _loops(cam).items():
                chain, points, arcs = layers[layer]
                assert len(arcs) > 0
                assert np.max(exact_chain(contour).distance(points)) <= tol, f"{cam.name} {layer}: a point of the SVG is off the contour"
                assert np.max(chain.distance(exact_samples(contour))) <= tol, f"{cam.name} {layer}: the SVG misses part of the contour"


def test_svg_exact_arcs_keep_their_centres(svg_curves):
    """An arc of the contour (the three-arc cams' six, a groove's rim circle, the bore) is written
    exactly: svgelements finds its centre and radius (to the file's 1e-9 mm numbers)."""
    from camgen.contour import Arc

    checked = 0
    for cams in svg_curves.values():
        for cam, layers in cams:
            for layer, contour in _loops(cam).items():
                _, _, arcs = layers[layer]
                for seg in (s for s in contour.segments if isinstance(s, Arc)):
                    gap = np.hypot(arcs[:, 0] - seg.center[0], arcs[:, 1] - seg.center[1]) + np.abs(arcs[:, 2] - seg.radius)
                    assert np.min(gap) <= 1e-6, f"{cam.name} {layer}: no SVG arc about the exact arc's centre"
                    checked += 1
            if cam.body.bore_diameter > 0:
                _, _, arcs = layers["BORE"]
                assert np.max(np.hypot(arcs[:, 0], arcs[:, 1])) <= 1e-8
                assert arcs[:, 2] == pytest.approx(cam.body.bore_diameter / 2, abs=1e-8)
    assert checked >= 12  # the default template's two three-arc cams


def test_svg_keyway_is_the_bodys(rendered):
    """The BORE path: the bore arc outside the keyway, then the keyway's corners (camgen.body's
    keyway rectangle), in the cam frame."""
    scene, cams = rendered["default"]
    for cam, svg, _, _ in cams:
        layers, _ = read_svg(svg)
        chain, points, _ = svg_curve(layers["BORE"])
        body = cam.body
        r, half = body.bore_diameter / 2, body.keyway_width / 2
        corners = body.keyway_corners(math.sqrt(r * r - half * half))
        ends = np.array([[s.end.x, -s.end.y] for s in layers["BORE"][:-1]])  # the M point and every end
        assert np.min(np.hypot(*(ends[:, None, :] - corners[None]).transpose(2, 0, 1)), axis=0) == pytest.approx(0, abs=1e-8)
        # points of the bore arc on the circle, none inside the keyway
        on_circle = np.abs(np.hypot(*points.T) - r) <= 1e-8
        angle = np.arctan2(points[on_circle, 1], points[on_circle, 0]) - body.keyway_angle
        assert np.all((np.abs(np.sin(angle)) * r >= half - 1e-8) | (np.cos(angle) < 0)), "the bore arc crosses the keyway"


# --------------------------------------------------------------------------------------------
# DXF R12
# --------------------------------------------------------------------------------------------
def _entity_names(text: str) -> set[str]:
    """The group-0 values of the ENTITIES section, read from the raw group pairs."""
    lines = text.split("\n")
    pairs = list(zip(lines[0::2], lines[1::2]))
    start = next(i for i, (c, v) in enumerate(pairs) if c.strip() == "2" and v == "ENTITIES")
    end = next(i for i in range(start, len(pairs)) if pairs[i][0].strip() == "0" and pairs[i][1] == "ENDSEC")
    return {v for c, v in pairs[start:end] if c.strip() == "0"}


def test_r12_dxf_reads_back_as_r12_within_chord_tol(rendered):
    """ezdxf reads an AC1009 file with no audit error; the entities are R12's (no LWPOLYLINE, no
    SPLINE, no subclass markers); every layer of what is cut is within the chord tolerance of the
    exact contour both ways, and holds the same ARCs, LINEs and CIRCLEs as the R2010 drawing."""
    import ezdxf

    for scene, cams in rendered.values():
        tol = scene.output.chord_tol
        for cam, _, r12, r2010 in cams:
            assert _entity_names(r12) <= R12_KINDS
            assert "AcDb" not in r12 and "LWPOLYLINE" not in r12 and "SPLINE" not in r12
            assert f"999\ncamgen_biarc_tol_mm = {tol!r}" in r12
            doc = ezdxf.read(io.StringIO(r12))
            assert doc.dxfversion == "AC1009"
            assert not doc.audit().has_errors
            new = ezdxf.read(io.StringIO(r2010))
            for layer, contour in _loops(cam).items():
                chain, points, kinds = dxf_layer(doc, layer)
                assert set(kinds) <= {"ARC", "LINE", "CIRCLE"}
                assert np.max(exact_chain(contour).distance(points)) <= tol
                assert np.max(chain.distance(exact_samples(contour))) <= tol
                assert dxf_layer(new, layer)[2] == kinds
                assert np.array_equal(dxf_layer(new, layer)[1], points)
            if cam.body.keyway_width > 0:  # the keyway's three sides: a POLYLINE through the body's corners
                (poly,) = [e for e in doc.modelspace() if e.dxf.layer == "KEYWAY"]
                assert poly.dxftype() == "POLYLINE" and not poly.is_closed
                corners = cam.body.keyway_outside_bore()
                assert np.array([(v.dxf.location.x, v.dxf.location.y) for v in poly.vertices]) == pytest.approx(corners, abs=1e-12)


def test_r12_refuses_splines():
    """R12 has no SPLINE: B-spline mode is refused naming both keys, before anything is computed."""
    from camgen.errors import ParameterError
    from camgen.scene import parse_scene

    table = {"output": {"formats": ["dxf"], "dxf_version": "R12", "dxf_splines": "bspline"},
             "cams": {"c": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0}}}
    with pytest.raises(ParameterError) as info:
        parse_scene(table, "t")
    assert info.value.name == "output.dxf_splines" and "R12" in str(info.value)


def test_librecad_draws_the_r12_file(rendered, tmp_path):
    """LibreCAD (libdxfrw) converts the R12 drawing of the groove cam (arcs, a circle, a POLYLINE)
    to PDF: the drawing has the exact drawing's aspect and every vertex of LibreCAD's paths lies
    on what is cut, within the PDF's device units (Qt writes whole units)."""
    from scipy.spatial import cKDTree

    from test_dxfwriter import PDF_UNITS_TOL, _pdf_paths, librecad_pdf

    librecad = require_tool("librecad")
    scene, cams = rendered["groove_cam"]
    cam, _, r12, _ = cams[0]
    path = tmp_path / f"{cam.name}.dxf"
    path.write_text(r12)
    paths = _pdf_paths(librecad_pdf(librecad, path))
    vertices = np.concatenate(paths)
    body = cam.body
    r = body.bore_diameter / 2
    k = body.keyway_outside_bore()
    loops = [exact_chain(c) for c in _loops(cam).values()]
    arcs = np.concatenate([c.arcs for c in loops] + [[[0.0, 0.0, r, 0.0, 2 * np.pi]]])
    segments = np.concatenate([c.segments for c in loops] + [np.concatenate([k[:-1], k[1:]], axis=1)])
    drawing = Chain(arcs, segments)  # what is cut, exactly
    lo_mm, hi_mm = drawing.samples.min(axis=0), drawing.samples.max(axis=0)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    scale = (hi - lo) / (hi_mm - lo_mm)
    assert scale[0] == pytest.approx(scale[1], rel=2 * PDF_UNITS_TOL / (hi[1] - lo[1]))
    s = scale.mean()
    mm = np.stack([lo_mm[0] + (vertices[:, 0] - lo[0]) / s, hi_mm[1] - (vertices[:, 1] - lo[1]) / s], 1)  # PDF y down
    # within the PDF's units, and Qt's cubic Beziers through arcs (at most 2.7e-4 of the radius: a quarter circle's)
    assert np.max(drawing.distance(mm)) <= PDF_UNITS_TOL / s + 2.7e-4 * np.max(arcs[:, 2]), "a LibreCAD vertex is off the drawing"
    assert len(paths) >= 4  # rim, two walls, the bore with its keyway


def test_barrel_cam_developed_drawing_in_r12_and_its_refusals(tmp_path):
    """The barrel form's own DXF (the developed drawing) follows ``dxf_version``: ezdxf reads the
    R12 file's POLYLINEs through the same vertices as the R2010 file's LWPOLYLINEs, and TEXT; SVG
    and IGES are refused for it naming the format, before anything is computed."""
    import tomllib

    import ezdxf

    from camgen.errors import ParameterError
    from camgen.planning import plan_run
    from camgen.scene import parse_scene, template_dir

    from camgen.export.barrel_drawing import dxf
    from camgen.writers import RunSettings

    scene, r2010 = _render("barrel_cam", formats=("dxf",))
    (cam,) = r2010.cams
    r12 = dxf(cam, RunSettings(scene.name, dataclasses.replace(scene.output, dxf_version="R12"), scene.machining), "dxf")
    assert _entity_names(r12) <= R12_KINDS
    old, new = ezdxf.read(io.StringIO(r12)), ezdxf.read(io.StringIO(r2010.files[f"{cam.name}.dxf"]))
    assert old.dxfversion == "AC1009" and not old.audit().has_errors
    polylines = [(e.dxf.layer, np.array([(v.dxf.location.x, v.dxf.location.y) for v in e.vertices]), e.is_closed)
                 for e in old.modelspace() if e.dxftype() == "POLYLINE"]
    lwpolylines = [(e.dxf.layer, np.array(e.get_points("xy")), e.closed) for e in new.modelspace() if e.dxftype() == "LWPOLYLINE"]
    assert len(polylines) == len(lwpolylines) >= 3
    for (la, pa, ca), (lb, pb, cb) in zip(polylines, lwpolylines):
        assert (la, ca) == (lb, cb) and np.array_equal(pa, pb)
    assert [e.dxf.text for e in old.modelspace() if e.dxftype() == "TEXT"] == [e.dxf.text for e in new.modelspace() if e.dxftype() == "TEXT"]
    table = tomllib.loads((template_dir() / "barrel_cam.toml").read_text())
    table.pop("machining", None)
    for fmt in ("svg",):  # iges: the STEP solid (tests/test_barrel_iges.py)
        table["output"] = {"formats": [fmt]}
        with pytest.raises(ParameterError) as caught:
            plan_run(parse_scene(table, "t", base_dir=tmp_path))
        assert caught.value.name == "output.formats" and fmt in str(caught.value)
