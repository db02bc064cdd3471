"""SIL lockstep benchmark (`make bench`): what the LCM transport costs, and the in-process transport.

    python -m aocs.bench_sil [--runs 3] [--scenario irassi_large] [--duration S] [--json FILE]
    python -m aocs.bench_sil --breakdown [--scenario S] [--law L] [--duration S]   # the period part by part, us

Prints, for irassi_large (500 s at 10 Hz = 5000 control steps):

1. the full lockstep run through real processes (plant_node, fsw_node and the
   recorder, `aocs run`): real-time factor (simulated s per wall s of the
   control loop), per-step round trip seen by the plant (sensors_t published
   -> actuator_cmd_t handled, median / p99), startup (process start to the
   first step) and total wall time, reported separately from the loop;
   the same with the plant receiving through the LCM library (plant_node
   --lcm-lib) instead of its direct udpm socket (aocs_wire.udpm); and the same run with
   `--transport direct` (fsw_node's node logic in the plant's process, docs/sil.md "Transports"), the
   three interleaved run by run (a shared machine's load drifts); each with the plant process's CPU time
   of the loop per step, the figure a loaded machine does not inflate;
2. the bare transport: a Python <-> fsw_node ping-pong of the same sensors_t
   through the LCM library, without plant or recorder (median / p99 round trip);
3. the same plant integrated in process without LCM
   (aocs_plant.integrate_open_loop): time per step and real-time factor;
4. reading a direct run's log back (lcmlog.read, the judgement's first step), with the compiled walk and decoder
   (sil/wire_kernels/lcmlog_kernel.c) and with numpy's, alternated;
and the ratio of 1 (LCM and direct) to 3 per step, i.e. what the transport and the process
boundary cost. Targets (issue 24): lockstep over LCM >= 2000x, direct >= 20,000x. A
benchmark, not a test: it prints figures and never fails on them.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import lcm

from aocs_core import compiled, paths
from aocs_flightcfg import fsw_config
from aocs_loop.frames import SensorFrame, valid_bits
from aocs_loop.lcm_adapter import LcmCodec
from aocs_plant import integrate_open_loop
from aocs_plant.scenario import load
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog, netns, wire

from .bench_breakdown import breakdown, print_breakdown


def _pct(vals, p):
    s = sorted(vals)
    return s[min(len(s) - 1, max(0, int(round(p / 100 * len(s) + 0.5)) - 1))]


def bench_in_process(sc, repeats: int) -> dict:
    times = [integrate_open_loop(sc) for _ in range(repeats)]
    per = statistics.median(times) / sc.n_steps
    return {"steps": sc.n_steps, "loop_s": statistics.median(times), "step_us": per * 1e6,
            "realtime_factor": sc.dt / per}


def bench_transport(sc, steps: int) -> dict:
    """Ping-pong of sensors_t / actuator_cmd_t with fsw_node, nothing else on the bus."""
    bindings = paths.import_bindings()
    codec = LcmCodec(wire.Codecs(bindings), bindings)   # the loop's own sensors_t packing
    with tempfile.TemporaryDirectory() as d:
        cfg = fsw_config.write(Path(d) / "b.cfg", fsw_config.node_config(sc, sc.control.law))
        node = subprocess.Popen([str(paths.fsw_node_exe()), str(cfg)], stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        try:
            lc = lcm.LCM(netns.LCM_URL)
            ready = []
            sub = lc.subscribe(wire.STATUS, lambda c, data: ready.append(1))
            end = time.monotonic() + 10
            while not ready and time.monotonic() < end:
                lc.handle_timeout(50)
            lc.unsubscribe(sub)
            if not ready:
                raise RuntimeError("fsw_node sent no heartbeat")
            box = []
            lc.subscribe(wire.ACTUATOR, lambda c, data: box.append(data))
            q, w = sc.attitude.q0, sc.attitude.w0
            valid = valid_bits().attitude | valid_bits().rate
            z = (0.0, 0.0, 0.0)
            pack = codec.pack_sensors
            rt = []
            perf = time.perf_counter_ns
            t0 = time.perf_counter()
            for k in range(steps):
                data = pack(SensorFrame(k, k * sc.dt, valid, q, w, z, z))
                box.clear()
                a = perf()
                lc.publish(wire.SENSORS, data)
                while not box:
                    if lc.handle_timeout(2000) <= 0:
                        raise RuntimeError(f"no reply to tick {k}")
                rt.append(perf() - a)
            loop = time.perf_counter() - t0
        finally:
            node.terminate()
            node.wait(5)
    return {"steps": steps, "loop_s": loop, "roundtrip_us_median": _pct(rt, 50) / 1e3,
            "roundtrip_us_p99": _pct(rt, 99) / 1e3, "step_us": loop / steps * 1e6}


#: the lockstep variants, flown interleaved run by run: name -> RunOptions keywords
VARIANTS = {"lcm": {}, "lcm_lib": {"plant_lcm_lib": True}, "direct": {"transport": "direct"}}


def _plant_summary(out: Path) -> dict:
    for line in reversed((out / "plant_node.stdout").read_text().splitlines()):
        if line.startswith("{"):
            return json.loads(line)["plant_node"]
    return {}


def bench_lockstep(scenario: str, runs: int, variants=tuple(VARIANTS), duration: float | None = None) -> dict:
    """Each variant flown `runs` times, interleaved (A B C A B C ...): name -> the runs' figures."""
    out = {v: [] for v in variants}
    with tempfile.TemporaryDirectory() as d:
        for i in range(runs):
            for v in variants:
                run_dir = Path(d) / f"{v}{i}"
                res = execute(RunOptions(scenario=scenario, out=str(run_dir), plots=False, quiet=True,
                                         duration=duration, telemetry_decimate=100, **VARIANTS[v]))
                m = res.metrics
                ls = m["lockstep"]
                rt = ls["roundtrip_ns"]
                steps = m["timing"]["steps"]
                cpu = _plant_summary(run_dir).get("loop_cpu_s")
                out[v].append({"realtime_factor": ls["realtime_factor"], "loop_s": ls["loop_s"],
                               "step_us": ls["loop_s"] / steps * 1e6,
                               "plant_cpu_step_us": cpu / steps * 1e6 if cpu is not None else None,
                               "roundtrip_us_median": rt["median"] / 1e3, "roundtrip_us_p99": rt["p99"] / 1e3,
                               "startup_s": ls["startup_s"], "wall_s": m["wall_s"],
                               "log_complete": m["log_complete"], "fsw_step_ns_median": m["timing"]["step_ns_median"]})
                if v == "direct":
                    out[v][-1].update(log_read_ms(run_dir / "run.lcmlog"))
                shutil.rmtree(run_dir, ignore_errors=True)
    return out


