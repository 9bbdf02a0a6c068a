"""The parts of a cam table a design study's designs share, read once while they stay the same.

A sweep over the base radius changes one key of the cam table per design; the body (bore,
keyway, thickness) and the follower train's dynamics keys stay the same, and their readers
(:func:`camgen.kinds.base.read_body`, :func:`camgen.kinds.dynamics.read_dynamics`) are pure
functions of those keys.  :func:`body_and_dynamics` gives them only those keys of the parsed table
(:func:`camgen.schema.restricted`: a reader cannot see, and so cannot depend on, a key outside its
cache key) and keeps its last results (``functools.lru_cache``, :data:`PART_CACHE`) keyed by their
values (:func:`camgen.frozen.frozen`) and the other arguments, with what the train's reader reads of
the registered follower.  What it returns is frozen (a :class:`~camgen.body.BodySpec`, a
:class:`~camgen.kinds.dynamics.DynamicsSpec`).

A train whose external load comes from a file (``external_load_csv``) is read each time: the
file may change between two scenes.
"""
from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from camgen.frozen import Keyed, Unfreezable
from camgen.schema import Key, Parsed, restricted

if TYPE_CHECKING:
    from camgen.body import BodySpec
    from camgen.kinds.dynamics import DynamicsSpec

__all__ = ["PART_CACHE", "body_and_dynamics"]

#: Results kept (the last ones: a scene's cams, a study's designs).
PART_CACHE = 8

Parts = tuple["BodySpec", "DynamicsSpec | None"]


@lru_cache(maxsize=None)  # constants only: made once
def _part_keys() -> tuple[Key, ...]:
    """The body's keys, then the follower train's."""
    from camgen.kinds.base import body_keys
    from camgen.kinds.dynamics import dynamics_keys

    return body_keys() + dynamics_keys()


def body_and_dynamics(where: str, parsed: Mapping[str, Any], *, motion: str, follower: str, rpm: float | None,
                      base_dir: Path | None = None, form_closed: bool = False) -> Parts:
    """:func:`camgen.kinds.base.read_body` of ``parsed``, then
    :func:`camgen.kinds.dynamics.read_dynamics` of it (the same arguments, the body's thickness),
    kept while their keys and the arguments are the same (not with a load file)."""
    from camgen.followers import get_follower

    part = restricted(parsed, _part_keys())
    args = (where, motion, follower, rpm, base_dir, form_closed)
    if "external_load_csv" not in part:
        model = get_follower(follower)  # what the train's reader reads of the registered follower is part of the key
        try:
            return _cached(Keyed(part), *args, model.contact, model.has_radius)
        except Unfreezable:
            pass
    return _read(part, *args)


def _read(part: Parsed, where: str, motion: str, follower: str, rpm: float | None, base_dir: Path | None,
          form_closed: bool) -> Parts:
    from camgen.kinds.base import read_body
    from camgen.kinds.dynamics import read_dynamics

    body = read_body(where, part)
    return body, read_dynamics(where, part, motion=motion, follower=follower, rpm=rpm, thickness=body.thickness,
                               base_dir=base_dir, form_closed=form_closed)


@lru_cache(maxsize=PART_CACHE)
def _cached(part: Keyed, where: str, motion: str, follower: str, rpm: float | None, base_dir: Path | None, form_closed: bool,
            contact: str, has_radius: bool) -> Parts:
    """``contact``, ``has_radius``: the registered follower's (a follower registered again under
    its name with another contact is another key)."""
    del contact, has_radius  # the reader looks the follower up itself; these only key its result
    return _read(part.value, where, motion, follower, rpm, base_dir, form_closed)
