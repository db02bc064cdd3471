"""`aocs campaign` end to end: a real Dask scheduler and two real worker processes started here
(`dask scheduler` / `dask worker` on loopback, inside this test's private network namespace), each
run the real SIL path (plant_node, fsw_node, LCM) in a namespace of its own.

Short runs (irassi_large cut to 20 s) keep it quick. Checked: every run recorded (Parquet, CSV, JSON,
report), a run made to fail (its dispersed actuator limit is negative, which the loader refuses)
recorded with its error while the others go on, a run made to time out, the repeat command of a run
flying the same run bit for bit (same metrics JSON but for the machine's timing figures), a rerun
into the same folder skipping every finished run, and bad input refused in one line.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from aocs_campaign import dispersions as D
from aocs_campaign import plan as P

SHORT = ["--set", "duration_s=20.0", "--set", "metrics.window_s=10.0"]
SEED = 5
#: the actuator limit dispersed over [-0.2, 1]: the runs whose draw is negative are refused by the loader
LIMIT = "actuator.axis_limit=uniform:-0.2:1.0"
RUNS = 6


def aocs(*args, timeout=600, check_rc=None):
    p = subprocess.run([sys.executable, "-m", "aocs.cli", *args], capture_output=True, text=True, timeout=timeout)
    if check_rc is not None:
        assert p.returncode == check_rc, p.stdout + p.stderr
    return p


@pytest.fixture(scope="module")
def dask_cluster(private_netns, tmp_path_factory):
    """`dask scheduler` and two `dask worker` processes (one thread each) on 127.0.0.1 in the private
    network namespace of this test process (conftest private_netns)."""
    d = tmp_path_factory.mktemp("dask")
    sched_file = d / "scheduler.json"
    bindir = Path(sys.executable).parent
    procs = [subprocess.Popen([str(bindir / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--no-dashboard", "--scheduler-file", str(sched_file)],
                              stdout=open(d / "scheduler.log", "w"), stderr=subprocess.STDOUT)]
    end = time.monotonic() + 60
    while not sched_file.is_file():
        assert time.monotonic() < end, (d / "scheduler.log").read_text()
        assert procs[0].poll() is None, (d / "scheduler.log").read_text()
        time.sleep(0.1)
    address = json.loads(sched_file.read_text())["address"]
    for i in range(2):
        procs.append(subprocess.Popen([str(bindir / "dask"), "worker", address, "--nthreads", "1", "--nworkers", "1",
                                       "--no-dashboard", "--name", f"w{i}"],
                                      stdout=open(d / f"worker{i}.log", "w"), stderr=subprocess.STDOUT))
    from dask.distributed import Client

    with Client(address, timeout="30s") as c:
        c.wait_for_workers(2, timeout=60)
    yield address
    for p in reversed(procs):
        p.terminate()
    for p in procs:
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            p.kill()


def _failing_indices():
    c = P.Campaign("irassi_large", "quat_pd", RUNS, SEED, SHORT[1::2], [LIMIT])
    runs = P.plan(c, D.parse_all(c.disperse))
    return {r.index for r in runs if r.overrides["actuator.axis_limit"] <= 0.0}


@pytest.fixture(scope="module")
def campaign_dir(dask_cluster, tmp_path_factory):
    out = tmp_path_factory.mktemp("campaign") / "mc"
    p = aocs("campaign", "irassi_large", "--law", "quat_pd", "--runs", str(RUNS), "--seed", str(SEED), *SHORT,
             "--disperse", LIMIT, "--disperse", "plant.w0=normal:0:1e-4", "--scheduler", dask_cluster,
             "--out", str(out), "-q")
    return out, p


def test_campaign_on_a_real_scheduler_records_every_run_and_the_failed_one(campaign_dir):
    import pyarrow.parquet as pq

    out, p = campaign_dir
    bad = _failing_indices()
    assert bad and len(bad) < RUNS, "seed must give both kinds of run"
    assert p.returncode == 1, p.stdout + p.stderr        # some run did not pass: not a success
    assert f"{len(bad)} of {RUNS} runs did not pass" in p.stderr
    rows = {r["index"]: r for r in (json.loads(f.read_text()) for f in (out / "runs").glob("*.json"))}
    assert sorted(rows) == list(range(RUNS))
    for i, r in rows.items():
        if i in bad:
            assert r["status"] == "error" and "actuator.axis_limit" in r["error"] and r["metrics"] is None
            assert (out / "runs" / f"{i:06d}" / "error.txt").is_file()       # the failed run's folder is kept
        else:
            assert r["status"] == "passed", r["error"]
            assert r["metrics"]["timing"]["steps"] == 200
            assert not (out / "runs" / f"{i:06d}").exists()                   # no logs kept without --keep-logs
    # every run on a worker of the cluster, in its own namespace: both workers took runs
    assert len({r["worker_pid"] for r in rows.values()}) == 2
    tab = pq.read_table(out / "results.parquet").to_pylist()
    assert [t["index"] for t in tab] == list(range(RUNS))
    good = [t for t in tab if t["index"] not in bad]
    assert all(t["m.pointing_error_arcsec.final_max"] > 0 for t in good)
    assert all(t["in.actuator.axis_limit"] == rows[t["index"]]["inputs"]["actuator.axis_limit"] for t in tab)
    csv = (out / "results.csv").read_text().splitlines()
    assert len(csv) == RUNS + 1 and "m.pointing_error_arcsec.final_max" in csv[0]
    doc = json.loads((out / "campaign.json").read_text())
    assert doc["status"] == {"passed": RUNS - len(bad), "failed": 0, "error": len(bad)}
    assert doc["requirements"]["limits"]["passed"] == RUNS - len(bad) and doc["requirements"]["limits"]["n"] == RUNS
    s = doc["metrics"]["m.pointing_error_arcsec.final_max"]
    vals = sorted(t["m.pointing_error_arcsec.final_max"] for t in good)
    assert s["min"] == vals[0] and s["max"] == vals[-1] and s["n"] == len(good)
    md = (out / "report.md").read_text()
    assert "95 % Wilson" in md or "95 % interval" in md
    for png in doc["plots"]:
        assert (out / png).is_file()


def test_repeat_command_flies_the_same_run_bit_for_bit(campaign_dir, tmp_path):
    out, _ = campaign_dir
    row = next(json.loads(f.read_text()) for f in sorted((out / "runs").glob("*.json"))
               if json.loads(f.read_text())["status"] == "passed")
    words = row["repeat_command"].split(" ")
    assert words[:2] == ["aocs", "run"]
    import shlex

    args = shlex.split(row["repeat_command"])[2:]
    j = args.index("--json")
    args[j + 1] = str(tmp_path / "repeat.json")
    aocs("run", *args, "--out", str(tmp_path / "repeat"), check_rc=0)
    again = json.loads((tmp_path / "repeat.json").read_text())
    assert P.flight_metrics(again) == P.flight_metrics(row["metrics"])
    assert again["pointing_error_arcsec"]["final_max"] == row["metrics"]["pointing_error_arcsec"]["final_max"]


def test_rerun_into_the_same_folder_skips_finished_runs(campaign_dir, dask_cluster):
    out, _ = campaign_dir
    before = {f.name: f.stat().st_mtime_ns for f in (out / "runs").glob("*.json")}
    p = aocs("campaign", "irassi_large", "--law", "quat_pd", "--runs", str(RUNS), "--seed", str(SEED), *SHORT,
             "--disperse", LIMIT, "--disperse", "plant.w0=normal:0:1e-4", "--scheduler", dask_cluster,
             "--out", str(out), "-q")
    assert "nothing to run" in p.stderr
    assert {f.name: f.stat().st_mtime_ns for f in (out / "runs").glob("*.json")} == before
    # two more runs: only those two run
    p = aocs("campaign", "irassi_large", "--law", "quat_pd", "--runs", str(RUNS + 2), "--seed", str(SEED), *SHORT,
             "--disperse", LIMIT, "--disperse", "plant.w0=normal:0:1e-4", "--scheduler", dask_cluster,
             "--out", str(out), "-q")
    assert f"2 runs of {RUNS + 2} ({RUNS} already done)" in p.stderr, p.stderr
    assert {f.name: f.stat().st_mtime_ns for f in (out / "runs").glob("*.json") if f.name in before} == before
    assert len(list((out / "runs").glob("*.json"))) == RUNS + 2
    # another campaign is refused in that folder
    p = aocs("campaign", "irassi_large", "--runs", "2", "--seed", "99", "--out", str(out), "-q")
    assert p.returncode == 2 and "holds another campaign" in p.stderr and "Traceback" not in p.stderr


def test_a_run_that_times_out_is_recorded_and_the_campaign_goes_on(dask_cluster, tmp_path):
    out = tmp_path / "mc"
    # the full 500 s run cannot finish in 0.2 s: each run is killed and recorded
    p = aocs("campaign", "irassi_large", "--runs", "2", "--seed", "1", "--timeout", "0.2",
             "--scheduler", dask_cluster, "--out", str(out), "-q")
    assert p.returncode == 1, p.stderr
    rows = [json.loads(f.read_text()) for f in sorted((out / "runs").glob("*.json"))]
    assert len(rows) == 2 and all(r["status"] == "error" and "timed out after 0.2 s" in r["error"] for r in rows)
    assert all((out / "runs" / f"{r['index']:06d}" / "run.lcmlog").is_file() for r in rows)   # logs kept


@pytest.mark.parametrize("argv,message", [
    (["--runs", "3", "--seed", "1", "--disperse", "plant.w9=normal:0:1"], "plant.w9"),
    (["--runs", "3", "--seed", "1", "--disperse", "plant.w0=normal:0:-1"], "plant.w0=normal:0:-1: sigma"),
    (["--runs", "0", "--seed", "1"], "--runs 0"),
    (["--seed", "1"], "--runs: missing"),
    (["--runs", "3", "--seed", "1", "--disperse", "plant.inertia[2][2]=normal:1e5:1"], "no physical inertia"),
    (["--runs", "3", "--seed", "1", "--law", "nonexistent"], "--law nonexistent: scenario irassi_large has no gains"),
    (["--runs", "3", "--seed", "1", "--disperse", "plant.w0=uniform:-1e308:1e308"], "hi - lo is not finite"),
    (["--runs", "3", "--seed", "1", "--scheduler", "tcp://127.0.0.1:x"], "--scheduler 'tcp://127.0.0.1:x'"),
])
def test_bad_campaign_input_is_one_line_and_exit_2(argv, message):
    p = aocs("campaign", "irassi_large", *argv, "--out", os.devnull + "-never")
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0] and lines[0].startswith("aocs campaign: error:"), p.stderr


def test_the_plant_server_forks_each_run_s_plant_and_outlives_a_killed_one(private_netns, fsw_node_bin,
                                                                           tmp_path, monkeypatch):
    """worker.run_task as a Dask worker thread calls it: the plant is forked by the worker's plant server
    (a single-threaded process, not a fork of the threaded worker) into the run's namespace; a run killed
    by its timeout takes its plant, not the server; a server that died is started again at the next run;
    and a worker that flew runs has no descriptor or thread more than before (the recorder's handles)."""
    import signal
    import threading

    from aocs_campaign import worker as W
    from aocs_wire import netns

    # run_task moves its thread into a namespace of its own and says so in the process's environment (as
    # in a worker, one run at a time): this test's own namespace is restored afterwards
    monkeypatch.setenv(netns.ENV_VAR, os.environ[netns.ENV_VAR])
    spec = {"index": 0, "scenario": "irassi_large", "law": "quat_pd",
            "overrides": {"duration_s": 20.0, "metrics.window_s": 10.0}}
    rows = []

    def fly(k, timeout_s=None, long=False):
        s = dict(spec, overrides={"duration_s": 5000.0} if long else spec["overrides"])
        t = threading.Thread(target=lambda: rows.append(W.run_task(s, str(tmp_path / str(k)), keep_logs=True,
                                                                   timeout_s=timeout_s)))
        t.start()
        t.join(300)
        return rows[-1]

    assert fly(0)["status"] == W.STATUS_PASSED
    server = W.PLANT_SERVER.pid
    fds, tasks = len(os.listdir("/proc/self/fd")), len(os.listdir("/proc/self/task"))
    plant = json.loads((tmp_path / "0" / "plant_node.stdout").read_text().strip().splitlines()[-1])
    assert plant["plant_node"]["reason"] == "done"
    r = fly(1, timeout_s=0.5, long=True)               # 5000 s of flight (~3 s here) do not fit in 0.5 s
    assert r["status"] == W.STATUS_ERROR and "timed out" in r["error"], r["error"]
    assert W.PLANT_SERVER.pid == server and W.PLANT_SERVER._proc.poll() is None
    assert fly(2)["status"] == W.STATUS_PASSED and W.PLANT_SERVER.pid == server
    os.kill(server, signal.SIGKILL)
    W.PLANT_SERVER._proc.wait(10)
    assert fly(3)["status"] == W.STATUS_PASSED and W.PLANT_SERVER.pid != server
    os.kill(W.PLANT_SERVER.pid, signal.SIGKILL)        # again: the next run starts another
    W.PLANT_SERVER._proc.wait(10)
    assert fly(4)["status"] == W.STATUS_PASSED
    try:
        fds_after = len(os.listdir("/proc/self/fd"))
    finally:
        W.PLANT_SERVER._proc.kill()                     # leave no server behind this test
        W.PLANT_SERVER._proc.wait(10)
    assert fds_after <= fds   # fewer: another test's ended in between
    end = time.monotonic() + 10.0     # a cancelled watchdog Timer's thread leaves on its own, soon after
    while len(os.listdir("/proc/self/task")) > tasks and time.monotonic() < end:
        time.sleep(0.05)
    assert len(os.listdir("/proc/self/task")) <= tasks, threading.enumerate()   # fewer: another test's ended


def test_two_runs_at_once_in_one_worker_a_timeout_kills_only_its_own(private_netns, fsw_node_bin, tmp_path,
                                                                     monkeypatch):
    """A worker flies RUNS_PER_WORKER runs at once, each thread in its own network namespace: run A, timed
    out, is killed with its plant and flight computer (the processes in A's namespace), while run B,
    started after A and flying at the same moment, passes (a watchdog that killed the children started
    since A began took B's too)."""
    import threading

    from aocs_campaign import worker as W
    from aocs_wire import netns

    monkeypatch.setenv(netns.ENV_VAR, os.environ[netns.ENV_VAR])
    assert W.RUNS_PER_WORKER >= 2
    rows = {}
    long_run = {"index": 0, "scenario": "irassi_large", "law": "quat_pd", "overrides": {"duration_s": 3000.0}}
    other_run = dict(long_run, index=1)     # ~2.5 s or more of flight: still flying when A is killed
    a = threading.Thread(target=lambda: rows.__setitem__("a", W.run_task(long_run, str(tmp_path / "a"),
                                                                         timeout_s=1.0)))
    b = threading.Thread(target=lambda: rows.__setitem__("b", W.run_task(other_run, str(tmp_path / "b"))))
    try:
        a.start()
        time.sleep(0.3)     # A is flying when B starts, and B still flies when A's time is up
        b.start()
        a.join(120)
        b.join(120)
        assert rows["a"]["status"] == W.STATUS_ERROR and "timed out" in rows["a"]["error"], rows["a"]["error"]
        assert rows["b"]["status"] == W.STATUS_PASSED, rows["b"]["error"]
        assert rows["b"]["metrics"]["timing"]["steps"] == 30000
        assert rows["b"]["wall_s"] > 1.0 - 0.3    # B was flying when A's watchdog fired
    finally:
        if W.PLANT_SERVER._proc is not None:
            W.PLANT_SERVER._proc.kill()
            W.PLANT_SERVER._proc.wait(10)


def _scheduler_tasks(client) -> int:
    return client.run_on_scheduler(lambda dask_scheduler: sum(str(k).startswith("aocs-run-")
                                                              for k in dask_scheduler.tasks))


def _finished_before(client, prefix: str, t_wall: float) -> set:
    """Keys of the runs of one campaign (key prefix) the scheduler saw finish (to memory) before t_wall."""
    def f(dask_scheduler, prefix, t_wall):
        return sorted({str(tr.key) for tr in dask_scheduler.transition_log
                       if str(tr.key).startswith(prefix) and tr.finish == "memory" and tr.timestamp < t_wall})
    return set(client.run_on_scheduler(f, prefix=prefix, t_wall=t_wall))


def test_a_million_runs_are_submitted_a_few_at_a_time_and_ctrl_c_keeps_every_finished_run(dask_cluster, tmp_path):
    """Bounded submission (issue 25, item 8): `--runs 1000000` on the two-worker cluster keeps at most
    in_flight_bound = 2 x 2 threads runs on the scheduler, writes rows as runs complete, and a Ctrl-C keeps
    every run the scheduler had finished before it; the folder resumes with those rows."""
    import signal

    from dask.distributed import Client

    from aocs_campaign import execute as E

    out = tmp_path / "mc"
    cmd = [sys.executable, "-m", "aocs.cli", "campaign", "irassi_large", "--law", "quat_pd", "--runs", "1000000",
           "--seed", "3", "--set", "duration_s=1.0", "--set", "metrics.window_s=0.5",
           "--disperse", "plant.w0=normal:0:1e-5", "--scheduler", dask_cluster, "--out", str(out), "-q", "--no-plots"]
    bound = E.IN_FLIGHT_PER_THREAD * 2
    with Client(dask_cluster, timeout="30s") as watch:
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        most = 0
        t_first = None
        t0 = time.monotonic()
        try:
            while True:
                most = max(most, _scheduler_tasks(watch))
                rows = len(list((out / "runs").glob("*.json"))) if (out / "runs").is_dir() else 0
                if rows and t_first is None:
                    t_first = time.monotonic() - t0
                if rows >= 4:
                    break
                assert proc.poll() is None, proc.communicate()[1]
                assert time.monotonic() - t0 < 180, f"{rows} rows after 180 s; {most} tasks on the scheduler"
                time.sleep(0.1)
            t_int = time.time()
            proc.send_signal(signal.SIGINT)
            _, err = proc.communicate(timeout=180)          # bounded: it stops by itself (a loaded machine)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        print(f"first row after {t_first:.1f} s of a 1,000,000-run campaign; at most {most} runs on the scheduler")
        assert proc.returncode == 130, err
        assert f"at most {bound} in flight" in err, err
        assert 1 <= most <= bound, most            # the old client submitted all 1,000,000 at once
        c = P.Campaign("irassi_large", "quat_pd", 1000000, 3, ["duration_s=1.0", "metrics.window_s=0.5"],
                       ["plant.w0=normal:0:1e-5"])
        done = _finished_before(watch, f"aocs-run-{c.fingerprint()}-", t_int)   # this campaign's runs only
    rows = {int(f.stem) for f in (out / "runs").glob("*.json")}
    indices = {int(k.rsplit("-", 1)[1]) for k in done}
    assert len(indices) >= 4, done          # the 4 rows seen before the Ctrl-C at least
    assert indices <= rows, sorted(indices - rows)  # no run finished before the Ctrl-C is lost
    kept = int(err.split("interrupted; ")[1].split()[0])
    assert kept == len(rows) and "Traceback" not in err
    assert all(E.load_row(out, i) is not None for i in rows)


def test_a_timeout_that_fires_before_the_run_has_processes_never_passes(private_netns, fsw_node_bin, tmp_path,
                                                                         monkeypatch):
    """--timeout 1e-9 (issue 25, item 9): the watchdog fires before the run has started a process, so it
    kills nothing; the run that then flies to its end is still one that exceeded its time: an error."""
    import threading

    from aocs_campaign import worker as W
    from aocs_wire import netns

    monkeypatch.setenv(netns.ENV_VAR, os.environ[netns.ENV_VAR])
    spec = {"index": 0, "scenario": "irassi_large", "law": "quat_pd",
            "overrides": {"duration_s": 1.0, "metrics.window_s": 0.5}}
    rows = []
    t = threading.Thread(target=lambda: rows.append(W.run_task(spec, str(tmp_path / "r"), timeout_s=1e-9,
                                                               fork=False)))
    t.start()
    t.join(120)
    assert rows and rows[0]["status"] == W.STATUS_ERROR, rows
    assert "timed out after 1e-09 s" in rows[0]["error"], rows[0]["error"]


def test_a_direct_campaign_re_flies_its_sample_over_lcm_bit_for_bit(private_netns, fsw_node_bin, tmp_path):
    """--transport direct: runs 0, 4 and 8 of 9 (--refly-every 4) flown again over LCM, all identical, in tasks of
    4 runs (1 worker of one thread, RUNS_PER_WORKER_DIRECT: 2 tasks in flight, runs_per_task); the rows and
    campaign.json name the transport; the repeat command flies the run in process."""
    out = tmp_path / "c"
    p = aocs("campaign", "irassi_large", "--law", "quat_pd", "--runs", "9", "--seed", str(SEED), *SHORT,
             "--disperse", "plant.w0=normal:0:1e-4", "--transport", "direct", "--refly-every", "4", "--workers", "1",
             "--out", str(out), "--no-plots", "-q", check_rc=0)
    assert "at most 2 in flight (4 runs per task)" in p.stderr, p.stderr
    doc = json.loads((out / "campaign.json").read_text())
    assert doc["transport"] == "direct" and doc["status"]["passed"] == 9
    assert doc["refly"] == {"sampled": 3, "identical": 3, "differ": []}
    assert "3 of 3 LCM re-flights bit-identical" in p.stdout
    rows = [json.loads((out / "runs" / f"{i:06d}.json").read_text()) for i in range(9)]
    assert [r["index"] for r in rows] == list(range(9))
    assert [bool(r.get("refly")) for r in rows] == [i % 4 == 0 for i in range(9)]
    assert all(r["transport"] == "direct" and "--transport direct" in r["repeat_command"] for r in rows)


def test_a_re_flight_that_differs_makes_the_run_an_error(private_netns, fsw_node_bin, tmp_path, monkeypatch):
    """The LCM re-flight given another initial body rate (a real other flight, injected into the worker's
    execute): the row is an error naming the fields that differ."""
    import dataclasses

    from aocs_campaign import worker as W
    from aocs_wire import netns

    monkeypatch.setenv(netns.ENV_VAR, os.environ[netns.ENV_VAR])
    real = W.execute

    def other_rate_over_lcm(opts):
        if opts.transport == "lcm":
            opts = dataclasses.replace(opts, sets=[*opts.sets, "plant.w0=[1e-4, 0.0, 0.0]"])
        return real(opts)

    monkeypatch.setattr(W, "execute", other_rate_over_lcm)
    spec = {"index": 0, "scenario": "irassi_large", "law": "quat_pd",
            "overrides": {"duration_s": 20.0, "metrics.window_s": 10.0}}
    # in a thread of its own, as a worker flies it: run_task moves its thread into a fresh namespace, which
    # must not be this test process's main thread (every later child of the process would be in the wrong one)
    box = {}
    t = threading.Thread(target=lambda: box.update(row=W.run_task(spec, str(tmp_path / "r"), fork=False,
                                                                  transport="direct", refly=True)))
    t.start()
    t.join()
    row = box["row"]
    assert row["status"] == W.STATUS_ERROR and not row["refly"]["identical"]
    assert row["error"].startswith("the LCM re-flight differs from the direct run: ")
    assert "actuator_cmd_t.u_sat" in row["error"] and "sensors_t.q" in row["error"]


def test_a_direct_run_stays_in_its_thread_s_namespace_and_an_lcm_run_gets_its_own(private_netns, fsw_node_bin,
                                                                                   tmp_path, monkeypatch):
    """In process no socket is opened: a direct run whose plant the plant server starts makes no namespace (its cost
    per run saved); an LCM run (and a direct one with its LCM re-flight, or without the server) still moves its
    thread into a fresh one."""
    from aocs_campaign import worker as W
    from aocs_wire import netns

    monkeypatch.setenv(netns.ENV_VAR, os.environ[netns.ENV_VAR])
    spec = {"index": 0, "scenario": "irassi_large", "law": "quat_pd",
            "overrides": {"duration_s": 20.0, "metrics.window_s": 10.0}}
    seen = {}

    def fly(name, **kw):
        def body():
            before = netns.current_netns_id()
            seen[name] = (before, W.run_task(spec, str(tmp_path / name), **kw), netns.current_netns_id())
        t = threading.Thread(target=body)
        t.start()
        t.join(300)
        return seen[name]

    try:
        before, row, after = fly("direct", transport="direct")
        assert row["status"] == W.STATUS_PASSED and after == before
        before, row, after = fly("direct-no-server", transport="direct", fork=False)
        assert row["status"] == W.STATUS_PASSED and after != before
        before, row, after = fly("lcm")
        assert row["status"] == W.STATUS_PASSED and after != before
        before, row, after = fly("refly", transport="direct", refly=True)
        assert row["status"] == W.STATUS_PASSED and row["refly"]["identical"] and after != before
    finally:
        _stop_plant_server(W)


def _stop_plant_server(W, runner=None) -> None:
    """The worker's plant server (or, given runner, the calling thread's plant runner) killed: no process left."""
    server = W.PLANT_SERVER if runner is None else W.plant_runner()
    if server._proc is not None:
        server._proc.kill()
        server._proc.wait(10)


def test_a_direct_run_is_flown_by_its_thread_s_plant_runner_and_a_timeout_kills_that_alone(private_netns, fsw_node_bin,
                                                                                          tmp_path, monkeypatch):
    """--transport direct: the worker thread's plant runner (a plant server that flies the runs itself, no fork per
    run) flies one run after another, each run's plant_node output its own. A direct run has no namespace of its own:
    its timeout (before its plant started; while it flies 50,000 s) kills that runner, never the worker's plant server
    nor anything else of the worker's namespace; the next direct run starts a new runner and passes."""
    from concurrent.futures import ThreadPoolExecutor

    from aocs_campaign import worker as W
    from aocs_wire import netns

    monkeypatch.setenv(netns.ENV_VAR, os.environ[netns.ENV_VAR])
    spec = {"index": 0, "scenario": "irassi_large", "law": "quat_pd",
            "overrides": {"duration_s": 20.0, "metrics.window_s": 10.0}}
    n = iter(range(100))
    with ThreadPoolExecutor(1) as pool:      # one thread, as a Dask worker's
        def fly(s=spec, **kw):
            return pool.submit(W.run_task, s, str(tmp_path / str(next(n))), keep_logs=True, **kw).result(300)

        try:
            assert fly()["status"] == W.STATUS_PASSED            # over LCM: the plant server forks its plant
            server = W.PLANT_SERVER.pid
            first = fly(transport="direct")
            runner = pool.submit(W.plant_runner).result()
            pid = runner.pid
            second = fly(transport="direct")
            assert first["status"] == second["status"] == W.STATUS_PASSED
            assert runner.pid == pid and pid not in (None, server)     # the same process flew both
            for r in (first, second):    # one summary each, flown by the same runner process
                lines = [json.loads(x) for x in (Path(r["run_dir"]) / "plant_node.stdout").read_text().splitlines()
                         if x.startswith('{"plant_node"')]
                assert len(lines) == 1 and lines[0]["plant_node"]["reason"] == "done"
            assert runner._proc.poll() is None
            for timeout_s in (1e-9, 0.3):    # before the plant is started; while it flies 50,000 s (~1 s or more)
                r = fly(dict(spec, overrides={"duration_s": 50000.0}), timeout_s=timeout_s, transport="direct")
                assert r["status"] == W.STATUS_ERROR and "timed out" in r["error"], r["error"]
                assert W.PLANT_SERVER.pid == server and W.PLANT_SERVER._proc.poll() is None
            assert runner._proc.poll() == -9
            assert fly(transport="direct")["status"] == W.STATUS_PASSED and runner._proc.poll() is None
        finally:
            _stop_plant_server(W)
            pool.submit(_stop_plant_server, W, "runner").result()
