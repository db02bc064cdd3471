"""Read an lcm-logger log of a run into numpy arrays, one table per channel.

    log = read("out/irassi_large-quat_pd/run.lcmlog")
    log.truth["q"]        # (n, 4) true attitude per tick
    log.cmd["u_sat"]      # (n, 3) saturated command per step
    log.counts            # events per channel, and undecodable payloads

Every field of the wire contract (docs/wire-contract.md) is a column, those of protocol version 3 too:
log.sensors["st_q"] (n, 4), ["st_t_meas_s"] (n,), ["gyro_w"] (n, 3) and the VALID_STAR_TRACKER /
VALID_GYRO bits of ["valid"]; log.cmd["estimator"], ["est_status"], ["q_est"] (n, 4), ["w_est"],
["bias_est"] (n, 3), ["est_p"] (n, 21; covariance() makes the (n, 6, 6) matrices), ["st_status"],
["n_st_used"], ["n_st_gated"], ["n_st_hostile"], ["n_est_restarts"]; log.truth["gyro_bias"] (n, 3).
Protocol version 4: log.sensors["mag_b_t"] (n, 3) and the VALID_MAGNETOMETER bit; log.cmd["mom_policy"],
["mom_status"], ["n_thrusters"], ["thruster_on_s"] (n, 12), ["dipole_am2"], ["u_unload"], ["h_wheels"], ["dh"]
(n, 3), ["unloading"], ["n_unload_events"]; unload_events() gives the rows where an unload started.

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

from aocs_core import compiled, paths

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
    fast = _scan_fast(path, data)
    if fast is not None:
        return fast
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


def _scan_fast(path: Path, data: bytes) -> LogScan | None:
    """scan() of a file whose events chain cleanly (_event_starts), in bulk: the event numbers are checked
    there; None for any other file (scan's walk then names the byte)."""
    ix = _index(np.frombuffer(data, dtype=np.uint8))
    if ix is None:
        return None
    starts, num = ix.starts, ix.num
    found = _chain_scan(len(data), starts, num)
    if isinstance(found, LogScan):
        return found
    i = found
    raise LogIntegrityError(f"{path}: log corrupt at byte {int(starts[i])} (event {int(num[i])} follows "
                            f"event {int(num[i - 1])})")


def _chain_scan(size: int, starts: np.ndarray, num: np.ndarray) -> LogScan | int:
    """The LogScan of a file of `size` bytes whose events start at `starts` (chained cleanly, _event_starts) with the
    event numbers `num`, or the index of the first event whose number does not follow its predecessor's."""
    bad = np.flatnonzero(np.diff(num) != 1)
    if bad.size:
        return int(bad[0]) + 1
    if starts.size == 0:
        return LogScan(0, size, None, None)
    return LogScan(int(starts.size), size, int(num[0]), int(num[-1]))


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
    fault_events: dict = field(default_factory=dict)   # AOCS_EVENTS (event_t): fault management's events
    #: scan(path) of the file, when the bulk decoder found it clean (its events chained, numbered in order): the
    #: caller need not walk the file again; None otherwise (scan() then names the damage)
    scan: LogScan | None = None


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


def _by_channel() -> dict:
    codecs = wire.Codecs(paths.import_bindings())
    return {wire.TRUTH: codecs.truth, wire.ACTUATOR: codecs.actuator, wire.SENSORS: codecs.sensors,
            wire.STATUS: codecs.status, wire.COMMAND: codecs.command, wire.EVENTS: codecs.event}


def read(path: str | Path, keep_raw: bool = False) -> Log:
    """The log's tables. A clean file (every event where the previous one ended, with the sync word, a
    valid channel length and within the file: what the recorder writes) is decoded in bulk (_read_fast:
    one numpy structured view per channel); any other goes through lcm.EventLog (_read_eventlog), whose
    skipping over damage the bulk decoder does not imitate. The two give the same tables bit for bit
    (tests/python/aocs_wire/test_lcmlog.py)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such log")
    log = _read_fast(path, keep_raw)
    return log if log is not None else _read_eventlog(path, keep_raw)


#: struct format character (wire._FMT) -> numpy dtype of the same big-endian encoding
_NP = {"b": "i1", "B": "u1", "h": ">i2", "i": ">i4", "q": ">i8", "f": ">f4", "d": ">f8"}


def _record_dtype(codec: wire.Codec) -> np.dtype:
    """The numpy structured dtype of one payload: the 8-byte fingerprint, then the fields in order."""
    fmt = codec.struct.format.lstrip(">")
    assert fmt.startswith("8s")
    items = [("_fingerprint", "V8")]
    for (name, n), typ in zip(codec.fields, codec.cls.__typenames__):
        code = _NP[wire._FMT[typ]]
        items.append((name, code) if n is None else (name, code, (n,)))
    dt = np.dtype(items)
    if dt.itemsize != codec.size:   # never: wire.Codec packs without padding, as numpy does here
        raise AssertionError(f"{codec.cls.__name__}: numpy record {dt.itemsize} B, codec {codec.size} B")
    return dt


#: records converted at once by _table_fast: a block of them (~1 MB) stays in the cache while every column of it
#: is converted, instead of one pass over the whole table per column (163 columns of a day's 864,000 records)
_BLOCK_RECORDS = 1024


def _convert(col: np.ndarray, typ: str, k) -> np.ndarray:
    """One column of records as _table gives it: int fields through float64, int64 scalars exactly, the rest
    float64."""
    if typ == "int64_t" and k is None:
        return col.astype(np.int64)
    if typ in _INT_TYPES:
        return col.astype(np.float64).astype(np.int64)
    return col.astype(np.float64)


#: the compiled decoder's kind of a (type, scalar) field, the conversion _convert makes: 0 float64, 1 int64 exactly,
#: 2 int64 through float64
_KIND = {(typ, scalar): (1 if (typ == "int64_t" and scalar) else 2) if typ in _INT_TYPES else 0
         for typ in wire._FMT for scalar in (True, False)}


def _table_fast(codec: wire.Codec, buf: np.ndarray, offsets: list, utimes: list) -> dict:
    """_table's columns from the payloads at offsets, decoded in bulk (_convert: the same dtypes and values),
    block by block of _BLOCK_RECORDS records."""
    n = len(offsets)
    fields = list(zip(codec.fields, codec.cls.__typenames__))
    out: dict = {}
    if not n:
        for (name, k), typ in fields:
            col = np.zeros((0,) if k is None else (0, k))
            out[name] = col.astype(np.int64) if typ in _INT_TYPES else col
    else:
        at = np.ascontiguousarray(offsets, dtype=np.int64)
        for (name, k), typ in fields:
            out[name] = np.empty((n,) if k is None else (n, k),
                                 dtype=np.int64 if typ in _INT_TYPES else np.float64)
        kernel = compiled.module(compiled.LCMLOG)
        if kernel is not None:   # every column in one pass over the records (sil/wire_kernels/lcmlog_kernel.c)
            kernel.decode(buf, at, [(*codec.layout(name), k or 1, _KIND[typ, k is None], out[name])
                                    for (name, k), typ in fields])
            out["log_utime"] = np.array(utimes, dtype=np.int64)
            return out
        dt = _record_dtype(codec)   # numpy's path: a structured view of each block's gathered rows
        for lo in range(0, n, _BLOCK_RECORDS):
            rec = _rows(buf, at[lo:lo + _BLOCK_RECORDS], dt.itemsize).reshape(-1).view(dt)
            for (name, k), typ in fields:
                out[name][lo:lo + rec.size] = _convert(rec[name], typ, k)
    out["log_utime"] = np.array(utimes, dtype=np.int64)
    return out


#: an event header as numpy reads it (the fields of _HEAD)
_HEAD_DTYPE = np.dtype([("sync", ">u4"), ("num", ">i8"), ("utime", ">i8"), ("ch_len", ">u4"), ("data_len", ">u4")])


def _rows(buf: np.ndarray, at: np.ndarray, width: int) -> np.ndarray:
    """The `width` bytes at each offset of `at` (each row within the file), as an (n, width) copy. Gathered
    through a sliding-window view of the file, not an (n, width) table of int64 indices: that table took 8
    times the rows' bytes (3 GB per channel for the 864,000 ticks of a day's log)."""
    if at.size == 0:
        return np.zeros((0, width), dtype=np.uint8)
    k = compiled.module(compiled.LCMLOG)
    if k is not None:   # one memcpy per row (sil/wire_kernels/lcmlog_kernel.c)
        return np.frombuffer(k.gather(buf, np.ascontiguousarray(at, dtype=np.int64), width),
                             dtype=np.uint8).reshape(-1, width)
    return np.lib.stride_tricks.sliding_window_view(buf, width)[at]


def _headers(buf: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The event headers starting at the byte offsets at (each within the file)."""
    return _rows(buf, at, _HEAD.size).reshape(-1).view(_HEAD_DTYPE)


