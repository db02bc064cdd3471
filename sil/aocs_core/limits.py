"""Actuator limit facts shared by the flight-software configuration and the analysis."""

#: per-axis limit (N m, or N) written to the flight computer when a scenario sets none
#: ("effectively unlimited": the executive requires one limit; SPEC 3 actuators)
UNLIMITED = 1.0e9

# ---- run timing (the scenario loader refuses values outside; docs/scenarios.md)
# the control rate and the actuator limits are bounded by the executive's own ranges, read from the
# build's registry (aocs_core.registry: limits; executive.h AOCS_EXEC_PERIOD_*, AOCS_EXEC_U_LIMIT_*)
#: longest run: 1e7 s (116 days) keeps t in ns far inside uint64 and ticks far inside the wire's
#: int64 / the executive's uint32 tick with wrap, and is longer than any attitude study needs
DURATION_S_MAX = 1.0e7
#: most control periods of one run (a 1 kHz loop for 116 days would be 1e10: refused)
STEPS_MAX = 100_000_000
#: most RK4 substeps per control period (more is a sign of a wrong rate, not of accuracy)
SUBSTEPS_MAX = 10_000
