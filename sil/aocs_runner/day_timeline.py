"""Redraw a run folder's mission-day timeline (aocs_analysis.day_timeline) from its log and run.json.

    python -m aocs_runner.day_timeline OUT_DIR      -> OUT_DIR/day_timeline.png

For a run flown with --no-plots (the day-long runs of docs/spec.md 5.11); `aocs run` draws it itself otherwise.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from aocs_analysis import day_timeline
from aocs_analysis import run_metrics as results
from aocs_plant.scenario import ScenarioError, load
from aocs_wire import lcmlog


def redraw(out_dir: Path) -> Path:
    """OUT_DIR/day_timeline.png from OUT_DIR/run.json and its log (the run's metrics recomputed)."""
    meta = json.loads((out_dir / "run.json").read_text())
    sc = load(meta["scenario_path"], meta.get("overrides") or {})
    log = lcmlog.read(out_dir / meta.get("log", "run.lcmlog"))
    metrics, series = results.compute(log, sc, meta)
    series["unloading"] = day_timeline.unloading_series(log, sc)
    return day_timeline.timeline(series, metrics, out_dir / day_timeline.FILE, f"{sc.id} / {meta['law']}")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m aocs_runner.day_timeline", description=__doc__.splitlines()[0])
    p.add_argument("out_dir", help="a run folder (aocs run --out)")
    d = Path(p.parse_args(argv).out_dir)
    if not (d / "run.json").is_file():
        print(f"day_timeline: {d}: no run.json (not a run folder)", file=sys.stderr)
        return 2
    try:
        print(redraw(d))
    except (ScenarioError, OSError, ValueError) as exc:
        print(f"day_timeline: {d}: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
