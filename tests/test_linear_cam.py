"""Linear (translating-plate) cams (form ``linear``): the follower rides the files camgen writes.

Every expected number comes from outside camgen's linear-cam code:

* the laws in closed form (Norton, *Design of Machinery*, eq. 8.6: cycloidal
  ``s = h (u - sin(2 pi u) / (2 pi))``, ``u = x / L`` over a segment of length ``L``);
* the ride: the roller dropped onto the exported profile (the DXF's B-splines read by ezdxf and
  scipy; the point list as a polygon), its centre's height found by brute force over the
  curve's points and edges; an oscillating arm turned down onto the polygon by bisection;
* the pressure angle: ``tan(alpha) = ds/dx`` (Rothbart, *Cam Design Handbook*, the translating
  cam), peak ``atan(2 h / L)`` for a cycloidal rise; for an oscillating arm, the angle between
  the simulated roller path's normal and the arm's direction of motion, by finite differences;
* the undercut threshold: the least convex radius ``(1 + s'^2)^(3/2) / |s''|`` of the graph,
  found by scipy's bounded scalar minimiser on the closed-form law;
* the G-code: LinuxCNC's rs274 and the cutting simulation of tests/cutting.py.
"""
from __future__ import annotations

import io
import json
import math

import numpy as np
import pytest

from helpers import require_tool

H, L_RISE = 20.0, 100.0  # the rise: 20 mm over 100 mm of travel
TRAVEL = 300.0
R = 10.0


def _segments(swing: bool = False):
    lift = "swing_deg" if swing else "lift_mm"
    h = 12.0 if swing else H
    return [{"law": "dwell", "span_mm": 50.0}, {"law": "cycloidal", "span_mm": 100.0, lift: h},
            {"law": "dwell", "span_mm": 50.0}, {"law": "cycloidal", "span_mm": 100.0, lift: -h}]


def cycloidal_lift(x: np.ndarray, h: float = H) -> np.ndarray:
    """The program above in closed form (Norton, eq. 8.6), periodic over the travel (mm)."""
    x = np.mod(x, TRAVEL)
    u = np.clip((x - 50.0) / L_RISE, 0.0, 1.0)
    w = np.clip((x - 200.0) / L_RISE, 0.0, 1.0)
    rise = h * (u - np.sin(2 * math.pi * u) / (2 * math.pi))
    fall = h * (w - np.sin(2 * math.pi * w) / (2 * math.pi))
    return rise - fall


def _cam(**extra):
    cam = {"kind": "motion_law", "form": "linear", "travel_mm": TRAVEL, "segments": _segments(), "follower": "roller",
           "roller_radius_mm": R, "margin_start_mm": 30.0, "margin_end_mm": 30.0, "below_pitch_mm": 45.0, "thickness_mm": 12.0}
    cam.update(extra)
    return cam


def _run(scene_table):
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene(scene_table, "lin")
    return execute(scene, plan_run(scene)).files


def _table(text):
    return np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, ndmin=2)


def _checks(files, cam="c"):
    report = json.loads(files["report.json"])
    return {c["name"]: c for c in report["cams"][cam]["checks"]}, report


# --------------------------------------------------------------------------------------------
# Independent readers and rides
# --------------------------------------------------------------------------------------------
def dxf_splines(text: str) -> list:
    """The PROFILE layer's SPLINEs as scipy B-splines (x, y) with their parameter ranges (ezdxf reads)."""
    import ezdxf
    from scipy.interpolate import BSpline

    doc = ezdxf.read(io.StringIO(text))
    assert not doc.audit().has_errors
    out = []
    for e in doc.modelspace():
        if e.dxf.layer == "PROFILE" and e.dxftype() == "SPLINE":
            knots, ctrl = np.array(e.knots, dtype=float), np.array(e.control_points, dtype=float)[:, :2]
            k = e.dxf.degree
            out.append((BSpline(knots, ctrl, k), float(knots[k]), float(knots[-k - 1])))
    return out


def roller_height_on_splines(splines: list, x: np.ndarray, r: float, samples: int = 20000) -> np.ndarray:
    """Height of the centre of a roller (radius r) dropped at abscissa x onto the B-splines:
    the best of dense samples, then a golden-section search of y(u) + sqrt(r^2 - (x(u) - x)^2)
    about it on that spline (the touching point is where that height is largest)."""
    best = np.full(x.shape, -np.inf)
    where = [None] * x.size
    for spline, lo, hi in splines:
        u = np.linspace(lo, hi, samples)
        p = spline(u)
        dx = p[None, :, 0] - x[:, None]
        g = np.where(np.abs(dx) <= r, p[None, :, 1] + np.sqrt(np.maximum(r * r - dx * dx, 0.0)), -np.inf)
        j = np.argmax(g, axis=1)
        better = g[np.arange(x.size), j] > best
        for i in np.flatnonzero(better):
            best[i] = g[i, j[i]]
            where[i] = (spline, u[max(j[i] - 1, 0)], u[min(j[i] + 1, samples - 1)])
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    for i, (spline, a, b) in enumerate(where):
        def height(v: float) -> float:
            q = spline(v)
            d = q[0] - x[i]
            return q[1] + math.sqrt(max(r * r - d * d, 0.0))

        c, d = b - ratio * (b - a), a + ratio * (b - a)
        fc, fd = height(c), height(d)
        for _ in range(60):
            if fc > fd:
                b, d, fd = d, c, fc
                c = b - ratio * (b - a)
                fc = height(c)
            else:
                a, c, fc = c, d, fd
                d = a + ratio * (b - a)
                fd = height(d)
        best[i] = max(best[i], fc, fd)
    return best


def roller_height_on_points(points: np.ndarray, x: np.ndarray, r: float) -> np.ndarray:
    """Height of the centre of a roller (radius r) dropped at abscissa x onto points (brute force)."""
    order = np.argsort(points[:, 0])
    px, py = points[order, 0], points[order, 1]
    out = np.full(x.shape, -np.inf)
    for i, xi in enumerate(x):
        lo, hi = np.searchsorted(px, [xi - r, xi + r])
        dx = px[lo:hi] - xi
        out[i] = np.max(py[lo:hi] + np.sqrt(np.maximum(r * r - dx * dx, 0.0)))
    return out


def roller_height_on_polygon(poly: np.ndarray, x: np.ndarray, r: float, closed: bool = True) -> np.ndarray:
    """Height of a roller's centre dropped at x onto a polygon (vertices and edges, exact; an open
    chain without ``closed``)."""
    a, b = (poly, np.roll(poly, -1, axis=0)) if closed else (poly[:-1], poly[1:])
    d = b - a
    length = np.hypot(d[:, 0], d[:, 1])
    keep = length > 0
    a, d, length = a[keep], d[keep], length[keep]
    n = np.stack([-d[:, 1], d[:, 0]], axis=1) / length[:, None]
    n = np.where(n[:, 1:2] < 0, -n, n)
    best = roller_height_on_points(poly, x, r)
    for i, xi in enumerate(x):
        near = (np.minimum(a[:, 0], a[:, 0] + d[:, 0]) <= xi + r) & (np.maximum(a[:, 0], a[:, 0] + d[:, 0]) >= xi - r) & (n[:, 1] > 1e-9)
        an, dn, nn, ln = a[near], d[near], n[near], length[near]
        y = (r - (xi - an[:, 0]) * nn[:, 0]) / nn[:, 1] + an[:, 1]
        foot = np.stack([xi - r * nn[:, 0], y - r * nn[:, 1]], axis=1)
        t = np.einsum("ij,ij->i", foot - an, dn) / ln**2
        ok = (t >= 0) & (t <= 1)
        if ok.any():
            best[i] = max(best[i], float(np.max(y[ok])))
    return best


