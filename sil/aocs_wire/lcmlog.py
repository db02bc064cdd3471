"""Read an lcm-logger log of a run into numpy arrays, one table per channel.

    log = read("out/irassi_large-quat_pd/run.lcmlog")
    log.truth["q"]        # (n, 4) true attitude per tick
    log.cmd["u_sat"]      # (n, 3) saturated command per step
    log.counts            # events per channel, and undecodable payloads

Each table is a dict field -> array in the logged order: scalars (n,),
fixed arrays (n, k); integer and boolean fields as int64, doubles as float64,
plus "log_utime" (the logger's receive time, us). Payloads that are not
exactly the channel's type (malformed, foreign fingerprint) are not decoded;
they are counted in counts["<CHANNEL>.undecodable"]. Runner markers
(AOCS_RUNNER, JSON) are in log.markers.
"""
from __future__ import annotations

import json
import struct
from dataclasses import dataclass, field
from pathlib import Path

import lcm
import numpy as np

from aocs_core import paths

from . import wire

_INT_TYPES = {"int8_t", "int16_t", "int32_t", "int64_t", "boolean", "byte"}

# lcm-logger's event format (lcm/eventlog.c; the recorder writes the same): per event the sync
# word, the event number, the receive time (us), channel length, data length, channel, data.
_SYNC = 0xEDA1DA01
_HEAD = struct.Struct(">IqqII")
#: longest channel name lcm allows (lcm.h LCM_MAX_CHANNEL_NAME_LENGTH)
_CHANNEL_MAX = 63


class LogIntegrityError(ValueError):
    """The file is not a whole lcm log: the message says "log truncated ..." or "log corrupt at byte N"."""


@dataclass
class LogScan:
    events: int          # whole events from the start of the file
    size: int            # file size, bytes
    first_event: int | None
    last_event: int | None


def scan(path: str | Path) -> LogScan:
    """Walks every event header of the file without trusting the reader's resynchronisation
    (lcm's reader skips over damage to the next sync word, silently). Raises LogIntegrityError
    on the first event that does not start where the previous one ended with the sync word, whose
    lengths run past the end of the file (truncated), or whose event number does not follow its
    predecessor's."""
    path = Path(path)
    data = path.read_bytes()
    size, off, n, first, prev = len(data), 0, 0, None, None
    while off < size:
        if size - off < _HEAD.size:
            raise LogIntegrityError(f"{path}: log truncated at byte {off} (a partial event header)")
        sync, num, _utime, ch_len, data_len = _HEAD.unpack_from(data, off)
        if sync != _SYNC:
            raise LogIntegrityError(f"{path}: log corrupt at byte {off} (no event starts there)")
        if not 0 < ch_len <= _CHANNEL_MAX:
            raise LogIntegrityError(f"{path}: log corrupt at byte {off} (channel length {ch_len})")
        end = off + _HEAD.size + ch_len + data_len
        if end > size:
            raise LogIntegrityError(f"{path}: log truncated at byte {off} (its last event is cut short)")
        if prev is not None and num != prev + 1:
            raise LogIntegrityError(f"{path}: log corrupt at byte {off} (event {num} follows event {prev})")
        first = num if first is None else first
        prev, off, n = num, end, n + 1
    return LogScan(n, size, first, prev)


@dataclass
class Log:
    path: Path
    truth: dict
    cmd: dict
    sensors: dict
    status: dict
    command: dict
    markers: list = field(default_factory=list)
    counts: dict = field(default_factory=dict)
    events: list | None = None    # raw (channel, data, utime) when keep_raw


def _table(codec: wire.Codec, rows: list, utimes: list) -> dict:
    cls = codec.cls
    out: dict = {}
    arr = np.array(rows, dtype=float).reshape(len(rows), -1) if rows else None
    for (name, n), typ in zip(codec.fields, cls.__typenames__):
        i = codec.index(name)
        if arr is None:
            col = np.zeros((0,) if n is None else (0, n))
        else:
            col = arr[:, i] if n is None else arr[:, i:i + n]
        if typ in _INT_TYPES:
            col = col.astype(np.int64)
        out[name] = col
    # int64 fields: decode exactly (doubles hold integers exactly only below 2^53)
    if rows:
        for (name, n), typ in zip(codec.fields, cls.__typenames__):
            if typ == "int64_t":
                i = codec.index(name)
                if n is None:
                    out[name] = np.array([r[i] for r in rows], dtype=np.int64)
    out["log_utime"] = np.array(utimes, dtype=np.int64)
    return out


