"""Metrics used by every run report: conventions and edge cases."""
import math

import numpy as np
import pytest

from aocs_analysis import metrics


def axis_angle_quat(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.concatenate([axis * math.sin(angle / 2), [math.cos(angle / 2)]])


def test_true_angle_and_reference_figure_of_a_known_rotation():
    angle = 10.0 / metrics.ARCSEC_PER_RAD  # 10 arcsec about x
    q = axis_angle_quat([1, 0, 0], angle)[None, :]
    err = metrics.pointing_errors_arcsec(q, np.array([0, 0, 0, 1.0]))
    assert err["true_angle"][0] == pytest.approx(10.0, rel=1e-9)
    assert err["per_axis"][0, 0] == pytest.approx(10.0, rel=1e-6)
    # the IRASSI report's |qe_i| is half the angle
    assert err["qe_arcsec"][0, 0] == pytest.approx(5.0, rel=1e-6)
    assert err["qe_arcsec"][0, 1] == 0.0
    # one attitude given alone (4,) is measured the same, as a scalar angle and 3-vectors
    one = metrics.pointing_errors_arcsec(q[0], np.array([0, 0, 0, 1.0]))
    assert one["true_angle"] == pytest.approx(10.0, rel=1e-9) and one["per_axis"].shape == (3,)


def test_error_quaternion_is_relative_to_the_target_and_sign_invariant():
    qd = axis_angle_quat([0, 0, 1], 0.3)
    q = metrics.quat_mul(axis_angle_quat([0, 1, 0], 0.01)[None, :], qd[None, :])
    for sign in (1.0, -1.0):
        err = metrics.pointing_errors_arcsec(sign * q, qd)
        assert err["true_angle"][0] == pytest.approx(0.01 * metrics.ARCSEC_PER_RAD, rel=1e-9)
        assert err["per_axis"][0, 1] == pytest.approx(0.01 * metrics.ARCSEC_PER_RAD, rel=1e-4)


def test_shuster_product_composes_attitude_matrices():
    def dcm(q):
        v, s = q[:3], q[3]
        skew = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
        return (s * s - v @ v) * np.eye(3) + 2 * np.outer(v, v) - 2 * s * skew

    rng = np.random.default_rng(1)
    for _ in range(50):
        q = rng.normal(size=4); q /= np.linalg.norm(q)
        p = rng.normal(size=4); p /= np.linalg.norm(p)
        qp = metrics.quat_mul(q[None], p[None])[0]
        np.testing.assert_allclose(dcm(qp), dcm(q) @ dcm(p), atol=1e-12)


def test_settle_time_needs_the_criterion_to_hold_until_the_end():
    t = np.arange(10.0)
    assert metrics.settle_time(t, np.array([0, 0, 1, 1, 0, 1, 1, 1, 1, 1], bool)) == 5.0
    assert metrics.settle_time(t, np.ones(10, bool)) == 0.0
    assert metrics.settle_time(t, np.array([1] * 9 + [0], bool)) is None


def test_effort_integrates_the_held_command_one_norm():
    t = np.array([0.0, 0.1, 0.3])
    u = np.array([[1.0, -2.0, 0.0], [0.5, 0.5, 0.5], [100.0, 100.0, 100.0]])
    # first command held 0.1 s, second 0.2 s, last one never applied
    assert metrics.effort(t, u) == pytest.approx(3.0 * 0.1 + 1.5 * 0.2)
    # the fewest samples: two (one command held 0.1 s), one or none (nothing held)
    assert metrics.effort(t[:2], u[:2]) == pytest.approx(3.0 * 0.1)
    assert metrics.effort(t[:1], u[:1]) == 0.0 and metrics.effort(t[:0], u[:0]) == 0.0
    assert metrics.time_in_saturation(t[:2], np.array([True, True])) == pytest.approx(0.1)
    assert metrics.time_in_saturation(t[:1], np.array([True])) == 0.0


def test_window_and_timing_summary():
    t = np.linspace(0, 500, 5001)
    assert np.count_nonzero(metrics.window_mask(t, 100.0)) == 1001
    assert metrics.window_mask(np.zeros(0), 100.0).shape == (0,)          # no sample: an empty mask
    assert metrics.window_mask(np.array([7.0]), 100.0).tolist() == [True]
    summary = metrics.timing_summary(np.arange(1, 101), 50.0, np.arange(1, 101) > 50)
    assert summary.step_ns_median == 50.5
    assert summary.step_ns_max == 100
    assert summary.overruns == 50
    # one step: every statistic is that step; none: zeros and the budget
    one = metrics.timing_summary(np.array([1234.0]), 2000.0, np.array([True]))
    assert (one.step_ns_median, one.step_ns_p99, one.step_ns_max, one.overruns) == (1234.0, 1234.0, 1234.0, 1)
    none = metrics.timing_summary(np.zeros(0), 2000.0, np.zeros(0, bool))
    assert (none.step_ns_median, none.step_ns_max, none.budget_ns, none.overruns) == (0.0, 0.0, 2000.0, 0)


def test_time_in_saturation_holds_each_flag_over_its_own_interval():
    """A flag at t_k holds until t_(k+1) (the command is held one period); the last sample's flag adds nothing:
    uneven steps 1, 2, 3 s, saturated on the second and third samples: 2 + 3 = 5 s; on the first and last: 1 s."""
    t = np.array([0.0, 1.0, 3.0, 6.0])
    assert metrics.time_in_saturation(t, np.array([False, True, True, False])) == 5.0
    assert metrics.time_in_saturation(t, np.array([True, False, False, True])) == 1.0
