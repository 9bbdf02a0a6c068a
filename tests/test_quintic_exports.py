"""Every writer on a contour of quintic spline segments, read back by independent programs and
compared with the exact analytic curve the quintics interpolate.

The curve: the polar trefoil ``r(phi) = 40 + 5 cos(3 phi)`` mm (counter-clockwise; concave near
phi = 60, 180, 300 deg where ``r^2 + 2 r'^2 - r r'' < 0``, smallest concave radius 122.5 mm),
interpolated by C2 quintic Hermite pieces (:meth:`Spline.hermite5`) of its exact points, first
and second derivatives on two segments of 30 pieces (the spline parameter is phi itself).

The contour's own distance from the exact curve has the closed-form bound :data:`FIT`: the
Hermite remainder ``h^6 max|P^(6)| / 46080`` (6! 4^3 = 46080 from ``(t - a)^3 (t - b)^3``), with
``P(phi) = 40 e^(i phi) + 2.5 e^(4 i phi) + 2.5 e^(-2 i phi)`` so ``|P^(6)| <= 40 + 2.5 (4^6 + 2^6)``.
Every file is read back by a program that is not camgen (ezdxf, scipy's B-splines, OpenCASCADE's
STEP reader, LinuxCNC's rs274, numpy's CSV reader, trimesh, admesh) and measured against the
exact curve by foot-point Newton iteration on its analytic derivatives.
"""
from __future__ import annotations

import io
import math

import numpy as np
import pytest

from camgen.contour import Contour, Spline
from camgen.errors import ExportError, GeometryError, ParameterError

PIECES = 30  # quintic pieces per segment (two segments)
H = math.pi / PIECES
#: Closed-form bound (mm) of the distance between the quintic contour and the exact curve.
FIT = H**6 * (40.0 + 2.5 * (4**6 + 2**6)) / 46080.0
#: Exact area (mm^2) of the trefoil: (1/2) integral of r^2 = pi (40^2 + 5^2 / 2).
AREA = math.pi * (40.0**2 + 12.5)
THICKNESS = 6.0
BORE = 12.0


def trefoil(phi: np.ndarray, order: int = 0) -> np.ndarray:
    """The exact curve's point (order 0), first or second derivative d/dphi (n, 2)."""
    phi = np.asarray(phi, dtype=float)
    r, r1, r2 = 40.0 + 5.0 * np.cos(3 * phi), -15.0 * np.sin(3 * phi), -45.0 * np.cos(3 * phi)
    u = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    v = np.stack([-np.sin(phi), np.cos(phi)], axis=-1)
    if order == 0:
        return r[..., None] * u
    if order == 1:
        return r1[..., None] * u + r[..., None] * v
    return (r2 - r)[..., None] * u + 2.0 * r1[..., None] * v


def exact_distance(points: np.ndarray) -> np.ndarray:
    """Distance (mm) of points (n, 2) to the exact trefoil (nearest of 20001 samples, then Newton
    on the foot-point condition with the analytic derivatives)."""
    from test_dxf import curve_distance

    return curve_distance(points, trefoil, 0.0, 2.0 * math.pi)


def inside_exact(points: np.ndarray) -> np.ndarray:
    """Points (n, 2) strictly inside the exact trefoil (star-shaped about the origin)."""
    phi = np.arctan2(points[:, 1], points[:, 0])
    return np.hypot(points[:, 0], points[:, 1]) < 40.0 + 5.0 * np.cos(3 * phi)


