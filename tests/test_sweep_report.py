"""The sweep report (camgen.study.report): the Pareto front, the feasibility map's colours and
cells, the best designs' scenes and runs, a self-contained page, refused options.

Rows come from camgen.study.design.evaluate_point over small grids of the plate_cam template
(serial, about 25 designs); every expectation is computed here from the rows themselves, a brute
force, the template read by tomllib, `camgen check` in a subprocess or the files of a run.
"""
from __future__ import annotations

import copy
import json
import math
import re
import subprocess
import sys
import tomllib
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from lxml import html as lhtml

from camgen.errors import ParameterError
from camgen.scene import template_path
from camgen.study.best import keep_files
from camgen.study.design import StudyScene, evaluate_point
from camgen.study.pareto import pareto_front
from camgen.study.report import sweep_report_files
from camgen.study.space import design_points, parse_vary

#: `camgen check` prints values to 6 significant digits.
CHECK_PRINT_REL = 5e-6
#: The points CSV of a run is written at chord_tol_mm = 0.001 with 9 decimals: its largest
#: radius is within the outer radius's own tolerance (OUTER_RADIUS_TOL = 1e-3 mm) of the row's.
OUTER_RADIUS_MM = 2e-3


def _rows(study: StudyScene, specs: list[str]) -> tuple[tuple, list[dict]]:
    variables = parse_vary(study.data, specs)
    rows = [evaluate_point(study, [v.key for v in variables], p) for p in design_points(variables, "grid")]
    return variables, rows


@pytest.fixture(scope="module")
def study() -> StudyScene:
    return StudyScene.load(str(template_path("plate_cam")))


@pytest.fixture(scope="module")
def mixed(study):
    """Two keys, every kind of design: refused (negative base radius), failing the pressure angle
    (small base radius), failing the jump check (weak spring), passing; and one crashed row as a
    sweep records it (its worker killed repeatedly: the error row's inputs under a new key)."""
    variables, rows = _rows(study, ["base_radius_mm=-5,15,30,45", "spring_preload_n=5,40"])
    crashed = dict(rows[0], key="c" * 16, status="crashed", error="camgen: error: the design killed its worker 3 times")
    return variables, rows + [crashed]


@pytest.fixture(scope="module")
def three(study):
    return _rows(study, ["base_radius_mm=15,30", "spring_preload_n=5,40", "roller_radius_mm=4,14"])


@pytest.fixture(scope="module")
def sizes(study):
    """Mostly passing designs of different size and pressure angle (a front of several)."""
    return _rows(study, ["base_radius_mm=25,35,45", "roller_radius_mm=4,10,14"])


def _page(files: dict[str, str]):
    return lhtml.fromstring(files["report.html"].encode("utf-8"))


def _dominated_brute(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """O(n^2): design i is dominated when some j is no worse in both and better in one."""
    n = a.size
    out = np.zeros(n, dtype=bool)
    for i in range(n):
        for j in range(n):
            if a[j] <= a[i] and b[j] <= b[i] and (a[j] < a[i] or b[j] < b[i]):
                out[i] = True
                break
    return out


@pytest.mark.parametrize("seed", range(6))
def test_pareto_front_equals_brute_force(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 120))
    # few distinct values: ties in one figure and repeated designs are common
    a = rng.integers(0, 12, n).astype(float) * 0.5
    b = rng.integers(0, 12, n).astype(float) * 0.25 - 1.0
    assert np.array_equal(pareto_front(a, b), ~_dominated_brute(a, b))


def test_pareto_front_continuous():
    rng = np.random.default_rng(7)
    a, b = rng.normal(size=300), rng.normal(size=300)
    expected = ~_dominated_brute(a, b)
    assert np.array_equal(pareto_front(a, b), expected) and 1 < expected.sum() < 300


@pytest.mark.parametrize("figures", [None, ("outer_radius_mm", "-least_radius_mm")])
def test_report_front_is_the_brute_force_front(study, sizes, figures):
    variables, rows = sizes
    files = sweep_report_files(study, variables, rows, pareto=figures, best=0)
    columns, signs = ("fig.plate.outer_radius_mm", "fig.plate.pressure_angle_deg"), (1.0, 1.0)
    if figures is not None:
        columns, signs = ("fig.plate.outer_radius_mm", "fig.plate.least_radius_mm"), (1.0, -1.0)
    passing = [r for r in rows if r["status"] == "pass"]
    assert len(passing) >= 5
    a = np.array([signs[0] * r[columns[0]] for r in passing])
    b = np.array([signs[1] * r[columns[1]] for r in passing])
    expected = {r["key"] for r, dominated in zip(passing, _dominated_brute(a, b)) if not dominated}
    page = _page(files)
    drawn = {c.get("data-key") for c in page.xpath("//svg[@id='pareto']//circle[@class='front']")}
    listed = {c.text for c in page.xpath("//table[@class='front']//tr/td[1]/code")}
    assert drawn == listed == expected
    assert 1 < len(expected) < len(passing)
    behind = {c.get("data-key") for c in page.xpath("//svg[@id='pareto']//circle[@class='passing']")}
    assert behind == {r["key"] for r in passing}  # the front drawn over every passing design


