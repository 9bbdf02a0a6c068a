"""DXF drawings, read back by ezdxf, GDAL (pyogrio) and OpenSCAD.

Distances are exact point-to-arc and point-to-segment distances (:class:`Chain`), measured
both ways: every point read back lies within the tolerance of the exact contour, and every
point of the exact contour lies within the tolerance of what was read back.
"""
from __future__ import annotations

import io
import math
import subprocess

import numpy as np
import pytest

from camgen.export.dxf import DxfOptions, contour_to_dxf
from cams import BODIES, radial_error
from helpers import distance_to_arcs, require_tool

TEMPLATES = ("default", "horse_leg", "motion_law", "tricycle", "plate_cam", "flat_follower", "knife_follower", "oscillating_roller",
             "oscillating_flat", "lift_table", "groove_cam", "conjugate_cam", "constant_breadth", "linear_cam",
             "packaging_machine", "wire_edm_cam")
#: templates whose form draws its own DXF (not a plate's profile): tests/test_barrel_drawing.py reads it back
OWN_DRAWING = ("barrel_cam",)
GDAL_STEP_DEG = 0.05  # OGR_ARC_STEPSIZE: GDAL samples arcs every 0.05 deg


# --------------------------------------------------------------------------------------------
# Independent geometry: exact distances to chains of arcs and segments
# --------------------------------------------------------------------------------------------
def _segment_distance(p, a, b):
    ab = b - a
    length2 = np.einsum("ij,ij->i", ab, ab)
    w = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    return np.hypot(*(p - a - w[:, None] * ab).T)


def _arc_distance(p, centre, radius, start, sweep):
    """Distance of points p (n, 2) to arcs (n,): radial distance where the point's angle lies in the
    sweep, else the distance to the nearer end point."""
    d = p - centre
    lo = np.where(sweep > 0, start, start + sweep)
    inside = np.mod(np.arctan2(d[:, 1], d[:, 0]) - lo, 2 * math.pi) <= np.abs(sweep)
    ends = [centre + radius[:, None] * np.stack([np.cos(a), np.sin(a)], 1) for a in (start, start + sweep)]
    end_dist = np.minimum(*(np.hypot(*(p - e).T) for e in ends))
    return np.where(inside, np.abs(np.hypot(d[:, 0], d[:, 1]) - radius), end_dist)


class Chain:
    """Arcs (k, 5: cx, cy, r, start rad, signed sweep rad) and segments (m, 4: x0, y0, x1, y1).

    :meth:`distance` takes, for each point, the exact distance to the entities owning its
    ``k`` nearest sample points (KD-tree on samples every ``spacing`` mm): an upper bound of
    the true distance, equal to it unless the nearest entity has no sample among them.
    """

    def __init__(self, arcs=None, segments=None, spacing: float = 0.05):
        from scipy.spatial import cKDTree

        self.arcs = np.zeros((0, 5)) if arcs is None or not len(arcs) else np.asarray(arcs, float).reshape(-1, 5)
        self.segments = np.zeros((0, 4)) if segments is None or not len(segments) else np.asarray(segments, float).reshape(-1, 4)
        pts, owner = [], []
        # samples from each entity's start up to (not including) its end: no duplicate points
        for i, (cx, cy, r, a0, sweep) in enumerate(self.arcs):
            n = 1 + int(min(abs(sweep) * r / spacing, 20000))
            t = a0 + sweep * np.arange(n) / n
            pts.append(np.stack([cx + r * np.cos(t), cy + r * np.sin(t)], 1))
            owner.append(np.full(n, i))
        if len(self.segments):
            seg = self.segments
            n = 1 + np.minimum(np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1]) / spacing, 20000).astype(int)
            idx = np.repeat(np.arange(len(seg)), n)
            f = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / n[idx]
            pts.append(seg[idx, :2] + f[:, None] * (seg[idx, 2:] - seg[idx, :2]))
            owner.append(len(self.arcs) + idx)
        self.samples = np.concatenate(pts)
        self.owner = np.concatenate(owner)
        self.tree = cKDTree(self.samples)

    def distance(self, points, k: int = 12):
        _, near = self.tree.query(points, k=k)
        best = np.full(len(points), np.inf)
        na = len(self.arcs)
        for j in range(k):
            e = self.owner[near[:, j]]
            is_arc = e < na
            d = np.empty(len(points))
            if is_arc.any():
                a = self.arcs[e[is_arc]]
                d[is_arc] = _arc_distance(points[is_arc], a[:, :2], a[:, 2], a[:, 3], a[:, 4])
            if (~is_arc).any():
                s = self.segments[e[~is_arc] - na]
                d[~is_arc] = _segment_distance(points[~is_arc], s[:, :2], s[:, 2:])
            best = np.minimum(best, d)
        return best


def exact_chain(contour, per_piece: int = 64) -> Chain:
    """The exact contour: its arcs as arcs, its spline pieces as polylines of ``per_piece`` chords
    (chord error (chord length)^2 / (8 x radius of curvature): below 1e-7 mm for the cams here)."""
    from camgen.contour import Arc

    arcs, segments = [], []
    for seg in contour.segments:
        if isinstance(seg, Arc):
            arcs.append([*seg.center, seg.radius, seg.start_angle, seg.sweep])
        else:
            p = seg.point(np.linspace(0.0, 1.0, seg.n_pieces * per_piece + 1))
            segments.append(np.concatenate([p[:-1], p[1:]], axis=1))
    return Chain(arcs, np.concatenate(segments) if segments else None)


