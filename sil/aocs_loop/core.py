"""The closed loop of one run, over any transport.

    port = PlantPort(plant)
    steps = fly(port, flight_computer, sc.n_steps, hooks=[recorder])

Per control period k (tick = start_tick + k, time t_k):
  1. sense:  frame = port.sense(tick)                 (frames.PlantPort: the plant's SensorFrame)
  2. step:   reply = flight_computer.step(frame)      (the adapter: pack, exchange, unpack)
  3. record: hook.period(frame, reply, plant)         (the plant still at t_k)
  4. apply:  port.apply(reply.command)                (Plant.apply's mapping, wheel torques included)
  5. advance one period with the command held;
and after the last period hook.end(plant) (the plant at t_N).

A transport is an adapter with one method per period, FlightComputer.step(SensorFrame) -> Reply: it packs
the frame in its own encoding, has the flight computer run one executive step, and unpacks the answer into
a Reply (frames.Reply: the Command and the step's telemetry). Starting and stopping the flight computer
(processes, QEMU, a loaded library) is the adapter's own business, before and after fly(). Adapters today:
aocs_loop.lcm_adapter.LcmFlightComputer (sensors_t / actuator_cmd_t, fsw_node or the PIL bridge),
aocs_pil.adapter.PilFlightComputer (STEP / STEP_REPLY frames to the image under QEMU),
aocs_loop.direct_adapter.DirectFlightComputer (the node logic in process, the same sensors_t / actuator_cmd_t
bytes). plant_node keeps its own recording loop for speed, with the same PlantPort and LcmCodec
(aocs_runner.plant_node), over LCM or over the in-process DirectBus.
"""
from __future__ import annotations

from typing import Protocol

from .frames import PlantPort, Reply, SensorFrame


class FlightComputer(Protocol):
    """One flight computer behind one transport."""

    def step(self, frame: SensorFrame) -> Reply:
        """Run one executive step on this frame; the flight computer's answer to it. Raises when there is
        none (a timeout, a process or emulator that died): the loop does not invent a command."""
        ...


class Hook:
    """Record hooks of the loop (no-ops here; override what you record)."""

    def period(self, frame: SensorFrame, reply: Reply, plant) -> None:
        """After the flight computer answered `frame`, before the command is applied (plant at t_k)."""

    def end(self, plant) -> None:
        """After the last period (plant at t_N)."""


def fly(port: PlantPort, fc: FlightComputer, n_steps: int, *, start_tick: int = 0, hooks=()) -> int:
    """The closed loop of n_steps periods (module docstring); returns the periods flown."""
    plant = port.plant
    sense, step, apply, advance = port.sense, fc.step, port.apply, plant.advance
    hooks = tuple(hooks)
    for k in range(n_steps):
        frame = sense(start_tick + k)
        reply = step(frame)
        for h in hooks:
            h.period(frame, reply, plant)
        apply(reply.command)
        advance()
    for h in hooks:
        h.end(plant)
    return n_steps


def replay(fc: FlightComputer, frames, *, hooks=()) -> int:
    """Open loop: the given frames (an earlier run's) to the flight computer, no plant; hooks get
    plant=None and no end(). Returns the frames sent."""
    hooks = tuple(hooks)
    n = 0
    for frame in frames:
        reply = fc.step(frame)
        for h in hooks:
            h.period(frame, reply, None)
        n += 1
    return n
