"""The exit-status contract: a design that fails a check writes report.json and report.html
showing it (plots included), no manufacturing file for a cam that cannot be made as designed,
one stderr line per failed check, and exits 1; information is never a pass."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from camgen.cli import main

MANUFACTURING = ("dxf", "_points.csv", "_lift.csv", ".stl", ".ngc")

UNDERCUT = """
[output]
formats = ["dxf", "points", "lift", "stl", "ngc", "html"]
[cams.u]
kind = "motion_law"
base_radius_mm = {base}
{follower}
[[cams.u.segments]]
law = "cycloidal"
span_deg = 60.0
lift_mm = 30.0
[[cams.u.segments]]
law = "dwell"
span_deg = 120.0
[[cams.u.segments]]
law = "cycloidal"
span_deg = 60.0
lift_mm = -30.0
[[cams.u.segments]]
law = "dwell"
span_deg = 120.0
"""


def _cycloidal_program(theta):
    """s, s', s'' (mm, per rad) of the UNDERCUT program, written out here from the law."""
    beta, h = math.radians(60.0), 30.0
    theta = np.mod(theta, 2 * math.pi)
    rise, ret = theta < beta, (theta >= math.radians(180)) & (theta < math.radians(240))
    tau = np.where(rise, theta / beta, np.where(ret, (theta - math.radians(180)) / beta, 0.0))
    sign = np.where(rise, 1.0, np.where(ret, -1.0, 0.0))
    s = np.where(rise, h * (tau - np.sin(2 * math.pi * tau) / (2 * math.pi)), 0.0)
    s = np.where(ret, h - h * (tau - np.sin(2 * math.pi * tau) / (2 * math.pi)), s)
    s = np.where((theta >= beta) & (theta < math.radians(180)), h, s)
    ds = sign * h / beta * (1 - np.cos(2 * math.pi * tau))
    d2s = sign * h / beta**2 * 2 * math.pi * np.sin(2 * math.pi * tau)
    return s, ds, d2s


def _run(tmp_path, text, capsys, name="scene"):
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    status = main(["run", str(path), "-o", str(tmp_path / "out")])
    captured = capsys.readouterr()
    folder = tmp_path / "out" / name
    return status, folder, captured.err


def _failed_lines(err, cam):
    return [line for line in err.splitlines() if line.startswith(f"camgen: check failed: cams.{cam}: ")]


def test_roller_undercut_writes_the_report_and_no_manufacturing_file(tmp_path, capsys):
    status, folder, err = _run(tmp_path, UNDERCUT.format(base=20.0, follower="roller_radius_mm = 25.0"), capsys)
    assert status == 1
    assert sorted(p.name for p in folder.iterdir()) == ["report.html", "report.json"]
    report = json.loads((folder / "report.json").read_text())
    cam = report["cams"]["u"]
    assert report["status"] == "fail" and cam["manufacturable"] is False
    assert sorted(cam["withheld_files"]) == sorted(["u.dxf", "u_points.csv", "u_lift.csv", "u.stl", "u.ngc"])
    undercut = next(c for c in cam["checks"] if c["name"] == "undercut")
    assert undercut["status"] == "fail" and undercut["blocks_manufacture"] and undercut["comparison"] == ">"
    # the pitch curve of a radial roller is the polar curve r = Rp + s(theta) at polar angle pi/2 - theta:
    # its radius of curvature (r^2 + r'^2)^1.5 / (r^2 + 2 r'^2 - r r'') in closed form
    theta = np.linspace(0, 2 * math.pi, 200001)
    s, ds, d2s = _cycloidal_program(theta)
    r, r1, r2 = 45.0 + s, -ds, d2s
    rho = (r * r + r1 * r1) ** 1.5 / (r * r + 2 * r1 * r1 - r * r2)
    assert undercut["value"] == pytest.approx(rho[rho > 0].min(), rel=1e-4)
    # one stderr line per failed check, each naming the cam and the check
    failed = [c["name"] for c in cam["checks"] if c["status"] == "fail"]
    assert len(_failed_lines(err, "u")) == len(failed) >= 1
    page = (folder / "report.html").read_text()
    assert "pitch curve to scale; the profile cannot be made (undercut)" in page
    assert "radius of curvature of the pitch curve" in page and page.count("<svg") >= 2


def test_flat_follower_undercut_reports_where(tmp_path, capsys):
    status, folder, err = _run(tmp_path, UNDERCUT.format(base=30.0, follower='follower = "flat"'), capsys)
    assert status == 1 and not [p for p in folder.iterdir() if p.name.endswith(MANUFACTURING)]
    check = next(c for c in json.loads((folder / "report.json").read_text())["cams"]["u"]["checks"] if c["name"] == "undercut")
    # the flat face's envelope has radius of curvature Rb + s + s'' (Norton eq. 8.31): closed form, its
    # minimum on a 1e-3 deg grid; camgen checks a 0.05 deg grid (its minimum is off by < 1e-5 relative)
    theta = np.linspace(0, 2 * math.pi, 360001)
    s, _, d2s = _cycloidal_program(theta)
    assert check["status"] == "fail" and check["value"] == pytest.approx(np.min(30.0 + s + d2s), rel=1e-5)
    # the two regions where it is <= 0: their ends within one sample (0.5 deg) of the closed form
    fine = np.linspace(0, 2 * math.pi, 720001)
    s, _, d2s = _cycloidal_program(fine)
    bad = 30.0 + s + d2s <= 0
    edges = np.degrees(fine[np.nonzero(np.diff(bad.astype(int)))[0]])
    assert len(check["where_deg"]) == 4
    assert np.allclose(sorted(check["where_deg"]), np.sort(edges), atol=0.5)
    assert _failed_lines(err, "u")


