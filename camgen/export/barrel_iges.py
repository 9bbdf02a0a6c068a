"""IGES 5.3 (mm) of a barrel cam: the STEP file's solid (:mod:`camgen.export.barrel_step` for a
groove, :mod:`camgen.export.barrel_rib_step` for a rib: exact cylinders and planes, the walls or
faces bicubic B-spline surfaces within ``fit_tol_mm`` of the exact ones) written by OCCT's IGES
processor in its B-rep mode as a plate cam's is (:func:`camgen.export.iges.iges_text`: one
manifold solid B-rep object, entity 186; units mm; fixed dates).  Needs the ``step`` extra (OCP).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["barrel_iges_bytes", "writer"]


def barrel_iges_bytes(groove: Any, rib: Any = None, name: str = "cam") -> bytes:
    """IGES file content of the barrel cam of ``groove`` (:class:`camgen.synthesis.barrel.BarrelGroove`),
    or of ``rib`` (:class:`camgen.synthesis.barrel.BarrelRib`) when given: the STEP file's solid."""
    from camgen.export.barrel_rib_step import rib_solid
    from camgen.export.barrel_step import groove_solid
    from camgen.export.iges import iges_text

    shape = rib_solid(rib, name) if rib is not None else groove_solid(groove, name)
    return iges_text(shape, name).encode("ascii")


def writer(cam: "CamResult", run: "RunSettings", fmt: str) -> bytes:
    """The barrel form's IGES writer (``CamForm.writers["iges"]``): the rib's solid for
    ``track = "rib"``, else the groove's."""
    from camgen.kinds.barrel import BarrelCam

    assert isinstance(cam.built, BarrelCam), f"cam {cam.name!r} is not a barrel cam"
    return barrel_iges_bytes(cam.built.groove, cam.built.rib, cam.name)
