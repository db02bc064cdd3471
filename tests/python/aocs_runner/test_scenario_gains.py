"""Gains designed for the scenario (aocs_runner.scenario_gains, issue 10 item 6): a set weight
changes K, the compiled table's own design flies the compiled table, a compiled table on another
plant warns. The designs are the real Riccati solver; the expected K are the closed form."""
from __future__ import annotations

import math

import numpy as np
import pytest

from aocs_flightcfg import fsw_config
from aocs_plant.scenario import ScenarioError, load
from aocs_runner import scenario_gains

J_IRASSI = (2059.5, 5954.2, 5974.3)
REF = "laws.lqr_quat.tables.lqr_quat_ref"


def _closed_form(j, q, r):
    # decoupled per axis (SPEC 2.5, diagonal J): K = [sqrt(q/r), sqrt((J sqrt(q r) + q) / r)]
    k = np.zeros((3, 6))
    for i, ji in enumerate(j):
        k[i, i] = math.sqrt(q / r)
        k[i, i + 3] = math.sqrt((ji * math.sqrt(q * r) + q) / r)
    return k


def _node_cfg(sc, law):
    g = scenario_gains.resolve(sc)
    return g, fsw_config.node_config(sc, law, gains={n: c.k for n, c in g.items() if c.k is not None})


def test_the_compiled_design_flies_the_compiled_table():
    sc = load("irassi_small")
    g, cfg = _node_cfg(sc, "lqr_quat")
    assert g["lqr_quat"].source == "compiled" and g["lqr_quat"].k is None and not g["lqr_quat"].warnings
    # bit-identical to the configuration without the design step: the same keys, the table by name
    assert cfg == fsw_config.node_config(sc, "lqr_quat")
    assert cfg["lqr_quat.table"] == "lqr_quat_ref" and "lqr_quat.k" not in cfg
    for sid, law in (("geo_hinf", "hinf"), ("landsat8_q10", "orbit_lqr")):
        sc = load(sid)
        g, cfg = _node_cfg(sc, law)
        assert g[law].source == "compiled" and not g[law].warnings, sid
        assert cfg == fsw_config.node_config(sc, law)


def test_a_set_weight_changes_k():
    sc = load("irassi_small", {f"{REF}.q": 2000.0})
    g, cfg = _node_cfg(sc, "lqr_quat")
    c = g["lqr_quat"]
    assert c.source == "designed"
    np.testing.assert_allclose(c.k, _closed_form(J_IRASSI, 2000.0, 1e-3), rtol=1e-12, atol=1e-9)
    # flown by value (row-major), not by table name
    assert "lqr_quat.table" not in cfg
    np.testing.assert_array_equal(np.array([float(x) for x in cfg["lqr_quat.k"].split()]).reshape(3, 6), c.k)
    compiled = _closed_form(J_IRASSI, 200.0, 1e-3)   # lqr_quat_ref (tests/python/aocs_design pins it)
    assert np.max(np.abs(c.k - compiled)) > 100.0
    assert "Q = 2000 I6, R = 0.001 I3" in c.summary() and "lqr_quat_ref" in c.summary()


def test_a_diagonal_weight_and_a_scenario_mass():
    sc = load("irassi_small", {f"{REF}.r": [0.001, 0.002, 0.004]})
    c = scenario_gains.resolve(sc)["lqr_quat"]
    assert c.source == "designed"
    for i, (ji, ri) in enumerate(zip(J_IRASSI, (0.001, 0.002, 0.004))):
        np.testing.assert_allclose(c.k[i], _closed_form(J_IRASSI, 200.0, ri)[i], rtol=1e-12, atol=1e-9)
    sc = load("landsat8_q10", {"plant.mass_kg": 2000.0})
    c = scenario_gains.resolve(sc)["orbit_lqr"]
    assert c.source == "designed" and "m = 2000 kg" in c.summary() and "m = 2623 kg" in c.summary()
    import control  # deferred: the independent LQR solver, only this check uses it

    from aocs_design import models

    a, b = models.orbit_model(2000.0, sc.orbit.orbit_radius_m, sc.orbit.mu)
    k, _, _ = control.lqr(a, b, 10.0 * np.eye(6), np.eye(3))
    np.testing.assert_allclose(c.k, k, rtol=1e-9, atol=1e-9 * np.max(np.abs(k)))


def test_the_scenario_inertia_is_designed_for():
    j = [[2500.0, 0.0, 0.0], [0.0, 5954.2, 0.0], [0.0, 0.0, 5974.3]]
    c = scenario_gains.resolve(load("irassi_small", {"plant.inertia": j}))["lqr_quat"]
    assert c.source == "designed" and not c.warnings
    np.testing.assert_allclose(c.k, _closed_form((2500.0, 5954.2, 5974.3), 200.0, 1e-3), rtol=1e-12, atol=1e-9)


def test_a_compiled_table_on_another_inertia_warns_naming_both(tmp_path):
    text = open(load("irassi_small").path).read()
    # no design weights under the table: the compiled table flies as it is
    text = text.replace("q = 200.0      # Q = 200 I6\nr = 0.001      # R = 0.001 I3\n", "")
    path = tmp_path / "irassi_small.toml"
    path.write_text(text)
    same = scenario_gains.resolve(load(str(path)))["lqr_quat"]
    assert same.source == "compiled" and not same.warnings
    j = [[2500.0, 0.0, 0.0], [0.0, 5954.2, 0.0], [0.0, 0.0, 5974.3]]
    c = scenario_gains.resolve(load(str(path), {"plant.inertia": j}))["lqr_quat"]
    assert c.source == "compiled" and c.k is None
    (w,) = c.warnings
    assert "lqr_quat_ref" in w and "J = diag(2059.5, 5954.2, 5974.3) kg m^2" in w
    assert "J = diag(2500, 5954.2, 5974.3) kg m^2" in w
    # a hinf table on another inertia: the same warning
    h = scenario_gains.resolve(load("geo_hinf", {"plant.inertia": [[1100.0, 0, 0], [0, 3015.65, 0],
                                                                    [0, 0, 3030.43]]}))["hinf"]
    assert h.source == "compiled" and "diag(1030.17, 3015.65, 3030.43)" in h.warnings[0]
    assert "diag(1100, 3015.65, 3030.43)" in h.warnings[0]


def test_one_weight_without_the_other_is_refused(tmp_path):
    text = open(load("irassi_small").path).read().replace("r = 0.001      # R = 0.001 I3\n", "", 1)
    path = tmp_path / "irassi_small.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError, match=r"lqr_quat_ref\.r.*both design weights q and r"):
        load(str(path))
