"""The scene schema as JSON for the live page (``GET /api/schema``).

Built from the :class:`camgen.schema.Key` objects of the registries (the kinds with their forms,
the followers a form takes, the ``[output]`` and ``[machining]`` tables), walked as
:mod:`camgen.keyref` walks them for ``camgen keys``: the page's form shows the same keys, units,
ranges and help as the key reference.
"""
from __future__ import annotations

import math
from typing import Any, Sequence

from camgen.schema import Choice, ChoiceList, Count, Flag, Key, Number, NumberList, TableList, Text, ValueType

__all__ = ["NO_FOLLOWER", "key_json", "schema_json"]

#: The follower entry of a cam type whose table has no ``follower`` key (a barrel, a trajectory
#: cam): every key of the type is listed under this name.
NO_FOLLOWER = ""

#: Longest help text sent per key, characters (the first sentence is the one-line help).
MAX_HELP = 300


def _type_name(value_type: ValueType) -> str:
    """The contract's type name of a schema value type."""
    if isinstance(value_type, Number):
        return "float"
    if isinstance(value_type, Count):
        return "int"
    if isinstance(value_type, Flag):
        return "bool"
    if isinstance(value_type, Choice):
        return "choice"
    if isinstance(value_type, Text):
        return "text"
    if isinstance(value_type, TableList):
        return "table"
    return "list"  # ChoiceList, NumberList, rows of numbers


def _unit(value_type: ValueType) -> str:
    if isinstance(value_type, Number):
        return value_type.unit
    if isinstance(value_type, NumberList):
        return value_type.item.unit
    if isinstance(value_type, Count):
        return value_type.unit
    return ""


def _choices(value_type: ValueType) -> list[str] | None:
    if isinstance(value_type, (Choice, ChoiceList)):
        return list(value_type.values)
    return None


def _json_value(value: Any) -> Any:
    """A default in scene units as JSON (a non-finite float as null: JSON has none)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, (list, tuple)):
        return [_json_value(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _json_value(v) for k, v in value.items()}
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return str(value)


def _help(doc: str) -> str:
    """The key's help in one line: its doc's first sentence, at most :data:`MAX_HELP` characters."""
    line = " ".join(doc.split())
    end = line.find(". ")
    first = line if end < 0 else line[: end + 1]
    return first if len(first) <= MAX_HELP else first[: MAX_HELP - 3] + "..."


def key_json(key: Key) -> dict[str, Any]:
    """One key as the page reads it: name, type, unit, range (as ``camgen keys`` prints it),
    default (scene units; null: none or required), choices, one-line help; a table list also
    ``keys``, the keys of each of its tables."""
    out: dict[str, Any] = {
        "name": key.name, "type": _type_name(key.type), "unit": _unit(key.type), "range": key.type.describe(),
        "default": None if key.required else _json_value(key.default), "required": key.required,
        "choices": _choices(key.type), "help": _help(key.doc),
        "requires": {other: _json_value(list(values)) for other, values in key.requires.items()},
    }
    if isinstance(key.type, TableList):
        out["keys"] = [key_json(k) for k in key.type.keys]
    return out


def _followers(keys: Sequence[Key]) -> dict[str, list[dict[str, Any]]]:
    """The keys of a cam type per follower it takes: a key that requires other followers is left
    out of a follower's list."""
    follower = next((k for k in keys if k.name == "follower"), None)
    if follower is None or not isinstance(follower.type, Choice):
        return {NO_FOLLOWER: [key_json(k) for k in keys]}
    return {name: [key_json(k) for k in keys if name in k.requires.get("follower", (name,))] for name in follower.type.values}


def schema_json() -> dict[str, Any]:
    """``{"kinds": {KIND: {"forms": {FORM: {"followers": {FOLLOWER: [KEY, ...]}}}, "default_form": FORM}},
    "segment_keys": [KEY, ...], "top": {"output": [KEY, ...], "machining": [KEY, ...]}}``; a
    KEY is :func:`key_json`."""
    from camgen.kinds import forms_of, get_kind, kind_names
    from camgen.motions import get_motion
    from camgen.outputs import machining_keys, output_keys

    kinds: dict[str, Any] = {}
    segment_keys: list[dict[str, Any]] = []
    for name in kind_names():
        forms = {}
        for form in forms_of(name):
            keys = get_kind(name, form).keys
            forms[form] = {"followers": _followers(keys)}
            segments = next((k for k in keys if k.name == "segments" and isinstance(k.type, TableList)), None)
            if segments is not None and not segment_keys:
                segment_keys = [key_json(k) for k in segments.type.keys] if isinstance(segments.type, TableList) else []
        kinds[name] = {"forms": forms, "default_form": get_motion(name).default_form}
    return {"kinds": kinds, "segment_keys": segment_keys,
            "top": {"output": [key_json(k) for k in output_keys()], "machining": [key_json(k) for k in machining_keys()]}}
