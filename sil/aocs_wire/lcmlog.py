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
from dataclasses import dataclass, field
from pathlib import Path

import lcm
import numpy as np

from aocs_core import paths

from . import wire

_INT_TYPES = {"int8_t", "int16_t", "int32_t", "int64_t", "boolean", "byte"}


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
