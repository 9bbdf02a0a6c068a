"""The ``sizing_ranges`` key (issue 26, item 4): every interval of a roller radius, arm length or
pivot distance at which a plate cam meets its design limits, quoted in report.json and used.

Each quoted end, put back into the scene, gives exit 0 through the CLI and 1e-3 mm beyond gives
exit 1; the intervals agree within 1e-3 mm with a brute-force scan (then bisection) of
feasibility written out here from closed forms, not camgen's:

* a centred translating roller: Norton's pressure angle tan(alpha) = |s'| / (Rb + r + s), the
  pitch curve's radius of curvature as the polar curve r = Rb + r + s (Norton's 2.5x rule) and
  Rothbart's Hertz line-contact stress (*Cam Design Handbook*, eq. 9.11) with the spring-loaded
  follower's force (:mod:`test_sizing_margins`);
* an oscillating roller: the roller centre from the arm's geometry turned into the cam frame,
  its pressure angle and pitch-curve curvature by central differences
  (:func:`test_sizing_margins.rocker_measures`).
"""
from __future__ import annotations

import math
import numpy as np
import pytest

from camgen.synthesis.followers import FollowerSpec
from test_sizing_margins import (
    ARM, LIMIT, PIVOT, ROLLER, STEEP_RETURN, THETA, _steep_law, _swing_law, cli, hertz_closed_form, norton_alpha_deg, pitch_radius,
    rocker, rocker_measures,
)

BEYOND = 1e-3  # mm: the step outside a quoted end that must fail
AGREE = 1e-3  # mm: how close the quoted ends are to the brute force's


def brute_force_runs(ok, lo: float, hi: float, step: float) -> list[tuple[float, float]]:
    """The runs of ``ok`` over the open range (lo, hi): a scan every ``step`` mm, then each
    transition bisected to 1e-5 mm (the passing side returned)."""
    grid = np.arange(lo + step, hi, step)
    passes = np.array([ok(float(v)) for v in grid])

    def bisect(bad: float, good: float) -> float:
        while abs(good - bad) > 1e-5:
            mid = 0.5 * (bad + good)
            bad, good = (bad, mid) if ok(mid) else (mid, good)
        return good

    runs, i = [], 0
    while i < grid.size:
        if not passes[i]:
            i += 1
            continue
        j = i
        while j + 1 < grid.size and passes[j + 1]:
            j += 1
        low = bisect(float(grid[i - 1]) if i > 0 else lo, float(grid[i]))
        high = bisect(float(grid[j + 1]) if j + 1 < grid.size else hi, float(grid[j]))
        runs.append((low, high))
        i = j + 1
    return runs


def quoted(report: dict, name: str) -> dict:
    return report["cams"]["c"]["figures"]["sizing_ranges"][name]


def check_status(report: dict, name: str) -> str:
    return {c["name"]: c["status"] for c in report["cams"]["c"]["checks"]}[name]


# --------------------------------------------------------------------------------------------
# The oscillating roller (the user's rocker of issue 26 at a base radius of 45 mm)
# --------------------------------------------------------------------------------------------
def rocker_ok(base: float, roller: float, arm: float, pivot: tuple[float, float], theta: np.ndarray = THETA[::2]) -> bool:
    """Feasible by the arm's geometry: pressure angle within LIMIT, the pitch curve's convex
    radius above the roller radius (no undercut)."""
    try:
        f = FollowerSpec("roller", base, motion="oscillating", roller_radius=roller, pivot=pivot, arm_length=arm, rotation="cw")
    except Exception:  # no such follower: the arm cannot reach the prime circle
        return False
    alpha, convex = rocker_measures(f, _swing_law(), theta)
    return alpha <= LIMIT and convex > roller


