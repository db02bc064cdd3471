"""Stability margins of every attitude law about its hold: predicted (python-control, ZOH and computation
delay) and measured in the SIL loop by input injection (`aocs analyze`, docs/spec.md "Stability margins")."""
