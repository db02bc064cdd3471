"""Hands each injected fault to the device it acts on (Plant.__init__): the sensor suite's per-sensor hooks
(star tracker, tachometer), the gyro's, the wheel array's and the thrusters' fault models. Link faults are the
transport's (link.py). Nothing is attached without faults: a run without faults is unchanged bit for bit."""
from __future__ import annotations

from aocs_core.fault_catalogue import GYRO, STAR_TRACKER, THRUSTERS, WHEELS

from .gyro import GyroFaults
from .star_tracker import StarTrackerFaults
from .tachometer import TachometerFaults
from .thrusters import ThrusterFaults
from .wheels import WheelFaults


def attach(plant, faults) -> dict:
    """The sensor hooks {sensor name: hook(t, value) -> value} for the plant's SensorSuite; the effectors' and
    the gyro's fault models are set on them."""
    dt = plant.dt
    by_device: dict = {}
    for f in faults:
        by_device.setdefault(f.spec.device, []).append(f)
    sensors = {s.name: s for s in plant.sensors}
    effs = {e.kind: e for e in plant.effectors}
    hooks = {}
    if STAR_TRACKER in by_device:
        hooks["star_tracker"] = StarTrackerFaults(by_device[STAR_TRACKER], dt, sensors["star_tracker"])
    if GYRO in by_device:
        sensors["gyro"].fault_model = GyroFaults(by_device[GYRO], dt)
    wf = [f for f in by_device.get(WHEELS, ()) if f.kind != "wheel_tach_failure"]
    if wf:
        effs["wheels"].fault_model = WheelFaults(wf, dt, effs["wheels"].n)
    tach = [f for f in by_device.get(WHEELS, ()) if f.kind == "wheel_tach_failure"]
    if tach:
        hooks["tachometer"] = TachometerFaults(tach, dt)
    if THRUSTERS in by_device:
        effs["thrusters"].fault_model = ThrusterFaults(by_device[THRUSTERS], dt)
    return hooks
