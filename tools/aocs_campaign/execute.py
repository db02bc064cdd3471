"""A campaign's runs on Dask distributed, one row file per finished run.

    execute.run(campaign, out, workers=K, scheduler=None | "tcp://HOST:PORT", ...)

- cluster: a LocalCluster of K worker processes (default K = the machine's
  cores) flying worker.runs_per_worker(transport) runs each at once (threads), on
  loopback, or the existing cluster at --scheduler;
- each run is worker.run_task (the real SIL path; an LCM run in a private
  network namespace of its own); a task flies runs_per_task of them one after
  another (worker.run_tasks: 4 direct runs, one LCM run); each run's row is
  written to OUT/runs/NNNNNN.json (atomic rename) as soon as its task comes
  back, so a campaign interrupted or killed keeps every run that finished,
  and a rerun into the same OUT skips them (the folder must hold the same
  campaign: OUT/campaign-plan.json);
- a run that crashes, is refused or times out comes back as a row with its
  error (worker.py); a worker process that dies is replaced by its nanny and
  Dask retries the task elsewhere, and a task that kills workers
  ALLOWED_FAILURES times is recorded, each of its runs, with Dask's error;
- bounded submission: at most in_flight_bound tasks submitted and not yet
  recorded (IN_FLIGHT_PER_THREAD per worker thread); the next is submitted as
  a task's rows are written, so a campaign of a million runs writes its first
  row as soon as a task completes and the client's memory does not grow with
  --runs;
- Ctrl-C (SIGINT) or SIGTERM records every task the scheduler holds as
  finished, cancels the rest, closes the cluster and returns with
  interrupted=True.
"""
from __future__ import annotations

import itertools
import json
import logging
import os
import signal
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from . import plan as P
from . import worker as W

#: how often Dask retries a run whose worker process died, before the run is recorded as failed
ALLOWED_FAILURES = 2
#: tasks submitted and not yet recorded, per worker thread (in_flight_bound): 2 keeps every thread busy
#: while the client records a task's rows and submits the next, and bounds the client's and scheduler's memory
IN_FLIGHT_PER_THREAD = 2
#: runs flown one after another by one Dask task (worker.run_tasks), per transport (1 when not named): a direct run
#: takes ~25 ms of a worker, of the order of what the scheduler, the client and the worker's event loop spend on a
#: task; an LCM run takes ~0.5 s
RUNS_PER_TASK = {"direct": 4}


@dataclass
class Outcome:
    done: int           # rows in the folder for this campaign (skipped + finished now)
    skipped: int        # already in the folder before this call
    finished: int       # finished by this call
    interrupted: bool
    wall_s: float       # of this call's runs, from the first submit to the last row
    workers: int


def runs_dir(out: Path) -> Path:
    return out / "runs"


def row_path(out: Path, index: int) -> Path:
    return runs_dir(out) / f"{index:06d}.json"


def load_row(out: Path, index: int) -> dict | None:
    """Run index's row, or None when there is none that counts: a file that cannot be read, is not JSON,
    is empty (`{}`), or is not a finished row of that run (its index, a known status); such a run is flown
    again and its file replaced."""
    try:
        row = json.loads(row_path(out, index).read_bytes())
    except (OSError, ValueError, RecursionError):
        return None
    if not isinstance(row, dict) or row.get("index") != index or row.get("status") not in W.STATUSES:
        return None
    return row


def _row_files(out: Path) -> dict[int, Path]:
    d = runs_dir(out)
    if not d.is_dir():
        return {}
    got = {}
    for p in d.glob("*.json"):
        if len(p.stem) == 6 and p.stem.isdigit():
            got[int(p.stem)] = p
    return got


def finished_indices(out: Path) -> set[int]:
    """The runs of OUT with a row that counts (load_row)."""
    return {i for i in _row_files(out) if load_row(out, i) is not None}


def resumable(out: Path, indices, retry_errors: bool = False) -> set[int]:
    """Those of indices whose run is done in OUT: a row that counts, and with retry_errors not an error."""
    files = _row_files(out)
    done = set()
    for i in indices:
        if i in files:
            row = load_row(out, i)
            if row is not None and not (retry_errors and row["status"] == W.STATUS_ERROR):
                done.add(i)
    return done


