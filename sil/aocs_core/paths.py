"""Where the runner finds things: the repository, the build tree, the binaries,
the generated LCM bindings. The firmware's facts (law ids and names, their
fields, budgets, gain tables, status and mode names) come from the build's law
registry: aocs_core.registry (mode values by name: aocs_core.modes), never a copy.

The build directory is AOCS_BUILD_DIR (default <repo>/build/host), the same
variable the SIL tests use.
"""
from __future__ import annotations

import os
import re
import shutil
import sys
from functools import lru_cache
from pathlib import Path

import lcm

REPO = Path(__file__).resolve().parents[2]

class SetupError(RuntimeError):
    """Something the run needs is not built or not installed (message says how to fix it)."""


BUILD_HINT = "build it first: cmake --preset host && cmake --build --preset host (or `make build-host`)"


def build_dir() -> Path:
    """$AOCS_BUILD_DIR, default <repo>/build/host, resolved (once per value: a run asks dozens of times)."""
    return _resolved(os.environ.get("AOCS_BUILD_DIR") or str(REPO / "build" / "host"))


@lru_cache(maxsize=16)
def _resolved(path: str) -> Path:
    return Path(path).resolve()


def pil_build_roots() -> list[Path]:
    """Where the PIL images are looked for, <root>/<preset>/aocs_pil.elf (docs/pil.md):
    $AOCS_PIL_BUILD_ROOT alone when set, else the parent of the host build directory
    (AOCS_BUILD_DIR=<root>/host, the presets' layout), then <repo>/build."""
    env_root = os.environ.get("AOCS_PIL_BUILD_ROOT")
    if env_root:
        return [Path(env_root)]
    roots = [build_dir().parent, (REPO / "build").resolve()]
    return roots if roots[0] != roots[1] else roots[:1]


def fsw_node_exe() -> Path:
    exe = build_dir() / "bin" / "fsw_node"
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        raise SetupError(f"fsw_node not found at {exe}; {BUILD_HINT}")
    return exe


def lcm_python_dir() -> Path:
    return build_dir() / "lcmtypes" / "python"


def import_bindings():
    """The generated package aocs_lcm (from the build tree), imported."""
    d = lcm_python_dir()
    if not (d / "aocs_lcm" / "__init__.py").is_file():
        raise SetupError(f"generated LCM Python bindings missing under {d}; {BUILD_HINT}")
    if str(d) not in sys.path:
        sys.path.insert(0, str(d))
    import aocs_lcm  # noqa: E402  deferred: generated in the build tree, importable only after the path above

    return aocs_lcm


def lcm_logger_exe() -> str:
    """The lcm-logger binary of the PyPI lcm package (lcm.LCM_BIN_DIR).

    Not the venv's bin/lcm-logger: that is a Python wrapper that runs the
    binary as its child, so signals and priorities sent to it would not reach
    the logger itself."""
    try:
        cand = Path(lcm.LCM_BIN_DIR) / "lcm-logger"
        if cand.is_file() and os.access(cand, os.X_OK):
            return str(cand.resolve())
    except (ImportError, AttributeError):
        pass
    found = shutil.which("lcm-logger")
    if found is None:
        raise SetupError("lcm-logger not found (pip install lcm==1.5.3 in the venv; scripts/setup.sh)")
    return found


def self_argv() -> list[str] | None:
    """argv that re-executes this program (None: netns's default, interpreter + sys.argv).

    `python -m aocs.cli ...` has sys.argv[0] = .../cli.py, which must be re-run as a module."""
    a0 = sys.argv[0] if sys.argv else ""
    if a0.endswith(("cli.py", "__main__.py")):
        return [sys.executable, "-m", "aocs.cli", *sys.argv[1:]]
    return None


def python_env() -> dict:
    """Environment for child Python processes: the bindings and our packages importable."""
    env = dict(os.environ)
    extra = [str(lcm_python_dir())]
    if env.get("PYTHONPATH"):
        extra.append(env["PYTHONPATH"])
    env["PYTHONPATH"] = os.pathsep.join(extra)
    return env


@lru_cache(maxsize=None)
def header_number(relpath: str, macro: str) -> float:
    """The number a C header defines (`#define MACRO 1.5e-3`, `1024u` or `AOCS_R(3600.0)`), read from the source tree:
    for the few fsw_node facts the Python mirrors need (node_wire.h, node_checks.h), so none is copied."""
    text = (REPO / relpath).read_text()
    m = re.search(rf"^#define\s+{re.escape(macro)}\s+(?:AOCS_R\()?([0-9.eE+-]+)[uUlL]*\b", text, re.M)
    if m is None:
        raise SetupError(f"{REPO / relpath}: no #define {macro}")
    return float(m.group(1))
