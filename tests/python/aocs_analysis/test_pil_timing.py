"""run_metrics.pil_timing (docs/pil.md): a processor-in-the-loop run's timing from the bridge's final JSON, the
instruction figures of the whole step and of the law's window, the budget at the nominal clock."""
from __future__ import annotations

import numpy as np
import pytest

from aocs_analysis import run_metrics


def test_the_bridge_summary_fills_the_timing():
    fsw = {"instructions": {"median": 41000, "p99": 41200, "max": 42100, "budget": 151000, "overruns": 0,
                            "inexact": 0},
           "law_instructions": {"median": 1500, "max": 1900}, "clock_hz": 168e6, "precision": "float"}
    cmd = {"tick": np.arange(5), "overrun": np.array([0, 1, 0, 0, 1])}
    timing, series = {"budget_ns": None}, {}
    run_metrics.pil_timing(timing, series, cmd, "pil-m4f", fsw)
    assert (timing["instructions_median"], timing["instructions_max"]) == (41000, 42100)
    assert (timing["law_instructions_median"], timing["law_instructions_max"]) == (1500, 1900)
    assert timing["budget_ns"] == pytest.approx(151000 * 1e9 / 168e6)
    assert timing["overruns"] == timing["over_step_budget"] == 2
    assert timing["target"] == "pil-m4f" and timing["precision"] == "float"
    np.testing.assert_allclose(series["budget_ns"], timing["budget_ns"])


def test_without_a_bridge_summary_the_figures_are_none():
    cmd = {"tick": np.arange(3), "overrun": np.zeros(3)}
    timing, series = {"budget_ns": 5.0e6}, {}
    run_metrics.pil_timing(timing, series, cmd, "pil-m7", None)
    assert timing["instructions_median"] is None and timing["law_instructions_median"] is None
    assert timing["budget_ns"] == 5.0e6 and timing["overruns"] == 0


def test_a_run_without_a_command_flagged_no_overrun():
    """No command at all (the image never answered): no overrun counted, no budget series."""
    cmd = {"tick": np.zeros(0, np.int64), "overrun": np.zeros(0)}
    timing, series = {"budget_ns": 5.0e6}, {}
    run_metrics.pil_timing(timing, series, cmd, "pil-m7", None)
    assert timing["overruns"] == timing["over_step_budget"] == 0
    assert "budget_ns" not in series