def _event_starts(buf: np.ndarray) -> np.ndarray | None:
    """Byte offsets of every event of a clean file, in order, or None when it is not one. Vectorised: the
    candidates are the offsets of the sync word (an event start, or those bytes inside a payload); each
    candidate's header says where the next event would start; the events are the candidates reached from
    offset 0 by following those links (pointer doubling), and the last one must end the file."""
    size = buf.size
    if size == 0:
        return np.zeros(0, dtype=np.int64)
    if size < _HEAD.size:
        return None
    cand = []
    for shift in range(4):   # the sync word at every alignment
        n4 = (size - shift) // 4
        if n4 <= 0:
            continue
        words = buf[shift:shift + 4 * n4].view(">u4")
        cand.append(np.flatnonzero(words == _SYNC) * 4 + shift)
    pos = np.sort(np.concatenate(cand)).astype(np.int64)
    pos = pos[pos <= size - _HEAD.size]
    if pos.size == 0 or pos[0] != 0:
        return None
    hdr = _headers(buf, pos)
    ch_len = hdr["ch_len"].astype(np.int64)
    ends = pos + _HEAD.size + ch_len + hdr["data_len"].astype(np.int64)
    n = pos.size
    good = (ch_len > 0) & (ch_len <= _CHANNEL_MAX) & (ends <= size)
    nxt = np.searchsorted(pos, ends)
    linked = (nxt < n) & (pos[np.minimum(nxt, n - 1)] == ends)
    done, dead = n, n + 1                       # two sentinel nodes: the end of the file, nowhere
    nxt = np.where(good & linked, nxt, np.where(good & (ends == size), done, dead))
    jump = np.concatenate([nxt, [done, dead]])
    on = np.zeros(n + 2, dtype=bool)
    on[0] = True
    while True:                                  # on: nodes reached in < 2^k links; jump: 2^k links
        more = on.copy()
        more[jump[on]] = True
        if np.array_equal(more, on):
            break
        on, jump = more, jump[jump]
    if on[dead] or not on[done]:
        return None
    return pos[on[:n]]


