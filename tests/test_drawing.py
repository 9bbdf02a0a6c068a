"""The manufacturing drawing and inspection table (issue 27, item 4).

- The inspection CSV against the closed-form law and follower geometry computed here: an
  in-line translating roller follower (along +y) whose law starts at rest touches the cam at
  cam angle 0 at (0, Rb), so the zero mark's ray is +y; turning the cam counter-clockwise by
  theta brings the cam's polar angle 90 deg - theta under it, and a checking roller of the
  follower's radius has its centre on the pitch curve, at Rb + r + s(theta) from the axis
  (Norton, Cam Design and Manufacturing Handbook, ch. 7: the pitch curve of a radial roller
  follower).  A roller of another radius r_c rests on the pitch curve's parallel at r_c - r (the
  envelope of circles of radius r_c tangent to the profile), solved here for each ray by bisection.
- The SVG read by svgelements: its profile path mapped back to the part (the centre lines' crossing,
  the scale) lies within the chord tolerance of the closed-form profile, and covers it.
- The PDF rendered by poppler's pdftoppm: the scale bar measures 100 mm on the page within 0.2 mm.
"""
from __future__ import annotations

import copy
import math
import re
import subprocess
import sys

import numpy as np
import pytest

from helpers import require_tool, scene_toml

RB, RR, H, BETA = 40.0, 10.0, 20.0, math.radians(120.0)
CAM = {"kind": "motion_law", "base_radius_mm": RB, "follower": "roller", "roller_radius_mm": RR, "rotation": "ccw",
       "thickness_mm": 10.0, "bore_diameter_mm": 12.0, "keyway_width_mm": 4.0, "keyway_depth_mm": 1.8,
       "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": H}, {"law": "dwell", "span_deg": 60.0},
                    {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -H}, {"law": "dwell", "span_deg": 60.0}]}
SCENE = {"output": {"formats": ["drawing", "drawing_pdf", "inspection"], "chord_tol_mm": 0.01}, "cams": {"c": CAM}}


def lift(theta: np.ndarray) -> np.ndarray:
    """The law in closed form: cycloidal rise over 0-120 deg, dwell, cycloidal return over 180-300 deg, dwell (mm)."""
    t = np.mod(theta, 2 * math.pi)
    rise = H * (t / BETA - np.sin(2 * math.pi * t / BETA) / (2 * math.pi))
    u = (t - math.radians(180.0)) / BETA
    fall = H * (1.0 - (u - np.sin(2 * math.pi * u) / (2 * math.pi)))
    return np.select([t <= BETA, t <= math.radians(180.0), t <= math.radians(300.0)], [rise, H, fall], 0.0)


def parallel(theta: np.ndarray, d: float) -> np.ndarray:
    """Points (n, 2) of the pitch curve's parallel at distance ``d`` outward (d = -RR: the profile), cam frame.
    Pitch: P(theta) = (RB + RR + s) (cos(pi/2 - theta), sin(pi/2 - theta)); its normal from the derivative by
    central differences of the closed form (step 1e-6 rad: error ~1e-12 relative)."""
    def pitch(t):
        r = RB + RR + lift(t)
        return np.column_stack([r * np.cos(math.pi / 2 - t), r * np.sin(math.pi / 2 - t)])

    p = pitch(theta)
    dp = (pitch(theta + 1e-6) - pitch(theta - 1e-6)) / 2e-6
    n = np.column_stack([-dp[:, 1], dp[:, 0]]) / np.hypot(dp[:, 0], dp[:, 1])[:, None]
    n *= np.sign(np.einsum("ij,ij->i", n, p))[:, None]  # outward
    return p + d * n


def ray_radius(phi: np.ndarray, d: float) -> np.ndarray:
    """Distance from the axis to the parallel at ``d`` along polar angles ``phi``: bisection on theta
    (the parallel's polar angle decreases as theta grows: the cam turns counter-clockwise)."""
    lo = np.mod(math.pi / 2 - phi, 2 * math.pi) - 0.3
    hi = lo + 0.6
    for _ in range(60):
        mid = (lo + hi) / 2
        q = parallel(mid, d)
        ang = np.angle((q[:, 0] + 1j * q[:, 1]) * np.exp(-1j * phi))  # polar angle minus phi, wrapped
        ahead = ang > 0  # not yet turned past the ray
        lo, hi = np.where(ahead, mid, lo), np.where(ahead, hi, mid)
    q = parallel((lo + hi) / 2, d)
    return np.hypot(q[:, 0], q[:, 1])


def run(tmp_path, **output) -> dict:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    table = copy.deepcopy(SCENE)
    table["output"].update(output)
    scene = parse_scene(table, "draw", source="draw.toml", base_dir=tmp_path)
    return dict(execute(scene, plan_run(scene)).files)


def read_csv(text: str) -> dict[str, np.ndarray]:
    lines = text.strip().split("\n")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return dict(zip(lines[0].split(","), data.T))


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return run(tmp_path_factory.mktemp("draw"))


