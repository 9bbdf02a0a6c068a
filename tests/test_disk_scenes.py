"""Disk cams at scene level: the keys (each changes what it documents, or is refused), sizing
against brute force, the follower table against the law in time, the checks against textbook
closed forms (Norton, Design of Machinery, ch. 8), and what the report and the DXF draw.

Every expected number is computed here: the cycloidal and harmonic laws written out, the
polar-curve formulas of a centred roller's pitch curve, Norton's pressure angle of an offset
roller, Rb + s + s'' of a flat face, and brute-force searches over base radius and offset.
"""
from __future__ import annotations

import copy
import io
import json
import math
import re

import numpy as np
import pytest

from camgen.cli import main
from helpers import scene_toml

D = math.radians
TWO_PI = 2.0 * math.pi


def cycloidal_program(theta: np.ndarray, h: float = 20.0, rise: float = D(120), dwell: float = D(60), ret: float = D(120)):
    """s, s', s'', s''' (mm, per rad^k) of cycloidal rise, dwell, cycloidal return, dwell, written out."""
    theta = np.mod(theta, TWO_PI)
    up = theta < rise
    top = (theta >= rise) & (theta < rise + dwell)
    down = (theta >= rise + dwell) & (theta < rise + dwell + ret)
    tau = np.where(up, theta / rise, np.where(down, (theta - rise - dwell) / ret, 0.0))
    beta = np.where(up, rise, ret)
    sign = np.where(up, 1.0, np.where(down, -1.0, 0.0))
    w = TWO_PI * tau
    s = np.where(up, h * (tau - np.sin(w) / TWO_PI), np.where(top, h, np.where(down, h - h * (tau - np.sin(w) / TWO_PI), 0.0)))
    v = sign * h / beta * (1 - np.cos(w))
    a = sign * h / beta**2 * TWO_PI * np.sin(w)
    j = sign * h / beta**3 * TWO_PI**2 * np.cos(w)
    return s, v, a, j


def plate(**changes) -> dict:
    """A scene (dict) of one translating roller cam with the cycloidal program; ``changes`` update the cam table."""
    cam = {"kind": "motion_law", "base_radius_mm": 40.0, "roller_radius_mm": 10.0, "rpm": 300.0,
           "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 60.0},
                        {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -20.0}, {"law": "dwell", "span_deg": 60.0}]}
    cam.update(changes)
    return {"output": {"formats": ["dxf", "ngc", "follower", "points"], "dxf_construction": True},  # PITCH and ZERO drawn
            "cams": {"c": {k: v for k, v in cam.items() if v is not None}}}


def oscillating(**changes) -> dict:
    scene = plate(follower_motion="oscillating", pivot_x_mm=90.0, pivot_y_mm=50.0, arm_length_mm=80.0, roller_radius_mm=8.0)
    scene["cams"]["c"]["segments"] = [{"law": "cycloidal", "span_deg": 100.0, "swing_deg": 15.0}, {"law": "dwell", "span_deg": 60.0},
                                      {"law": "poly4567", "span_deg": 120.0, "swing_deg": -15.0}, {"law": "dwell", "span_deg": 80.0}]
    scene["cams"]["c"].update(changes)
    scene["cams"]["c"] = {k: v for k, v in scene["cams"]["c"].items() if v is not None}
    return scene


def _oscillating_flat(face_offset: float) -> dict:
    scene = oscillating(follower="flat", roller_radius_mm=None, arm_length_mm=None, base_radius_mm=50.0, pivot_x_mm=130.0,
                        pivot_y_mm=60.0, face_offset_mm=face_offset)
    return _segment(_segment(scene, 0, swing_deg=8.0), 2, swing_deg=-8.0)


def run(scene: dict, tmp_path=None) -> tuple[dict, dict]:
    """Files (name -> text or bytes) and the report of a scene run by the pipeline in memory."""
    from pathlib import Path

    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    parsed = parse_scene(scene, "s", base_dir=Path(tmp_path) if tmp_path is not None else None)
    result = execute(parsed, plan_run(parsed))
    return result.files, json.loads(result.files["report.json"])


def checks_of(report: dict, cam: str = "c") -> dict:
    return {c["name"]: c for c in report["cams"][cam]["checks"]}


# --------------------------------------------------------------------------------------------
# Refused keys and values: one line naming the key and why, exit 2, nothing written
# --------------------------------------------------------------------------------------------
def _segment(scene: dict, index: int, **changes) -> dict:
    scene = copy.deepcopy(scene)
    seg = scene["cams"]["c"]["segments"][index]
    seg.update(changes)
    scene["cams"]["c"]["segments"][index] = {k: v for k, v in seg.items() if v is not None}
    return scene


