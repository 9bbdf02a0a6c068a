"""What every export of a body with pockets shares: the walls flattened, their layers and their
vertex count, the checks every writer makes of them, and the refusal of an output.

A pocket (:class:`camgen.kinds.base.Pocket`) is the region inside its ``walls[0]`` and outside
its other walls, cut from the body's top face (z = thickness) down ``depth`` mm; the body is the
cam's outline extruded by the thickness, minus bore and keyway, minus its pockets.  Nothing here
names a form: a groove's two walls and a slot's one loop go through the same functions.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, NoReturn, Sequence

import numpy as np

from camgen.errors import ExportError, GeometryError, ParameterError

if TYPE_CHECKING:
    from camgen.kinds.base import Pocket

__all__ = ["POCKET_LAYER_COLORS", "check_pockets", "refuse_pocket_format", "wall_flat_count", "wall_loops"]

#: ACI colours of the pockets' wall layers in the DXF, in order (cycled): 5 blue, 30 orange,
#: 140, 200, 240; none of the colours of the PROFILE, BORE, KEYWAY and construction layers.
POCKET_LAYER_COLORS = (5, 30, 140, 200, 240)


def check_pockets(pockets: "Sequence[Pocket]", thickness: float, reserved: Sequence[str] = ()) -> None:
    """Refuse pockets no file can hold (a form's bug, not an input error): a pocket without
    walls or with a depth outside (0, thickness], two walls on one layer or a wall on a
    ``reserved`` layer (PROFILE, BORE, ...; DXF layer names ignore case)."""
    seen = {name.upper() for name in reserved}
    for pocket in pockets:
        if not pocket.walls:
            raise ExportError(f"pocket {pocket.name!r} has no walls")
        if not 0.0 < pocket.depth <= thickness:
            raise GeometryError(f"pocket {pocket.name!r} is {pocket.depth:g} mm deep in a body {thickness:g} mm thick "
                                "(its depth must be > 0 and at most the thickness)")
        for wall in pocket.walls:
            if wall.layer.upper() in seen:
                raise ExportError(f"pocket {pocket.name!r}: the layer {wall.layer!r} is taken by another wall or by the part")
            seen.add(wall.layer.upper())


def wall_loops(pockets: "Sequence[Pocket]", chord_tol: float) -> list[tuple[str, np.ndarray]]:
    """Every wall of ``pockets`` in order as (its layer, its flattened polygon (n, 2), mm,
    counter-clockwise, first vertex not repeated): each chord within ``chord_tol`` mm of the wall
    (:meth:`camgen.contour.Contour.flatten`)."""
    return [(wall.layer, wall.contour.flatten(chord_tol)) for pocket in pockets for wall in pocket.walls]


def wall_flat_count(pockets: "Sequence[Pocket]", chord_tol: float) -> int:
    """Vertices of every wall flattened at ``chord_tol`` mm (what the point list and the meshes
    hold besides the outline and the hole)."""
    return sum(int(wall.contour.flatten_params(chord_tol).size) for pocket in pockets for wall in pocket.walls)


def refuse_pocket_format(cam: str, fmt: str, pockets: "Sequence[Pocket]", why: str) -> NoReturn:
    """Raise the one-line refusal of output ``fmt`` for cam ``cam``, whose body has ``pockets``:
    a :class:`ParameterError` naming ``output.formats``, the format, the cam and ``why``."""
    walls = ", ".join(wall.layer for pocket in pockets for wall in pocket.walls)
    raise ParameterError("output.formats", fmt, f"formats without {fmt} for cam '{cam}'",
                         f"its body has pockets (walls {walls}) and {why}")
