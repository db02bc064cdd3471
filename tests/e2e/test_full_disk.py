"""A full disk is an I/O failure, not bad input (issue 25, item 9): `aocs run` and `aocs campaign` writing
into a real full filesystem (a tmpfs of 64 KiB filled to the last block, mounted in a mount namespace of
the command's own) end with exit 3 and one line naming the file and "No space left on device", never a
traceback and never exit 2 (bad input)."""
from __future__ import annotations

import shlex
import shutil
import subprocess
import sys

import pytest


def _in_full_fs(tmp_path, argv):
    mnt = tmp_path / "full"
    mnt.mkdir()
    script = (f"mount -t tmpfs -o size=64k none {shlex.quote(str(mnt))} && "
              f"dd if=/dev/zero of={shlex.quote(str(mnt / 'fill'))} bs=4k 2>/dev/null; "
              f"exec {shlex.join(argv(mnt))}")
    if shutil.which("unshare") is None:
        pytest.skip("no unshare(1)")
    probe = subprocess.run(["unshare", "--mount", "true"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip("no mount namespace here (needs root or CAP_SYS_ADMIN)")
    return subprocess.run(["unshare", "--mount", "sh", "-c", script], capture_output=True, text=True, timeout=300)


def _one_io_line(p, prog):
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 3, p.stderr
    assert "Traceback" not in p.stderr
    bad = [x for x in lines if x.startswith(f"aocs {prog}: error")]
    assert len(bad) == 1 and "No space left on device" in bad[0] and "I/O failure" in bad[0], p.stderr
    return bad[0]


def test_aocs_run_into_a_full_disk(tmp_path, fsw_node_bin):
    p = _in_full_fs(tmp_path, lambda mnt: [sys.executable, "-m", "aocs.cli", "run", "irassi_small", "--duration",
                                           "1", "--out", str(mnt / "run"), "--no-plots", "-q"])
    assert str(tmp_path / "full") in _one_io_line(p, "run")


def test_aocs_campaign_into_a_full_disk(tmp_path):
    # the folder is written before any cluster: the scheduler address is never reached
    p = _in_full_fs(tmp_path, lambda mnt: [sys.executable, "-m", "aocs.cli", "campaign", "irassi_large", "--runs",
                                           "2", "--seed", "1", "--scheduler", "tcp://127.0.0.1:9", "--out",
                                           str(mnt / "mc"), "-q"])
    assert "campaign-plan" in _one_io_line(p, "campaign")
