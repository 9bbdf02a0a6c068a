"""Every least or largest value camgen quotes is one it tried (issue "Trust, round 2", item 12).

Each hint is used: the scene with the quoted value passes the check it is about, and a value
just beyond fails, where it is a bound.  The pass/fail verdicts are also computed here from the
textbook geometry, written out on its own: Norton's pressure angle of a centred translating roller
(*Design of Machinery*, ch. 8: tan(alpha) = s' / (Rp + s)) and, for an oscillating roller, the
angle between the pitch curve's normal and the roller centre's velocity (perpendicular to the arm).

The case of the issue: an oscillating roller that fails its pressure angle was told "set base
radius to at least 43.935 mm" while 60, 65 and 70 mm all failed: the pressure angle of an
oscillating follower is not monotonic in the base radius (it falls, then rises again as the cam
grows towards the pivot), so the base radii that pass make an interval, bounded on both sides.
"""
from __future__ import annotations

import math
import re
import tomllib
from fractions import Fraction

import numpy as np
import pytest

from camgen.scene import parse_scene, template_path
from test_dynamics_scenes import rise_return

D = math.radians
#: The pressure-angle limit that makes the oscillating template fail at 30 mm (deg).
LIMIT = 27.0


def _scene(name: str, **changes) -> dict:
    """A bundled template as a dict, its one cam's keys changed (None removes a key)."""
    scene = tomllib.loads(template_path(name).read_text(encoding="utf-8"))
    cam = next(iter(scene["cams"].values()))
    for key, value in changes.items():
        if value is None:
            cam.pop(key, None)
        else:
            cam[key] = value
    scene["output"]["formats"] = ["dxf"]
    return scene


def _checks(scene: dict) -> dict:
    """{check name: CheckResult} of the scene's one cam, by the pipeline (no files)."""
    from camgen.pipeline import Plan, compute

    parsed = parse_scene(scene, "hint", base_dir=template_path("default").parent)
    result = compute(parsed, Plan((), frozenset(), full_report=False))
    return {c.name: c for c in result.cams[0].checks}


def _law_and_follower(scene: dict):
    parsed = parse_scene(scene, "hint", base_dir=template_path("default").parent)
    params = parsed.cams[0].params
    return params.law, params.follower


# --------------------------------------------------------------------------------------------
# Oscillating roller: an interval
# --------------------------------------------------------------------------------------------
def oscillating_pressure_deg(scene: dict, base: float, step_deg: float = 0.01) -> float:
    """Largest pressure angle (deg) of the scene's oscillating roller at base radius ``base``.

    Roller centre C = O + L u(g0 + tau psi) (O the pivot, L the arm, g0 where C is on the prime
    circle and a positive swing moves it outwards); seen from the cam, turning by sigma theta, the
    pitch curve's tangent in the fixed frame is T = dC/dtheta - sigma J C (J: a quarter turn);
    C moves along J u; the pressure angle is the angle between the pitch normal and that motion,
    asin(|T . J u| / |T|).  Cam angles every ``step_deg``, the swing law's own values."""
    from test_followers import rest_arm_angle

    law, f = _law_and_follower(scene)
    f = type(f)(f.kind, base, motion=f.motion, roller_radius=f.roller_radius, pivot=f.pivot, arm_length=f.arm_length,
                lift_turn="ccw" if f.tau > 0 else "cw", rotation="ccw" if f.sigma > 0 else "cw")
    theta = np.radians(np.arange(0.0, 360.0, step_deg))
    psi, dpsi = (np.asarray(v) for v in law(theta)[:2])
    g = rest_arm_angle(f) + f.tau * psi
    u = np.stack([np.cos(g), np.sin(g)], axis=-1)
    ju = np.stack([-u[:, 1], u[:, 0]], axis=-1)
    c = np.asarray(f.pivot) + f.arm_length * u
    jc = np.stack([-c[:, 1], c[:, 0]], axis=-1)
    tangent = f.arm_length * f.tau * dpsi[:, None] * ju - f.sigma * jc
    along = np.abs(np.sum(tangent * ju, axis=1)) / np.hypot(*tangent.T)
    return float(np.degrees(np.max(np.arcsin(np.clip(along, 0.0, 1.0)))))


