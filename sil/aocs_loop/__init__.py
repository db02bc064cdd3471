"""aocs_loop: the one closed loop of a run, whatever carries it to the flight computer.

- frames.py: what crosses the loop once per control period, defined once: the SensorFrame the flight
  software gets (made from the plant by PlantPort.sense) and the Command the plant takes back (applied by
  PlantPort.apply), with the Reply around it (the flight computer's telemetry of that step);
- core.py: the loop (sense -> flight computer step -> apply -> advance, with record hooks) over a
  FlightComputer adapter, the one interface a transport implements;
- lcm_adapter.py: the LCM adapter (sensors_t out, actuator_cmd_t back), whose packing plant_node uses too;
- direct_adapter.py: the in-process adapter (`--transport direct`): fsw_node's node logic as a shared library,
  the same sensors_t / actuator_cmd_t bytes through its C ABI (DirectFlightComputer, and DirectBus for
  plant_node's loop);
- history.py: a run's command history, its digest and the bit-for-bit comparison of two runs' logs.

The PIL adapter (STEP / STEP_REPLY frames to the image under QEMU) lives with its frames in
aocs_pil.adapter, a layer above this package. docs/architecture.md, "The closed loop".
"""
