"""Where the runner finds things: the repository, the build tree, the binaries,
the generated LCM bindings, and firmware facts read from the headers (law ids,
status names, timing budgets), so none of them is copied by hand.

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

#: law names in executive.h enum order (the wire's law_id; docs/wire-contract.md)
LAW_IDS = {
    "none": 0, "crp_linear": 1, "quat_pd": 2, "quat_nlpd_neg": 3, "quat_nlpd_pos": 4, "smc": 5,
    "lqr_quat": 6, "hinf": 7, "mrp_sat": 8, "mrp_sat_tanh": 9, "orbit_lqr": 10,
}
LAW_NAMES_BY_ID = {v: k for k, v in LAW_IDS.items()}

#: actuator_cmd_t.mode values
MODE_STANDBY, MODE_NOMINAL, MODE_SAFE = 0, 1, 2
MODE_NAMES = {MODE_STANDBY: "standby", MODE_NOMINAL: "nominal", MODE_SAFE: "safe"}

#: header macro of each law's declared host step budget (AOCS_<LAW>_BUDGET_NS)
_BUDGET_MACROS = {
    "crp_linear": ("crp_linear.h", "AOCS_CRP_LINEAR_BUDGET_NS"),
    "quat_pd": ("quat_pd.h", "AOCS_QUAT_PD_BUDGET_NS"),
    "quat_nlpd_neg": ("quat_nlpd.h", "AOCS_QUAT_NLPD_BUDGET_NS"),
    "quat_nlpd_pos": ("quat_nlpd.h", "AOCS_QUAT_NLPD_BUDGET_NS"),
    "smc": ("smc.h", "AOCS_SMC_BUDGET_NS"),
    "lqr_quat": ("lqr_quat.h", "AOCS_LQR_QUAT_BUDGET_NS"),
    "hinf": ("hinf.h", "AOCS_HINF_BUDGET_NS"),
    "mrp_sat": ("mrp_sat.h", "AOCS_MRP_SAT_BUDGET_NS"),
    "mrp_sat_tanh": ("mrp_sat.h", "AOCS_MRP_SAT_BUDGET_NS"),
    "orbit_lqr": ("orbit_lqr.h", "AOCS_ORBIT_LQR_BUDGET_NS"),
}


class SetupError(RuntimeError):
    """Something the run needs is not built or not installed (message says how to fix it)."""


BUILD_HINT = "build it first: cmake --preset host && cmake --build --preset host (or `make build-host`)"


def build_dir() -> Path:
    return Path(os.environ.get("AOCS_BUILD_DIR", REPO / "build" / "host")).resolve()


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
def status_names() -> dict[int, str]:
    """aocs_status_t value -> name, parsed from firmware/include/aocs/types.h ({} if absent)."""
    p = REPO / "firmware" / "include" / "aocs" / "types.h"
    try:
        text = p.read_text()
        body = text[text.index("typedef enum {"):text.index("} aocs_status_t;")]
    except (OSError, ValueError):
        return {}
    names = re.findall(r"^\s*(AOCS_[A-Z0-9_]+)\s*(?:=\s*0)?\s*,", body, re.M)
    return dict(enumerate(names))


def status_name(code: int) -> str:
    return status_names().get(int(code), f"status {int(code)}")


def status_code(name: str) -> int:
    """aocs_status_t value of a status name (KeyError when the firmware has no such status)."""
    for code, n in status_names().items():
        if n == name:
            return code
    raise KeyError(f"no aocs_status_t named {name}")


@lru_cache(maxsize=None)
def law_budget_ns(law: str) -> int:
    """Declared host step budget of a law (ns), read from its header; the safe-mode budget for 'none'."""
    inc = REPO / "firmware" / "include" / "aocs"
    if law == "none":
        header, macro = inc / "executive.h", "AOCS_EXEC_SAFE_BUDGET_NS"
    else:
        name, macro = _BUDGET_MACROS[law]
        header = inc / "control" / name
    m = re.search(rf"#define\s+{macro}\s+(\d+)u?", header.read_text())
    if m is None:
        raise SetupError(f"{header}: no #define {macro}")
    return int(m.group(1))