def test_the_oscillating_hint_is_an_interval_whose_ends_pass(tmp_path):
    scene = _scene("oscillating_roller", base_radius_mm=30.0, pressure_angle_limit_deg=LIMIT)
    for base in (40.0, 30.0):  # the formula here is camgen's geometry
        ours = oscillating_pressure_deg(scene, base)
        theirs = _checks(_scene("oscillating_roller", base_radius_mm=base))["pressure_angle"].value
        assert ours == pytest.approx(theirs, abs=1e-3)
    checks = _checks(scene)
    assert checks["pressure_angle"].failed
    advice = checks["min_base_radius"]
    low, high = (float(v) for v in re.search(r"set base_radius_mm between ([\d.]+) and ([\d.]+) ", advice.note).groups())
    assert advice.value == low and high > low + 5.0
    for base in (low, high, 0.5 * (low + high)):  # used: every check of the hint passes
        used = _checks(_scene("oscillating_roller", base_radius_mm=base, pressure_angle_limit_deg=LIMIT))
        assert used["pressure_angle"].passed and used["undercut"].passed and "min_base_radius" not in used
        assert oscillating_pressure_deg(scene, base) <= LIMIT + 1e-4
    for base in (low - 0.002, high + 0.002, 60.0, 65.0, 70.0):  # just beyond each end, and the radii
        assert oscillating_pressure_deg(scene, base) > LIMIT
        assert _checks(_scene("oscillating_roller", base_radius_mm=base, pressure_angle_limit_deg=LIMIT))["pressure_angle"].failed


def test_sizing_of_an_oscillating_roller_is_the_low_end():
    """sizing = "base_radius" builds the smallest passing base radius: the hint's low end."""
    hinted = _checks(_scene("oscillating_roller", base_radius_mm=30.0, pressure_angle_limit_deg=LIMIT))["min_base_radius"].value
    sized = _checks(_scene("oscillating_roller", base_radius_mm=None, sizing="base_radius", pressure_angle_limit_deg=LIMIT))
    assert sized["sizing"].value == pytest.approx(hinted, abs=1e-3) and sized["pressure_angle"].passed


