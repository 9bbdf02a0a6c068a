"""camgen's CSV files open with every reader's default settings (issue 21, item 13).

Every CSV a run writes (point lists, lift tables, follower tables, trajectory rides, horse-leg
paths) is read by ``pandas.read_csv(path)`` with no arguments: its columns are the ones
report.json's ``tables`` object describes, every column is float64, and the numbers are
compared with sources outside the writer: the paper's three-arc cam, the cycloidal law written
out, the tricycle's target path y = 202.4396 sin(pi x / 1000) (paper 004, eq. 15), the scene
files' own settings (read with tomllib).  LibreOffice Calc (when installed) opens them with its
default CSV filter into one column per field.
"""
from __future__ import annotations

import math
import subprocess
import tomllib

import numpy as np
import pytest

from helpers import distance_to_arcs, require_tool

TWO_PI = 2.0 * math.pi
#: The paper-000 three-arc cams of the default template: (a, b, c) mm (c: the base radius).
PAPER = {"stride_length": (220.0, 160.0, 25.0), "stride_height": (220.0, 220.0, 10.0)}
#: Templates whose runs hold every kind of CSV: default (points, lift, ride, legs; the session's
#: default_run), plate_cam (a translating follower's table), oscillating_roller (an oscillating one).
FOLLOWER_TEMPLATES = ("plate_cam", "oscillating_roller")


#: Column name endings and the units they stand for (longest first).
UNITS = {"mm_per_s": "mm/s", "m_per_s2": "m/s^2", "m_per_s3": "m/s^3", "rad_per_s": "rad/s", "rad_per_s2": "rad/s^2",
         "rad_per_s3": "rad/s^3", "mm": "mm", "deg": "deg", "s": "s"}


def template_toml(name: str) -> dict:
    from camgen.scene import template_path

    return tomllib.loads(template_path(name).read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def follower_runs(tmp_path_factory):
    """``camgen run --only points,lift,follower`` of the follower templates: name -> output folder."""
    from camgen.cli import main
    from camgen.scene import template_path

    out = {}
    for name in FOLLOWER_TEMPLATES:
        folder = tmp_path_factory.mktemp(name)
        assert main(["run", str(template_path(name)), "-o", str(folder), "--only", "points,lift,follower", "-q"]) == 0
        out[name] = folder / name
    return out


def report_of(folder) -> dict:
    import json

    return json.loads((folder / "report.json").read_text())


def read(path):
    import pandas

    return pandas.read_csv(path)  # no arguments: the reader's defaults


def _folders(default_run, follower_runs) -> dict:
    return {"default": default_run, **follower_runs}


# --------------------------------------------------------------------------------------------
# Every CSV: pandas defaults, the described columns, float64
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("template", ("default",) + FOLLOWER_TEMPLATES)
def test_every_csv_opens_with_pandas_defaults_as_described_in_report_json(template, default_run, follower_runs):
    import jsonschema

    from camgen.report import REPORT_SCHEMA

    folder = _folders(default_run, follower_runs)[template]
    report = report_of(folder)
    jsonschema.validate(report, REPORT_SCHEMA)
    csvs = sorted(p.name for p in folder.glob("*.csv"))
    assert csvs and sorted(report["tables"]) == csvs
    for name in csvs:
        text = (folder / name).read_text()
        assert not [line for line in text.splitlines() if line.startswith("#")]
        frame = read(folder / name)
        table = report["tables"][name]
        assert list(frame.columns) == list(table["columns"]), name
        for column, meaning in table["columns"].items():  # the unit in the name is the unit of the description
            assert meaning.endswith(", " + UNITS[next(u for u in UNITS if column.endswith("_" + u))]), (name, column)
        assert all(str(t) == "float64" for t in frame.dtypes), (name, frame.dtypes)
        assert len(frame) > 10 and np.all(np.isfinite(frame.to_numpy()))
        assert ("cam" in table) != ("mechanism" in table)
        assert table.get("cam", "") in report["cams"] or table.get("mechanism") in report["mechanisms"]
    kinds = {name.rsplit("_", 1)[-1] for name in csvs}
    expected = {"default": {"points.csv", "lift.csv", "ride.csv", "12.5.csv", "14.5.csv", "18.5.csv"}}
    assert kinds == expected.get(template, {"points.csv", "lift.csv", "follower.csv"})


def test_a_table_without_a_description_is_a_bug_not_a_file():
    from camgen.export.tablemeta import tables_metadata
    from camgen.scene import load_template

    with pytest.raises(RuntimeError, match="x_unknown.csv"):
        tables_metadata(load_template("default"), [], ["x_unknown.csv", "report.json"])


# --------------------------------------------------------------------------------------------
# The numbers against sources outside the writers
# --------------------------------------------------------------------------------------------
def test_point_lists_lie_on_the_paper_cams_within_the_stated_chord_tolerance(default_run):
    import camgen

    report = report_of(default_run)
    chord_tol = template_toml("default").get("output", {}).get("chord_tol_mm", 1e-3)
    for name, (a, b, c) in PAPER.items():
        table = report["tables"][f"{name}_points.csv"]
        assert table["cam"] == name and table["chord_tol_mm"] == chord_tol
        data = read(default_run / f"{name}_points.csv").to_numpy()
        arcs = camgen.three_arc_cam(a, b, c).segments
        assert np.max(distance_to_arcs(data, arcs)) <= 2e-9  # printed with 9 decimals
        # every chord (the last row joins the first) within the tolerance: the chord's midpoint is
        # its farthest point from an arc it cuts, at most the sagitta r (1 - cos(half angle))
        closed = np.vstack([data, data[:1]])
        mid = (closed[1:] + closed[:-1]) / 2
        assert np.max(distance_to_arcs(mid, arcs)) <= chord_tol + 2e-9
        # counter-clockwise: positive shoelace area
        x, y = closed[:, 0], closed[:, 1]
        assert np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]) > 0


