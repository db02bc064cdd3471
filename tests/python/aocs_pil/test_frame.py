"""The host side of the PIL link, without an emulator.

- the Python frame codec (sil/aocs_pil/frame.py) against the C header
  (constants, enums, payload sizes) and the golden vectors that
  tests/unit/test_pil_frame.c also checks against the C codec;
- every fixed payload layout: the registry JSON's rows against pil_frame.h's as text,
  and each payload encoded here, decoded by the C codec (the test hook
  `aocs_registry_dump --pil-payload`), every row found by name with the values Python
  put there, and encoded back by C to Python's bytes;
- the configuration the bridge flies: read by fsw_node's parser (the
  aocs_node_config tool behind sil/aocs_pil/config.py), encoded as the
  CONFIG payload in the file's order, and for a list of broken files the same
  message as fsw_node; the registry's JSON rows against the C rows.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import struct
import subprocess
import zlib

import pytest

import registry_text
from aocs_core import registry
from aocs_pil import config as nodecfg
from aocs_pil import frame
from aocs_wire import netns
from pil_support import REPO

HEADER = (REPO / "firmware/pil/include/aocs/pil_frame.h").read_text()
#: the configuration registry's header: the CONFIG field ids and limits pil_frame.h takes from it
CONFIG_HEADER = (REPO / "firmware/include/aocs/config_registry.h").read_text()

GOLDEN_BYE = bytes([0x41, 0x50, 0x49, 0x4C, 0x05, 0x08, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x17, 0x44, 0x7C,
                    0x14])
GOLDEN_HELLO = bytes([0x41, 0x50, 0x49, 0x4C, 0x05, 0x01, 0x1C, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00,
                      0x00, 0x08, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0xD0, 0x07,
                      0x00, 0x00, 0xD0, 0x07, 0x00, 0x00, 0x2F, 0x00, 0x00, 0x00, 0xE6, 0x9F, 0x3A, 0x44])


def c_define(name: str) -> int:
    m = re.search(rf"^#define {name} \(?(0x[0-9A-Fa-f]+|\d+)[uU]?L?\)?", HEADER + CONFIG_HEADER, re.M)
    assert m, f"{name} not found in pil_frame.h or config_registry.h"
    return int(m.group(1), 0)


def c_enum(typedef: str) -> dict[str, int]:
    body = HEADER[:HEADER.index(f"}} {typedef};")]
    body = body[body.rindex("typedef enum {"):]
    return {k: int(v) for k, v in re.findall(r"^\s*(AOCS_PIL_\w+) = (\d+)", body, re.M)}


def test_constants_and_enums_match_the_c_header():
    assert frame.MAGIC == c_define("AOCS_PIL_MAGIC")
    assert frame.MAGIC.to_bytes(4, "little") == b"APIL"
    assert frame.VERSION == c_define("AOCS_PIL_VERSION")
    assert frame.HEADER_BYTES == c_define("AOCS_PIL_HEADER_BYTES")
    assert frame.CRC_BYTES == c_define("AOCS_PIL_CRC_BYTES")
    assert frame.PAYLOAD_MAX == c_define("AOCS_PIL_PAYLOAD_MAX")
    assert frame.ICOUNT_SHIFT == c_define("AOCS_PIL_ICOUNT_SHIFT")
    assert frame.TABLE_NAME_MAX == c_define("AOCS_CONFIG_TABLE_NAME_MAX")
    assert (frame.TARGET_HOST, frame.TARGET_CORTEX_M4F, frame.TARGET_CORTEX_M7) == (
        c_define("AOCS_PIL_TARGET_HOST"), c_define("AOCS_PIL_TARGET_CORTEX_M4F"), c_define("AOCS_PIL_TARGET_CORTEX_M7"))
    sizes = {"HELLO": frame.HELLO, "STEP": frame.STEP, "STEP_REPLY": frame.STEP_REPLY, "SELECT": frame.SELECT,
             "ACK": frame.ACK, "BYE_REPLY": frame.BYE_REPLY, "ERROR": frame.ERROR}
    for name, st in sizes.items():
        assert st.size == c_define(f"AOCS_PIL_{name}_BYTES"), name
    types = c_enum("aocs_pil_type_t")
    assert {f"AOCS_PIL_T_{v}": k for k, v in frame.TYPE_NAMES.items()} == types
    errs = c_enum("aocs_pil_err_t")
    assert errs == {name: i for i, name in enumerate(frame.ERR_NAMES)}
    # the CONFIG fields: the general and per-wheel rows of config_fields.def and the law fields of laws.def, as the C
    # sources write them, against what the Python codec encodes (read from the build's registry)
    kinds = {"REAL": "f", "U64": "u"}
    want = {x["name"]: (x["pil_id"], kinds[x["kind"]], x["count"]) for x in registry_text.exec_field_rows()}
    want |= {f["name"]: (f["pil_id"], "s", 0) if f["type"] == "TABLE" else (f["pil_id"], "f", f["count"])
             for f in registry_text.field_rows()}
    assert frame.cfg_fields() == want


# ---- the fixed payloads: one layout, the rows of pil_frame.h, on both sides ------------------------
PAYLOADS = sorted(registry.load().pil_payloads)


def test_the_payload_rows_of_the_registry_are_the_rows_of_pil_frame_h():
    reg = registry.load()
    rows = registry_text.pil_payload_rows()
    assert sorted(rows) == sorted([*PAYLOADS, "COUNTERS"])
    for name, layout in reg.pil_payloads.items():
        assert [(f.name, f.kind, f.member) for f in layout.fields] == [
            (r["name"], r["kind"], r["member"]) for r in rows[name]], name
        assert layout.bytes == c_define(f"AOCS_PIL_{name}_BYTES") == frame.STRUCTS[name].size, name
    assert [(f.name, f.kind, f.member) for f in reg.pil_counters] == [
        (r["name"], r["kind"], r["member"]) for r in rows["COUNTERS"]]
    assert frame.COUNTER_NAMES == tuple(r["name"] for r in rows["COUNTERS"])


@pytest.fixture(scope="module")
def dump_bin(aocs_build_dir):
    exe = aocs_build_dir / "bin" / "aocs_registry_dump"
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        pytest.fail(f"aocs_registry_dump not found at {exe}; build it first (make build-host)")
    return exe


def sample(f, i: int) -> list:
    """Values for row i that no other row has: exact in binary32 too, negative for an i32, high bits set for the
    unsigned ones (a swapped, shifted, truncated or sign-lost field cannot pass)."""
    base = 100 * (i + 1)
    return [{"f64": -1000.0 + (base + j) / 8, "i32": -(base + j), "u64": (0xA5 << 56) + base + j,
             "u32": 0x80000000 + base + j}[f.wire] for j in range(f.count)]


@pytest.mark.parametrize("name", PAYLOADS)
def test_the_c_codec_reads_every_row_where_python_writes_it(name, dump_bin, tmp_path):
    """Encoded by Python from the registry's rows, decoded by the C codec from pil_frame.h's rows: every row by
    name with Python's values, and the C encoder gives Python's bytes back. Fails if the two disagree on any
    field's name, order, kind or count."""
    layout = registry.load().pil_payloads[name]
    flat = {f.name: sample(f, i) for i, f in enumerate(layout.fields)}
    values = {f.name: dict(zip(frame.COUNTER_NAMES, flat[f.name])) if f.kind == "counters"
              else tuple(flat[f.name]) if f.count > 1 else flat[f.name][0] for f in layout.fields}
    payload = frame.pack(name, values)
    assert frame.unpack(name, payload) == values
    path = tmp_path / f"{name}.bin"
    path.write_bytes(payload)
    res = subprocess.run([str(dump_bin), "--pil-payload", name, str(path)], capture_output=True, text=True,
                         timeout=20)
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["pil_err"] == "AOCS_PIL_OK"
    assert list(out["fields"]) == [f.name for f in layout.fields]
    assert out["fields"] == flat
    assert bytes.fromhex(out["encoded"]) == payload
    # one byte short or long: the C decoder refuses, as Python does
    path.write_bytes(payload[:-1])
    res = subprocess.run([str(dump_bin), "--pil-payload", name, str(path)], capture_output=True, text=True,
                         timeout=20)
    assert json.loads(res.stdout)["pil_err"] == "AOCS_PIL_ERR_PAYLOAD"
    with pytest.raises(frame.FrameError, match=f"{name} payload of {len(payload) + 1} bytes"):
        frame.unpack(name, payload + b"\0")