# --------------------------------------------------------------------------------------------
# Translating roller: at least
# --------------------------------------------------------------------------------------------
_RISE = [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
         {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]


def _translating(base: float) -> dict:
    return {"output": {"formats": ["dxf"]}, "cams": {"c": {"kind": "motion_law", "base_radius_mm": base, "roller_radius_mm": 10.0,
                                                           "segments": _RISE}}}


def _norton_pressure_deg(base: float) -> float:
    """Centred translating roller: tan(alpha) = |s'| / (Rb + r + s) (Norton ch. 8), cycloidal written out."""
    theta = np.radians(np.arange(0.0, 360.0, 0.005))
    s, v, _ = rise_return(theta, "cycloidal", 20.0, D(120), D(60), D(120))
    return float(np.degrees(np.max(np.arctan(np.abs(v) / (base + 10.0 + s)))))


def test_the_translating_hint_is_a_least_value_that_passes():
    checks = _checks(_translating(10.0))
    assert checks["pressure_angle"].failed
    note = checks["min_base_radius"].note
    least = float(re.search(r"increase base_radius_mm to at least ([\d.]+) ", note).group(1))
    assert checks["min_base_radius"].value == least
    assert _norton_pressure_deg(least) <= 30.0 + 1e-6 < _norton_pressure_deg(least - 0.002)
    assert _checks(_translating(least))["pressure_angle"].passed
    assert _checks(_translating(least - 0.002))["pressure_angle"].failed


# --------------------------------------------------------------------------------------------
# Machining: the least step_down_mm
# --------------------------------------------------------------------------------------------
def _passes(depth: str, step: str) -> int:
    """Depth passes, counted exactly on the decimals (Fraction): ceil(depth / step)."""
    return max(1, math.ceil(Fraction(depth) / Fraction(step)))


@pytest.mark.parametrize("thickness, breakthrough", [("40", "0.1"), ("20", "0.5"), ("8", "0.3"), ("12.7", "0.25"), ("100", "1"),
                                                     ("3.3", "0"), ("55.5", "0.05")])
def test_the_least_step_down_quoted_is_accepted(thickness, breakthrough):
    """The refusal of too many passes (by the scene reader) quotes a least step_down_mm; that value
    is accepted and one unit of its last digit less is refused (40.1 mm once gave 0.0401 mm, itself
    refused)."""
    from camgen.errors import ParameterError
    from camgen.export.gcode import MAX_PASSES

    def scene(step: str):
        s = _scene("oscillating_roller", thickness_mm=float(thickness))
        s["output"]["formats"] = ["ngc"]
        s["machining"] = {"tool_diameter_mm": 6.0, "step_down_mm": float(step), "breakthrough_mm": float(breakthrough)}
        return parse_scene(s, "hint")

    depth = str(Fraction(thickness) + Fraction(breakthrough))
    with pytest.raises(ParameterError, match="machining.step_down_mm") as info:
        scene("0.001")
    least = re.search(r">= ([\d.e-]+) mm", info.value.valid).group(1)
    scene(least)  # accepted
    assert _passes(depth, least) <= MAX_PASSES
    lower = Fraction(least) - Fraction(10) ** (math.floor(math.log10(float(least))) - 2)  # one unit of the 3rd digit less
    assert _passes(depth, str(float(lower))) > MAX_PASSES  # the quoted value is the least of its three digits
    with pytest.raises(ParameterError):
        scene(str(float(lower)))


# --------------------------------------------------------------------------------------------
# Rounded in the right direction
# --------------------------------------------------------------------------------------------
def test_the_steerable_radius_is_rounded_up():
    """Paper 004's device (D = 50, d = 30, L = 77, r_b = 75.5 mm): right turns need R > D + d L / r_b
    = 80.59602649... mm; a path of any radius above the quoted value must steer."""
    from camgen.synthesis.trajectory import steerable_paths

    quoted = float(re.search(r"radius > ([\d.]+) mm", steerable_paths(30.0, 77.0, 50.0, 75.5)).group(1))
    exact = Fraction(50) + Fraction(30 * 77) / Fraction("75.5")
    assert Fraction(quoted) >= exact and quoted - float(exact) < 1e-4


def test_the_follower_radius_hint_of_a_concave_contact_is_rounded_down():
    """A concave profile of radius 12.3456789 mm takes a follower of radius up to that (combined
    curvature 1/rho_cam + 1/rho_follower >= 0); the hint quotes 12.3456, which touches."""
    from camgen import dynamics as dy
    from camgen.errors import GeometryError

    mat = dy.ContactMaterial(width=10.0)
    with pytest.raises(GeometryError) as info:
        dy.hertz_line_stress(100.0, -12.3456789, 20.0, mat)
    hinted = float(re.search(r"at most ([\d.]+) mm", str(info.value)).group(1))
    assert hinted <= 12.3456789 and 12.3456789 - hinted < 1e-4
    assert np.isfinite(dy.hertz_line_stress(100.0, -12.3456789, hinted, mat))


def test_the_gcode_chord_tolerance_quoted_is_accepted():
    """"output.chord_tol_mm >= 8.5e-06 mm with ngc": that tolerance with 6 decimals is accepted."""
    from camgen.errors import ParameterError

    scene = _scene("oscillating_roller")
    scene["output"] = {"formats": ["ngc"], "chord_tol_mm": 1e-6}
    scene["machining"] = {"tool_diameter_mm": 6.0}
    with pytest.raises(ParameterError, match="output.chord_tol_mm") as info:
        parse_scene(scene, "hint")
    least = float(re.search(r">= ([\d.e-]+) mm", info.value.valid).group(1))
    scene["output"]["chord_tol_mm"] = least
    scene["machining"]["decimals"] = 6
    parsed = parse_scene(scene, "hint")  # accepted
    assert parsed.machining.chord_tol == least and parsed.machining.decimals == 6  # the final spec carries the tolerance
    scene["output"]["chord_tol_mm"] = least - 10.0 ** (math.floor(math.log10(least)) - 1)  # a unit of its 2nd digit less: refused
    with pytest.raises(ParameterError, match="output.chord_tol_mm"):
        parse_scene(scene, "hint")
