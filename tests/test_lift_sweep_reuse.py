"""A sweep of the rise and return (a new motion program at every design) shares the layouts of the
angles its programs are asked at (camgen.synthesis.laws ``_angle_layout``, ``_grid_layout``) and
each segment's VDI 2143 row (camgen.synthesis.vdi2143 ``_law_values``): rows made one after the
other in this process, the caches hit from the second design on, equal bit for bit (every column
but ``eval_ms``, floats through JSON's shortest repr) the row a fresh process makes of the same
design alone (nothing kept)."""
from __future__ import annotations

import json
import subprocess
import sys

from camgen.scene import template_path
from camgen.study.design import StudyScene, evaluate_point
from camgen.study.keys import resolve_key

PLATE = template_path("plate_cam")
#: The rise's lift per design (the return's is its negative), in the order evaluated.
LIFTS = [14.0, 18.5, 11.25]

_ALONE = """
import json, sys
from camgen.study.design import StudyScene, evaluate_point
from camgen.study.keys import resolve_key
study = StudyScene.load(sys.argv[1])
keys = [resolve_key(study.data, f"cams.plate.segments[{i}].lift_mm") for i in (0, 2)]
lift = float(sys.argv[2])
row = evaluate_point(study, keys, [lift, -lift])
row.pop("eval_ms")
print(json.dumps(row, sort_keys=True))
"""


def test_rows_of_a_lift_sweep_in_a_row_equal_each_design_alone_in_a_fresh_process():
    from camgen.synthesis import laws, vdi2143

    procs = [subprocess.Popen([sys.executable, "-c", _ALONE, str(PLATE), repr(lift)], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for lift in LIFTS]
    try:
        _compare(procs, laws, vdi2143)
    finally:
        for proc in procs:  # none left running, whatever failed
            if proc.poll() is None:
                proc.kill()
            proc.communicate()


def _compare(procs, laws, vdi2143):  # type: ignore[no-untyped-def]
    from camgen.motions.motion_law import _cached_law

    study = StudyScene.load(str(PLATE))
    keys = [resolve_key(study.data, f"cams.plate.segments[{i}].lift_mm") for i in (0, 2)]
    caches = (laws._angle_layout, laws._grid_layout, vdi2143._law_values)
    _cached_law.cache_clear()  # (a program an earlier test read for the same lifts keeps its values: no layout asked)
    for cache in caches:
        cache.cache_clear()
    rows = []
    for k, lift in enumerate(LIFTS):
        before = [cache.cache_info().hits for cache in caches]
        row = evaluate_point(study, keys, [lift, -lift])
        row.pop("eval_ms")
        rows.append(json.dumps(row, sort_keys=True))
        if k:  # a new program whose pieces lie where the last one's did: every cache serves it
            assert all(cache.cache_info().hits > b for cache, b in zip(caches, before)), k
        assert row["status"] in ("pass", "fail") and row["error"] == "", row["error"]
    for lift, proc, mine in zip(LIFTS, procs, rows):
        stdout, stderr = proc.communicate(timeout=300)
        assert proc.returncode == 0, stderr
        assert json.loads(stdout) == json.loads(mine), lift
        assert stdout.strip() == mine, lift
    assert len(set(rows)) == len(LIFTS)  # the lifts change the rows
