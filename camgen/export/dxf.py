"""2-D DXF export with ezdxf: R2010, units mm, arcs as exact ARC entities.

Spline segments are written as clamped cubic B-splines built from their Bezier pieces
(knots of multiplicity 3 at every break): an exact representation of the piecewise cubic
that independent readers evaluate correctly (fit-point-only or raw periodic-knot SPLINEs
are misread, see ``shared/research/ecosystem.md`` section 3).

Files are deterministic: ezdxf's fixed-metadata mode replaces the creation time stamps and
random GUIDs, and the CLASSES section is sorted (ezdxf fills it in hash-seed order).
"""
from __future__ import annotations

import io
import math
from collections import OrderedDict
from pathlib import Path

import numpy as np

from camgen.contour import Arc, Contour, Spline
from camgen.export.atomic import write_atomic

PROFILE_LAYER = "PROFILE"


def spline_bezier_controls(spline: Spline) -> tuple[np.ndarray, np.ndarray]:
    """Exact clamped B-spline form of a piecewise cubic: knots (3K + 5,) and control points (3K + 1, 2).

    Each cubic piece on ``[t_i, t_i + h]`` becomes its four Bezier control points; interior
    breaks get knot multiplicity 3, the ends multiplicity 4.
    """
    a = spline.coeffs[::-1]  # ascending powers in tau: (4, K, 2)
    h = np.diff(spline.breaks)[:, None]
    # power basis in s = tau / h: p(s) = a0 + a1 h s + a2 h^2 s^2 + a3 h^3 s^3
    b0 = a[0]
    b1 = a[1] * h
    b2 = a[2] * h**2
    b3 = a[3] * h**3
    p0 = b0
    p1 = b0 + b1 / 3.0
    p2 = b0 + 2.0 * b1 / 3.0 + b2 / 3.0
    p3 = b0 + b1 + b2 + b3
    controls = np.concatenate([p0[:1], np.stack([p1, p2, p3], axis=1).reshape(-1, 2)])
    t = spline.breaks
    knots = np.concatenate([[t[0]] * 4, np.repeat(t[1:-1], 3), [t[-1]] * 4])
    return knots, controls


def contour_to_dxf(contour: Contour, layer: str = PROFILE_LAYER) -> str:
    """DXF text (R2010, $INSUNITS = 4 mm) of ``contour``: one ARC or SPLINE entity per segment."""
    import ezdxf

    previous = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True  # fixed dates, GUIDs and marker string
    try:
        return _contour_to_dxf(contour, layer)
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = previous


def _contour_to_dxf(contour: Contour, layer: str) -> str:
    import ezdxf
    from ezdxf import units

    doc = ezdxf.new("R2010", units=units.MM)
    doc.header["$MEASUREMENT"] = 1
    doc.header["$LUNITS"] = 2
    doc.header["$LUPREC"] = 6
    doc.layers.add(layer, color=7)
    msp = doc.modelspace()
    for seg in contour.segments:
        if isinstance(seg, Arc):
            start = math.degrees(seg.start_angle)
            end = math.degrees(seg.start_angle + seg.sweep)
            if seg.sweep < 0:  # DXF arcs always run counter-clockwise from start to end
                start, end = end, start
            msp.add_arc(seg.center, seg.radius, start, end, dxfattribs={"layer": layer})
        else:
            knots, controls = spline_bezier_controls(seg)
            msp.add_open_spline(controls, degree=3, knots=knots, dxfattribs={"layer": layer})
    # ezdxf adds CLASS entries from a set of the entity types in use, so their order follows
    # Python's hash seed; add them now and sort them so every process writes the same bytes
    doc.classes.add_required_classes(doc.dxfversion)
    doc.classes.classes = OrderedDict(sorted(doc.classes.classes.items()))
    stream = io.StringIO()
    doc.write(stream)
    return stream.getvalue()


def write_dxf(contour: Contour, path: str | Path) -> Path:
    """Write ``contour`` to ``path`` as DXF, atomically."""
    return write_atomic(path, contour_to_dxf(contour))
