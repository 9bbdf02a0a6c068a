"""Disk cams ridden on their exported geometry: every law x every follower x both rotations.

Each cam is made by the pipeline from a scene (kinds ``motion_law`` and ``lift_table``) and
written as camgen writes it; the files are read back by independent readers and ridden by the
independent simulator tests/ride.py; the follower's position is compared with the one the law
requires (computed here from the conventions of camgen.synthesis.followers' docstring: rest
positions from plane geometry, tests/test_followers.py).

* **DXF with exact B-splines** (``dxf_splines = "bspline"``), read back by ezdxf, each SPLINE
  turned into a piecewise cubic by scipy: the ride error is <= 1e-6 mm (translating followers)
  or 1e-6 rad (oscillating ones) at the default ``fit_tol_mm`` (1e-7 mm).
* **DXF of biarcs** (the default) read back by ezdxf, and the **points CSV**: their stated
  tolerance is ``chord_tol_mm`` (the largest distance from the exact profile).  A profile moved
  by ``d`` along its normal moves the follower by ``d / lever``: ``lever`` = cos(pressure angle)
  for a translating roller or knife (mm per mm), 1 for a translating flat face, the arm length x
  cos(pressure angle) for an oscillating roller or knife (mm per rad), and the contact's distance
  along the face from the pivot's foot for an oscillating flat face.  The ride error must stay
  within ``chord_tol_mm / lever`` (1 % slack for the first-order estimate); the pressure angle in
  the lever is computed here by Kennedy's theorem (the instant centre), not taken from camgen's
  kinematics, so a wrong pressure angle cannot widen the tolerance.  The points CSV is
  ridden as the polygon it is: vertex and edge contacts (rollers), edge crossings (knives), vertex
  support (flat faces).

The program of every law: cycloidal, dwell, simple harmonic, double harmonic rise and return,
modified trapezoid, modified sine, modified cycloidal rise and return, 3-4-5, 4-5-6-7, constant
velocity with blends and a polynomial from boundary conditions, each over 29 deg (so one cam holds
them all), and a periodic quintic lift table; plain constant velocity (velocity jumps: profile corners) for knives.
"""
from __future__ import annotations

import functools
import io
import math

import numpy as np
import pytest

from camgen.synthesis.followers import FollowerSpec
from camgen.synthesis.laws import MotionProgram, Segment
from camgen.synthesis.lift_table import LiftTable
import ride
from test_followers import required_position, rest_arm_angle, rest_face_angle
from test_followers import ride_position as followers_ride

D = math.radians
TWO_PI = 2.0 * math.pi
CHORD_TOL = 1e-3  # mm, the scenes' chord_tol_mm
EXACT_TOL = 1e-6  # mm or rad: the ride on the exact B-spline DXF
LIFT, SWING = 3.0, 2.5  # mm, deg
SPAN = 29.0  # deg, every motion segment (12 of them and a 12 deg dwell)

#: (law, extra keys, lift sign) of the program of every law; the dwell spans 12 deg
PROGRAM = [("cycloidal", {}, 1), ("dwell", {}, 0), ("simple_harmonic", {}, -1), ("double_harmonic", {}, 1),
           ("double_harmonic", {}, -1), ("modified_trapezoid", {}, 1), ("modified_sine", {}, -1),
           ("modified_cycloidal", {}, 1), ("modified_cycloidal", {}, -1), ("poly345", {}, 1),
           ("poly4567", {}, -1), ("constant_velocity", {"blend": 0.25}, 1), ("polynomial", {}, -1)]

