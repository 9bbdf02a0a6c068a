"""Where a sweep's designs are evaluated: in this process, or on Dask workers.

:func:`run_points` hands every finished batch of rows to a sink as it arrives.  With one worker
and no cluster the batches run here, one after the other (no extra package).  Otherwise
``dask.distributed`` (camgen's ``sweep`` extra) runs them: a local cluster of process workers,
one thread each, bound to 127.0.0.1 with no dashboard unless asked, or an existing cluster by its
address (``tcp://host:port``; a ``tls://`` address uses Dask's own security configuration,
``distributed.comm.tls.*``).

- Every worker must run this camgen version (a row names the version that made it): a worker
  that differs stops the sweep before any point runs (:class:`VersionMismatch`, exit 2).
- The base scene travels with each batch: it is small (the plate cam template pickles to ~4 kB,
  ~16 us to send and read back, against Dask's ~5 ms a task), and a batch then depends on no data
  held by a worker that may die (a scattered copy dies with every worker that held it).
- Points go in batches of :func:`batch_size` points, so that Dask's per-task overhead
  (:data:`TASK_OVERHEAD_S`) stays below :data:`OVERHEAD_SHARE` of a batch's compute.
- A batch whose worker died is retried by the scheduler; one that killed
  :data:`ALLOWED_FAILURES` + 1 workers (Dask's KilledWorker) is split into single points, and a
  single point that does it :data:`SOLO_KILLS` times is recorded with status ``crashed``: the
  sweep goes on.
- At most :data:`TASKS_PER_WORKER` batches per worker are in flight (a killed client loses at
  most those).
"""
from __future__ import annotations

import math
import time
from collections import deque
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence

from camgen.errors import CamgenError

if TYPE_CHECKING:
    from camgen.study.design import Row, StudyScene
    from camgen.study.keys import KeyPath
    from camgen.study.space import Value

__all__ = ["ALLOWED_FAILURES", "CONNECT_TIMEOUT_S", "ClusterLost", "Execution", "Runner", "OVERHEAD_SHARE", "SERIAL_PART_S", "SOLO_KILLS", "STALL_S", "WAIT_POLL_S",
           "TASKS_PER_WORKER", "TASK_OVERHEAD_S", "VersionMismatch", "batch_size", "crashed_row",
           "worker_version"]

#: Dask's overhead per task (scheduling, transfer of a batch and its rows), s: measured ~5 ms.
TASK_OVERHEAD_S = 0.005
#: The largest share of a batch's compute the per-task overhead may take.
OVERHEAD_SHARE = 0.1
#: Batches in flight per worker (enough to keep it busy; a killed client loses at most these).
TASKS_PER_WORKER = 4
#: A local cluster's scheduler gives up on a task (KilledWorker) after its workers died this many
#: times running it, plus one.
ALLOWED_FAILURES = 1
#: A point alone that got KilledWorker this many times is recorded ``crashed`` (once may be bad
#: luck: it was queued on a worker another point killed).
SOLO_KILLS = 2
#: Without a finished batch for this long, s, the client asks the scheduler which of its batches
#: it still runs; one it forgot or gave up on without telling the client (seen with an error too
#: deep to send back) is handled as a batch that killed its worker.
STALL_S = 5.0
#: How often the client looks for finished batches, s (Ctrl-C is seen between two looks).
WAIT_POLL_S = 0.05
#: Compute time of one part file in process, s (a killed sweep loses at most this much).
SERIAL_PART_S = 1.0
#: How long to wait for a cluster's scheduler and its first worker, s.
CONNECT_TIMEOUT_S = 30.0

#: A sink of finished rows (one batch at a time).
Sink = Callable[[list["Row"]], None]


class VersionMismatch(CamgenError):
    """A worker runs another camgen version than this client (exit 2)."""


class ClusterLost(CamgenError):
    """The cluster cannot be reached, has no worker, or went away mid-sweep (exit 2: the parts
    written so far are kept; ``--resume`` continues)."""


