"""Friction and loads (issue 25, item 3): the guide's bushing reactions against the stem's
statics solved here (moments about another point, numpy.linalg.solve), binding at its
threshold tan(phi) = L / (mu (L + 2a)), the flat face's friction torque against the friction
work per turn from the contact's sliding distance (finite differences of the contact points on
the cam and along the face), the roller pin and slip, refusals."""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

from camgen.cli import main
from helpers import scene_toml


def _run(scene: dict):
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    parsed = parse_scene(copy.deepcopy(scene), "s")
    result = execute(parsed, plan_run(parsed))
    return result.cams[0], json.loads(result.files["report.json"])


def _cam_json(report: dict) -> dict:
    cams = report["cams"]
    return cams[0] if isinstance(cams, list) else next(iter(cams.values()))


def _segments(h: float) -> list[dict]:
    return [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": h}, {"law": "dwell", "span_deg": 60.0},
            {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -h}, {"law": "dwell", "span_deg": 60.0}]


def plate(**changes) -> dict:
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 300.0, "thickness_mm": 10.0,
           "segments": _segments(20.0), "mass_kg": 0.6, "spring_rate_n_per_mm": 2.0, "spring_preload_n": 35.0}
    cam.update(changes)
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {k: v for k, v in cam.items() if v is not None}}}


def _statics(lateral: float, axial: float, offset: float, overhang: float, length: float) -> np.ndarray:
    """The two bushing reactions from equilibrium written here: contact at (offset, 0), near bushing at
    (0, overhang), far at (0, overhang + length); sum of lateral forces and of moments about the origin."""
    a = np.array([[1.0, 1.0], [-overhang, -(overhang + length)]])
    rhs = np.array([-lateral, -offset * axial])
    return np.linalg.solve(a, rhs)


@pytest.mark.parametrize("lateral, axial, offset, overhang, length", [
    (30.0, 100.0, 0.0, 20.0, 40.0), (-12.5, 80.0, 0.0, 0.0, 25.0), (-4.0, 200.0, 7.5, 15.0, 60.0), (9.0, 50.0, -3.0, 35.0, 10.0)])
def test_bushing_reactions_against_statics(lateral, axial, offset, overhang, length):
    from camgen.friction import guide_reactions

    near, far = guide_reactions(np.array([lateral]), np.array([axial]), offset, overhang, length)
    expected = _statics(lateral, axial, offset, overhang, length)
    np.testing.assert_allclose([near[0], far[0]], expected, rtol=1e-12, atol=1e-12)


def test_binding_at_its_threshold():
    """A roller: F at pressure angle phi with tan(phi) = L / (mu (L + 2a)) binds exactly (ratio 1);
    a little less steep it does not."""
    from camgen.friction import binding_ratio, guide_reactions

    mu, length, overhang, force = 0.15, 40.0, 20.0, 250.0
    critical = math.atan(length / (mu * (length + 2.0 * overhang)))
    for phi, expect in ((critical, 1.0), (critical * 0.98, None)):
        lateral, axial = force * math.sin(phi), force * math.cos(phi)
        near, far = _statics(lateral, axial, 0.0, overhang, length)
        ratio = binding_ratio(mu, *guide_reactions(np.array([lateral]), np.array([axial]), 0.0, overhang, length), np.array([axial]))
        assert ratio[0] == pytest.approx(mu * (abs(near) + abs(far)) / axial, rel=1e-12)
        if expect is None:
            assert ratio[0] < 1.0
        else:
            assert ratio[0] == pytest.approx(1.0, rel=1e-12)


def test_guide_check_in_a_scene():
    cam, report = _run(plate(guide_length_mm=40.0, guide_overhang_mm=20.0, guide_friction=0.1))
    res = cam.dynamics.result
    fig = _cam_json(report)["figures"]["dynamics"]
    side = res.contact_force * np.sin(res.pressure_angle)  # F_axial tan(phi)
    assert fig["side_load_peak_N"] == pytest.approx(float(np.max(np.abs(side))), rel=1e-12)
    assert fig["guide_reaction_near_peak_N"] == pytest.approx(float(np.max(np.abs(side))) * 60.0 / 40.0, rel=1e-12)
    tan_phi = np.abs(np.tan(res.pressure_angle))
    assert fig["guide_binding_ratio_peak"] == pytest.approx(float(np.max(0.1 * tan_phi * 80.0 / 40.0)), rel=1e-9)
    check = next(c for c in _cam_json(report)["checks"] if c["name"] == "guide_binding")
    assert check["status"] == "pass"
    # a short guide with a long overhang and a sticky bushing binds: the check fails
    bad = _run(plate(guide_length_mm=5.0, guide_overhang_mm=60.0, guide_friction=0.5))[1]
    assert next(c for c in _cam_json(bad)["checks"] if c["name"] == "guide_binding")["status"] == "fail"


