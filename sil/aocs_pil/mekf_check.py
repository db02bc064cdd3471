"""The MEKF on the flight image (issue 20, docs/pil.md "The MEKF on the targets").

For irassi_hold_mekf (the IRASSI hold on a star tracker and a gyro through the MEKF) and one law:

- the M4F (float) image fed the host's sensor samples (`harness.run(..., sensors=host.sensors)`, through the
  bridge) against the host's double-precision fsw_node: the per-step angle between the two estimates, held
  against FLOAT_TOLERANCE_ARCSEC below, and the commands;
- the M4F image in its own closed loop (`harness.run_direct`) against the host's closed loop: the pointing
  error's rms over the last 100 s of each (the trajectories part at the first rounding, their statistics must
  not);
- the instructions of every step on the M4F (float) and the M7 (double) against the step's budget (the law's
  plus the MEKF's allowance of the registry), and whether each count is exact (no SysTick reload inside the
  window: pil_icount.h).

`python -m aocs_pil.mekf_check [--duration S] [--law L] [--json F]` prints the figures (`make pil-mekf`).
"""
from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
from pathlib import Path

from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_wire import netns

from . import harness

SCENARIO = "irassi_hold_mekf"

#: The float image's estimate may differ from the double one by rounding only. A unit quaternion rounded to
#: binary32 moves by at most |dq| <= sqrt(4) 2^-25 (each of the four components, below 1 in magnitude, rounds
#: by at most half an ulp, 2^-25), a rotation of at most 2 |dq| = 2^-23 rad = 0.0246 arcsec. Two such roundings reach the estimate unfiltered: the tracker's sample as the float image
#: takes it, and the estimate it hands out (the filter keeps q_hat in double; its float gain and covariance
#: carry relative errors near 1e-6 on corrections of about 1e-6 rad, 1e-12 rad). Tolerance: their sum, 2^-22
#: rad = 0.049 arcsec on the largest per-step difference, 1/20 of the 0.97 arcsec rms the filter knows the
#: attitude to with these sensors: float precision is not what limits the knowledge.
FLOAT_TOLERANCE_ARCSEC = 2.0 ** -22 * ARCSEC_PER_RAD


def _angle_arcsec(qa, qb) -> float:
    """Rotation angle between two unit quaternions (scalar last), 2 atan2(|vec e|, |e4|), e = qa (x) qb^-1."""
    ax, ay, az, aw = qa
    bx, by, bz, bw = -qb[0], -qb[1], -qb[2], qb[3]
    ex = aw * bx + bw * ax + (ay * bz - az * by)
    ey = aw * by + bw * ay + (az * bx - ax * bz)
    ez = aw * bz + bw * az + (ax * by - ay * bx)
    ew = aw * bw - (ax * bx + ay * by + az * bz)
    return 2.0 * math.atan2(math.sqrt(ex * ex + ey * ey + ez * ez), abs(ew)) * ARCSEC_PER_RAD


def estimate_differences(a, b) -> list[float]:
    """Per-step angle (arcsec) between the estimates of two runs, over the steps where both gave one."""
    return [_angle_arcsec(x.q, y.q) for x, y in zip(a.estimates, b.estimates) if x.status == 0 and y.status == 0]


def _rms(xs) -> float:
    return math.sqrt(sum(x * x for x in xs) / len(xs)) if xs else math.nan


def instruction_row(r) -> dict:
    ins = r.instructions
    return {"target": r.target, "steps": len(ins), "median": statistics.median(ins), "max": max(ins),
            "budget": r.replies[-1].budget, "overruns": r.replies[-1].pil_overruns,
            "inexact": sum(1 for x in r.replies if not x.exact),
            "executive_window_median": statistics.median(x.law_instructions for x in r.replies),
            "estimate_invalid_steps": sum(1 for e in r.estimates if e.status != 0)}


#: the split of an MEKF step: the tracker at 2 Hz, so four steps of five propagate only and the fifth also updates
SPLIT_OVERRIDES = {"sensors.star_tracker.rate_hz": 2.0}
SPLIT_DURATION_S = 60.0


def split_row(r) -> dict:
    """Instructions of the steps that propagated only (no tracker sample) and of those that also updated with a
    used sample (the estimate's st_status 0), the first step (the filter's start) left out."""
    prop = [x.instructions for x, e in zip(r.replies[1:], r.estimates[1:]) if e.st_status != 0]
    upd = [x.instructions for x, e in zip(r.replies[1:], r.estimates[1:]) if e.st_status == 0]
    return {"target": r.target, "propagate_median": statistics.median(prop), "propagate_max": max(prop),
            "update_median": statistics.median(upd), "update_max": max(upd), "steps": [len(prop), len(upd)],
            "inexact": sum(1 for x in r.replies if not x.exact), "budget": r.replies[-1].budget}


