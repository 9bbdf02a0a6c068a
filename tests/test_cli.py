"""The command line: `--only` plans only the stages its formats need (checked in a child
process: the modules it imported and the stages report.json records), `camgen check` exit
codes, `camgen new` then `camgen run`, the key reference, help, version, and a kind registered
from outside the package."""
from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

import camgen
from camgen.cli import main
from helpers import CHECKOUT

#: Modules of stages a DXF-only job must not run: the error-model fit (camgen's tricycle_fit; its
#: scipy.optimize cannot tell, scipy.interpolate imports it), meshes (manifold3d, trimesh, meshio),
#: STEP (OCP), report.html (matplotlib and camgen's page).
HEAVY = ("camgen.mechanisms.tricycle_fit", "camgen.export.solid", "manifold3d", "trimesh", "meshio", "matplotlib", "OCP",
         "camgen.report.html")

PROBE = (
    "import sys, json; from camgen.cli import main; status = main(sys.argv[3:] + ['-o', sys.argv[1], '--quiet']);"
    "print('STATUS=%d' % status); print('MODULES=' + json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
    "('scipy', 'manifold3d', 'trimesh', 'meshio', 'matplotlib', 'OCP', 'ezdxf', 'camgen'))))"
)


def _child_run(outdir, *args):
    proc = subprocess.run([sys.executable, "-c", PROBE, str(outdir), "unused", *args], capture_output=True, text=True, timeout=300)
    assert "Traceback" not in proc.stderr, proc.stderr
    lines = dict(line.split("=", 1) for line in proc.stdout.splitlines() if "=" in line)
    return int(lines["STATUS"]), set(json.loads(lines["MODULES"])), proc


@pytest.mark.parametrize("fmt, expect_modules, absent_modules", [
    ("dxf", {"camgen.export.dxfwriter"}, HEAVY + ("ezdxf",)),  # camgen's own writer: no ezdxf at run time
    ("points", set(), HEAVY + ("ezdxf",)),
    ("lift", set(), HEAVY + ("ezdxf",)),
    ("ngc", set(), HEAVY + ("ezdxf",)),
    ("stl", {"manifold3d", "camgen.export.solid"}, ("camgen.mechanisms.tricycle_fit", "trimesh", "meshio", "matplotlib", "ezdxf")),
])
def test_only_runs_the_stages_its_format_needs(fmt, expect_modules, absent_modules, tmp_path):
    status, modules, _ = _child_run(tmp_path, "run", "--only", fmt)
    assert status == 0
    assert expect_modules <= modules
    assert not [m for m in absent_modules if m in modules], modules
    folder = tmp_path / "default"
    suffix = {"dxf": ".dxf", "points": "_points.csv", "lift": "_lift.csv", "ngc": ".ngc", "stl": ".stl"}[fmt]
    written = sorted(p.name for p in folder.iterdir())
    assert written == sorted([f"{c}{suffix}" for c in ("stride_length", "stride_height", "steering")] + ["report.json"])
    report = json.loads((folder / "report.json").read_text())
    assert report["stages"] == (["mesh"] if fmt == "stl" else [])
    # no ride simulation, no fit, no sweep: their figures are absent, the checks are all there
    steering = report["cams"]["steering"]["figures"]
    assert "ride_max_error_mm" not in steering and "fits" not in steering
    assert "sweep" not in report["mechanisms"]["horse_leg"]
    assert {c["name"] for c in report["cams"]["steering"]["checks"]} >= {"undercut", "pressure_angle", "continuity"}


def test_full_run_runs_every_stage(default_run):
    report = json.loads((default_run / "report.json").read_text())
    assert report["stages"] == ["analysis", "mesh", "plots"]
    assert "fits" in report["cams"]["steering"]["figures"] and "sweep" in report["mechanisms"]["horse_leg"]


