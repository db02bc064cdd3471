"""The spacecraft's orbit in N (environment/reference_orbit.py): the circular reference orbit, Bryson's
frame in N, and the orbit plant's relative state added, against a two-body integration in N done here."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from aocs_plant import Plant, load
from aocs_plant.environment.reference_orbit import CircularOrbit
from aocs_plant.orbit import MU_EARTH

R = 7078137.0
INC, RAAN, U0 = math.radians(98.2), math.radians(40.0), math.radians(-25.0)


def test_circular_orbit_geometry():
    o = CircularOrbit(R, MU_EARTH, INC, RAAN, U0)
    n = math.sqrt(MU_EARTH / R ** 3)
    for t in (0.0, 1234.5, 5000.0):
        r, v = map(np.array, o.reference(t))
        assert np.linalg.norm(r) == pytest.approx(R, rel=1e-14)
        assert np.linalg.norm(v) == pytest.approx(math.sqrt(MU_EARTH / R), rel=1e-14)
        assert abs(r @ v) < 1e-6 * R
        h = np.cross(r, v) / (R * np.linalg.norm(v))
        assert h[2] == pytest.approx(math.cos(INC), abs=1e-14)                      # inclination
        node = np.cross((0.0, 0.0, 1.0), h)
        assert math.atan2(node[1], node[0]) == pytest.approx(RAAN, abs=1e-12)      # ascending node
        # the argument of latitude advances at n from u0: the angle from the node
        u = math.atan2(r @ np.cross(h, node / np.linalg.norm(node)), r @ node / np.linalg.norm(node))
        assert (u - U0 - n * t + math.pi) % (2 * math.pi) - math.pi == pytest.approx(0.0, abs=1e-12)
        o1, o2, o3 = map(np.array, o.frame(t))
        np.testing.assert_allclose(np.array([o1, o2, o3]) @ np.array([o1, o2, o3]).T, np.eye(3), atol=1e-15)
        np.testing.assert_allclose(np.cross(o1, o2), o3, atol=1e-15)                 # right-handed
        np.testing.assert_allclose(o3, -r / R, atol=1e-15)                            # nadir
        np.testing.assert_allclose(o2, -h, atol=1e-15)                                # minus the orbit normal
        np.testing.assert_allclose(o1, v / np.linalg.norm(v), atol=1e-15)            # along-track


def _two_body(r0, v0, t_end):
    def f(_, y):
        r = y[:3]
        return np.concatenate([y[3:], -MU_EARTH * r / np.linalg.norm(r) ** 3])
    sol = solve_ivp(f, (0.0, t_end), np.concatenate([r0, v0]), method="DOP853", rtol=1e-13, atol=1e-9)
    return sol.y[:3, -1], sol.y[3:, -1]


def test_the_orbit_plant_state_in_n_is_two_body_motion():
    """The nonlinear orbit plant is exact two-body relative motion about the chief (orbit.py): mapped to N
    with the chief's orbit and frame, its state must follow the two-body motion integrated in N from the
    same start (the plant's RK4 at 10 substeps: mm over 1500 s)."""
    ov = {"plant.model": "nonlinear", "integrator.substeps": 10, "environment.orbit": {
        "inclination_deg": 98.2, "raan_deg": 40.0, "arg_latitude0_deg": -25.0}}
    p = Plant(load("landsat8_q1", ov))
    st0 = p.environment_state()
    r0, v0 = np.array(st0["r_n_m"]), np.array(st0["v_n_m_s"])
    rc0, _ = p.environment.orbit.reference(0.0)
    assert np.linalg.norm(r0 - rc0) == pytest.approx(math.sqrt(50 ** 2 + 100 ** 2 + 350 ** 2), rel=1e-9)
    for _ in range(15000):
        p.advance()
    r_ref, v_ref = _two_body(r0, v0, p.t)
    st = p.environment_state()
    assert np.linalg.norm(np.array(st["r_n_m"]) - r_ref) < 5e-3
    assert np.linalg.norm(np.array(st["v_n_m_s"]) - v_ref) < 5e-6
    # the relative motion was real: the spacecraft drifted from the chief by more than its start offset
    rc, _ = p.environment.orbit.reference(p.t)
    assert np.linalg.norm(np.array(st["r_n_m"]) - rc) > 400.0


def test_zero_relative_state_is_the_reference():
    o = CircularOrbit(R, MU_EARTH, INC, RAAN, U0)
    assert o.state(100.0, (0.0,) * 6) == o.reference(100.0) == o.state(100.0)
