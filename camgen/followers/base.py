"""The follower axis: what touches the cam.

A follower is one module in :mod:`camgen.followers` exposing ``FOLLOWER``, a
:class:`FollowerKind`: its name (the scene's ``follower`` value), the keys of its own (a roller's
radius, a face's length), and its **contact**, which is all the cam forms ask of it:

- ``"point"``: a circle of radius ``r >= 0`` about a point of the follower (a roller, ``r > 0``;
  a knife edge, ``r = 0``).  The point's path relative to the cam is the pitch curve and the
  profile its offset by ``r`` (:func:`camgen.synthesis.followers.kinematics`);
- ``"face"``: a straight face (a flat-faced follower); the profile is the envelope of its lines;
- ``"faces"``: two parallel faces a cam of constant breadth fits between (a yoke).

Every placement (translating, oscillating about a pivot) and every form that carries the
contact takes a new follower with no change elsewhere: the closed forms, the checks, sizing,
dynamics and drawings depend on the contact and its radius, never on the follower's name.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Literal, Mapping

from camgen.schema import Key

__all__ = ["CONTACTS", "Contact", "FollowerKind"]

Contact = Literal["point", "face", "faces"]
#: The contacts a follower may have (see the module docstring).
CONTACTS: tuple[Contact, ...] = ("point", "face", "faces")


def _no_radius(parsed: Mapping[str, Any]) -> float:
    return 0.0


@dataclass(frozen=True)
class FollowerKind:
    """A registered follower.

    Attributes
    ----------
    name : the ``follower`` value in scene files.
    summary : what it is, a few words for the key reference.
    contact : ``"point"``, ``"face"`` or ``"faces"`` (see the module docstring).
    keys : the follower's own keys (each needs ``follower`` = this name, or one of the names that
        share the key).
    radius : ``parsed -> r`` (mm): a point contact's radius from the parsed keys (internal names);
        0 for a knife edge and for faces.
    has_radius : whether ``radius`` is > 0 (a roller-like point contact whose profile is the pitch
        curve's offset), as opposed to a knife edge riding its pitch curve.
    """

    name: str
    summary: str
    contact: Contact
    keys: tuple[Key, ...] = ()
    radius: Callable[[Mapping[str, Any]], float] = _no_radius
    has_radius: bool = False
