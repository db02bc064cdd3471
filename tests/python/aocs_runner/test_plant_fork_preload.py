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
