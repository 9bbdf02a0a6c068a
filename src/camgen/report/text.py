"""Text the reports take from outside camgen (file names), made fit for a UTF-8 file."""
from __future__ import annotations


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
