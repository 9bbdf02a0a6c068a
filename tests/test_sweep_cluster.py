"""``camgen sweep`` on Dask: a local cluster's rows equal the in-process rows bit for bit; a point
that kills its worker every time is recorded ``crashed`` and the sweep goes on; a worker of
another camgen version is refused; against a real scheduler and workers started as their own
programs, a worker killed mid-sweep and the client killed, ``--resume`` completes the set with
every key once and no finished point evaluated again.

Worker behaviour is planted by Dask worker preloads written here (a test-only patch of the
evaluation, never in camgen): ``DASK_DISTRIBUTED__WORKER__PRELOAD`` for a local cluster's
workers, ``--preload`` for ``dask worker``."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import pytest

from helpers import CHECKOUT

pytest.importorskip("distributed")
pq = pytest.importorskip("pyarrow.parquet")
pd = pytest.importorskip("pandas")

TEMPLATE = CHECKOUT / "templates" / "plate_cam.toml"
#: How long a test waits for a sweep or a cluster program, s (a hang fails, it is no timing).
WAIT_S = 240.0

#: Kills its worker (SIGKILL) whenever it evaluates a base radius of 35 mm.
CRASH_PRELOAD = """
import os, signal
import camgen.study.design as design
_evaluate = getattr(design, "_unpatched", design.evaluate_point)  # Dask may run a preload twice
def evaluate_point(study, keys, values):
    if 35.0 in list(values):
        os.kill(os.getpid(), signal.SIGKILL)
    return _evaluate(study, keys, values)
design._unpatched = _evaluate
design.evaluate_point = evaluate_point
"""
#: Claims another camgen version.
VERSION_PRELOAD = """
import camgen
camgen.__version__ = "0.0.0+other"
"""
#: Logs every point a worker evaluates (one key a line, to the file named by SWEEP_TEST_LOG), and
#: slows each down by 0.1 s so that a kill lands mid-sweep.
COUNT_PRELOAD = """
import os, time
import camgen.study.design as design
_evaluate = getattr(design, "_unpatched", design.evaluate_point)  # Dask may run a preload twice
def evaluate_point(study, keys, values):
    time.sleep(0.1)
    row = _evaluate(study, keys, values)
    with open(os.environ["SWEEP_TEST_LOG"], "a") as log:
        log.write(row["key"] + "\\n")
    return row