def test_only_refuses_an_unknown_format(tmp_path, capsys):
    assert main(["run", "--only", "dxf,dwg", "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--only" in err and "dwg" in err
    assert not (tmp_path / "out").exists()


def _scene(tmp_path, body: str, name: str = "s.toml"):
    path = tmp_path / name
    path.write_text(body)
    return str(path)


def test_check_exit_codes_and_table(tmp_path, capsys):
    good = _scene(tmp_path, '[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 160\nc_mm = 25\n')
    assert main(["check", good]) == 0
    table = capsys.readouterr().out
    assert "constant_breadth" in table and "pass" in table and "FAIL" not in table
    # pressure angle above its limit: a translating roller on the three-arc cam with a 10 deg limit
    bad = _scene(tmp_path, '[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 160\nc_mm = 25\nfollower = "roller"\n'
                           'roller_radius_mm = 10\npressure_angle_limit_deg = 10\n', "bad.toml")
    assert main(["check", bad]) == 1
    captured = capsys.readouterr()
    assert "pressure_angle" in captured.out and "FAIL" in captured.out
    assert [line for line in captured.err.splitlines() if line.startswith("camgen: check failed: cams.x: pressure_angle")]
    wrong = _scene(tmp_path, '[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 600\nc_mm = 25\n', "wrong.toml")
    assert main(["check", wrong]) == 2
    assert "cams.x.b_mm" in capsys.readouterr().err
    assert not list(tmp_path.glob("outputs"))  # check writes nothing


def test_new_then_run_the_copy(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["templates"]) == 0
    listing = capsys.readouterr().out
    for name in ("default", "horse_leg", "motion_law", "tricycle"):
        assert any(line.startswith(name + " ") and len(line) > len(name) + 10 for line in listing.splitlines())
    assert main(["new", "motion_law", "my_cam.toml"]) == 0
    capsys.readouterr()
    assert main(["new", "motion_law", "my_cam.toml"]) == 2  # never overwrites
    assert "exists" in capsys.readouterr().err
    assert main(["run", "my_cam.toml", "-o", "build", "--quiet"]) == 0
    assert capsys.readouterr().out == ""  # --quiet prints nothing
    written = {p.name for p in (tmp_path / "build" / "my_cam").iterdir()}
    assert {"rise_return.dxf", "rise_return.ngc", "report.json"} <= written
    assert main(["new", "no_such_template"]) == 2


def test_key_reference_is_current():
    """docs/scene-keys.md (in the repository) is exactly what `camgen keys` prints."""
    from camgen.keyref import reference

    assert (CHECKOUT / "docs" / "scene-keys.md").read_text(encoding="utf-8") == reference(), \
        "regenerate it: camgen keys > docs/scene-keys.md"


def test_keys_command(capsys):
    assert main(["keys", "motion_law"]) == 0
    text = capsys.readouterr().out
    assert "`base_radius_mm`" in text and "`span_deg`" in text and "`a_mm`" not in text
    assert main(["keys", "nonsense"]) == 2
    assert "keys" in capsys.readouterr().err


def test_every_key_is_documented_with_its_effect():
    from camgen.jobs import get_job, job_names
    from camgen.kinds import get_kind, kind_names
    from camgen.outputs import machining_keys, output_keys
    from camgen.schema import EFFECTS

    groups = [get_kind(k).keys for k in kind_names()] + [get_job(j).keys for j in job_names()] + [output_keys(), machining_keys()]
    for keys in groups:
        for key in keys:
            assert key.doc.strip() and key.affects and set(key.affects) <= set(EFFECTS), key.name


@pytest.mark.parametrize("command", ["run", "check", "templates", "new", "keys"])
def test_help_has_examples(command, capsys):
    with pytest.raises(SystemExit) as stop:
        main([command, "--help"])
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert "examples:" in out and f"camgen {command}" in out


def test_version(capsys):
    with pytest.raises(SystemExit):
        main(["--version"])
    assert capsys.readouterr().out.strip() == f"camgen {camgen.__version__}"


def test_a_kind_registered_from_outside_runs_end_to_end(tmp_path):
    """Adding a motion that is a design of its own (it makes its plate cam itself) is one module and one
    registry line: a circular disc cam defined here."""
    import math

    from camgen.checks import Follower
    from camgen.contour import Arc, Contour
    from camgen.motions import Motion, register, unregister
    from camgen.kinds.base import (
        BuiltCam,
        CamKind,
        CamSpec,
        body_keys,
        check_keys,
        read_body,
        read_checks,
    )
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene
    from camgen.schema import REQUIRED, Key, Length

    def read(where, name, parsed, base_dir=None):
        return CamSpec(name, "disc", parsed["radius"], read_body(where, parsed), read_checks(parsed), Follower("flat"))

    def build(spec, stages):
        contour = Contour([Arc((0.0, 0.0), spec.params, 0.0, 2 * math.pi)])
        return BuiltCam(spec.name, spec.kind, contour, {"radius_mm": spec.params}, spec.body, spec.follower)

    keys = (Key("radius_mm", Length(), "Radius of the disc.", ("profile",), default=REQUIRED),) + body_keys() + check_keys()
    register(Motion("disc", "a circular disc", realisations={"plate": CamKind("disc", "a circular disc", keys, read, build)}))
    try:
        scene = parse_scene({"output": {"formats": ["dxf", "points"]}, "cams": {"d": {"kind": "disc", "radius_mm": 30.0}}}, "t")
        result = execute(scene, plan_run(scene))
        assert {"d.dxf", "d_points.csv", "report.json"} <= set(result.files)
        report = json.loads(result.files["report.json"])
        assert report["cams"]["d"]["kind"] == "disc" and report["status"] == "pass"
        # the flat face on a circle: constant breadth absent (no yoke), zero pressure angle, undercut passes
        checks = {c["name"]: c for c in report["cams"]["d"]["checks"]}
        assert checks["undercut"]["status"] == "pass" and checks["undercut"]["value"] == pytest.approx(1 / 30.0)
    finally:
        unregister("disc")


def _run_on_terminal(args, tmp_path):
    """stderr of `camgen run` with stderr on a pseudo-terminal (what a user's shell gives it)."""
    import os
    import pty

    leader, follower = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "camgen", "run", *args, "-o", str(tmp_path)], stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=follower, env={**os.environ, "COLUMNS": "100", "TERM": "xterm"})
    os.close(follower)
    chunks = []
    while True:
        try:
            data = os.read(leader, 4096)
        except OSError:  # the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    os.close(leader)
    assert proc.wait(timeout=300) == 0
    return b"".join(chunks).decode("utf-8", "replace")