REFUSED = {
    "no base radius": (plate(base_radius_mm=None), "cams.c.base_radius_mm", "required unless sizing"),
    "base radius with sizing": (plate(sizing="base_radius"), "cams.c.base_radius_mm", "computes the base radius"),
    "roller radius of a flat face": (plate(follower="flat"), "cams.c.roller_radius_mm", "only with follower = 'roller'"),
    "offset of an oscillating arm": (oscillating(follower_offset_mm=3.0), "cams.c.follower_offset_mm", "only with follower_motion"),
    "pivot of a translating follower": (plate(pivot_x_mm=90.0), "cams.c.pivot_x_mm", "only with follower_motion"),
    "arm of a flat face": (oscillating(follower="flat", roller_radius_mm=None), "cams.c.arm_length_mm", "only with follower"),
    "face offset of a roller": (oscillating(face_offset_mm=5.0), "cams.c.face_offset_mm", "only with follower"),
    "swing turn of a translating follower": (plate(swing_turn="cw"), "cams.c.swing_turn", "only with follower_motion"),
    "face length of a roller": (plate(face_half_length_mm=20.0), "cams.c.face_half_length_mm", "only with follower"),
    "no pivot": (oscillating(pivot_y_mm=None), "cams.c.pivot_y_mm", "required for an oscillating"),
    "no arm": (oscillating(arm_length_mm=None), "cams.c.arm_length_mm", "required for an oscillating"),
    "lift of an arm": (_segment(oscillating(), 0, swing_deg=None, lift_mm=5.0), "cams.c.segments[0].lift_mm", "swing_deg for an oscillating"),
    "swing of a translating follower": (_segment(plate(), 0, lift_mm=None, swing_deg=5.0), "cams.c.segments[0].swing_deg",
                                        "lift_mm for a translating"),
    "blend of a cycloidal": (_segment(plate(), 0, blend=0.2), "cams.c.segments[0].blend", "only for constant_velocity"),
    "start of a cycloidal": (_segment(plate(), 0, start=[0.0, 0.0, 0.0]), "cams.c.segments[0].start", "only for polynomial"),
    "polynomial without end": (_segment(plate(), 0, law="polynomial", lift_mm=None, start=[0.0, 0.0, 0.0]),
                               "cams.c.segments[0].end", "at both ends"),
    "velocity jump under a roller": (_segment(plate(), 0, law="constant_velocity"), "cams.c.segments[0].law", "velocity jumps"),
    "lift in a dwell": (_segment(plate(), 1, lift_mm=3.0), "cams.c.segments[1].lift_mm", "for a dwell"),
    "no lift in a rise": (_segment(plate(), 0, lift_mm=None), "cams.c.segments[0].lift_mm", "a non-zero lift_mm"),
    "spans not a turn": (_segment(plate(), 3, span_deg=50.0), "cams.c.segments", "360 deg"),
    "no return": (_segment(plate(), 2, lift_mm=-15.0), "cams.c.segments[3]", "displacement jumps"),
    "offset sized for a flat face": (plate(follower="flat", roller_radius_mm=None, base_radius_mm=None, sizing="base_radius_and_offset"),
                                     "cams.c.sizing", "translating roller or knife"),
    "offset given and sized": (plate(base_radius_mm=None, sizing="base_radius_and_offset", follower_offset_mm=3.0),
                               "cams.c.follower_offset_mm", "computes the offset"),
    "offset beyond the prime circle": (plate(follower_offset_mm=50.0), "cams.c.follower_offset_mm", "prime radius = 50"),
    "pivot inside the prime circle": (oscillating(pivot_x_mm=20.0, pivot_y_mm=10.0), "cams.c.pivot_x_mm/pivot_y_mm", "farther than"),
    "follower table without rpm": (plate(rpm=None), "cams.c.rpm", "cam speed"),
    "fit tolerance": (plate(fit_tol_mm=0.0), "cams.c.fit_tol_mm", "1e-10"),
    "lift table file": ({"output": {"formats": ["dxf"]}, "cams": {"c": {"kind": "lift_table", "lift_table_csv": "missing.csv",
                                                                       "base_radius_mm": 40.0}}}, "cams.c.lift_table_csv", "readable"),
}


@pytest.mark.parametrize("case", REFUSED)
def test_keys_where_they_change_nothing_or_wrong_values_are_refused(case, tmp_path, capsys):
    scene, key, why = REFUSED[case]
    path = tmp_path / "bad.toml"
    path.write_text(scene_toml(scene))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("camgen: error: ") and err.count("\n") == 1
    assert f"'{key}'" in err and why in err, err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").rglob("*"))


# --------------------------------------------------------------------------------------------
# Every key changes what it documents
# --------------------------------------------------------------------------------------------
def _profile(files: dict) -> str:
    """The PROFILE layer's entities of the DXF (the drawing's other layers aside)."""
    import ezdxf

    doc = ezdxf.read(io.StringIO(files["c.dxf"]))
    return repr([(e.dxftype(), sorted((k, str(v)) for k, v in e.dxfattribs().items() if k not in ("handle", "owner")))
                 for e in doc.modelspace() if e.dxf.layer == "PROFILE"])


def _layer(files: dict, layer: str) -> str:
    import ezdxf

    doc = ezdxf.read(io.StringIO(files["c.dxf"]))
    return repr([(e.dxftype(), sorted((k, str(v)) for k, v in e.dxfattribs().items() if k not in ("handle", "owner")))
                 for e in doc.modelspace() if e.dxf.layer == layer])


EFFECTS = {
    # key: (base scene, changed scene, what must change, what must not)
    "base_radius_mm": (plate(), plate(base_radius_mm=45.0), ("profile", "ngc"), ()),
    "follower": (plate(), plate(follower="knife", roller_radius_mm=None), ("profile", "ngc"), ()),
    "roller_radius_mm": (plate(), plate(roller_radius_mm=12.0), ("profile", "pitch"), ()),
    "follower_offset_mm (roller)": (plate(), plate(follower_offset_mm=6.0), ("profile", "ngc"), ()),
    "follower_offset_mm (flat)": (plate(follower="flat", roller_radius_mm=None, base_radius_mm=60.0),
                                  plate(follower="flat", roller_radius_mm=None, base_radius_mm=60.0, follower_offset_mm=4.0),
                                  ("face_length",), ("profile", "ngc")),
    "follower_motion": (plate(), oscillating(), ("profile", "ngc"), ()),
    "pivot_x_mm": (oscillating(), oscillating(pivot_x_mm=95.0), ("profile",), ()),
    "pivot_y_mm": (oscillating(), oscillating(pivot_y_mm=45.0), ("profile",), ()),
    "arm_length_mm": (oscillating(), oscillating(arm_length_mm=85.0), ("profile",), ()),
    "face_offset_mm": (_oscillating_flat(10.0), _oscillating_flat(15.0), ("profile",), ()),
    "swing_turn": (oscillating(), oscillating(swing_turn="cw", pivot_x_mm=-90.0), ("profile",), ()),
    "rotation": (plate(follower_offset_mm=5.0), plate(follower_offset_mm=5.0, rotation="cw"), ("profile", "zero"), ()),
    "face_half_length_mm": (plate(follower="flat", roller_radius_mm=None, base_radius_mm=60.0),
                            plate(follower="flat", roller_radius_mm=None, base_radius_mm=60.0, face_half_length_mm=12.0),
                            ("face_length",), ("profile", "ngc")),
    "fit_tol_mm": (plate(), plate(fit_tol_mm=1e-5), ("profile", "pieces"), ()),
    "sizing": (plate(), plate(base_radius_mm=None, sizing="base_radius"), ("profile", "base_radius"), ()),
    "rpm": (plate(), plate(rpm=600.0), ("follower",), ("profile", "ngc")),
    "segments.law": (plate(), _segment(plate(), 0, law="poly345"), ("profile",), ()),
    "segments.span_deg": (plate(), _segment(_segment(plate(), 0, span_deg=110.0), 1, span_deg=70.0), ("profile",), ()),
    "segments.lift_mm": (plate(), _segment(_segment(plate(), 0, lift_mm=18.0), 2, lift_mm=-18.0), ("profile",), ()),
    "segments.swing_deg": (oscillating(), _segment(_segment(oscillating(), 0, swing_deg=12.0), 2, swing_deg=-12.0), ("profile",), ()),
    "segments.blend": (_segment(plate(), 0, law="constant_velocity", blend=0.2), _segment(plate(), 0, law="constant_velocity", blend=0.3),
                       ("profile",), ()),
    "segments.start/end": (_segment(plate(), 0, law="polynomial", lift_mm=None, start=[0.0, 0.0, 0.0], end=[20.0, 0.0, 0.0]),
                           _segment(plate(), 0, law="polynomial", lift_mm=None, start=[0.0, 0.0, 0.0], end=[20.0, 0.0, 0.0, 0.0]),
                           ("profile",), ()),
}


