"""Dynamics of a barrel cam's rib (track = "rib"): two rollers straddle the rib, the upper one on its
upper face, the lower one under its lower face.

Every expected number comes from outside camgen's barrel and dynamics code:

* the cycloidal law in closed form (Norton, *Design of Machinery*, eq. 8.6; test_barrel_dynamics'
  ``cycloid``): s'' vanishes and changes sign at the middle of the rise and of the return;
* Newton's second law along the follower's coordinate (translating: m s'' w^2 + c s' w + load + m g;
  oscillating: I psi'' w^2 + the arm's weight m g cg cos psi) and the sign rule stated in
  camgen.kinds.barrel_rib_dynamics: a face only pushes, so the upper roller (on the upper face)
  carries the force where the cam must push the follower up (Q > 0), the lower roller where Q < 0;
* the contact normal from first principles, for each roller with its own axis velocity (its arm
  point's derivative, closed form here): perpendicular to the roller's velocity relative to the cam;
  the normal force Q / (lever cos alpha), the lever the distance from the pivot to the roller's axis,
  sqrt(L^2 + o^2) from the stated geometry;
* the power balance of a frictionless contact: T w = Q w q';
* the crossovers: with gravity along -z the axial force m (s'' w^2 + g) changes sign where
  sin(2 pi u) = g beta^2 / (2 pi h w^2) in the return (closed form);
* the line-contact Hertz pressure (Johnson, *Contact Mechanics*, 1985, eq. 4.45,
  ``p0 = sqrt(P E* (1/R1 + 1/R2) / pi)``, P the load per unit length), each face's radius measured
  here as the circle through three neighbouring points of its roller's axis path developed at R_m,
  offset by w towards the rib.
"""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from helpers import scene_toml
from test_barrel_dynamics import G, R_M, circle_curvature, cycloid, run, segments, table

RPM, MASS, LOAD, DAMP = 150.0, 0.8, 5.0, 20.0
RIB_W, RR, CLEAR, LENGTH = 10.0, 8.0, 0.05, 90.0
W = RR + CLEAR / 2
O = RIB_W / 2 + W  # each roller axis' offset from the pitch line
H, BETA, TWO_PI = 40.0, math.radians(120.0), 2.0 * math.pi
OMEGA = RPM * TWO_PI / 60.0
ARM, SWING, INERTIA, ARM_MASS, CG = 60.0, math.radians(20.0), 2e-3, 0.3, 25.0


def rib(**extra) -> dict:
    return table(**{"track": "rib", "rib_width_mm": RIB_W, "cylinder_length_mm": LENGTH, "rpm": RPM, **extra})


def osc_rib(**extra) -> dict:
    return rib(**{"follower_motion": "oscillating", "arm_length_mm": ARM, "rotation": "cw", "segments": segments("swing_deg", 20.0),
                  "pressure_angle_limit_deg": 60.0, "inertia_kg_m2": INERTIA, **extra})


def check(cam, name: str):
    return next(c for c in cam.checks if c.name == name)


# --------------------------------------------------------------------------------------------
# Translating follower
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def translating():
    return run(rib(mass_kg=MASS, external_load_n=LOAD, damping_n_s_per_m=DAMP))


def axial_force(theta: np.ndarray) -> np.ndarray:
    """N along +z the rib must give the follower (Newton): m a + c v + load + weight (gravity along -z)."""
    _, v, a = cycloid(theta)
    return MASS * a * OMEGA**2 * 1e-3 + DAMP * v * OMEGA * 1e-3 + LOAD + MASS * G


def test_translating_rib_forces_follow_the_sign_rule_and_the_torque_the_power_balance(translating):
    """The upper roller carries Q / cos(alpha) where Q > 0, the lower one -Q / cos(alpha) where
    Q < 0 (tan(alpha) = s' / R_m for both: a z shift changes neither velocity nor normal); the
    torque is Q s' (N*m)."""
    res = translating.dynamics_stage.outcome.result
    theta = res.theta
    _, v, _ = cycloid(theta)
    q = axial_force(theta)
    cos = np.cos(np.arctan(v / R_M))
    scale = np.max(np.abs(q))
    assert np.max(np.abs(res.generalised_force - q)) <= 1e-9 * scale
    assert np.max(np.abs(res.contact_force - np.maximum(q, 0.0) / cos)) <= 1e-9 * scale
    assert np.max(np.abs(res.contact_force_2 - np.maximum(-q, 0.0) / cos)) <= 1e-9 * scale
    torque = q * v * 1e-3
    assert np.max(np.abs(res.torque - torque)) <= 1e-9 * np.max(np.abs(torque))