def test_flat_face_friction_torque_against_the_friction_work():
    """The work of friction over a turn, sum of mu F |slip|, the slip at each step from the contact
    points by finite differences: the contact's run along the cam (cam frame) minus its run along
    the face (the face's x, turned into the cam frame): equal to the integral of the face's
    friction torque mu F h the module derives (h = rho - s'')."""
    mu = 0.12
    cam, report = _run(plate(follower="flat", roller_radius_mm=None, base_radius_mm=45.0, contact_friction=mu))
    res, data = cam.dynamics.result, cam.built.envelope.data
    theta = res.theta
    q = data.contact_point[:, 0] + 1j * data.contact_point[:, 1]  # cam frame (ccw cam: ground = cam frame turned by +theta)
    x = data.face_position
    nxt = np.append(theta[1:], theta[0] + 2.0 * math.pi)
    mid = 0.5 * (theta + nxt)
    run_on_cam = np.roll(q, -1) - q
    run_on_face = (np.roll(x, -1) - x) * np.exp(-1j * mid)  # along the face (ground +x), seen from the cam
    slip = np.abs(run_on_cam - run_on_face)
    force = np.maximum(0.5 * (res.contact_force + np.roll(res.contact_force, -1)), 0.0)
    work = float(np.sum(mu * force * slip)) * 1e-3  # N*mm -> J
    fig = _cam_json(report)["figures"]["dynamics"]
    assert fig["friction_energy_per_turn_J"] == pytest.approx(work, rel=1e-5)
    # and the torque with friction is the frictionless torque plus it
    assert fig["torque_with_friction_rms_Nm"] > fig["torque_rms_Nm"]


def test_roller_pin_friction_and_slip():
    """Pin torque mu_p F r_pin; slip ratio (pin torque + J alpha) / (mu_c F R): with no roller inertia it is
    mu_p r_pin / (mu_c R) at every loaded angle."""
    cam, report = _run(plate(roller_pin_radius_mm=4.0, roller_pin_friction=0.2, contact_friction=0.1))
    res = cam.dynamics.result
    fig = _cam_json(report)["figures"]["dynamics"]
    assert fig["roller_pin_torque_peak_Nmm"] == pytest.approx(0.2 * 4.0 * float(np.max(res.contact_force)), rel=1e-12)
    assert fig["roller_slip_ratio_peak"] == pytest.approx(0.2 * 4.0 / (0.1 * 10.0), rel=1e-12)
    assert next(c for c in _cam_json(report)["checks"] if c["name"] == "roller_slip")["status"] == "pass"
    # a heavy roller skids where the force is least and the acceleration large
    heavy = _run(plate(roller_pin_radius_mm=4.0, roller_inertia_kg_mm2=400.0, contact_friction=0.05))[1]
    assert next(c for c in _cam_json(heavy)["checks"] if c["name"] == "roller_slip")["status"] == "fail"


@pytest.mark.parametrize("changes, key", [
    ({"guide_length_mm": 40.0}, "guide_overhang_mm"),
    ({"guide_overhang_mm": 10.0}, "guide_length_mm"),
    ({"guide_friction": 0.2}, "guide_friction"),
    ({"guide_length_mm": 0.0, "guide_overhang_mm": 10.0}, "guide_length_mm"),
    ({"guide_friction": 1.5, "guide_length_mm": 40.0, "guide_overhang_mm": 10.0}, "guide_friction"),
    ({"roller_pin_friction": 0.1}, "roller_pin_friction"),
    ({"contact_friction": 0.1}, "contact_friction"),
    ({"contact_friction": 0.0, "roller_pin_radius_mm": 3.0}, "contact_friction"),
    ({"follower": "knife", "roller_radius_mm": None, "contact_friction": 0.1}, "contact_friction"),
])
def test_bad_input_refused_naming_the_key(tmp_path, capsys, changes, key):
    path = tmp_path / "scene.toml"
    path.write_text(scene_toml(plate(**changes)))
    out = tmp_path / "out"
    code = main(["run", str(path), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and err[0].startswith("camgen: error: ") and key in err[0]
    assert not out.exists() or not any(out.rglob("*.*"))