def _aspects(files: dict, report: dict) -> dict:
    cam = report["cams"]["c"]
    checks = {c["name"]: c for c in cam["checks"]}
    return {"profile": _profile(files), "pitch": _layer(files, "PITCH"), "zero": _layer(files, "ZERO"), "ngc": files.get("c.ngc"),
            "follower": files.get("c_follower.csv"), "face_length": json.dumps(checks.get("face_length")),
            "pieces": cam["figures"].get("profile_pieces"), "base_radius": cam["figures"]["base_radius_mm"]}


@pytest.mark.parametrize("key", EFFECTS)
def test_every_key_changes_what_it_documents(key):
    before, after, changed, kept = EFFECTS[key]
    a, b = (_aspects(*run(scene)) for scene in (before, after))
    for aspect in changed:
        assert a[aspect] != b[aspect], (key, aspect)
    for aspect in kept:
        assert a[aspect] == b[aspect], (key, aspect)


def test_fit_tol_is_met_and_lift_table_file_changes_the_profile(tmp_path):
    for tol in (1e-5, 1e-8):
        report = run(plate(fit_tol_mm=tol))[1]
        assert report["cams"]["c"]["figures"]["fit_error_mm"] <= tol == report["cams"]["c"]["figures"]["fit_tol_mm"]
    angle = np.arange(0, 360, 10.0)
    profiles = []
    for k, amplitude in enumerate((8.0, 10.0)):
        (tmp_path / f"t{k}.csv").write_text("angle_deg,lift_mm\n" + "".join(f"{a:g},{amplitude * (1 - math.cos(D(a))):.9f}\n" for a in angle))
        scene = {"output": {"formats": ["dxf"]}, "cams": {"c": {"kind": "lift_table", "lift_table_csv": f"t{k}.csv", "base_radius_mm": 40.0}}}
        profiles.append(_profile(run(scene, tmp_path)[0]))
    assert profiles[0] != profiles[1]


# --------------------------------------------------------------------------------------------
# Checks against textbook closed forms
# --------------------------------------------------------------------------------------------
FINE = np.linspace(0.0, TWO_PI, 720001)


def test_pressure_angle_of_an_offset_roller_is_nortons():
    """Norton, ch. 8: tan(alpha) = (s' - e) / (sqrt(Rp^2 - e^2) + s) for a counter-clockwise cam (offset on +x)."""
    e, rp = 8.0, 50.0
    checks = checks_of(run(plate(follower_offset_mm=e))[1])
    s, v, _, _ = cycloidal_program(FINE)
    alpha = np.degrees(np.arctan((v - e) / (math.sqrt(rp**2 - e**2) + s)))
    assert checks["pressure_angle"]["value"] == pytest.approx(np.max(np.abs(alpha)), rel=1e-5)
    assert checks["pressure_angle"]["limit"] == pytest.approx(30.0) and checks["pressure_angle"]["status"] == "pass"
    worst = FINE[np.argmax(np.abs(alpha))]
    assert checks["pressure_angle"]["where_deg"][0] == pytest.approx(math.degrees(worst), abs=0.06)


def test_roller_undercut_value_is_the_pitch_curves_polar_radius_of_curvature():
    """Centred roller: the pitch curve is the polar curve r = Rp + s; its radius of curvature
    (r^2 + r'^2)^1.5 / (r^2 + 2 r'^2 - r r'') (textbook polar formula), smallest convex value."""
    checks = checks_of(run(plate(base_radius_mm=30.0, roller_radius_mm=12.0))[1])
    s, v, a, _ = cycloidal_program(FINE)
    r = 42.0 + s
    denom = r**2 + 2 * v**2 - r * a
    rho = (r**2 + v**2) ** 1.5 / denom
    assert checks["undercut"]["value"] == pytest.approx(np.min(rho[denom > 0]), rel=1e-5)
    assert checks["undercut"]["limit"] == 12.0 and checks["undercut"]["status"] == "pass"
    # the profile's smallest convex radius is the pitch's less the roller
    assert checks["min_convex_radius"]["value"] == pytest.approx(np.min(rho[denom > 0]) - 12.0, rel=1e-5)


