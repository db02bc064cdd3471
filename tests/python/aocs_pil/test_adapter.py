"""aocs_pil.adapter: a SensorFrame's STEP payload (the bridge's and the direct path's one translation) and
the Reply of a STEP_REPLY, without an emulator."""
from __future__ import annotations

import math

from aocs_loop.frames import SensorFrame, valid_bits
from aocs_pil import adapter, frame

Q = (0.1, 0.2, 0.3, 0.9273618495495703)
W = (1e-3, -2e-3, 3e-3)
Z = (0.0, 0.0, 0.0)


def _step(payload):
    v = frame.STEP.unpack(payload)
    return {"tick": v[0], "t_ns": v[1], "valid": v[2], "q": v[3:7], "w": v[7:10], "pos": v[10:13],
            "vel": v[13:16], "wheels": v[16:22]}


def test_an_attitude_frame_with_tachometers(aocs_lcm):
    b = valid_bits()
    s = _step(adapter.step_payload(SensorFrame(12, 1.2, b.attitude | b.rate | b.wheels, Q, W, Z, Z, (1.0, -2.0))))
    assert (s["tick"], s["t_ns"], s["valid"]) == (12, 1_200_000_000, adapter.EXEC_VALID_ATT | adapter.EXEC_VALID_RATE)
    assert s["q"] == Q and s["w"] == W and s["wheels"][:2] == (1.0, -2.0)
    assert all(math.isnan(x) for x in s["wheels"][2:])          # the wheels it does not measure read NaN


def test_tachometers_without_their_bit_read_nan(aocs_lcm):
    b = valid_bits()
    s = _step(adapter.step_payload(SensorFrame(1, 0.1, b.attitude, Q, W, Z, Z, (1.0, -2.0))))
    assert s["valid"] == adapter.EXEC_VALID_ATT and all(math.isnan(x) for x in s["wheels"])


def test_the_orbit_bit_needs_position_and_velocity(aocs_lcm):
    b = valid_bits()
    one = SensorFrame(1, 0.1, b.position, (0.0, 0.0, 0.0, 1.0), Z, (1.0, 2.0, 3.0), (4.0, 5.0, 6.0))
    assert _step(adapter.step_payload(one))["valid"] == 0
    both = SensorFrame(1, 0.1, b.position | b.velocity, (0.0, 0.0, 0.0, 1.0), Z, (1.0, 2.0, 3.0), (4.0, 5.0, 6.0))
    s = _step(adapter.step_payload(both))
    assert s["valid"] == adapter.EXEC_VALID_ORBIT and s["pos"] == (1.0, 2.0, 3.0) and s["vel"] == (4.0, 5.0, 6.0)


def test_the_reply_of_a_step_reply():
    r = frame.StepReply(tick=7, step_status=0, law=3, mode=1, law_status=5, input_status=0, u_cmd=(0.1, 0.2, 0.3),
                        u_unsat=(1.0, 2.0, 3.0), saturated=1, overrun=0, exact=1, instructions=21600,
                        law_instructions=1000, budget=50000, counters=dict.fromkeys(frame.COUNTER_NAMES, 0),
                        pil_overruns=0, exec_law=3, exec_mode=1, u_wheels=(0.01, 0.02, 0.03, 0.04, 0.0, 0.0),
                        wheel_scale=1.0, wheel_limited=0, wheel_status=0, h_total=(0.0, 0.0, 0.0), speed_margin=1.0)
    rep = adapter.reply_of(r, 7, 4, 216e6)
    assert rep.command.u == (0.1, 0.2, 0.3) and rep.command.u_wheels == (0.01, 0.02, 0.03, 0.04)
    assert (rep.law_id, rep.mode, rep.status, rep.step_ns, rep.overrun, rep.raw) == (3, 1, 5, 100_000, False, r)
    assert adapter.reply_of(r, 7, 0, 216e6).command.u_wheels == ()
