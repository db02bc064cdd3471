"""Shared helpers of the PIL tests (test_frame, test_pil_image, test_pil_bridge).

Locates the PIL images: $AOCS_PIL_BUILD_ROOT/<preset>/aocs_pil.elf
(default <repo>/build, the ARM presets' build trees). A missing image makes
the test FAIL with the command that builds it; nothing skips. No tests here.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from aocs_pil import frame, qemu

REPO = Path(__file__).resolve().parents[1]
TARGETS = ("pil-m4f", "pil-m7")


def build_root() -> Path:
    return Path(os.environ.get("AOCS_PIL_BUILD_ROOT", REPO / "build")).resolve()


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
