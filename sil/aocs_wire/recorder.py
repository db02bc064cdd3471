"""The run's LCM log recorder: every message on every channel, none dropped.

Writes the lcm-logger file format (lcm.EventLog, lcm-logplayer and lcm-spy
read it): per event the sync word 0xEDA1DA01, the event number, the receive
time (us since the epoch), the channel and the payload.

Why not lcm-logger itself: the LCM library queues at most 30 received but
not yet handled messages per subscription and silently drops the rest;
lcm-logger does not raise that limit. A lockstep run publishes ~30,000
messages/s, and on a 2-core machine shared by the plant and the flight
computer the logger's main thread is regularly off the CPU for more than
1 ms: measured, 0.1-2 % of the messages of a 30,000-step landsat8_q1 run were
missing, in bursts (the kernel socket reported no drops). This recorder
subscribes with an unbounded queue (set_queue_capacity(0)) and runs as a
thread of the runner, whose main thread only polls its children. It is
ready when it has recorded its own start marker, and everything published
before its end marker is in the file when stop() returns.
`aocs run --recorder lcm-logger` uses lcm-logger instead (orchestrate.py).
"""
from __future__ import annotations

import json
import struct
import threading
import time
from pathlib import Path

import lcm

from . import netns, wire

_SYNC = 0xEDA1DA01
_HEAD = struct.Struct(">IqqII")


def encode_event(n: int, utime: int, channel: str, data: bytes) -> bytes:
    ch = channel.encode()
    return _HEAD.pack(_SYNC, n, utime, len(ch), len(data)) + ch + data


class Recorder:
    """Record every channel to path until stop()."""

    def __init__(self, path: str | Path, url: str | None = None, recv_buf: int = 4 * 1024 * 1024,
                 flush_s: float = 0.25):
        if url is None:
            netns.require_netns()
            url = f"{netns.LCM_URL}&recv_buf_size={recv_buf}"
        self.path = Path(path)
        self._f = open(self.path, "wb")
        self._lc = lcm.LCM(url)
        self._pub = lcm.LCM(url.split("&recv_buf_size")[0])
        self._buf: list[bytes] = []
        self._n = 0
        self._flush_s = flush_s
        self._stop = threading.Event()
        self._seen_markers: set = set()
        self._cv = threading.Condition()
        self.error: BaseException | None = None
        self._sub = self._lc.subscribe(".*", self._on_message)
        self._sub.set_queue_capacity(0)  # unbounded: never drop
        self._thread = threading.Thread(target=self._run, name="aocs-recorder", daemon=True)
        self._markers = 0

    @property
    def count(self) -> int:
        return self._n

    def _on_message(self, channel, data):
        self._buf.append(encode_event(self._n, time.time_ns() // 1000, channel, data))
        self._n += 1
        if channel == wire.RUNNER:
            try:
                tag = json.loads(data.decode()).get("tag")
            except (UnicodeDecodeError, json.JSONDecodeError, AttributeError):
                tag = None
            if tag is not None:
                with self._cv:
                    self._seen_markers.add(tag)
                    self._cv.notify_all()

    def _write(self):
        if self._buf:
            buf, self._buf = self._buf, []
            self._f.write(b"".join(buf))
            self._f.flush()

    def _run(self):
        try:
            next_flush = time.monotonic() + self._flush_s
            while not self._stop.is_set():
                self._lc.handle_timeout(20)
                if time.monotonic() >= next_flush:
                    self._write()
                    next_flush = time.monotonic() + self._flush_s
            # drain what is queued
            while self._lc.handle_timeout(0) > 0:
                pass
            self._write()
        except BaseException as exc:  # noqa: BLE001 - reported by stop()
            self.error = exc
        finally:
            self._release_reader()

    def _release_reader(self):
        """Destroy the receiving handle: called by the thread that reads it, once it has stopped reading
        (or by stop() when that thread never started), so no handle is freed while a thread is inside it.
        pylcm has no close(), and its objects are not tracked by Python's cycle collector: the
        subscription's callback (a bound method of this recorder) makes a cycle that is never freed, and
        with it the handle's sockets, pipe and receive thread. In a worker that flies hundreds of runs
        the leaked descriptors pass FD_SETSIZE (1024) and LCM's select() then writes past its fd_set
        on the stack (the segfaults in _lcm.so of docs/campaigns.md). Unsubscribing breaks the cycle;
        dropping the last reference destroys the handle (lcm_destroy) here."""
        lc, sub = self._lc, self._sub
        self._lc = self._sub = None
        if lc is not None and sub is not None:
            try:
                lc.unsubscribe(sub)
            except Exception:  # noqa: BLE001 - the handle goes either way
                pass
        del lc, sub

    def marker(self, what: str, timeout: float = 5.0, **info) -> None:
        """Publish an AOCS_RUNNER marker and wait (bounded) until it is recorded."""
        self._markers += 1
        tag = f"{what}-{self._markers}"
        data = json.dumps({"marker": what, "tag": tag, "wall_time": time.time(), **info}).encode()
        end = time.monotonic() + timeout
        with self._cv:
            while tag not in self._seen_markers:
                left = end - time.monotonic()
                if left <= 0 or not self._thread.is_alive():
                    raise RuntimeError(f"the recorder did not see its '{what}' marker within {timeout} s"
                                       + (f": {self.error}" if self.error else ""))
                self._pub.publish(wire.RUNNER, data)
                self._cv.wait(min(left, 0.05))

    def start(self, **info) -> "Recorder":
        self._thread.start()
        self.marker("start", **info)
        return self

    def stop(self, **info) -> None:
        try:
            if self._thread.is_alive():
                self.marker("end", **info)
        finally:
            self._stop.set()
            if self._thread.ident is None:   # never started: nothing reads the handle
                self._release_reader()
            else:
                self._thread.join(timeout=10.0)
            if not self._thread.is_alive():
                self._f.close()
            # the publishing handle is used by this (the caller's) thread only, in marker()
            self._pub = None
        if self.error is not None:
            raise RuntimeError(f"recorder failed: {self.error}")
