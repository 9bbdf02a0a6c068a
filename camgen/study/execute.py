"""Where a sweep's designs are evaluated: in this process, or on Dask workers.

:func:`run_points` hands every finished batch of rows to a sink as it arrives.  With one worker
and no cluster the batches run here, one after the other (no extra package).  Otherwise
``dask.distributed`` (camgen's ``sweep`` extra) runs them: a local cluster of process workers,
one thread each, bound to 127.0.0.1 with no dashboard unless asked, or an existing cluster by its
address (``tcp://host:port``; a ``tls://`` address uses Dask's own security configuration,
``distributed.comm.tls.*``).

- Every worker must run this camgen version (a row names the version that made it): a worker
  that differs stops the sweep before any point runs (:class:`VersionMismatch`, exit 2).
- The base scene is sent once, as a task every batch depends on (a restarted worker fetches it
  from another, or the scheduler recomputes it: it survives every worker dying).
- Points go in batches of :func:`batch_size` points, so that Dask's per-task overhead
  (:data:`TASK_OVERHEAD_S`) stays below :data:`OVERHEAD_SHARE` of a batch's compute.
- A batch whose worker died is retried by the scheduler; one that killed
  :data:`ALLOWED_FAILURES` + 1 workers (Dask's KilledWorker) is split into single points, and a
  single point that does it is recorded with status ``crashed``: the sweep goes on.
- At most :data:`TASKS_PER_WORKER` batches per worker are in flight (a killed client loses at
  most those).
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence

from camgen.errors import CamgenError

if TYPE_CHECKING:
    from camgen.study.design import Row, StudyScene
    from camgen.study.keys import KeyPath
    from camgen.study.space import Value

__all__ = ["ALLOWED_FAILURES", "CONNECT_TIMEOUT_S", "ClusterLost", "Execution", "OVERHEAD_SHARE", "SERIAL_PART_S",
           "TASKS_PER_WORKER", "TASK_OVERHEAD_S", "VersionMismatch", "batch_size", "crashed_row", "run_points",
           "worker_version"]

#: Dask's overhead per task (scheduling, transfer of a batch and its rows), s: measured ~5 ms.
TASK_OVERHEAD_S = 0.005
#: The largest share of a batch's compute the per-task overhead may take.
OVERHEAD_SHARE = 0.1
#: Batches in flight per worker (enough to keep it busy; a killed client loses at most these).
TASKS_PER_WORKER = 4
#: A local cluster's scheduler gives up on a task (KilledWorker) after its workers died this many
#: times running it, plus one.
ALLOWED_FAILURES = 2
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


def crashed_row(study: "StudyScene", keys: "Sequence[KeyPath]", values: "Sequence[Value]", deaths: int) -> "Row":
    """The row of a point whose evaluation killed its worker ``deaths`` times (status ``crashed``)."""
    from camgen import __version__
    from camgen.study.design import point_key

    names = [k.name for k in keys]
    row: Row = dict(zip(names, values))
    row.update(key=point_key(names, values), status="crashed",
               error=f"camgen: error: the evaluation of this design killed its worker {deaths} times (a crash in a "
                     "library, or memory); run 'camgen check' on its scene to see why",
               camgen_version=__version__, scene_hash=study.scene_hash, eval_ms=None)
    return row


def worker_version() -> str:
    """The camgen version of the process it runs in (asked of every worker)."""
    import camgen

    return camgen.__version__


def _chunks(points: "Sequence[tuple[Value, ...]]", size: int) -> list[list[tuple["Value", ...]]]:
    return [list(points[i:i + size]) for i in range(0, len(points), size)]


def run_points(study: "StudyScene", keys: "Sequence[KeyPath]", points: "Sequence[tuple[Value, ...]]", eval_s: float,
               execution: Execution, sink: Sink) -> int:
    """Evaluate ``points`` (each a tuple of values of ``keys``) and give each batch of rows to
    ``sink`` as it finishes; return the number of workers that ran them.

    ``eval_s``: a measured evaluation's time, s (it sizes the batches).
    """
    if not points:
        return execution.workers if execution.cluster is None else 0
    if execution.in_process:
        from camgen.interrupt import checkpoint
        from camgen.study.design import evaluate_batch

        size = execution.batch or max(1, math.ceil(SERIAL_PART_S / max(eval_s, 1e-9)))
        for batch in _chunks(points, size):
            checkpoint()
            sink(evaluate_batch(study, keys, batch))
        return 1
    return _run_dask(study, keys, points, eval_s, execution, sink)


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
    with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES}):
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


def _hold(study: "StudyScene") -> "StudyScene":
    """The base scene as a task's result (sent once; every batch depends on it)."""
    return study


def _run_dask(study: "StudyScene", keys: "Sequence[KeyPath]", points: "Sequence[tuple[Value, ...]]", eval_s: float,
              execution: Execution, sink: Sink) -> int:
    from distributed import KilledWorker, as_completed

    from camgen.interrupt import checkpoint
    from camgen.study.design import evaluate_batch

    client = _client(execution)
    try:
        workers = _check_versions(client)
        size = execution.batch or batch_size(eval_s, len(points), workers)
        held = client.submit(_hold, study, pure=False)
        pending: deque[list[tuple[Value, ...]]] = deque(_chunks(points, size))
        window = max(1, workers * TASKS_PER_WORKER)
        flight: dict[Any, list[tuple[Value, ...]]] = {}
        done = as_completed()

        def submit() -> None:
            while pending and len(flight) < window:
                batch = pending.popleft()
                future = client.submit(evaluate_batch, held, keys, batch, pure=False, retries=1)
                flight[future] = batch
                done.add(future)

        submit()
        for future in done:
            checkpoint()
            batch = flight.pop(future)
            try:
                rows = future.result()
            except KilledWorker:
                if len(batch) > 1:  # find the point that kills: each on its own
                    pending.extendleft([p] for p in reversed(batch))
                else:
                    rows = [crashed_row(study, keys, batch[0], ALLOWED_FAILURES + 1)]
                    sink(rows)
            except (OSError, TimeoutError) as exc:
                raise ClusterLost(f"lost the Dask cluster mid-sweep ({type(exc).__name__}: {' '.join(str(exc).split())[:120]}); "
                                  "the results so far are kept: run again with --resume") from None
            else:
                sink(rows)
            future.release()
            submit()
        return workers
    finally:
        cluster = getattr(client, "cluster", None)
        client.close()
        if cluster is not None:
            cluster.close()

