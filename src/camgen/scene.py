"""Scene files: schema, reading and validation.

A scene is a TOML file naming the cams to build and the outputs wanted.  Lengths carry
``_mm`` in their key, angles ``_deg`` (degrees only here, at the edge: they are stored in
radians, under the key without its suffix).

.. code-block:: toml

    name = "default"                 # output folder name (default: the file's stem)

    [output]
    formats = ["dxf", "points"]      # see FORMATS
    chord_tol_mm = 0.001

    [machining]                      # G-code settings (formats = [..., "ngc"])
    tool_diameter_mm = 6.0

    [cams.stride_length]
    kind = "three_arc"
    a_mm = 220.0
    b_mm = 160.0
    c_mm = 25.0
    thickness_mm = 20.0              # body keys: see BODY_KEYS
    bore_diameter_mm = 20.0

Reading never evaluates user text; unknown keys, wrong types and out-of-range values raise
:class:`~camgen.errors.SceneError` or :class:`~camgen.errors.ParameterError` naming the key.
"""
from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from camgen.errors import ParameterError, SceneError, require_finite, require_positive

#: Output formats a scene may request, and what each writes per cam.
FORMATS: dict[str, str] = {
    "dxf": "<cam>.dxf: 2-D profile (exact ARCs, clamped B-splines or biarcs), bore, keyway, centre mark; R2010, mm",
    "points": "<cam>_points.csv: XY point list at the chord tolerance",
    "lift": "<cam>_lift.csv: polar lift table (cam angle -> radius, lift above the base radius)",
    "stl": "<cam>.stl: binary STL of the extruded body",
    "stl_ascii": "<cam>_ascii.stl: ASCII STL of the extruded body",
    "3mf": "<cam>.3mf", "obj": "<cam>.obj", "ply": "<cam>.ply", "vtu": "<cam>.vtu (VTK, FEA)",
    "msh": "<cam>.msh (Gmsh 2.2, FEA)", "inp": "<cam>.inp (Abaqus, FEA)",
    "ngc": "<cam>.ngc: RS274/NGC G-code milling the profile",
    "html": "report.html: the design-check report with plots (needs the report extra: matplotlib)",
    "step": "<cam>.step: exact solid, AP214, mm (needs the step extra: cadquery-ocp-novtk)",
}
DEFAULT_FORMATS = ("dxf", "points")

# key -> (type, required); types: mm, deg, float, int, bool, str, str_list, or a tuple of choices
Schema = dict[str, tuple[Any, bool]]

#: Keys of the cam body (solid, DXF bore/keyway, G-code depth), valid for every cam kind.
BODY_KEYS: Schema = {
    "thickness_mm": ("mm", False),
    "bore_diameter_mm": ("mm", False),
    "keyway_width_mm": ("mm", False),
    "keyway_depth_mm": ("mm", False),
    "keyway_angle_deg": ("deg", False),
    "min_wall_mm": ("mm", False),
    # follower model of the design checks (camgen.checks.Follower)
    "follower": (("yoke", "flat", "roller"), False),
    "follower_motion": (("translating", "oscillating"), False),
    "roller_radius_mm": ("mm", False),
    "follower_offset_mm": ("mm", False),
    "follower_direction_deg": ("deg", False),
    "pivot_distance_mm": ("mm", False),
    "pivot_angle_deg": ("deg", False),
    "arm_length_mm": ("mm", False),
    "face_half_length_mm": ("mm", False),
    "pressure_angle_limit_deg": ("deg", False),
    "rpm": ("float", False),
}

#: Cam kinds and their own keys.
CAM_KINDS: dict[str, Schema] = {
    "three_arc": {"a_mm": ("mm", True), "b_mm": ("mm", True), "c_mm": ("mm", True), "source": ("str", False)},
    "trajectory": {
        "expression": ("str", False),
        "trajectory_csv": ("str", False),
        "period_mm": ("mm", False),
        "samples": ("int", False),
        "curvature": (("exact", "forward", "central"), False),
        "wheelbase_mm": ("mm", False),
        "half_track_mm": ("mm", False),
        "lever_mm": ("mm", False),
        "rod_radius_mm": ("mm", False),
        "z_rear": ("int", False),
        "z_cam": ("int", False),
        "worm_teeth": ("int", False),
        "ride_periods": ("int", False),
        "fit_tables": ("str_list", False),
        "source": ("str", False),
    },
    "motion_law": {
        "base_radius_mm": ("mm", True),
        "segments": ("segment_list", True),
        "samples": ("int", False),
        "source": ("str", False),
    },
}

#: Keys of one ``[[cams.<name>.segments]]`` table of a motion-law cam.
SEGMENT_KEYS: Schema = {"law": (("cycloidal", "harmonic", "poly345", "poly4567", "dwell"), True), "span_deg": ("deg", True), "lift_mm": ("mm", False)}

OUTPUT_KEYS: Schema = {
    "formats": ("str_list", False),
    "chord_tol_mm": ("mm", False),
    "dxf_splines": (("biarc", "bspline"), False),  # default biarc: ARCs/LINEs within chord_tol_mm; bspline: exact SPLINEs
    "dxf_pitch": ("bool", False),
    "lift_step_deg": ("deg", False),
}

