"""The design-check report: ``report.json`` (machine-readable).

Layout (:data:`REPORT_SCHEMA`)::

    {"scene": str, "camgen_version": str, "source_file": str, "chord_tol_mm": float,
     "status": "pass" | "fail", "stages": [str, ...], "files": [str, ...],
     "cams": {name: {"kind": str, "form": str, "manufacturable": bool, "withheld_files": [str, ...],
              "figures": {..., "dynamics": {...}},
              "checks": [{"name", "status": "pass" | "fail" | "info", "value", "limit",
                          "comparison", "unit", "where_deg", "note", "blocks_manufacture"}, ...]}},
     "mechanisms": {...},
     "tables": {"<file>.csv": {"content": str, "columns": {column: str}, "cam" | "mechanism": str, ...}}}

``tables`` describes every CSV the run writes (the CSVs hold only a header row and numbers):
what it holds, each column's meaning and unit, and the settings it was made with
(:mod:`camgen.export.tablemeta`).

A check passes when ``value comparison limit`` holds (``"<="``, ``"<"``, ``">="``, ``">"``,
``"at least"`` for continuity levels); ``"info"`` checks have no limit and never pass or fail.
``status`` is "fail" when any check failed (the run's exit status is then 1).  Keys carry
their unit (``_mm``, ``_deg``, ``_mm2``, ``_s``); numbers are finite.

``figures.dynamics`` (cams with a follower train, :mod:`camgen.kinds.dynamics`): the cam speed,
the smallest and largest contact force (N) and where, the camshaft torque's peak and RMS (N*m)
and where it peaks, the power's peak, RMS and mean (W), the work per turn (J); force-closed
trains: the jump speed (rpm, null: never), the jump margin (N), the cam-angle ranges where the
follower leaves the cam, the smallest preload and spring rate that keep the margin at this
speed (translating N and N/mm, oscillating N*mm and N*mm/rad); form-closed ones (a yoke): the
largest force on each face; with a contact material: the peak Hertz stress (MPa) and where.
"""
from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from camgen.errors import ExportError

if TYPE_CHECKING:
    from camgen.report.model import JsonValue, ReportInput

__all__ = ["REPORT_SCHEMA", "report_dict", "report_json"]

_CHECK = {
    "type": "object",
    "required": ["name", "status", "value", "limit", "comparison", "unit", "note", "blocks_manufacture"],
    "properties": {
        "name": {"type": "string"},
        "status": {"enum": ["pass", "fail", "info"]},
        "value": {"type": ["number", "string"]},
        "limit": {"type": ["number", "string", "null"]},
        "comparison": {"enum": ["<=", "<", ">=", ">", "at least", ""]},
        "unit": {"type": "string"},
        "where_deg": {"type": "array", "items": {"type": "number", "minimum": 0, "maximum": 360}},
        "where_mm": {"type": "array", "items": {"type": "number"}},  # a linear cam's plate travel
        "note": {"type": "string"},
        "blocks_manufacture": {"type": "boolean"},
    },
    "additionalProperties": False,
    "oneOf": [{"required": ["where_deg"]}, {"required": ["where_mm"]}],  # angles, or a linear cam's travel
    # information has no limit; a limited check states how the value must compare with it
    "if": {"properties": {"status": {"const": "info"}}},
    "then": {"properties": {"limit": {"type": "null"}, "comparison": {"const": ""}}},
    "else": {"properties": {"limit": {"type": ["number", "string"]}, "comparison": {"enum": ["<=", "<", ">=", ">", "at least"]}}},
}
_NUMBERS = {"type": "object", "additionalProperties": {"type": ["number", "string", "boolean", "array", "object"]}}
_ANGLE = {"type": "number", "minimum": 0, "maximum": 360}
_DYNAMICS = {
    "type": "object",
    "required": ["closure", "follower_motion", "rpm", "min_contact_force_N", "max_contact_force_N", "max_contact_force_deg",
                 "torque_peak_Nm", "torque_rms_Nm", "torque_peak_deg", "power_peak_W", "power_rms_W", "mean_power_W",
                 "energy_per_turn_J"],
    "properties": {
        "closure": {"enum": ["force", "form"]},
        "follower_motion": {"enum": ["translating", "oscillating"]},
        "rpm": {"type": "number", "exclusiveMinimum": 0},
        "jump_rpm": {"type": ["number", "null"], "minimum": 0},
        "jump_ranges_deg": {"type": "array", "items": _ANGLE},
        "max_contact_force_deg": _ANGLE, "min_contact_force_deg": _ANGLE, "torque_peak_deg": _ANGLE, "hertz_stress_peak_deg": _ANGLE,
        "hertz_stress_peak_MPa": {"type": "number", "minimum": 0},
    },
    "additionalProperties": {"type": ["number", "string", "null", "array"]},
    # a spring-loaded train states its jump speed and the spring that keeps the margin; a yoke its two faces' forces
    "if": {"properties": {"closure": {"const": "force"}}},
    "then": {"required": ["jump_rpm", "jump_margin_N", "jump_ranges_deg"]},
    "else": {"required": ["max_contact_force_1_N", "max_contact_force_2_N"]},
}

