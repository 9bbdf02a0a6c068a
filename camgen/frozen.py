"""Canonical hashable forms of decoded scene values: the keys of the scene readers' caches.

A design study validates one scene per design, and most of its tables do not change from one
design to the next (a sweep over the base radius keeps the motion program, the output and the
machining tables).  The readers of those tables are pure functions of them, so they keep their
last results (``functools.lru_cache``, bounded) keyed by :func:`frozen`: the table's values with
their types, so that two tables have the same key only when every reader sees the same table:

* ``1``, ``1.0`` and ``True`` are equal in Python but read differently (a whole number, a
  number, a flag): each value is keyed with its type;
* ``0.0`` and ``-0.0`` are equal too: a zero float is keyed by its text, sign included;
* a dict keeps its order (a reader may name the first of several bad keys) and a
  :class:`camgen.schema.Parsed` its attributes (which keys were given, the tool limit).

A value with no hashable form (not a TOML type) raises :class:`Unfreezable`: the caller reads
it without its cache.  :class:`Keyed` carries a table into a cached reader under its frozen
form; :func:`fresh` copies a cached result's dicts and lists for each caller.
"""
from __future__ import annotations

from typing import Any, Hashable

__all__ = ["Keyed", "Unfreezable", "fresh", "frozen"]

#: Types keyed by type and value (equal values of these types are read the same).
_TAGGED = frozenset({int, bool, type(None)})


class Unfreezable(TypeError):
    """A value with no hashable form (the caller reads it without a cache)."""


def frozen(value: object) -> Hashable:
    """The canonical hashable form of a decoded TOML value or a parsed table: equal forms, equal
    values of equal types (module notes); raises :class:`Unfreezable` for any other value.  A
    frozenset is its own form (its items are hashable: a set of key names)."""
    kind = type(value)
    if kind is str:
        return value  # a str never equals the tuples of the other forms
    if kind is float:
        return (float, value) if value else (float, repr(value))  # 0.0 and -0.0 apart
    if kind in _TAGGED or kind is frozenset:
        return (kind, value)
    if isinstance(value, dict):
        items = tuple([(k, v if type(v) is str else frozen(v)) for k, v in value.items()])
        attrs = getattr(value, "__dict__", None)  # a dict subclass's own attributes (Parsed.given, .tool_limit)
        return (kind, items) if not attrs else (kind, items, tuple([(k, frozen(v)) for k, v in sorted(attrs.items())]))
    if kind is list or kind is tuple:
        return (kind, tuple([v if type(v) is str else frozen(v) for v in value]))  # type: ignore[attr-defined]
    try:
        hash(value)
    except TypeError:
        raise Unfreezable(f"no hashable form of a {kind.__name__}") from None
    return (kind, value)


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


def fresh(value: Any) -> Any:
    """A copy of a cached JSON-like ``value`` for one caller: its dicts and lists new (the caller
    may change them; a tuple's too), everything else shared (immutable)."""
    kind = type(value)
    if kind is dict:
        return {k: fresh(v) if type(v) in _COPIED else v for k, v in value.items()}
    if kind is list:
        return [fresh(v) if type(v) in _COPIED else v for v in value]
    if kind is tuple:
        return tuple([fresh(v) if type(v) in _COPIED else v for v in value])
    return value


#: The containers :func:`fresh` copies.
_COPIED = frozenset({dict, list, tuple})