MACHINING_KEYS: Schema = {
    "tool_diameter_mm": ("mm", False),
    "step_down_mm": ("mm", False),
    "safe_z_mm": ("mm", False),
    "feed_mm_per_min": ("float", False),
    "plunge_feed_mm_per_min": ("float", False),
    "spindle_rpm": ("float", False),
    "direction": (("climb", "conventional"), False),
    "dialect": (("linuxcnc", "grbl"), False),
    "cutter_compensation": ("bool", False),
    "lead_mm": ("mm", False),
    "spline_mode": (("lines", "biarcs"), False),
    "decimals": ("int", False),
}

#: Mechanisms a scene may analyse, and their keys.
MECHANISMS: dict[str, Schema] = {
    "horse_leg": {
        "stride_cam": ("str", True),
        "height_cam": ("str", True),
        "inclinations_deg": ("float_list", False),
        "sweep_deg": ("float_list", False),
        "pressure_angle_limit_deg": ("deg", False),
        "ground_y_mm": ("mm", False),
        "positions": ("int", False),
    },
}

_NAME = re.compile(r"^[A-Za-z0-9_.-]{1,64}$")


@dataclass(frozen=True)
class CamSpec:
    """One cam of a scene: its name, kind and validated parameters (mm, rad; keys without unit suffix)."""

    name: str
    kind: str
    params: Mapping[str, Any]


@dataclass(frozen=True)
class OutputSpec:
    """What a run writes: formats, chord tolerance (mm) of flattened outputs, DXF and lift options."""

    formats: tuple[str, ...] = DEFAULT_FORMATS
    chord_tol: float = 1e-3
    dxf_splines: str = "biarc"
    dxf_pitch: bool = True
    lift_step: float = math.radians(1.0)


@dataclass(frozen=True)
class Scene:
    """A validated scene."""

    name: str
    source: str
    output: OutputSpec
    cams: tuple[CamSpec, ...] = field(default_factory=tuple)
    machining: Mapping[str, Any] = field(default_factory=dict)
    mechanisms: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)


def _check_keys(where: str, table: Mapping[str, Any], allowed: set[str], required: set[str] = frozenset()) -> None:
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise SceneError(f"{where}: unknown key(s) {', '.join(map(repr, unknown))}; allowed: {', '.join(sorted(allowed))}")
    missing = sorted(required - set(table))
    if missing:
        raise SceneError(f"{where}: missing key(s) {', '.join(map(repr, missing))}")


def _check_name(where: str, name: object) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise ParameterError(where, name, "1-64 characters of letters, digits, '_', '.', '-'", "used as a file name")
    return name


def _parse_value(key: str, kind: Any, value: object) -> object:
    if isinstance(kind, tuple):
        if value not in kind:
            raise ParameterError(key, value, f"one of {', '.join(kind)}")
        return value
    if kind in ("mm", "float"):
        return require_finite(key, value)
    if kind == "deg":
        return math.radians(require_finite(key, value))
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise ParameterError(key, value, "a whole number")
        return value
    if kind == "bool":
        if not isinstance(value, bool):
            raise ParameterError(key, value, "true or false")
        return value
    if kind == "str":
        if not isinstance(value, str):
            raise ParameterError(key, value, "a string")
        return value
    if kind == "segment_list":
        if not isinstance(value, list) or not value or not all(isinstance(v, dict) for v in value):
            raise ParameterError(key, value, "a list of [[segments]] tables (law, span_deg, lift_mm)")
        return tuple(_parse_table(f"{key}[{i}]", v, SEGMENT_KEYS) for i, v in enumerate(value))
    if kind == "float_list":
        if not isinstance(value, list) or not value:
            raise ParameterError(key, value, "a non-empty list of numbers")
        return tuple(require_finite(key, v) for v in value)
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ParameterError(key, value, "a list of strings")
    return tuple(value)


def _strip_unit(key: str) -> str:
    for suffix in ("_mm", "_deg"):
        if key.endswith(suffix):
            return key[: -len(suffix)]
    return key


def _parse_table(where: str, table: object, schema: Schema) -> dict[str, Any]:
    """Validate ``table`` against ``schema``; keys lose their unit suffix, degrees become radians."""
    if not isinstance(table, dict):
        raise SceneError(f"[{where}] must be a table")
    _check_keys(f"[{where}]", table, set(schema), {k for k, (_, req) in schema.items() if req})
    return {_strip_unit(k): _parse_value(f"{where}.{k}", schema[k][0], v) for k, v in table.items()}