def exact_samples(contour, per_piece: int = 48, per_arc: int = 4000) -> np.ndarray:
    """Points on the exact contour: ``per_piece`` per spline piece, ``per_arc`` per arc."""
    from camgen.contour import Arc

    out = []
    for seg in contour.segments:
        n = per_arc if isinstance(seg, Arc) else seg.n_pieces * per_piece
        out.append(seg.point(np.arange(n) / n))
    return np.concatenate(out)


def read_dxf(text):
    import ezdxf

    doc = ezdxf.read(io.StringIO(text))
    assert not doc.audit().has_errors
    assert doc.dxfversion == "AC1024" and doc.header["$INSUNITS"] == 4
    return doc


def defined_layers(doc) -> set[str]:
    """Names in the file's LAYER table (ezdxf adds "Defpoints" when it loads a file without it)."""
    return {layer.dxf.name for layer in doc.layers} - {"Defpoints"}


def dxf_layer(doc, layer: str, per_span: int = 64, arc_points: int = 200):
    """A layer read back by ezdxf: (Chain of its ARCs and LINEs, points on them (n, 2), entity types).

    ARC angles come from the file (counter-clockwise from start to end), ``arc_points`` points on
    each; SPLINEs are evaluated by ezdxf at ``per_span`` points per knot span and kept as polylines."""
    arcs, segments, points, kinds = [], [], [], []
    for e in doc.modelspace():
        if e.dxf.layer != layer:
            continue
        kinds.append(e.dxftype())
        if e.dxftype() in ("ARC", "CIRCLE"):  # a CIRCLE: a whole turn (a groove cam's rim, a circular wall)
            a0 = math.radians(e.dxf.start_angle) if e.dxftype() == "ARC" else 0.0
            sweep = math.radians((e.dxf.end_angle - e.dxf.start_angle) % 360.0) if e.dxftype() == "ARC" else 2 * math.pi
            arcs.append([e.dxf.center.x, e.dxf.center.y, e.dxf.radius, a0, sweep])
            t = a0 + sweep * np.linspace(0, 1, arc_points)
            points.append(np.stack([e.dxf.center.x + e.dxf.radius * np.cos(t), e.dxf.center.y + e.dxf.radius * np.sin(t)], 1))
        elif e.dxftype() == "LINE":
            a, b = np.array(e.dxf.start)[:2], np.array(e.dxf.end)[:2]
            segments.append(np.concatenate([a, b])[None])
            points.append(a + np.linspace(0, 1, 50)[:, None] * (b - a))
        elif e.dxftype() == "SPLINE":
            knots = np.unique(np.array(e.knots))
            t = np.append((knots[:-1, None] + np.arange(per_span) / per_span * np.diff(knots)[:, None]).ravel(), knots[-1])
            p = np.array(list(e.construction_tool().points(t)))[:, :2]
            segments.append(np.concatenate([p[:-1], p[1:]], axis=1))
            points.append(p)
        else:
            raise AssertionError(f"unexpected {e.dxftype()} on layer {layer}")
    chain = Chain(arcs, np.concatenate(segments) if segments else None)
    return chain, np.concatenate(points), kinds


def gdal_layers(path) -> dict:
    """Every layer of a DXF as read by GDAL (pyogrio): name -> list of vertex arrays (n, 2)."""
    import pyogrio
    import shapely

    pyogrio.set_gdal_config_options({"OGR_ARC_STEPSIZE": str(GDAL_STEP_DEG)})
    try:
        meta, _, wkb, fields = pyogrio.raw.read(path)
    finally:
        pyogrio.set_gdal_config_options({"OGR_ARC_STEPSIZE": None})
    layer = fields[list(meta["fields"]).index("Layer")]
    out: dict = {}
    for name, geom in zip(layer, shapely.from_wkb(wkb)):
        out.setdefault(name, []).append(shapely.get_coordinates(geom))
    return out


def gdal_chain(lines) -> Chain:
    return Chain(segments=np.concatenate([np.concatenate([p[:-1], p[1:]], axis=1) for p in lines]))


def gdal_sagitta(chain: Chain) -> float:
    """Largest gap between an arc and GDAL's chords through it, r (1 - cos(step / 2))."""
    if not len(chain.arcs):
        return 0.0
    return float(np.max(chain.arcs[:, 2])) * (1.0 - math.cos(math.radians(GDAL_STEP_DEG) / 2))


def assert_round_trip(contour, doc, path, layer: str, tol: float, gdal: bool = True) -> None:
    """``layer`` of the DXF lies within ``tol`` of ``contour`` and covers it, by ezdxf and GDAL."""
    exact = exact_chain(contour)
    samples = exact_samples(contour)
    chain, points, _ = dxf_layer(doc, layer)
    assert np.max(exact.distance(points)) <= tol, "ezdxf: a point of the file is off the contour"
    assert np.max(chain.distance(samples)) <= tol, "ezdxf: a point of the contour is off the file"
    if gdal:
        lines = gdal_layers(path)[layer]
        vertices = np.concatenate(lines)
        assert np.max(exact.distance(vertices)) <= tol, "GDAL: a vertex of the file is off the contour"
        chords = gdal_chain(lines)
        assert np.max(chords.distance(samples)) <= tol + gdal_sagitta(chain), "GDAL: a point of the contour is off the file"


