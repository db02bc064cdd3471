"""Whole lockstep periods of the in-process transport, compiled (docs/spec.md 5.13.2; issue 24).

plant_node's lockstep loop over the in-process node (`--transport direct`) hands runs of periods to the kernel
aocs_direct_loop_kernel.DirectLoop (sil/plant_kernels/direct_loop_kernel.c) when the plant is one the kernel
flies: the rigid body alone with its compiled period (at most one fixed-direction gravity gradient), the body
actuator held with its axis and norm limits and scale factor, ideal attitude and rate sensors without latency or
faults, a fixed target, no wheels, thrusters or magnetorquers, no injected fault. Between two scheduled events
(commands, link faults) and progress lines the kernel runs the periods, the same statements in the same order as
the Python loop: the same sensors_t, actuator_cmd_t, event_t and truth_t bytes in the log, the same plant state,
the same integration check. The ticks with events stay in Python, and so does whatever ends a run (no reply, a
command the plant cannot take, a node error): the kernel stops there and the loop reports it as its own.

    seg, why = build(loop)       # seg None: this run stays in Python, for the reason `why`
    status, done, extra = seg.run(tick0, count)

The Python loop stays the definition and the fallback: no kernel built, AOCS_PLANT_KERNELS=python or =periods.
tests/python/aocs_runner/test_compiled_loop.py flies runs both ways and compares the logs and the state.
"""
from __future__ import annotations

import ctypes

from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_loop.frames import POLICY_MAGNETORQUERS, POLICY_THRUSTERS
from aocs_plant import kernels
from aocs_plant.effectors.actuator import Actuator
from aocs_plant.integration_error import RICHARDSON_RK4, StepDoubling
from aocs_plant.sensors.attitude import AttitudeSensor
from aocs_plant.sensors.rate import RateSensor

#: DirectLoop.run's statuses (direct_loop_kernel.c)
DONE, NO_REPLY, MISMATCH, NODE_ERROR = 0, 1, 2, 3
#: the most periods one run() flies (its log block, about 1.6 kB a period; a signal is seen between runs)
MAX_PERIODS = 2048

_Z3 = (0.0, 0.0, 0.0)
_Q1 = (0.0, 0.0, 0.0, 1.0)


def why_not(loop) -> str | None:
    """Why plant_node's lockstep loop `loop` (plant_node._Loop) cannot hand its periods to the kernel, None when
    it can."""
    plant, port, link = loop.plant, loop.port, loop.link
    if not link.direct:
        return "not the in-process transport"
    if kernels.module(kernels.DIRECT_LOOP) is None:
        return f"{kernels.DIRECT_LOOP} not built or turned off ({kernels.ENV})"
    if plant.kind != "attitude":
        return "the orbit plant"
    if plant._general or plant._pending or plant._hooked or plant._time_varying or plant._dist_other:
        return "effectors with state (wheels, thrusters, an actuator lag), events, period hooks or time-varying terms"
    if plant._compiled_period is None:
        return "no compiled period (two or more attitude terms)"
    act = plant.actuator
    if type(act) is not Actuator or plant.actuators != [act] or plant._held != [act]:
        return "not the body actuator alone"
    if act.lag_tau_s is not None or act.slew_rate_limit_per_s is not None or act._queue:
        return "an actuator lag, slew-rate limit or delay"
    if port.n_wheels or port.n_thrusters or port.magnetorquers:
        return "wheels, thrusters or magnetorquers"
    suite = plant._suite
    if (plant.faults or suite.faults or suite.hooks or suite.latency or suite._recorders or suite._flagged
            or sorted(type(s).__name__ for s in plant.sensors) != ["AttitudeSensor", "RateSensor"]
            or not all(type(s) in (AttitudeSensor, RateSensor) and s.config.ideal for s in plant.sensors)):
        return "sensors other than ideal attitude and rate, latency or faults"
    if not loop.fixed_target or loop._truth_tail is None:
        return "a moving target"
    check = loop.check
    if type(check) is not StepDoubling or check.kind != "attitude" or check.substeps != plant.substeps:
        return "another integration check"
    if len(plant._dist_terms) > 1 or any(e not in plant._terms for e in plant._dist_terms):
        return "disturbance terms the compiled period does not have"
    return None


def build(loop) -> tuple["CompiledLoop | None", str | None]:
    """(the compiled loop of plant_node's lockstep loop `loop`, None) or (None, why it stays in Python)."""
    why = why_not(loop)
    return (CompiledLoop(loop) if why is None else None), why


def _fn_address(lib, name: str) -> int:
    return ctypes.cast(getattr(lib, name), ctypes.c_void_p).value