def _first_failing(row: dict) -> str:
    """The expected colour class of a row: its status, or its first failing check (row order)."""
    if row["status"] != "fail":
        return row["status"]
    return next(c.split(".")[2] for c, v in row.items() if c.startswith("check.") and c.endswith(".status") and v == "fail")


def test_feasibility_colours_follow_the_first_failing_check(study, mixed):
    variables, rows = mixed
    page = _page(sweep_report_files(study, variables, rows, best=0))
    circles = page.xpath("//svg[@id='feasibility']//circle")
    by_key = {r["key"]: r for r in rows}
    assert sorted(c.get("data-key") for c in circles) == sorted(by_key)  # every design once
    legend = {li.get("data-category"): re.search(r"background:(#[0-9a-fA-F]{6})", li.xpath(".//span")[0].get("style")).group(1)
              for li in page.xpath("//ul[@class='legend']/li")}
    expected = Counter(_first_failing(r) for r in rows)
    assert {"pass", "error", "crashed", "pressure_angle", "jump"} <= set(expected)  # the grid has every kind
    assert set(legend) == set(expected)
    assert len(set(legend.values())) == len(legend)  # one colour per category
    for circle in circles:
        row = by_key[circle.get("data-key")]
        assert circle.get("data-category") == _first_failing(row)
        assert circle.get("fill") == legend[_first_failing(row)]
        assert circle.get("data-status") == row["status"]
    legend_counts = {li.get("data-category"): int(re.search(r"\((\d+)\)", li.text_content()).group(1))
                     for li in page.xpath("//ul[@class='legend']/li")}
    assert legend_counts == dict(expected)
    r, g, b = (int(legend["pass"][i:i + 2], 16) for i in (1, 3, 5))
    assert g > r and g > b  # pass green
    r, g, b = (int(legend["error"][i:i + 2], 16) for i in (1, 3, 5))
    assert r == g == b and 0 < r < 255  # error grey
    assert legend["crashed"] == "#000000"
    # the map's x axis is the base radius: a larger radius further right
    cx = {c.get("data-key"): float(c.get("cx")) for c in circles}
    radii = sorted({r["cams.plate.base_radius_mm"] for r in rows})
    columns = [{cx[r["key"]] for r in rows if r["cams.plate.base_radius_mm"] == v} for v in radii]
    assert all(len(c) == 1 for c in columns)  # one column of discs per base radius
    xs = [c.pop() for c in columns]
    assert xs == sorted(xs) and len(set(xs)) == len(xs)


def test_three_keys_map_shows_the_share_passing_per_cell(study, three):
    variables, rows = three
    page = _page(sweep_report_files(study, variables, rows, best=0))
    assert not page.xpath("//svg[@id='feasibility']//circle")
    cells = page.xpath("//svg[@id='feasibility']//rect[@class='cell']")
    groups: dict[tuple[str, str], list[str]] = {}
    for r in rows:
        groups.setdefault((f"{r['cams.plate.base_radius_mm']:g}", f"{r['cams.plate.spring_preload_n']:g}"), []).append(r["status"])
    got = {(c.get("data-x"), c.get("data-y")): (int(c.get("data-pass")), int(c.get("data-count"))) for c in cells}
    assert got == {k: (v.count("pass"), len(v)) for k, v in groups.items()}
    assert {p for p, _ in got.values()} >= {0, 1}  # cells with different shares


def test_map_keys_choose_the_axes(study, three):
    variables, rows = three
    page = _page(sweep_report_files(study, variables, rows, map_keys=["roller_radius_mm", "cams.plate.base_radius_mm"], best=0))
    labels = [t.text for t in page.xpath("//svg[@id='feasibility']/text[@class='xlabel' or @class='ylabel']")]
    assert labels == ["cams.plate.roller_radius_mm", "cams.plate.base_radius_mm"]
    cells = page.xpath("//svg[@id='feasibility']//rect[@class='cell']")
    assert {c.get("data-x") for c in cells} == {"4", "14"} and {c.get("data-y") for c in cells} == {"15", "30"}


