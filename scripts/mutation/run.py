#!/usr/bin/env python3
"""make mutation: a seeded sample of single-line mutants, each run against the tests that can see it
(docs/mutation.md).

Areas: firmware/src (C; the host, host-float and host-sanitize unit tests, rebuilt in scratch build
directories), the plant (sil/aocs_plant) and the metrics (sil/aocs_analysis) packages (Python; their pytest
directories).
Every mutant is applied to a scratch copy of the tree (build/mutation/src), never to the worktree; the
copy is refreshed from the worktree at every start, so an interrupted run leaves no mutant behind that
a later run would test against. Each mutant ends killed, survived, timeout (counted as killed) or
build_error (the compiler refused it: not a mutant, left out of the score); the ones listed in
tests/mutation/equivalent.toml are marked equivalent with their reason and not run.

    .venv/bin/python scripts/mutation/run.py --seed 25 --c 60 --plant 20 --metrics 20
    .venv/bin/python scripts/mutation/run.py --only 'firmware/src/control/integral.c:16:'   # by id prefix
"""
from __future__ import annotations

import argparse
import fcntl
import hashlib
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import mutants as mut

REPO = Path(__file__).resolve().parents[2]
OUT = REPO / "build" / "mutation"
SRC = OUT / "src"
EQUIVALENT = REPO / "tests" / "mutation" / "equivalent.toml"
#: preset -> its cache variables, run in this order (a mutant is killed by the first that fails): double, float,
#: then double under ASan + UBSan (as `make test` runs the unit tests: an out-of-bounds write the two plain builds
#: survive is a failing test there)
C_PRESETS = {"host": ("-DAOCS_REAL_FLOAT=OFF",), "host-float": ("-DAOCS_REAL_FLOAT=ON",),
             "host-sanitize": ("-DAOCS_REAL_FLOAT=OFF", "-DAOCS_SANITIZE=ON")}


@dataclass
class Area:
    name: str
    lang: str
    root: str  # sources, relative to the repository
    tests: str  # the pytest directory (Python areas)
    files: list[str] = field(default_factory=list)


AREAS = {
    "firmware": Area("firmware", "c", "firmware/src", ""),
    "plant": Area("plant", "py", "sil/aocs_plant", "tests/python/aocs_plant"),
    "metrics": Area("metrics", "py", "sil/aocs_analysis", "tests/python/aocs_analysis"),
}


def fail(msg: str) -> None:
    print(f"mutation: {msg}", file=sys.stderr)
    sys.exit(2)


def run(cmd: list[str], cwd: Path, timeout: float | None = None, env: dict | None = None) -> tuple[str, str]:
    """('ok' | 'fail' | 'timeout', output) of one command, niced, its process group killed on timeout."""
    p = subprocess.Popen(["nice", "-n", "10", *cmd], cwd=cwd, env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        return "timeout", out
    return ("ok" if p.returncode == 0 else "fail"), out


def refresh_scratch() -> None:
    """build/mutation/src := the worktree's tracked files as they are now (committed or not). A file that
    differs is rewritten (a new modification time), so ninja rebuilds what an interrupted run left mutated;
    files no longer tracked are removed."""
    out = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, check=True, capture_output=True).stdout
    tracked = {f for f in out.decode().split("\0") if f and (REPO / f).is_file()}
    for f in tracked:
        src, dst = REPO / f, SRC / f
        data = src.read_bytes()
        if not dst.is_file() or dst.is_symlink() or dst.read_bytes() != data:
            dst.parent.mkdir(parents=True, exist_ok=True)
            dst.unlink(missing_ok=True)
            dst.write_bytes(data)
            dst.chmod(src.stat().st_mode & 0o777)
    for p in sorted(SRC.rglob("*"), reverse=True):
        rel = str(p.relative_to(SRC))
        if p.is_dir() and p.name == "__pycache__":
            shutil.rmtree(p, ignore_errors=True)
        elif p.is_file() and rel not in tracked:
            p.unlink()


def load_equivalent() -> dict[tuple, str]:
    if not EQUIVALENT.exists():
        return {}
    try:
        data = tomllib.loads(EQUIVALENT.read_text())
    except tomllib.TOMLDecodeError as e:
        fail(f"{EQUIVALENT.relative_to(REPO)}: {e}")
    out = {}
    for i, e in enumerate(data.get("mutant", [])):
        try:
            out[(e["file"], e["line"], e["old"], e["new"], int(e.get("occurrence", 0)))] = e["reason"]
        except KeyError as k:
            fail(f"{EQUIVALENT.relative_to(REPO)}: [[mutant]] number {i + 1} has no {k}")
    return out


