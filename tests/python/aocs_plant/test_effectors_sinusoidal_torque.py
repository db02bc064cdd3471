"""Sinusoidal disturbance torque (aocs_plant.effectors.sinusoidal_torque) against hand evaluations:
the torque at any time, the plant's response against the closed-form integral, the section's errors."""
from __future__ import annotations

import math

import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load

SECTION = "disturbances.sinusoidal_torque"


def _scenario(amp=(1e-3, 2e-3, 0.0), freq=(0.5, 0.1, 0.0), phase=(0.3, 0.0, 0.0), **extra):
    ov = {"disturbances.constant_torque.enabled": False, "disturbances.gravity_gradient_l2.enabled": False,
          f"{SECTION}.enabled": True, f"{SECTION}.amplitude_nm": list(amp), f"{SECTION}.frequency_rad_s": list(freq),
          f"{SECTION}.phase_rad": list(phase), "duration_s": 20.0, "metrics.window_s": 20.0}
    ov.update(extra)
    return load("irassi_small", ov)


def test_torque_is_the_sinusoid_per_axis():
    p = Plant(_scenario())
    (eff,) = [e for e in p.effectors if e.kind == "sinusoidal_torque"]
    for t in (0.0, 1.3, 7.77):
        want = (1e-3 * math.sin(0.5 * t + 0.3), 2e-3 * math.sin(0.1 * t), 0.0)
        assert eff.torque(t) == pytest.approx(want, abs=1e-18)
    assert p.truth()["effectors"]["sinusoidal_torque.torque_nm"] == pytest.approx((1e-3 * math.sin(0.3), 0.0, 0.0))


def test_the_disturbance_is_the_sum_with_the_constant_torque_per_axis():
    """plant.disturbance() (what the log's truth records as torque_dist) with a constant torque (1, 2, 3) mN m
    as well: the sum axis by axis, the constant part first and the sinusoid added to it."""
    p = Plant(_scenario(**{"disturbances.constant_torque.enabled": True,
                           "disturbances.constant_torque.torque_nm": [1e-3, 2e-3, 3e-3],
                           "disturbances.constant_torque.scale": 1.0}))
    want = (1e-3 + 1e-3 * math.sin(0.3), 2e-3, 3e-3)
    assert p.disturbance() == pytest.approx(want, rel=1e-15)


def test_the_body_integrates_the_sinusoid_to_rk4_accuracy():
    """From rest with a tiny torque the body barely turns, so w(t) = J^-1 int u dt:
    int a sin(w t + p) dt = a (cos p - cos(w t + p)) / w, closed form here."""
    sc = _scenario()
    p = Plant(sc)
    for _ in range(sc.n_steps):
        p.advance()
    t = sc.duration_s
    J = np.diag(np.array(sc.attitude.inertia)[[0, 1, 2], [0, 1, 2]])
    impulse = np.array([1e-3 * (math.cos(0.3) - math.cos(0.5 * t + 0.3)) / 0.5,
                        2e-3 * (1.0 - math.cos(0.1 * t)) / 0.1, 0.0])
    want = np.linalg.solve(J, impulse)
    # the gyroscopic term w x J w couples the axes at second order in the tiny rates
    np.testing.assert_allclose(p.truth()["w"], want, rtol=1e-6, atol=1e-5 * np.abs(want).max())


def test_section_errors_name_the_key():
    with pytest.raises(ScenarioError, match=f"{SECTION}.amplitude_nm"):
        _scenario(amp=(-1.0, 0.0, 0.0))
    with pytest.raises(ScenarioError, match=f"{SECTION}.frequency_rad_s: 10 rad/s advances 1 rad per RK4 substep"):
        _scenario(freq=(10.0, 0.0, 0.0))
    assert _scenario(freq=(10.0, 0.0, 0.0), **{"integrator.substeps": 2}).substeps == 2