def check(law: str = "quat_pid", duration_s: float | None = None, log=print, split: bool = True) -> dict:
    """The figures (module docstring); must run inside the private network namespace (the host run is LCM)."""
    host = harness.run(SCENARIO, law, "host", duration_s=duration_s)
    log(f"mekf_check: host (double) closed loop, {len(host.u_sat)} steps, {host.wall_s:.1f} s")
    same = harness.run(SCENARIO, law, "pil-m4f", duration_s=duration_s, sensors=host.sensors)
    log(f"mekf_check: M4F (float) on the host's samples, {same.wall_s:.1f} s")
    m4f = harness.run_direct(SCENARIO, law, "pil-m4f", duration_s=duration_s)
    log("mekf_check: M4F closed loop done")
    m7 = harness.run_direct(SCENARIO, law, "pil-m7", duration_s=duration_s)
    log("mekf_check: M7 closed loop done")
    splits = [split_row(harness.run_direct(SCENARIO, law, t, duration_s=SPLIT_DURATION_S, overrides=SPLIT_OVERRIDES))
              for t in (("pil-m4f", "pil-m7") if split else ())]
    for r in (host, same):
        if r.returncode != 0:
            raise RuntimeError(f"{r.target} failed: {r.stderr[-2000:]}")
    d = estimate_differences(host, same)
    u = harness.compare(host, same)
    n = int(round(100.0 / host.dt))
    pe_host, pe_m4f = host.pointing_arcsec[-(n + 1):], m4f.pointing_arcsec[-(n + 1):]
    return {"scenario": SCENARIO, "law": law, "steps": len(host.u_sat),
            "tolerance_arcsec": FLOAT_TOLERANCE_ARCSEC,
            "same_samples": {"estimate_diff_max_arcsec": max(d), "estimate_diff_rms_arcsec": _rms(d),
                             "steps_compared": len(d), "within_tolerance": max(d) <= FLOAT_TOLERANCE_ARCSEC,
                             "u_sat_abs_max_diff": u["u_sat_abs_max_diff"],
                             "u_max": max(abs(x) for v in host.u_sat for x in v)},
            "closed_loop": {"host_pointing_rms_arcsec": _rms(pe_host), "m4f_pointing_rms_arcsec": _rms(pe_m4f),
                            "host_pointing_max_arcsec": max(pe_host), "m4f_pointing_max_arcsec": max(pe_m4f),
                            "window_s": 100.0},
            "instructions": [instruction_row(m4f), instruction_row(m7)], "split": splits}


def markdown(res: dict) -> str:
    s, c = res["same_samples"], res["closed_loop"]
    out = [f"{res['scenario']}, {res['law']}, {res['steps']} steps of 0.1 s:", "",
           "| M4F (float) against the host (double) | figure |", "|---|---|",
           f"| same samples: largest per-step angle between the estimates | {s['estimate_diff_max_arcsec']:.3g} arcsec "
           f"(tolerance {res['tolerance_arcsec']:.3g}: {'within' if s['within_tolerance'] else 'EXCEEDED'}) |",
           f"| same samples: rms of that angle | {s['estimate_diff_rms_arcsec']:.3g} arcsec |",
           f"| same samples: largest command difference / largest command | {s['u_sat_abs_max_diff']:.3g} / "
           f"{s['u_max']:.3g} N m |",
           f"| own closed loops: pointing rms, last 100 s, host / M4F | {c['host_pointing_rms_arcsec']:.4g} / "
           f"{c['m4f_pointing_rms_arcsec']:.4g} arcsec |",
           f"| own closed loops: pointing max, last 100 s, host / M4F | {c['host_pointing_max_arcsec']:.4g} / "
           f"{c['m4f_pointing_max_arcsec']:.4g} arcsec |", "",
           "| target | steps | instructions per step, median | worst | budget (law + MEKF) | inexact counts | "
           "overruns |", "|---|---|---|---|---|---|---|"]
    for r in res["instructions"]:
        out.append(f"| {r['target']} | {r['steps']} | {r['median']:.0f} | {r['max']} | {r['budget']} | "
                   f"{r['inexact']} | {r['overruns']} |")
    if res.get("split"):
        out += ["", f"Propagation and update apart: the tracker at 2 Hz ({SPLIT_DURATION_S:g} s), whole steps:", "",
                "| target | propagation only: median / worst | with an update: median / worst | steps | "
                "inexact counts | budget |", "|---|---|---|---|---|---|"]
        for r in res["split"]:
            out.append(f"| {r['target']} | {r['propagate_median']:.0f} / {r['propagate_max']} | "
                       f"{r['update_median']:.0f} / {r['update_max']} | {r['steps'][0]} + {r['steps'][1]} | "
                       f"{r['inexact']} | {r['budget']} |")
    return "\n".join(out)


def _main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m aocs_pil.mekf_check",
                                 description="The MEKF on the PIL images: float against double, instructions.")
    ap.add_argument("--law", default="quat_pid")
    ap.add_argument("--duration", type=float, default=None, help="seconds (default the scenario's 2000 s)")
    ap.add_argument("--json", help="write the figures here")
    args = ap.parse_args(argv)
    netns.reexec_in_netns([sys.executable, "-m", "aocs_pil.mekf_check", *sys.argv[1:]])
    res = check(args.law, args.duration, log=lambda s: print(s, file=sys.stderr, flush=True))
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=1))
    print(markdown(res))
    return 0 if res["same_samples"]["within_tolerance"] else 1


if __name__ == "__main__":
    sys.exit(_main())
