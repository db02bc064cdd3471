"""AOCS desktop tools: the `aocs` CLI, gain design, metrics, plots, reports."""
