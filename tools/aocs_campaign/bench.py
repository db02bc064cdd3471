"""`make bench-campaign`: campaign throughput against sequential `aocs run` processes (docs/campaigns.md).

    python -m aocs_campaign.bench [--runs 40] [--transports lcm,direct] [--workers K] [--single 3] [--json FILE]

1. `aocs campaign irassi_large --law quat_pd --runs N` with four dispersions (inertia, initial attitude,
   initial rate, disturbance scale) at 0.5 N m, 500 s runs, on a local Dask cluster, once per transport
   (`--transport lcm`, then `--transport direct`, whose every 50th run is re-flown over LCM and compared):
   runs per minute of the whole command (cluster start and report included) and of its runs alone (first
   submit to last row), the ratio direct / lcm, and the re-flights found identical;
2. the same N runs as sequential `aocs run` processes (each run's repeat command from the campaign's rows):
   runs per minute;
3. `aocs run irassi_large --law quat_pd -q --no-plots` as a whole process, --single times: wall and CPU
   seconds (this process's children's rusage), median.

Every figure is printed with the machine's load average: on a shared machine quote medians and ratios.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

DISPERSE = ["plant.inertia[0][0]=normal:2059.5:60", "plant.inertia[1][1]=normal:5954.2:180",
            "plant.inertia[2][2]=normal:5974.3:180", "plant.inertia[0][1]=normal:0:20",
            "plant.euler321_deg=rotation:1", "plant.w0=normal:0:1e-4",
            "disturbances.constant_torque.scale=normal:1:0.2"]
AOCS = [sys.executable, "-m", "aocs.cli"]


def _timed(cmd, **kw):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    wall = time.monotonic() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return p, wall, cpu


def _campaign(args, out: Path, transport: str) -> tuple[dict, list[dict]]:
    """One `aocs campaign` of the benchmark over `transport`: its figures and its rows."""
    cmd = AOCS + ["campaign", "irassi_large", "--law", "quat_pd", "--runs", str(args.runs), "--seed",
                  str(args.seed), "--set", "actuator.axis_limit=0.5", "--out", str(out), "-q", "--no-plots",
                  "--transport", transport]
    for d in DISPERSE:
        cmd += ["--disperse", d]
    if args.workers:
        cmd += ["--workers", str(args.workers)]
    p, wall, cpu = _timed(cmd)
    doc = json.loads((out / "campaign.json").read_text()) if (out / "campaign.json").is_file() else {}
    th = doc.get("throughput") or {}
    if p.returncode not in (0, 1):
        print(p.stderr, file=sys.stderr)
    rows = [json.loads(f.read_text()) for f in sorted((out / "runs").glob("*.json"))] if (out / "runs").is_dir() else []
    return ({"exit": p.returncode, "wall_s": wall, "cpu_s": cpu, "status": doc.get("status"),
             "runs_per_minute_whole_command": 60.0 * args.runs / wall, "refly": doc.get("refly"),
             "runs_per_minute_runs": th.get("runs_per_minute"), "workers": th.get("workers")}, rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m aocs_campaign.bench", description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=40)
    ap.add_argument("--transports", default="lcm,direct", help="campaigns to fly, one per transport (comma list)")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--single", type=int, default=3, help="whole-process timings of one aocs run (0: none)")
    ap.add_argument("--sequential", type=int, default=None,
                    help="how many of the campaign's runs to repeat as sequential aocs run processes "
                         "(default: all; 0: none)")
    ap.add_argument("--seed", type=int, default=14)
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    res = {"load_before": os.getloadavg()}
    transports = [t for t in args.transports.split(",") if t]
    with tempfile.TemporaryDirectory(prefix="aocs-bench-campaign-") as tmp:
        res["campaigns"] = {}
        rows = []
        for transport in transports:
            out = Path(tmp) / f"mc-{transport}"
            c, r = _campaign(args, out, transport)
            res["campaigns"][transport] = c
            rows = rows or r      # the sequential runs repeat the first campaign's
        res["campaign"] = res["campaigns"].get("lcm") or next(iter(res["campaigns"].values()))
        # 2. the same runs, one `aocs run` process after the other
        walls = []
        ok = 0
        t0 = time.monotonic()
        for r in rows[:len(rows) if args.sequential is None else args.sequential]:
            words = [w for w in shlex.split(r["repeat_command"])[2:]]
            if "--transport" in words:      # the sequential processes fly over LCM
                i = words.index("--transport")
                del words[i:i + 2]
            j = words.index("--json")
            words[j + 1] = str(Path(tmp) / "seq.json")
            q, w, _ = _timed(AOCS + ["run", *words, "--out", str(Path(tmp) / "seq")])
            walls.append(w)
            ok += q.returncode == 0
        seq_wall = time.monotonic() - t0
        res["sequential_aocs_run"] = {"runs": len(walls), "passed": ok, "wall_s": seq_wall,
                                      "runs_per_minute": 60.0 * len(walls) / seq_wall if walls else None,
                                      "median_run_wall_s": statistics.median(walls) if walls else None}
        # 3. one aocs run, whole process
        singles = []
        for _ in range(args.single):
            q, w, c = _timed(AOCS + ["run", "irassi_large", "--law", "quat_pd", "-q", "--no-plots", "--out",
                                     str(Path(tmp) / "single")])
            singles.append((w, c, q.returncode))
        res["single_aocs_run"] = {"n": len(singles),
                                  "median_wall_s": statistics.median(s[0] for s in singles) if singles else None,
                                  "median_cpu_s": statistics.median(s[1] for s in singles) if singles else None,
                                  "exits": [s[2] for s in singles]}
    res["load_after"] = os.getloadavg()
    s, one = res["sequential_aocs_run"], res["single_aocs_run"]
    print(f"bench-campaign: {args.runs} dispersed irassi_large 500 s runs, quat_pd at 0.5 N m "
          f"(load average before {res['load_before'][0]:.1f}, after {res['load_after'][0]:.1f} on "
          f"{os.cpu_count()} cores)")
    for transport, c in res["campaigns"].items():
        rf = c.get("refly")
        print(f"  aocs campaign --transport {transport} ({c['workers']} Dask workers): "
              f"{c['runs_per_minute_whole_command']:.1f} runs/min whole command ({c['wall_s']:.1f} s), "
              f"{c['runs_per_minute_runs'] or 0:.1f} runs/min of runs alone; status {c['status']}"
              + (f"; LCM re-flights identical {rf['identical']}/{rf['sampled']}" if rf else ""))
    cs = res["campaigns"]
    if "lcm" in cs and "direct" in cs and cs["lcm"]["runs_per_minute_runs"] and cs["direct"]["runs_per_minute_runs"]:
        print(f"  direct / lcm: {cs['direct']['runs_per_minute_runs'] / cs['lcm']['runs_per_minute_runs']:.1f}x "
              f"runs/min of runs alone, {cs['direct']['runs_per_minute_whole_command'] / cs['lcm']['runs_per_minute_whole_command']:.1f}x "
              f"whole command (target >= 10x)")
    if s["runs"]:
        print(f"  sequential aocs run processes: {s['runs_per_minute']:.1f} runs/min ({s['wall_s']:.1f} s, "
              f"median {s['median_run_wall_s']:.2f} s per run, {s['passed']}/{s['runs']} passed)")
    if one["n"]:
        print(f"  one aocs run irassi_large --law quat_pd -q --no-plots: median {one['median_wall_s']:.2f} s wall, "
              f"{one['median_cpu_s']:.2f} s CPU over {one['n']} (exits {one['exits']})")
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
