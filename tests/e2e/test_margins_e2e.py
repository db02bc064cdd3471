"""`aocs analyze` against the real loop (plant_node, fsw_node, LCM; issue 22): for quat_pd on irassi_large
the loop measured by a multisine at the plant input agrees with the python-control prediction at >= 5
frequencies across each axis's crossover (within 1 dB and 5 deg; the issue's bound), the linear law
reproduces the C law's logged commands, a loop gain past the predicted gain margin diverges while just
inside converges; and the measurement tells a wrong model apart (a prediction with one period of delay
against a loop flown without it is off by w dt in phase)."""
from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np

from aocs_margins import analyze, law_models, loop_model, measure
from aocs_plant.scenario import load


def test_quat_pd_measured_equals_predicted_and_its_gain_margin_holds_in_sil(tmp_path):
    out = tmp_path / "a.json"
    r = subprocess.run([sys.executable, "-W", "ignore", "-m", "aocs.cli", "analyze", "irassi_large", "--law",
                        "quat_pd", "--measure", "--verify", "--plots", "--no-rates", "--json", str(out),
                        "--out", str(tmp_path / "runs"), "-q"], capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout + r.stderr
    res = json.loads(out.read_text())
    for ax in ("x", "y", "z"):
        loop = res["loops"][ax]
        pts = loop["measured"]
        f = [p["frequency_rad_s"] for p in pts]
        assert len(pts) >= 5 and min(f) < loop["crossover_rad_s"] < max(f)
        for p in pts:
            assert abs(p["gain_db"] - p["predicted_gain_db"]) <= 1.0, p
            assert abs((p["phase_deg"] - p["predicted_phase_deg"] + 180) % 360 - 180) <= 5.0, p
        assert loop["law_residual"] < 1e-6
    v = res["gain_margin_verified"]
    assert v["verified"] and v["runs"][0]["converged"] and v["runs"][1]["diverged"]
    assert v["runs"][0]["loop_gain"] < 10 ** (res["loops"]["mimo"]["gain_margin_db"] / 20) < v["runs"][1]["loop_gain"]
    assert all((tmp_path / "runs" / "quat_pd" / n).is_file() for n in ("bode.png", "nichols.png"))


def test_a_model_with_the_wrong_delay_is_caught(private_netns, fsw_node_bin, aocs_lcm, tmp_path):
    sc = load("irassi_large")
    law = law_models.linear_law(sc, "quat_pd")
    p = loop_model.plant(sc, law.output)
    model = loop_model.loop(p, law, sc.dt, 1)             # predicts one period of delay ...
    w_c = analyze.margins.siso(loop_model.loop_at(model, 0))["crossover_rad_s"]
    _, pts = measure.measure_axis("irassi_large", sc, law, model, p, 0, w_c, 0, tmp_path)   # ... flown without
    err = [abs((q["phase_deg"] - q["predicted_phase_deg"] + 180) % 360 - 180) for q in pts]
    # the missing z^-1 is w dt of phase lag in l alone; with the other loops closed and the gain change it is
    # not exactly that, but far beyond the 5 deg bound at and above the crossover
    assert max(err) > 5.0 and np.mean(err) > 5.0
    assert max(err) <= math.degrees(max(q["frequency_rad_s"] for q in pts) * sc.dt) * 3
