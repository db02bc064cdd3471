"""How the plant reaches the flight computer (`--transport` of aocs run, compare and campaign; docs/sil.md,
"Transports"):

- lcm (default): fsw_node (or the PIL bridge) as its own process, sensors_t and actuator_cmd_t over LCM;
- direct: the same node logic (sil/fsw_node/node_core.c) as a shared library in the plant's process
  (aocs_loop.direct_adapter), lockstep only; its command history is the LCM lockstep run's, bit for bit.
"""
from __future__ import annotations

TRANSPORTS = ("lcm", "direct")

#: lockstep over LCM: how long the plant's wait for each reply, and fsw_node's for each sensors_t, poll the socket
#: before they sleep, us (plant_node --wait-spin-us, fsw_node.cfg wait_spin_us; aocs_wire/udpm.py). A sleeping
#: process on an idle virtual CPU takes about as long to wake as the other side takes to answer; 200 us covers a
#: lockstep answer (25 us median here) with room, and a process that waits longer sleeps as before.
#: Measured: docs/benchmarks.md, "Waiting without sleeping"
LOCKSTEP_WAIT_SPIN_US = 200.0


def check_transport(transport) -> None:
    """ValueError naming --transport unless it is one of TRANSPORTS."""
    if transport not in TRANSPORTS:
        raise ValueError(f"--transport {transport!r}: not a transport (one of {', '.join(TRANSPORTS)})")