#: the followers, in scene keys
FOLLOWERS = {
    "roller": {"follower": "roller", "base_radius_mm": 40.0, "roller_radius_mm": 10.0},
    "roller_offset": {"follower": "roller", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "follower_offset_mm": 12.0},
    "flat": {"follower": "flat", "base_radius_mm": 150.0, "follower_offset_mm": 3.0},
    "knife": {"follower": "knife", "base_radius_mm": 40.0, "follower_offset_mm": -6.0},
    "osc_roller": {"follower": "roller", "follower_motion": "oscillating", "base_radius_mm": 40.0, "roller_radius_mm": 8.0,
                   "pivot_x_mm": 110.0, "pivot_y_mm": 40.0, "arm_length_mm": 95.0},
    "osc_flat": {"follower": "flat", "follower_motion": "oscillating", "base_radius_mm": 120.0, "pivot_x_mm": 150.0,
                 "pivot_y_mm": 80.0, "face_offset_mm": 20.0, "swing_turn": "cw"},
    "osc_knife": {"follower": "knife", "follower_motion": "oscillating", "base_radius_mm": 40.0, "pivot_x_mm": -90.0,
                  "pivot_y_mm": 60.0, "arm_length_mm": 80.0, "swing_turn": "cw"},
}
ROTATIONS = ("ccw", "cw")


def oscillating(name: str) -> bool:
    return FOLLOWERS[name].get("follower_motion") == "oscillating"


def size_of(name: str) -> float:
    """Lift (mm) or swing (deg) of every segment: the flat faces' envelopes stay convex with it."""
    return {"osc_flat": 1.5}.get(name, SWING if oscillating(name) else LIFT)


def segments_toml(name: str, plain_constant_velocity: bool = False) -> list[dict]:
    """The [[segments]] tables of the program of every law, in scene units."""
    key, size = ("swing_deg" if oscillating(name) else "lift_mm"), size_of(name)
    if plain_constant_velocity:  # velocity jumps at both ends: corners a knife follows
        return [{"law": "constant_velocity", "span_deg": 150.0, key: size}, {"law": "dwell", "span_deg": 60.0},
                {"law": "cycloidal", "span_deg": 150.0, key: -size}]
    out = []
    for law, extra, sign in PROGRAM:
        item = {"law": law, "span_deg": 12.0 if law == "dwell" else SPAN, **extra}
        if law == "polynomial":  # from the top (s = size) back to rest, zero jerk at the end: degree 6
            item.update(start=[size, 0.0, 0.0], end=[0.0, 0.0, 0.0, 0.0])
        elif law != "dwell":
            item[key] = sign * size
        out.append(item)
    return out


def required_law(name: str, plain_constant_velocity: bool = False) -> MotionProgram:
    """The same program built here from the library (rad, mm or rad of swing)."""
    size = D(size_of(name)) if oscillating(name) else size_of(name)
    if plain_constant_velocity:
        return MotionProgram([Segment("constant_velocity", D(150), size), Segment("dwell", D(60), 0.0),
                              Segment("cycloidal", D(150), -size)])
    segs = []
    for law, extra, sign in PROGRAM:
        if law == "polynomial":
            segs.append(Segment(law, D(SPAN), start=(size, 0.0, 0.0), end=(0.0, 0.0, 0.0, 0.0)))
        else:
            segs.append(Segment(law, D(12.0 if law == "dwell" else SPAN), sign * size if law != "dwell" else 0.0, **extra))
    return MotionProgram(segs, unit="rad" if oscillating(name) else "mm")


def table_rows(name: str) -> tuple[np.ndarray, np.ndarray]:
    """A lift table (deg, mm or deg of swing): two harmonics, one row per 4 deg."""
    angle = np.arange(0.0, 360.0, 4.0)
    t = np.radians(angle)
    shape = (1 - np.cos(t)) / 2 + 0.15 * np.sin(2 * t) * (1 - np.cos(t)) / 2
    return angle, size_of(name) * shape


def follower_spec(name: str, rotation: str) -> FollowerSpec:
    """The follower of the scene keys, for the rest-position helpers and the levers."""
    k = FOLLOWERS[name]
    osc = oscillating(name)
    return FollowerSpec(k["follower"], k["base_radius_mm"], "oscillating" if osc else "translating", k.get("roller_radius_mm", 0.0),
                        k.get("follower_offset_mm", 0.0), (k["pivot_x_mm"], k["pivot_y_mm"]) if osc else None,
                        k.get("arm_length_mm", 0.0), k.get("face_offset_mm", 0.0), k.get("swing_turn", "ccw"), rotation)


