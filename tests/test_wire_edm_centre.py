"""Wire-EDM programs in the wire-centre mode (wire_compensation = false), run through LinuxCNC's
rs274 and cut in a simulation.

The numbers the programs are judged by come from outside camgen.export.wire_edm_centre: the exact
profile the program was made from, the offsets of the rule the header states (wire radius +
spark gap + allowance k), rs274's canonical moves (no compensation: the program's own path is the
wire's centre) and the profile's arc length.  The checks are those of tests/test_wire_edm.py (its
helpers): cut k stays offset_k - 1 um from the profile and reaches every point outside the tab
within offset_k + 1 um; the tab has its stated length; the cut-off cuts exactly the tab.
"""
from __future__ import annotations

import re

import numpy as np
import pytest

from camgen.export.gcode import MachiningSpec
from camgen.export.wire_edm import wire_edm_program
from camgen.export.wire_edm_spec import WireEdmSpec
from cutting import CUT_TOL, ExactProfile
from test_wire_edm import _arc_lengths, _in_stretch, cams, cut_report, needs_rs274, run_rs274, tab_stretch  # noqa: F401 (fixtures)


def _program(contour, thickness, name, skims, allowances, spline_mode="biarcs", **wire_keys) -> str:
    wire = WireEdmSpec(wire_diameter=0.25, spark_gap=0.03, skim_cuts=skims, cut_allowances=allowances, tab_width=4.0,
                       wire_compensation=False, **wire_keys)
    return wire_edm_program(contour, MachiningSpec(dialect="wire_edm", chord_tol=1e-3, spline_mode=spline_mode, wire_edm=wire),
                            name, "edm", thickness)


@pytest.mark.parametrize("skims, allowances, spline_mode", [(2, None, "biarcs"), (0, None, "lines"), (3, (0.15, 0.05, 0.01), "biarcs")])
@pytest.mark.usefixtures("needs_rs274")
def test_each_wire_centre_cut_leaves_its_allowance_and_the_tab_its_width(cams, skims, allowances, spline_mode, tmp_path):
    for name, contour, thickness in cams:
        program = _program(contour, thickness, name, skims, allowances, spline_mode)
        kerf = 0.125 + 0.03
        expected = [kerf + a for a in (allowances or tuple(0.1 * 0.2**k for k in range(skims)))] + [kerf]  # the documented rule
        code = [re.sub(r"\(.*?\)", "", line) for line in program.splitlines()]
        assert not any(re.search(r"\bG4[12]|\bD\d", line) for line in code), name  # no compensation, no register
        assert all(f"offset by {o:.4f}" in program for o in expected), name  # the header states each cut's offset
        assert "wire-centre path" in program and "offset refit" in program
        status, message, chains = run_rs274(program, [1e-9] * len(expected), tmp_path)  # registers unused: ~0 in the table
        assert status == 0, (name, message)
        n = skims + 1
        assert len(chains) == n + 1, (name, len(chains))  # n cuts, then the cut-off after the last stop
        profile = ExactProfile(contour)
        s = _arc_lengths(profile.vertices)[:-1]
        total = float(_arc_lengths(profile.vertices)[-1])
        for k, (chain, offset) in enumerate(zip(chains[:n], expected), 1):
            s_start, s_stop = tab_stretch(chain, profile)
            assert abs((s_stop - s_start) % total - 4.0) <= CUT_TOL, (name, k, s_stop - s_start)
            tab = _in_stretch(s, s_start, s_stop, total)
            gouge, proud = cut_report(chain, profile, offset, skip=tab)
            assert gouge <= CUT_TOL and proud <= CUT_TOL, (name, k, gouge, proud)
        gouge, proud = cut_report(chains[n], profile, expected[-1], skip=~tab)
        assert gouge <= CUT_TOL and proud <= CUT_TOL, (name, "cut-off", gouge, proud)
        assert all(mv["end"][2] == 0.0 and mv["start"][2] == 0.0 for c in chains for mv in c), name  # no Z


@pytest.mark.usefixtures("needs_rs274")
def test_the_simulation_sees_a_wire_centre_path_at_the_wrong_offset(cams, tmp_path):
    """The check itself: the last cut judged against an offset 5 um larger than its own (as if the
    program had used a thinner wire) gouges by 5 um, more than the tests accept."""
    name, contour, thickness = cams[0]
    program = _program(contour, thickness, name, 0, None)
    status, message, chains = run_rs274(program, [1e-9], tmp_path)
    assert status == 0, message
    profile = ExactProfile(contour)
    gouge, _ = cut_report(chains[0], profile, 0.155 + 0.005, skip=np.zeros(len(profile.vertices), bool))
    assert gouge > CUT_TOL and abs(gouge - 0.005) <= CUT_TOL, gouge


def test_the_key_is_read_and_refused_without_its_dialect(tmp_path):
    from test_wire_edm import CAM, _cli

    proc = _cli(f'[output]\nformats = ["ngc"]\n[machining]\ndialect = "wire_edm"\nwire_compensation = false\n{CAM}', tmp_path)
    assert proc.returncode == 0, proc.stderr
    program = (tmp_path / "out" / "edm" / "c.ngc").read_text()
    assert "wire-centre path" in program and not re.search(r"^[^(]*G41", program, re.M)
    (tmp_path / "milling").mkdir()  # a fresh directory: nothing written there
    proc = _cli(f'[output]\nformats = ["ngc"]\n[machining]\nwire_compensation = false\n{CAM}', tmp_path / "milling")
    assert proc.returncode == 2 and "machining.wire_compensation" in proc.stderr, proc.stderr