def test_the_payload_classes_are_the_rows():
    """Hello, StepReply, Ack, Bye, Error: one attribute per row, in row order, and back to the same bytes."""
    reg = registry.load()
    for cls, name in ((frame.Hello, "HELLO"), (frame.StepReply, "STEP_REPLY"), (frame.Ack, "ACK"),
                      (frame.Bye, "BYE_REPLY"), (frame.Error, "ERROR")):
        assert list(cls.__dataclass_fields__) == [f.name for f in reg.pil_payloads[name].fields]
        payload = bytes(i % 251 for i in range(frame.STRUCTS[name].size))
        assert cls.decode(payload).encode() == payload
    r = frame.StepReply.decode(bytes(frame.STEP_REPLY.size))
    assert r.counters == dict.fromkeys(frame.COUNTER_NAMES, 0) and r.u_wheels == (0.0,) * frame.WHEELS_MAX
    assert frame.encode_select(3) == frame.SELECT.pack(3, 0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="STEP q: 3 values, 4 expected"):
        frame.encode_step(1, 2, 3, (0.0, 0.0, 1.0), (0, 0, 0), (0, 0, 0), (0, 0, 0))


def test_golden_frames_byte_for_byte():
    # the same vectors as tests/unit/test_pil_frame.c (header by hand, CRC from zlib)
    assert frame.encode(frame.T_BYE, 7) == GOLDEN_BYE
    hello = frame.Hello(2, 8, 7, 1, 2000, 2000, 47)
    assert frame.encode(frame.T_HELLO, 0, hello.encode()) == GOLDEN_HELLO
    h, payload = frame.check_frame(GOLDEN_HELLO)
    assert (h.type, h.length, h.seq) == (frame.T_HELLO, 28, 0)
    assert frame.Hello.decode(payload) == hello
    assert frame.crc32(b"123456789") == 0xCBF43926
    assert struct.unpack("<I", GOLDEN_BYE[-4:])[0] == zlib.crc32(GOLDEN_BYE[:-4])