def _outline_polygon(text: str) -> np.ndarray:
    return _table(text)


# --------------------------------------------------------------------------------------------
# The ride
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def edge_files():
    scene = {"output": {"formats": ["dxf", "points"], "dxf_splines": "bspline", "chord_tol_mm": 4e-7, "dxf_construction": True},
             "cams": {"c": _cam()}}
    return _run(scene)


def test_translating_roller_rides_the_dxf_and_the_point_list_within_1e_6_mm(edge_files):
    """The roller dropped onto the DXF's B-splines and onto the point list at every mm of travel
    sits at the closed-form lift (x, s(x)) within 1e-6 mm: x = 0 is where it starts, on the pitch
    line y = 0."""
    x = np.linspace(0.0, TRAVEL, 601)
    expected = cycloidal_lift(x)
    spline = roller_height_on_splines(dxf_splines(edge_files["c.dxf"]), x, R)
    assert np.max(np.abs(spline - expected)) < 1e-6, float(np.max(np.abs(spline - expected)))
    polygon = roller_height_on_polygon(_table(edge_files["c_points.csv"]), x, R)
    assert np.max(np.abs(polygon - expected)) < 1e-6, float(np.max(np.abs(polygon - expected)))
    checks, _ = _checks(edge_files)
    assert all(c["status"] != "fail" for c in checks.values())
    # the pressure angle: tan(alpha) = ds/dx, largest on the cycloidal rise 2 h / L (Rothbart; Norton eq. 8.6)
    assert checks["pressure_angle"]["value"] == pytest.approx(math.degrees(math.atan(2 * H / L_RISE)), abs=1e-6)


def test_the_plate_spans_its_margins_below_pitch_and_marks_x_zero(edge_files):
    """The outline reaches from -margin_start to travel + margin_end and down to -below_pitch (the
    point list's extremes); the DXF's CENTER cross marks the plate frame's origin (x = 0 on the
    pitch line), and no ZERO layer claims a cam angle 0 or a rotation."""
    import ezdxf

    pts = _table(edge_files["c_points.csv"])
    assert pts[:, 0].min() == pytest.approx(-30.0, abs=1e-9) and pts[:, 0].max() == pytest.approx(TRAVEL + 30.0, abs=1e-9)
    assert pts[:, 1].min() == pytest.approx(-45.0, abs=1e-9)
    doc = ezdxf.read(io.StringIO(edge_files["c.dxf"]))
    centre = [e for e in doc.modelspace() if e.dxf.layer == "CENTER" and e.dxftype() == "LINE"]
    assert len(centre) == 2
    mids = [(np.array(e.dxf.start)[:2] + np.array(e.dxf.end)[:2]) / 2 for e in centre]
    assert all(np.hypot(*m) < 1e-12 for m in mids)
    assert not [e for e in doc.modelspace() if e.dxf.layer == "ZERO"]