def test_flat_face_checks_are_rb_plus_s_plus_s2_and_the_face_reach_is_s_prime():
    """Norton, ch. 8: a translating flat face's cam has radius of curvature Rb + s + s''; the contact
    lies s' from the follower axis (so the face must reach max |s'| each way)."""
    report = run(plate(follower="flat", roller_radius_mm=None, base_radius_mm=60.0, face_half_length_mm=15.0))[1]
    checks = checks_of(report)
    s, v, a, _ = cycloidal_program(FINE)
    assert checks["undercut"]["value"] == pytest.approx(np.min(60.0 + s + a), rel=1e-6)
    assert checks["face_length"]["value"] == pytest.approx(np.max(np.abs(v)), rel=1e-6)
    assert checks["face_length"]["status"] == ("pass" if np.max(np.abs(v)) <= 15.0 else "fail")
    assert checks["pressure_angle"]["value"] == 0.0
    assert checks["min_convex_radius"]["value"] == pytest.approx(np.min(60.0 + s + a), rel=1e-6)


def test_continuity_and_law_joins_where_the_harmonic_acceleration_steps():
    """A simple harmonic rise after a dwell starts with s'' = pi^2 L / (2 beta^2) (Norton, SHM): the
    acceleration jumps at both its ends, the profile is G1 exactly there and G2 elsewhere."""
    scene = _segment(_segment(plate(), 0, law="simple_harmonic"), 2, law="simple_harmonic")
    checks = checks_of(run(scene)[1])
    jump = math.pi**2 * 20.0 / (2 * D(120) ** 2)
    assert checks["continuity"]["value"] == "G1" and checks["continuity"]["status"] == "pass"
    assert sorted(checks["continuity"]["where_deg"]) == pytest.approx([0.0, 120.0, 180.0, 300.0], abs=1e-6)
    joins = checks["law_joins"]
    assert joins["value"] == 4 and sorted(joins["where_deg"]) == pytest.approx([0.0, 120.0, 180.0, 300.0], abs=1e-6)
    found = [float(x) for x in re.findall(r"acceleration jumps by (-?[\d.e+-]+) mm/rad\^2", joins["note"])]
    assert np.allclose(np.abs(found), jump, rtol=1e-5) and len(found) == 4
    cycloidal = checks_of(run(plate())[1])  # cycloidal: zero acceleration at its ends, the profile is G2
    assert cycloidal["continuity"]["value"] == "G2" and cycloidal["continuity"]["where_deg"] == []


# --------------------------------------------------------------------------------------------
# Sizing against brute force
# --------------------------------------------------------------------------------------------
def _centred_roller_feasible(bases: np.ndarray, roller: float, limit: float) -> np.ndarray:
    """Pressure angle atan(|s'| / (Rp + s)) <= limit and the pitch curve's convex radius > roller."""
    s, v, a, _ = (x[None, :] for x in cycloidal_program(np.linspace(0.0, TWO_PI, 14400, endpoint=False)))
    r = bases[:, None] + roller + s
    alpha = np.arctan(np.abs(v) / r)
    denom = r**2 + 2 * v**2 - r * a
    rho = np.where(denom > 0, (r**2 + v**2) ** 1.5 / np.where(denom > 0, denom, 1.0), np.inf)
    return (alpha.max(axis=1) <= limit) & (rho.min(axis=1) > roller)


def _first_feasible(feasible, lo: float, hi: float, step: float = 0.01) -> float:
    """The first feasible base radius on a grid of ``step`` mm: a 0.5 mm scan, then ``step`` over the
    interval before the first feasible point of the scan."""
    coarse = np.arange(lo, hi, 0.5)
    k = int(np.argmax(feasible(coarse)))
    fine = np.arange(coarse[max(k - 1, 0)], coarse[k] + step, step)
    return float(fine[np.argmax(feasible(fine))])


def test_sizing_the_base_radius_against_a_brute_force_search():
    limit = 25.0
    report = run(plate(base_radius_mm=None, sizing="base_radius", pressure_angle_limit_deg=limit))[1]
    figures, checks = report["cams"]["c"]["figures"], checks_of(report)
    found = figures["sizing"]["base_radius_mm"]
    assert figures["base_radius_mm"] == found and checks["sizing"]["value"] == found
    brute = _first_feasible(lambda b: _centred_roller_feasible(b, 10.0, D(limit)), 1.0, 80.0)
    assert brute - 0.01 <= found <= brute + 0.002  # grid step 0.01; camgen rounds up to 0.001
    assert checks["pressure_angle"]["status"] == "pass" and checks["pressure_angle"]["value"] >= limit - 0.01


def test_sizing_base_radius_and_offset_against_nortons_bound_over_offsets():
    """Translating roller on an asymmetric program (a fast rise, a slow return): for each offset e
    the pressure-angle limit alone needs d0 >= max(|s' - e| / tan(limit) - s) and
    Rb = sqrt(d0^2 + e^2) - r (Norton's formula solved); the smallest over a grid of offsets is
    what sizing finds (its undercut check passes: the pressure angle binds)."""
    limit = 25.0
    program = [{"law": "cycloidal", "span_deg": 90.0, "lift_mm": 20.0}, {"law": "dwell", "span_deg": 90.0},
               {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -20.0}]
    report = run(plate(base_radius_mm=None, sizing="base_radius_and_offset", pressure_angle_limit_deg=limit, segments=program))[1]
    sizing = report["cams"]["c"]["figures"]["sizing"]
    s, v, _, _ = cycloidal_program(np.linspace(0.0, TWO_PI, 14400, endpoint=False), rise=D(90), dwell=D(90), ret=D(180))
    offsets = np.arange(-20.0, 20.0, 0.02)
    d0 = np.max((np.abs(v[None, :] - offsets[:, None])) / math.tan(D(limit)) - s[None, :], axis=1)
    base = np.hypot(d0, offsets) - 10.0
    k = int(np.argmin(base))
    assert base[k] - 0.01 <= sizing["base_radius_mm"] <= base[k] + 0.01
    assert abs(sizing["offset_mm"] - offsets[k]) <= 0.5  # the optimum is flat in e
    assert offsets[k] > 2.0  # a real offset: on +x, where it lowers the rise's pressure angle (ccw cam)
    assert checks_of(report)["undercut"]["status"] == "pass"


