"""The follower registry: one module per follower, one line here.

Adding a follower: write ``camgen/followers/<name>.py`` exposing ``FOLLOWER`` (a
:class:`~camgen.followers.base.FollowerKind`) and add its module to :data:`FOLLOWER_MODULES`.
A follower with a point contact (a circle of some radius) or a face is taken by every form and
placement that carry that contact, with its checks, sizing, dynamics and drawings.
"""
from __future__ import annotations

import importlib

from camgen.followers.base import CONTACTS, Contact, FollowerKind

__all__ = ["CONTACTS", "FOLLOWER_MODULES", "Contact", "FollowerKind", "follower_names", "get_follower", "register", "unregister"]

#: follower name (the ``follower`` value in scene files) -> module defining ``FOLLOWER``
FOLLOWER_MODULES: dict[str, str] = {
    "roller": "camgen.followers.roller",
    "flat": "camgen.followers.flat",
    "knife": "camgen.followers.knife",
    "yoke": "camgen.followers.yoke",
}

_EXTRA: dict[str, FollowerKind] = {}


def register(follower: FollowerKind) -> None:
    """Register a follower defined outside this package (plug-ins, tests)."""
    _EXTRA[follower.name] = follower


def unregister(name: str) -> None:
    _EXTRA.pop(name, None)


def follower_names(contacts: tuple[Contact, ...] = CONTACTS) -> tuple[str, ...]:
    """The registered followers whose contact is one of ``contacts``, in registry order (then
    the registered ones by name)."""
    names = list(FOLLOWER_MODULES) + sorted(set(_EXTRA) - set(FOLLOWER_MODULES))
    return tuple(n for n in names if get_follower(n).contact in contacts)


def get_follower(name: str) -> FollowerKind:
    """The registered follower ``name`` (KeyError if none)."""
    if name in _EXTRA:
        return _EXTRA[name]
    follower: FollowerKind = importlib.import_module(FOLLOWER_MODULES[name]).FOLLOWER
    return follower
