"""report.json against its documented layout; report.html rendered by headless Chromium."""
from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from camgen.report import REPORT_SCHEMA
from camgen.tests.helpers import require_tool


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
    from camgen.tests.test_horse_leg import KEYS, PAPER  # Section 6.1, typed from the paper

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
