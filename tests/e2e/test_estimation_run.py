"""A run that flies the MEKF (irassi_hold_mekf, shortened): the run JSON's `estimation` section, under the names
scripts look for, and figures that would be wrong if the filter, the wire or the metrics were (issue 20).

The knowledge error is checked against the analytic steady state of the run's own sensors (Farrenkopf, as
aocs_analysis.estimation_bounds computes it independently of the filter) over the last half of a 1000 s hold.
The about-boresight axis' error wanders slowly (the bias it leans on), so a 200 s half gave 0.78 of its bound
once; over 500 s the three axes were 0.97, 0.97, 1.08 of it (the seed is fixed: the figures do not move
between runs), and the 15 % band fails only on a real disagreement."""
from __future__ import annotations

import json
import math

import pytest

from aocs import cli
from aocs_analysis import estimation_bounds


def test_a_hold_on_the_mekf_knows_its_attitude_as_the_sensors_allow(tmp_path):
    out = tmp_path / "hold"
    assert cli.main(["run", "irassi_hold_mekf", "--duration", "1000", "--out", str(out), "-q"]) == 0
    m = json.loads((out / "metrics.json").read_text())
    e = m["estimation"]
    ke = e["knowledge_error_arcsec"]
    assert ke["frame"] == "B" and len(ke["rms_per_axis"]) == 3 and ke["max"] >= max(ke["rms_per_axis"])
    st, gy = e["sensors"]["star_tracker"], e["sensors"]["gyro"]
    assert (st["noise_cross_arcsec"], st["noise_about_arcsec"], st["rate_hz"]) == (1.0, 8.0, 10.0)
    assert (gy["arw_rad_sqrt_s"], gy["rrw_rad_s_sqrt_s"]) == (1.45e-6, 1.0e-10)
    # the bound, computed here from the scenario's figures (boresight on z_B: cross on x, y, about on z)
    ss = estimation_bounds.farrenkopf
    dt = 0.1
    bound = [ss(n / estimation_bounds.ARCSEC_PER_RAD, 1.45e-6, 1.0e-10, dt).attitude_post_arcsec
             for n in (1.0, 1.0, 8.0)]
    assert e["steady_state_bound_arcsec"] == pytest.approx(bound, rel=1e-6)
    for rms, b in zip(ke["rms_per_axis"], bound):
        assert 0.85 * b < rms < 1.15 * b, (ke["rms_per_axis"], bound)
    assert 0.99 <= e["three_sigma_fraction"] <= 0.9995
    # the laws fly the estimate: the true pointing is no better than the knowledge allows, and is bounded by it
    assert e["pointing_error_arcsec"]["rms"] > 0.5 * e["knowledge_error_arcsec"]["rms"]
    for name in ("knowledge_error.png", "bias_estimate.png", "nees.png"):
        assert (out / name).stat().st_size > 10_000, name
    # a reference scenario flies no filter and has no section
    ref = tmp_path / "ref"
    assert cli.main(["run", "irassi_small", "--duration", "5", "--out", str(ref), "-q", "--no-plots"]) == 0
    assert json.loads((ref / "metrics.json").read_text())["estimation"] is None


# (star tracker cross-boresight 1-sigma arcsec (about: 8 times it), gyro ARW rad/s^0.5, RRW rad/s^1.5, tracker Hz):
# a navigation-grade gyro (the scenario's) and a tactical-grade one (0.15 deg/h^0.5), 1 and 5 arcsec trackers, at
# the 10 Hz control rate and at 2 Hz (the bound then is the rms over the update cycle, estimation_bounds)
SENSOR_SETS = [(1.0, 1.45e-6, 1.0e-10, 10.0), (5.0, 1.45e-6, 1.0e-10, 10.0), (1.0, 4.4e-5, 1.0e-8, 10.0),
               (5.0, 4.4e-5, 1.0e-8, 2.0), (1.0, 1.45e-6, 1.0e-10, 2.0)]


