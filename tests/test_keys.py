"""Every scene key changes what its documentation says it changes (issue "Trust", item 3).

For every key of every cam kind, of [output], [machining] and of every mechanism, the walk
builds a working scene, changes that one key (to another valid value), runs the pipeline and
compares the files: every output class the key's ``affects`` names must change, and no
manufacturing file outside them may change.  A key that changes nothing where it is accepted
would fail here; keys that only make sense with another setting are refused without it
(checked by ``test_conditional_keys_are_refused_where_they_do_nothing``).
"""
from __future__ import annotations

import copy

import pytest

from camgen.jobs import get_job, job_names
from camgen.kinds import get_kind, kind_names
from camgen.outputs import machining_keys, output_keys
from camgen.schema import Choice, Count, Flag, Key, Number, Text

#: Which files each effect may change, and which of them must change (at least one).
MAY = {
    "profile": {"dxf", "points", "lift", "stl", "ngc", "json", "ride"},
    "pitch": {"dxf", "json"},
    "body": {"dxf", "stl", "json", "ngc"},  # the G-code cuts the bore or says it is left (camgen.export.gcode_bore)
    "thickness": {"stl", "ngc", "json"},
    "gcode": {"ngc"},
    "dxf": {"dxf"},
    "tables": {"lift"},
    "tolerance": {"dxf", "points", "stl", "ngc", "json"},
    "report": {"json"},
    "files": {"dxf", "points", "lift", "stl", "ngc", "json", "obj", "ride"},
    "mechanism": {"json", "legs"},
    "motion": {"json", "follower"},
    "fea": {"fea", "json"},
    "drawing": {"drawing"},
    "step": {"step"},
}
MUST = {
    "profile": {"dxf", "points"}, "pitch": {"dxf"}, "body": {"dxf", "stl"}, "thickness": {"stl", "ngc"}, "gcode": {"ngc"},
    "dxf": {"dxf"}, "tables": {"lift"}, "tolerance": {"points", "dxf", "stl", "ngc"}, "report": {"json"}, "files": {"obj"},
    "mechanism": {"legs", "json"},
    "motion": {"json"},
    "fea": {"fea"},
    "drawing": {"drawing"},
    "step": {"step"},
}
MANUFACTURING = {"dxf", "points", "lift", "stl", "ngc", "obj"}
#: kinds whose keys test_disk_cams.py walks
DISK_KINDS = {"motion_law", "lift_table"}


def classify(name: str) -> str:
    for suffix, kind in (("_points.csv", "points"), ("_lift.csv", "lift"), ("_ride.csv", "ride"), (".dxf", "dxf"), (".stl", "stl"),
                         (".ngc", "ngc"), (".obj", "obj"), ("report.json", "json"), ("_follower.csv", "follower"),
                         (".inp", "fea"), (".msh", "fea"), (".vtu", "fea"),
                         ("_drawing.svg", "drawing"), ("_drawing.pdf", "drawing"), ("_inspection.csv", "drawing"), (".step", "step")):
        if name.endswith(suffix):
            return kind
    return "legs" if name.startswith("leg_path") else name


def run(scene_table: dict, tmp_path) -> dict[str, bytes]:
    from camgen.pipeline import execute, plan_run
    from camgen.scene import parse_scene

    scene = parse_scene(copy.deepcopy(scene_table), "walk", source="walk.toml", base_dir=tmp_path)
    files = execute(scene, plan_run(scene)).files
    out: dict[str, bytes] = {}
    for name, data in files.items():
        out.setdefault(classify(name), b"")
        out[classify(name)] += name.encode() + b"\0" + (data.encode() if isinstance(data, str) else data)
    return out


def scene(cam: dict, formats=("dxf", "points", "lift", "ngc"), machining=None, **extra) -> dict:
    # the construction layers on: keys that change the follower-centre path change the PITCH layer
    table = {"output": {"formats": list(formats), **({"dxf_construction": True} if "dxf" in formats else {})}, "cams": {"c": cam}, **extra}
    if "ngc" in formats:
        table["machining"] = machining or {"tool_diameter_mm": 6.0}
    return table


# --------------------------------------------------------------------------------------------
# Working bases and, per key, how to change it
# --------------------------------------------------------------------------------------------
THREE_ARC = {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0, "bore_diameter_mm": 20.0, "keyway_width_mm": 6.0,
             "keyway_depth_mm": 2.8, "thickness_mm": 10.0}