def _parse_output(table: object) -> OutputSpec:
    if table is None:
        return OutputSpec()
    p = _parse_table("output", table, OUTPUT_KEYS)
    formats = p.get("formats", DEFAULT_FORMATS)
    bad = [f for f in formats if f not in FORMATS]
    if bad:
        raise ParameterError("output.formats", bad, f"formats from {sorted(FORMATS)}")
    chord_tol = require_positive("output.chord_tol_mm", p.get("chord_tol", 1e-3))
    if not 1e-7 <= chord_tol <= 1.0:
        raise ParameterError("output.chord_tol_mm", chord_tol, "1e-7 <= chord_tol_mm <= 1 mm")
    step = p.get("lift_step", math.radians(1.0))
    if not math.radians(0.01) <= step <= math.radians(10.0):
        raise ParameterError("output.lift_step_deg", math.degrees(step), "0.01 <= lift_step_deg <= 10")
    return OutputSpec(tuple(dict.fromkeys(formats)), chord_tol, p.get("dxf_splines", OutputSpec.dxf_splines), p.get("dxf_pitch", True), step)


def _parse_cam(name: str, table: object, base_dir: Path | None) -> CamSpec:
    where = f"cams.{name}"
    _check_name(where, name)
    if not isinstance(table, dict):
        raise SceneError(f"[{where}] must be a table")
    kind = table.get("kind")
    if kind not in CAM_KINDS:
        raise ParameterError(f"{where}.kind", kind, f"one of {sorted(CAM_KINDS)}")
    params = _parse_table(where, {k: v for k, v in table.items() if k != "kind"}, {**CAM_KINDS[kind], **BODY_KEYS})
    if kind == "trajectory":
        if ("expression" in params) == ("trajectory_csv" in params):
            raise SceneError(f"[{where}]: give exactly one of 'expression' (with 'period_mm') or 'trajectory_csv'")
        if "expression" in params and "period" not in params:
            raise SceneError(f"[{where}]: 'expression' needs 'period_mm'")
        if "trajectory_csv" in params:
            path = Path(params["trajectory_csv"])
            params["trajectory_csv"] = str(path if path.is_absolute() or base_dir is None else base_dir / path)
    if kind == "motion_law" and params.get("follower", "roller") not in ("roller", "flat"):
        raise ParameterError(f"{where}.follower", params["follower"], "roller or flat for a motion-law cam")
    return CamSpec(name, kind, params)


def parse_scene(data: Mapping[str, Any], name: str, source: str = "<memory>", base_dir: Path | None = None) -> Scene:
    """Validate a decoded TOML table and return a :class:`Scene` (``base_dir``: where relative file names point)."""
    _check_keys("scene", data, {"name", "output", "cams", "machining", "mechanisms"}, {"cams"})
    scene_name = _check_name("name", data.get("name", name))
    cams = data["cams"]
    if not isinstance(cams, dict) or not cams:
        raise SceneError("scene: [cams] must hold at least one [cams.<name>] table")
    machining = _parse_table("machining", data.get("machining", {}), MACHINING_KEYS)
    cam_specs = tuple(_parse_cam(k, v, base_dir) for k, v in cams.items())
    mechanisms_table = data.get("mechanisms", {})
    if not isinstance(mechanisms_table, dict):
        raise SceneError("[mechanisms] must be a table of [mechanisms.<kind>] tables")
    unknown = sorted(set(mechanisms_table) - set(MECHANISMS))
    if unknown:
        raise SceneError(f"[mechanisms]: unknown mechanism(s) {', '.join(map(repr, unknown))}; known: {', '.join(sorted(MECHANISMS))}")
    mechanisms = {k: _parse_table(f"mechanisms.{k}", v, MECHANISMS[k]) for k, v in mechanisms_table.items()}
    names = {c.name: c for c in cam_specs}
    for kind, params in mechanisms.items():
        for key in ("stride_cam", "height_cam"):
            if key in params and (params[key] not in names or names[params[key]].kind != "three_arc"):
                raise ParameterError(f"mechanisms.{kind}.{key}", params[key], f"the name of a three_arc cam of this scene: {sorted(n for n, c in names.items() if c.kind == 'three_arc')}")
    return Scene(scene_name, source, _parse_output(data.get("output")), cam_specs, machining, mechanisms)


def load_scene(path: str | Path, display: str | None = None) -> Scene:
    """Read and validate a scene file; ``display`` is how reports name it (default: ``path``).

    Raises
    ------
    SceneError
        If the file cannot be read or is not valid TOML, or does not follow the schema.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(f"cannot read scene file '{path}': {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise SceneError(f"scene file '{path}' is not UTF-8 text") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file '{path}' is not valid TOML: {exc}") from None
    return parse_scene(data, path.stem, display or str(path), path.parent)


def load_template(name: str) -> Scene:
    """Load a bundled template scene (``templates/<name>.toml``)."""
    return load_scene(template_path(name), display=f"templates/{name}.toml")


def template_dir() -> Path:
    """Folder of the bundled template scenes (package data ``camgen/templates``)."""
    from importlib.resources import files

    return Path(str(files("camgen.templates")))


def template_path(name: str) -> Path:
    """Path of a bundled template scene (``templates/<name>.toml``)."""
    path = template_dir() / f"{name}.toml"
    if not path.is_file():
        raise SceneError(f"no bundled template named '{name}'")
    return path