# --------------------------------------------------------------------------------------------
# Test cams: concave profiles
# --------------------------------------------------------------------------------------------
def trefoil():
    """Spline cam r = 40 + 8 cos(3 theta): concave near theta = 60, 180, 300 deg (r^2 + 2 r'^2 - r r'' < 0)."""
    from camgen.contour import Contour, Spline

    theta = np.linspace(0.0, 2 * math.pi, 721)
    r = 40.0 + 8.0 * np.cos(3 * theta)
    pts = np.stack([r * np.cos(theta), r * np.sin(theta)], axis=1)
    pts[-1] = pts[0]
    return Contour([Spline.interpolate(theta, pts, periodic=True)])


def notched():
    """A 40 mm circle with a concave notch: a clockwise arc (centre (60, 0)) joining the circle's
    points at -20 and +20 deg, and a straight-sided spline piece on the far side."""
    from camgen.contour import Arc, Contour, Spline

    a = math.radians(20.0)
    p_lo, p_hi = 40.0 * np.array([math.cos(a), -math.sin(a)]), 40.0 * np.array([math.cos(a), math.sin(a)])
    centre = np.array([60.0, 0.0])
    rho = float(np.hypot(*(p_hi - centre)))
    start = math.atan2(*(p_lo - centre)[::-1])
    end = math.atan2(*(p_hi - centre)[::-1])
    notch = Arc(tuple(centre), rho, start, -((start - end) % (2 * math.pi)))  # clockwise through 180 deg: concave
    upper = Arc((0.0, 0.0), 40.0, a, math.pi - a)  # up to (-40, 0)
    lower = Arc((0.0, 0.0), 40.0, math.pi + 0.3, math.pi - a - 0.3)  # from 180 + 17.2 deg to -20 deg
    q0, q1 = upper.end_point, lower.start_point
    coeffs = np.zeros((4, 1, 2))
    coeffs[2, 0], coeffs[3, 0] = q1 - q0, q0  # a straight piece (LINE in both modes)
    return Contour([notch, upper, Spline(np.array([0.0, 1.0]), coeffs), lower])


def _render_dxfs(construction: bool) -> dict:
    """Every bundled template: its cams and their DXF text, rendered as `camgen run` does (with
    ``output.dxf_construction = construction``)."""
    import dataclasses

    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template

    out = {}
    for name in TEMPLATES:
        scene = load_template(name)
        scene = dataclasses.replace(scene, output=dataclasses.replace(scene.output, dxf_construction=construction))
        result = execute(scene, plan_run(scene, only=["dxf"]))
        out[name] = (scene, {c.name: (c, result.files[f"{c.name}.dxf"]) for c in result.cams})
    return out


@pytest.fixture(scope="module")
def template_dxfs():
    """The default DXFs of every template: what is cut (PROFILE, BORE, KEYWAY)."""
    return _render_dxfs(False)


@pytest.fixture(scope="module")
def construction_dxfs():
    """The DXFs of every template with ``output.dxf_construction = true``."""
    return _render_dxfs(True)


# --------------------------------------------------------------------------------------------
# Default DXF of every template: ARCs and LINEs only, within chord_tol both ways
# --------------------------------------------------------------------------------------------
def test_templates_are_all_tested():
    from camgen.scene import template_dir

    assert sorted(p.stem for p in template_dir().glob("*.toml")) == sorted(TEMPLATES + OWN_DRAWING)


@pytest.mark.parametrize("template", TEMPLATES)
def test_template_dxf_has_no_spline_and_reads_back_within_chord_tol(template, template_dxfs, construction_dxfs, tmp_path):
    scene, cams = template_dxfs[template]
    tol = scene.output.chord_tol
    for name, (cam, text) in cams.items():
        doc = read_dxf(text)
        kinds = {e.dxftype() for e in doc.modelspace()}
        assert "SPLINE" not in kinds and kinds <= {"ARC", "LINE", "LWPOLYLINE", "CIRCLE"}
        assert dict(doc.header.custom_vars)["camgen_biarc_tol_mm"] == repr(tol)
        path = tmp_path / f"{name}.dxf"
        path.write_text(text)
        assert_round_trip(cam.contour, doc, path, "PROFILE", tol)
        for wall in (wall for pocket in cam.pockets for wall in pocket.walls):  # a groove's walls, each on its layer
            assert_round_trip(wall.contour, doc, path, wall.layer, tol)
        if cam.pitch is not None:
            _, with_construction = construction_dxfs[template][1][name]
            path.write_text(with_construction)
            assert_round_trip(cam.pitch, read_dxf(with_construction), path, "PITCH", tol)
        # three-arc cams stay their six exact arcs
        if cam.kind == "three_arc":
            radii = sorted(e.dxf.radius for e in doc.modelspace() if e.dxf.layer == "PROFILE" and e.dxftype() == "ARC")
            assert len([e for e in doc.modelspace() if e.dxf.layer == "PROFILE"]) == 6
            assert radii == pytest.approx(sorted(s.radius for s in cam.contour.segments), abs=1e-12)


def _roller_radius(spec):
    """The roller radius the scene gives a cam (disk cams: their follower spec), else None."""
    params = spec.params
    follower = getattr(params, "follower", getattr(getattr(params, "params", None), "first", None))  # a conjugate pair's: roller A
    if follower is not None and hasattr(follower, "roller_radius"):
        return follower.roller_radius if follower.kind == "roller" else None
    return spec.follower.roller_radius if spec.follower is not None and spec.follower.kind == "roller" else None


