"""SIGINT and SIGTERM end a run cleanly: one line, status 130 or 143, the previous outputs whole.

:func:`handling` installs handlers for the duration of a command.  A signal is *remembered*, not
raised where it lands: raising from a signal handler unwinds through whatever runs at that moment,
and inside a compiled library that calls back into Python (manifold3d's nanobind bindings) that
aborts or crashes the interpreter, while libraries that catch every exception around their
optional imports (trimesh) swallow it.  The run asks instead at every step (:func:`checkpoint`,
called by the pipeline's progress callback and before the output folder is swapped) and stops
there with :class:`Interrupted`; a step takes at most a few seconds (meshing a cam at the size
caps, up to a minute).  A second signal ends the process at once (the user insists): the staging
folder being written, if any, is removed first.  That is done by a watcher thread woken through
:func:`signal.set_wakeup_fd`, so it also works while the main thread is inside a long call of a
compiled library (gmsh, manifold3d) that releases the interpreter lock.
:func:`deferred` marks the swap of the run's folder and the removal of the previous run, which a
second signal must not cut in half either: there it is remembered like the first.
"""
from __future__ import annotations

import contextlib
import os
import shutil
import signal
import threading
from pathlib import Path
from types import FrameType
from typing import Iterator

__all__ = ["Interrupted", "SIGNALS", "checkpoint", "deferred", "handling", "received", "scratch", "signal_name"]

#: The signals a run ends on; the exit status of each is 128 + its number, as shells report it.
SIGNALS = (signal.SIGINT, signal.SIGTERM)
_SIGNAL_BYTES = frozenset(int(s) for s in SIGNALS)


class Interrupted(BaseException):
    """The run was asked to stop by ``signum``; :attr:`status` is the conventional exit status.

    A :class:`BaseException`, so that no ``except Exception`` on the way takes it for an error.
    """

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    @property
    def status(self) -> int:
        return 128 + self.signum


_received: list[int] = []
_deferring: list[bool] = []
_scratch: list[Path] = []


def _handler(signum: int, frame: FrameType | None) -> None:
    _received.append(signum)


def _watch(read_fd: int) -> None:
    """The watcher thread: on the second SIGINT/SIGTERM (outside :func:`deferred`), remove the
    staging folder being written and end the process at once."""
    seen = 0
    while True:
        try:
            data = os.read(read_fd, 64)
        except OSError:
            return
        if not data:  # the command is over: the write end was closed
            return
        for signum in (b for b in data if b in _SIGNAL_BYTES):
            seen += 1
            if seen > 1 and not _deferring:
                for path in list(_scratch):
                    shutil.rmtree(path, ignore_errors=True)
                os.write(2, f"camgen: stopped by {signal.Signals(signum).name} (a second signal: at once); "
                            "the previous outputs are as they were\n".encode())
                os._exit(128 + signum)


def signal_name(signum: int) -> str:
    """``SIGINT``, ``SIGTERM``, ..."""
    return signal.Signals(signum).name


def received() -> int | None:
    """The first signal received since :func:`handling` began, or None."""
    return _received[0] if _received else None


def checkpoint() -> None:
    """Raise :class:`Interrupted` if a signal was received."""
    if _received:
        raise Interrupted(_received[0])


@contextlib.contextmanager
def handling(exiting: bool = False) -> Iterator[None]:
    """Remember SIGINT and SIGTERM inside the block (:func:`checkpoint` acts on them).

    After it the previous handlers are put back (the tests call the command line in their own
    process), or, with ``exiting`` (the ``camgen`` program, which exits next), both signals are
    ignored: the verdict is made, and a signal during the interpreter's shutdown must neither
    print a traceback nor change the exit status.
    """
    if threading.current_thread() is not threading.main_thread():  # only the main thread may set handlers
        yield
        return
    previous = {s: signal.getsignal(s) for s in SIGNALS}
    _received.clear()
    read_fd, write_fd = os.pipe()
    os.set_blocking(write_fd, False)
    previous_fd = signal.set_wakeup_fd(write_fd, warn_on_full_buffer=False)
    watcher = threading.Thread(target=_watch, args=(read_fd,), name="camgen-signals", daemon=True)
    watcher.start()
    for s in SIGNALS:
        signal.signal(s, _handler)
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, signal.SIG_IGN if exiting else handler)
        signal.set_wakeup_fd(previous_fd)
        os.close(write_fd)
        watcher.join()
        os.close(read_fd)
        _received.clear()


@contextlib.contextmanager
def scratch(path: Path) -> Iterator[None]:
    """``path`` (a staging folder) is removed if a second signal ends the process inside the block."""
    _scratch.append(path)
    try:
        yield
    finally:
        _scratch.remove(path)


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """Inside the block even a second signal is only remembered (a swap is never cut in half)."""
    _deferring.append(True)
    try:
        yield
    finally:
        _deferring.pop()
