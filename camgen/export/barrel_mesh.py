"""The barrel cam's mesh stage: the body of a groove (:mod:`camgen.export.barrel_solid`) or of a
rib (:mod:`camgen.export.barrel_rib_solid`) at the chord tolerance, registered by the barrel form
(:attr:`camgen.forms.base.CamForm.stages`)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

from camgen.errors import GeometryError
from camgen.export.barrel_rib_solid import rib_solid
from camgen.export.barrel_solid import barrel_solid

if TYPE_CHECKING:
    from camgen.outputs import OutputSpec
    from camgen.results import CamResult

__all__ = ["mesh_stage"]


def mesh_stage(cam: "CamResult", output: "OutputSpec", progress: Any) -> "CamResult":
    """``cam`` (a barrel cam: ``cam.built.groove``) with its solid at ``output.chord_tol``, or the
    failure that stopped it (a failed check): :func:`camgen.pipeline.mesh_stage`'s signature."""
    from camgen.checks import CheckResult
    from camgen.kinds.barrel import BarrelCam

    progress(f"meshing cam '{cam.name}'")
    assert isinstance(cam.built, BarrelCam), f"cam {cam.name!r} is not a barrel cam"
    try:
        if cam.built.rib is not None:  # track = "rib": the root cylinder with the rib on it
            return cam.with_(solid=rib_solid(cam.built.rib, output.chord_tol, cam.name, tuple(output.formats)))
        return cam.with_(solid=barrel_solid(cam.built.groove, output.chord_tol, cam.name, tuple(output.formats)))
    except GeometryError as exc:  # the failed check camgen.pipeline.mesh_stage reports: no manufacturing file
        failure = CheckResult("solid_export", "failed", "made as designed", "", "", False, [], " ".join(str(exc).split()),
                              blocks_manufacture=True)
        return cam.with_(mesh_failures=cam.mesh_failures + (failure,))
