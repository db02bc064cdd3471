"""aocs_flightcfg: the flight computer's configuration, as policy.

- fsw_config: the fsw_node configuration file written from a scenario (which
  keys, valued from which scenario sections, and the runner's policy for what
  a scenario does not say: the safe-mode gain, the unlimited torque limits).
  Its keys are the configuration registry's (aocs_core.registry); the file is
  read by fsw_node's one parser (and, for PIL, by the same parser run as the
  host tool aocs_node_config).
"""
