"""The eigenaxis bang-bang bound (sil/aocs_analysis/slew_bound.py, SPEC 5.1): the IRASSI figures of
SPEC 5.1 and an independent check of the formula (a numerically integrated bang-bang slew about e,
torque J alpha e on the binding axis at the limit)."""
import math

import numpy as np
import pytest

from aocs_analysis import slew_bound as sb
from aocs_core.conventions import euler321_deg_to_quat, quat_from_axis_angle, quat_mul
from aocs_plant.scenario import load


@pytest.mark.parametrize("limit, bound", [(1.0, 114.3), (0.5, 161.6), (0.2, 255.6)])
def test_irassi_large_bounds_of_spec(limit, bound):
    sc = load("irassi_large", {"actuator.axis_limit": limit})
    theta, _ = sb.eigenaxis(sc.attitude.q0, sc.target.qd0)
    assert math.degrees(theta) == pytest.approx(39.31, abs=0.005)
    assert sb.scenario_slew_bound_s(sc) == pytest.approx(bound, abs=0.05)


def test_no_limit_no_bound_and_orbit():
    assert sb.scenario_slew_bound_s(load("irassi_large")) is None
    assert sb.slew_bound_s(np.eye(3), (0, 0, 0, 1), (0, 0, 0, 1), 1.0, None) == 0.0


def test_no_rotation_is_zero_about_a_unit_axis():
    """qf = q0 (either sign): theta = 0, and the axis returned is still a unit vector (any will do)."""
    q = (0.1, -0.2, 0.3, math.sqrt(1.0 - 0.14))
    for qf in (q, tuple(-x for x in q)):
        theta, e = sb.eigenaxis(q, qf)
        assert theta == 0.0 and np.linalg.norm(e) == 1.0


def test_a_half_turn_is_pi_about_its_own_axis():
    """qf = (0, 1, 0, 0) from the identity: |vector part| = 1 exactly, a rotation of pi about y (not no
    rotation), whose bound is 2 sqrt(pi / alpha) with alpha = u / J_yy."""
    theta, e = sb.eigenaxis((0.0, 0.0, 0.0, 1.0), (0.0, 1.0, 0.0, 0.0))
    assert theta == pytest.approx(math.pi, rel=1e-15) and e.tolist() == [0.0, 1.0, 0.0]
    j = np.diag([10.0, 20.0, 30.0])
    assert sb.slew_bound_s(j, (0.0, 0.0, 0.0, 1.0), (0.0, 1.0, 0.0, 0.0), 0.5, None) == pytest.approx(
        2.0 * math.sqrt(math.pi / (0.5 / 20.0)), rel=1e-14)


def test_bound_by_integration_and_sign_invariance():
    rng = np.random.default_rng(3)
    j = np.diag([10.0, 20.0, 30.0])
    for _ in range(5):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        theta = rng.uniform(0.1, 3.0)
        q0 = tuple(euler321_deg_to_quat(rng.uniform(-90, 90, size=3)))
        qf = quat_mul(quat_from_axis_angle(axis, theta), q0)
        u = 0.7
        t_b = sb.slew_bound_s(j, q0, qf, u, None)
        # independent: the binding axis reaches |u| exactly; integrate theta'' = +-alpha over t_b
        je = j @ axis
        alpha = u / np.max(np.abs(je))
        n = 20000
        h = t_b / n
        th, w = 0.0, 0.0
        for k in range(n):
            a = alpha if (k + 0.5) * h < t_b / 2 else -alpha
            th += w * h + 0.5 * a * h * h
            w += a * h
        assert th == pytest.approx(theta, rel=1e-9)
        assert abs(w) < 1e-9
        # q and -q: the same slew
        assert sb.slew_bound_s(j, tuple(-x for x in q0), qf, u, None) == pytest.approx(t_b, rel=1e-12)
        # the norm ball binds |J e| instead
        assert sb.slew_bound_s(j, q0, qf, None, u) == pytest.approx(
            2.0 * math.sqrt(theta * np.linalg.norm(je) / u), rel=1e-12)


def test_the_wheel_envelope_is_the_spec_5_3_pyramid():
    """SPEC 5.3: about 0.58 N m on the pyramid axis (4 * 0.25 / sqrt 3), 0.41 N m transverse
    (2 * 0.25 sqrt(2/3)); the scenario's bound uses the healthy wheels only."""
    import math

    import numpy as np

    from aocs_analysis import slew_bound
    from aocs_plant import load

    w = load("irassi_rw").effectors["wheels"]          # pyramid about body x
    eye = np.eye(3)
    assert slew_bound.alpha_max(eye, [1.0, 0.0, 0.0], None, None, w) == pytest.approx(1.0 / math.sqrt(3), rel=1e-12)
    assert slew_bound.alpha_max(eye, [0.0, 1.0, 0.0], None, None, w) == pytest.approx(0.5 * math.sqrt(2 / 3), rel=1e-12)
    # a limit tighter than the wheels wins
    assert slew_bound.alpha_max(eye, [0.0, 1.0, 0.0], 0.1, None, w) == pytest.approx(0.1)
    full = slew_bound.scenario_slew_bound_s(load("irassi_rw"))
    reduced = slew_bound.scenario_slew_bound_s(load("irassi_rw_failed"))
    assert full == pytest.approx(186.84, abs=0.01) and reduced == pytest.approx(252.98, abs=0.01)


def test_a_wheel_the_axis_does_not_use_does_not_limit_it():
    """Three wheels on the body axes with limits 0.1, 0.05 and 0.02 N m, J = diag(2, 4, 8): about x only the x
    wheel works (the others' share is exactly 0), alpha = 0.1 / 2; about y, 0.05 / 4; a failed wheel leaves
    the allocation too (the y wheel failed: about x still 0.1 / 2)."""
    import types
    w = types.SimpleNamespace(n=3, failed=(), axes=[(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)],
                              torque_limit_nm=[0.1, 0.05, 0.02])
    j = np.diag([2.0, 4.0, 8.0])
    assert sb.alpha_max(j, [1.0, 0.0, 0.0], None, None, w) == 0.1 / 2.0
    assert sb.alpha_max(j, [0.0, 1.0, 0.0], None, None, w) == 0.05 / 4.0
    failed = types.SimpleNamespace(**{**vars(w), "failed": (1,)})
    assert sb.alpha_max(j, [1.0, 0.0, 0.0], None, None, failed) == 0.1 / 2.0