def read(path: str | Path, keep_raw: bool = False) -> Log:
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such log")
    codecs = wire.Codecs(paths.import_bindings())
    by_channel = {wire.TRUTH: codecs.truth, wire.ACTUATOR: codecs.actuator, wire.SENSORS: codecs.sensors,
                  wire.STATUS: codecs.status, wire.COMMAND: codecs.command}
    rows: dict[str, list] = {c: [] for c in by_channel}
    utimes: dict[str, list] = {c: [] for c in by_channel}
    counts: dict[str, int] = {}
    markers = []
    raw = [] if keep_raw else None
    log = lcm.EventLog(str(path), "r")
    try:
        for ev in log:
            ch, data = ev.channel, ev.data
            counts[ch] = counts.get(ch, 0) + 1
            if raw is not None:
                raw.append((ch, data, ev.timestamp))
            codec = by_channel.get(ch)
            if codec is not None:
                v = codec.unpack(data)
                if v is None:
                    key = f"{ch}.undecodable"
                    counts[key] = counts.get(key, 0) + 1
                else:
                    rows[ch].append(v)
                    utimes[ch].append(ev.timestamp)
            elif ch == wire.RUNNER:
                try:
                    markers.append(json.loads(data.decode()))
                except (UnicodeDecodeError, json.JSONDecodeError):
                    pass
    finally:
        log.close()
    t = {c: _table(by_channel[c], rows[c], utimes[c]) for c in by_channel}
    return Log(path, t[wire.TRUTH], t[wire.ACTUATOR], t[wire.SENSORS], t[wire.STATUS], t[wire.COMMAND],
               markers, counts, raw)


def _tick_gap(ticks: np.ndarray, first: int, last: int | None, absent_ok=()) -> str | None:
    """None when the ticks present, with absent_ok added, are exactly first, first+1, ..., last (last
    None: up to the largest present). Repeats and order are not judged: fault events duplicate or
    replay frames on purpose, and a `drop` event sends no frame (absent_ok)."""
    ticks = np.union1d(ticks, np.asarray(sorted(absent_ok), dtype=np.int64)) if absent_ok else np.unique(ticks)
    if ticks.size == 0:
        return "none at all"
    if int(ticks[0]) != first:
        return f"the first is {int(ticks[0])}, not {first}"
    steps = np.diff(ticks)
    bad = np.flatnonzero(steps != 1)
    if bad.size:
        i = int(bad[0])
        return f"tick {int(ticks[i + 1])} follows tick {int(ticks[i])}"
    if last is not None and int(ticks[-1]) != last:
        return f"the last is {int(ticks[-1])}, not {last}"
    return None


def completeness_problems(log: Log, n_steps: int | None = None, *, replies_expected: int | None = None,
                          dropped_ticks=()) -> list[str]:
    """What is missing from a run's log (empty when it is whole): the recorder's start and end
    markers, every sensor frame 0 .. n_steps-1 but the dropped ones (`drop` events), every truth
    sample 0 .. n_steps and, when given, the number of flight-computer replies (lockstep: one per
    sensor frame less the dropped ones)."""
    problems = []
    kinds = [m.get("marker") for m in log.markers]
    if "start" not in kinds:
        problems.append("no start marker of the recorder")
    if "end" not in kinds:
        problems.append("log truncated: no end marker of the recorder")
    gap = _tick_gap(log.sensors["tick"], 0, None if n_steps is None else n_steps - 1, dropped_ticks)
    if gap:
        problems.append(f"sensor frames incomplete: {gap}")
    if n_steps is not None:
        gap = _tick_gap(log.truth["tick"], 0, n_steps)
        if gap:
            problems.append(f"truth samples incomplete: {gap}")
    if replies_expected is not None and log.cmd["tick"].size != replies_expected:
        problems.append(f"{log.cmd['tick'].size} flight-computer replies logged, {replies_expected} expected")
    return problems
