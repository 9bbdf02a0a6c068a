"""Constant acceleration, trapezoidal acceleration, the SCCA family and the skewed (asymmetric)
modified sine / trapezoid (camgen.synthesis.laws_scca, built in camgen.synthesis.laws) against
outside numbers.

Outside references: Norton, *Design of Machinery*, 2nd ed., Table 8-3 (peak coefficients of the
named laws) and sec. 8.3, eq. 8.24 (the SCCA family's peak acceleration in closed form);
Rothbart, *Cam Design Handbook* (2004), sec. 3, eqs. 3.10-3.13 (the skewed modified trapezoid:
the peak velocity of the symmetric curve, the accelerations scaled by the halves' spans, the
displacement at the transition); closed forms derived by hand (noted at each test); 8th-order
central finite differences; left and right limits measured at every join; the independent,
long-standing implementations of the named laws in LAWS; the CLI run on scenes written here.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from camgen.cli import main
from camgen.synthesis.laws import (
    LAWS,
    MotionProgram,
    Segment,
    asymmetric_modified_sine,
    asymmetric_modified_trapezoid,
    scca_law,
)
from helpers import scene_toml

PI = math.pi
D = math.radians

# Norton, Design of Machinery, 2nd ed., Table 8-3: (Cv, Ca, Cj) of double-dwell rises
NORTON_TABLE_8_3 = {
    "modified_trapezoid": (2.000, 4.888, 61.43),
    "modified_sine": (1.760, 5.528, 69.47),
    "cycloidal": (2.000, 6.283, 39.48),
    "simple_harmonic": (1.571, 4.935, math.inf),
    "constant_acceleration": (2.000, 4.000, math.inf),
}
# Norton sec. 8.3 (SCCA family): the named laws as (b, c, d)
SCCA_MEMBERS = {
    "constant_acceleration": (0.0, 1.0, 0.0),
    "modified_trapezoid": (0.25, 0.5, 0.25),
    "simple_harmonic": (0.0, 0.0, 1.0),
    "modified_sine": (0.25, 0.0, 0.75),
    "cycloidal": (0.5, 0.0, 0.5),
}

# 8th-order central difference for a first derivative (offsets -4..4)
FD8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])


def fd(f, x, h):
    """d f / dx at x by the 8th-order central stencil (error ~ h^8 f^(9))."""
    return sum(c * f(x + k * h) for c, k in zip(FD8, range(-4, 5)) if c) / h


def constant_acceleration_written_out(tau):
    """Norton ch. 8, constant (parabolic) acceleration written out: S = 2 tau^2 (tau < 1/2), else 1 - 2 (1 - tau)^2."""
    up = tau < 0.5
    return (np.where(up, 2 * tau**2, 1 - 2 * (1 - tau) ** 2), np.where(up, 4 * tau, 4 * (1 - tau)), np.where(up, 4.0, -4.0),
            np.zeros_like(tau))


def scca_edges(b, c, d):
    """The SCCA zone edges (Norton sec. 8.3: widths b/2, c/2, d, c/2, b/2), zero-width zones dropped."""
    out, at = [], 0.0
    for w in (b / 2, c / 2, d, c / 2, b / 2):
        if w > 0:
            at += w
            out.append(at)
    return out[:-1]


#: every law of this module, with the breaks and continuity the formulas give them (written here
#: from the definitions: 1 acceleration jumps, 2 jerk jumps, 3 only beyond the jerk), and
#: against a dwell at the start and at the end
def _cases():
    cases = {
        "constant_acceleration": (LAWS["constant_acceleration"], 1, 1, {0.5: 1}),
        "trapezoidal": (LAWS["trapezoidal"], 2, 2, {1 / 8: 2, 3 / 8: 2, 5 / 8: 2, 7 / 8: 2}),
    }
    for b, c, d in ((0.2, 0.3, 0.5), (0.1, 0.6, 0.3), (0.0, 0.4, 0.6), (0.3, 0.7, 0.0), (0.35, 0.0, 0.65), (1.0, 0.0, 0.0)):
        internal = {}
        for t in scca_edges(b, c, d):
            internal[t] = 3
        if d == 0.0 and c > 0:  # +A meets -A in the middle
            internal[0.5] = 1
        if b == 1.0:  # the two sine ramps meet in the middle
            internal = {0.5: 1}
        start = 1 if b == 0.0 else 2  # b = 0: the constant (or cosine) acceleration starts at once
        cases[f"scca_{b}_{c}_{d}"] = (scca_law((b, c, d)), start, start, internal)
    for f in (0.3, 0.4, 0.5, 0.7):
        g = 1 - f
        skew = {} if f == 0.5 else {f: 2}  # the jerk steps at the transition unless the halves are equal
        cases[f"asymmetric_modified_sine_{f}"] = (asymmetric_modified_sine(f), 2, 2, {f / 4: 3, f + 3 * g / 4: 3, **skew})
        cases[f"asymmetric_modified_trapezoid_{f}"] = (asymmetric_modified_trapezoid(f), 2, 2,
                                                        {f / 4: 3, 3 * f / 4: 3, f + g / 4: 3, f + 3 * g / 4: 3, **skew})
    return cases


CASES = _cases()


# ------------------------------------------------------------------------------------------------
# peak coefficients
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(SCCA_MEMBERS))
def test_scca_members_peak_coefficients_are_nortons_table_8_3(name):
    """Norton, Design of Machinery, 2nd ed., Table 8-3 (to its printed digits), for the SCCA
    family's named members; constant acceleration also under its own name."""
    laws = [scca_law(SCCA_MEMBERS[name])] + ([LAWS["constant_acceleration"]] if name == "constant_acceleration" else [])
    for law in laws:
        for ours, theirs, label in zip((law.cv, law.ca, law.cj), NORTON_TABLE_8_3[name], ("Cv", "Ca", "Cj")):
            if math.isinf(theirs):
                assert math.isinf(ours), (label, ours)
            else:
                digits = 2 if theirs >= 10 else 3
                assert abs(ours - theirs) <= 0.5 * 10**-digits + 1e-12, (label, ours, theirs)


