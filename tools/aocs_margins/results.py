"""The margins section of docs/results.md (`make results`): every analysed law on its reference scenario,
predicted and measured in the SIL loop, the gain margin shown in SIL, the sampled-versus-continuous loss,
the lowest control rate and the saturation check, as aocs_report document blocks."""
from __future__ import annotations

import shutil
from pathlib import Path

from aocs_plant.scenario import load
from aocs_report.document import BulletList, Column, Figure, Paragraph, Section, Table

from . import analyze, law_models

#: (scenario, law or "all"): the IRASSI laws at the hold of the large slew's target (issue 22), the
#: H-infinity tables on geo_hinf, crp_linear on its reference example
CASES = (("irassi_large", "all"), ("geo_hinf", "all"), ("rtc_ex1a", "crp_linear"))
#: the laws whose Bode and Nichols plots go into docs/results/
FIGURES = (("irassi_large", "quat_pd", None), ("irassi_large", "lqr_quat", "lqr_quat_strong"),
           ("geo_hinf", "hinf", "hinf_regional"))

INTRO = (
    "`aocs analyze SCENARIO --law LAW --measure --verify` (docs/spec.md, \"Stability margins\"): each law "
    "linearised about its hold, the rigid body about the same hold, the zero-order hold and one control period "
    "of computation delay, as discrete-time python-control models; the loop broken at the plant input. "
    "GM, PM, DM, modulus margin (1 / peak |S|) and crossover are the weakest of the three axis loops "
    "(loop-at-a-time, the other axes closed) and the multivariable loop (uniform gain, phase and delay in all "
    "channels); disk = the multivariable balanced disk margin (Seiler, Packard, Gahinet 2020). Verdict "
    "against GM >= 6 dB, PM >= 30 deg, modulus margin >= 0.5. Measured: per axis one SIL run (real "
    "processes) with the actuator delayed one period ([actuator] delay_periods = 1) and a 7-tone multisine "
    "at the plant input from 0.4 to 2 times the axis crossover; the worst difference between measured and "
    "predicted loop over all 21 tones (bound: 1 dB, 5 deg); law residual = the linear law's commands from "
    "the logged states against the C law's logged commands, over their range. Gain margin in SIL: the loop "
    "gain at the plant input ([actuator] scale_factor) 0.9 and 1.1 times the predicted gain margin, from "
    "1e-3 deg off the hold.")


def _f(x, fmt=".3g"):
    return "inf" if x is None else format(x, fmt)


def _worst(res: dict, key: str, low: bool = True):
    vals = [m[key] for m in res["loops"].values()]
    if any(v is None for v in vals) and key in ("gain_margin_db",):
        vals = [v for v in vals if v is not None] or [None]
    vals = [v for v in vals if v is not None]
    return (min(vals) if low else max(vals)) if vals else None


def _name(res):
    return res["law"] + (f" ({res['table']})" if res["table"] else "")


def predicted_table(results) -> Table:
    rows = []
    for r in results:
        gm, pm = _worst(r, "gain_margin_db"), _worst(r, "phase_margin_deg")
        mm = _worst(r, "modulus_margin")
        wc = max(m["crossover_rad_s"] for m in r["loops"].values() if m["crossover_rad_s"])
        rows.append([r["scenario"], _name(r), _f(gm, ".2f"), _f(pm, ".1f"), _f(_worst(r, "delay_margin_s"), ".3f"),
                     _f(mm, ".3f"), _f(wc, ".3g"), _f(r["loops"]["mimo"]["disk_margin"], ".3f"),
                     "pass" if r["meets_requirements"] else "FAIL"])
    return Table((Column("scenario"), Column("law"), Column("GM", "dB"), Column("PM", "deg"), Column("DM", "s"),
                  Column("modulus"), Column("w_c", "rad/s"), Column("disk"), Column("6 dB / 30 deg / 0.5")), rows)


def measured_table(results) -> Table:
    rows = []
    for r in results:
        a = r.get("agreement")
        v = r.get("gain_margin_verified") or {}
        runs = v.get("runs") or []
        sil = "n/a" if not runs else (
            f"{'converged' if runs[0]['converged'] else 'NOT converged'} / "
            f"{'diverged' if runs[1]['diverged'] else 'NOT diverged'}")
        n = sum(len(r["loops"][ax].get("measured") or []) for ax in ("x", "y", "z"))
        rows.append([r["scenario"], _name(r), str(n), _f(a and a["worst_gain_db"], ".2g"),
                     _f(a and a["worst_phase_deg"], ".2g"), _f(a and a["worst_law_residual"], ".1g"),
                     "yes" if a and a["within"] else "NO", sil])
    return Table((Column("scenario"), Column("law"), Column("tones"), Column("worst gain error", "dB"),
                  Column("worst phase error", "deg"), Column("law residual"), Column("within 1 dB / 5 deg"),
                  Column("0.9 GM / 1.1 GM in SIL")), rows)


