"""`aocs analyze` on bad input: one line naming what is wrong, exit 2, no traceback; and the JSON names the
issue asks for (loops x, y, z, mimo with their margins), without SIL runs."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest


def _analyze(*args, timeout=300):
    return subprocess.run([sys.executable, "-W", "ignore", "-m", "aocs.cli", "analyze", *args],
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.parametrize("args,names", [
    (["no_such_scenario"], "no_such_scenario"),
    (["irassi_large", "--law", "orbit_lqr"], "orbit_lqr"),
    (["irassi_large", "--law", "lqr_quat:no_table"], "no_table"),
    (["landsat8_q1"], "orbit"),
    (["irassi_large", "--law", "quat_pd", "--delay", "-1"], "--delay"),
])
def test_bad_input_is_one_line_exit_2(args, names):
    r = _analyze(*args)
    assert r.returncode == 2, r.stdout + r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("aocs analyze: error:") and names in lines[0], r.stderr
    assert "Traceback" not in r.stderr


def test_json_has_the_issue_names(tmp_path):
    out = tmp_path / "a.json"
    r = _analyze("irassi_large", "--law", "quat_pd", "--no-rates", "--json", str(out))
    assert r.returncode == 0, r.stderr
    res = json.loads(out.read_text())
    assert set(res["loops"]) == {"x", "y", "z", "mimo"}
    for loop in res["loops"].values():
        for key in ("gain_margin_db", "phase_margin_deg", "delay_margin_s", "modulus_margin", "crossover_rad_s"):
            assert isinstance(loop[key], float), (key, loop)
    assert "disk_margin" in res["loops"]["mimo"] and res["delay_periods"] == 1 and res["dt_s"] == 0.1
    assert "x " in r.stdout and "mimo" in r.stdout
