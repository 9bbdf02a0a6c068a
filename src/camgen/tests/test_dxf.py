"""DXF drawings, read back by ezdxf and GDAL."""
from __future__ import annotations

import io
import math

import numpy as np
import pytest

from camgen.export.dxf import DxfOptions, contour_to_dxf
from camgen.tests.cams import BODIES, radial_error
from camgen.tests.helpers import distance_to_arcs


def _read_dxf(text):
    import ezdxf

    doc = ezdxf.read(io.StringIO(text))
    assert not doc.audit().has_errors
    assert doc.dxfversion == "AC1024" and doc.header["$INSUNITS"] == 4
    return doc


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_dxf_entities_match_the_contour_by_ezdxf(name, contours, steering):
    contour = contours[name]
    pitch = steering.pitch if name == "steering" else None
    doc = _read_dxf(contour_to_dxf(contour, BODIES[name], pitch))
    msp = doc.modelspace()
    profile = [e for e in msp if e.dxf.layer == "PROFILE"]
    assert len(profile) == contour.n_segments
    for entity, seg in zip(profile, contour.segments):
        if entity.dxftype() == "ARC":
            assert entity.dxf.radius == pytest.approx(seg.radius, abs=1e-9)
        else:
            assert entity.dxftype() == "SPLINE" and entity.dxf.degree == 3
            knots = np.array(entity.knots)
            assert np.all(knots[:4] == knots[0]) and np.all(knots[-4:] == knots[-1])  # clamped
            pts = np.array(list(entity.construction_tool().points(np.linspace(knots[0], knots[-1], 5001))))[:, :2]
            assert np.max(radial_error(contour, pts)) <= 1e-6
    bore = [e for e in msp if e.dxf.layer == "BORE"]
    assert bore and bore[0].dxf.radius == pytest.approx(BODIES[name].bore_diameter / 2)
    assert len([e for e in msp if e.dxf.layer == "KEYWAY"]) == 1
    assert len([e for e in msp if e.dxf.layer == "CENTER"]) == 2
    assert bool([e for e in msp if e.dxf.layer == "PITCH"]) == (pitch is not None)


@pytest.mark.parametrize("name", ["stride", "steering"])
def test_dxf_read_by_gdal_within_1e6(name, contours, tmp_path):
    import pyogrio
    import shapely
    contour = contours[name]
    path = tmp_path / "cam.dxf"
    path.write_text(contour_to_dxf(contour, BODIES[name]))
    pyogrio.set_gdal_config_options({"OGR_ARC_STEPSIZE": "0.5"})  # GDAL samples arcs every 0.5 deg
    meta, _, wkb, fields = pyogrio.raw.read(path)
    layer = fields[list(meta["fields"]).index("Layer")]
    lines = shapely.from_wkb(wkb)[layer == "PROFILE"]
    pts = np.concatenate([shapely.get_coordinates(g) for g in lines])
    assert len(pts) > 100
    if name == "stride":
        assert np.max(distance_to_arcs(pts, contour.segments)) <= 1e-6
    else:
        assert np.max(radial_error(contour, pts)) <= 1e-6
    # the PROFILE pieces go all the way round: their total length is the contour's perimeter
    assert sum(g.length for g in lines) == pytest.approx(contour.length, rel=1e-4)


@pytest.mark.parametrize("tol", [1e-2, 1e-3, 1e-4])
def test_dxf_biarcs_within_tolerance(tol, contours, tmp_path):
    contour = contours["steering"]
    doc = _read_dxf(contour_to_dxf(contour, options=DxfOptions(splines="biarc", biarc_tol=tol)))
    arcs = [e for e in doc.modelspace() if e.dxf.layer == "PROFILE"]
    assert {e.dxftype() for e in arcs} <= {"ARC", "LINE"}
    from types import SimpleNamespace

    segs = [
        SimpleNamespace(center=(e.dxf.center.x, e.dxf.center.y), radius=e.dxf.radius, start_angle=math.radians(e.dxf.start_angle),
                        sweep=math.radians((e.dxf.end_angle - e.dxf.start_angle) % 360))
        for e in arcs if e.dxftype() == "ARC"
    ]
    # every point of the exact profile is within tol of the arcs read back from the file
    samples = contour.evaluate(np.linspace(0, 1, 20000, endpoint=False))
    assert np.max(distance_to_arcs(samples, segs)) <= tol * (1 + 1e-6)
    # and they come back in fewer entities than the spline has pieces when the tolerance allows
    if tol >= 1e-3:
        assert len(arcs) < contour.segments[0].n_pieces

