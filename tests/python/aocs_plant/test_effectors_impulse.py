"""Impulsive delta-v on the orbit plant (SPEC 3.3, debris hit): a DISCRETE effector."""
import pytest

from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors import Form


@pytest.mark.parametrize("model", ["linear", "nonlinear"])
def test_debris_impulse_applied_once_at_its_time(model):
    sc = load("landsat8_debris", {"control.enabled": False, "plant.model": model})
    plant = Plant(sc)
    assert [e.form for e in plant.effectors if e.kind == "impulse"] == [Form.DISCRETE]
    while plant.t < 60.0 - 1e-9:
        plant.advance()
    assert plant.k == 600
    assert plant.sense()["vel"] == (0.0, 0.0, 0.0)  # the sample at t = 60 s precedes the hit
    assert not plant.truth()["effectors"]["impulse.applied"]
    plant.advance()
    tr = plant.truth()
    assert tr["effectors"]["impulse.applied"]
    assert tr["vel"][0] == pytest.approx(0.015424, rel=1e-3)  # n * 0.1 s ~ 1e-4
    v_after = tr["vel"][0]
    for _ in range(10):
        plant.advance()
    # no second kick: the velocity only evolves by the slow orbital dynamics
    assert plant.truth()["vel"][0] == pytest.approx(v_after, rel=1e-3)


def test_impulse_between_periods_splits_the_period():
    sc = load("landsat8_debris", {"control.enabled": False, "disturbances.impulse.time_s": 60.05})
    plant = Plant(sc)
    for _ in range(601):
        plant.advance()
    # moving for 0.05 s of the 0.1 s period after the hit
    assert plant.truth()["pos"][0] == pytest.approx(0.015424 * 0.05, rel=1e-2)


def test_disabled_or_scaled():
    off = Plant(load("landsat8_debris", {"control.enabled": False, "disturbances.impulse.enabled": False}))
    half = Plant(load("landsat8_debris", {"control.enabled": False, "disturbances.impulse.scale": 0.5}))
    for p in (off, half):
        for _ in range(601):
            p.advance()
    assert off.truth()["vel"] == (0.0, 0.0, 0.0)
    assert half.truth()["vel"][0] == pytest.approx(0.5 * 0.015424, rel=1e-3)


def test_section_errors():
    with pytest.raises(ScenarioError, match=r"disturbances.impulse.time_s: 3000.0 s is not inside the run"):
        load("landsat8_debris", {"disturbances.impulse.time_s": 3000.0})
