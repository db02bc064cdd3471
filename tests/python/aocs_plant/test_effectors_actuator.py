"""The body-torque (force) actuator effector (SPEC 3.4): limits, rate limit, zero-order hold,
the first-order lag as effector state integrated with the body, and its [actuator] section."""
import math

import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors import BodyContext, Form
from aocs_plant.effectors.actuator import Actuator, ActuatorConfig


def actuator(dt=0.1, **limits):
    return Actuator(ActuatorConfig(**limits), BodyContext("attitude", dt, 1, 0))


def bare_irassi(**extra):
    """irassi_large without disturbances, at rest at the identity: only the actuator acts."""
    ov = {"disturbances.gravity_gradient_l2.enabled": False, "disturbances.constant_torque.enabled": False,
          "plant.euler321_deg": [0.0, 0.0, 0.0]}
    ov.update(extra)
    return Plant(load("irassi_large", ov))


JY = 5954.2  # IRASSI principal inertia about y, kg m^2

# ----------------------------------------------------------------- per-period limits


def test_unlimited_by_default_and_a_held_effector():
    a = actuator()
    assert a.hold((5e3, -7e3, 1.0)) == (5e3, -7e3, 1.0)
    assert a.saturated_count == 0
    assert a.form == Form.HELD and a.state_size == 0 and a.value() == (5e3, -7e3, 1.0)


def test_axis_saturation_clips_each_component():
    a = actuator(axis_limit=1.0)
    assert a.hold((5.0, -5.0, 0.1)) == (1.0, -1.0, 0.1)
    assert a.saturated_count == 1
    assert a.hold((0.5, -0.5, 0.1)) == (0.5, -0.5, 0.1)
    assert a.saturated_count == 1


def test_norm_saturation_keeps_direction():
    a = actuator(norm_limit=1.0)
    np.testing.assert_allclose(a.hold((3.0, 4.0, 0.0)), (0.6, 0.8, 0.0), rtol=1e-15)
    b = actuator(axis_limit=2.0, norm_limit=1.0)  # axis clip first, then the norm
    np.testing.assert_allclose(b.hold((3.0, 0.0, 0.0)), (1.0, 0.0, 0.0))


def test_slew_rate_limit_per_control_period():
    a = actuator(slew_rate_limit_per_s=1.0)  # 1 N m/s -> 0.1 N m per period
    outs = [a.hold((10.0, -10.0, 0.05))[0] for _ in range(3)]
    np.testing.assert_allclose(outs, (0.1, 0.2, 0.3), rtol=1e-14)
    assert a.held[1] == pytest.approx(-0.3) and a.held[2] == 0.05
    assert a.slew_rate_limited_count == 3


def test_each_axis_moves_from_its_own_previous_value():
    """The rate limit per axis: from (0.05, -0.05, 0.02), a command 0.07 N m away on every axis (inside the
    0.1 N m step) is taken as it is; 0.3 away, each axis moves one step from its own value."""
    a = actuator(slew_rate_limit_per_s=1.0)
    assert a.hold((0.05, -0.05, 0.02)) == (0.05, -0.05, 0.02)
    np.testing.assert_allclose(a.hold((0.12, -0.12, 0.09)), (0.12, -0.12, 0.09), rtol=1e-14)
    np.testing.assert_allclose(a.hold((0.42, -0.42, -0.21)), (0.22, -0.22, -0.01), rtol=1e-13)
    assert a.slew_rate_limited_count == 1


# ----------------------------------------------------------------- zero-order hold through the plant


def test_plant_holds_the_command_over_the_period_and_refuses_nan():
    plant = bare_irassi()
    assert plant.apply({"u_body": (0.0, 2.0, 0.0)})
    plant.advance()
    # principal axis: w = u dt / Jy exactly (no gyroscopic coupling)
    assert plant.truth()["w"][1] == pytest.approx(2.0 * 0.1 / JY, rel=1e-13)
    assert plant.truth()["applied"] == (0.0, 2.0, 0.0)
    assert not plant.apply({"u_body": (math.nan, 0.0, 0.0)})
    plant.advance()  # previous command still held (ZOH)
    assert plant.truth()["w"][1] == pytest.approx(2.0 * 0.2 / JY, rel=1e-13)
    assert plant.counters["bad_commands"] == 1 and plant.counters["commands"] == 2
    assert plant.truth()["effectors"]["actuator.commanded"] == (0.0, 2.0, 0.0)