@pytest.mark.parametrize("cross,arw,rrw,rate", SENSOR_SETS)
def test_the_knowledge_error_is_the_analytic_steady_state_within_ten_percent(tmp_path, cross, arw, rrw, rate):
    """Issue 20's first acceptance figure: the measured 1-sigma knowledge error per axis within 10 % of the
    Farrenkopf steady state of the run's sensors, for every sensor set (measured at 0.93 to 1.08)."""
    out = tmp_path / "run"
    sets = {"sensors.star_tracker.noise_cross_arcsec": cross, "sensors.star_tracker.noise_about_arcsec": 8 * cross,
            "sensors.gyro.arw_rad_sqrt_s": arw, "sensors.gyro.rrw_rad_s_sqrt_s": rrw,
            "sensors.star_tracker.rate_hz": rate}
    argv = ["run", "irassi_hold_mekf", "--duration", "1000", "--out", str(out), "-q", "--no-plots"]
    for k, v in sets.items():
        argv += ["--set", f"{k}={v!r}"]
    assert cli.main(argv) == 0
    e = json.loads((out / "metrics.json").read_text())["estimation"]
    assert e["sensors"]["star_tracker"]["rate_hz"] == rate and e["sensors"]["gyro"]["arw_rad_sqrt_s"] == arw
    for ratio in e["knowledge_rms_over_bound"]:
        assert 0.9 <= ratio <= 1.1, e["knowledge_rms_over_bound"]
    # never over-confident (a filter whose P is too small drops below 0.99; 0.9973 for a Gaussian error); the
    # 5 arcsec tracker's slower error gave 0.9991 over this 500 s window
    assert e["three_sigma_fraction"] >= 0.99


def _run(tmp_path, name, duration, sets, seed=0):
    out = tmp_path / name
    argv = ["run", "irassi_hold_mekf", "--duration", str(duration), "--out", str(out), "-q", "--no-plots",
            "--set", f"seed={seed}"]
    for k, v in sets.items():
        argv += ["--set", f"{k}={v}"]
    assert cli.main(argv) == 0
    return json.loads((out / "metrics.json").read_text())["estimation"], out


BIAS_1DEG_H = math.radians(1.0) / 3600.0   # rad/s


def _predicted_time_s(e0_att_rad, bias_radps, window_s=30.0, k=1.5):
    """The stated convergence time, computed here (independently of aocs_analysis.estimation_transients) from
    the per-axis two-state filter of the hold's sensors (1 / 8 arcsec tracker at 10 Hz, ARW 1.45e-6, RRW 1e-10),
    P0 = 1 deg, 1 deg/h: the expected squared error m_a^2 + N_aa, its trailing mean over window_s inside
    k times the steady state (the rms over an update cycle; the tracker at the control rate: the post value)."""
    import numpy as np
    dt, sv, su = 0.1, 1.45e-6, 1.0e-10
    phi = np.array([[1.0, -dt], [0.0, 1.0]])
    q = np.array([[sv ** 2 * dt + su ** 2 * dt ** 3 / 3, -su ** 2 * dt ** 2 / 2], [-su ** 2 * dt ** 2 / 2, su ** 2 * dt]])
    steps, w = 3000, int(round(window_s / dt))
    t_in = 0.0
    for axis, sn_as in enumerate((1.0, 1.0, 8.0)):
        r = (sn_as / estimation_bounds.ARCSEC_PER_RAD) ** 2
        p = np.diag([math.radians(1.0) ** 2, BIAS_1DEG_H ** 2])
        m = np.array([e0_att_rad[axis], bias_radps[axis]])
        n = np.zeros((2, 2))
        sq = []
        for kk in range(steps):
            if kk:
                p, n, m = phi @ p @ phi.T + q, phi @ n @ phi.T + q, phi @ m
            g = p[:, :1] / (p[0, 0] + r)
            a = np.eye(2) - g @ np.array([[1.0, 0.0]])
            p, n, m = a @ p @ a.T + r * g @ g.T, a @ n @ a.T + r * g @ g.T, a @ m
            sq.append(m[0] ** 2 + n[0, 0])
        ss = estimation_bounds.farrenkopf(math.sqrt(r), sv, su, dt).attitude_post
        c = np.cumsum(np.r_[0.0, sq])
        lo = np.maximum(np.arange(1, steps + 1) - w, 0)
        rms = np.sqrt((c[1:] - c[lo]) / (np.arange(1, steps + 1) - lo))
        outside = np.flatnonzero(rms > k * ss)
        t_in = max(t_in, 0.0 if outside.size == 0 else (outside[-1] + 1) * dt)
    return t_in