ROLLER = {"follower": "roller", "roller_radius_mm": 10.0}
OSCILLATING = {**ROLLER, "follower_motion": "oscillating", "pivot_x_mm": 400.0, "pivot_y_mm": 0.0, "arm_length_mm": 380.0}
TRAJECTORY = {"kind": "trajectory", "expression": "202.4396*sin(pi*x/1000)", "period_mm": 2000.0, "samples": 180,
              "bore_diameter_mm": 8.0, "thickness_mm": 8.0}

#: the yoke's dynamics (form closure) and a spring-loaded flat face's, on the three-arc cam
YOKE_DYNAMICS = {"rpm": 30.0, "mass_kg": 20.0}
FLAT_DYNAMICS = {"follower": "flat", "rpm": 30.0, "mass_kg": 20.0, "spring_rate_n_per_mm": 1.0, "spring_preload_n": 100.0}
VERTICAL_YOKE = {**YOKE_DYNAMICS, "follower_direction_deg": 90.0}  # its weight loads the faces
SPRING_LENGTHS = {**FLAT_DYNAMICS, "spring_preload_n": None, "spring_free_length_mm": 150.0, "spring_installed_length_mm": 50.0}
DYNAMICS_WALK = {
    "mass_kg": (YOKE_DYNAMICS, {"mass_kg": 25.0}),
    "spring_rate_n_per_mm": (FLAT_DYNAMICS, {"spring_rate_n_per_mm": 1.5}),
    "spring_preload_n": (FLAT_DYNAMICS, {"spring_preload_n": 120.0}),
    "spring_free_length_mm": (SPRING_LENGTHS, {"spring_free_length_mm": 160.0}),
    "spring_installed_length_mm": (SPRING_LENGTHS, {"spring_installed_length_mm": 40.0}),
    "damping_n_s_per_m": (YOKE_DYNAMICS, {"damping_n_s_per_m": 50.0}),
    "external_load_n": (YOKE_DYNAMICS, {"external_load_n": 10.0}),
    "external_load_csv": ({**YOKE_DYNAMICS, "external_load_csv": "load_a.csv"}, {"external_load_csv": "load_b.csv"}),
    "gravity": (VERTICAL_YOKE, {"gravity": False}),
    "gravity_deg": (VERTICAL_YOKE, {"gravity_deg": -80.0}),
    "contact_width_mm": (YOKE_DYNAMICS, {"contact_width_mm": 15.0}),
    "cam_modulus_gpa": (YOKE_DYNAMICS, {"cam_modulus_gpa": 200.0}),
    "cam_poisson": (YOKE_DYNAMICS, {"cam_poisson": 0.28}),
    "follower_modulus_gpa": (YOKE_DYNAMICS, {"follower_modulus_gpa": 200.0}),
    "follower_poisson": (YOKE_DYNAMICS, {"follower_poisson": 0.28}),
    "allowable_contact_stress_mpa": (YOKE_DYNAMICS, {"allowable_contact_stress_mpa": 10.0}),
    "jump_margin_n": (FLAT_DYNAMICS, {"jump_margin_n": 5.0}),
    "torque_limit_n_m": (YOKE_DYNAMICS, {"torque_limit_n_m": 1.0}),
    # the compliant train (issue 25 item 2): a spring-loaded flat face (a yoke is form-closed)
    "train_stiffness_n_per_mm": (FLAT_DYNAMICS, {"train_stiffness_n_per_mm": 500.0}),
    "damping_ratio": ({**FLAT_DYNAMICS, "train_stiffness_n_per_mm": 500.0}, {"damping_ratio": 0.1}),
    "residual_vibration_limit_mm": ({**FLAT_DYNAMICS, "train_stiffness_n_per_mm": 500.0}, {"residual_vibration_limit_mm": 0.05}),
    # the two-mass train (follower stiffness and tool mass given together)
    "follower_stiffness_n_per_mm": ({**FLAT_DYNAMICS, "train_stiffness_n_per_mm": 500.0, "follower_stiffness_n_per_mm": 500.0,
                                     "tool_mass_kg": 5.0},
                                    {"follower_stiffness_n_per_mm": 800.0}),
    "tool_mass_kg": ({**FLAT_DYNAMICS, "train_stiffness_n_per_mm": 500.0, "follower_stiffness_n_per_mm": 800.0, "tool_mass_kg": 5.0},
                     {"tool_mass_kg": 6.0}),
    "return_spring_on": ({**FLAT_DYNAMICS, "train_stiffness_n_per_mm": 500.0, "follower_stiffness_n_per_mm": 800.0, "tool_mass_kg": 5.0},
                         {"return_spring_on": "cam_side"}),
}

