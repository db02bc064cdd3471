"""The analytic steady-state knowledge of a gyro + star-tracker filter (aocs_analysis/estimation_bounds.py):
Farrenkopf's closed form against the discrete algebraic Riccati equation, against a Kalman filter and a
Monte Carlo written out here, and against published limits."""
import math

import numpy as np
import pytest

from aocs_analysis.estimation_bounds import between_updates, farrenkopf, riccati, steady_state_per_axis

ARCSEC = 180.0 * 3600.0 / math.pi
DEG_H = math.pi / 180.0 / 3600.0      # 1 deg/h in rad/s
#: gyro grades (sigma_v rad/s^0.5, sigma_u rad/s^1.5): navigation (0.002 deg/h^0.5 ARW), tactical
#: (0.1 deg/h^0.5), and the classic example of Crassidis & Junkins, Optimal Estimation of Dynamic Systems
#: (sqrt(10) 1e-7, sqrt(10) 1e-10)
GYROS = {"navigation": (0.002 * math.pi / 180 / 60, 1e-11), "tactical": (0.1 * math.pi / 180 / 60, 1e-9),
         "crassidis_junkins": (math.sqrt(10) * 1e-7, math.sqrt(10) * 1e-10)}


@pytest.mark.parametrize("gyro", sorted(GYROS))
@pytest.mark.parametrize("arcsec", [1.0, 5.0, 60.0])
@pytest.mark.parametrize("dt", [0.1, 1.0, 10.0])
def test_the_closed_form_is_the_riccati_solution(gyro, arcsec, dt):
    sv, su = GYROS[gyro]
    f, r = farrenkopf(arcsec / ARCSEC, sv, su, dt), riccati(arcsec / ARCSEC, sv, su, dt)
    for name in ("attitude_pre", "attitude_post", "bias_pre", "bias_post"):
        assert getattr(f, name) == pytest.approx(getattr(r, name), rel=1e-8), name
    assert f.attitude_post < min(f.attitude_pre, arcsec / ARCSEC)     # an update helps; the filter beats the tracker


def test_the_continuous_time_limit():
    """As dt -> 0 with sigma_n^2 dt = r fixed, both the pre- and post-update variances tend to the
    continuous-time steady state of the same two-state filter, P_aa = r^(1/2) (sigma_v^2 + 2 sigma_u r^(1/2))^(1/2)
    (the continuous Riccati equation solved by hand: 0 = -2 p12 + sigma_v^2 - p11^2 / r, 0 = -p22 - p11 p12 / r,
    0 = sigma_u^2 - p12^2 / r; the published continuous-time result of this model, e.g. Crassidis & Junkins,
    Optimal Estimation of Dynamic Systems, 2nd ed., 2012, and Markley & Crassidis 2014, ch. 6: the
    steady state of the continuous-time filter; see docs/spec.md 5.6)."""
    sv, su = GYROS["crassidis_junkins"]
    r = (1.0 / ARCSEC) ** 2 * 1.0          # 1 arcsec at 1 Hz
    p_cont = math.sqrt(r) * math.sqrt(sv * sv + 2 * su * math.sqrt(r))
    gaps = []
    for dt in (1.0, 1e-2, 1e-4):
        f = farrenkopf(math.sqrt(r / dt), sv, su, dt)
        gaps.append(max(abs(f.attitude_pre ** 2 / p_cont - 1), abs(f.attitude_post ** 2 / p_cont - 1)))
    assert gaps[0] > gaps[1] > gaps[2] and gaps[2] < 1e-4
    # the bias: p22 = sigma_u (sigma_v^2 + 2 sigma_u r^(1/2))^(1/2) r^(1/2) ... from p22 = -p11 p12 / r
    p12 = -su * math.sqrt(r)
    p22 = -p_cont * p12 / r
    f = farrenkopf(math.sqrt(r / 1e-4), sv, su, 1e-4)
    assert f.bias_post ** 2 == pytest.approx(p22, rel=1e-3)