def test_translating_rib_crossovers_with_the_weight_against_the_closed_form():
    """Inertia and weight only: Q = m (s'' w^2 1e-3 + g) < 0 where s'' < -g 1e3 / w^2: s'' =
    (2 pi h / beta^2) sin(2 pi u) in the rise, its negative in the return, so with
    k = g 1e3 beta^2 / (2 pi h w^2) and u1 = asin(k) / (2 pi) the lower roller carries the load for u in
    (1/2 + u1, 1 - u1) of the rise and (u1, 1/2 - u1) of the return: the contact_force check lists
    those four cam angles (on its 0.1 deg grid); wall_crossover lists the law's zeros of s'' (60 and
    240 deg, to 1e-6 deg) and says the load passes between the rib's rollers."""
    cam = run(rib(mass_kg=MASS))
    k = G * 1e3 / OMEGA**2 / (TWO_PI * H / BETA**2)
    assert 0.0 < k < 1.0
    u1 = math.asin(k) / TWO_PI
    spans = [(math.degrees(BETA * (0.5 + u1)), math.degrees(BETA * (1.0 - u1))),
             (math.degrees(math.pi + BETA * u1), math.degrees(math.pi + BETA * (0.5 - u1)))]
    want = [a for span in spans for a in span]
    load = check(cam, "contact_force")
    assert len(load.where_deg) == 4 and np.allclose(sorted(load.where_deg), want, atol=0.1 + 1e-9), (load.where_deg, want)
    crossing = check(cam, "wall_crossover")
    assert crossing.value == 2 and np.allclose(crossing.where_deg, [60.0, 240.0], atol=1e-6)
    assert "rib's upper roller to its lower one" in crossing.note
    res = cam.dynamics_stage.outcome.result
    deg = np.degrees(res.theta)
    lower_loaded = np.zeros_like(deg, dtype=bool)
    near = np.zeros_like(deg, dtype=bool)
    for a, b in spans:  # Q < 0: only the lower roller pushes (down)
        lower_loaded |= (deg > a + 0.05) & (deg < b - 0.05)
        near |= (np.abs(deg - a) <= 0.05) | (np.abs(deg - b) <= 0.05)
    assert np.all(res.contact_force_2[lower_loaded] > 0) and np.all(res.contact_force[lower_loaded] == 0)
    upper_loaded = ~lower_loaded & ~near
    assert np.all(res.contact_force[upper_loaded] > 0) and np.all(res.contact_force_2[upper_loaded] == 0)


def test_translating_rib_hertz_stress_against_the_two_cylinder_formula():
    """Each roller (radius Rr) against its face's developed radius at R_m: the pitch curve shifted by
    +-o (the same curve), measured by three-point circles, the upper face below the upper roller
    -(rho + w), the lower face above the lower roller rho - w."""
    e_c, e_f, nu_c, nu_f, width = 200.0, 110.0, 0.28, 0.33, 6.0
    cam = run(rib(mass_kg=MASS, external_load_n=LOAD, gravity=False, cam_modulus_gpa=e_c, follower_modulus_gpa=e_f, cam_poisson=nu_c,
                  follower_poisson=nu_f, contact_width_mm=width))
    res = cam.dynamics_stage.outcome.result
    theta, step = res.theta, 1e-4
    x = np.stack([R_M * (theta + d) for d in (-step, 0.0, step)])  # sigma = +1: x = R_m phi = -R_m theta, the same circle
    z = np.stack([cycloid(theta + d)[0] for d in (-step, 0.0, step)])
    with np.errstate(divide="ignore"):
        rho = 1.0 / circle_curvature(x, z)
    e_star = 1.0 / ((1 - nu_c**2) / (e_c * 1e3) + (1 - nu_f**2) / (e_f * 1e3))
    deg = np.degrees(theta)
    ends = np.abs(deg - 60.0 * np.round(deg / 60.0)) < 0.05  # the law's joins: the circles straddle them
    for got, force, face in ((res.hertz_stress, res.contact_force, -(rho + W)), (res.hertz_stress_2, res.contact_force_2, rho - W)):
        want = np.sqrt(force / width * e_star * (1.0 / face + 1.0 / RR) / math.pi)
        assert np.max(np.abs(got - want)[~ends]) <= 1e-6 * np.max(want)


