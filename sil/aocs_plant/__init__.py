"""aocs_plant: the SIL plant simulator (SPEC sections 3 and 4).

Rigid-body attitude and relative-orbit dynamics, the effectors acting on them
(`effectors/`: one module per disturbance or actuator, each actuator reading
its own command fields), the sensors (`sensors/`: one module per sensor) and
the environment (`environment/`: orbit, Sun, Earth, magnetic field slot)
(docs/extending.md), driven one control period at a time through `Plant`,
built from a validated scenario file (`scenario.load`). Hot path on plain
Python floats.
"""
from aocs_core.conventions import pointing_error_arcsec, pointing_error_rad, qe_arcsec

from .plant import Plant, integrate_open_loop
from .scenario import Scenario, ScenarioError, law_names, list_scenarios, load

__all__ = ["Plant", "integrate_open_loop", "load", "list_scenarios", "Scenario", "ScenarioError",
           "law_names", "pointing_error_rad", "pointing_error_arcsec", "qe_arcsec"]