def _check_table(scene: Path) -> tuple[int, dict[str, tuple[str, str]]]:
    proc = subprocess.run([sys.executable, "-m", "camgen", "check", str(scene)], capture_output=True, text=True, timeout=120)
    table = {}
    for line in proc.stdout.splitlines()[1:]:
        parts = line.split()
        if len(parts) >= 4 and parts[0] == "plate":
            table[parts[1]] = (parts[2], parts[3])
    return proc.returncode, table


def test_best_scenes_are_the_designs(study, sizes, tmp_path):
    variables, rows = sizes
    files = sweep_report_files(study, variables, rows, best=3)
    passing = sorted((r for r in rows if r["status"] == "pass"), key=lambda r: r["fig.plate.outer_radius_mm"])
    best = passing[:3]
    assert sorted(files) == sorted([f"best/{r['key']}.toml" for r in best] + ["report.html"])
    page = _page(files)
    assert [tr.get("data-key") for tr in page.xpath("//table[@class='best']//tr[@data-key]")] == [r["key"] for r in best]
    assert [a.get("href") for a in page.xpath("//table[@class='best']//a")] == [f"best/{r['key']}.toml" for r in best]
    base_text = template_path("plate_cam").read_text(encoding="utf-8")
    base = tomllib.loads(base_text)
    comments = [line.split("#", 1)[1].strip() for line in base_text.splitlines() if "#" in line]
    for row in best:
        text = files[f"best/{row['key']}.toml"]
        expected = copy.deepcopy(base)
        expected["cams"]["plate"]["base_radius_mm"] = row["cams.plate.base_radius_mm"]
        expected["cams"]["plate"]["roller_radius_mm"] = row["cams.plate.roller_radius_mm"]
        assert tomllib.loads(text) == expected
        assert all(c in text for c in comments)  # every comment kept, trailing ones too
        scene = tmp_path / f"{row['key']}.toml"
        scene.write_text(text, encoding="utf-8")
        code, table = _check_table(scene)
        assert code == 0
        checks = {c.split(".")[2]: v for c, v in row.items()
                  if c.startswith("check.plate.") and not c.endswith(".status") and v is not None}
        assert checks and set(checks) <= set(table)
        for name, value in checks.items():
            status, shown = table[name]
            assert status == row[f"check.plate.{name}.status"]
            assert float(shown) == pytest.approx(value, rel=CHECK_PRINT_REL)
        assert float(table["pressure_angle"][1]) == pytest.approx(row["fig.plate.pressure_angle_deg"], rel=CHECK_PRINT_REL)
        assert float(table["camshaft_torque"][1]) == pytest.approx(row["fig.plate.torque_peak_n_m"], rel=CHECK_PRINT_REL)


def test_rank_by_another_figure_largest_first(study, sizes):
    variables, rows = sizes
    files = sweep_report_files(study, variables, rows, best=4, rank="-least_radius_mm")
    passing = sorted((r for r in rows if r["status"] == "pass"), key=lambda r: -r["fig.plate.least_radius_mm"])
    page = _page(files)
    assert [tr.get("data-key") for tr in page.xpath("//table[@class='best']//tr[@data-key]")] == [r["key"] for r in passing[:4]]


def test_keep_files_runs_the_best_design(study, sizes, tmp_path):
    variables, rows = sizes
    results = keep_files(study, variables, rows, 1, None, tmp_path)
    row = min((r for r in rows if r["status"] == "pass"), key=lambda r: r["fig.plate.outer_radius_mm"])
    folder = tmp_path / "best" / row["key"]
    assert len(results) == 1 and sorted(p.name for p in (tmp_path / "best").iterdir()) == [row["key"]]
    report = json.loads((folder / "report.json").read_text(encoding="utf-8"))
    cam = report["cams"]["plate"]
    figures, dynamics = cam["figures"], cam["figures"]["dynamics"]
    assert figures["base_radius_mm"] == row["cams.plate.base_radius_mm"]
    assert figures["follower"]["roller_radius_mm"] == row["cams.plate.roller_radius_mm"]
    assert dynamics["torque_peak_Nm"] == pytest.approx(row["fig.plate.torque_peak_n_m"], rel=1e-12)
    assert dynamics["hertz_stress_peak_MPa"] == pytest.approx(row["fig.plate.contact_stress_mpa"], rel=1e-12)
    assert dynamics["jump_rpm"] == pytest.approx(row["fig.plate.jump_rpm"], rel=1e-12)
    checks = {c["name"]: c for c in cam["checks"]}
    assert checks["pressure_angle"]["value"] == pytest.approx(row["fig.plate.pressure_angle_deg"], rel=1e-12)
    assert all(checks[c.split(".")[2]]["status"] == v for c, v in row.items() if c.startswith("check.") and c.endswith(".status"))
    xy = np.loadtxt(folder / "plate_points.csv", delimiter=",", skiprows=1)
    assert float(np.hypot(xy[:, 0], xy[:, 1]).max()) == pytest.approx(row["fig.plate.outer_radius_mm"], abs=OUTER_RADIUS_MM)


