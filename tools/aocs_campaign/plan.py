"""A campaign's definition and its runs: what each run sets, and the command that repeats it.

    Campaign(scenario, law, runs, seed, sets, dispersions) -> plan(c) -> [RunSpec, ...]

The definition comes from the command line and/or a `[campaign]` table of a
campaign file (docs/campaigns.md):

    [campaign]
    scenario = "irassi_large"          # only in a campaign file
    law = "quat_pd"
    runs = 1000
    seed = 1
    set = ["actuator.axis_limit=0.5"]  # like --set
    disperse = ["plant.w0=normal:0:1e-4", "plant.euler321_deg=rotation:2"]

Each run's overrides are the campaign's --set plus its dispersed values
(dispersions.sample: a function of seed and index), and its repeat command
`aocs run SCENARIO --law L --set ... --json FILE --no-plots -q` carries them
written with repr, so that command alone flies the same run bit for bit.
"""
from __future__ import annotations

import hashlib
import json
import shlex
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path

from aocs_plant import scenario as scmod
from aocs_runner import scenario_opts
from aocs_runner.transport import check_transport

from . import dispersions as D
from . import fault_dispersion as FD

#: most runs of one campaign (a campaign folder holds one result file per run)
RUNS_MAX = 1_000_000
#: --transport direct: run i is flown again over LCM when i % REFLY_EVERY == 0 (run 0 always), and the two
#: command histories must be the same bit for bit (worker.run_task; docs/campaigns.md)
REFLY_EVERY = 50
CAMPAIGN_KEYS = ("scenario", "law", "runs", "seed", "set", "disperse", "faults")


class CampaignError(ValueError):
    """A campaign definition that cannot be run; the message names the option or key."""


@dataclass
class Campaign:
    scenario: str
    law: str | None
    runs: int
    seed: int
    sets: list = field(default_factory=list)
    disperse: list = field(default_factory=list)
    #: lcm | direct (aocs_runner.transport); not part of the identity: both fly the same rows
    transport: str = "lcm"
    #: direct: every how many runs one is re-flown over LCM (0: none)
    refly_every: int = REFLY_EVERY
    #: [campaign.faults]: one injected fault per run, its kind and times drawn (fault_dispersion.py); None: none
    faults: dict | None = None

    def refly(self, index: int) -> bool:
        """Whether run index is re-flown over LCM and compared (a direct campaign's sample)."""
        return self.transport == "direct" and self.refly_every > 0 and index % self.refly_every == 0

    def identity(self) -> dict:
        """What defines the campaign's rows, recorded in its folder (campaign-plan.json): the scenario file and
        the digest of its parsed content (an edited file is another campaign, a comment is not), the law, the
        seed, the --set and the dispersions; fingerprint is their digest. A resumed folder must hold the same."""
        doc = scmod.document(self.scenario)
        d = {"scenario": str(scmod.resolve(self.scenario)),
             "scenario_sha256": hashlib.sha256(json.dumps(doc, sort_keys=True, default=str).encode()).hexdigest(),
             "law": self.law, "seed": self.seed, "sets": list(self.sets), "disperse": list(self.disperse)}
        if self.faults is not None:      # (absent without: the fingerprints of campaigns without faults unchanged)
            d["faults"] = self.faults
        return {"fingerprint": hashlib.sha256(json.dumps(d, sort_keys=True).encode()).hexdigest()[:16], **d}

    def fingerprint(self) -> str:
        """What makes two campaigns the same (identity()'s digest)."""
        return self.identity()["fingerprint"]


@dataclass
class RunSpec:
    index: int
    scenario: str
    law: str | None
    overrides: dict     # dotted key -> value (the campaign's --set, then the dispersed values)
    inputs: dict        # dispersed scalar -> value (results columns)

    def to_dict(self) -> dict:
        return asdict(self)


