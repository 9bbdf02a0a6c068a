"""Cam form ``constant_breadth``: a cam whose breadth (the distance between two parallel
tangents) is the same in every direction, so that a yoke of two parallel flat faces holds it
closed without a spring; with two rollers a fixed distance apart, the constant diameter of its
pitch curve does the same.

Every displacement law (motion program, lift table) is realised with the rule
``s(theta + 180 deg) = C - s(theta)`` (derivation: :mod:`camgen.synthesis.breadth`): the motion
gives the first half-turn (``half_turn = true``) or the whole turn, checked against the rule.
The profile is the exact envelope of the upper face or roller (the plate machinery); the checks
and drawings are :mod:`camgen.kinds.breadth`'s.  The three-arc cam of paper 000
(:mod:`camgen.motions.three_arc`, six exact arcs) realises this form by its own construction.
"""
from __future__ import annotations

from camgen.forms.base import CamForm
from camgen.kinds.breadth import build_breadth, evaluate_breadth, keys, read_breadth

__all__ = ["FORM"]

FORM = CamForm(
    name="constant_breadth",
    summary="constant-breadth cam between a yoke's two parallel faces, or constant-diameter cam between two rollers, for any law "
            "keeping s(theta + 180 deg) = C - s(theta) (the three-arc cam of paper 000 is the one of six exact arcs)",
    keys=keys,
    read=read_breadth,
    build=build_breadth,
    evaluate=evaluate_breadth,
)
