"""aocs_core.compiled: the kernel modules loaded once per process, whichever thread asks first (a campaign worker's two
runs read their logs at once), and turned off by AOCS_PLANT_KERNELS."""
from __future__ import annotations

import sysconfig
import threading

from aocs_core import compiled


def test_threads_asking_at_once_get_the_one_module_without_sysconfig(aocs_build_dir, monkeypatch):
    """sysconfig.get_config_var's first call fills a dict another thread may read half-filled (EXT_SUFFIX None: a
    worker's run crashed with a TypeError): the loader does not ask it."""
    monkeypatch.delenv(compiled.ENV, raising=False)
    monkeypatch.setattr(compiled, "_loaded", {})

    def no_sysconfig(*args):
        raise AssertionError(f"sysconfig.get_config_var{args}")
    monkeypatch.setattr(sysconfig, "get_config_var", no_sysconfig)
    start = threading.Barrier(8)
    got = []

    def ask():
        start.wait()
        got.append(compiled.module(compiled.LCMLOG))
    threads = [threading.Thread(target=ask) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(30)
    assert len(got) == 8 and got[0] is not None and all(m is got[0] for m in got)


def test_the_environment_turns_modules_off(monkeypatch):
    monkeypatch.setenv(compiled.ENV, "python")
    assert compiled.module(compiled.LCMLOG) is None and compiled.module(compiled.RIGID_BODY) is None
    monkeypatch.setenv(compiled.ENV, "periods")
    assert compiled.module(compiled.DIRECT_LOOP) is None and compiled.enabled(compiled.LCMLOG)
