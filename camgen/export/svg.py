"""SVG of what is cut, for laser and plasma cutters: the profile, the bore and keyway, and each
pocket wall, as stroked paths of exact arcs and lines in millimetres.

Units and frame: ``width`` and ``height`` are in ``mm`` and the ``viewBox`` spans the same
numbers, so one user unit is one millimetre and the file prints and imports at 1:1.  The cam
frame has y up, SVG's y down: every point (x, y) is written as (x, -y) (the y axis flipped about
the x axis), so the drawing looks as it does in the DXF and the cam axis is the user-space origin.
The ``viewBox`` is the exact bounding box of everything drawn (as the DXF's extents,
:func:`camgen.export.dxf.drawing_bounds`) grown by :data:`MARGIN_MM` on every side.

Curves are the DXF's in its arc mode (:func:`camgen.export.dxf.arc_contour`): arc segments
exactly, spline segments as G1 biarcs within the chord tolerance, straight pieces as lines.  An
arc is an ``A`` command (radius, large-arc flag, sweep flag 0 for an arc counter-clockwise in the
cam frame, which the flip makes a negative-angle arc in SVG's frame), cut into pieces of at most
:data:`MAX_ARC_SWEEP` so that a reader finds each centre from the end points and the radius
without the ill-conditioning of a sweep near a whole turn (a whole circle is four quarter arcs).
Each closed curve is one path ending in ``Z``; numbers are decimals rounded to
:data:`RESOLUTION_MM` (1 nm: a hundredth of the least chord tolerance, no exponents).  Every path is stroked (``fill="none"``, stroke
:data:`STROKE_MM` mm), grouped by the DXF's layer names (``<g id="PROFILE">``, ``BORE``, wall
layers); the tolerance and the flip are stated in the file's ``<desc>``.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from camgen.contour import Arc, Contour
from camgen.errors import ExportError

if TYPE_CHECKING:
    from camgen.results import CamResult
    from camgen.writers import RunSettings

__all__ = ["DECIMALS", "MARGIN_MM", "MAX_ARC_SWEEP", "RESOLUTION_MM", "STROKE_MM", "profile_svg", "writer"]

#: Margin around the drawing's exact bounding box, mm.
MARGIN_MM = 1.0
#: Stroke width of every path, mm (a hairline for laser software that cuts stroked paths).
STROKE_MM = 0.1
#: Decimal places of every number (mm) and the resolution they give.
DECIMALS = 9
RESOLUTION_MM = 10.0 ** -DECIMALS
#: Largest sweep of one ``A`` command (rad): a quarter turn.
MAX_ARC_SWEEP = 0.5 * math.pi


def _num(value: float) -> str:
    """``value`` (mm) to :data:`DECIMALS` places, trailing zeros dropped, never ``-0``."""
    x = float(value)
    if not math.isfinite(x):
        raise ExportError(f"cannot write SVG: a coordinate is {x!r} (not a finite number)")
    text = f"{x:.{DECIMALS}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _xy(p: np.ndarray) -> str:
    """A point of the cam frame in SVG user units (y flipped)."""
    return f"{_num(p[0])},{_num(-p[1])}"


def _arc_commands(arc: Arc) -> list[str]:
    """``A`` commands of ``arc`` (from the current point, its start), each at most :data:`MAX_ARC_SWEEP`."""
    count = max(1, math.ceil(abs(arc.sweep) / MAX_ARC_SWEEP - 1e-12))
    ends = arc.point(np.arange(1, count + 1) / count)
    r = _num(arc.radius)
    sweep_flag = "0" if arc.sweep > 0 else "1"  # counter-clockwise in the cam frame: negative angles once y is flipped
    return [f"A{r},{r} 0 0 {sweep_flag} {_xy(p)}" for p in ends]


def _path_data(contour: Contour) -> str:
    """Path data of a closed curve of arcs and straight pieces (as :func:`camgen.export.dxf.arc_contour` gives)."""
    commands = [f"M{_xy(contour.segments[0].start_point)}"]
    for seg in contour.segments:
        if isinstance(seg, Arc):
            commands.extend(_arc_commands(seg))
        elif seg.n_pieces == 1 and not np.any(seg.coeffs[:-2]):
            commands.append(f"L{_xy(seg.end_point)}")
        else:  # pragma: no cover - arc_contour leaves none
            raise ExportError("cannot write SVG: a curved spline segment (convert it to biarcs first)")
    commands.append("Z")
    return " ".join(commands)


def _bore_path(body: Any) -> str:
    """The bore (a circle) or the bore arc outside the keyway and the keyway's three sides: one closed path."""
    r = body.bore_diameter / 2
    if body.keyway_width <= 0:
        return _path_data(Contour([Arc((0.0, 0.0), r, 0.0, 2.0 * math.pi)]))
    corners = body.keyway_outside_bore()  # from the bore circle at -w/2 out, across, back to the circle at +w/2
    gap = math.asin(body.keyway_width / 2 / r)
    arc = Arc((0.0, 0.0), r, body.keyway_angle + gap, 2.0 * math.pi - 2.0 * gap)  # +w/2 side round to the -w/2 side
    commands = [f"M{_xy(corners[3])}", *_arc_commands(arc), *(f"L{_xy(p)}" for p in corners[1:3]), "Z"]
    return " ".join(commands)


