"""One campaign run on a Dask worker: the real SIL path (aocs_runner.run.execute: plant_node,
fsw_node; the plant records the bus), an LCM run in a private network namespace of its own.

`run_tasks` (a few `run_task` one after another) is what the client submits. It runs in a worker thread (a
worker flies RUNS_PER_WORKER at once). For an LCM run the thread moves into a fresh network namespace
(aocs_wire.netns.enter_netns with fresh=True; Linux namespaces are per thread, and the run's flight computer
inherits it; the plant is forked by the worker's plant server, plant_server.py, into it); a --transport direct run
opens no socket and is flown by the thread's plant runner (plant_runner), in no namespace of its own. Each run
returns one row: status, error text, the run's metrics JSON and its pointing error decimated for the campaign's
overlay plot. It never raises for a run that went wrong: a crash, a refused value or a timeout is a row with status
"error" and the text that `aocs run` would have printed.

A worker needs CAP_SYS_ADMIN in its user namespace to make the namespaces:
root, or a worker started under `unshare --user --map-root-user`
(docs/campaigns.md); `netns_check` says which, or why neither.
"""
from __future__ import annotations

import dataclasses
import functools
import os
import shutil
import signal
import threading
import time
import traceback
from pathlib import Path

import numpy as np

from aocs_core import libc, paths
from aocs_flightcfg import fsw_config
from aocs_plant.scenario import ScenarioError
from aocs_runner import events as evmod
from aocs_runner import orchestrate, scenario_opts
from aocs_runner.run import RunFailed, RunOptions, execute
from aocs_wire import netns

from .plant_server import PlantServer

#: points per run kept of the pointing error history (overlay plot)
SERIES_POINTS = 500
#: files of a run folder kept for a run that passed when --keep-logs is not given: none (the row has
#: every metric); a run that failed or errored keeps its whole folder (log, config, node output)
STATUS_PASSED, STATUS_FAILED, STATUS_ERROR = "passed", "failed", "error"
STATUSES = (STATUS_PASSED, STATUS_FAILED, STATUS_ERROR)
#: lockstep wait for each command, s: `aocs run`'s 2 s is too short on a machine loaded by a campaign's
#: parallel runs (the flight is the same: a wait bounds the run, it does not enter it)
REPLY_TIMEOUT_S = 10.0
#: runs a local worker process flies at once (threads, each run in its own network namespace): a lockstep
#: run is a ping-pong of plant and flight computer, each waiting on the other, ~0.8 of a core for one run;
#: two per core keep the cores busy
RUNS_PER_WORKER = 2
#: the same for --transport direct: a direct run's plant is its thread's plant runner, a process of its own, so one
#: thread per worker keeps a worker and its runner on the cores (`aocs campaign ... --transport direct`, 200 runs,
#: alternated with 2 threads per worker: 2172 against 1969 runs/min; 3 threads: 1784 against 2094)
RUNS_PER_WORKER_DIRECT = 1


def runs_per_worker(transport: str) -> int:
    """Runs a local worker process flies at once (its threads) for a campaign over `transport`."""
    return RUNS_PER_WORKER_DIRECT if transport == "direct" else RUNS_PER_WORKER


def netns_check() -> str | None:
    """None when this process can make a private network namespace per run, else why not (one line)."""
    err = None

    def probe():
        nonlocal err
        try:
            netns.enter_netns(fresh=True)
        except (netns.NetnsError, OSError) as exc:
            err = str(exc)

    t = threading.Thread(target=probe)   # a throw-away thread: its namespace goes with it
    t.start()
    t.join()
    return err


def _decimate(series: dict | None) -> dict | None:
    if not series or "true_angle" not in series:
        return None
    t = np.asarray(series["t"], float)
    e = np.asarray(series["true_angle"], float)
    step = max(1, int(np.ceil(t.size / SERIES_POINTS)))
    idx = np.arange(0, t.size, step)
    if idx.size and idx[-1] != t.size - 1:
        idx = np.append(idx, t.size - 1)
    return {"t_s": t[idx].tolist(), "pointing_error_arcsec": e[idx].tolist()}


