"""The sensor frame-counter rule of fsw_node (sil/fsw_node/node_wire.c aocs_node_seq_check), for the
PIL bridge, which must behave like fsw_node on LCM (docs/wire-contract.md, "Frame acceptance").

Counters are compared modulo 2^64 (the int64 on the wire read as unsigned bits): a frame 1..W ahead
of the last accepted one is accepted (the gap counted as lost); the same or one behind (the upper
half of the circle) is a duplicate; further ahead is a jump, dropped, unless K consecutive dropped
frames each continue the one before: then the K-th is adopted (resynchronisation). One forged frame
can therefore never silence the bridge. W and K are read from node_wire.h, their one definition.
"""
from __future__ import annotations

from aocs_core import paths

_MASK = (1 << 64) - 1
_BEHIND = 1 << 63


def constants() -> tuple[int, int]:
    """(W, K) = (AOCS_NODE_SEQ_WINDOW, AOCS_NODE_SEQ_RESYNC_FRAMES) from sil/fsw_node/node_wire.h."""
    h = "sil/fsw_node/node_wire.h"
    return int(paths.header_number(h, "AOCS_NODE_SEQ_WINDOW")), int(paths.header_number(h, "AOCS_NODE_SEQ_RESYNC_FRAMES"))


class FrameSequence:
    OK, GAP, RESYNC, DUPLICATE, JUMP = "ok", "gap", "resync", "duplicate", "jump"

    def __init__(self):
        self.window, self.resync_frames = constants()
        self.have_last = False
        self.last = 0
        self.cand_last = 0
        self.cand_run = 0
        self.lost = self.duplicate = self.jump = self.resyncs = 0

    def _continues(self, a: int, b: int) -> bool:
        return 1 <= ((b - a) & _MASK) <= self.window

    def check(self, frame: int) -> str:
        f = frame & _MASK
        if not self.have_last:
            self.have_last, self.last, self.cand_run = True, f, 0
            return self.OK
        if self._continues(self.last, f):
            d = (f - self.last) & _MASK
            r = self.OK
            if d > 1:
                self.lost += d - 1
                r = self.GAP
            self.last, self.cand_run = f, 0
            return r
        d = (f - self.last) & _MASK
        self.cand_run = self.cand_run + 1 if self.cand_run > 0 and self._continues(self.cand_last, f) else 1
        self.cand_last = f
        if self.cand_run >= self.resync_frames:
            self.last, self.cand_run = f, 0
            self.resyncs += 1
            return self.RESYNC
        if d == 0 or d >= _BEHIND:
            self.duplicate += 1
            return self.DUPLICATE
        self.jump += 1
        return self.JUMP

    @staticmethod
    def accepted(result: str) -> bool:
        return result in (FrameSequence.OK, FrameSequence.GAP, FrameSequence.RESYNC)
