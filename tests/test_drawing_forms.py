"""The manufacturing drawing and inspection table of the other cam forms (issue 27 item 4, leftovers).

Every number comes from the closed-form law and follower geometry of tests/test_drawing.py (an
in-line translating roller follower, cycloidal rise and return: its pitch curve is at
``RB + RR + s(theta)`` on the ray at polar angle ``90 deg - theta``):

* groove cam: its walls are the pitch curve's parallels at +- half the groove width
  ``w = 2 RR + c`` (the roller widened by half the clearance on each side); the SVG's two wall
  paths read by svgelements lie within the chord tolerance of them; the inspection table's plug of
  the groove's width rests on both walls, its centre on the pitch curve: ``RB + RR + s``; the PDF
  rendered by pdftoppm: the rim and both walls cross a column of the page where the closed form
  puts them at scale, within 0.2 mm;
* conjugate pair: cam B's roller rides ``D`` below roller A on the stem, so its inspection table
  (the ray through its zero mark, straight down) reads ``D - (RB + RR + s)``, and cam A's the plate
  cam's; each cam has its own drawing;
* constant breadth: the yoke's breadth ``B = 2 base + C`` (the scene's rule): the drawn dimension
  line is B long at scale in the SVG, the two extension lines B apart on the rendered PDF;
* linear cam (tests/test_linear_cam.py's cycloidal program, translating roller): the table is
  the closed-form lift against x; the SVG's length and height dimension lines are the plate's
  (margins + travel; below the pitch line + the dwell's lift less the roller) and its edge the
  roller's exact envelope within the chord tolerance; the PDF's plate is its length at scale;
  an oscillating follower's table is its swing against x;
* barrel cams: tests/test_barrel_sheet.py (a rib's drawing and table refused naming output.formats).
"""
from __future__ import annotations

import copy
import math
import subprocess

import numpy as np
import pytest

from helpers import require_tool
from test_drawing import CAM, RB, RR, lift, parallel, read_csv

CLEARANCE, DEPTH, RIM = 0.05, 5.0, 86.0
HALF = RR + CLEARANCE / 2  # half the groove's width
D = 150.0  # conjugate: roller B's centre below roller A's along the stem
TOL = 0.01  # the scenes' chord tolerance (mm)


def _run(cams: dict, tmp_path, **output) -> dict:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    table = {"output": {"formats": ["drawing", "drawing_pdf", "inspection"], "chord_tol_mm": TOL, **output}, "cams": cams}
    scene = parse_scene(copy.deepcopy(table), "forms", source="forms.toml", base_dir=tmp_path)
    return dict(execute(scene, plan_run(scene)).files)


GROOVE = dict(CAM, form="groove", groove_clearance_mm=CLEARANCE, groove_depth_mm=DEPTH, rim_radius_mm=RIM)


@pytest.fixture(scope="module")
def groove_files(tmp_path_factory):
    return _run({"g": GROOVE}, tmp_path_factory.mktemp("groove"), drawing_scale="1:2")


def _svg_paths(svg_text: str, tmp_path, scale: float) -> tuple[dict[str, np.ndarray], float, float]:
    """Every named path read by svgelements (vertices and chord midpoints), in part mm (cam frame),
    and the axis on the page (mm): where the centre lines cross."""
    from svgelements import SVG, Path

    name = tmp_path / "d.svg"
    name.write_text(svg_text)
    doc = SVG.parse(str(name))
    per_mm = doc.width / float(doc.values["width"].removesuffix("mm"))

    def points(path) -> np.ndarray:
        out = []
        for seg in path.segments():
            if seg.end is None or type(seg).__name__ == "Move":
                continue
            out.extend(seg.point(t) for t in (0.0, 0.5, 1.0))
        return np.array([[p.x, p.y] for p in out]) / per_mm

    page = {e.id: points(e) for e in doc.elements() if isinstance(e, Path) and e.id}
    cx, cy = page["centre_y"][:, 0].mean(), page["centre_x"][:, 1].mean()
    part = {k: np.column_stack([(v[:, 0] - cx) / scale, (cy - v[:, 1]) / scale]) for k, v in page.items()}
    return part, float(cx), float(cy)


