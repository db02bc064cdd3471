"""The scenario's [estimator] section (aocs_plant.scenario, docs/spec.md 5.6.11): the default passthrough (every
reference scenario, no key written), type "mekf" with its tuning, the sensor figures taken from the scenario's
[sensors.star_tracker] and [sensors.gyro] (one description of both sides), one-line errors naming the key, and
what aocs_flightcfg.fsw_config writes, read back by fsw_node's own parser (aocs_pil.config)."""
from pathlib import Path

import pytest

from aocs_core import registry
from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_flightcfg import fsw_config
from aocs_pil import config as node_config
from aocs_plant.scenario import EstimatorConfig, ScenarioError, list_scenarios, load

ST_GYRO = Path(__file__).resolve().parent / "data" / "sensors_st_gyro.toml"
MEKF = {"estimator.type": "mekf"}


def test_default_is_passthrough_and_writes_no_key():
    filtered = set()
    for sid in list_scenarios():
        sc = load(sid)
        if sc.estimator.type != "passthrough":
            filtered.add(sid)
            continue
        assert sc.estimator == EstimatorConfig()
        for law in sc.control.laws:
            cfg = fsw_config.node_config(sc, law)
            assert "estimator" not in cfg and not any(k.startswith("mekf.") for k in cfg), (sid, law)
    # the reference scenarios stay on passthrough: only the MEKF hold, the realistic-suite *_mekf files and the
    # fault scenario built on irassi_rw_mekf (issue 26) fly a filter
    assert filtered == {"irassi_hold_mekf", "irassi_small_mekf", "irassi_large_mekf", "irassi_rw_mekf",
                        "irassi_rw_failed_mekf", "irassi_day_mekf", "irassi_rw_wheel_dies"}
    assert all(sid.endswith("_mekf") for sid in filtered - {"irassi_rw_wheel_dies"})
    cfg = fsw_config.node_config(load("irassi_hold_mekf"), "quat_pd")
    assert cfg["estimator"] == "mekf" and "mekf.st_sigma_cross_rad" in cfg
    # a passthrough given by name is the default too
    assert load(ST_GYRO, {"estimator.type": "passthrough"}).estimator == EstimatorConfig()


def test_defaults_are_the_registry_defaults():
    """EstimatorConfig's defaults are the flight software's (the mekf.* rows' DEFAULT, aocs_mekf_config_default)."""
    fields = {f.key: f for f in registry.load().config_fields}
    assert fields["estimator"].names == ("passthrough", "mekf")
    e = load(ST_GYRO, MEKF).estimator
    assert e.type == "mekf" and e.noise_scale == 1.0
    for k in ("gate_chi2", "p0_att_sigma_rad", "p0_bias_sigma_radps", "max_gap_s"):
        assert getattr(e, k) == fields[f"mekf.{k}"].default[0] == getattr(EstimatorConfig(), k)
    assert tuple(e.bias0_radps) == tuple(fields["mekf.bias0_radps"].default) == (0.0, 0.0, 0.0)


def test_mekf_keys_come_from_the_sensor_sections():
    sc = load(ST_GYRO, {**MEKF, "estimator.gate_chi2": 25.0, "estimator.p0_att_sigma_rad": 0.1,
                        "estimator.p0_bias_sigma_radps": 1e-5, "estimator.max_gap_s": 3.0,
                        "estimator.bias0_radps": [1e-6, 0.0, -1e-6],
                        "sensors.star_tracker.mounting_q": [0.0, 0.6, 0.0, 0.8]})
    cfg = fsw_config.node_config(sc, "quat_pd")
    st, gyro = sc.sensors["star_tracker"], sc.sensors["gyro"]
    assert cfg["estimator"] == "mekf"
    assert cfg["mekf.st_q_SB"] == "0.0 0.6 0.0 0.8"
    assert float(cfg["mekf.st_sigma_cross_rad"]) == 1.0 / ARCSEC_PER_RAD == st.noise_cross_arcsec / ARCSEC_PER_RAD
    assert float(cfg["mekf.st_sigma_about_rad"]) == 8.0 / ARCSEC_PER_RAD
    assert float(cfg["mekf.gyro_arw_radpsqrts"]) == gyro.arw == 5.8e-7
    assert float(cfg["mekf.gyro_rrw_radps1p5"]) == gyro.rrw == 1.0e-11
    assert float(cfg["mekf.gate_chi2"]) == 25.0 and float(cfg["mekf.max_gap_s"]) == 3.0
    assert float(cfg["mekf.p0_att_sigma_rad"]) == 0.1 and float(cfg["mekf.p0_bias_sigma_radps"]) == 1e-5
    assert cfg["mekf.bias0_radps"] == "1e-06 0.0 -1e-06"
    # every key is a key of the flight software
    keys = {f.key for f in registry.load().config_fields}
    assert {k for k in cfg if k.startswith("mekf.")} <= keys