design._unpatched = _evaluate
design.evaluate_point = evaluate_point
"""


def _camgen(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "camgen", *args], capture_output=True, text=True, timeout=WAIT_S,
                          env={**os.environ, **(env or {})})


def _parts(folder):
    return sorted((folder / "parts").glob("part-*.parquet"))


def _table(folder) -> "pd.DataFrame":
    frame = pd.concat([pd.read_parquet(p) for p in _parts(folder)], ignore_index=True)
    return frame.sort_values("key", ignore_index=True)


def _preload(tmp_path, name: str, text: str) -> str:
    path = tmp_path / f"{name}.py"
    path.write_text(text)
    return str(path)


def test_a_local_cluster_gives_the_rows_of_one_process(tmp_path):
    grid = ["--vary", "base_radius_mm=20:45:5", "--vary", "roller_radius_mm=8,12", "-q"]
    serial = _camgen("sweep", str(TEMPLATE), *grid, "-o", str(tmp_path / "serial"))
    parallel = _camgen("sweep", str(TEMPLATE), *grid, "--workers", "2", "--batch", "2", "-o", str(tmp_path / "parallel"))
    assert serial.returncode == 0 and parallel.returncode == 0, serial.stderr + parallel.stderr
    one, two = (tmp_path / d / "plate_cam-sweep" for d in ("serial", "parallel"))
    assert len(_parts(two)) == 1 + 6  # the measured point, then 11 points in batches of two
    a, b = _table(one).drop(columns="eval_ms"), _table(two).drop(columns="eval_ms")
    assert len(a) == 12 and a["key"].is_unique
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    s1 = pd.read_csv(one / "summary.csv", dtype=str, keep_default_na=False).drop(columns="eval_ms")
    s2 = pd.read_csv(two / "summary.csv", dtype=str, keep_default_na=False).drop(columns="eval_ms")
    pd.testing.assert_frame_equal(s1, s2)
    facts = json.loads((two / "sweep.json").read_text())
    assert facts["workers"] == 2 and facts["execution"] == "local cluster of 2 workers"


def test_a_point_that_kills_its_worker_is_recorded_crashed(tmp_path):
    env = {"DASK_DISTRIBUTED__WORKER__PRELOAD": json.dumps([_preload(tmp_path, "crash", CRASH_PRELOAD)])}
    proc = _camgen("sweep", str(TEMPLATE), "--vary", "base_radius_mm=20:45:5", "--workers", "2", "--batch", "2",
                   "-o", str(tmp_path / "out"), "-q", env=env)
    assert proc.returncode == 0, proc.stderr
    rows = pd.read_csv(tmp_path / "out" / "plate_cam-sweep" / "summary.csv", keep_default_na=False)
    status = dict(zip(rows["cams.plate.base_radius_mm"], rows["status"]))
    assert status.pop(35.0) == "crashed"
    assert set(status) == {20.0, 25.0, 30.0, 40.0, 45.0} and set(status.values()) <= {"pass", "fail"}
    crashed = rows[rows["status"] == "crashed"].iloc[0]
    assert crashed["error"].startswith("camgen: error:") and crashed["eval_ms"] == ""
    # 30 mm shared a batch with 35 mm: split off and evaluated alone, its row is the in-process one
    serial = _camgen("sweep", str(TEMPLATE), "--vary", "base_radius_mm=30.0,40.0", "-o", str(tmp_path / "serial"), "-q")
    assert serial.returncode == 0
    alone = pd.read_csv(tmp_path / "serial" / "plate_cam-sweep" / "summary.csv", keep_default_na=False)
    for _, row in alone.iterrows():
        mine = rows[rows["key"] == row["key"]].iloc[0]
        columns = [c for c in alone.columns if c != "eval_ms"]
        assert [str(mine[c]) for c in columns] == [str(row[c]) for c in columns]


def test_a_worker_of_another_version_is_refused(tmp_path):
    env = {"DASK_DISTRIBUTED__WORKER__PRELOAD": json.dumps([_preload(tmp_path, "version", VERSION_PRELOAD)])}
    proc = _camgen("sweep", str(TEMPLATE), "--vary", "base_radius_mm=20,30", "--workers", "2", "-o", str(tmp_path / "out"),
                   env=env)
    assert proc.returncode == 2
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("camgen: error: worker tcp://127.0.0.1:") and "0.0.0+other" in lines[0]
    assert not (tmp_path / "out" / "plate_cam-sweep" / "parts").exists() or not _parts(tmp_path / "out" / "plate_cam-sweep")


def _wait_for(condition, what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"waited {WAIT_S} s for {what}")
        time.sleep(0.05)


def test_a_killed_worker_and_client_then_resume_on_a_real_cluster(tmp_path):
    file = tmp_path / "scheduler.json"
    log = tmp_path / "evaluated.txt"
    log.touch()
    env = {**os.environ, "SWEEP_TEST_LOG": str(log)}
    programs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0",
                                  "--no-dashboard", "--scheduler-file", str(file)], env=env, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL)]
    try:
        _wait_for(file.exists, "the scheduler file")
        for _ in range(2):
            programs.append(subprocess.Popen(
                [sys.executable, "-m", "distributed.cli.dask_worker", "--scheduler-file", str(file), "--nthreads", "1",
                 "--no-nanny", "--no-dashboard", "--host", "127.0.0.1", "--preload", _preload(tmp_path, "count", COUNT_PRELOAD)],
                env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        _wait_for(lambda: "address" in file.read_text(), "the scheduler's address")
        address = json.loads(file.read_text())["address"]
        folder = tmp_path / "out" / "plate_cam-sweep"
        sweep = ["sweep", str(TEMPLATE), "--vary", "base_radius_mm=20:59:1", "--cluster", address, "--batch", "1",
                 "-o", str(tmp_path / "out"), "-q"]
        client = subprocess.Popen([sys.executable, "-m", "camgen", *sweep], env=env, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
        programs.append(client)  # stopped at the end whatever happens
        _wait_for(lambda: len(_parts(folder)) >= 5, "five parts")
        programs[1].send_signal(signal.SIGKILL)  # a worker dies mid-sweep: its point goes to the other
        killed_at = len(_parts(folder))
        _wait_for(lambda: len(_parts(folder)) >= killed_at + 5, "five more parts on the other worker")
        assert client.poll() is None  # still running: the client is stopped mid-sweep
        client.send_signal(signal.SIGKILL)
        client.wait(timeout=WAIT_S)
        time.sleep(1.0)  # the points in flight when the client died finish on the worker
        finished = set(_table(folder)["key"])
        assert 10 <= len(finished) < 40
        before = log.read_text().split()
        # the address from DASK_SCHEDULER_ADDRESS this time (no --cluster, no --workers)
        at = sweep.index("--cluster")
        resumed = _camgen(*sweep[:at], *sweep[at + 2:], "--resume",
                          env={"SWEEP_TEST_LOG": str(log), "DASK_SCHEDULER_ADDRESS": address})
        assert resumed.returncode == 0, resumed.stderr
        again = log.read_text().split()[len(before):]
        table = _table(folder)
        assert table["key"].is_unique and len(table) == 40  # every key once
        assert sorted(table["cams.plate.base_radius_mm"]) == [float(r) for r in range(20, 60)]
        missing = set(table["key"]) - finished
        assert not set(again) & finished  # no finished point evaluated again
        assert len(again) == len(set(again)) == len(missing) - 1  # the first is measured in the client
        facts = json.loads((folder / "sweep.json").read_text())
        assert facts["evaluated"] == len(missing) and facts["resumed"] == len(finished) and facts["workers"] == 1
        assert facts["execution"] == f"cluster {address}"
    finally:
        for program in reversed(programs):
            if program.poll() is None:
                program.send_signal(signal.SIGTERM)
        for program in programs:
            try:
                program.wait(timeout=30)
            except subprocess.TimeoutExpired:  # a busy machine: killed, and waited for (no process left running)
                program.kill()
                program.wait()


def test_a_local_worker_killed_mid_sweep_and_every_key_once():
    """A local cluster's worker SIGKILLed after the third batch (its nanny starts another): every
    point's row arrives exactly once."""
    from camgen.study.design import StudyScene, point_key
    from camgen.study.execute import Execution, Runner
    from camgen.study.keys import resolve_key

    study = StudyScene.load(str(TEMPLATE))
    keys = [resolve_key(study.data, "base_radius_mm")]
    points = [(20.0 + i,) for i in range(16)]
    got: list[str] = []
    killed: list[int] = []
    with Runner(Execution(workers=2, batch=1)) as runner:
        def sink(rows):
            got.extend(str(r["key"]) for r in rows)
            if len(got) == 3:
                pid = next(iter(runner.client.run(os.getpid).values()))
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)
        runner.run(study, keys, points, 0.03, sink)
        after = set(runner.client.run(os.getpid).values())
    assert killed and killed[0] not in after  # the worker did die (and was replaced)
    assert len(got) == len(set(got)) == 16
    assert set(got) == {point_key([keys[0].name], p) for p in points}