@dataclass(frozen=True)
class Execution:
    """How to run a sweep: ``workers`` in a local cluster (1: in this process) or the ``cluster``
    at an address; ``batch`` points per task (None: :func:`batch_size`); ``dashboard``: the local
    cluster's dashboard on 127.0.0.1:8787."""

    workers: int = 1
    cluster: str | None = None
    batch: int | None = None
    dashboard: bool = False

    @property
    def in_process(self) -> bool:
        return self.cluster is None and self.workers == 1

    def describe(self) -> str:
        if self.cluster is not None:
            return f"cluster {self.cluster}"
        return "in process" if self.workers == 1 else f"local cluster of {self.workers} workers"


def batch_size(eval_s: float, points: int, workers: int) -> int:
    """Points per task: enough that :data:`TASK_OVERHEAD_S` is at most :data:`OVERHEAD_SHARE` of
    the batch's compute at ``eval_s`` seconds a point, but no more than a worker's share of the
    ``points`` (every worker gets work)."""
    need = math.ceil(TASK_OVERHEAD_S / (OVERHEAD_SHARE * max(eval_s, 1e-9)))
    share = max(1, math.ceil(points / max(workers, 1)))
    return max(1, min(need, share))


def crashed_row(study: "StudyScene", keys: "Sequence[KeyPath]", values: "Sequence[Value]") -> "Row":
    """The row of a point whose evaluation killed its worker every time it ran, until the scheduler
    gave up on it (Dask's KilledWorker): status ``crashed``."""
    from camgen import __version__
    from camgen.study.design import point_key

    names = [k.name for k in keys]
    row: Row = dict(zip(names, values))
    row.update(key=point_key(names, values), status="crashed",
               error="camgen: error: the evaluation of this design killed its worker each time it ran (a crash in a "
                     "library, or memory); run 'camgen check' on its scene to see why",
               camgen_version=__version__, scene_hash=study.scene_hash, eval_ms=None)
    return row


def worker_version() -> str:
    """The camgen version of the process it runs in (asked of every worker)."""
    import camgen

    return camgen.__version__


def _chunks(points: "Sequence[tuple[Value, ...]]", size: int) -> list[list[tuple["Value", ...]]]:
    return [list(points[i:i + size]) for i in range(0, len(points), size)]


class Runner:
    """Where the batches run: in this process, or on the Dask cluster it connected to (every worker
    checked to run this camgen version).  Use as a context manager (the local cluster is closed at
    the end); :attr:`workers` is the number of workers."""

    def __init__(self, execution: Execution) -> None:
        self.execution = execution
        self.client: Any = None
        self.workers = 1

    def __enter__(self) -> "Runner":
        if not self.execution.in_process:
            self.client = _client(self.execution)
            try:
                self.workers = _check_versions(self.client)
            except BaseException:
                self.close()
                raise
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        if self.client is not None:
            cluster = getattr(self.client, "cluster", None)
            self.client.close()
            if cluster is not None:
                cluster.close()
            self.client = None

    def run(self, study: "StudyScene", keys: "Sequence[KeyPath]", points: "Sequence[tuple[Value, ...]]", eval_s: float,
            sink: Sink) -> None:
        """Evaluate ``points`` (each a tuple of values of ``keys``) and give each batch of rows to
        ``sink`` as it finishes.  ``eval_s``: a measured evaluation's time, s (it sizes the batches)."""
        if not points:
            return
        if self.client is None:
            from camgen.interrupt import checkpoint
            from camgen.study.design import evaluate_batch

            size = self.execution.batch or max(1, math.ceil(SERIAL_PART_S / max(eval_s, 1e-9)))
            for batch in _chunks(points, size):
                checkpoint()
                sink(evaluate_batch(study, keys, batch))
            return
        _run_dask(self.client, self.workers, study, keys, points, eval_s, self.execution, sink)


def _client(execution: Execution) -> Any:
    """A Dask client of a new local cluster or of the cluster at ``execution.cluster``."""
    from camgen.study.optional import require

    distributed = require("distributed", "camgen sweep with --workers N > 1 or --cluster")
    import logging

    import dask

    if execution.cluster is not None:
        try:
            return distributed.Client(execution.cluster, timeout=CONNECT_TIMEOUT_S)
        except (OSError, TimeoutError, ValueError) as exc:
            raise ClusterLost(f"cannot reach the Dask scheduler at '{execution.cluster}' ({' '.join(str(exc).split())[:160]}): "
                              "start it with 'dask scheduler' (README: Design sweeps) or give another --cluster") from None
    # a worker takes one batch at a time (no batch queued on a worker that another batch kills)
    with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES,
                          "distributed.scheduler.worker-saturation": 1.0}):
        cluster = distributed.LocalCluster(n_workers=execution.workers, threads_per_worker=1, processes=True,
                                           host="127.0.0.1",
                                           dashboard_address="127.0.0.1:8787" if execution.dashboard else None,
                                           silence_logs=logging.CRITICAL)
    return distributed.Client(cluster)