CASES = [(name, rotation, law) for name in FOLLOWERS for rotation in ROTATIONS for law in ("every_law", "lift_table")]
CASES += [(name, rotation, "constant_velocity") for name in ("knife", "osc_knife") for rotation in ROTATIONS]


def cam_name(name: str, rotation: str, law: str) -> str:
    return f"{law}_{name}_{rotation}"


@functools.lru_cache(maxsize=None)
def _tables_dir() -> str:
    import tempfile

    folder = tempfile.mkdtemp(prefix="camgen_disk_tables_")
    for name in FOLLOWERS:
        angle, lift = table_rows(name)
        with open(f"{folder}/{name}.csv", "w", encoding="utf-8") as handle:
            handle.write("angle_deg,lift\n" + "".join(f"{a:.1f},{v:.12f}\n" for a, v in zip(angle, lift)))
    return folder


def scene_data(dxf_splines: str, formats: list[str]) -> dict:
    cams = {}
    for name, rotation, law in CASES:
        table = {**FOLLOWERS[name], "rotation": rotation}
        if law == "lift_table":
            table.update(kind="lift_table", lift_table_csv=f"{name}.csv")
        else:
            table.update(kind="motion_law", segments=segments_toml(name, law == "constant_velocity"))
        cams[cam_name(name, rotation, law)] = table
    # the construction layers on: the ZERO and PITCH tests read them
    return {"output": {"formats": formats, "chord_tol_mm": CHORD_TOL, "dxf_splines": dxf_splines, "dxf_construction": True}, "cams": cams}


@functools.lru_cache(maxsize=None)
def exported(dxf_splines: str) -> dict[str, str]:
    """Every cam of the matrix, written by the pipeline as `camgen run` does: file name -> text."""
    from pathlib import Path

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    formats = ["dxf", "points"] if dxf_splines == "bspline" else ["dxf"]
    scene = parse_scene(scene_data(dxf_splines, formats), "disk", base_dir=Path(_tables_dir()))
    result = execute(scene, plan_run(scene))
    failed = [(cam, check.name) for cam, check in result.failed_checks() if check.blocks_manufacture]
    assert not failed, failed
    return {name: data for name, data in result.files.items() if isinstance(data, str)}


# --------------------------------------------------------------------------------------------
# Reading the files back (ezdxf, scipy, numpy): no camgen code but the Contour container
# --------------------------------------------------------------------------------------------
def _read(text: str):
    import ezdxf

    doc = ezdxf.read(io.StringIO(text))
    assert not doc.audit().has_errors
    return doc


def bspline_contour(text: str, layer: str = "PROFILE"):
    """The ``layer``'s SPLINEs as piecewise cubics (scipy BSpline -> PPoly), in file order."""
    from scipy.interpolate import BSpline, PPoly

    from camgen.contour import Contour, Spline

    segments = []
    for e in _read(text).modelspace():
        if e.dxf.layer != layer:
            continue
        assert e.dxftype() == "SPLINE" and e.dxf.degree == 3
        knots, ctrl = np.array(e.knots, dtype=float), np.array(e.control_points, dtype=float)[:, :2]
        parts = [PPoly.from_spline(BSpline(knots, ctrl[:, k], 3)) for k in range(2)]
        keep = np.diff(parts[0].x) > 0
        breaks = np.append(parts[0].x[:-1][keep], parts[0].x[-1])
        coeffs = np.stack([p.c[:, keep] for p in parts], axis=-1)
        segments.append(Spline(breaks, coeffs))
    return Contour(segments, closure_tol=1e-6)


