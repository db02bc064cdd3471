"""Dispersions (aocs_campaign.dispersions) and the campaign plan (aocs_campaign.plan): parsing, the
errors that name the key, values a pure function of (seed, index, key), physical inertias, rotations,
and the repeat command reading back the same values bit for bit (through aocs_runner.scenario_opts,
the parser `aocs run --set` uses)."""
from __future__ import annotations

import math
import shlex

import numpy as np
import pytest

from aocs_campaign import dispersions as D
from aocs_campaign import plan as P
from aocs_core.conventions import euler321_deg_to_quat, quat_mul
from aocs_plant.scenario import load
from aocs_runner import scenario_opts


def campaign(disperse, sets=("actuator.axis_limit=0.5",), runs=50, seed=11):
    return P.Campaign("irassi_large", "quat_pd", runs, seed, list(sets), list(disperse))


@pytest.mark.parametrize("spec,message", [
    ("plant.w0", "expected KEY=DIST"),
    ("plant.w0=gauss:0:1", "unknown distribution 'gauss'"),
    ("plant.w0=normal:0", "expected normal:MEAN:SIGMA"),
    ("plant.w0=normal:0:-1", "sigma -1.0 is negative"),
    ("plant.w0=normal:0:abc", "sigma 'abc' is not a number"),
    ("plant.w0=normal:0:inf", "is not finite"),
    ("plant.w0=uniform:2:1", "lo 2.0 is above hi 1.0"),
    ("plant.w0[1]=rotation:1", "not to one element"),
    ("plant..w0=normal:0:1", "is not a scenario key"),
    ("plant.w0=uniform:-1e308:1e308", "hi - lo is not finite"),              # issue 25, item 9
    ("plant.w0=normal:0:1e308", "draws beyond 10 sigma are not finite"),
    ("plant.w0=normal:-1.7e308:1e307", "draws beyond 10 sigma are not finite"),
    ("seed=integer:0:1.5", "hi '1.5' is not an integer"),
    ("seed=integer:9:3", "lo 9 is above hi 3"),
    ("seed=integer:0", "expected integer:LO:HI"),
    ("seed=integer:0:99999999999999999999", "beyond a 64-bit integer"),
])
def test_malformed_dispersions_name_the_key(spec, message):
    with pytest.raises(D.DispersionError) as exc:
        D.parse(spec)
    assert message in str(exc.value) and spec.split("=")[0] in str(exc.value)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize("disperse,message", [
    (["plant.w9=normal:0:1"], "plant.w9"),                                 # the loader names the unknown key
    (["plant.w0[3]=normal:0:1"], "plant.w0[3] does not exist"),
    (["plant.inertia[0]=normal:0:1"], "plant.inertia[i][j]"),
    (["plant.w0=normal:0:1", "plant.w0[1]=normal:0:1"], "also dispersed as a whole"),
    (["description=normal:0:1"], "not a number"),
    (["plant.w0=rotation:1", "control.law=uniform:0:1"], "control.law"),
    (["actuator.axis_limit=normal:0.5:0.1"], "also given with --set"),
    (["plant.inertia[0][0]=normal:1e6:1"], "no physical inertia"),       # J1 > J2 + J3 at every draw
    (["laws.quat_pd.kp=normal:-5000:1"], "laws.quat_pd.kp"),             # run 0's value refused by the loader
])
def test_dispersions_the_scenario_cannot_take_are_refused_before_anything_runs(disperse, message):
    with pytest.raises(D.DispersionError) as exc:
        P.check(campaign(disperse))
    assert message in str(exc.value)


def test_values_are_a_function_of_seed_index_and_key_alone():
    c = campaign(["plant.w0=normal:0:1e-4", "disturbances.constant_torque.scale=uniform:0.5:1.5"])
    d = P.check(c)
    a = P.plan(c, d)
    b = P.plan(c, d, indices=[7, 3])
    assert b[0].overrides == a[7].overrides and b[1].overrides == a[3].overrides
    assert a[0].overrides != a[1].overrides
    # a dispersion added does not move the others' values
    c2 = campaign(c.disperse + ["plant.euler321_deg=rotation:1"])
    a2 = P.plan(c2, P.check(c2))
    assert all(x.overrides["plant.w0"] == y.overrides["plant.w0"] for x, y in zip(a, a2))
    # another seed does
    c3 = P.Campaign(c.scenario, c.law, c.runs, 12, c.sets, c.disperse)
    assert P.plan(c3, P.check(c3))[0].overrides["plant.w0"] != a[0].overrides["plant.w0"]


def test_draws_follow_the_distribution():
    c = campaign(["plant.w0[1]=normal:0.001:0.0002", "disturbances.constant_torque.scale=uniform:0.5:1.5"],
                 runs=4000)
    runs = P.plan(c, P.check(c))
    w = np.array([r.inputs["plant.w0[1]"] for r in runs])
    s = np.array([r.inputs["disturbances.constant_torque.scale"] for r in runs])
    # 4000 draws: the mean within 4 standard errors, the spread within 5 %
    assert abs(w.mean() - 0.001) < 4 * 0.0002 / math.sqrt(w.size)
    assert abs(w.std() / 0.0002 - 1.0) < 0.05
    assert s.min() >= 0.5 and s.max() <= 1.5 and abs(s.mean() - 1.0) < 4 * (1 / math.sqrt(12)) / math.sqrt(s.size)
    assert all(r.overrides["plant.w0"][0] == 0.0 and r.overrides["plant.w0"][2] == 0.0 for r in runs[:10])