def test_step_payload_layout():
    p = frame.encode_step(0x01020304, 0x1122334455667788, 3, (1.0, -2.0, 0.5, 0.0), (0.25, -0.125, 4.0),
                          (1.0, 2.0, 3.0), (-1.0, -2.0, -3.0))
    assert len(p) == 256
    assert p[:4] == bytes([4, 3, 2, 1])
    assert struct.unpack_from("<Q", p, 4)[0] == 0x1122334455667788
    assert p[12] == 3
    assert struct.unpack_from("<Q", p, 16)[0] == 0x3FF0000000000000
    assert struct.unpack_from("<Q", p, 24)[0] == 0xC000000000000000
    assert struct.unpack_from("<Q", p, 112)[0] == 0xC008000000000000
    # the six tachometers after vel (tests/unit/test_pil_frame.c: -300.5 at byte 120); unmeasured: NaN
    assert all(math.isnan(x) for x in struct.unpack_from("<6d", p, 120))
    p = frame.encode_step(1, 2, 3, (0.0, 0.0, 0.0, 1.0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (-300.5, 10.0))
    assert struct.unpack_from("<Q", p, 120)[0] == 0xC072C80000000000
    assert struct.unpack_from("<d", p, 128)[0] == 10.0 and math.isnan(struct.unpack_from("<d", p, 136)[0])
    with pytest.raises(ValueError):
        frame.encode_step(1, 2, 3, (0.0, 0.0, 0.0, 1.0), (0, 0, 0), (0, 0, 0), (0, 0, 0), (1.0,) * 7)
    # version 3: the star tracker's sample and time of measurement, the gyro's rate, after the tachometers
    # (tests/unit/test_pil_frame.c: st_q[0] at byte 168, st_t_meas_ns at 200, gyro_w[0] at 208)
    p = frame.encode_step(1, 2, 3, (0.0, 0.0, 0.0, 1.0), (0, 0, 0), (0, 0, 0), (0, 0, 0), st_q=(0.5, -0.5, 0.5, -0.5),
                          st_t_meas_ns=0x8877665544332211, gyro_w=(0.0078125, -0.25, 1.0))
    assert struct.unpack_from("<Q", p, 168)[0] == 0x3FE0000000000000
    assert struct.unpack_from("<Q", p, 192)[0] == 0xBFE0000000000000
    assert struct.unpack_from("<Q", p, 200)[0] == 0x8877665544332211
    assert struct.unpack_from("<Q", p, 208)[0] == 0x3F80000000000000
    assert frame.unpack("STEP", p)["gyro_w"] == (0.0078125, -0.25, 1.0)
    # without them: the identity, time 0 (no time), zero rate
    d = frame.unpack("STEP", frame.encode_step(1, 2, 3, (0.0, 0.0, 0.0, 1.0), (0, 0, 0), (0, 0, 0), (0, 0, 0)))
    assert (d["st_q"], d["st_t_meas_ns"], d["gyro_w"]) == ((0.0, 0.0, 0.0, 1.0), 0, (0.0, 0.0, 0.0))


def test_step_reply_layout_of_the_estimate():
    """The estimate follows the 244 bytes of the version 2 reply (tests/unit/test_pil_frame.c checks the same
    offsets on the C encoder)."""
    r = dataclasses.replace(frame.StepReply.decode(bytes(frame.STEP_REPLY.size)), estimator=1, est_status=-4,
                            q_est=(0.0, 0.0, -0.75, 0.5), est_p=tuple(0.0625 * (i + 1) for i in range(21)),
                            st_status=-7, n_st_used=0x80000001, n_est_restarts=4)
    p = r.encode()
    assert len(p) == 736
    assert struct.unpack_from("<I", p, 244)[0] == 1 and struct.unpack_from("<i", p, 248)[0] == -4
    assert struct.unpack_from("<Q", p, 268)[0] == 0xBFE8000000000000
    assert struct.unpack_from("<Q", p, 332)[0] == 0x3FB0000000000000
    assert struct.unpack_from("<i", p, 500)[0] == -7 and struct.unpack_from("<I", p, 504)[0] == 0x80000001
    assert struct.unpack_from("<I", p, 516)[0] == 4
    assert frame.StepReply.decode(p) == r


@pytest.mark.parametrize("mutate, fragment", [
    (lambda b: b"X" + b[1:], "bad magic"),
    (lambda b: b[:4] + b"\x01" + b[5:], "protocol version 1"),
    (lambda b: b[:6] + b"\x01\x04" + b[8:], "payload length 1025"),
    (lambda b: b[:-1] + bytes([b[-1] ^ 0x80]), "CRC mismatch"),
    (lambda b: b[:-1], "frame of 15 bytes"),
])
def test_every_check_names_what_failed(mutate, fragment):
    with pytest.raises(frame.FrameError, match=fragment):
        frame.check_frame(mutate(GOLDEN_BYE))


def test_every_single_bit_flip_is_detected():
    for i in range(len(GOLDEN_HELLO) * 8):
        bad = bytearray(GOLDEN_HELLO)
        bad[i // 8] ^= 1 << (i % 8)
        with pytest.raises(frame.FrameError):
            frame.check_frame(bytes(bad))


def test_config_field_list_encoding():
    cf = frame.ConfigFields()
    cf.add("LAW", 2)
    cf.add("U_MAX_AXIS", [0.5, 0.6, 0.7])
    cf.add("HINF_TABLE", "hinf_min")
    raw = cf.encode()
    assert raw[:2] == bytes([1, 1]) and struct.unpack_from("<Q", raw, 2)[0] == 2
    assert raw[10:12] == bytes([8, 3]) and struct.unpack_from("<3d", raw, 12) == (0.5, 0.6, 0.7)
    assert raw[36:] == bytes([28, 8]) + b"hinf_min"
    with pytest.raises(ValueError):
        frame.ConfigFields([("U_MAX_AXIS", [1.0, 2.0])]).encode()
    with pytest.raises(ValueError):
        frame.ConfigFields([("HINF_TABLE", "x" * 32)]).encode()


# ---- the bridge reads a configuration with fsw_node's parser --------------------------------
def config_entries(payload: bytes) -> dict:
    """A CONFIG payload's entries, decoded here by hand from the layout of pil_frame.h (an independent
    reader): field id -> values (a name for a gain-table entry)."""
    by_id = {v[0]: (k, v[1]) for k, v in frame.cfg_fields().items()}
    out, i = {}, 0
    while i < len(payload):
        fid, count = payload[i], payload[i + 1]
        i += 2
        name, kind = by_id[fid]
        if kind == "s":
            out[name] = payload[i:i + count].decode()
            i += count
        elif kind == "u":
            out[name] = struct.unpack_from("<Q", payload, i)[0]
            i += 8
        else:
            vals = list(struct.unpack_from(f"<{count}d", payload, i))
            out[name] = vals if count > 1 else vals[0]
            i += 8 * count
    return out


def test_config_fields_of_the_registry_are_the_rows_of_the_def_files():
    """The build's registry JSON (how Python learns every key) against the rows as the C sources write them."""
    reg = registry.load()
    general = [x for x in reg.config_fields if not x.per_wheel and x.law is None]
    rows = registry_text.exec_field_rows()
    assert [(x.pil_name, x.pil_id, x.key) for x in general] == [
        (r["name"], r["pil_id"], r["key"]) for r in rows if not r["name"].startswith("WHEEL") or r["name"].startswith("WHEELS_")]
    wheel = [x for x in reg.config_fields if x.per_wheel]
    assert [(x.pil_name, x.key, x.count, x.rule) for x in wheel] == [
        (w["name"], w["key"], w["count"], w["rule"].lower()) for w in registry_text.wheel_field_rows()]
    laws = [x for x in reg.config_fields if x.law is not None]
    assert [(x.key, x.pil_id, x.rule, x.help) for x in laws] == [
        (f["key"], f["pil_id"], f["rule"].lower(), f["help"]) for f in registry_text.field_rows()]
    assert {x.pil_name: x.names for x in general if x.kind == "enum"} == {
        "GUIDANCE_MODE": ("step", "slew"), "GUIDANCE_PROFILE": ("bang_coast_bang", "jerk_limited"),
        "ESTIMATOR": ("passthrough", "mekf"), "MEKF_INIT_MODE": ("first_star_tracker", "configured"),
        "MOM_POLICY": ("none", "magnetorquers", "thrusters"),
        "MOM_TRIGGER": ("threshold", "continuous")}


def test_law_and_gain_table_names_are_the_firmware_ones():
    """The laws and, per `<law>.table` key, the gain tables the registry names are the C's."""
    reg = registry.load()
    assert reg.law_names() == ("none",) + tuple(r["name"] for r in registry_text.law_rows())
    tables = registry_text.table_rows()
    for key in (k for k in reg.config_fields if k.kind == "table"):
        assert reg.tables_for(key.law) == tuple(t["name"] for t in tables if t["law"].lower() == key.law)


def test_values_reach_the_field_list(tmp_path):
    p = tmp_path / "ok.cfg"
    p.write_text("law = smc  # comment\nmode = lockstep\ncontrol_period_s = 0x1.999999999999ap-4\n"
                 "u_max_axis = 0.5, 0.6 ,0.7\ninertia = 1 2 3\nsmc.lambda = 1 1 1\nbudget_ns = 5000\n"
                 "lqr_quat.table = lqr_quat_strong\nrecover_good_samples = 4\nwheels.count = 4\n"
                 "wheel3.js_kgm2 = 0.25\nguidance.mode = slew\n")
    cfg = nodecfg.load(p)
    assert cfg.law == "smc" and cfg.period_s == 0.1 and cfg.n_wheels == 4 and cfg.guidance_mode == "slew"
    assert cfg.stale_timeout_ns == 200_000_000           # 2 periods, as node_config.c
    assert cfg.lines["wheel3.js_kgm2"] == 11 and cfg.lines["law"] == 1
    payload = cfg.pil_payload(168e6)
    fields = config_entries(payload)
    assert fields["LAW"] == 5 and fields["PERIOD_S"] == 0.1
    assert fields["U_MAX_AXIS"] == [0.5, 0.6, 0.7]
    assert fields["INERTIA"] == [1.0, 0, 0, 0, 2.0, 0, 0, 0, 3.0]
    assert fields["BUDGET_INSTR"] == 840                   # 5000 ns at 168 MHz
    assert fields["LQR_QUAT_TABLE"] == "lqr_quat_strong"
    assert fields["RECOVER_GOOD_SAMPLES"] == 4
    assert fields["WHEEL3_JS"] == 0.25 and fields["GUIDANCE_MODE"] == 1
    assert fields["STALE_TIMEOUT_NS"] == 200_000_000
    assert "lcm_url" not in fields and "MODE" not in fields
    # in the file's order, the stale timeout last
    assert list(fields)[:3] == ["LAW", "PERIOD_S", "U_MAX_AXIS"] and list(fields)[-1] == "STALE_TIMEOUT_NS"


def test_the_hint_names_the_rows_of_the_status():
    hint = nodecfg.status_hint("AOCS_ERR_GUIDANCE_JERK_TIME_INVALID", "quat_pd")
    assert hint.startswith("guidance.jerk_time_s (s, ramp time")
    assert "wheel<i>.omega_max_radps" in nodecfg.status_hint("AOCS_ERR_WHEEL_FRICTION_EXCEEDS_LIMIT", "quat_pd")
    assert nodecfg.status_hint("AOCS_ERR_GAIN_TABLE_INVALID", "hinf") == "hinf.k / hinf.table"
    assert nodecfg.status_hint("AOCS_OK", "quat_pd") == "the keys of the selected law"


BAD_CONFIGS = {
    "unknown_key": "law = quat_pd\nquat_pd.kq = 1\n",
    "twice": "law = quat_pd\nlaw = smc\n",
    "no_equals": "law quat_pd\n",
    "bad_token": "u_max_axis = 1 x 3\n",
    "underscore": "u_max_norm = 1_000\n",             # Python float() would take it, strtod does not
    "trailing_junk": "u_max_norm = 1.5abc\n",
    "hex_ok_then_error": "u_max_norm = 0x1p-2\nk_safe = 0\n",   # the hex float is fine: error on line 2
    "underflow": "u_max_norm = 1e-400\n",
    "overflow": "u_max_norm = 1e400\n",
    "infinity": "k_safe = inf\n",
    "nan": "k_safe = nan\n",
    "too_many": "target_w = 1 2 3 4\n",
    "too_few": "target_q = 0 0 1\n",
    "negative_gain": "quat_pd.kp = -4000.5\n",
    "negative_limit": "u_max_norm = -1e-7\n",
    "not_whole": "recover_good_samples = 2.5\n",
    "u32_range": "missing_max_periods = 5e9\n",
    "u64_not_whole": "budget_ns = 1.5\n",
    "stale_range": "stale_timeout_s = 2e9\n",
    "law": "law = quat_pdi\n",
    "mode": "mode = fast\n",
    "url": "lcm_url = " + "u" * 256 + "\n",
    "inertia_count": "inertia = 1 2 3 4\n",
    "empty": "k_safe =\n",
    "table_unknown": "hinf.table = hinf_best\n",
    "table_family": "orbit_lqr.table = lqr_quat_ref\n",
    "table_and_k": "lqr_quat.table = lqr_quat_ref\n" + "lqr_quat.k = " + " ".join(["1"] * 18) + "\n",
    "long_line": "# " + "x" * 1030 + "\n",
    # the node's timeout ranges (node_checks.h), which the bridge applies too (issue 11)
    "idle_range": "law = none\nu_max_norm = 1\nidle_timeout_s = 2e10\n",
    "idle_tiny": "law = none\nu_max_norm = 1\nidle_timeout_s = 1e-10\n",
    "run_range": "law = none\nu_max_norm = 1\nrun_timeout_s = 1e300\n",
    "status_range": "law = none\nu_max_norm = 1\nstatus_period_s = 1e-5\n",
}


@pytest.mark.parametrize("name", sorted(BAD_CONFIGS))
def test_config_errors_are_fsw_nodes(name, tmp_path, fsw_node_bin):
    path = tmp_path / f"{name}.cfg"
    path.write_text(BAD_CONFIGS[name])
    with pytest.raises(nodecfg.ConfigError) as exc:
        nodecfg.load(path)
    # fsw_node stops at the configuration, before opening LCM; run it isolated all the same
    res = subprocess.run(netns.wrap([str(fsw_node_bin), str(path)]), capture_output=True, text=True, timeout=10)
    assert res.returncode == 2, res.stderr
    assert res.stderr.strip() == f"fsw_node: config error: {exc.value}"


def test_version_4_layout_of_the_magnetometer_and_the_momentum_stage():
    """The magnetometer follows the 232 bytes of the version 3 STEP, the momentum stage the 520 bytes of the version
    3 reply (tests/unit/test_pil_frame.c checks the same offsets on the C encoder)."""
    p = frame.encode_step(1, 2, 3, (0.0, 0.0, 0.0, 1.0), (0, 0, 0), (0, 0, 0), (0, 0, 0),
                          mag_b_t=(0.0009765625, -0.5, 1.0))
    assert struct.unpack_from("<Q", p, 232)[0] == 0x3F50000000000000
    assert struct.unpack_from("<Q", p, 240)[0] == 0xBFE0000000000000
    assert frame.unpack("STEP", p)["mag_b_t"] == (0.0009765625, -0.5, 1.0)
    r = dataclasses.replace(frame.StepReply.decode(bytes(frame.STEP_REPLY.size)), mom_policy=2, mom_status=-3,
                            n_thrusters=12, thruster_on_s=tuple(0.0078125 * (i + 1) for i in range(12)),
                            dipole_am2=(1.5, -2.5, 0.25), u_unload=(-0.125, 0.0, 0.5), h_wheels=(10.0, -2.0, 0.5),
                            dh=(9.0, -2.0, 0.5), unloading=1, n_unload_events=0x80000003,
                            thruster_latch_closed=2)
    p = r.encode()
    assert struct.unpack_from("<I", p, 520)[0] == 2 and struct.unpack_from("<i", p, 524)[0] == -3
    assert struct.unpack_from("<I", p, 528)[0] == 12
    assert struct.unpack_from("<Q", p, 532)[0] == 0x3F80000000000000
    assert struct.unpack_from("<Q", p, 628)[0] == 0x3FF8000000000000
    assert struct.unpack_from("<Q", p, 652)[0] == 0xBFC0000000000000
    assert struct.unpack_from("<Q", p, 676)[0] == 0x4024000000000000
    assert struct.unpack_from("<Q", p, 700)[0] == 0x4022000000000000
    assert struct.unpack_from("<I", p, 724)[0] == 1 and struct.unpack_from("<I", p, 728)[0] == 0x80000003
    assert struct.unpack_from("<I", p, 732)[0] == 2 and len(p) == 736   # version 5: the latch valves, last
    assert frame.StepReply.decode(p) == r
