"""The `aocs run / list / replay` command lines: output, exit codes, messages."""
from __future__ import annotations

import json

import pytest

from aocs import cli
from aocs_plant.scenario import list_scenarios, load
from aocs_wire import lcmlog


def test_list_names_every_scenario_with_its_laws_and_every_law(capsys):
    assert cli.main(["list"]) == 0
    out = capsys.readouterr().out
    for sid in list_scenarios():
        sc = load(sid)
        line = next(ln for ln in out.splitlines() if ln.startswith(sid + " "))
        assert sc.kind in line and sc.control.law in line and f"{sc.duration_s:g} s" in line
        for law in sc.control.laws:
            assert law in line
    assert "lqr_quat[lqr_quat_ref, lqr_quat_strong]" in out
    for law, lid in (("crp_linear", 1), ("orbit_lqr", 10), ("mrp_sat_tanh", 9)):
        assert f"{law}" in out and f"[{lid:2d}]" in out
    assert cli.main(["list", "--ids"]) == 0
    assert capsys.readouterr().out.split() == list_scenarios()


@pytest.mark.parametrize("argv,message", [
    (["run", "no_such_scenario"], "no such scenario file"),
    (["run", "irassi_large", "--law", "hinf"], "has no gains for it"),
    (["run", "irassi_large", "--law", "warp_drive"], "has no gains for it"),
    (["run", "irassi_large", "--event", "5:explode"], "unknown event"),
    (["run", "irassi_large", "--event", "900:drop"], "after the end of the run"),
    (["run", "irassi_large", "--duration", "0.05"], "duration_s"),
    (["run", "irassi_large", "--set", "laws.quat_pd.kd=-1.0"], "laws.quat_pd.kd"),
    (["run", "landsat8_srp", "--set", "control.enabled=false", "--law", "orbit_lqr"], "control is disabled"),
    (["run", "irassi_large", "--law", ""], "--law: empty law name"),
    (["run", "irassi_large", "--duration", "1e-300"], "shorter than one control period"),
    (["run", "irassi_large", "--duration", "nan"], "--duration nan"),
    (["run", "irassi_large", "--reply-timeout", "nan"], "--reply-timeout nan"),
    (["run", "irassi_large", "--reply-timeout", "-1"], "--reply-timeout -1"),
])
def test_bad_input_exits_2_with_a_message_naming_it(private_netns, capsys, tmp_path, argv, message):
    assert cli.main(argv + ["--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "aocs run: error:" in err and message in err, err
    assert not (tmp_path / "o" / "run.lcmlog").exists()


def test_output_paths_are_checked_before_the_run(private_netns, capsys, tmp_path):
    """--out on a file, --json on a folder or in a folder that does not exist: one line, exit 2,
    nothing written (and no folder created for --json)."""
    a_file = tmp_path / "a_file"
    a_file.write_text("keep me\n")
    cases = [(["--out", str(a_file)], "exists and is not a folder"),
             (["--out", str(tmp_path / "o"), "--json", str(tmp_path)], "is a folder, not a file"),
             (["--out", str(tmp_path / "o"), "--json", str(tmp_path / "no" / "such" / "m.json")], "does not exist")]
    for extra, message in cases:
        assert cli.main(["run", "irassi_large", "--duration", "1", "-q", "--no-plots", *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "aocs run: error:" in err and message in err, err
    assert a_file.read_text() == "keep me\n"
    assert not (tmp_path / "no").exists() and not (tmp_path / "o" / "run.lcmlog").exists()


def test_pil_targets_start_the_bridge_or_say_it_is_missing(monkeypatch, tmp_path):
    import importlib.util

    from aocs_core import paths
    from aocs_runner import run as cmd_run

    cfg = tmp_path / "c.cfg"
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: object())
    assert cmd_run.fc_command("pil-m7", cfg)[1:] == ["-m", "aocs_pil.bridge", "--target", "pil-m7", str(cfg)]
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: None)
    with pytest.raises(paths.SetupError, match="aocs_pil.bridge"):
        cmd_run.fc_command("pil-m4f", cfg)
    assert cmd_run.fc_command("host", cfg)[1] == str(cfg)


def test_cli_run_prints_the_table_and_lcm_logger_can_record(private_netns, fsw_node_bin, capsys, tmp_path):
    """A short run through the command line, recorded by lcm-logger this time. lcm-logger drops
    messages when the machine is loaded (docs/sil.md): then the verdict says so, and --allow lets
    this run pass; either way the log is a standard one with both markers."""
    out = tmp_path / "o"
    rc = cli.main(["run", "irassi_small", "--duration", "20", "--out", str(out), "--no-plots", "-q",
                   "--recorder", "lcm-logger", "--json", str(tmp_path / "m.json"), "--allow", "incomplete-log"])
    text = capsys.readouterr().out
    assert rc == 0
    assert "settle time" in text and "verdict" in text
    m = json.loads((tmp_path / "m.json").read_text())
    assert m["scenario"] == "irassi_small"
    if m["log_complete"]:
        assert m["duration_s"] == 20.0 and m["verdict"]["allowed"] == [] and "pointing, last 20 s" in text
    else:
        assert m["verdict"]["allowed"] == ["incomplete-log"]
    log = lcmlog.read(out / "run.lcmlog")
    assert [mk["marker"] for mk in log.markers][:1] == ["start"] and log.markers[-1]["marker"] == "end"
    assert log.truth["tick"].size > 0 and log.cmd["tick"].size > 0
    meta = json.loads((out / "run.json").read_text())
    assert meta["recorder"] == "lcm-logger" and meta["fsw_config"]["law"] == "quat_pd"


def test_replay_refuses_a_missing_log(private_netns, capsys, tmp_path):
    assert cli.main(["replay", str(tmp_path / "nope.lcmlog")]) == 2
    assert "aocs replay: error:" in capsys.readouterr().err


def test_a_scenario_file_anywhere_runs_by_its_path(private_netns, capsys, tmp_path):
    """docs/extending.md, "Adding a scenario": a new file with its own id, outside sil/scenarios/."""
    from aocs_plant.scenario import SCENARIO_DIR

    text = (SCENARIO_DIR / "irassi_small.toml").read_text().replace('id = "irassi_small"', 'id = "my_case"')
    path = tmp_path / "my_case.toml"
    path.write_text(text)
    rc = cli.main(["run", str(path), "--duration", "5", "-q", "--no-plots", "--out", str(tmp_path / "o"),
                   "--json", str(tmp_path / "m.json")])
    assert rc == 0, capsys.readouterr().err
    assert json.loads((tmp_path / "m.json").read_text())["scenario"] == "my_case"
    path.write_text(text.replace("kp = 4000.0", "kq = 4000.0", 1))
    assert cli.main(["run", str(path), "--duration", "5", "-q", "--no-plots", "--out", str(tmp_path / "o2")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(path) in err and "kq" in err, err


def test_a_set_design_weight_flies_a_k_designed_for_it(private_netns, capsys, tmp_path):
    """Issue 10 item 6 through the command line: --set on an LQR weight designs K at run start, the
    flight software flies it (the node config carries lqr_quat.k, the commands change); the
    scenario's own weights fly the compiled table by name."""
    runs = {}
    for name, sets in (("ref", []), ("q2000", ["--set", "laws.lqr_quat.tables.lqr_quat_ref.q=2000"])):
        rc = cli.main(["run", "irassi_small", "--law", "lqr_quat", "--duration", "20", "-q", "--no-plots",
                       "--out", str(tmp_path / name), "--json", str(tmp_path / f"{name}.json"), *sets])
        assert rc == 0, capsys.readouterr().err
        runs[name] = (json.loads((tmp_path / f"{name}.json").read_text()),
                      json.loads((tmp_path / name / "run.json").read_text())["fsw_config"],
                      lcmlog.read(tmp_path / name / "run.lcmlog"))
    text = capsys.readouterr().out
    (m_ref, cfg_ref, log_ref), (m_new, cfg_new, log_new) = runs["ref"], runs["q2000"]
    assert m_ref["gain"]["source"] == "compiled" and cfg_ref["lqr_quat.table"] == "lqr_quat_ref"
    assert "lqr_quat.k" not in cfg_ref
    assert m_new["gain"]["source"] == "designed" and "lqr_quat.table" not in cfg_new
    k = [float(x) for x in cfg_new["lqr_quat.k"].split()]
    assert k[0] == pytest.approx((2000 / 0.001) ** 0.5, rel=1e-12)     # sqrt(Q / R), SPEC 2.5
    assert "K designed at run start" in text and "Q = 2000 I6" in text
    # the first command is -K x of the same first sample: larger by the gain
    u_ref, u_new = log_ref.cmd["u_sat"][0], log_new.cmd["u_sat"][0]
    assert abs(u_new[0]) > 1.5 * abs(u_ref[0])
    # and the result: at 20 s the stiffer loop is nearer the target
    e_ref, e_new = log_ref.truth["pointing_err_arcsec"][-1], log_new.truth["pointing_err_arcsec"][-1]
    assert e_new < 0.8 * e_ref, (e_new, e_ref)


def test_the_plant_as_recorder_logs_the_same_run_as_the_recorder_thread(private_netns, capsys, tmp_path):
    """--recorder plant (aocs campaign's runs): the plant writes the log from its own socket, truth in
    the log only. Same flight (every metric but the machine's timing), the same messages per channel
    but the node's wall-clock heartbeats, both markers, the forged frames of the events, and fsw_node's
    exiting status (sent after the last tick, when the runner stops it) in the log."""
    from aocs_campaign.plan import flight_metrics

    events = ["--event", "5:malformed", "--event", "7:duplicate", "--event", "9:foreign"]
    got = {}
    for rec in ("builtin", "plant"):
        out = tmp_path / rec
        rc = cli.main(["run", "irassi_small", "--duration", "20", "--out", str(out), "--no-plots", "-q",
                       "--recorder", rec, "--json", str(tmp_path / f"{rec}.json"), *events])
        capsys.readouterr()
        assert rc == 0, rec
        m = json.loads((tmp_path / f"{rec}.json").read_text())
        assert m["log_complete"] and m["verdict"]["passed"], (rec, m["verdict"])
        got[rec] = (m, lcmlog.read(out / "run.lcmlog"))
    (ma, la), (mb, lb) = got["builtin"], got["plant"]
    assert flight_metrics(ma) == flight_metrics(mb)
    status = "AOCS_STATUS"
    assert {k: v for k, v in la.counts.items() if k != status} == {k: v for k, v in lb.counts.items() if k != status}
    assert lb.counts["AOCS_SENSORS.undecodable"] == 1 and lb.counts["AOCS_TRUTH"] == la.counts["AOCS_TRUTH"] == 201
    assert [mk["marker"] for mk in lb.markers][0] == "start" and lb.markers[-1]["marker"] == "end"
    assert lb.status["exiting"].tolist()[-1] == 1
    assert json.loads((tmp_path / "plant" / "run.json").read_text())["recorder"] == "plant"
