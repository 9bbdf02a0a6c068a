"""report.json against its documented layout; report.html rendered by headless Chromium; a kind's
own report section drawn from the typed report input."""
from __future__ import annotations

import dataclasses
import json
import subprocess

import numpy as np
import pytest

from camgen.report import REPORT_SCHEMA
from camgen.report.model import SectionData
from helpers import require_tool


def test_report_json_follows_the_documented_layout(default_run):
    import jsonschema
    report = json.loads((default_run / "report.json").read_text())
    jsonschema.validate(report, REPORT_SCHEMA)
    names = {c["name"] for cam in report["cams"].values() for c in cam["checks"]}
    assert {"undercut", "pressure_angle", "continuity", "constant_breadth", "wall_thickness", "face_length",
            "follower_motion", "min_convex_radius", "min_concave_radius"} <= names
    # the schema is not vacuous: a report without checks' units fails it
    broken = json.loads((default_run / "report.json").read_text())
    del broken["cams"]["stride_length"]["checks"][0]["unit"]
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(broken, REPORT_SCHEMA)


def test_report_json_holds_the_papers_numbers(default_run):
    """report.json's figures against numbers from outside camgen: paper 000 (Section 6: yoke
    widths 2 e2 = 330 and 2 e5 = 240 mm; Section 6.1: the leg figures within 3 %, the stride-cam
    pressure angle below 26 deg), paper 004 (S = 2189.0270 mm, eq. 9) and the drive-wheel
    diameter d = S Z1 / (pi Z2) (the paper prints 116.19 mm with pi = 3.14)."""
    report = json.loads((default_run / "report.json").read_text())
    cams = report["cams"]
    assert cams["stride_length"]["figures"]["breadth_mm"] == 330.0 and cams["stride_height"]["figures"]["breadth_mm"] == 240.0
    steering = cams["steering"]["figures"]
    assert steering["arc_length_mm"] == pytest.approx(2189.0270, abs=5e-5)
    assert steering["drive_wheel_diameter_mm"] == pytest.approx(2189.0270 * 20 / (3.14 * 120), rel=0.001)
    from test_horse_leg import KEYS, PAPER  # Section 6.1, typed from the paper

    leg = report["mechanisms"]["horse_leg"]
    for alpha, values in PAPER.items():
        for key, value in zip(KEYS, values):
            assert leg[f"alpha_{alpha:g}"][key] == pytest.approx(value, rel=0.03), (alpha, key)
        assert leg[f"alpha_{alpha:g}"]["max_pressure_angle_deg"] < 26.0


def test_report_html_is_self_contained(default_run):
    """(Byte-identical across processes: tests/test_run.py compares every output file.)"""
    page = (default_run / "report.html").read_text()
    assert page.startswith("<!DOCTYPE html>") and page.count("<svg") >= 10
    # nothing fetched from elsewhere: no scripts, no linked images, styles or fonts
    for marker in ("<script", "src=", 'href="http', "href='http", "url(http", "<link", "@import"):
        assert marker not in page, marker


def test_report_html_renders_in_headless_chromium(default_run, tmp_path):
    browser = require_tool("chromium")
    shot = tmp_path / "shot.png"
    proc = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         f"--user-data-dir={tmp_path / 'profile'}", "--enable-logging=stderr", "--v=0",
         "--window-size=1200,3000", f"--screenshot={shot}", (default_run / "report.html").as_uri()],
        capture_output=True, text=True, timeout=120,
    )
    assert shot.exists(), proc.stderr[-2000:]
    console_errors = [line for line in proc.stderr.splitlines() if "CONSOLE" in line and ("ERROR" in line or "Uncaught" in line)]
    assert not console_errors, console_errors
    from PIL import Image

    image = np.asarray(Image.open(shot).convert("L"), dtype=float)
    assert image.shape[0] >= 1000 and image.std() > 10  # not blank: text and plots on white
    assert (image < 128).mean() > 0.01  # a fair amount of dark ink


# --------------------------------------------------------------------------------------------
# The design and the motion program as tables (issue 21, item 14)
# --------------------------------------------------------------------------------------------
def _html_of(template: str, tmp_path):
    """report.html of a bundled template (html only), parsed, and the template's TOML."""
    import tomllib

    from lxml import html as lxml_html

    from camgen.cli import main
    from camgen.scene import template_path

    path = template_path(template)
    assert main(["run", str(path), "-o", str(tmp_path), "--only", "html", "--quiet"]) == 0
    scene = tomllib.loads(path.read_text(encoding="utf-8"))
    page = (tmp_path / template / "report.html").read_text(encoding="utf-8")
    report = json.loads((tmp_path / template / "report.json").read_text(encoding="utf-8"))
    return lxml_html.fromstring(page), scene, report