def test_no_angle_random_walk_is_allowed_and_still_the_riccati_solution():
    """sigma_v = 0 (a gyro with rate random walk only) is a filter too: the closed form is the Riccati
    iteration's fixed point; a negative or non-finite figure, or no tracker noise, is refused."""
    sn, su, dt = 3.0 / ARCSEC, 1e-9, 0.5
    f, r = farrenkopf(sn, 0.0, su, dt), riccati(sn, 0.0, su, dt)
    for name in ("attitude_pre", "attitude_post", "bias_pre", "bias_post"):
        assert getattr(f, name) == pytest.approx(getattr(r, name), rel=1e-8), name
    assert 0.0 < f.attitude_post < sn
    for bad in ((0.0, 1e-6, su, dt), (sn, -1e-9, su, dt), (sn, 1e-6, -1e-12, dt), (sn, 1e-6, su, 0.0),
                (sn, math.nan, su, dt)):
        with pytest.raises(ValueError, match="need sigma_n > 0"):
            farrenkopf(*bad)


def test_no_rate_random_walk_is_the_one_state_filter():
    """sigma_u = 0: the bias is known in steady state, and the angle filter is scalar: the predicted variance
    p solves p^2 - q p - q R = 0 with q = sigma_v^2 dt (Farrenkopf's S_u = 0 case)."""
    sn, sv, dt = 3.0 / ARCSEC, 1e-6, 0.5
    q, rr = sv * sv * dt, sn * sn
    p = 0.5 * (q + math.sqrt(q * q + 4 * q * rr))
    f = farrenkopf(sn, sv, 0.0, dt)
    assert f.attitude_pre ** 2 == pytest.approx(p, rel=1e-12)
    assert f.attitude_post ** 2 == pytest.approx(p * rr / (p + rr), rel=1e-12)
    assert f.bias_post == 0.0
    with pytest.raises(ValueError, match="sigma_u > 0"):
        riccati(sn, sv, 0.0, dt)


def _phi_q(sv, su, dt):
    phi = np.array([[1.0, -dt], [0.0, 1.0]])
    q = np.array([[sv ** 2 * dt + su ** 2 * dt ** 3 / 3, -su ** 2 * dt ** 2 / 2], [-su ** 2 * dt ** 2 / 2, su ** 2 * dt]])
    return phi, q


def test_a_kalman_filter_iterated_to_steady_state_and_a_monte_carlo_agree():
    """A Kalman filter written here, run from a large initial covariance until it stops moving, reaches the
    bound; a Monte Carlo of 4000 single-axis runs of the true model (angle, bias) with that filter has the
    bound's pre- and post-update error variances within 5 sigma of sampling (started in steady state: the
    estimation error drawn from the converged covariance)."""
    # the tactical ARW with a fast bias walk (1e-7 rad/s^1.5), so that the iteration converges in ~4000 steps
    sn, sv, su, dt = 5.0 / ARCSEC, GYROS["tactical"][0], 1e-7, 1.0
    phi, q = _phi_q(sv, su, dt)
    p = np.diag([1e-4, 1e-10])
    for i in range(1_000_000):
        m = phi @ p @ phi.T + q
        k = m[:, 0] / (m[0, 0] + sn * sn)
        p, last = m - np.outer(k, m[0, :]), p
        if np.all(np.abs(p - last) <= 1e-14 * np.abs(p)):
            break
    f = farrenkopf(sn, sv, su, dt)
    assert math.sqrt(m[0, 0]) == pytest.approx(f.attitude_pre, rel=1e-9)
    assert math.sqrt(p[0, 0]) == pytest.approx(f.attitude_post, rel=1e-9)
    # Monte Carlo: the truth x = (theta, beta) driven by noise of covariance q, the filter's estimate xh
    rng = np.random.default_rng(20)
    runs, steps = 4000, 50
    chol = np.linalg.cholesky(q)
    x = np.zeros((runs, 2))
    x[:, 1] = rng.normal(0, 1e-6, runs)
    xh = x - rng.standard_normal((runs, 2)) @ np.linalg.cholesky(p).T
    for _ in range(steps):
        x = x @ phi.T + rng.standard_normal((runs, 2)) @ chol.T
        xh = xh @ phi.T
        m = phi @ p @ phi.T + q
        pre_err = x[:, 0] - xh[:, 0]
        k = m[:, 0] / (m[0, 0] + sn * sn)
        z = x[:, 0] + sn * rng.standard_normal(runs)
        xh = xh + np.outer(z - xh[:, 0], k)
        p = m - np.outer(k, m[0, :])
    post_err = x[:, 0] - xh[:, 0]
    tol = 5 * math.sqrt(2 / runs)
    assert pre_err.var() == pytest.approx(f.attitude_pre ** 2, rel=tol)
    assert post_err.var() == pytest.approx(f.attitude_post ** 2, rel=tol)
    print(f"Monte Carlo (5 arcsec at 1 Hz, tactical ARW, RRW 1e-7): pre {pre_err.std() * ARCSEC:.4f} arcsec (bound "
          f"{f.attitude_pre_arcsec:.4f}), post {post_err.std() * ARCSEC:.4f} arcsec (bound {f.attitude_post_arcsec:.4f})")


