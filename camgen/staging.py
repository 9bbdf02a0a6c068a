"""A run is all or nothing: its files go to a staging folder that replaces the output folder in
one step, so the folder always holds one complete run (the previous one or the new one).

Layout, next to the target ``OUTDIR/<scene>``: ``OUTDIR/.camgen-<scene>.<pid>.<token>.staging``
(the new run being written), ``...retired`` (the previous run moved aside) and ``...old`` (the
previous run after the swap, being removed).  The swap:

* no previous run: ``rename(staging, target)`` (atomic);
* a previous run: ``renameat2(staging, target, RENAME_EXCHANGE)`` swaps the two folders in one
  atomic step (Linux >= 3.15 on the usual file systems); where the kernel or file system does
  not offer it, ``rename(target, retired)`` then ``rename(staging, target)``, and a crash between
  the two leaves the previous run in ``retired``, which the next run puts back first.

A killed run leaves only hidden ``.camgen-<scene>.*`` entries beside the target; the next run of
the same scene removes those of processes no longer alive, and every ``...old`` one.  Files are flushed to disk
(``fsync``) before the swap.

What may stand at ``OUTDIR/<scene>`` (:func:`preflight`, checked before anything is computed and
again before writing): nothing, an empty folder, or a previous run (a folder of plain files with
its ``report.json``) that this user may remove.  Anything else (a symbolic link, a file, a folder
camgen did not write, a read-only previous run) is refused with its path and nothing is moved:
camgen never renames a user's entry into a hidden name.  Once the new run is in place the run
has succeeded; if the previous run cannot then be removed, the caller is told
(:attr:`WrittenRun.leftover`) and the next run of the scene removes it.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import errno
import os
import secrets
import shutil
import stat
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

from camgen.errors import ExportError
from camgen.interrupt import checkpoint, deferred, scratch

__all__ = ["WrittenRun", "exchange", "preflight", "recover", "write_run"]

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
    out: list[tuple[Path, int, str]] = []
    if not target.parent.is_dir():
        return out
    for entry in target.parent.iterdir():
        name = entry.name
        if not name.startswith(prefix):
            continue
        parts = name[len(prefix):].split(".")
        if len(parts) == 3 and parts[0].isdigit() and parts[2] in ("staging", "retired", "old"):
            out.append((entry, int(parts[0]), parts[2]))
    return out


def _remove(path: Path) -> None:
    """Remove a leftover entry of camgen's: a folder with what it holds, or a single entry."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        try:
            path.unlink()
        except OSError:
            pass


def recover(target: Path) -> None:
    """Put back a previous run a crash left in ``retired`` and remove the leftovers of runs of
    this scene whose process is gone."""
    leftovers = [(p, pid, state) for p, pid, state in _entries(target) if state == "old" or not _alive(pid)]
    if not os.path.lexists(target):
        retired = [p for p, _, state in leftovers if state == "retired"]
        if retired:
            os.replace(retired[0], target)
            leftovers = [item for item in leftovers if item[0] != retired[0]]
    for path, _, _ in leftovers:
        if path.is_dir() and not path.is_symlink():
            _remove(path)
        elif not os.path.lexists(target):  # a user's link or file an older camgen hid by mistake: its name back
            os.replace(path, target)


def _refuse(target: Path, what: str, fix: str) -> ExportError:
    return ExportError(f"cannot write the run into '{target}': {what}; {fix}")


