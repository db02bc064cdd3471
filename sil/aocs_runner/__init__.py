"""aocs_runner: one run in the loop, as real processes.

- run: one scenario run (plant_node + flight computer + recorder), its log and metrics;
- orchestrate: starting, supervising and stopping the processes with bounded waits;
- plant_node: the plant as an LCM process (`python -m aocs_runner.plant_node`);
- fsw_config: the flight computer's configuration file written from a scenario;
- events, scenario_opts: scheduled commands and faults, `--set` overrides;
- demo: the main job (`make sil`).
"""
