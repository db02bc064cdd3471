"""Monte Carlo campaigns over the real SIL path (SPEC 5.4, docs/campaigns.md): dispersions, the plan of
runs and their repeat commands, execution on Dask distributed, statistics, the report and its plots."""