def biarc_contour(text: str, layer: str = "PROFILE"):
    """The ``layer``'s ARCs and LINEs as one counter-clockwise chain (each entity oriented to
    start where the previous one ends)."""
    from camgen.contour import Arc, Contour, Spline
    from camgen.errors import GeometryError

    pairs = []
    for e in _read(text).modelspace():
        if e.dxf.layer != layer:
            continue
        if e.dxftype() == "ARC":
            c, r = (e.dxf.center.x, e.dxf.center.y), e.dxf.radius
            a0, a1 = math.radians(e.dxf.start_angle), math.radians(e.dxf.end_angle)
            sweep = (a1 - a0) % TWO_PI
            pairs.append((Arc(c, r, a0, sweep), Arc(c, r, a1, -sweep)))
        else:
            assert e.dxftype() == "LINE"
            p, q = np.array(e.dxf.start)[:2], np.array(e.dxf.end)[:2]

            def line(a, b):
                coeffs = np.zeros((4, 1, 2))
                coeffs[2, 0], coeffs[3, 0] = b - a, a
                return Spline(np.array([0.0, 1.0]), coeffs)

            pairs.append((line(p, q), line(q, p)))
    for first in (0, 1):
        chain = [pairs[0][first]]
        for fw, bw in pairs[1:]:
            end = chain[-1].end_point
            chain.append(fw if np.hypot(*(fw.start_point - end)) <= np.hypot(*(bw.start_point - end)) else bw)
        try:
            return Contour(chain, closure_tol=1e-6)
        except GeometryError:
            continue
    raise AssertionError(f"the {layer} layer is not one closed chain")


def csv_points(text: str) -> np.ndarray:
    import pandas

    frame = pandas.read_csv(io.StringIO(text))  # the reader's defaults
    assert list(frame.columns) == ["x_mm", "y_mm"]
    return frame.to_numpy()


# --------------------------------------------------------------------------------------------
# Polygon rides: vertex contacts (tests/ride.py) and edge contacts of a roller
# --------------------------------------------------------------------------------------------
def _edges(pts: np.ndarray, theta: np.ndarray, sigma: float, r: float):
    """The polygon's edges turned by sigma theta, offset outward by r: start (M, N, 2), direction (M, N, 2)."""
    x = ride._rot(sigma * theta, pts)
    d = np.roll(x, -1, axis=1) - x
    length = np.hypot(d[..., 0], d[..., 1])
    normal = np.stack([d[..., 1], -d[..., 0]], axis=-1) / length[..., None]  # outward on a counter-clockwise polygon
    return x + r * normal, d


def polygon_translating_roller(pts, theta, offset, r, sigma):
    """Roller-centre height on the polygon: the highest of its vertex contacts and its edge contacts
    (the roller centre on an edge moved out by r, crossing the line x = offset)."""
    best = ride.translating_roller(pts, theta, offset, r, sigma)
    for sl in ride._chunks(theta.size, len(pts)):
        a, d = _edges(pts, theta[sl], sigma, r)
        with np.errstate(divide="ignore", invalid="ignore"):
            w = (offset - a[..., 0]) / d[..., 0]
            y = np.where((w >= 0) & (w <= 1), a[..., 1] + w * d[..., 1], -np.inf)
        best[sl] = np.maximum(best[sl], y.max(axis=1))
    return best


def polygon_oscillating_roller(pts, theta, f, rest, sigma):
    """Arm angle on the polygon: the most lifted of the vertex contacts and the edge contacts (the
    roller centre on an edge moved out by r, on the arm circle |C - pivot| = arm)."""
    lift = f.tau * ride._wrap(ride.oscillating_roller(pts, theta, f.pivot, f.arm_length, f.roller_radius, rest, f.tau, sigma) - rest)
    o = np.asarray(f.pivot)
    for sl in ride._chunks(theta.size, len(pts)):
        a, d = _edges(pts, theta[sl], sigma, f.roller_radius)
        rel = a - o
        qa = np.sum(d * d, axis=-1)
        qb = 2.0 * np.sum(d * rel, axis=-1)
        qc = np.sum(rel * rel, axis=-1) - f.arm_length**2
        disc = qb * qb - 4 * qa * qc
        root = np.sqrt(np.maximum(disc, 0.0))
        for sign in (1.0, -1.0):
            w = (-qb + sign * root) / (2 * qa)
            c = rel + w[..., None] * d
            g = np.arctan2(c[..., 1], c[..., 0])
            up = f.tau * ride._wrap(g - rest)
            up = np.where((disc >= 0) & (w >= 0) & (w <= 1) & (np.abs(up) < D(60)), up, -np.inf)
            lift[sl] = np.maximum(lift[sl], up.max(axis=1))
    return rest + f.tau * lift