#: key -> (changes to the base, changes for the altered run), where a generic change does not fit
OVERRIDES: dict[str, dict[str, tuple[dict, dict]]] = {
    "three_arc": {
        **DYNAMICS_WALK,
        "follower": ({}, ROLLER),
        "follower_motion": (ROLLER, OSCILLATING),
        "pivot_x_mm": (OSCILLATING, {"pivot_x_mm": 390.0}),
        "pivot_y_mm": (OSCILLATING, {"pivot_y_mm": 100.0}),
        "arm_length_mm": (OSCILLATING, {"arm_length_mm": 370.0}),
        "roller_radius_mm": (ROLLER, {"roller_radius_mm": 12.0}),
        "follower_offset_mm": (ROLLER, {"follower_offset_mm": 5.0}),
        "face_half_length_mm": ({}, {"face_half_length_mm": 400.0}),
        "b_mm": ({}, {"b_mm": 150.0}),
        # the jerk limit at rpm (issue 26 item 5): a limit the cam's jerk stays under, then one it exceeds
        "jerk_limit_m_per_s3": ({"rpm": 30.0, "jerk_limit_m_per_s3": 1e6}, {"jerk_limit_m_per_s3": 1e-6}),
        "jerk_limit_rad_per_s3": ({**OSCILLATING, "rpm": 30.0, "jerk_limit_rad_per_s3": 1e6}, {"jerk_limit_rad_per_s3": 1e-6}),
    },
    "trajectory": {
        "expression": ({}, {"expression": "190*sin(pi*x/1000)"}),
        "trajectory_csv": ({"expression": None, "period_mm": None, "trajectory_csv": "a.csv"}, {"trajectory_csv": "b.csv"}),
        "worm_teeth": ({"fit_tables": ["A1"]}, {"worm_teeth": 60}),
        "fit_tables": ({}, {"fit_tables": ["A1"]}),
        "curvature": ({}, {"curvature": "central"}),
        "period_mm": ({}, {"period_mm": 4000.0}),  # two periods of the path per cam turn: still periodic
        "keyway_width_mm": ({"keyway_width_mm": 2.0, "keyway_depth_mm": 1.0}, {"keyway_width_mm": 2.5}),
        "keyway_depth_mm": ({"keyway_width_mm": 2.0, "keyway_depth_mm": 1.0}, {"keyway_depth_mm": 1.2}),
        "keyway_angle_deg": ({"keyway_width_mm": 2.0, "keyway_depth_mm": 1.0}, {"keyway_angle_deg": 45.0}),
        "jerk_limit_m_per_s3": ({"rpm": 30.0, "jerk_limit_m_per_s3": 1e6}, {"jerk_limit_m_per_s3": 1e-6}),  # issue 26 item 5
    },
}


def _changed(value, key: Key):
    """Another valid value of ``key`` near ``value`` (scene units)."""
    kind = key.type
    if isinstance(kind, Flag):
        return not value
    if isinstance(kind, Choice):
        return next(v for v in kind.values if v != value)
    if isinstance(kind, Count):
        return value + 1 if value + 1 <= kind.high else value - 1
    if isinstance(kind, Text):
        return (value or "note") + " (changed)"
    if isinstance(kind, Number):
        if value is None:
            return 1.0 if kind.low < 1.0 < kind.high else (kind.low + kind.high) / 2
        if kind.scale != 1.0 or kind.unit == "deg":  # angles: turn a little
            for new in (value + 10.0, value - 10.0, value * 1.5, value * 0.5):
                if kind.low <= new * kind.scale / kind.scale <= kind.high and new != value:
                    return new
        new = value * 1.1 if value else 1.0
        return new if kind.low <= new <= kind.high else value * 0.9
    raise AssertionError(f"no generic change for {key.name} ({type(kind).__name__}): add an override")


def _apply(table: dict, changes: dict) -> dict:
    out = dict(table)
    for k, v in changes.items():
        if v is None:
            out.pop(k, None)
        else:
            out[k] = v
    return out


def _key_cases():
    cases = []
    for kind_name in kind_names():
        if kind_name in DISK_KINDS:
            continue  # test_disk_cams.py walks their keys
        for key in get_kind(kind_name).keys:
            if key.name == "form":
                continue  # one form per motion today: test_axes checks every other form is refused
            cases.append(pytest.param(kind_name, key.name, id=f"{kind_name}.{key.name}"))
    return cases


