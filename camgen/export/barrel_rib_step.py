"""STEP (AP214, mm) of a barrel cam with a rib through OpenCASCADE (OCP): the root cylinder less
the bore, with the rib standing on it up to the rim, one solid.

The rib's two faces (:class:`~camgen.synthesis.barrel.BarrelRib`: the upper roller's lower
envelope above, the lower roller's upper envelope below) are written exactly as a groove's walls
are (:mod:`camgen.export.barrel_step`): bicubic B-spline surfaces within ``fit_tol_mm`` of the
exact faces (measured axially), reaching a little inside the root and outside the rim, the tube
between them closed by ruled surfaces (:func:`~camgen.export.barrel_step.tube_solid`).  The tube
is cut down to the exact cylinder of the rim radius (OCCT's common: the rib's top is that
cylinder), fused with the exact root cylinder (its part inside the root radius vanishes into it),
and the bore is cut; the result must be one solid that OCCT's checker finds valid.  Where the
faces cross (the rib too narrow for its rollers' spacing) on the radii the tube spans, or the rib
reaches an end face, the STEP is refused (a :class:`GeometryError` naming the cam), as the mesh is
(:mod:`camgen.export.barrel_rib_solid`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from camgen.errors import GeometryError
from camgen.export.barrel_step import (OVERLAP, barrel_step_bytes, build_solid, cut_shape, inside_ends, one_valid_solid, solid_step_bytes,
                                      tube_solid)

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["CROSSING_RADII", "CROSSING_SAMPLES", "rib_solid", "rib_step_bytes", "writer"]

#: Radii (evenly from the tube's inner to its outer radius) and polar angles (over a turn) at which
#: the faces are checked not to cross before the tube is made.
CROSSING_RADII = 5
CROSSING_SAMPLES = 720


def _faces_apart(rib: Any, r_lo: float, r_hi: float, cam: str) -> None:
    """GeometryError where the rib's faces touch or cross on the radii the tube spans (module notes)."""
    r = np.linspace(r_lo, r_hi, CROSSING_RADII)[:, None]
    phi = 2.0 * math.pi * np.arange(CROSSING_SAMPLES)[None, :] / CROSSING_SAMPLES
    least = float(np.min(rib.thickness(r, phi)))
    if not least > 0.0:
        raise GeometryError(f"cam '{cam}': the rib's faces cross (its least width along z between radius {r_lo:.6g} and {r_hi:.6g} "
                            f"mm is {least:.4g} mm): the rollers cut the rib away")


def _body(rib: Any, tol: float, cam: str) -> Any:
    """The rib cam's OCCT solid (module notes)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Fuse
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    rim, root, length, bore = (float(rib.rim_radius), float(rib.root_radius), float(rib.length), float(rib.bore_radius))
    if not 0.0 <= bore < root < rim:
        raise GeometryError(f"cam '{cam}': the barrel needs 0 <= bore radius < root radius < rim radius (bore {bore:g} mm, root "
                            f"{root:g} mm, rim {rim:g} mm)")
    inside_ends(rib, cam, "rib")
    reach = min(1.0, OVERLAP * (rim - root))  # the tube's reach past root and rim (tube_solid's)
    _faces_apart(rib, root - reach, rim + reach, cam)
    axis = gp_Ax2(gp_Pnt(0.0, 0.0, 0.0), gp_Dir(0.0, 0.0, 1.0))
    below = gp_Ax2(gp_Pnt(0.0, 0.0, -1.0), gp_Dir(0.0, 0.0, 1.0))
    tube = tube_solid(rib, tol, cam)
    common = BRepAlgoAPI_Common(tube, BRepPrimAPI_MakeCylinder(axis, rim, length).Shape())
    if not common.IsDone():
        raise GeometryError(f"cam '{cam}': OpenCASCADE cannot trim the rib at the rim radius")
    fuse = BRepAlgoAPI_Fuse(BRepPrimAPI_MakeCylinder(axis, root, length).Shape(), common.Shape())
    if not fuse.IsDone():
        raise GeometryError(f"cam '{cam}': OpenCASCADE cannot join the rib to the root cylinder")
    body = fuse.Shape()
    if bore > 0.0:
        body = cut_shape(body, BRepPrimAPI_MakeCylinder(below, bore, length + 2.0).Shape(), "the bore", cam)
    return one_valid_solid(body, cam)


def rib_solid(rib: Any, name: str = "cam") -> Any:
    """The OCCT solid of the STEP file of the barrel cam with the rib ``rib`` (:func:`rib_step_bytes`),
    for the other writers of that solid (IGES)."""
    return build_solid(lambda: _body(rib, float(rib.fit_tol), name), name)


def rib_step_bytes(rib: Any, name: str = "cam", schema: str = "AP214") -> bytes:
    """STEP file content of the barrel cam with the rib ``rib``
    (:class:`camgen.synthesis.barrel.BarrelRib`; module notes): its faces within ``rib.fit_tol`` mm
    of the exact ones, stated in the header."""
    tol = float(rib.fit_tol)
    return solid_step_bytes(lambda: _body(rib, tol, name), name,
                            f"B-spline rib faces within {tol!r} mm (axially) of the exact faces; cylinders and planes exact", schema)


def writer(cam: "CamResult", run: "RunSettings", fmt: str) -> bytes:
    """The barrel form's STEP writer (``CamForm.writers["step"]``): the rib's solid
    (:func:`rib_step_bytes`) for ``track = "rib"``, else the groove's
    (:func:`camgen.export.barrel_step.barrel_step_bytes`)."""
    from camgen.kinds.barrel import BarrelCam

    assert isinstance(cam.built, BarrelCam), f"cam {cam.name!r} is not a barrel cam"
    if cam.built.rib is not None:
        return rib_step_bytes(cam.built.rib, cam.name, run.output.step_schema)
    return barrel_step_bytes(cam.built.groove, cam.name, run.output.step_schema)