def test_applied_changes_only_when_the_period_is_integrated():
    plant = bare_irassi()
    plant.apply({"u_body": (1.0, 0.0, 0.0)})
    assert plant.applied == (0.0, 0.0, 0.0) and plant.truth()["commanded"] == (1.0, 0.0, 0.0)
    plant.advance()
    assert plant.applied == (1.0, 0.0, 0.0)


def test_realistic_limit_override_saturates_plant_torque():
    sc = load("irassi_large")
    plant = Plant(load("irassi_large", {"actuator.axis_limit": sc.actuator.realistic_axis_limit}))
    plant.apply({"u_body": (100.0, -100.0, 0.1)})
    plant.advance()
    assert plant.truth()["applied"] == (0.5, -0.5, 0.1)


# ----------------------------------------------------------------- the lag: effector state


def test_lag_is_a_general_effector_with_three_states():
    plant = bare_irassi(**{"actuator.lag_tau_s": 0.5})
    a = plant.actuator
    assert a.form == Form.GENERAL and a.state_size == 3 and plant.effector_state(a) == (0.0, 0.0, 0.0)
    # its derivative: ydot = (c - y) / tau, and the body feels y
    a.hold((1.0, -2.0, 4.0))
    torque, ydot = a.derivative(0.0, plant.body_state(), (0.5, 0.0, 0.0))
    assert torque == (0.5, 0.0, 0.0) and ydot == pytest.approx((1.0, -4.0, 8.0), rel=1e-15)


def test_lag_step_response_and_delivered_impulse():
    tau, dt, n = 0.5, 0.1, 10
    plant = bare_irassi(**{"actuator.lag_tau_s": tau, "integrator.substeps": n})
    plant.apply({"u_body": (0.0, 1.0, -2.0)})
    applied = []
    for _ in range(5):  # 0.5 s = one time constant
        plant.advance()
        applied.append(plant.applied[1])
    y = plant.effector_state(plant.actuator)
    # RK4 with h / tau = 0.02: (h/tau)^5 / 120 ~ 3e-11 per step, ~1e-9 after 50 steps
    assert y[1] == pytest.approx(1.0 - math.exp(-1.0), rel=1e-8)
    assert y[2] == pytest.approx(-2.0 * (1.0 - math.exp(-1.0)), rel=1e-8)
    # delivered impulse: the integral of 1 - exp(-t / tau) over [0, 0.5] ...
    impulse = sum(applied) * dt
    assert impulse == pytest.approx(0.5 - tau * (1 - math.exp(-1.0)), rel=1e-8)
    # ... and exactly what the body received (principal axis from rest: Jy w = impulse)
    assert plant.truth()["w"][1] * JY == pytest.approx(impulse, rel=1e-12)
    assert plant.truth()["effectors"]["actuator.output"] == y


def test_lag_is_fourth_order_in_the_substep():
    def final_w(n):
        plant = bare_irassi(**{"actuator.lag_tau_s": 0.3, "integrator.substeps": n})
        for k in range(30):
            plant.apply({"u_body": (0.0, 50.0 if k % 10 < 5 else -50.0, 0.0)})
            plant.advance()
        return plant.truth()["w"][1]
    ref = final_w(128)
    e = [abs(final_w(n) - ref) for n in (1, 2, 4)]
    assert 12.0 < e[0] / e[1] < 20.0 and 12.0 < e[1] / e[2] < 20.0, e


