"""SIL lockstep benchmark (`make bench`): what the LCM transport costs.

    python -m aocs.bench_sil [--runs 3] [--scenario irassi_large] [--json FILE]

Prints, for irassi_large (500 s at 10 Hz = 5000 control steps):

1. the full lockstep run through real processes (plant_node, fsw_node and the
   recorder, `aocs run`): real-time factor (simulated s per wall s of the
   control loop), per-step round trip seen by the plant (sensors_t published
   -> actuator_cmd_t handled, median / p99), startup (process start to the
   first step) and total wall time, reported separately from the loop;
   the same with the plant receiving through the LCM library (plant_node
   --lcm-lib) instead of its direct udpm socket (aocs_wire.udpm);
2. the bare transport: a Python <-> fsw_node ping-pong of the same sensors_t
   through the LCM library, without plant or recorder (median / p99 round trip);
3. the same plant integrated in process without LCM
   (aocs_plant.integrate_open_loop): time per step and real-time factor;
and the ratio of 1 to 3 per step, i.e. what the transport and the process
boundary cost. The target is a lockstep real-time factor above 1000. A
benchmark, not a test: it prints figures and never fails on them.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import lcm

from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_loop.frames import SensorFrame, valid_bits
from aocs_loop.lcm_adapter import LcmCodec
from aocs_plant import integrate_open_loop
from aocs_plant.scenario import load
from aocs_runner.run import RunOptions, execute
from aocs_wire import netns, wire


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


def bench_lockstep(scenario: str, runs: int, lcm_lib: bool = False) -> list[dict]:
    out = []
    with tempfile.TemporaryDirectory() as d:
        for i in range(runs):
            res = execute(RunOptions(scenario=scenario, out=str(Path(d) / f"r{i}"), plots=False, quiet=True,
                                     plant_lcm_lib=lcm_lib))
            m = res.metrics
            ls = m["lockstep"]
            rt = ls["roundtrip_ns"]
            out.append({"realtime_factor": ls["realtime_factor"], "loop_s": ls["loop_s"],
                        "step_us": ls["loop_s"] / m["timing"]["steps"] * 1e6,
                        "roundtrip_us_median": rt["median"] / 1e3, "roundtrip_us_p99": rt["p99"] / 1e3,
                        "startup_s": ls["startup_s"], "wall_s": m["wall_s"], "log_complete": m["log_complete"],
                        "fsw_step_ns_median": m["timing"]["step_ns_median"]})
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m aocs.bench_sil", description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="irassi_large")
    p.add_argument("--runs", type=int, default=3, help="lockstep runs (the median is reported)")
    p.add_argument("--json", help="also write the figures here")
    args = p.parse_args(argv)

    netns.reexec_in_netns([sys.executable, "-m", "aocs.bench_sil", *(sys.argv[1:] if argv is None else argv)])

    sc = load(args.scenario)
    print(f"SIL lockstep benchmark: {sc.id}, {sc.n_steps} steps of {sc.dt:g} s "
          f"({sc.duration_s:g} s simulated), {args.runs} runs", flush=True)
    runs = bench_lockstep(args.scenario, args.runs)
    runs_lib = bench_lockstep(args.scenario, args.runs, lcm_lib=True)
    transport = bench_transport(sc, sc.n_steps)
    plant = bench_in_process(sc, max(3, args.runs))
    med = {k: statistics.median(r[k] for r in runs) for k in runs[0] if k != "log_complete"}
    med_lib = {k: statistics.median(r[k] for r in runs_lib) for k in runs_lib[0] if k != "log_complete"}
    rows = [
        ("lockstep run, real-time factor (median)", f"{med['realtime_factor']:.0f}x  (runs: "
         + ", ".join(f"{r['realtime_factor']:.0f}x" for r in runs) + "; target > 1000x)"),
        ("  control loop", f"{med['loop_s']:.3f} s, {med['step_us']:.1f} us per step"),
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
        ("plant in process, no LCM", f"{plant['step_us']:.1f} us per step, {plant['realtime_factor']:.0f}x real time"),
        ("ratio lockstep / in-process per step", f"{med['step_us'] / plant['step_us']:.1f}"),
    ]
    w = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"  {k:<{w}}  {v}")
    if args.json:
        Path(args.json).write_text(json.dumps({"scenario": sc.id, "lockstep_runs": runs, "lockstep_median": med,
                                               "lockstep_lcm_lib_runs": runs_lib,
                                               "transport": transport, "in_process": plant}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
