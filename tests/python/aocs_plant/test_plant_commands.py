"""Plant.apply(command): one mapping of named fields, each actuator reading its own (command_fields); a new
actuator module with its own field (the toy thrusters below, the example of docs/extending.md "Adding an
actuator") flies next to the body actuator with nothing else changed."""
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from aocs_plant import Plant, load
from aocs_plant.effectors import ATTITUDE, REGISTRY, Effector, Form

# ----------------------------------------------------------------- the example module of docs/extending.md


@dataclass(frozen=True)
class ThrustersConfig:
    arms: tuple              # per thruster, r_i x d_i: the torque of one newton (N m / N, B)
    max_thrust_n: float


class ToyThrusters(Effector):
    """[toy_thrusters]: two thrusters; the command field "u_thrusters" (N, one per thruster) is clipped to
    [0, max_thrust_n] and held over the period: torque = sum_i (r_i x d_i) f_i."""

    kind = "toy_thrusters"
    group = None                     # a top-level section [toy_thrusters]
    applies_to = (ATTITUDE,)
    role = "actuator"                # takes commands, sums into "applied"; replaces nothing
    form = Form.HELD                 # value() read once per period, after the command

    @classmethod
    def read(cls, sec, ctx):
        a = sec.vector("arms_m", n=6)
        return ThrustersConfig((a[0:3], a[3:6]), sec.number("max_thrust_n", positive=True))

    def __init__(self, config, body):
        super().__init__(config, body)
        self.command_fields = {"u_thrusters": len(config.arms)}   # its own field, one value per thruster
        self.f = (0.0,) * len(config.arms)

    def command(self, cmd):
        f = cmd.get("u_thrusters")
        if f is not None:            # absent: the thrusts of the last command stay
            m = self.config.max_thrust_n
            self.f = tuple(min(m, max(0.0, x)) for x in f)

    def value(self):
        t = [0.0, 0.0, 0.0]
        for a, f in zip(self.config.arms, self.f):
            for i in range(3):
                t[i] += a[i] * f
        return tuple(t)
# end of the example


ARMS = ((0.0, 0.5, 0.0), (0.25, 0.0, -0.5))
DT = 0.01                                         # rtc_ex1a: 100 Hz, J = I3, no disturbance


@pytest.fixture
def thrusters(monkeypatch):
    monkeypatch.setitem(REGISTRY, "toy_thrusters", ToyThrusters)


def _plant():
    return Plant(load("rtc_ex1a", {"plant.w0": [0.0, 0.0, 0.0], "toy_thrusters": {
        "arms_m": [*ARMS[0], *ARMS[1]], "max_thrust_n": 2.0}}))


def test_two_actuators_each_read_their_own_field(thrusters):
    p = _plant()
    assert p.command_fields == {"u_body": 3, "u_thrusters": 2}
    assert [a.kind for a in p.actuators] == ["actuator", "toy_thrusters"]
    assert p.apply({"u_body": (0.1, 0.0, -0.2), "u_thrusters": (1.0, 3.0)})      # the second clipped to 2 N
    p.advance()
    torque = np.array((0.1, 0.0, -0.2)) + np.array(ARMS[0]) * 1.0 + np.array(ARMS[1]) * 2.0
    # J = I3 from rest, torque held: w x J w = 0, so w(dt) = torque dt (RK4 exact for a constant rate of change)
    np.testing.assert_allclose(p.truth()["w"], torque * DT, rtol=1e-13, atol=1e-18)
    np.testing.assert_allclose(p.applied, torque, rtol=1e-15)
    assert p.truth()["effectors"]["toy_thrusters.torque_nm"] == pytest.approx(tuple(torque - (0.1, 0.0, -0.2)))
    # a field the command does not carry keeps its held value
    assert p.apply({"u_thrusters": (0.0, 0.0)})
    p.advance()
    np.testing.assert_allclose(p.applied, (0.1, 0.0, -0.2), rtol=1e-15)


def test_a_non_finite_value_refuses_the_whole_command(thrusters):
    p = _plant()
    p.apply({"u_body": (0.1, 0.0, 0.0), "u_thrusters": (1.0, 1.0)})
    assert not p.apply({"u_body": (0.3, 0.0, 0.0), "u_thrusters": (math.nan, 1.0)})
    p.advance()
    np.testing.assert_allclose(p.applied, np.array((0.1, 0.0, 0.0)) + np.add(ARMS[0], ARMS[1]), rtol=1e-15)
    assert p.counters["bad_commands"] == 1 and p.counters["commands"] == 2


def test_taken_is_the_checked_command_and_take_gives_it_to_a_twin_plant(thrusters):
    """Plant.taken holds the command as apply() converted it (None after a refused one); a second plant of the
    same scenario given it by take() (the integration check's shadow) integrates the same period bit for bit."""
    p, twin = _plant(), _plant()
    assert p.taken is None
    assert p.apply({"u_body": [1, 0, -2], "u_thrusters": np.array([1.0, 3.0])})
    assert p.taken == {"u_body": (1.0, 0.0, -2.0), "u_thrusters": (1.0, 3.0)}
    assert all(type(x) is float for v in p.taken.values() for x in v)
    twin.take(p.taken)
    p.advance()
    twin.advance()
    assert p.truth()["w"] == twin.truth()["w"] and p.applied == twin.applied
    assert not p.apply({"u_body": (math.nan, 0.0, 0.0)})
    assert p.taken is None