def test_lag_on_the_orbit_plant():
    # the linear orbit is then integrated by RK4 with the lag (exactly enough: n h ~ 1e-4)
    sc = load("landsat8_q1", {"actuator.lag_tau_s": 1.0, "integrator.substeps": 4})
    lag, ref = Plant(sc), Plant(load("landsat8_q1"))
    for p in (lag, ref):
        p.apply({"u_orbit": (0.1, 0.0, 0.0)})
        for _ in range(600):
            p.advance()
    # 60 s = 60 tau: the lag cost tau * F of impulse, so dv = -tau F / m (to first order in n t)
    dv = lag.truth()["vel"][0] - ref.truth()["vel"][0]
    assert dv == pytest.approx(-1.0 * 0.1 / 2623.0, rel=0.05)
    assert lag.applied == pytest.approx((0.1, 0.0, 0.0), rel=1e-12)


# ----------------------------------------------------------------- the [actuator] section


def test_section_defaults_and_errors():
    assert load("irassi_large").actuator == ActuatorConfig(realistic_axis_limit=0.5)
    assert load("rtc_ex1a").actuator == ActuatorConfig()
    with pytest.raises(ScenarioError, match=r"irassi_large.toml: actuator.axis_limit: must be > 0"):
        load("irassi_large", {"actuator.axis_limit": 0.0})
    with pytest.raises(ScenarioError, match=r"actuator.limit: unknown key"):
        load("irassi_large", {"actuator.limit": 0.5})
    # the lag is integrated by RK4: it must not be shorter than the substep
    with pytest.raises(ScenarioError, match=r"actuator.lag_tau_s: 0.05 s is shorter than the integration step .*"
                                            r"raise integrator.substeps"):
        load("irassi_large", {"actuator.lag_tau_s": 0.05})
    assert load("irassi_large", {"actuator.lag_tau_s": 0.05, "integrator.substeps": 2}).actuator.lag_tau_s == 0.05


# ----------------------------------------------------------------- computation delay, scale factor (issue 22)


def test_delay_periods_holds_each_command_that_many_periods_later():
    a = actuator(delay_periods=2)
    held = []
    for c in ((1.0, 0.0, 0.0), (2.0, 0.0, 0.0), (3.0, 0.0, 0.0), (4.0, 0.0, 0.0)):
        a.command({"u_body": c})
        held.append(a.value()[0])
    assert held == [0.0, 0.0, 1.0, 2.0]


def test_scale_factor_scales_the_limited_command_and_the_slew_limit_sees_the_unscaled_one():
    a = actuator(axis_limit=1.0, scale_factor=2.5)
    assert a.hold((5.0, -0.2, 0.0)) == (2.5, -0.5, 0.0)
    b = actuator(slew_rate_limit_per_s=1.0, scale_factor=2.0)
    outs = [b.hold((10.0, 0.0, 0.0))[0] for _ in range(3)]
    np.testing.assert_allclose(outs, (0.2, 0.4, 0.6), rtol=1e-14)


def test_delay_and_scale_through_the_plant():
    """A 1 N m step commanded once, delayed one period and scaled by 2: the body's rate after two periods is
    what 2 N m over exactly one period gives (w = 2 dt / J), and nothing moved in the first."""
    p = bare_irassi(**{"actuator.delay_periods": 1, "actuator.scale_factor": 2.0})
    p.apply({"u_body": (0.0, 1.0, 0.0)})
    p.advance()
    assert p.body.w[1] == 0.0
    p.apply({"u_body": (0.0, 0.0, 0.0)})
    p.advance()
    assert p.body.w[1] == pytest.approx(2.0 * 0.1 / JY, rel=1e-12)


@pytest.mark.parametrize("key,value,says", [("delay_periods", 1.5, "integer"), ("delay_periods", -1, ">= 0"),
                                            ("delay_periods", 101, "at most 100"), ("scale_factor", 0.0, "> 0")])
def test_delay_and_scale_keys_are_checked(key, value, says):
    with pytest.raises(ScenarioError, match=says) as e:
        load("irassi_large", {f"actuator.{key}": value})
    assert f"actuator.{key}" in str(e.value)
