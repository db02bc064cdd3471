"""Scheduled events (aocs_runner.events) and --set overrides (aocs_runner.scenario_opts).

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import pytest

from aocs_plant.scenario import ScenarioError, load
from aocs_runner import events, scenario_opts


def test_events_parse_and_schedule():
    ev = events.parse_all(["5.05:malformed", "10:law=smc", "0:drop", "3:law=bogus", "7:law=42",
                           "8:target=0,0,0,2", "9:mode=standby", "1:stale"])
    by = {e.text: e for e in ev}
    assert by["10:law=smc"].law_id == 5 and by["10:law=smc"].is_command
    assert by["3:law=bogus"].law_id == events.UNKNOWN_LAW_ID
    assert by["7:law=42"].law_id == 42
    assert by["8:target=0,0,0,2"].target == (0.0, 0.0, 0.0, 2.0)
    assert by["9:mode=standby"].mode == 0
    sched = events.schedule(ev, 0.1, 200)
    # first tick with t_k >= T: 5.05 s -> tick 51; 10 s -> tick 100 (no rounding drift)
    assert [e.kind for e in sched[51]] == ["malformed"]
    assert [e.kind for e in sched[100]] == ["law"]
    assert [e.kind for e in sched[0]] == ["drop"]
    assert events.schedule(events.parse_all(["2:drop"]), 0.1, 50, start_tick=100) == {100: [ev[0].__class__(
        2.0, "drop", text="2:drop")]}
    for bad in ("x:drop", "5", "5:explode", "5:drop=1", "5:target=1,2,3", "-1:drop", "5:mode=weird"):
        with pytest.raises(events.EventError):
            events.parse(bad)
    with pytest.raises(events.EventError, match="after the end"):
        events.schedule(events.parse_all(["20:drop"]), 0.1, 200)


def test_overrides_parse_toml_values_and_round_trip():
    ov = scenario_opts.overrides(["control.enabled=false", "actuator.axis_limit=0.5", "plant.model=nonlinear",
                                  'sensors.faults=[{channel="rate", kind="nan", start_s=1.0, end_s=2.0}]'],
                                 duration=30, seed=4, limit=0.2)
    assert ov["control.enabled"] is False and ov["plant.model"] == "nonlinear"
    assert ov["actuator.axis_limit"] == 0.2          # --limit wins over --set
    assert ov["duration_s"] == 30.0 and ov["seed"] == 4
    assert ov["sensors.faults"][0]["kind"] == "nan"
    assert scenario_opts.parse_sets(scenario_opts.to_args(ov)[1::2]) == ov
    sc = load("irassi_small", ov | {"plant.model": None, "metrics.window_s": 30.0})
    assert sc.duration_s == 30 and sc.actuator.axis_limit == 0.2 and not sc.control.enabled
    with pytest.raises(ScenarioError):
        load("irassi_large", {"laws.quat_pd.kp": -4000.0})   # a negative gain is refused
    with pytest.raises(ValueError):
        scenario_opts.parse_sets(["novalue"])