def test_groove_inspection_is_the_pitch_curve_read_by_a_plug_of_the_grooves_width(groove_files):
    import json

    table = read_csv(groove_files["g_inspection.csv"])
    theta = np.radians(table["cam_angle_deg"])
    assert np.allclose(table["polar_angle_deg"], np.mod(90.0 - table["cam_angle_deg"], 360.0), atol=1e-9)
    assert np.max(np.abs(table["centre_radius_mm"] - (RB + RR + lift(theta)))) <= 1e-6
    # the lift above the plug's lowest centre: the inner wall's base circle (RB - c/2 on the dwell) plus the plug's radius
    assert np.max(np.abs(table["lift_mm"] - lift(theta))) <= 1e-6
    meta = json.loads(groove_files["report.json"])["tables"]["g_inspection.csv"]
    assert meta["roller_radius_mm"] == pytest.approx(HALF, abs=1e-12)


def test_groove_walls_in_the_svg_are_the_exact_walls_at_scale(groove_files, tmp_path):
    from scipy.spatial import cKDTree

    svg = groove_files["g_drawing.svg"]
    assert f"GROOVE {2 * HALF:.3f} WIDE, {DEPTH:.3f} DEEP" in svg
    paths, _, _ = _svg_paths(svg, tmp_path, 0.5)
    theta = np.linspace(0.0, 2 * math.pi, 400_001)
    for name, d in (("groove_outer", HALF), ("groove_inner", -HALF), ("centre_line", 0.0)):
        exact = parallel(theta, d)
        gap, _ = cKDTree(exact).query(paths[name])
        assert gap.max() <= TOL + 2e-5 / 0.5 + 2e-6, (name, gap.max())  # chord tolerance, coordinates rounded to 1e-5 page mm
        back, _ = cKDTree(paths[name]).query(exact[::50])
        assert back.max() <= 1.0, name  # the path covers the whole wall
    rim = np.hypot(*paths["profile"].T)
    assert np.all(np.abs(rim - RIM) <= TOL + 1e-4)  # the outline: the rim circle


def _dark_runs(column: np.ndarray) -> np.ndarray:
    """Centres (pixel index) of the runs of dark pixels of a column."""
    idx = np.flatnonzero(column)
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    return np.array([r.mean() for r in runs if r.size])


def _render(pdf: bytes, tmp_path, dpi: int = 600) -> np.ndarray:
    from PIL import Image

    pdftoppm = require_tool("pdftoppm")
    (tmp_path / "d.pdf").write_bytes(pdf)
    subprocess.run([pdftoppm, "-r", str(dpi), "-gray", "-singlefile", str(tmp_path / "d.pdf"), str(tmp_path / "d")], check=True)
    return np.asarray(Image.open(tmp_path / "d.pgm").convert("L")) < 128


def test_groove_pdf_shows_rim_and_walls_where_they_are_at_scale(groove_files, tmp_path):
    dpi, k, x_cut = 600, 0.5, 3.0
    image = _render(groove_files["g_drawing.pdf"], tmp_path, dpi)
    _, cx, cy = _svg_paths(groove_files["g_drawing.svg"], tmp_path, k)
    column = image[:, int(round((cx + k * x_cut) / 25.4 * dpi))]
    centres = _dark_runs(column) / dpi * 25.4  # page mm
    theta = np.linspace(0.0, 2 * math.pi, 400_001)

    def top_crossing(curve: np.ndarray) -> float:
        i = np.flatnonzero(np.sign(curve[:-1, 0] - x_cut) != np.sign(curve[1:, 0] - x_cut))
        w = (x_cut - curve[i, 0]) / (curve[i + 1, 0] - curve[i, 0])
        return float(np.max(curve[i, 1] + w * (curve[i + 1, 1] - curve[i, 1])))

    expected = {"rim": math.sqrt(RIM**2 - x_cut**2), "outer wall": top_crossing(parallel(theta, HALF)),
                "inner wall": top_crossing(parallel(theta, -HALF))}
    for what, y in expected.items():
        nearest = float(np.min(np.abs(centres - (cy - k * y))))  # the page's y is down
        assert nearest <= 0.2, (what, nearest)
    # the groove's width across this column, on the page: the two walls' lines k w apart (less the slant)
    gap = expected["outer wall"] - expected["inner wall"]
    walls = [float(centres[np.argmin(np.abs(centres - (cy - k * expected[w])))]) for w in ("outer wall", "inner wall")]
    assert walls[1] - walls[0] == pytest.approx(k * gap, abs=0.2)