def _arm_ride(poly: np.ndarray, x: np.ndarray, pivot: tuple[float, float], r: float, tau: float, edge: bool = False) -> np.ndarray:
    """Swing (rad) at which the arm (pivot fixed, arm to the origin at zero swing) turned down
    from high above rests its roller on the polygon, by bisection on the clearance (the distance
    from the roller's centre to the polygon less r, negative with the centre inside the plate).
    ``edge``: ``poly`` is the plate's top edge only, an open chain in increasing x (the centre is
    inside where it is below the chain)."""
    px, py = pivot
    arm = math.hypot(px, py)
    rest = math.atan2(-py, -px)
    a, b = (poly[:-1], poly[1:]) if edge else (poly, np.roll(poly, -1, axis=0))

    def clearance(phi: np.ndarray) -> np.ndarray:
        g = rest + tau * phi
        c = np.stack([x + px + arm * np.cos(g), py + arm * np.sin(g)], axis=1)
        out = np.empty(x.size)
        for i in range(x.size):
            near = (np.abs(a[:, 0] - c[i, 0]) < r + 5.0)
            aa, bb = a[near], b[near]
            d = bb - aa
            t = np.clip(np.einsum("ij,ij->i", c[i] - aa, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
            foot = aa + t[:, None] * d
            out[i] = np.min(np.hypot(*(c[i] - foot).T)) - r
        if edge:
            return np.where(c[:, 1] < np.interp(c[:, 0], poly[:, 0], poly[:, 1]), -np.abs(out) - r, out)
        # inside the plate (crossing number of a ray to +x): the roller is below the edge
        ya, yb = a[:, 1][None, :], b[:, 1][None, :]
        cy, cx = c[:, 1:2], c[:, 0:1]
        crosses = (ya > cy) != (yb > cy)
        at = a[:, 0][None, :] + (cy - ya) * (b[:, 0] - a[:, 0])[None, :] / np.where(yb == ya, 1.0, yb - ya)
        inside = np.sum(crosses & (at > cx), axis=1) % 2 == 1
        return np.where(inside, -np.abs(out) - r, out)

    lo, hi = np.full(x.size, -0.2), np.full(x.size, 0.6)
    for _ in range(45):
        mid = 0.5 * (lo + hi)
        touching = clearance(mid) < 0
        lo, hi = np.where(touching, mid, lo), np.where(touching, hi, mid)
    return 0.5 * (lo + hi)


def test_oscillating_roller_rides_the_point_list_and_the_dxf_within_1e_6_rad():
    """An arm pivoted at (90, 40) mm (cw lifts it) swings 12 deg by the cycloidal program; turned
    down onto the exported point list and onto the DXF's B-splines at 61 travels, it rests at the
    closed-form swing within 1e-6 rad.  Its pressure angle (the simulated roller path's normal against the arm's motion,
    finite differences) is the report's."""
    cam = _cam(follower_motion="oscillating", pivot_x_mm=90.0, pivot_y_mm=40.0, swing_turn="cw", segments=_segments(swing=True),
               roller_radius_mm=8.0)
    files = _run({"output": {"formats": ["points", "dxf"], "chord_tol_mm": 2e-7, "dxf_splines": "bspline"}, "cams": {"c": cam}})
    x = np.linspace(0.0, TRAVEL, 61)
    swing = _arm_ride(_table(files["c_points.csv"]), x, (90.0, 40.0), 8.0, -1.0)
    expected = np.radians(cycloidal_lift(x, 12.0))
    assert np.max(np.abs(swing - expected)) < 1e-6, float(np.max(np.abs(swing - expected)))
    # the DXF's B-splines (the top edge), sampled densely: chords of 0.005 mm sag < 1e-7 mm here
    edge = np.concatenate([curve(np.linspace(lo, hi, 40001)) for curve, lo, hi in dxf_splines(files["c.dxf"])])
    edge = edge[np.argsort(edge[:, 0])]
    swing = _arm_ride(edge, x, (90.0, 40.0), 8.0, -1.0, edge=True)
    assert np.max(np.abs(swing - expected)) < 1e-6, float(np.max(np.abs(swing - expected)))
    # pressure angle, independently: the roller centre path C(x) and the arm's direction of motion
    xs = np.linspace(0.0, TRAVEL, 300001)
    rest, arm = math.atan2(-40.0, -90.0), math.hypot(90.0, 40.0)
    g = rest - np.radians(cycloidal_lift(xs, 12.0))
    c = np.stack([xs + 90.0 + arm * np.cos(g), 40.0 + arm * np.sin(g)], axis=1)
    tangent = np.gradient(c, xs, axis=0)
    motion = -np.stack([-np.sin(g), np.cos(g)], axis=1)  # cw: the arm turns clockwise as it lifts
    cos_a = np.abs(tangent[:, 0] * motion[:, 1] - tangent[:, 1] * motion[:, 0]) / np.hypot(*tangent.T)
    alpha = np.degrees(np.max(np.arccos(np.clip(cos_a, -1, 1))))
    checks, _ = _checks(files)
    assert checks["pressure_angle"]["value"] == pytest.approx(alpha, abs=1e-4)


# --------------------------------------------------------------------------------------------
# Undercut threshold
# --------------------------------------------------------------------------------------------
def _least_convex_radius(h: float, length: float) -> float:
    """min over the cycloidal rise of (1 + s'^2)^(3/2) / |s''| where s'' < 0 (scipy, bounded)."""
    from scipy.optimize import minimize_scalar

    def rho(u: float) -> float:
        d1 = h / length * (1 - math.cos(2 * math.pi * u))
        d2 = 2 * math.pi * h / length**2 * math.sin(2 * math.pi * u)
        return (1 + d1 * d1) ** 1.5 / -d2 if d2 < 0 else math.inf

    best = min((minimize_scalar(rho, bounds=(a, b), method="bounded", options={"xatol": 1e-14}) for a, b in
                ((0.5 + 1e-9, 0.75), (0.75, 1 - 1e-9))), key=lambda r: r.fun)
    return float(best.fun)


def test_undercut_threshold_matches_an_independent_root_search():
    """A steep rise (20 mm over 30 mm: cycloidal) has a least convex pitch radius rho*: a roller
    1e-6 relative below it passes the undercut check and is made; 1e-6 above it fails it, named,
    and no manufacturing file is written (exit status 1)."""
    steep = [{"law": "dwell", "span_mm": 120.0}, {"law": "cycloidal", "span_mm": 30.0, "lift_mm": 20.0},
             {"law": "dwell", "span_mm": 120.0}, {"law": "cycloidal", "span_mm": 30.0, "lift_mm": -20.0}]
    rho = _least_convex_radius(20.0, 30.0)
    assert 3.0 < rho < 30.0
    below = _run({"output": {"formats": ["dxf"]}, "cams": {"c": _cam(segments=steep, roller_radius_mm=rho * (1 - 1e-6),
                                                                     pressure_angle_limit_deg=89.0)}})
    checks, report = _checks(below)
    assert checks["undercut"]["status"] == "pass" and "c.dxf" in below
    assert checks["undercut"]["value"] == pytest.approx(rho, rel=1e-9)
    above = _run({"output": {"formats": ["dxf"]}, "cams": {"c": _cam(segments=steep, roller_radius_mm=rho * (1 + 1e-6),
                                                                     pressure_angle_limit_deg=89.0)}})
    checks, report = _checks(above)
    assert checks["undercut"]["status"] == "fail" and "c.dxf" not in above and report["status"] == "fail"


def _quintic(length: float, start: tuple, end: tuple) -> np.polynomial.Polynomial:
    """The quintic with s, s', s'' given at x = 0 and x = length (numpy's linear solve)."""
    rows = []
    for x0 in (0.0, length):
        rows.append([x0**k for k in range(6)])
        rows.append([k * x0 ** (k - 1) if k >= 1 else 0.0 for k in range(6)])
        rows.append([k * (k - 1) * x0 ** (k - 2) if k >= 2 else 0.0 for k in range(6)])
    return np.polynomial.Polynomial(np.linalg.solve(np.array(rows), np.array([*start, *end], dtype=float)))


def _least_radius_of(poly, length: float, valley: bool) -> float:
    """min of (1 + s'^2)^(3/2) / |s''| over the valleys (s'' > 0) or peaks (s'' < 0) of ``poly``
    on [0, length]: the best of a dense grid refined by scipy's bounded minimiser."""
    from scipy.optimize import minimize_scalar

    d1, d2 = poly.deriv(1), poly.deriv(2)

    def rho(x: float) -> float:
        a = float(d2(x))
        return (1 + float(d1(x)) ** 2) ** 1.5 / abs(a) if (a > 0) == valley and a != 0 else math.inf

    x = np.linspace(0.0, length, 30001)
    i = int(np.argmin([rho(v) for v in x]))
    lo, hi = x[max(i - 1, 0)], x[min(i + 1, x.size - 1)]
    return float(minimize_scalar(rho, bounds=(lo, hi), method="bounded", options={"xatol": 1e-14}).fun)


def test_slot_walls_undercut_on_either_side():
    """A slot needs the pitch radius above its half width on both sides.  A quintic rise of 20 mm
    over 30 mm starting with an acceleration of 0.1 mm/mm^2 has tighter valleys (concave seen from
    above, the slot's upper wall) than peaks: a roller 1e-6 above the valley's least radius passes
    the edge cam's undercut check (peaks only) but fails the slot's; 1e-6 below it passes both."""
    program = [{"law": "dwell", "span_mm": 90.0},  # the conditions per mm of travel: a = 0.1 mm/mm^2
               {"law": "polynomial", "span_mm": 30.0, "start": [0.0, 0.0, 0.1], "end": [20.0, 0.0, 0.0]},
               {"law": "dwell", "span_mm": 60.0}, {"law": "cycloidal", "span_mm": 120.0, "lift_mm": -20.0}]
    rise = _quintic(30.0, (0.0, 0.0, 0.1), (20.0, 0.0, 0.0))
    valley, peak = _least_radius_of(rise, 30.0, True), _least_radius_of(rise, 30.0, False)
    assert valley < peak * 0.9
    slot = {"linear_form": "slot", "above_pitch_mm": 45.0, "slot_depth_mm": 6.0, "slot_clearance_mm": 0.0}
    for form in ({}, slot):
        for scale, status in ((1 - 1e-6, "pass"), (1 + 1e-6, "pass" if not form else "fail")):
            files = _run({"output": {"formats": ["dxf"]}, "cams": {"c": _cam(segments=program, roller_radius_mm=valley * scale, **form)}})
            undercut = _checks(files)[0]["undercut"]
            assert undercut["status"] == status, (form, scale, undercut)
            if form:
                assert undercut["value"] == pytest.approx(valley, rel=1e-9)


# --------------------------------------------------------------------------------------------
# The slot's pocket
# --------------------------------------------------------------------------------------------
SLOT_CLEARANCE, SLOT_DEPTH, SLOT_ABOVE, THICKNESS = 0.2, 6.0, 45.0, 12.0
HALF = R + SLOT_CLEARANCE / 2  # the slot's half width


def _slot_cam(**extra):
    return _cam(linear_form="slot", above_pitch_mm=SLOT_ABOVE, slot_depth_mm=SLOT_DEPTH, slot_clearance_mm=SLOT_CLEARANCE, **extra)


def cycloidal_slope(x: np.ndarray, h: float = H) -> np.ndarray:
    """ds/dx of the program (the derivative of Norton eq. 8.6: h / L (1 - cos(2 pi u)))."""
    x = np.mod(x, TRAVEL)
    u, w = (x - 50.0) / L_RISE, (x - 200.0) / L_RISE
    rise = np.where((u > 0) & (u < 1), h / L_RISE * (1 - np.cos(2 * math.pi * u)), 0.0)
    fall = np.where((w > 0) & (w < 1), h / L_RISE * (1 - np.cos(2 * math.pi * w)), 0.0)
    return rise - fall


def exact_slot(spacing: float = 0.002) -> np.ndarray:
    """The slot's boundary from the closed forms (counter-clockwise, points <= ``spacing`` mm
    apart): the pitch graph (x, s(x)) offset by -HALF along its normal (-s', 1)/sqrt(1 + s'^2)
    over 0..TRAVEL, the half circle of radius HALF about (TRAVEL, s(TRAVEL)) (a dwell: from
    straight down to straight up), the offset by +HALF back, the half circle about (0, s(0))."""
    x = np.linspace(0.0, TRAVEL, int(TRAVEL / spacing * 1.1) + 1)
    y, d = cycloidal_lift(x), cycloidal_slope(x)
    n = np.stack([-d, np.ones_like(d)], axis=1) / np.hypot(d, 1.0)[:, None]
    pitch = np.stack([x, y], axis=1)
    t = np.linspace(0.0, math.pi, int(math.pi * HALF / spacing) + 1)[1:-1]
    end = np.stack([TRAVEL + HALF * np.sin(t), cycloidal_lift(np.array([TRAVEL]))[0] - HALF * np.cos(t)], axis=1)
    start = np.stack([-HALF * np.sin(t), cycloidal_lift(np.array([0.0]))[0] + HALF * np.cos(t)], axis=1)
    return np.vstack([pitch - HALF * n, end, (pitch + HALF * n)[::-1], start])


def slot_area() -> float:
    """The slot's area: the band of half width HALF about the pitch graph has area 2 HALF x the
    graph's length (the parallel-curve area, Steiner: the curvature terms of the two sides
    cancel while |rho| > HALF), plus the two half discs; the length by scipy's quad."""
    from scipy.integrate import quad

    length = sum(quad(lambda v: math.sqrt(1 + float(cycloidal_slope(np.array([v]))[0]) ** 2), a, b, epsabs=1e-12, epsrel=1e-13)[0]
                 for a, b in ((0, 50), (50, 150), (150, 200), (200, 300)))
    return 2 * HALF * length + math.pi * HALF**2


@pytest.fixture(scope="module")
def slot_files():
    scene = {"output": {"formats": ["dxf", "points", "stl", "step", "ngc"], "dxf_splines": "bspline", "chord_tol_mm": 1e-3},
             "machining": {"tool_diameter_mm": 2 * HALF}, "cams": {"c": _slot_cam()}}
    return _run(scene)


def _slot_built(**extra):
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"c": _slot_cam(**extra)}}, "lin")
    (cam,) = compute(scene, plan_run(scene)).cams
    return cam


