"""VDI 2143 (issue 26 items 2 and 5): the laws' characteristic values, the motion tasks of a
program's segments, report.json's and report.html's VDI table, and the law's acceleration
harmonics per cam.

Where the expected numbers come from:

* C_Mdyn = max |V A|: the issue's independent computation (cycloidal 8.16, 3-4-5 6.69, modified
  sine 5.46), the cycloid's closed form ``2 pi max (1 - cos x) sin x = 3 sqrt(3) pi / 2`` (at
  ``x = 2 pi / 3``), and a brute-force maximum over 2,000,001 points of the 3-4-5 law written out
  here (``V = 30 t^2 (1 - t)^2``, ``A = 60 t (1 - t)(1 - 2 t)``).
* Cv, Ca, Cj: Norton, *Design of Machinery*, Table 8-3 ("factors for peak velocity and
  acceleration of some cam functions"), as printed (three or four digits; his 4-5-6-7 Ca 7.526
  and simple harmonic Ca 4.945 are 1.7e-3 and 2.1e-3 above the exact 7.5132 and pi^2/2).
* Motion tasks: the ends of each segment written out (a cycloid starts and ends at rest, a
  simple harmonic rise with zero velocity and acceleration +-pi^2/2, a polynomial's ends are its
  conditions).
* Harmonics: the amplitude of ``s'' = (L/2) cos(theta)`` (a simple harmonic rise and return over
  half a turn each) is ``L/2`` at harmonic 1 and 0 above (the piecewise-linear interpolant of its
  samples, step h: exactly ``(L/2) sinc^2(h/2)``); and numpy's FFT of the plate cam's acceleration,
  written out, at 65,536 cam angles, within the interpolation's bound ``(1/pi) int |a - I_h a|``
  measured on that grid.
"""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import numpy as np
import pytest

from camgen.synthesis import laws
from camgen.synthesis.harmonics import ACCELERATION_HARMONICS
from camgen.synthesis.vdi2143 import TASK_NAMES, VDI_NAMES, program_values, segment_values

TWO_PI = 2.0 * math.pi


def _rise(name: str):
    return segment_values(laws.Segment(name, 1.3, 7.0))


# --------------------------------------------------------------------------------------------
# characteristic values
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name, published", [("cycloidal", 8.16), ("poly345", 6.69), ("modified_sine", 5.46)])
def test_c_mdyn_against_the_issues_independent_values(name, published):
    assert round(_rise(name).c_mdyn, 2) == published
    ret = segment_values(laws.Segment(name, 0.7, -3.0))  # a return: the time-reversed rise, the same value
    assert round(ret.c_mdyn, 2) == published


def test_c_mdyn_of_the_cycloid_in_closed_form():
    x = 2.0 * math.pi / 3.0  # d/dx (1 - cos x) sin x = cos x - cos 2x = 0
    closed = TWO_PI * (1.0 - math.cos(x)) * math.sin(x)
    assert closed == pytest.approx(3.0 * math.sqrt(3.0) * math.pi / 2.0, rel=1e-15)
    assert _rise("cycloidal").c_mdyn == pytest.approx(closed, rel=1e-12)


def test_c_mdyn_of_the_345_against_brute_force():
    t = np.linspace(0.0, 1.0, 2_000_001)
    v = 30.0 * t**2 * (1.0 - t) ** 2
    a = 60.0 * t * (1.0 - t) * (1.0 - 2.0 * t)
    assert _rise("poly345").c_mdyn == pytest.approx(float(np.max(np.abs(v * a))), rel=1e-10)


def test_c_mdyn_of_a_polynomial_segment_is_normalised_by_its_lift():
    # a 3-4-5 in physical units (lift 4 mm over 0.9 rad, rest to rest) is the 3-4-5
    seg = laws.Segment("polynomial", 0.9, start=(1.0, 0.0, 0.0), end=(5.0, 0.0, 0.0))
    values = segment_values(seg)
    assert values.c_mdyn == pytest.approx(_rise("poly345").c_mdyn, rel=1e-12)
    assert (values.cv, values.ca, values.cj) == pytest.approx((15.0 / 8.0, 10.0 / math.sqrt(3.0), 60.0), rel=1e-12)
    assert values.vdi_name is not None and values.vdi_name.german == "Polynom 5. Grades"


