"""A study process keeps its freed memory for the next design (glibc's malloc settings).

One design's evaluation makes arrays of a few hundred kB (the dense cam-angle grid's kinematics:
complex rows of 7,000 angles and more) and frees them; glibc's malloc serves blocks above its
mmap threshold (128 kB at start) by fresh ``mmap`` calls and returns them at ``free``, so every
design pays the system calls and the page faults of fresh memory again (about a sixth of a
plate-cam design's time, measured in benchmarks/bench_evaluate.py).  :func:`keep_heap` raises the
threshold (:data:`MMAP_THRESHOLD`) and the heap's trim threshold (:data:`TRIM_THRESHOLD`) with
``mallopt``, so such blocks come from the heap and stay in the process between designs.  It
changes where arrays live, never a value; elsewhere than glibc (or where ``mallopt`` refuses) it
does nothing.  Called by :meth:`camgen.study.design.StudyScene.scene` (a study's designs: a
sweep's worker, the optimiser), never by ``camgen run`` or ``camgen check``.
"""
from __future__ import annotations

import functools

__all__ = ["MMAP_THRESHOLD", "TRIM_THRESHOLD", "keep_heap"]

#: Blocks below this size (bytes) come from the heap, not from a fresh ``mmap`` (glibc's largest
#: allowed value on 64-bit systems is 32 MiB).
MMAP_THRESHOLD = 16 << 20
#: Free memory at the top of the heap is given back to the system only beyond this (bytes).
TRIM_THRESHOLD = 64 << 20
# glibc's mallopt parameter numbers (malloc.h)
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3


@functools.cache
def keep_heap() -> bool:
    """Set glibc's mmap and trim thresholds for this process (once); True where both were set."""
    import ctypes
    import sys

    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(None)  # the process's own C library
        libc.gnu_get_libc_version  # glibc's own function: another C library's mallopt numbers differ
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return bool(mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and bool(mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD))