def quintic_contour(segments: int = 2) -> Contour:
    out = []
    for k in range(segments):
        t = np.linspace(2 * math.pi * k / segments, 2 * math.pi * (k + 1) / segments, 2 * PIECES // segments + 1)
        out.append(Spline.hermite5(t, trefoil(t), trefoil(t, 1), trefoil(t, 2)))
    return Contour(out)


@pytest.fixture(scope="module")
def contour() -> Contour:
    c = quintic_contour()
    assert all(seg.degree == 5 for seg in c.segments)
    return c


def exact_samples(count: int = 20_000) -> np.ndarray:
    return trefoil(2.0 * math.pi * np.arange(count) / count)


def test_the_quintic_contour_is_within_its_closed_form_bound(contour):
    """The reference itself: the quintic contour lies within FIT (3.0e-7 mm) of the exact curve
    and encloses its exact area."""
    assert 2e-7 < FIT < 4e-7
    pts = contour.evaluate(np.linspace(0.0, 2.0, 40_001))
    assert np.max(exact_distance(pts)) <= FIT
    assert contour.area == pytest.approx(AREA, abs=FIT * 2 * math.pi * 45.0)


# --------------------------------------------------------------------------------------------
# B-spline forms and the cubic compact form
# --------------------------------------------------------------------------------------------
def _scipy_curve(knots, controls, degree):
    from scipy.interpolate import BSpline

    b = BSpline(knots, controls, degree)
    return lambda t, order: b(t, order)


def test_bspline_forms_of_a_quintic_are_exact_degree_5(contour):
    """spline_bspline / spline_bezier_controls keep the quintic's degree: scipy evaluates the
    degree-5 B-spline (knots.size - controls - 1 = 5) on the exact curve within FIT; the C2 joins
    of hermite5 get knot multiplicity 3 (5 for the Bezier form), the ends 6."""
    from camgen.export.dxf import spline_bezier_controls, spline_bspline

    seg = contour.segments[0]
    for form, inner in ((spline_bspline, 3), (spline_bezier_controls, 5)):
        knots, controls = form(seg)
        degree = knots.size - len(controls) - 1
        assert degree == 5
        values, counts = np.unique(knots, return_counts=True)
        assert counts[0] == counts[-1] == 6 and np.all(counts[1:-1] == inner) and values.size == PIECES + 1
        t = np.linspace(seg.breaks[0], seg.breaks[-1], 6001)
        pts = _scipy_curve(knots, controls, 5)(t, 0)
        assert np.max(np.hypot(*(pts - trefoil(t)).T)) <= FIT + 1e-9  # same parameter: phi


@pytest.mark.parametrize("tol", [1e-6, 1e-8])
def test_compact_form_of_a_quintic_is_cubic_within_tol(contour, tol):
    """compact_spline turns every quintic segment into C2 cubic pieces within tol of it: within
    tol + FIT of the exact curve both ways (scipy's cubic B-spline of the result against the
    analytic curve), same end points and first and second derivatives as the exact curve there."""
    from camgen.export.dxf import compact_spline, spline_bspline

    for seg in contour.segments:
        cubic = compact_spline(seg, tol)
        assert cubic.degree == 3
        knots, controls = spline_bspline(cubic)
        assert knots.size - len(controls) - 1 == 3
        curve = _scipy_curve(knots, controls, 3)
        lo, hi = float(seg.breaks[0]), float(seg.breaks[-1])
        pts = curve(np.linspace(lo, hi, 5001), 0)
        assert np.max(exact_distance(pts)) <= tol * (1 + 1e-6) + FIT
        from test_dxf import curve_distance

        back = curve_distance(trefoil(np.linspace(lo, hi, 5001)), curve, lo, hi)
        assert np.max(back) <= tol * (1 + 1e-6) + FIT
        for order in (0, 1, 2):  # hermite5 interpolates these exactly at the ends
            ends = curve(np.array([lo, hi]), order)
            want = trefoil(np.array([lo, hi]), order)
            assert np.allclose(ends, want, rtol=0, atol=1e-9 * (1 + np.max(np.abs(want))))


def test_a_quintic_that_no_cubic_reaches_is_a_geometry_error(contour):
    """A quintic run is never kept: below what cubics can reach (the fit's piece limit) the
    compact form is a GeometryError, not the quintic written with cubic formulas."""
    import camgen.numerics.splinefit as splinefit
    from camgen.export.dxf import compact_spline

    seg = contour.segments[0]
    limit = splinefit.MAX_PIECES
    try:
        splinefit.MAX_PIECES = PIECES  # as many cubic pieces as quintic ones: not enough for 1e-9 mm
        with pytest.raises(GeometryError, match="cubic form of a degree-5 spline"):
            compact_spline(seg, 1e-9)
    finally:
        splinefit.MAX_PIECES = limit


def test_dxf_writes_only_cubic_splines():
    """The DXF writer refuses a quintic segment that reaches it (it writes degree-3 SPLINEs)."""
    from camgen.export.dxf import _add_contour
    from camgen.export.dxfwriter import DxfDocument

    with pytest.raises(ExportError, match="degree-5"):
        _add_contour(DxfDocument(), quintic_contour(1), "PROFILE")
    with pytest.raises(ParameterError):
        from camgen.export.dxf import _degree_of

        _degree_of(type("Fake", (), {"degree": 4})())


# --------------------------------------------------------------------------------------------
# DXF read back by ezdxf
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("tol", [1e-6, 1e-8])
def test_bspline_dxf_of_a_quintic_contour_reads_back_cubic_within_tol(contour, tol):
    """ezdxf: every PROFILE entity is a clamped SPLINE of degree 3, one per segment; the curves it
    defines (control points and knots from the file, evaluated by scipy) lie within
    bspline_tol + FIT of the exact curve and cover it; the header extents are the exact curve's
    bounding box (within the same tolerance)."""
    from camgen.export.dxf import DxfOptions, contour_to_dxf
    from test_dxf import curve_distance, read_dxf

    doc = read_dxf(contour_to_dxf(contour, options=DxfOptions(splines="bspline", bspline_tol=tol)))
    assert float(doc.header.custom_vars.get("camgen_bspline_tol_mm")) == tol
    entities = [e for e in doc.modelspace() if e.dxf.layer == "PROFILE"]
    assert [e.dxftype() for e in entities] == ["SPLINE"] * contour.n_segments
    slack = tol * (1 + 1e-6) + FIT
    cover = []
    for entity in entities:
        assert entity.dxf.degree == 3
        knots = np.array(entity.knots)
        controls = np.array(entity.control_points)[:, :2]
        assert np.all(knots[:4] == knots[0]) and np.all(knots[-4:] == knots[-1])
        curve = _scipy_curve(knots, controls, 3)
        pts = curve(np.linspace(knots[0], knots[-1], 4001), 0)
        assert np.max(exact_distance(pts)) <= slack
        tool = entity.construction_tool()  # ezdxf's own evaluation, on its knots normalised to [0, max_t]
        ez = np.array(list(tool.points(np.linspace(0.0, tool.max_t, 101))))[:, :2]
        assert np.max(np.abs(ez - curve(np.linspace(knots[0], knots[-1], 101), 0))) <= 1e-8
        cover.append(curve_distance(exact_samples(4000), curve, knots[0], knots[-1], seeds=4001))
    assert np.max(np.min(cover, axis=0)) <= slack
    dense = exact_samples(2_000_000)  # sampled bounding box: within 45 (pi / 1e6)^2 / 2 = 2e-10 mm
    box = np.concatenate([dense.min(axis=0), dense.max(axis=0)])
    extents = np.array([*doc.header["$EXTMIN"][:2], *doc.header["$EXTMAX"][:2]])
    assert np.max(np.abs(extents - box)) <= slack + 1e-9


@pytest.mark.parametrize("tol", [1e-3, 1e-4])
def test_biarc_dxf_of_a_quintic_contour_is_within_chord_tol(contour, tol, tmp_path):
    """The default DXF (biarcs) read back by ezdxf: ARCs and LINEs only, within chord_tol + FIT of
    the exact curve both ways."""
    from camgen.export.dxf import DxfOptions, contour_to_dxf
    from test_dxf import dxf_layer, read_dxf

    doc = read_dxf(contour_to_dxf(contour, options=DxfOptions(chord_tol=tol)))
    chain, points, kinds = dxf_layer(doc, "PROFILE")
    assert set(kinds) <= {"ARC", "LINE"} and "ARC" in kinds
    assert np.max(exact_distance(points)) <= tol + FIT
    assert np.max(chain.distance(exact_samples())) <= tol + FIT


# --------------------------------------------------------------------------------------------
# STEP read back by OpenCASCADE
# --------------------------------------------------------------------------------------------
def _exact_volume() -> float:
    return (AREA - math.pi * BORE**2 / 4) * THICKNESS


@pytest.mark.parametrize("exact", [True, False])
def test_step_of_a_quintic_contour(contour, exact, tmp_path):
    """OCCT reads the STEP back: with exact=True the profile edges are degree-5 B-splines (interior
    knots of multiplicity 3: the C2 joins) on the exact curve within FIT (same parameter, phi);
    by default cubic edges within bspline_tol (1e-8) + FIT.  Both ways (the edges cover the curve)
    and the volume is the exact area less the bore, times the thickness (OCCT's integration)."""
    from camgen.body import BodySpec
    from camgen.export.step import step_bytes, step_volume
    from test_dxf import curve_distance
    from test_step import _step_shape, step_bspline_edges

    data = step_bytes(contour, BodySpec(thickness=THICKNESS, bore_diameter=BORE), "trefoil", exact=exact)
    edges = step_bspline_edges(_step_shape(data, tmp_path))
    assert edges
    slack = FIT + (1e-9 if exact else 1e-8 * (1 + 1e-6))
    cover = []
    for degree, knots, poles in edges:
        assert degree == (5 if exact else 3)
        if exact:
            mult = np.unique(knots, return_counts=True)[1]
            assert mult[0] == mult[-1] == 6 and set(mult[1:-1]) <= {3}
        curve = _scipy_curve(knots, poles, degree)
        t = np.linspace(knots[0], knots[-1], 2001)
        pts = curve(t, 0)
        if exact:  # the quintic's own parameter: compare at equal phi
            assert np.max(np.hypot(*(pts - trefoil(t)).T)) <= slack
        assert np.max(exact_distance(pts)) <= slack
        cover.append(curve_distance(exact_samples(4000), curve, knots[0], knots[-1], seeds=2001))
    assert np.max(np.min(cover, axis=0)) <= slack
    assert step_volume(data) == pytest.approx(_exact_volume(), rel=1e-6)


# --------------------------------------------------------------------------------------------
# G-code run by LinuxCNC's rs274
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize(("comp", "mode", "direction"), [(False, "biarcs", "climb"), (True, "biarcs", "conventional"),
                                                         (True, "lines", "climb")])
def test_gcode_of_a_quintic_contour_cuts_the_exact_curve(contour, comp, mode, direction, tmp_path):
    """rs274 runs the program; its tool-centre moves (with cutter compensation: rs274's own
    compensated path) stay outside the exact curve and at least r - tol from it (no gouge), and
    every point of the exact curve is within r + tol of them (nothing left standing), with
    tol = chord_tol + FIT + 1e-4 (rs274's 4 printed decimals and the sampling of its moves).
    Under compensation the profile itself is rotated to the start point: a quintic piece cut
    in two by the Taylor shift."""
    from scipy.spatial import cKDTree

    from camgen.export.gcode import MachiningSpec, gcode_program
    from cutting import _passes, sample_moves
    from helpers import require_tool, rs274_canon

    require_tool("rs274")
    spec = MachiningSpec(tool_diameter=8.0, thickness=2.0, step_down=2.0, cutter_compensation=comp, spline_mode=mode,
                         direction=direction)
    status, message, canon = rs274_canon(gcode_program(contour, spec), tmp_path)
    assert status == 0, message
    chains = _passes(canon)
    assert len(chains) == 2  # 2 mm, then the breakthrough (the same XY moves)
    pts = sample_moves(chains[-1], 0.02)[0]
    tol = spec.chord_tol + FIT + 1e-4
    assert not inside_exact(pts).any()
    assert np.min(exact_distance(pts)) >= spec.tool_radius - tol
    reach, _ = cKDTree(pts).query(exact_samples())
    assert np.max(reach) <= spec.tool_radius + tol


def test_split_of_a_quintic_piece_stays_on_the_curve(contour):
    """gcode._split cuts a quintic inside a piece: head and tail are quintics that meet at the cut
    and follow the exact curve at their own parameters (phi) within FIT."""
    from camgen.export.gcode import _split

    seg = contour.segments[1]
    for u in (0.013, 0.5 + 0.3 / PIECES, 0.97):
        head, tail = _split(seg, u)
        cut = seg.breaks[0] + u * seg.span
        assert head.degree == tail.degree == 5
        assert head.breaks[-1] == tail.breaks[0] == pytest.approx(cut)
        assert not np.any(np.isclose(seg.breaks, cut, atol=1e-9))  # inside a piece: the shifted one
        for part in (head, tail):
            t = np.linspace(part.breaks[0], part.breaks[-1], 3001)
            for order in (0, 1):
                err = np.max(np.hypot(*(part.eval_t(t, order) - trefoil(t, order)).T))
                assert err <= (FIT if order == 0 else 1e-5), (u, order, err)


# --------------------------------------------------------------------------------------------
# Point list and meshes
# --------------------------------------------------------------------------------------------
def test_points_csv_of_a_quintic_contour(contour):
    """pandas reads the CSV with its defaults: every row on the exact curve (within FIT + the 9 printed decimals) and
    every point of the exact curve within chord_tol + FIT of the closed polygon of the rows."""
    import pandas

    from camgen.export.points import points_csv
    from test_dxf import Chain

    chord_tol = 1e-3
    frame = pandas.read_csv(io.StringIO(points_csv(contour, chord_tol)))
    assert list(frame.columns) == ["x_mm", "y_mm"]
    pts = frame.to_numpy()
    assert len(pts) > 100
    assert np.max(exact_distance(pts)) <= FIT + 1e-9
    polygon = Chain(segments=np.concatenate([pts, np.roll(pts, -1, axis=0)], axis=1), spacing=0.01)
    assert np.max(polygon.distance(exact_samples())) <= chord_tol + FIT + 1e-9


def test_stl_of_a_quintic_contour(contour, tmp_path):
    """trimesh and admesh read the binary STL: closed, and its volume is the exact area less the
    bore times the thickness within the chords' tolerance (each chord cuts off at most chord_tol
    times its length, on the profile and on the bore polygon) and float32 rounding."""
    import trimesh

    from camgen.body import BodySpec
    from camgen.export.solid import cam_solid, mesh_bytes
    from helpers import require_tool
    from test_solid import admesh_clean

    chord_tol = 1e-3
    solid = cam_solid(contour, BodySpec(thickness=THICKNESS, bore_diameter=BORE), chord_tol)
    path = tmp_path / "trefoil.stl"
    path.write_bytes(mesh_bytes(solid, "stl"))
    mesh = trimesh.load(path, force="mesh")
    assert mesh.is_watertight and mesh.is_winding_consistent
    from scipy.integrate import quad

    length = quad(lambda p: math.hypot(40 + 5 * math.cos(3 * p), 15 * math.sin(3 * p)), 0.0, 2 * math.pi, limit=200)[0]
    budget = ((length + math.pi * BORE) * chord_tol + length * FIT) * THICKNESS
    assert abs(mesh.volume - _exact_volume()) <= budget + 1e-6 * _exact_volume()
    out = admesh_clean(require_tool("admesh"), path)
    import re

    admesh_volume = float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1))
    assert abs(admesh_volume - _exact_volume()) <= budget + max(1e-6, len(solid.triangles) * 2.0**-24) * _exact_volume()
