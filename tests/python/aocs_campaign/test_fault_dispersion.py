"""A campaign's dispersed fault ([campaign.faults], tools/aocs_campaign/fault_dispersion.py): the kinds, start
times and units drawn per run with the stated distributions, a pure function of (seed, index), appended to the
scenario's [[faults]], accepted by the loader, repeatable from the run's command; bad tables named by key."""
from __future__ import annotations

import shlex
from collections import Counter

import numpy as np
import pytest

from aocs_campaign import fault_dispersion as FD
from aocs_campaign import plan as P
from aocs_campaign.dispersions import DispersionError
from aocs_plant.scenario import load
from aocs_runner import scenario_opts

TABLE = {"kinds": ["wheel_torque_loss", "wheel_stuck", "st_bias_step"], "start_s": [40.0, 120.0],
         "duration_s": [10.0, 20.0], "units": [0, 3], "params": {"st_bias_step": {"bias_arcsec": 30.0}}}


def _campaign(runs=400, faults=TABLE, **kw):
    return P.Campaign("irassi_rw_mekf", "quat_pd", runs, 7, faults=faults, **kw)


def test_each_run_gets_one_fault_drawn_from_the_table():
    c = _campaign()
    specs = P.plan(c, P.check(c))
    kinds, starts, units = Counter(), [], []
    for r in specs:
        (f,) = r.overrides["faults"]
        kinds[f["kind"]] += 1
        assert 40.0 <= f["start_s"] <= 120.0 and 10.0 <= f["end_s"] - f["start_s"] <= 20.0
        starts.append(f["start_s"])
        if f["kind"] == "st_bias_step":
            assert "unit" not in f and f["bias_arcsec"] == 30.0
        else:
            units.append(f["unit"])
        assert r.inputs["fault.start_s"] == f["start_s"]
        assert TABLE["kinds"][r.inputs["fault.kind_index"]] == f["kind"]
    # uniform kinds (each 1/3: 400 runs, 5 sigma of a binomial is 47), uniform start (mean 80, sd 23.1)
    assert all(abs(n - 400 / 3) < 47 for n in kinds.values())
    assert abs(np.mean(starts) - 80.0) < 5 * (80.0 / np.sqrt(12.0)) / np.sqrt(400)
    assert set(units) == {0, 1, 2, 3}
    # the loader takes every run's scenario (a sample)
    for r in specs[:5]:
        assert len(load("irassi_rw_mekf", r.overrides).faults) == 1


def test_draws_are_a_function_of_seed_and_index_and_repeat_bit_identical():
    a = P.plan(_campaign(30), P.check(_campaign(30)))
    b = P.plan(_campaign(40), P.check(_campaign(40)))
    assert [r.overrides for r in a] == [r.overrides for r in b[:30]]
    other = P.Campaign("irassi_rw_mekf", "quat_pd", 30, 8, faults=TABLE)
    assert [r.overrides for r in a] != [r.overrides for r in P.plan(other, P.check(other))]
    for r in a:
        words = shlex.split(P.repeat_command(r))
        sets = [words[i + 1] for i, w in enumerate(words) if w == "--set"]
        back = scenario_opts.parse_sets(sets)
        assert repr(back["faults"]) == repr(r.overrides["faults"])


def test_the_scenarios_own_faults_are_kept_and_a_campaign_without_the_table_is_unchanged():
    c = P.Campaign("irassi_rw_wheel_dies", "quat_pd", 3, 1, faults={"kinds": ["st_frozen"], "start_s": [10, 20]})
    for r in P.plan(c, P.check(c)):
        assert [f["kind"] for f in r.overrides["faults"]] == ["wheel_torque_loss", "st_frozen"]
    plain = P.Campaign("irassi_rw_mekf", "quat_pd", 3, 1)
    assert all("faults" not in r.overrides for r in P.plan(plain, P.check(plain)))
    assert "faults" not in plain.identity()


@pytest.mark.parametrize("table, message", [
    ({"start_s": [1, 2]}, r"campaign.faults.kinds: expected a non-empty list"),
    ({"kinds": ["wheel_melts"], "start_s": [1, 2]}, r"campaign.faults.kinds: unknown kind 'wheel_melts'"),
    ({"kinds": ["st_frozen"]}, r"campaign.faults.start_s: missing"),
    ({"kinds": ["st_frozen"], "start_s": [5, 2]}, r"campaign.faults.start_s: expected \[lo, hi\]"),
    ({"kinds": ["st_frozen"], "start_s": [1, 2], "units": [0.5, 2]}, r"campaign.faults.units: expected \[lo, hi\]"),
    ({"kinds": ["st_frozen"], "start_s": [1, 2], "when": 3}, r"campaign.faults.when: unknown key"),
    ({"kinds": ["st_frozen"], "start_s": [1, 2], "params": {"st_outage": {}}}, r"params.st_outage: not one of"),
])
def test_bad_tables_are_named_by_key(table, message):
    with pytest.raises(DispersionError, match=message):
        FD.check(table)


def test_a_unit_the_scenario_does_not_have_is_refused_by_the_loader():
    c = _campaign(faults={"kinds": ["wheel_torque_loss"], "start_s": [1, 2], "units": [4, 4]})
    with pytest.raises(DispersionError, match=r"faults\[0\].unit: wheel 4 does not exist"):
        P.check(c)


def test_the_campaign_file_table(tmp_path):
    f = tmp_path / "mc.toml"
    f.write_text('[campaign]\nscenario = "irassi_rw_mekf"\nruns = 5\nseed = 2\n'
                 '[campaign.faults]\nkinds = ["wheel_torque_loss"]\nstart_s = [40.0, 80.0]\nunits = [0, 3]\n')
    sec = P.read_file_section(str(f))
    assert sec["faults"]["kinds"] == ["wheel_torque_loss"]
    f.write_text('[campaign]\nscenario = "irassi_rw_mekf"\nfaults = 3\n')
    with pytest.raises(P.CampaignError, match="campaign.faults: must be a table"):
        P.read_file_section(str(f))