def test_groove_inspection_refuses_another_roller(tmp_path):
    from camgen.errors import ParameterError

    with pytest.raises(ParameterError) as caught:
        _run({"g": GROOVE}, tmp_path, formats=["inspection"], inspection_roller_radius_mm=4.0)
    assert caught.value.name == "output.inspection_roller_radius_mm" and "groove" in str(caught.value)


def test_conjugate_pair_each_cam_its_drawing_and_table(tmp_path):
    cam = dict(CAM, form="conjugate", roller_b_distance_mm=D, conjugate_preload_mm=0.0, follower_offset_mm=0.0)
    files = _run({"p": cam}, tmp_path, drawing_scale="1:2")
    assert {"p_a_drawing.svg", "p_b_drawing.svg", "p_a_drawing.pdf", "p_b_drawing.pdf"} <= set(files)
    a, b = read_csv(files["p_a_inspection.csv"]), read_csv(files["p_b_inspection.csv"])
    theta = np.radians(a["cam_angle_deg"])
    assert np.max(np.abs(a["centre_radius_mm"] - (RB + RR + lift(theta)))) <= 1e-6
    assert np.allclose(b["polar_angle_deg"], np.mod(270.0 - b["cam_angle_deg"], 360.0), atol=1e-9)  # its zero mark: straight down
    assert np.max(np.abs(b["centre_radius_mm"] - (D - (RB + RR + lift(theta))))) <= 1e-6
    for name in ("p_a", "p_b"):
        assert f"CONJUGATE CAM {name}" in files[f"{name}_drawing.svg"]


