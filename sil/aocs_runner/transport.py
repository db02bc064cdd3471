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


def lockstep_cpus() -> tuple[int, int] | None:
    """(the plant's CPU, the flight computer's CPU) for a lockstep run over LCM: two of the CPUs this process may
    use, or None when it may use one only. Two processes that hand every period to each other run best each on
    its own CPU; left to the scheduler they often share one, each waking the other (docs/benchmarks.md,
    "Waiting without sleeping": irassi_large's lockstep then falls from about 3000x to about 1800x)."""
    import os  # deferred: only a lockstep run over LCM asks

    cpus = sorted(os.sched_getaffinity(0))
    return (cpus[0], cpus[1]) if len(cpus) >= 2 else None


def check_transport(transport) -> None:
    """ValueError naming --transport unless it is one of TRANSPORTS."""
    if transport not in TRANSPORTS:
        raise ValueError(f"--transport {transport!r}: not a transport (one of {', '.join(TRANSPORTS)})")