def test_lift_tables_state_the_paper_base_radius_and_step(default_run):
    report = report_of(default_run)
    step = template_toml("default").get("output", {}).get("lift_step_deg", 1.0)
    for name, (a, b, c) in PAPER.items():
        table = report["tables"][f"{name}_lift.csv"]
        assert table["base_radius_mm"] == pytest.approx(c, abs=1e-12)  # the base arc's radius c (paper 000, Fig. 3)
        assert table["angle_step_deg"] == step
        frame = read(default_run / f"{name}_lift.csv")
        assert np.allclose(frame["polar_angle_deg"], step * np.arange(round(360 / step)), atol=1e-9)
        assert np.allclose(frame["radius_mm"] - frame["lift_mm"], c, atol=2e-9)
        # the largest radius of a three-arc cam is 2a + c - b (the nose arc's far point)
        assert frame["radius_mm"].max() <= 2 * a + c - b + 1e-9


def cycloidal_table(theta: np.ndarray, h: float, beta: float, omega: float) -> np.ndarray:
    """Lift (mm), velocity (mm/s), acceleration (m/s^2), jerk (m/s^3) of a cycloidal rise h over
    beta at omega, written out: s = h (u - sin(2 pi u) / 2 pi), u = theta / beta."""
    u = theta / beta
    w = TWO_PI * u
    return np.stack([h * (u - np.sin(w) / TWO_PI), h * omega / beta * (1 - np.cos(w)),
                     1e-3 * h * omega**2 / beta**2 * TWO_PI * np.sin(w), 1e-3 * h * omega**3 / beta**3 * TWO_PI**2 * np.cos(w)], axis=1)


