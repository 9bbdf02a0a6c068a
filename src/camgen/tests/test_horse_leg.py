"""Horse-robot single leg (paper 000, Sections 3-6)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from camgen.errors import GeometryError
from camgen.mechanisms import horse_leg as hl

LEG = hl.HorseLeg()
# Section 6.1: lift, leg horizontal, body height change, body horizontal, stride (mm)
PAPER = {
    12.5: (47.72, 506.33, 67.76, 631.22, 417.18),
    14.5: (139.68, 611.79, 67.13, 555.32, 548.59),
    18.5: (1293.14, 852.04, 30.62, 232.85, 226.83),
}
KEYS = ("lift_mm", "leg_horizontal_mm", "body_height_change_mm", "body_horizontal_mm", "stride_mm")


@pytest.fixture(scope="module")
def solutions():
    theta1 = hl.cycle(3600)
    return {a: hl.solve_leg(LEG, math.radians(a), theta1) for a in PAPER}


def cis(angle):
    return np.exp(1j * np.asarray(angle))


def z(points):
    return points[..., 0] + 1j * points[..., 1]


@pytest.mark.parametrize("alpha", sorted(PAPER))
def test_every_loop_equation_closes(solutions, alpha):
    """Residuals of eqs. (5), (8), (11), (14), (17) with the solved unknowns, as the paper writes them."""
    s, leg = solutions[alpha], LEG
    a1 = math.radians(alpha)
    th1 = s.theta1
    sign = np.where(s.phi1 >= 0, 1.0, -1.0)
    beta10 = -s.beta1 * sign
    psi = th1 + s.phi1 + beta10
    # the output angle is Table 1's for the contact's input angle
    from camgen.synthesis.three_arc import yoke_law

    beta_t, r_t = yoke_law(*leg.stride_cam, s.phi1)
    assert np.max(np.abs(beta_t - s.beta1)) <= 1e-9 and np.max(np.abs(r_t - s.radius1)) <= 1e-9
    o7, o6, o4, o5 = (complex(*getattr(leg, k)) for k in ("o7", "o6", "o4", "o5"))
    lhs5 = s.radius1 * cis(th1 + s.phi1) + s.h * cis(psi + math.pi / 2) + leg.e2 * cis(psi + math.pi)
    rhs5 = o7 + leg.r_p * cis(a1 + math.pi / 2) + s.s * cis(a1)
    assert np.max(np.abs(lhs5 - rhs5)) <= 1e-9  # eq. (5)
    theta2 = math.pi / 2 + th1 + beta10 + s.phi1 + leg.gamma2
    lhs8 = rhs5 + leg.l1 * cis(theta2)  # eq. (7) with the missing j restored
    assert np.max(np.abs(lhs8 - (o6 + leg.r6 * cis(s.theta6)))) <= 1e-9  # eq. (8)
    theta_a = np.angle(z(s.b) - z(s.a))
    lhs11 = leg.r1 * cis(th1 + leg.gamma1) + leg.r_ab * cis(theta_a)
    assert np.max(np.abs(lhs11 - (o4 + leg.r4 * cis(s.theta4 + leg.gamma4)))) <= 1e-9  # eq. (11)
    sign4 = np.where(s.phi4 >= 0, 1.0, -1.0)
    psi4 = s.theta4 + s.phi4 - s.beta4 * sign4
    lhs14 = o4 + s.radius4 * cis(s.theta4 + s.phi4) + s.h4 * cis(psi4 + math.pi / 2) + leg.e5 * cis(psi4 + math.pi)
    assert np.max(np.abs(lhs14 - o5)) <= 1e-9  # eq. (14)
    theta5 = 1.5 * math.pi + s.theta4 - s.beta4 * sign4 + s.phi4 - leg.gamma5
    lhs17 = o5 + leg.r5 * cis(theta5)
    rhs17 = o6 + leg.r7 * cis(s.theta6 + leg.gamma6) + leg.r8 * cis(s.theta8) + s.slider * cis(leg.theta_u + s.theta8 - math.pi)
    assert np.max(np.abs(lhs17 - rhs17)) <= 1e-9  # eq. (17)
    w = o6 + leg.r7 * cis(s.theta6 + leg.gamma6) + leg.r8 * cis(s.theta8) + leg.s8 * cis(math.pi + s.theta8 - leg.theta_p)
    assert np.max(np.abs(w - z(s.w))) <= 1e-9  # eq. (18)


@pytest.mark.parametrize("alpha", sorted(PAPER))
def test_paper_figures_within_three_percent(solutions, alpha):
    figures = hl.gait_figures(LEG, solutions[alpha])
    for key, paper in zip(KEYS, PAPER[alpha]):
        assert figures[key] == pytest.approx(paper, rel=0.03), key
    # "the maximum angle of the stride length cam mechanism was less than 26 deg"
    assert figures["max_pressure_angle_deg"] < 26.0


def test_the_paper_figures_imply_one_ground_line(solutions):
    """Each case's (lowest foot point + the paper's body height change) gives the ground line:
    the three agree within 1.5 mm (the foot's vertical range is 116-1340 mm)."""
    lines = [solutions[a].w[:, 1].min() + PAPER[a][2] for a in PAPER]
    assert np.ptp(lines) < 1.5 and abs(np.mean(lines) - LEG.ground_y) < 1.0


@pytest.mark.parametrize("alpha", sorted(PAPER))
def test_pressure_angle_by_the_instant_centre_and_by_velocities(solutions, alpha):
    """Eqs. (19)-(25) against the velocity of the fork point at N from numerical derivatives of
    the solved fork pose (Q, psi) over the cam angle."""
    s = solutions[alpha]
    step = s.theta1[1] - s.theta1[0]
    dq = (np.roll(s.q, -1, axis=0) - np.roll(s.q, 1, axis=0)) / (2 * step)
    dpsi = np.angle(np.exp(1j * (np.roll(s.psi, -1) - np.roll(s.psi, 1)))) / (2 * step)
    rel = s.contact - s.q
    velocity = dq + dpsi[:, None] * np.stack([-rel[:, 1], rel[:, 0]], axis=1)
    normal = np.stack([np.cos(s.psi), np.sin(s.psi)], axis=1)
    speed = np.linalg.norm(velocity, axis=1)
    moving = speed > 1e-3  # mm/rad: on the dwell arcs the fork stands still and the angle is geometric only
    assert moving.mean() > 0.5
    cos = np.abs(np.sum(velocity * normal, axis=1))[moving] / speed[moving]
    by_velocity = np.degrees(np.arccos(np.clip(cos, 0, 1)))
    assert np.max(np.abs(by_velocity - np.degrees(s.pressure_angle[moving]))) <= 0.01


def test_literal_equation_20_gives_the_implausible_angles(solutions):
    for alpha in PAPER:
        literal = np.degrees(hl.pressure_angle(LEG, solutions[alpha], literal=True))
        assert literal.max() > 59.0  # the misprinted slide term: 60-90 deg, far above "< 26 deg"


def test_grashof_margin_closed_form():
    assert hl.grashof_margin(LEG) == pytest.approx(655 + 44 - 35 - math.hypot(114, 654), abs=1e-12)
    assert 0 < hl.grashof_margin(LEG) < 0.2


@pytest.mark.parametrize("alpha", sorted(PAPER))
def test_body_path_spans_the_papers_body_motion(alpha, solutions):
    """Paper 000, Section 6.1: during stance the body (O1) rises and falls by the body height
    change and moves forward by the body horizontal displacement; the path starts where the foot
    touches down (the body displacement is zero there)."""
    body = hl.body_path(LEG, solutions[alpha])
    _, _, height, horizontal, _ = PAPER[alpha]
    assert np.ptp(body[:, 1]) == pytest.approx(height, rel=0.03)  # the figures agree within 2.1 % (test_paper_figures)
    assert np.ptp(body[:, 0]) == pytest.approx(horizontal, rel=0.03)
    step = np.max(np.hypot(*np.diff(solutions[alpha].w, axis=0).T))
    assert np.min(np.hypot(body[:, 0], body[:, 1])) <= step  # the sample next to touch-down


def test_beyond_the_assembly_limit_is_a_clear_error():
    with pytest.raises(GeometryError, match=r"stride-length loop cannot close at cam angle theta1 = .* deg for alpha1 = 21\.000 deg"):
        hl.solve_leg(LEG, math.radians(21.0), hl.cycle(360))
    with pytest.raises(GeometryError, match="four-bar"):
        hl.four_bar(hl.HorseLeg(r_ab=400.0), hl.cycle(360))


def test_other_branches_are_reported():
    rows = hl.branch_table(LEG, math.radians(14.5), hl.cycle(360))
    assert len(rows) == 8
    chosen = rows[0]
    assert chosen["stride_psi0_deg"] == 206.5 and chosen["four_bar"] == 1 and chosen["height_side"] == 1
    # the chosen branch keeps the foot at the ground (about 2 m below the stride cam) ...
    assert chosen["foot_y_range_mm"][0] < LEG.ground_y < chosen["foot_y_range_mm"][1]
    # ... the second stride-loop root lifts it more than a metre, beside the body
    assert all(r["foot_y_range_mm"][0] > -1200 for r in rows if r["stride_psi0_deg"] == 221.5 and "error" not in r)


def test_lead_screw_equation_2():
    assert hl.lead_screw_length(LEG, math.radians(14.5)) == pytest.approx(100 * math.cos(math.radians(14.5)) - 33 * math.sin(math.radians(14.5)))


def test_scene_writes_leg_paths_and_report(tmp_path):
    import pandas

    from camgen.cli import main
    from camgen.scene import template_path

    assert main(["run", str(template_path("horse_leg")), "-o", str(tmp_path)]) == 0
    out = tmp_path / "horse_leg"
    report = json.loads((out / "report.json").read_text())
    leg = report["mechanisms"]["horse_leg"]
    for alpha in PAPER:
        figures = leg[f"alpha_{alpha:g}"]
        assert set(figures) >= set(KEYS) | {"max_pressure_angle_deg", "grashof_margin_mm"}
        frame = pandas.read_csv(out / f"leg_path_alpha_{alpha:g}.csv")  # the reader's defaults
        assert list(frame.columns) == ["theta1_deg", "x_mm", "y_mm", "pressure_angle_deg"]
        data = frame.to_numpy()
        assert data.shape == (3600, 4) and data[1, 0] == pytest.approx(0.1) and data[-1, 0] == pytest.approx(359.9)
        assert np.max(data[:, 2]) - LEG.ground_y == pytest.approx(figures["lift_mm"], abs=1e-6)
    sweep = leg["sweep"]
    assert [r["alpha1_deg"] for r in sweep][:3] == [10.0, 10.5, 11.0] and sweep[-1]["alpha1_deg"] == 19.0
    assert all(r["within_limit"] for r in sweep)  # below 45 deg from 10 to 19 deg
