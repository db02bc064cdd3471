"""plant_fork.preload: what every plant loads at its start, loaded in the process that forks them (a campaign's plant
server), so that each fork inherits it instead of loading it again."""
from __future__ import annotations

from aocs_core import compiled
from aocs_loop import direct_adapter
from aocs_plant import kernels
from aocs_runner import plant_fork


def test_preload_loads_the_kernels_and_the_node_library(aocs_build_dir, monkeypatch):
    monkeypatch.delenv(kernels.ENV, raising=False)
    monkeypatch.setattr(compiled, "_loaded", {})
    monkeypatch.setattr(direct_adapter, "_lib", None)
    plant_fork.preload()
    assert compiled._loaded[kernels.RIGID_BODY] is not None and compiled._loaded[kernels.DIRECT_LOOP] is not None
    assert direct_adapter._lib is not None


def test_preload_leaves_what_it_cannot_load_to_the_plant(monkeypatch, tmp_path):
    """A build directory without the libraries: preload says nothing (the plant reports it when it needs it)."""
    monkeypatch.setenv("AOCS_BUILD_DIR", str(tmp_path))
    monkeypatch.setattr(compiled, "_loaded", {})
    monkeypatch.setattr(direct_adapter, "_lib", None)
    plant_fork.preload()
    assert compiled._loaded.get(kernels.DIRECT_LOOP) is None and direct_adapter._lib is None


def test_run_here_gives_the_exit_code_and_leaves_the_process_as_it_was(tmp_path):
    """plant_fork.run_here flies plant_node in this process (a campaign's plant runner flies one run after another):
    its exit code, its output in the file, and this process's stdout and signal handlers as they were."""
    import os
    import signal

    before = (os.fstat(1).st_ino, signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM))
    assert plant_fork.run_here(["no_such_scenario", "--mode", "lockstep"], tmp_path / "a.stdout") == 2
    assert plant_fork.run_here(["--no-such-option"], tmp_path / "b.stdout") == 2          # argparse's SystemExit
    assert (tmp_path / "a.stdout").is_file() and (tmp_path / "b.stdout").is_file()
    assert (os.fstat(1).st_ino, signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before
