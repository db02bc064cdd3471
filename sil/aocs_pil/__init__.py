"""aocs_pil: processor in the loop.

The flight image built for an emulated Cortex-M (firmware/port/cortex-m/
pil_main.c, targets cortex-m4f and cortex-m7) closed in the SIL loop:

- frame.py: the request/reply frame codec (host side of aocs/pil_frame.h);
- qemu.py: starting, driving and stopping QEMU with bounded waits;
- config.py: the fsw_node configuration file, parsed exactly as fsw_node does;
- bridge.py: `python -m aocs_pil.bridge --target pil-m4f|pil-m7 CONFIG_FILE`,
  an LCM node that behaves like fsw_node, with the image as its executive;
- harness.py: closed-loop runs of a scenario with the in-process plant
  against fsw_node or the bridge (equivalence, accuracy, budgets).

docs/pil.md describes the whole.
"""
