"""The steering cam of paper 004 cut as a groove (form ``groove`` of the trajectory motion).

The reference is the paper, not camgen: the rod-centre distance at cam angle theta is
R = L + d L k / (1 + D k) (eq. 13 with rho + r_d, eq. 14 for Table 2: L = 77, D = 50, d = 30 mm),
k the path's curvature at the point reached after the arc length S theta / (2 pi), S the
period's arc length; here the path's derivatives are typed from its expression and the arc
length is a dense trapezoid sum, and the rod sits at polar angle -theta.  The groove's walls lie
w = r_d + c / 2 from that path on both sides; camgen writes them, ezdxf and scipy read them back:

* every reference rod centre is w from each exported wall (nearest point over the whole wall,
  polished by Newton steps), the inner wall inside it and the outer outside;
* a rod of radius w on the exported inner wall (its centre on the path) steers the tricycle
  along the path: DOP853 on the read-back B-spline (tests/test_tricycle.py's integrator) within
  the targets of the open cam;
* the walls can be made exactly while the path's convex radius exceeds w (inner wall) and its
  concave radius exceeds w (outer wall): the thresholds from the reference path's curvature by
  finite differences;
* rs274 runs the groove's program and a simulated cutter reaches both walls, gouging neither.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from helpers import require_tool
from test_disk_cams import bspline_contour
from test_groove import nearest_distance
from test_tricycle import _dop853_ride_on

L_MM, D_MM, LEVER_MM = 77.0, 50.0, 30.0  # Table 2
ROD = 1.5
CLEARANCE = 0.05
W = ROD + CLEARANCE / 2
PAPER = ((202.4396, math.pi / 1000),)  # y = sum a sin(k x): paper 004, eq. (15)
TWO_SINE = ((202.4396, math.pi / 1000), (150.0, 2 * math.pi / 1000))
PERIOD = 2000.0


def expression(terms) -> str:
    return " + ".join(f"{a}*sin({k * 1000 / math.pi:g}*pi*x/1000)" for a, k in terms)


def reference_path(terms, theta: np.ndarray) -> np.ndarray:
    """Rod centres (n, 2) mm at cam angles theta from the paper's eqs. (9)-(14), independent of camgen."""
    x = np.linspace(0.0, PERIOD, 2_000_001)
    slope = sum(a * k * np.cos(k * x) for a, k in terms)
    arc = np.concatenate([[0.0], np.cumsum(0.5 * (np.hypot(1, slope[1:]) + np.hypot(1, slope[:-1])) * np.diff(x))])
    xs = np.interp(np.mod(theta, 2 * math.pi) / (2 * math.pi) * arc[-1], arc, x)
    d1 = sum(a * k * np.cos(k * xs) for a, k in terms)
    d2 = sum(-a * k * k * np.sin(k * xs) for a, k in terms)
    kappa = d2 / (1 + d1 * d1) ** 1.5
    radius = L_MM + LEVER_MM * L_MM * kappa / (1 + D_MM * kappa)
    return radius[:, None] * np.stack([np.cos(-theta), np.sin(-theta)], axis=1)