_TABLE = {
    "type": "object",
    "required": ["content", "columns"],
    "properties": {
        "content": {"type": "string"},
        "columns": {"type": "object", "minProperties": 1, "propertyNames": {"pattern": "^[a-z][a-z0-9_]*$"},
                    "additionalProperties": {"type": "string"}},
        "cam": {"type": "string"},
        "mechanism": {"type": "string"},
    },
    "oneOf": [{"required": ["cam"]}, {"required": ["mechanism"]}],
    "additionalProperties": {"type": ["number", "string", "array"]},
}

#: The documented layout of report.json, as a JSON Schema (draft 2020-12).
REPORT_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "type": "object",
    "required": ["scene", "camgen_version", "status", "stages", "files", "cams", "mechanisms", "tables"],
    "properties": {
        "scene": {"type": "string"},
        "camgen_version": {"type": "string"},
        "source_file": {"type": "string"},
        "chord_tol_mm": {"type": "number", "exclusiveMinimum": 0},
        "status": {"enum": ["pass", "fail"]},
        "stages": {"type": "array", "items": {"enum": ["analysis", "plots", "mesh"]}},
        "files": {"type": "array", "items": {"type": "string"}},
        "cams": {
            "type": "object",
            "additionalProperties": {
                "type": "object",
                "required": ["kind", "form", "manufacturable", "withheld_files", "figures", "checks"],
                "properties": {
                    "kind": {"type": "string"},
                    "form": {"type": "string"},
                    "manufacturable": {"type": "boolean"},
                    "withheld_files": {"type": "array", "items": {"type": "string"}},
                    "figures": {**_NUMBERS, "properties": {"dynamics": _DYNAMICS}},
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
                    "required": ["grashof_margin_mm"],
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
        "tables": {"type": "object", "propertyNames": {"pattern": "\\.csv$"}, "additionalProperties": _TABLE},
    },
    "additionalProperties": False,
}


def report_dict(report: "ReportInput") -> dict[str, "JsonValue"]:
    """report.json's object for ``report`` (:data:`REPORT_SCHEMA`)."""
    return {
        "scene": report.scene,
        "camgen_version": report.camgen_version,
        "source_file": report.source_file,
        "chord_tol_mm": report.chord_tol_mm,
        "status": "fail" if report.failed else "pass",
        "stages": list(report.stages),
        "files": list(report.files),
        "cams": {
            cam.name: {"kind": cam.kind, "form": cam.form, "manufacturable": cam.manufacturable, "withheld_files": list(cam.withheld_files),
                       "figures": cam.figures, "checks": [c.as_json() for c in cam.checks]}
            for cam in report.cams
        },
        "mechanisms": {m.name: m.figures for m in report.mechanisms},
        "tables": report.tables,
    }


def _plain(value: Any, where: str) -> Any:
    """Convert numpy scalars/arrays to plain JSON types; refuse NaN and infinity."""
    if isinstance(value, Mapping):  # a dict, or a stage's read-only figures
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


def report_json(report: Mapping[str, Any]) -> str:
    """Deterministic JSON text of ``report`` (keys in the order given, 2-space indent)."""
    return json.dumps(_plain(report, "report"), indent=2, allow_nan=False) + "\n"
