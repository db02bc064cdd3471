"""A lockstep run over LCM pins plant_node and fsw_node each to a CPU of its own (flight._pin; docs/sil.md), and
the pinning changes the run's speed only: the same command history pinned, unpinned and in process."""
from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from aocs_loop import history
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog


def _plant_summary(out: Path) -> dict:
    lines = [ln for ln in (out / "plant_node.stdout").read_text().splitlines() if ln.startswith("{")]
    return json.loads(lines[-1])["plant_node"]


def _fly(tmp_path, name, **kw) -> tuple[Path, dict]:
    out = tmp_path / name
    res = execute(RunOptions(scenario="irassi_rw", out=str(out), duration=20.0, plots=False, quiet=True, **kw))
    assert res.metrics["verdict"]["passed"], res.metrics["verdict"]
    return out, json.loads((out / "run.json").read_text())


@pytest.mark.skipif(len(os.sched_getaffinity(0)) < 2, reason="pinning needs two CPUs")
def test_pinned_unpinned_and_direct_fly_the_same_commands(tmp_path, private_netns, fsw_node_bin):  # noqa: ARG001
    mine = sorted(os.sched_getaffinity(0))
    pinned, meta = _fly(tmp_path, "pinned")
    assert meta["pinned_cpus"] == {"plant_node": mine[0], "fsw_node": mine[1]}
    assert _plant_summary(pinned)["cpus"] == [mine[0]]            # the loop ran on the plant's CPU alone
    free, meta = _fly(tmp_path, "free", pin_cpus=False)
    assert meta["pinned_cpus"] is None and _plant_summary(free)["cpus"] == mine
    direct, meta = _fly(tmp_path, "direct", transport="direct")
    assert meta["pinned_cpus"] is None
    ref = lcmlog.read(pinned / "run.lcmlog")
    for other in (free, direct):
        assert history.differences(ref, lcmlog.read(other / "run.lcmlog")) == [], other.name
