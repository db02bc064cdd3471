"""`aocs` command line: one entry point, sub-commands implemented by modules.

Each sub-command module exposes `add_arguments(parser)` and `run(args) -> int`;
they are imported lazily so `aocs list` does not pay for cvxpy.
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
    "gains": ("aocs.cmd_gains", "regenerate every gain design and the firmware tables"),
    "compare": ("aocs.cmd_compare", "run every applicable law on a scenario and compare them"),
    "results": ("aocs.cmd_results", "regenerate docs/results.md for every reference scenario"),
}


def _load(name: str):
    module_name, _ = SUBCOMMANDS[name]
    return importlib.import_module(module_name)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    parser = argparse.ArgumentParser(prog="aocs", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)
    available = {}
    for name, (module_name, help_text) in SUBCOMMANDS.items():
        try:
            module = _load(name)
        except ModuleNotFoundError as exc:
            # a sub-command whose module is not there yet is not offered
            if exc.name and module_name.startswith(exc.name):
                continue
            raise
        p = sub.add_parser(name, help=help_text)
        module.add_arguments(p)
        available[name] = module
    args = parser.parse_args(argv)
    return int(available[args.command].run(args) or 0)


if __name__ == "__main__":
    sys.exit(main())