def test_page_is_self_contained_and_has_no_nan(study, mixed):
    variables, rows = mixed
    # rows read back from Parquet: NaN and None in figure columns, numpy scalars as inputs
    damaged = [dict(r) for r in rows]
    for r in damaged:
        if r["status"] == "fail":
            r["fig.plate.torque_peak_n_m"] = math.nan
            r["fig.plate.jump_rpm"] = None
        r["cams.plate.spring_preload_n"] = np.float64(r["cams.plate.spring_preload_n"])
    for these in (rows, damaged):
        text = sweep_report_files(study, variables, these, best=5)["report.html"]
        page = lhtml.fromstring(text.encode("utf-8"))
        for element in page.iter():
            for attr in ("src", "href"):
                value = element.get(attr)
                assert value is None or not re.match(r"\s*(https?:)?//", value), (element.tag, value)
        assert not page.xpath("//script | //link | //img | //iframe")
        assert not re.search(r"\bnan\b|\binf\b", text, re.IGNORECASE)
        assert "http" not in text.replace('xmlns="http://www.w3.org/2000/svg"', "")


def test_same_rows_same_bytes(study, three):
    variables, rows = three
    assert sweep_report_files(study, variables, rows) == sweep_report_files(study, variables, list(rows))


@pytest.mark.parametrize(("options", "name", "named"), [
    ({"map_keys": ["thickness_mm", "base_radius_mm"]}, "--map", "cams.plate.spring_preload_n"),
    ({"map_keys": ["base_radius_mm"]}, "--map", "2 of the varied keys"),
    ({"map_keys": ["base_radius_mm", "cams.plate.base_radius_mm"]}, "--map", "two different"),
    ({"map_keys": ["cams.nope.x", "base_radius_mm"]}, "--map", "one of the varied keys"),
    ({"pareto": ["outer_radius_mm"]}, "--pareto", "two figures"),
    ({"pareto": ["outer_radius_mm", "size"]}, "--pareto", "pressure_angle_deg"),
    ({"pareto": ["outer_radius_mm", "fig.plate.outer_radius_mm"]}, "--pareto", "two different"),
    ({"rank": "radius"}, "--rank", "outer_radius_mm"),
    ({"rank": "cams.other.outer_radius_mm"}, "--rank", "jump_rpm"),
    ({"best": -1}, "--best", "0 to"),
    ({"best": True}, "--best", "0 to"),
])
def test_bad_options_refused(study, mixed, options, name, named):
    variables, rows = mixed
    with pytest.raises(ParameterError) as caught:
        sweep_report_files(study, variables, rows, **options)
    assert caught.value.name == name and named in str(caught.value)


def test_keep_files_count_refused(study, sizes, tmp_path):
    variables, rows = sizes
    with pytest.raises(ParameterError) as caught:
        keep_files(study, variables, rows, -2, None, tmp_path)
    assert caught.value.name == "--keep-files" and not any(tmp_path.iterdir())


def test_header_counts_the_statuses(study, mixed):
    variables, rows = mixed
    page = _page(sweep_report_files(study, variables, rows, method="grid", best=0))
    header = {tr.xpath("./th")[0].text: tr.xpath("./td")[0].text for tr in page.xpath("//table[@class='header']//tr")}
    counts = Counter(r["status"] for r in rows)
    assert {s: int(header[s]) for s in ("pass", "fail", "error", "crashed")} == {s: counts[s] for s in ("pass", "fail", "error", "crashed")}
    assert header["points"] == str(len(rows)) and header["method"] == "grid"
    assert header["scene hash"] == study.scene_hash and header["camgen version"] == rows[0]["camgen_version"]


