"""The follower registry: one module per follower, one line here.

Adding a follower: write ``camgen/followers/<name>.py`` exposing ``FOLLOWER`` (a
:class:`~camgen.followers.base.FollowerKind`) and add its module to :data:`FOLLOWER_MODULES`.
A follower with a point contact (a circle of some radius) or a face is taken by every form and
placement that carry that contact, with its checks, sizing, dynamics and drawings.
"""
from __future__ import annotations

from camgen.followers.base import CONTACTS, Contact, FollowerKind
from camgen.registry import Registry

__all__ = ["CONTACTS", "FOLLOWER_MODULES", "Contact", "FollowerKind", "follower_names", "get_follower", "known", "register",
           "sampled_follower_names", "unregister"]

#: follower name (the ``follower`` value in scene files) -> module defining ``FOLLOWER``
FOLLOWER_MODULES: dict[str, str] = {
    "roller": "camgen.followers.roller",
    "flat": "camgen.followers.flat",
    "knife": "camgen.followers.knife",
    "yoke": "camgen.followers.yoke",
}

_REGISTRY: Registry[FollowerKind] = Registry(FOLLOWER_MODULES, "FOLLOWER")

#: Register (or remove) an entry defined outside this package (plug-ins, tests).
register = _REGISTRY.register
unregister = _REGISTRY.unregister


def known(name: str) -> bool:
    """Whether ``name`` is a registered follower."""
    return _REGISTRY.known(name)


def follower_names(contacts: tuple[Contact, ...] = CONTACTS) -> tuple[str, ...]:
    """The registered followers whose contact is one of ``contacts``, in registry order (then
    the registered ones by name)."""
    return tuple(n for n in _REGISTRY.names() if _REGISTRY.get(n).contact in contacts)


def sampled_follower_names(contacts: tuple[Contact, ...] = CONTACTS) -> tuple[str, ...]:
    """The followers with one of ``contacts`` whose checks can be sampled from a contour
    (:class:`camgen.checks.Follower`): faces, a face, a point with a radius (a knife edge needs
    the plate cam's closed forms)."""
    return tuple(n for n in follower_names(contacts) if get_follower(n).contact != "point" or get_follower(n).has_radius)


def get_follower(name: str) -> FollowerKind:
    """The registered follower ``name`` (KeyError if none)."""
    return _REGISTRY.get(name)
