"""Constant disturbance torque (SPEC 3.3): its section, its value, the plant feels it."""
import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors import BodyContext, Form
from aocs_plant.effectors.constant_torque import ConstantTorque, ConstantTorqueConfig


def test_value_is_scale_times_torque_and_constant():
    e = ConstantTorque(ConstantTorqueConfig(True, 0.5, (1.0, -2.0, 4.0)), BodyContext("attitude", 0.1, 1, 0))
    assert e.form == Form.CONSTANT and e.state_size == 0
    assert e.value() == (0.5, -1.0, 2.0)
    assert e.truth(3.0, (0, 0, 0, 1, 0, 0, 0), ()) == {"torque_nm": (0.5, -1.0, 2.0)}


def test_disturbance_scale_and_enable_flags():
    base = Plant(load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False}))
    assert base.truth()["disturbance"] == pytest.approx((1.18e-3,) * 3, rel=1e-15)
    assert base.truth()["effectors"]["constant_torque.torque_nm"] == pytest.approx((1.18e-3,) * 3, rel=1e-15)
    half = Plant(load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False,
                                       "disturbances.constant_torque.scale": 0.5}))
    assert half.truth()["disturbance"] == pytest.approx((0.59e-3,) * 3, rel=1e-15)
    off = Plant(load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False,
                                      "disturbances.constant_torque.enabled": False}))
    assert off.truth()["disturbance"] == (0.0, 0.0, 0.0)
    assert "constant_torque.torque_nm" not in off.truth()["effectors"]  # a disabled section builds nothing


def test_the_body_feels_it():
    # principal axes at rest, no other torque: w(t) = J^-1 u t exactly (no gyroscopic coupling)
    plant = Plant(load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False,
                                        "disturbances.constant_torque.torque_nm": [0.0, 2e-3, 0.0],
                                        "plant.euler321_deg": [0.0, 0.0, 0.0]}))
    for _ in range(10):
        plant.advance()
    np.testing.assert_allclose(plant.truth()["w"], (0.0, 2e-3 * 1.0 / 5954.2, 0.0), rtol=1e-13, atol=1e-20)


def test_section_errors():
    with pytest.raises(ScenarioError, match=r"disturbances.constant_torque.torque_nm: missing required key"):
        load("irassi_large", {"disturbances.constant_torque.torque_nm": None})
    with pytest.raises(ScenarioError, match=r"disturbances.constant_torque.scale: must be >= 0"):
        load("irassi_large", {"disturbances.constant_torque.scale": -1.0})
    with pytest.raises(ScenarioError, match=r"disturbances.constant_torque.enabled: expected true or false"):
        load("irassi_large", {"disturbances.constant_torque.enabled": 1})
