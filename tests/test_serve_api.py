"""The server of ``camgen serve`` (issue 29 items 1, 3, 4): its endpoints against the command line
on the same scene, and its refusals.

Every expected value comes from another program: report.json and the DXF files that ``camgen
run`` (a subprocess) writes for the scene, the line ``camgen check`` prints on stderr for bad
input, Python's own TOML parser for the saved text.  The server runs in a thread of the test
process on a free port (one test starts ``camgen serve`` itself) and is spoken to with
:mod:`http.client`, as a browser would.
"""
from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import threading
import tomllib
from pathlib import Path

import pytest

from camgen.scene import template_path
from camgen.serve.files import FileStore
from camgen.serve.server import MAX_BODY, make_server
from camgen.serve.toml_text import scene_toml

#: report.json's figures of the mesh stage (the solid of STL, 3MF, ...): an evaluation does not mesh the cam.
MESH_FIGURES = ("solid_triangles", "solid_volume_mm3")
#: Seconds a request or a command may take before the test fails instead of hanging.
TIMEOUT_S = 120


@pytest.fixture(scope="module")
def server():
    """``camgen serve`` of the bundled default scene on a free port, in a thread."""
    srv = make_server(None, port=0)
    thread = threading.Thread(target=srv.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True)
    thread.start()
    yield srv
    srv.shutdown()
    srv.server_close()


def request(port: int, method: str, path: str, body: object = None, headers: dict[str, str] | None = None,
            raw: bytes | None = None) -> tuple[int, bytes, dict[str, str]]:
    """One request as a browser on this machine sends it (Host 127.0.0.1:PORT, a JSON body)."""
    conn = http_client(port)
    sent = {"Host": f"127.0.0.1:{port}", "Content-Type": "application/json"}
    sent.update(headers or {})
    data = raw if raw is not None else None if body is None else json.dumps(body).encode("utf-8")
    conn.request(method, path, body=data, headers=sent)
    response = conn.getresponse()
    out = response.status, response.read(), {k.lower(): v for k, v in response.getheaders()}
    conn.close()
    return out


def http_client(port: int):
    import http.client

    return http.client.HTTPConnection("127.0.0.1", port, timeout=TIMEOUT_S)


def post(port: int, path: str, body: object) -> dict:
    status, data, _ = request(port, "POST", path, body)
    assert status == 200, data
    return json.loads(data)


def camgen(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "camgen", *args], capture_output=True, text=True, timeout=TIMEOUT_S, cwd=cwd)


def default_data() -> dict:
    return tomllib.loads(template_path("default").read_text(encoding="utf-8"))


# -- the endpoints against the command line ---------------------------------------------------


def test_scene_is_the_file_as_read(server):
    status, data, headers = request(server.port, "GET", "/api/scene")
    assert status == 200 and headers["content-type"] == "application/json"
    scene = json.loads(data)
    text = template_path("default").read_text(encoding="utf-8")
    assert scene["text"] == text  # comments and all
    assert scene["data"] == tomllib.loads(text)
    assert scene["name"] == "default"


@pytest.mark.parametrize("template", ["default", "plate_cam"])
def test_evaluate_equals_report_json_of_camgen_run(server, tmp_path, template):
    """The page's figures and checks of every cam are report.json's of ``camgen run`` (another
    process) on the same scene, value for value (but the figures of the mesh, which the page does
    not make): the default scene (three cams of two kinds, a mechanism) and the plate cam (dynamics)."""
    path = template_path(template)
    answer = post(server.port, "/api/evaluate", {"seq": 7, "data": tomllib.loads(path.read_text(encoding="utf-8"))})
    assert answer["seq"] == 7 and answer["ok"] is True and answer["error"] is None
    run = camgen("run", str(path), "-o", str(tmp_path), "-q")
    assert run.returncode == 0, run.stderr
    report = json.loads((tmp_path / template / "report.json").read_text(encoding="utf-8"))
    assert answer["verdict"] == report["status"] == "pass"
    assert [c["name"] for c in answer["cams"]] == list(report["cams"])
    for cam in answer["cams"]:
        expected = report["cams"][cam["name"]]
        assert (cam["kind"], cam["form"]) == (expected["kind"], expected["form"])
        assert cam["figures"] == {k: v for k, v in expected["figures"].items() if k not in MESH_FIGURES}
        assert [{k: v for k, v in c.items() if k not in ("where", "keys")} for c in cam["checks"]] == expected["checks"]
    assert answer["mechanisms"] == report["mechanisms"]


