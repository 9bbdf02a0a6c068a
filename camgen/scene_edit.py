"""Scene text edited in place: new values written into a scene's TOML with its comments kept.

A design study (``camgen sweep``, ``camgen optimize``) and the live page (``camgen serve``) change
values of a scene and hand the designer a scene file back.  :func:`edit_scene_text` writes the
decoded table ``data`` into the original text through tomlkit (a style-preserving TOML library):
every comment and blank line of a key that is still there stays where it was, a changed value
keeps its line's trailing comment, keys and tables that are gone are removed, new ones are
added at the end of their table.  The result is read back with :mod:`tomllib`; if it does not
decode to ``data`` (a layout tomlkit cannot edit), the scene is written afresh without comments
(:func:`scene_text`), so the text always holds exactly ``data``.
"""
from __future__ import annotations

import tomllib
from typing import TYPE_CHECKING, Any, Mapping

if TYPE_CHECKING:
    from tomlkit.container import Container
    from tomlkit.items import AoT, Table

__all__ = ["edit_scene_text", "scene_text", "set_value"]


def scene_text(data: Mapping[str, Any]) -> str:
    """``data`` (a decoded scene) as TOML text, tables in the order given (no comments)."""
    import tomlkit

    return tomlkit.dumps(dict(data))


def _is_table_list(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _replace(table: "Container | Table", key: str, value: Any) -> None:
    """``table[key] = value``, the old value's trailing comment kept on a scalar."""
    import tomlkit
    from tomlkit.items import Item

    old = table.get(key)
    item = tomlkit.item(value)
    if isinstance(old, Item) and old.trivia.comment and not isinstance(value, (dict, list)):
        item.trivia.comment = old.trivia.comment
        # the comment stays in its column: the gap shrinks or grows by the value's change in width
        width = len(old.as_string()) + len(old.trivia.comment_ws)
        item.trivia.comment_ws = " " * max(1, width - len(item.as_string()))
    table[key] = item


def _update(table: "Container | Table", new: Mapping[str, Any]) -> None:
    """Make ``table`` hold ``new``: unchanged items untouched, changed ones replaced in place."""
    from tomlkit.items import AoT, Table

    for key in [k for k in table if k not in new]:
        del table[key]
    for key, value in new.items():
        old = table.get(key)
        if isinstance(value, dict) and isinstance(old, Table):
            _update(old, value)
        elif _is_table_list(value) and isinstance(old, AoT):
            _update_list(old, value)
        elif key not in table or _plain(old) != value:
            _replace(table, key, value)


def _update_list(tables: "AoT", new: list[dict[str, Any]]) -> None:
    """An array of tables (``[[cams.x.segments]]``) made to hold ``new``: common entries edited
    in place, extra ones removed from the end, new ones appended."""
    while len(tables) > len(new):
        del tables[len(tables) - 1]
    for old, value in zip(list(tables), new):
        _update(old, value)
    for value in new[len(tables):]:
        tables.append(_table(value))


def _table(value: Mapping[str, Any]) -> "Table":
    import tomlkit

    table = tomlkit.table()
    table.trivia.indent = "\n"  # a blank line before it, as between the others
    for key, item in value.items():
        table[key] = item
    return table


def _plain(item: Any) -> Any:
    """A tomlkit item as plain Python values (for comparison)."""
    unwrap = getattr(item, "unwrap", None)
    return unwrap() if unwrap is not None else item


def edit_scene_text(text: str, data: Mapping[str, Any]) -> str:
    """``text`` (a scene's TOML) edited to hold ``data``, its comments kept where their keys are.

    Parameters
    ----------
    text : the original scene text (TOML).
    data : the scene as a decoded table (what :func:`tomllib.loads` of the result must give).

    Returns
    -------
    The new TOML text; decoding it gives ``data`` exactly (checked).
    """
    import tomlkit
    from tomlkit.exceptions import TOMLKitError

    try:
        document = tomlkit.parse(text)
        _update(document, data)
        edited = tomlkit.dumps(document)
        if tomllib.loads(edited) == dict(data):
            return edited
    except (TOMLKitError, tomllib.TOMLDecodeError, ValueError, KeyError, TypeError):
        pass
    fresh = scene_text(data)
    assert tomllib.loads(fresh) == dict(data), "a scene table TOML cannot hold"
    return fresh


def set_value(data: Mapping[str, Any], path: tuple[str | int, ...], value: Any) -> dict[str, Any]:
    """A copy of the decoded scene ``data`` with the value at ``path`` (table keys and list
    indices, e.g. ``("cams", "plate", "segments", 0, "lift_mm")``) set to ``value``; the tables
    and lists on the path are copied, the rest shared (``data`` is not changed)."""
    out: dict[str, Any] = dict(data)
    node: Any = out
    for i, step in enumerate(path[:-1]):
        child = node[step]
        child = dict(child) if isinstance(child, dict) else list(child)
        node[step] = child
        node = child
    node[path[-1]] = value
    return out