def ride_position(f: FollowerSpec, cam, theta, polygon: bool = False):
    """The follower position (mm; rad: arm or face angle) the simulator finds on ``cam``."""
    if f.motion == "translating":
        if f.kind == "roller":
            if polygon:
                return polygon_translating_roller(cam, theta, f.offset, f.roller_radius, f.sigma)
            return ride.translating_roller(cam, theta, f.offset, f.roller_radius, f.sigma)
        if f.kind == "knife":
            return ride.translating_knife(cam, theta, f.offset, f.sigma)
        return ride.translating_flat(cam, theta, f.sigma)
    if f.kind == "flat":
        return ride.oscillating_flat(cam, theta, f.pivot, f.face_offset, rest_face_angle(f), f.tau, f.sigma)
    if polygon and f.kind == "roller":
        return polygon_oscillating_roller(cam, theta, f, rest_arm_angle(f), f.sigma)
    return ride.oscillating_roller(cam, theta, f.pivot, f.arm_length, f.roller_radius, rest_arm_angle(f), f.tau, f.sigma)


def ride_error(f: FollowerSpec, cam, theta, law, polygon: bool = False) -> np.ndarray:
    got = ride_position(f, cam, theta, polygon)
    diff = got - required_position(f, law(theta)[0])
    return np.abs(ride._wrap(diff)) if f.motion == "oscillating" else np.abs(diff)


def lever(f: FollowerSpec, law, theta) -> np.ndarray:
    """How far the follower point moves per unit of follower position along the contact normal
    (see the module docstring): mm/mm or mm/rad, from the law's s and s' and plane geometry, not
    camgen's pressure angle.  Kennedy's theorem: the common normal passes through the instant
    centre I of cam and follower, (sigma s', 0) for a follower moving along +y, -r P / (1 - r) on
    the line to the pivot P for an arm turning r = sigma tau s' times as fast as the cam.  A
    roller or knife: cos(alpha) (translating) or arm x cos(alpha) (oscillating), alpha between the
    normal through the roller centre (tip) C and C's velocity; an oscillating flat face: the
    contact's distance along the face from the pivot's foot, |(I - P) . J w|."""
    s, ds = law(theta)[:2]
    if f.motion == "translating":
        if f.kind == "flat":
            return np.ones_like(theta)
        normal = np.stack([f.offset - f.sigma * ds, math.sqrt(f.prime_radius**2 - f.offset**2) + s], axis=-1)  # C - I
        return np.abs(normal[:, 1]) / np.hypot(*normal.T)
    pivot = np.asarray(f.pivot)
    ratio = f.sigma * f.tau * ds
    instant = -ratio[:, None] * pivot / (1.0 - ratio)[:, None]
    angle = (rest_face_angle(f) if f.kind == "flat" else rest_arm_angle(f)) + f.tau * s
    u = np.stack([np.cos(angle), np.sin(angle)], axis=-1)  # the face normal w, or along the arm
    ju = np.stack([-u[:, 1], u[:, 0]], axis=-1)
    if f.kind == "flat":
        return np.abs(np.sum((instant - pivot) * ju, axis=1))
    normal = pivot + f.arm_length * u - instant
    return f.arm_length * np.abs(np.sum(normal * ju, axis=1)) / np.hypot(*normal.T)


def the_law(name: str, law: str):
    if law == "lift_table":
        angle, lift = table_rows(name)
        if oscillating(name):
            return LiftTable(angle, np.radians(lift), unit="rad")
        return LiftTable(angle, lift)
    return required_law(name, law == "constant_velocity")


def ride_angles(law, count: int) -> np.ndarray:
    brk = np.asarray(law.breaks)
    return np.concatenate([np.linspace(0.0, TWO_PI, count, endpoint=False) + D(0.137), brk + 1e-4, brk - 1e-4])


