"""Friction, loads and contact fatigue in report.html (issue 25, items 3 and 5): the curves the
page draws against report.json's figures of the same run (read back as JSON) and against the
closed forms of the curves themselves (a roller follower: side load F sin phi, bushing
reactions |F_x| (L + a) / L and |F_x| a / L, binding mu_g |tan phi| (L + 2a) / L, pin torque
mu_p F r_pin, traction mu_c F R; Johnson's line contact: b = 2 F / (pi w p_max), shear 0.30
p_max at 0.78 b), and the plots' titles on the page.  The figures themselves are tested in
test_friction.py and test_contact_life.py."""
from __future__ import annotations

import copy
import json

import numpy as np
import pytest

L, A, MU_G, MU_P, R_PIN, MU_C, R_ROLLER, WIDTH = 40.0, 20.0, 0.1, 0.2, 4.0, 0.15, 10.0, 10.0


def _segments(h: float) -> list[dict]:
    return [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": h}, {"law": "dwell", "span_deg": 60.0},
            {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -h}, {"law": "dwell", "span_deg": 60.0}]


def plate(**changes) -> dict:
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": R_ROLLER, "rpm": 300.0, "thickness_mm": 10.0,
           "segments": _segments(20.0), "mass_kg": 0.6, "spring_rate_n_per_mm": 2.0, "spring_preload_n": 35.0}
    cam.update(changes)
    return {"output": {"formats": ["dxf", "html"]}, "cams": {"c": {k: v for k, v in cam.items() if v is not None}}}


FRICTION = {"guide_length_mm": L, "guide_overhang_mm": A, "guide_friction": MU_G, "roller_pin_radius_mm": R_PIN,
            "roller_pin_friction": MU_P, "contact_friction": MU_C, "cam_modulus_gpa": 206.0, "follower_modulus_gpa": 206.0,
            "contact_width_mm": WIDTH}


def _run(scene: dict):
    """(the built cam, its report curves, report.json's figures.dynamics, report.html) of ``scene``."""
    from camgen.pipeline import execute, plan_run
    from camgen.report_data import report_input
    from camgen.scene import parse_scene

    parsed = parse_scene(copy.deepcopy(scene), "s")
    result = execute(parsed, plan_run(parsed))
    cam = result.cams[0]
    curves = report_input(result.scene, result.cams, result.jobs, result.plan.stages, [], drawn=True).cams[0].dynamics
    figures = json.loads(result.files["report.json"])["cams"]["c"]["figures"]["dynamics"]
    return cam, curves, figures, result.files["report.html"]


