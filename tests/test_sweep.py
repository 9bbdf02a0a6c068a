"""``camgen sweep`` in process: the grid's points, each row's checks against ``camgen check`` run
as a separate program on the same design, --resume evaluating only the missing points, the
results read back by pyarrow/pandas, and bad input refused in one line with nothing written.

The parallel and cluster runs are in test_sweep_cluster.py."""
from __future__ import annotations

import csv
import itertools
import json
import re
import subprocess
import sys

import pytest

from camgen.cli import main
from helpers import CHECKOUT

pq = pytest.importorskip("pyarrow.parquet")
pd = pytest.importorskip("pandas")

TEMPLATE = CHECKOUT / "templates" / "plate_cam.toml"
#: The grid of the tests: base radius 20, 30, 40 mm (a step of 10 mm) x roller radius 8, 10 mm.
BASES = (20.0, 30.0, 40.0)
ROLLERS = (8, 10)
#: ``camgen check`` prints a value with 6 significant digits.
PRINTED_REL = 5e-6


def _sweep(tmp_path, *extra: str) -> int:
    return main(["sweep", str(TEMPLATE), "--vary", "base_radius_mm=20:40:10", "--vary", "roller_radius_mm=8,10",
                 "-o", str(tmp_path / "out"), "-q", *extra])


def _folder(tmp_path):
    return tmp_path / "out" / "plate_cam-sweep"


def _summary(tmp_path) -> list[dict[str, str]]:
    with (_folder(tmp_path) / "summary.csv").open(newline="") as handle:
        return list(csv.DictReader(handle))


