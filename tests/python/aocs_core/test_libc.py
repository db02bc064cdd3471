"""aocs_core.libc: the C library found once per process (ctypes.util.find_library runs `ldconfig -p` in a
subprocess at every call), and the namespace and process calls going through it."""
from __future__ import annotations

import ctypes.util

import pytest

from aocs_core import libc
from aocs_runner import orchestrate


def test_the_library_is_found_once_and_the_process_calls_use_it(monkeypatch):
    lib = libc.libc()
    assert lib is libc.libc() and lib.getpid() > 0

    def no_second_search(name):
        raise AssertionError(f"find_library({name!r}) again")
    monkeypatch.setattr(ctypes.util, "find_library", no_second_search)
    orchestrate.set_process_name("aocs-test")   # prctl through the cached handle, no ldconfig
    with open("/proc/self/task/%d/comm" % __import__("threading").get_native_id()) as f:
        assert f.read().strip() == "aocs-test"


def test_a_missing_library_is_an_oserror(monkeypatch):
    libc.libc.cache_clear()
    try:
        monkeypatch.setattr(ctypes.util, "find_library", lambda name: "/nonexistent/libc-missing.so")
        with pytest.raises(OSError):
            libc.libc()
    finally:
        monkeypatch.undo()
        libc.libc.cache_clear()
        libc.libc()
