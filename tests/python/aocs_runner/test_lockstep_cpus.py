"""Where a lockstep run's two processes run (run.cpus_of, transport.lockstep_cpus): a run over LCM on the host, by
itself, pins plant_node and fsw_node each to a CPU of its own; everything else is left to the scheduler."""
from __future__ import annotations

import dataclasses
import os

import pytest

from aocs_runner import transport
from aocs_runner.run import RunOptions, cpus_of, plan_run


@pytest.fixture
def plan(tmp_path):
    opts = RunOptions(scenario="irassi_small", out=str(tmp_path / "o"), plots=False, quiet=True)
    return opts, plan_run(opts)


def test_a_lockstep_run_over_lcm_pins_its_two_processes_to_two_cpus(plan, monkeypatch):
    opts, p = plan
    mine = sorted(os.sched_getaffinity(0))   # run.json names the two the plan chose on this machine
    assert p.meta["pinned_cpus"] == ({"plant_node": mine[0], "fsw_node": mine[1]} if len(mine) >= 2 else None)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {5, 3, 9})
    assert cpus_of(opts, p) == (3, 5)


@pytest.mark.parametrize("change", [{"transport": "direct"}, {"pin_cpus": False},
                                    {"plant_launcher": object()}, {"target": "pil-m7"}],
                         ids=["direct", "no_pin_cpus", "in_a_campaign", "pil"])
def test_other_runs_are_left_to_the_scheduler(plan, monkeypatch, change):
    opts, p = plan
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})
    assert cpus_of(dataclasses.replace(opts, **change), p) is None


def test_a_realtime_run_and_a_single_cpu_are_not_pinned(tmp_path, monkeypatch):
    opts = RunOptions(scenario="irassi_small", out=str(tmp_path / "rt"), plots=False, quiet=True, realtime=True)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1})
    assert cpus_of(opts, plan_run(opts)) is None
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {4})
    assert transport.lockstep_cpus() is None


def test_the_repeat_command_keeps_no_pin_cpus(tmp_path):
    opts = RunOptions(scenario="irassi_small", out=str(tmp_path / "n"), plots=False, quiet=True, pin_cpus=False)
    assert "--no-pin-cpus" in plan_run(opts).meta["repeat_command"]
    assert plan_run(opts).meta["pinned_cpus"] is None