def all_mutants(area: Area, sources: dict[str, str]) -> list[mut.Mutant]:
    """Every mutant of the area; sources gets each file's text as read now (the run's pristine copy: edits to
    the worktree while the run goes on change neither the mutants nor what is restored)."""
    ext = ".c" if area.lang == "c" else ".py"
    out = []
    for f in sorted((REPO / area.root).rglob(f"*{ext}")):
        rel = str(f.relative_to(REPO))
        sources[rel] = f.read_text()
        out.extend(mut.mutants_of(rel, sources[rel], area.lang))
    return out


# ---- C: scratch builds, the tests that link the mutated object ----
class CBuilds:
    def __init__(self, jobs: int):
        self.jobs = jobs
        self.dirs = {p: OUT / p for p in C_PRESETS}
        self.baseline_s: dict[str, float] = {}
        self.users: dict[str, list[str]] = {}  # firmware/src/x.c -> test executables linking its object

    def setup(self) -> None:
        for preset, cache in C_PRESETS.items():
            d = self.dirs[preset]
            st, out = run(["cmake", "-S", str(SRC), "-B", str(d), "-G", "Ninja", "-DCMAKE_BUILD_TYPE=RelWithDebInfo",
                           *cache, "-DAOCS_BUILD_SIL=OFF", "-DAOCS_BUILD_TESTS=ON"], REPO)
            if st != "ok":
                fail(f"configure of the scratch {preset} build failed:\n{out[-2000:]}")
            st, out = run(["cmake", "--build", str(d), "-j", str(self.jobs)], REPO)
            if st != "ok":
                fail(f"the unmutated scratch {preset} build failed:\n{out[-2000:]}")
            t0 = time.monotonic()
            st, out = run(["ctest", "--test-dir", str(d), "-j", str(self.jobs)], REPO)
            if st != "ok":
                fail(f"the unmutated {preset} unit tests fail; fix them first:\n{out[-2000:]}")
            self.baseline_s[preset] = time.monotonic() - t0
        self.users = self._users(self.dirs["host"])

    def _users(self, d: Path) -> dict[str, list[str]]:
        tests = sorted(p for p in (d / "tests" / "unit").glob("test_*") if p.is_file() and os.access(p, os.X_OK))
        defined = {t.name: set(_nm(t)) for t in tests}
        users = {}
        objs = d / "firmware" / "CMakeFiles" / "aocs_fw.dir"
        for obj in objs.rglob("*.c.o"):
            rel = str(obj.relative_to(objs))[:-2]  # src/x/y.c
            syms = set(_nm(obj))
            users["firmware/" + rel] = [t for t, s in defined.items() if syms & s]
        return users

    def test(self, m: mut.Mutant) -> tuple[str, str]:
        tests = self.users.get(m.path, [])
        if not tests:
            return "survived", "no unit test links this object"
        for preset, d in self.dirs.items():
            st, out = run(["cmake", "--build", str(d), "-j", str(self.jobs), "--target", *tests], REPO, timeout=600)
            if st != "ok":
                return "build_error", _tail(out)
            st, out = run(["ctest", "--test-dir", str(d), "-j", str(self.jobs), "--stop-on-failure",
                           "--timeout", str(int(30 + 10 * self.baseline_s[preset])), "-R",
                           "^(" + "|".join(tests) + ")$"], REPO, timeout=120 + 20 * self.baseline_s[preset])
            if st == "timeout" or "***Timeout" in out:
                return "timeout", f"{preset}: " + _tail(out)
            if st != "ok":
                failed = re.findall(r"\d+ - (\S+) \(", out)
                return "killed", f"{preset}: " + ", ".join(failed or ["ctest failed"])
        return "survived", f"{', '.join(C_PRESETS)} pass: {', '.join(tests)}"


def _nm(path: Path) -> list[str]:
    r = subprocess.run(["nm", "--defined-only", "-g", str(path)], capture_output=True, text=True)
    return [ln.split()[-1] for ln in r.stdout.splitlines() if ln.strip() and ln.split()[-2] in ("T", "D", "R", "B")]


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def _tail(out: str, n: int = 400) -> str:
    return " ".join(out.strip().splitlines()[-4:])[-n:]