@pytest.mark.parametrize("template", ["motion_law", "tricycle", "plate_cam", "oscillating_roller"])
def test_pitch_layer_is_the_roller_centre_path(template, construction_dxfs):
    """Every PITCH point lies one roller radius (from the scene file) outside the exact profile,
    and every point of the profile's parallel curve (GEOS buffer) lies on the PITCH layer."""
    import shapely
    from shapely.geometry import Polygon

    scene, cams = construction_dxfs[template]
    tol = scene.output.chord_tol
    for spec in scene.cams:
        cam, text = cams[spec.name]
        roller = _roller_radius(spec)
        doc = read_dxf(text)
        chain, points, _ = dxf_layer(doc, "PITCH")
        profile = exact_chain(cam.contour)
        assert np.max(np.abs(profile.distance(points) - roller)) <= tol + 1e-6
        # on the roller's side: outside the cam
        assert not np.any(shapely.contains_xy(Polygon(exact_samples(cam.contour, 8)), points[:, 0], points[:, 1]))
        ring = np.asarray(Polygon(exact_samples(cam.contour, 64)).buffer(roller, quad_segs=256).exterior.coords)
        assert np.max(chain.distance(ring)) <= tol + roller * (1 - math.cos(math.pi / 1024)) + 1e-6


@pytest.mark.parametrize("construction", [False, True])
@pytest.mark.parametrize("template", TEMPLATES)
def test_header_extents_are_the_bounds_of_everything_drawn(template, construction, template_dxfs, construction_dxfs, tmp_path):
    scene, cams = (construction_dxfs if construction else template_dxfs)[template]
    for name, (cam, text) in cams.items():
        doc = read_dxf(text)
        lo, hi = np.array(doc.header["$EXTMIN"]), np.array(doc.header["$EXTMAX"])
        assert lo[2] == hi[2] == 0.0
        assert np.allclose(doc.header["$LIMMIN"], lo[:2]) and np.allclose(doc.header["$LIMMAX"], hi[:2])
        path = tmp_path / f"{name}.dxf"
        path.write_text(text)
        layers = gdal_layers(path)
        vertices = np.concatenate([p for lines in layers.values() for p in lines])
        assert set(layers) >= ({"PROFILE", "CENTER"} if construction else {"PROFILE"})
        # every vertex GDAL reads lies inside the extents, and the extents touch the drawing:
        # GDAL's arc vertices miss an extreme by at most the sagitta of its 0.05 deg step
        assert np.all(vertices >= lo[:2] - 1e-9) and np.all(vertices <= hi[:2] + 1e-9)
        slack = 400.0 * (1 - math.cos(math.radians(GDAL_STEP_DEG)))
        assert np.all(vertices.min(axis=0) - lo[:2] <= slack) and np.all(hi[:2] - vertices.max(axis=0) <= slack)
        # and they agree with the exact drawing within the chord tolerance (the profile dominates)
        exact = exact_samples(cam.contour)
        assert np.all(exact.min(axis=0) >= lo[:2] - scene.output.chord_tol - 1e-9)
        assert np.all(exact.max(axis=0) <= hi[:2] + scene.output.chord_tol + 1e-9)