def _assert_effect(key: Key, before: dict, after: dict) -> None:
    changed = {k for k in set(before) | set(after) if before.get(k) != after.get(k)}
    allowed = set().union(*(MAY[e] for e in key.affects))
    for effect in key.affects:
        assert changed & MUST[effect], f"{key.name}: documented to change {effect} ({sorted(MUST[effect])}), changed {sorted(changed)}"
    stray = (changed & MANUFACTURING) - allowed
    assert not stray, f"{key.name}: changed {sorted(stray)}, documented only {list(key.affects)}"


@pytest.mark.parametrize("kind_name, key_name", _key_cases())
def test_every_cam_key_changes_what_it_documents(kind_name, key_name, tmp_path):
    key = next(k for k in get_kind(kind_name).keys if k.name == key_name)
    base_cam = {"three_arc": THREE_ARC, "trajectory": TRAJECTORY}[kind_name]
    if kind_name == "trajectory" and key_name == "trajectory_csv":
        _write_tables(tmp_path)
    if key_name == "external_load_csv":  # two load tables over cam angle (N)
        for name, load in (("load_a.csv", 10.0), ("load_b.csv", 12.0)):
            (tmp_path / name).write_text("cam_angle_deg,load_n\n0,0\n180," + str(load) + "\n")
    base_changes, alt_changes = OVERRIDES.get(kind_name, {}).get(key_name, ({}, None))
    base = _apply(base_cam, base_changes)
    if alt_changes is None:
        current = base.get(key.name, key.default)
        alt_changes = {key.name: _changed(current, key)}
    alt = _apply(base, alt_changes)
    formats = ("dxf", "points", "lift", "ngc") + (("stl",) if {"body", "thickness", "tolerance"} & set(key.affects) else ())
    _assert_effect(key, run(scene(base, formats), tmp_path), run(scene(alt, formats), tmp_path))


def _write_tables(folder) -> None:
    """Two periodic trajectory tables (x, y mm) of different amplitude."""
    import numpy as np

    x = np.linspace(0.0, 2000.0, 201)
    for name, amplitude in (("a.csv", 200.0), ("b.csv", 190.0)):
        y = amplitude * np.sin(np.pi * x / 1000.0)
        y[-1] = y[0]
        (folder / name).write_text("x_mm,y_mm\n" + "".join(f"{a:.12g},{b:.12g}\n" for a, b in zip(x, y)))


SPLINE_CAM = dict(TRAJECTORY)


#: A small plate cam (its drawing fits A4 at 1:1, so drawing_sheet = "A3" changes it) for the drawing's keys.
SMALL_PLATE = {"kind": "motion_law", "base_radius_mm": 6.0, "follower": "roller", "roller_radius_mm": 2.0, "bore_diameter_mm": 3.0,
               "segments": [{"law": "cycloidal", "span_deg": 180.0, "lift_mm": 3.0},
                            {"law": "cycloidal", "span_deg": 180.0, "lift_mm": -3.0}]}


@pytest.mark.parametrize("key_name", [k.name for k in output_keys()])
def test_every_output_key_changes_what_it_documents(key_name, tmp_path):
    key = next(k for k in output_keys() if k.name == key_name)
    if "drawing" in key.affects:  # the drawing's keys: its formats, a plate cam, the key's example value
        from camgen.export.drawing_spec import INSPECTION_FORMATS

        base = scene(SMALL_PLATE, ("dxf", "points") + INSPECTION_FORMATS)
        alt = copy.deepcopy(base)
        alt["output"][key_name] = key.example
        _assert_effect(key, run(base, tmp_path), run(alt, tmp_path))
        return
    base_output = {"formats": ["dxf", "points", "lift", "stl", "ngc"] + (["inp"] if "fea" in key.affects else [])
                   + (["step"] if "step" in key.affects else [])}
    base = scene(SPLINE_CAM, base_output["formats"])
    if "fea" in key.affects:  # a coarser tolerance keeps the FEA meshes small
        base["output"]["chord_tol_mm"] = 0.01
    current = {"formats": base_output["formats"], "dxf_splines": "biarc", "dxf_construction": True, "chord_tol_mm": 0.001,
               "lift_step_deg": 1.0, "fea_element_size_mm": None, "fea_elements": "wedge", "dxf_version": "R2010",
               "step_schema": "AP214"}[key_name]
    alt = copy.deepcopy(base)
    alt["output"][key_name] = base_output["formats"] + ["obj"] if key_name == "formats" else _changed(current, key)
    if key_name == "fea_element_size_mm":  # a size of the cam's scale (the default is 4.2 mm)
        alt["output"][key_name] = 8.0
    _assert_effect(key, run(base, tmp_path), run(alt, tmp_path))


