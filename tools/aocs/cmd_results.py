"""`aocs results [--out docs] [--quick]`: regenerate docs/results.md and docs/results/*.png
(the work is in aocs_compare.results_doc; this module is the command line)."""
from __future__ import annotations

import sys
from pathlib import Path

from aocs_compare.compare import REPO
from aocs_compare.results_doc import LIMIT_DURATION_S, build
from aocs_core import paths
from aocs_runner import orchestrate
from aocs_wire import netns


def add_arguments(p) -> None:
    p.add_argument("--out", default=str(REPO / "docs"), help="where results.md and results/*.png go (default docs)")
    p.add_argument("--runs", default="out/results", help="where the runs' logs go (default out/results)")
    p.add_argument("--quick", action="store_true",
                   help=f"limited IRASSI runs of 500 s instead of {LIMIT_DURATION_S:g} s")
    p.add_argument("--reuse", action="store_true",
                   help="read back the runs already in --runs that passed with the same configuration "
                        "(to finish an interrupted regeneration) instead of running them again")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


def run(args) -> int:
    netns.reexec_in_netns(paths.self_argv())
    out = Path(args.out)
    try:
        text, failed = build(out, Path(args.runs), args.quick, args.quiet, reuse=args.reuse)
    except orchestrate.RunAborted as exc:
        print(f"aocs results: aborted: {exc}", file=sys.stderr)
        return 1
    (out / "results.md").write_text(text)
    print(f"aocs results: wrote {out / 'results.md'} and {out / 'results'}/*.png"
          + (f"; {failed} runs FAILED" if failed else ""))
    return 1 if failed else 0
