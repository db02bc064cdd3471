"""The environment (environment/__init__.py): the [environment] section, what an attitude and an orbit
scenario get, the Sun and Earth directions from the spacecraft, the magnetic field slot, and a model
added there (docs/extending.md "Adding an environment model")."""
import math
from datetime import datetime, timezone

import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load
from aocs_plant.environment import AU_M, MODELS, Environment, EnvironmentConfig, OrbitConfig
from aocs_plant.environment import epoch as ep
from aocs_plant.environment.sun import sun_position_au
from aocs_plant.orbit import MU_EARTH

ORBIT = {"radius_m": 7078137.0, "inclination_deg": 98.2, "raan_deg": 10.0, "arg_latitude0_deg": 30.0}


def _error(sid, ov) -> str:
    with pytest.raises(ScenarioError) as err:
        load(sid, ov)
    msg = str(err.value)
    assert "\n" not in msg and msg.startswith(str(load(sid).path) + ": environment")
    return msg.split(": ", 1)[1]


def test_defaults_attitude_has_no_orbit_orbit_has_its_chief():
    sc = load("irassi_large")
    assert sc.environment == EnvironmentConfig() and sc.environment.epoch_utc == ep.J2000
    st = Plant(sc).environment_state()
    assert st["r_n_m"] is None and st["earth_n"] is None and st["b_n_t"] is None
    # no orbit: the Sun from the Earth's centre
    s = np.array(sun_position_au(2451545.0))
    np.testing.assert_allclose(st["sun_n"], s / np.linalg.norm(s), rtol=1e-15)
    assert st["sun_distance_m"] == pytest.approx(np.linalg.norm(s) * AU_M, rel=1e-15)
    orb = load("landsat8_q1")
    assert orb.environment.orbit == OrbitConfig(orb.orbit.orbit_radius_m, orb.orbit.mu)


def test_an_attitude_scenario_with_an_orbit():
    sc = load("geo_hinf", {"environment": {"epoch_utc": "2026-06-21T08:24:00Z", "orbit": ORBIT}})
    assert sc.environment.orbit == OrbitConfig(7078137.0, MU_EARTH, 98.2, 10.0, 30.0)
    p = Plant(sc)
    for _ in range(50):
        p.advance()
    st = p.environment_state()
    r = np.array(st["r_n_m"])
    assert np.linalg.norm(r) == pytest.approx(7078137.0, rel=1e-14)
    np.testing.assert_allclose(st["earth_n"], -r / np.linalg.norm(r), rtol=1e-15)
    # the Sun from the spacecraft: the geocentric Sun less the spacecraft's position (a 1e-5 rad parallax)
    jd = ep.julian_date(datetime(2026, 6, 21, 8, 24, tzinfo=timezone.utc)) + p.t / 86400.0
    d = np.array(sun_position_au(jd)) * AU_M - r
    np.testing.assert_allclose(st["sun_n"], d / np.linalg.norm(d), rtol=1e-14, atol=1e-15)
    assert st["sun_n"][2] == pytest.approx(math.sin(math.radians(23.436)), abs=2e-4)   # the June solstice


def test_epoch_as_a_toml_datetime_or_a_string():
    a = load("irassi_large", {"environment.epoch_utc": datetime(2026, 3, 20, 14, 46)}).environment
    b = load("irassi_large", {"environment.epoch_utc": "2026-03-20T14:46:00Z"}).environment
    assert a == b and Environment(a).julian_date(86400.0) == ep.julian_date(a.epoch_utc) + 1.0


@pytest.mark.parametrize("sid,ov,what", [
    ("irassi_large", {"environment.epoch_utc": "yesterday"}, "environment.epoch_utc: 'yesterday' is not an ISO 8601"),
    ("irassi_large", {"environment.epoch_utc": "2077-01-01T00:00:00Z"}, "environment.epoch_utc: 2077-01-01T00:00:00"
                                                                        "+00:00 is outside 1950 to 2050"),
    ("irassi_large", {"environment.orbit": {"inclination_deg": 10.0}}, "environment.orbit.radius_m: missing required"),
    ("irassi_large", {"environment.orbit": dict(ORBIT, inclination_deg=181.0)},
     "environment.orbit.inclination_deg: 181 deg is outside [0, 180] deg"),
    ("landsat8_q1", {"environment.orbit": {"radius_m": 7e6}}, "environment.orbit.radius_m: an orbit scenario's "
                                                              "reference orbit is its chief's"),
    ("irassi_large", {"environment.magnetic_field": {"model": "wmm"}},
     "environment.magnetic_field.model: unknown value 'wmm', expected one of none, igrf"),
    ("irassi_large", {"environment.sun": True}, "environment.sun: unknown key"),
])
def test_section_errors_name_the_key(sid, ov, what):
    assert _error(sid, ov).startswith(what)


def test_the_magnetic_field_slot_answers_none():
    env = Environment(EnvironmentConfig(orbit=OrbitConfig(7e6, MU_EARTH)))
    assert env.magnetic_field(0.0, env.orbit_state(0.0)[0]) is None and env.magnetic_field(0.0, None) is None


# ----------------------------------------------------------------- a model added (docs/extending.md)

class ToyDipole:
    """A centred dipole along -z_N: B = (mu0 / 4 pi) (3 (m . r_hat) r_hat - m) / r^3, m = -7.94e22 A m^2 z."""

    name = "toy_dipole"

    def field_n_t(self, jd, r_n_m):
        m = (0.0, 0.0, -7.94e22)
        r = math.sqrt(sum(x * x for x in r_n_m))
        u = [x / r for x in r_n_m]
        mu = sum(a * b for a, b in zip(m, u))
        return tuple(1e-7 * (3.0 * mu * u[i] - m[i]) / r ** 3 for i in range(3))


def test_a_field_model_added_to_the_slot_is_selected_by_the_scenario(monkeypatch):
    monkeypatch.setitem(MODELS, "toy_dipole", ToyDipole)
    sc = load("irassi_large", {"environment": {"orbit": dict(ORBIT, inclination_deg=0.0, raan_deg=0.0,
                                                               arg_latitude0_deg=0.0),
                                                "magnetic_field": {"model": "toy_dipole"}}})
    b = Plant(sc).environment_state()["b_n_t"]
    # on the equator the dipole field is -m / r^3 (mu0 / 4 pi): 7.94e15 / R^3 = 22.4 uT, along +z
    assert b == pytest.approx((0.0, 0.0, 1e-7 * 7.94e22 / 7078137.0 ** 3), rel=1e-12, abs=1e-20)
    assert 2.2e-5 < b[2] < 2.3e-5


def test_effectors_get_the_plants_environment(monkeypatch):
    from aocs_plant.effectors import REGISTRY, Effector

    seen = []

    class Probe(Effector):
        kind = "probe"

        @classmethod
        def read(cls, sec, ctx):
            return sec.boolean("enabled")

        @staticmethod
        def active(config):
            return config

        def __init__(self, config, body):
            super().__init__(config, body)
            seen.append(body.environment)

    monkeypatch.setitem(REGISTRY, "probe", Probe)
    p = Plant(load("irassi_large", {"disturbances.probe": {"enabled": True}}))
    assert seen == [p.environment] and p.sensors and all(s.kind == "attitude" for s in p.sensors)
