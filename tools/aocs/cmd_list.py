"""`aocs list`: the scenarios (id, kind, default law, applicable laws, duration) and the laws
(from the build's law registry, aocs_core.registry)."""
from __future__ import annotations

import sys

from aocs_core import registry
from aocs_plant.scenario import ScenarioError, list_scenarios, load


def add_arguments(p) -> None:
    p.add_argument("--ids", action="store_true", help="print the scenario ids only, one per line")


def run(args) -> int:
    ids = list_scenarios()
    if args.ids:
        print("\n".join(ids))
        return 0
    rows = []
    bad = 0
    for sid in ids:
        try:
            sc = load(sid)
        except ScenarioError as exc:
            print(f"aocs list: {exc}", file=sys.stderr)
            bad += 1
            continue
        laws = []
        for name, lc in sc.control.laws.items():
            laws.append(f"{name}[{', '.join(lc.tables)}]" if lc.tables else name)
        default = sc.control.law + (f" ({sc.law.table})" if sc.law.table else "")
        if not sc.control.enabled:
            default += ", control off"
        rows.append((sid, sc.kind, default, " ".join(laws), f"{sc.duration_s:g} s", f"{sc.control_rate_hz:g} Hz"))
    head = ("scenario", "kind", "default law", "laws (gain tables)", "duration", "rate")
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(head)]
    fmt = lambda r: "  ".join(f"{c:<{w}}" for c, w in zip(r, widths)).rstrip()  # noqa: E731
    print(fmt(head))
    for r in rows:
        print(fmt(r))
    print()
    print("laws (aocs run --law NAME; wire id in brackets; the flight software's law registry):")
    for law in registry.load().laws:
        print(f"  {law.name:<14} [{law.id:2d}]  {law.title}")
    return 1 if bad else 0
