"""A run is all or nothing (issue "Trust", item 8): killing `camgen run` at any moment leaves
the output folder holding one complete run, the previous or the new one, with no temp files;
the next run clears what the killed one left beside it."""
from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time

import pytest

SCENE = """name = "kill"
[output]
formats = ["dxf", "points", "lift", "stl"]
[cams.c]
kind = "three_arc"
a_mm = {a}
b_mm = 160.0
c_mm = 25.0
"""
TRIALS = 16


def _snapshot(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _run(scene, outdir):
    return subprocess.Popen([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(outdir), "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def test_killed_runs_leave_the_old_or_the_new_complete_run(tmp_path):
    scenes = {}
    references = {}
    for label, a in (("A", 220.0), ("B", 230.0)):
        scenes[label] = tmp_path / f"{label}.toml"
        scenes[label].write_text(SCENE.format(a=a))
        ref = tmp_path / f"ref_{label}"
        start = time.perf_counter()
        assert _run(scenes[label], ref).wait(timeout=300) == 0
        duration = time.perf_counter() - start
        references[label] = _snapshot(ref / "kill")
    assert references["A"] != references["B"] and set(references["A"]) == set(references["B"])
    out = tmp_path / "out"
    assert _run(scenes["A"], out).wait(timeout=300) == 0
    state = "A"
    rng = random.Random(7)
    outcomes = {"old": 0, "new": 0}
    for _ in range(TRIALS):
        new = "B" if state == "A" else "A"
        proc = _run(scenes[new], out)
        time.sleep(rng.uniform(0.0, 1.2 * duration))
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        now = _snapshot(out / "kill")
        assert now in (references["A"], references["B"]), "the folder holds a mix of runs or a partial run"
        assert not [name for name in now if name.startswith(".")]  # no temp files inside
        state = "A" if now == references["A"] else "B"
        outcomes["new" if state == new else "old"] += 1
    # the next run clears what the killed runs left beside the folder
    assert _run(scenes["A"], out).wait(timeout=300) == 0
    assert sorted(p.name for p in out.iterdir()) == ["kill"]
    assert _snapshot(out / "kill") == references["A"]
    assert sum(outcomes.values()) == TRIALS


def test_a_run_interrupted_between_the_two_renames_is_put_back(tmp_path, monkeypatch):
    """Where the kernel cannot swap folders in one step, a crash between the two renames leaves
    the previous run under `.camgen-<scene>.<pid>.<token>.retired`; the next run restores it
    before anything else."""
    from camgen import staging

    target = tmp_path / "scene"
    staging.write_run(target, {"a.txt": "old"})
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True).stdout.strip()
    os.rename(target, tmp_path / f".camgen-scene.{dead}.abcd1234.retired")  # the state a crash would leave
    (tmp_path / f".camgen-scene.{dead}.ffff0000.staging").mkdir()  # a half-written new run
    staging.recover(target)
    assert (target / "a.txt").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene"]


def test_the_fallback_without_an_atomic_swap_writes_the_new_run(tmp_path, monkeypatch):
    from camgen import staging

    monkeypatch.setattr(staging, "exchange", lambda a, b: False)
    target = tmp_path / "scene"
    staging.write_run(target, {"a.txt": "old", "b.txt": "gone"})
    staging.write_run(target, {"a.txt": "new"})
    assert {p.name: p.read_text() for p in target.iterdir()} == {"a.txt": "new"}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene"]


@pytest.mark.parametrize("name", ["../x", "sub/x"])
def test_file_names_cannot_leave_the_run_folder(name, tmp_path):
    from camgen import staging
    from camgen.errors import ExportError

    with pytest.raises(ExportError, match="outside"):
        staging.write_run(tmp_path / "scene", {name: "x"})
    assert not (tmp_path / "x").exists() and not (tmp_path / "scene").exists()
