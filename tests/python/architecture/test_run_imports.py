"""What `aocs run` imports before it flies (issue 19: `make bench` no worse than before the architecture work).

A fresh interpreter imports the run sub-command's module and the plant node, then lists the heavy modules it has
loaded: none of the analysis of a filter (scipy.stats, scipy.linalg), of campaigns (dask) or of reports
(matplotlib, pandas) may come in with them (together about 1.5 s of CPU and 100 MB at every run's start before
they were deferred). pyarrow comes only when telemetry.parquet is written, after the loop."""
from __future__ import annotations

import json
import subprocess
import sys

#: modules a run's start must not import (their users import them where they need them)
HEAVY = ("scipy.stats", "scipy.linalg", "scipy.signal", "scipy.optimize", "dask", "distributed", "matplotlib",
         "pandas", "pyarrow", "plotly")


def _loaded_after(*modules: str) -> set:
    code = ("import json, sys\n" + "".join(f"import {m}\n" for m in modules)
            + "print(json.dumps(sorted(sys.modules)))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    return set(json.loads(res.stdout))


def test_aocs_run_starts_without_the_heavy_modules():
    loaded = _loaded_after("aocs.cmd_run", "aocs_runner.plant_node")
    assert "aocs_runner.run" in loaded and "aocs_plant" in loaded   # the run's own modules are there
    bad = sorted(m for m in HEAVY if m in loaded)
    assert not bad, f"`aocs run` imports {bad} before it flies: defer them to the function that needs them"


def test_the_api_still_gives_every_name():
    """aocs_api's campaign, compare and report are imported on first use: each name still resolves."""
    code = ("import aocs_api as a\n"
            "print(all(callable(getattr(a, n)) for n in a.__all__) and 'campaign' in dir(a))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert res.stdout.strip() == "True"