def test_from_a_1_deg_error_and_an_unknown_1_deg_per_h_bias_the_filter_converges_in_the_stated_time(tmp_path):
    """Issue 20's convergence: the filter started (mekf.init_mode = configured) at the true attitude turned by
    1 deg, the gyro's bias 1 deg/h on every axis, unknown (prior 0): the knowledge error's 30 s rms per axis
    enters 3 times the steady state for good within the stated time, the expected rms of the filter's own
    gains inside 1.5 times (computed here: 35.6 s for these sensors); 3 seeds."""
    e0 = [math.radians(1.0) / math.sqrt(3.0)] * 3
    sets = {"estimator.init_mode": '"configured"', "estimator.init_error_deg": "[%r, %r, %r]" % tuple(
        math.degrees(x) for x in e0), "sensors.gyro.bias_rad_s": "[%r, %r, %r]" % ((BIAS_1DEG_H,) * 3)}
    stated = _predicted_time_s(e0, [BIAS_1DEG_H] * 3)
    assert 10.0 < stated < 60.0, stated
    for seed in (0, 1, 2):
        e, _ = _run(tmp_path, f"conv{seed}", 300, sets, seed)
        c = e["transients"]["convergence"]
        # the run's own start: the configured error and the true bias, as the scenario set them
        assert c["start"]["e0_att_B_rad"] == pytest.approx(e0, abs=2e-5)
        assert c["start"]["e0_bias_B_radps"] == pytest.approx([BIAS_1DEG_H] * 3, rel=1e-3)
        assert c["predicted_time_s"] == pytest.approx(stated, abs=0.15)
        assert c["time_s"] is not None and c["time_s"] <= stated, c
        # the configured start is 1 deg off: the run's first estimate was not the tracker's
        assert e["samples"]["valid"] >= 2999


def test_a_600_s_star_tracker_outage_stays_inside_3_sigma_and_recovers_within_60_s(tmp_path):
    """Issue 20's outage: the tracker gone for 600 s of a hold (sensors.star_tracker.outages): the knowledge
    error stays inside the filter's own growing 3 sigma, and within 60 s of the tracker's return the filter's
    sigma is back within 1.1 of the steady state and the error's 30 s rms within 3 times it for good; over
    the 200 s after those 60 s the rms is the steady state's (within 0.7 to 1.3)."""
    e, _ = _run(tmp_path, "outage", 1600, {"sensors.star_tracker.outages": "[[600.0, 1200.0]]"})
    (o,) = e["transients"]["outages"]
    assert (o["start_s"], o["end_s"]) == (600.0, 1200.0)
    # a consistent filter's error crosses 3 sigma rarely (0.27 % of independent samples; this seed: never, the
    # largest 0.94 of it): at least 99 % inside, none beyond 3.5 sigma (the firmware test's rule)
    assert o["inside_3sigma_fraction"] >= 0.99 and o["max_ratio_to_3sigma"] <= 3.5 / 3.0, o
    # the 3 sigma did grow (from about 1 arcsec to tens: the gyro alone for 600 s)
    assert min(o["three_sigma_at_end_arcsec"]) > 10.0 * 3.0 * max(o["bound_S_arcsec"][:2])
    assert o["recovery_time_s"] is not None and o["recovery_time_s"] <= 60.0, o
    for ratio in o["rms_over_bound"]:
        assert 0.7 <= ratio <= 1.3, o["rms_over_bound"]


