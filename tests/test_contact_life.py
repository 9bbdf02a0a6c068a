"""Contact fatigue and life (issue 25, item 4): the Hertz half-width and the sub-surface shear
against Johnson's closed forms (the shear's peak found here by maximising McEwen's stress field
numerically), the roller bearing's L10 against ISO 281 on hand examples, the roller's
revolutions a turn against the profile's length, the S-N allowable, refusals, and existing
scenes unchanged.

Numbers come from: Johnson, *Contact Mechanics* (CUP 1985) eqs. 4.43-4.45 (line contact:
b = sqrt(4 P R / (pi E*)), p0 = 2 P / (pi b); below the centre sigma_z = -p0 b / sqrt(b^2 + z^2),
sigma_x = -(p0 / b) ((b^2 + 2 z^2) / sqrt(b^2 + z^2) - 2 z)); ISO 281:2007 L10 = (C/P)^p.
"""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from camgen.cli import main
from helpers import scene_toml

E_STEEL = 210e3  # MPa
NU = 0.3


def _run(scene: dict):
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    parsed = parse_scene(copy.deepcopy(scene), "s")
    result = execute(parsed, plan_run(parsed))
    return result.cams[0], json.loads(result.files["report.json"])


def _segments(h: float, rise: float, dwell: float, ret: float) -> list[dict]:
    return [{"law": "cycloidal", "span_deg": rise, "lift_mm": h}, {"law": "dwell", "span_deg": dwell},
            {"law": "cycloidal", "span_deg": ret, "lift_mm": -h}, {"law": "dwell", "span_deg": 360.0 - rise - dwell - ret}]


def plate(**changes) -> dict:
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 300.0, "thickness_mm": 10.0,
           "segments": _segments(20.0, 120.0, 60.0, 120.0), "mass_kg": 0.6, "spring_rate_n_per_mm": 2.0, "spring_preload_n": 35.0}
    cam.update(changes)
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {k: v for k, v in cam.items() if v is not None}}}


# ---- Hertz line contact -------------------------------------------------------------------------
def test_half_width_and_pressure_against_johnson():
    from camgen.contact_life import hertz_half_width
    from camgen.dynamics import ContactMaterial, hertz_line_stress

    material = ContactMaterial(width=10.0)
    force = np.array([500.0, 1000.0, 4000.0, 0.0])
    rho_cam, rho_roller = np.array([30.0, -60.0, 25.0, 30.0]), 10.0
    # Johnson eq. 4.43/4.44 written out with the numbers: E* = E / (2 (1 - nu^2)) for two steels
    e_star = E_STEEL / (2.0 * (1.0 - NU**2))
    r = 1.0 / (1.0 / rho_cam + 1.0 / rho_roller)
    p = force / 10.0
    b_expected = np.sqrt(4.0 * p * r / (math.pi * e_star))
    b = hertz_half_width(force, 1.0 / rho_cam + 1.0 / rho_roller, material.width, material.compliance)
    np.testing.assert_allclose(b, b_expected, rtol=1e-12)
    p0 = hertz_line_stress(force, rho_cam, rho_roller, material)
    np.testing.assert_allclose(p0[:3], 2.0 * p[:3] / (math.pi * b_expected[:3]), rtol=1e-12)
    assert b[3] == 0.0 and p0[3] == 0.0


def _tau1(z: float, b: float = 1.0, p0: float = 1.0) -> float:
    """McEwen's principal shear stress (sigma_x - sigma_z) / 2 below the centre of a line contact."""
    root = math.hypot(b, z)
    sigma_z = -p0 * b / root
    sigma_x = -(p0 / b) * ((b * b + 2.0 * z * z) / root - 2.0 * z)
    return abs(sigma_x - sigma_z) / 2.0


def test_subsurface_shear_peak_and_depth_from_the_stress_field():
    """The 0.30 p0 at 0.78 b the module uses, against the maximum of McEwen's field found numerically
    (bounded Brent on the depth): they agree to the two digits Johnson quotes."""
    from camgen.contact_life import subsurface_shear

    found = minimize_scalar(lambda z: -_tau1(z), bounds=(0.0, 5.0), method="bounded", options={"xatol": 1e-12})
    depth, peak = float(found.x), -float(found.fun)
    shear, where = subsurface_shear(np.array([1000.0]), np.array([0.1]))
    assert shear[0] == pytest.approx(1000.0 * peak, rel=2e-3)  # 0.30 vs 0.3004
    assert where[0] == pytest.approx(0.1 * depth, rel=1e-2)  # 0.78 vs 0.786