def _write_atomic(path: Path, text: str) -> None:
    tmp = path.with_suffix(".tmp")
    try:
        tmp.write_text(text)
        os.replace(tmp, path)
    except OSError as exc:      # a full disk fails in write(), whose error names no file: name it
        tmp.unlink(missing_ok=True)
        raise OSError(exc.errno, exc.strerror, str(path)) from None


def prepare_dir(c: P.Campaign, out: Path) -> None:
    """Creates OUT or checks that it holds this campaign (P.Campaign.identity: scenario and its content,
    law, seed, --set, dispersions); a folder with rows but no readable plan is refused (whose rows?)."""
    if out.exists() and not out.is_dir():
        raise P.CampaignError(f"--out {out}: exists and is not a folder")
    ident = c.identity()
    old, why = P.load_campaign_dir_plan(out)
    if old is None and _row_files(out):
        raise P.CampaignError(f"--out {out}: holds {len(_row_files(out))} run rows but its campaign-plan.json is "
                              f"{why}: it cannot be told which campaign they belong to; choose another folder "
                              "(or move runs/ away)")
    if old is not None and old.get("fingerprint") != ident["fingerprint"]:
        diff = [k for k in ("scenario", "scenario_sha256", "law", "seed", "sets", "disperse")
                if old.get(k) != ident[k]] or ["fingerprint"]
        raise P.CampaignError(f"--out {out}: holds another campaign (scenario {old.get('scenario')}, law "
                              f"{old.get('law')}, seed {old.get('seed')}, dispersions {old.get('disperse')}; "
                              f"differs in {', '.join(diff)}); choose another folder")
    runs_dir(out).mkdir(parents=True, exist_ok=True)
    old_runs = old.get("runs", 0) if old is not None else 0
    meta = {**ident, "runs": max(c.runs, old_runs if isinstance(old_runs, int) else 0)}
    _write_atomic(out / "campaign-plan.json", json.dumps(meta, indent=1) + "\n")


def _cluster(workers: int | None, scheduler: str | None, transport: str = "lcm"):
    from dask.distributed import Client, LocalCluster  # deferred: ~1 s, only a campaign needs Dask

    if scheduler:
        from .scheduler_probe import HANDSHAKE_TIMEOUT_S, probe  # deferred: only with --scheduler

        probe(scheduler)          # one line within HANDSHAKE_TIMEOUT_S when the peer is not a Dask scheduler
        try:
            client = Client(scheduler, timeout=f"{HANDSHAKE_TIMEOUT_S:g}s")
        except OSError as exc:   # not an I/O failure of ours (cmd_campaign): the scheduler's
            raise P.CampaignError(f"--scheduler {scheduler}: {str(exc).splitlines()[0]}") from None
        return client, None
    n = workers or os.cpu_count() or 1
    # CRITICAL: a worker's heartbeat that finds the scheduler gone while the cluster closes logs an ERROR with a
    # traceback; a run that broke is in its row (worker.run_task), not in Dask's log
    cluster = LocalCluster(n_workers=n, threads_per_worker=W.runs_per_worker(transport), processes=True,
                           host="127.0.0.1", dashboard_address=None, silence_logs=logging.CRITICAL)
    return Client(cluster), cluster


def check_workers(client) -> list[str]:
    """One line per worker that cannot make a private network namespace (empty: all can)."""
    res = client.run(W.netns_check)
    return [f"worker {addr}: {why}" for addr, why in sorted(res.items()) if why]


def _threads(client) -> int:
    return sum(w.get("nthreads", 1) for w in client.scheduler_info(n_workers=-1)["workers"].values())


def in_flight_bound(client) -> int:
    """Most tasks submitted and not yet recorded: IN_FLIGHT_PER_THREAD per worker thread of the cluster."""
    return max(2, IN_FLIGHT_PER_THREAD * _threads(client))


