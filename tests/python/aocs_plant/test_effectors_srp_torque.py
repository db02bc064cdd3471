"""Solar radiation pressure torque (SPEC 3.3) against the formula written out here."""
import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors import srp_torque as srp

F10 = 1361.0 / 299792458.0 * (1 + 0.6) * 10.0   # (Pe / c)(1 + Y) A at 1 AU, A = 10 m^2, Y = 0.6


def test_force_and_torque():
    assert srp.srp_force_magnitude(10.0, 0.6) == pytest.approx(F10, rel=1e-15)
    assert srp.srp_force_magnitude(10.0, 0.6, distance_au=2.0) == pytest.approx(F10 / 4, rel=1e-15)
    # F x h for F along z and h = 0.1 m along x: (0, 0.1 F, 0)
    np.testing.assert_allclose(srp.srp_torque((0, 0, F10), (0.1, 0, 0)), (0, 0.1 * F10, 0), rtol=1e-15)


def _sc(**extra):
    sec = {"enabled": True, "area_m2": 10.0, "reflectivity": 0.6, "direction_b": [0.0, 0.0, 1.0],
           "cp_offset_m": [0.1, 0.0, 0.0]}
    sec.update(extra)
    return load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False,
                                 "disturbances.constant_torque.enabled": False, "disturbances.srp_torque": sec})


def test_srp_torque_enters_the_attitude_plant():
    plant = Plant(_sc())
    np.testing.assert_allclose(plant.truth()["disturbance"], (0.0, 0.1 * F10, 0.0), rtol=1e-14)
    np.testing.assert_allclose(plant.truth()["effectors"]["srp_torque.torque_nm"], (0.0, 0.1 * F10, 0.0), rtol=1e-14)
    plant.advance()
    np.testing.assert_allclose(plant.truth()["w"], (0.0, 0.1 * F10 * 0.1 / 5954.2, 0.0), rtol=1e-6)
    half = Plant(_sc(scale=0.5))
    np.testing.assert_allclose(half.truth()["disturbance"], (0.0, 0.05 * F10, 0.0), rtol=1e-14)


def test_section_errors():
    with pytest.raises(ScenarioError, match=r"disturbances.srp_torque.direction_b: must be a unit vector"):
        _sc(direction_b=[0.0, 1.0, 1.0])
    with pytest.raises(ScenarioError, match=r"disturbances.srp_torque.reflectivity: must be >= 0"):
        _sc(reflectivity=-0.1)
