"""Internal parameter names back to scene keys, from the schema: one helper for every table.

A spec built from a parsed table (a follower, a body, a follower train, the machining settings)
validates its own parameters and names them as it knows them (``offset``, ``bore_diameter``);
the user needs the scene key (``cams.x.follower_offset_mm``).  Each :class:`~camgen.schema.Key`
knows its scene name, the field it is stored under and the other internal names it feeds
(:attr:`~camgen.schema.Key.feeds`), so the table's keys are the whole map: no module keeps a
map of its own.
"""
from __future__ import annotations

from typing import Callable, Sequence, TypeVar

from camgen.errors import ParameterError
from camgen.schema import Key

__all__ = ["renamed", "scene_key"]

T = TypeVar("T")


def scene_key(keys: Sequence[Key], internal: str) -> str:
    """The scene key of ``keys`` that the internal parameter ``internal`` comes from.

    A key matches by its field (``a_mm`` -> ``a``) or by a name it feeds; two keys feeding one
    parameter are named together (``pivot_x_mm/pivot_y_mm``).  A name no key gives is returned
    as it is (a parameter the scene does not set: the error names it so the message still says
    what is wrong).
    """
    return _matching(keys, internal) or internal


def _matching(keys: Sequence[Key], internal: str) -> str | None:
    """The scene name(s) of the keys of ``keys`` that give ``internal``, or None."""
    names = [k.name for k in keys if k.field == internal or internal in k.feeds]
    return "/".join(dict.fromkeys(names)) if names else None


def renamed(where: str, keys: Sequence[Key], make: Callable[[], T], also: Sequence[tuple[str, Sequence[Key]]] = ()) -> T:
    """Call ``make``; a :class:`ParameterError` naming an internal parameter, bare or under
    ``where``, is re-raised naming its scene key under ``where`` (``cams.x`` + ``bore_diameter``
    -> ``cams.x.bore_diameter_mm``; ``cams.x.segments[0]`` + ``cams.x.segments[0].span`` ->
    ``cams.x.segments[0].span_deg``); any other scene path passes unchanged.

    ``also``: other tables ``(where, keys)`` the spec takes values from, searched when ``keys``
    has none for the name (the machining spec's ``chord_tol`` is ``output.chord_tol_mm``).
    """
    try:
        return make()
    except ParameterError as exc:
        internal = exc.name.removeprefix(f"{where}.")
        if "." in internal:  # a scene path already (of a table within this one, or another)
            raise
        path = f"{where}.{internal}"
        for table, table_keys in ((where, keys), *also):
            key = _matching(table_keys, internal)
            if key is not None:
                path = f"{table}.{key}"
                break
        raise ParameterError(path, exc.value, exc.valid, exc.why) from None
