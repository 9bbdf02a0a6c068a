"""Cam form ``linear``: a plate moving in a straight line (along x) drives a translating (+y) or
oscillating roller or knife.

Realises every displacement law (:attr:`camgen.motions.base.Motion.read_law`) written in plate
travel: a motion program's segments give ``span_mm`` (their sum is the travel), a lift table's
first column is x in mm within ``travel_mm``.  The
pitch curve is the graph ``(x, s(x))`` (translating) or the arm's path over the moving plate
(oscillating); the profile is its exact offset by the roller radius within ``fit_tol_mm``
(``linear_form = "edge"``: the plate's top edge) or a slot between its offsets both ways
(``"slot"``: a :class:`~camgen.kinds.base.Pocket` closed by half circles about the pitch curve's
ends, inside the plate).  Conventions and
closed forms: :mod:`camgen.synthesis.linear`; keys, build and checks: :mod:`camgen.kinds.linear`.
"""
from __future__ import annotations

from camgen.forms.base import CamForm
from camgen.kinds.linear import build_linear, evaluate_linear, linear_keys, read_linear

__all__ = ["FORM"]

FORM = CamForm(
    name="linear",
    summary="linear (translating-plate) cam: a plate moving along x drives a translating or oscillating roller or knife, on its "
            "edge or in a slot; the program's abscissa is the plate travel in mm (span_mm)",
    keys=linear_keys,
    read=read_linear,
    build=build_linear,
    evaluate=evaluate_linear,
    report_section="camgen.kinds.linear:linear_section",
    formats_refused={"lift": "its plate turns about no axis, so it has no polar lift table (the point list and the DXF hold the edge)",
                     "follower": "it has no cam speed (rpm) to tabulate the follower's motion at"},
    # the plate's drawing and its inspection table, lift against x (camgen.export.drawing_linear)
    writers={"drawing": "camgen.export.drawing_linear:drawing_svg", "drawing_pdf": "camgen.export.drawing_linear:drawing_pdf",
             "inspection": "camgen.export.drawing_linear:inspection"},
)