def test_an_oscillating_rollers_ranges_against_brute_force_and_the_cli(tmp_path):
    status, report = cli(tmp_path, rocker(45.0, sizing_ranges=["roller_radius", "arm_length", "pivot_distance"]), "asked")
    assert status == 0
    d0 = math.hypot(*PIVOT)
    ux, uy = PIVOT[0] / d0, PIVOT[1] / d0
    predicates = {
        "roller_radius": lambda r: rocker_ok(45.0, r, ARM, PIVOT),
        "arm_length": lambda arm: rocker_ok(45.0, ROLLER, arm, PIVOT),
        "pivot_distance": lambda d: rocker_ok(45.0, ROLLER, ARM, (ux * d, uy * d)),
    }
    scene = {"roller_radius": ROLLER, "arm_length": ARM, "pivot_distance": d0}
    for name, ok in predicates.items():
        answer = quoted(report, name)
        assert answer["scene_mm"] == pytest.approx(scene[name])
        lo, hi = answer["searched_mm"]
        expected = brute_force_runs(ok, lo, hi, 0.1)
        runs = answer["intervals"]
        assert len(runs) == len(expected) >= 1, (name, runs, expected)
        for run, (low, high) in zip(runs, expected):
            assert run["low_mm"] == pytest.approx(low, abs=AGREE) and run["high_mm"] == pytest.approx(high, abs=AGREE), (name, run, low, high)
            assert run["low_bound"] == run["high_bound"] == "pressure_angle"  # independent: the brute force fails the angle there
            assert not ok(run["low_mm"] - BEYOND) and not ok(run["high_mm"] + BEYOND)
        # each end used in the scene: exit 0; 1e-3 mm beyond: exit 1 with the pressure-angle check failed
        for run in runs:
            for value, expected_status in ((run["low_mm"], 0), (run["high_mm"], 0), (run["low_mm"] - BEYOND, 1),
                                           (run["high_mm"] + BEYOND, 1)):
                if name == "pivot_distance":
                    keys = {"pivot_x_mm": ux * value, "pivot_y_mm": uy * value}
                else:
                    keys = {f"{name}_mm": value}
                status, used = cli(tmp_path, rocker(45.0, **keys), f"{name}-{value:.6f}")
                assert status == expected_status, (name, value)
                if expected_status:
                    assert check_status(used, "pressure_angle") == "fail"
    # the pivot's quoted (x, y) is the distance along the pivot's own direction
    run = quoted(report, "pivot_distance")["intervals"][0]
    assert run["low_pivot_mm"] == pytest.approx([ux * run["low_mm"], uy * run["low_mm"]], abs=1e-9)


# --------------------------------------------------------------------------------------------
# The translating roller: the Hertz stress bounds the least roller, Norton's rule the largest
# --------------------------------------------------------------------------------------------
BASE, FACTOR, RPM = 40.0, 2.5, 300.0
ALLOWABLE = 364.8  # MPa: about the closed-form stress of a 6 mm roller at this base radius


def translating(**more) -> dict:
    return {"kind": "motion_law", "base_radius_mm": BASE, "roller_radius_mm": 10.0, "segments": STEEP_RETURN,
            "pressure_angle_limit_deg": 45.0, "min_pitch_radius_roller_factor": FACTOR, "rpm": RPM, "mass_kg": 0.5,
            "spring_rate_n_per_mm": 2.0, "spring_preload_n": 150.0, "contact_width_mm": 10.0, "thickness_mm": 10.0,
            "allowable_contact_stress_mpa": ALLOWABLE, **more}


def translating_ok(r: float) -> bool:
    law = _steep_law()
    return bool(r > 0 and max(norton_alpha_deg(BASE, r)) <= 45.0 and pitch_radius(BASE, r, law).min() >= FACTOR * r
                and hertz_closed_form(BASE, r, law) <= ALLOWABLE)


def test_a_translating_rollers_range_against_the_closed_forms_and_the_cli(tmp_path):
    status, report = cli(tmp_path, translating(sizing_ranges=["roller_radius"]), "asked")
    assert status == 0
    answer = quoted(report, "roller_radius")
    lo, hi = answer["searched_mm"]
    assert (lo, hi) == (0.0, BASE)
    expected = brute_force_runs(translating_ok, lo, hi, 0.1)
    assert len(expected) == 1 and len(answer["intervals"]) == 1
    run, (low, high) = answer["intervals"][0], expected[0]
    assert run["low_mm"] == pytest.approx(low, abs=AGREE) and run["high_mm"] == pytest.approx(high, abs=AGREE)
    assert 5.0 < low < 7.0 and high < BASE - 1.0  # both ends bound by a limit, not by the range
    # what bounds each end, by the closed forms: the stress below, Norton's rule above
    law = _steep_law()
    assert run["low_bound"] == "hertz_stress" and hertz_closed_form(BASE, run["low_mm"] - BEYOND, law) > ALLOWABLE
    assert run["high_bound"] == "pitch_curvature"
    assert pitch_radius(BASE, run["high_mm"] + BEYOND, law).min() < FACTOR * (run["high_mm"] + BEYOND)
    for value, expected_status, check in ((run["low_mm"], 0, None), (run["high_mm"], 0, None),
                                          (run["low_mm"] - BEYOND, 1, "hertz_stress"), (run["high_mm"] + BEYOND, 1, "pitch_curvature")):
        status, used = cli(tmp_path, translating(roller_radius_mm=value), f"r{value:.6f}")
        assert status == expected_status, value
        if check is not None:
            assert check_status(used, check) == "fail"


