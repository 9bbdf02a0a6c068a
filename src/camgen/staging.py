"""A run is all or nothing: its files go to a staging folder that replaces the output folder in
one step, so the folder always holds one complete run (the previous one or the new one).

Layout, next to the target ``OUTDIR/<scene>``: ``OUTDIR/.camgen-<scene>.<pid>.<token>.staging``
(the new run being written) and ``...retired`` (the previous run being removed).  The swap:

* no previous run: ``rename(staging, target)`` (atomic);
* a previous run: ``renameat2(staging, target, RENAME_EXCHANGE)`` swaps the two folders in one
  atomic step (Linux >= 3.15 on the usual file systems); where the kernel or file system does
  not offer it, ``rename(target, retired)`` then ``rename(staging, target)``, and a crash between
  the two leaves the previous run in ``retired``, which the next run puts back first.

A killed run leaves only hidden ``.camgen-<scene>.*`` entries beside the target; the next run of
the same scene removes those of processes no longer alive.  Files are flushed to disk
(``fsync``) before the swap.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import errno
import os
import secrets
import shutil
from pathlib import Path
from typing import Mapping

from camgen.errors import ExportError

_RENAME_EXCHANGE = 2  # linux/fs.h
_AT_FDCWD = -100


def _libc_renameat2():
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        function = libc.renameat2
    except (OSError, AttributeError):
        return None
    function.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    function.restype = ctypes.c_int
    return function


def exchange(a: Path, b: Path) -> bool:
    """Swap the directory entries ``a`` and ``b`` atomically; False where the system cannot."""
    function = _libc_renameat2()
    if function is None:
        return False
    if function(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP, errno.EXDEV):
        return False
    raise OSError(code, os.strerror(code), str(b))


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _entries(target: Path) -> list[tuple[Path, int, str]]:
    """Hidden staging/retired entries of ``target``'s scene: (path, pid, state)."""
    prefix = f".camgen-{target.name}."
    out = []
    if not target.parent.is_dir():
        return out
    for entry in target.parent.iterdir():
        name = entry.name
        if not name.startswith(prefix):
            continue
        parts = name[len(prefix):].split(".")
        if len(parts) == 3 and parts[0].isdigit() and parts[2] in ("staging", "retired"):
            out.append((entry, int(parts[0]), parts[2]))
    return out


def recover(target: Path) -> None:
    """Put back a previous run a crash left in ``retired`` and remove the leftovers of runs of
    this scene whose process is gone."""
    leftovers = [(p, pid, state) for p, pid, state in _entries(target) if not _alive(pid)]
    if not target.exists():
        retired = [p for p, _, state in leftovers if state == "retired"]
        if retired:
            os.replace(retired[0], target)
            leftovers = [item for item in leftovers if item[0] != retired[0]]
    for path, _, _ in leftovers:
        shutil.rmtree(path, ignore_errors=True)


def _write(folder: Path, files: Mapping[str, str | bytes]) -> None:
    for name, data in files.items():
        path = folder / name
        if path.parent != folder:  # names are checked when the scene is read; keep it that way
            raise ExportError(f"refusing to write '{name}' outside the run's folder")
        raw = data.encode("utf-8") if isinstance(data, str) else data
        with open(path, "wb") as handle:
            handle.write(raw)
            handle.flush()
            os.fsync(handle.fileno())
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_run(target: str | Path, files: Mapping[str, str | bytes]) -> list[Path]:
    """Write ``files`` (name -> text or bytes; text as UTF-8 with '\\n' line ends) as the folder
    ``target``, replacing what was there in one atomic step; return the paths written."""
    target = Path(target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        recover(target)
        token = f"{os.getpid()}.{secrets.token_hex(4)}"
        staging = target.parent / f".camgen-{target.name}.{token}.staging"
        staging.mkdir(mode=0o777)
        try:
            _write(staging, files)
            if not target.exists():
                os.rename(staging, target)
            elif exchange(staging, target):
                shutil.rmtree(staging)  # now the previous run
            else:
                retired = target.parent / f".camgen-{target.name}.{token}.retired"
                os.rename(target, retired)
                os.rename(staging, target)
                shutil.rmtree(retired)
        except BaseException:
            shutil.rmtree(staging, ignore_errors=True)
            raise
    except OSError as exc:
        raise ExportError(f"cannot write the run into '{target}': {exc.strerror or exc}") from None
    return [target / name for name in files]
