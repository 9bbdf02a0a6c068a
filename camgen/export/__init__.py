"""camgen's file writers and the geometry they need (DXF, point and lift tables, surface
meshes, STEP, FEA meshes, G-code), one module per format or job.  The package namespace imports
none of them: import the module you need."""
from __future__ import annotations

__all__: list[str] = []