def test_scene_figures_follow_the_closed_forms():
    """report.json's half-width, shear and case depth against Johnson written out at the worst
    sample of the run's own contact force and radius (an independent formula on the same inputs)."""
    cam, report = _run(plate(contact_width_mm=8.0, case_depth_factor=2.5))
    fig = report["cams"][0]["figures"]["dynamics"] if isinstance(report["cams"], list) else report["cams"]["c"]["figures"]["dynamics"]
    res, kin = cam.dynamics.result, cam.dynamics.kinematics
    e_star = E_STEEL / (2.0 * (1.0 - NU**2))
    load = np.maximum(res.contact_force, 0.0) / 8.0
    r = 1.0 / (1.0 / kin.rho_cam + 1.0 / 10.0)
    b = np.sqrt(4.0 * load * r / (math.pi * e_star))
    assert fig["hertz_half_width_peak_mm"] == pytest.approx(float(np.max(b)), rel=1e-9)
    assert fig["subsurface_shear_peak_MPa"] == pytest.approx(0.30 * fig["hertz_stress_peak_MPa"], rel=1e-12)
    assert fig["subsurface_shear_depth_max_mm"] == pytest.approx(0.78 * float(np.max(b)), rel=1e-9)
    assert fig["case_depth_mm"] == pytest.approx(2.5 * 0.78 * float(np.max(b)), rel=1e-9)
    names = {c["name"] for c in _checks(report)}
    assert "case_depth" in names


def _checks(report: dict) -> list[dict]:
    cams = report["cams"]
    cam = cams[0] if isinstance(cams, list) else next(iter(cams.values()))
    return cam["checks"]


def _figures(report: dict) -> dict:
    cams = report["cams"]
    cam = cams[0] if isinstance(cams, list) else next(iter(cams.values()))
    return cam["figures"]["dynamics"]


# ---- S-N allowable --------------------------------------------------------------------------------
def test_sn_allowable_by_hand_and_its_check():
    from camgen.contact_life import SnCurve

    # 1500 MPa at 1e7 cycles, m = 6.6: at 1e8 cycles 1500 * 10^(-1/6.6) = 1058.2203... (by hand)
    assert SnCurve(1500.0, 1e7, 6.6).allowable(1e8) == pytest.approx(1500.0 * 10.0 ** (-1.0 / 6.6), rel=1e-14)
    keys = {"sn_stress_mpa": 1500.0, "sn_cycles": 1e7, "sn_exponent": 6.6}
    ok = _run(plate(**keys, contact_design_cycles=1e8))[1]
    check = next(c for c in _checks(ok) if c["name"] == "contact_fatigue")
    assert check["limit"] == pytest.approx(1058.2203466, rel=1e-9) and check["status"] == "pass"
    peak = _figures(ok)["hertz_stress_peak_MPa"]
    # a stress-cycle point that puts the allowable just under the peak: the check fails
    tight = _run(plate(sn_stress_mpa=peak * 0.99, sn_cycles=1e8, sn_exponent=6.6, contact_design_cycles=1e8))[1]
    assert not next(c for c in _checks(tight) if c["name"] == "contact_fatigue")["status"] == "pass"


# ---- ISO 281 L10 ----------------------------------------------------------------------------------
def test_l10_constant_load_by_hand():
    from camgen.contact_life import BALL_EXPONENT, ROLLER_EXPONENT, bearing_life, equivalent_load

    # 5^(10/3) = exp(10/3 ln 5) = exp(5.36459) = 213.747 million revolutions (the brief's "214.4" is a rounding slip)
    assert bearing_life(10_000.0, 2_000.0, ROLLER_EXPONENT) == pytest.approx(213.747, rel=1e-5)
    assert bearing_life(10_000.0, 2_000.0, BALL_EXPONENT) == pytest.approx(125.0, rel=1e-14)  # 5^3
    assert equivalent_load(np.full(7, 2000.0), np.full(7, 0.3), ROLLER_EXPONENT) == pytest.approx(2000.0, rel=1e-14)


def test_l10_two_level_spectrum_by_hand():
    """30 % of the revolutions at 2 kN, 70 % at 4 kN: P = (0.3 2000^p + 0.7 4000^p)^(1/p), p = 10/3,
    worked by hand: P = 3639.27 N, L10 = (10000 / 3639.27)^(10/3) = 29.06 Mrev."""
    from camgen.contact_life import ROLLER_EXPONENT, bearing_life, equivalent_load

    p = 10.0 / 3.0
    expected = (0.3 * 2000.0**p + 0.7 * 4000.0**p) ** (1.0 / p)
    load = equivalent_load(np.array([2000.0, 4000.0, 0.0]), np.array([3.0, 7.0, 0.0]), ROLLER_EXPONENT)
    assert load == pytest.approx(expected, rel=1e-14)
    assert load == pytest.approx(3639.27, rel=1e-5)
    assert bearing_life(10_000.0, load, ROLLER_EXPONENT) == pytest.approx(29.06, rel=1e-3)