# Norton, Design of Machinery, Table 8-3: Cv, Ca, Cj as printed; tolerance: his rounding
NORTON_8_3 = {
    "cycloidal": (2.000, 6.283, 40.0),
    "modified_trapezoid": (2.000, 4.888, 61.0),
    "modified_sine": (1.760, 5.528, 69.0),
    "poly345": (1.875, 5.777, 60.0),
    "poly4567": (2.188, 7.526, 52.0),
}


@pytest.mark.parametrize("name", sorted(NORTON_8_3))
def test_peak_coefficients_against_nortons_table_8_3(name):
    cv, ca, cj = NORTON_8_3[name]
    values = _rise(name)
    assert values.cv == pytest.approx(cv, rel=1e-3)
    assert values.ca == pytest.approx(ca, rel=2.5e-3)
    assert values.cj == pytest.approx(cj, rel=1.5e-2)  # Cj printed to two digits (39.5 -> 40, 61.4 -> 61, 69.5 -> 69)


def test_simple_harmonic_against_nortons_table_8_3():
    values = _rise("simple_harmonic")
    assert values.cv == pytest.approx(1.571, rel=1e-3)
    assert values.ca == pytest.approx(4.945, rel=2.5e-3)  # exact pi^2 / 2 = 4.9348
    assert values.task == "U-U"  # Norton's infinite Cj between dwells: the acceleration is not zero at the ends


# --------------------------------------------------------------------------------------------
# motion tasks
# --------------------------------------------------------------------------------------------
def _program() -> tuple[laws.MotionProgram, list[str]]:
    """A program with a segment of every motion task (v per rad, a per rad^2) and the tasks its
    ends give, written out."""
    span = TWO_PI / 11.0
    segs = [
        (laws.Segment("cycloidal", span, 10.0), "R-R"),  # V(0) = 1 - cos 0 = 0, A(0) = 2 pi sin 0 = 0; the same at 1
        (laws.Segment("dwell", span), "R"),
        (laws.Segment("double_harmonic", span, 5.0), "R-U"),  # V(1) = 0, A(1) = -pi^2 (Norton's single-dwell rise)
        (laws.Segment("double_harmonic", span, -5.0), "U-R"),  # the time-reversed rise
        (laws.Segment("simple_harmonic", span, -2.0), "U-U"),  # A = (pi^2/2) cos(pi t): +-pi^2/2 at the ends, V = 0
        (laws.Segment("constant_velocity", span, 2.0), "G-G"),  # V = 1, A = 0 throughout
        (laws.Segment("polynomial", span, start=(10.0, 3.0, 0.0), end=(12.0, 0.0, 0.0)), "G-R"),
        (laws.Segment("polynomial", span, start=(12.0, 0.0, 0.0), end=(10.0, -3.0, 0.0)), "R-G"),
        (laws.Segment("polynomial", span, start=(10.0, 0.0, 4.0), end=(8.0, -3.0, 0.0)), "U-G"),
        (laws.Segment("polynomial", span, start=(8.0, -3.0, 0.0), end=(5.0, 0.0, 2.0)), "G-U"),
        (laws.Segment("polynomial", span, start=(5.0, 1.0, 1.0), end=(0.0, -1.0, 2.0)), "B-B"),
    ]
    return laws.MotionProgram([s for s, _ in segs]), [t for _, t in segs]


def test_task_types_of_a_program_with_every_kind_of_segment():
    program, expected = _program()
    rows = program_values(program)
    assert [r.task for r in rows] == expected
    assert {t for task in expected for t in task.split("-")} == set(TASK_NAMES)  # R, G, U and B all met


