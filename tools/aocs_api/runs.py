"""One run in the loop (lockstep SIL: plant_node and fsw_node as real processes on LCM, aocs_runner.run), as a result
object: the metrics as a dict, the telemetry as a pandas DataFrame, the page as HTML.

A run needs a private network namespace: in a process already inside one (`aocs run`) it runs in place; otherwise
it runs in a thread that makes a fresh one (root or CAP_SYS_ADMIN, as `aocs campaign`'s workers)."""
from __future__ import annotations

import json
import threading
from dataclasses import dataclass, field
from pathlib import Path

from aocs_analysis import telemetry as T
from aocs_analysis import verdict
from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_plant.scenario import ScenarioError
from aocs_report import html as html_mod
from aocs_report import run_report
from aocs_runner import events as evmod
from aocs_runner import orchestrate
from aocs_runner.run import RunFailed, RunOptions, execute
from aocs_wire import netns

from .errors import AocsError, check_output_file, failed, io_failure, usage
from .scenario import sets_of

#: what a run's bad input raises below the API (each turned into AocsError "error")
BAD_INPUT = (ScenarioError, ValueError, TypeError, fsw_config.ConfigError, evmod.EventError, paths.SetupError,
             netns.NetnsError, run_report.ReportError)


@dataclass
class RunResult:
    """A finished run: its folder, metrics (metrics.json as a dict) and, read when first asked, its telemetry."""
    out_dir: Path
    metrics: dict
    table: str = ""
    plots: list = field(default_factory=list)
    _telemetry: object = None

    @property
    def passed(self) -> bool:
        return bool(self.metrics["verdict"]["passed"])

    @property
    def verdict(self) -> str:
        """"passed", or what failed (one line)."""
        return "passed" if self.passed else verdict.summary(self.metrics["verdict"])

    @property
    def telemetry(self):
        """Every decoded series, one row per control tick (telemetry.parquet, units in the column names)."""
        if self._telemetry is None:
            self._telemetry = T.read(self.out_dir / "telemetry.parquet")
        return self._telemetry

    @property
    def run_record(self) -> dict:
        return json.loads((self.out_dir / "run.json").read_text())

    @property
    def repeat_command(self) -> str:
        """The `aocs run` command that flies this run again."""
        return self.run_record["repeat_command"]

    def html(self, path) -> Path:
        """Writes the run's interactive page (one self-contained HTML file) to path."""
        return write_page(run_report.run_document(self.out_dir), path)


def write_page(doc, path) -> Path:
    path = Path(path)
    path.write_text(html_mod.render(doc))
    return path


def in_private_netns(fn):
    """fn() inside a private network namespace: here when this thread is in one, else in a thread of its own that
    makes a fresh one (its child processes inherit it)."""
    if netns.in_netns():
        return fn()
    box: dict = {}

    def target():
        try:
            netns.enter_netns(fresh=True)
            box["value"] = fn()
        except BaseException as exc:  # noqa: BLE001 - handed back to the caller's thread
            box["error"] = exc

    t = threading.Thread(target=target, name="aocs-api-run")
    t.start()
    t.join()
    if "error" in box:
        raise box["error"]
    return box["value"]


def run_options(opts: RunOptions, html: str | None = None) -> RunResult:
    """The run of these options (what `aocs run` flies), and its page at html; AocsError on bad input or a failed
    process. A run whose verdict fails is returned (passed False), as `aocs run` prints it before exiting 1."""
    check_output_file("--html", html)
    try:
        res = in_private_netns(lambda: execute(opts))
    except BAD_INPUT as exc:
        raise usage(exc) from None
    except (RunFailed, orchestrate.RunAborted) as exc:
        raise failed(exc) from None
    except OSError as exc:      # after the ValueErrors: a full disk, a vanished folder (not bad input)
        raise io_failure(exc, opts.out or "out/") from None
    out = RunResult(Path(res.out_dir), res.metrics, res.table, list(res.plots))
    if html is not None:
        out.html(html)
    return out


def run(scenario, law: str | None = None, *, overrides: dict | None = None, sets=(), duration: float | None = None,
        limit: float | None = None, guidance: str | None = None, seed: int | None = None, events=(),
        out=None, telemetry_decimate: int = 1, html=None, plots: bool = False, label: str | None = None,
        allow=(), target: str = "host", quiet: bool = True, transport: str = "lcm", faults=()) -> RunResult:
    """One lockstep SIL run of scenario (an id, a file or a Scenario) with law (default the scenario's); the
    keyword arguments are `aocs run`'s options (overrides: {dotted key: value}, as --set; faults: --fault texts)."""
    try:
        name, s = sets_of(scenario, sets, overrides)
    except TypeError as exc:
        raise usage(exc) from None
    opts = RunOptions(scenario=name, law=law, duration=duration, out=None if out is None else str(out), limit=limit,
                      target=target, transport=transport, seed=seed, guidance=guidance, sets=s, events=list(events), label=label,
                      plots=plots, quiet=quiet, allow=tuple(allow), telemetry_decimate=telemetry_decimate,
                      faults=list(faults))
    return run_options(opts, None if html is None else str(html))


def load_run(folder) -> RunResult:
    """A run already in its folder (run.json, metrics.json, telemetry.parquet)."""
    folder = Path(folder)
    try:
        r = run_report.read_run(folder)
    except run_report.ReportError as exc:
        raise AocsError(str(exc)) from None
    return RunResult(folder, r.metrics, _telemetry=r.telemetry)
