"""Gain design: Riccati (LQR) and LMI (H-infinity) designs and their checks (SPEC 2.5, 2.6, 2.8),
for `aocs gains` (the compiled tables, written by aocs_gains) and for the runner (a scenario's own
gain designed at run start, aocs_runner.scenario_gains)."""