@dataclass
class _Index:
    """The events of a clean file, one entry each in file order: where it starts, its number, receive time (us),
    where its payload starts and its length, and its channel (an index into names)."""
    starts: np.ndarray
    num: np.ndarray
    utime: np.ndarray
    payload: np.ndarray
    data_len: np.ndarray
    chan_id: np.ndarray
    names: list


def _index(buf: np.ndarray) -> _Index | None:
    """The events of a clean file (_event_starts), or None when it is not one or a channel name is not UTF-8 text.
    The compiled walk (aocs_lcmlog_kernel.index: one pass over the headers) when it is built, else numpy's."""
    k = compiled.module(compiled.LCMLOG)
    if k is not None:
        found = k.index(buf)
        if found is None:
            return None
        *arrays, names = found
        return _Index(*(np.frombuffer(a, dtype=np.int64) for a in arrays), names)
    starts = _event_starts(buf)
    if starts is None:
        return None
    n_ev = starts.size
    hdr = _headers(buf, starts)
    ch_len = hdr["ch_len"].astype(np.int64)
    # the channel of every event: one name table per channel length
    chan_id = np.empty(n_ev, dtype=np.int64)
    names: list[str] = []
    for L in np.unique(ch_len):
        sel = np.flatnonzero(ch_len == L)
        raw_names = _rows(buf, starts[sel] + _HEAD.size, int(L)).reshape(-1).view(f"S{int(L)}")
        uniq, inv = np.unique(raw_names, return_inverse=True)
        base = len(names)
        for u in uniq:
            b = bytes(u).ljust(int(L), b"\0")   # numpy's S type drops trailing NULs
            try:
                names.append(b.decode())
            except UnicodeDecodeError:
                return None
        chan_id[sel] = base + inv.reshape(-1)
    return _Index(starts, hdr["num"].astype(np.int64), hdr["utime"].astype(np.int64), starts + _HEAD.size + ch_len,
                  hdr["data_len"].astype(np.int64), chan_id, names)