# --------------------------------------------------------------------------------------------
# The rides
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name, rotation, law", CASES)
def test_ride_on_the_exact_bspline_dxf(name, rotation, law):
    """<= 1e-6 mm (rad) riding the DXF's exact B-splines read back by ezdxf and scipy."""
    f = follower_spec(name, rotation)
    motion = the_law(name, law)
    cam = bspline_contour(exported("bspline")[f"{cam_name(name, rotation, law)}.dxf"])
    error = ride_error(f, cam, ride_angles(motion, 720), motion)
    assert np.max(error) <= EXACT_TOL
    if law == "constant_velocity":  # the corners the velocity jumps make are in the file
        assert "G0" in [j.continuity for j in cam.joints()]


@pytest.mark.parametrize("name, rotation, law", [c for c in CASES if c[2] != "lift_table"])
def test_ride_on_the_biarc_dxf_and_the_points_csv(name, rotation, law):
    """Within chord_tol_mm / lever riding the default DXF's ARCs and LINEs, and the points CSV as a polygon."""
    f = follower_spec(name, rotation)
    motion = the_law(name, law)
    theta = ride_angles(motion, 360)
    bound = CHORD_TOL / lever(f, motion, theta) * 1.01 + 1e-9
    cam = biarc_contour(exported("biarc")[f"{cam_name(name, rotation, law)}.dxf"])
    biarc = ride_error(f, cam, theta, motion)
    assert np.all(biarc <= bound), float(np.max(biarc / bound))
    points = csv_points(exported("bspline")[f"{cam_name(name, rotation, law)}_points.csv"])
    polygon = ride_error(f, points, theta, motion, polygon=True)
    assert np.all(polygon <= bound), float(np.max(polygon / bound))
    # and the tolerance is used, not a hundred times over-kept: the polygon's chords are felt
    assert np.max(polygon * lever(f, motion, theta)) > 0.05 * CHORD_TOL


@pytest.mark.parametrize("rotation", ROTATIONS)
@pytest.mark.parametrize("name", sorted(FOLLOWERS))
def test_zero_layer_marks_cam_angle_0_and_the_rotation(name, rotation):
    """The ZERO layer: a LINE from the axis to the point the follower touches at cam angle 0 (found
    by the ride on the exact B-splines), and an arrow about the axis pointing the way the cam turns."""
    f = follower_spec(name, rotation)
    text = exported("bspline")[f"{cam_name(name, rotation, 'every_law')}.dxf"]
    cam = bspline_contour(text)
    _, t = followers_ride(f, cam, np.zeros(1), return_param=True)
    contact = cam.evaluate(t)[0]
    entities = [e for e in _read(text).modelspace() if e.dxf.layer == "ZERO"]
    lines = [(np.array(e.dxf.start)[:2], np.array(e.dxf.end)[:2]) for e in entities if e.dxftype() == "LINE"]
    arcs = [e for e in entities if e.dxftype() == "ARC"]
    assert len(arcs) == 1 and len(lines) == 3
    radial = [(a, b) for a, b in lines if np.hypot(*a) == 0.0]
    assert len(radial) == 1 and np.hypot(*(radial[0][1] - contact)) <= 1e-6
    # the arrow head: two LINEs meeting at the arc's end in the direction of rotation
    tips = [b for a, b in lines if np.hypot(*a) > 0.0]
    assert np.hypot(*(tips[0] - tips[1])) == 0.0
    zero = math.atan2(contact[1], contact[0])
    tip = math.atan2(tips[0][1], tips[0][0])
    turn = math.remainder(tip - zero, TWO_PI)
    assert math.copysign(1.0, turn) == f.sigma and abs(abs(turn) - D(40)) <= 1e-9
    arc = arcs[0].dxf
    ends = {round(math.remainder(math.radians(a) - zero, TWO_PI), 9) for a in (arc.start_angle, arc.end_angle)}
    assert ends == {0.0, round(f.sigma * D(40), 9)}  # the arc runs from the zero line to the tip