def test_slot_pocket_is_the_roller_path_widened_by_the_clearance_closed_inside_the_plate():
    """The slot's wall (one closed contour, the pocket) keeps r + c/2 from the closed-form pitch
    graph over the travel 0..300 mm (so its ends are half circles about the graph's end points),
    lies inside the plate (x from -HALF to TRAVEL + HALF), and is cut slot_depth_mm deep into a
    rectangular plate; the pocket's open centre runs along the graph from (0, s(0)) to its end."""
    from scipy.spatial import cKDTree

    cam = _slot_built()
    (pocket,) = cam.pockets
    assert pocket.depth == SLOT_DEPTH and pocket.width == pytest.approx(2 * HALF) and pocket.clearance == SLOT_CLEARANCE
    wall = pocket.walls[0].contour.flatten(1e-6)
    assert wall[:, 0].min() == pytest.approx(-HALF, abs=1e-6) and wall[:, 0].max() == pytest.approx(TRAVEL + HALF, abs=1e-6)
    xs = np.linspace(0.0, TRAVEL, 300001)
    pitch = np.stack([xs, cycloidal_lift(xs)], axis=1)
    distance = cKDTree(pitch).query(wall)[0]
    # the pitch polyline's spacing (0.001 mm) bounds the nearest-vertex distance's excess by 5e-8 mm
    assert np.max(np.abs(distance - HALF)) < 2e-6, float(np.max(np.abs(distance - HALF)))
    centre = np.vstack([seg.point(np.linspace(0, 1, 2001)) for seg in pocket.centre_path])
    assert np.max(np.abs(centre[:, 1] - cycloidal_lift(centre[:, 0]))) < 1e-6
    assert centre[0] == pytest.approx([0.0, 0.0], abs=1e-12) and centre[-1] == pytest.approx([TRAVEL, 0.0], abs=1e-9)
    outline = cam.contour.flatten(1e-6)
    assert outline[:, 0].min() == pytest.approx(-30.0) and outline[:, 1].max() == pytest.approx(SLOT_ABOVE)


def _slot_layer(text: str) -> tuple[list, np.ndarray]:
    """The SLOT layer of the DXF read by ezdxf: its SPLINEs as scipy B-splines (with parameter
    ranges) and its ARCs as dense points."""
    import ezdxf
    from scipy.interpolate import BSpline

    doc = ezdxf.read(io.StringIO(text))
    assert not doc.audit().has_errors
    splines, arcs = [], []
    for e in doc.modelspace().query('*[layer=="SLOT"]'):
        if e.dxftype() == "SPLINE":
            knots, ctrl = np.array(e.knots, dtype=float), np.array(e.control_points, dtype=float)[:, :2]
            k = e.dxf.degree
            splines.append((BSpline(knots, ctrl, k), float(knots[k]), float(knots[-k - 1])))
        else:
            assert e.dxftype() == "ARC", e.dxftype()
            a0, a1 = math.radians(e.dxf.start_angle), math.radians(e.dxf.end_angle)
            t = np.linspace(a0, a0 + (a1 - a0) % (2 * math.pi), 20001)
            arcs.append(np.stack([e.dxf.center[0] + e.dxf.radius * np.cos(t), e.dxf.center[1] + e.dxf.radius * np.sin(t)], axis=1))
    return splines, np.vstack(arcs)


