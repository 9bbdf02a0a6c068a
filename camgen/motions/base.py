"""The motion axis: what the follower must do, read from a cam table.

A motion is one module in :mod:`camgen.motions` exposing ``MOTION``, a :class:`Motion`.  It is one
of two sorts:

- a **displacement law** (``read_law``): the follower's lift or swing s(theta) as a
  :class:`~camgen.synthesis.followers.Displacement` (a motion program, a lift table).  Every cam
  form that realises a law (:attr:`camgen.forms.base.CamForm.read`) takes it, for every follower
  that form carries;
- a **design of its own** (``realisations``): a motion whose cam comes from its paper's own
  synthesis, not from a law and a follower envelope (the steering path of paper 004, the
  three-arc geometry of paper 000).  It names the forms it realises and how
  (:class:`~camgen.kinds.base.CamKind` per form).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping

from camgen.schema import Key

if TYPE_CHECKING:
    from camgen.kinds.base import CamKind
    from camgen.synthesis.followers import FollowerSpec

__all__ = ["LawReading", "Motion"]


@dataclass(frozen=True)
class LawReading:
    """A displacement law read from a cam table: the law (s in mm for a translating follower, rad
    of swing for an oscillating one, as functions of the cam angle in rad) and the figures the
    report shows about it."""

    law: Any  # a camgen.synthesis.followers.Displacement (MotionProgram, LiftTable, ...)
    figures: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Motion:
    """A registered motion.

    Attributes
    ----------
    name : the ``kind`` value in scene files.
    summary : one line for ``camgen keys`` and the template list.
    keys : the keys of the motion itself (a law's segments or table file); a design of its own
        lists every key of its cam table in its realisations instead.
    read_law : ``(where, parsed, follower, base_dir) -> LawReading``: the law, errors naming scene
        keys under ``where``; ``follower`` is the follower it will drive (its motion says whether
        the law is a lift in mm or a swing in rad).  None for a design of its own.
    read_half_law : as ``read_law``, from a program over the first half-turn (0 to 180 deg)
        completed by the rule ``s(theta + 180 deg) = C - s(theta)``, ``C = s(0) + s(180 deg)``
        (the constant-breadth form, :mod:`camgen.synthesis.breadth`); None: the motion takes no
        half-turn program.
    realisations : form name -> the cam type this motion makes in that form by its own synthesis.
    default_form : the form a cam table without ``form`` gets.
    """

    name: str
    summary: str
    keys: tuple[Key, ...] = ()
    read_law: "Callable[[str, Mapping[str, Any], FollowerSpec, Path | None], LawReading] | None" = None
    read_half_law: "Callable[[str, Mapping[str, Any], FollowerSpec, Path | None], LawReading] | None" = None
    realisations: "Mapping[str, CamKind]" = field(default_factory=dict)
    default_form: str = "plate"
