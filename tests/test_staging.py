"""A run is all or nothing (issue "Trust", item 8; "Trust, round 2", items 7 and 8): killing
`camgen run` at any moment leaves the output folder holding one complete run, the previous or the
new one, with no temp files there or in $TMPDIR; the next run clears what a SIGKILLed one left
beside it.  SIGINT and SIGTERM end a run with one line and status 130 / 143, and leave nothing
beside the folder."""
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
SIGNAL_TRIALS = 10


def _snapshot(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _run(scene, outdir, tmpdir=None, stderr=subprocess.DEVNULL):
    env = {**os.environ, **({"TMPDIR": str(tmpdir)} if tmpdir is not None else {})}
    return subprocess.Popen([sys.executable, "-m", "camgen", "run", str(scene), "-o", str(outdir), "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=stderr, env=env)


def _handles_signals(pid: int) -> bool:
    """Whether the process catches SIGTERM yet (Linux: the SigCgt mask of /proc/PID/status), i.e.
    camgen's main() has installed its handlers: before that the interpreter is still starting."""
    try:
        with open(f"/proc/{pid}/status") as status:
            mask = next(int(line.split()[1], 16) for line in status if line.startswith("SigCgt:"))
    except (OSError, StopIteration):
        return False
    return bool(mask >> (signal.SIGTERM - 1) & 1)


def _references(tmp_path):
    """The two scenes, their complete runs, and how long a run lasts in all and once its signal
    handlers are in (to spread the signals over a run; no time is asserted)."""
    scenes, references, durations, working = {}, {}, [], []
    for label, a in (("A", 220.0), ("B", 230.0)):
        scenes[label] = tmp_path / f"{label}.toml"
        scenes[label].write_text(SCENE.format(a=a))
        ref = tmp_path / f"ref_{label}"
        start = time.perf_counter()
        proc = _run(scenes[label], ref)
        while proc.poll() is None and not _handles_signals(proc.pid):
            time.sleep(0.001)
        ready = time.perf_counter()
        assert proc.wait(timeout=300) == 0
        durations.append(time.perf_counter() - start)
        working.append(time.perf_counter() - ready)
        references[label] = _snapshot(ref / "kill")
    assert references["A"] != references["B"] and set(references["A"]) == set(references["B"])
    return scenes, references, max(durations), min(working)


def test_killed_runs_leave_the_old_or_the_new_complete_run(tmp_path):
    scenes, references, duration, _ = _references(tmp_path)
    out = tmp_path / "out"
    temp = tmp_path / "tmpdir"
    temp.mkdir()
    assert _run(scenes["A"], out).wait(timeout=300) == 0
    state = "A"
    rng = random.Random(7)
    outcomes = {"old": 0, "new": 0}
    for _ in range(TRIALS):
        new = "B" if state == "A" else "A"
        proc = _run(scenes[new], out, temp)
        time.sleep(rng.uniform(0.0, 1.2 * duration))
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
        now = _snapshot(out / "kill")
        assert now in (references["A"], references["B"]), "the folder holds a mix of runs or a partial run"
        assert not [name for name in now if name.startswith(".")]  # no temp files inside
        assert list(temp.iterdir()) == [], "a killed run left files in $TMPDIR"
        state = "A" if now == references["A"] else "B"
        outcomes["new" if state == new else "old"] += 1
    # the next run clears what the killed runs left beside the folder
    assert _run(scenes["A"], out).wait(timeout=300) == 0
    assert sorted(p.name for p in out.iterdir()) == ["kill"]
    assert _snapshot(out / "kill") == references["A"]
    assert sum(outcomes.values()) == TRIALS


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="waits on /proc/PID/status for the handlers")
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_interrupted_runs_end_with_one_line_and_leave_nothing_behind(signum, tmp_path):
    """SIGINT / SIGTERM at random moments of a run (once its handlers are in, i.e. past the
    interpreter's start-up): status 130 / 143 and the one line "camgen: stopped by SIG...", or
    0 when the run had finished; the folder holds the old or the new complete run, nothing else
    stands beside it (the staging folder is removed on the way out) and $TMPDIR stays empty."""
    scenes, references, _, working = _references(tmp_path)
    out = tmp_path / "out"
    temp = tmp_path / "tmpdir"
    temp.mkdir()
    assert _run(scenes["A"], out).wait(timeout=300) == 0
    state = "A"
    rng = random.Random(int(signum))
    statuses = []
    for _ in range(SIGNAL_TRIALS):
        new = "B" if state == "A" else "A"
        proc = _run(scenes[new], out, temp, stderr=subprocess.PIPE)
        while proc.poll() is None and not _handles_signals(proc.pid):
            time.sleep(0.001)
        time.sleep(rng.uniform(0.0, working))
        proc.send_signal(signum)
        err = proc.communicate(timeout=120)[1].decode()
        statuses.append(proc.returncode)
        assert proc.returncode in (0, 128 + signum), (proc.returncode, err)
        if proc.returncode:
            assert err.startswith(f"camgen: stopped by {signal.Signals(signum).name}") and len(err.splitlines()) == 1, err
        else:
            assert err == ""
        now = _snapshot(out / "kill")
        assert now in (references["A"], references["B"]), "the folder holds a mix of runs or a partial run"
        assert sorted(p.name for p in out.iterdir()) == ["kill"], "an interrupted run left something beside the folder"
        assert list(temp.iterdir()) == [], "an interrupted run left files in $TMPDIR"
        state = "A" if now == references["A"] else "B"
    assert statuses.count(128 + signum) >= SIGNAL_TRIALS // 3, statuses  # most signals land inside the run


def test_a_run_interrupted_between_the_two_renames_is_put_back(tmp_path, monkeypatch):
    """Where the kernel cannot swap folders in one step, a crash between the two renames leaves
    the previous run under `.camgen-<scene>.<pid>.<token>.retired`; the next run restores it
    before anything else."""
    from camgen import staging

    target = tmp_path / "scene"
    staging.write_run(target, {"a.txt": "old", "report.json": "{}"})
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
    staging.write_run(target, {"a.txt": "old", "b.txt": "gone", "report.json": "{}"})
    staging.write_run(target, {"a.txt": "new", "report.json": "{}"})
    assert {p.name: p.read_text() for p in target.iterdir()} == {"a.txt": "new", "report.json": "{}"}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene"]


@pytest.mark.parametrize("name", ["../x", "sub/x"])
def test_file_names_cannot_leave_the_run_folder(name, tmp_path):
    from camgen import staging
    from camgen.errors import ExportError

    with pytest.raises(ExportError, match="outside"):
        staging.write_run(tmp_path / "scene", {name: "x"})
    assert not (tmp_path / "x").exists() and not (tmp_path / "scene").exists()