def test_a_word_valued_key_has_a_column_per_word(study):
    variables, rows = _rows(study, ["cams.plate.segments[0].law=cycloidal,poly345,harmonic", "base_radius_mm=20,40"])
    page = _page(sweep_report_files(study, variables, rows, best=0))
    ticks = [t.text for t in page.xpath("//svg[@id='feasibility']/g[@class='xticks']/text")]
    assert sorted(ticks) == ["cycloidal", "harmonic", "poly345"]
    cx = {c.get("data-key"): c.get("cx") for c in page.xpath("//svg[@id='feasibility']//circle")}
    columns = {law: {cx[r["key"]] for r in rows if r["cams.plate.segments[0].law"] == law} for law in ticks}
    assert all(len(c) == 1 for c in columns.values()) and len({c.pop() for c in columns.values()}) == 3


def _synthetic(study, specs: list[str], count: int, method: str) -> tuple[tuple, list[dict]]:
    """Rows as a sweep of ``count`` sampled designs records them, with a made-up outcome (the map
    reads only the inputs and statuses): pass when the base radius is above 35 mm."""
    variables = parse_vary(study.data, specs)
    rows = []
    for i, point in enumerate(design_points(variables, method, count, seed=3)):
        row = dict(zip([v.name for v in variables], point))
        ok = row["cams.plate.base_radius_mm"] > 35.0
        row.update(key=f"{i:016x}", status="pass" if ok else "fail", error="", camgen_version="0", scene_hash=study.scene_hash)
        row["check.plate.pressure_angle.status"] = "pass" if ok else "fail"
        rows.append(row)
    return variables, rows


def test_many_values_are_binned(study):
    from camgen.study.report import MAP_BINS, MAP_CATEGORIES

    variables, rows = _synthetic(study, ["base_radius_mm=20:50", "roller_radius_mm=4:14", "spring_preload_n=5:40"], 400, "lhs")
    assert len({r["cams.plate.base_radius_mm"] for r in rows}) > MAP_CATEGORIES
    page = _page(sweep_report_files(study, variables, rows, best=0))
    cells = page.xpath("//svg[@id='feasibility']//rect[@class='cell']")
    x = np.array([r["cams.plate.base_radius_mm"] for r in rows])
    y = np.array([r["cams.plate.roller_radius_mm"] for r in rows])
    passed = np.array([r["status"] == "pass" for r in rows], dtype=float)
    count, xe, ye = np.histogram2d(x, y, bins=MAP_BINS)
    npass, _, _ = np.histogram2d(x, y, bins=[xe, ye], weights=passed)
    assert len(cells) == int((count > 0).sum())
    assert sorted(int(c.get("data-count")) for c in cells) == sorted(int(n) for n in count[count > 0])
    assert sum(int(c.get("data-pass")) for c in cells) == int(passed.sum())
    assert sorted((int(c.get("data-count")), int(c.get("data-pass"))) for c in cells) == sorted(
        (int(n), int(p)) for n, p in zip(count[count > 0], npass[count > 0]))


def test_too_many_designs_for_discs_become_cells(study):
    from camgen.study.report import MAP_POINTS

    variables, rows = _synthetic(study, ["base_radius_mm=20:50", "roller_radius_mm=4:14"], MAP_POINTS + 1, "lhs")
    page = _page(sweep_report_files(study, variables, rows, best=0))
    assert not page.xpath("//svg[@id='feasibility']//circle")
    assert sum(int(c.get("data-count")) for c in page.xpath("//svg[@id='feasibility']//rect[@class='cell']")) == len(rows)


def test_written_files_are_the_report_files(study, sizes, tmp_path):
    from camgen.study.report import write_report_files

    variables, rows = sizes
    files = sweep_report_files(study, variables, rows, best=2)
    write_report_files(tmp_path, files)
    written = {p.relative_to(tmp_path).as_posix(): p.read_text(encoding="utf-8") for p in tmp_path.rglob("*") if p.is_file()}
    assert written == files  # and no temporary file left
    with pytest.raises(ParameterError):
        write_report_files(tmp_path, {"../x.toml": "a = 1\n"})
    assert not (tmp_path.parent / "x.toml").exists()


def test_rows_read_back_from_parquet_give_the_same_report(study, mixed, tmp_path):
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    variables, rows = mixed
    columns = list(dict.fromkeys(c for r in rows for c in r))
    pq.write_table(pa.table({c: [r.get(c) for r in rows] for c in columns}), tmp_path / "part.parquet")
    back = pq.read_table(tmp_path / "part.parquet").to_pylist()
    assert [r["key"] for r in back] == [r["key"] for r in rows]
    assert sweep_report_files(study, variables, back, best=3) == sweep_report_files(study, variables, rows, best=3)