@pytest.mark.parametrize("b, d", [(0.25, 0.25), (0.25, 0.75), (0.5, 0.5), (0.2, 0.5), (0.1, 0.3), (0.4, 0.1), (0.05, 0.9)])
def test_scca_peak_coefficients_are_nortons_closed_forms(b, d):
    """Norton sec. 8.3, eq. 8.24: Ca = 4 pi^2 / ((pi^2 - 8)(b^2 - d^2) - 2 pi (pi - 2) b + pi^2);
    the peak velocity is the area under A up to mid-rise, Cv = Ca (b/pi + c/2 + d/pi); the jerk
    peaks on the steeper of the sine ramp (Ca pi / b) and the middle cosine (Ca pi / d) (by hand)."""
    c = 1 - b - d
    law = scca_law((b, c, d))
    ca = 4 * PI**2 / ((PI**2 - 8) * (b * b - d * d) - 2 * PI * (PI - 2) * b + PI**2)
    assert law.ca == pytest.approx(ca, rel=1e-12)
    assert law.cv == pytest.approx(ca * (b / PI + c / 2 + d / PI), rel=1e-12)
    assert law.cj == pytest.approx(ca * PI / min(b, d), rel=1e-11)


def test_trapezoidal_and_constant_acceleration_closed_forms():
    """By hand.  Constant acceleration: V(1/2) = 4 * 1/2 = 2, A = +-4.  Trapezoidal with ramps r =
    1/8: S(1/2) = A (5/192 + 12/192 + 1/192) = 3 A / 32 = 1/2 gives A = 16/3; V(1/2) = A (r/2 + (1/2 - 2r)
    + r/2) = 3 A / 8 = 2; J = A / r = 128/3 on every ramp (the middle ramp falls 2A over 2r)."""
    law = LAWS["trapezoidal"]
    assert (law.cv, law.ca, law.cj) == pytest.approx((2.0, 16 / 3, 128 / 3), rel=1e-12)
    law = LAWS["constant_acceleration"]
    assert (law.cv, law.ca) == pytest.approx((2.0, 4.0), rel=1e-14) and math.isinf(law.cj)


