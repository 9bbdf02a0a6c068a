"""A barrel cam's dimensioned drawing (SVG, PDF) and inspection table (CSV), issue 27 item 4.

Every number comes from outside camgen's barrel code (tests/test_barrel_form.py's cam: a groove
10 mm deep in a cylinder of radius 55 mm, mean radius R_m = 50 mm, a translating roller of
8 mm radius and 0.05 mm clearance, Norton's cycloidal rise of 40 mm over 120 deg, dwell, return,
dwell; the roller axis at lift 0 at z0 = (length - 40) / 2, the scene's default):

* the table: the roller axis' height ``z0 + s(theta)`` and the lift ``s(theta)`` of the closed-form
  law (an oscillating follower: the arm angle ``psi0 + s``, ``psi0 = -swing / 2``, in degrees);
* the SVG read by svgelements: the developed pitch curve back in part mm is ``(R_m phi, z0 +
  s(-sigma phi))`` within the chord tolerance; in the dwells the walls are ``z_c +- w`` (``w = Rr +
  c / 2``: the roller's section there is a circle of radius w about its axis); the groove width's
  dimension line is 2 w long, the developed outline 2 pi R_m by the length, the side view's
  cylinder 2 R_o by the length and the bore's hidden lines its diameter apart;
* the PDF rendered by pdftoppm: a row through the side view crosses the cylinder's outline
  k 2 R_o (+ one wide line) apart, a row through the developed view its outline k 2 pi R_m (+ one
  thin line) apart, within 0.2 mm;
* a rib (12 mm wide, cylinder 90 mm long: z0 = (90 - 40) / 2): the same table (the pitch line's
  height); its faces in the dwells at ``z_c +- rib_width / 2`` (each roller's axis ``rib_width / 2
  + w`` from the pitch line, its section a circle of radius w), the width dimensioned 12 mm;
* an oscillating follower's rib (tests/test_barrel_rib_oscillating.py's: arm 60 mm, 20 deg swing,
  rib 10 mm): the arm angle in the table; the width dimensioned in the upper dwell, where the arm
  stands at psi = +10 deg, is the two rollers' gap along z: ``(rib_width + 2 w) cos(psi) - 2 w``
  (their axes ``rib_width + 2 w`` apart along the arm's normal);
* a checking roller other than w is refused naming output.inspection_roller_radius_mm; at 1:1 the drawing
  does not fit A3 (side view 110 mm + developed 314 mm at scale) and is refused naming
  output.drawing_scale and 1:2.
"""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

from test_barrel_drawing import ARM, SWING, oscillating
from test_barrel_form import CLEAR, DEPTH, H, R_O, RR, cam, cycloidal
from test_drawing import read_csv
from test_drawing_forms import _dark_runs, _page_paths, _render

R_M = R_O - DEPTH / 2
W = RR + CLEAR / 2
LENGTH, BORE = 80.0, 30.0
Z0 = (LENGTH - H) / 2
TOL = 0.01  # the scenes' chord tolerance (mm)
K = 0.5  # scale 1:2


def _run(table: dict, tmp_path, **output) -> dict:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    out = {"formats": ["drawing", "drawing_pdf", "inspection"], "chord_tol_mm": TOL, **output}
    if {"drawing", "drawing_pdf"} & set(out["formats"]):
        out.setdefault("drawing_scale", "1:2")
    scene = parse_scene(copy.deepcopy({"output": out, "cams": {"c": table}}), "barrel", source="barrel.toml", base_dir=tmp_path)
    return dict(execute(scene, plan_run(scene)).files)


@pytest.fixture(scope="module", params=["ccw", "cw"])
def files(request, tmp_path_factory):
    rotation = request.param
    return rotation, _run(cam(rotation=rotation, bore_diameter_mm=BORE), tmp_path_factory.mktemp(f"barrel_{rotation}"))


def test_inspection_table_is_the_roller_axis_height_of_the_closed_form_law(files):
    rotation, f = files
    text = f["c_inspection.csv"]
    assert text.split("\n")[0] == "cam_angle_deg,axial_position_mm,lift_mm"
    table = read_csv(text)
    assert np.allclose(table["cam_angle_deg"], 10.0 * np.arange(36), atol=1e-9, rtol=0)  # the default 10 deg step
    theta = np.radians(table["cam_angle_deg"])
    assert np.max(np.abs(table["lift_mm"] - cycloidal(theta))) <= 1e-8
    assert np.max(np.abs(table["axial_position_mm"] - (Z0 + cycloidal(theta)))) <= 1e-8
    meta = json.loads(f["report.json"])["tables"]["c_inspection.csv"]
    assert meta["plug_radius_mm"] == pytest.approx(W, abs=1e-12) and meta["lift_zero_axis_height_mm"] == pytest.approx(Z0)
    assert meta["rotation"] == rotation


