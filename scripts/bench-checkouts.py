#!/usr/bin/env python3
"""The lockstep loop of one scenario in several checkouts, interleaved: is a change no slower than a baseline?

    scripts/bench-checkouts.py [--rounds 15] [--scenario irassi_large] BASELINE CHECKOUT [CHECKOUT ...]

Each checkout is a directory with its own host build (build/host) and a .venv; per round, `aocs run SCENARIO
--no-plots -q` is flown once in each checkout in turn (the checkout's own sources, build and flight software,
lockstep over LCM), and each run's `lockstep.realtime_factor` (simulated time over the loop's wall time, from its
metrics.json) is kept. Prints every run's factor, the median per checkout, and for each checkout after the first
its per-round ratio to the baseline (> 1: faster) with their median and how many rounds it was faster in: a
shared machine's load drifts between rounds, not within one. A benchmark: it prints figures and never fails on
them (docs/benchmarks.md, "Issue 19's last criterion").
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path


def fly(checkout: Path, scenario: str, out: Path) -> float | None:
    """One `aocs run` in the checkout; its real-time factor, None when the run left no figure."""
    env = dict(os.environ, PATH=f"{checkout / '.venv' / 'bin'}:{os.environ.get('PATH', '')}",
               PYTHONPATH=f"{checkout / 'sil'}:{checkout / 'tools'}", AOCS_BUILD_DIR=str(checkout / "build" / "host"))
    cmd = [str(checkout / ".venv" / "bin" / "python"), "-c",
           "import sys; sys.argv[0] = 'aocs'; from aocs.cli import main; sys.exit(main())",
           "run", scenario, "--out", str(out), "--no-plots", "-q"]
    subprocess.run(cmd, cwd=checkout, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        return float(json.loads((out / "metrics.json").read_text())["lockstep"]["realtime_factor"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("checkouts", nargs="+", type=Path, help="the baseline first, then the checkouts to compare")
    p.add_argument("--rounds", type=int, default=15)
    p.add_argument("--scenario", default="irassi_large")
    a = p.parse_args()
    if len(a.checkouts) < 2:
        p.error("give a baseline and at least one checkout to compare with it")
    for c in a.checkouts:
        if not (c / ".venv" / "bin" / "python").exists() or not (c / "build" / "host").is_dir():
            print(f"bench-checkouts: {c}: no .venv/bin/python or build/host (set it up and build it first)",
                  file=sys.stderr)
            return 2
    names = [str(c) for c in a.checkouts]
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for r in range(a.rounds):
            row = [fly(c.resolve(), a.scenario, Path(d) / f"r{r}-{i}") for i, c in enumerate(a.checkouts)]
            rows.append(row)
            print(f"round {r + 1:2d}: " + "  ".join("failed" if x is None else f"{x:.0f}x" for x in row), flush=True)
    for i, name in enumerate(names):
        vals = [row[i] for row in rows if row[i] is not None]
        med = f"{statistics.median(vals):.0f}x" if vals else "no run"
        print(f"{name}: median {med} of {len(vals)} runs")
        if i == 0:
            continue
        ratios = [row[i] / row[0] for row in rows if row[i] is not None and row[0] is not None]
        if ratios:
            print(f"  / {names[0]} per round: median {statistics.median(ratios):.3f} (from {min(ratios):.3f} to "
                  f"{max(ratios):.3f}), faster in {sum(x > 1.0 for x in ratios)} of {len(ratios)} rounds")
    return 0


if __name__ == "__main__":
    sys.exit(main())