@pytest.fixture(scope="module")
def grid(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("grid")
    assert _sweep(tmp, "--batch", "2") == 0
    return tmp


def _scene_with(base: float, roller: float, folder) -> str:
    """The template with the two keys replaced in its text (not through camgen's scene editor)."""
    text = TEMPLATE.read_text()
    text, n1 = re.subn(r"(?m)^base_radius_mm = [0-9.]+", f"base_radius_mm = {base!r}", text)
    text, n2 = re.subn(r"(?m)^roller_radius_mm = [0-9.]+", f"roller_radius_mm = {roller!r}", text)
    assert n1 == n2 == 1
    path = folder / f"design_{base}_{roller}.toml"
    path.write_text(text)
    return str(path)


def _check_table(scene: str) -> dict[str, tuple[str, str]]:
    """``camgen check``'s table, run as its own program: check name -> (result, value)."""
    proc = subprocess.run([sys.executable, "-m", "camgen", "check", scene], capture_output=True, text=True, timeout=300)
    assert proc.returncode in (0, 1), proc.stderr
    lines = proc.stdout.splitlines()
    header = re.split(r"\s{2,}", lines[0].strip())
    assert header[:4] == ["cam", "check", "result", "value"]
    out = {}
    for line in lines[1:]:
        if line.startswith("camgen:"):
            continue
        cells = re.split(r"\s{2,}", line.strip())
        out[cells[1]] = (cells[2], cells[3])
    return out


def test_the_grid_is_every_combination_once(grid):
    rows = _summary(grid)
    got = [(float(r["cams.plate.base_radius_mm"]), int(r["cams.plate.roller_radius_mm"])) for r in rows]
    assert got == list(itertools.product(BASES, ROLLERS))  # point order: the product, last key fastest
    assert len({r["key"] for r in rows}) == len(rows)
    facts = json.loads((_folder(grid) / "sweep.json").read_text())
    assert facts["points"] == 6 and facts["method"] == "grid" and sum(facts["counts"].values()) == 6
    assert facts["counts"] == {s: sum(r["status"] == s for r in rows) for s in ("pass", "fail", "error", "crashed")}
    # three part files of two rows (--batch 2: the first, measured, point is a part of its own)
    parts = sorted((_folder(grid) / "parts").iterdir())
    assert [pq.read_metadata(p).num_rows for p in parts] == [1, 2, 2, 1]


@pytest.mark.parametrize("base, roller", [(20.0, 8), (40.0, 10)])
def test_a_rows_checks_are_camgen_checks(grid, base, roller, tmp_path):
    row = next(r for r in _summary(grid) if float(r["cams.plate.base_radius_mm"]) == base
               and int(r["cams.plate.roller_radius_mm"]) == roller)
    table = _check_table(_scene_with(base, roller, tmp_path))
    # the summary has every row's columns: this design's checks are those with a status
    names = {c.split(".")[2] for c in row if c.startswith("check.plate.") and c.endswith(".status") and row[c]}
    assert names == set(table)
    for name in names:
        result, value = table[name]
        assert row[f"check.plate.{name}.status"] == result.lower(), name
        if not re.fullmatch(r"-?[0-9.]+(e[-+]?[0-9]+)?", value):  # '-', 'G2', 'no concave part': no number
            assert row[f"check.plate.{name}"] == "", name
        else:
            assert float(row[f"check.plate.{name}"]) == pytest.approx(float(value), rel=PRINTED_REL), name
    failed = any(result == "FAIL" for n, (result, _) in table.items() if n in names)
    assert row["status"] == ("fail" if failed else "pass")


def test_the_parts_read_back_as_the_summary(grid):
    parts = pd.concat([pd.read_parquet(p) for p in sorted((_folder(grid) / "parts").iterdir())], ignore_index=True)
    summary = pd.read_csv(_folder(grid) / "summary.csv", keep_default_na=True)
    assert list(parts["key"]) == list(summary["key"])
    assert parts["cams.plate.base_radius_mm"].dtype == "float64" and parts["cams.plate.roller_radius_mm"].dtype == "int64"
    for column in parts.columns:
        if parts[column].dtype == "float64":
            assert (parts[column].isna() == summary[column].isna()).all(), column
            assert (parts[column].dropna() == summary[column].dropna()).all(), column  # repr: the same float
    assert not any("nan" in line.lower() for line in (_folder(grid) / "summary.csv").read_text().splitlines())


def test_resume_evaluates_only_the_missing_points(grid, tmp_path):
    import shutil

    shutil.copytree(grid / "out", tmp_path / "out")
    parts = sorted((_folder(tmp_path) / "parts").iterdir())
    lost = [k for p in parts[1:3] for k in pq.read_table(p).column("key").to_pylist()]
    for p in parts[1:3]:
        p.unlink()
    (_folder(tmp_path) / "parts" / ".part-00009.parquet.x.tmp").write_text("a killed write")
    assert _sweep(tmp_path, "--resume") == 0
    facts = json.loads((_folder(tmp_path) / "sweep.json").read_text())
    assert facts["evaluated"] == len(lost) == 4 and facts["resumed"] == 2
    before = pd.read_csv(_folder(grid) / "summary.csv").drop(columns="eval_ms")
    after = pd.read_csv(_folder(tmp_path) / "summary.csv").drop(columns="eval_ms")
    pd.testing.assert_frame_equal(before, after)
    names = sorted(p.name for p in (_folder(tmp_path) / "parts").iterdir())
    assert not [n for n in names if n.endswith(".tmp")]
    new = [k for n in names if n not in {p.name for p in parts} for k in pq.read_table(_folder(tmp_path) / "parts" / n)
           .column("key").to_pylist()]
    assert sorted(new) == sorted(lost)  # each missing point once, nothing else again


def test_resume_refuses_the_parts_of_another_scene(grid, tmp_path):
    import shutil

    shutil.copytree(grid / "out", tmp_path / "out")
    scene = tmp_path / "plate_cam.toml"
    scene.write_text(TEMPLATE.read_text().replace("rpm = 300.0", "rpm = 310.0"))
    assert main(["sweep", str(scene), "--vary", "base_radius_mm=20:40:10", "-o", str(tmp_path / "out"), "-q", "--resume"]) == 2


def test_lhs_puts_one_point_in_each_stratum(tmp_path):
    """McKay et al. (1979): n points, each variable's range cut in n equal strata, one point each."""
    n = 6
    assert main(["sweep", str(TEMPLATE), "--vary", "base_radius_mm=30:60", "--vary", "roller_radius_mm=6:12", "--method",
                 "lhs", "--samples", str(n), "--seed", "3", "-o", str(tmp_path / "out"), "-q"]) == 0
    rows = _summary(tmp_path)
    for key, low, high in (("base_radius_mm", 30.0, 60.0), ("roller_radius_mm", 6.0, 12.0)):
        values = [float(r[f"cams.plate.{key}"]) for r in rows]
        assert sorted(int((v - low) / (high - low) * n) for v in values) == list(range(n)), key


def _refused(tmp_path, capfd, *args: str) -> str:
    out = tmp_path / "out"
    assert main(["sweep", *args, "-o", str(out), "-q"]) == 2
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and err.startswith("camgen: error:"), err
    assert not out.exists()
    return err


def test_an_unknown_key_is_refused(tmp_path, capfd):
    assert "bogus_mm" in _refused(tmp_path, capfd, str(TEMPLATE), "--vary", "bogus_mm=1,2")


def test_a_table_that_is_not_in_the_scene_is_refused(tmp_path, capfd):
    assert "cams.other" in _refused(tmp_path, capfd, str(TEMPLATE), "--vary", "cams.other.base_radius_mm=1,2")


def test_a_value_out_of_range_is_refused(tmp_path, capfd):
    err = _refused(tmp_path, capfd, str(TEMPLATE), "--vary", "base_radius_mm=-5:40:5")
    assert "cams.plate.base_radius_mm" in err and "-5.0" in err


def test_a_listed_value_out_of_range_is_refused(tmp_path, capfd):
    err = _refused(tmp_path, capfd, str(TEMPLATE), "--vary", "cams.plate.segments[0].span_deg=90,400")
    assert "cams.plate.segments[0].span_deg" in err and "400" in err


def test_a_points_file_with_a_bad_column_is_refused(tmp_path, capfd):
    points = tmp_path / "points.csv"
    points.write_text("base_radius_mm,nope..key\n30,1\n40,2\n")
    assert "nope..key" in _refused(tmp_path, capfd, str(TEMPLATE), "--points", str(points))


def test_a_grid_over_max_points_is_refused(tmp_path, capfd):
    from camgen.study.space import MAX_POINTS

    err = _refused(tmp_path, capfd, str(TEMPLATE), "--vary", "base_radius_mm=10:100:0.01", "--vary",
                   "roller_radius_mm=1:20:0.01")
    assert str(MAX_POINTS) in err  # 9001 x 1901 points


def test_a_range_without_a_step_needs_a_sampler(tmp_path, capfd):
    assert "--method" in _refused(tmp_path, capfd, str(TEMPLATE), "--vary", "base_radius_mm=30:60")


def test_an_existing_folder_needs_resume(grid, tmp_path, capfd):
    import shutil

    shutil.copytree(grid / "out", tmp_path / "out")
    before = {p: p.stat().st_mtime_ns for p in (tmp_path / "out").rglob("*")}
    assert _sweep(tmp_path) == 2
    err = capfd.readouterr().err
    assert err.count("\n") == 1 and "--resume" in err
    assert {p: p.stat().st_mtime_ns for p in (tmp_path / "out").rglob("*")} == before


def test_a_design_the_scene_refuses_is_an_error_row(tmp_path):
    # each value is valid with the template's other keys; a follower offset of 45 mm is not with a
    # base radius of 30 mm (the offset must be below the prime radius, 30 + 10 mm): that design's row
    assert main(["sweep", str(TEMPLATE), "--vary", "base_radius_mm=30,40", "--vary", "follower_offset_mm=8,45",
                 "-o", str(tmp_path / "out"), "-q"]) == 0
    rows = {(float(r["cams.plate.base_radius_mm"]), float(r["cams.plate.follower_offset_mm"])): r for r in _summary(tmp_path)}
    assert [k for k, r in rows.items() if r["status"] == "error"] == [(30.0, 45.0)]
    text = re.sub(r"(?m)^base_radius_mm = [0-9.]+", "base_radius_mm = 30.0", TEMPLATE.read_text())
    text = re.sub(r"(?m)^follower_offset_mm = [0-9.]+", "follower_offset_mm = 45.0", text)
    (tmp_path / "bad.toml").write_text(text)
    proc = subprocess.run([sys.executable, "-m", "camgen", "check", str(tmp_path / "bad.toml")], capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 2
    assert rows[(30.0, 45.0)]["error"] == proc.stderr.strip()


@pytest.mark.parametrize("hidden, option", [(("pyarrow", "pyarrow.parquet"), ()),
                                            (("distributed",), ("--workers", "2"))])
def test_a_missing_extra_is_one_line_naming_it(tmp_path, capfd, monkeypatch, hidden, option):
    for module in hidden:
        monkeypatch.setitem(sys.modules, module, None)  # import_module raises ImportError
    err = _refused(tmp_path, capfd, str(TEMPLATE), "--vary", "base_radius_mm=30,40", *option)
    assert "camgen[sweep]" in err and f"'{hidden[0]}'" in err


def test_the_scenes_sweep_table_gives_the_defaults(tmp_path):
    scene = tmp_path / "plate_cam.toml"
    scene.write_text(TEMPLATE.read_text() + '\n[sweep]\nmethod = "grid"\n\n[sweep.vary]\nbase_radius_mm = "30:40:10"\n'
                     '"cams.plate.roller_radius_mm" = [8.0, 10.0]\n')
    assert main(["sweep", str(scene), "-o", str(tmp_path / "a"), "-q"]) == 0
    rows = list(csv.DictReader((tmp_path / "a" / "plate_cam-sweep" / "summary.csv").read_text().splitlines()))
    assert [(r["cams.plate.base_radius_mm"], r["cams.plate.roller_radius_mm"]) for r in rows] == [
        ("30.0", "8.0"), ("30.0", "10.0"), ("40.0", "8.0"), ("40.0", "10.0")]
    # the command line overrides the table: its --vary replaces the table's keys
    assert main(["sweep", str(scene), "--vary", "rpm=200,400", "-o", str(tmp_path / "b"), "-q"]) == 0
    facts = json.loads((tmp_path / "b" / "plate_cam-sweep" / "sweep.json").read_text())
    assert [v["key"] for v in facts["variables"]] == ["cams.plate.rpm"] and facts["points"] == 2


def test_the_sweep_writes_its_report_and_the_best_designs(grid, tmp_path):
    """The report and the best designs' scenes come with the sweep: report.html names every point;
    each best/<key>.toml is the template with that row's values (tomllib), ranked by the outer
    radius among passing rows (the summary's own numbers); --keep-files 1 runs the best design,
    whose report.json gives the row's torque."""
    import tomllib

    folder = _folder(grid)
    html = (folder / "report.html").read_text(encoding="utf-8")
    rows = _summary(grid)
    assert all(r["key"] in html for r in rows)
    passing = sorted((r for r in rows if r["status"] == "pass"), key=lambda r: float(r["fig.plate.outer_radius_mm"]))
    scenes = sorted(p.stem for p in (folder / "best").glob("*.toml"))
    assert scenes == sorted(r["key"] for r in passing[:10])
    best = passing[0]
    data = tomllib.loads((folder / "best" / f"{best['key']}.toml").read_text(encoding="utf-8"))
    assert data["cams"]["plate"]["base_radius_mm"] == float(best["cams.plate.base_radius_mm"])
    assert data["cams"]["plate"]["roller_radius_mm"] == int(best["cams.plate.roller_radius_mm"])
    assert _sweep(tmp_path, "--keep-files", "1", "--best", "2") == 0
    kept = _folder(tmp_path) / "best" / best["key"]
    report = json.loads((kept / "report.json").read_text(encoding="utf-8"))
    assert report["cams"]["plate"]["figures"]["dynamics"]["torque_peak_Nm"] == float(best["fig.plate.torque_peak_n_m"])
    assert len(list((_folder(tmp_path) / "best").glob("*.toml"))) == 2


@pytest.mark.parametrize("option, value, named", [
    ("--pareto", "outer_radius_mm,nope", "--pareto"),
    ("--map", "base_radius_mm,follower_offset_mm", "--map"),
    ("--rank", "nope", "--rank"),
    ("--keep-files", "-1", "--keep-files"),
])
def test_bad_report_options_are_refused_before_any_design(tmp_path, capsys, option, value, named):
    assert _sweep(tmp_path, option, value) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and named in err and not (tmp_path / "out").exists()
