"""The fsw_node configuration file, read by fsw_node's own parser.

The bridge flies a configuration file on the emulated MCU exactly as
fsw_node would fly it on the host: the file is parsed by the one C parser
(sil/fsw_node/node_config.c, on the configuration registry's rows), run as
the host tool `aocs_node_config` (sil/fsw_node/tool), which also encodes the
PIL CONFIG frame from the parsed configuration. A file fsw_node refuses is
refused here with fsw_node's message; nothing of the key table, the number
syntax or the rules is repeated in Python.
"""
from __future__ import annotations

import json
import subprocess
from dataclasses import dataclass, field, fields
from functools import lru_cache
from pathlib import Path

from aocs_core import paths, registry


class ConfigError(ValueError):
    """A configuration fsw_node would reject; str() is fsw_node's message."""


def tool_exe() -> Path:
    exe = paths.build_dir() / "bin" / "aocs_node_config"
    if not exe.is_file():
        raise paths.SetupError(f"aocs_node_config not found at {exe}; {paths.BUILD_HINT}")
    return exe


def _run(args: list[str]) -> str:
    res = subprocess.run([str(tool_exe()), *args], capture_output=True, text=True, timeout=30)
    if res.returncode != 0:
        raise ConfigError(res.stderr.strip() or f"aocs_node_config exited {res.returncode}")
    return res.stdout


@dataclass
class NodeConfig:
    """What the bridge needs of a parsed configuration (aocs_node_config_t)."""
    path: str
    law: str
    run_mode: str
    period_s: float
    idle_timeout_s: float
    run_timeout_s: float
    status_period_s: float
    lcm_url: str
    budget_ns: int
    stale_timeout_ns: int
    n_wheels: int
    guidance_mode: str
    lines: dict = field(default_factory=dict)   # key -> line of the file

    def pil_payload(self, clock_hz: float) -> bytes:
        """The CONFIG frame's payload: the file's keys in its order, a ns budget as instructions at clock_hz."""
        return bytes.fromhex(json.loads(_run([self.path, "--pil-clock-hz", repr(float(clock_hz))]))["pil_config"])


def load(path: str | Path) -> NodeConfig:
    """aocs_node_config_load and the timeout checks; ConfigError with fsw_node's message on any problem."""
    d = json.loads(_run([str(path)]))
    d["run_mode"] = d.pop("mode")   # the file's key 'mode'; every other member is the tool's JSON key of its name
    return NodeConfig(path=str(path), **{f.name: d[f.name] for f in fields(NodeConfig) if f.name != "path"})


@lru_cache(maxsize=None)
def status_hint(status_name: str, law: str) -> str:
    """The keys to check for an aocs_exec_init status, in fsw_node's words (aocs_node_config_status_hint)."""
    return _run(["--hint", status_name, law]).strip()


def key_of_pil_id(pil_id: int) -> str:
    """The configuration key of a PIL CONFIG field id (str(pil_id) when it has none)."""
    return registry.load().config_key_of_pil_id(pil_id) or str(pil_id)
