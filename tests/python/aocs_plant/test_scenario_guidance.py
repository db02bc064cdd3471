"""The scenario's [guidance] section (aocs_plant.scenario, docs/spec.md 5.1.1): defaults, bounds,
one-line errors naming the key, and what aocs_flightcfg.fsw_config writes for it (nothing in step mode)."""
import pytest

from aocs_flightcfg import fsw_config
from aocs_plant.scenario import GuidanceConfig, ScenarioError, load
from aocs_runner import scenario_opts


def test_default_is_step_and_writes_no_key():
    sc = load("irassi_large")
    assert sc.guidance == GuidanceConfig() and sc.guidance.mode == "step"
    assert not any(k.startswith("guidance.") for k in fsw_config.node_config(sc, "quat_pd"))


def test_slew_keys_written_from_the_section():
    sc = load("irassi_large", {"guidance.mode": "slew", "guidance.profile": "jerk_limited",
                               "guidance.jerk_time_s": 4.0, "guidance.margin": 0.9,
                               "guidance.rate_limit_radps": 0.01, "actuator.axis_limit": 1.0})
    cfg = fsw_config.node_config(sc, "smc")
    assert cfg["guidance.mode"] == "slew" and cfg["guidance.profile"] == "jerk_limited"
    assert cfg["guidance.margin"] == "0.9" and cfg["guidance.rate_limit_radps"] == "0.01"
    assert cfg["guidance.jerk_time_s"] == "4.0"
    assert cfg["inertia"] == "2059.5 0.0 0.0 0.0 5954.2 0.0 0.0 0.0 5974.3"  # the one inertia


def test_cli_shorthand():
    assert scenario_opts.overrides(guidance="slew") == {"guidance.mode": "slew"}
    assert scenario_opts.overrides() == {}


@pytest.mark.parametrize("ov, key, words", [
    ({"guidance.mode": "glide"}, "guidance.mode", "unknown value 'glide'"),
    ({"guidance.profile": "s_curve"}, "guidance.profile", "unknown value"),
    ({"guidance.margin": 0.0}, "guidance.margin", "must be in [0.01, 1]"),
    ({"guidance.margin": 1e-300}, "guidance.margin", "must be in [0.01, 1]"),      # issue 25, item 7
    ({"guidance.margin": 1.2}, "guidance.margin", "above 1"),
    ({"guidance.margin": float("nan")}, "guidance.margin", ""),
    ({"guidance.rate_limit_radps": -0.1}, "guidance.rate_limit_radps", "must be 0 (none) or in [1e-6, 10] rad/s"),
    ({"guidance.rate_limit_radps": 1e-300}, "guidance.rate_limit_radps", "must be 0 (none) or in [1e-6, 10]"),
    ({"guidance.profile": "jerk_limited", "guidance.jerk_time_s": 1e-300}, "guidance.jerk_time_s",
     "must be 0 (none) or in [1e-3, 1000] s"),
    ({"guidance.rate_limit_radps": 50.0}, "guidance.rate_limit_radps", "above 10"),
    ({"guidance.jerk_time_s": 2.0}, "guidance.jerk_time_s", "bang_coast_bang"),
    ({"guidance.profile": "jerk_limited"}, "guidance.jerk_time_s", "needs a ramp time"),
    ({"guidance.profile": "jerk_limited", "guidance.jerk_time_s": 5000.0}, "guidance.jerk_time_s", "above 1000"),
    ({"guidance.speed": 1.0}, "guidance.speed", "unknown key"),
    ({"guidance.mode": "slew", "target.wd": [0.0, 1e-4, 0.0]}, "guidance.mode", "fixed target"),
])
def test_bad_values_name_the_key(ov, key, words):
    with pytest.raises(ScenarioError) as ei:
        load("irassi_large", ov)
    msg = str(ei.value)
    assert f": {key}:" in msg and words in msg and "\n" not in msg


def test_orbit_scenario_has_no_guidance():
    with pytest.raises(ScenarioError, match="guidance: slew guidance applies to attitude scenarios only"):
        load("landsat8_srp", {"guidance.mode": "slew"})
