"""End-to-end `camgen run`: files, report layout, independent DXF readers, determinism, errors."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

import camgen
from camgen.cli import main
from helpers import distance_to_arcs

PAPER = {"stride_length": (220.0, 160.0, 25.0, 330.0), "stride_height": (220.0, 220.0, 10.0, 240.0)}


def test_default_scene_writes_dxf_csv_and_report(default_run):
    names = sorted(p.name for p in default_run.iterdir())
    per_cam = [".dxf", "_points.csv", "_lift.csv", ".stl", ".3mf", ".ngc"]
    expected = [f"{cam}{suffix}" for cam in ("stride_length", "stride_height", "steering") for suffix in per_cam]
    legs = [f"leg_path_alpha_{a}.csv" for a in ("12.5", "14.5", "18.5")]
    assert names == sorted(expected + legs + ["steering_ride.csv", "report.json", "report.html"])
    assert not [p for p in default_run.iterdir() if p.name.startswith(".")]  # no temp files left


def test_report_json_layout_and_paper_figures(default_run):
    report = json.loads((default_run / "report.json").read_text())
    assert set(report) >= {"scene", "camgen_version", "cams", "mechanisms"}
    assert report["scene"] == "default" and report["camgen_version"] == camgen.__version__
    for name, (a, b, c, yoke) in PAPER.items():
        cam = report["cams"][name]
        assert cam["kind"] == "three_arc"
        fig = cam["figures"]
        assert fig["breadth_mm"] == yoke  # paper 000, Section 6: 2 e2 = 330, 2 e5 = 240
        assert fig["breadth_error_mm"] <= 1e-9
        assert fig["base_radius_mm"] == c and fig["max_radius_mm"] == 2 * a + c - b
        for check in cam["checks"]:
            assert set(check) >= {"name", "status", "value", "limit", "comparison", "unit", "where_deg"}
            assert check["status"] in ("pass", "info")
            # a check with a limit states how the value must compare with it; information has none
            assert (check["limit"] is None) == (check["status"] == "info") == (check["comparison"] == "")
        continuity = next(ch for ch in cam["checks"] if ch["name"] == "continuity")
        assert continuity["value"] == "G1" and len(continuity["where_deg"]) == 6


def test_dxf_read_back_by_ezdxf(default_run):
    import ezdxf

    for name, (a, b, c, _) in PAPER.items():
        doc = ezdxf.readfile(default_run / f"{name}.dxf")
        assert doc.dxfversion == "AC1024" and doc.header["$INSUNITS"] == 4
        auditor = doc.audit()
        assert not auditor.has_errors
        arcs = [e for e in doc.modelspace() if e.dxftype() == "ARC" and e.dxf.layer == "PROFILE"]
        assert len(arcs) == 6 and all(e.dxf.layer == "PROFILE" for e in arcs)
        cam = camgen.three_arc_cam(a, b, c)
        for entity, seg in zip(arcs, cam.segments):
            center = entity.dxf.center
            assert np.allclose([center.x, center.y], seg.center, atol=1e-9)
            assert entity.dxf.radius == pytest.approx(seg.radius, abs=1e-9)
            # ARC runs counter-clockwise from start_angle: its start point is the segment's
            start = math.radians(entity.dxf.start_angle)
            p = np.array([center.x, center.y]) + entity.dxf.radius * np.array([math.cos(start), math.sin(start)])
            assert np.allclose(p, seg.start_point, atol=1e-9)
        # the radii are the paper's: c, a+c, a+c-b, 2a+c-b, a+c-b, a+c
        assert [e.dxf.radius for e in arcs] == pytest.approx([c, a + c, a + c - b, 2 * a + c - b, a + c - b, a + c])


def _chain(pieces: list) -> np.ndarray:
    """The pieces (n_i, 2) joined end to end into one ring, each turned round where needed
    (GDAL returns DXF arcs running clockwise)."""
    ring = [pieces[0]]
    rest = list(pieces[1:])
    while rest:
        end = ring[-1][-1]
        gaps = [min(np.hypot(*(p[0] - end)), np.hypot(*(p[-1] - end))) for p in rest]
        piece = rest.pop(int(np.argmin(gaps)))
        ring.append(piece if np.hypot(*(piece[0] - end)) <= np.hypot(*(piece[-1] - end)) else piece[::-1])
    return np.concatenate(ring)


def test_dxf_read_back_by_gdal(default_run):
    import pyogrio
    import shapely
    for name, (a, b, c, _) in PAPER.items():
        meta, _, wkb, fields = pyogrio.raw.read(default_run / f"{name}.dxf")
        layer = fields[list(meta["fields"]).index("Layer")]
        geoms = shapely.from_wkb(wkb)[layer == "PROFILE"]
        assert len(geoms) == 6
        pts = np.concatenate([shapely.get_coordinates(g) for g in geoms])
        cam = camgen.three_arc_cam(a, b, c)
        assert np.max(distance_to_arcs(pts, cam.segments)) <= 1e-6
        # GDAL's vertices cover the whole profile: the polygon through them (the six pieces in
        # drawing order) has the cam's area less the circular segments cut off by GDAL's chords
        # (each r^2 (d - sin d) / 2 for a chord over d; GDAL steps every 4 deg by default, so each
        # chord's segment is at most that of a full 4-deg step: a closed-form bound)
        polygon = shapely.Polygon(_chain([shapely.get_coordinates(g) for g in geoms]))
        step = math.radians(4.0)
        deficit = sum(seg.radius**2 * (step - math.sin(step)) / 2 * math.ceil(abs(seg.sweep) / step) for seg in cam.segments)
        assert 0.0 <= cam.area - polygon.area <= deficit


def test_points_csv_lies_on_the_contour(default_run):
    import pandas

    report = json.loads((default_run / "report.json").read_text())
    for name, (a, b, c, _) in PAPER.items():
        frame = pandas.read_csv(default_run / f"{name}_points.csv")  # the reader's defaults: header row, numbers
        assert list(frame.columns) == ["x_mm", "y_mm"]
        assert report["tables"][f"{name}_points.csv"]["chord_tol_mm"] == 1e-3  # the template's tolerance
        data = frame.to_numpy()
        cam = camgen.three_arc_cam(a, b, c)
        assert np.max(distance_to_arcs(data, cam.segments)) <= 2e-9  # printed with 9 decimals
        # consecutive points: the chord sagitta stays within the tolerance (r (1 - cos(angle/2)))
        closed = np.vstack([data, data[:1]])
        chord = np.linalg.norm(np.diff(closed, axis=0), axis=1)
        assert np.max(chord) <= 2 * math.sqrt(2 * (2 * a + c - b) * 1e-3) + 1e-6


def test_same_scene_gives_identical_bytes_in_other_processes(default_run, tmp_path):
    for seed in ("0", "12345"):
        env = dict(os.environ, PYTHONHASHSEED=seed)
        subprocess.run([sys.executable, "-m", "camgen", "run", "-o", str(tmp_path / seed)], check=True, env=env, capture_output=True)
        for path in default_run.iterdir():
            assert (tmp_path / seed / "default" / path.name).read_bytes() == path.read_bytes(), path.name


HEAVY_PROBE = (
    "import sys; from camgen.cli import main; main(['run', *sys.argv[2:], '-o', sys.argv[1]]);"
    "heavy = [m for m in ('manifold3d', 'trimesh', 'matplotlib', 'meshio', 'scipy') if m in sys.modules];"
    "print('HEAVY=' + ','.join(heavy))"
)


def test_dxf_only_job_does_not_import_heavy_libraries(tmp_path):
    # a DXF + CSV job with a spline cam: nothing heavy (camgen's splines are numpy)
    scene = tmp_path / "spline.toml"
    scene.write_text('[output]\nformats = ["dxf", "points"]\n[cams.s]\nkind = "trajectory"\nexpression = "202.4396*sin(pi*x/1000)"\nperiod_mm = 2000\n')
    out = subprocess.run([sys.executable, "-c", HEAVY_PROBE, str(tmp_path), str(scene)], check=True, capture_output=True, text=True)
    assert out.stdout.strip().splitlines()[-1] == "HEAVY="
    # a three-arc DXF job needs none of them
    scene = tmp_path / "arcs.toml"
    scene.write_text('[output]\nformats = ["dxf"]\n[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 160\nc_mm = 25\n')
    out = subprocess.run([sys.executable, "-c", HEAVY_PROBE, str(tmp_path), str(scene)], check=True, capture_output=True, text=True)
    assert out.stdout.strip().splitlines()[-1] == "HEAVY="
    assert sorted(p.name for p in (tmp_path / "arcs").iterdir()) == ["report.json", "x.dxf"]
    bare = subprocess.run([sys.executable, "-c", "import camgen, camgen.cli, sys; print('numpy' in sys.modules)"],
                          check=True, capture_output=True, text=True)
    assert bare.stdout.strip() == "False"


# --- bad input: one line, exit 2, nothing written ----------------------------------------------------
BAD_SCENES = {
    "toml": ("[cams.x\nkind = 1", "not valid TOML"),
    "unknown_key": ('[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 160\nc_mm = 25\nd_mm = 3', "unknown key(s) 'd_mm'"),
    "missing": ('[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 160', "missing key(s) 'c_mm'"),
    "kind": ('[cams.x]\nkind = "eval(1)"', "cams.x.kind"),
    "domain": ('[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 300\nc_mm = 25', "cams.x.b_mm"),
    "type": ('[cams.x]\nkind = "three_arc"\na_mm = "220"\nb_mm = 160\nc_mm = 25', "cams.x.a_mm"),
    "nan": ('[cams.x]\nkind = "three_arc"\na_mm = nan\nb_mm = 160\nc_mm = 25', "cams.x.a_mm"),
    "format": ('[output]\nformats = ["dwg"]\n[cams.x]\nkind = "three_arc"\na_mm = 1\nb_mm = 1\nc_mm = 1', "output.formats"),
    "tol": ('[output]\nchord_tol_mm = 0\n[cams.x]\nkind = "three_arc"\na_mm = 1\nb_mm = 1\nc_mm = 1', "output.chord_tol_mm"),
    "name": ('name = "../evil"\n[cams.x]\nkind = "three_arc"\na_mm = 1\nb_mm = 1\nc_mm = 1', "parameter 'name'"),
    "nocams": ('name = "x"', "missing key(s) 'cams'"),
    "segments": ('[cams.m]\nkind = "motion_law"\nbase_radius_mm = 40\n[[cams.m.segments]]\nlaw = "cycloidal"\nspan_deg = 90\nlift_mm = 5',
                 "cams.m.segments"),
    "law": ('[cams.m]\nkind = "motion_law"\nbase_radius_mm = 40\n[[cams.m.segments]]\nlaw = "sine"\nspan_deg = 360', "cams.m.segments[0].law"),
}


@pytest.mark.parametrize("case", BAD_SCENES)
def test_bad_scene_one_line_error_nothing_written(case, tmp_path, capsys):
    text, expected = BAD_SCENES[case]
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    out = tmp_path / "out"
    assert main(["run", str(scene), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1
    assert expected in err
    assert not out.exists() or not any(out.rglob("*"))


def test_missing_scene_file(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.toml"), "-o", str(tmp_path)]) == 2
    assert "cannot read scene file" in capsys.readouterr().err


def test_console_script_entry_point(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "camgen", "run", str(tmp_path / "missing.toml")], capture_output=True, text=True)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr


@pytest.mark.parametrize("template", ["tricycle", "horse_leg", "motion_law", "plate_cam", "flat_follower", "knife_follower",
                                      "oscillating_roller", "oscillating_flat", "lift_table", "groove_cam", "conjugate_cam", "constant_breadth",
                                      "barrel_cam", "packaging_machine"])
def test_bundled_templates_run(template, tmp_path):
    from camgen.scene import template_path

    assert main(["run", str(template_path(template)), "-o", str(tmp_path)]) == 0
    report = json.loads((tmp_path / template / "report.json").read_text())
    assert report["status"] == "pass"
    assert all(check["status"] != "fail" for cam in report["cams"].values() for check in cam["checks"])
    assert (tmp_path / template / "report.html").stat().st_size > 10_000
