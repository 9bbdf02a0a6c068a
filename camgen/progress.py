"""Progress display for long runs: on stderr, only on a terminal, and only once a run has taken
longer than :data:`SHOW_AFTER_S` (most runs finish before anything is shown)."""
from __future__ import annotations

import sys
import time
from typing import Any

__all__ = ["SHOW_AFTER_S", "TerminalProgress"]

#: A run shows progress once it has taken this long, s.
SHOW_AFTER_S = 1.0


class TerminalProgress:
    """Callable with the description of each step; call :meth:`close` at the end."""

    def __init__(self, enabled: bool = True) -> None:
        self.enabled = enabled and sys.stderr.isatty()
        self.start = time.perf_counter()
        self.bar: Any = None
        self.task: Any = None

    def __call__(self, step: str) -> None:
        if not self.enabled:
            return
        if self.bar is None:
            if time.perf_counter() - self.start < SHOW_AFTER_S:
                return
            from rich.console import Console  # lazily: only when a run is slow enough to show it
            from rich.progress import (
                Progress,
                SpinnerColumn,
                TextColumn,
                TimeElapsedColumn,
            )

            self.bar = Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(), transient=True,
                                console=Console(stderr=True), redirect_stdout=False, redirect_stderr=False)
            self.bar.start()
            self.task = self.bar.add_task(step)
        self.bar.update(self.task, description=step)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
            self.bar = None