def test_friction_curves_and_plots_of_a_roller():
    cam, curves, fig, page = _run(plate(**FRICTION))
    res, fr = cam.dynamics.result, curves.friction
    assert fr is not None
    force, phi = np.maximum(res.contact_force, 0.0), res.pressure_angle
    # the drawn torque with friction peaks at report.json's figure; without it at the frictionless figure
    assert np.max(np.abs(fr.torque_with_friction)) == pytest.approx(fig["torque_with_friction_peak_Nm"], rel=1e-12)
    assert np.max(np.abs(fr.torque)) == pytest.approx(fig["torque_peak_Nm"], rel=1e-12)
    assert np.all(fr.torque_with_friction - fr.torque >= 0)  # friction only ever adds to the torque the shaft gives
    assert np.max(fr.friction_torque) == pytest.approx(fig["friction_torque_peak_Nm"], rel=1e-12)
    # the guide: closed forms of a roller (its force through the stem's axis)
    side = np.abs(force * np.sin(phi))
    np.testing.assert_allclose(np.abs(fr.side_load), side, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fr.guide_near, side * (L + A) / L, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fr.guide_far, side * A / L, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fr.binding, MU_G * np.abs(np.tan(phi)) * (L + 2 * A) / L, rtol=1e-9, atol=1e-12)
    assert np.max(fr.guide_near) == pytest.approx(fig["guide_reaction_near_peak_N"], rel=1e-12)
    assert np.max(fr.binding) == pytest.approx(fig["guide_binding_ratio_peak"], rel=1e-12)
    # the roller: pin friction, traction limit, and (no roller inertia) the torque to turn it is the pin's
    np.testing.assert_allclose(fr.pin_torque, MU_P * R_PIN * force, rtol=1e-12)
    np.testing.assert_allclose(fr.traction_limit, MU_C * force * R_ROLLER, rtol=1e-12)
    np.testing.assert_allclose(fr.roller_drive_torque, MU_P * R_PIN * force, rtol=1e-12)
    assert fr.slip_peak == pytest.approx(fig["roller_slip_ratio_peak"], rel=1e-12)
    # contact fatigue: Johnson's line contact from the drawn curves and the dynamics' Hertz stress
    p_max = res.hertz_stress
    np.testing.assert_allclose(fr.half_width, 2.0 * force / (np.pi * WIDTH * p_max), rtol=1e-9)
    np.testing.assert_allclose(fr.shear, 0.30 * p_max, rtol=1e-12)
    np.testing.assert_allclose(fr.shear_depth, 0.78 * fr.half_width, rtol=1e-12)
    assert fr.case_depth == pytest.approx(fig["case_depth_mm"], rel=1e-12)
    assert np.max(fr.shear) == pytest.approx(fig["subsurface_shear_peak_MPa"], rel=1e-12)
    # the page: one figure of them, each plot titled with report.json's numbers
    assert page.count("friction, loads and contact fatigue at 300 rpm") == 1
    for title in (f"camshaft torque with friction: peak {fig['torque_with_friction_peak_Nm']:.4g} N*m "
                  f"(without {fig['torque_peak_Nm']:.4g})",
                  f"guide loads: side {fig['side_load_peak_N']:.4g} N, bushings {fig['guide_reaction_near_peak_N']:.4g} and "
                  f"{fig['guide_reaction_far_peak_N']:.4g} N at most",
                  f"guide binding margin: the bushings' friction up to {fig['guide_binding_ratio_peak']:.4g} x the axial force",
                  f"roller slip margin: torque to turn it up to {fig['roller_slip_ratio_peak']:.4g} x the traction",
                  f"sub-surface maximum shear 0.30 p_max (Johnson 4.2): peak {fig['subsurface_shear_peak_MPa']:.4g} MPa",
                  f"contact half-width and shear depth: deepest {fig['subsurface_shear_depth_max_mm']:.4g} mm",
                  f"case depth asked for {fig['case_depth_mm']:.4g} mm", "cam angle (deg)", "camshaft torque (N*m)",
                  "force across the stem (N)", "torque on the roller (N*mm)", "sub-surface shear (MPa)",
                  "depth below the surface (mm)"):
        assert title in page, title


def test_plots_only_where_they_apply():
    """A scene without friction keys draws none; contact-fatigue keys alone draw no torque with
    friction (there is none) and no guide reactions (no guide given), only the side load."""
    _, curves, _, page = _run(plate())
    assert curves.friction is None and "friction, loads and contact fatigue" not in page
    cam, curves, fig, page = _run(plate(case_depth_factor=3.0, cam_modulus_gpa=206.0, follower_modulus_gpa=206.0,
                                        contact_width_mm=WIDTH))
    fr = curves.friction
    assert fr.torque_with_friction is None and "camshaft torque with friction" not in page
    assert fr.guide_near is None and fr.binding is None and "guide binding margin" not in page
    assert f"side load on the guide (F_axial tan phi): peak {fig['side_load_peak_N']:.4g} N" in page
    assert fr.case_depth == pytest.approx(3.0 * 0.78 * float(np.max(fr.half_width)), rel=1e-12)
    assert "no further friction plot for these keys" in page  # three panels: the fourth says so


def test_flat_face_friction_torque_drawn():
    """A translating flat face's friction torque mu_c F h (the cam's surface slides along the face
    at w h, h = base radius + lift the face's distance from the cam axis): drawn as the friction's
    share; the drawn torque with friction peaks at report.json's figure."""
    cam, curves, fig, page = _run(plate(follower="flat", roller_radius_mm=None, base_radius_mm=45.0, contact_friction=0.12))
    fr, res = curves.friction, cam.dynamics.result
    h = 45.0 + cam.dynamics.kinematics.s  # the face's distance from the cam axis: base radius + lift
    np.testing.assert_allclose(fr.friction_torque, 0.12 * np.maximum(res.contact_force, 0.0) * h * 1e-3, rtol=1e-9, atol=1e-12)
    assert np.max(np.abs(fr.torque_with_friction)) == pytest.approx(fig["torque_with_friction_peak_Nm"], rel=1e-12)
    assert f"camshaft torque with friction: peak {fig['torque_with_friction_peak_Nm']:.4g} N*m (without" in page
