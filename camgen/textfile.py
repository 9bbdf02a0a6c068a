"""Users' text: reading their text files (scenes, tables) safely, and showing their file names.

A file is read only if it is a regular file of at most a stated number of bytes (never more is
read: /dev/zero, a pipe or a huge file fail at once), in UTF-8.  :func:`display_path` shows a file
name in any locale.
"""
from __future__ import annotations

import os
import stat

__all__ = ["TextFileError", "display_path", "read_text_file"]


class TextFileError(Exception):
    """Why a user's file could not be read (the caller turns it into its own CamgenError)."""


def read_text_file(path: str | os.PathLike[str], limit: int) -> str:
    """The UTF-8 text of the regular file ``path`` (a leading BOM dropped), at most ``limit`` bytes.

    Raises
    ------
    TextFileError
        Saying why: a name the system cannot take (a NUL character), missing or unreadable, not
        a regular file, larger than ``limit``, not UTF-8.
    """
    try:
        info = os.stat(path)
    except OSError as exc:
        raise TextFileError(exc.strerror or str(exc)) from None
    except ValueError:  # os.stat's answer to a name no file can have
        raise TextFileError("the file name holds a NUL character") from None
    if not stat.S_ISREG(info.st_mode):
        raise TextFileError("not a regular file (a directory, device or pipe)")
    if info.st_size > limit:
        raise TextFileError(f"{info.st_size} bytes, more than the {limit} bytes allowed")
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)
    except OSError as exc:
        raise TextFileError(exc.strerror or str(exc)) from None
    if len(data) > limit:
        raise TextFileError(f"more than the {limit} bytes allowed")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise TextFileError("not UTF-8 text") from None


def display_path(path: str) -> str:
    """``path`` as text for a UTF-8 report, whatever the locale camgen runs in.

    Python decodes a file name it cannot read in the locale's encoding into lone surrogates
    (PEP 383: an ASCII locale turns the UTF-8 bytes of ``dé.toml`` into ``d\\udcc3\\udca9.toml``),
    which no UTF-8 file can hold.  Those surrogates are turned back into the name's bytes and
    read as UTF-8 (the usual encoding of file names on Linux and macOS; Windows names are text
    already): ``dé.toml``.  Bytes that are not UTF-8 become U+FFFD, other lone surrogates '?'.
    A name without surrogates is returned as it is.
    """
    try:
        raw = path.encode("utf-8", "surrogateescape")
    except UnicodeEncodeError:  # a surrogate no decoder makes (not U+DC80..U+DCFF): shown as '?'
        raw = path.encode("utf-8", "replace")
    return raw.decode("utf-8", "replace")