def _table(tree, cls: str) -> tuple[str, list[list[str]]]:
    """Caption and body rows (cell texts) of the table of class ``cls``."""
    (table,) = tree.xpath(f"//table[@class='{cls}']")
    rows = [[td.text_content().strip() for td in tr.xpath("./td")] for tr in table.xpath("./tbody/tr")]
    return table.xpath("string(./caption)"), rows


def _design(tree) -> dict[str, tuple[str, str]]:
    return {row[0]: (row[1], row[2]) for row in _table(tree, "design")[1]}


@pytest.mark.parametrize("template", ["plate_cam", "oscillating_roller", "motion_law"])
def test_the_motion_program_table_is_the_scenes_segments(template, tmp_path):
    """Each [[segments]] table of the scene (read here with tomllib) is one row: its law, the cam
    angles where it starts and ends (the running sum of the spans from 0), its span, its lift or
    swing (0 for a dwell; a polynomial's is its end s minus its start s) and its end conditions."""
    tree, scene, _ = _html_of(template, tmp_path)
    (cam,) = scene["cams"].values()
    caption, rows = _table(tree, "program")
    rotation = {"ccw": "counter-clockwise", "cw": "clockwise"}[cam.get("rotation", "ccw")]
    assert f"direction of rotation ({rotation}" in caption
    assert len(rows) == len(cam["segments"])
    start = 0.0
    for i, (row, seg) in enumerate(zip(rows, cam["segments"])):
        end = start + seg["span_deg"]
        if seg["law"] == "polynomial":
            motion = seg["end"][0] - seg["start"][0]
            for side in ("start", "end"):
                s, v, a = seg[side][:3]
                assert f"{side}: s = {s:g} {'deg' if 'swing_deg' in seg else 'mm'}, v = {v:g}" in row[6] and f"a = {a:g}" in row[6]
        else:
            motion = seg.get("lift_mm", seg.get("swing_deg", 0.0))
        assert int(row[0]) == i and row[1] == seg["law"]
        assert [float(c) for c in row[2:6]] == pytest.approx([start, end, seg["span_deg"], motion], abs=1e-9)
        start = end
    assert start == pytest.approx(360.0)
    header = [th.text_content() for th in tree.xpath("//table[@class='program']/thead//th")]
    assert ("swing (deg)" if cam.get("follower_motion") == "oscillating" else "lift (mm)") in header


@pytest.mark.parametrize("template", ["plate_cam", "oscillating_roller", "motion_law"])
def test_the_design_table_holds_the_scenes_values_with_units(template, tmp_path):
    """The design table against the scene file: follower, rotation, base radius, roller, offset or
    arm, cam speed and body, each with its unit; sized values marked and equal to report.json's
    sizing figures."""
    tree, scene, report = _html_of(template, tmp_path)
    (name, cam), = scene["cams"].items()
    design = _design(tree)

    def value(label: str) -> tuple[float, str]:
        text, unit = design[label]
        return float(text), unit

    assert design["follower"][0] == f"{cam.get('follower', 'roller')}, {cam.get('follower_motion', 'translating')}"
    assert design["cam rotation (as the DXF is drawn)"][0].endswith(f"({cam.get('rotation', 'ccw')})")
    assert value("roller radius") == (cam["roller_radius_mm"], "mm")
    assert value("cam speed") == (cam["rpm"], "rpm")
    assert value("thickness") == (cam["thickness_mm"], "mm")
    assert value("bore diameter") == (cam["bore_diameter_mm"], "mm")
    if "sizing" in cam:
        sizing = report["cams"][name]["figures"]["sizing"]
        assert value("base radius (sized)") == (pytest.approx(sizing["base_radius_mm"], rel=1e-5), "mm")
        assert value("follower offset (its axis: x = offset) (sized)") == (pytest.approx(sizing["offset_mm"], rel=1e-5), "mm")
        assert "pressure angle <= 30 deg" in design["sizing"][0] and "base_radius_mm" not in cam
    else:
        assert value("base radius") == (cam["base_radius_mm"], "mm")
    if cam.get("follower_motion") == "oscillating":
        assert value("arm length (pivot to roller centre or knife tip)") == (cam["arm_length_mm"], "mm")
        assert design["arm pivot (x, y)"] == (f"{cam['pivot_x_mm']:g}, {cam['pivot_y_mm']:g}", "mm")
    elif "follower_offset_mm" in cam:
        assert value("follower offset (its axis: x = offset)") == (cam["follower_offset_mm"], "mm")
    # no figure is shown as a Python literal (a dict or a list in brackets)
    text = tree.text_content()
    for literal in ("{'", "['", "'law'", "'span_deg'", "[0.0", "[5.0"):
        assert literal not in text, literal


