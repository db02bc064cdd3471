"""The API's scenario overrides (the same --set texts the command line passes, checked by the same loader), its one
exception type with the command line's line, and `aocs report`'s refusal of a folder it cannot report, without a
run (no processes)."""
from __future__ import annotations

import json

import pytest

import aocs_api as aocs
from aocs import cli
from aocs_api.reports import kind_of
from aocs_api.scenario import sets_of
from aocs_runner import scenario_opts


def test_overrides_become_the_command_line_s_set_texts_and_load_the_same_scenario():
    sc = aocs.scenario("irassi_rw").with_overrides({"actuator.axis_limit": 0.5, "guidance.mode": "slew"},
                                                   duration_s=200.0)
    name, sets = sets_of(sc, ["seed=3"], {"laws.quat_pd.kp": 100.0})
    assert name == "irassi_rw"
    assert sets == ["actuator.axis_limit=0.5", 'guidance.mode="slew"', "duration_s=200.0", "seed=3",
                    "laws.quat_pd.kp=100.0"]
    via_cli = scenario_opts.parse_sets(["actuator.axis_limit=0.5", "guidance.mode=slew", "duration_s=200"])
    assert scenario_opts.parse_sets(sets[:3]) == {**via_cli, "duration_s": 200.0}
    loaded = sc.load()
    assert loaded.duration_s == 200.0 and loaded.actuator.axis_limit == 0.5 and loaded.guidance.mode == "slew"
    assert "quat_pid" in sc.laws


@pytest.mark.parametrize("name,overrides,message", [
    ("no_such_scenario", {}, "no such scenario"),
    ("irassi_rw", {"actuator.axis_limit": -1.0}, "actuator.axis_limit"),
    ("irassi_rw", {"guidance.mode": "warp"}, "guidance"),
])
def test_a_bad_scenario_or_key_is_one_aocs_error(name, overrides, message):
    with pytest.raises(aocs.AocsError) as e:
        aocs.scenario(name, overrides)
    assert message in str(e.value) and "\n" not in str(e.value)
    assert e.value.kind == "error" and e.value.exit_code == 2
    assert e.value.line("run") == f"aocs run: error: {e.value}"


def test_report_names_what_a_folder_lacks(tmp_path, capsys):
    assert cli.main(["report", str(tmp_path / "none"), "--html", str(tmp_path / "x.html")]) == 2
    assert capsys.readouterr().err.strip() == f"aocs report: error: {tmp_path / 'none'}: no such folder"
    (tmp_path / "run.json").write_text(json.dumps({"telemetry": "telemetry.parquet"}))
    (tmp_path / "metrics.json").write_text("{}")
    assert kind_of(tmp_path) == "run"
    assert cli.main(["report", str(tmp_path), "--html", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"aocs report: error: {tmp_path / 'telemetry.parquet'}: missing (a run of this version writes "
                   "it beside run.lcmlog)")
    assert not (tmp_path / "x.html").exists()
    assert cli.main(["report", str(tmp_path), "--html", str(tmp_path)]) == 2
    assert "is a folder, not a file" in capsys.readouterr().err
    (tmp_path / "campaign.json").write_text("{}")
    assert kind_of(tmp_path) == "campaign"
