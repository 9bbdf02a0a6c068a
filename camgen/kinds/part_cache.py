"""The parts of a cam table a design study's designs share, each read once while it stays the same.

A sweep over the base radius changes one key of the cam table per design; the body (bore,
keyway, thickness) and the follower train's dynamics keys stay the same, and their readers
(:func:`camgen.kinds.base.read_body`, :func:`camgen.kinds.dynamics.read_dynamics`) are pure
functions of those keys.  Each reader here is given only its own keys of the parsed table
(:func:`camgen.schema.restricted`: a reader cannot see, and so cannot depend on, a key outside
its cache key) and keeps its last results (``functools.lru_cache``, :data:`PART_CACHE` each) keyed
by their values (:func:`camgen.frozen.frozen`) and its other arguments (the train's: what it reads
of the registered follower too).  What they return is
frozen (a :class:`~camgen.body.BodySpec`, a :class:`~camgen.kinds.dynamics.DynamicsSpec`).

A train whose external load comes from a file (``external_load_csv``) is read each time: the
file may change between two scenes.
"""
from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.frozen import Keyed, Unfreezable
from camgen.schema import Parsed, restricted

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.kinds.dynamics import DynamicsSpec

__all__ = ["PART_CACHE", "body_of", "dynamics_of"]

#: Results each reader keeps (the last ones: a scene's cams, a study's designs).
PART_CACHE = 8


def body_of(where: str, parsed: Mapping[str, Any]) -> "BodySpec":
    """:func:`camgen.kinds.base.read_body` of ``parsed``'s body keys, kept while they are the same."""
    from camgen.kinds.base import body_keys, read_body

    part = restricted(parsed, body_keys())
    try:
        keyed = Keyed(part)
    except Unfreezable:
        return read_body(where, part)
    return _body(keyed, where)


@lru_cache(maxsize=PART_CACHE)
def _body(part: Keyed, where: str) -> "BodySpec":
    from camgen.kinds.base import read_body

    return read_body(where, part.value)


def dynamics_of(where: str, parsed: Mapping[str, Any], *, motion: str, follower: str, rpm: float | None, thickness: float,
                base_dir: Path | None = None, form_closed: bool = False) -> "DynamicsSpec | None":
    """:func:`camgen.kinds.dynamics.read_dynamics` of ``parsed``'s dynamics keys (the same
    arguments), kept while they and the arguments are the same (not with a load file)."""
    from camgen.followers import get_follower
    from camgen.kinds.dynamics import dynamics_keys

    part = restricted(parsed, dynamics_keys())
    args = (where, motion, follower, rpm, thickness, base_dir, form_closed)
    if "external_load_csv" not in part:
        model = get_follower(follower)  # what the reader reads of the registered follower is part of the key
        try:
            return _dynamics(Keyed(part), *args, model.contact, model.has_radius)
        except Unfreezable:
            pass
    return _read_dynamics(part, *args)


def _read_dynamics(part: Parsed, where: str, motion: str, follower: str, rpm: float | None, thickness: float,
                   base_dir: Path | None, form_closed: bool) -> "DynamicsSpec | None":
    from camgen.kinds.dynamics import read_dynamics

    return read_dynamics(where, part, motion=motion, follower=follower, rpm=rpm, thickness=thickness, base_dir=base_dir,
                         form_closed=form_closed)


@lru_cache(maxsize=PART_CACHE)
def _dynamics(part: Keyed, where: str, motion: str, follower: str, rpm: float | None, thickness: float, base_dir: Path | None,
              form_closed: bool, contact: str, has_radius: bool) -> "DynamicsSpec | None":
    """``contact``, ``has_radius``: the registered follower's (a follower registered again under
    its name with another contact is another key)."""
    del contact, has_radius  # the reader looks the follower up itself; these only key its result
    return _read_dynamics(part.value, where, motion, follower, rpm, thickness, base_dir, form_closed)
