"""report.html in runs that once crashed (issue 21, item 3): a trajectory cam that undercuts, and
a non-ASCII scene path in an ASCII locale.  Each is a design verdict or a clean run, never a
traceback."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import pytest
from lxml import html as lxml_html

from camgen.cli import main
from test_trajectory_limits import RD, exact_undercut_factor, gauss_expression

#: A Gaussian bump 28 mm wide: narrower than the width (29.86 mm) below which the exact
#: rod-centre path of paper 004's device has a convex radius under the rod radius.
BUMP_WIDTH = 28.0


def _undercut_scene(tmp_path, formats=("dxf", "points", "html")):
    scene = tmp_path / "bump.toml"
    scene.write_text(f'[output]\nformats = {json.dumps(list(formats))}\n[cams.x]\nkind = "trajectory"\n'
                     f'expression = "{gauss_expression(BUMP_WIDTH)}"\nperiod_mm = 2000.0\nsamples = 720\n', encoding="utf-8")
    return scene


def _check_rows(page: str) -> dict[str, list[str]]:
    """The checks table of report.html: check name -> its cells' text."""
    tree = lxml_html.fromstring(page)
    table = tree.xpath("//h3[normalize-space()='Checks']/following-sibling::table[1]")[0]
    rows = [[cell.text_content().strip() for cell in row.xpath("./td")] for row in table.xpath(".//tr[td]")]
    return {row[0]: row for row in rows}


def test_the_bump_undercuts_by_the_closed_form():
    """The scene below is one the rod cannot follow: the exact path's least 1 - r_d kappa < 0."""
    assert float(exact_undercut_factor(BUMP_WIDTH).min()) < 0.0


def test_an_undercutting_trajectory_cam_with_html_reports_the_failed_check(tmp_path, capsys):
    scene = _undercut_scene(tmp_path)
    assert main(["run", str(scene), "-o", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert "camgen: check failed: cams.x: undercut" in err and "Traceback" not in err
    run = tmp_path / "out" / "bump"
    assert sorted(p.name for p in run.iterdir()) == ["report.html", "report.json"]  # no manufacturing file
    report = json.loads((run / "report.json").read_text(encoding="utf-8"))
    assert report["status"] == "fail" and report["cams"]["x"]["manufacturable"] is False
    undercut = next(c for c in report["cams"]["x"]["checks"] if c["name"] == "undercut")
    assert undercut["status"] == "fail" and undercut["blocks_manufacture"] and undercut["limit"] == RD
    assert undercut["value"] < RD
    row = _check_rows((run / "report.html").read_text(encoding="utf-8"))["undercut"]
    assert row[1] == "FAIL" and float(row[2]) == pytest.approx(undercut["value"], rel=1e-5)
    page = (run / "report.html").read_text(encoding="utf-8")
    assert "No ride" in page  # the ride section says why it has nothing to show
    # the exact rod-centre path turns both ways, so its radius of curvature runs through infinity:
    # the curvature plot cannot show it all and says which values it leaves out
    kappa = (1.0 - exact_undercut_factor(BUMP_WIDTH)) / RD
    assert kappa.min() < 0.0 < kappa.max()
    (note,) = lxml_html.fromstring(page).xpath("//*[local-name()='text'][@class='clipnote']")
    assert note.text.startswith("clipped, not shown: radius of curvature of the pitch curve above ")
    assert " mm and below \u2212" in note.text


def test_an_undercutting_trajectory_cam_in_a_subprocess_has_no_traceback(tmp_path):
    scene = _undercut_scene(tmp_path, ("html",))
    proc = subprocess.run([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(tmp_path / "out")],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 1, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr and "camgen: check failed: cams.x: undercut" in proc.stderr
    assert (tmp_path / "out" / "bump" / "report.html").is_file()


def _ascii_locale() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("LC_") and k not in ("LANG", "LANGUAGE", "PYTHONIOENCODING")}
    return {**env, "LC_ALL": "C", "LANG": "C", "PYTHONUTF8": "0"}


def test_a_non_ascii_scene_path_in_an_ascii_locale(tmp_path):
    """`LC_ALL=C PYTHONUTF8=0 camgen run dé.toml` with html into a non-ASCII folder: Python
    decodes the names with surrogates there; the files are UTF-8 and name the scene as it is."""
    from camgen.scene import template_path

    text = template_path("plate_cam").read_text(encoding="utf-8")
    text = 'name = "plate"\n' + re.sub(r"(?m)^formats = .*$", 'formats = ["dxf", "html"]', text)
    assert 'formats = ["dxf", "html"]' in text
    # the names as bytes, so that the test does not depend on its own locale either
    folder = tmp_path / os.fsdecode("sc\u00e8nes".encode("utf-8"))
    folder.mkdir()
    scene = folder / os.fsdecode("d\u00e9.toml".encode("utf-8"))
    scene.write_bytes(text.encode("utf-8"))
    out = tmp_path / os.fsdecode("r\u00e9sultats".encode("utf-8"))
    probe = subprocess.run([sys.executable, "-c", "import sys; print(sys.getfilesystemencoding(), sys.flags.utf8_mode)"],
                           capture_output=True, text=True, env=_ascii_locale())
    assert probe.stdout.split() == ["ascii", "0"]  # the locale the user had: ASCII file names, no UTF-8 mode
    proc = subprocess.run([sys.executable, "-m", "camgen", "run", os.fsencode(scene), "-o", os.fsencode(out)],
                          capture_output=True, env=_ascii_locale(), timeout=600, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr.decode("utf-8", "replace")[-2000:]
    assert proc.stderr == b""
    listed = proc.stdout.splitlines()
    printed = os.fsencode(out) + b"/plate/"
    assert printed + b"report.html" in listed and printed + b"plate.dxf" in listed  # the names printed as given
    page = (out / "plate" / "report.html").read_bytes().decode("utf-8")  # strict UTF-8
    assert "d\u00e9.toml" in page
    report = json.loads((out / "plate" / "report.json").read_bytes().decode("utf-8"))
    assert report["source_file"].endswith("sc\u00e8nes/d\u00e9.toml")