def test_follower_table_of_the_plate_cam_states_its_speed_and_is_the_law_in_time(follower_runs):
    """plate_cam.toml: cycloidal rise of 20 mm over 120 deg at 300 rpm (read from the file)."""
    folder = follower_runs["plate_cam"]
    cam = template_toml("plate_cam")["cams"]["plate"]
    rpm = cam["rpm"]
    rise = cam["segments"][0]
    assert rise["law"] == "cycloidal"
    table = report_of(folder)["tables"]["plate_follower.csv"]
    omega = rpm * TWO_PI / 60.0
    assert table["cam"] == "plate" and table["follower_motion"] == "translating" and table["rpm"] == rpm
    assert table["omega_rad_per_s"] == pytest.approx(omega, rel=1e-15) and table["turn_s"] == pytest.approx(60.0 / rpm, rel=1e-15)
    assert table["jerk_impulses_deg"] == []  # cycloidal and 3-4-5 laws: the acceleration never jumps (Norton, ch. 8)
    frame = read(folder / "plate_follower.csv")
    assert list(frame.columns) == ["cam_angle_deg", "time_s", "lift_mm", "velocity_mm_per_s", "acceleration_m_per_s2", "jerk_m_per_s3"]
    assert np.allclose(np.diff(frame["cam_angle_deg"]), table["cam_angle_step_deg"], atol=1e-8)
    assert np.allclose(frame["time_s"], frame["cam_angle_deg"] / 360.0 * table["turn_s"], atol=1e-9)
    theta = np.radians(frame["cam_angle_deg"].to_numpy())
    up = theta < math.radians(rise["span_deg"])
    wanted = cycloidal_table(theta[up], rise["lift_mm"], math.radians(rise["span_deg"]), omega)
    assert np.allclose(frame.to_numpy()[up, 2:], wanted, atol=2e-9, rtol=1e-11)


def test_follower_table_of_an_oscillating_arm_states_its_units(follower_runs):
    folder = follower_runs["oscillating_roller"]
    cam_name, cam = next(iter(template_toml("oscillating_roller")["cams"].items()))
    table = report_of(folder)["tables"][f"{cam_name}_follower.csv"]
    assert table["follower_motion"] == "oscillating" and table["rpm"] == cam["rpm"]
    frame = read(folder / f"{cam_name}_follower.csv")
    assert list(frame.columns) == list(table["columns"])
    assert list(frame.columns)[2:] == ["lift_deg", "velocity_rad_per_s", "acceleration_rad_per_s2", "jerk_rad_per_s3"]
    for column, unit in zip(list(frame.columns)[2:], ("deg", "rad/s", "rad/s^2", "rad/s^3")):
        assert table["columns"][column].endswith(unit)
    # the swing's range is the segments' largest swing (deg), read from the scene file
    swings = np.cumsum([s.get("swing_deg", 0.0) for s in cam["segments"]])
    assert frame["lift_deg"].max() - frame["lift_deg"].min() == pytest.approx(np.ptp(np.append(swings, 0.0)), abs=1e-6)