def log_read_ms(path: Path, repeats: int = 7) -> dict:
    """lcmlog.read of a run's log (the judgement's first step), with the compiled walk and decoder and with numpy's
    (AOCS_PLANT_KERNELS=python), alternated: the median of each, ms."""
    times: dict = {"log_read_ms_compiled": [], "log_read_ms_numpy": []}
    saved = os.environ.get(compiled.ENV)
    try:
        for _ in range(repeats):
            for key, env in (("log_read_ms_compiled", ""), ("log_read_ms_numpy", "python")):
                os.environ[compiled.ENV] = env
                t0 = time.perf_counter()
                lcmlog.read(path)
                times[key].append(1e3 * (time.perf_counter() - t0))
    finally:
        if saved is None:
            os.environ.pop(compiled.ENV, None)
        else:
            os.environ[compiled.ENV] = saved
    return {k: statistics.median(v) for k, v in times.items()}


#: the direct loop's parts (plant_node._Loop.run_lockstep's callees) -> what they are, for the breakdown
PARTS = {"publish": "transport: sensors_t to the node in process (ctypes, C decode, executive step, encode), "
                    "both messages logged, reply unpacked",
         "sensors": "plant sensing + sensors_t packing", "truth": "truth_t of the tick, packed and logged",
         "advance": "plant: integrate one period", "apply": "plant: apply the command (actuator models)",
         "command": "actuator_cmd_t values -> Command", "_check_end": "integration-error check (step doubling)",
         "begin": "integration-error check: state kept",
         "handle_timeout": "waiting for fsw_node's reply (the LCM round trip: its receive, decode, step, "
                           "encode, send, and the plant's socket read and dispatch)"}


