"""Telemetry and report benchmark (`make bench-telemetry`; docs/benchmarks.md): what a notebook pays to look at a run.

    python -m aocs.bench_telemetry [--scenario irassi_rw] [--duration 500] [--reads 20] [--json FILE]

Flies one lockstep run (`aocs run SCENARIO --law quat_pid --guidance slew --duration D`, real processes), then
prints: the size of its telemetry.parquet (rows, columns, bytes) and of its LCM log; the time to read the table into
a pandas DataFrame (aocs_analysis.telemetry.read, pyarrow; median and best of --reads reads, after one warm-up read,
in this process: the figure a notebook sees for its second and later reads); the time to decode the LCM log itself
(aocs_wire.lcmlog.read), the alternative; and the size and build time of the run's HTML page. A benchmark, not a
test: it prints figures and never fails on them.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from aocs_analysis import telemetry
from aocs_api import run as api_run
from aocs_report import html, run_report
from aocs_wire import lcmlog


def _times(fn, n: int) -> list[float]:
    out = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m aocs.bench_telemetry", description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="irassi_rw")
    ap.add_argument("--law", default="quat_pid")
    ap.add_argument("--duration", type=float, default=500.0)
    ap.add_argument("--reads", type=int, default=20)
    ap.add_argument("--json", help="also write the figures here")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="aocs-bench-telemetry-") as tmp:
        out = Path(tmp) / "run"
        r = api_run(args.scenario, law=args.law, guidance="slew", duration=args.duration, out=out)
        tel, log = out / "telemetry.parquet", out / "run.lcmlog"
        telemetry.read(tel)   # warm-up: pyarrow's and pandas' first-use costs
        reads = _times(lambda: telemetry.read(tel), args.reads)
        decodes = _times(lambda: lcmlog.read(log), max(3, args.reads // 5))
        df = telemetry.read(tel)
        t0 = time.perf_counter()
        page = html.render(run_report.run_document(out))
        page_s = time.perf_counter() - t0
        fig = {"scenario": args.scenario, "law": args.law, "duration_s": args.duration, "rows": len(df),
               "columns": len(df.columns), "parquet_bytes": tel.stat().st_size, "log_bytes": log.stat().st_size,
               "read_median_s": statistics.median(reads), "read_best_s": min(reads), "reads": len(reads),
               "log_decode_median_s": statistics.median(decodes), "html_bytes": len(page.encode()),
               "html_build_s": page_s, "verdict": r.verdict, "load_average_1min": os.getloadavg()[0],
               "cpus": os.cpu_count()}
    print(f"{args.scenario} / {args.law}, {args.duration:g} s lockstep run: telemetry.parquet {fig['rows']} rows x "
          f"{fig['columns']} columns, {fig['parquet_bytes'] / 1e6:.2f} MB (LCM log {fig['log_bytes'] / 1e6:.2f} MB)")
    print(f"  read into pandas: median {fig['read_median_s'] * 1e3:.1f} ms, best {fig['read_best_s'] * 1e3:.1f} ms "
          f"over {fig['reads']} reads (target < 100 ms)")
    print(f"  decoding the LCM log instead: median {fig['log_decode_median_s'] * 1e3:.1f} ms")
    print(f"  run page: {fig['html_bytes'] / 1e6:.2f} MB HTML, built in {fig['html_build_s']:.2f} s")
    print(f"  machine: {fig['cpus']} cores, 1-minute load average {fig['load_average_1min']:.1f} during the benchmark")
    if args.json:
        Path(args.json).write_text(json.dumps(fig, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