def test_follower_table_states_where_the_acceleration_jumps(tmp_path):
    """Simple harmonic rise and return: the acceleration h pi^2 / (2 beta^2) cos(pi theta / beta)
    jumps from and to 0 at each end of both motions (Norton, *Design of Machinery*, ch. 8: the
    simple harmonic law's infinite jerk at the ends): at 0, 120, 180 and 300 deg."""
    from camgen.cli import main
    from helpers import scene_toml

    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 100.0,
           "segments": [{"law": "harmonic", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                        {"law": "harmonic", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]}
    (tmp_path / "h.toml").write_text(scene_toml({"output": {"formats": ["follower"]}, "cams": {"c": cam}}))
    assert main(["run", str(tmp_path / "h.toml"), "-o", str(tmp_path), "-q"]) in (0, 1)
    table = report_of(tmp_path / "h")["tables"]["c_follower.csv"]
    assert table["jerk_impulses_deg"] == pytest.approx([0.0, 120.0, 180.0, 300.0], abs=1e-9)
    frame = read(tmp_path / "h" / "c_follower.csv")
    peak = 1e-3 * 20.0 * math.pi**2 / (2 * math.radians(120.0) ** 2) * (100.0 * TWO_PI / 60.0) ** 2
    assert frame["acceleration_m_per_s2"].iloc[0] == pytest.approx(peak, rel=1e-9)


def test_ride_table_is_the_ride_about_the_paper_path(default_run):
    """The steering cam's ride: lateral_error_mm is the distance from the target path of paper
    004, eq. 15, y = 202.4396 sin(pi x / 1000), along its normal, computed here from the x, y
    columns; the report names that path."""
    cam = template_toml("default")["cams"]["steering"]
    table = report_of(default_run)["tables"]["steering_ride.csv"]
    assert table["cam"] == "steering" and table["trajectory"].replace(" ", "").startswith(cam["expression"].replace(" ", ""))
    frame = read(default_run / "steering_ride.csv")
    assert np.allclose(frame["theta_deg"], table["theta_step_deg"] * np.arange(len(frame)), atol=1e-9)
    assert len(frame) * table["theta_step_deg"] == pytest.approx(360.0)
    x, y = frame["x_mm"].to_numpy(), frame["y_mm"].to_numpy()
    f = 202.4396 * np.sin(np.pi * x / 1000.0)
    slope = 202.4396 * np.pi / 1000.0 * np.cos(np.pi * x / 1000.0)
    assert np.allclose(frame["lateral_error_mm"], (y - f) / np.sqrt(1 + slope**2), atol=3e-9)
    assert np.max(np.abs(frame["lateral_error_mm"])) < 0.1  # the ride follows the path


def test_leg_path_tables_state_their_inclination_and_ground(default_run):
    leg = template_toml("default")["mechanisms"]["horse_leg"]
    tables = report_of(default_run)["tables"]
    for alpha in leg["inclinations_deg"]:
        name = f"leg_path_alpha_{alpha:g}.csv"
        assert tables[name]["mechanism"] == "horse_leg"
        assert tables[name]["alpha1_deg"] == alpha and tables[name]["ground_y_mm"] == leg["ground_y_mm"]
        frame = read(default_run / name)
        assert list(frame.columns) == ["theta1_deg", "x_mm", "y_mm", "pressure_angle_deg"]
        assert frame["theta1_deg"].iloc[0] == 0.0 and frame["theta1_deg"].iloc[-1] < 360.0
        # the foot crosses the ground line: it is above and below it during a turn
        assert frame["y_mm"].min() < leg["ground_y_mm"] < frame["y_mm"].max()


# --------------------------------------------------------------------------------------------
# A spreadsheet: LibreOffice Calc's default CSV import (optional: not installed by CI)
# --------------------------------------------------------------------------------------------
def _ods_rows(path) -> list[list]:
    """The first sheet of an OpenDocument spreadsheet: rows of cells (float or str)."""
    import zipfile

    from lxml import etree

    ns = {"table": "urn:oasis:names:tc:opendocument:xmlns:table:1.0", "office": "urn:oasis:names:tc:opendocument:xmlns:office:1.0",
          "text": "urn:oasis:names:tc:opendocument:xmlns:text:1.0"}
    root = etree.fromstring(zipfile.ZipFile(path).read("content.xml"))
    sheet = root.find(".//table:table", ns)
    rows = []
    for row in sheet.iterfind("table:table-row", ns):
        cells = []
        for cell in row.iterfind("table:table-cell", ns):
            repeat = int(cell.get(f"{{{ns['table']}}}number-columns-repeated", "1"))
            kind = cell.get(f"{{{ns['office']}}}value-type")
            value = float(cell.get(f"{{{ns['office']}}}value")) if kind == "float" else "".join(cell.itertext())
            cells.extend([value] * min(repeat, 64))
        while cells and cells[-1] == "":
            cells.pop()
        repeat = int(row.get(f"{{{ns['table']}}}number-rows-repeated", "1"))
        if cells:
            rows.extend([cells] * repeat)
    return rows


def test_libreoffice_opens_every_kind_of_csv_in_columns(default_run, follower_runs, tmp_path):
    soffice = require_tool("soffice")  # LibreOffice Calc (.ci/run installs it)
    paths = [default_run / n for n in ("stride_length_points.csv", "stride_length_lift.csv", "steering_ride.csv",
                                       "leg_path_alpha_12.5.csv")]
    paths += [follower_runs["plate_cam"] / "plate_follower.csv"]
    profile = (tmp_path / "profile").as_uri()
    proc = subprocess.run([soffice, f"-env:UserInstallation={profile}", "--headless", "--convert-to", "ods", "--outdir",
                           str(tmp_path), *map(str, paths)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    for path in paths:
        rows = _ods_rows(tmp_path / (path.stem + ".ods"))
        frame = read(path)
        assert rows[0] == list(frame.columns), path.name  # the header: one name per column
        numbers = np.array(rows[1:], dtype=float)  # every other cell a number, one field per column
        assert numbers.shape == frame.shape
        assert np.array_equal(numbers, frame.to_numpy()), path.name