@pytest.mark.parametrize("key_name", [k.name for k in machining_keys()])
def test_every_machining_key_changes_what_it_documents(key_name, tmp_path):
    key = next(k for k in machining_keys() if k.name == key_name)
    fanuc = {"program_number": 2, "tool_number": 2, "radius_register": 2}  # keys of the fanuc dialect only (none given: their defaults)
    machining = {"tool_diameter_mm": 6.0, **({"dialect": "fanuc"} if key_name in fanuc else {}),
                 **({"holding_tabs": 2} if key_name.startswith("holding_tab_") else {})}  # a tab's size: with tabs
    if key.requires.get("dialect") == ("wire_edm",):  # a wire-EDM key: with its dialect, which refuses the milling keys
        machining = {"dialect": "wire_edm"}
    if key_name == "bore_tool_number":  # the bore tool's number: with a bore tool (else no tool change)
        machining["bore_tool_diameter_mm"] = 4.0
    base = scene(SPLINE_CAM, ("dxf", "points", "ngc"), machining)
    alt = copy.deepcopy(base)
    value = alt["machining"].get(key_name, key.default)
    overrides = {"lead_mm": 5.0, "cutter_compensation": True, "cut_allowances_mm": [0.12, 0.03], "decimals": 5, "bore_tool_number": 3, "holding_tab_height_mm": 2.0, "entry": "ramp", **fanuc}
    alt["machining"][key_name] = overrides[key_name] if key_name in overrides else _changed(value, key)
    _assert_effect(key, run(base, tmp_path), run(alt, tmp_path))


LEG_SCENE = {
    "output": {"formats": ["dxf"]},
    "cams": {"stride": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0},
             "stride_copy": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 160.0, "c_mm": 25.0},
             "height": {"kind": "three_arc", "a_mm": 220.0, "b_mm": 220.0, "c_mm": 10.0}},
    "mechanisms": {"horse_leg": {"stride_cam": "stride", "height_cam": "height", "inclinations_deg": [12.5], "sweep_deg": [12.0, 13.0, 0.5]}},
}


#: Two cams with dynamics on one shaft (mechanisms.machine), the motor limits given.
_MACHINE_CAM = {"kind": "motion_law", "follower": "roller", "base_radius_mm": 40.0, "roller_radius_mm": 8.0, "rpm": 100.0,
                "mass_kg": 0.5, "spring_rate_n_per_mm": 2.0, "spring_preload_n": 40.0,
                "segments": [{"law": "cycloidal", "span_deg": 120.0, "lift_mm": 10.0}, {"law": "dwell", "span_deg": 60.0},
                             {"law": "cycloidal", "span_deg": 120.0, "lift_mm": -10.0}, {"law": "dwell", "span_deg": 60.0}]}
MACHINE_SCENE = {
    "output": {"formats": ["dxf"]},
    "cams": {"a": dict(_MACHINE_CAM), "b": dict(_MACHINE_CAM, mass_kg=1.0), "c": dict(_MACHINE_CAM)},
    "mechanisms": {"machine": {"rpm": 100.0, "cams": [{"name": "a", "phase_deg": 0.0}, {"name": "b", "phase_deg": 90.0}],
                               "motor_torque_limit_n_m": 2.0, "motor_power_limit_w": 100.0}},
}
#: A changed value of the machine's keys the generic walk cannot make.
MACHINE_CHANGES = {"cams": [{"name": "a", "phase_deg": 0.0}, {"name": "b", "phase_deg": 120.0}], "timing_curves": ["velocity"]}