@pytest.mark.parametrize("template", ["default", "motion_law", "tricycle"])
def test_openscad_imports_the_profile_layer(template, construction_dxfs, tmp_path):
    """OpenSCAD 2021 imports the PROFILE layer as one closed outline: the extruded volume is
    the exact area x height within the chord tolerance bound.

    Bound per mm of perimeter: the biarc tolerance, plus OpenSCAD's import grid (it snaps DXF
    points to 0.001 mm: up to 0.0005 * sqrt(2) mm off), plus its chords through the ARCs
    ($fa = 0.1 deg, $fs = 0.05 mm: sagitta <= r (1 - cos(max(0.1 deg, 0.05 mm / r) / 2)))."""
    import trimesh

    openscad = require_tool("openscad")
    scene, cams = construction_dxfs[template]  # a drawing with construction layers: the PROFILE layer alone
    height = 10.0
    for cam, text in cams.values():
        (tmp_path / "cam.dxf").write_text(text)
        (tmp_path / "cam.scad").write_text(f'linear_extrude(height={height}) import("cam.dxf", layer="PROFILE", $fn=0, $fa=0.1, $fs=0.05);\n')
        proc = subprocess.run([openscad, "-o", "cam.stl", "--export-format", "binstl", "cam.scad"], cwd=tmp_path,
                              capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        assert "WARNING" not in proc.stderr and "ERROR" not in proc.stderr, proc.stderr
        mesh = trimesh.load(tmp_path / "cam.stl", force="mesh")
        assert mesh.is_watertight and mesh.body_count == 1
        chain, _, _ = dxf_layer(read_dxf(text), "PROFILE")
        r = chain.arcs[:, 2]
        step = np.minimum(np.abs(chain.arcs[:, 4]), np.maximum(math.radians(0.1), 0.05 / r))
        tessellation = float(np.sum(r * np.abs(chain.arcs[:, 4]) * r * (1 - np.cos(step / 2))))
        bound = height * (cam.contour.length * (scene.output.chord_tol + 0.0005 * math.sqrt(2)) + tessellation)
        assert abs(mesh.volume - cam.contour.area * height) <= bound + 1e-6 * mesh.volume  # + float32 STL


# --------------------------------------------------------------------------------------------
# What is cut and what is construction (issue 21, item 13)
# --------------------------------------------------------------------------------------------
CUT = {"PROFILE", "BORE", "KEYWAY"}


@pytest.mark.parametrize("template", TEMPLATES)
def test_default_dxf_holds_only_what_is_cut(template, template_dxfs, construction_dxfs):
    """The default DXF defines and draws PROFILE, BORE and KEYWAY only (those the body has);
    ``dxf_construction`` adds PITCH (roller followers), CENTER and ZERO (cams that know their
    cam angle 0) and changes nothing else."""
    scene, cams = template_dxfs[template]
    for name, (cam, text) in cams.items():
        doc = read_dxf(text)
        body = cam.body
        cut = {"PROFILE"} | ({"BORE"} if body.bore_diameter > 0 else set()) | ({"KEYWAY"} if body.keyway_width > 0 else set())
        cut |= {wall.layer for pocket in cam.pockets for wall in pocket.walls}  # a groove's walls are cut too
        assert {e.dxf.layer for e in doc.modelspace()} == cut
        assert defined_layers(doc) == cut | {"0"}
        _, with_construction = construction_dxfs[template][1][name]
        full = read_dxf(with_construction)
        roller = _roller_radius(next(spec for spec in scene.cams if spec.name == name)) is not None
        linear = next(spec for spec in scene.cams if spec.name == name).form == "linear"  # its pitch curve is open: no PITCH layer
        construction = {"CENTER"} | ({"PITCH"} if roller and not linear else set()) | ({"ZERO"} if cam.zero_mark is not None else set())
        assert {e.dxf.layer for e in full.modelspace()} == cut | construction
        assert cut_entities(doc) == cut_entities(full)  # the cut layers are the same entities in both files


def cut_entities(doc) -> list:
    """The entities on the cut layers: type, layer and attributes (handles aside)."""
    return [(e.dxftype(), e.dxf.layer, str(e.dxfattribs(drop={"handle", "owner"}))) for e in doc.modelspace() if e.dxf.layer in CUT]


def hole_area(body) -> float:
    """Closed-form area (mm^2) of the hole: the bore circle, pi r^2, plus the keyway rectangle's
    part outside it: the rectangle beyond the chord at x0 = sqrt(r^2 - (w/2)^2), w (reach - x0),
    less the circular segment beyond that chord, r^2 (t - sin t) / 2 with t = 2 asin(w / 2r)
    (the area of a circular segment of central angle t: e.g. CRC Standard Mathematical Tables)."""
    r = body.bore_diameter / 2
    if body.keyway_width == 0:
        return math.pi * r * r
    w = body.keyway_width
    x0 = math.sqrt(r * r - w * w / 4)
    t = 2 * math.asin(w / (2 * r))
    return math.pi * r * r + w * (body.bore_diameter / 2 + body.keyway_depth - x0) - r * r * (t - math.sin(t)) / 2


#: Largest gap (mm) between the ends of two pieces of the hole outline that meet.
JOIN_TOL = 1e-9


def hole_loop(doc, arc_points: int = 200_001) -> np.ndarray:
    """The BORE and KEYWAY entities read back by ezdxf, chained end to end into one closed ring
    (k, 2); AssertionError if a piece's end meets no other piece within :data:`JOIN_TOL` or the
    chain does not close.  ARCs are sampled at ``arc_points`` points from their DXF angles."""
    pieces = []
    for e in doc.modelspace():
        if e.dxf.layer not in ("BORE", "KEYWAY"):
            continue
        kind = e.dxftype()
        if kind in ("ARC", "CIRCLE"):
            a0 = math.radians(e.dxf.start_angle) if kind == "ARC" else 0.0
            sweep = math.radians((e.dxf.end_angle - e.dxf.start_angle) % 360.0) if kind == "ARC" else 2 * math.pi
            t = a0 + sweep * np.linspace(0.0, 1.0, arc_points)
            p = np.stack([e.dxf.center.x + e.dxf.radius * np.cos(t), e.dxf.center.y + e.dxf.radius * np.sin(t)], axis=1)
            if kind == "ARC":  # the DXF's own end points (ezdxf), not the samples' rounding
                p[0], p[-1] = np.array(e.start_point)[:2], np.array(e.end_point)[:2]
            pieces.append(p)
        elif kind == "LWPOLYLINE":
            assert not e.closed
            pieces.append(np.array(e.get_points("xy")))
        else:
            raise AssertionError(f"unexpected {kind} on layer {e.dxf.layer}")
    ring = [pieces.pop(0)]
    while pieces:
        end = ring[-1][-1]
        gaps = [min(np.hypot(*(p[0] - end)), np.hypot(*(p[-1] - end))) for p in pieces]
        k = int(np.argmin(gaps))
        assert gaps[k] <= JOIN_TOL, f"the hole outline is open: a gap of {gaps[k]:.3g} mm"
        piece = pieces.pop(k)
        ring.append(piece if np.hypot(*(piece[0] - end)) <= np.hypot(*(piece[-1] - end)) else piece[::-1])
    loop = np.concatenate([ring[0]] + [p[1:] for p in ring[1:]])
    assert np.hypot(*(loop[-1] - loop[0])) <= JOIN_TOL, "the hole outline does not close"
    return loop[:-1] if len(ring) > 1 else loop


HOLE_BODIES = {
    **BODIES,
    "bore only": BODIES["stride"].__class__(thickness=10.0, bore_diameter=16.0),
    "keyway at 0 deg": BODIES["stride"].__class__(thickness=10.0, bore_diameter=20.0, keyway_width=6.0, keyway_depth=2.8,
                                                 keyway_angle=0.0),
    "keyway at 217 deg, wide": BODIES["stride"].__class__(thickness=10.0, bore_diameter=20.0, keyway_width=15.0, keyway_depth=4.0,
                                                         keyway_angle=math.radians(217.0)),
}


@pytest.mark.parametrize("mode", ["biarc", "bspline"])
@pytest.mark.parametrize("name", sorted(HOLE_BODIES))
def test_hole_outline_is_one_closed_loop_of_the_closed_form_area(name, mode, contours):
    """The bore and keyway read back by ezdxf chain end to end into one closed curve whose area
    is the closed-form hole area (:func:`hole_area`), within the sampling of the arc (its 200,000
    chords cut off at most r^2 sweep (sweep / 200,000)^2 / 12)."""
    from helpers import shoelace

    body = HOLE_BODIES[name]
    doc = read_dxf(contour_to_dxf(contours["stride"], body, options=DxfOptions(splines=mode)))
    loop = hole_loop(doc)
    r = body.bore_diameter / 2
    if body.keyway_width:  # the keyway is on the outline: it reaches keyway_depth beyond the bore
        assert np.max(np.hypot(*loop.T)) >= r + body.keyway_depth
    sampling = r * r * 2 * math.pi * (2 * math.pi / 200_000) ** 2 / 12
    assert abs(abs(shoelace(loop)) - hole_area(body)) <= sampling + 1e-9 * hole_area(body)


@pytest.mark.parametrize("template", ["default", "plate_cam"])
def test_openscad_imports_the_whole_default_dxf_as_the_part(template, template_dxfs, tmp_path):
    """OpenSCAD's import() of the whole default DXF, extruded by the cam's thickness, is the part:
    volume = (profile area - hole area) x thickness, the profile area exact (Contour.area, tested
    against closed forms elsewhere), the hole's in closed form (:func:`hole_area`); one body with
    one through hole (Euler number 0).  Bound as in test_openscad_imports_the_profile_layer, the
    bore's chords included."""
    import trimesh

    openscad = require_tool("openscad")
    scene, cams = template_dxfs[template]
    for cam, text in cams.values():
        body = cam.body
        assert body.bore_diameter > 0 and body.keyway_width > 0
        (tmp_path / "cam.dxf").write_text(text)
        (tmp_path / "cam.scad").write_text(f'linear_extrude(height={body.thickness!r}) import("cam.dxf", $fn=0, $fa=0.1, $fs=0.05);\n')
        proc = subprocess.run([openscad, "-o", "cam.stl", "--export-format", "binstl", "cam.scad"], cwd=tmp_path,
                              capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        assert "WARNING" not in proc.stderr and "ERROR" not in proc.stderr, proc.stderr
        mesh = trimesh.load(tmp_path / "cam.stl", force="mesh")
        assert mesh.is_watertight and mesh.body_count == 1 and mesh.euler_number == 0
        chain, _, _ = dxf_layer(read_dxf(text), "PROFILE")
        r = np.append(chain.arcs[:, 2], body.bore_diameter / 2)
        sweep = np.append(np.abs(chain.arcs[:, 4]), 2 * math.pi)
        step = np.minimum(sweep, np.maximum(math.radians(0.1), 0.05 / r))
        tessellation = float(np.sum(r * sweep * r * (1 - np.cos(step / 2))))
        hole_perimeter = math.pi * body.bore_diameter + 2 * (body.keyway_depth + body.keyway_width)
        snap = (cam.contour.length + hole_perimeter) * 0.0005 * math.sqrt(2)
        bound = body.thickness * (cam.contour.length * scene.output.chord_tol + snap + tessellation)
        part = (cam.contour.area - hole_area(body)) * body.thickness
        assert abs(mesh.volume - part) <= bound + 1e-6 * mesh.volume  # + float32 STL
        assert bound < 0.01 * part  # the bound is tight enough to tell a missing hole or a stray layer


def test_removed_dxf_pitch_key_is_refused_naming_its_replacement(tmp_path, capsys):
    from camgen.cli import main
    from camgen.errors import ParameterError
    from camgen.scene import parse_scene

    table = {"output": {"formats": ["dxf"], "dxf_pitch": True}, "cams": {"c": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0,
                                                                                "c_mm": 25.0}}}
    with pytest.raises(ParameterError, match=r"output\.dxf_pitch.*output\.dxf_construction = true"):
        parse_scene(table, "s")
    (tmp_path / "s.toml").write_text('[output]\nformats = ["dxf"]\ndxf_pitch = false\n[cams.c]\nkind = "three_arc"\n'
                                     'a_mm = 220.0\nb_mm = 160.0\nc_mm = 25.0\n')
    assert main(["run", str(tmp_path / "s.toml"), "-o", str(tmp_path / "out"), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("camgen: error: ") and "output.dxf_construction" in err
    assert not (tmp_path / "out").exists()


def test_construction_key_without_a_dxf_is_refused():
    from camgen.errors import ParameterError
    from camgen.scene import parse_scene

    cams = {"c": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0}}
    with pytest.raises(ParameterError, match=r"output\.dxf_construction.*only with \"dxf\" in output\.formats"):
        parse_scene({"output": {"formats": ["points"], "dxf_construction": True}, "cams": cams}, "s")
    assert parse_scene({"output": {"formats": ["dxf"], "dxf_construction": True}, "cams": cams}, "s").output.dxf_construction


# --------------------------------------------------------------------------------------------
# Concave profiles in both modes
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("mode", ["biarc", "bspline"])
@pytest.mark.parametrize("shape", ["trefoil", "notched"])
def test_concave_profiles_round_trip(shape, mode, tmp_path):
    contour = {"trefoil": trefoil, "notched": notched}[shape]()
    assert not contour.is_convex()
    tol = 1e-3
    text = contour_to_dxf(contour, options=DxfOptions(splines=mode, chord_tol=tol))
    assert text == contour_to_dxf(contour, options=DxfOptions(splines=mode, chord_tol=tol))  # deterministic
    doc = read_dxf(text)
    _, _, kinds = dxf_layer(doc, "PROFILE")
    path = tmp_path / "cam.dxf"
    path.write_text(text)
    if mode == "biarc":
        assert set(kinds) <= {"ARC", "LINE"}
        # the concave parts come back as clockwise arcs: the file's ARCs run counter-clockwise,
        # so a concave arc's end point is where the contour enters it
        assert_round_trip(contour, doc, path, "PROFILE", tol)
    else:
        assert ("SPLINE" in kinds) == (shape == "trefoil")
        # exact B-splines: within the spline sampling error of ezdxf's polyline (1e-6 mm); GDAL
        # evaluates SPLINEs at its own points, so only its vertices are checked
        assert_round_trip(contour, doc, path, "PROFILE", 1e-6, gdal=False)
        vertices = np.concatenate(gdal_layers(path)["PROFILE"])
        assert np.max(exact_chain(contour).distance(vertices)) <= 1e-6
    if shape == "notched":
        assert "LINE" in kinds and "ARC" in kinds


# --------------------------------------------------------------------------------------------
# Exact B-spline option, options, and entities
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["stride", "steering"])
def test_bspline_entities_match_the_contour_by_ezdxf(name, contours, steering):
    contour = contours[name]
    pitch = steering.pitch if name == "steering" else None
    doc = read_dxf(contour_to_dxf(contour, BODIES[name], pitch, DxfOptions(splines="bspline", center_mark=5.0)))
    msp = doc.modelspace()
    profile = [e for e in msp if e.dxf.layer == "PROFILE"]
    assert len(profile) == contour.n_segments
    for entity, seg in zip(profile, contour.segments):
        if entity.dxftype() == "ARC":
            assert entity.dxf.radius == pytest.approx(seg.radius, abs=1e-9)
        else:
            assert entity.dxftype() == "SPLINE" and entity.dxf.degree == 3
            knots = np.array(entity.knots)
            assert np.all(knots[:4] == knots[0]) and np.all(knots[-4:] == knots[-1])  # clamped
            pts = np.array(list(entity.construction_tool().points(np.linspace(knots[0], knots[-1], 5001))))[:, :2]
            assert np.max(radial_error(contour, pts)) <= 1e-6
    bore = [e for e in msp if e.dxf.layer == "BORE"]
    assert bore and bore[0].dxf.radius == pytest.approx(BODIES[name].bore_diameter / 2)
    assert len([e for e in msp if e.dxf.layer == "KEYWAY"]) == 1
    assert len([e for e in msp if e.dxf.layer == "CENTER"]) == 2
    assert bool([e for e in msp if e.dxf.layer == "PITCH"]) == (pitch is not None)
    # only the layers drawn are defined
    assert defined_layers(doc) == {"0", "PROFILE", "BORE", "KEYWAY", "CENTER"} | ({"PITCH"} if pitch else set())
    assert dict(doc.header.custom_vars) == {"camgen_splines": "bspline", "camgen_bspline_tol_mm": "1e-08"}  # the stated tolerance


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_bspline_dxf_read_by_gdal_within_1e6(name, contours, tmp_path):
    contour = contours[name]
    path = tmp_path / "cam.dxf"
    path.write_text(contour_to_dxf(contour, BODIES[name], options=DxfOptions(splines="bspline")))
    lines = gdal_layers(path)["PROFILE"]
    pts = np.concatenate(lines)
    assert len(pts) > 100
    if name == "stride":
        assert np.max(distance_to_arcs(pts, contour.segments)) <= 1e-6
    else:
        assert np.max(radial_error(contour, pts)) <= 1e-6
    # the PROFILE pieces go all the way round: their total length is the contour's perimeter
    assert sum(np.sum(np.hypot(*np.diff(p, axis=0).T)) for p in lines) == pytest.approx(contour.length, rel=1e-4)


@pytest.mark.parametrize("tol", [1e-2, 1e-3, 1e-4])
def test_biarcs_within_tolerance_and_fewer_than_the_spline_pieces(tol, contours, tmp_path):
    contour = contours["steering"]
    text = contour_to_dxf(contour, options=DxfOptions(chord_tol=tol))  # biarc is the default
    doc = read_dxf(text)
    path = tmp_path / "cam.dxf"
    path.write_text(text)
    assert_round_trip(contour, doc, path, "PROFILE", tol, gdal=tol >= 1e-3)
    _, _, kinds = dxf_layer(doc, "PROFILE")
    assert set(kinds) <= {"ARC", "LINE"}
    if tol >= 1e-3:  # fewer entities than the spline has pieces when the tolerance allows
        assert len(kinds) < contour.segments[0].n_pieces


def test_dxf_options_are_checked():
    from camgen.errors import ParameterError

    with pytest.raises(ParameterError, match="dxf_splines"):
        DxfOptions(splines="nurbs")
    with pytest.raises(ParameterError, match="chord_tol"):
        DxfOptions(chord_tol=0.0)
    assert DxfOptions().splines == "biarc"


# --------------------------------------------------------------------------------------------
# Compact B-splines within bspline_tol, measured both ways against the contour
# --------------------------------------------------------------------------------------------
def curve_distance(points: np.ndarray, curve, t_lo: float, t_hi: float, seeds: int = 20_001) -> np.ndarray:
    """Distance (mm) of every point (n, 2) to a parametric curve ``curve(t, order)`` (points,
    first and second derivatives, (m, 2)) on [t_lo, t_hi]: the nearest of ``seeds`` samples,
    then Newton steps on (C(t) - p) . C'(t) = 0 (the foot point)."""
    from scipy.spatial import cKDTree

    grid = np.linspace(t_lo, t_hi, seeds)
    _, nearest = cKDTree(curve(grid, 0)).query(points)
    t = grid[nearest]
    for _ in range(8):
        p, d1, d2 = curve(t, 0), curve(t, 1), curve(t, 2)
        g = np.einsum("ij,ij->i", p - points, d1)
        dg = np.einsum("ij,ij->i", d1, d1) + np.einsum("ij,ij->i", p - points, d2)
        t = np.clip(t - g / dg, t_lo, t_hi)
    return np.hypot(*(curve(t, 0) - points).T)


def _spline_curve(seg):
    return lambda t, order: seg.eval_t(t, order)


def _bspline_curve(knots, controls):
    from scipy.interpolate import BSpline

    b = BSpline(knots, controls, 3)
    ders = [b, b.derivative(1), b.derivative(2)]
    return lambda t, order: ders[order](t)


def _two_way(seg, other, other_range, count: int = 5_001) -> tuple[float, float]:
    """Largest distance from ``other`` (curve(t, order) on other_range) to the segment, and
    from the segment to ``other``, both at ``count`` points."""
    t_other = np.linspace(*other_range, count)
    t_seg = np.linspace(seg.breaks[0], seg.breaks[-1], count)
    there = curve_distance(other(t_other, 0), _spline_curve(seg), seg.breaks[0], seg.breaks[-1])
    back = curve_distance(seg.eval_t(t_seg), other, *other_range)
    return float(there.max()), float(back.max())


@pytest.mark.parametrize("template", ["tricycle", "motion_law", "lift_table"])
@pytest.mark.parametrize("tol", [1e-6, 1e-8])
def test_compact_spline_is_within_tol_both_ways_with_fewer_pieces(template, tol, template_dxfs):
    """The compact form of every spline segment: cubic, within tol of the segment both ways, no
    more pieces than a cubic segment (fewer where the tolerance allows: a looser tolerance, fewer
    pieces; a quintic segment's cubic form needs more), the same end points, tangents and second
    derivatives (so joints keep their G1/G2 continuity), C2 inside."""
    from camgen.contour import Contour, Spline
    from camgen.export.dxf import compact_spline

    _, cams = template_dxfs[template]
    for cam, _ in cams.values():
        new_segments = []
        for seg in cam.contour.segments:
            if not isinstance(seg, Spline):
                new_segments.append(seg)
                continue
            new = compact_spline(seg, tol)
            new_segments.append(new)
            assert new.degree == 3
            assert new.n_pieces <= seg.n_pieces or seg.degree > 3
            there, back = _two_way(seg, _spline_curve(new), (new.breaks[0], new.breaks[-1]))
            assert there <= tol * (1 + 1e-6) and back <= tol * (1 + 1e-6), (there, back)
            for order in (0, 1, 2):
                for t, piece, tau in ((seg.breaks[0], 0, 0.0), (seg.breaks[-1], -1, None)):
                    want = seg.eval_piece(np.array([seg.n_pieces - 1 if piece else 0]),
                                          np.array([np.diff(seg.breaks)[-1] if piece else 0.0]), order)[0]
                    got = new.eval_piece(np.array([new.n_pieces - 1 if piece else 0]),
                                         np.array([np.diff(new.breaks)[-1] if piece else 0.0]), order)[0]
                    assert np.allclose(got, want, rtol=0, atol=1e-9 * (1 + np.max(np.abs(want)))), (order, got, want)
        compact = Contour(new_segments)
        assert [j.continuity for j in compact.joints()] == [j.continuity for j in cam.contour.joints()]
        if tol == 1e-6:  # the compact form saves pieces at a looser tolerance
            splines = [s for s in cam.contour.segments if isinstance(s, Spline) and s.degree == 3]
            assert not splines or sum(compact_spline(s, 1e-6).n_pieces for s in splines) < 0.8 * sum(s.n_pieces for s in splines)


@pytest.mark.parametrize("template", ["tricycle", "motion_law"])
def test_bspline_dxf_is_within_the_stated_tolerance_both_ways(template, template_dxfs):
    """The B-spline DXF read back by ezdxf: every SPLINE (knots and control points, evaluated by
    scipy) lies within the header's camgen_bspline_tol_mm of its contour segment and the segment
    within it of the SPLINE; C2 runs are written with simple knots (fewer control points than
    a cubic segment's exact form wherever the tolerance allows); every SPLINE is cubic."""
    from camgen.contour import Spline

    _, cams = template_dxfs[template]
    for cam, _ in cams.values():
        doc = read_dxf(contour_to_dxf(cam.contour, options=DxfOptions(splines="bspline")))
        tol = float(doc.header.custom_vars.get("camgen_bspline_tol_mm"))
        assert tol == 1e-8
        entities = [e for e in doc.modelspace() if e.dxf.layer == "PROFILE"]
        assert len(entities) == cam.contour.n_segments
        for entity, seg in zip(entities, cam.contour.segments):
            if not isinstance(seg, Spline) or entity.dxftype() != "SPLINE":
                continue
            assert entity.dxf.degree == 3
            knots, controls = np.array(entity.knots), np.array(entity.control_points)[:, :2]
            inner = knots[4:-4]
            assert np.all(np.diff(inner) > 0)  # simple interior knots: C2 everywhere inside
            there, back = _two_way(seg, _bspline_curve(knots, controls), (knots[0], knots[-1]))
            assert there <= tol * (1 + 1e-6) and back <= tol * (1 + 1e-6), (there, back)
            assert len(controls) <= seg.n_pieces + 3 or seg.degree > 3
