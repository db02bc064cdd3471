"""Gain design tools (`aocs gains`): Riccati and LMI designs, checks, tables, --check, --json.

The H-infinity designs (two solvers each) take ~15 s; they are computed once
per session through the cached `generate` and shared by the tests below.
"""
from __future__ import annotations

import argparse
import json
import math
import re
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest

from aocs import cmd_gains
from aocs_design import checks, lmi_hinf, models, riccati

REPO = Path(__file__).resolve().parents[3]
J_IRASSI = [2059.5, 5954.2, 5974.3]
GEO = (1030.17, 3015.65, 3030.43, 7.292115e-5)


@pytest.fixture(scope="session")
def generated():
    designs, files = cmd_gains.generate(cmd_gains.DEFAULT_CONFIG)
    return {d.name: d for d in designs}, files


def _args(**kw):
    p = argparse.ArgumentParser()
    cmd_gains.add_arguments(p)
    a = p.parse_args([])
    for k, v in kw.items():
        setattr(a, k, v)
    return a


# ---- models (SPEC 2.5, 2.6, 2.8 written out by hand) ----

def test_orbit_model_matches_spec_equations():
    mu, r, m = 3.986004418e14, 7080e3, 2623.0
    a, b = models.orbit_model(m, r, mu)
    n = math.sqrt(mu / r**3)
    x = np.array([1.0, -2.0, 3.0, 40.0, -50.0, 60.0])
    du, dv, dw, dx, dy, dz = x
    expected = [n * dw - n**2 * dx, -n**2 * dy, -n * du + 2 * n**2 * dz, du + n * dz, dv, dw - n * dx]
    np.testing.assert_allclose(a @ x, expected, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(b[:3], np.eye(3) / m)
    np.testing.assert_array_equal(b[3:], 0.0)


def test_hinf_model_matches_spec_equations():
    ix, iy, iz, w0 = GEO
    p = models.hinf_model(ix, iy, iz, w0)
    x = np.array([0.1, -0.2, 0.3, 0.01, -0.02, 0.03])
    phi, th, psi, dphi, dth, dpsi = x
    acc = p.a @ x
    # Ix phi'' + 4 (Iy - Iz) w0^2 phi + (Iy - Iz - Ix) w0 psi' = 0, and so on (corrected yaw line)
    assert ix * acc[3] + 4 * (iy - iz) * w0**2 * phi + (iy - iz - ix) * w0 * dpsi == pytest.approx(0, abs=1e-18)
    assert iy * acc[4] + 3 * (ix - iz) * w0**2 * th == pytest.approx(0, abs=1e-18)
    assert iz * acc[5] + (iy - ix) * w0**2 * psi + (ix + iz - iy) * w0 * dphi == pytest.approx(0, abs=1e-18)
    np.testing.assert_array_equal(acc[:3], x[3:])
    # z = 1e-3 M q'' for any u, d: C1 x + D1 u + D2 d
    u, d = np.array([1.0, 2.0, 3.0]), np.array([-0.5, 0.1, 0.2])
    qdd = (p.a @ x + p.b1 @ u + p.b2 @ d)[3:]
    np.testing.assert_allclose(p.c1 @ x + p.d1 @ u + p.d2 @ d, 1e-3 * np.diag([ix, iy, iz]) @ qdd, rtol=1e-13)
    # open loop: pitch unstable (Ix < Iz)
    assert np.max(np.linalg.eigvals(p.a).real) > 0


# ---- Riccati ----

def test_lqr_quat_i_model_matches_spec_equations():
    # SPEC 5.2: z' = qe_vec, qe_vec' = 0.5 we, J we' = u
    a, b = models.lqr_quat_i_model(J_IRASSI)
    x = np.array([1.0, -2.0, 3.0, 0.1, -0.2, 0.3, 0.01, -0.02, 0.03])
    u = np.array([1.0, 2.0, -3.0])
    xdot = a @ x + b @ u
    np.testing.assert_array_equal(xdot[0:3], x[3:6])
    np.testing.assert_allclose(xdot[3:6], 0.5 * x[6:9], rtol=1e-15)
    np.testing.assert_allclose(np.asarray(J_IRASSI) * xdot[6:9], u, rtol=1e-15)


@pytest.mark.parametrize("name", ["lqr_quat_ref", "lqr_quat_strong", "orbit_lqr_q1", "orbit_lqr_q01",
                                  "orbit_lqr_q10", "lqr_quat_i_ref", "lqr_quat_i_suite",
                                  "lqr_quat_i_rw_suite"])
def test_are_solution_satisfies_equation(generated, name):
    d = generated[0][name]
    s = d.s
    res = d.a.T @ s + s @ d.a - s @ d.b @ np.linalg.inv(d.r) @ d.b.T @ s + d.q
    assert np.linalg.norm(res, 2) <= 1e-12 * np.linalg.norm(s, 2) * np.linalg.norm(d.a, 2) + 1e-12 * np.linalg.norm(d.q, 2)
    assert np.max(np.linalg.eigvals(d.a - d.b @ d.k).real) < 0


@pytest.mark.parametrize("name", ["lqr_quat_ref", "lqr_quat_strong", "orbit_lqr_q1", "orbit_lqr_q01",
                                  "orbit_lqr_q10", "lqr_quat_i_ref", "lqr_quat_i_suite",
                                  "lqr_quat_i_rw_suite"])
def test_k_equals_python_control_lqr(generated, name):
    import control

    d = generated[0][name]
    k, _, _ = control.lqr(d.a, d.b, d.q, d.r)
    np.testing.assert_allclose(d.k, k, rtol=1e-9, atol=1e-9 * np.max(np.abs(k)))


@pytest.mark.parametrize("name,q,r", [("lqr_quat_ref", 200.0, 1e-3), ("lqr_quat_strong", 2000.0, 1e-5)])
def test_lqr_quat_closed_form(generated, name, q, r):
    # decoupled per axis: K = [sqrt(q/r), sqrt((J sqrt(q r) + q) / r)] (2x2 ARE by hand)
    k = generated[0][name].k
    expected = np.zeros((3, 6))
    for i, j in enumerate(J_IRASSI):
        expected[i, i] = math.sqrt(q / r)
        expected[i, i + 3] = math.sqrt((j * math.sqrt(q * r) + q) / r)
    np.testing.assert_allclose(k, expected, rtol=1e-12, atol=1e-12 * np.max(expected))


def test_uncontrollable_lqr_is_rejected():
    a, b = models.lqr_quat_model(J_IRASSI)
    b[5, :] = 0.0   # zero row: the yaw axis has no actuator
    with pytest.raises(checks.UncontrollableError, match=r"not controllable.*rank 4 < 6"):
        riccati.lqr("bad", "lqr_quat", a, b, np.eye(6), np.eye(3))


def test_lqr_refuses_an_r_not_positive_definite_and_a_q_not_semidefinite():
    a, b = models.lqr_quat_model(J_IRASSI)
    q = np.eye(6)
    # R singular (its smallest eigenvalue exactly 0) or indefinite: refused before the solver
    for r in (np.diag([1.0, 1.0, 0.0]), np.diag([1.0, -1e-3, 1.0])):
        with pytest.raises(checks.DesignError, match="R is not positive definite"):
            riccati.lqr("bad", "lqr_quat", a, b, q, r)
    # Q with a negative eigenvalue, however small: refused
    with pytest.raises(checks.DesignError, match="Q is not positive semidefinite"):
        riccati.lqr("bad", "lqr_quat", a, b, np.diag([1.0, 1.0, 1.0, 1.0, 1.0, -1e-9]), np.eye(3))
    # Q semidefinite with eigenvalues exactly 0 (the rates unweighted; the attitude weight still makes the pair
    # detectable): accepted, and the closed loop is stable
    d = riccati.lqr("ok", "lqr_quat", a, b, np.diag([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]), np.eye(3))
    assert d.slowest_pole_re < 0.0


def test_uncontrollable_hinf_is_rejected():
    ix, iy, iz, w0 = GEO
    p = models.hinf_model(ix, iy, iz, w0)
    b1 = p.b1.copy()
    b1[3:, 1] = 0.0    # no pitch torque: the unstable pitch mode cannot be reached
    bad = models.HinfPlant(p.a, b1, p.b2, p.c1, p.d1, p.d2)
    with pytest.raises(checks.UncontrollableError, match="not controllable"):
        lmi_hinf.design("bad", bad, alpha=None, alpha_sel=0.01, delta=0.05, k_rtol=1e-3)


# ---- H-infinity LMI ----

@pytest.mark.parametrize("name", ["hinf_min", "hinf_regional", "hinf_bounded"])
def test_lmi_satisfied_at_emitted_gain(generated, name):
    d = generated[0][name]
    w = d.k @ d.x
    m = lmi_hinf.assemble_lmi(d.plant, d.x, w, d.gamma)
    assert np.max(np.linalg.eigvalsh(m)) < 0
    assert np.min(np.linalg.eigvalsh(d.x)) > 0
    dec = lmi_hinf.assemble_decay(d.plant, d.x, w, d.alpha_sel)
    assert np.max(np.linalg.eigvalsh(dec)) < 0
    # the same matrix at a gamma below |D2| = 1e-3 cannot be negative definite
    assert np.max(np.linalg.eigvalsh(lmi_hinf.assemble_lmi(d.plant, d.x, w, 0.9e-3))) > 0


@pytest.mark.parametrize("name", ["hinf_min", "hinf_regional", "hinf_bounded"])
def test_gamma_agrees_with_independent_norm(generated, name):
    d = generated[0][name]
    a, b, c, dd = lmi_hinf.closed_loop(d.plant, d.k)
    # independent of the LMI and of the tool's own bisection: dense sweep
    ws = np.logspace(-6, 3, 3000)
    peak = max(np.linalg.svd(c @ np.linalg.solve(1j * w * np.eye(6) - a, b) + dd, compute_uv=False)[0]
               for w in ws)
    assert peak <= d.hinf_norm * (1 + 1e-9)
    assert d.hinf_norm <= d.gamma * (1 + 1e-9)
    assert d.hinf_norm >= 1e-3 * (1 - 1e-12)         # every stabilising K: >= |D2|
    # minimum designs: the norm is within the selection factor of gamma* (not just below gamma)
    assert d.hinf_norm <= d.gamma_star * (1 + d.delta)
    assert d.gamma == pytest.approx((1 + d.delta) * d.gamma_star, rel=1e-12)
    assert abs(d.hinf_norm - d.gamma) / d.gamma <= d.delta


def test_hinf_norm_against_known_system():
    # G(s) = 1 / (s^2 + 2 z s + 1): ||G||inf = 1 / (2 z sqrt(1 - z^2)) for z < 1/sqrt 2
    z = 0.1
    a = np.array([[0.0, 1.0], [-1.0, -2 * z]])
    b = np.array([[0.0], [1.0]])
    c = np.array([[1.0, 0.0]])
    r = checks.hinf_norm(a, b, c, np.zeros((1, 1)))
    assert r["norm"] == pytest.approx(1 / (2 * z * math.sqrt(1 - z * z)), rel=1e-8)


@pytest.mark.parametrize("name", ["hinf_min", "hinf_regional", "hinf_bounded"])
def test_clarabel_and_scs_agree(generated, name):
    d = generated[0][name]
    rel = np.linalg.norm(d.k_raw - d.k_scs) / np.linalg.norm(d.k_raw)
    assert rel <= d.k_rtol == 1e-3
    assert d.gamma_star_scs == pytest.approx(d.gamma_star, rel=1e-4)
    # the rounded table is the Clarabel gain to 9 significant digits
    np.testing.assert_allclose(d.k, d.k_raw, rtol=1e-8, atol=1e-9 * np.max(np.abs(d.k_raw)))


def test_regional_poles_in_region(generated):
    d = generated[0]["hinf_regional"]
    assert np.max(d.poles.real) < -0.05 * (1 - 1e-6)
    assert np.max(generated[0]["hinf_min"].poles.real) < -0.01 * (1 - 1e-6)


def test_bounded_design_is_bounded_below_by_minus_identity(generated):
    """-I < [...] < 0 at the emitted K (SI units); the plain design violates the bound, so the
    bounded form picks a different K, not the plain one relabelled."""
    d = generated[0]["hinf_bounded"]
    plain = generated[0]["hinf_min"]
    m = lmi_hinf.assemble_lmi(d.plant, d.x, d.k @ d.x, d.gamma)
    eig = np.linalg.eigvalsh(m)
    assert -1.0 < eig.min() and eig.max() < 0
    m_plain = lmi_hinf.assemble_lmi(plain.plant, plain.x, plain.k @ plain.x, plain.gamma)
    assert np.linalg.eigvalsh(m_plain).min() < -1.0
    assert np.linalg.norm(d.k - plain.k) > 0.1 * np.linalg.norm(plain.k)
    assert d.form == "bounded" and plain.form == "plain" and generated[0]["hinf_regional"].form == "decay_rate"
    assert np.max(d.poles.real) < -d.alpha_sel * (1 - 1e-6)


def test_infeasible_lmi_is_rejected():
    ix, iy, iz, w0 = GEO
    p = models.hinf_model(ix, iy, iz, w0)
    # gamma below |D2| = 1e-3: no K can satisfy the bounded-real LMI
    with pytest.raises(checks.InfeasibleLMIError, match="infeasible"):
        lmi_hinf.min_effort_gain("too_small_gamma", p, 0.5e-3, 0.05)


# ---- command: tables, --check, --json ----

def test_failed_design_writes_no_table(tmp_path):
    cfg = (REPO / "tools" / "gains.toml").read_text()
    cfg = cfg.replace('[designs.lqr_quat_ref]\nkind = "lqr_quat"', '[designs.lqr_quat_ref]\nkind = "bogus"')
    (tmp_path / "bad.toml").write_text(cfg)
    out = tmp_path / "gains"
    rc = cmd_gains.run(_args(config=tmp_path / "bad.toml", out_dir=out, no_report=True))
    assert rc == 2
    assert not out.exists()


def test_check_passes_on_committed_tables(generated, capsys):
    assert cmd_gains.run(_args(check=True)) == 0
    assert "match" in capsys.readouterr().out


def test_check_fails_on_tampered_copy(generated, tmp_path, capsys):
    for name in generated[1]:  # aocs_gains.h, aocs_gains.c, gain_tables.def
        shutil.copy(REPO / "firmware" / "gains" / name, tmp_path / name)
    assert cmd_gains.run(_args(check=True, out_dir=tmp_path)) == 0
    src = tmp_path / "aocs_gains.c"
    text = src.read_text()
    first = text.index("AOCS_R(447.2135954999")
    src.write_text(text[:first] + "AOCS_R(447.0" + text[first + len("AOCS_R(447.2135954999"):])
    capsys.readouterr()
    assert cmd_gains.run(_args(check=True, out_dir=tmp_path)) == 1
    err = capsys.readouterr().err
    assert "aocs_gains.c: differs from its design (2 changed lines)" in err
    assert "AOCS_R(447.0" in err


def test_check_accepts_last_digit_noise_but_not_a_small_real_change(generated, tmp_path, capsys):
    """Solver noise (another BLAS: the 16th digit, or an LMI table's 6.5e-6 on another CPU) passes with a
    note; ten times the tolerance does not."""
    for name in generated[1]:  # aocs_gains.h, aocs_gains.c, gain_tables.def
        shutil.copy(REPO / "firmware" / "gains" / name, tmp_path / name)
    src = tmp_path / "aocs_gains.c"
    text = src.read_text()
    # the first entry of lqr_quat_ref (sqrt(Q/R) = 447.2135954999...), moved in its last digits
    original = re.search(r"AOCS_R\(447\.2135954999\d*\)", text).group(0)
    noisy = f"AOCS_R({float(original[7:-1]) + 2.3e-13:.17g})"
    assert noisy != original
    src.write_text(text.replace(original, noisy, 1))
    capsys.readouterr()
    assert cmd_gains.run(_args(check=True, out_dir=tmp_path)) == 0
    assert "not bit-for-bit" in capsys.readouterr().out
    lmi_noise = f"AOCS_R({float(original[7:-1]) * (1 + 6.5e-6):.17g})"
    src.write_text(text.replace(original, lmi_noise, 1))
    assert cmd_gains.run(_args(check=True, out_dir=tmp_path)) == 0
    real = f"AOCS_R({float(original[7:-1]) * (1 + 10 * cmd_gains.TABLE_RTOL):.17g})"
    src.write_text(text.replace(original, real, 1))
    assert cmd_gains.run(_args(check=True, out_dir=tmp_path)) == 1
    # a changed design input or word in the provenance is never noise
    for old, new in (("lqr_quat_ref: SPEC 2.5", "lqr_quat_ref: SPEC 2.6"), ("Q = 200 I6", "Q = 201 I6"),
                     ("scipy 1.17.1", "scipy 1.17.2")):
        assert old in text
        src.write_text(text.replace(old, new, 1))
        assert cmd_gains.run(_args(check=True, out_dir=tmp_path)) == 1


def test_table_registration_is_generated_in_design_order(generated, tmp_path, capsys):
    """gain_tables.def: one row per design of tools/gains.toml, in its order (the table ids)."""
    designs, files = generated
    text = files["gain_tables.def"]
    assert text == (REPO / "firmware" / "gains" / "gain_tables.def").read_text()
    rows = [ln.strip() for ln in text.splitlines() if ln.strip().startswith("X(")]
    assert len(rows) == len(designs)
    for row, d in zip(rows, designs.values()):
        assert row.startswith(f'X({d.name.upper()}, "{d.name}", {d.inputs["kind"].upper()}, aocs_gains_{d.name}_K)')
    # a hand edit of the registration is caught like one of the tables
    for name in files:
        shutil.copy(REPO / "firmware" / "gains" / name, tmp_path / name)
    reg = tmp_path / "gain_tables.def"
    reg.write_text(reg.read_text().replace(", HINF,", ", LQR_QUAT,", 1))
    capsys.readouterr()
    assert cmd_gains.run(_args(check=True, out_dir=tmp_path)) == 1
    assert "gain_tables.def: differs from its design" in capsys.readouterr().err


def test_committed_tables_contain_provenance():
    text = (REPO / "firmware" / "gains" / "aocs_gains.c").read_text()
    for name in ("lqr_quat_ref", "lqr_quat_strong", "orbit_lqr_q1", "orbit_lqr_q01", "orbit_lqr_q10",
                 "hinf_min", "hinf_regional", "hinf_bounded"):
        assert f"const real_t aocs_gains_{name}_K[3][6]" in text
    for name in ("lqr_quat_i_ref", "lqr_quat_i_suite", "lqr_quat_i_rw_suite"):
        assert f"const real_t aocs_gains_{name}_K[3][9]" in text   # SPEC 5.2: x = [z; qe_vec; we]
    designs = tomllib.loads((REPO / "tools" / "gains.toml").read_text())["designs"]
    n_hinf = sum(d["kind"] == "hinf" for d in designs.values())
    assert text.count("generated by `aocs gains`; do not edit") >= len(designs)
    # each Riccati design states its residual, each H-inf design its independently computed norm
    assert text.count("ARE residual") == len(designs) - n_hinf and n_hinf == 3
    assert text.count("independent closed-loop H-inf norm") == n_hinf
    header = (REPO / "firmware" / "gains" / "aocs_gains.h").read_text()
    assert "#ifndef AOCS_GAINS_H" in header and '#include "aocs/types.h"' in header


def test_json_has_required_keys(generated, tmp_path):
    path = tmp_path / "gains.json"
    assert cmd_gains.run(_args(check=True, json=path)) == 0
    data = json.loads(path.read_text())
    assert set(data) == {"lqr_quat_ref", "lqr_quat_strong", "orbit_lqr_q1", "orbit_lqr_q01",
                         "orbit_lqr_q10", "hinf_min", "hinf_regional", "lqr_quat_i_ref", "hinf_bounded",
                         "lqr_quat_i_suite", "lqr_quat_i_rw_suite"}
    for name, e in data.items():
        n = 9 if e["kind"] == "lqr_quat_i" else 6   # the state of the law: [z; qe_vec; we] for lqr_quat_i
        assert np.array(e["K"]).shape == (3, n)
        poles = np.array(e["closed_loop_poles"])
        assert poles.shape == (n, 2)
        assert e["slowest_pole_re"] == pytest.approx(poles[:, 0].max()) and e["slowest_pole_re"] < 0
        if name.startswith("hinf"):
            assert e["hinf_norm_check"] <= e["gamma"]
            # issue 10 acceptance: the plain LMI's minimum is |D2| = 1e-3 up to the solver margin
            assert 1e-3 <= e["gamma_min"] < 1.02e-3
            assert e["gamma_min"] <= e["gamma_star"] * (1 + 1e-6) and e["gamma"] > e["gamma_star"]
        else:
            assert e["are_residual"] >= 0
    np.testing.assert_array_equal(np.array(data["hinf_min"]["K"]), generated[0]["hinf_min"].k)
    assert {n: data[n]["form"] for n in ("hinf_min", "hinf_regional", "hinf_bounded")} == {
        "hinf_min": "plain", "hinf_regional": "decay_rate", "hinf_bounded": "bounded"}


@pytest.mark.parametrize("content,message", [
    (None, "no such design configuration file"),
    (b"x = [\n", "not valid TOML"),
    (b"\xff\xfe = 1\n", "not UTF-8 text (byte 0)"),
    (b"[plants.irassi]\ninertia_diag = [1.0, 2.0, 3.0]\n", "missing key 'designs'"),
    (b'[plants.irassi]\ninertia_diag = "abc"\n[designs.x]\nkind = "lqr_quat"\nplant = "irassi"\nq = 1.0\nr = 1.0\n',
     "a value of the wrong type or size"),
])
def test_a_bad_design_configuration_is_one_line_and_exit_2(tmp_path, capsys, content, message):
    cfg = tmp_path / "g.toml"
    if content is not None:
        cfg.write_bytes(content)
    out = tmp_path / "out"
    assert cmd_gains.run(_args(config=cfg, out_dir=out, no_report=True)) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("aocs gains: error: ") and str(cfg) in err and message in err, err
    assert not out.exists()
