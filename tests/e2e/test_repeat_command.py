"""run.json's repeat_command (shown on the run page) flies the same run: a run with shorthands (--limit, --seed,
--guidance, --duration) and an event, then its repeat command alone, give the same metrics, number for number."""
from __future__ import annotations

import json
import shlex
import subprocess
import sys


def _aocs(words, out):
    assert words[:2] == ["aocs", "run"]
    p = subprocess.run([sys.executable, "-m", "aocs.cli", *words[1:], "--out", str(out), "-q", "--no-plots"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    return json.loads((out / "metrics.json").read_text()), json.loads((out / "run.json").read_text())


def _figures(m: dict) -> dict:
    pe = m["pointing_error_arcsec"]
    return {"settle": m["settle_time_s"], "final_max": pe["final_max"], "final_rms": pe["final_rms"],
            "effort": m["effort"], "max_abs_torque": m["max_abs_torque_nm"],
            # every counter but the overruns: the step time against its budget is the machine's, not the run's
            "counters": {k: v for k, v in m["counters"].items() if k != "overruns"},
            "wheels": m["wheels"]["per_wheel"], "commands": m["commands"]}


def test_the_repeat_command_flies_the_same_run(tmp_path):
    m1, meta = _aocs(["aocs", "run", "irassi_rw", "--law", "quat_pid", "--guidance", "slew", "--duration", "60",
                      "--limit", "0.4", "--seed", "7", "--event", "30:mode=nominal"], tmp_path / "a")
    cmd = shlex.split(meta["repeat_command"])
    assert "--limit" not in cmd and "actuator.axis_limit=0.4" in cmd and "seed=7" in cmd and "30:mode=nominal" in cmd
    m2, _ = _aocs(cmd, tmp_path / "b")
    assert _figures(m2) == _figures(m1)
