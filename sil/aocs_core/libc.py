"""The C library through ctypes, loaded once per process.

ctypes.util.find_library runs `ldconfig -p` in a subprocess (a few milliseconds) at every call: the network namespace
calls (unshare, setns) and the process calls (prctl) of every run went through it, in a campaign's forked plants too.
libc() finds it once; a process forked afterwards inherits the handle.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import functools


@functools.cache
def libc() -> ctypes.CDLL:
    """The C library, errno kept for ctypes.get_errno (OSError when it cannot be loaded)."""
    return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)


#: mallopt(3) parameters (malloc.h)
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
#: what a process that flies one run after another keeps of what a run freed: blocks below MMAP_BYTES come from the
#: heap (not a fresh mapping each), and up to TRIM_BYTES of free heap stay mapped for the next run
KEEP_MMAP_BYTES = 32 << 20     # glibc's largest (DEFAULT_MMAP_THRESHOLD_MAX on 64 bits)
KEEP_TRIM_BYTES = 256 << 20


def keep_freed_memory() -> bool:
    """glibc's malloc told to keep the memory a run frees for the next (mallopt: M_MMAP_THRESHOLD KEEP_MMAP_BYTES,
    M_TRIM_THRESHOLD KEEP_TRIM_BYTES), for a process that flies many runs (a campaign's worker, its plant servers):
    by default each run's large arrays (the log, its decoded columns) are fresh mappings, zeroed page by page by the
    kernel and unmapped again, run after run. Larger blocks (a mission day's log) are still mapped and returned at
    once. False when the C library is not glibc (nothing changed)."""
    try:
        mallopt = libc().mallopt   # int mallopt(int, int): ctypes passes Python ints as C ints
    except (OSError, AttributeError):
        return False
    return bool(mallopt(M_MMAP_THRESHOLD, KEEP_MMAP_BYTES)) and bool(mallopt(M_TRIM_THRESHOLD, KEEP_TRIM_BYTES))