def profile_loop(scenario: str, duration: float | None, transport: str) -> list[tuple[str, float]]:
    """cProfile of one run's plant process (plant_node in this process) over `transport`: each part of the
    lockstep loop's per-period time as a fraction of the loop (profiling slows Python calls, not the C step
    nor the wait: the fractions, not the times, are what it says). Over LCM fsw_node runs as its own process
    and the plant publishes truth_t on the bus without recording (the runner's recorder is not there)."""
    import contextlib  # deferred: only --profile needs these
    import cProfile  # deferred: see above
    import io  # deferred: see above
    import pstats  # deferred: see above

    from aocs_runner import plant_node  # deferred: see above
    from aocs_runner.run import plan_run, plant_arguments  # deferred: see above

    with tempfile.TemporaryDirectory() as d:
        opts = RunOptions(scenario=scenario, out=str(Path(d) / "p"), plots=False, quiet=True, duration=duration,
                          transport=transport, recorder="plant" if transport == "direct" else "builtin")
        plan = plan_run(opts)
        args = plant_arguments(opts, plan)
        node = None if transport == "direct" else subprocess.Popen(
            plan.fc_cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        prof = cProfile.Profile()
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                prof.runcall(plant_node.main, [str(a) for a in args])
        finally:
            if node is not None:
                node.terminate()
                node.wait(10)
    st = pstats.Stats(prof).stats
    loop = next(k for k in st if k[2] == "run_lockstep")
    total = st[loop][3]
    parts = [(name, edge[3] / total) for (f, ln, name), (cc, nc, tt, ct, callers) in st.items()
             for caller, edge in callers.items() if caller == loop and edge[3] / total >= 0.005]
    parts.sort(key=lambda p: -p[1])
    parts.append(("run_lockstep itself", st[loop][2] / total))
    return parts


def _median(runs: list[dict]) -> dict:
    return {k: statistics.median(r[k] for r in runs) for k in runs[0] if k != "log_complete"}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m aocs.bench_sil", description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="irassi_large")
    p.add_argument("--runs", type=int, default=3, help="lockstep runs of each transport (the median is reported)")
    p.add_argument("--duration", type=float, default=None, help="run length, s (default the scenario's)")
    p.add_argument("--json", help="also write the figures here")
    p.add_argument("--profile", action="store_true",
                   help="only the breakdown of the loop over LCM and direct (cProfile of the plant process)")
    p.add_argument("--breakdown", action="store_true",
                   help="only the loop's period part by part in us over LCM and direct (aocs.bench_breakdown)")
    p.add_argument("--law", default=None, help="--breakdown: the law flown (default the scenario's)")
    args = p.parse_args(argv)

    netns.reexec_in_netns([sys.executable, "-m", "aocs.bench_sil", *(sys.argv[1:] if argv is None else argv)])

    sc = load(args.scenario, None if args.duration is None else {"duration_s": args.duration,
                                                                "metrics.window_s": args.duration})
    print(f"SIL lockstep benchmark: {sc.id}, {sc.n_steps} steps of {sc.dt:g} s "
          f"({sc.duration_s:g} s simulated), {args.runs} runs of each transport, interleaved "
          f"(load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)", flush=True)
    if args.breakdown:
        for transport in ("lcm", "direct"):
            print_breakdown(breakdown(args.scenario, args.duration, transport, args.law))
        return 0
    if args.profile:
        for transport in ("lcm", "direct"):
            print(f"{transport} loop, share of the loop's profiled time per part (cProfile of the plant process):")
            for name, share in profile_loop(args.scenario, args.duration, transport):
                what = PARTS.get(name, "")
                if transport == "lcm" and name == "publish":
                    what = "sensors_t sent on the udpm socket"
                print(f"  {100 * share:5.1f} %  {name}: {what}")
        return 0
    flown = bench_lockstep(args.scenario, args.runs, duration=args.duration)
    runs, runs_lib, runs_dir = flown["lcm"], flown["lcm_lib"], flown["direct"]
    transport = bench_transport(sc, sc.n_steps)
    plant = bench_in_process(sc, max(3, args.runs))
    med, med_lib, med_dir = _median(runs), _median(runs_lib), _median(runs_dir)
    rows = [
        ("lockstep run, real-time factor (median)", f"{med['realtime_factor']:.0f}x  (runs: "
         + ", ".join(f"{r['realtime_factor']:.0f}x" for r in runs) + "; target >= 2000x)"),
        ("  control loop", f"{med['loop_s']:.3f} s, {med['step_us']:.1f} us per step, plant process CPU "
         f"{med['plant_cpu_step_us']:.1f} us per step"),
        ("  per-step round trip (plant view)", f"median {med['roundtrip_us_median']:.1f} us, "
         f"p99 {med['roundtrip_us_p99']:.1f} us"),
        ("  startup (process start to first step)", f"{med['startup_s']:.2f} s"),
        ("  wall time of the whole run", f"{med['wall_s']:.2f} s (startup, loop, recorder, analysis)"),
        ("  executive step (fsw_node, median)", f"{med['fsw_step_ns_median']:.0f} ns"),
        ("  log complete", ", ".join(str(r["log_complete"]) for r in runs)),
        ("same, plant receiving through the LCM library", f"{med_lib['realtime_factor']:.0f}x  (runs: "
         + ", ".join(f"{r['realtime_factor']:.0f}x" for r in runs_lib) + f"), round trip median "
         f"{med_lib['roundtrip_us_median']:.1f} us"),
        ("bare transport ping-pong (Python <-> fsw_node)", f"median {transport['roundtrip_us_median']:.1f} us, "
         f"p99 {transport['roundtrip_us_p99']:.1f} us, {transport['step_us']:.1f} us per step"),
        ("direct (--transport direct), real-time factor", f"{med_dir['realtime_factor']:.0f}x  (runs: "
         + ", ".join(f"{r['realtime_factor']:.0f}x" for r in runs_dir) + "; target >= 20,000x)"),
        ("  control loop", f"{med_dir['loop_s']:.3f} s, {med_dir['step_us']:.1f} us per step, process CPU "
         f"{med_dir['plant_cpu_step_us']:.1f} us per step (flight software included)"),
        ("  log complete", ", ".join(str(r["log_complete"]) for r in runs_dir)),
        ("  reading its log back (lcmlog.read)", f"{med_dir['log_read_ms_compiled']:.1f} ms compiled, "
         f"{med_dir['log_read_ms_numpy']:.1f} ms numpy (medians)"),
        ("plant in process, no LCM", f"{plant['step_us']:.1f} us per step, {plant['realtime_factor']:.0f}x real time"),
        ("ratio lockstep / in-process per step", f"{med['step_us'] / plant['step_us']:.1f}"),
        ("ratio direct / in-process per step", f"{med_dir['step_us'] / plant['step_us']:.1f}"),
        ("direct speed-up over lockstep LCM", f"{med_dir['realtime_factor'] / med['realtime_factor']:.1f}x"),
    ]
    w = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"  {k:<{w}}  {v}")
    if args.json:
        Path(args.json).write_text(json.dumps({"scenario": sc.id, "lockstep_runs": runs, "lockstep_median": med,
                                               "lockstep_lcm_lib_runs": runs_lib,
                                               "direct_runs": runs_dir, "direct_median": med_dir,
                                               "transport": transport, "in_process": plant}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
