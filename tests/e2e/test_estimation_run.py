"""A run that flies the MEKF (irassi_hold_mekf, shortened): the run JSON's `estimation` section, under the names
scripts look for, and figures that would be wrong if the filter, the wire or the metrics were (issue 20).

The knowledge error is checked against the analytic steady state of the run's own sensors (Farrenkopf, as
aocs_analysis.estimation_bounds computes it independently of the filter) over the last half of a 1000 s hold.
The about-boresight axis' error wanders slowly (the bias it leans on), so a 200 s half gave 0.78 of its bound
once; over 500 s the three axes were 0.97, 0.97, 1.08 of it (the seed is fixed: the figures do not move
between runs), and the 15 % band fails only on a real disagreement."""
from __future__ import annotations

import json

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