def test_roller_rides_both_walls_of_the_slot_on_the_dxf_with_its_clearance(slot_files):
    """The roller (10 mm) in the slot (clearance 0.2 mm), dropped onto the SLOT layer of the DXF
    (ezdxf reads its B-splines and arcs, scipy evaluates them) at 301 travels: resting on the
    lower wall its centre follows the curve 0.1 mm below the pitch graph (x, s(x)) along its
    normal, pressed up on the upper wall the curve 0.1 mm above; both curves by brute force from
    the closed-form graph (the envelope of circles of 0.1 mm about 10^6 of its points), within
    1e-6 mm."""
    from scipy.interpolate import BSpline

    splines, arcs = _slot_layer(slot_files["c.dxf"])
    mid = [(sp, lo, hi) for sp, lo, hi in splines]
    below = [m for m in mid if m[0](0.5 * (m[1] + m[2]))[1] < cycloidal_lift(np.array([m[0](0.5 * (m[1] + m[2]))[0]]))[0]]
    above = [m for m in mid if m not in below]
    assert len(below) >= 1 and len(above) >= 1
    mirrored = [(BSpline(sp.t, sp.c * np.array([1.0, -1.0]), sp.k), lo, hi) for sp, lo, hi in above]
    x = np.linspace(0.0, TRAVEL, 301)

    def on_arcs(points: np.ndarray) -> np.ndarray:  # the roller's height dropped onto the arcs' points (-inf: none within r)
        dx = points[None, :, 0] - x[:, None]
        return np.max(np.where(np.abs(dx) <= R, points[None, :, 1] + np.sqrt(np.maximum(R * R - dx * dx, 0.0)), -np.inf), axis=1)

    low_arcs = arcs[:, 1] < cycloidal_lift(arcs[:, 0])  # the arcs' halves below the graph (its ends: dwells at 0)
    on_lower = np.maximum(roller_height_on_splines(below, x, R), on_arcs(arcs[low_arcs]))
    on_upper = -np.maximum(roller_height_on_splines(mirrored, x, R), on_arcs(arcs[~low_arcs] * np.array([1.0, -1.0])))
    gx = np.linspace(-1.0, TRAVEL + 1.0, 1_000_001)
    gy = cycloidal_lift(gx)
    half = SLOT_CLEARANCE / 2
    low_curve, high_curve = np.empty(x.size), np.empty(x.size)
    for i, xi in enumerate(x):
        near = np.abs(gx - xi) <= half
        rise = np.sqrt(np.maximum(half * half - (gx[near] - xi) ** 2, 0.0))
        low_curve[i] = np.min(gy[near] - rise)
        high_curve[i] = np.max(gy[near] + rise)
    assert np.max(np.abs(on_lower - low_curve)) < 1e-6, float(np.max(np.abs(on_lower - low_curve)))
    assert np.max(np.abs(on_upper - high_curve)) < 1e-6, float(np.max(np.abs(on_upper - high_curve)))


def test_slot_point_list_holds_the_exact_slot(slot_files):
    """The point list's SLOT wall: every vertex at HALF from the closed-form pitch graph over the
    travel within 1e-6 mm (the boundary: the walls and the end half circles), the loop
    counter-clockwise with the closed-form area within its chords' bound (chord_tol_mm x length)."""
    from scipy.spatial import cKDTree

    lines = slot_files["c_points.csv"].splitlines()
    header = lines[0].split(",")
    assert "wall" in header, header
    col = header.index("wall")
    rows = [line.split(",") for line in lines[1:] if line.split(",")[col] == "SLOT"]
    pts = np.array([[float(r[0]), float(r[1])] for r in rows])
    xs = np.linspace(0.0, TRAVEL, 300001)
    distance = cKDTree(np.stack([xs, cycloidal_lift(xs)], axis=1)).query(pts)[0]
    # the slot's boundary is where the distance from the graph over 0..TRAVEL is HALF; the graph's
    # spacing (0.001 mm) makes the nearest vertex at most 0.001^2 / (8 HALF) = 1.3e-8 mm farther
    assert np.max(np.abs(distance - HALF)) < 1e-6, float(np.max(np.abs(distance - HALF)))
    area = 0.5 * float(np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
    assert area == pytest.approx(slot_area(), abs=2e-3 * 700)


def _plate_area() -> float:
    """The plate: 360 x 90 mm, its four corners rounded by 2 mm (the default corner_radius_mm)."""
    return (TRAVEL + 60.0) * (45.0 + SLOT_ABOVE) - 4 * (1 - math.pi / 4) * 2.0**2


def test_slotted_plate_stl_passes_admesh_with_the_closed_form_volume(slot_files, tmp_path):
    """admesh reads the STL: nothing to repair, one part; its volume is plate area x thickness -
    slot area x depth (closed forms above) within the chords' bound (every chord within
    chord_tol_mm = 1e-3 of its curve: each side face sweeps at most its loop's length x tol x its
    height) and float32's rounding."""
    import re

    from test_solid import admesh_clean

    path = tmp_path / "c.stl"
    path.write_bytes(slot_files["c.stl"])
    out = admesh_clean(require_tool("admesh"), path)
    volume = float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1))
    exact = _plate_area() * THICKNESS - slot_area() * SLOT_DEPTH
    bound = 1e-3 * (2 * (360.0 + 90.0) * THICKNESS + 2 * 330.0 * SLOT_DEPTH) + 1e-6 * exact
    assert abs(volume - exact) <= bound, (volume, exact, bound)
    assert bound < 0.01 * slot_area() * SLOT_DEPTH


def test_slotted_plate_step_is_valid_in_occt_with_the_closed_form_volume(slot_files):
    """OpenCASCADE reads the STEP: BRepCheck valid, one solid, its volume (OCCT's own
    integration, BRepGProp) the closed form within 1e-6 relative."""
    pytest.importorskip("OCP")
    from OCP.BRepCheck import BRepCheck_Analyzer
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from test_pocket_files import _occt_shape

    shape = _occt_shape(slot_files["c.step"])
    assert BRepCheck_Analyzer(shape).IsValid()
    solids, count = TopExp_Explorer(shape, TopAbs_SOLID), 0
    while solids.More():
        count += 1
        solids.Next()
    assert count == 1
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    exact = _plate_area() * THICKNESS - slot_area() * SLOT_DEPTH
    assert abs(props.Mass() - exact) <= 1e-6 * exact, (props.Mass(), exact)


def test_a_plate_too_short_for_the_slot_fails_naming_the_margins_and_their_least_values_hold():
    """margin_end_mm = 12 leaves 12 - HALF = 1.9 mm beyond the slot's end half circle (a dwell
    there: its rightmost point is TRAVEL + HALF), below min_wall_mm = 3: plate_length fails
    (exit 1, no manufacturing file) naming margin_end_mm and the least margin, HALF + 3 = 13.1 mm
    (the closed form); that hint (rounded up to 1e-6 mm, as printed) is then accepted and the
    slot made."""
    import re

    scene = {"output": {"formats": ["dxf", "stl"]}, "cams": {"c": _slot_cam(margin_end_mm=12.0, min_wall_mm=3.0)}}
    files = _run(scene)
    checks, report = _checks(files)
    assert checks["plate_length"]["status"] == "fail" and report["status"] == "fail"
    assert checks["plate_length"]["value"] == pytest.approx(12.0 - HALF, abs=1e-9)
    assert "c.dxf" not in files and "c.stl" not in files
    hint = re.search(r"margin_end_mm >= ([\d.]+)", checks["plate_length"]["note"])
    assert hint and float(hint.group(1)) == pytest.approx(HALF + 3.0, abs=2e-6), checks["plate_length"]["note"]
    assert "margin_start_mm" not in checks["plate_length"]["note"]
    files = _run({**scene, "cams": {"c": _slot_cam(margin_end_mm=float(hint.group(1)), min_wall_mm=3.0)}})
    checks, report = _checks(files)
    assert checks["plate_length"]["status"] == "pass" and report["status"] == "pass" and "c.stl" in files