def read_file_section(path: str) -> dict:
    """The [campaign] table of a campaign or scenario file ({} when there is none)."""
    p = scmod.resolve(path)
    try:
        with open(p, "rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise CampaignError(f"{p}: no such file") from None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise CampaignError(f"{p}: not readable as TOML: {exc}") from None
    sec = data.get("campaign")
    if sec is None:
        return {}
    if not isinstance(sec, dict):
        raise CampaignError(f"{p}: campaign: must be a table")
    for k, v in sec.items():
        if k not in CAMPAIGN_KEYS:
            raise CampaignError(f"{p}: campaign.{k}: unknown key; known: {', '.join(CAMPAIGN_KEYS)}")
        if k in ("set", "disperse") and not (isinstance(v, list) and all(isinstance(x, str) for x in v)):
            raise CampaignError(f"{p}: campaign.{k}: must be a list of strings (\"KEY=...\")")
        if k in ("runs", "seed") and not (isinstance(v, int) and not isinstance(v, bool)):
            raise CampaignError(f"{p}: campaign.{k}: must be an integer")
        if k in ("scenario", "law") and not isinstance(v, str):
            raise CampaignError(f"{p}: campaign.{k}: must be a string")
        if k == "faults" and not isinstance(v, dict):
            raise CampaignError(f"{p}: campaign.faults: must be a table (kinds, start_s, ...; docs/campaigns.md)")
    sec = dict(sec)
    if "kind" in data:            # a scenario file: it is the scenario
        if "scenario" in sec:
            raise CampaignError(f"{p}: campaign.scenario: a scenario file's campaign flies that scenario")
        sec["scenario"] = str(p)
    elif "scenario" not in sec:
        raise CampaignError(f"{p}: campaign.scenario: missing (the scenario id or file)")
    return sec


def document(c: Campaign) -> dict:
    """The scenario document with the campaign's --set applied (the nominal of every dispersion)."""
    return scmod.document(c.scenario, scenario_opts.parse_sets(c.sets))


def check(c: Campaign) -> list[D.Dispersion]:
    """Validates the campaign before anything runs; returns its dispersions."""
    if not 1 <= c.runs <= RUNS_MAX:
        raise CampaignError(f"--runs {c.runs}: must be in [1, {RUNS_MAX}]")
    if c.seed < 0:
        raise CampaignError(f"--seed {c.seed}: must be >= 0")
    check_transport(c.transport)
    if isinstance(c.refly_every, bool) or not isinstance(c.refly_every, int) or c.refly_every < 0:
        raise CampaignError(f"--refly-every {c.refly_every}: must be a whole number >= 0 (0: no LCM re-flight)")
    disps = D.parse_all(c.disperse)
    base = scenario_opts.parse_sets(c.sets)
    for d in disps:
        if d.key in base and not d.index:
            raise D.DispersionError(f"--disperse {d.text}: {d.key} is also given with --set")
    doc = document(c)
    sid = doc.get("id", c.scenario)
    D.check_against(disps, doc, sid)
    FD.check(c.faults)
    # every dispersed key goes through the loader once (a key the loader does not know is named by it)
    ov, _ = D.sample(disps, doc, c.seed, 0)
    ov.update(FD.overrides(c.faults, doc, c.seed, 0)[0])
    try:
        sc = scmod.load(c.scenario, {**base, **ov})
    except scmod.ScenarioError as exc:
        names = ", ".join([d.text for d in disps] + (["[campaign.faults]"] if c.faults is not None else [])) \
            or "(none)"
        raise D.DispersionError(f"--disperse {names}: the scenario refuses run 0's values: {exc}") from None
    try:
        scenario_opts.resolve_law(sc, c.law)      # a law the scenario cannot fly: refused before any cluster
    except ValueError as exc:
        raise CampaignError(str(exc)) from None
    return disps


def iter_plan(c: Campaign, disps: list[D.Dispersion], indices=None):
    """The RunSpec of each run of indices (default: all), one at a time (a campaign of a million runs
    submits a few at once: execute.run)."""
    doc = document(c)
    base = scenario_opts.parse_sets(c.sets)
    for i in (range(c.runs) if indices is None else indices):
        ov, inputs = D.sample(disps, doc, c.seed, i)
        fov, finputs = FD.overrides(c.faults, doc, c.seed, i)
        yield RunSpec(i, c.scenario, c.law, {**base, **ov, **fov}, {**inputs, **finputs})


def plan(c: Campaign, disps: list[D.Dispersion], indices=None) -> list[RunSpec]:
    return list(iter_plan(c, disps, indices))


def repeat_command(spec: RunSpec, json_path: str = "run.json", transport: str = "lcm") -> str:
    """The `aocs run` command that repeats this run alone (same metrics JSON, bit for bit)."""
    words = ["aocs", "run", spec.scenario]
    if spec.law:
        words += ["--law", spec.law]
    words += scenario_opts.to_args(spec.overrides)
    if transport != "lcm":
        words += ["--transport", transport]
    words += ["--recorder", "plant", "--json", json_path, "--no-plots", "-q"]   # the campaign's recorder (worker.py)
    return shlex.join(words)


def load_campaign_dir_plan(out: Path) -> tuple[dict | None, str]:
    """OUT's campaign-plan.json, or None and why not (missing, unreadable, not JSON, no fingerprint)."""
    p = out / "campaign-plan.json"
    if not p.exists():
        return None, "missing"
    try:
        d = json.loads(p.read_bytes())
    except OSError as exc:
        return None, f"unreadable ({exc.strerror or exc})"
    except (ValueError, RecursionError):
        return None, "corrupt (not JSON)"
    if not isinstance(d, dict) or not isinstance(d.get("fingerprint"), str):
        return None, "corrupt (no campaign fingerprint)"
    return d, "ok"


#: metrics of a run that measure the machine, not the flight (wall and step times, the log's path,
#: the node's own timing report, the overruns these cause and so the verdict's timing check): left
#: out when a repeated run is compared with the campaign's row; everything else is bit-identical
VOLATILE_METRICS = ("timing", "lockstep", "loop", "realtime", "fsw_node", "wall_s", "log", "verdict",
                    "counters.overruns")


def flight_metrics(metrics: dict) -> dict:
    """The metrics without VOLATILE_METRICS (a deep copy)."""
    out = json.loads(json.dumps(metrics))
    for k in VOLATILE_METRICS:
        node = out
        parts = k.split(".")
        for p in parts[:-1]:
            node = node.get(p, {}) if isinstance(node, dict) else {}
        if isinstance(node, dict):
            node.pop(parts[-1], None)
    return out
