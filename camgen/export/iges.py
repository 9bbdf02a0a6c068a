"""IGES 5.3 (mm) of the cam body, through OpenCASCADE (OCP): the STEP file's solid in IGES.

The solid is the one :func:`camgen.export.step.cam_solid` builds for the STEP file (exact circles,
B-spline edges within the same tolerance, bore, keyway and pockets cut), written by OCCT's IGES
processor in its B-rep mode (``write.iges.brep.mode`` 1): a manifold solid B-rep object (entity
186) with its shells, faces, loops, edges and vertices (entities 514, 510, 508, 504, 502), so a
reader gets one closed solid, not loose trimmed surfaces (OCCT's faces mode, entity 144).  Units
mm (global section unit flag 2, ``2HMM``).  The global section's file name is the cam's, its
author ``camgen`` and its two dates fixed (``20000101.000000``), so the same cam gives the same
bytes.  Needs the ``step`` extra (OCP).
"""
from __future__ import annotations

import io
import os
from typing import TYPE_CHECKING, Any, Sequence

from camgen.errors import ExportError

if TYPE_CHECKING:
    from camgen.contour import Contour
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["IGES_DATE", "iges_bytes", "iges_text", "writer"]

#: The fixed date of the global section (IGES 5.3 section 2.2.4.3, fields 18 and 25: YYYYMMDD.HHNNSS).
IGES_DATE = "20000101.000000"


def iges_text(shape: Any, name: str) -> str:
    """The IGES text (mm, B-rep mode) of an OCCT ``shape``, written in memory with OCCT's
    messages kept off stdout; :class:`ExportError` naming cam ``name`` when OCCT cannot write it."""
    from OCP.IGESControl import IGESControl_Controller, IGESControl_Writer
    from OCP.Interface import Interface_Static
    from OCP.TCollection import TCollection_HAsciiString

    IGESControl_Controller.Init_s()  # defines the write.iges.* settings
    if not (Interface_Static.SetCVal_s("write.iges.unit", "MM") and Interface_Static.SetIVal_s("write.iges.brep.mode", 1)):
        raise ExportError(f"cam '{name}': OpenCASCADE refused the IGES settings (unit MM, B-rep mode)")
    stream = io.BytesIO()
    saved = os.dup(1)  # OCCT prints messages on stdout: keep the CLI quiet
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
        try:
            writer = IGESControl_Writer("MM", 1)  # 1: B-rep mode (a solid), not trimmed surfaces
            added = writer.AddShape(shape)
            writer.ComputeModel()
            model = writer.Model()
            section = model.GlobalSection()
            section.SetFileName(TCollection_HAsciiString(f"{name}.igs"))
            section.SetAuthorName(TCollection_HAsciiString("camgen"))
            section.SetDate(TCollection_HAsciiString(IGES_DATE))
            section.SetLastChangeDate(TCollection_HAsciiString(IGES_DATE))
            model.SetGlobalSection(section)
            done = writer.Write(stream)
        finally:
            os.dup2(saved, 1)
            os.close(saved)
    if not (added and done) or not stream.getvalue():
        raise ExportError(f"cam '{name}': OpenCASCADE could not write the IGES file")
    return stream.getvalue().decode("ascii", errors="replace")


def iges_bytes(contour: "Contour", body: Any, name: str = "cam", pockets: Sequence[Any] = ()) -> bytes:
    """IGES file content of the extruded cam body (``body``: :class:`camgen.export.solid.SolidSpec`),
    the solid of the STEP file (:func:`camgen.export.step.cam_solid`, default tolerances)."""
    from camgen.export.step import cam_solid

    return iges_text(cam_solid(contour, body, name, pockets=pockets), name).encode("ascii")


def writer(cam: "CamResult", run: "RunSettings", fmt: str) -> bytes:
    """The registered ``iges`` output of a plate cam (with its pockets)."""
    assert cam.contour is not None, f"cam {cam.name!r} has no profile to write"
    return iges_bytes(cam.contour, cam.body, cam.name, cam.pockets)
