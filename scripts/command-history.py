#!/usr/bin/env python3
"""Command histories of the reference scenarios, for checking that a refactoring changes nothing.

    scripts/command-history.py record DIR [--duration S]   # fly every reference case, write DIR/history.json
    scripts/command-history.py check DIR                    # fly them again, compare with DIR/history.json
    scripts/command-history.py check DIR --transport direct # the same cases in process (`aocs run --transport
                                                            # direct`) against the LCM lockstep history

A case is a reference scenario (sil/scenarios/*.toml) with one of its laws (its own, every law it defines
for the IRASSI ones, with and without slew guidance where it has [guidance]). Each is flown with
`aocs run` in lockstep; the digest of a case (aocs_loop.history.digest) is the SHA-256 of the decoded fields of its log that every
protocol version since 2 has, as exact bits: of every actuator_cmd_t the fields of COMMAND_FIELDS (all
but the timing ones, utime, step_ns, overrun, n_overrun, and the protocol version), of every sensors_t
those of SENSOR_FIELDS (the valid bits of version 2 only): the flight software's commands and the plant's
sensor stream, bit for bit. So the same script run on a version 2 checkout and on a later one gives
comparable digests (a new wire field changes the bytes of every message, not what they say).
`check` exits 1 and names every case whose digest moved.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
AOCS = ROOT / ".venv" / "bin" / "aocs"
VENV_PYTHON = ROOT / ".venv" / "bin" / "python"

#: (scenario, law, extra aocs run arguments): the reference cases
CASES = [
    ("rtc_ex1a", None, []), ("rtc_ex2a", None, []), ("rtc_ex3b", None, []),
    ("gao_mrp", None, []), ("gao_mrp", "mrp_sat_tanh", []), ("geo_hinf", None, []),
    ("landsat8_q1", None, []), ("landsat8_srp", None, []), ("landsat8_debris", None, ["--duration", "70"]),
    ("irassi_small", "quat_pd", []), ("irassi_small", "quat_nlpd_neg", []), ("irassi_small", "smc", []),
    ("irassi_small", "lqr_quat", []), ("irassi_small", "quat_pid", []), ("irassi_small", "lqr_quat_i", []),
    ("irassi_large", "quat_pd", ["--limit", "0.5", "--guidance", "slew"]),
    ("irassi_large", "quat_pid", ["--limit", "0.5", "--guidance", "slew"]),
    ("irassi_large", "smc", ["--limit", "0.5"]),
    ("irassi_rw", "quat_pid", ["--guidance", "slew"]), ("irassi_rw", "lqr_quat_i", []),
    ("irassi_rw_failed", "quat_pd", ["--guidance", "slew"]),
]

def _digest(log_path: Path) -> dict:
    """aocs_loop.history.digest of the run's log (the fields and their order are defined there, once)."""
    sys.path[:0] = [str(ROOT / "sil"), str(ROOT / "tools")]
    from aocs_loop import history  # noqa: E402  (the venv's packages, after the path is set)
    from aocs_wire import lcmlog  # noqa: E402
    return history.digest(lcmlog.read(log_path))


def _fly(scenario: str, law: str | None, extra: list[str], duration: float, out: Path,
         transport: str = "lcm") -> dict:
    args = [str(AOCS), "run", scenario, "--duration", str(duration), "--out", str(out), "--no-plots", "-q",
            "--seed", "7", "--transport", transport]
    if law:
        args += ["--law", law]
    args += extra
    proc = subprocess.run(args, capture_output=True, text=True)
    log = out / "run.lcmlog"
    if not log.is_file():
        # the checkout's path left out, so that a refusal reads the same from any checkout
        return {"error": f"exit {proc.returncode}: {proc.stderr.replace(str(ROOT), '<repo>').strip()[-300:]}"}
    d = _digest(log)
    d["exit"] = proc.returncode
    return d


def _key(scenario, law, extra) -> str:
    return " ".join([scenario, law or "(default)", *extra])


def main() -> int:
    if Path(sys.prefix).resolve() != (ROOT / ".venv").resolve() and VENV_PYTHON.is_file():
        # run as `scripts/command-history.py`: the log reader needs the venv's packages (lcm, numpy)
        os.execv(str(VENV_PYTHON), [str(VENV_PYTHON), str(Path(__file__).resolve()), *sys.argv[1:]])
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("action", choices=("record", "check"))
    p.add_argument("dir")
    p.add_argument("--duration", type=float, default=60.0, help="s of each case (default 60)")
    p.add_argument("--transport", choices=("lcm", "direct"), default="lcm",
                   help="aocs run --transport of every case (default lcm; a history is always compared as is)")
    a = p.parse_args()
    d = Path(a.dir)
    d.mkdir(parents=True, exist_ok=True)
    ref = json.loads((d / "history.json").read_text()) if a.action == "check" else None
    duration = ref["duration"] if ref else a.duration
    results, bad = {}, []
    for scenario, law, extra in CASES:
        k = _key(scenario, law, extra)
        r = _fly(scenario, law, extra, duration, d / "runs" / k.replace(" ", "_"), a.transport)
        results[k] = r
        if ref is not None:
            same = ref["cases"].get(k) == r
            if not same:
                bad.append(k)
            print(f"{'same   ' if same else 'CHANGED'} {k}", flush=True)
        else:
            print(f"recorded {k}: {r.get('n_commands', r.get('error'))}", flush=True)
    if ref is None:
        (d / "history.json").write_text(json.dumps({"duration": duration, "cases": results}, indent=1))
        return 0
    print(f"{len(CASES) - len(bad)} of {len(CASES)} cases bit-identical")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
