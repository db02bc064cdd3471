"""The Python API for notebooks and scripts (docs/python-api.md): what the `aocs` command line does, as functions
that return results instead of printing them. The command line is a thin layer over it.

    import aocs_api as aocs
    sc = aocs.scenario("irassi_rw").with_overrides({"duration_s": 200.0})
    r = aocs.run(sc, law="quat_pid", guidance="slew")
    r.metrics["settle_time_s"], r.telemetry["wheel_speed_true_1_rad_s"].max()
    r.html("r.html")

Bad input and failed runs raise AocsError, whose message is the one line the command line prints.
"""
import importlib

from .errors import AocsError
from .runs import RunResult, load_run, run
from .scenario import Scenario, scenario

#: name -> the module of this package that defines it, imported on first use (PEP 562): `aocs run` imports this
#: package for its runs and does not pay for the campaign, comparison and report modules (scipy, dask: about 1 s
#: of every run's start). (The names eager above share a submodule's name or are what a run needs.)
_LAZY = {"CampaignResult": "campaigns", "campaign": "campaigns", "load_campaign": "campaigns",
         "CompareResult": "comparisons", "compare": "comparisons", "report": "reports"}

__all__ = ["AocsError", "Scenario", "scenario", "run", "load_run", "RunResult", "compare", "CompareResult",
           "campaign", "CampaignResult", "load_campaign", "report"]


def __getattr__(name: str):
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