def sampled_table(results) -> Table:
    rows = []
    for r in results:
        c = r["continuous"]["mimo"]
        d = r["loops"]["mimo"]
        rows.append([r["scenario"], _name(r), _f(c["phase_margin_deg"], ".1f"), _f(d["phase_margin_deg"], ".1f"),
                     _f(c["gain_margin_db"], ".1f"), _f(d["gain_margin_db"], ".1f"),
                     _f(r.get("lowest_rate_hz"), ".3g")])
    return Table((Column("scenario"), Column("law"), Column("PM continuous", "deg"),
                  Column("PM sampled + delay", "deg"), Column("GM continuous", "dB"), Column("GM sampled + delay", "dB"),
                  Column("lowest rate for 6 dB / 30 deg", "Hz")), rows)


def saturation_table(results) -> Table:
    rows = []
    for r in results:
        df = r.get("describing_function")
        if not df:
            continue
        cells = []
        for ax in ("x", "y", "z"):
            a = df["axes"][ax]
            cells.append("none" if not a["limit_cycle"] else f"at {a['command_amplitude_nm']:.3g} N m")
        rows.append([r["scenario"], _name(r), _f(df["limit_nm"], "g"), *cells])
    return Table((Column("scenario"), Column("law"), Column("limit", "N m"), Column("x"), Column("y"),
                  Column("z")), rows)


def section(docs: Path, runs: Path, progress=None) -> tuple[Section, int]:
    """The section and the number of laws that failed (a SIL run, or the measured agreement)."""
    results, failed = [], 0
    figs = []
    for sid, laws in CASES:
        sc = load(sid)
        for law, table in law_models.law_rows(sc, laws):
            name = f"{law}-{table}" if table else law
            res, big_l = analyze.analyse(sc, law, table, delay=1)
            try:
                analyze.measured(sid, sc, res, big_l, runs / "margins" / sid / name, progress)
                res["gain_margin_verified"] = analyze.verify_gain_margin(sid, sc, res, big_l,
                                                                         runs / "margins" / sid / name, progress)
            except RuntimeError as exc:            # a failed SIL run: the row says so, the table goes on
                res["error"] = str(exc)
                failed += 1
            else:
                failed += not (res["agreement"]["within"] and res["gain_margin_verified"]["verified"])
            results.append(analyze.finite_json(res))
            if (sid, law, table) in FIGURES:
                from . import plots  # deferred: matplotlib only for the figures
                for p in plots.draw(res, big_l, runs / "margins" / sid / name):
                    dst = docs / "results" / f"margins_{sid}_{name}_{p.name}"
                    shutil.copyfile(p, dst)
                    figs.append(Figure(str(dst.relative_to(docs)), f"{sid} {name}: {p.stem}"))
    sec = Section("Stability margins, predicted and measured in the loop").add(
        Paragraph(INTRO), predicted_table(results), measured_table(results),
        Paragraph("Sampled against continuous (multivariable loop): the same gains without hold and delay, and "
                  "the lowest control rate at which the loop with the hold and one period of delay keeps 6 dB "
                  "and 30 deg on every loop (bisection to 1 %)."), sampled_table(results),
        Paragraph("Saturation (describing function, SPEC 3.4 per-axis limit at the scenario's realistic value): "
                  "the saturation's -1/N(A) covers the negative real axis left of -1, so a limit cycle is "
                  "predicted only where a loop crosses it with |L| > 1 (a lower gain margin, the integral "
                  "laws); the limit cycle's command amplitude, at which N(A) = 1/|L| there. The integral laws' conditional "
                  "integration (integral.c) stops the integrator on a saturated command, which the describing "
                  "function does not model: it states what the loop would do without that anti-windup."),
        saturation_table(results), BulletList([f"{r['scenario']} {_name(r)}: {r['error']}" for r in results
                                               if r.get("error")] or ["every SIL run of this section passed"]),
        *figs)
    return sec, failed
