"""aocs_core.paths: where the build is, and the mode values it names.

Expected values come from independent sources: the environment variable and
the firmware's own mode names (through the build's registry).
"""
from __future__ import annotations

from pathlib import Path

from aocs_core import paths, registry

REPO = Path(__file__).resolve().parents[3]


def test_build_dir_follows_aocs_build_dir(monkeypatch, tmp_path):
    monkeypatch.setenv("AOCS_BUILD_DIR", str(tmp_path))
    assert paths.build_dir() == tmp_path.resolve()
    monkeypatch.delenv("AOCS_BUILD_DIR")
    assert paths.build_dir() == (REPO / "build" / "host").resolve()


def test_mode_values_are_the_executives():
    names = registry.load().mode_names
    assert names[paths.MODE_STANDBY] == "standby"
    assert names[paths.MODE_NOMINAL] == "nominal"
    assert names[paths.MODE_SAFE] == "safe"
    assert len(names) == 3