def test_unknown_fields_wrong_sizes_and_bare_vectors_are_errors():
    p = Plant(load("irassi_large"))
    with pytest.raises(ValueError, match=r"command field 'u_wheels': no actuator of this plant reads it "
                                         r"\(fields: u_body\)"):
        p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.0,) * 4})
    with pytest.raises(ValueError, match=r"command field 'u_body': 2 values, its actuator takes 3"):
        p.apply({"u_body": (0.0, 0.0)})
    with pytest.raises(ValueError, match=r"the command must be a mapping of fields \(u_body\), got tuple"):
        p.apply((0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match=r"'u_body': no actuator of this plant reads it \(fields: u_orbit\)"):
        Plant(load("landsat8_q1")).apply({"u_body": (0.0, 0.0, 0.0)})


def test_the_wheel_array_reads_u_wheels_and_records_u_body():
    p = Plant(load("irassi_rw", {"plant.w0": [0.0, 0.0, 0.0]}))
    assert p.command_fields == {"u_body": 3, "u_wheels": 4} and p.wheel_array is p.actuator
    p.apply({"u_body": (1.0, 2.0, 3.0), "u_wheels": (0.1, 0.0, 0.0, 0.0)})
    p.advance()
    tr = p.truth()
    assert tr["commanded"] == (1.0, 2.0, 3.0) and tr["effectors"]["wheels.torque_cmd_nm"] == (0.1, 0.0, 0.0, 0.0)
    p.apply({"u_body": (0.0, 0.0, 0.0)})           # no u_wheels: the motors keep their torque
    assert p.truth()["effectors"]["wheels.torque_cmd_nm"] == (0.1, 0.0, 0.0, 0.0)


def test_docs_extending_shows_this_actuator_verbatim():
    here = Path(__file__)
    doc = (here.parents[3] / "docs" / "extending.md").read_text()
    marker = "<!-- verbatim: tests/python/aocs_plant/test_plant_commands.py -->\n```python\n"
    assert marker in doc
    block = doc.split(marker, 1)[1].split("```", 1)[0]
    assert "class ToyThrusters(Effector):" in block and "def command(" in block
    assert block in here.read_text()


# ----------------------------------------------------------------- an integer field: the thrusters' latch valves
LAYOUT = {"thrust_n": 1.0, "positions_m": [0, 1.2, 0, 0, -1.2, 0], "directions": [0, 0, 1, 0, 0, -1],
          "latch_branch": [0, 1]}        # two thrusters, each +x (1.2 N m with 1 N), thruster 0 on A, 1 on B


def _latch_plant():
    return Plant(load("irassi_large", {"thrusters": dict(LAYOUT), "disturbances": None}))


def test_the_latch_mask_is_an_integer_field_the_plant_checks():
    """thruster_latch_closed is declared a Mask of 2 bits: an int, or a float with an integral value, in [0, 3]
    (numpy's too) is taken as an int; the plant flies it (thruster 0's torque gone with A closed)."""
    from aocs_plant.effectors import Mask
    p = _latch_plant()
    assert p.command_fields == {"u_body": 3, "thruster_on_s": 2, "thruster_latch_closed": Mask(2)}
    for v, want in ((3, 3), (0, 0), (1.0, 1), (np.int64(2), 2), (np.float64(1.0), 1), (np.float32(3.0), 3)):
        assert p.apply({"thruster_latch_closed": v})
        assert p.taken == {"thruster_latch_closed": want} and type(p.taken["thruster_latch_closed"]) is int
    assert p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": (0.05, 0.05), "thruster_latch_closed": 1})
    p.advance()
    tr = p.truth()["effectors"]
    assert tr["thrusters.latch_closed"] == 1 and tr["thrusters.on_time_s"] == (0.0, 0.05)
    assert tr["thrusters.torque_nm"] == pytest.approx((1.2 * 0.05 / p.dt, 0.0, 0.0), rel=1e-14)
    assert p.counters["bad_commands"] == 0


@pytest.mark.parametrize("bad", [2.5, -1, 4, -1.0, 4.0, math.nan, math.inf, "1", "A", None, True, (1,), [0], 1 + 0j,
                                 np.int64(7)])
def test_a_bad_latch_mask_refuses_the_whole_command(bad):
    """Like a non-finite value: apply returns False, counts the command as bad, forgets Plant.taken, and every
    actuator holds its previous command (the valves, the on-times and the body torque alike)."""
    p = _latch_plant()
    assert p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": (0.05, 0.05), "thruster_latch_closed": 2})
    assert not p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": (0.08, 0.0), "thruster_latch_closed": bad})
    assert p.counters["bad_commands"] == 1 and p.counters["commands"] == 2 and p.taken is None
    p.advance()
    tr = p.truth()["effectors"]
    assert tr["thrusters.latch_closed"] == 2 and tr["thrusters.on_time_s"] == (0.05, 0.0)
    assert tr["thrusters.on_time_cmd_s"] == (0.05, 0.05)
