"""Cam form ``constant_breadth``: a cam whose breadth (the distance between two parallel
tangents) is the same in every direction, so that a yoke of two parallel flat faces (or two
rollers a fixed distance apart) holds it closed without a spring.

Today the three-arc cam of paper 000 is the one realisation
(:mod:`camgen.motions.three_arc`, six exact arcs); a constant-breadth cam for any displacement
law (rise over 180 deg, the complementary return) is a ``read`` and ``build`` here.
"""
from __future__ import annotations

from camgen.forms.base import CamForm

__all__ = ["FORM"]

FORM = CamForm(
    name="constant_breadth",
    summary="constant-breadth cam for a yoke follower (two parallel faces): the three-arc cam of paper 000",
)