def test_without_a_limit_beyond_it_the_end_is_the_range_searched(tmp_path):
    """No stress limit and no Norton factor: nothing bounds a larger translating roller before the
    search's cap (the base radius), which is quoted as such, and the least roller is bounded by
    the geometry (no roller of radius 0)."""
    cam = {key: value for key, value in translating().items()
           if key not in ("allowable_contact_stress_mpa", "min_pitch_radius_roller_factor")}
    status, report = cli(tmp_path, {**cam, "sizing_ranges": ["roller_radius"]}, "open")
    (run,) = quoted(report, "roller_radius")["intervals"]
    assert status == 0 and run["high_mm"] == BASE and run["high_bound"] == "range_searched"
    assert run["low_bound"] == "geometry" and 0.0 < run["low_mm"] <= BEYOND
    assert cli(tmp_path, {**cam, "roller_radius_mm": run["high_mm"]}, "cap")[0] == 0


# --------------------------------------------------------------------------------------------
# Refusals
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("cam, value", [
    ({"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "segments": STEEP_RETURN}, ["arm_length"]),
    ({"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "segments": STEEP_RETURN}, ["pivot_distance"]),
    ({"kind": "motion_law", "follower": "flat", "base_radius_mm": 60.0, "segments": STEEP_RETURN}, ["roller_radius"]),
    ({"kind": "motion_law", "follower": "knife", "base_radius_mm": 60.0, "segments": STEEP_RETURN}, ["roller_radius"]),
    ({"kind": "motion_law", "follower": "flat", "follower_motion": "oscillating", "base_radius_mm": 40.0, "pivot_x_mm": 90.0,
      "pivot_y_mm": 50.0, "face_offset_mm": 20.0, "segments": [{"law": "cycloidal", "span_deg": 180.0, "swing_deg": 10.0},
                                                            {"law": "cycloidal", "span_deg": 180.0, "swing_deg": -10.0}]},
     ["arm_length"]),
    ({"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "segments": STEEP_RETURN}, ["base_radius"]),
    ({"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "segments": STEEP_RETURN}, "roller_radius"),
])
def test_a_quantity_the_follower_does_not_have_is_refused(tmp_path, capsys, cam, value):
    from camgen.cli import main
    from helpers import scene_toml

    path = tmp_path / "bad.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"c": {**cam, "sizing_ranges": value}}}), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["run", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: error:") and "cams.c.sizing_ranges" in err[0], err
    assert not out.exists() or not any(out.rglob("*.dxf"))


def test_an_oscillating_knife_may_ask_for_its_arm_and_pivot(tmp_path):
    """A knife has an arm and a pivot but no roller: its arm length and pivot ranges are quoted
    (searched over |d - L| < Rb: no roller), each end passing when used."""
    cam = {**rocker(53.0, sizing_ranges=["arm_length", "pivot_distance"]), "follower": "knife"}
    del cam["roller_radius_mm"]
    status, report = cli(tmp_path, cam, "knife")
    assert status in (0, 1)
    d0 = math.hypot(*PIVOT)
    assert quoted(report, "arm_length")["searched_mm"] == pytest.approx([d0 - 53.0, d0 + 53.0])
    run = quoted(report, "arm_length")["intervals"][0]
    assert cli(tmp_path, {**cam, "arm_length_mm": run["high_mm"]}, "knife-end")[0] == 0


def test_the_report_page_shows_the_ranges(tmp_path):
    from camgen.cli import main
    from helpers import scene_toml

    path = tmp_path / "page.toml"
    cam = translating(sizing_ranges=["roller_radius"])
    path.write_text(scene_toml({"output": {"formats": ["dxf", "html"]}, "cams": {"c": cam}}), encoding="utf-8")
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 0
    page = (tmp_path / "out" / "page" / "report.html").read_text(encoding="utf-8")
    section = page[page.index("<h3>Sizing ranges</h3>"):]
    section = section[: section.index("</table>")]
    assert "roller radius (roller_radius_mm)" in section and "hertz_stress" in section and "pitch_curvature" in section