def test_between_updates_and_per_axis():
    sn, (sv, su), dt = 1.0 / ARCSEC, GYROS["navigation"], 1.0
    f = farrenkopf(sn, sv, su, dt)
    assert between_updates(sn, sv, su, dt, 1) == pytest.approx(f.attitude_post, rel=1e-9)
    mid = between_updates(sn, sv, su, dt, 10)
    assert f.attitude_post < mid < f.attitude_pre
    # sigma_u = 0 goes through the one-state filter
    assert between_updates(sn, sv, 0.0, dt, 1) == pytest.approx(farrenkopf(sn, sv, 0.0, dt).attitude_post)
    # ... and between updates only the angle random walk adds (the bias known: no tau^2 term),
    # var(tau) = post^2 + sigma_v^2 tau at tau = j dt / n
    post2 = farrenkopf(sn, sv, 0.0, dt).attitude_post ** 2
    want = math.sqrt(sum(post2 + sv * sv * j * dt / 10 for j in range(10)) / 10)
    assert between_updates(sn, sv, 0.0, dt, 10) == pytest.approx(want, rel=1e-12)
    # per axis of S: x, y from the cross-boresight noise, z from the about-boresight noise
    x, y, z = steady_state_per_axis(1.0, 8.0, 5.0, sv, su)
    assert x == y == pytest.approx(farrenkopf(1.0 / ARCSEC, sv, su, 0.2).attitude_post_arcsec)
    assert z == pytest.approx(farrenkopf(8.0 / ARCSEC, sv, su, 0.2).attitude_post_arcsec)
    pre = steady_state_per_axis(1.0, 8.0, 5.0, sv, su, when="pre")
    assert all(a > b for a, b in zip(pre, (x, y, z)))
    with pytest.raises(ValueError):
        steady_state_per_axis(1.0, 8.0, 5.0, sv, su, when="mid")
    with pytest.raises(ValueError):
        farrenkopf(0.0, sv, su, dt)


def test_the_issue_20_sensor_sets():
    """The figures the later MEKF acceptance compares against (printed for the record)."""
    rows = []
    for arcsec in (1.0, 5.0):
        for gyro in ("navigation", "tactical"):
            for hz in (10.0, 1.0):
                sv, su = GYROS[gyro]
                f = farrenkopf(arcsec / ARCSEC, sv, su, 1.0 / hz)
                rows.append((arcsec, gyro, hz, round(f.attitude_post_arcsec, 4), round(f.attitude_pre_arcsec, 4)))
                assert f.attitude_post_arcsec < arcsec     # the filter beats the tracker alone
    print("sigma_n arcsec, gyro, Hz, post, pre (arcsec):", rows)
