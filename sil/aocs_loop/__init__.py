"""aocs_loop: the one closed loop of a run, whatever carries it to the flight computer.

- frames.py: what crosses the loop once per control period, defined once: the SensorFrame the flight
  software gets (made from the plant by PlantPort.sense) and the Command the plant takes back (applied by
  PlantPort.apply), with the Reply around it (the flight computer's telemetry of that step);
- core.py: the loop (sense -> flight computer step -> apply -> advance, with record hooks) over a
  FlightComputer adapter, the one interface a transport implements;
- lcm_adapter.py: the LCM adapter (sensors_t out, actuator_cmd_t back), whose packing plant_node uses too.

The PIL adapter (STEP / STEP_REPLY frames to the image under QEMU) lives with its frames in
aocs_pil.adapter, a layer above this package. docs/architecture.md, "The closed loop".
"""
