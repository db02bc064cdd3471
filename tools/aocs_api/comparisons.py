"""Every applicable law on one scenario (aocs_compare.compare), as a result object: one row per law as a DataFrame,
each law's run, the overlaid page as HTML."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from aocs_compare import report_page
from aocs_compare.compare import compare as compare_runs
from aocs_runner import orchestrate

from .errors import EXIT_FAILED, AocsError, check_output_file, usage
from .runs import BAD_INPUT, RunResult, in_private_netns, load_run, write_page
from .scenario import sets_of


@dataclass
class CompareResult:
    out_dir: Path
    scenario: object         # aocs_plant.scenario.Scenario as flown
    rows: list               # aocs_compare.compare.Row, one per law (and gain table)

    @property
    def table(self):
        """One row per law: the figures of the comparison table, and the run's verdict."""
        import pandas as pd  # deferred: ~0.3 s, only when the table is asked for

        out = []
        for r in self.rows:
            m = r.metrics or {}
            pe = m.get("pointing_error_arcsec") or {}
            out.append({"law": r.name, "error": r.error, "settle_time_s": m.get("settle_time_s"),
                        "pointing_final_max_arcsec": pe.get("final_max"), "pointing_final_rms_arcsec": pe.get("final_rms"),
                        "max_torque_norm_nm": m.get("max_torque_norm_nm"), "effort": m.get("effort"),
                        "passed": bool(m) and bool(m["verdict"]["passed"])})
        return pd.DataFrame(out)

    @property
    def runs(self) -> dict[str, RunResult]:
        """Each law's run (its metrics and telemetry), by row name."""
        return {r.name: load_run(r.out_dir) for r in self.rows if r.metrics is not None}

    @property
    def passed(self) -> bool:
        return not any(r.error for r in self.rows)

    def html(self, path) -> Path:
        return write_page(report_page.compare_document(self.out_dir), path)


def compare(scenario, *, laws: str = "all", overrides: dict | None = None, sets=(), limit: float | None = None,
            duration: float | None = None, guidance: str | None = None, out=None, telemetry_decimate: int = 1,
            html=None, run_plots: bool = False, quiet: bool = True, transport: str = "lcm") -> CompareResult:
    """`aocs compare`: one lockstep SIL run per applicable law (laws: "all" or "quat_pd,smc")."""
    check_output_file("--html", html)
    try:
        name, s = sets_of(scenario, sets, overrides)
    except TypeError as exc:
        raise usage(exc) from None
    folder = Path(out) if out is not None else Path("out") / "compare" / Path(name).stem
    try:
        folder.mkdir(parents=True, exist_ok=True)
        sc, rows, _ = in_private_netns(lambda: compare_runs(
            name, folder, laws=laws, limit=limit, duration=duration, guidance=guidance, sets=s, run_plots=run_plots,
            quiet=quiet, telemetry_decimate=telemetry_decimate, transport=transport))
    except BAD_INPUT as exc:
        raise usage(exc) from None
    except orchestrate.RunAborted as exc:
        raise AocsError(str(exc), "aborted", EXIT_FAILED) from None
    res = CompareResult(folder, sc, rows)
    if html is not None:
        res.html(html)
    return res
