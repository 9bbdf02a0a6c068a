"""A design evaluation's dynamics figures (issue 28 item 6): its plan has no report figures, so
``figures.dynamics`` holds only what a design's row reads (the peak torque, the jump speed, the
peak contact stress: camgen.study.design.main_figures), each the value ``camgen run`` writes to
report.json for the same scene; the report-only summaries (rms torque and power, energy, where
the peaks are) are not made."""
from __future__ import annotations

import copy
import json
import subprocess
import sys
import tomllib

import pytest

from helpers import scene_toml

#: Changes of templates/plate_cam.toml: the template, a failing torque limit, a spring too weak at speed (the jump fails).
DESIGNS = {
    "template": {},
    "low_torque_limit": {"torque_limit_n_m": 0.5, "rpm": 600.0},
    "fast": {"rpm": 3000.0},
}
#: The keys of figures.dynamics a design's row reads.
ROW_KEYS = {"torque_peak_Nm", "jump_rpm", "hertz_stress_peak_MPa"}


def _scene(change: dict) -> dict:
    from camgen.scene import template_path

    data = tomllib.loads(template_path("plate_cam").read_text(encoding="utf-8"))
    data["output"]["formats"] = ["dxf"]
    data["cams"]["plate"].update(copy.deepcopy(change))
    return data


@pytest.mark.parametrize("design", sorted(DESIGNS))
def test_the_design_evaluations_dynamics_figures_are_camgen_runs(design, tmp_path):
    from camgen.evaluation import evaluation_plan
    from camgen.pipeline import compute
    from camgen.scene import parse_scene
    from camgen.study.design import main_figures

    data = _scene(DESIGNS[design])
    scene = parse_scene(data, "plate")
    (cam,) = compute(scene, evaluation_plan(scene)).cams
    mine = dict(cam.figures["dynamics"])
    assert set(mine) == ROW_KEYS | {"closure", "follower_motion"}  # no report-only figure made
    text = scene_toml(data) + "[machining]\n" + "".join(f"{k} = {v!r}\n" for k, v in data["machining"].items())
    path = tmp_path / "plate.toml"
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-P", "-m", "camgen", "run", str(path), "-o", str(out), "--only", "dxf"],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode in (0, 1), proc.stderr
    report = json.loads(next(out.rglob("report.json")).read_text(encoding="utf-8"))
    cams = report["cams"]
    theirs = (cams["plate"] if isinstance(cams, dict) else cams[0])["figures"]["dynamics"]
    for key in mine:  # bit for bit: report.json's floats read back exactly
        assert mine[key] == theirs[key], (key, mine[key], theirs[key])
    assert {"torque_rms_Nm", "power_rms_W", "energy_per_turn_J", "torque_peak_deg"} <= set(theirs)
    row = main_figures(cam)
    assert row["torque_peak_n_m"] == theirs["torque_peak_Nm"] and row["jump_rpm"] == theirs["jump_rpm"]
    assert row["contact_stress_mpa"] == theirs["hertz_stress_peak_MPa"]