def test_vdi_names_alongside_the_textbook_names():
    program, _ = _program()
    rows = program_values(program)
    assert rows[0].vdi_name == VDI_NAMES["cycloidal"] and "geneigte Sinuslinie" in VDI_NAMES["cycloidal"].german
    assert VDI_NAMES["modified_sine"].german == "modifizierte Sinuslinie"
    assert rows[1].vdi_name is not None and rows[1].vdi_name.german == "Rast"
    assert rows[2].vdi_name is None  # the double harmonic has no VDI 2143 name we know
    assert rows[6].vdi_name is not None and rows[6].vdi_name.german == "Polynom 5. Grades"  # 6 conditions: degree 5


# --------------------------------------------------------------------------------------------
# report.json and report.html
# --------------------------------------------------------------------------------------------
PLATE = {
    "output": {"formats": ["html"]},
    "cams": {"c": {"kind": "motion_law", "base_radius_mm": 40.0, "follower": "roller", "roller_radius_mm": 10.0, "rpm": 300.0,
                   "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                                {"law": "poly345", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]}},
}


def _run(scene: dict) -> tuple[dict, str]:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    parsed = parse_scene(copy.deepcopy(scene), "s")
    result = execute(parsed, plan_run(parsed))
    return json.loads(result.files["report.json"]), result.files["report.html"]


@pytest.fixture(scope="module")
def plate_run():
    return _run(PLATE)


def test_report_json_has_the_vdi_rows_per_segment(plate_run):
    report, page = plate_run
    rows = report["cams"]["c"]["figures"]["vdi2143"]["segments"]
    assert [r["law"] for r in rows] == ["cycloidal", "dwell", "poly345", "dwell"]
    assert [r["task"] for r in rows] == ["R-R", "R", "R-R", "R"]
    cyc, _, p345, _ = rows
    assert (cyc["Cv"], cyc["Ca"], cyc["Cj"], cyc["C_Mdyn"]) == pytest.approx(
        (2.0, TWO_PI, TWO_PI**2, 3.0 * math.sqrt(3.0) * math.pi / 2.0), rel=1e-12)
    assert (p345["Cv"], p345["Ca"], p345["Cj"]) == pytest.approx((15.0 / 8.0, 10.0 / math.sqrt(3.0), 60.0), rel=1e-12)
    assert cyc["vdi_name"] == "geneigte Sinuslinie (Sinoide)" and p345["vdi_name"] == "Polynom 5. Grades"
    # the human report: the table, with the same names and tasks
    table = page[page.index("<table class='vdi'>"):]
    table = table[: table.index("</table>")]
    assert "geneigte Sinuslinie" in table and "Polynom 5. Grades" in table and table.count("R-R") == 2
    assert "8.1621" in table  # C_Mdyn to the page's six digits


# --------------------------------------------------------------------------------------------
# harmonics
# --------------------------------------------------------------------------------------------
def test_harmonic_one_of_a_harmonic_rise_and_return_in_closed_form():
    lift, rpm = 10.0, 120.0
    scene = copy.deepcopy(PLATE)
    scene["cams"]["c"].update(rpm=rpm, segments=[{"law": "simple_harmonic", "span_deg": 180.0, "lift_mm": lift},
                                                 {"law": "simple_harmonic", "span_deg": 180.0, "lift_mm": -lift}])
    report, _ = _run(scene)
    block = report["cams"]["c"]["figures"]["acceleration_harmonics"]
    amplitudes = np.array(block["amplitude_mm_per_rad2"])
    assert amplitudes.size == block["harmonics"] == ACCELERATION_HARMONICS
    # s = (L/2)(1 - cos theta): s'' = (L/2) cos theta, one harmonic
    h = TWO_PI / block["samples"]
    sinc2 = (math.sin(h / 2.0) / (h / 2.0)) ** 2
    assert amplitudes[0] == pytest.approx(lift / 2.0 * sinc2, rel=1e-10)
    assert amplitudes[0] == pytest.approx(lift / 2.0, rel=h**2 / 12.0)
    assert np.all(amplitudes[1:] <= 1e-9 * lift)
    omega = TWO_PI * rpm / 60.0
    assert block["amplitude_m_per_s2"][0] == pytest.approx(lift / 2.0 * sinc2 * omega**2 * 1e-3, rel=1e-10)


def _plate_acceleration(theta: np.ndarray) -> np.ndarray:
    """s'' (mm/rad^2) of PLATE's program, written out: cycloidal rise 20 mm over 120 deg,
    dwell, 3-4-5 return over 120 deg, dwell."""
    beta, h = math.radians(120.0), 20.0
    a = np.zeros_like(theta)
    up = theta < beta
    a[up] = TWO_PI * h / beta**2 * np.sin(TWO_PI * theta[up] / beta)
    down = (theta >= math.radians(180.0)) & (theta < math.radians(300.0))
    t = (theta[down] - math.radians(180.0)) / beta
    a[down] = -h / beta**2 * (60.0 * t - 180.0 * t**2 + 120.0 * t**3)
    return a


def test_harmonics_against_numpys_fft(plate_run):
    report, _ = plate_run
    block = report["cams"]["c"]["figures"]["acceleration_harmonics"]
    got = np.array(block["amplitude_mm_per_rad2"])
    m = 1 << 16
    theta = TWO_PI * np.arange(m) / m
    coefficients = np.fft.rfft(_plate_acceleration(theta)) / m
    expected = 2.0 * np.abs(coefficients[1: ACCELERATION_HARMONICS + 1])
    # the interpolant of the samples at the report's cam angles against the law: (1/pi) int |a - I_h a| on the fine grid
    samples = block["samples"]
    coarse = TWO_PI * np.arange(samples) / samples
    interpolated = np.interp(theta, coarse, _plate_acceleration(coarse), period=TWO_PI)
    bound = float(np.mean(np.abs(_plate_acceleration(theta) - interpolated))) * TWO_PI / math.pi
    assert np.all(np.abs(got - expected) <= bound + 1e-9 * float(expected.max())), (np.abs(got - expected).max(), bound)
    assert bound < 1e-4 * float(expected.max())  # the bound is tight: the harmonics are good to 1e-4 of the largest


# --------------------------------------------------------------------------------------------
# the descriptions kept across programs (camgen.synthesis.vdi2143 ``_law_values``)
# --------------------------------------------------------------------------------------------
def test_segments_with_other_lifts_in_a_row_keep_nortons_values_and_the_fresh_ones():
    """A sweep of lifts: the cycloid's Cv, Ca, Cj are Norton's (Table 8-3: 2.000, 6.283, 40) at every
    lift, rise or return; every segment's description, kept or not, is the one made with nothing kept;
    a polynomial's (its own law per segment) differs with its conditions."""
    from camgen.synthesis import vdi2143

    span = TWO_PI / 3.0
    segments = [laws.Segment("cycloidal", span, lift) for lift in (7.0, 12.5, -3.0, 7.0, 0.25)]
    segments += [laws.Segment("poly345", span, lift) for lift in (4.0, -9.0)] + [laws.Segment("dwell", span)]
    segments += [laws.Segment("polynomial", span, start=(0.0, v, 0.0), end=(2.0, 0.0, 0.0)) for v in (0.0, 3.0, 0.0)]
    segments += [laws.Segment("double_harmonic", span, lift) for lift in (5.0, -5.0, 6.0)]
    vdi2143._law_values.cache_clear()
    rows = [segment_values(seg) for seg in segments]
    assert vdi2143._law_values.cache_info().hits == 4  # the cycloid's rises 12.5, 7 and 0.25 after 7; the harmonic's 6 after 5
    for row in rows[:5]:
        assert (row.cv, row.ca, row.cj) == pytest.approx((2.000, 6.283, 39.48), rel=1e-3)
        assert row.task == "R-R"
    assert rows[7].task == "R" and rows[7].cv == 0.0
    assert rows[9].task == "G-R" and rows[8].task == "R-R" and rows[10].task == "R-R"
    assert [r.task for r in rows[11:]] == ["R-U", "U-R", "R-U"]  # Norton's single-dwell rise, time-reversed for the return
    for seg, row in zip(segments, rows):
        vdi2143._law_values.cache_clear()  # nothing kept
        assert segment_values(seg) == row
