"""Shared helpers of the PIL tests (test_pil_frame, test_pil_image, test_pil_bridge).

- makes `import aocs_pil` work before pyproject.toml maps the package
  (a private directory with a link aocs_pil -> sil/pil on sys.path and on
  PYTHONPATH, so `python -m aocs_pil.bridge` works in child processes too);
- reads the law registry of the host build (registry());
- locates the PIL images: $AOCS_PIL_BUILD_ROOT/<preset>/aocs_pil.elf
  (default <repo>/build, the ARM presets' build trees). A missing image
  makes the test FAIL with the command that builds it; nothing skips.

No tests here.
"""
from __future__ import annotations

import hashlib
import importlib
import os
import sys
import tempfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
TARGETS = ("pil-m4f", "pil-m7")


def _bootstrap() -> None:
    try:
        importlib.import_module("aocs_pil")
        return
    except ImportError:
        pass
    tag = hashlib.sha1(str(REPO).encode()).hexdigest()[:12]
    d = Path(tempfile.gettempdir()) / f"aocs-pil-path-{os.getuid()}-{tag}"
    d.mkdir(exist_ok=True)
    link = d / "aocs_pil"
    if not link.exists():
        try:
            link.symlink_to(REPO / "sil" / "pil", target_is_directory=True)
        except FileExistsError:
            pass
    sys.path.insert(0, str(d))
    os.environ["PYTHONPATH"] = str(d) + (os.pathsep + os.environ["PYTHONPATH"] if os.environ.get("PYTHONPATH")
                                         else "")


_bootstrap()

from aocs_pil import frame, qemu  # noqa: E402


def build_root() -> Path:
    return Path(os.environ.get("AOCS_PIL_BUILD_ROOT", REPO / "build")).resolve()


def registry() -> dict:
    """The law registry of the host build ($AOCS_BUILD_DIR, default build/host):
    registry/aocs_registry.json, written at build time from firmware/include/aocs/laws.def."""
    import json  # only the registry readers need it

    bdir = Path(os.environ.get("AOCS_BUILD_DIR", REPO / "build" / "host")).resolve()
    path = bdir / "registry" / "aocs_registry.json"
    if not path.is_file():
        pytest.fail(f"{path} missing: build it first (make build-host)")
    return json.loads(path.read_text())


def image(target: str) -> Path:
    t = qemu.TARGETS[target]
    path = qemu.image_path(t)
    if not path.is_file():
        pytest.fail(f"PIL image {path} missing: build it with `cmake --preset {t.preset} && "
                    f"cmake --build --preset {t.preset}` (or point AOCS_PIL_BUILD_ROOT at the ARM build trees)")
    return path


def start(target: str, reply_timeout: float = 5.0) -> qemu.Qemu:
    q = qemu.Qemu(qemu.TARGETS[target], image(target), reply_timeout=reply_timeout)
    q.start()
    return q


def configure(q: qemu.Qemu, **fields) -> frame.Ack:
    """CONFIG with the given fields (names of frame.CFG_FIELDS, lower case); returns the ACK."""
    cf = frame.ConfigFields()
    for name, value in fields.items():
        cf.add(name.upper(), value)
    _, p = q.request(frame.T_CONFIG, cf.encode(), frame.T_CONFIG_ACK)
    return frame.Ack.decode(p)