@pytest.mark.parametrize("template", sorted(p.stem for p in template_path("default").parent.glob("*.toml")))
def test_every_template_evaluates_to_strict_json_as_run_only_json(template):
    """Every bundled scene: the answer is strict JSON (no NaN, no infinity), and its figures and
    checks are report.json's of ``camgen run --only json`` on the scene (the writer's file read
    back), so the plot data the page adds changes no figure."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import load_template
    from camgen.serve.api import evaluate, load_source

    answer = evaluate(load_source(str(template_path(template))), {"seq": 1, "data": tomllib.loads(template_path(template).read_text(encoding="utf-8"))})
    answer = json.loads(json.dumps(answer, allow_nan=False))
    scene = load_template(template, ["json"])
    report = json.loads(execute(scene, plan_run(scene, ["json"])).files["report.json"])
    assert answer["ok"] and answer["verdict"] == report["status"]
    for cam in answer["cams"]:
        assert cam["figures"] == report["cams"][cam["name"]]["figures"]
        assert [{k: v for k, v in c.items() if k not in ("where", "keys")} for c in cam["checks"]] == report["cams"][cam["name"]]["checks"]
        for check in cam["checks"]:
            assert all(key.startswith(("cams.", "machining.", "mechanisms.")) for key in check["keys"])


def test_evaluate_draws_the_plate_cam(server):
    """A plate cam's outline, follower path and curves: the outline within the radii report.json
    gives (base radius; bounds), the follower's path lifted by the stroke, angles over one turn."""
    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    cam = post(server.port, "/api/evaluate", {"seq": 1, "data": data})["cams"][0]
    import numpy as np

    profile = np.array(cam["profile"])
    assert 3 <= len(profile) <= 2000
    xmin, ymin, xmax, ymax = cam["figures"]["bounds_mm"]
    assert profile[:, 0].min() >= xmin - 1e-6 and profile[:, 0].max() <= xmax + 1e-6
    assert profile[:, 1].min() >= ymin - 1e-6 and profile[:, 1].max() <= ymax + 1e-6
    path = cam["follower_path"]
    assert len(path["theta_deg"]) <= 360 and path["theta_deg"][0] == 0.0 and path["theta_deg"][-1] < 360.0
    y = np.array(path["points"])[:, 1]
    assert y.max() - y.min() == pytest.approx(cam["figures"]["stroke_mm"], abs=0.01)  # 20 mm rise, sampled every 2 deg
    pa = cam["plots"]["pressure_angle"]
    check = next(c for c in cam["checks"] if c["name"] == "pressure_angle")
    assert max(abs(v) for v in pa["deg"]) == pytest.approx(check["value"], abs=0.2)  # the plot thinned to 721 samples
    assert pa["limit_deg"] == check["limit"] == data["cams"]["plate"].get("pressure_angle_limit_deg", 30.0)
    assert len(cam["plots"]["svaj"]["s"]) <= 721 and cam["plots"]["dynamics"] is not None
    assert cam["rotation"] == "ccw"


def test_failed_check_names_the_keys_to_change(server):
    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    data["cams"]["plate"]["base_radius_mm"] = 15.0  # a small cam: the pressure angle goes over 30 deg
    answer = post(server.port, "/api/evaluate", {"seq": 2, "data": data})
    assert answer["ok"] and answer["verdict"] == "fail"
    failed = {c["name"]: c for c in answer["cams"][0]["checks"] if c["status"] == "fail"}
    assert failed["pressure_angle"]["value"] > failed["pressure_angle"]["limit"]
    assert failed["pressure_angle"]["keys"][0] == "cams.plate.base_radius_mm"


