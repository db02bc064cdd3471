"""The Python API for notebooks and scripts (docs/python-api.md): what the `aocs` command line does, as functions
that return results instead of printing them. The command line is a thin layer over it.

    import aocs_api as aocs
    sc = aocs.scenario("irassi_rw").with_overrides({"duration_s": 200.0})
    r = aocs.run(sc, law="quat_pid", guidance="slew")
    r.metrics["settle_time_s"], r.telemetry["wheel_speed_true_1_rad_s"].max()
    r.html("r.html")

Bad input and failed runs raise AocsError, whose message is the one line the command line prints.
"""
from .campaigns import CampaignResult, campaign, load_campaign
from .comparisons import CompareResult, compare
from .errors import AocsError
from .reports import report
from .runs import RunResult, load_run, run
from .scenario import Scenario, scenario

__all__ = ["AocsError", "Scenario", "scenario", "run", "load_run", "RunResult", "compare", "CompareResult",
           "campaign", "CampaignResult", "load_campaign", "report"]
