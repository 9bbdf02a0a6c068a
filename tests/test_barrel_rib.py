"""A barrel cam's rib (track = "rib"): its faces against the issue's brute force (the union of the
two roller solids, computed here), its thickness check at its threshold, its mesh (watertight, the
volume of an independent integral) and the refusals of what is not built yet."""
from __future__ import annotations

import math

import numpy as np
import pytest

from test_barrel_form import cam as groove_cam, check, run
from test_barrel_geometry import DEG, R_I, R_M, R_O, WALL_TOL, Follower, groove

RIB_W = 12.0


def rib_of(sigma: int, width: float = RIB_W):
    from camgen.synthesis.barrel import BarrelRib

    return BarrelRib(groove("translating", sigma, 4.0, clearance=0.1), width)


@pytest.mark.parametrize("sigma", [1, -1])
def test_rib_faces_match_the_union_of_the_two_roller_solids(sigma):
    """The upper face is the lower edge of the union of the upper roller (axis at z_c + o), the
    lower face the upper edge of the lower roller's (z_c - o), o = width / 2 + Rr + c / 2."""
    rib = rib_of(sigma)
    o = RIB_W / 2 + 4.0 + 0.05
    assert rib.roller_offset == pytest.approx(o, abs=1e-15)
    rollers = {1: Follower("translating", sigma, 4.05, z0=10.0 + o), -1: Follower("translating", sigma, 4.05, z0=10.0 - o)}
    phi = np.array([0.1, 35.0, 60.0, 100.0, 150.0, 200.0, 240.0, 275.0, 330.0]) * DEG
    worst = 0.0
    for r in (R_I, R_M, R_O):
        for side in (1, -1):
            got = rib.wall_height(side, np.asarray(r), phi)
            bf = np.array([rollers[side].brute_wall(-side, r, p) for p in phi])
            worst = max(worst, float(np.max(np.abs(got - bf))))
    assert worst < WALL_TOL, worst


def test_rib_thickness_check_against_the_brute_force_and_at_its_threshold():
    """The least width along z (the check's grid of polar angles at the root, where it is least)
    from the brute force; the width grows one to one with rib_width_mm, so a rib min_wall + 1e-4 mm
    wider than the brute force's least passes and 1e-4 mm narrower fails."""
    from camgen.kinds.barrel import RIB_THICKNESS_SAMPLES

    o = RIB_W / 2 + 8.0 + 0.025  # the form's scene: Rr 8, clearance 0.05
    up, lo = Follower("translating", 1, 8.025, z0=0.0 + o), Follower("translating", 1, 8.025, z0=0.0 - o)
    step = 2.0 * math.pi / RIB_THICKNESS_SAMPLES
    coarse = np.arange(0, RIB_THICKNESS_SAMPLES, 10) * step

    def width(phis):
        return np.array([up.brute_wall(-1, 45.0, p) - lo.brute_wall(1, 45.0, p) for p in phis])

    k = int(np.argmin(width(coarse)))
    fine = coarse[k] + np.arange(-10, 11) * step
    least = float(np.min(width(fine)))
    table = dict(groove_cam(track="rib", rib_width_mm=RIB_W, cylinder_length_mm=90.0, min_wall_mm=2.0))
    _, report = run(table)
    assert check(report, "rib_thickness")["value"] == pytest.approx(least, abs=1e-6)
    excess = RIB_W - least
    for delta, passed in ((1e-4, "pass"), (-1e-4, "fail")):
        _, report = run(dict(table, rib_width_mm=2.0 + excess + delta))
        assert check(report, "rib_thickness")["status"] == passed


@pytest.mark.parametrize("bore", [0.0, 30.0])
def test_rib_mesh_is_watertight_with_the_volume_of_an_independent_integral(bore):
    """manifold3d's volume of the mesh against pi (R_i^2 - R_b^2) L + the rib's integral of its width
    r dr dphi (Gauss-Legendre in r, trapezoid over the periodic polar angle), within chord_tol times
    the mesh's area; admesh (independent) finds no open edge and one part."""
    import manifold3d

    from camgen.export.barrel_rib_solid import rib_solid

    tol = 0.01
    rib = rib_of(1)
    from dataclasses import replace

    rib = replace(rib, groove=replace(rib.groove, bore_radius=0.5 * bore))
    solid = rib_solid(rib, tol)
    m = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=solid.vertices, tri_verts=solid.triangles.astype(np.uint64)))
    assert m.status() == manifold3d.Error.NoError and len(m.decompose()) == 1
    x, wts = np.polynomial.legendre.leggauss(8)
    r = 0.5 * (R_O + R_I) + 0.5 * (R_O - R_I) * x
    phi = 2.0 * math.pi * np.arange(4096) / 4096
    width = rib.thickness(r[:, None], phi[None, :])
    rib_volume = 0.5 * (R_O - R_I) * float(np.sum(wts * r * width.mean(axis=1) * 2.0 * math.pi))
    want = math.pi * (R_I**2 - (0.5 * bore) ** 2) * 70.0 + rib_volume
    v, t = solid.vertices, solid.triangles
    area = 0.5 * float(np.sum(np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1)))
    assert abs(solid.volume - want) <= tol * area, (solid.volume, want, tol * area)


def test_rib_faces_cross_when_the_rib_is_too_narrow():
    """A rib narrower than its rollers' spacing allows: the thickness check fails (negative) and the
    mesh is refused (its faces cross)."""
    from camgen.errors import GeometryError
    from camgen.export.barrel_rib_solid import rib_solid

    rib = rib_of(1, width=0.5)
    assert float(np.min(rib.thickness(np.asarray(R_I), np.linspace(0, 2 * math.pi, 721)))) < 0.0
    with pytest.raises(GeometryError):
        rib_solid(rib, 0.05)


@pytest.mark.parametrize("extra, key", [({"track": "rib"}, "rib_width_mm"), ({"rib_width_mm": 5.0}, "rib_width_mm")])
def test_bad_rib_scenes_are_refused_naming_the_key(extra, key, tmp_path, capsys):
    from camgen.cli import main
    from helpers import scene_toml

    path = tmp_path / "s.toml"
    path.write_text(scene_toml({"output": {"formats": ["dxf"]}, "cams": {"c": groove_cam(**extra)}}))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("camgen: error:") and f"cams.c.{key}" in err[0], err
