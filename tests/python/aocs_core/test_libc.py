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


def test_keep_freed_memory_sets_both_thresholds_and_says_when_it_could_not(monkeypatch):
    """mallopt(M_MMAP_THRESHOLD, 32 MiB) and mallopt(M_TRIM_THRESHOLD, 256 MiB), the values glibc accepts (the real
    library answers True); False when mallopt refuses or there is none."""
    assert libc.keep_freed_memory() is True     # glibc here: both accepted

    class Fake:
        def __init__(self, answer):
            self.answer, self.calls = answer, []
            self.mallopt = self._mallopt

        def _mallopt(self, param, value):
            self.calls.append((param, value))
            return self.answer

    fake = Fake(1)
    monkeypatch.setattr(libc, "libc", lambda: fake)
    assert libc.keep_freed_memory() is True
    assert fake.calls == [(-3, 32 * 2**20), (-1, 256 * 2**20)]
    monkeypatch.setattr(libc, "libc", lambda: Fake(0))
    assert libc.keep_freed_memory() is False
    monkeypatch.setattr(libc, "libc", lambda: object())          # no mallopt: not glibc
    assert libc.keep_freed_memory() is False