@pytest.mark.parametrize("symmetric, skewed", [("modified_trapezoid", asymmetric_modified_trapezoid),
                                               ("modified_sine", asymmetric_modified_sine)])
@pytest.mark.parametrize("f", [0.1, 0.3, 0.45, 0.5, 0.6, 0.8])
def test_skewed_laws_follow_rothbarts_relations(symmetric, skewed, f):
    """Rothbart, Cam Design Handbook, sec. 3, eqs. 3.10-3.13 (skewed modified trapezoid, p the
    ratio of the halves' spans): the peak velocity is the symmetric curve's; each half's peak
    acceleration is the symmetric one's times beta / (2 beta_i) (equal velocity areas); the follower is
    at h beta_1 / beta at the transition.  The jerk of a half stretched by 2 beta_i / beta is the
    symmetric one's divided by (2 beta_i / beta)^2 (by hand).  The symmetric values are Norton Table 8-3's."""
    law = skewed(f)
    cv, ca, cj = NORTON_TABLE_8_3[symmetric]
    short = min(f, 1 - f)
    assert abs(law.cv - cv) <= 0.5e-3
    assert law.ca == pytest.approx(ca / (2 * short), abs=0.5e-3 / (2 * short))
    assert law.cj == pytest.approx(cj / (4 * short**2), abs=0.5e-2 / (4 * short**2))
    s, v, a, _ = law.evaluate(np.array([f]))
    assert s[0] == pytest.approx(f, abs=1e-14) and v[0] == pytest.approx(law.cv, rel=1e-12) and abs(a[0]) < 1e-12
    # the two pulses' peaks, each at its own half (Rothbart eqs. 3.12, 3.13)
    tau = np.linspace(0, 1, 40001)
    acc = law.evaluate(tau)[2]
    assert acc[tau <= f].max() == pytest.approx(ca / (2 * f), abs=0.5e-3 / (2 * f))
    assert -acc[tau >= f].min() == pytest.approx(ca / (2 * (1 - f)), abs=0.5e-3 / (2 * (1 - f)))


# ------------------------------------------------------------------------------------------------
# derivatives and continuity
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(CASES))
def test_v_a_j_are_the_derivatives_of_s_inside_every_piece(name):
    """V, A, J against 8th-order central differences of S, V, A at 200 points inside each piece (the
    stencil kept inside the piece)."""
    law = CASES[name][0]
    h = 1e-4
    s0, s1 = law.evaluate(np.array([0.0, 1.0]))[0]
    assert s0 == pytest.approx(0.0, abs=1e-15) and s1 == pytest.approx(1.0, abs=1e-14)
    for piece in law.pieces:
        margin = 5 * h
        tau = np.linspace(piece.lo + margin, piece.hi - margin, 200)
        vals = law.evaluate(tau)
        for n in range(3):
            numeric = fd(lambda x, n=n: law.evaluate(x)[n], tau, h)
            scale = max(1.0, float(np.max(np.abs(law.evaluate(np.linspace(0, 1, 2001))[n + 1]))))
            assert np.max(np.abs(numeric - vals[n + 1])) <= 1e-8 * scale, (name, piece.lo, ["V", "A", "J"][n])


def one_sided(law, tau, delta=1e-9):
    """(left, right) limits of S, V, A, J at tau (a dwell at S = 0 left of 0, at S = 1 right of 1)."""
    left = [v[0] for v in law.evaluate(np.array([tau - delta]))] if tau > 0 else [0.0] * 4
    right = [v[0] for v in law.evaluate(np.array([tau + delta]))] if tau < 1 else [1.0, 0, 0, 0]
    return np.array(left), np.array(right)


def fourth_derivative_jump(law, tau):
    """|d4S/dtau4| right minus left at tau, each side's by an 8th-order central difference of J inside its piece."""
    h = 1e-5

    def jerk(x):
        return law.evaluate(x)[3]
    return abs(fd(jerk, np.array([tau + 5 * h]), h)[0] - fd(jerk, np.array([tau - 5 * h]), h)[0])