@pytest.mark.parametrize("job_name, key_name", [(j, k.name) for j in job_names() for k in get_job(j).keys])
def test_every_mechanism_key_changes_what_it_documents(job_name, key_name, tmp_path):
    key = next(k for k in get_job(job_name).keys if k.name == key_name)
    if job_name == "machine":
        base = copy.deepcopy(MACHINE_SCENE)
        alt = copy.deepcopy(MACHINE_SCENE)
        table = alt["mechanisms"]["machine"]
        if key_name == "rpm":  # the cams turn at the machine's speed
            for cam in (*base["cams"].values(), *alt["cams"].values()):
                cam.pop("rpm")
            alt["cams"] = {"a": {k: v for k, v in _MACHINE_CAM.items() if k not in ("mass_kg", "spring_rate_n_per_mm", "spring_preload_n", "rpm")}}
            base["cams"] = copy.deepcopy(alt["cams"])
            for scene in (base, alt):
                scene["mechanisms"]["machine"]["cams"] = [{"name": "a", "phase_deg": 0.0}]
            table = alt["mechanisms"]["machine"]
        table[key_name] = MACHINE_CHANGES.get(key_name) or _changed(table.get(key_name, key.default), key)
        _assert_effect(key, run(base, tmp_path), run(alt, tmp_path))
        return
    base = copy.deepcopy(LEG_SCENE)
    alt = copy.deepcopy(LEG_SCENE)
    table = alt["mechanisms"][job_name]
    special = {"stride_cam": "stride_copy", "inclinations_deg": [14.5], "sweep_deg": [12.0, 13.0, 1.0], "ground_y_mm": -2070.0}
    if key_name == "height_cam":  # another three-arc cam of the same size: only the naming in the report changes
        alt["cams"]["height_copy"] = dict(alt["cams"]["height"])
        base["cams"]["height_copy"] = dict(base["cams"]["height"])
        table[key_name] = "height_copy"
    elif special.get(key_name) is not None:
        table[key_name] = special[key_name]
    else:
        table[key_name] = _changed(table.get(key_name, key.default), key)
    _assert_effect(key, run(base, tmp_path), run(alt, tmp_path))


# --------------------------------------------------------------------------------------------
# Keys that would do nothing are refused
# --------------------------------------------------------------------------------------------
REFUSED = [
    ({**THREE_ARC, "roller_radius_mm": 10.0}, "cams.c.roller_radius_mm", "follower"),  # yoke: no roller
    ({**THREE_ARC, **ROLLER, "face_half_length_mm": 30.0}, "cams.c.face_half_length_mm", "follower"),
    ({**THREE_ARC, **ROLLER, "pivot_x_mm": 300.0}, "cams.c.pivot_x_mm", "follower_motion"),
    ({**THREE_ARC, **OSCILLATING, "follower_offset_mm": 5.0}, "cams.c.follower_offset_mm", "follower_motion"),
    ({**THREE_ARC, **OSCILLATING, "follower_direction_deg": 5.0}, "cams.c.follower_direction_deg", "follower_motion"),
    ({**THREE_ARC, "keyway_width_mm": 0.0}, "cams.c.keyway_depth_mm", "width"),
    ({**TRAJECTORY, "worm_teeth": 40}, "cams.c.worm_teeth", "fit_tables"),
]


@pytest.mark.parametrize("cam, key, why", REFUSED)
def test_conditional_keys_are_refused_where_they_do_nothing(cam, key, why, tmp_path):
    from camgen.errors import CamgenError
    from camgen.scene import parse_scene

    with pytest.raises(CamgenError, match=rf"{key}.*{why}|{why}.*{key}") as caught:
        parse_scene(scene(cam, ("dxf",)), "walk")
    assert key in str(caught.value)


@pytest.mark.parametrize("table, key", [
    ({"output": {"formats": ["dxf"], "lift_step_deg": 2.0}}, "output.lift_step_deg"),
    ({"output": {"formats": ["points"], "dxf_splines": "bspline"}}, "output.dxf_splines"),
    ({"output": {"formats": ["dxf"]}, "machining": {"feed_mm_per_min": 300.0}}, "machining.feed_mm_per_min"),
    ({"output": {"formats": ["stl"], "fea_element_size_mm": 3.0}}, "output.fea_element_size_mm"),
    ({"output": {"formats": ["dxf"], "fea_elements": "tetra"}}, "output.fea_elements"),
])
def test_output_and_machining_keys_without_their_file_are_refused(table, key):
    from camgen.errors import ParameterError
    from camgen.scene import parse_scene

    with pytest.raises(ParameterError, match=key.replace(".", r"\.")):
        parse_scene({**table, "cams": {"c": dict(THREE_ARC)}}, "walk")


def test_the_walk_covers_every_kind():
    """Every registered kind is walked here or, for the disk-cam kinds, in test_disk_cams.py."""
    walked = {c.values[0] for c in _key_cases()}
    assert set(kind_names()) - walked <= DISK_KINDS