def test_noise_scale_mistunes_the_filter_only():
    a = fsw_config.node_config(load(ST_GYRO, MEKF), "quat_pd")
    sc = load(ST_GYRO, {**MEKF, "estimator.noise_scale": 3.0})
    b = fsw_config.node_config(sc, "quat_pd")
    for k in ("mekf.st_sigma_cross_rad", "mekf.st_sigma_about_rad", "mekf.gyro_arw_radpsqrts",
              "mekf.gyro_rrw_radps1p5"):
        assert float(b[k]) == pytest.approx(3.0 * float(a[k]), rel=1e-15)
    assert sc.sensors["star_tracker"].noise_cross_arcsec == 1.0   # the plant's sensor is unchanged
    assert a["mekf.gate_chi2"] == b["mekf.gate_chi2"]


def test_fsw_node_parser_takes_the_mekf_configuration(tmp_path):
    """fsw_node's own parser (aocs_node_config) reads the file and inits the executive with the MEKF; the PIL
    CONFIG frame carries the estimator and the mekf fields (ids 68 .. 78)."""
    cfg = fsw_config.node_config(load(ST_GYRO, MEKF), "quat_pd")
    p = fsw_config.write(tmp_path / "mekf.cfg", cfg)
    nc = node_config.load(p)
    assert nc.law == "quat_pd"
    assert nc.lines["estimator"] and nc.lines["mekf.gate_chi2"]
    payload = nc.pil_payload(168e6)
    assert len(payload) > 0
    # a value the filter refuses is refused by the parser with the row's rule
    bad = dict(cfg, **{"mekf.gyro_arw_radpsqrts": "0.0"})
    with pytest.raises(node_config.ConfigError, match="mekf.gyro_arw_radpsqrts"):
        node_config.load(fsw_config.write(tmp_path / "bad.cfg", bad))
    with pytest.raises(node_config.ConfigError, match="estimator"):
        node_config.load(fsw_config.write(tmp_path / "bad2.cfg", dict(cfg, estimator="kalman")))