def preflight(target: str | Path) -> None:
    """Refuse an output folder this run could not replace whole, before anything is computed.

    ``target`` (``OUTDIR/<scene>``) must be absent, an empty folder or a previous run (plain
    files with a ``report.json``) that may be removed; its parent must be (or become) a folder
    this user may write in.

    Raises
    ------
    ExportError
        Naming the path, what stands there and what to do.
    """
    target = Path(target)
    other = "run with another -o OUTDIR, or move it away"
    parent = target.parent
    while not os.path.lexists(parent) and parent != parent.parent:  # the folders a run would create
        parent = parent.parent
    if not parent.is_dir():
        raise _refuse(target, f"'{parent}' is not a folder", "choose another -o OUTDIR")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise _refuse(target, f"this user may not write in the folder '{parent}'", "choose another -o OUTDIR")
    try:
        info = os.lstat(target)
    except FileNotFoundError:
        return
    except OSError as exc:
        raise _refuse(target, exc.strerror or str(exc), other) from None
    if stat.S_ISLNK(info.st_mode):
        raise _refuse(target, f"it is a symbolic link (to '{os.readlink(target)}'), and camgen replaces the folder of a run "
                      "whole: it neither follows nor replaces links", "remove the link, or " + other)
    if not stat.S_ISDIR(info.st_mode):
        raise _refuse(target, "a file stands there, not the folder of a previous run", "remove it, or " + other)
    try:
        entries = list(os.scandir(target))
    except OSError as exc:
        raise _refuse(target, f"its previous run cannot be read ({exc.strerror or exc})", other) from None
    foreign = sorted(e.name for e in entries if not e.is_file(follow_symlinks=False))
    if foreign or (entries and not any(e.name == "report.json" for e in entries)):
        what = f"'{foreign[0]}' is not a file camgen writes" if foreign else "it has no report.json"
        raise _refuse(target, f"the folder is not a previous camgen run ({what}), and a run replaces the folder whole",
                      "move what it holds, or " + other)
    if entries and not os.access(target, os.W_OK | os.X_OK):
        raise _refuse(target, "the previous run in it is read-only, so it could not be replaced",
                      f"make it writable (chmod u+w '{target}'), or " + other)


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


@dataclass(frozen=True)
class WrittenRun:
    """What :func:`write_run` did: the ``files`` now in the run's folder, and ``leftover``, the
    hidden folder of the previous run where it could not be removed (the next run removes it)."""

    files: list[Path]
    leftover: Path | None = None


def write_run(target: str | Path, files: Mapping[str, str | bytes]) -> WrittenRun:
    """Write ``files`` (name -> text or bytes; text as UTF-8 with '\\n' line ends) as the folder
    ``target``, replacing what was there in one atomic step.

    Raises
    ------
    ExportError
        If ``target`` cannot take a run (:func:`preflight`) or the files cannot be written; then
        ``target`` is as it was.  Once the new run is in place nothing is raised.
    """
    target = Path(target)
    preflight(target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        recover(target)
        token = f"{os.getpid()}.{secrets.token_hex(4)}"
        staging = target.parent / f".camgen-{target.name}.{token}.staging"
        staging.mkdir(mode=0o777)
        try:
            with scratch(staging):
                _write(staging, files)
                checkpoint()  # a run asked to stop goes no further than here
                with deferred():  # the swap and the removal of the previous run are never cut in half
                    previous = _swap(staging, target, token)
        except BaseException:
            with deferred():
                shutil.rmtree(staging, ignore_errors=True)
            raise
    except OSError as exc:
        raise ExportError(f"cannot write the run into '{target}': {exc.strerror or exc}") from None
    leftover = None
    if previous is not None:  # the run is written: the previous one is removed, or left for the next run
        with deferred():
            old = target.parent / f".camgen-{target.name}.{token}.old"
            try:
                os.rename(previous, old)  # marked done: any later run may remove it, whatever became of this process
            except OSError:
                old = previous
            shutil.rmtree(old, ignore_errors=True)
        leftover = old if os.path.lexists(old) else None
    return WrittenRun([target / name for name in files], leftover)


def _swap(staging: Path, target: Path, token: str) -> Path | None:
    """Put ``staging`` in place of ``target``; return where the previous run went (None: none)."""
    if not os.path.lexists(target):
        os.rename(staging, target)
        return None
    if exchange(staging, target):
        return staging  # now the previous run
    retired = target.parent / f".camgen-{target.name}.{token}.retired"
    os.rename(target, retired)
    try:
        os.rename(staging, target)
    except BaseException:
        os.rename(retired, target)
        raise
    return retired