def _developed(paths: dict[str, np.ndarray], name: str) -> np.ndarray:
    """A developed-view path back in part mm: x from the outline's left edge, z up from its bottom edge."""
    outline = paths["developed_outline"]
    left, bottom = float(outline[:, 0].min()), float(outline[:, 1].max())
    return np.column_stack([(paths[name][:, 0] - left) / K, (bottom - paths[name][:, 1]) / K])


def test_svg_developed_pitch_curve_and_walls_are_the_closed_form_at_scale(files, tmp_path):
    from scipy.spatial import cKDTree

    rotation, f = files
    sigma = 1 if rotation == "ccw" else -1
    svg = f["c_drawing.svg"]
    assert f"DEVELOPED AT MEAN RADIUS R = {R_M:.3f}" in svg and f"{2 * W:.3f} WIDE" in svg and f"{DEPTH:.3f} DEEP" in svg
    paths = _page_paths(svg, tmp_path)
    outline = paths["developed_outline"]
    assert float(np.ptp(outline[:, 0])) / K == pytest.approx(2 * math.pi * R_M, abs=1e-4)
    assert float(np.ptp(outline[:, 1])) / K == pytest.approx(LENGTH, abs=1e-4)
    slack = TOL + 2e-5 / K + 1e-4  # the chord tolerance, coordinates rounded to 1e-5 page mm, the reference's spacing
    phi = np.linspace(0.0, 2 * math.pi, 400_001)
    exact = np.column_stack([R_M * phi, Z0 + cycloidal(-sigma * phi)])
    drawn = _developed(paths, "pitch_curve")
    gap, _ = cKDTree(exact).query(drawn)
    assert gap.max() <= slack, gap.max()
    back, _ = cKDTree(drawn).query(exact[::100])
    assert back.max() <= 1.0  # the path covers the whole turn
    # the walls in the dwells (cam angles 120..180 and 300..360 deg: z_c = z0 + H, z0): z_c +- w
    for name, side in (("wall_upper", 1), ("wall_lower", -1)):
        wall = _developed(paths, name)
        theta = np.mod(-sigma * wall[:, 0] / R_M, 2 * math.pi)
        for lo, hi, z_c in ((125.0, 175.0, Z0 + H), (305.0, 355.0, Z0)):
            inside = (theta > math.radians(lo)) & (theta < math.radians(hi))
            assert inside.sum() > 10 and np.max(np.abs(wall[inside, 1] - (z_c + side * W))) <= slack, name
    assert float(np.ptp(paths["track_width"][:, 1])) / K == pytest.approx(2 * W, abs=1e-4)  # dimensioned in the upper dwell


def test_svg_side_view_cylinder_and_bore_at_scale(files, tmp_path):
    _, f = files
    svg = f["c_drawing.svg"]
    paths = _page_paths(svg, tmp_path)
    assert float(np.ptp(paths["cylinder"][:, 0])) / K == pytest.approx(2 * R_O, abs=1e-4)
    assert float(np.ptp(paths["cylinder"][:, 1])) / K == pytest.approx(LENGTH, abs=1e-4)
    gap = float(paths["bore_right"][:, 0].mean() - paths["bore_left"][:, 0].mean()) / K
    assert gap == pytest.approx(BORE, abs=1e-4)
    assert float(np.ptp(paths["bore"][:, 0])) / K == pytest.approx(BORE, abs=1e-4)  # the dimension line
    assert f"\u00d8{2 * R_O:.3f}" in svg and f"\u00d8{BORE:.3f} BORE" in svg and f">{LENGTH:.3f}<" in svg


def test_pdf_prints_the_cylinder_and_the_developed_turn_at_scale(files, tmp_path):
    """pdftoppm's rendering at 600 dpi: a row 5 mm above the bottom face (below the lower wall,
    z0 - w = 12 mm) crosses the cylinder's two sides (wide lines) and the developed outline's two
    ends (thin lines), each pair k times the part's size apart plus one line's width."""
    _, f = files
    dpi = 600
    paths = _page_paths(f["c_drawing.svg"], tmp_path)
    image = _render(f["c_drawing.pdf"], tmp_path, dpi)
    bottom = float(paths["developed_outline"][:, 1].max())
    row = image[int(round((bottom - K * 5.0) / 25.4 * dpi))]
    for name, size, line in (("cylinder", 2 * R_O, 0.5), ("developed_outline", 2 * math.pi * R_M, 0.25)):
        lo, hi = paths[name][:, 0].min() - 3.0, paths[name][:, 0].max() + 3.0
        dark = np.flatnonzero(row[int(lo / 25.4 * dpi):int(hi / 25.4 * dpi)])
        assert len(_dark_runs(row[int(lo / 25.4 * dpi):int(hi / 25.4 * dpi)])) >= 2
        measured = (dark.max() - dark.min() + 1) / dpi * 25.4
        assert measured == pytest.approx(K * size + line, abs=0.2), name