@pytest.mark.parametrize("name", sorted(CASES))
def test_continuity_at_every_join_measured_from_both_sides(name):
    """At both ends (against dwells) and at every join of the formulas: the left and right limits
    agree up to the continuity the formulas give, the next order jumps by a clear amount, and
    the law's declared breaks say the same (order 3 breaks: the 4th derivative jumps, measured)."""
    law, start, end, internal = CASES[name]
    scale = [1.0] + [p for p, _ in law.peaks]
    where = {0.0: start, 1.0: end, **internal}
    for tau, cont in where.items():
        left, right = one_sided(law, tau)
        jump = np.abs(right - left)
        for n in range(cont + 1):
            assert jump[n] <= 1e-6 * max(1.0, scale[n]), (name, tau, n, jump)
        if cont < 3:
            assert jump[cont + 1] >= 1e-3 * scale[cont + 1], (name, tau, cont, jump)
        elif 0 < tau < 1:
            assert fourth_derivative_jump(law, tau) >= 1e-3 * scale[3], (name, tau)
    declared = sorted((round(b.tau, 12), b.continuity) for b in law.breaks)
    assert declared == sorted((round(t, 12), c) for t, c in internal.items()), (name, declared)
    # and nowhere else: inside the pieces every quantity is smooth (no jump between neighbours)
    tau = np.linspace(0, 1, 100001)
    steps = np.abs(np.diff(law.evaluate(tau)[3]))
    mid = 0.5 * (tau[1:] + tau[:-1])
    away = np.min(np.abs(mid[:, None] - np.array(list(where))[None, :]), axis=1) > 1e-4
    assert np.max(steps[away]) <= 0.01 * scale[3]


def test_zero_width_join_of_the_cycloid_member_is_no_break():
    """SCCA (1/2, 0, 1/2): the first ramp and the middle cosine are the same sine (no break declared,
    and none measured up to the 4th derivative)."""
    law = scca_law((0.5, 0.0, 0.5))
    assert law.breaks == ()
    for tau in (0.25, 0.75):
        left, right = one_sided(law, tau)
        assert np.max(np.abs(right - left)) <= 1e-6 * 40
        assert fourth_derivative_jump(law, tau) <= 1e-4 * 40


# ------------------------------------------------------------------------------------------------
# special cases
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(SCCA_MEMBERS))
def test_scca_special_cases_are_the_named_laws(name):
    """S, V, A, J of the SCCA member equal the named law's (their own, older implementation in
    LAWS; constant acceleration also written out here) on a grid, to rounding."""
    member = scca_law(SCCA_MEMBERS[name])
    tau = np.linspace(0.0, 1.0, 4001)
    ours = member.evaluate(tau)
    references = [LAWS[name].evaluate(tau)]
    if name == "constant_acceleration":
        references.append(constant_acceleration_written_out(tau))
    for theirs in references:
        for n in range(4):
            scale = max(1.0, float(np.max(np.abs(theirs[n]))))
            if name == "constant_acceleration" and n == 2:  # at tau = 1/2 one takes +4, the other may take -4
                keep = np.abs(tau - 0.5) > 1e-12
                assert np.max(np.abs(ours[n][keep] - theirs[n][keep])) <= 1e-12 * scale
                continue
            assert np.max(np.abs(ours[n] - theirs[n])) <= 1e-12 * scale, (name, n)


@pytest.mark.parametrize("symmetric, skewed", [("modified_trapezoid", asymmetric_modified_trapezoid),
                                               ("modified_sine", asymmetric_modified_sine)])
def test_skewed_law_at_one_half_is_the_symmetric_law(symmetric, skewed):
    tau = np.linspace(0.0, 1.0, 4001)
    ours, theirs = skewed(0.5).evaluate(tau), LAWS[symmetric].evaluate(tau)
    for n in range(4):
        assert np.max(np.abs(ours[n] - theirs[n])) <= 1e-12 * max(1.0, float(np.max(np.abs(theirs[n]))))