def test_a_pressure_angle_failure_says_which_base_radius_passes():
    limit = 25.0
    report = run(plate(base_radius_mm=15.0, pressure_angle_limit_deg=limit))[1]
    checks = checks_of(report)
    assert checks["pressure_angle"]["status"] == "fail"
    advice = checks["min_base_radius"]
    brute = _first_feasible(lambda b: _centred_roller_feasible(b, 10.0, D(limit)), 1.0, 80.0)
    assert brute - 0.01 <= advice["value"] <= brute + 0.002
    assert f"increase base_radius_mm to at least {advice['value']:.3f}" in advice["note"]


def test_sizing_holds_concave_radii_to_the_named_tool():
    """A knife's cam is its tip's path: with a 16 mm tool its smallest concave radius of curvature
    (polar-curve formula of r = Rb + s) must reach 8 mm; without a tool only the pressure angle binds."""
    scene = plate(follower="knife", roller_radius_mm=None, base_radius_mm=None, sizing="base_radius", pressure_angle_limit_deg=60.0)
    free = run(scene)[1]["cams"]["c"]["figures"]["sizing"]["base_radius_mm"]
    scene["machining"] = {"tool_diameter_mm": 16.0}
    report = run(scene)[1]
    found = report["cams"]["c"]["figures"]["sizing"]["base_radius_mm"]
    s, v, a, _ = cycloidal_program(np.linspace(0.0, TWO_PI, 14400, endpoint=False))

    def concave_min(rb: float) -> float:
        r = rb + s
        denom = r**2 + 2 * v**2 - r * a
        return float(np.min(np.where(denom < 0, -(r**2 + v**2) ** 1.5 / np.where(denom < 0, denom, -1.0), np.inf)))

    def feasible(bases: np.ndarray) -> np.ndarray:
        return np.array([concave_min(b) >= 8.0 and np.max(np.degrees(np.arctan(np.abs(v) / (b + s)))) <= 60.0 for b in bases])

    brute = _first_feasible(feasible, 1.0, 60.0)
    assert found > free + 1.0  # the tool binds
    assert brute - 0.01 <= found <= brute + 0.002
    assert checks_of(report)["min_concave_radius"]["status"] == "pass"


# --------------------------------------------------------------------------------------------
# The follower table (<cam>_follower.csv) against the law in time
# --------------------------------------------------------------------------------------------
def _table(text: str) -> tuple[list[str], np.ndarray]:
    import pandas

    frame = pandas.read_csv(io.StringIO(text))  # the reader's defaults
    return list(frame.columns), frame.to_numpy()


def test_follower_table_is_the_law_in_time_at_the_scene_rpm():
    """Cycloidal rise h over T = beta / omega seconds: s = h (t/T - sin(2 pi t/T) / 2 pi),
    v = h/T (1 - cos), a = 2 pi h/T^2 sin, j = 4 pi^2 h/T^3 cos (SI: m/s^2, m/s^3)."""
    tables = {}
    for rpm in (300.0, 600.0):
        files, _ = run(plate(rpm=rpm))
        header, data = _table(files["c_follower.csv"])
        assert header == ["cam_angle_deg", "time_s", "lift_mm", "velocity_mm_per_s", "acceleration_m_per_s2", "jerk_m_per_s3"]
        omega = rpm * TWO_PI / 60.0
        theta = np.radians(data[:, 0])
        assert data.shape[0] == 3600 and np.allclose(data[:, 1], theta / omega, atol=1e-9)
        t = theta / omega  # the time column has 9 decimals: the exact time of each row's cam angle
        rise = theta < D(120)
        T, h = D(120) / omega, 20.0
        u = TWO_PI * t[rise] / T
        assert np.allclose(data[rise, 2], h * (t[rise] / T - np.sin(u) / TWO_PI), atol=2e-9)
        assert np.allclose(data[rise, 3], h / T * (1 - np.cos(u)), atol=2e-9, rtol=1e-12)
        assert np.allclose(data[rise, 4], 1e-3 * TWO_PI * h / T**2 * np.sin(u), atol=2e-9, rtol=1e-12)
        assert np.allclose(data[rise, 5], 1e-3 * TWO_PI**2 * h / T**3 * np.cos(u), atol=2e-9, rtol=1e-11)
        tables[rpm] = data
    slow, fast = tables[300.0], tables[600.0]
    assert np.allclose(fast[:, 2], slow[:, 2], atol=1e-9)  # the lift against cam angle does not depend on speed
    for column, power in ((3, 1), (4, 2), (5, 3)):  # velocity ~ omega, acceleration ~ omega^2, jerk ~ omega^3
        assert np.allclose(fast[:, column], 2.0**power * slow[:, column], atol=1e-8 * 2.0**power)


def test_motion_figures_at_rpm_are_the_cycloidal_peaks():
    """Cycloidal rise h over beta at omega: peak velocity 2 h omega / beta, acceleration
    2 pi h omega^2 / beta^2, jerk 4 pi^2 h omega^3 / beta^3 (Norton, Table 8-3: Cv 2, Ca 2 pi, Cj 4 pi^2)."""
    rpm, h, beta = 300.0, 20.0, D(120)
    at = run(plate(rpm=rpm))[1]["cams"]["c"]["figures"]["motion_at_rpm"]
    omega = rpm * TWO_PI / 60.0
    assert at["rpm"] == rpm
    assert at["max_velocity_mm_per_s"] == pytest.approx(2 * h * omega / beta, rel=1e-9)
    assert at["max_acceleration_m_per_s2"] == pytest.approx(1e-3 * TWO_PI * h * omega**2 / beta**2, rel=1e-9)
    assert at["max_jerk_m_per_s3"] == pytest.approx(1e-3 * TWO_PI**2 * h * omega**3 / beta**3, rel=1e-9)


