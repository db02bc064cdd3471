"""`aocs compare` on a realistic-suite slew (irassi_small_mekf: star tracker and gyro through the MEKF, issue 20),
briefly, through real processes: every row's run JSON has the `estimation` section with the metric window's
knowledge, control and pointing error, the command prints them, and the figures hang together.

Independent checks: the knowledge error is recomputed here from the LCM log (truth against the logged
estimate, an angle computed with plain numpy), the pointing figure is the one the run's own pointing metric
gives over the same window, and the three errors obey the triangle inequality of rotation angles (pointing
<= knowledge + control, sample by sample, so for the rms and the max too), which fails if two of them were
swapped or taken against the wrong reference. The filter's accuracy is held against the analytic
(Farrenkopf) bound of the scenario's sensors, computed here."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from test_compare import aocs_compare, by_row

from aocs_analysis import estimation_bounds
from aocs_wire import lcmlog

AS_PER_RAD = 180.0 / math.pi * 3600.0
DURATION_S = 80.0     # the small slew settles in 14-23 s for these laws; the last 80 s window is the metric window


def _angle_arcsec(q_a, q_b) -> np.ndarray:
    """Rotation angle between two attitude histories (n, 4), scalar last: 2 atan2(|vec e|, |e4|) of
    e = q_a (x) q_b^-1 (the angle is the same whichever product convention), well conditioned near 0."""
    a, b = np.asarray(q_a, float), np.asarray(q_b, float)
    av, a4, bv, b4 = a[:, :3], a[:, 3], -b[:, :3], b[:, 3]
    ev = a4[:, None] * bv + b4[:, None] * av + np.cross(av, bv)
    e4 = a4 * b4 - np.sum(av * bv, axis=1)
    return 2.0 * np.arctan2(np.linalg.norm(ev, axis=1), np.abs(e4)) * AS_PER_RAD


@pytest.fixture(scope="module")
def small_mekf(tmp_path_factory):
    return aocs_compare(tmp_path_factory.mktemp("small_mekf"), "irassi_small_mekf", "--laws", "quat_pid,smc",
                        "--duration", str(DURATION_S))


def test_a_realistic_suite_slew_reports_knowledge_control_and_pointing(small_mekf):
    ms, stdout, out = small_mekf
    rows = by_row(ms)
    assert set(rows) == {"quat_pid", "smc"}
    assert "attitude knowledge (truth - estimate)" in stdout
    for name in ("quat_pid", "smc"):
        assert re.search(rf"^{name}\s+\d", stdout.split("attitude knowledge")[1], re.M), stdout
    # the analytic bound of the scenario's suite: 1 arcsec cross-boresight (x, y), 8 arcsec about it (z), 10 Hz,
    # gyro ARW 1.45e-6 rad/s^0.5, RRW 1e-10 rad/s^1.5, updated every 0.1 s control period
    bound = math.sqrt(sum(estimation_bounds.farrenkopf(n / AS_PER_RAD, 1.45e-6, 1.0e-10, 0.1).attitude_post_arcsec ** 2
                          for n in (1.0, 1.0, 8.0)))
    for name, m in rows.items():
        assert m["verdict"]["passed"], name
        e = m["estimation"]
        mw = e["metric_window"]
        k, c, p = mw["knowledge_arcsec"], mw["control_arcsec"], mw["pointing_arcsec"]
        assert mw["window_s"] == pytest.approx(DURATION_S) and mw["samples"] >= 0.95 * DURATION_S * 10
        # the knowledge error, recomputed from the log over the same window (est_status 0 = a valid estimate)
        log = lcmlog.read(out / name / "run.lcmlog")
        tr, cmd = log.truth, log.cmd
        idx = {int(t): i for i, t in enumerate(tr["tick"])}
        pairs = [(idx[int(t)], j) for j, t in enumerate(cmd["tick"]) if int(t) in idx and cmd["est_status"][j] == 0]
        it, ic = (np.array(x) for x in zip(*pairs))
        t = tr["t_s"][it]
        w = t >= t[-1] - DURATION_S
        ke = _angle_arcsec(tr["q"][it][w], cmd["q_est"][ic][w])
        assert k["rms"] == pytest.approx(math.sqrt(np.mean(ke ** 2)), rel=1e-6)
        assert k["max"] == pytest.approx(ke.max(), rel=1e-6)
        # a filter doing its job: near the analytic steady state of its sensors (80 s: about 8 correlation times
        # of the about-boresight error, hence the wide band), never over-confident
        assert 0.6 * bound < k["rms"] < 1.5 * bound, (k, bound)
        assert e["three_sigma_fraction"] >= 0.98
        # the pointing max is the run's own pointing metric over the same window (true angle, truth vs target)
        assert p["max"] == pytest.approx(m["pointing_error_arcsec"]["final_max"], rel=1e-9)
        # triangle inequality of rotation angles: truth-ref <= (truth-est) + (est-ref)
        assert p["rms"] <= k["rms"] + c["rms"] + 1e-9 and p["max"] <= k["max"] + c["max"] + 1e-9
        # the laws fly the estimate: no better than the knowledge allows at low frequency
        assert p["rms"] > 0.5 * k["rms"]
    report = (out / "report.md").read_text()
    assert "Attitude knowledge, control and pointing error" in report

