"""The design-check report: ``report.json`` (machine-readable).

Layout::

    {"scene": str, "camgen_version": str, "source_file": str, "chord_tol_mm": float,
     "files": [str, ...],
     "cams": {name: {"kind": str, "figures": {...}, "checks": [{"name", "passed", "value",
              "limit", "unit", "where_deg", "note"}, ...]}},
     "mechanisms": {...}}

Keys carry their unit (``_mm``, ``_deg``, ``_mm2``, ``_s``); numbers are finite.
"""
from __future__ import annotations

import json
import math
from typing import Any, Sequence

from camgen.errors import ExportError

_CHECK = {
    "type": "object",
    "required": ["name", "passed", "value", "limit", "unit", "where_deg", "note"],
    "properties": {
        "name": {"type": "string"},
        "passed": {"type": "boolean"},
        "value": {"type": ["number", "string"]},
        "limit": {"type": ["number", "string"]},
        "unit": {"type": "string"},
        "where_deg": {"type": "array", "items": {"type": "number", "minimum": 0, "maximum": 360}},
        "note": {"type": "string"},
    },
    "additionalProperties": False,
}
_NUMBERS = {"type": "object", "additionalProperties": {"type": ["number", "string", "boolean", "array", "object"]}}

#: The documented layout of report.json, as a JSON Schema (draft 2020-12).
REPORT_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "type": "object",
    "required": ["scene", "camgen_version", "cams", "mechanisms"],
    "properties": {
        "scene": {"type": "string"},
        "camgen_version": {"type": "string"},
        "source_file": {"type": "string"},
        "chord_tol_mm": {"type": "number", "exclusiveMinimum": 0},
        "files": {"type": "array", "items": {"type": "string"}},
        "cams": {
            "type": "object",
            "additionalProperties": {
                "type": "object",
                "required": ["kind", "figures", "checks"],
                "properties": {
                    "kind": {"enum": ["three_arc", "trajectory", "motion_law"]},
                    "figures": _NUMBERS,
                    "checks": {"type": "array", "items": _CHECK},
                },
                "additionalProperties": False,
            },
        },
        "mechanisms": {
            "type": "object",
            "properties": {
                "horse_leg": {
                    "type": "object",
                    "required": ["grashof_margin_mm", "sweep"],
                    "patternProperties": {
                        "^alpha_": {
                            "type": "object",
                            "required": ["lift_mm", "leg_horizontal_mm", "body_height_change_mm", "body_horizontal_mm",
                                         "stride_mm", "max_pressure_angle_deg", "grashof_margin_mm"],
                        }
                    },
                }
            },
        },
    },
    "additionalProperties": False,
}


def report_dict(scene: Any, cams: Sequence[Any], files: Sequence[str], mechanisms: dict | None = None) -> dict[str, Any]:
    """Assemble the report for a run of ``scene`` that built ``cams`` and writes ``files``."""
    from camgen import __version__

    return {
        "scene": scene.name,
        "camgen_version": __version__,
        "source_file": scene.source,
        "chord_tol_mm": scene.output.chord_tol,
        "files": list(files),
        "cams": {
            cam.name: {"kind": cam.kind, "figures": cam.figures, "checks": [c.as_dict() for c in cam.checks]}
            for cam in cams
        },
        "mechanisms": mechanisms or {},
    }


def _plain(value: Any, where: str) -> Any:
    """Convert numpy scalars/arrays to plain JSON types; refuse NaN and infinity."""
    if isinstance(value, dict):
        return {str(k): _plain(v, f"{where}.{k}") for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if hasattr(value, "tolist"):
        return _plain(value.tolist(), where)
    if isinstance(value, bool) or value is None or isinstance(value, (str, int)):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ExportError(f"report value {where} = {value} is not finite")
        return value
    raise ExportError(f"report value {where} has unsupported type {type(value).__name__}")


def report_json(report: dict[str, Any]) -> str:
    """Deterministic JSON text of ``report`` (sorted keys inside figures, 2-space indent)."""
    return json.dumps(_plain(report, "report"), indent=2, allow_nan=False) + "\n"