# --------------------------------------------------------------------------------------------
# G-code
# --------------------------------------------------------------------------------------------
def test_gcode_of_the_edge_cuts_the_exact_outline(edge_files, tmp_path):
    """rs274 accepts the edge cam's program, and the cutting simulation leaves the exact outline
    within 1 um (no gouge, nothing proud) on every pass."""
    require_tool("rs274")
    from cutting import ExactProfile, simulate

    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": ["ngc"]}, "machining": {"tool_diameter_mm": 10.0}, "cams": {"c": _cam()}}, "lin")
    (cam,) = compute(scene, plan_run(scene)).cams
    program = _run({"output": {"formats": ["ngc"]}, "machining": {"tool_diameter_mm": 10.0}, "cams": {"c": _cam()}})["c.ngc"]
    # the outline's straight sides flatten to single chords hundreds of mm long, and the cutting
    # simulation's distance bound grows with the longest chord: split every chord to <= 0.02 mm
    # (points on a straight side are on the exact curve; on a curved one within PROFILE_TOL)
    from scipy.spatial import cKDTree

    profile = ExactProfile(cam.contour)
    v = profile.vertices
    w = np.roll(v, -1, axis=0)
    parts = np.maximum(1, np.ceil(np.hypot(*(w - v).T) / 0.02).astype(int))
    frac = np.concatenate([np.arange(n) / n for n in parts])
    start = np.repeat(np.arange(v.shape[0]), parts)
    profile.vertices = v[start] + frac[:, None] * (w[start] - v[start])
    profile.spacing = float(np.max(np.hypot(*np.diff(np.vstack([profile.vertices, profile.vertices[:1]]), axis=0).T)))
    profile.tol = 2 * profile.tol
    profile.tree = cKDTree(profile.vertices)
    report = simulate(program, cam.contour, 5.0, tmp_path, profile=profile)
    assert report.status == 0, report.message
    assert report.gouge <= 1e-3 and report.proud <= 1e-3, (report.gouge, report.proud)
    assert all(p.outside for p in report.passes)


def _dense_outline(contour, step: float = 0.02):
    """The plate's outline as the cutting simulation's profile: flattened within 1e-7 mm (tests/
    cutting.py's PROFILE_TOL), its long straight chords split to <= ``step`` mm (points on a
    straight side are on the exact curve: the simulation's distance bound grows with the spacing)."""
    from test_gcode_pockets import Sampled

    v = contour.flatten(1e-7)
    w = np.roll(v, -1, axis=0)
    parts = np.maximum(1, np.ceil(np.hypot(*(w - v).T) / step).astype(int))
    frac = np.concatenate([np.arange(n) / n for n in parts])
    start = np.repeat(np.arange(v.shape[0]), parts)
    return Sampled(v[start] + frac[:, None] * (w[start] - v[start]), 1e-7)


def _slot_floor(n: int = 3001) -> np.ndarray:
    """Points of the slot's floor (closed form): across the band about the graph, and the end half discs."""
    x = np.linspace(0.0, TRAVEL, n)
    d = cycloidal_slope(x)
    nrm = np.stack([-d, np.ones_like(d)], axis=1) / np.hypot(d, 1.0)[:, None]
    t = np.linspace(-HALF, HALF, 41)
    band = (np.stack([x, cycloidal_lift(x)], axis=1)[None] + t[:, None, None] * nrm[None]).reshape(-1, 2)
    rho, phi = np.meshgrid(np.linspace(0.0, HALF, 21), np.linspace(0.0, 2 * math.pi, 181))
    disc = np.stack([(rho * np.cos(phi)).ravel(), (rho * np.sin(phi)).ravel()], axis=1)
    return np.vstack([band, disc, disc + np.array([TRAVEL, 0.0])])


@pytest.mark.parametrize("diameter, strategy", [(2 * HALF, "one pass along the pitch curve"), (6.0, "pocket cleared, one wall pass")])
def test_gcode_of_the_slot_cuts_the_exact_slot(diameter, strategy, tmp_path):
    """rs274 accepts the slotted plate's program; the cutting simulation (tests/cutting.py: the
    tool disc swept along rs274's moves) leaves the slot's wall (the closed-form boundary,
    exact_slot) within 1 um (no gouge, nothing proud at the floor), every cut inside it, the floor
    at slot_depth_mm with no island; the outline is cut through, nothing gouged or proud.  A tool
    of the slot's width runs along the open pitch curve there and back; a 6 mm tool clears it by
    the wall's inward offsets (stepover <= 3 mm) and finishes along the wall."""
    require_tool("rs274")
    from cutting import CUT_TOL, simulate_pockets
    from test_gcode_pockets import Sampled

    scene = {"output": {"formats": ["ngc"]}, "machining": {"tool_diameter_mm": diameter, "step_down_mm": 2.5}, "cams": {"c": _slot_cam()}}
    program = _run(scene)["c.ngc"]
    assert strategy in program
    cam = _slot_built()
    exact = exact_slot(0.002)
    report = simulate_pockets(program, _dense_outline(cam.contour), {"SLOT": Sampled(exact, 0.002**2 / (8 * HALF))}, diameter / 2, tmp_path)
    outline, pocket = report.outline, report.pocket
    assert outline.status == 0, outline.message
    assert pocket is not None and pocket.between
    assert pocket.gouge["SLOT"] <= CUT_TOL and pocket.proud["SLOT"] <= CUT_TOL, (pocket.gouge, pocket.proud)
    assert pocket.deepest == -SLOT_DEPTH and len(pocket.levels) == math.ceil(SLOT_DEPTH / 2.5)
    starts, floors = np.array(pocket.levels).T
    assert starts[0] == 0.0 and np.all(starts[1:] == floors[:-1]) and floors[-1] == -SLOT_DEPTH
    assert pocket.island(_slot_floor(), diameter / 2) <= CUT_TOL
    assert outline.gouge <= CUT_TOL and outline.proud <= CUT_TOL and all(p.outside for p in outline.passes)


# --------------------------------------------------------------------------------------------
# Refusals
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("extra, key", [
    ({"follower": "flat"}, "follower"),
    ({"linear_form": "slot", "follower": "knife", "above_pitch_mm": 40.0, "slot_depth_mm": 5.0}, "follower"),
    ({"linear_form": "slot", "above_pitch_mm": 40.0, "slot_depth_mm": 12.0}, "slot_depth_mm"),
    ({"follower_motion": "oscillating", "pivot_x_mm": -50.0, "pivot_y_mm": 30.0, "swing_turn": "cw"}, "pivot_x_mm"),
    ({"slot_depth_mm": 5.0}, "slot_depth_mm"),
])
def test_bad_linear_scenes_are_refused_naming_the_key(extra, key):
    from camgen.errors import CamgenError
    from camgen.scene import parse_scene

    cam = _cam(**extra)
    if cam.get("follower") == "knife":
        cam.pop("roller_radius_mm")
    if cam.get("follower") == "flat":
        cam.pop("roller_radius_mm")
    with pytest.raises(CamgenError) as caught:
        parse_scene({"cams": {"c": cam}}, "t")
    assert f"cams.c.{key}" in str(caught.value), str(caught.value)


