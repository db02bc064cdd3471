#!/usr/bin/env python3
"""Driver of the per-law host benchmark (issue 5): step times and callgrind
instruction counts of every control law and of the executive step with it.

    tools/bench/bench_laws.py [--steps N] [--callgrind-steps M] [--repeats R]
                              [--law NAME]... [--no-callgrind] [--json FILE]

1. runs `bench_laws --steps N` (timing mode: median / p99 / worst ns per law,
   per executive step, and the executive's own step time, see bench_laws.c);
2. for every law, R times (default 2): `valgrind --tool=callgrind
   --instr-atstart=no --toggle-collect=<step symbol> bench_laws --law L
   --callgrind-steps M` and the same with `--exec` (symbol aocs_exec_step,
   with aocs_hal_time_ns and aocs_hal_cycles toggled off inside it),
   reads the total Ir of the callgrind output and checks that the R totals
   are identical (instruction counts are exact and repeatable; a mismatch is
   an error, exit 1). The executive count leaves out the HAL clock reads
   inside aocs_exec_step (their count depends on the clock value);
3. prints one table (law | ns median | ns p99 | ns worst | budget ns |
   instr/step), the budget check (a law whose declared BUDGET_NS (laws.def)
   is below the measured p99 of its step, or of the executive's own step
   time, is listed), and writes everything to --json FILE.

The build directory comes from AOCS_BUILD_DIR (default <repo>/build/host);
the program is <build>/bin/bench_laws. Standard library only.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
#: spread of the exec callgrind totals between runs that comes from the measured step times (the
#: executive's running maximum and overrun branches), not from the code: instructions per run
EXEC_CLOCK_SLACK_INSTR = 64
BUILD_HINT = "build it first: make build-host (or cmake --preset host && cmake --build --preset host)"
TIMING_KINDS = ("timer", "law", "exec", "exec_self")
INT_FIELDS = ("steps", "median_ns", "p99_ns", "worst_ns", "budget_ns", "over_budget", "errors")


class BenchError(RuntimeError):
    pass


def build_dir() -> Path:
    return Path(os.environ.get("AOCS_BUILD_DIR", REPO / "build" / "host")).resolve()


def bench_binary(bdir: Path) -> Path:
    exe = bdir / "bin" / "bench_laws"
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        raise BenchError(f"bench_laws not found at {exe} (AOCS_BUILD_DIR={bdir}); {BUILD_HINT}")
    return exe


def run(cmd: list[str]) -> subprocess.CompletedProcess:
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise BenchError(f"{' '.join(cmd)} exited {proc.returncode}\n{proc.stdout}{proc.stderr}")
    return proc


def list_laws(exe: Path) -> tuple[list[dict], bool, list[str]]:
    """Laws known to the program (name, callgrind symbol, budget, family), whether
    it was built with valgrind/callgrind.h, and the executive's toggle-collect
    symbols (aocs_exec_step, then the HAL reads inside it that are not counted)."""
    out = run([str(exe), "--list"]).stdout
    laws, has_cg_h, exec_symbols = [], None, []
    for line in out.splitlines():
        if line.startswith("#"):
            m = re.search(r"executive symbol: (\w+); excluded: ([\w,]*); callgrind\.h: (\d)", line)
            if m:
                exec_symbols = [m.group(1)] + [s for s in m.group(2).split(",") if s]
                has_cg_h = m.group(3) == "1"
            continue
        name, symbol, budget, family = line.split()
        laws.append({"name": name, "step_symbol": symbol, "budget_ns": int(budget), "family": family})
    if not laws or has_cg_h is None:
        raise BenchError(f"{exe} --list printed no laws or no executive symbol line:\n{out}")
    return laws, has_cg_h, exec_symbols


def parse_table(text: str) -> tuple[dict, list[dict]]:
    """The timing table of bench_laws: '#' comment lines, a header, one row per line."""
    meta, header, rows = {}, None, []
    for line in text.splitlines():
        if line.startswith("#"):
            meta.update(dict(re.findall(r"(\w+)=(\S+)", line)))
            continue
        fields = line.split()
        if not fields:
            continue
        if header is None:
            header = fields
            continue
        if len(fields) != len(header):
            raise BenchError(f"malformed row (expected {len(header)} fields): {line!r}")
        row = dict(zip(header, fields))
        for key in INT_FIELDS:
            if key in row:
                row[key] = int(row[key])
        if "mean_ns" in row:
            row["mean_ns"] = float(row["mean_ns"])
        if "checksum" in row:
            row["checksum"] = float(row["checksum"])
        rows.append(row)
    if header is None:
        raise BenchError(f"no table in the output:\n{text}")
    return meta, rows


def run_timing(exe: Path, steps: int, seed: int | None, laws: list[str] | None) -> tuple[dict, list[dict]]:
    cmd = [str(exe), "--steps", str(steps)]
    if seed is not None:
        cmd += ["--seed", str(seed)]
    for name in laws or []:
        cmd += ["--law", name]
    return parse_table(run(cmd).stdout)


def callgrind_total(exe: Path, law: str, symbols: list[str], steps: int, use_exec: bool, seed: int | None,
                    has_cg_h: bool, workdir: Path, tag: str) -> int:
    """Total Ir collected inside symbols[0] (minus the nested symbols[1:]) over
    `steps` steps, one valgrind run. Each --toggle-collect flips collection on
    entry and exit of its function."""
    out_file = workdir / f"callgrind.{law}.{'exec' if use_exec else 'law'}.{tag}.out"
    cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out_file}"]
    cmd += [f"--toggle-collect={s}" for s in symbols]
    if has_cg_h:
        # the program switches instrumentation on around its loop only
        cmd.append("--instr-atstart=no")
    cmd += [str(exe), "--law", law, "--callgrind-steps", str(steps)]
    if use_exec:
        cmd.append("--exec")
    if seed is not None:
        cmd += ["--seed", str(seed)]
    run(cmd)
    text = out_file.read_text()
    m = re.search(r"^totals:\s+(\d+)", text, re.M)
    if m is None:
        raise BenchError(f"no 'totals:' line in {out_file}")
    return int(m.group(1))


def host_info() -> dict:
    cpu = ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        load = list(os.getloadavg())
    except OSError:
        load = []
    return {"machine": platform.machine(), "kernel": platform.release(), "cpu": cpu,
            "cpus": os.cpu_count(), "loadavg": load, "python": platform.python_version()}


def fmt_int(v) -> str:
    return "-" if v is None else f"{v:d}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--steps", type=int, default=200000, help="timed steps per row (default 200000)")
    ap.add_argument("--callgrind-steps", type=int, default=1024,
                    help="steps per callgrind run, a multiple of the 512-state ring (default 1024)")
    ap.add_argument("--repeats", type=int, default=2, help="callgrind runs per row, must agree (default 2)")
    ap.add_argument("--law", action="append", dest="laws", metavar="NAME", help="only this law (repeatable)")
    ap.add_argument("--seed", type=int, default=None, help="seed of the state ring (default: the program's)")
    ap.add_argument("--no-callgrind", action="store_true", help="timing only")
    ap.add_argument("--strict-budget", action="store_true",
                    help="exit 1 when a budget is below a measured p99 (default: report only)")
    ap.add_argument("--json", type=Path, default=None, metavar="FILE", help="write all figures as JSON")
    args = ap.parse_args(argv)
    if args.steps < 1 or args.callgrind_steps < 1 or args.repeats < 1:
        ap.error("--steps, --callgrind-steps and --repeats must be >= 1")

    try:
        bdir = build_dir()
        exe = bench_binary(bdir)
        known, has_cg_h, exec_symbols = list_laws(exe)
        names = [law["name"] for law in known]
        for name in args.laws or []:
            if name not in names:
                raise BenchError(f"unknown law {name!r}; known: {', '.join(names)}")
        chosen = [law for law in known if not args.laws or law["name"] in args.laws]

        meta, rows = run_timing(exe, args.steps, args.seed, args.laws)
        by_kind = {(r["kind"], r["law"]): r for r in rows}
        timer = by_kind.get(("timer", "-"))

        if not args.no_callgrind and shutil.which("valgrind") is None:
            raise BenchError("valgrind not found (Debian package valgrind, installed by scripts/setup.sh); "
                             "use --no-callgrind for timing only")

        results = []
        with tempfile.TemporaryDirectory(prefix="bench_laws.") as tmp:
            for law in chosen:
                name = law["name"]
                entry = {"name": name, "family": law["family"], "budget_ns": law["budget_ns"],
                         "step_symbol": law["step_symbol"], "exec_symbols": exec_symbols}
                for kind in ("law", "exec", "exec_self"):
                    row = by_kind.get((kind, name))
                    if row is None:
                        raise BenchError(f"timing table has no '{kind}' row for {name}")
                    entry[kind] = {k: v for k, v in row.items() if k not in ("kind", "law")}
                if not args.no_callgrind:
                    totals, per_step = {}, {}
                    for kind, symbols in (("law", [law["step_symbol"]]), ("exec", exec_symbols)):
                        runs = [callgrind_total(exe, name, symbols, args.callgrind_steps, kind == "exec", args.seed,
                                                has_cg_h, Path(tmp), str(i)) for i in range(args.repeats)]
                        # the law alone is deterministic to the instruction; a whole executive step also
                        # branches on its own measured step time (the running maximum, the overrun
                        # count: executive.c), so two runs may differ by a few instructions in all
                        slack = 0 if kind == "law" else EXEC_CLOCK_SLACK_INSTR
                        if max(runs) - min(runs) > slack:
                            raise BenchError(f"callgrind totals of {kind} {name} differ between runs: {runs}")
                        totals[kind] = runs
                        per_step[kind] = min(runs) / args.callgrind_steps
                    entry["callgrind_totals"] = totals
                    entry["instr_per_step"] = {k: round(v) for k, v in per_step.items()}
                    entry["instr_per_step_exact"] = per_step
                over = []
                if law["budget_ns"] < entry["law"]["p99_ns"]:
                    over.append("law step p99")
                if law["budget_ns"] < entry["exec_self"]["p99_ns"]:
                    over.append("executive step_time_ns p99")
                entry["budget_below_p99"] = over
                results.append(entry)
    except BenchError as exc:
        print(f"bench_laws.py: {exc}", file=sys.stderr)
        return 1

    # ---- the table ----
    head = ("law", "ns median", "ns p99", "ns worst", "budget ns", "instr/step")
    lines = []
    for e in results:
        ips = e.get("instr_per_step", {})
        for kind, label in (("law", e["name"]), ("exec", f"exec:{e['name']}")):
            t = e[kind]
            lines.append((label, fmt_int(t["median_ns"]), fmt_int(t["p99_ns"]), fmt_int(t["worst_ns"]),
                          fmt_int(e["budget_ns"]), fmt_int(ips.get(kind))))
    widths = [max(len(head[i]), *(len(r[i]) for r in lines)) for i in range(len(head))]
    print(f"# bench_laws: real_t={meta.get('real_t', '?')} steps={meta.get('steps', '?')} "
          f"seed={meta.get('seed', '?')} build={bdir}")
    if timer is not None:
        print(f"# clock overhead (two back-to-back aocs_hal_time_ns reads, inside every figure): "
              f"median {timer['median_ns']} ns, p99 {timer['p99_ns']} ns")
    print("| " + " | ".join(h.ljust(w) for h, w in zip(head, widths)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for r in lines:
        print("| " + r[0].ljust(widths[0]) + " | " + " | ".join(v.rjust(w) for v, w in zip(r[1:], widths[1:])) + " |")
    if not args.no_callgrind:
        print(f"# instr/step: callgrind Ir inside the step function / {args.callgrind_steps} steps; "
              f"{args.repeats} runs per row, totals identical in every row")
    violations = [e for e in results if e["budget_below_p99"]]
    if violations:
        for e in violations:
            print(f"BUDGET: {e['name']}: AOCS budget {e['budget_ns']} ns is below the measured "
                  f"{' and '.join(e['budget_below_p99'])} "
                  f"(law p99 {e['law']['p99_ns']} ns, executive p99 {e['exec_self']['p99_ns']} ns)")
    else:
        print("# budget check: every declared BUDGET_NS (laws.def) is above the measured p99 "
              "(law step and the executive's own step time)")

    if args.json is not None:
        doc = {
            "tool": "tools/bench/bench_laws.py",
            "host": host_info(),
            "config": {"steps": args.steps, "callgrind_steps": None if args.no_callgrind else args.callgrind_steps,
                       "repeats": None if args.no_callgrind else args.repeats, "bench_meta": meta,
                       "build_dir": str(bdir), "callgrind_h": has_cg_h},
            "timer": None if timer is None else {k: v for k, v in timer.items() if k not in ("kind", "law")},
            "laws": results,
            "budget_violations": [e["name"] for e in violations],
        }
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(doc, indent=2) + "\n")
    return 1 if (violations and args.strict_budget) else 0


if __name__ == "__main__":
    sys.exit(main())