def test_a_skewed_return_is_the_time_reversed_rise_in_a_program():
    """A return of the skewed law runs the rise backwards: s(theta) = L (1 - S(1 - tau))."""
    f, span, lift = 0.3, D(150), 12.0
    program = MotionProgram([Segment("dwell", D(60)), Segment("asymmetric_modified_sine", span, lift, accel_fraction=f),
                             Segment("asymmetric_modified_sine", span, -lift, accel_fraction=f)])
    tau = np.linspace(0, 1, 501)
    rise = asymmetric_modified_sine(f).evaluate(1 - tau)
    s, v, a, j = program(D(60) + span + tau * span)
    assert np.max(np.abs(s - lift * rise[0])) <= 1e-12 * lift
    assert np.max(np.abs(v + lift * rise[1] / span)) <= 1e-11 * lift
    assert np.max(np.abs(a - lift * rise[2] / span**2)) <= 1e-10 * lift


# ------------------------------------------------------------------------------------------------
# scenes: the keys, and bad values refused
# ------------------------------------------------------------------------------------------------
def scene(first: dict, formats=("points", "html")) -> dict:
    segs = [{"span_deg": 120.0, "lift_mm": 12.0, **first}, {"law": "dwell", "span_deg": 60.0},
            {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -12.0}, {"law": "dwell", "span_deg": 60.0}]
    return {"output": {"formats": list(formats)},
            "cams": {"c": {"kind": "motion_law", "base_radius_mm": 45.0, "roller_radius_mm": 8.0, "segments": segs}}}


def run_cli(tmp_path, data: dict, name: str = "s"):
    path = tmp_path / f"{name}.toml"
    path.write_text(scene_toml(data))
    out = tmp_path / f"out_{name}"
    return main(["run", str(path), "-o", str(out), "--quiet"]), out


def points(out) -> np.ndarray:
    (csv,) = out.rglob("c_points.csv")
    return np.loadtxt(csv, delimiter=",", skiprows=1)


def polar_radius(pts: np.ndarray, n: int = 3600) -> np.ndarray:
    """The profile's distance from the cam centre (mm) at n polar angles, interpolated."""
    phi = np.arctan2(pts[:, 1], pts[:, 0])
    order = np.argsort(phi)
    grid = np.linspace(-PI, PI, n, endpoint=False)
    return np.interp(grid, phi[order], np.hypot(pts[:, 0], pts[:, 1])[order], period=2 * PI)


def test_scene_scca_cycloid_member_cuts_the_cycloidal_cam_and_the_keys_change_the_profile(tmp_path):
    """The profile of scca = [0.5, 0, 0.5] is the cycloidal one (to the file's 1e-9 mm); changing
    scca or accel_fraction changes the profile (each key does what it documents), and the report
    gives the segment's parameters."""
    code, out = run_cli(tmp_path, scene({"law": "cycloidal"}), "cyc")
    assert code == 0
    reference = points(out)
    code, out = run_cli(tmp_path, scene({"law": "scca", "scca": [0.5, 0.0, 0.5]}), "scca_cyc")
    assert code == 0
    assert np.max(np.abs(points(out) - reference)) <= 2e-9
    report = json.loads(next(out.rglob("report.json")).read_text())
    assert report["cams"]["c"]["figures"]["segments"][0]["scca"] == [0.5, 0.0, 0.5]
    assert "b 0.5, c 0, d 0.5 (sine ramps, constant, middle cosine)" in next(out.rglob("report.html")).read_text()
    profiles = []
    for k, first in enumerate(({"law": "scca", "scca": [0.25, 0.5, 0.25]}, {"law": "scca", "scca": [0.25, 0.0, 0.75]},
                               {"law": "asymmetric_modified_trapezoid", "accel_fraction": 0.4},
                               {"law": "asymmetric_modified_trapezoid", "accel_fraction": 0.3})):
        code, out = run_cli(tmp_path, scene(first), f"k{k}")
        assert code == 0
        if "accel_fraction" in first:
            shown = f"positive acceleration over {first['accel_fraction']:g} of the span"
            assert shown in next(out.rglob("report.html")).read_text()
        profiles.append(points(out))
    polar = [polar_radius(p) for p in profiles]
    assert np.max(np.abs(polar[0] - polar[1])) > 1e-3
    assert np.max(np.abs(polar[2] - polar[3])) > 1e-3