# --------------------------------------------------------------------------------------------
# Oscillating follower: both rollers on the arm's end along its normal
# --------------------------------------------------------------------------------------------
def roller_axes(theta: np.ndarray, side: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The roller's axis (y, z) at the arm angle psi (default rest -swing/2, pivot (-L, length/2))
    and d = d(y, z)/dpsi (the stated geometry: A + side o n, n = (-sin psi, cos psi))."""
    psi = -SWING / 2 + cycloid(theta, SWING)[0]
    o = side * O
    y = -ARM + ARM * np.cos(psi) - o * np.sin(psi)
    z = LENGTH / 2 + ARM * np.sin(psi) + o * np.cos(psi)
    d = np.stack([-ARM * np.sin(psi) - o * np.cos(psi), ARM * np.cos(psi) - o * np.sin(psi)], axis=-1)
    return y, z, d


def cos_alpha(theta: np.ndarray, side: int) -> np.ndarray:
    """cos of the roller's pressure angle at its section R_m from the cam axis: its normal is
    perpendicular to its velocity relative to the cam (sigma = -1: the cam moves the section at -t along y)."""
    y, _, d = roller_axes(theta, side)
    t = np.sqrt(R_M**2 - y**2)
    rel = cycloid(theta, SWING)[1][:, None] * d - np.stack([-t, np.zeros_like(t)], axis=-1)
    n = np.stack([-rel[:, 1], rel[:, 0]], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return np.abs(np.sum(n * d, axis=-1)) / np.linalg.norm(d, axis=-1)


@pytest.fixture(scope="module")
def oscillating():
    return run(osc_rib(mass_kg=ARM_MASS, cg_distance_mm=CG))


def test_oscillating_rib_forces_on_each_roller_and_the_torque(oscillating):
    """Q = I psi'' w^2 (N*mm) + m g cg cos psi (the arm's weight, gravity along -z); the upper roller
    carries Q / (L' cos alpha_up) where Q > 0, the lower one -Q / (L' cos alpha_lo) where Q < 0, each
    with its own normal, L' = sqrt(L^2 + o^2) (the pivot to either roller's axis); T = Q psi'."""
    res = oscillating.dynamics_stage.outcome.result
    theta = res.theta
    phi, dphi, d2phi = cycloid(theta, SWING)
    psi = -SWING / 2 + phi
    q = INERTIA * d2phi * OMEGA**2 * 1e3 + ARM_MASS * G * CG * np.cos(psi)
    assert np.max(np.abs(res.generalised_force - q)) <= 1e-9 * np.max(np.abs(q))
    lever = math.hypot(ARM, O)
    scale = np.max(np.abs(q)) / lever
    up, lo = cos_alpha(theta, 1), cos_alpha(theta, -1)
    assert np.max(np.abs(up - lo)) > 1e-3  # the rollers' normals differ: the test tells them apart
    assert np.max(np.abs(res.contact_force - np.maximum(q, 0.0) / (lever * up))) <= 1e-9 * scale
    assert np.max(np.abs(res.contact_force_2 - np.maximum(-q, 0.0) / (lever * lo))) <= 1e-9 * scale
    torque = q * dphi * 1e-3
    assert np.max(np.abs(res.torque - torque)) <= 1e-9 * np.max(np.abs(torque))


def test_oscillating_rib_hertz_stress_against_the_two_cylinder_formula(oscillating):
    """Each roller's axis path developed at R_m, x = R_m (asin(y / R_m) - sigma theta), z, measured by
    three-point circles; the upper face (below the upper roller) -(rho + w), the lower face rho - w;
    Johnson eq. 4.45 with steel (210 GPa, 0.3) and the default contact length, the rib's height."""
    res = oscillating.dynamics_stage.outcome.result
    theta, step = res.theta, 1e-4
    e_star = 1.0 / (2.0 * (1 - 0.3**2) / 210e3)
    deg = np.degrees(theta)
    inside = np.abs(deg - 60.0 * np.round(deg / 60.0)) > 0.05
    for side, got, force in ((1, res.hertz_stress, res.contact_force), (-1, res.hertz_stress_2, res.contact_force_2)):
        pts = [roller_axes(theta + dt, side) for dt in (-step, 0.0, step)]
        x = np.stack([R_M * (np.arcsin(p[0] / R_M) + (theta + dt)) for p, dt in zip(pts, (-step, 0.0, step))])
        z = np.stack([p[1] for p in pts])
        with np.errstate(divide="ignore"):
            rho = 1.0 / circle_curvature(x, z)
        face = -(rho + W) if side > 0 else rho - W
        want = np.sqrt(force / 10.0 * e_star * (1.0 / face + 1.0 / RR) / math.pi)
        assert np.max(np.abs(got - want)[inside]) <= 1e-6 * np.max(want), side


def test_oscillating_rib_crossovers_at_the_middle_of_swing_and_return():
    """Inertia the only load: the arm's torque I psi'' w^2 changes sign at 60 and 240 deg."""
    cam = run(osc_rib(gravity=False))
    assert np.allclose(check(cam, "wall_crossover").where_deg, [60.0, 240.0], atol=1e-6)
    assert np.allclose(sorted(check(cam, "contact_force").where_deg), [60.0, 240.0], atol=0.1 + 1e-9)


def test_the_report_names_the_ribs_rollers():
    """report.html's dynamics panel names the rib's two rollers, not a groove's walls."""
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene({"output": {"formats": ["html"]}, "cams": {"c": rib(mass_kg=MASS, gravity=False)}}, "t")
    html = execute(scene, plan_run(scene)).files["report.html"]
    assert "upper roller on the rib's upper face (pushes the follower out)" in html
    assert "lower roller on its lower face (pulls it back)" in html and "the groove's two walls" not in html


@pytest.mark.parametrize("key, value", [("spring_rate_n_per_mm", 2.0), ("jump_margin_n", 1.0)])
def test_springs_are_refused_on_a_rib(key, value, tmp_path):
    """The rib is form-closed (its two faces hold the follower both ways): exit 2 naming the key."""
    cam = rib(mass_kg=MASS)
    cam[key] = value
    path = tmp_path / "s.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"b": cam}}), encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "camgen", "run", str(path), "--out", str(tmp_path / "out")], capture_output=True,
                          text=True)
    assert done.returncode == 2 and done.stderr.startswith("camgen: error: ") and done.stderr.count("\n") == 1, done.stderr
    assert f"cams.b.{key}" in done.stderr and not (tmp_path / "out").exists()