def oscillating_program(theta: np.ndarray, swing: float = D(15.0)):
    """psi, psi', psi'', psi''' (rad, per rad of cam angle) of :func:`oscillating`'s program,
    written out: cycloidal swing out over 100 deg, dwell 60, 4-5-6-7 back over 120 deg
    (Norton, Design of Machinery, ch. 8: P = 35 u^4 - 84 u^5 + 70 u^6 - 20 u^7), dwell 80."""
    theta = np.mod(theta, TWO_PI)
    out = [np.zeros_like(theta) for _ in range(4)]
    up = theta < D(100)
    u, b = theta[up] / D(100), D(100)
    w = TWO_PI * u
    for k, value in enumerate((swing * (u - np.sin(w) / TWO_PI), swing / b * (1 - np.cos(w)),
                               TWO_PI * swing / b**2 * np.sin(w), TWO_PI**2 * swing / b**3 * np.cos(w))):
        out[k][up] = value
    out[0][(theta >= D(100)) & (theta < D(160))] = swing
    back = (theta >= D(160)) & (theta < D(280))
    u, b = (theta[back] - D(160)) / D(120), D(120)
    p = (35 * u**4 - 84 * u**5 + 70 * u**6 - 20 * u**7, 140 * u**3 - 420 * u**4 + 420 * u**5 - 140 * u**6,
         420 * u**2 - 1680 * u**3 + 2100 * u**4 - 840 * u**5, 840 * u - 5040 * u**2 + 8400 * u**3 - 4200 * u**4)
    out[0][back] = swing * (1 - p[0])
    for k in (1, 2, 3):
        out[k][back] = -swing * p[k] / b**k
    return tuple(out)


def test_oscillating_follower_table_is_in_degrees_and_radians_per_second():
    """The arm's swing in deg and its angular velocity, acceleration and jerk in rad/s, rad/s^2,
    rad/s^3: psi' w, psi'' w^2, psi''' w^3 of the program written out (oscillating_program), over
    the whole turn at two speeds (the jerk off the two rows where the cycloid's jerk jumps)."""
    for rpm in (120.0, 450.0):
        files, _ = run(oscillating(rpm=rpm))
        header, data = _table(files["c_follower.csv"])
        assert header == ["cam_angle_deg", "time_s", "lift_deg", "velocity_rad_per_s", "acceleration_rad_per_s2", "jerk_rad_per_s3"]
        omega = rpm * TWO_PI / 60.0
        theta = np.radians(data[:, 0])
        assert data.shape[0] == 3600 and np.allclose(data[:, 1], theta / omega, atol=1e-9)
        psi, dpsi, d2psi, d3psi = oscillating_program(theta)
        assert np.allclose(data[:, 2], np.degrees(psi), rtol=0, atol=2e-9)
        assert np.allclose(data[:, 3], dpsi * omega, rtol=1e-12, atol=2e-9)
        assert np.allclose(data[:, 4], d2psi * omega**2, rtol=1e-11, atol=2e-9)
        smooth = np.min(np.abs(data[:, 0, None] - np.array([0.0, 100.0, 360.0])), axis=1) > 1e-6
        assert np.allclose(data[smooth, 5], d3psi[smooth] * omega**3, rtol=1e-11, atol=2e-9)
        assert np.max(np.abs(data[:, 4])) > 10.0 and np.max(np.abs(data[:, 5])) > 1e3  # the columns are not ~0


def _instant_centre_pressure_angle(keys: dict, theta: np.ndarray, psi: np.ndarray, dpsi: np.ndarray, rest: float) -> np.ndarray:
    """|pressure angle| (rad) of an oscillating roller or flat face by Kennedy's theorem: the common
    normal passes through the instant centre of cam and arm, I = -r P / (1 - r) on the line from the
    cam axis to the pivot P, r = (arm's angular velocity) / (cam's) = sigma tau psi'.  Roller: the
    angle between the normal through the roller centre C and C's velocity (perpendicular to the
    arm); flat face (normal w, offset f from the pivot): tan(alpha) = f / xi with the contact's
    distance along the face from the pivot's foot xi = (I - P) . J w."""
    pivot = np.array([keys["pivot_x_mm"], keys["pivot_y_mm"]])
    sigma = 1.0 if keys.get("rotation", "ccw") == "ccw" else -1.0
    tau = 1.0 if keys.get("swing_turn", "ccw") == "ccw" else -1.0
    r = sigma * tau * dpsi
    centre = -r[:, None] * pivot / (1.0 - r)[:, None]
    angle = rest + tau * psi
    u = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    along = np.stack([-u[:, 1], u[:, 0]], axis=-1)  # J u
    if keys.get("follower") == "flat":
        xi = np.sum((centre - pivot) * along, axis=1)
        return np.arctan(np.abs(keys["face_offset_mm"] / xi))
    normal = pivot + keys["arm_length_mm"] * u - centre
    return np.arccos(np.abs(np.sum(normal * along, axis=1)) / np.hypot(*normal.T))


