"""Scene files: schema, reading and validation.

A scene is a TOML file naming the cams to build and the outputs wanted.  Lengths carry
``_mm`` in their key, angles ``_deg`` (degrees only here, at the edge; radians inside).

.. code-block:: toml

    name = "default"                 # output folder name (default: the file's stem)

    [output]
    formats = ["dxf", "points"]      # see FORMATS
    chord_tol_mm = 0.001

    [cams.stride_length]
    kind = "three_arc"
    a_mm = 220.0
    b_mm = 160.0
    c_mm = 25.0

Reading never evaluates user text; unknown keys, wrong types and out-of-range values raise
:class:`~camgen.errors.SceneError` or :class:`~camgen.errors.ParameterError` naming the key.
"""
from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from camgen.errors import ParameterError, SceneError, require_finite, require_positive

#: Output formats a scene may request, and what each writes per cam.
FORMATS: dict[str, str] = {
    "dxf": "<cam>.dxf: 2-D profile, exact ARC entities, R2010, mm",
    "points": "<cam>_points.csv: XY point list at the chord tolerance",
}
DEFAULT_FORMATS = ("dxf", "points")

#: Cam kinds and their keys: kind -> {key: (type, required)}.  Types: "mm" (finite number, mm;
#: stored without the suffix), "int", "str", "str_list".
CAM_KINDS: dict[str, dict[str, tuple[str, bool]]] = {
    "three_arc": {"a_mm": ("mm", True), "b_mm": ("mm", True), "c_mm": ("mm", True), "source": ("str", False)},
    "trajectory": {
        "expression": ("str", False),
        "trajectory_csv": ("str", False),
        "period_mm": ("mm", False),
        "samples": ("int", False),
        "curvature": ("str", False),
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
}

_NAME = re.compile(r"^[A-Za-z0-9_.-]{1,64}$")


@dataclass(frozen=True)
class CamSpec:
    """One cam of a scene: its name, kind and validated parameters (mm, rad)."""

    name: str
    kind: str
    params: Mapping[str, Any]


@dataclass(frozen=True)
class OutputSpec:
    """What a run writes: formats and the chord tolerance (mm) of every flattened output."""

    formats: tuple[str, ...] = DEFAULT_FORMATS
    chord_tol: float = 1e-3


@dataclass(frozen=True)
class Scene:
    """A validated scene."""

    name: str
    source: str
    output: OutputSpec
    cams: tuple[CamSpec, ...] = field(default_factory=tuple)


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


def _parse_output(table: object) -> OutputSpec:
    if table is None:
        return OutputSpec()
    if not isinstance(table, dict):
        raise SceneError("[output] must be a table")
    _check_keys("[output]", table, {"formats", "chord_tol_mm"})
    formats = table.get("formats", list(DEFAULT_FORMATS))
    if not isinstance(formats, list) or not all(isinstance(f, str) for f in formats):
        raise ParameterError("output.formats", formats, f"a list of strings from {sorted(FORMATS)}")
    bad = [f for f in formats if f not in FORMATS]
    if bad:
        raise ParameterError("output.formats", bad, f"formats from {sorted(FORMATS)}")
    chord_tol = require_positive("output.chord_tol_mm", table.get("chord_tol_mm", 1e-3))
    if not 1e-7 <= chord_tol <= 1.0:
        raise ParameterError("output.chord_tol_mm", chord_tol, "1e-7 <= chord_tol_mm <= 1 mm")
    return OutputSpec(tuple(dict.fromkeys(formats)), chord_tol)


def _parse_value(key: str, kind: str, value: object) -> object:
    if kind == "mm":
        return require_finite(key, value)
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, int):
            raise ParameterError(key, value, "a whole number")
        return value
    if kind == "str":
        if not isinstance(value, str):
            raise ParameterError(key, value, "a string")
        return value
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ParameterError(key, value, "a list of strings")
    return tuple(value)


def _parse_cam(name: str, table: object, base_dir: Path | None) -> CamSpec:
    where = f"cams.{name}"
    _check_name(where, name)
    if not isinstance(table, dict):
        raise SceneError(f"[{where}] must be a table")
    kind = table.get("kind")
    if kind not in CAM_KINDS:
        raise ParameterError(f"{where}.kind", kind, f"one of {sorted(CAM_KINDS)}")
    schema = CAM_KINDS[kind]
    _check_keys(f"[{where}]", table, {"kind", *schema}, {k for k, (_, req) in schema.items() if req})
    params: dict[str, Any] = {}
    for key, (typ, _) in schema.items():
        if key in table:
            value = _parse_value(f"{where}.{key}", typ, table[key])
            params[key[:-3] if typ == "mm" else key] = value
    if kind == "trajectory":
        if ("expression" in params) == ("trajectory_csv" in params):
            raise SceneError(f"[{where}]: give exactly one of 'expression' (with 'period_mm') or 'trajectory_csv'")
        if "expression" in params and "period" not in params:
            raise SceneError(f"[{where}]: 'expression' needs 'period_mm'")
        if "trajectory_csv" in params:
            path = Path(params["trajectory_csv"])
            params["trajectory_csv"] = str(path if path.is_absolute() or base_dir is None else base_dir / path)
    return CamSpec(name, kind, params)


def parse_scene(data: Mapping[str, Any], name: str, source: str = "<memory>", base_dir: Path | None = None) -> Scene:
    """Validate a decoded TOML table and return a :class:`Scene` (``base_dir``: where relative file names point)."""
    _check_keys("scene", data, {"name", "output", "cams"}, {"cams"})
    scene_name = _check_name("name", data.get("name", name))
    cams = data["cams"]
    if not isinstance(cams, dict) or not cams:
        raise SceneError("scene: [cams] must hold at least one [cams.<name>] table")
    return Scene(scene_name, source, _parse_output(data.get("output")), tuple(_parse_cam(k, v, base_dir) for k, v in cams.items()))


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
    """Folder of the bundled template scenes: ``templates/`` of a source checkout, else the
    installed ``camgen.templates`` package data."""
    checkout = Path(__file__).resolve().parent.parent / "templates"
    if (checkout / "default.toml").is_file():
        return checkout
    from importlib.resources import files

    return Path(str(files("camgen.templates")))


def template_path(name: str) -> Path:
    """Path of a bundled template scene (``templates/<name>.toml``)."""
    path = template_dir() / f"{name}.toml"
    if not path.is_file():
        raise SceneError(f"no bundled template named '{name}'")
    return path
