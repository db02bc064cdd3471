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
missing, in bursts (the kernel socket reported no drops).

This recorder reads the udpm group's socket itself (udpm.Udpm, the plant's
reader, with a catch-all subscription and a 4 MiB socket buffer): no queue
of the library, no receive thread handing each message over a pipe to a
Python callback. It runs as one thread of the runner, whose main thread only
polls its children; it costs ~4 us of CPU per message where the library's
path cost ~15 us (0.3 s of a 500 s irassi_large run, 20,000 messages). It is
ready when it has recorded its own start marker, and everything published
before its end marker is in the file when stop() returns. The thread that
reads the socket closes it, after its last read.
`aocs run --recorder lcm-logger` uses lcm-logger instead (orchestrate.py).
"""
from __future__ import annotations

import json
import struct
import threading
import time
from pathlib import Path

from . import netns, wire
from .udpm import Udpm

_SYNC = 0xEDA1DA01
_HEAD = struct.Struct(">IqqII")
#: the recorder's nap after reading what was queued, s
NAP_S = 0.002


#: the marker channel as udpm.Udpm's catch-all gives it
RUNNER_CHANNEL = wire.RUNNER.encode()


def encode_event(n: int, utime: int, channel: str, data: bytes) -> bytes:
    ch = channel.encode()
    return _HEAD.pack(_SYNC, n, utime, len(ch), len(data)) + ch + data


def marker_of(data: bytes) -> dict | None:
    """The JSON object of an AOCS_RUNNER marker's payload, None for a damaged one."""
    try:
        m = json.loads(data.decode())
    except (UnicodeDecodeError, json.JSONDecodeError):
        return None
    return m if isinstance(m, dict) else None


def marker_message(what: str, tag: str, **info) -> bytes:
    """An AOCS_RUNNER marker's payload (JSON): its kind ("start", "end"), a tag unique in the run, the
    wall time and the run's information (scenario, law, mode)."""
    return json.dumps({"marker": what, "tag": tag, "wall_time": time.time(), **info}).encode()


class EventLogWriter:
    """Events appended in memory (event number, receive time in us since the epoch, channel, payload) and
    written to an lcm-logger file by flush(): the recorder thread's and the recording plant's log."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        self._f = open(self.path, "wb")
        self._buf: list[bytes] = []     # header, channel, payload of each event: joined when written
        self.count = 0

    def add(self, channel: bytes, data: bytes) -> None:
        """One event (the plant's hot loop: three per tick, no copy of the payload until it is written)."""
        self._buf += (_HEAD.pack(_SYNC, self.count, time.time_ns() // 1000, len(channel), len(data)), channel,
                      data)
        self.count += 1

    def add_block(self, block: bytes, count: int) -> None:
        """count events already encoded as this file's records, numbered from self.count on (the compiled loop's
        block, aocs_runner.compiled_loop): written after the pending ones."""
        self.flush()
        self._f.write(block)
        self.count += count

    @property
    def pending(self) -> int:
        """Events not yet written."""
        return len(self._buf) // 3

    def flush(self) -> None:
        if self._buf:
            buf, self._buf = self._buf, []
            self._f.write(b"".join(buf))
            self._f.flush()

    def close(self) -> None:
        if not self._f.closed:
            self.flush()
            self._f.close()


class Recorder:
    """Record every channel to path until stop()."""

    def __init__(self, path: str | Path, url: str | None = None, recv_buf: int = 4 * 1024 * 1024,
                 flush_s: float = 0.25):
        if url is None:
            netns.require_netns()
            url = netns.LCM_URL
        self.path = Path(path)
        self._log = EventLogWriter(self.path)
        self._link: Udpm | None = Udpm(url, recv_buf=recv_buf)
        self._link.subscribe_all(self._on_message)
        self._flush_s = flush_s
        self._stop = threading.Event()
        self._seen_markers: set = set()
        self._cv = threading.Condition()
        self.error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="aocs-recorder", daemon=True)
        self._markers = 0
        self._last_counters: dict | None = None

    @property
    def count(self) -> int:
        return self._log.count

    def _on_message(self, channel, data):
        self._log.add(channel, data)
        tag = (marker_of(data) or {}).get("tag") if channel == RUNNER_CHANNEL else None
        if tag is not None:
            with self._cv:
                self._seen_markers.add(tag)
                self._cv.notify_all()

    def _run(self):
        link = self._link
        try:
            next_flush = time.monotonic() + self._flush_s
            while not self._stop.is_set():
                if link.handle_timeout(20):
                    # a nap after each burst: the socket buffer holds the next ones (4 MiB, ~60 ms of a
                    # lockstep run), read in one go, instead of a wake-up per message that takes a core
                    # from the plant or the flight computer (their round trip is the run's pace)
                    time.sleep(NAP_S)
                if time.monotonic() >= next_flush:
                    self._log.flush()
                    next_flush = time.monotonic() + self._flush_s
            # drain what is queued
            while link.handle_timeout(0) > 0:
                pass
            self._log.flush()
        except BaseException as exc:  # noqa: BLE001 - reported by stop()
            self.error = exc
        finally:
            self._release_reader()

    @property
    def udpm_counters(self) -> dict | None:
        """The reader's udpm.Udpm.counters (fragments, garbage, what the bounded reassembly dropped)."""
        link = self._link
        return link.counters if link is not None else self._last_counters

    def _release_reader(self):
        """Close the sockets: called by the thread that reads them, once it has stopped reading (or by
        stop() when that thread never started), so no socket is closed under a read. A campaign worker
        records hundreds of runs in one process: every recorder gives its descriptors back."""
        link, self._link = self._link, None
        if link is not None:
            self._last_counters = link.counters
            link.close()

    def marker(self, what: str, timeout: float = 5.0, **info) -> None:
        """Publish an AOCS_RUNNER marker and wait (bounded) until it is recorded."""
        self._markers += 1
        tag = f"{what}-{self._markers}"
        data = marker_message(what, tag, **info)
        end = time.monotonic() + timeout
        with self._cv:
            while tag not in self._seen_markers:
                left = end - time.monotonic()
                link = self._link
                if left <= 0 or not self._thread.is_alive() or link is None:
                    raise RuntimeError(f"the recorder did not see its '{what}' marker within {timeout} s"
                                       + (f": {self.error}" if self.error else ""))
                link.publish(wire.RUNNER, data)   # a plain sendto, safe beside the reading thread
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
            if self._thread.ident is None:   # never started: nothing reads the sockets
                self._release_reader()
            else:
                self._thread.join(timeout=10.0)
            if not self._thread.is_alive():
                self._log.close()
        if self.error is not None:
            raise RuntimeError(f"recorder failed: {self.error}")