@pytest.mark.parametrize("case", ["roller ccw", "roller cw", "flat"])
def test_oscillating_report_figures_are_in_degrees(case):
    """report.json of an oscillating follower: every *_deg figure in degrees, against plane
    geometry and the program written out: the stroke (the swing), the arm's rest angle (the arm
    circle meets the prime circle where a positive swing moves outward; a face's rest normal: the
    face tangent to the base circle) and the largest pressure angle (Kennedy's instant centre,
    on a 0.01 deg grid) with where it is; the speeds in rad/s, rad/s^2, rad/s^3 (the cycloid's
    peaks 2, 2 pi, 4 pi^2 x swing / beta^n x w^n: the larger of the program's two motions).
    camgen's pressure angle is the largest on its check grid: within 1e-4 deg below the peak."""
    from camgen.synthesis.followers import FollowerSpec
    from test_followers import rest_arm_angle, rest_face_angle

    scene = {"roller ccw": oscillating(), "roller cw": oscillating(swing_turn="cw", pivot_x_mm=-90.0, rotation="cw"),
             "flat": _oscillating_flat(10.0)}[case]
    keys = scene["cams"]["c"]
    swing = D(8.0) if case == "flat" else D(15.0)
    rpm, omega = keys["rpm"], keys["rpm"] * TWO_PI / 60.0
    figures = run(scene)[1]["cams"]["c"]
    checks, figures = {c["name"]: c for c in figures["checks"]}, figures["figures"]
    assert figures["stroke_deg"] == pytest.approx(math.degrees(swing), rel=1e-12)
    spec = dict(base_radius=keys["base_radius_mm"], motion="oscillating", pivot=(keys["pivot_x_mm"], keys["pivot_y_mm"]),
                rotation=keys.get("rotation", "ccw"), lift_turn=keys.get("swing_turn", "ccw"))
    if case == "flat":
        rest = rest_face_angle(FollowerSpec("flat", face_offset=keys["face_offset_mm"], **spec))
        got = figures["follower"]["rest_face_normal_deg"]
    else:
        rest = rest_arm_angle(FollowerSpec("roller", roller_radius=keys["roller_radius_mm"], arm_length=keys["arm_length_mm"], **spec))
        got = figures["follower"]["rest_arm_angle_deg"]
    assert abs(math.remainder(got - math.degrees(rest), 360.0)) <= 1e-9
    theta = np.arange(36000) * (TWO_PI / 36000)
    psi, dpsi, _, _ = oscillating_program(theta, swing)
    alpha = _instant_centre_pressure_angle(keys, theta, psi, dpsi, rest)
    pressure = checks["pressure_angle"]
    assert pressure["unit"] == "deg" and pressure["limit"] == 45.0  # the oscillating default (README)
    peak = math.degrees(np.max(alpha))  # camgen's is the largest on its check grid: a little below, never above
    assert peak - 1e-4 <= pressure["value"] <= peak + 1e-9
    assert pressure["where_deg"][0] == pytest.approx(math.degrees(theta[np.argmax(alpha)]), abs=0.1)
    stroke = checks["follower_motion"]
    assert stroke["value"] == pytest.approx(swing if stroke["unit"] == "rad" else math.degrees(swing), rel=1e-12)
    beta = D(100)
    assert figures["motion_at_rpm"] == pytest.approx({"rpm": rpm, "max_velocity_rad_per_s": 2 * swing / beta * omega,
                                                      "max_acceleration_rad_per_s2": TWO_PI * swing / beta**2 * omega**2,
                                                      "max_jerk_rad_per_s3": TWO_PI**2 * swing / beta**3 * omega**3}, rel=1e-9)


def test_follower_table_of_a_yoke_cam(tmp_path):
    """The constant-breadth cam's yoke (paper 000 stride cam a, b, c = 220, 160, 25): largest speed
    sqrt(a^2 - b^2/4) omega (the flank arc about O' at C), stroke 2a - b."""
    a, b, c, rpm = 220.0, 160.0, 25.0, 30.0
    scene = {"output": {"formats": ["follower"]}, "cams": {"c": {"kind": "three_arc", "a_mm": a, "b_mm": b, "c_mm": c, "rpm": rpm}}}
    header, data = _table(run(scene)[0]["c_follower.csv"])
    assert header[2] == "lift_mm"
    omega = rpm * TWO_PI / 60.0
    assert np.max(np.abs(data[:, 3])) == pytest.approx(math.sqrt(a * a - b * b / 4) * omega, rel=1e-5)
    assert np.ptp(data[:, 2]) == pytest.approx(2 * a - b, abs=1e-6) and np.min(data[:, 2]) == 0.0


# --------------------------------------------------------------------------------------------
# The report: zero mark, rotation, animation
# --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rotation, turn", [("ccw", "360"), ("cw", "-360")])
def test_report_animates_the_follower_riding_the_cam(rotation, turn):
    scene = plate(rotation=rotation)
    scene["output"] = {"formats": ["html"]}
    page = run(scene)[0]["report.html"]
    for marker in ("<script", "src=", "href='http", 'href="http', "<link", "@import"):
        assert marker not in page
    assert f"type='rotate' from='0 0 0' to='{turn} 0 0'" in page
    values = re.search(r"type='translate' values='([^']+)'", page).group(1)
    lift = np.array([float(v.split(",")[1]) for v in values.split(";")])
    theta = TWO_PI * np.arange(180) / 180
    assert lift.size == 181 and np.allclose(lift[:-1], cycloidal_program(theta)[0], atol=1e-4) and lift[-1] == lift[0]
    assert "cam angle 0 (contact point)" in page  # the zero mark in the profile figure
    assert ">ccw<" in page if rotation == "ccw" else ">cw<" in page  # the rotation arrow's label


def test_report_of_an_oscillating_follower_turns_the_arm_about_its_pivot():
    scene = oscillating()
    scene["output"] = {"formats": ["html"]}
    page = run(scene)[0]["report.html"]
    values = re.search(r"type='rotate' values='([^']+)'", page).group(1).split(";")
    angles = np.array([float(v.split()[0]) for v in values])
    pivots = {tuple(v.split()[1:]) for v in values}
    assert pivots == {("90.000", "50.000")}
    theta = TWO_PI * np.arange(180) / 180
    tau = np.clip(theta / D(100), 0.0, 1.0)
    rising = theta < D(100)
    assert np.allclose(angles[:-1][rising], 15.0 * (tau - np.sin(TWO_PI * tau) / TWO_PI)[rising], atol=1e-4)  # ccw swing turn


def test_animation_turns_a_cw_arm_the_other_way():
    scene = oscillating(swing_turn="cw", pivot_x_mm=-90.0)
    scene["output"] = {"formats": ["html"]}
    page = run(scene)[0]["report.html"]
    angles = np.array([float(v.split()[0]) for v in re.search(r"type='rotate' values='([^']+)'", page).group(1).split(";")])
    theta = TWO_PI * np.arange(180) / 180
    tau = np.clip(theta / D(100), 0.0, 1.0)
    rising = theta < D(100)
    assert np.allclose(angles[:-1][rising], -15.0 * (tau - np.sin(TWO_PI * tau) / TWO_PI)[rising], atol=1e-4)