def _check_versions(client: Any) -> int:
    """The number of workers, each checked to run this camgen version."""
    from camgen import __version__

    try:
        client.wait_for_workers(1, timeout=CONNECT_TIMEOUT_S)
    except (TimeoutError, OSError):
        raise ClusterLost(f"the Dask cluster at '{client.scheduler.address}' has no worker after {CONNECT_TIMEOUT_S:g} s: "
                          "start some with 'dask worker ADDRESS'") from None
    versions = client.run(worker_version)
    for worker, version in sorted(versions.items()):
        if version != __version__:
            raise VersionMismatch(f"worker {worker} runs camgen {version}, this client camgen {__version__}: install the same "
                                  "camgen on every worker (a row must not depend on where it ran)")
    return len(versions)


def _live_keys(dask_scheduler: Any, keys: list[str]) -> list[str]:
    """The ``keys`` the scheduler holds and has not given up on (run on the scheduler)."""
    return [k for k in keys if k in dask_scheduler.tasks and dask_scheduler.tasks[k].state != "erred"]


def _killed(pending: "deque[tuple[list[tuple[Value, ...]], int]]", batch: "list[tuple[Value, ...]]", kills: int,
            crashed: "Callable[[Row], None]", study: "StudyScene", keys: "Sequence[KeyPath]") -> None:
    """A batch whose workers died running it: its points each on their own, a point alone again
    (:data:`SOLO_KILLS`), then recorded ``crashed``."""
    if len(batch) > 1:
        pending.extendleft(([p], 0) for p in reversed(batch))
    elif kills + 1 < SOLO_KILLS:
        pending.append((batch, kills + 1))
    else:
        crashed(crashed_row(study, keys, batch[0]))


def _run_dask(client: Any, workers: int, study: "StudyScene", keys: "Sequence[KeyPath]",
              points: "Sequence[tuple[Value, ...]]", eval_s: float, execution: Execution, sink: Sink) -> None:
    from distributed import KilledWorker

    from camgen.interrupt import checkpoint
    from camgen.study.design import evaluate_batch

    size = execution.batch or batch_size(eval_s, len(points), workers)
    #: a batch of points and how many times it killed its workers (KilledWorker) alone
    pending: deque[tuple[list[tuple[Value, ...]], int]] = deque((b, 0) for b in _chunks(points, size))
    window = max(1, workers * TASKS_PER_WORKER)
    flight: dict[Any, tuple[list[tuple[Value, ...]], int]] = {}

    progress = time.monotonic()
    while pending or flight:
        while pending and len(flight) < window:
            batch, kills = pending.popleft()
            flight[client.submit(evaluate_batch, study, keys, batch, pure=False)] = (batch, kills)
        # lost: its result was on a worker that died before it reached us (the scheduler forgets it)
        finished = [f for f in flight if f.done() or f.status in ("lost", "cancelled")]
        if not finished:
            time.sleep(WAIT_POLL_S)
            if time.monotonic() - progress > STALL_S:  # nothing for a while: has the scheduler forgotten a batch?
                progress = time.monotonic()
                alive = set(client.run_on_scheduler(_live_keys, keys=[str(f.key) for f in flight]))
                for future in [f for f in flight if str(f.key) not in alive]:  # as a KilledWorker
                    _killed(pending, *flight.pop(future), lambda row: sink([row]), study, keys)
        checkpoint()  # Ctrl-C / SIGTERM between two polls
        if finished:
            progress = time.monotonic()
        for future in finished:
            batch, kills = flight.pop(future)
            if future.status == "finished":
                sink(future.result())
                continue
            error = future.exception() if future.status == "error" else None
            if error is not None and not isinstance(error, KilledWorker):
                raise error
            if error is None:  # cancelled or lost (a scheduler restart): again
                pending.append((batch, kills))
            else:
                _killed(pending, batch, kills, lambda row: sink([row]), study, keys)