def path_radii(terms) -> tuple[float, float]:
    """Smallest convex and concave radii of curvature (mm) of the reference rod-centre path
    (central differences on 400k points)."""
    theta = np.linspace(0, 2 * math.pi, 400_000, endpoint=False)
    p = reference_path(terms, theta)
    d1 = (np.roll(p, -1, axis=0) - np.roll(p, 1, axis=0)) / 2
    d2 = np.roll(p, -1, axis=0) - 2 * p + np.roll(p, 1, axis=0)
    # the path runs clockwise in theta (polar angle -theta): convex where the cross product is negative
    kappa = -(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.hypot(*d1.T) ** 3
    convex = 1 / kappa.max()
    concave = -1 / kappa.min() if kappa.min() < 0 else math.inf
    return float(convex), float(concave)


def run(tmp_path: Path, terms=PAPER, formats=("dxf",), **keys) -> tuple[int, str, Path]:
    from camgen.cli import main

    cam = {"kind": "trajectory", "form": "groove", "expression": expression(terms), "period_mm": PERIOD, "rod_radius_mm": ROD,
           "groove_clearance_mm": CLEARANCE, "thickness_mm": 8.0, "bore_diameter_mm": 8.0, "min_wall_mm": 3.0, **keys}
    def value(v):
        return json.dumps(v) if isinstance(v, (str, list)) else repr(v)

    output = {"formats": list(formats), "chord_tol_mm": 0.001, **({"dxf_splines": "bspline"} if "dxf" in formats else {})}
    tables = {"output": output, "cams.steering": cam}
    if "ngc" in formats:  # a cutter as wide as the groove: one pass along the rod-centre path
        tables["machining"] = {"tool_diameter_mm": 2 * cam["rod_radius_mm"] + cam["groove_clearance_mm"], "step_down_mm": 2.0}
    path = tmp_path / "scene.toml"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("".join(f"[{name}]\n" + "".join(f"{k} = {value(v)}\n" for k, v in table.items()) for name, table in tables.items()))
    status = main(["run", str(path), "-o", str(tmp_path / "out"), "--quiet"])
    return status, "", tmp_path / "out" / "scene"


@pytest.fixture(scope="module")
def paper_groove(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("groove")
    status, _, out = run(tmp, formats=("dxf", "ngc"))
    assert status == 0
    text = (out / "steering.dxf").read_text()
    return {"inner": bspline_contour(text, "GROOVE_INNER"), "outer": bspline_contour(text, "GROOVE_OUTER"), "dxf": text,
            "ngc": (out / "steering.ngc").read_text(), "report": json.loads((out / "report.json").read_text())}


def test_every_rod_centre_of_the_paper_is_w_from_both_exported_walls(paper_groove):
    theta = np.concatenate([2 * math.pi * np.arange(720) / 720, np.linspace(0, 2 * math.pi, 997, endpoint=False) + 0.0013])
    centres = reference_path(PAPER, theta)
    for wall in ("inner", "outer"):
        gap = nearest_distance(paper_groove[wall], centres)
        assert np.max(np.abs(gap - W)) <= 1e-6, (wall, np.max(np.abs(gap - W)))
    # the inner wall inside the path, the outer outside: polar radii along each centre's ray
    for wall, sign in (("inner", -1), ("outer", 1)):
        poly = paper_groove[wall].flatten(1e-5)
        ang = np.mod(np.arctan2(poly[:, 1], poly[:, 0]), 2 * math.pi)
        order = np.argsort(ang)
        radius = np.interp(np.mod(-theta, 2 * math.pi), ang[order], np.hypot(*poly[order].T), period=2 * math.pi)
        assert np.all(sign * (radius - np.hypot(*centres.T)) > 0.9 * W), wall


def test_a_rod_of_radius_w_on_the_exported_inner_wall_steers_along_the_path(paper_groove):
    """The groove's centre line is the open cam's rod-centre path: the ride meets the open cam's
    targets (tests/test_tricycle.py: 2e-8 mm over one period, 1e-6 mm over ten), by DOP853 on
    the read-back inner wall with the rod's centre w from it."""
    import ezdxf
    import io

    doc = ezdxf.read(io.StringIO(paper_groove["dxf"]))
    (spline,) = [e for e in doc.modelspace() if e.dxf.layer == "GROOVE_INNER"]
    one, ten = _dop853_ride_on(np.array(spline.knots), np.array(spline.control_points)[:, :2], rod_radius=W)
    assert one <= 2e-8 and ten <= 1e-6, (one, ten)
    figures = paper_groove["report"]["cams"]["steering"]["figures"]
    assert figures["ride_max_error_mm"] == pytest.approx(one, abs=2e-8)


def test_the_steering_play_is_the_clearance_over_the_lever_at_the_paper_radii(paper_groove):
    """The rod's centre lies within c / 2 of the path: the steering angle atan((R - L) / d)
    (eq. 1) moves by at most this much; R from eq. (14) at the 720 samples."""
    radius = np.hypot(*reference_path(PAPER, 2 * math.pi * np.arange(720) / 720).T)
    alpha = np.arctan((radius - L_MM) / LEVER_MM)
    play = max(np.max(np.abs(np.arctan((radius + s * CLEARANCE / 2 - L_MM) / LEVER_MM) - alpha)) for s in (-1, 1))
    groove = paper_groove["report"]["cams"]["steering"]["figures"]["groove"]
    assert groove["steering_play_deg"] == pytest.approx(math.degrees(play), rel=1e-6)
    assert groove["width_mm"] == pytest.approx(2 * W) and groove["wall_offset_mm"] == pytest.approx(W)


@pytest.mark.parametrize("terms, rod, which", [(TWO_SINE, 2.0, "outer"), (PAPER, 70.0, "inner")])
def test_the_walls_can_be_made_while_the_path_turns_wider_than_w(terms, rod, which, tmp_path):
    """The outer wall needs the path's concave radius above w, the inner its convex radius: with
    w 0.01 mm below the reference threshold the groove is made (exit 0), 0.01 mm above it is not
    (exit 1, the undercut check failing on that wall, no drawing written); the open cam with the
    same rod is made either way."""
    convex, concave = path_radii(terms)
    threshold = concave if which == "outer" else convex
    keys = {"rod_radius_mm": rod, "bore_diameter_mm": 0.0, "min_wall_mm": 0.0, "pressure_angle_limit_deg": 89.0,
            "samples": 5000}  # the synthesis resolves the sharp turns: its path within microns of the reference
    made, _, out_made = run(tmp_path / "below", terms, groove_clearance_mm=2 * (threshold - 0.01 - rod), **keys)
    failed, _, out_failed = run(tmp_path / "above", terms, groove_clearance_mm=2 * (threshold + 0.01 - rod), **keys)
    assert made == 0 and (out_made / "steering.dxf").exists()
    assert failed == 1 and not (out_failed / "steering.dxf").exists()
    checks = {c["name"]: c for c in json.loads((out_failed / "report.json").read_text())["cams"]["steering"]["checks"]}
    assert checks["undercut"]["status"] == "fail" and f"{which} wall (GROOVE_{which.upper()})" in checks["undercut"]["note"]
    assert checks["undercut"]["value"] == pytest.approx(threshold, abs=2e-3)


@pytest.mark.usefixtures("needs_rs274")
def test_rs274_runs_the_groove_program_and_the_cutter_reaches_both_walls_gouging_neither(paper_groove, tmp_path):
    from cutting import CUT_TOL, simulate_pockets

    from camgen.contour import Arc, Contour

    rim = paper_groove["report"]["cams"]["steering"]["figures"]["groove"]["rim_radius_mm"]
    walls = {"GROOVE_OUTER": paper_groove["outer"], "GROOVE_INNER": paper_groove["inner"]}
    report = simulate_pockets(paper_groove["ngc"], Contour([Arc((0.0, 0.0), rim, 0.0, 2 * math.pi)]), walls, W, tmp_path)
    assert report.outline.status == 0, report.outline.message
    assert "one pass along the pitch curve" in paper_groove["ngc"]
    for layer in walls:
        assert report.pocket.gouge[layer] <= CUT_TOL and report.pocket.proud[layer] <= CUT_TOL, layer


@pytest.fixture
def needs_rs274():
    return require_tool("rs274")


@pytest.mark.parametrize("keys, key", [
    ({"groove_depth_mm": 8.0}, "groove_depth_mm"),
    ({"rod_radius_mm": 40.0, "groove_clearance_mm": 80.0}, "groove_clearance_mm"),
])
def test_bad_groove_input_is_refused_naming_the_key(keys, key, tmp_path, capsys):
    status, _, out = run(tmp_path, **keys)
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and err[0].startswith("camgen: error:") and f"cams.steering.{key}" in err[0], err
    assert not out.exists() or not any(out.iterdir())


def test_a_rim_too_close_to_the_outer_wall_fails_its_check_at_the_threshold(paper_groove, tmp_path):
    """The rim's wall: rim radius less the outer wall's largest radius (the read-back wall,
    densely sampled) against min_wall_mm."""
    reach = float(np.max(np.hypot(*paper_groove["outer"].flatten(1e-6).T)))

    for rim, expected in ((reach + 3.0 + 0.01, 0), (reach + 3.0 - 0.01, 1)):
        status, _, out = run(tmp_path / f"{rim:.3f}", rim_radius_mm=rim)
        checks = {c["name"]: c for c in json.loads((out / "report.json").read_text())["cams"]["steering"]["checks"]}
        assert status == expected and checks["rim_wall"]["value"] == pytest.approx(rim - reach, abs=2e-4), (rim, checks["rim_wall"])
