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
