"""The scenario's [fdir] section (aocs_plant.scenario, docs/scenarios.md): any fault-management key of the
configuration registry, checked by its registry rule, written to fsw_node's configuration as given; nothing
written without the section (the flight software's defaults); one-line errors naming the key."""
import pytest

from aocs_core import registry
from aocs_flightcfg import fsw_config
from aocs_plant.scenario import ScenarioError, load


def test_no_section_writes_no_key():
    sc = load("irassi_rw_mekf")
    assert dict(sc.fdir) == {}
    assert not any(k.startswith("fdir.") for k in fsw_config.node_config(sc, "quat_pid"))


def test_every_registry_key_is_taken_and_written():
    fields = [f for f in registry.load().config_fields if f.key.startswith("fdir.")]
    assert {f.key for f in fields} >= {"fdir.enabled", "fdir.st_chi2", "fdir.gyro_bias_chi2", "fdir.gyro_bias_persist"}
    sets = {f.key: (3 if f.kind == "u32" else 0.5) for f in fields if f.key != "fdir.enabled"}
    sets["fdir.enabled"] = 0
    cfg = fsw_config.node_config(load("irassi_rw_mekf", sets), "quat_pid")
    for k, v in sets.items():
        assert cfg[k] == str(v), k


@pytest.mark.parametrize("key,value,message", [
    ("fdir.nope", 1.0, "fdir.nope: is not a fault-management key"),
    ("fdir.st_persist", 1.5, "fdir.st_persist: expected an integer"),
    ("fdir.st_persist", 0, "fdir.st_persist: 0 must be > 0"),
    ("fdir.st_persist", 2 ** 32, "beyond a 32-bit count"),
    ("fdir.st_chi2", -1.0, "fdir.st_chi2: -1.0 must be > 0"),
    ("fdir.gyro_bias_chi2", -0.5, "fdir.gyro_bias_chi2: -0.5 must be >= 0"),
    ("fdir.gyro_bias_chi2", "x", "expected a number"),
])
def test_values_outside_the_registry_rule_are_refused_naming_the_key(key, value, message):
    with pytest.raises(ScenarioError) as exc:
        load("irassi_rw_mekf", {key: value})
    assert message in str(exc.value) and "\n" not in str(exc.value)


@pytest.mark.parametrize("key,bad,good", [
    ("fdir.enabled", 2, 0), ("fdir.st_frozen_samples", 1, 2), ("fdir.gyro_stuck_samples", 1, 2),
    ("fdir.wheel_residual_frac", 1.5, 1.0), ("fdir.wheel_residual_frac", 0.0, 0.5),
    ("fdir.gyro_bias_chi2", -1.0, 0.0), ("fdir.st_persist", 0, 1),
])
def test_the_flight_software_s_parser_and_the_loader_draw_the_same_line(tmp_path, key, bad, good):
    """The stage's own rules (a switch, a fraction, repeat counts) are registry rules: fsw_node's parser (the
    same C as the PIL bridge's, here as the aocs_node_config tool) and the scenario loader refuse the same value
    with the registry row's text, and take the one inside."""
    from aocs_pil import config as pil_config

    f = next(x for x in registry.load().config_fields if x.key == key)
    cfg = fsw_config.node_config(load("irassi_rw_mekf"), "quat_pid")
    for v, ok in ((bad, False), (good, True)):
        path = fsw_config.write(tmp_path / "n.cfg", {**cfg, key: repr(v)})
        try:
            pil_config.load(path)
            msg = ""
        except pil_config.ConfigError as exc:
            msg = str(exc)
        assert (f"must be {f.rule_text}" in msg) != ok, (key, v, msg)
        if ok:
            load("irassi_rw_mekf", {key: v})
        else:
            with pytest.raises(ScenarioError, match=f"{key}: .*must be"):
                load("irassi_rw_mekf", {key: v})
