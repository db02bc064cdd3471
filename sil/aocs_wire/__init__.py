"""aocs_wire: the transport between the plant and the flight computer.

- wire: the LCM channels and message helpers (docs/wire-contract.md);
- udpm: a direct reader of LCM's UDP multicast (the plant's fast path);
- lcmlog: reading an lcm-logger file into arrays;
- recorder: the runner's lossless log recorder;
- netns: the private network namespace every SIL process runs in.
"""
