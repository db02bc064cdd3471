"""Impulsive delta-v on the orbit plant (SPEC 3.3, debris hit): a DISCRETE effector."""
import numpy as np
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


def test_a_moving_spacecraft_integrates_every_period_of_the_split_one_whole():
    """From a moving state the periods before the hit (its event pending) are flown like any period (the
    impulse disabled: the same state bit for bit), and the period of a hit at 60.05 s is the two halves flown
    apart: 0.05 s, the jump, 0.05 s (the same plant without the impulse, its state kicked by hand)."""
    x0 = [1e-3, -2e-3, 5e-4, 10.0, -4.0, 2.5]
    hit = Plant(load("landsat8_debris", {"control.enabled": False, "plant.x0": x0,
                                         "disturbances.impulse.time_s": 60.05}))
    ref = Plant(load("landsat8_debris", {"control.enabled": False, "plant.x0": x0,
                                         "disturbances.impulse.enabled": False}))
    for _ in range(600):
        hit.advance()
        ref.advance()
    assert hit.orbit.x == ref.orbit.x and any(v != x0[i] for i, v in enumerate(ref.orbit.x))
    hit.advance()
    ref._segment(60.0, 0.05, (0.0, 0.0, 0.0))
    kicked = list(ref.orbit.x)
    kicked[0] += 0.015424
    ref.orbit.x = tuple(kicked)
    ref._segment(60.05, 0.05, (0.0, 0.0, 0.0))
    np.testing.assert_allclose(hit.orbit.x, ref.orbit.x, rtol=1e-12, atol=1e-15)


def test_the_jump_is_delta_v_along_its_direction_on_every_axis():
    """jump(): the inertial velocity (u, v, w) moves by scale x delta_v_m_s x direction, each component on its
    own axis; the position does not jump."""
    sc = load("landsat8_debris", {"disturbances.impulse.direction": [0.0, 0.6, -0.8],
                                  "disturbances.impulse.scale": 2.0})
    imp, = [e for e in Plant(sc).effectors if e.kind == "impulse"]
    body = (1e-3, -2e-3, 3e-3, 10.0, 20.0, 30.0)
    dv = 2.0 * 0.015424
    np.testing.assert_allclose(imp.jump(60.0, body), (1e-3, -2e-3 + 0.6 * dv, 3e-3 - 0.8 * dv, 10.0, 20.0, 30.0),
                               rtol=1e-15)


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
