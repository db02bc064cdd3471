"""`aocs list`: the scenarios (id, kind, default law, applicable laws, duration) and the laws."""
from __future__ import annotations

import sys

from aocs_core.paths import LAW_IDS
from aocs_plant.scenario import ScenarioError, list_scenarios, load

LAW_DOC = {
    "crp_linear": "SPEC 2.1 linear feedback on Cayley-Rodrigues parameters",
    "quat_pd": "SPEC 2.2 linear quaternion PD",
    "quat_nlpd_neg": "SPEC 2.3 nonlinear PD, kd (1 - qe.qe)",
    "quat_nlpd_pos": "SPEC 2.3 nonlinear PD, kd (1 + qe.qe)",
    "smc": "SPEC 2.4 sliding mode with boundary layer",
    "lqr_quat": "SPEC 2.5 LQR on the reduced quaternion (compiled gain tables)",
    "hinf": "SPEC 2.6 H-infinity state feedback, Earth pointing (compiled gain tables)",
    "mrp_sat": "SPEC 2.7 saturated MRP regulator, linear saturations",
    "mrp_sat_tanh": "SPEC 2.7 saturated MRP regulator, tanh saturation",
    "orbit_lqr": "SPEC 2.8 LQR station keeping, force (compiled gain tables)",
}


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
    print("laws (aocs run --law NAME; wire id in brackets):")
    for name, lid in LAW_IDS.items():
        if name != "none":
            print(f"  {name:<14} [{lid:2d}]  {LAW_DOC[name]}")
    return 1 if bad else 0
