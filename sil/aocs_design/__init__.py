"""Gain design: Riccati (LQR) and LMI (H-infinity) designs compiled into
constant firmware tables by `aocs gains` (SPEC 2.5, 2.6, 2.8)."""