def test_inspection_with_the_followers_roller_is_base_plus_roller_plus_lift(files):
    table = read_csv(files["c_inspection.csv"])
    theta = np.radians(table["cam_angle_deg"])
    assert table["cam_angle_deg"].size == 36 and np.allclose(np.diff(table["cam_angle_deg"]), 10.0)
    assert np.allclose(table["polar_angle_deg"], np.mod(90.0 - table["cam_angle_deg"], 360.0), atol=1e-9)
    assert np.max(np.abs(table["centre_radius_mm"] - (RB + RR + lift(theta)))) <= 1e-6
    assert np.max(np.abs(table["lift_mm"] - lift(theta))) <= 1e-6
    import json

    meta = json.loads(files["report.json"])["tables"]["c_inspection.csv"]  # the table states its roller, step and ray
    assert (meta["roller_radius_mm"], meta["angle_step_deg"], meta["rotation"]) == (RR, 10.0, "ccw")
    assert meta["zero_mark_polar_angle_deg"] == pytest.approx(90.0, abs=1e-9)


def test_inspection_with_another_roller_rests_on_the_parallel_curve(tmp_path):
    rc = 4.0
    table = read_csv(run(tmp_path, inspection_roller_radius_mm=rc, inspection_step_deg=5.0)["c_inspection.csv"])
    assert table["cam_angle_deg"].size == 72
    expected = ray_radius(np.radians(table["polar_angle_deg"]), rc - RR)
    assert np.max(np.abs(table["centre_radius_mm"] - expected)) <= 1e-6
    # a probe point reads the profile itself (the parallel at -RR)
    table = read_csv(run(tmp_path, inspection_roller_radius_mm=0.0)["c_inspection.csv"])
    assert np.max(np.abs(table["centre_radius_mm"] - ray_radius(np.radians(table["polar_angle_deg"]), -RR))) <= 1e-6


def _svg_profile(svg_text: str, tmp_path, scale: float, centre_only: bool = False):
    """The profile path read by svgelements, in part mm (cam frame); ``centre_only``: the page x (mm) of the axis."""
    from svgelements import SVG, Path

    name = tmp_path / "d.svg"
    name.write_text(svg_text)
    doc = SVG.parse(str(name))
    per_mm = doc.width / float(doc.values["width"].removesuffix("mm"))  # svgelements' units per mm
    elements = {e.id: e for e in doc.elements() if isinstance(e, Path) and e.id}

    def points(path, n=1):
        out = []
        for seg in path.segments():
            if seg.end is None or type(seg).__name__ == "Move":
                continue
            out.extend(seg.point(t) for t in np.linspace(0.0, 1.0, n + 1)[1:])
        return np.array([[p.x, p.y] for p in out]) / per_mm

    cx = points(elements["centre_y"])[:, 0].mean()
    cy = points(elements["centre_x"])[:, 1].mean()
    if centre_only:
        return float(cx)
    page = points(elements["profile"], 2)  # vertices and chord midpoints
    return np.column_stack([(page[:, 0] - cx) / scale, (cy - page[:, 1]) / scale])


@pytest.mark.parametrize("scale, k", [("1:1", 1.0), ("1:2", 0.5)])
def test_svg_profile_is_the_profile_within_the_chord_tolerance_at_scale(tmp_path, scale, k):
    from scipy.spatial import cKDTree

    svg = run(tmp_path, drawing_scale=scale)["c_drawing.svg"]
    assert 'width="420mm" height="297mm" viewBox="0 0 420 297"' in svg or 'width="297mm" height="210mm" viewBox="0 0 297 210"' in svg
    drawn = _svg_profile(svg, tmp_path, k)
    exact = parallel(np.linspace(0.0, 2 * math.pi, 400_001), -RR)  # spacing 1.1e-3 mm: nearest-point error < 1e-8 mm
    tol = 0.01 + 1e-5 / k  # the chord tolerance, and the file's coordinates rounded to 1e-5 page mm
    gap, _ = cKDTree(exact).query(drawn)
    assert gap.max() <= tol + 2e-6
    back, _ = cKDTree(drawn).query(exact[::50])  # the drawn path covers the whole profile
    assert back.max() <= 1.0  # samples every half chord: a chord within 0.01 mm of radius <= 70 mm is < 2.4 mm long


def longest_dark_runs(image: np.ndarray, block: int = 256) -> np.ndarray:
    """The longest run of dark pixels in each row of ``image`` (bool, dark True): the count since the
    last light pixel, its row maximum (in blocks of rows to bound memory)."""
    out = np.empty(image.shape[0], dtype=np.int64)
    col = np.arange(1, image.shape[1] + 1, dtype=np.int32)
    for lo in range(0, image.shape[0], block):
        rows = image[lo : lo + block]
        last_light = np.maximum.accumulate(np.where(rows, 0, col), axis=1)
        out[lo : lo + block] = (col - last_light).max(axis=1)
    return out


