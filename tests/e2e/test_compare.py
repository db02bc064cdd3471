"""`aocs compare` over the reference scenarios, through real processes.

Every comparison below is `python -m aocs.cli compare ...` in a subprocess:
it re-executes itself in a private network namespace and runs each law in
its own SIL run (plant_node + fsw_node + recorder). Expected values are
computed here from the scenario files, the compiled gain tables and the LCM
logs, independently of the comparison's own arithmetic.
"""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from aocs_wire import lcmlog

REPO = Path(__file__).resolve().parents[2]
GAINS_C = REPO / "firmware" / "gains" / "aocs_gains.c"
SCEN = REPO / "sil" / "scenarios"
AS_PER_RAD = 180.0 / math.pi * 3600.0
#: measured final error / d-over-kp estimate must be within this factor (stated in the report)
STEADY_FACTOR = 1.10


def aocs_compare(tmp: Path, *args: str) -> tuple[list[dict], str, Path]:
    out = tmp / "cmp"
    js = tmp / "cmp.json"
    tmp.mkdir(parents=True, exist_ok=True)
    bin_dir = Path(os.environ.get("AOCS_BUILD_DIR", REPO / "build" / "host")) / "bin" / "fsw_node"
    if not bin_dir.is_file():
        pytest.fail(f"fsw_node missing at {bin_dir}: build it first (cmake --preset host && cmake --build --preset host)")
    p = subprocess.run([sys.executable, "-m", "aocs.cli", "compare", *args, "--out", str(out), "--json", str(js),
                        "-q"], cwd=tmp, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stdout + p.stderr
    return json.loads(js.read_text()), p.stdout, out


def by_row(ms: list[dict]) -> dict:
    return {m["row"]: m for m in ms}


def k_diag(table: str) -> np.ndarray:
    """Attitude block of a compiled K table, parsed here from the C source."""
    body = re.search(r"aocs_gains_" + table + r"_K\[3\]\[6\] = \{(.*?)\};", GAINS_C.read_text(), re.S).group(1)
    k = np.array([float(x) for x in re.findall(r"AOCS_R\(([^)]*)\)", body)]).reshape(3, 6)
    return np.diag(k[:, :3])


# --------------------------------------------------------------------------- irassi_small, every law
@pytest.fixture(scope="module")
def irassi_small(tmp_path_factory):
    return aocs_compare(tmp_path_factory.mktemp("irassi_small"), "irassi_small")


def test_irassi_small_reference_gains_reach_0_3_arcsec_except_lqr_ref(irassi_small):
    ms, _, _ = irassi_small
    rows = by_row(ms)
    assert set(rows) == {"quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc", "lqr_quat-lqr_quat_ref",
                         "lqr_quat-lqr_quat_strong", "quat_pid", "lqr_quat_i-lqr_quat_i_ref"}
    for name in ("quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc", "lqr_quat-lqr_quat_strong", "quat_pid",
                 "lqr_quat_i-lqr_quat_i_ref"):
        pe = rows[name]["pointing_error_arcsec"]
        assert pe["final_max"] <= 0.3, (name, pe)
        assert pe["meets_requirement"] is True
    ref = rows["lqr_quat-lqr_quat_ref"]["pointing_error_arcsec"]
    assert ref["final_max"] > 0.3 and ref["meets_requirement"] is False
    # the right gain tables ran: the ref table commands far less torque than the strong one
    assert rows["lqr_quat-lqr_quat_ref"]["max_torque_norm_nm"] < rows["lqr_quat-lqr_quat_strong"]["max_torque_norm_nm"]


def test_irassi_small_report_explains_why_lqr_ref_misses(irassi_small):
    ms, _, out = irassi_small
    report = (out / "report.md").read_text()
    toml = tomllib.loads((SCEN / "irassi_small.toml").read_text())
    d = np.array(toml["disturbances"]["constant_torque"]["torque_nm"])
    k = k_diag("lqr_quat_ref")
    assert np.allclose(k, math.sqrt(200.0 / 0.001), rtol=1e-9)   # LQR with Q = q I, R = r I: kp = sqrt(q/r)
    est = 2.0 * math.asin(float(np.linalg.norm(d / k))) * AS_PER_RAD
    meas = by_row(ms)["lqr_quat-lqr_quat_ref"]["pointing_error_arcsec"]["final_max"]
    assert 1.0 / STEADY_FACTOR < meas / est < STEADY_FACTOR, (meas, est)
    assert est > 0.3
    assert "no integral action" in report
    assert "constant disturbance / proportional gain" in report
    assert f"{est:.4g}" in report and f"{k[0]:.6g}" in report
    line = next(ln for ln in report.splitlines() if ln.startswith("| lqr_quat-lqr_quat_ref |"))
    assert f"{est:.4g}" in line and "NO" in line


def test_compare_writes_every_promised_file(irassi_small):
    ms, stdout, out = irassi_small
    for f in ("report.md", "compare.json", "pointing_error.png", "torque_norm.png"):
        assert (out / f).is_file() and (out / f).stat().st_size > 0, f
    for f in ("pointing_error.png", "torque_norm.png"):
        assert (out / f).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert (out / f).stat().st_size < 150_000
    assert json.loads((out / "compare.json").read_text()) == ms
    report = (out / "report.md").read_text()
    assert "](pointing_error.png)" in report and "](torque_norm.png)" in report
    for m in ms:
        run = out / m["row"]
        assert (run / "run.lcmlog").is_file() and (run / "metrics.json").is_file()
        # the table shows each run's measured final error, from its own log
        log = lcmlog.read(run / "run.lcmlog")
        t = log.truth["t_s"]
        last = log.truth["pointing_err_arcsec"][t >= t[-1] - 100.0 - 1e-9]
        assert m["pointing_error_arcsec"]["final_max"] == pytest.approx(float(np.max(last)), rel=1e-6, abs=1e-9)
        assert m["row"] in stdout and f"| {m['row']} |" in report
    for col in ("final max as", "qe_arcsec max", "settle s", "max norm u N m", "effort", "sat s",
                "step ns med/p99/budget", "overruns", "0.3 as", "0.05 as"):
        assert col in stdout and col in report


# --------------------------------------------------------------------------- gao_mrp
def test_gao_mrp_never_exceeds_uM(tmp_path):
    ms, _, out = aocs_compare(tmp_path, "gao_mrp")
    um = 0.05
    assert {m["row"] for m in ms} == {"mrp_sat", "mrp_sat_tanh"}
    for m in ms:
        log = lcmlog.read(out / m["row"] / "run.lcmlog")
        assert log.cmd["tick"].size == 15000
        u = np.linalg.norm(log.cmd["u_sat"], axis=1)
        ua = np.linalg.norm(log.truth["torque_applied"], axis=1)
        assert np.max(u) <= um and np.max(ua) <= um, (m["row"], np.max(u), np.max(ua))
        assert np.max(u) > 0.2 * um                     # the bound is exercised, not trivially met
        assert m["max_torque_norm_nm"] == pytest.approx(float(np.max(u)), rel=1e-12)
        assert m["settle_time_s"] is not None


# --------------------------------------------------------------------------- landsat8 Q ordering
def _settle(t, pos, vel):
    inside = np.all(np.abs(pos) < 0.1, axis=1) & np.all(np.abs(vel) < 0.01, axis=1)
    out = np.nonzero(~inside)[0]
    return None if out.size and out[-1] == t.size - 1 else float(t[out[-1] + 1] if out.size else t[0])


def test_landsat8_settles_fastest_with_q10_slowest_with_q01(tmp_path):
    settle = {}
    for sid in ("landsat8_q10", "landsat8_q1", "landsat8_q01"):
        ms, _, out = aocs_compare(tmp_path / sid, sid, "--duration", "1500")
        (m,) = ms
        log = lcmlog.read(out / m["row"] / "run.lcmlog")
        own = _settle(log.truth["t_s"], log.truth["pos"], log.truth["vel"])
        assert own is not None and m["settle_time_s"] == pytest.approx(own, abs=1e-9), (sid, own, m)
        settle[sid] = own
    assert settle["landsat8_q10"] < settle["landsat8_q1"] < settle["landsat8_q01"], settle


# --------------------------------------------------------------------------- geo_hinf measured gain
def test_geo_hinf_measured_disturbance_to_output_gain_below_gamma(tmp_path):
    """Measured gain = L2(z) / L2(d) over the run, z = 1e-3 M q'' (SPEC 2.6), d = logged disturbance torque,
    from a run started on the LVLH frame (zero initial error: only d drives z). q'' is taken here as the
    finite difference of the true body rate (w - wd differs from q' by terms of order w0 * angle)."""
    from aocs_compare import results_doc as cmd_results
    from aocs_plant.scenario import load

    ms, _, out = aocs_compare(tmp_path, "geo_hinf", "--laws", "hinf:hinf_regional",
                              "--set", "plant.euler321_deg=[0.0, 0.0, 0.0]",
                              "--set", "plant.w0=[0.0, -7.292115e-05, 0.0]")
    (m,) = ms
    text = GAINS_C.read_text()
    blk = text[text.index(" * hinf_regional: "):]
    gamma = float(re.search(r"gamma = ([0-9.eE+-]+)", blk[:blk.index("*/")]).group(1))
    assert 1.0e-3 < gamma < 1.1e-3
    log = lcmlog.read(out / m["row"] / "run.lcmlog")
    dt = 0.1
    toml = tomllib.loads((SCEN / "geo_hinf.toml").read_text())
    mdiag = np.diag(np.array(toml["plant"]["inertia"]))
    w = log.truth["w"]
    z = 1e-3 * mdiag * np.diff(w, axis=0) / dt
    d = log.truth["torque_dist"][:-1]
    gain = float(np.sqrt(np.sum(z ** 2)) / np.sqrt(np.sum(d ** 2)))
    assert 0.0 < gain < gamma, (gain, gamma)
    assert np.max(np.abs(d)) > 0.9e-4                       # the 1e-4 N m disturbance was applied
    # the results page's figure (3-2-1 angles, second differences) agrees with this one
    mine = cmd_results.hinf_measured_gain(lcmlog.read(out / m["row"] / "run.lcmlog"),
                                          load("geo_hinf", {"plant.euler321_deg": [0.0, 0.0, 0.0]}))
    assert mine["gain"] == pytest.approx(gain, rel=0.1)
    assert cmd_results.designed_gamma("hinf_regional") == gamma


def test_hinf_sweep_measures_the_design_gain_below_gamma(tmp_path):
    """`aocs compare geo_hinf --sweep` at two frequencies: the SIL loop's measured gain in the sweep
    direction is the design's |Gzd(jw) e| (within 5 %; the issue asks a factor 2) and never above gamma."""
    out = tmp_path / "sweep"
    res = subprocess.run([sys.executable, "-m", "aocs.cli", "compare", "geo_hinf", "--sweep", "--freqs", "0.1,1",
                          "--out", str(out), "-q", "--json", str(tmp_path / "s.json")],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    s = json.loads((tmp_path / "s.json").read_text())
    assert s["failed"] == 0 and s["within_factor_2"] and s["below_gamma"]
    for p in s["points"]:
        assert p["measured"] == pytest.approx(p["design"], rel=0.05), p
        assert p["measured"] <= s["gamma"] and p["design"] <= p["sigma_max"] * (1 + 1e-12)
    assert (out / "sweep.png").is_file() and "never above gamma: yes" in res.stdout


def test_hinf_run_reports_gamma_and_its_measured_gain(tmp_path):
    res = subprocess.run([sys.executable, "-m", "aocs.cli", "run", "geo_hinf", "-q", "--no-plots",
                          "--out", str(tmp_path / "r"), "--json", str(tmp_path / "m.json")],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    m = json.loads((tmp_path / "m.json").read_text())
    assert m["hinf"]["table"] == "hinf_regional" and m["hinf"]["gamma"] == pytest.approx(1.05e-3, rel=1e-3)
    assert 0.0 < m["hinf"]["measured"]["gain"] < m["hinf"]["gamma"]
    assert "gamma of K (hinf_regional)" in res.stdout
