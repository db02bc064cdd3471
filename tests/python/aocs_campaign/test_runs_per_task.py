"""How many runs a campaign's Dask task flies (execute.runs_per_task, worker.run_tasks)."""
from __future__ import annotations

import pytest

from aocs_campaign import execute as E
from aocs_campaign import worker as W


def test_direct_runs_are_grouped_only_when_every_thread_still_has_its_tasks():
    k = E.RUNS_PER_TASK["direct"]
    assert k > 1 and E.RUNS_PER_TASK.get("lcm", 1) == 1
    threads = 4
    full = threads * E.IN_FLIGHT_PER_THREAD * k          # enough runs for every thread's tasks of k runs
    assert E.runs_per_task("direct", full, threads) == k
    assert E.runs_per_task("direct", 10 * full, threads) == k
    assert E.runs_per_task("direct", full - 1, threads) == k - 1
    assert E.runs_per_task("direct", threads * E.IN_FLIGHT_PER_THREAD - 1, threads) == 1
    assert E.runs_per_task("direct", 0, threads) == 1 and E.runs_per_task("direct", 5, 1) == 2
    assert E.runs_per_task("lcm", 10**6, threads) == 1


def test_run_tasks_refuses_lists_of_different_lengths():
    with pytest.raises(ValueError, match="2 specs, 1 folders and 2 re-flight flags"):
        W.run_tasks([{}, {}], ["a"], refly=[False, True])
    assert W.run_tasks([], []) == []


def test_a_direct_campaign_s_workers_fly_one_run_at_a_time_an_lcm_one_s_two():
    """A direct run's plant is its thread's plant runner (a process of its own): one thread per local worker; an LCM
    run is a ping-pong of two processes, each waiting on the other: two."""
    assert W.runs_per_worker("direct") == W.RUNS_PER_WORKER_DIRECT == 1
    assert W.runs_per_worker("lcm") == W.RUNS_PER_WORKER == 2
