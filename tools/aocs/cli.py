"""`aocs` command line: one entry point, sub-commands implemented by modules.

Each sub-command module exposes `add_arguments(parser)` and `run(args) -> int`;
only the module of the sub-command given is imported, so `aocs list` or
`aocs run` does not pay for the others' imports (scipy, cvxpy, matplotlib).
"""
from __future__ import annotations

import argparse
import importlib
import sys

# name -> (module, help)
SUBCOMMANDS = {
    "run": ("aocs.cmd_run", "run a scenario in the loop (plant + flight software over LCM)"),
    "list": ("aocs.cmd_list", "list scenarios and control laws"),
    "replay": ("aocs.cmd_replay", "replay a recorded LCM log through the flight software"),
    "play": ("aocs.cmd_play", "publish a recorded LCM log again, paced by its simulation clock (for viewers)"),
    "gains": ("aocs.cmd_gains", "regenerate every gain design and the firmware tables"),
    "compare": ("aocs.cmd_compare", "run every applicable law on a scenario and compare them"),
    "results": ("aocs.cmd_results", "regenerate docs/results.md for every reference scenario"),
    "docs": ("aocs.cmd_docs", "regenerate the docs' tables of laws, configuration keys and budgets from the registry"),
    "analyze": ("aocs.cmd_analyze", "stability margins of a law about its hold, predicted and measured in the loop"),
    "campaign": ("aocs.cmd_campaign", "Monte Carlo campaign of dispersed runs on Dask (statistics, plots, report)"),
    "report": ("aocs.cmd_report", "interactive HTML page of a run, comparison or campaign folder"),
}

#: sub-commands that run in a private network namespace (aocs_wire.netns), entered before their module is
#: imported: in place with unshare(2) where this process may (root, or CAP_SYS_ADMIN), so nothing is paid
#: twice; otherwise by re-executing once inside `unshare -n` (its imports, numpy and the plant, then come
#: after the re-exec only)
NETNS_FIRST = ("run",)


def _netns_first() -> None:
    from aocs_core import paths  # deferred: only a sub-command of NETNS_FIRST needs it
    from aocs_wire import netns  # deferred: see above

    try:
        netns.enter_netns()   # this process is single-threaded here: every thread and child inherits it
        return
    except (netns.NetnsError, OSError):
        pass   # not allowed in place: re-execute inside unshare -n (which may still manage, e.g. with sudo rules)
    try:
        netns.reexec_in_netns(paths.self_argv())
    except netns.NetnsError:
        pass  # the sub-command reports it in its own words


def _load(name: str):
    module_name, _ = SUBCOMMANDS[name]
    return importlib.import_module(module_name)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    parser = argparse.ArgumentParser(prog="aocs", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    # only the chosen sub-command's module is imported (each costs numpy, scipy or matplotlib time);
    # without one (or with --help first) every sub-command is listed from its help text alone
    chosen = next((a for a in argv if not a.startswith("-")), None)
    if chosen in NETNS_FIRST and not any(a in ("-h", "--help") for a in argv):
        _netns_first()
    modules = {}
    for name, (module_name, help_text) in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_text)
        if name == chosen:
            modules[name] = _load(name)
            modules[name].add_arguments(p)
    args = parser.parse_args(argv)
    return int(modules[args.command].run(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