def _in_namespace(ns: str) -> list:
    """This process's descendants that live in the network namespace ns (a run's: its plant, joined by
    setns from the plant server, and its flight computer)."""
    import psutil  # deferred: only a run that timed out needs it (a distributed dependency)

    out = []
    for c in psutil.Process().children(recursive=True):
        try:
            if os.readlink(f"/proc/{c.pid}/ns/net") == ns:
                out.append(c)
        except OSError:
            continue
    return out


class _Watchdog:
    """Kills the run's processes after timeout_s; the run then fails with "timed out": the plants it launched
    through `launcher` (a --transport direct run's is the thread's plant runner, which flies it), and with a network
    namespace of its own (an LCM run: a worker flies RUNS_PER_WORKER runs at once, each in its own namespace) every
    process in that namespace; never the other processes of the worker (its plant server, its other runs')."""

    def __init__(self, timeout_s: float | None, own_namespace: bool):
        self.fired = False
        self._t = None
        self._ns = netns.current_netns_id() if own_namespace else None   # the run thread's, entered before this
        self._plants: list[int] = []
        self._lock = threading.Lock()
        if timeout_s:
            self._t = threading.Timer(timeout_s, self._fire)
            self._t.daemon = True

    def launcher(self, launch):
        """launch (the plant server's), recording the pid of each plant it starts for this run."""
        def launch_recorded(*args, **kwargs):
            with self._lock:
                child = launch(*args, **kwargs)
                self._plants.append(child.pid)
                if self.fired:        # fired while the plant was being started: it is over time too
                    _kill(child.pid)
                return child
        return launch_recorded

    def _fire(self):
        import psutil  # deferred: see _in_namespace

        with self._lock:
            self.fired = True
            for pid in self._plants:
                _kill(pid)
            for c in _in_namespace(self._ns) if self._ns is not None else ():
                try:
                    c.kill()
                except psutil.Error:
                    pass

    def __enter__(self):
        if self._t:
            self._t.start()
        return self

    def __exit__(self, *exc):
        if self._t:
            self._t.cancel()
        return False


def _kill(pid: int) -> None:
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


#: this worker's plant server (plant_server.py): started at the first run, before the run's namespace and
#: watchdog, so it is neither in a run's namespace nor one of the run's children the watchdog kills
PLANT_SERVER = PlantServer()
#: each worker thread's plant runner for --transport direct: a plant server that flies the thread's direct runs
#: itself, one after the other (PlantServer.launch with here=True), instead of forking a plant per run
_RUNNERS = threading.local()


def plant_runner() -> PlantServer:
    """The calling thread's plant runner (started at its first direct run; it ends with the thread)."""
    runner = getattr(_RUNNERS, "server", None)
    if runner is None:
        runner = _RUNNERS.server = PlantServer()
    return runner


def _refly_lcm(opts: RunOptions, out: Path, plant_launcher) -> dict:
    """--transport direct, a sampled run: the same run again over LCM (plant_node + fsw_node) in out/lcm, its
    command history compared bit for bit with the direct run's (aocs_loop.history.differences); its plant started
    by plant_launcher (the worker's plant server's fork)."""
    from aocs_loop import history  # deferred: only a sampled run compares logs
    from aocs_wire import lcmlog  # deferred: see above

    lcm_out = out / "lcm"
    execute(dataclasses.replace(opts, out=str(lcm_out), transport="lcm", plant_launcher=plant_launcher))
    diff = history.differences(lcmlog.read(out / "run.lcmlog"), lcmlog.read(lcm_out / "run.lcmlog"))
    return {"transport": "lcm", "identical": not diff, "differences": diff[:10]}


@functools.cache
def _keep_freed_memory() -> bool:
    """Once per worker process: malloc keeps what a run frees for the next (aocs_core.libc.keep_freed_memory)."""
    return libc.keep_freed_memory()