YOKE = {"kind": "motion_law", "form": "constant_breadth", "follower": "yoke", "half_turn": True, "base_radius_mm": 40.0,
        "face_half_length_mm": 30.0, "thickness_mm": 10.0, "bore_diameter_mm": 16.0,
        "segments": [{"law": "dwell", "span_deg": 30.0}, {"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0},
                     {"law": "dwell", "span_deg": 30.0}]}
BREADTH = 2 * 40.0 + 20.0  # B = 2 base + C, C = s(0) + s(180 deg) = 0 + 20 (the form's rule)


def test_constant_breadth_dimension_at_scale_in_svg_and_pdf(tmp_path):
    for scale, k in (("1:1", 1.0), ("1:2", 0.5)):
        files = _run({"y": YOKE}, tmp_path, drawing_scale=scale)
        svg = files["y_drawing.svg"]
        assert f"BREADTH {BREADTH:.3f} IN EVERY DIRECTION" in svg
        paths, cx, cy = _svg_paths(svg, tmp_path, k)
        line = paths["breadth"]
        assert float(np.ptp(line[:, 0])) == pytest.approx(BREADTH, abs=TOL + 1e-4)  # the dimension line, back in part mm
        # the PDF: a row between the profile's bottom and the dimension line crosses only the two extension lines
        dpi = 600
        image = _render(files["y_drawing.pdf"], tmp_path, dpi)
        y_row = cy - k * float(np.mean(line[:, 1])) - 2.0  # 2 mm above the dimension line on the page
        row = image[int(round(y_row / 25.4 * dpi))]
        ext = (cx + k * np.array([-0.6, 0.6]) * BREADTH) / 25.4 * dpi
        dark = np.flatnonzero(row[int(ext[0]):int(ext[1])])
        outer = (dark.max() - dark.min() + 1) / dpi * 25.4
        assert outer == pytest.approx(k * BREADTH + 0.25, abs=0.2)  # the lines' outer edges: k B + one thin line's width


# ----------------------------------------------------------------------------------- linear cam
def _page_paths(svg_text: str, tmp_path) -> dict[str, np.ndarray]:
    """Every named path of the SVG read by svgelements: its points (segment ends and midpoints), page mm."""
    from svgelements import SVG, Path

    name = tmp_path / "l.svg"
    name.write_text(svg_text)
    doc = SVG.parse(str(name))
    per_mm = doc.width / float(doc.values["width"].removesuffix("mm"))
    out = {}
    for e in doc.elements():
        if isinstance(e, Path) and e.id:
            pts = [seg.point(t) for seg in e.segments() if seg.end is not None and type(seg).__name__ != "Move" for t in (0.0, 0.5, 1.0)]
            out[e.id] = np.array([[p.x, p.y] for p in pts]) / per_mm
    return out


@pytest.fixture(scope="module")
def linear_files(tmp_path_factory):
    from test_linear_cam import _cam

    return _run({"l": _cam()}, tmp_path_factory.mktemp("linear"), drawing_scale="1:2")


def test_linear_inspection_is_the_lift_against_x(linear_files):
    """The travel in 36 equal steps (the default 10 deg of a turn), both ends: the roller's centre
    at the lift of the closed-form program (Norton's cycloidal rise and return)."""
    import json

    from test_linear_cam import TRAVEL, cycloidal_lift

    table = read_csv(linear_files["l_inspection.csv"])
    assert np.allclose(table["x_mm"], TRAVEL * np.arange(37) / 36, atol=1e-9, rtol=0)
    assert np.max(np.abs(table["lift_mm"] - cycloidal_lift(table["x_mm"]))) <= 2e-9
    meta = json.loads(linear_files["report.json"])["tables"]["l_inspection.csv"]
    assert meta["roller_radius_mm"] == 10.0 and meta["x_step_mm"] == pytest.approx(TRAVEL / 36)


def test_linear_svg_plate_dimensions_and_edge_at_scale(linear_files, tmp_path):
    """The dimension lines are the plate's length (margins + travel) and height (below the pitch
    line + the edge's top: the dwell's lift less the roller) at scale; the drawn edge lies within
    the chord tolerance of the roller's exact envelope (the pitch curve (x, s(x)) offset by -r)."""
    from scipy.spatial import cKDTree

    from test_linear_cam import H, R, TRAVEL, cycloidal_lift

    k = 0.5
    svg = linear_files["l_drawing.svg"]
    paths = _page_paths(svg, tmp_path)
    assert float(np.ptp(paths["length"][:, 0])) / k == pytest.approx(30.0 + TRAVEL + 30.0, abs=TOL + 1e-4)
    assert float(np.ptp(paths["height"][:, 1])) / k == pytest.approx(45.0 + H - R, abs=TOL + 1e-4)
    # the part frame on the page: x = 0 from the x_zero line, y = 0 from the pitch line
    x0, y0 = float(paths["x_zero"][:, 0].mean()), float(paths["pitch_line"][:, 1].mean())
    drawn = np.column_stack([(paths["profile"][:, 0] - x0) / k, (y0 - paths["profile"][:, 1]) / k])
    top = drawn[(drawn[:, 0] > 5.0) & (drawn[:, 0] < TRAVEL - 5.0) & (drawn[:, 1] > -20.0)]
    x = np.linspace(-10.0, TRAVEL + 10.0, 400_001)
    s = cycloidal_lift(x)
    ds = np.gradient(s, x)
    exact = np.column_stack([x + R * ds / np.hypot(1.0, ds), s - R / np.hypot(1.0, ds)])  # C - r n, n = (-s', 1) / |.|
    gap, _ = cKDTree(exact).query(top)
    assert top.shape[0] > 100 and gap.max() <= TOL + 2e-5 / k + 1e-4, gap.max()  # + the closed form's finite-difference slope


def test_linear_pdf_plate_length_at_scale(linear_files, tmp_path):
    """pdftoppm's rendering: a row through the plate's body crosses its two ends k L + one wide line apart."""
    from test_linear_cam import TRAVEL

    k, dpi = 0.5, 600
    paths = _page_paths(linear_files["l_drawing.svg"], tmp_path)
    image = _render(linear_files["l_drawing.pdf"], tmp_path, dpi)
    y0 = float(paths["pitch_line"][:, 1].mean())
    row = image[int(round((y0 + k * 30.0) / 25.4 * dpi))]  # 30 mm below the pitch line on the part
    left, right = paths["profile"][:, 0].min() - 3.0, paths["profile"][:, 0].max() + 3.0  # a window: the plate, not the dimensions
    lo, hi = int(left / 25.4 * dpi), int(right / 25.4 * dpi)
    dark = np.flatnonzero(row[lo:hi])
    measured = (dark.max() - dark.min() + 1) / dpi * 25.4
    assert measured == pytest.approx(k * (30.0 + TRAVEL + 30.0) + 0.5, abs=0.2)


def test_linear_oscillating_follower_table_is_the_swing_against_x(tmp_path):
    """An arm pivoted at (90, 40) mm swinging 12 deg by the cycloidal program (tests/test_linear_cam.py):
    the table's swing is the closed-form program in degrees; the drawing is written."""
    from test_linear_cam import TRAVEL, _cam, _segments, cycloidal_lift

    cam = _cam(follower_motion="oscillating", pivot_x_mm=90.0, pivot_y_mm=40.0, swing_turn="cw", segments=_segments(swing=True))
    files = _run({"o": cam}, tmp_path, drawing_scale="1:2", formats=["inspection", "drawing"])
    table = read_csv(files["o_inspection.csv"])
    assert list(table) == ["x_mm", "swing_deg"]
    assert np.allclose(table["x_mm"], TRAVEL * np.arange(37) / 36, atol=1e-9, rtol=0)
    assert np.max(np.abs(table["swing_deg"] - cycloidal_lift(table["x_mm"], 12.0))) <= 2e-9
    assert "SWING" in files["o_drawing.svg"]


def test_linear_slot_wall_at_scale(tmp_path):
    """A slot cam (tests/test_linear_cam.py's): the drawn slot wall is the closed-form slot boundary
    (the pitch graph's offsets by the half width and the end half circles) within the chord
    tolerance; the height dimension is below + above the pitch line."""
    from scipy.spatial import cKDTree

    from test_linear_cam import SLOT_ABOVE, _slot_cam, exact_slot

    k = 0.5
    files = _run({"s": _slot_cam()}, tmp_path, drawing_scale="1:2", formats=["drawing"])
    paths = _page_paths(files["s_drawing.svg"], tmp_path)
    assert float(np.ptp(paths["height"][:, 1])) / k == pytest.approx(45.0 + SLOT_ABOVE, abs=TOL + 1e-4)
    x0, y0 = float(paths["x_zero"][:, 0].mean()), float(paths["pitch_line"][:, 1].mean())
    drawn = np.column_stack([(paths["slot"][:, 0] - x0) / k, (y0 - paths["slot"][:, 1]) / k])
    exact = exact_slot()
    gap, _ = cKDTree(exact).query(drawn)
    assert gap.max() <= TOL + 2e-5 / k + 2e-3, gap.max()  # + the reference's 0.002 mm spacing
    # the drawn wall covers the whole slot: every exact point within the chord tolerance of the drawn polyline
    q, a_, b_ = exact[::100][:, None, :], drawn[None, :-1, :], drawn[None, 1:, :]
    t = np.clip(np.sum((q - a_) * (b_ - a_), axis=2) / np.maximum(np.sum((b_ - a_) ** 2, axis=2), 1e-30), 0.0, 1.0)
    back = np.min(np.hypot(*np.moveaxis(q - (a_ + t[..., None] * (b_ - a_)), 2, 0)), axis=1)
    assert back.max() <= TOL + 2e-5 / k + 2e-3, back.max()
