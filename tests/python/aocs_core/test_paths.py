"""aocs_core.paths: where the build is (expected: the environment variable)."""
from __future__ import annotations

from pathlib import Path

from aocs_core import paths

REPO = Path(__file__).resolve().parents[3]


def test_build_dir_follows_aocs_build_dir(monkeypatch, tmp_path):
    monkeypatch.setenv("AOCS_BUILD_DIR", str(tmp_path))
    assert paths.build_dir() == tmp_path.resolve()
    monkeypatch.delenv("AOCS_BUILD_DIR")
    assert paths.build_dir() == (REPO / "build" / "host").resolve()