def test_lift_table_reads_x_in_mm(tmp_path):
    """A lift table's first column is the travel x in mm for a linear cam: a table of the
    cycloidal program sampled every 2.5 mm rides within the quintic spline's interpolation error."""
    x = np.arange(0.0, TRAVEL, 2.5)
    (tmp_path / "t.csv").write_text("x_mm,lift_mm\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(x, cycloidal_lift(x))))
    cam = _cam(kind="lift_table", lift_table_csv=str(tmp_path / "t.csv"))
    del cam["segments"]
    files = _run({"output": {"formats": ["points"], "chord_tol_mm": 1e-5}, "cams": {"c": cam}})
    xs = np.linspace(0.0, TRAVEL, 301)
    got = roller_height_on_polygon(_table(files["c_points.csv"]), xs, R)
    assert np.max(np.abs(got - cycloidal_lift(xs))) < 2e-3


def test_a_plate_too_shallow_for_its_corners_is_refused_with_a_depth_that_works():
    """below_pitch_mm too small for the top corners' fillets: refused naming the key and the least
    depth; that hint (plus its printed rounding) is then accepted and the plate made."""
    import re

    from camgen.errors import ParameterError

    cam = _cam(below_pitch_mm=11.0)
    with pytest.raises(ParameterError) as caught:
        _run({"output": {"formats": ["dxf"]}, "cams": {"c": cam}})
    assert caught.value.name == "cams.c.below_pitch_mm" and caught.value.value == 11.0
    least = float(re.search(r"> ([0-9.]+) mm", caught.value.valid).group(1))
    files = _run({"output": {"formats": ["dxf"]}, "cams": {"c": _cam(below_pitch_mm=least + 1e-3, min_wall_mm=0.5)}})
    assert "c.dxf" in files and _checks(files)[1]["status"] == "pass"


def test_knife_rides_the_point_list_and_the_dxf():
    """A knife's profile is its pitch curve: the plate's top edge, read from the point list (the
    polygon's height at x, chords within chord_tol_mm = 2e-7) and from the DXF's B-splines (a
    roller of radius 1e-9 mm dropped on them), is the closed-form lift within 1e-6 mm."""
    cam = _cam(follower="knife")
    del cam["roller_radius_mm"]
    files = _run({"output": {"formats": ["dxf", "points"], "chord_tol_mm": 2e-7, "dxf_splines": "bspline"}, "cams": {"c": cam}})
    x = np.linspace(0.0, TRAVEL, 601)
    poly = _table(files["c_points.csv"])
    top = poly[poly[:, 1] > -40.0]  # the edge (the bottom is at -45)
    order = np.argsort(top[:, 0])
    height = np.interp(x, top[order, 0], top[order, 1])
    assert np.max(np.abs(height - cycloidal_lift(x))) < 1e-6
    spline = np.full(x.shape, -np.inf)
    for curve, lo, hi in dxf_splines(files["c.dxf"]):  # the height where x(u) = x, by bisection on u
        u = np.linspace(lo, hi, 20001)
        px = curve(u)[:, 0]
        for i, xi in enumerate(x):
            cross = np.flatnonzero((px[:-1] - xi) * (px[1:] - xi) <= 0)
            for j in cross:
                a, b = u[j], u[j + 1]
                fa = curve(a)[0] - xi
                if fa == 0.0:  # the sample is the point
                    b = a
                for _ in range(60 if a != b else 0):
                    m = 0.5 * (a + b)
                    fm = curve(m)[0] - xi
                    a, b, fa = (m, b, fm) if (fm > 0) == (fa > 0) else (a, m, fa)
                spline[i] = max(spline[i], float(curve(0.5 * (a + b))[1]))
    assert np.max(np.abs(spline - cycloidal_lift(x))) < 1e-6


def test_the_edge_plate_solid_is_closed_with_the_exact_volume(tmp_path):
    """A knife's edge is the graph of s itself, so the plate's area is closed form: the margins
    (15 and 30 mm) lie in dwells at zero lift, the integral of a cycloidal rise or fall of h over
    L is h L / 2 (Norton eq. 8.6), each of the four corners rounded with radius 2 mm cuts off
    (1 - pi/4) 2^2.  admesh reads the STL: nothing to repair, one part, and its volume is that area
    times the thickness within the chords' tolerance."""
    import re

    from test_solid import admesh_clean

    program = [{"law": "dwell", "span_mm": 50.0}, {"law": "cycloidal", "span_mm": 100.0, "lift_mm": 20.0},
               {"law": "dwell", "span_mm": 50.0}, {"law": "cycloidal", "span_mm": 80.0, "lift_mm": -20.0},
               {"law": "dwell", "span_mm": 20.0}]
    cam = _cam(follower="knife", segments=program, margin_start_mm=15.0, corner_radius_mm=2.0)
    del cam["roller_radius_mm"]
    files = _run({"output": {"formats": ["stl"], "chord_tol_mm": 1e-3}, "cams": {"c": cam}})
    area = (15.0 + TRAVEL + 30.0) * 45.0 + 20.0 * (100.0 / 2 + 50.0 + 80.0 / 2) - 4 * (1 - math.pi / 4) * 2.0**2
    exact = area * 12.0
    path = tmp_path / "c.stl"
    path.write_bytes(files["c.stl"])
    out = admesh_clean(require_tool("admesh"), path)
    volume = float(re.search(r"Volume\s*:\s*([\d.]+)", out).group(1))
    perimeter = 2 * (345.0 + 45.0) + 2 * 20.0  # the outline's length is below this (the rise and fall add < 2 h)
    assert abs(volume - exact) <= perimeter * 1e-3 * 12.0 + 1e-6 * exact, (volume, exact)


def test_lift_table_x_beyond_the_travel_is_refused_in_mm(tmp_path):
    """A lift table's x column running past one travel is refused naming lift_table_csv, the line
    and the x in mm (not as a cam angle)."""
    from camgen.errors import ParameterError
    from camgen.scene import parse_scene

    x = np.arange(0.0, TRAVEL + 20.0, 10.0)
    (tmp_path / "t.csv").write_text("".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(x, cycloidal_lift(x))))
    cam = _cam(kind="lift_table", lift_table_csv=str(tmp_path / "t.csv"))
    del cam["segments"]
    with pytest.raises(ParameterError) as caught:
        parse_scene({"cams": {"c": cam}}, "t")
    assert caught.value.name == "cams.c.lift_table_csv"
    assert "line 32: x 310 mm after 300 mm" in str(caught.value) and "<= 300 mm" in str(caught.value), str(caught.value)