def test_bad_value_gives_the_line_camgen_check_prints(server, tmp_path):
    text = template_path("default").read_text(encoding="utf-8").replace("c_mm = 25.0", "c_mm = -5.0")
    scene = tmp_path / "default.toml"  # the server's scene name, so that every message is the same
    scene.write_text(text, encoding="utf-8")
    check = camgen("check", str(scene))
    assert check.returncode == 2
    answer = post(server.port, "/api/evaluate", {"seq": 3, "data": tomllib.loads(text)})
    assert answer["ok"] is False and answer["cams"] == [] and answer["seq"] == 3
    assert answer["error"]["message"] == check.stderr.strip()
    assert answer["error"]["key"] == "cams.stride_length.c_mm"


def test_files_dxf_equal_camgen_run_only_dxf(server, tmp_path):
    answer = post(server.port, "/api/files", {"data": default_data(), "formats": ["dxf"]})
    assert answer["error"] is None
    run = camgen("run", "-o", str(tmp_path), "--only", "dxf", "-q")
    assert run.returncode == 0, run.stderr
    written = {p.name: p.read_bytes() for p in (tmp_path / "default").iterdir()}
    assert sorted(f["name"] for f in answer["files"]) == sorted(written)
    assert {"stride_length.dxf", "stride_height.dxf", "steering.dxf"} <= set(written)
    for made in answer["files"]:
        status, data, headers = request(server.port, "GET", made["url"])
        assert status == 200 and len(data) == made["bytes"]
        assert data == written[made["name"]], made["name"]
        assert headers["content-disposition"] == f'attachment; filename="{made["name"]}"'
        assert "sandbox" in headers["content-security-policy"]


def test_save_of_an_unchanged_scene_keeps_its_text(server):
    text = template_path("plate_cam").read_text(encoding="utf-8")
    answer = post(server.port, "/api/save", {"text": text, "data": tomllib.loads(text)})
    assert answer == {"text": text, "error": None}


def test_save_keeps_the_comments_of_the_keys_kept(server):
    """With the comment-keeping editor (camgen.scene_edit, issue 28's): a changed value keeps its
    line's comment, and the others stay."""
    pytest.importorskip("camgen.scene_edit")
    text = template_path("plate_cam").read_text(encoding="utf-8")
    data = tomllib.loads(text)
    data["cams"]["plate"]["base_radius_mm"] = 45.0
    answer = post(server.port, "/api/save", {"text": text, "data": data})
    assert answer["error"] is None and tomllib.loads(answer["text"]) == data
    assert "base_radius_mm = 45.0        # the roller touches the cam 40 mm from the axis at zero lift" in answer["text"]
    assert [line for line in text.splitlines() if line.startswith("#")] == [line for line in answer["text"].splitlines()
                                                                             if line.startswith("#")]


def test_save_refuses_a_value_toml_cannot_hold(server):
    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    data["cams"]["plate"]["rpm"] = None
    answer = post(server.port, "/api/save", {"text": "", "data": data})
    assert answer["text"] is None and answer["error"]["message"].startswith("camgen: error: cams.plate.rpm:")


def test_save_gives_toml_camgen_run_accepts(server, tmp_path):
    text = template_path("plate_cam").read_text(encoding="utf-8")
    data = tomllib.loads(text)
    cam = data["cams"]["plate"]
    cam["base_radius_mm"] = 45.0
    cam["segments"][-1:] = [{"law": "dwell", "span_deg": 30.0}, {"law": "dwell", "span_deg": 30.0}]  # a segment added
    answer = post(server.port, "/api/save", {"text": text, "data": data})
    assert answer["error"] is None
    assert tomllib.loads(answer["text"]) == data
    saved = tmp_path / "plate_cam.toml"
    saved.write_text(answer["text"], encoding="utf-8")
    run = camgen("run", str(saved), "-o", str(tmp_path / "out"), "--only", "dxf", "-q")
    assert run.returncode == 0, run.stderr
    report = json.loads((tmp_path / "out" / "plate_cam" / "report.json").read_text(encoding="utf-8"))
    assert report["cams"]["plate"]["figures"]["base_radius_mm"] == 45.0
    assert len(report["cams"]["plate"]["figures"]["segments"]) == 5


