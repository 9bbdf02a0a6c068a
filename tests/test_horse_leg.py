"""Horse-robot single leg (paper 000, Sections 3-6)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from camgen.errors import GeometryError
from camgen.mechanisms import horse_leg as hl
from helpers import tree  # noqa: F401  (fixture)

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


# --------------------------------------------------------------------------------------------
# Where the foot walks on the ground line; the sweep's step count (issue "Trust, round 2", item 10)
# --------------------------------------------------------------------------------------------
def _crossings(y: np.ndarray, ground: float) -> int:
    """How often the closed path of heights ``y`` passes the line y = ground (written here)."""
    side = np.sign(y - ground)
    side[side == 0] = -1.0  # on the line counts as not above
    return int(np.count_nonzero(side != np.roll(side, 1)))


def _leg_scene(tmp_path, capsys, inclinations, ground=None, positions=None, sweep=None):
    """Exit status and stderr of ``camgen check`` of the horse-leg template with these settings."""
    from camgen.cli import main
    from camgen.scene import template_path

    text = template_path("horse_leg").read_text(encoding="utf-8")
    lines = []
    for line in text.splitlines():
        key = line.split("=")[0].strip()
        if key == "inclinations_deg":
            line = f"inclinations_deg = [{', '.join(repr(float(a)) for a in inclinations)}]"
        elif key == "ground_y_mm" and ground is not None:
            line = f"ground_y_mm = {float(ground)!r}"
        elif key == "positions" and positions is not None:
            line = f"positions = {positions}"
        elif key == "sweep_deg" and sweep is not None:
            line = f"sweep_deg = [{', '.join(sweep)}]"
        lines.append(line)
    path = tmp_path / "leg.toml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    code = main(["check", str(path)])
    return code, capsys.readouterr().err


def test_the_foot_walks_on_the_default_ground_up_to_19_717_deg(tmp_path, capsys):
    """The leg assembles up to 20.111 deg, but from about 19.7174 deg its foot path's lowest point
    is above the default ground line (-2074 mm): no stance.  The range quoted, rounded inwards,
    is used at both ends; 0.002 deg beyond it (the refinement's tolerance plus the rounding) the
    path does not reach the line and camgen says so, naming the key and the range."""
    ((lo, hi),) = hl.gait_range(LEG, 3600)
    shown = (math.ceil(math.degrees(lo) * 1000) / 1000, math.floor(math.degrees(hi) * 1000) / 1000)
    assert shown == (9.382, 19.717)
    theta1 = hl.cycle(3600)
    for alpha, count in ((9.382, 2), (19.717, 2), (19.719, 0), (20.111, 0)):
        assert _crossings(hl.solve_leg(LEG, math.radians(alpha), theta1).w[:, 1], LEG.ground_y) == count
    code, err = _leg_scene(tmp_path, capsys, [9.382, 19.717])
    assert code in (0, 1) and "error" not in err, err  # 9.382 deg fails its pressure angle: exit 1
    for alpha in (19.719, 19.762, 20.111):
        code, err = _leg_scene(tmp_path, capsys, [12.5, alpha])
        assert code == 2 and err.count("\n") == 1, err
        assert "parameter 'mechanisms.horse_leg.inclinations_deg[1]'" in err and "9.382 to 19.717 deg" in err
        assert "lowest point is above the line" in err and "assembles with cams 'stride_length' and 'stride_height' from 9.382 " \
            "to 20.111 deg" in err


def test_the_ground_lines_quoted_for_an_inclination_are_crossed_twice(tmp_path, capsys):
    """At 19.762 deg (refused on the default line) the error lists the ground lines that would
    serve there, rounded inwards to 0.1 mm: each end of each is used, and the path crosses it twice."""
    import re

    code, err = _leg_scene(tmp_path, capsys, [19.762], positions=720)
    assert code == 2
    quoted = re.search(r"set ground_y_mm to (.*?) for alpha1 = 19.762 deg", err).group(1)
    ends = [float(v) for pair in re.findall(r"(-?[\d.]+) to (-?[\d.]+) mm", quoted) for v in pair]
    y = hl.solve_leg(LEG, math.radians(19.762), hl.cycle(720)).w[:, 1]
    assert ends[0] == math.ceil(y.min() * 10) / 10  # from just above the lowest foot point
    for ground in ends:
        assert _crossings(y, ground) == 2, ground
        code, err = _leg_scene(tmp_path, capsys, [19.762], ground=ground, positions=720)
        assert code in (0, 1) and "error" not in err, (ground, err)


def test_ground_lines_against_a_brute_force_count():
    """A wavy closed path y = sin t + 0.4 sin 3t (two dips near its top): the intervals of ground
    lines crossed exactly twice, against a count at 20001 lines."""
    t = np.linspace(0.0, 2 * math.pi, 2000, endpoint=False)
    y = np.sin(t) + 0.4 * np.sin(3 * t)
    intervals = hl.ground_lines(y)
    assert len(intervals) >= 2  # the dips make bands crossed four times
    for g in np.linspace(y.min() - 0.1, y.max() + 0.1, 20001):
        inside = any(low <= g < high for low, high in intervals)
        assert inside == (_crossings(y, g) == 2), g


@pytest.mark.parametrize("sweep", [("0.0", "20.0", "0.1"), ("10.0", "13.8", "0.019"), ("12.0", "16.6", "0.023"),
                                   ("-87.9", "-84.1", "0.019"), ("9.95", "19.95", "0.05"), ("-90.0", "90.0", "0.9")])
def test_a_sweep_of_exactly_200_steps_is_accepted_and_201_refused(sweep):
    """[from, to, step] written in decimals: 200 steps exactly (Fraction arithmetic here), though
    (to - from) / step in binary is a hair above 200 for three of them (13.8 - 10 over 0.019:
    200.00000000000003); one step more is refused."""
    from fractions import Fraction

    from camgen.errors import ParameterError
    from camgen.jobs.horse_leg import sweep_values
    from camgen.scene import parse_scene

    start, stop, step = (Fraction(v) for v in sweep)
    assert (stop - start) / step == 200

    def scene(values):
        return {"cams": {"s": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0},
                         "h": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 220.0, "c_mm": 10.0}},
                "mechanisms": {"horse_leg": {"stride_cam": "s", "height_cam": "h", "sweep_deg": [float(Fraction(v)) for v in values]}}}

    spec = parse_scene(scene(sweep), "leg").mechanisms[0].settings
    values = np.degrees(sweep_values(spec.sweep_deg))
    assert values.size == 201 and values[-1] == pytest.approx(float(stop), abs=1e-9) and values[-1] <= float(stop) + 1e-12
    longer = (sweep[0], str(stop + step), sweep[2])
    if stop + step <= 90:
        with pytest.raises(ParameterError, match=r"mechanisms.horse_leg.sweep_deg.*at most 200 steps \(201 steps\)"):
            parse_scene(scene(longer), "leg")


def test_the_readme_quotes_the_walking_range(tree):
    """README's Limits bullet on the horse leg: the assembly range, the walking range on the
    default ground line and the lowest foot point at the assembly's end, as computed here."""
    ((a_lo, a_hi),) = hl.assembly_range(LEG, 3600)
    ((w_lo, w_hi),) = hl.gait_range(LEG, 3600)
    text = " ".join((tree / "README.md").read_text(encoding="utf-8").split())
    inward = lambda lo, hi: (f"{math.ceil(math.degrees(lo) * 1000) / 1000:g}", f"{math.floor(math.degrees(hi) * 1000) / 1000:g}")  # noqa: E731
    assert "assembles for `alpha1` from {} to {} deg".format(*inward(a_lo, a_hi)) in text
    assert f"only up to {inward(w_lo, w_hi)[1]} deg" in text and inward(w_lo, w_hi)[0] == inward(a_lo, a_hi)[0]
    lowest = hl.solve_leg(LEG, math.radians(20.111), hl.cycle(3600)).w[:, 1].min()
    assert f"({lowest:.1f} mm at 20.111 deg)" in text and lowest > LEG.ground_y