def test_an_integer_dispersion_gives_each_run_its_own_noise_seed():
    c = campaign(["seed=integer:0:9"], runs=2000)
    runs = P.plan(c, P.check(c))
    seeds = [r.overrides["seed"] for r in runs]
    # integers, both ends reached, every value about equally often (2000 draws of 10: 200 +- 4 sigma)
    assert all(type(x) is int for x in seeds) and min(seeds) == 0 and max(seeds) == 9
    counts = np.bincount(seeds, minlength=10)
    assert np.all(np.abs(counts - 200) < 4 * math.sqrt(2000 * 0.1 * 0.9))
    # the loader takes the drawn seed, and the repeat command gives it back as an integer
    assert load("irassi_large", {"seed": seeds[3]}).seed == seeds[3]
    words = shlex.split(P.repeat_command(runs[3]))
    assert f"seed={seeds[3]}" in words and scenario_opts.parse_sets([f"seed={seeds[3]}"]) == {"seed": seeds[3]}


@pytest.mark.parametrize("J,ok", [
    ([[1.0, 0, 0], [0, 2.0, 0], [0, 0, 2.5]], True),
    ([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 3.0]], False),     # 3 is not below 1 + 1
    ([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 2.0]], False),     # equal: a flat body, not below
    ([[2.0, 0.1, 0], [0.2, 2.0, 0], [0, 0, 2.0]], False),  # not symmetric
    ([[1.0, 2.0, 0], [2.0, 1.0, 0], [0, 0, 1.0]], False),  # eigenvalue -1
])
def test_inertia_validity(J, ok):
    assert (D.inertia_problem(J) is None) == ok


def test_dispersed_inertias_are_symmetric_positive_definite_and_physical():
    # wide dispersions: many raw draws violate the triangle rule and are resampled
    c = campaign(["plant.inertia[0][0]=normal:2059.5:2500", "plant.inertia[0][1]=normal:0:800",
                  "plant.inertia[1][2]=normal:0:800", "plant.inertia[2][2]=normal:5974.3:1500"], runs=300)
    runs = P.plan(c, P.check(c))
    for r in runs:
        J = np.array(r.overrides["plant.inertia"])
        assert np.array_equal(J, J.T)
        eig = np.linalg.eigvalsh(J)
        assert eig[0] > 0 and all(e < eig.sum() - e for e in eig)
        assert J[0][1] == r.inputs["plant.inertia[0][1]"] and J[1][1] == 5954.2
    # and the loader agrees
    for r in runs[:20]:
        load("irassi_large", r.overrides)


def test_rotation_keeps_the_attitude_representation_and_the_angle_is_dispersed():
    c = campaign(["plant.euler321_deg=rotation:2.0", "disturbances.constant_torque.torque_nm=rotation:10"],
                 runs=2000)
    runs = P.plan(c, P.check(c))
    q0 = euler321_deg_to_quat([14.0, 14.0, 14.0])
    ang = []
    for r in runs:
        q = euler321_deg_to_quat(r.overrides["plant.euler321_deg"])
        dq = quat_mul(q, (-q0[0], -q0[1], -q0[2], q0[3]))
        ang.append(math.degrees(2 * math.asin(min(1.0, math.sqrt(dq[0] ** 2 + dq[1] ** 2 + dq[2] ** 2)))))
        t = r.overrides["disturbances.constant_torque.torque_nm"]
        assert math.isclose(math.hypot(*t), math.hypot(1.18e-3, 1.18e-3, 1.18e-3), rel_tol=1e-12)
    # |N(0, 2 deg)|: mean 2 sqrt(2/pi) deg
    assert abs(np.mean(ang) - 2.0 * math.sqrt(2 / math.pi)) < 4 * 2.0 * math.sqrt(1 - 2 / math.pi) / math.sqrt(2000)


def test_repeat_command_reads_back_bit_identical():
    c = campaign(["plant.w0=normal:0:1e-4", "plant.euler321_deg=rotation:2", "plant.inertia[0][1]=normal:0:5",
                  "disturbances.constant_torque.scale=uniform:0.5:1.5"], runs=20)
    for r in P.plan(c, P.check(c)):
        words = shlex.split(P.repeat_command(r))
        assert words[:5] == ["aocs", "run", "irassi_large", "--law", "quat_pd"]
        sets = [words[i + 1] for i, w in enumerate(words) if w == "--set"]
        back = scenario_opts.parse_sets(sets)
        assert back == r.overrides
        for k, v in r.overrides.items():   # the same floats, not just equal-looking ones
            assert repr(back[k]) == repr(v)


def test_campaign_file_section(tmp_path):
    f = tmp_path / "mc.toml"
    f.write_text('[campaign]\nscenario = "irassi_large"\nruns = 5\nseed = 2\nset = ["actuator.axis_limit=0.5"]\n'
                 'disperse = ["plant.w0=normal:0:1e-4"]\n')
    sec = P.read_file_section(str(f))
    assert sec["runs"] == 5 and sec["disperse"] == ["plant.w0=normal:0:1e-4"]
    f.write_text('[campaign]\nscenario = "irassi_large"\nrunz = 5\n')
    with pytest.raises(P.CampaignError, match="campaign.runz: unknown key"):
        P.read_file_section(str(f))
    # a scenario file may carry its own [campaign] table: the loader accepts it, the campaign flies that file
    sc = (tmp_path / "irassi_large.toml")
    sc.write_text(load("irassi_large").path and open(load("irassi_large").path).read()
                  + '\n[campaign]\nruns = 3\nseed = 1\ndisperse = ["plant.w0=normal:0:1e-4"]\n')
    sec = P.read_file_section(str(sc))
    assert sec["scenario"] == str(sc) and sec["runs"] == 3
    load(str(sc))