def test_roller_revolutions_a_turn_against_the_profile_length():
    """A translating roller turns on its pin L_profile / (2 pi R) times a turn: the length of the
    cam's contour (its polyline, an independent curve) over the roller's circumference."""
    cam, report = _run(plate(roller_dynamic_load_rating_n=8000.0))
    contour = cam.built.contour
    pts = np.asarray(contour.flatten(1e-5))
    length = float(np.sum(np.hypot(*np.diff(np.vstack([pts, pts[:1]]), axis=0).T)))
    assert _figures(report)["roller_revs_per_turn"] == pytest.approx(length / (2.0 * math.pi * 10.0), rel=1e-4)


def test_bearing_life_in_hours_and_its_check():
    cam, report = _run(plate(roller_dynamic_load_rating_n=8000.0, min_bearing_life_h=1000.0))
    fig = _figures(report)
    res = cam.dynamics.result
    p = 10.0 / 3.0
    assert fig["bearing_L10_Mrev"] == pytest.approx((8000.0 / fig["bearing_equivalent_load_N"]) ** p, rel=1e-12)
    hours = fig["bearing_L10_Mrev"] * 1e6 / (fig["roller_revs_per_turn"] * res.rpm * 60.0)
    assert fig["bearing_L10_h"] == pytest.approx(hours, rel=1e-12)
    # the equivalent load lies between the smallest and largest contact force
    assert float(np.min(res.contact_force)) < fig["bearing_equivalent_load_N"] < float(np.max(res.contact_force))
    assert next(c for c in _checks(report) if c["name"] == "bearing_life")["status"] == "pass"
    failing = _run(plate(roller_dynamic_load_rating_n=8000.0, min_bearing_life_h=2.0 * hours))[1]
    assert not next(c for c in _checks(failing) if c["name"] == "bearing_life")["status"] == "pass"
    ball = _figures(_run(plate(roller_dynamic_load_rating_n=8000.0, roller_bearing="ball"))[1])
    assert ball["bearing_L10_Mrev"] == pytest.approx((8000.0 / ball["bearing_equivalent_load_N"]) ** 3, rel=1e-12)


# ---- bad input, nothing changed -----------------------------------------------------------------
@pytest.mark.parametrize("changes, key", [
    ({"sn_stress_mpa": 1500.0, "sn_cycles": 1e7}, "sn_exponent"),
    ({"min_bearing_life_h": 100.0}, "min_bearing_life_h"),
    ({"roller_dynamic_load_rating_n": 0.0}, "roller_dynamic_load_rating_n"),
    ({"roller_dynamic_load_rating_n": 1000.0, "roller_bearing": "needle"}, "roller_bearing"),
    ({"case_depth_factor": 0.5}, "case_depth_factor"),
    ({"follower": "flat", "roller_radius_mm": None, "roller_pin_radius_mm": 3.0}, "roller_pin_radius_mm"),
    ({"follower": "knife", "roller_radius_mm": None, "case_depth_factor": 2.0}, "case_depth_factor"),
    ({"mass_kg": None, "spring_rate_n_per_mm": None, "spring_preload_n": None, "case_depth_factor": 2.0}, "mass_kg"),
])
def test_bad_input_refused_naming_the_key(tmp_path, capsys, changes, key):
    scene = plate(**changes)
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    out = tmp_path / "out"
    code = main(["run", str(path), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and err[0].startswith("camgen: error: ") and key in err[0]
    assert not out.exists() or not any(out.rglob("*.*"))


def test_groove_refuses_the_keys(tmp_path, capsys):
    scene = plate(form="groove", spring_rate_n_per_mm=None, spring_preload_n=None, roller_dynamic_load_rating_n=8000.0)
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(scene))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "roller_dynamic_load_rating_n" in err[0]


def test_no_key_no_change():
    """Without the new keys the dynamics figures and checks are those of before (the golden test
    holds every template's bytes; here: none of the new figures appears)."""
    report = _run(plate())[1]
    fig = _figures(report)
    for name in ("case_depth_mm", "side_load_peak_N", "bearing_L10_h", "friction_torque_peak_Nm"):
        assert name not in fig
    assert {c["name"] for c in _checks(report)} == {"jump", "hertz_stress", "camshaft_torque"} | {
        c["name"] for c in _checks(report) if c["name"] not in {"case_depth", "friction_torque", "bearing_life"}}
