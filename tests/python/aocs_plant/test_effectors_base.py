"""The effector interface (aocs_plant/effectors/base.py) exercised by a toy stateful effector
defined here, as docs/extending.md describes: a rotor (one reaction wheel) whose axial momentum
is its state, driven by the command, exchanging torque with the body (SPEC 5.3's equations).

Total angular momentum in inertial components, H_N = A(q)^T (J_b w + g h), must be conserved to
integration accuracy whatever the motor does; the same rotor with the gyroscopic term left out
must not conserve it (so the check can fail).
"""
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from aocs_core.conventions import quat_to_dcm
from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors import ATTITUDE, REGISTRY, Effector, Form
from aocs_plant.effectors.base import unit_vector


@dataclass(frozen=True)
class RotorConfig:
    axis: tuple              # unit spin axis g in B
    spin_inertia: float      # Js, kg m^2
    friction: float          # viscous b, N m s (internal: must not change H)
    h0: float                # initial axial momentum, N m s


class ToyRotor(Effector):
    """[toy_rotor]: tau = -g . c - b Omega, Omega = h / Js - g . w;
    body torque -w x (g h) - g tau, hdot = tau (SPEC 5.3 with one wheel)."""

    kind = "toy_rotor"
    group = None                     # a top-level section [toy_rotor]
    applies_to = (ATTITUDE,)
    role = "actuator"                # takes the command ...
    replaces = ("actuator",)         # ... instead of the plain body-torque actuator
    command_fields = {"u_body": 3}   # the field it reads: the body torque command (N m, B)
    form = Form.GENERAL
    state_size = 1
    gyroscopic = True

    @classmethod
    def read(cls, sec, ctx):
        return RotorConfig(unit_vector(sec, "axis"), sec.number("spin_inertia_kg_m2", positive=True),
                           sec.number("friction_nms", required=False, default=0.0, nonneg=True),
                           sec.number("h0_nms", required=False, default=0.0))

    def __init__(self, config, body):
        super().__init__(config, body)
        g, js = config.axis, config.spin_inertia
        self.g, self.js, self.b = g, js, config.friction
        self.inertia_offset = tuple(js * g[i] * g[j] for i in range(3) for j in range(3))
        self.c = (0.0, 0.0, 0.0)

    def initial_state(self):
        return (self.config.h0,)

    def command(self, cmd):
        self.c = cmd.get("u_body", self.c)

    def motor_torque(self, body, h):
        g = self.g
        omega = h / self.js - (g[0] * body[4] + g[1] * body[5] + g[2] * body[6])
        return -(g[0] * self.c[0] + g[1] * self.c[1] + g[2] * self.c[2]) - self.b * omega

    def derivative(self, t, body, x):
        g, h = self.g, x[0]
        w1, w2, w3 = body[4], body[5], body[6]
        tau = self.motor_torque(body, h)
        gh = (g[0] * h, g[1] * h, g[2] * h) if self.gyroscopic else (0.0, 0.0, 0.0)
        torque = (-(w2 * gh[2] - w3 * gh[1]) - g[0] * tau,
                  -(w3 * gh[0] - w1 * gh[2]) - g[1] * tau,
                  -(w1 * gh[1] - w2 * gh[0]) - g[2] * tau)
        return torque, (tau,)

    @property
    def commanded(self):
        return self.c

    def truth(self, t, body, x):
        return {"h_nms": x[0], "omega_rad_s": x[0] / self.js - sum(self.g[i] * body[4 + i] for i in range(3))}


class NoGyroRotor(ToyRotor):
    kind = "toy_rotor"
    gyroscopic = False


@pytest.fixture
def rotor(monkeypatch):
    def use(cls=ToyRotor):
        monkeypatch.setitem(REGISTRY, "toy_rotor", cls)
    use()
    return use


AXIS = (0.6, 0.0, 0.8)
GAO_J = [[42.0, 1.8, -1.5], [1.8, 25.0, -1.2], [-1.5, -1.2, 61.8]]


