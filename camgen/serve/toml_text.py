"""A decoded scene written back as TOML text (no comments): what ``POST /api/save`` returns when
the comment-keeping editor (``camgen.scene_edit.edit_scene_text``, the lead's) is not installed.

Tables in the order given; in each, its plain values first, then its sub-tables (``[cams.plate]``)
and arrays of tables (``[[cams.plate.segments]]``); a table inside a list is written inline.
Strings are TOML basic strings (JSON's escapes are TOML's: ``\\"``, ``\\\\``, ``\\n``, ``\\uXXXX``),
floats by ``repr`` (the shortest text that reads back to the same float; ``inf``/``nan`` as TOML's).
``tomllib.loads(scene_toml(data)) == data`` for every decoded scene.
"""
from __future__ import annotations

import json
import math
import re
from typing import Any, Mapping

from camgen.errors import SceneError

__all__ = ["scene_toml", "toml_key", "toml_value"]

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def toml_key(key: str) -> str:
    """``key`` bare where TOML allows it, else quoted."""
    return key if _BARE.match(key) else json.dumps(key, ensure_ascii=False)


def toml_value(value: Any, path: str = "scene") -> str:
    """One value as inline TOML (a table inside a list as an inline table)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v, f"{path}[{i}]") for i, v in enumerate(value)) + "]"
    if isinstance(value, Mapping):
        return "{" + ", ".join(f"{toml_key(str(k))} = {toml_value(v, f'{path}.{k}')}" for k, v in value.items()) + "}"
    raise SceneError(f"{path}: a value TOML cannot hold ({type(value).__name__})")


def _is_table_list(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, Mapping) for v in value)


def _table(lines: list[str], path: list[str], table: Mapping[str, Any]) -> None:
    plain = [(k, v) for k, v in table.items() if not isinstance(v, Mapping) and not _is_table_list(v)]
    for key, value in plain:
        lines.append(f"{toml_key(str(key))} = {toml_value(value, '.'.join(path + [str(key)]) or 'scene')}")
    for key, value in table.items():
        if isinstance(value, Mapping):
            sub = path + [str(key)]
            has_plain = any(not isinstance(v, Mapping) and not _is_table_list(v) for v in value.values())
            if has_plain or not value:  # a header only where it holds values (or the table is empty)
                lines.extend(["", f"[{'.'.join(toml_key(p) for p in sub)}]"])
            _table(lines, sub, value)
        elif _is_table_list(value):
            sub = path + [str(key)]
            for item in value:
                lines.extend(["", f"[[{'.'.join(toml_key(p) for p in sub)}]]"])
                _table(lines, sub, item)


def scene_toml(data: Mapping[str, Any]) -> str:
    """The TOML text of the decoded scene ``data``."""
    lines: list[str] = []
    _table(lines, [], data)
    return "\n".join(lines).lstrip("\n") + "\n"