def test_progress_is_shown_on_a_terminal_for_long_runs_only(tmp_path):
    """A long run (the default scene at a 10 nm chord tolerance with every surface mesh format:
    several seconds) shows its steps on stderr on a terminal; with --quiet, or with stderr not a
    terminal, nothing is printed there."""
    from camgen.outputs import OUTPUTS
    from camgen.scene import template_path

    formats = ", ".join(f'"{name}"' for name, fmt in OUTPUTS.items()
                        if not fmt.implied and name not in ("step", "follower", "vtu", "msh", "inp")  # FEA meshes: minutes here
                        and name not in ("drawing", "drawing_pdf", "inspection"))  # the drawing: disk cams only, none here
    text = template_path("default").read_text(encoding="utf-8")
    text = re.sub(r"(?m)^formats = .*$", f"formats = [{formats}]", text)
    text = text.replace("chord_tol_mm = 0.001", "chord_tol_mm = 0.00001").replace("tool_diameter_mm = 8.0", "tool_diameter_mm = 8.0\ndecimals = 6")
    scene = tmp_path / "long.toml"
    scene.write_text(text, encoding="utf-8")
    shown = _run_on_terminal([str(scene)], tmp_path / "a")
    assert any(step in shown for step in ("building cam", "checking cam", "writing ")), shown[-500:]
    assert _run_on_terminal(["--quiet"], tmp_path / "b").strip() == ""
    piped = subprocess.run([sys.executable, "-m", "camgen", "run", "-o", str(tmp_path / "c")], capture_output=True, text=True)
    assert piped.returncode == 0 and piped.stderr == ""