def runs_per_task(transport: str, todo: int, threads: int) -> int:
    """Runs per task: RUNS_PER_TASK of the transport, fewer when the campaign is too small to give every worker
    thread IN_FLIGHT_PER_THREAD tasks of that many."""
    return max(1, min(RUNS_PER_TASK.get(transport, 1), todo // max(1, threads * IN_FLIGHT_PER_THREAD)))


def _scheduler_finished(client, futures) -> set:
    """Keys of futures the scheduler holds as finished (their result in a worker's memory), even when
    this client has not yet heard of it (an interrupt keeps those runs too)."""
    keys = [f.key for f in futures]

    def finished(dask_scheduler, keys):
        return [k for k in keys if (ts := dask_scheduler.tasks.get(k)) is not None and ts.state == "memory"]
    try:
        return set(client.run_on_scheduler(finished, keys=keys))
    except Exception:  # noqa: BLE001 - a scheduler that forbids run_on_scheduler or is gone: what we know
        return {f.key for f in futures if f.status == "finished"}


def run(c: P.Campaign, disps, out: Path, *, workers: int | None = None, scheduler: str | None = None,
        keep_logs: bool = False, timeout_s: float | None = None, progress: bool = True, retry_errors: bool = False,
        say=lambda msg: print(msg, file=sys.stderr, flush=True)) -> Outcome:
    """Flies the runs of c not yet in OUT. Bounded submission: at most in_flight_bound(client) runs are
    submitted and not yet recorded; each row is written as its run completes and the next run is submitted
    then, so the first row, the client's memory and an interrupt do not wait for the last submission. On
    Ctrl-C or SIGTERM every run the scheduler holds as finished is recorded before the rest is cancelled."""
    from dask import config as dask_config  # deferred: see _cluster
    from dask.distributed import as_completed  # deferred: see _cluster

    prepare_dir(c, out)
    # a row that does not count (corrupt, empty) is flown again; with retry_errors so is a run that did not
    # complete (crash, timeout, refused)
    done0 = resumable(out, range(c.runs), retry_errors)
    todo = [i for i in range(c.runs) if i not in done0]
    if not todo:
        say(f"aocs campaign: all {c.runs} runs already in {out}/ (nothing to run)")
        return Outcome(len(done0), len(done0), 0, False, 0.0, 0)
    specs = P.iter_plan(c, disps, todo)
    fingerprint = c.fingerprint()
    dask_config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES})
    state = {"recording": False, "stop": False}
    old_handlers = {}

    def on_signal(signum, frame):  # noqa: ARG001
        state["stop"] = True
        if not state["recording"]:     # a row being written is finished first (checked after it)
            raise KeyboardInterrupt

    for sig in (signal.SIGINT, signal.SIGTERM):
        old_handlers[sig] = signal.signal(sig, on_signal)
    client = cluster = None
    finished = 0
    bar = None
    inflight: dict = {}
    t0 = time.monotonic()

    def submit_next(ac) -> bool:
        batch = [s for s in itertools.islice(specs, per_task)]
        if not batch:
            return False
        f = client.submit(W.run_tasks, [s.to_dict() for s in batch],
                          [str(runs_dir(out) / f"{s.index:06d}") for s in batch], keep_logs, timeout_s,
                          transport=c.transport, refly=[c.refly(s.index) for s in batch],
                          key=f"aocs-run-{fingerprint}-{batch[0].index}", pure=False)
        inflight[f] = batch
        ac.add(f)
        return True

    def take(fut) -> None:
        nonlocal finished
        batch = inflight.pop(fut)
        try:
            rows = fut.result(timeout=60)
        except Exception as exc:  # noqa: BLE001 - a task that killed its workers (KilledWorker) or lost
            rows = [{"index": s.index, "status": W.STATUS_ERROR, "metrics": None, "series": None,
                     "error": f"crashed: the run{'s' if len(batch) > 1 else ''} of its task ended the worker "
                              f"process {ALLOWED_FAILURES + 1} times ({type(exc).__name__}: {exc})",
                     "wall_s": None, "worker_pid": None} for s in batch]
        for s, row in zip(batch, rows):
            record(out, s, row, c.transport)
            finished += 1
            if bar is not None:
                bar.update(1)
                if row["status"] != W.STATUS_PASSED:
                    bar.write(f"aocs campaign: run {s.index} {row['status']}: {str(row['error']).splitlines()[0]}",
                              file=sys.stderr)

    try:
        client, cluster = _cluster(workers, scheduler, c.transport)
        problems = check_workers(client)
        if problems:
            raise P.CampaignError("no private network namespace per run on " + "; ".join(problems)
                                  + " (start the workers as root or under `unshare --user --map-root-user`, "
                                  "docs/campaigns.md)")
        n_workers = len(client.scheduler_info(n_workers=-1)["workers"])
        bound = in_flight_bound(client)
        per_task = runs_per_task(c.transport, len(todo), _threads(client))
        say(f"aocs campaign: {len(todo)} runs of {c.runs} ({len(done0)} already done) on {n_workers} Dask "
            f"workers ({scheduler or 'local cluster'}), at most {bound} in flight"
            + (f" ({per_task} runs per task)" if per_task > 1 else "") + f"; results in {out}/")
        if progress:
            from tqdm import tqdm  # deferred: only with a progress bar

            bar = tqdm(total=c.runs, initial=len(done0), unit="run", desc="aocs campaign", file=sys.stderr,
                       dynamic_ncols=True, smoothing=0.1)
        t0 = time.monotonic()
        ac = as_completed()
        while len(inflight) < bound and submit_next(ac):
            pass
        for fut in ac:
            state["recording"] = True
            take(fut)
            state["recording"] = False
            del fut           # released before the next is submitted: at most `bound` on the scheduler
            if state["stop"]:
                raise KeyboardInterrupt
            submit_next(ac)
    except KeyboardInterrupt:
        state["recording"] = True     # a second Ctrl-C does not break the keeping of what finished
        done_keys = _scheduler_finished(client, list(inflight)) if client is not None and inflight else set()
        for fut in [f for f in inflight if f.key in done_keys]:
            try:
                take(fut)
            except Exception:  # noqa: BLE001 - its result is gone with the cluster: flown again on resume
                pass
        state["stop"] = True
    finally:
        wall = time.monotonic() - t0
        if bar is not None:
            bar.close()
        if state["stop"]:
            say(f"aocs campaign: interrupted; {finished} runs finished in this call are kept in {out}/runs/")
        for sig, h in old_handlers.items():
            signal.signal(sig, h)
        if client is not None and inflight:
            try:
                client.cancel(list(inflight))
            except Exception:  # noqa: BLE001 - closing after an interrupt or a lost scheduler
                pass
        _close(client, cluster)
    n_workers_final = locals().get("n_workers", 0)
    return Outcome(len(done0) + finished, len(done0), finished, state["stop"], wall, n_workers_final)


def _close(client, cluster) -> None:
    # each step bounded: a cluster that does not close in time is left to its nannies (they end with us)
    for obj in (client, cluster):
        if obj is None:
            continue
        try:
            obj.close(timeout=10) if obj is client else obj.close(timeout=10)
        except Exception:  # noqa: BLE001 - closing after an interrupt or a lost scheduler
            pass


def record(out: Path, spec: P.RunSpec, row: dict, transport: str = "lcm") -> None:
    """The row of one finished run, with its inputs, its transport and the command that repeats it."""
    row = dict(row)
    row["inputs"] = spec.inputs
    row["overrides"] = spec.overrides
    row["transport"] = transport
    row["repeat_command"] = P.repeat_command(spec, f"run-{spec.index:06d}.json", transport)
    _write_atomic(row_path(out, spec.index), json.dumps(row) + "\n")


def read_rows(out: Path, runs: int) -> list[dict]:
    """The rows that count (load_row) of runs 0 .. runs - 1, by index."""
    rows = []
    for i in sorted(_row_files(out)):
        if i < runs:
            row = load_row(out, i)
            if row is not None:
                rows.append(row)
    return rows
