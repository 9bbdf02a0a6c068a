"""The base-radius advices of the last few designs, kept for the next ones (issue 28 item 6).

A failing plate-cam design states the base radii that would pass
(:func:`camgen.synthesis.sizing.base_radius_advice`: a search that evaluates the design at a few
trial base radii, about 2 ms).  The search reads the law, the design limits, the search options
and every follower parameter but the base radius (each trial radius replaces it), so the failing
designs of a sweep over the base radius (or over keys the search does not read: the speed, the
dynamics, the machining) find the same advice.  Here the advice is computed once per
:class:`AdviceQuery` and kept (``functools.lru_cache``, :data:`ADVICE_CACHE_SIZE` entries, each
holding its law): a query equals another for an equal law and the same follower parameters and
limits, compared by value and by their exact text (``repr``: ``-0.0`` and ``0.0`` differ), so a
hit returns exactly what the search would return.  A law is equal to another when it is the same
object, or when both are :class:`camgen.synthesis.laws.MotionProgram` of equal segments (the
frozen :class:`camgen.synthesis.laws.Segment`: law name, span, lift and options, compared by
value and text), unit and tolerances: the program is made from these alone, so each design's
parse of an unchanged ``[[segments]]`` table gives an equal law.  The advice is a frozen dataclass of floats
and tuples (immutable); a search that finds no base radius (:class:`GeometryError`) is kept as
its message and raised again.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, TypeVar, cast

from camgen.errors import GeometryError
from camgen.synthesis.laws import PROGRAM_KEY, MotionProgram

if TYPE_CHECKING:
    from camgen.synthesis.followers import FollowerSpec

__all__ = ["ADVICE_CACHE_SIZE", "AdviceQuery", "PROGRAM_KEY", "cached_advice"]

#: Advices kept (a sweep's latest few search inputs; each entry holds its law object alive).
ADVICE_CACHE_SIZE = 4

#: The advice (:class:`camgen.synthesis.sizing.BaseRadiusAdvice`: frozen, floats and tuples).
Advice = TypeVar("Advice")
#: The search: (follower, law, limits (:class:`camgen.synthesis.sizing.DesignLimits`), tol mm, scan, digits) -> the advice.
Search = Callable[["FollowerSpec", Any, Any, float, int, int], Any]


# PROGRAM_KEY (camgen.synthesis.laws): where a motion program keeps its :func:`_law_key` (made
# once per program: a program does not change; one of the values MotionProgram does not pickle).


def _law_key(law: Any) -> tuple[Any, ...]:
    """What makes ``law`` equal to another: a motion program's segments, unit and tolerances (and
    their exact text), else the object itself (``("object", id)``, compared by identity).  A
    program's key is made once and kept on it (:data:`PROGRAM_KEY`: a radius sweep's failing
    designs ask with the same program object)."""
    if type(law) is MotionProgram:
        kept = law.__dict__.get(PROGRAM_KEY)
        if kept is not None:
            return cast(tuple, kept)
        key = (law.segments, law.unit, law.span_tol, law.join_tol)
        try:
            hash(key)
        except TypeError:  # a segment holding a list (a polynomial's ends, spline points): by identity
            return ("object", id(law))
        made = ("program", key, repr(key))
        law.__dict__[PROGRAM_KEY] = made
        return made
    return ("object", id(law))


def _follower_text(follower: "FollowerSpec") -> str:
    """Every parameter of ``follower`` the search reads (all but the base radius), as exact text;
    with its contact and whether it has a radius, which the spec takes from the follower registry
    (a follower registered again under its name with another contact is another search)."""
    f = follower
    return repr((f.kind, f.contact, f.has_radius, f.motion, f.roller_radius, f.offset, f.pivot, f.arm_length, f.face_offset,
                 f.lift_turn, f.rotation))


@dataclass(frozen=True, eq=False)
class AdviceQuery:
    """The inputs of one base-radius advice.  Hashed by the law's key (:func:`_law_key`) and the
    exact text of the rest; equal to another query for the same search, an equal law (the same
    object, or a motion program of equal segments), the same follower parameters (the base radius
    aside) and equal limits with the same text."""

    search: Search
    follower: "FollowerSpec"
    law: Any
    limits: Any  # camgen.synthesis.sizing.DesignLimits (frozen, hashable)
    tol: float
    scan: int
    digits: int
    key: tuple[Any, ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        options = repr((self.tol, self.scan, self.digits))
        object.__setattr__(self, "key", (self.search, _law_key(self.law), _follower_text(self.follower), options, self.limits,
                                         repr(self.limits)))

    def __hash__(self) -> int:
        kept = self.__dict__.get("_hash")  # (made once: the cache's lookup and its insertion both ask)
        if kept is None:
            kept = hash(self.key)
            object.__setattr__(self, "_hash", kept)
        return cast(int, kept)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, AdviceQuery) or other.key != self.key:
            return False
        return self.key[1][0] == "program" or other.law is self.law  # an object law: the same object


@functools.lru_cache(maxsize=ADVICE_CACHE_SIZE)
def _outcome(query: AdviceQuery) -> tuple[Any, tuple[Any, ...]]:
    """The advice of ``query`` and no error, or None and the arguments of the GeometryError raised."""
    try:
        return query.search(query.follower, query.law, query.limits, query.tol, query.scan, query.digits), ()
    except GeometryError as exc:
        if type(exc) is not GeometryError:  # a subclass may carry more than its arguments: not kept
            raise
        return None, exc.args


def cached_advice(search: Callable[["FollowerSpec", Any, Any, float, int, int], Advice], follower: "FollowerSpec", law: Any,
                  limits: Any, tol: float, scan: int, digits: int) -> Advice:
    """``search(follower, law, limits, tol, scan, digits)``, from the last few designs' advices
    when one had the same inputs (the base radius aside); limits that cannot be hashed are
    searched every time.

    Raises
    ------
    GeometryError
        When no base radius passes (the search's message, kept with the advice).
    """
    query = AdviceQuery(search, follower, law, limits, tol, scan, digits)
    try:
        hash(query)
    except TypeError:  # limits holding an unhashable value: no reuse
        return search(follower, law, limits, tol, scan, digits)
    advice, error = _outcome(query)
    if advice is None:
        raise GeometryError(*error)
    return cast(Advice, advice)