def config(loop, node_functions: tuple[int, int] | None = None) -> tuple:
    """DirectLoop's configuration of plant_node's lockstep loop `loop` (direct_loop_kernel.c, DirectLoop_init's
    order): the plant's period, the actuator's limits, the target, the integration check, the node's functions
    (node_functions: the addresses of aocs_direct_sensors and aocs_direct_event, default the loaded library's; a test
    wraps them), the messages' templates and field layouts (aocs_wire.wire), the channels."""
    plant, link, port = loop.plant, loop.link, loop.port
    codecs, codec = link.codecs, link.codec
    sen, tru, act = codecs.sensors, codecs.truth, codecs.actuator
    node = link.lc.node
    a = plant.actuator
    s_tpl = codec.pack_fields(0, 0.0, 0, _Q1, _Z3, _Z3, _Z3, (), _Q1, 0.0, _Z3, _Z3)
    t_tpl = loop.pack_t(0, 0, 0, 0.0, *_Q1, *_Z3, *_Z3, *_Z3, *_Z3, *_Z3, *_Z3, *_Z3, 0.0, *_Z3, *loop._truth_tail)
    functions = node_functions or (_fn_address(node.lib, "aocs_direct_sensors"),
                                   _fn_address(node.lib, "aocs_direct_event"))
    return (
        plant.dt, plant.substeps, plant._const, plant._const_dist, bool(plant._dist_terms),
        a.axis_limit, a.norm_limit, float(a.config.scale_factor), loop.sc.target.qd0, ARCSEC_PER_RAD, RICHARDSON_RK4,
        loop.check.every, loop.check.threshold, *functions, node.handle, port._att | port._rate,
        s_tpl, tuple(sen.layout(f) for f in ("frame", "utime", "tick", "t_s", "valid", "q", "w")),
        t_tpl, tuple(tru.layout(f) for f in ("frame", "utime", "tick", "t_s", "q", "w", "torque_applied",
                                             "torque_dist", "pointing_err_arcsec", "qe_arcsec")),
        tuple(act.layout(f) for f in ("tick", "u_sat", "n_wheels", "mom_policy", "n_thrusters")),
        act.size, act.fingerprint, codec.max_wheels, codec.max_thrusters, POLICY_THRUSTERS, POLICY_MAGNETORQUERS,
        tuple(c.encode() for c in (link.wire.SENSORS, link.wire.ACTUATOR, link.wire.TRUTH, link.wire.EVENTS)),
    )


def kernel(loop, node_functions: tuple[int, int] | None = None):
    """The DirectLoop of plant_node's lockstep loop `loop` (config)."""
    plant = loop.plant
    gg = kernels.gg_argument([e.compiled_term() for e in plant._terms])
    return kernels.module(kernels.DIRECT_LOOP).DirectLoop(plant.body.J, plant.body.Ji, gg, config(loop, node_functions))


class CompiledLoop:
    """DirectLoop over one plant_node lockstep loop: state in from the Python objects before each run, out after."""

    def __init__(self, loop, node_functions: tuple[int, int] | None = None):
        self.loop = loop
        self._kernel = kernel(loop, node_functions)

    def _state(self) -> tuple:
        loop = self.loop
        plant, check, a = loop.plant, loop.check, loop.plant.actuator
        taken = plant.taken
        log = loop.link.log
        return (*plant.body.q, *plant.body.w, plant.k, *a.held, *a._limited, a.saturated_count,
                plant.counters["commands"], plant.counters["bad_commands"], taken is not None,
                *(taken["u_body"] if taken is not None else _Z3), *plant._applied, *check._last, *check.local_max,
                *check.local_sum, check.worst_t, check.periods, check.checked, log.count if log is not None else 0,
                loop.frame_truth, loop.bad_replies, loop.stale_replies)

    def _set_state(self, s: tuple, periods: int, sampled: int) -> None:
        loop = self.loop
        plant, check, a = loop.plant, loop.check, loop.plant.actuator
        body = plant.body
        body.q, body.w, plant.k = s[0:4], s[4:7], s[7]
        a.held, a._limited, a.saturated_count = s[8:11], s[11:14], s[14]
        # the integration check's shadow plant took every command the main one took: its actuator holds the same
        sa = check.shadow.actuator
        sa.held, sa._limited = a.held, a._limited
        c = plant.counters
        c["commands"], c["bad_commands"], c["steps"] = s[15], s[16], plant.k
        c["samples"] += sampled
        plant.taken = {"u_body": s[18:21]} if s[17] else None
        plant._applied = s[21:24]
        check._last, check.local_max, check.local_sum = s[24:26], list(s[26:28]), list(s[28:30])
        check.worst_t, check.periods, check.checked, check._start = s[30], s[31], s[32], None
        loop.frame_truth, loop.bad_replies, loop.stale_replies = s[34], s[35], s[36]
        if periods:
            plant._sample = None
            plant._suite.record()   # the sensors' truth of the period the plant is now in

    def run(self, tick0: int, count: int) -> tuple[int, int, object]:
        """Fly count periods from tick0 (the plant at tick0, no integration check pending): (status, periods done,
        extra). DONE: all of them. NO_REPLY: period `done` got no answer for its tick. MISMATCH: its command names
        actuators the plant has not (extra: the actuator_cmd_t payload). NODE_ERROR: a node call failed (extra: the
        message). The messages are recorded, and the loop's and plant's state set, up to that point."""
        loop = self.loop
        before = self._state()
        status, done, state, block, rt, extra = self._kernel.run(before, tick0, count)
        self._set_state(state, done, done + (status != DONE))
        log = loop.link.log
        if log is not None:
            log.add_block(block, state[33] - before[33])
        loop.rt_ns.frombytes(rt)
        loop.steps += done
        loop.compiled_periods += done
        loop.last_tick = tick0 + done - (status == DONE)
        if done:
            loop.last_answered = tick0 + done - 1
        return status, done, extra
