"""Canonical hashable forms of decoded scene values: the keys of the scene readers' caches.

A design study validates one scene per design, and most of its tables do not change from one
design to the next (a sweep over the base radius keeps the motion program, the output and the
machining tables).  The readers of those tables are pure functions of them, so they keep their
last results (``functools.lru_cache``, bounded) keyed by :func:`frozen`: the table's pickle
(:mod:`pickle`, the highest protocol), which holds every value with its type, so that two tables
have the same key only when every reader sees the same table:

* ``1``, ``1.0`` and ``True`` are equal in Python but read differently (a whole number, a
  number, a flag): pickle writes each with its type;
* ``0.0`` and ``-0.0`` are equal too: pickle writes a float's 8 bytes, its sign included;
* a dict keeps its order (a reader may name the first of several bad keys) and a
  :class:`camgen.schema.Parsed` its attributes (which keys were given, the tool limit).

Equal bytes are equal values of equal types (pickle reads them back); equal values may have
different bytes (a set's order, an object shared twice), which costs a cache miss, never a wrong
hit.  A value pickle cannot write raises :class:`Unfreezable`: the caller reads it without its
cache.  :class:`Keyed` carries a table into a cached reader under its frozen form; :func:`fresh`
copies a cached result's dicts and lists for each caller.
"""
from __future__ import annotations

import pickle
from typing import Any

__all__ = ["Copies", "Keyed", "Unfreezable", "frozen"]


class Unfreezable(TypeError):
    """A value with no hashable form (the caller reads it without a cache)."""


def frozen(value: object) -> bytes:
    """The canonical hashable form of a decoded TOML value or a parsed table: its pickle (equal
    forms: equal values of equal types, module notes); raises :class:`Unfreezable` for a value
    pickle cannot write."""
    try:
        return pickle.dumps(_shallow(value), pickle.HIGHEST_PROTOCOL)
    except Exception as exc:  # pickle's errors: PicklingError, TypeError, AttributeError, RecursionError ...
        raise Unfreezable(f"no hashable form of a {type(value).__name__}: {type(exc).__name__}") from None


#: Marks a dict subclass written as its class's name, items and attributes (no parsed value is a
#: tuple starting with this text and a class name).
_DICT_SUBCLASS = "camgen.frozen: a dict subclass"


def _shallow(value: object) -> object:
    """``value`` with a dict subclass at the top or one level down in a list or tuple written as
    (marker, its class's name, its items as a dict, its attributes): the same information as its
    pickle (a :class:`camgen.schema.Parsed`'s ``__reduce__``), in fewer steps.  Deeper ones are
    pickled as they are."""
    kind = type(value)
    if isinstance(value, (tuple, list)) and (kind is tuple or kind is list):
        items = [_shallow(v) if isinstance(v, dict) and type(v) is not dict else v for v in value]
        return tuple(items) if kind is tuple else items
    if isinstance(value, dict) and kind is not dict:
        return (_DICT_SUBCLASS, f"{kind.__module__}.{kind.__qualname__}", dict(value), getattr(value, "__dict__", None))
    return value


class Keyed:
    """``value`` under the key :func:`frozen` of it: equal and hashed by that key only, so that a
    ``functools.lru_cache`` reader keyed by it reads ``value`` on a miss (raises
    :class:`Unfreezable` where ``value`` has no hashable form)."""

    __slots__ = ("value", "key", "_hash")

    def __init__(self, value: Any) -> None:
        self.value = value
        self.key = frozen(value)
        self._hash = hash(self.key)

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Keyed) and self._hash == other._hash and self.key == other.key


class Copies:
    """A JSON-like value (dicts, lists, numbers, text) kept as its pickle: :meth:`copy` is a new
    deep copy of it each time, so a cached result's figures are each caller's own (the caller may
    change them; the cache's stay as they were made)."""

    __slots__ = ("_pickle",)

    def __init__(self, value: Any) -> None:
        self._pickle = pickle.dumps(value, pickle.HIGHEST_PROTOCOL)

    def copy(self) -> Any:
        return pickle.loads(self._pickle)