def _scenario(substeps=2, **rotor):
    sec = {"axis": list(AXIS), "spin_inertia_kg_m2": 0.5, "friction_nms": 0.02, "h0_nms": 3.0}
    sec.update(rotor)
    return load("gao_mrp", {"toy_rotor": {k: v for k, v in sec.items() if v is not None},
                            "plant.w0": [0.05, -0.08, 0.12], "integrator.substeps": substeps})


def _momentum(plant):
    e = plant.actuator
    q, w = plant.body.q, np.array(plant.body.w)
    J_b = np.array(plant.body.J).reshape(3, 3)
    H_B = J_b @ w + np.array(e.g) * plant.effector_state(e)[0]
    return np.array(quat_to_dcm(q)).T @ H_B


def _run(plant, periods):
    """Drive the rotor with a varying command; (H0, worst relative drift of H_N, largest |h - h0|)."""
    H0 = _momentum(plant)
    h0 = plant.effector_state(plant.actuator)[0]
    worst = swing = 0.0
    for k in range(periods):
        t = plant.t
        plant.apply({"u_body": (0.3 * math.sin(0.05 * t), -0.2 * math.cos(0.031 * t), 0.25 * math.sin(0.017 * t + 1.0))})
        plant.advance()
        if k % 100 == 0:
            worst = max(worst, np.linalg.norm(_momentum(plant) - H0) / np.linalg.norm(H0))
            swing = max(swing, abs(plant.effector_state(plant.actuator)[0] - h0))
    return H0, worst, swing


def test_toy_rotor_is_built_from_its_section_and_replaces_the_actuator(rotor):
    sc = _scenario()
    assert sc.effectors["toy_rotor"] == RotorConfig(AXIS, 0.5, 0.02, 3.0)
    plant = Plant(sc)
    assert [e.kind for e in plant.effectors] == ["toy_rotor"]
    assert plant.actuator.kind == "toy_rotor" and plant.effector_state(plant.actuator) == (3.0,)
    # J_b = J - Js g g^T is the body's inertia (SPEC 5.3)
    J_b = np.array(GAO_J) - 0.5 * np.outer(AXIS, AXIS)
    np.testing.assert_allclose(np.array(plant.body.J).reshape(3, 3), J_b, rtol=1e-15)


def test_toy_rotor_conserves_total_inertial_momentum_over_a_long_run(rotor):
    plant = Plant(_scenario())
    w_start = plant.body.w
    H0, worst, swing = _run(plant, 20000)    # 2000 s at 10 Hz, 2 RK4 substeps: h = 0.05 s
    # integration accuracy: RK4's truncation error, ~2e-9 of |H| (~8 N m s) here ...
    assert worst < 1e-8, worst
    # ... which it is: halving the step divides it by ~2^4
    _, finer, _ = _run(Plant(_scenario(substeps=4)), 20000)
    assert 10.0 < worst / finer < 22.0, (worst, finer)
    # the exchange was real: the rotor's momentum swung by N m s and the body rate moved
    assert swing > 1.0, swing
    assert np.linalg.norm(np.subtract(plant.body.w, w_start)) > 1e-2
    tr = plant.truth()["effectors"]
    assert tr["toy_rotor.h_nms"] == plant.effector_state(plant.actuator)[0] and "toy_rotor.omega_rad_s" in tr
    assert plant.truth()["commanded"] == plant.actuator.c


def test_leaving_out_the_gyroscopic_term_breaks_conservation(rotor):
    rotor(NoGyroRotor)
    _, worst, _ = _run(Plant(_scenario()), 2000)
    assert worst > 1e-3, worst


