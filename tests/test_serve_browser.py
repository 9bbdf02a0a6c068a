"""The live design page of ``camgen serve`` in a real headless Chromium (Playwright for Python).

One designer's session on the plate-cam template: the base radius lowered until the page shows
the pressure-angle check failing with the key to change, raised until it passes again, a bad
value shown next to its field with the line ``camgen check`` prints, a segment added to the
motion program, the scene saved.  Every number the page showed is then compared with what the
command line computes independently from the saved file: ``camgen run`` (report.json's figures
and checks) and ``camgen run --only dxf`` (the DXF, byte for byte against the page's download).
Timings are in benchmarks/bench_serve.py, not here.
"""
from __future__ import annotations

import json
import os
import re
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from helpers import require_tool

#: Longest wait for one step of the page (an evaluation, a download), ms.
STEP_MS = 20_000
#: Longest wait for the server to listen, s.
START_S = 60.0
#: camgen check's table prints 6 significant digits: a value it prints is within half a unit of
#: the 6th digit, at most 5e-6 relative.
PRINTED_REL = 5e-6


def _camgen(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-P", "-m", "camgen", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120, stdin=subprocess.DEVNULL)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _serve(scene: Path, port: int, log: Path) -> subprocess.Popen[bytes]:
    """``camgen serve SCENE --port PORT`` listening; its stderr goes to ``log`` (a pipe nobody
    reads could fill and stop it)."""
    with log.open("wb") as err:
        proc = subprocess.Popen([sys.executable, "-P", "-m", "camgen", "serve", str(scene), "--port", str(port)],
                                cwd=scene.parent, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err)
    deadline = time.monotonic() + START_S
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise AssertionError(f"camgen serve ended ({proc.returncode}): {log.read_text()}")
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=0.5):
                return proc
        except OSError:
            time.sleep(0.1)
    proc.kill()
    raise AssertionError("camgen serve did not listen")


def _idle(page: Any) -> None:
    """Wait until the newest edit's evaluation is drawn (no edit pending, no request open)."""
    page.wait_for_selector('body[data-busy="0"]:not([data-drawn-seq="0"])', state="attached", timeout=STEP_MS)


def _set(page: Any, path: str, text: str) -> None:
    """Type ``text`` into the field of the dotted scene path and wait for its evaluation."""
    page.fill(f'[data-path="{path}"] input', text)
    _idle(page)


def _check(page: Any, name: str) -> tuple[str, float, str]:
    """(status, value, keys named) of a check row as the page shows it."""
    row = page.locator(f'#checks tr[data-check="{name}"]')
    status = row.locator("td.status").inner_text().strip()
    value = float(row.locator("td.value").get_attribute("data-value") or "nan")
    return status, value, row.locator("td.keys").get_attribute("data-keys") or ""


def _figure(page: Any, name: str) -> float:
    return float(page.locator(f'#figures tr[data-figure="{name}"] td.value').get_attribute("data-value") or "nan")


