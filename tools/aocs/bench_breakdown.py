"""The lockstep loop's control period part by part, in microseconds (issue 24's per-period breakdown).

    python -m aocs.bench_sil --breakdown [--scenario irassi_large] [--duration S]

plant_node's lockstep loop runs in this process (its arguments as `aocs run` gives them, the plant recording the
log), the flight computer as fsw_node over LCM or in process (`--transport direct`). Each part of the loop below
is timed with perf_counter_ns around its call from the loop (a call made inside another timed part counts in that
part); each part's time per period is summarised by its median and its mean over the run, and the period itself
(from one sensors_t to the next) likewise. The timers cost about 0.1 us per call. A figure, never a verdict.

In process the periods normally run compiled (aocs_runner.compiled_loop: no Python part to time, its cost per period
is the direct factor of `make bench`); the breakdown times the Python loop the compiled one replaces
(AOCS_PLANT_KERNELS=periods), which is also the loop of the plants it does not fly.
"""
from __future__ import annotations

import contextlib
import importlib
import io
import json
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

from aocs_plant import kernels
from aocs_runner import plant_node
from aocs_runner.run import RunOptions, plan_run, plant_arguments

#: (module, class, method) -> what the part is; timed when the loop calls it
PARTS = {
    ("aocs_runner.plant_node", "_Loop", "sensors"): "plant: sensors sampled, sensors_t packed",
    ("aocs_wire.udpm", "Udpm", "publish"): "sensors_t sent on the udpm socket",
    ("aocs_loop.direct_adapter", "DirectBus", "publish"): "sensors_t to the node in process: C decode, executive "
                                                           "step, encode; both messages logged; the reply unpacked",
    ("aocs_wire.recorder", "EventLogWriter", "flush"): "the log written (LCM: every LOG_FLUSH_TICKS periods)",
    ("aocs_wire.udpm", "Udpm", "handle_timeout"): "waiting for fsw_node's reply: its receive, decode, step, encode, "
                                                  "send; the plant's socket reads, dispatch and recording",
    ("aocs_runner.plant_node", "_Loop", "truth"): "truth_t of the tick built, packed and logged",
    ("aocs_runner.plant_node", "_Loop", "_check_end"): "integration-error check (step doubling, sampled)",
    ("aocs_loop.lcm_adapter", "LcmCodec", "command"): "actuator_cmd_t values -> Command",
    ("aocs_loop.frames", "PlantPort", "apply"): "plant: the command applied (actuator models)",
    ("aocs_plant.integration_error", "StepDoubling", "begin"): "integration check: state kept",
    ("aocs_plant.plant", "Plant", "advance"): "plant: one period integrated",
}
#: the part whose call starts a period
FIRST = ("aocs_runner.plant_node", "_Loop", "sensors")


class _Timers:
    """Wraps each part's method with a timer; per period (counted from FIRST's calls) the time of each part."""

    def __init__(self):
        self.per_part: dict = {k: [] for k in PARTS}
        self.starts: list[int] = []
        self.depth = 0
        self._undo = []

    def install(self) -> None:
        for key in PARTS:
            mod, cls, meth = key
            owner = getattr(importlib.import_module(mod), cls)
            orig = owner.__dict__[meth]
            setattr(owner, meth, self._wrap(key, orig))
            self._undo.append((owner, meth, orig))

    def remove(self) -> None:
        for owner, meth, orig in reversed(self._undo):
            setattr(owner, meth, orig)
        self._undo.clear()

    def _wrap(self, key, fn):
        perf = time.perf_counter_ns
        acc = self.per_part[key]
        starts = self.starts
        first = key == FIRST
        timers = self

        def timed(*a, **k):
            if timers.depth:
                return fn(*a, **k)
            t0 = perf()
            if first:
                starts.append(t0)
                for lst in timers.per_part.values():
                    lst.append(0)
            timers.depth = 1
            try:
                return fn(*a, **k)
            finally:
                timers.depth = 0
                if acc:   # calls before the first period (the heartbeat wait) are not counted
                    acc[-1] += perf() - t0
        return timed


def breakdown(scenario: str, duration: float | None, transport: str, law: str | None = None) -> dict:
    """One run's loop, part by part: {"period": (median, mean) us, "parts": [(name, what, median, mean)],
    "steps": n, "fsw_step_ns_median": ...}."""
    timers = _Timers()
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "b"
        opts = RunOptions(scenario=scenario, law=law, out=str(out), plots=False, quiet=True, duration=duration,
                          transport=transport)
        plan = plan_run(opts)
        args = [str(a) for a in plant_arguments(opts, plan)]
        node = None if transport == "direct" else subprocess.Popen(
            plan.fc_cmd, stdout=open(out / "fsw_node.stdout", "w"), stderr=subprocess.DEVNULL)
        end_wait = plant_node.END_MARKER_TIMEOUT_S
        plant_node.END_MARKER_TIMEOUT_S = 0.0   # no runner here to send the end marker the recording plant waits for
        timers.install()
        saved = os.environ.get(kernels.ENV)
        if saved is None:
            os.environ[kernels.ENV] = "periods"   # the Python loop, part by part (module docstring)
        try:
            with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
                plant_node.main(args)
        finally:
            timers.remove()
            if saved is None:
                del os.environ[kernels.ENV]
            plant_node.END_MARKER_TIMEOUT_S = end_wait
            if node is not None:
                node.terminate()
                node.wait(10)
        step_ns = _fsw_step_ns(out / "fsw_node.stdout")
    n = len(timers.starts) - 1                      # whole periods: from one sensors call to the next
    periods = [(b - a) / 1e3 for a, b in zip(timers.starts, timers.starts[1:])]
    parts = []
    for key, what in PARTS.items():
        v = [x / 1e3 for x in timers.per_part[key][:n]]
        if v and any(v):
            parts.append((key[2], what, statistics.median(v), statistics.fmean(v)))
    parts.sort(key=lambda p: -p[3])
    rest = [p - sum(timers.per_part[k][i] / 1e3 for k in PARTS) for i, p in enumerate(periods)]
    parts.append(("loop", "the loop's own statements, the timers", statistics.median(rest), statistics.fmean(rest)))
    return {"transport": transport, "steps": n, "dt": plan.sc.dt,
            "period": (statistics.median(periods), statistics.fmean(periods)),
            "parts": parts, "fsw_step_ns_median": step_ns}


def _fsw_step_ns(path: Path):
    """The executive's step_ns median from the flight computer's exit summary (fsw_node's, or the in-process node's
    that plant_node writes in its place), None when there is none."""
    try:
        for line in reversed(path.read_text().splitlines()):
            if line.startswith("{"):
                return json.loads(line)["fsw_node"]["step_ns"]["median"]
    except (OSError, ValueError, KeyError):
        pass
    return None


def print_breakdown(res: dict) -> None:
    med, mean = res["period"]
    print(f"{res['transport']} loop{' (the Python loop the compiled one replaces)' if res['transport'] == 'direct' else ''}"
          f", {res['steps']} periods: period median {med:.1f} us, mean {mean:.1f} us "
          f"({res['dt'] * 1e6 / mean:.0f}x real time at the mean)")
    print(f"  {'median us':>9} {'mean us':>8} {'share':>6}  part")
    for name, what, m, a in res["parts"]:
        print(f"  {m:9.1f} {a:8.1f} {100 * a / mean:5.1f}%  {name}: {what}")
    if res["fsw_step_ns_median"] is not None:
        print(f"  (fsw_node's executive step alone, median: {res['fsw_step_ns_median']} ns)")
