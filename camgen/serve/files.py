"""The files ``camgen serve`` made for download, kept in memory (nothing is written to disk).

Each run's files are kept under a random token (:func:`secrets.token_urlsafe`); at most
:data:`MAX_RUNS` runs are kept, the oldest dropped first.  A download names a token and a file
name: only a pair this store made is found (anything else: None, the server's 404).  The store
is the one mutable object the server's request threads share: a lock guards it.  A second lock,
:attr:`FileStore.making`, is held while a run's files are made: one run at a time, since the
libraries some formats call (gmsh for the FEA meshes, OpenCASCADE for STEP) keep global state and
are not safe to call from two threads at once.
"""
from __future__ import annotations

import secrets
import threading
from collections import OrderedDict
from dataclasses import dataclass
from typing import Mapping
from urllib.parse import quote

__all__ = ["FileStore", "MAX_RUNS", "MadeFile", "TOKEN_BYTES"]

#: Runs whose files are kept; a new run beyond them drops the oldest.
MAX_RUNS = 20
#: Random bytes of a token (URL-safe base64: 22 characters).
TOKEN_BYTES = 16


@dataclass(frozen=True)
class MadeFile:
    """One file of a run: its name, the URL it is downloaded from, its size in bytes."""

    name: str
    url: str
    bytes: int


class FileStore:
    """Files by (token, name), at most ``max_runs`` runs (thread-safe)."""

    def __init__(self, max_runs: int = MAX_RUNS) -> None:
        self._runs: OrderedDict[str, dict[str, bytes]] = OrderedDict()
        self._max_runs = max_runs
        self._lock = threading.Lock()
        #: Held while a run's files are made (one at a time: see the module's docstring).
        self.making = threading.Lock()

    def add(self, files: Mapping[str, str | bytes]) -> tuple[MadeFile, ...]:
        """Keep ``files`` (text is stored as its UTF-8 bytes, as ``camgen run`` writes it) under a
        new token; return each file with its download URL."""
        data = {name: content.encode("utf-8") if isinstance(content, str) else bytes(content) for name, content in files.items()}
        token = secrets.token_urlsafe(TOKEN_BYTES)
        with self._lock:
            self._runs[token] = data
            while len(self._runs) > self._max_runs:
                self._runs.popitem(last=False)
        return tuple(MadeFile(name, f"/files/{token}/{quote(name, safe='')}", len(content)) for name, content in data.items())

    def get(self, token: str, name: str) -> bytes | None:
        """The bytes of file ``name`` of run ``token``, or None if this store did not make it (or
        dropped it)."""
        with self._lock:
            run = self._runs.get(token)
            return None if run is None else run.get(name)

    def __len__(self) -> int:
        with self._lock:
            return len(self._runs)
