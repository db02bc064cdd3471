"""`aocs docs [--check]`: regenerate the docs' tables of registry facts (laws, configuration keys, budgets)
from the build's registry (aocs.docs_tables); --check only reports the files that are behind (exit 1)."""
from __future__ import annotations

import sys

from aocs_core import paths

from . import docs_tables


def add_arguments(p) -> None:
    p.add_argument("--check", action="store_true", help="exit 1 when a generated table differs from the registry")


def run(args) -> int:
    root = paths.REPO
    try:
        if args.check:
            stale = docs_tables.stale_files(root)
            for rel in stale:
                print(f"aocs docs: {rel}: a generated table differs from the registry (run `aocs docs`)",
                      file=sys.stderr)
            return 1 if stale else 0
        for rel in docs_tables.write(root):
            print(f"aocs docs: wrote {rel}")
    except (ValueError, OSError, paths.SetupError) as exc:
        print(f"aocs docs: error: {exc}", file=sys.stderr)
        return 2
    return 0