def test_generic_curvature_plot_is_against_the_polar_angle(default_run):
    page = (default_run / "report.html").read_text()
    assert "polar angle on the cam (deg)" in page


def test_polynomial_end_conditions_are_per_degree_of_cam_angle():
    """start/end give v per degree and a per degree^2: a polynomial ending at v = 0.1 mm/deg joins a
    constant velocity of 10 mm over 100 deg (0.1 mm/deg) without a velocity jump, and the table shows
    v = 0.1 mm/deg x 180/pi x omega and a = 0.002 mm/deg^2 x (180/pi)^2 x omega^2 at that end."""
    program = [{"law": "polynomial", "span_deg": 90.0, "start": [0.0, 0.0, 0.0], "end": [10.0, 0.1, 0.002]},
               {"law": "polynomial", "span_deg": 30.0, "start": [10.0, 0.1, 0.002], "end": [13.0, 0.1, 0.0]},
               {"law": "constant_velocity", "span_deg": 100.0, "lift_mm": 10.0},
               {"law": "polynomial", "span_deg": 140.0, "start": [23.0, 0.1, 0.0], "end": [0.0, 0.0, 0.0]}]
    files, report = run(plate(follower="knife", roller_radius_mm=None, base_radius_mm=60.0, rpm=60.0, segments=program))
    joins = checks_of(report)["law_joins"]
    assert "velocity jumps" not in joins["note"] and "displacement" not in joins["note"]
    _, data = _table(files["c_follower.csv"])
    omega = TWO_PI  # 60 rpm
    row = int(np.argmin(np.abs(data[:, 0] - 90.0)))  # 90 deg starts the second polynomial: its start values
    assert data[row, 3] == pytest.approx(0.1 * 180 / math.pi * omega, rel=1e-9)
    assert data[row, 4] == pytest.approx(0.002 * (180 / math.pi) ** 2 * omega**2 * 1e-3, rel=1e-9)
    assert data[int(np.argmin(np.abs(data[:, 0] - 150.0))), 3] == pytest.approx(0.1 * 180 / math.pi * omega, rel=1e-9)


def test_the_kinds_key_lists_are_the_librarys():
    """The kinds name the laws and the default tolerance without importing the library; they agree."""
    from camgen.kinds.disk import DEFAULT_FIT_TOL
    from camgen.motions.motion_law import LAW_NAMES
    from camgen.synthesis.followers import DEFAULT_FIT_TOL as LIBRARY_FIT_TOL
    from camgen.synthesis.laws import LAWS

    assert sorted(LAW_NAMES) == sorted(LAWS) and DEFAULT_FIT_TOL == LIBRARY_FIT_TOL


@pytest.mark.parametrize("follower", ["roller", "flat"])
def test_an_undercut_cam_is_report_only_and_the_advised_base_radius_cures_it(follower):
    """Too small a base radius: the undercut fails (blocks manufacture, no DXF), the report still
    follows the documented layout, and the base radius the advice names passes when used."""
    import jsonschema

    from camgen.report import REPORT_SCHEMA

    keys = {"follower": "flat", "roller_radius_mm": None} if follower == "flat" else {"roller_radius_mm": 25.0}
    segments = [{"law": "cycloidal", "span_deg": 60.0, "lift_mm": 30.0}, {"law": "dwell", "span_deg": 120.0},
                {"law": "cycloidal", "span_deg": 60.0, "lift_mm": -30.0}, {"law": "dwell", "span_deg": 120.0}]
    files, report = run(plate(base_radius_mm=20.0, segments=segments, **keys))
    jsonschema.validate(report, REPORT_SCHEMA)
    checks = checks_of(report)
    assert checks["undercut"]["status"] == "fail" and checks["undercut"]["blocks_manufacture"]
    assert len(checks["undercut"]["where_deg"]) >= 2 and "c.dxf" not in files and "c_follower.csv" in files
    advised = checks["min_base_radius"]["value"]
    assert advised > 20.0 and f"increase base_radius_mm to at least {advised:.3f}" in checks["min_base_radius"]["note"]
    cured = checks_of(run(plate(base_radius_mm=advised, segments=segments, **keys))[1])
    assert cured["undercut"]["status"] == "pass" and cured["pressure_angle"]["status"] == "pass"
    below = checks_of(run(plate(base_radius_mm=advised - 0.05, segments=segments, **keys))[1])
    assert "fail" in (below["undercut"]["status"], below["pressure_angle"]["status"])


def test_new_lift_table_copies_its_table_and_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "designs").mkdir()
    assert main(["new", "lift_table", "designs"]) == 0
    assert sorted(p.name for p in (tmp_path / "designs").iterdir()) == ["lift_table.csv", "lift_table.toml"]
    assert main(["run", "designs/lift_table.toml", "-o", "out", "--quiet"]) == 0
    assert main(["new", "lift_table", "designs/again.toml"]) == 2  # the table is there: never overwritten
    assert "lift_table.csv' exists already" in capsys.readouterr().err


def test_disk_report_renders_in_headless_chromium(tmp_path):
    """The animated SVG is valid: Chromium renders the page without console errors."""
    import subprocess

    from helpers import require_tool

    browser = require_tool("chromium")
    scene = oscillating()
    scene["output"] = {"formats": ["html"]}
    page = tmp_path / "report.html"
    page.write_text(run(scene)[0]["report.html"])
    shot = tmp_path / "shot.png"
    proc = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         f"--user-data-dir={tmp_path / 'profile'}", "--enable-logging=stderr", "--v=0",
         "--window-size=1200,3000", f"--screenshot={shot}", page.as_uri()],
        capture_output=True, text=True, timeout=120,
    )
    assert shot.exists(), proc.stderr[-2000:]
    assert not [line for line in proc.stderr.splitlines() if "CONSOLE" in line and ("ERROR" in line or "Uncaught" in line)]