def profile_crossings(x: float) -> tuple[float, float]:
    """Highest and lowest y (mm) where the closed-form profile crosses the vertical line at ``x`` mm (cam frame)."""
    p = parallel(np.linspace(0.0, 2 * math.pi, 400_001), -RR)
    i = np.flatnonzero(np.sign(p[:-1, 0] - x) != np.sign(p[1:, 0] - x))
    w = (x - p[i, 0]) / (p[i + 1, 0] - p[i, 0])
    y = p[i, 1] + w * (p[i + 1, 1] - p[i, 1])
    return float(y.max()), float(y.min())


def test_pdf_scale_bar_measures_100_mm_and_the_profile_its_height_at_scale(tmp_path):
    pdftoppm = require_tool("pdftoppm")
    from PIL import Image

    x_cut = 5.0  # mm right of the axis: the column crosses the profile, bore and base circle, no leader outside the profile
    top, bottom = profile_crossings(x_cut)
    for scale, k in (("1:1", 1.0), ("1:2", 0.5)):
        files = run(tmp_path, drawing_scale=scale)
        (tmp_path / "d.pdf").write_bytes(files["c_drawing.pdf"])
        centre_x = _svg_profile(files["c_drawing.svg"], tmp_path, k, centre_only=True)
        dpi = 600
        subprocess.run([pdftoppm, "-r", str(dpi), "-gray", "-singlefile", str(tmp_path / "d.pdf"), str(tmp_path / "d")],
                       check=True)
        image = np.asarray(Image.open(tmp_path / "d.pgm").convert("L")) < 128
        assert image.shape[1] / dpi * 25.4 == pytest.approx(420.0, abs=0.1)  # the A3 sheet, landscape
        # the bar: the thickest band of rows whose longest dark run is 50-150 mm (frame lines are longer, the
        # title block's lines and the table's rules thin)
        length = longest_dark_runs(image) / dpi * 25.4
        rows = np.flatnonzero((length > 50.0) & (length < 150.0))
        bands = np.split(rows, np.flatnonzero(np.diff(rows) > 1) + 1)
        bar = max(bands, key=len)
        assert len(bar) / dpi * 25.4 == pytest.approx(3.0, abs=0.2)
        assert np.median(length[bar]) == pytest.approx(100.0, abs=0.2)
        # the profile's height along the column x_cut right of the axis (the axis from the SVG of the same drawing):
        # the outer edges of its 0.5 mm line are k (top - bottom) + 0.5 mm apart on the page
        column = image[:, int(round((centre_x + k * x_cut) / 25.4 * dpi))]
        dark = np.flatnonzero(column)
        inside = dark[(dark > 11.0 / 25.4 * dpi) & (dark < (297.0 - 11.0) / 25.4 * dpi)]  # the frame's lines left out
        height = (inside.max() - inside.min() + 1) / dpi * 25.4
        assert height == pytest.approx(k * (top - bottom) + 0.5, abs=0.2)


def _cli(table: dict, tmp_path, name: str) -> subprocess.CompletedProcess:
    import json

    extra = "".join(f"{k} = {json.dumps(v)}\n" for k, v in table["output"].items() if k != "formats")  # scene_toml writes formats only
    text = scene_toml(table).replace("[output]\n", "[output]\n" + extra, 1)
    (tmp_path / f"{name}.toml").write_text(text, encoding="utf-8")
    return subprocess.run([sys.executable, "-m", "camgen", "run", str(tmp_path / f"{name}.toml"), "-o", str(tmp_path / name)],
                          capture_output=True, text=True)


def test_a_drawing_too_large_for_its_sheet_is_refused_naming_the_largest_scale_that_fits(tmp_path):
    from camgen.export.drawing_spec import DRAWING_SCALES

    table = copy.deepcopy(SCENE)
    table["output"].update(drawing_scale="5:1", drawing_sheet="A4")
    refused = _cli(table, tmp_path, "big")
    assert refused.returncode == 2 and not (tmp_path / "big").exists()
    (line,) = refused.stderr.strip().splitlines()
    assert line.startswith("camgen: error: parameter 'output.drawing_scale' = '5:1'") and "A4" in line, line
    hint = re.search(r"valid range is (\d+:\d+) or smaller", line).group(1)
    table["output"]["drawing_scale"] = hint  # the hint, used: the drawing is written on A4
    assert _cli(table, tmp_path, "fits").returncode == 0
    assert 'width="297mm" height="210mm"' in next((tmp_path / "fits").rglob("c_drawing.svg")).read_text()
    table["output"]["drawing_scale"] = DRAWING_SCALES[DRAWING_SCALES.index(hint) - 1]  # the next larger scale does not fit
    assert _cli(table, tmp_path, "larger").returncode == 2


def test_a_cam_without_a_zero_mark_is_refused_naming_output_formats(tmp_path):
    table = {"output": {"formats": ["inspection"]}, "cams": {"t": {"kind": "three_arc", "a_mm": 100.0, "b_mm": 100.0, "c_mm": 35.0}}}
    refused = _cli(table, tmp_path, "arc")
    (line,) = refused.stderr.strip().splitlines()
    assert refused.returncode == 2 and "'output.formats' = 'inspection'" in line and "cam 't'" in line, line
