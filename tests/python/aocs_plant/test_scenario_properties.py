"""Property-based tests (hypothesis) of the scenario loader: whatever value an override gives a key,
the loader returns a valid scenario or raises ScenarioError with a one-line message naming the file
and the key; never another exception (issue 11, item 5)."""
from __future__ import annotations

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from aocs_plant.scenario import ScenarioError, load

NUMBERS = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10 ** 400, 10 ** 400),
                    st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 1e308, 1e9, -1.0]))
VALUES = st.one_of(NUMBERS, st.booleans(), st.text(max_size=8), st.lists(NUMBERS, max_size=5),
                   st.lists(st.lists(NUMBERS, max_size=4), max_size=4), st.dictionaries(st.text(max_size=4), NUMBERS,
                                                                                       max_size=2))
KEYS = {
    "irassi_small": ["control_rate_hz", "duration_s", "seed", "integrator.substeps", "integrator.tolerance_arcsec",
                     "plant.w0", "plant.euler321_deg", "plant.inertia", "laws.quat_pd.kp", "laws.smc.eps",
                     "actuator.axis_limit", "actuator.norm_limit", "actuator.slew_rate_limit_per_s", "actuator.lag_tau_s",
                     "disturbances.constant_torque.torque_nm", "disturbances.constant_torque.scale",
                     "disturbances.sinusoidal_torque.frequency_rad_s", "metrics.window_s", "settle.pointing_arcsec_max",
                     "target.wd", "laws.lqr_quat.table", "laws.quat_pd.kq"],
    "rtc_ex1a": ["plant.rho", "laws.crp_linear.k1"],
    "gao_mrp": ["plant.sigma", "laws.mrp_sat.l2", "laws.mrp_sat.u_max", "laws.mrp_sat_tanh.m3"],
    "landsat8_debris": ["disturbances.impulse.time_s", "disturbances.impulse.delta_v_m_s", "plant.x0"],
}
CASES = [(sid, key) for sid, keys in KEYS.items() for key in keys]


def _check(sid, key, value):
    try:
        sc = load(sid, {key: value})
    except ScenarioError as exc:
        msg = str(exc)
        assert "\n" not in msg and msg.split(": ", 1)[0].endswith(f"{sid}.toml"), msg
        return
    # accepted: then the run it describes is one the flight software and the tick arithmetic can follow
    assert sc.n_steps >= 1 and math.isfinite(sc.dt) and sc.dt > 0.0
    if sc.attitude is not None:
        assert all(math.isfinite(x) for x in sc.attitude.q0)
        assert abs(math.sqrt(sum(x * x for x in sc.attitude.q0)) - 1.0) < 1e-9


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=st.sampled_from(CASES), value=VALUES)
def test_any_override_value_loads_or_is_one_clear_error(case, value):
    _check(*case, value)


@settings(max_examples=150, deadline=None)
@given(sid=st.sampled_from(sorted(KEYS)), key=st.text(min_size=1, max_size=20), value=NUMBERS)
def test_any_key_loads_or_is_one_clear_error(sid, key, value):
    _check(sid, key, value)
