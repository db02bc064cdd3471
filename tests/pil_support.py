"""Shared helpers of the PIL tests (test_frame, test_pil_image, test_pil_bridge, the budget tests).

Locates the PIL images: $AOCS_PIL_BUILD_ROOT/<preset>/aocs_pil.elf
(default <repo>/build, the ARM presets' build trees). A missing image makes
the test FAIL with the command that builds it; nothing skips. No tests here.
"""
from __future__ import annotations

import os
from collections.abc import Callable
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


def fly(target: str, fields: dict, steps: int, payload: Callable[[int], bytes],
        after: Callable[[int, frame.StepReply], None] | None = None) -> tuple[frame.Ack, list]:
    """A PIL image configured with `fields` (its ACK must be clean), then `steps` STEP frames: payload(k) is the
    k-th STEP payload, after(k, reply) sees each reply (e.g. to integrate the wheels the test models). Returns
    the ACK and the replies; the image is stopped, or killed on an error."""
    q = start(target)
    try:
        ack = configure(q, **fields)
        assert (ack.pil_err, ack.status) == (0, 0), ack
        replies = []
        for k in range(steps):
            _, raw = q.request(frame.T_STEP, payload(k), frame.T_STEP_REPLY)
            r = frame.StepReply.decode(raw)
            replies.append(r)
            if after is not None:
                after(k, r)
        q.stop()
        return ack, replies
    finally:
        q.kill()
