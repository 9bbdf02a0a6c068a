"""A sweep's progress on stderr: points done of the total, pass / fail / error / crashed, the rate
and the time left.

On a terminal one line is redrawn at most every :data:`REDRAW_S`; elsewhere (a log file, CI) a
line is printed at most every :data:`LOG_EVERY_S`, and one at the end.
"""
from __future__ import annotations

import sys
import time
from collections import Counter
from typing import TYPE_CHECKING, Sequence, TextIO

if TYPE_CHECKING:
    from camgen.study.design import Row

__all__ = ["LOG_EVERY_S", "REDRAW_S", "SweepProgress"]

#: Least time between two redraws of the line on a terminal, s.
REDRAW_S = 0.25
#: Least time between two progress lines when stderr is not a terminal, s.
LOG_EVERY_S = 10.0


class SweepProgress:
    """Call :meth:`add` with each batch of rows, :meth:`close` at the end.

    ``total``: the points of the sweep; ``done``: those finished before (``--resume``);
    ``enabled``: False for ``-q``.
    """

    def __init__(self, total: int, done: int = 0, enabled: bool = True, stream: TextIO | None = None) -> None:
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.tty = self.enabled and self.stream.isatty()
        self.total, self.before, self.done = total, done, done
        self.counts: Counter[str] = Counter()
        self.start = time.perf_counter()
        self.shown = self.start

    def add(self, rows: "Sequence[Row]") -> None:
        self.done += len(rows)
        self.counts.update(str(r["status"]) for r in rows)
        now = time.perf_counter()
        if self.enabled and now - self.shown >= (REDRAW_S if self.tty else LOG_EVERY_S):
            self.shown = now
            self._show(now)

    def line(self, now: float | None = None) -> str:
        """``done/total  pass N  fail N  error N  [crashed N]  R designs/s  T left`` (after
        ``--resume``: the points done before, and the counts and rate of this run)."""
        elapsed = (now or time.perf_counter()) - self.start
        new = self.done - self.before
        rate = new / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate > 0 else float("inf")
        counts = "  ".join(f"{s} {self.counts[s]}" for s in ("pass", "fail", "error", "crashed")
                           if s != "crashed" or self.counts[s])
        eta = f"{left:.0f} s left" if left != float("inf") else "time left unknown"
        before = f" ({self.before} from before; this run:)" if self.before else ""
        return f"camgen sweep: {self.done}/{self.total}{before}  {counts}  {rate:.1f} designs/s  {eta}"

    def _show(self, now: float) -> None:
        if self.tty:
            self.stream.write("\r\033[K" + self.line(now))
        else:
            self.stream.write(self.line(now) + "\n")
        self.stream.flush()

    def close(self) -> None:
        if self.tty:
            self.stream.write("\r\033[K")
            self.stream.flush()
