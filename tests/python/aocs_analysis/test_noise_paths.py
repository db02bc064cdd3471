"""aocs_analysis.noise_paths against closed-form results of the per-axis linear loop J theta'' = u + d,
u = -kq theta/2 - kw theta' - kz z, z' = theta/2 (written out here, not taken from the module)."""
import numpy as np
import pytest

from aocs_analysis import noise_paths as NP

J = 5974.3


def test_a_constant_torque_leaves_d_over_half_kq_without_integral_action_and_nothing_with_it():
    t = np.arange(0.0, 3000.0, 0.5)
    zero = np.zeros((t.size, 3))
    d = (1.18e-3, -2e-3, 5e-4)
    pd = NP.paths(t, zero, zero, [J] * 3, [NP.AxisGains(4000.0, 8000.0)] * 3, d)
    # steady state of J theta'' = -kq theta / 2 - kw theta' + d: theta = 2 d / kq
    np.testing.assert_allclose(pd["disturbance"][-1], 2.0 * np.array(d) / 4000.0, rtol=1e-6)
    pid = NP.paths(t, zero, zero, [J] * 3, [NP.AxisGains(400.0, 2000.0, 12.0)] * 3, d)
    assert np.all(np.abs(pid["disturbance"][-1]) < 1e-3 * np.abs(2.0 * np.array(d) / 400.0))


def test_a_constant_attitude_error_is_followed_one_to_one_and_a_rate_bias_is_not():
    """T(0) = 1: a constant estimate offset n moves the truth by -n; a constant rate error is rejected by the
    integral (a P-D law holds theta = -2 kw n_w / kq instead)."""
    t = np.arange(0.0, 4000.0, 0.5)
    n = np.tile([2e-6, -1e-6, 3e-6], (t.size, 1))
    g = NP.AxisGains(400.0, 2000.0, 12.0)
    r = NP.paths(t, n, np.zeros_like(n), [J] * 3, [g] * 3)
    np.testing.assert_allclose(r["attitude"][-1], -n[-1], rtol=1e-5)
    # no disturbance given, none applied: the noises alone make the total
    assert not np.any(r["disturbance"]) and not np.any(r["rate"])
    np.testing.assert_array_equal(r["total"], r["attitude"])
    pd = NP.paths(t, np.zeros_like(n), n, [J] * 3, [NP.AxisGains(4000.0, 8000.0)] * 3)
    np.testing.assert_allclose(pd["rate"][-1], -2.0 * 8000.0 * n[-1] / 4000.0, rtol=1e-6)
    np.testing.assert_array_equal(pd["total"], pd["rate"])     # the rate noise alone makes this total
    pid = NP.paths(t, np.zeros_like(n), n, [J] * 3, [g] * 3)
    assert np.all(np.abs(pid["rate"][-1]) < 1e-3 * np.abs(n[-1]))
    d = (1e-4, 0.0, -2e-4)
    both = NP.paths(t, n, n, [J] * 3, [g] * 3, d)             # and the three paths add up
    np.testing.assert_allclose(both["total"], r["attitude"] + pid["rate"] + both["disturbance"], rtol=1e-12,
                               atol=1e-18)


def test_the_peak_of_t_is_one_for_pd_and_above_one_for_the_reference_pid():
    """quat_pid's reference gains (SPEC 5.2, J33): its zeros kq/2 s + kz/2 below its poles make |T| peak above 1;
    a critically damped P-D loop's |T| = |wn^2 / (wn^2 - w^2 + 2 j wn w)| never exceeds 1."""
    peak_pid, w_pid = NP.t_peak(J, NP.AxisGains(400.0, 2000.0, 12.0))
    assert peak_pid > 1.1 and 0.01 < w_pid < 0.2
    kq = 2.0 * 2000.0 ** 2 / (4.0 * J)    # kw^2 = 4 J kq/2: critically damped
    peak_pd, _ = NP.t_peak(J, NP.AxisGains(kq, 2000.0))
    assert peak_pd == pytest.approx(1.0, abs=1e-3)


def test_the_noises_of_a_log_are_estimate_minus_truth_on_the_ticks_both_sides_logged():
    """n_att = -(knowledge error) = estimate - truth and n_rate = w_est - w_true, paired by tick (a command
    tick the truth did not log is left out, the commands' order kept); pointing = 2 qe_i against the target.
    The estimate is the truth turned by +a about x (n_att = (a, 0, 0)), the truth the target turned by b about
    y (pointing (0, 2 sin(b / 2), 0))."""
    import types

    from aocs_analysis.run_metrics import target_quat
    from aocs_core import conventions as rot
    from aocs_plant.scenario import load

    sc = load("geo_hinf")
    ticks = np.arange(10)
    t = ticks * sc.dt
    a, b = 3e-5, -2e-4
    row = lambda v: np.tile(v, (t.size, 1))  # noqa: E731
    q_true = rot.quat_mul_rows(row([0.0, np.sin(b / 2), 0.0, np.cos(b / 2)]), target_quat(sc, t))
    w_true = np.column_stack([1e-3 * t, -2e-3 * np.ones_like(t), 5e-4 * np.cos(t)])
    cmd_ticks = np.array([9, 2, 11, 5])
    on = np.array([9, 2, 9, 5])               # the truth row of each command (11: none)
    q_est = rot.quat_mul_rows(row([np.sin(a / 2), 0.0, 0.0, np.cos(a / 2)])[on], q_true[on])
    dw = np.array([[1e-6, -2e-6, 3e-6], [4e-6, 5e-6, -6e-6], [0.0, 0.0, 0.0], [-7e-6, 8e-6, 9e-6]])
    log = types.SimpleNamespace(truth={"tick": ticks, "t_s": t, "q": q_true, "w": w_true},
                                cmd={"tick": cmd_ticks, "q_est": q_est, "w_est": w_true[on] + dw})
    n = NP.noises_from_log(log, sc)
    keep = [0, 1, 3]
    np.testing.assert_array_equal(n["t"], t[on[keep]])
    np.testing.assert_allclose(n["n_att_rad"], np.tile([a, 0.0, 0.0], (3, 1)), rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(n["n_rate_radps"], dw[keep], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(n["pointing_rad"], np.tile([0.0, 2.0 * np.sin(b / 2), 0.0], (3, 1)), rtol=1e-9,
                               atol=1e-14)


@pytest.mark.parametrize("kz", [0.0, 1.0, 12.0])
def test_the_three_paths_are_the_loops_transfer_functions_written_out(kz):
    """At s = j w the paths are, from J theta'' = u + d, u = -kq theta/2 - kw theta' - kz z, z' = theta/2
    (theta the truth, n added to the measured attitude and rate): T_att = -(kq/2 + kz/(2 s)) / D,
    T_rate = -kw / D, T_d = 1 / D with D = J s^2 + kw s + kq/2 + kz/(2 s) (every integral gain, 1 among
    them, keeps its term)."""
    from scipy import signal
    g = NP.AxisGains(400.0, 2000.0, kz)
    w = np.logspace(-3, 1, 50)
    s = 1j * w
    d = J * s ** 2 + g.kw * s + g.kq / 2.0 + g.kz / (2.0 * s)
    expected = (-(g.kq / 2.0 + g.kz / (2.0 * s)) / d, -g.kw / d, 1.0 / d)
    for (num, den), want in zip(NP.closed_loop(J, g), expected):
        _, h = signal.freqs(num, den, w)
        np.testing.assert_allclose(h, want, rtol=1e-9)