def test_rk4_order_of_the_concatenated_state(rotor):
    """Body and rotor states advance together in one RK4: the error falls as h^4."""
    def final(n):
        plant = Plant(load("gao_mrp", {"toy_rotor": {"axis": list(AXIS), "spin_inertia_kg_m2": 0.5, "h0_nms": 20.0},
                                       "plant.w0": [0.3, -0.4, 0.5], "integrator.substeps": n}))
        for _ in range(100):
            plant.apply({"u_body": (3.0, -2.0, 2.5)})
            plant.advance()
        return np.array(plant.body.w + plant.effector_state(plant.actuator))
    ref = final(64)
    e = [np.abs(final(n) - ref).max() for n in (1, 2, 4)]
    assert 12.0 < e[0] / e[1] < 20.0 and 12.0 < e[1] / e[2] < 20.0, e


def test_its_section_is_validated_like_any_other(rotor):
    with pytest.raises(ScenarioError, match=r"gao_mrp.toml: toy_rotor.axis: must be a unit vector"):
        _scenario(axis=[1.0, 1.0, 0.0])
    with pytest.raises(ScenarioError, match=r"gao_mrp.toml: toy_rotor.colour: unknown key"):
        _scenario(colour="red")
    with pytest.raises(ScenarioError, match=r"toy_rotor.spin_inertia_kg_m2: missing required key"):
        _scenario(spin_inertia_kg_m2=None)
    with pytest.raises(ScenarioError, match=r"toy_rotor: \[toy_rotor\] does not apply to a orbit scenario"):
        load("landsat8_q1", {"toy_rotor": {"axis": [1.0, 0.0, 0.0], "spin_inertia_kg_m2": 0.5}})


class Zero(Effector):
    """GENERAL and stateless, contributing nothing: forces the concatenated-state path."""
    kind = "zero"
    applies_to = (ATTITUDE,)
    form = Form.GENERAL

    @classmethod
    def read(cls, sec, ctx):
        return {"enabled": sec.boolean("enabled")}

    @staticmethod
    def active(config):
        return config["enabled"]

    def derivative(self, t, body, x):
        return (0.0, 0.0, 0.0), ()


@pytest.mark.parametrize("sid", ["irassi_large", "geo_hinf", "gao_mrp"])
def test_the_concatenated_state_path_equals_the_fast_path_bit_for_bit(monkeypatch, sid):
    monkeypatch.setitem(REGISTRY, "zero", Zero)
    fast = Plant(load(sid))
    general = Plant(load(sid, {"disturbances.zero": {"enabled": True}}))
    assert general._general and not fast._general
    for k in range(300):
        for p in (fast, general):
            p.apply({"u_body": (0.01 * math.sin(0.1 * k), 0.02, -0.01)})
            p.advance()
        assert fast.body.q == general.body.q and fast.body.w == general.body.w


def test_a_state_on_a_form_that_is_not_general_is_refused(monkeypatch):
    class Bad(Zero):
        kind = "bad"
        form = Form.ATTITUDE
        state_size = 2
    monkeypatch.setitem(REGISTRY, "bad", Bad)
    with pytest.raises(ValueError, match="only a GENERAL effector may have state"):
        Plant(load("irassi_large", {"disturbances.bad": {"enabled": True}}))


def test_docs_extending_shows_this_rotor_verbatim():
    """docs/extending.md's example module is the ToyRotor of this file, copied verbatim."""
    here = Path(__file__)
    doc = (here.parents[3] / "docs" / "extending.md").read_text()
    marker = "<!-- verbatim: tests/python/aocs_plant/test_effectors_base.py -->\n```python\n"
    assert marker in doc
    block = doc.split(marker, 1)[1].split("```", 1)[0]
    assert "class ToyRotor(Effector):" in block and "def derivative(" in block
    assert block in here.read_text()


def test_an_inertia_offset_larger_than_the_body_is_refused(rotor):
    with pytest.raises(ValueError, match=r"inertia less the effectors' inertia_offset \(toy_rotor\) "
                                         r"is not positive definite"):
        Plant(_scenario(spin_inertia_kg_m2=100.0))
