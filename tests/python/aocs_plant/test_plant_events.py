"""DISCRETE effectors (aocs_plant/plant.py, _period_with_events): the plant splits a control period at every
event inside it, so the body moves for exactly the time between the events. Exercised by a toy effector
defined here, as docs/extending.md describes: rate kicks about a principal axis of a body at rest, where the
attitude after the period is a rotation by sum(w_k (t_{k+1} - t_k)) about that axis (written out here)."""
import math
from dataclasses import dataclass

import pytest

from aocs_plant import Plant, load
from aocs_plant.effectors import ATTITUDE, REGISTRY, Effector, Form


@dataclass(frozen=True)
class KicksConfig:
    times_s: tuple
    dw_rad_s: float           # added to w_z at every time


class ToyKicks(Effector):
    """[toy_kicks]: w_z jumps by dw_rad_s at each of times_s."""

    kind = "toy_kicks"
    group = None
    applies_to = (ATTITUDE,)
    form = Form.DISCRETE

    @classmethod
    def read(cls, sec, ctx):
        return KicksConfig(tuple(sec.array("times_s", nonneg=True)), sec.number("dw_rad_s", positive=True))

    def event_times(self):
        return self.config.times_s

    def jump(self, t, body):
        return (*body[:6], body[6] + self.config.dw_rad_s)


@pytest.mark.parametrize("times", [(0.52, 0.57), (0.5, 0.55, 0.58), (0.53,)])
def test_events_in_one_period_move_the_body_for_the_time_between_them(monkeypatch, times):
    monkeypatch.setitem(REGISTRY, "toy_kicks", ToyKicks)
    dw = 0.01
    sc = load("gao_mrp", {"control.enabled": False, "plant.sigma": [0.0, 0.0, 0.0],
                          "plant.inertia": [[40.0, 0.0, 0.0], [0.0, 25.0, 0.0], [0.0, 0.0, 60.0]],
                          "integrator.substeps": 4, "toy_kicks": {"times_s": list(times), "dw_rad_s": dw}})
    plant = Plant(sc)
    for _ in range(6):                        # to t = 0.6 s: the events are in the period [0.5, 0.6)
        plant.advance()
    end = 6 * sc.dt
    assert plant.t == pytest.approx(end, abs=1e-12)
    # w_z = k dw after the k-th kick, held until the next one or the end of the period
    theta = sum((k + 1) * dw * ((times[k + 1] if k + 1 < len(times) else end) - t) for k, t in enumerate(times))
    q = plant.body.q
    assert plant.body.w == pytest.approx((0.0, 0.0, len(times) * dw), abs=1e-15)
    assert q == pytest.approx((0.0, 0.0, math.sin(theta / 2), math.cos(theta / 2)), rel=1e-9, abs=1e-15)
