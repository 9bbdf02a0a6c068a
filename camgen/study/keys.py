"""Scene keys named by their path, as a study names what it varies.

A key is written as camgen names it in its messages: ``cams.plate.base_radius_mm``,
``cams.plate.segments[2].lift_mm``, ``machining.tool_diameter_mm``; a bare key name
(``base_radius_mm``) names that key of the scene's only cam.  :func:`resolve_key` turns it
into the path of table keys and list indices in the decoded scene.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Mapping

from camgen.errors import ParameterError

__all__ = ["KEY_RULE", "KeyPath", "resolve_key"]

#: How a study names a scene key (the refusal of a key that is none says it).
KEY_RULE = ("a scene key's path as camgen names it: 'cams.<cam>.<key>', 'cams.<cam>.segments[<i>].<key>', "
            "'output.<key>', 'machining.<key>', 'mechanisms.<name>.<key>', or a bare key of the scene's only cam")
_STEP = re.compile(r"^([A-Za-z_][A-Za-z0-9_.-]*?)((?:\[\d+\])*)$")
_PART = re.compile(r"[A-Za-z0-9_-]+(?:\[\d+\])*")


@dataclass(frozen=True)
class KeyPath:
    """A scene key: ``name`` as the study shows it (canonical: ``cams.plate.base_radius_mm``) and
    ``path``, the table keys and list indices that reach it in the decoded scene."""

    name: str
    path: tuple[str | int, ...]


def _split(text: str) -> tuple[str | int, ...] | None:
    """``cams.x.segments[2].lift_mm`` -> ``('cams', 'x', 'segments', 2, 'lift_mm')`` (None: not a path)."""
    out: list[str | int] = []
    for part in text.split("."):
        if not _PART.fullmatch(part):
            return None
        head, *indices = part.replace("]", "").split("[")
        out.append(head)
        out.extend(int(i) for i in indices)
    return tuple(out)


def _name(path: tuple[str | int, ...]) -> str:
    text = ""
    for step in path:
        text += f"[{step}]" if isinstance(step, int) else (f".{step}" if text else step)
    return text


def resolve_key(data: Mapping[str, Any], key: str, option: str = "--vary") -> KeyPath:
    """The path of ``key`` in the decoded scene ``data``.

    The tables and lists on the way must exist (a list index within the list); the last key may
    be absent (a key left at its default): whether it is a key of that table at all is the scene
    schema's to say when the first point is read.

    Raises
    ------
    ParameterError
        Naming ``option`` and ``key`` when it is no path, its tables are not in the scene, or a
        bare key is given for a scene of several cams.
    """
    path = _split(key.strip()) if isinstance(key, str) else None
    if not path:
        raise ParameterError(option, key, KEY_RULE)
    if len(path) == 1:
        cams = data.get("cams")
        names = list(cams) if isinstance(cams, dict) else []
        if len(names) != 1:
            raise ParameterError(option, key, KEY_RULE, f"the scene has {len(names)} cams ({', '.join(names)}): name one, "
                                 f"e.g. 'cams.{names[0] if names else 'NAME'}.{key}'")
        path = ("cams", names[0], path[0])
    node: Any = data
    for i, step in enumerate(path[:-1]):
        where = _name(path[: i + 1])
        if isinstance(step, int):
            if not isinstance(node, list) or not 0 <= step < len(node):
                size = len(node) if isinstance(node, list) else 0
                raise ParameterError(option, key, KEY_RULE, f"'{_name(path[:i])}' has {size} entries, indices 0 to {size - 1}")
        elif not isinstance(node, dict) or step not in node:
            raise ParameterError(option, key, KEY_RULE, f"the scene has no table '{where}'")
        node = node[step]
    last = path[-1]
    if isinstance(last, int) or not isinstance(node, dict):
        raise ParameterError(option, key, KEY_RULE, "the path must end at a key of a table")
    if isinstance(node.get(last), (dict, list)):
        raise ParameterError(option, key, KEY_RULE, f"'{_name(path)}' is a table or list, not a value")
    return KeyPath(_name(path), path)