def profile_svg(contour: Contour, body: Any = None, pockets: Sequence[Any] = (), chord_tol: float = 1e-3, name: str = "cam") -> str:
    """SVG text of what is cut (module notes): ``contour`` (the PROFILE), the bore and keyway of
    ``body`` (a :class:`camgen.body.BodySpec`; None or no bore: none) and every wall of
    ``pockets`` (:class:`camgen.kinds.base.Pocket`) on its layer; spline segments as biarcs within
    ``chord_tol`` mm."""
    from camgen.errors import require_positive
    from camgen.export.dxf import PROFILE_LAYER, arc_contour, drawing_bounds

    tol = require_positive("chord_tol", chord_tol, "mm")
    profile = arc_contour(contour, tol)
    walls = [(wall.layer, arc_contour(wall.contour, tol)) for pocket in pockets for wall in pocket.walls]
    has_bore = body is not None and body.bore_diameter > 0
    x0, y0, x1, y1 = drawing_bounds(profile, body if has_bore else None, None, 0.0, None, [wall for _, wall in walls])
    x0, y0, x1, y1 = x0 - MARGIN_MM, y0 - MARGIN_MM, x1 + MARGIN_MM, y1 + MARGIN_MM
    width, height = _num(x1 - x0), _num(y1 - y0)
    layers = [(PROFILE_LAYER, _path_data(profile))]
    if has_bore:
        layers.append(("BORE", _bore_path(body)))
    layers += [(layer, _path_data(wall)) for layer, wall in walls]
    style = f'fill="none" stroke="#000000" stroke-width="{_num(STROKE_MM)}"'
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{width}mm" height="{height}mm" '
        f'viewBox="{_num(x0)} {_num(-y1)} {width} {height}">',
        f"<title>camgen cam {_escape(name)}: what is cut</title>",
        f"<desc>1 user unit = 1 mm; y of the cam frame is -y here (y axis flipped, cam axis at 0,0); arcs exact, "
        f"spline segments as biarcs within {_num(tol)} mm; numbers to {RESOLUTION_MM:g} mm</desc>",
    ]
    for layer, data in layers:
        lines.append(f'<g id="{layer}" {style}><path d="{data}"/></g>')
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def writer(cam: "CamResult", run: "RunSettings", fmt: str) -> str:
    """The registered ``svg`` output: what is cut, at the run's chord tolerance."""
    assert cam.contour is not None, f"cam {cam.name!r} has no profile to write"
    return profile_svg(cam.contour, cam.body, cam.pockets, run.output.chord_tol, cam.name)