def test_the_2000_s_hold_is_consistent(tmp_path):
    """Issue 20's consistency on irassi_hold_mekf as it is (2000 s, seed 0): the +-3 sigma fraction in [99 %,
    99.9 %]; the attitude NEES windows, spaced by the slowest error component's correlation time (the
    about-boresight axis, about 9 s; docs/spec.md 5.7), inside their 95 % band for at least 95 % of the windows
    (measured 0.962; the old spacing, by the NEES's own shorter time, gave 0.935); the 6-dof NEES has no
    fraction in one run, and says why: the bias error decorrelates in hours (sigma_v / sigma_u = 1.45e4 s)."""
    e, _ = _run(tmp_path, "hold", 2000, {})
    assert 0.99 <= e["three_sigma_fraction"] <= 0.999
    na = e["nees_attitude"]
    assert na["spacing_s"] >= 2.0 * 8.0 and na["independent_windows"] >= 5
    assert e["nees_attitude_in_band_fraction"] >= 0.95
    assert e["nees_attitude"]["mean"] == pytest.approx(3.0, rel=0.1)
    assert e["nees_in_band_fraction"] is None and "autocorrelation" in e["nees"]["none_because"]
    assert e["nees"]["mean"] == pytest.approx(6.0, rel=0.15)


def _nees6_of_run(out):
    """The 6-dof NEES per control step of a run, from its log: the truth and the estimate of the same tick."""
    import numpy as np

    from aocs_analysis import estimation as E
    from aocs_wire import lcmlog
    log = lcmlog.read(out / "run.lcmlog")
    tr, cmd = log.truth, log.cmd
    rows = {int(k): i for i, k in enumerate(tr["tick"])}
    it, ic = (np.asarray(x, dtype=np.int64) for x in zip(*[(rows[int(k)], j) for j, k in enumerate(cmd["tick"])
                                                          if int(k) in rows]))
    dth = E.knowledge_error_rad(tr["q"][it], cmd["q_est"][ic])
    eps = E.nees_full(dth, cmd["bias_est"][ic], tr["gyro_bias"][it], E.covariance_from_upper(cmd["est_p"][ic]))
    eps[cmd["est_status"][ic] != 0] = np.nan
    return tr["t_s"][it], eps


def test_the_6_dof_nees_of_an_ensemble_of_holds_is_consistent(tmp_path):
    """Issue 20's consistency for the whole error state (attitude and bias), which one run cannot test (the bias
    error decorrelates in hours): Bar-Shalom's Monte Carlo test over 6 seeds of the hold (1000 s each), the
    ensemble mean NEES at every instant of the last half inside its 95 % band chi2(36) / 6 for at least 90 %
    of the instants (a consistent filter: about 95 %, with the scatter of an ensemble correlated in time)."""
    import numpy as np

    from aocs_analysis import estimation as E
    runs = []
    for seed in range(1, 7):
        _, out = _run(tmp_path, f"ens{seed}", 1000, {}, seed)
        t, eps = _nees6_of_run(out)
        runs.append(eps[t >= 500.0])
    n = min(len(r) for r in runs)
    res = E.nees_ensemble_test(np.array([r[:n] for r in runs]), 6)
    print(f"ensemble NEES (6 dof, 6 runs x 500 s): {res['in_band_fraction']:.3f} of {res['instants']} instants in "
          f"[{res['band'][0]:.2f}, {res['band'][1]:.2f}], mean {res['mean']:.2f}")
    assert res["instants"] >= 4900
    assert res["in_band_fraction"] >= 0.9 and res["mean"] == pytest.approx(6.0, rel=0.15), res
