"""docs/python-api.md runs as written: its fenced python blocks, in order, in one namespace, in a scratch folder
(the documented code is the tested code); then what the blocks made is checked, and the API's error line is the
command line's."""
from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DOC = REPO / "docs" / "python-api.md"
FENCE = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def blocks() -> list[str]:
    return FENCE.findall(DOC.read_text())


def test_the_worked_example_runs_as_written(tmp_path):
    code = blocks()
    assert len(code) >= 8, "docs/python-api.md lost its examples"
    ns: dict = {"__name__": "__doc_example__"}
    cwd = os.getcwd()
    os.chdir(tmp_path)
    out = io.StringIO()
    try:
        for i, src in enumerate(code):
            with contextlib.redirect_stdout(out):
                exec(compile(src, f"{DOC.name} block {i + 1}", "exec"), ns)   # noqa: S102 - the doc's own code
    finally:
        os.chdir(cwd)
    printed = out.getvalue()
    assert "refused: " in printed and "actuator.axis_limit" in printed
    for f in ("run.html", "compare.html", "mc.html", "run/telemetry.parquet", "run/run.lcmlog"):
        assert (tmp_path / "out" / "api" / f).is_file(), f
    assert ns["r"].passed and len(ns["df"]) == 2001           # 200 s at 10 Hz, both ends
    assert list(ns["c"].table["law"]) == ["quat_pd", "smc"]
    assert len(ns["rows"]) == 3 and set(ns["rows"]["status"]) == {"passed"}


def test_the_api_error_is_the_command_line_s_line(tmp_path):
    import aocs_api as aocs

    try:
        aocs.run("irassi_rw", law="warp_drive", out=tmp_path / "x")
    except aocs.AocsError as exc:
        line = exc.line("run")
    p = subprocess.run([sys.executable, "-m", "aocs.cli", "run", "irassi_rw", "--law", "warp_drive", "--out",
                        str(tmp_path / "x")], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and p.stderr.strip() == line
