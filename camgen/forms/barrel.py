"""Cam form ``barrel``: a cylinder turning about its axis whose groove drives a roller along the
axis (translating) or swinging on an arm about an axis perpendicular to it (oscillating), with a
cylindrical or conical roller, the cam turning either way.

Realises every displacement law (:attr:`camgen.motions.base.Motion.read_law`): the groove's walls
are the exact envelopes of the roller at every radius from root to rim
(:mod:`camgen.synthesis.barrel`); keys, build and checks: :mod:`camgen.kinds.barrel`.  The body
is no plate, so the form writes its own files: the developed drawing and the walls' point list
(:mod:`camgen.export.barrel_drawing`), the groove's dimensioned drawing and inspection table
(:mod:`camgen.export.barrel_sheet`, a rib's too), the solid (:mod:`camgen.export.barrel_solid`, the mesh
stage; STEP :mod:`camgen.export.barrel_step`, a rib's :mod:`camgen.export.barrel_rib_step`, the same solid as IGES
:mod:`camgen.export.barrel_iges`) and the 4th-axis program
(:mod:`camgen.export.gcode_barrel`).  The groove is form-closed: its dynamics (both walls' forces,
torque, Hertz stress) are :mod:`camgen.kinds.barrel_dynamics`; a rib's (its two rollers)
:mod:`camgen.kinds.barrel_rib_dynamics`.
"""
from __future__ import annotations

from camgen.forms.base import CamForm
from camgen.kinds.barrel import barrel_keys, build_barrel, evaluate_barrel, read_barrel
from camgen.kinds.barrel_dynamics import barrel_dynamics_keys
from camgen.kinds.barrel_rib_dynamics import barrel_follower_kinematics

__all__ = ["FORM"]

_FEA = "an FEA mesh of a barrel cam is not built yet (this release meshes plate bodies only)"

FORM = CamForm(
    name="barrel",
    summary="barrel (cylindrical) cam: a groove in a turning cylinder drives a translating or oscillating roller (cylindrical or "
            "conical), both walls the exact envelopes of the roller at every radius",
    keys=lambda: barrel_keys() + barrel_dynamics_keys(),
    read=read_barrel,
    build=build_barrel,
    evaluate=evaluate_barrel,
    follower_dynamics=barrel_follower_kinematics,
    report_section="camgen.report.barrel:barrel_section",
    formats_refused={"lift": "a cylinder has no polar lift table (the point list holds the walls at root, mean and rim radius)",
                     "vtu": _FEA, "msh": _FEA, "inp": _FEA,
                     "svg": "a cylinder has no flat profile to cut (the developed drawing is the dxf)"},
    writers={"dxf": "camgen.export.barrel_drawing:dxf", "points": "camgen.export.barrel_drawing:points",
             "step": "camgen.export.barrel_rib_step:writer", "ngc": "camgen.export.gcode_barrel_rib:writer",
             "iges": "camgen.export.barrel_iges:writer",
             # the groove's (a rib's) drawing: side view, developed track; its inspection table (camgen.export.barrel_sheet)
             "drawing": "camgen.export.barrel_sheet:drawing_svg", "drawing_pdf": "camgen.export.barrel_sheet:drawing_pdf",
             "inspection": "camgen.export.barrel_sheet:inspection"},
    stages={"mesh": "camgen.export.barrel_mesh:mesh_stage"},
)
