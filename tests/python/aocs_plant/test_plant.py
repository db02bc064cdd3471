"""Plant facade: time base, target motion, truth, closed-loop smoke runs, benchmark.

The closed-loop runs use small control laws written here from SPEC 2 (not the
firmware) only to show that each scenario's plant, duration and settle
criterion fit together.
"""
import math

import numpy as np
import pytest
from scipy.linalg import solve_continuous_are

from aocs_core.conventions import quat_error, quat_to_crp, quat_to_dcm, quat_to_euler321
from aocs_plant import Plant, integrate_open_loop, load
from aocs_plant.orbit import bryson_matrices


def test_time_is_period_count_times_dt():
    plant = Plant(load("rtc_ex1a"))
    for _ in range(1000):
        plant.advance()
    assert plant.t == 1000 * 0.01 and plant.k == 1000 and plant.counters["steps"] == 1000
    with pytest.raises(ValueError):
        plant.sense(0.5)
    assert plant.sense(10.0)["seq"] == 1000


def test_rotating_target_follows_the_lvlh_frame():
    sc = load("geo_hinf")
    plant = Plant(sc)
    w0 = 7.292115e-5
    t = 0.25 * 2 * math.pi / w0  # a quarter orbit
    qd, wd = plant.target(t)
    assert wd == (0.0, -w0, 0.0)
    # A_ON(t) = A2(-w0 t): at a quarter orbit the LVLH z axis (nadir) is -x_N
    a = np.array(quat_to_dcm(qd))
    np.testing.assert_allclose(a[2], (-1.0, 0.0, 0.0), atol=1e-12)


def test_a_target_turning_at_1_rad_s_about_x_turns():
    """qd(t) = dq(wd t) (x) qd0 for any non-zero wd, 1 rad/s about x included (only wd = 0 is held at qd0):
    A(qd(t)) = A_x(wd t) A(qd0), the frame turned 0.5 rad about its x axis after 0.5 s."""
    plant = Plant(load("irassi_large", {"target.wd": [1.0, 0.0, 0.0]}))
    qd0, _ = plant.target(0.0)
    qd, wd = plant.target(0.5)
    assert wd == (1.0, 0.0, 0.0)
    c, s = math.cos(0.5), math.sin(0.5)
    a_x = np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])
    np.testing.assert_allclose(np.array(quat_to_dcm(qd)), a_x @ np.array(quat_to_dcm(qd0)), atol=1e-14)


def test_geo_plant_starts_with_the_stated_small_errors():
    plant = Plant(load("geo_hinf"))
    qd, _ = plant.target()
    e = np.degrees(quat_to_euler321(quat_error(plant.truth()["q"], qd)))
    np.testing.assert_allclose(e, (0.5, -0.5, 0.5), atol=1e-12)


def test_truth_contents():
    tr = Plant(load("irassi_large")).truth()
    for key in ("t", "q", "w", "q_target", "w_target", "pointing_rad", "pointing_arcsec",
                "qe_arcsec", "disturbance", "applied", "commanded"):
        assert key in tr
    tr = Plant(load("landsat8_q1")).truth()
    assert tr["pos"] == (50.0, -100.0, 350.0) and tr["vel"] == (1.0, -1.0, -6.0)


def _run(sc, law, settled):
    plant = Plant(sc)
    last_out = 0.0
    for _ in range(sc.n_steps):
        s = plant.sense()
        plant.apply({"u_body" if sc.kind == "attitude" else "u_orbit": law(s, plant)})
        plant.advance()
        if not settled(plant.truth()):
            last_out = plant.t
    return last_out, plant


def test_rtc_ex2a_settles_under_crp_linear():
    sc = load("rtc_ex2a")
    k1, k2 = sc.law.params["k1"], sc.law.params["k2"]

    def law(s, plant):
        qe = quat_error(s["q"], plant.target()[0])
        if qe[3] < 0:
            qe = tuple(-x for x in qe)
        rho = quat_to_crp(qe)
        return tuple(-k1 * s["w"][i] - k2 * rho[i] for i in range(3))

    def settled(tr):
        q = tr["q"] if tr["q"][3] >= 0 else tuple(-x for x in tr["q"])
        return (np.linalg.norm(quat_to_crp(q)) < sc.settle.rho_norm_max
                and np.linalg.norm(tr["w"]) < sc.settle.w_norm_max_rad_s)

    t_settle, _ = _run(sc, law, settled)
    assert 5.0 < t_settle < 0.75 * sc.duration_s


def test_landsat8_q1_settles_under_orbit_lqr():
    sc = load("landsat8_q1")
    A, B = bryson_matrices(sc.orbit.n, sc.orbit.mass_kg)
    tab = sc.law.tables[sc.law.table]
    Q, R = np.diag(tab["q"]), np.diag(tab["r"])
    K = np.linalg.solve(R, B.T @ solve_continuous_are(A, B, Q, R))

    def law(s, plant):
        return tuple(-K @ np.array(s["vel"] + s["pos"]))

    def settled(tr):
        return (max(map(abs, tr["pos"])) < sc.settle.pos_abs_max_m
                and max(map(abs, tr["vel"])) < sc.settle.vel_abs_max_m_s)

    t_settle, _ = _run(sc, law, settled)
    assert 100.0 < t_settle < 0.5 * sc.duration_s


def test_integrate_open_loop_benchmark_runs():
    sc = load("irassi_large")
    wall = integrate_open_loop(sc, 200)
    assert 0.0 < wall < 5.0
