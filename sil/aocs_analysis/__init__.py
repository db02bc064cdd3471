"""aocs_analysis: what a run's log means.

- metrics: pointing error, settle time and saturation from arrays;
- run_metrics: every metric of one run from its LCM log (the run JSON);
- plots: the figures of a run.
"""
