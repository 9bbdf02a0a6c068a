"""The jerk limit (issue 26 item 5): ``jerk_limit_m_per_s3`` (translating) and
``jerk_limit_rad_per_s3`` (oscillating) at the cam's rpm.

The expected largest jerk is the closed form ``Cj L w^3 / beta^3`` of the segment with the largest
``Cj / beta^3`` (Norton, Design of Machinery, Table 8-3's convention; the cycloid's ``Cj = 4 pi^2``
since ``J = 4 pi^2 cos(2 pi t)``, the 3-4-5's ``Cj = 60`` at its ends since ``J = 60 - 360 t +
360 t^2``), ``w = 2 pi rpm / 60``; the check's threshold is shown by running the CLI on the scene
with the limit 1e-6 above (exit 0) and 1e-6 below (exit 1) that value.
"""
from __future__ import annotations

import copy
import json
import math

import pytest

from camgen.cli import main
from helpers import scene_toml

TWO_PI = 2.0 * math.pi
LIFT, RPM = 20.0, 300.0
OMEGA = TWO_PI * RPM / 60.0

PLATE = {
    "output": {"formats": ["dxf"]},
    "cams": {"c": {"kind": "motion_law", "base_radius_mm": 50.0, "follower": "roller", "roller_radius_mm": 10.0, "rpm": RPM,
                   "segments": [{"law": "cycloidal", "span_deg": 150.0, "lift_mm": LIFT}, {"law": "dwell", "span_deg": 30.0},
                                {"law": "poly345", "span_deg": 120.0, "lift_mm": -LIFT}, {"law": "dwell", "span_deg": 60.0}]}},
}


def expected_jerk_m_per_s3() -> float:
    """The larger of the two segments' closed-form peaks (m/s^3)."""
    cycloid = 4.0 * math.pi**2 * LIFT * OMEGA**3 / math.radians(150.0) ** 3
    p345 = 60.0 * LIFT * OMEGA**3 / math.radians(120.0) ** 3
    return max(cycloid, p345) * 1e-3


def _check(scene: dict, tmp_path, capsys) -> tuple[int, str, dict]:
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    out = tmp_path / "out"
    code = main(["run", str(path), "-o", str(out), "-q"])
    err = capsys.readouterr().err
    found = sorted(out.glob("*/report.json"))
    report = json.loads(found[0].read_text()) if found else {}
    return code, err, report


def _with(**keys) -> dict:
    scene = copy.deepcopy(PLATE)
    scene["cams"]["c"].update(keys)
    return scene


def _jerk(report: dict) -> dict:
    return next(c for c in report["cams"]["c"]["checks"] if c["name"] == "jerk_limit")


def test_the_largest_jerk_is_the_closed_form(tmp_path, capsys):
    expected = expected_jerk_m_per_s3()
    code, err, report = _check(_with(jerk_limit_m_per_s3=2.0 * expected), tmp_path, capsys)
    assert code == 0, err
    check = _jerk(report)
    assert check["value"] == pytest.approx(expected, rel=1e-9) and check["unit"] == "m/s^3" and check["status"] == "pass"
    assert report["cams"]["c"]["figures"]["motion_at_rpm"]["max_jerk_m_per_s3"] == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("factor, status", [(1.0 + 1e-6, 0), (1.0 - 1e-6, 1)])
def test_the_threshold_by_the_cli(tmp_path, capsys, factor, status):
    code, err, report = _check(_with(jerk_limit_m_per_s3=factor * expected_jerk_m_per_s3()), tmp_path, capsys)
    assert code == status, err
    assert _jerk(report)["status"] == ("pass" if status == 0 else "fail")
    assert [c["name"] for c in report["cams"]["c"]["checks"] if c["status"] == "fail"] == ([] if status == 0 else ["jerk_limit"])
    assert report["status"] == ("pass" if status == 0 else "fail")


def test_an_oscillating_arm_in_rad_per_s3(tmp_path, capsys):
    swing = 15.0  # deg: a cycloidal swing out over 120 deg and back over 120 deg
    scene = _with(follower_motion="oscillating", pivot_x_mm=70.0, pivot_y_mm=0.0, arm_length_mm=60.0,
                  segments=[{"law": "cycloidal", "span_deg": 120.0, "swing_deg": swing}, {"law": "dwell", "span_deg": 60.0},
                            {"law": "cycloidal", "span_deg": 120.0, "swing_deg": -swing}, {"law": "dwell", "span_deg": 60.0}])
    expected = 4.0 * math.pi**2 * math.radians(swing) * OMEGA**3 / math.radians(120.0) ** 3
    scene["cams"]["c"]["jerk_limit_rad_per_s3"] = expected * (1 - 1e-6)
    code, err, report = _check(scene, tmp_path, capsys)
    assert code == 1, err
    check = _jerk(report)
    assert check["value"] == pytest.approx(expected, rel=1e-9) and check["unit"] == "rad/s^3"
    assert [c["name"] for c in report["cams"]["c"]["checks"] if c["status"] == "fail"] == ["jerk_limit"]


def test_an_acceleration_jump_is_an_unbounded_jerk(tmp_path, capsys):
    # simple harmonic between dwells: A = +-pi^2/2 at the ends against 0 in the dwells (Norton: Cj infinite)
    scene = _with(jerk_limit_m_per_s3=1e12, segments=[
        {"law": "simple_harmonic", "span_deg": 150.0, "lift_mm": LIFT}, {"law": "dwell", "span_deg": 30.0},
        {"law": "simple_harmonic", "span_deg": 150.0, "lift_mm": -LIFT}, {"law": "dwell", "span_deg": 30.0}])
    code, err, report = _check(scene, tmp_path, capsys)
    assert code == 1, err
    check = _jerk(report)
    assert check["value"] == "unbounded" and check["status"] == "fail"
    assert sorted(check["where_deg"]) == [0.0, 150.0, 180.0, 330.0]


@pytest.mark.parametrize("keys, named", [
    ({"jerk_limit_rad_per_s3": 10.0}, "cams.c.jerk_limit_rad_per_s3"),  # a translating follower's jerk is in m/s^3
    ({"jerk_limit_m_per_s3": 10.0, "rpm": None}, "cams.c.rpm"),  # the jerk at speed needs the speed
    ({"jerk_limit_m_per_s3": 0.0}, "cams.c.jerk_limit_m_per_s3"),  # a limit > 0
])
def test_refusals_name_the_key(tmp_path, capsys, keys, named):
    scene = _with(**{k: v for k, v in keys.items() if v is not None})
    for k, v in keys.items():
        if v is None:
            del scene["cams"]["c"][k]
    code, err, _ = _check(scene, tmp_path, capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camgen: error: ") and named in lines[0], err
    assert not (tmp_path / "out").exists()


def test_an_oscillating_follower_refuses_the_translating_key(tmp_path, capsys):
    scene = _with(follower_motion="oscillating", pivot_x_mm=70.0, pivot_y_mm=0.0, arm_length_mm=60.0, jerk_limit_m_per_s3=10.0,
                  segments=[{"law": "cycloidal", "span_deg": 180.0, "swing_deg": 10.0},
                            {"law": "cycloidal", "span_deg": 180.0, "swing_deg": -10.0}])
    code, err, _ = _check(scene, tmp_path, capsys)
    assert code == 2 and "cams.c.jerk_limit_m_per_s3" in err and "jerk_limit_rad_per_s3" in err, err
