"""Injected faults (issue 26; docs/spec.md 5.14): the catalogue of sensor, actuator and link faults the plant
can inject during a run, from the scenario's top-level [[faults]] entries and `aocs run --fault`.

- aocs_core/fault_catalogue.py (shared with the analysis): the kinds, their devices, parameters and what
  the flight software is expected to do;
- fault.py: one fault and the rule of when it is active; reader.py: [[faults]]; option.py: --fault;
- one model module per device: star_tracker.py, gyro.py, wheels.py, tachometer.py, thrusters.py, link.py;
- attach.py: hands each fault to the device it acts on (Plant.__init__).

The older sensor-integrity faults ([[sensors.faults]]: dropout, nan, nonunit) stay in sensors/faults.py.
"""
from __future__ import annotations

from aocs_core.fault_catalogue import KINDS, Kind

from .attach import attach
from .fault import Fault
from .option import FaultOptionError
from .option import parse as parse_option
from .option import parse_all as parse_options
from .reader import read

__all__ = ["attach", "KINDS", "Kind", "Fault", "FaultOptionError", "parse_option", "parse_options", "read"]
