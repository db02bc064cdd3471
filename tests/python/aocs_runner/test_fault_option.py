"""`aocs run --fault KIND@START[-END][:unit=N][:key=value]` (aocs_plant/faults/option.py) and the scenario's
[[faults]] (faults/reader.py): the entries they make, every bad input refused in one line naming the option or
the file, entry and key, the link burst's drops scheduled like --event drops."""
from __future__ import annotations

import subprocess
import sys

import pytest

from aocs_plant import ScenarioError, load
from aocs_plant.faults import FaultOptionError, parse_option
from aocs_runner import events as evmod
from aocs_runner import scenario_opts
from aocs_runner.run import RunOptions, prepare, with_faults


def test_the_option_makes_the_entry():
    assert parse_option("wheel_torque_loss@60:unit=1") == {"kind": "wheel_torque_loss", "start_s": 60.0, "unit": 1}
    assert parse_option("st_bias_step@100-160.5:bias_arcsec=30:axis=[0,0,1]") == {
        "kind": "st_bias_step", "start_s": 100.0, "end_s": 160.5, "bias_arcsec": 30, "axis": [0, 0, 1]}
    assert parse_option("gyro_bias_step@1e1:bias_rad_s=[1e-5,-2e-5,0.0]")["bias_rad_s"] == [1e-5, -2e-5, 0.0]


@pytest.mark.parametrize("spec, message", [
    ("wheel_torque_loss", "expected KIND@START"),
    ("wheel_melts@60", "unknown kind 'wheel_melts'"),
    ("st_frozen@-5", "is not START or START-END"),
    ("st_frozen@5-x", "is not START or START-END"),
    ("st_frozen@5:unit", "'unit': expected key=value"),
    ("st_frozen@5:unit=1:unit=2", "unit given twice"),
    ("st_bias_step@5:bias_arcsec=[1,", "bias_arcsec: '[1,' is not a TOML value"),
])
def test_bad_options_are_named(spec, message):
    with pytest.raises(FaultOptionError, match=message.replace("[", r"\[")) as e:
        parse_option(spec)
    assert str(e.value).startswith(f"--fault {spec!r}") and "\n" not in str(e.value)


def test_the_options_are_appended_to_the_scenarios_faults(tmp_path):
    ov = {"faults": with_faults("irassi_rw_wheel_dies", {}, ["st_frozen@100-110"])}
    sc = load("irassi_rw_wheel_dies", ov)
    assert [(f.kind, f.unit, f.start_s, f.end_s) for f in sc.faults] == [
        ("wheel_torque_loss", 1, 60.0, 1000.0), ("st_frozen", None, 100.0, 110.0)]
    # and through the run's options: run.json's overrides carry them to plant_node and the repeat command
    sc2, ov2, _, _ = prepare(RunOptions("irassi_rw_mekf", out=str(tmp_path), faults=["wheel_stuck@30:unit=2"]))
    assert [(f.kind, f.unit, f.param("stop_time_s")) for f in sc2.faults] == [("wheel_stuck", 2, 1.0)]
    assert scenario_opts.parse_sets(scenario_opts.to_args(ov2)[1::2])["faults"] == ov2["faults"]


@pytest.mark.parametrize("entry, message", [
    ({"kind": "wheel_torque_loss", "start_s": 60.0}, r"faults\[0\].unit: missing required key"),
    ({"kind": "wheel_torque_loss", "unit": 4, "start_s": 60.0}, r"faults\[0\].unit: wheel 4 does not exist"),
    ({"kind": "gyro_stuck_axis", "unit": 3, "start_s": 1.0}, r"faults\[0\].unit: axis 3 does not exist"),
    ({"kind": "st_frozen", "unit": 0, "start_s": 1.0}, r"faults\[0\].unit: st_frozen takes no unit"),
    ({"kind": "st_frozen", "start_s": 1000.0}, r"faults\[0\].start_s: 1000 s is not inside the run"),
    ({"kind": "st_frozen", "start_s": 10.0, "end_s": 10.0}, r"faults\[0\].end_s: must be after start_s"),
    ({"kind": "st_bias_step", "start_s": 1.0}, r"faults\[0\].bias_arcsec: missing required key"),
    ({"kind": "st_noise_increase", "start_s": 1.0, "factor": -2.0}, r"faults\[0\].factor: must be > 0"),
    ({"kind": "gyro_bias_step", "start_s": 1.0, "bias_rad_s": [1.0, 2.0]},
     r"faults\[0\].bias_rad_s: expected an array of 3 numbers"),
    ({"kind": "wheel_stuck", "unit": 0, "start_s": 1.0, "speeed_rad_s": 1.0}, r"faults\[0\].speeed_rad_s: unknown key"),
    ({"kind": "thruster_stuck_open", "unit": 0, "start_s": 1.0}, r"faults\[0\].kind: thruster_stuck_open needs a "
                                                                  r"\[thrusters\] section"),
])
def test_bad_entries_are_named_by_file_entry_and_key(entry, message):
    with pytest.raises(ScenarioError, match=r"irassi_rw_mekf.toml: " + message):
        load("irassi_rw_mekf", {"faults": [entry]})


def test_a_star_tracker_fault_needs_a_star_tracker():
    with pytest.raises(ScenarioError, match=r"faults\[0\].kind: st_frozen needs a \[sensors.star_tracker\]"):
        load("irassi_rw", {"faults": [{"kind": "st_frozen", "start_s": 1.0}]})


def test_the_link_burst_is_dropped_like_drop_events():
    sc = load("irassi_rw", {"faults": [{"kind": "link_drop_burst", "start_s": 20.0, "end_s": 20.3}]})
    evs = evmod.fault_events(sc.faults, sc.dt, sc.n_steps)
    sched = evmod.schedule(evs, sc.dt, sc.n_steps)
    assert sorted(sched) == [200, 201, 202] and all(e.kind == "drop" for v in sched.values() for e in v)
    assert evmod.dropped_ticks(["5:drop"], sc.dt, sc.n_steps, sc.faults) == {50, 200, 201, 202}
    # run.json's form of the faults (aocs replay reads it)
    assert evmod.dropped_ticks([], sc.dt, sc.n_steps, [f.to_json() for f in sc.faults]) == {200, 201, 202}


def test_aocs_run_refuses_a_bad_fault_in_one_line():
    r = subprocess.run([sys.executable, "-c", "import sys; from aocs.cli import main; sys.exit(main())", "run", "irassi_rw_mekf", "--transport", "direct",
                        "--fault", "wheel_torque_loss@60:unit=9", "--out", "/tmp/never-flown-fault"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "faults[0].unit: wheel 9 does not exist" in lines[0], r.stderr