# ---- Python: pytest on the scratch copy (PYTHONPATH ahead of the venv's editable install) ----
class PyTests:
    def __init__(self):
        self.env = dict(os.environ, PYTHONPATH=f"{SRC / 'sil'}:{SRC / 'tools'}", PYTHONDONTWRITEBYTECODE="1",
                        AOCS_BUILD_DIR=str(REPO / "build" / "host"))
        self.baseline_s: dict[str, float] = {}

    def pytest(self, paths: list[str], timeout: float | None) -> tuple[str, str]:
        return run([sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", *paths], SRC,
                   timeout=timeout, env=self.env)

    def setup(self, areas: list[Area]) -> None:
        st, out = run([sys.executable, "-c", "import aocs_plant, aocs_analysis; print(aocs_plant.__file__)"], SRC,
                      env=self.env)
        if st != "ok" or not out.strip().startswith(str(SRC)):
            fail(f"the scratch copy does not shadow the installed packages: {out.strip()}")
        for a in areas:
            t0 = time.monotonic()
            st, out = self.pytest([a.tests], None)
            if st != "ok":
                fail(f"the unmutated {a.tests} fails; fix it first:\n{_tail(out, 2000)}")
            self.baseline_s[a.name] = time.monotonic() - t0

    def test(self, m: mut.Mutant, area: Area) -> tuple[str, str]:
        # the test files named after the module first (quick), then the whole directory
        stem = Path(m.path).stem
        focused = sorted(str(p.relative_to(SRC)) for p in (SRC / area.tests).rglob(f"test_*{stem}*.py"))
        limit = 60 + 4 * self.baseline_s[area.name]
        for paths in ([focused] if focused else []) + [[area.tests]]:
            st, out = self.pytest(paths, limit)
            if st == "timeout":
                return "timeout", " ".join(paths)
            if st != "ok":
                failed = re.findall(r"^FAILED (\S+)", out, re.M) or re.findall(r"^ERROR (\S+)", out, re.M)
                return "killed", ", ".join(failed[:2]) or _tail(out)
        return "survived", f"{area.tests} passes"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=25)
    ap.add_argument("--c", type=int, default=60, help="mutants drawn in firmware/src")
    ap.add_argument("--plant", type=int, default=20, help="mutants drawn in sil/aocs_plant")
    ap.add_argument("--metrics", type=int, default=20, help="mutants drawn in sil/aocs_analysis")
    ap.add_argument("--only", action="append", default=[], help="run the mutants whose id starts with this "
                    "(path:line:col:op); repeatable; no sampling")
    ap.add_argument("--list", action="store_true", help="print the sample and stop")
    ap.add_argument("--resume-from", type=Path, help="a report.json of an earlier run: its killed, timeout and "
                    "build_error rows are kept when the mutated file is byte for byte the same (tests may only have "
                    "been added since); every other drawn mutant runs")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", type=Path, default=OUT)
    a = ap.parse_args()
    for k in ("c", "plant", "metrics", "jobs"):
        if getattr(a, k) < 0:
            fail(f"--{k} must be >= 0, got {getattr(a, k)}")

    equivalent = load_equivalent()
    counts = {"firmware": a.c, "plant": a.plant, "metrics": a.metrics}
    sample: list[tuple[Area, mut.Mutant]] = []
    sources: dict[str, str] = {}
    for name, area in AREAS.items():
        pool = all_mutants(area, sources)
        if a.only:
            chosen = [m for m in pool if any(m.ident.startswith(p) for p in a.only)]
        else:
            chosen = sorted(random.Random(f"{a.seed}:{name}").sample(pool, min(counts[name], len(pool))),
                            key=lambda m: (m.path, m.line, m.col))
        sample += [(area, m) for m in chosen]
    if a.only and not sample:
        fail(f"no mutant id starts with {a.only}")
    if a.list:
        for area, m in sample:
            print(f"{area.name:8s} {m.ident}  |  {m.line_text}")
        return

    kept = {}
    if a.resume_from is not None:
        try:
            prev = json.loads(a.resume_from.read_text())
        except (OSError, ValueError) as e:
            fail(f"--resume-from {a.resume_from}: {e}")
        kept = {r["id"]: r for r in prev.get("mutants", []) if r.get("status") in ("killed", "timeout", "build_error")
                and r.get("file_sha256") == _sha(sources.get(r.get("file"), ""))}
    OUT.mkdir(parents=True, exist_ok=True)
    lock = open(OUT / ".lock", "w")  # noqa: SIM115  (held for the whole run)
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        fail(f"another mutation run uses {SRC} (lock {OUT / '.lock'}); wait for it")
    refresh_scratch()
    for rel, text in sources.items():  # the scratch copy holds exactly the text the mutants were made from
        if (SRC / rel).read_text() != text:
            fail(f"{rel} changed while the mutants were drawn; run again")
    used = {area.name for area, m in sample if m.key() not in equivalent and m.ident not in kept}
    cb = CBuilds(a.jobs)
    if "firmware" in used:
        print(f"mutation: building the unmutated scratch {', '.join(C_PRESETS)} unit tests", flush=True)
        cb.setup()
    py = PyTests()
    py_areas = [AREAS[n] for n in ("plant", "metrics") if n in used]
    if py_areas:
        print("mutation: running the unmutated plant and metrics tests", flush=True)
        py.setup(py_areas)

    results = []
    t_start = time.monotonic()
    for i, (area, m) in enumerate(sample):
        pristine = sources[m.path]
        target = SRC / m.path
        eq = equivalent.get(m.key())
        t0 = time.monotonic()
        if eq is not None:
            status, detail = "equivalent", eq
        elif m.ident in kept:
            status, detail = kept[m.ident]["status"], kept[m.ident]["detail"] + f" (from {a.resume_from})"
        else:
            try:
                target.write_text(m.apply(pristine))
                status, detail = cb.test(m) if area.lang == "c" else py.test(m, area)
            finally:
                target.write_text(pristine)
        row = {"area": area.name, "id": m.ident, "file": m.path, "line": m.line, "op": m.op, "old": m.old,
               "new": m.new, "occurrence": m.occurrence, "original": m.line_text,
               "mutated": m.diff_line(pristine), "file_sha256": _sha(pristine), "status": status, "detail": detail,
               "seconds": round(time.monotonic() - t0, 1)}
        results.append(row)
        print(f"[{i + 1}/{len(sample)}] {status:11s} {area.name:8s} {m.ident}  ({row['seconds']} s)", flush=True)
        write_report(a, results, time.monotonic() - t_start)  # after every mutant: an interrupted run keeps its rows
    summary = write_report(a, results, time.monotonic() - t_start)
    for name, s in summary.items():
        print(f"mutation: {name}: {s['killed']} of {s['scored']} non-equivalent mutants killed ({s['score_pct']} %), "
              f"{s['survived']} survived, {s['equivalent']} equivalent, {s['build_error']} build errors")
    print(f"mutation: report {a.out / 'report.md'}")