BAD = {
    "scca sum": ({"law": "scca", "scca": [0.2, 0.3, 0.6]}, "cams.c.segments[0].scca", "b + c + d = 1"),
    "scca length": ({"law": "scca", "scca": [0.5, 0.5]}, "cams.c.segments[0].scca", "3 to 3 numbers"),
    "scca negative": ({"law": "scca", "scca": [-0.2, 0.7, 0.5]}, "cams.c.segments[0].scca[0]", "0 <= x <= 1"),
    "scca missing": ({"law": "scca"}, "cams.c.segments[0].scca", "for an scca segment"),
    "scca on cycloidal": ({"law": "cycloidal", "scca": [0.5, 0.0, 0.5]}, "cams.c.segments[0].scca", "only for scca"),
    "fraction range": ({"law": "asymmetric_modified_sine", "accel_fraction": 0.99}, "cams.c.segments[0].accel_fraction",
                       "0.05 <= x <= 0.95"),
    "fraction missing": ({"law": "asymmetric_modified_trapezoid"}, "cams.c.segments[0].accel_fraction",
                         "asymmetric_modified_trapezoid segment"),
    "fraction on trapezoidal": ({"law": "trapezoidal", "accel_fraction": 0.3}, "cams.c.segments[0].accel_fraction",
                                "only for asymmetric_modified_sine or asymmetric_modified_trapezoid"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_parameters_exit_2_with_one_line_naming_the_key(case, tmp_path, capsys):
    first, key, why = BAD[case]
    code, out = run_cli(tmp_path, scene(first))
    assert code == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1, err
    assert f"'{key}'" in err and why in err, err
    assert not out.exists() or not any(out.rglob("*"))


# ------------------------------------------------------------------------------------------------
# the exported cams ride the new laws (as test_disk_cams.py rides every older law)
# ------------------------------------------------------------------------------------------------
#: (law, options, span deg, lift sign): every new law, rises and returns, over one turn
RIDE_PROGRAM = [("scca", {"scca": [0.2, 0.3, 0.5]}, 60.0, 1), ("asymmetric_modified_sine", {"accel_fraction": 0.3}, 60.0, 1),
                ("dwell", {}, 20.0, 0), ("trapezoidal", {}, 60.0, -1), ("constant_acceleration", {}, 60.0, -1),
                ("asymmetric_modified_trapezoid", {"accel_fraction": 0.4}, 50.0, 1),
                ("asymmetric_modified_trapezoid", {"accel_fraction": 0.7}, 50.0, -1)]


@pytest.mark.parametrize("name", ["roller", "roller_offset", "flat", "osc_roller"])
def test_exported_cam_rides_the_new_laws(name, tmp_path):
    """<= 1e-6 mm (rad) riding the DXF's exact B-splines (read back by ezdxf and scipy) against the
    program of the new laws built from the library (test_disk_cams.py's ride)."""
    from pathlib import Path

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene
    from test_disk_cams import EXACT_TOL, FOLLOWERS, bspline_contour, follower_spec, oscillating, ride_angles, ride_error, size_of

    osc = oscillating(name)
    key, size = ("swing_deg" if osc else "lift_mm"), size_of(name)
    segs = [{"law": law, "span_deg": span, **extra, **({key: sign * size} if sign else {})} for law, extra, span, sign in RIDE_PROGRAM]
    data = {"output": {"formats": ["dxf"], "dxf_splines": "bspline"},
            "cams": {"c": {**FOLLOWERS[name], "rotation": "ccw", "kind": "motion_law", "segments": segs}}}
    parsed = parse_scene(data, "s", base_dir=Path(tmp_path))
    result = execute(parsed, plan_run(parsed))
    assert not [c.name for _, c in result.failed_checks() if c.blocks_manufacture]
    amount = D(size) if osc else size
    motion = MotionProgram([Segment(law, D(span), sign * amount if sign else 0.0,
                                    scca=extra.get("scca"), accel_fraction=extra.get("accel_fraction"))
                            for law, extra, span, sign in RIDE_PROGRAM], unit="rad" if osc else "mm")
    cam = bspline_contour(result.files["c.dxf"])
    error = ride_error(follower_spec(name, "ccw"), cam, ride_angles(motion, 720), motion)
    assert np.max(error) <= EXACT_TOL