@pytest.mark.parametrize("src, ov, key, words", [
    ("irassi_large", MEKF, "estimator.type", "needs [sensors.star_tracker] and [sensors.gyro]"),
    (ST_GYRO, {**MEKF, "sensors.gyro": None}, "estimator.type", "[sensors.gyro] is missing"),
    (ST_GYRO, {**MEKF, "sensors.star_tracker": None}, "estimator.type", "[sensors.star_tracker] is missing"),
    (ST_GYRO, {**MEKF, "sensors.star_tracker.noise_cross_arcsec": 0.0},
     "sensors.star_tracker.noise_cross_arcsec", "must be > 0 with estimator type \"mekf\""),
    (ST_GYRO, {**MEKF, "sensors.gyro.rrw_rad_s_sqrt_s": 0.0}, "sensors.gyro.rrw_rad_s_sqrt_s", "must be > 0"),
    (ST_GYRO, {"estimator.type": "kalman"}, "estimator.type", "unknown value 'kalman'"),
    (ST_GYRO, {"estimator.gate_chi2": 9.0}, "estimator.gate_chi2", "applies to type = \"mekf\" only"),
    (ST_GYRO, {**MEKF, "estimator.st_sigma_cross_rad": 1e-5}, "estimator.st_sigma_cross_rad",
     "is a sensor figure"),
    (ST_GYRO, {**MEKF, "estimator.gate_chi2": 0.0}, "estimator.gate_chi2", "> 0"),
    (ST_GYRO, {**MEKF, "estimator.max_gap_s": 7200.0}, "estimator.max_gap_s", "above 3600"),
    (ST_GYRO, {**MEKF, "estimator.noise_scale": -1.0}, "estimator.noise_scale", "> 0"),
    (ST_GYRO, {**MEKF, "estimator.bias0_radps": [0.0, float("nan"), 0.0]}, "estimator.bias0_radps[1]", "finite"),
    (ST_GYRO, {**MEKF, "estimator.gain": 1.0}, "estimator.gain", "unknown key"),
    ("landsat8_srp", MEKF, "estimator.type", "attitude scenarios only"),
    (ST_GYRO, {**MEKF, "estimator.init_mode": "guess"}, "estimator.init_mode", "unknown value 'guess'"),
    (ST_GYRO, {**MEKF, "estimator.init_mode": "configured"}, "estimator.init_mode",
     "needs init_q_BN or init_error_deg"),
    (ST_GYRO, {**MEKF, "estimator.init_error_deg": [1.0, 0.0, 0.0]}, "estimator.init_error_deg",
     'applies to init_mode = "configured" only'),
    (ST_GYRO, {**MEKF, "estimator.init_mode": "configured", "estimator.init_q_BN": [0.0, 0.0, 0.0, 1.0],
               "estimator.init_error_deg": [1.0, 0.0, 0.0]}, "estimator.init_error_deg", "not both"),
    (ST_GYRO, {**MEKF, "estimator.init_mode": "configured", "estimator.init_q_BN": [0.0, 0.0, 0.0, 1.1]},
     "estimator.init_q_BN", "is not a unit quaternion"),
    (ST_GYRO, {**MEKF, "estimator.init_mode": "configured", "estimator.init_q_BN": [0.0, float("nan"), 0.0, 1.0]},
     "estimator.init_q_BN[1]", "finite"),
    (ST_GYRO, {**MEKF, "estimator.init_mode": "configured", "estimator.init_error_deg": [200.0, 0.0, 0.0]},
     "estimator.init_error_deg", "below 180 deg"),
])
def test_bad_values_name_the_key(src, ov, key, words):
    with pytest.raises(ScenarioError) as ei:
        load(src, ov)
    msg = str(ei.value)
    assert f": {key}:" in msg and words in msg and "\n" not in msg


def test_a_configured_start_is_the_initial_attitude_turned_by_the_stated_error():
    """init_error_deg = dth0 gives init_q_BN = dq(-dth0) (x) q_BN(0): the knowledge error of the truth against
    it (aocs_analysis.estimation, written independently) is dth0; fsw_node reads the keys back."""
    import numpy as np

    from aocs_analysis import estimation as E
    sc = load(ST_GYRO, {**MEKF, "estimator.init_mode": "configured", "estimator.init_error_deg": [0.3, -0.5, 0.8]})
    e = sc.estimator
    assert e.init_mode == "configured" and e.init_error_deg == (0.3, -0.5, 0.8)
    dth = E.knowledge_error_rad(np.array([sc.attitude.q0]), np.array([e.init_q_BN]))[0]
    assert np.allclose(np.degrees(dth), [0.3, -0.5, 0.8], atol=1e-12)
    cfg = fsw_config.node_config(sc, sc.law.name)
    assert cfg["mekf.init_mode"] == "configured"
    assert [float(x) for x in cfg["mekf.init_q_BN"].split()] == pytest.approx(list(e.init_q_BN), abs=1e-15)
    # the default start writes its mode and no estimate
    cfg0 = fsw_config.node_config(load(ST_GYRO, MEKF), sc.law.name)
    assert cfg0["mekf.init_mode"] == "first_star_tracker" and "mekf.init_q_BN" not in cfg0