def run_task(spec: dict, run_dir: str, keep_logs: bool = False, timeout_s: float | None = None,
             fork: bool = True, transport: str = "lcm", refly: bool = False) -> dict:
    """Fly one run (spec: plan.RunSpec.to_dict()); the result row (never raises for the run itself).
    transport: lcm or direct (aocs_runner.transport); refly (direct): fly it again over LCM and compare the
    command histories: a difference makes the row an error naming it."""
    t0 = time.monotonic()
    row = {"index": spec["index"], "status": STATUS_ERROR, "error": None, "metrics": None, "series": None,
           "worker_pid": os.getpid(), "run_dir": run_dir}
    out = Path(run_dir)
    _keep_freed_memory()
    try:
        # a direct run opens no socket: flown by the thread's plant runner (the watchdog knows its pid), it makes no
        # namespace
        here = fork and transport == "direct"
        server = plant_runner() if here else PLANT_SERVER
        if fork:
            server.ensure_running()
            if refly:
                PLANT_SERVER.ensure_running()   # before the namespace: see PLANT_SERVER
        own_namespace = transport != "direct" or refly or not fork
        if own_namespace:
            netns.enter_netns(fresh=True)
        wd = _Watchdog(timeout_s, own_namespace)
        # the same --set text as the repeat command (plan.repeat_command): the run reads its values back
        # from that text, as `aocs run` does, so the two are the same run bit for bit
        sets = [f"{k}={scenario_opts.toml_value(v)}" for k, v in spec["overrides"].items()]
        # the plant records the bus, its truth in the log only (aocs_runner.plant_node --log): no recorder
        # thread in this worker, ~0.3 s less CPU per 500 s run
        opts = RunOptions(scenario=spec["scenario"], law=spec["law"], out=str(out), sets=sets, plots=False,
                          quiet=True, reply_timeout=REPLY_TIMEOUT_S, recorder="plant", transport=transport,
                          plant_launcher=wd.launcher(functools.partial(server.launch, here=here)) if fork else None,
                          telemetry="always" if keep_logs else "failed")   # a passed run's folder is deleted
        with wd:
            try:
                res = execute(opts)
            except RunFailed as exc:
                if wd.fired:
                    raise RunFailed(f"timed out after {timeout_s:g} s (killed); {exc}") from None
                raise
            if wd.fired:   # fired before the run had a process to kill (a tiny --timeout): still over time
                raise RunFailed(f"timed out after {timeout_s:g} s (the run took {time.monotonic() - t0:.3g} s)")
            if refly:
                row["refly"] = _refly_lcm(opts, out, wd.launcher(PLANT_SERVER.launch) if fork else None)
        m = res.metrics
        row["metrics"] = m
        row["series"] = _decimate(res.series)
        row["status"] = STATUS_PASSED if m["verdict"]["passed"] else STATUS_FAILED
        if row["status"] == STATUS_FAILED:
            from aocs_analysis import verdict  # deferred: only a failed verdict needs its summary

            row["error"] = verdict.summary(m["verdict"])
        if refly and not row["refly"]["identical"]:
            row["status"] = STATUS_ERROR
            row["error"] = ("the LCM re-flight differs from the direct run: " + "; ".join(row["refly"]["differences"]))
    except (ScenarioError, ValueError, fsw_config.ConfigError, evmod.EventError, paths.SetupError,
            netns.NetnsError) as exc:
        row["error"] = f"refused: {exc}"
    except (RunFailed, orchestrate.RunAborted) as exc:
        row["error"] = f"FAILED: {exc}"
    except Exception as exc:  # noqa: BLE001 - a campaign records every run, whatever broke
        row["error"] = f"crashed: {type(exc).__name__}: {exc}\n{traceback.format_exc(limit=8)}"
    row["wall_s"] = time.monotonic() - t0
    if row["status"] == STATUS_PASSED and not keep_logs:
        shutil.rmtree(out, ignore_errors=True)
    elif row["error"]:
        out.mkdir(parents=True, exist_ok=True)   # a run refused before it started has no folder yet
        (out / "error.txt").write_text(row["error"] + "\n")
    return row


def run_tasks(specs: list, run_dirs: list, keep_logs: bool = False, timeout_s: float | None = None,
              fork: bool = True, transport: str = "lcm", refly=None) -> list[dict]:
    """Several runs one after another (run_task each, refly[i] for run i): one Dask task for a few short runs, whose
    scheduler, client and event-loop costs per task would otherwise be of the order of a direct run's own."""
    refly = [False] * len(specs) if refly is None else list(refly)
    if not (len(specs) == len(run_dirs) == len(refly)):
        raise ValueError(f"run_tasks: {len(specs)} specs, {len(run_dirs)} folders and {len(refly)} re-flight flags")
    return [run_task(s, d, keep_logs, timeout_s, fork=fork, transport=transport, refly=r)
            for s, d, r in zip(specs, run_dirs, refly)]