def test_save_of_a_bad_scene_gives_the_line_camgen_check_prints(server, tmp_path):
    text = template_path("plate_cam").read_text(encoding="utf-8")
    data = tomllib.loads(text)
    data["cams"]["plate"]["roller_radius_mm"] = 0.0
    answer = post(server.port, "/api/save", {"text": text, "data": data})
    saved = tmp_path / "plate_cam.toml"
    saved.write_text(answer["text"], encoding="utf-8")
    check = camgen("check", str(saved))
    assert check.returncode == 2 and answer["error"]["message"] == check.stderr.strip()
    assert answer["error"]["key"] == "cams.plate.roller_radius_mm"


@pytest.mark.parametrize("name", sorted(p.stem for p in template_path("default").parent.glob("*.toml")))
def test_saved_text_parses_to_the_scene(name):
    """Every bundled scene written back (no comment-keeping editor): Python's TOML parser reads
    the same table."""
    data = tomllib.loads(template_path(name).read_text(encoding="utf-8"))
    assert tomllib.loads(scene_toml(data)) == data


def test_evaluations_at_once_keep_their_own_answers(server):
    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    radii = [38.0, 42.0, 46.0, 50.0]
    answers: dict[float, dict] = {}

    def one(radius: float) -> None:
        scene = json.loads(json.dumps(data))
        scene["cams"]["plate"]["base_radius_mm"] = radius
        answers[radius] = post(server.port, "/api/evaluate", {"seq": int(radius), "data": scene})

    threads = [threading.Thread(target=one, args=(r,)) for r in radii]
    for t in threads:
        t.start()
    for t in threads:
        t.join(TIMEOUT_S)
    for radius in radii:
        assert answers[radius]["seq"] == int(radius)
        assert answers[radius]["cams"][0]["figures"]["base_radius_mm"] == radius


# -- refusals ---------------------------------------------------------------------------------


def test_page_is_served_with_its_policy(server):
    status, data, headers = request(server.port, "GET", "/")
    assert status == 200 and headers["content-type"].startswith("text/html")
    assert headers["content-security-policy"].startswith("default-src 'self'")
    assert b"<html" in data.lower()


@pytest.mark.parametrize("host", ["evil.example", "evil.example:{port}", "127.0.0.1:1", "localhost", "", "10.0.0.1:{port}"])
def test_wrong_host_is_403(server, host):
    status, _, _ = request(server.port, "GET", "/api/scene", headers={"Host": host.format(port=server.port)})
    assert status == 403


@pytest.mark.parametrize("origin", ["http://evil.example", "http://127.0.0.1:1", "null", "https://127.0.0.1:{port}"])
def test_another_sites_page_is_403(server, origin):
    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    headers = {"Origin": origin.format(port=server.port)}
    assert request(server.port, "POST", "/api/evaluate", {"seq": 1, "data": data}, headers)[0] == 403
    assert request(server.port, "POST", "/api/evaluate", {"seq": 1, "data": data},
                   {"Origin": f"http://localhost:{server.port}", "Host": f"localhost:{server.port}"})[0] == 200


@pytest.mark.parametrize("host", ["localhost:{port}", "LOCALHOST:{port}", "[::1]:{port}"])
def test_loopback_names_are_answered(server, host):
    status, _, _ = request(server.port, "GET", "/api/scene", headers={"Host": host.format(port=server.port)})
    assert status == 200


def test_oversized_body_is_413_unread(server):
    conn = http_client(server.port)
    conn.putrequest("POST", "/api/evaluate", skip_host=True)
    conn.putheader("Host", f"127.0.0.1:{server.port}")
    conn.putheader("Content-Type", "application/json")
    conn.putheader("Content-Length", str(MAX_BODY + 1))
    conn.endheaders()  # no body sent: the server must answer from the headers alone
    response = conn.getresponse()
    assert response.status == 413
    conn.close()
    status, _, _ = request(server.port, "POST", "/api/evaluate", raw=b" " * MAX_BODY)  # the cap itself is read (not JSON: 400)
    assert status == 400


@pytest.mark.parametrize("path", ["/../pyproject.toml", "/%2e%2e/", "/%2E%2E/pyproject.toml", "/files/..%2f..%2fREADME.md/x",
                                  "/api/../api/scene", "/page.html", "/camgen/serve/page.html", "/files/", "/files/abc",
                                  "/files/AAAAAAAAAAAAAAAAAAAAAA/plate.dxf", "/api", "//etc/passwd", "/%5c..%5cpyproject.toml"])