def test_serve_page_in_chromium(tmp_path):
    browser_path = require_tool("chromium")
    playwright_api = pytest.importorskip("playwright.sync_api")
    assert _camgen("new", "plate_cam", "plate_cam.toml", cwd=tmp_path).returncode == 0
    scene = tmp_path / "plate_cam.toml"
    port = _free_port()
    server_log = tmp_path / "serve.err"
    server = _serve(scene, port, server_log)
    errors: list[str] = []
    try:
        with playwright_api.sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=browser_path, headless=True, args=["--no-sandbox"])
            context = browser.new_context(accept_downloads=True, viewport={"width": 1400, "height": 1000})
            page = context.new_page()
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda e: errors.append(str(e)))
            requests: list[str] = []
            page.on("request", lambda r: requests.append(r.url))
            page.goto(f"http://127.0.0.1:{port}/")
            _idle(page)
            base = "cams.plate.base_radius_mm"
            assert page.input_value(f'[data-path="{base}"] input') == "40"
            assert _check(page, "pressure_angle")[0] == "pass"
            assert page.locator("#verdict").get_attribute("class") == "badge pass"
            # every cam key of the schema is on the form with its unit, range and help
            assert page.locator('[data-path="cams.plate.roller_radius_mm"] small').inner_text().startswith("a number mm")
            # the profile with its follower and rotation arrow, the plots with the pressure-angle limits
            assert page.locator("#cam-outline").count() == 1 and page.locator("#rotation-arrow").count() == 1
            assert page.locator('#follower path[data-label="roller"]').count() == 1
            for plot in ("plot-s", "plot-v", "plot-a", "plot-j", "plot-pressure", "plot-curvature", "plot-force", "plot-torque"):
                assert page.locator(f"#{plot} path.series").count() == 1, plot
            assert page.locator("#plot-pressure line.limit").count() == 2

            # a second cam added (its own tab, form and drawing), then removed
            page.click("#add-cam")
            _idle(page)
            assert page.locator("#tabs button.cam").all_inner_texts() == ["plate", "cam2"]
            assert page.locator('[data-path="cams.cam2.base_radius_mm"] input').count() == 1
            assert page.locator("#cam-outline").count() == 1 and _check(page, "pressure_angle")[0] == "pass"
            page.click("#remove-cam")
            _idle(page)
            assert page.locator("#tabs button.cam").all_inner_texts() == ["plate"]

            # an answer older than the one shown is dropped: the evaluation of 45 mm is held back
            # until that of 40 mm is drawn, then let through
            held: list[Any] = []

            def hold_first(route: Any) -> None:
                if held:
                    route.continue_()
                else:
                    held.append((route, route.fetch()))

            shown_seq = int(page.get_attribute("body", "data-drawn-seq") or "0")
            page.route("**/api/evaluate", hold_first)
            page.fill(f'[data-path="{base}"] input', "45")
            for _ in range(STEP_MS // 50):  # past the debounce: the request of 45 mm is sent (and held)
                if held:
                    break
                page.wait_for_timeout(50)
            page.fill(f'[data-path="{base}"] input', "40")
            page.wait_for_selector(f'body[data-drawn-seq="{shown_seq + 2}"]', state="attached", timeout=STEP_MS)
            assert len(held) == 1 and json.loads(held[0][0].request.post_data or "{}")["data"]["cams"]["plate"]["base_radius_mm"] == 45
            route, response = held[0]
            route.fulfill(response=response)
            _idle(page)
            page.unroute("**/api/evaluate")
            assert page.get_attribute("body", "data-drawn-seq") == str(shown_seq + 2)
            assert _figure(page, "base_radius_mm") == 40.0

            # lower the base radius until the pressure angle is too large
            radius = 40
            while _check(page, "pressure_angle")[0] != "fail":
                radius -= 5
                assert radius > 0, "the pressure-angle check never failed"
                _set(page, base, str(radius))
            failed_at = radius
            status, angle, keys = _check(page, "pressure_angle")
            assert base in keys.split()
            assert "base_radius_mm" in page.locator('#checks tr[data-check="pressure_angle"] td.keys').inner_text()
            failing = [row.get_attribute("data-check") for row in page.locator("#checks tr.fail").all()]
            assert page.locator("#verdict").get_attribute("class") == "badge fail"
            # camgen check on that scene fails the same checks; its table prints the angle to 6 digits
            text = scene.read_text()
            probe = tmp_path / "probe.toml"
            probe.write_text(re.sub(r"base_radius_mm = 40\.0", f"base_radius_mm = {failed_at}.0", text))
            done = _camgen("check", str(probe), cwd=tmp_path)
            assert done.returncode == 1
            assert failing == re.findall(r"^\S+\s+(\S+)\s+FAIL\b", done.stdout, re.M) == ["pressure_angle"]
            printed = re.search(r"^\S+\s+pressure_angle\s+FAIL\s+(\S+)", done.stdout, re.M)
            assert printed and abs(angle - float(printed.group(1))) <= PRINTED_REL * angle

            # a bad value: the CLI's line next to the field, nothing else changed
            _set(page, base, "-3")
            probe.write_text(re.sub(r"base_radius_mm = 40\.0", "base_radius_mm = -3", text))
            done = _camgen("check", str(probe), cwd=tmp_path)
            assert done.returncode == 2
            cli_line = done.stderr.strip().splitlines()[-1]
            assert page.locator(f'[data-path="{base}"] .err').inner_text().strip() == cli_line
            assert page.locator("#verdict").inner_text() == "bad input"

            # raise it again until every check passes
            radius = failed_at
            while page.locator("#verdict").get_attribute("class") != "badge pass":
                radius += 5
                assert radius <= 80, "the checks never passed again"
                _set(page, base, str(radius))
            assert _check(page, "pressure_angle")[0] == "pass"

            # add a segment: the last dwell (60 deg) becomes 30 deg (the program no longer closes:
            # the line camgen check prints for that scene, next to the table) and a 30-deg dwell follows
            _set(page, "cams.plate.segments[3].span_deg", "30")
            last = text.rindex("span_deg = 60.0")
            edited = text[:last] + "span_deg = 30.0" + text[last + len("span_deg = 60.0"):]
            probe.write_text(edited.replace("base_radius_mm = 40.0", f"base_radius_mm = {radius}.0"))
            done = _camgen("check", str(probe), cwd=tmp_path)
            assert done.returncode == 2
            assert page.locator(".err:not(:empty)").all_inner_texts() == [done.stderr.strip().splitlines()[-1]]
            assert page.locator('[data-path="cams.plate.segments"] .err').inner_text() == done.stderr.strip().splitlines()[-1]
            page.click("#add-segment")
            page.select_option('[data-path="cams.plate.segments[4].law"] select', "dwell")
            _set(page, "cams.plate.segments[4].span_deg", "30")
            assert page.locator("#segments tr[data-path]").count() == 5
            assert page.locator("#verdict").get_attribute("class") == "badge pass"

            shown = {"pressure_angle": _check(page, "pressure_angle")[1], "undercut": _check(page, "undercut")[1],
                     "base_radius_mm": _figure(page, "base_radius_mm"), "stroke_mm": _figure(page, "stroke_mm"),
                     "area_mm2": _figure(page, "area_mm2"), "torque_peak_Nm": _figure(page, "dynamics.torque_peak_Nm")}

            # save: the TOML offered for download
            page.click("#save")
            page.wait_for_selector("#save-link", timeout=STEP_MS)
            with page.expect_download(timeout=STEP_MS) as info:
                page.click("#save-link")
            saved = tmp_path / "saved" / "plate_cam.toml"
            saved.parent.mkdir()
            info.value.save_as(saved)
            assert info.value.suggested_filename == "plate_cam.toml"

            # the DXF of the current design, downloaded
            page.click('button.dl[data-format="dxf"]')
            page.wait_for_selector('#links a.file-link[download="plate.dxf"]', timeout=STEP_MS)
            with page.expect_download(timeout=STEP_MS) as info:
                page.click('#links a.file-link[download="plate.dxf"]')
            dxf = tmp_path / "page.dxf"
            info.value.save_as(dxf)
            context.close()
            browser.close()
    finally:
        server.send_signal(signal.SIGINT)
        try:
            server.wait(timeout=10)
        except subprocess.TimeoutExpired:
            server.kill()
    assert not errors, errors
    assert "Traceback" not in server_log.read_text() and "internal error" not in server_log.read_text()
    # the page works offline: it asked nothing of any other host
    assert [u for u in requests if not u.startswith((f"http://127.0.0.1:{port}/", "blob:", "data:"))] == []

    # the saved scene holds what the page showed, and keeps the template's comments
    saved_text = saved.read_text()
    assert re.search(rf"^base_radius_mm = {radius}(\.0)?\b", saved_text, re.M)
    assert "# the roller touches the cam" in saved_text
    done = _camgen("run", str(saved), "-o", "out", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    report = json.loads(next((tmp_path / "out").glob("*/report.json")).read_text())
    cam = report["cams"]["plate"]
    checks = {c["name"]: c["value"] for c in cam["checks"]}
    figures = cam["figures"]
    assert len(figures["segments"]) == 5
    assert shown == {"pressure_angle": checks["pressure_angle"], "undercut": checks["undercut"],
                     "base_radius_mm": figures["base_radius_mm"], "stroke_mm": figures["stroke_mm"],
                     "area_mm2": figures["area_mm2"], "torque_peak_Nm": figures["dynamics"]["torque_peak_Nm"]}
    assert shown["base_radius_mm"] == radius

    # the page's DXF equals the one camgen run writes for the saved scene, byte for byte
    done = _camgen("run", str(saved), "--only", "dxf", "-o", "dxf_out", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert dxf.read_bytes() == next((tmp_path / "dxf_out").glob("*/plate.dxf")).read_bytes()
    assert os.path.getsize(dxf) > 0


def test_page_is_one_self_contained_file():
    """The installed page names no other file or host (it works offline): no script or style
    sheet by reference, no URL but the SVG namespace (checked without a browser too)."""
    from importlib.resources import files

    text = (files("camgen.serve") / "page.html").read_text(encoding="utf-8")
    assert re.findall(r"<script[^>]*\bsrc=|<link[^>]*stylesheet|@import|<iframe|<img[^>]*\bsrc=\"?[a-z]", text, re.I) == []
    assert set(re.findall(r"[a-z]+://[^\s\"'`)]+", text, re.I)) == {"http://www.w3.org/2000/svg"}