def test_oscillating_follower_table_is_the_arm_angle(tmp_path):
    from test_barrel_drawing import LENGTH_OSC

    files = _run(oscillating(), tmp_path, formats=["inspection", "drawing"])
    text = files["c_inspection.csv"]
    assert text.split("\n")[0] == "cam_angle_deg,arm_angle_deg,swing_deg"
    table = read_csv(text)
    theta = np.radians(table["cam_angle_deg"])
    swing = np.degrees(cycloidal(theta, math.radians(SWING)))
    assert np.max(np.abs(table["swing_deg"] - swing)) <= 1e-8
    assert np.max(np.abs(table["arm_angle_deg"] - (-SWING / 2 + swing))) <= 1e-8
    assert ARM > 0 and LENGTH_OSC > 0 and "ARM ANGLE" in files["c_drawing.svg"]


def test_refusals_name_their_keys(tmp_path):
    from camgen.errors import ParameterError

    with pytest.raises(ParameterError) as caught:
        _run(cam(), tmp_path, formats=["drawing"], drawing_scale="1:1")
    assert caught.value.name == "output.drawing_scale" and "1:2 or smaller" in str(caught.value)
    with pytest.raises(ParameterError) as caught:
        _run(cam(), tmp_path, formats=["inspection"], inspection_roller_radius_mm=RR)
    assert caught.value.name == "output.inspection_roller_radius_mm" and f"{W:g}" in str(caught.value)


RIB_W, RIB_LENGTH = 12.0, 90.0


def test_rib_table_faces_and_width(tmp_path):
    from scipy.spatial import cKDTree

    z0 = (RIB_LENGTH - H) / 2
    files = _run(cam(track="rib", rib_width_mm=RIB_W, cylinder_length_mm=RIB_LENGTH, min_wall_mm=2.0), tmp_path)
    table = read_csv(files["c_inspection.csv"])
    theta = np.radians(table["cam_angle_deg"])
    assert np.max(np.abs(table["axial_position_mm"] - (z0 + cycloidal(theta)))) <= 1e-8
    assert np.max(np.abs(table["lift_mm"] - cycloidal(theta))) <= 1e-8
    meta = json.loads(files["report.json"])["tables"]["c_inspection.csv"]
    assert meta["fork_spacing_mm"] == pytest.approx(RIB_W + 2 * W, abs=1e-12)
    svg = files["c_drawing.svg"]
    assert f"RIB DEVELOPED AT MEAN RADIUS R = {R_M:.3f}" in svg and f"RIB {RIB_W:.3f} WIDE" in svg
    paths = _page_paths(svg, tmp_path)
    slack = TOL + 2e-5 / K + 1e-4
    phi = np.linspace(0.0, 2 * math.pi, 400_001)
    gap, _ = cKDTree(np.column_stack([R_M * phi, z0 + cycloidal(-phi)])).query(_developed(paths, "pitch_curve"))
    assert gap.max() <= slack
    for name, side in (("rib_upper", 1), ("rib_lower", -1)):
        face = _developed(paths, name)
        theta = np.mod(-face[:, 0] / R_M, 2 * math.pi)
        for lo, hi, z_c in ((125.0, 175.0, z0 + H), (305.0, 355.0, z0)):
            inside = (theta > math.radians(lo)) & (theta < math.radians(hi))
            assert inside.sum() > 10 and np.max(np.abs(face[inside, 1] - (z_c + side * RIB_W / 2))) <= slack, name
    assert float(np.ptp(paths["track_width"][:, 1])) / K == pytest.approx(RIB_W, abs=1e-4)


def test_oscillating_rib_width_in_the_dwell_is_the_rollers_gap(tmp_path):
    from test_barrel_rib_oscillating import OSC_SWING, SCENE_W, osc_rib

    files = _run(osc_rib(), tmp_path, formats=["inspection", "drawing"])
    table = read_csv(files["c_inspection.csv"])
    swing = np.degrees(cycloidal(np.radians(table["cam_angle_deg"]), OSC_SWING))
    assert np.max(np.abs(table["arm_angle_deg"] - (-math.degrees(OSC_SWING) / 2 + swing))) <= 1e-8
    paths = _page_paths(files["c_drawing.svg"], tmp_path)
    psi = OSC_SWING / 2
    gap = (10.0 + 2 * SCENE_W) * math.cos(psi) - 2 * SCENE_W
    assert float(np.ptp(paths["track_width"][:, 1])) / K == pytest.approx(gap, abs=1e-4)
