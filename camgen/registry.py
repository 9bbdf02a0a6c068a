"""One registry implementation for the axes of a cam (motions, forms, followers).

A registry maps names to the modules that define its entries (one module per entry, imported
when first asked for) and holds the entries registered from outside the package (plug-ins,
tests).  Each axis keeps its own module (:mod:`camgen.motions`, :mod:`camgen.forms`,
:mod:`camgen.followers`) with its table of modules; this is the lookup they share.
"""
from __future__ import annotations

import importlib
import sys
from typing import Generic, Mapping, Protocol, TypeVar

__all__ = ["Named", "Registry", "generation"]


class Named(Protocol):
    @property
    def name(self) -> str: ...


E = TypeVar("E", bound=Named)

#: How many times an entry was registered or removed, in any registry of this process (each
#: :meth:`Registry.register` / :meth:`Registry.unregister` adds one): what is composed from the
#: registries' entries (:func:`camgen.kinds.get_kind`) stays valid while it is unchanged.
_GENERATION = 0


def generation() -> int:
    """The registries' state stamp: changes whenever an entry is registered or removed in any
    registry (the package's own entries, imported on first use, never change)."""
    return _GENERATION


def _changed() -> None:
    global _GENERATION
    _GENERATION += 1


class Registry(Generic[E]):
    """Entries by name: ``modules`` (name -> module exposing ``attribute``), then the registered ones.

    Parameters
    ----------
    modules : the package's own entries, name -> module path (kept by reference: the axis's
        table is the one place to add a line).
    attribute : the module attribute holding the entry (``"MOTION"``, ``"FORM"``, ``"FOLLOWER"``).
    """

    def __init__(self, modules: Mapping[str, str], attribute: str) -> None:
        self._modules = modules
        self._attribute = attribute
        self._extra: dict[str, E] = {}

    def register(self, entry: E) -> None:
        """Add (or replace) an entry defined outside the package."""
        self._extra[entry.name] = entry
        _changed()

    def unregister(self, name: str) -> None:
        """Remove a registered entry (the package's own stay)."""
        self._extra.pop(name, None)
        _changed()

    def names(self) -> list[str]:
        """The package's entries in table order, then the registered ones by name."""
        return list(self._modules) + sorted(set(self._extra) - set(self._modules))

    def known(self, name: str) -> bool:
        return name in self._extra or name in self._modules

    def get(self, name: str) -> E:
        """The entry ``name`` (KeyError if none); a registered entry shadows the package's."""
        if name in self._extra:
            return self._extra[name]
        path = self._modules[name]
        module = sys.modules.get(path)  # imported before: the module itself (what import_module returns), without its machinery
        entry: E = getattr(module if module is not None else importlib.import_module(path), self._attribute)
        return entry