class _Curve:
    """A clamped cubic B-spline (x, y) from a DXF SPLINE as scipy piecewise polynomials, with derivatives."""

    def __init__(self, knots: np.ndarray, ctrl: np.ndarray) -> None:
        from scipy.interpolate import BSpline, PPoly

        self.parts = [PPoly.from_spline(BSpline(knots, ctrl[:, k], 3)) for k in range(2)]
        self.lo, self.hi = float(knots[0]), float(knots[-1])

    def __call__(self, u: np.ndarray, order: int = 0) -> np.ndarray:
        return np.stack([(p.derivative(order) if order else p)(u) for p in self.parts], axis=-1)

    def derivative(self, order: int):
        return lambda u: self(u, order)


def test_pitch_layer_of_an_oscillating_roller_is_its_centre_path():
    """The PITCH layer (exact B-splines) holds the roller centre at every cam angle: the arm's end
    at the required swing, turned into the cam frame."""
    name, rotation = "osc_roller", "cw"
    f = follower_spec(name, rotation)
    motion = required_law(name)
    doc = _read(exported("bspline")[f"{cam_name(name, rotation, 'every_law')}.dxf"])
    splines = [_Curve(np.array(e.knots), np.array(e.control_points)[:, :2]) for e in doc.modelspace() if e.dxf.layer == "PITCH"]
    assert splines
    theta = np.linspace(0.0, TWO_PI, 2000, endpoint=False)
    g = rest_arm_angle(f) + f.tau * motion(theta)[0]
    centre = np.asarray(f.pivot) + f.arm_length * np.stack([np.cos(g), np.sin(g)], axis=1)
    c, s = np.cos(-f.sigma * theta), np.sin(-f.sigma * theta)
    wanted = np.stack([c * centre[:, 0] - s * centre[:, 1], s * centre[:, 0] + c * centre[:, 1]], axis=1)
    best = np.full(theta.size, np.inf)
    for spline in splines:  # nearest point of each spline: dense samples, then Newton on |B(u) - q|^2
        lo, hi = spline.lo, spline.hi
        u = np.linspace(lo, hi, 4000)
        pts = spline(u)
        near = np.argmin(np.hypot(pts[None, :, 0] - wanted[:, None, 0], pts[None, :, 1] - wanted[:, None, 1]), axis=1)
        x = u[near]
        d1, d2 = spline.derivative(1), spline.derivative(2)
        for _ in range(8):
            r = spline(x) - wanted
            g1 = np.sum(r * d1(x), axis=1)
            g2 = np.sum(d1(x) ** 2, axis=1) + np.sum(r * d2(x), axis=1)
            x = np.clip(x - g1 / g2, lo, hi)
        best = np.minimum(best, np.hypot(*(spline(x) - wanted).T))
    assert np.max(best) <= 1e-6


def test_step_and_mesh_of_a_disk_cam_with_g1_joints(tmp_path):
    """A cam of several spline segments joined G1 (a harmonic rise: the acceleration steps) exports
    to STEP (OpenCASCADE reads back one solid of the exact volume) and to a watertight STL whose
    volume is within the chord tolerance of the exact area x thickness (trimesh)."""
    import trimesh

    from camgen.export.step import step_volume
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    segments = [{"law": "simple_harmonic", "span_deg": 120.0, "lift_mm": 15.0}, {"law": "dwell", "span_deg": 60.0},
                {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -15.0}, {"law": "dwell", "span_deg": 60.0}]
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "follower_offset_mm": 5.0, "rotation": "cw",
           "thickness_mm": 6.0, "segments": segments}
    scene = parse_scene({"output": {"formats": ["step", "stl"]}, "cams": {"c": cam}}, "s")
    result = execute(scene, plan_run(scene))
    built = result.cams[0]
    assert [j.continuity for j in built.contour.joints()].count("G1") == 2  # the harmonic rise's ends
    exact = built.contour.area * 6.0
    assert step_volume(result.files["c.step"]) == pytest.approx(exact, rel=1e-4)  # OCCT integrates B-spline faces approximately
    path = tmp_path / "c.stl"
    path.write_bytes(result.files["c.stl"])
    mesh = trimesh.load(path, force="mesh")
    assert mesh.is_watertight and mesh.body_count == 1
    assert abs(mesh.volume - exact) <= built.contour.length * CHORD_TOL * 6.0 + 1e-6 * exact  # float32 STL