def _read_fast(path: Path, keep_raw: bool) -> Log | None:
    """None when the file is not a clean sequence of events (the caller reads it with lcm.EventLog)."""
    data = path.read_bytes()
    buf = np.frombuffer(data, dtype=np.uint8)
    ix = _index(buf)
    if ix is None:
        return None
    by_channel = _by_channel()
    starts, utime, payload, data_len, chan_id, names = ix.starts, ix.utime, ix.payload, ix.data_len, ix.chan_id, ix.names
    found = _chain_scan(len(data), starts, ix.num)
    clean = found if isinstance(found, LogScan) else None
    if len(set(names)) != len(names):           # never with names of different lengths; kept honest
        return None
    # counts, in the order the reference reader inserts its keys (first event of each key)
    first: list[tuple[float, str, int]] = []
    per_channel: dict[str, np.ndarray] = {}
    for k, name in enumerate(names):
        idx = np.flatnonzero(chan_id == k)
        per_channel[name] = idx
        first.append((float(idx[0]), name, int(idx.size)))
    tables = {}
    for ch, codec in by_channel.items():
        idx = per_channel.get(ch, np.zeros(0, dtype=np.int64))
        ok = data_len[idx] == codec.size
        fp = np.frombuffer(codec.fingerprint, dtype=np.uint8)
        cand = idx[ok]
        if cand.size:
            fps = _rows(buf, payload[cand], 8)
            fp_ok = np.all(fps == fp, axis=1)
            ok[np.flatnonzero(ok)[~fp_ok]] = False
        bad = idx[~ok]
        if bad.size:
            first.append((float(bad[0]) + 0.5, f"{ch}.undecodable", int(bad.size)))
        use = idx[ok]
        tables[ch] = _table_fast(codec, buf, payload[use], utime[use])
    counts = {key: c for _, key, c in sorted(first)}
    markers = []
    for e in per_channel.get(wire.RUNNER, []):
        p = int(payload[e])
        try:
            markers.append(json.loads(data[p:p + int(data_len[e])].decode()))
        except (UnicodeDecodeError, json.JSONDecodeError):
            pass
    raw = None
    if keep_raw:
        raw = [(names[c], data[p:p + d], u) for c, p, d, u in
               zip(chan_id.tolist(), payload.tolist(), data_len.tolist(), utime.tolist())]
    t = tables
    return Log(path, t[wire.TRUTH], t[wire.ACTUATOR], t[wire.SENSORS], t[wire.STATUS], t[wire.COMMAND],
               markers, counts, raw, t[wire.EVENTS], clean)


def _events(log, path: Path):
    """The events of lcm.EventLog log; LogIntegrityError for one the reader cannot decode (a damaged channel
    name that is not UTF-8 text: lcm raises UnicodeDecodeError)."""
    n = 0
    while True:
        try:
            ev = next(log)
        except StopIteration:
            return
        except UnicodeDecodeError:
            raise LogIntegrityError(f"{path}: log corrupt after event {n} (a channel name that is not text)") \
                from None
        n += 1
        yield ev


def _read_eventlog(path: Path, keep_raw: bool = False) -> Log:
    """The reference reader: lcm.EventLog and one Codec.unpack per event (lcm's resynchronisation over
    damage included). read() uses it for any file that is not a clean sequence of events."""
    by_channel = _by_channel()
    rows: dict[str, list] = {c: [] for c in by_channel}
    utimes: dict[str, list] = {c: [] for c in by_channel}
    counts: dict[str, int] = {}
    markers = []
    raw = [] if keep_raw else None
    log = lcm.EventLog(str(path), "r")
    try:
        for ev in _events(log, path):
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
               markers, counts, raw, t[wire.EVENTS])


def unload_events(cmd: dict):
    """The row indices of log.cmd where an unload (a momentum dump) started: "unloading" set on a row where
    the row before (if any) had it clear."""
    on = np.asarray(cmd["unloading"]) != 0
    prev = np.concatenate(([False], on[:-1]))
    return np.flatnonzero(on & ~prev)


def covariance(p_upper) -> np.ndarray:
    """The (n, 6, 6) symmetric covariances of the estimate from actuator_cmd_t's est_p, (n, 21) (or one row of
    21): the upper triangle row by row, P00 P01 .. P05 P11 .. P55 (firmware estimate.h)."""
    p = np.asarray(p_upper, dtype=np.float64)
    one = p.ndim == 1
    p = p.reshape(-1, 21)
    i, j = np.triu_indices(6)
    out = np.zeros((p.shape[0], 6, 6))
    out[:, i, j] = p
    out[:, j, i] = p
    return out[0] if one else out


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
