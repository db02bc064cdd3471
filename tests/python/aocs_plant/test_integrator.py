"""The RK4 over a concatenated state (aocs_plant/integrator.py)."""
import math

import pytest

from aocs_plant.integrator import rk4
from aocs_plant.orbit import NonlinearOrbit


def test_one_step_is_the_classical_rk4_polynomial():
    # y' = lam y: one step multiplies by 1 + z + z^2/2 + z^3/6 + z^4/24, z = lam h
    lam, h = -0.7, 0.3
    z = lam * h
    (y,) = rk4(lambda t, y: (lam * y[0],), 0.0, (2.0,), h)
    assert y == pytest.approx(2.0 * (1 + z + z * z / 2 + z ** 3 / 6 + z ** 4 / 24), rel=1e-15)


def test_time_and_extra_arguments_reach_the_right_hand_side():
    # y' = a t^3: RK4 (Simpson in t) integrates cubics exactly
    (y,) = rk4(lambda t, y, a: (a * t ** 3,), 1.0, (0.0,), 0.5, 4.0)
    assert y == pytest.approx(1.5 ** 4 - 1.0, rel=1e-14)


def test_fourth_order_on_a_coupled_system():
    def F(t, y):
        return (y[1], -y[0] - 0.1 * y[1] + math.sin(t))

    def solve(n):
        y, h = (1.0, 0.0), 10.0 / n
        for i in range(n):
            y = rk4(F, i * h, y, h)
        return y
    ref = solve(12800)
    e = [abs(solve(n)[0] - ref[0]) for n in (200, 400, 800)]
    assert 14.0 < e[0] / e[1] < 18.0 and 14.0 < e[1] / e[2] < 18.0, e


def test_same_arithmetic_as_the_nonlinear_orbit_stepper():
    orbit = NonlinearOrbit(3.986004418e14, 7080e3, 2623.0, (1.0, -1.0, -6.0, 50.0, -100.0, 350.0))
    force = (0.01, -0.02, 0.005)
    y = orbit.x
    for _ in range(50):
        y = rk4(lambda t, x: orbit.derivative(x, force), 0.0, y, 0.1)
    orbit.propagate(5.0, force, substeps=50)
    assert y == orbit.x  # bit for bit
