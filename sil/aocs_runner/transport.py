"""How the plant reaches the flight computer (`--transport` of aocs run, compare and campaign; docs/sil.md,
"Transports"):

- lcm (default): fsw_node (or the PIL bridge) as its own process, sensors_t and actuator_cmd_t over LCM;
- direct: the same node logic (sil/fsw_node/node_core.c) as a shared library in the plant's process
  (aocs_loop.direct_adapter), lockstep only; its command history is the LCM lockstep run's, bit for bit.
"""
from __future__ import annotations

TRANSPORTS = ("lcm", "direct")


def check_transport(transport) -> None:
    """ValueError naming --transport unless it is one of TRANSPORTS."""
    if transport not in TRANSPORTS:
        raise ValueError(f"--transport {transport!r}: not a transport (one of {', '.join(TRANSPORTS)})")