# --- a kind's own report section takes typed data, never the built cam -------------------------------
@dataclasses.dataclass(frozen=True)
class DiscSection(SectionData):
    """The toy kind's section data: its radius (mm)."""

    radius: float


#: What disc_section was called with, in order (this module is the one pytest imported).
DISC_CALLS: list = []


def disc_section(Figure, cam) -> str:
    """The toy kind's part of report.html (named by its report_section "test_report:disc_section")."""
    DISC_CALLS.append(cam)
    return f"<p id='disc-section'>{cam.name}: radius {cam.section.radius:g} mm</p>"


def test_a_kinds_report_section_takes_the_typed_report_input():
    """A disc (radius 30 mm, centred) with a flat face: its section is called with the cam's
    CamReport (frozen, read-only), whose section data is what the kind's plots stage made, and
    whose curves are the disc's closed forms: outline within the drawing's chord tolerance of the
    30 mm circle (chords inside it), the face touching it 30 mm from the axis, a radius of
    curvature of 30 mm everywhere, pressure angle and lift 0.  A run without report.html draws
    nothing and calls no section."""
    import math

    from camgen.checks import Follower
    from camgen.contour import Arc, Contour
    from camgen.motions import Motion, register, unregister
    from camgen.kinds.base import BuiltCam, CamKind, CamSpec, body_keys, check_keys, read_body, read_checks
    from camgen.pipeline import execute, plan_run
    from camgen.report.model import CamReport, CheckRow
    from camgen.report_data import DRAWING_CHORD_MM
    from camgen.scene import parse_scene
    from camgen.schema import REQUIRED, Key, Length

    def read(where, name, parsed, base_dir=None):
        return CamSpec(name, "disc", parsed["radius"], read_body(where, parsed), read_checks(parsed), Follower("flat"))

    def build(spec, stages):
        contour = Contour([Arc((0.0, 0.0), spec.params, 0.0, 2 * math.pi)])
        section = DiscSection(spec.params) if "plots" in stages else None  # the section's data: the built cam carries it
        return BuiltCam(spec.name, spec.kind, contour, {"radius_mm": spec.params}, spec.body, spec.follower, section=section)

    keys = (Key("radius_mm", Length(), "Radius of the disc.", ("profile",), default=REQUIRED),) + body_keys() + check_keys()
    kind = CamKind("disc", "a circular disc", keys, read, build, report_section=f"{__name__}:disc_section")
    register(Motion("disc", "a circular disc", realisations={"plate": kind}))  # a motion that is a design of its own
    try:
        DISC_CALLS.clear()
        scene = parse_scene({"output": {"formats": ["dxf"]}, "cams": {"d": {"kind": "disc", "radius_mm": 30.0}}}, "t")
        assert "report.html" not in execute(scene, plan_run(scene)).files and DISC_CALLS == []
        scene = parse_scene({"output": {"formats": ["html"]}, "cams": {"d": {"kind": "disc", "radius_mm": 30.0}}}, "t")
        result = execute(scene, plan_run(scene))
    finally:
        unregister("disc")
    (cam,) = DISC_CALLS
    assert isinstance(cam, CamReport) and not isinstance(cam, BuiltCam)
    assert cam.section == DiscSection(30.0) and cam.figures["radius_mm"] == 30.0
    report = json.loads(result.files["report.json"])
    assert [c.name for c in cam.checks] == [c["name"] for c in report["cams"]["d"]["checks"]]
    assert all(isinstance(c, CheckRow) for c in cam.checks)
    page = result.files["report.html"]
    assert page.count("<p id='disc-section'>d: radius 30 mm</p>") == 1
    assert page.index("Computed figures") < page.index("disc-section")  # after the cam's own tables
    # the curves report.html drew, against the disc's closed forms
    plots = cam.plots
    radius = np.hypot(*plots.profile.T)
    assert np.all(radius <= 30.0 + 1e-9) and np.all(radius >= 30.0 - DRAWING_CHORD_MM) and plots.pitch is None
    assert plots.faces.distances == pytest.approx((30.0,)) and plots.roller is None and plots.follower_drawing is None
    assert plots.curvature[1] == pytest.approx(np.full(plots.curvature[1].size, 30.0), rel=1e-9)
    assert np.all(plots.pressure_angle[1] == 0.0) and np.ptp(plots.motion.lift) == pytest.approx(0.0, abs=1e-9)
    assert plots.outline_bounds == pytest.approx((-30.0, -30.0, 30.0, 30.0))
    # frozen and read-only: the report cannot change what the run computed
    with pytest.raises(dataclasses.FrozenInstanceError):
        cam.section.radius = 1.0
    with pytest.raises(TypeError):
        cam.figures["radius_mm"] = 1.0
    with pytest.raises(ValueError):
        plots.profile[0, 0] = 0.0