def write_report(a, results: list[dict], seconds: float) -> dict:
    summary = {}
    for name in AREAS:
        rows = [r for r in results if r["area"] == name]
        if not rows:
            continue
        c = {s: sum(r["status"] == s for r in rows) for s in
             ("killed", "timeout", "survived", "equivalent", "build_error")}
        scored = c["killed"] + c["timeout"] + c["survived"]
        summary[name] = {**c, "killed": c["killed"] + c["timeout"], "drawn": len(rows), "scored": scored,
                         "score_pct": round(100.0 * (c["killed"] + c["timeout"]) / scored, 1) if scored else None}
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / "report.json").write_text(json.dumps(
        {"seed": a.seed, "only": a.only, "resumed_from": str(a.resume_from) if a.resume_from else None, "seconds": round(seconds), "summary": summary, "mutants": results}, indent=1))
    md = ["# Mutation report", "",
          f"Seed {a.seed}" + (f", only {a.only}" if a.only else f", drawn: firmware {a.c}, plant {a.plant}, "
                                                               f"metrics {a.metrics}") + f"; {seconds:.0f} s"
          + (f"; resumed from {a.resume_from}: {sum('(from ' in str(r['detail']) for r in results)} killed or "
             "build_error rows carried over (same file bytes), the rest run now" if a.resume_from else "") + ".", "",
          "| area | drawn | killed (incl. timeout) | survived | equivalent | build error | killed / non-equivalent |",
          "|---|---|---|---|---|---|---|"]
    for name, s in summary.items():
        md.append(f"| {name} | {s['drawn']} | {s['killed']} | {s['survived']} | {s['equivalent']} | "
                  f"{s['build_error']} | {s['killed']}/{s['scored']} ({s['score_pct']} %) |")
    for title, want in (("Survivors", ("survived",)), ("Equivalent (tests/mutation/equivalent.toml)", ("equivalent",)),
                        ("All mutants", None)):
        rows = [r for r in results if want is None or r["status"] in want]
        md += ["", f"## {title}", ""]
        if not rows:
            md.append("none")
            continue
        md += ["| status | mutant | original | mutated | detail |", "|---|---|---|---|---|"]
        for r in rows:
            cells = [r["status"], f"`{r['file']}:{r['line']}` {r['op']}", f"`{r['original']}`", f"`{r['mutated']}`",
                     r["detail"]]
            md.append("| " + " | ".join(str(x).replace("|", "\\|") for x in cells) + " |")
    (a.out / "report.md").write_text("\n".join(md) + "\n")
    return summary


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        fail("interrupted; the worktree was never mutated and the scratch copy is refreshed at the next start")