def test_pressure_angle_failure_exits_1_and_still_writes_the_makeable_cam(tmp_path, capsys):
    text = ('[output]\nformats = ["dxf", "points"]\n[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 160\nc_mm = 25\n'
            'follower = "roller"\nroller_radius_mm = 10\npressure_angle_limit_deg = 10\n')
    status, folder, err = _run(tmp_path, text, capsys)
    assert status == 1
    assert {"x.dxf", "x_points.csv", "report.json"} <= {p.name for p in folder.iterdir()}
    cam = json.loads((folder / "report.json").read_text())["cams"]["x"]
    check = next(c for c in cam["checks"] if c["name"] == "pressure_angle")
    assert check["status"] == "fail" and check["comparison"] == "<=" and check["limit"] == pytest.approx(10.0)
    assert cam["manufacturable"] is True and cam["withheld_files"] == []
    assert [line for line in _failed_lines(err, "x") if ": pressure_angle = " in line and "must be <= 10" in line]


def test_broken_wall_blocks_the_cam(tmp_path, capsys):
    text = ('[output]\nformats = ["dxf", "stl"]\n[cams.x]\nkind = "three_arc"\na_mm = 220\nb_mm = 160\nc_mm = 25\n'
            'bore_diameter_mm = 48\nmin_wall_mm = 3\n')
    status, folder, err = _run(tmp_path, text, capsys)
    assert status == 1 and sorted(p.name for p in folder.iterdir()) == ["report.json"]
    check = next(c for c in json.loads((folder / "report.json").read_text())["cams"]["x"]["checks"] if c["name"] == "wall_thickness")
    # the base arc is c = 25 mm from the axis, the bore 24 mm: 1 mm, less the stated 1e-4 mm measuring allowance
    assert check["status"] == "fail" and check["value"] == pytest.approx(25.0 - 24.0 - 1e-4, abs=1e-9) and check["comparison"] == ">="
    assert _failed_lines(err, "x")


def test_tool_that_would_gouge_blocks_the_gcode(tmp_path, capsys):
    text = ('[output]\nformats = ["dxf", "ngc"]\n[machining]\ntool_diameter_mm = 20.0\n'
            '[cams.s]\nkind = "trajectory"\nexpression = "40*sin(2*pi*x/400)"\nperiod_mm = 400\n')
    status, folder, err = _run(tmp_path, text, capsys)
    # the ride simulation (not a manufacturing file) is written; the DXF and G-code are not
    assert status == 1 and sorted(p.name for p in folder.iterdir()) == ["report.json", "s_ride.csv"]
    check = next(c for c in json.loads((folder / "report.json").read_text())["cams"]["s"]["checks"] if c["name"] == "min_concave_radius")
    assert check["status"] == "fail" and check["limit"] == 10.0 and check["blocks_manufacture"]
    # the concave radius is where an offset of the profile reverses (an independent computation)
    from camgen.errors import GeometryError
    from camgen.scene import load_scene
    from camgen.pipeline import Plan, compute

    contour = compute(load_scene(tmp_path / "scene.toml"), Plan((), frozenset())).cams[0].contour
    contour.offset(check["value"] - 0.05, spline_tol=1e-5)
    with pytest.raises(GeometryError):
        contour.offset(check["value"] + 0.05, spline_tol=1e-5)
    assert _failed_lines(err, "s")


def test_without_a_named_tool_concave_radii_are_information(tmp_path, capsys):
    text = ('[output]\nformats = ["dxf"]\n[cams.s]\nkind = "trajectory"\nexpression = "40*sin(2*pi*x/400)"\nperiod_mm = 400\n'
            'pressure_angle_limit_deg = 60\n')  # this sharp path's rod sees 49.5 deg
    status, folder, _ = _run(tmp_path, text, capsys)
    assert status == 0 and (folder / "s.dxf").exists()
    check = next(c for c in json.loads((folder / "report.json").read_text())["cams"]["s"]["checks"] if c["name"] == "min_concave_radius")
    assert check["status"] == "info" and check["limit"] is None


def test_information_is_never_a_pass(default_run):
    report = json.loads((default_run / "report.json").read_text())
    checks = [c for cam in report["cams"].values() for c in cam["checks"]]
    info = [c for c in checks if c["limit"] is None]
    assert info and all(c["status"] == "info" and c["comparison"] == "" for c in info)  # follower motion, convex radius ...
    assert all(c["comparison"] in ("<=", "<", ">=", ">", "at least") for c in checks if c["limit"] is not None)
