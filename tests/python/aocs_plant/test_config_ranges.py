"""One place for the ranges of the configuration values (issue 25, item 7): the configuration registry's
RULE column (config_fields.def AOCS_CONFIG_RULE_ROWS), applied identically by the flight software's
parser (fsw_node and the PIL bridge run the same C parser, node_config.c, here as the aocs_node_config
tool) and by the scenario loader (through the registry JSON); the plant refuses what would crash it."""
from __future__ import annotations

import math

import pytest

from aocs_core import registry
from aocs_flightcfg import fsw_config
from aocs_pil import config as pil_config
from aocs_plant import scenario as scmod

#: the rows with a physical range (not only a sign), and their scenario key (None: no scenario key)
RANGED = {"js_kgm2": "wheels.spin_inertia_kg_m2", "u_max_nm": "wheels.torque_limit_nm",
          "omega_max_radps": "wheels.speed_limit_rad_s", "viscous_nms": "wheels.viscous_nms",
          "coulomb_nm": "wheels.coulomb_nm", "coulomb_width_radps": "wheels.coulomb_width_rad_s",
          "null_speed_radps": "wheels.null_speed_rad_s", "wheels.null_gain": "wheels.null_gain_per_s",
          "guidance.margin": "guidance.margin", "guidance.rate_limit_radps": "guidance.rate_limit_radps",
          "guidance.jerk_time_s": "guidance.jerk_time_s"}


def _rows():
    return {f.key: f for f in registry.load().config_fields if f.key in RANGED}


def _probe_values(f):
    lo = f.rule_lo if f.rule_lo != 0.0 else 1e-12
    return sorted({f.rule_lo, f.rule_hi, math.nextafter(f.rule_lo, -math.inf), math.nextafter(f.rule_hi, math.inf),
                   lo * 0.5, f.rule_hi * 2.0, 0.0, 1e300, -1e300, 1e-300, -1e-300, 1.0})


def test_every_ranged_row_has_a_physical_range():
    rows = _rows()
    assert set(rows) == set(RANGED)
    for f in rows.values():
        assert f.rule not in ("any", "pos", "nonneg"), f.key
        assert -1e5 <= f.rule_lo and f.rule_hi <= 1e5 and f.rule_lo < f.rule_hi, f.key
        assert not f.holds(1e300) and not f.holds(-1e300), f.key
        if f.rule_lo > 0.0:        # a quantity > 0 (or 0 = off): a tiny positive value is a mistake
            assert not f.holds(1e-300), f.key


@pytest.fixture(scope="module")
def base_config(tmp_path_factory):
    """fsw_node's configuration of irassi_rw (wheels, null-space management on, a jerk-limited slew)."""
    sc = scmod.load("irassi_rw", {"wheels.null_gain_per_s": 0.01, "guidance.mode": "slew", "guidance.profile": "jerk_limited",
                                  "guidance.jerk_time_s": 5.0})
    cfg = fsw_config.node_config(sc, sc.control.law)
    assert "wheel0.null_speed_radps" in cfg and "guidance.jerk_time_s" in cfg
    return cfg, tmp_path_factory.mktemp("cfg")


@pytest.mark.parametrize("key", sorted(RANGED))
def test_the_c_parser_applies_the_registry_s_range_as_python_reads_it(base_config, key):
    """For values at, just inside and just outside each edge and the absurd ones: the C parser refuses the
    value for its range exactly when the registry row's range (Python) refuses it."""
    cfg, d = base_config
    f = _rows()[key]
    file_key = f"wheel0.{key}" if f.per_wheel else key
    for v in _probe_values(f):
        path = fsw_config.write(d / "n.cfg", {**cfg, file_key: repr(v)})
        try:
            pil_config.load(path)
            msg = ""
        except pil_config.ConfigError as exc:
            msg = str(exc)
        if f.holds(v):
            assert f"must be {f.rule_text}" not in msg, (key, v, msg)
        else:     # refused, for its range (a subnormal: the parser's "not a finite number" comes first)
            assert f"key '{file_key}'" in msg and (f"must be {f.rule_text}" in msg or "not a finite number" in msg), \
                (key, v, msg)


@pytest.mark.parametrize("key", sorted(RANGED))
@pytest.mark.parametrize("v", [1e300, 1e-300, -1e300])
def test_the_scenario_loader_refuses_what_the_flight_software_refuses(key, v):
    f = _rows()[key]
    if f.holds(v):
        return
    ov = {RANGED[key]: v}
    if key == "guidance.jerk_time_s":
        ov["guidance.profile"] = "jerk_limited"
    if key == "null_speed_radps":
        ov["wheels.null_gain_per_s"] = 0.01
    with pytest.raises(scmod.ScenarioError) as exc:
        scmod.load("irassi_rw", ov)
    assert RANGED[key] in str(exc.value) and "\n" not in str(exc.value)


def test_the_plant_refuses_wheels_heavier_than_the_spacecraft():
    """J - sum Js g g^T not positive definite (the plant raised a ValueError traceback from plant_node)."""
    with pytest.raises(scmod.ScenarioError, match="wheels.spin_inertia_kg_m2.*not positive definite"):
        scmod.load("irassi_rw", {"plant.inertia": [[0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]]})
