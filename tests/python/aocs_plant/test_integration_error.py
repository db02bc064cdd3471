"""The plant's integration error estimate (aocs_plant.integration_error) against the true error of
one period, computed here with a tight reference integrator, and its verdict on the rtc examples."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from aocs_core.conventions import ARCSEC_PER_RAD, pointing_error_rad, quat_error
from aocs_plant import Plant, load
from aocs_plant.integration_error import StepDoubling


def _rigid_rhs(J):
    Ji = np.linalg.inv(J)

    def f(_t, y):
        q, w = y[:4], y[4:]
        q1, q2, q3, q4 = q
        xi = np.array([[q4, -q3, q2], [q3, q4, -q1], [-q2, q1, q4], [-q1, -q2, -q3]])
        return np.concatenate([0.5 * xi @ w, Ji @ (-np.cross(w, J @ w))])
    return f


def test_local_estimate_matches_the_true_error_of_a_period():
    """A torque-free tumble (rtc_ex1a's body, J = I3 would not tumble: use IRASSI's J) for one period:
    16/15 x (one-substep - two-substep) is the one-substep RK4 error within 10 %."""
    sc = load("irassi_large", {"plant.w0": [0.3, -0.2, 0.25], "disturbances.constant_torque.enabled": False,
                               "disturbances.gravity_gradient_l2.enabled": False})
    p, chk = Plant(sc), StepDoubling(sc)
    q0, w0 = p.body.q, p.body.w
    chk.begin(p)
    p.advance()
    chk.end(p)
    J = np.array(sc.attitude.inertia, float)
    ref = solve_ivp(_rigid_rhs(J), (0.0, sc.dt), np.array(q0 + w0), rtol=1e-13, atol=1e-15, method="DOP853").y[:, -1]
    ref_q = tuple(ref[:4] / np.linalg.norm(ref[:4]))
    true_err = pointing_error_rad(p.body.q, ref_q) * ARCSEC_PER_RAD
    est = chk.summary()["attitude_arcsec_local_max"]
    assert true_err > 1e-6                      # a real error, so the comparison means something
    assert est == pytest.approx(true_err, rel=0.1)
    # the rate: the same estimate of |w - w_ref|, rad/s, kept apart from the attitude's
    true_rate_err = float(np.linalg.norm(np.array(p.body.w) - ref[4:]))
    assert true_rate_err > 1e-12
    assert chk.summary()["rate_rad_s_local_max"] == pytest.approx(true_rate_err, rel=0.1)


def _pd_run(sid, substeps, every=None):
    sc = load(sid, {"integrator.substeps": substeps})
    p, chk = Plant(sc), (StepDoubling(sc) if every is None else StepDoubling(sc, every))
    k1, k2 = (sc.control.laws["crp_linear"].params[k] for k in ("k1", "k2"))
    for _ in range(sc.n_steps):
        s = p.sense()
        e = quat_error(s["q"], sc.target.qd0)
        e = e if e[3] >= 0 else tuple(-x for x in e)
        rho = [e[i] / e[3] for i in range(3)]
        u = tuple(-k1 * s["w"][i] - k2 * rho[i] for i in range(3))   # SPEC 2.1
        p.apply({"u_body": u})
        chk.apply({"u_body": u})
        chk.begin(p)
        p.advance()
        chk.end(p)
    return chk.summary()


def test_rtc_needs_its_ten_substeps():
    """SPEC 4: the rtc examples (rates up to 58 rad/s at 100 Hz) converge with 10 or more substeps;
    with one the estimate exceeds the tolerance, with ten it does not; the error falls ~2^4 per halving."""
    one, ten = _pd_run("rtc_ex1a", 1), _pd_run("rtc_ex1a", 10)
    assert one["exceeds_tolerance"] and not ten["exceeds_tolerance"]
    assert one["attitude_arcsec_sum"] > 1e3 * ten["attitude_arcsec_sum"]
    assert one["tolerance_arcsec"] == 1e-3 and one["periods"] == 4000 and one["checked_periods"] >= 400
    assert "step doubling" in one["method"]


def test_sampled_check_agrees_with_checking_every_period():
    """The run checks one period in CHECK_EVERY; its extrapolated sum and its largest local error
    stay close to those of checking every period (the local error moves smoothly)."""
    sampled, every = _pd_run("rtc_ex1a", 1), _pd_run("rtc_ex1a", 1, every=1)
    assert every["checked_periods"] == every["periods"] == 4000
    assert sampled["attitude_arcsec_sum"] == pytest.approx(every["attitude_arcsec_sum"], rel=0.5)
    assert sampled["attitude_arcsec_local_max"] == pytest.approx(every["attitude_arcsec_local_max"], rel=0.5)


def test_exact_linear_orbit_has_no_integration_error():
    """The linear orbit model is propagated exactly: from a moving state (velocity of mm/s, position of metres)
    both the position and the velocity estimates are zero to rounding."""
    sc = load("landsat8_q1", {"duration_s": 100.0, "metrics.window_s": 100.0,
                              "plant.x0": [1e-3, -2e-3, 5e-4, 10.0, -4.0, 2.5]})
    p, chk = Plant(sc), StepDoubling(sc)
    for _ in range(sc.n_steps):
        chk.begin(p)
        p.advance()
        chk.end(p)
    s = chk.summary()
    assert s["position_m_sum"] < 1e-9 and not s["exceeds_tolerance"] and s["velocity_m_s_local_max"] < 1e-12
    assert max(abs(v) for v in p.orbit.x[:3]) > 1e-4        # it did move


def test_a_sum_exactly_at_the_tolerance_does_not_exceed_it():
    """exceeds_tolerance means more than the tolerance: a summed estimate equal to it (the boundary, as the
    verdict's factor and the requirements are judged) does not exceed it, the next float above does."""
    chk = StepDoubling(load("gao_mrp"))
    chk.local_sum[0] = chk.tolerance
    assert not chk.summary()["exceeds_tolerance"]
    chk.local_sum[0] = math.nextafter(chk.tolerance, math.inf)
    assert chk.summary()["exceeds_tolerance"]


def test_without_a_tolerance_every_local_error_is_above_the_threshold():
    """No integrator tolerance (None): the per-period threshold is 0, so any positive local error makes the next
    period checked too (a threshold of 1 / n_steps would let errors of that size pass unchecked)."""
    chk = StepDoubling(dataclasses.replace(load("gao_mrp"), integrator_tolerance=None))
    assert chk.threshold == 0.0
    chk = StepDoubling(load("gao_mrp"))
    assert chk.threshold == chk.tolerance / load("gao_mrp").n_steps