def test_paths_outside_the_served_set_are_404(server, path):
    assert request(server.port, "GET", path)[0] == 404


def test_a_made_file_under_another_token_or_name_is_404(server):
    answer = post(server.port, "/api/files", {"data": tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8")),
                                              "formats": ["dxf"]})
    url = next(f["url"] for f in answer["files"] if f["name"] == "plate.dxf")
    _, _, token, name = url.split("/")
    assert request(server.port, "GET", url)[0] == 200
    assert request(server.port, "GET", f"/files/{token}/report.html")[0] == 404
    assert request(server.port, "GET", f"/files/{token[:-1] + ('A' if token[-1] != 'A' else 'B')}/{name}")[0] == 404


@pytest.mark.parametrize("method, path", [("GET", "/api/evaluate"), ("POST", "/"), ("POST", "/api/scene"), ("DELETE", "/"),
                                          ("PUT", "/api/save"), ("HEAD", "/api/scene")])
def test_wrong_method_is_405(server, method, path):
    status, _, headers = request(server.port, method, path, body={})
    assert status == 405 and headers["allow"] in ("GET", "POST")


@pytest.mark.parametrize("media", ["text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x"])
def test_post_that_is_not_json_is_415(server, media):
    assert request(server.port, "POST", "/api/evaluate", body={"seq": 1, "data": {}}, headers={"Content-Type": media})[0] == 415


@pytest.mark.parametrize("body", [b"not json", b"[1, 2]", b'{"seq": "1", "data": {}}', b'{"seq": 1}', b'{"data": {}, "formats": []}'])
def test_malformed_request_is_400(server, body):
    assert request(server.port, "POST", "/api/evaluate", raw=body)[0] == 400
    assert request(server.port, "POST", "/api/files", raw=body)[0] == 400


def test_file_store_keeps_the_newest_runs():
    store = FileStore(max_runs=2)
    first, second, third = (store.add({"a.txt": f"run {i}"})[0] for i in range(3))
    tokens = {f.url.split("/")[2] for f in (first, second, third)}
    assert len(tokens) == 3 and len(store) == 2
    assert store.get(first.url.split("/")[2], "a.txt") is None
    assert store.get(third.url.split("/")[2], "a.txt") == b"run 2"


# -- the command --------------------------------------------------------------------------------


def test_taken_port_is_one_line_exit_2():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        proc = camgen("serve", "--port", str(port))
    assert proc.returncode == 2 and proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("camgen: error:")
    assert str(port) in lines[0] and "--port" in lines[0]


def test_remote_host_needs_the_flag():
    proc = camgen("serve", "--host", "0.0.0.0", "--port", "0")
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1 and "--allow-remote" in proc.stderr


def test_camgen_serve_prints_its_url_and_stops_on_ctrl_c(tmp_path):
    scene = tmp_path / "plate.toml"
    scene.write_text(template_path("plate_cam").read_text(encoding="utf-8"), encoding="utf-8")
    proc = subprocess.Popen([sys.executable, "-m", "camgen", "serve", str(scene), "--port", "0"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    try:
        line = proc.stdout.readline()
        assert line.startswith("camgen: serving") and "http://127.0.0.1:" in line
        port = int(line.split("http://127.0.0.1:")[1].split("/")[0])
        status, data, _ = request(port, "GET", "/api/scene")
        assert status == 200 and json.loads(data)["text"] == scene.read_text(encoding="utf-8")
        for cut in (b"POST /api/evaluate HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: application/json\r\n"
                    b"Content-Length: 100\r\n\r\n{\"seq\"" % port, b"GET /api/sch"):  # browsers that go away mid-request
            with socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT_S) as conn:
                conn.sendall(cut)
        assert request(port, "GET", "/api/scene")[0] == 200  # still serving
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=TIMEOUT_S)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130
    assert err.strip().splitlines() == ["camgen: stopped by SIGINT; the previous outputs are as they were"]  # no traceback
    assert sorted(os.listdir(tmp_path)) == ["plate.toml"]  # nothing written