def test_the_report_draws_against_travel_and_animates_the_plate():
    """report.html: the linear cam's section plots against the plate travel in mm (not cam angle),
    draws the plate and follower at travel 0, and slides the plate by the whole travel (SMIL, no
    script); the generic cam-angle curves are left out."""
    from camgen.scene import load_template

    from camgen.pipeline import execute, plan_run

    scene = load_template("linear_cam")
    files = execute(scene, plan_run(scene)).files
    page = files["report.html"]
    assert "lifter: linear cam against plate travel" in page and "plate travel x (mm)" in page
    assert "plate and follower at travel 0" in page
    assert f"from='0 0' to='{-TRAVEL:.3f} 0'" in page and "<script" not in page
    assert "no curves: the profile cannot be made" not in page
    report = json.loads(files["report.json"])
    assert report["status"] == "pass" and report["cams"]["lifter"]["figures"]["travel_mm"] == TRAVEL


# --------------------------------------------------------------------------------------------
# The program's abscissa: plate travel in mm
# --------------------------------------------------------------------------------------------
def test_a_program_in_span_mm_is_the_span_deg_program_mapped_onto_the_travel():
    """A linear cam's program in span_mm with a polynomial's conditions per mm (v in mm/mm, a in
    mm/mm^2) gives, to rounding, the law the equivalent cam-angle program gives (spans
    span_mm x 360 / T deg, conditions per degree: v x T / 360, a x (T / 360)^2, the mapping
    x = T theta / 360 deg), read as a plate cam's program reads it; the travel is the spans' sum
    (travel_mm left out) and equal when given."""
    from camgen.motions.motion_law import read_program
    from camgen.pipeline import compute, plan_run
    from camgen.scene import parse_scene

    mm = [{"law": "dwell", "span_mm": 40.0}, {"law": "polynomial", "span_mm": 60.0, "start": [0.0, 0.0, 0.01], "end": [10.0, 0.0, -0.005]},
          {"law": "cycloidal", "span_mm": 50.0, "lift_mm": 8.0}, {"law": "dwell", "span_mm": 30.0},
          {"law": "poly345", "span_mm": 120.0, "lift_mm": -18.0}]
    travel = 300.0
    k = travel / 360.0  # mm of travel per degree
    deg = [{"law": "dwell", "span": math.radians(40.0 / k)},
           {"law": "polynomial", "span": math.radians(60.0 / k), "start": (0.0, 0.0, 0.01 * k * k), "end": (10.0, 0.0, -0.005 * k * k)},
           {"law": "cycloidal", "span": math.radians(50.0 / k), "lift": 8.0}, {"law": "dwell", "span": math.radians(30.0 / k)},
           {"law": "poly345", "span": math.radians(120.0 / k), "lift": -18.0}]
    reference = read_program("cams.c", tuple(deg), "translating")
    for given in ({}, {"travel_mm": travel}):
        cam = _cam(segments=mm, **given)
        if not given:
            del cam["travel_mm"]
        scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"c": cam}}, "lin")
        (built,) = compute(scene, plan_run(scene)).cams
        p = built.spec.params
        assert p.travel == travel
        theta = (np.arange(72000) + 0.5) * (2 * math.pi / 72000)  # off the breaks (at whole multiples of 2 pi / 72000)
        for got, want in zip(p.law(theta), reference(theta)):
            assert np.max(np.abs(got - want)) <= 1e-12 * max(1.0, float(np.max(np.abs(want)))), float(np.max(np.abs(got - want)))
        # the polynomial's start: a = 0.01 mm/mm^2 at x = 40 mm (the law in x, d2s/dx2 = s''(theta) (2 pi / T)^2)
        a = p.law(np.array([2 * math.pi * 40.0 / travel + 1e-12]))[2][0] * (2 * math.pi / travel) ** 2
        assert a == pytest.approx(0.01, rel=1e-6)


def _check_cli(tmp_path, text: str):
    import subprocess
    import sys

    path = tmp_path / "s.toml"
    path.write_text(text)
    return subprocess.run([sys.executable, "-m", "camgen", "check", str(path)], capture_output=True, text=True, timeout=120)


_LINEAR_TOML = """[cams.c]
kind = "motion_law"
form = "linear"
follower = "roller"
roller_radius_mm = 10.0
{travel}
[[cams.c.segments]]
law = "dwell"
{span} = 60.0
[[cams.c.segments]]
law = "cycloidal"
span_mm = 100.0
lift_mm = 20.0
[[cams.c.segments]]
law = "dwell"
span_mm = 40.0
[[cams.c.segments]]
law = "cycloidal"
span_mm = 100.0
lift_mm = -20.0
"""


@pytest.mark.parametrize("travel, span, key, words", [
    ("", "span_deg", "cams.c.segments[0].span_deg", "use span_mm"),
    ("travel_mm = 250.0", "span_mm", "cams.c.travel_mm", "300 mm, the sum of the segments' span_mm"),
    ("", "# no span:", "cams.c.segments[0].span_mm", "every segment gives its span"),
])
def test_a_linear_program_in_the_wrong_abscissa_is_refused_naming_the_key(tmp_path, travel, span, key, words):
    """Exit 2 and one stderr line ``camgen: error:`` naming the key: span_deg on a linear cam (use
    span_mm), travel_mm other than the spans' sum, a segment without its span."""
    run = _check_cli(tmp_path, _LINEAR_TOML.format(travel=travel, span=span))
    lines = run.stderr.strip().splitlines()
    assert run.returncode == 2 and len(lines) == 1 and lines[0].startswith("camgen: error: "), (run.returncode, run.stderr)
    assert key in lines[0] and words in lines[0], lines[0]


def test_span_mm_on_a_cam_turning_about_an_axis_is_refused_naming_it(tmp_path):
    """A plate cam's program runs over the cam angle: a segment's span_mm is refused (exit 2, one
    line naming it and span_deg); a span_deg program there reads as before (exit 0)."""
    text = """[cams.c]
kind = "motion_law"
follower = "roller"
roller_radius_mm = 8.0
base_radius_mm = 40.0
[[cams.c.segments]]
law = "cycloidal"
{span} = 180.0
lift_mm = 10.0
[[cams.c.segments]]
law = "cycloidal"
span_deg = 180.0
lift_mm = -10.0
"""
    run = _check_cli(tmp_path, text.format(span="span_mm"))
    lines = run.stderr.strip().splitlines()
    assert run.returncode == 2 and len(lines) == 1 and lines[0].startswith("camgen: error: "), (run.returncode, run.stderr)
    assert "cams.c.segments[0].span_mm" in lines[0] and "span_deg" in lines[0], lines[0]
    assert _check_cli(tmp_path, text.format(span="span_deg")).returncode == 0


@pytest.mark.parametrize("fmt", ["lift", "follower"])
def test_formats_a_linear_cam_cannot_have_are_refused_naming_output_formats(fmt):
    """The polar lift table and the follower table at a cam speed (a plate turns about no axis,
    has no rpm) are refused before anything is computed: output.formats, the format, the cam."""
    from camgen.errors import ParameterError
    from camgen.planning import plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": ["dxf", fmt]}, "cams": {"c": _cam()}}, "t")
    with pytest.raises(ParameterError) as caught:
        plan_run(scene)
    assert caught.value.name == "output.formats" and caught.value.value == fmt and "cams.c" in str(caught.value)
    assert caught.value.valid == 'any format but "lift", "follower"'
