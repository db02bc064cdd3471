"""Constant SRP force on the orbit plant (SPEC 3.3)."""
import pytest

from aocs_plant import Plant, ScenarioError, load

MASS = 2623.0


def test_constant_srp_force_changes_velocity_by_f_t_over_m():
    sc = load("landsat8_srp", {"control.enabled": False})
    plant = Plant(sc)
    F = 4.4e-6 * 3.0  # N along x
    assert plant.truth()["disturbance"] == pytest.approx((F, 0.0, 0.0), rel=1e-15)
    assert plant.truth()["effectors"]["srp_force.force_n"] == pytest.approx((F, 0.0, 0.0), rel=1e-15)
    assert sc.disturbances.srp_force.force_n == pytest.approx((F, 0.0, 0.0), rel=1e-15)
    for _ in range(100):  # 10 s
        plant.advance()
    dv = plant.truth()["vel"][0]
    # first order in n t = 0.01: the rotating-frame coupling changes it by < 1e-4 relative
    assert dv == pytest.approx(F * 10.0 / MASS, rel=1e-3)


def test_scale_and_section_errors():
    half = Plant(load("landsat8_srp", {"disturbances.srp_force.scale": 0.5}))
    assert half.disturbance() == pytest.approx((2.2e-6 * 3.0, 0.0, 0.0), rel=1e-15)
    with pytest.raises(ScenarioError, match=r"disturbances.srp_force.direction: must be a unit vector"):
        load("landsat8_srp", {"disturbances.srp_force.direction": [1.0, 1.0, 0.0]})
    with pytest.raises(ScenarioError, match=r"disturbances.srp_force: disturbance 'srp_force' does not apply to a "
                                            r"attitude scenario"):
        load("irassi_large", {"disturbances.srp_force": {"enabled": True}})
