"""Actuator limit facts shared by the flight-software configuration and the analysis."""

#: per-axis limit (N m, or N) written to the flight computer when a scenario sets none
#: ("effectively unlimited": the executive requires one limit; SPEC 3 actuators)
UNLIMITED = 1.0e9
