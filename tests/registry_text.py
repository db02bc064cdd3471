"""The registry rows as written in the C sources, read as text (no tests here).

An independent reading of firmware/include/aocs/laws.def, firmware/gains/gain_tables.def,
firmware/include/aocs/config_fields.def and the payload rows of
firmware/pil/include/aocs/pil_frame.h, for the tests that check
the build's registry JSON (aocs_core.registry) and the Python consumers against the C.
"""
from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
LAWS_DEF = REPO / "firmware/include/aocs/laws.def"
GAIN_TABLES_DEF = REPO / "firmware/gains/gain_tables.def"
CONFIG_FIELDS_DEF = REPO / "firmware/include/aocs/config_fields.def"
CONFIG_REGISTRY_H = REPO / "firmware/include/aocs/config_registry.h"
PIL_FRAME_H = REPO / "firmware/pil/include/aocs/pil_frame.h"


def _macro_body(text: str, name: str) -> str:
    """The replacement list of `#define name(X)`, continuation lines joined, comments dropped."""
    start = text.index(f"#define {name}(X)")
    lines = []
    for line in text[start:].splitlines()[1:]:
        lines.append(line.rstrip("\\").rstrip())
        if not line.rstrip().endswith("\\"):
            break
    return re.sub(r"/\*.*?\*/", " ", " ".join(lines))


def _rows(body: str) -> list[list[str]]:
    """X(...) rows split into their top-level arguments (strings kept whole)."""
    out, i = [], 0
    while True:
        i = body.find("X(", i)
        if i < 0:
            return out
        depth, j, args, cur, in_str = 0, i + 2, [], "", False
        while True:
            c = body[j]
            if in_str:
                cur += c
                in_str = c != '"'
            elif c == '"':
                cur += c
                in_str = True
            elif c == "(":
                depth += 1
                cur += c
            elif c == ")" and depth == 0:
                args.append(cur.strip())
                break
            elif c == ")":
                depth -= 1
                cur += c
            elif c == "," and depth == 0:
                args.append(cur.strip())
                cur = ""
            else:
                cur += c
            j += 1
        out.append(args)
        i = j


def _str(x: str) -> str:
    assert x.startswith('"') and x.endswith('"'), x
    return x[1:-1]


def _num(x: str) -> int:
    return int(x.rstrip("uU"))


def law_rows() -> list[dict]:
    """AOCS_LAW_ROWS: one dict per law in row (= id) order."""
    cols = ("id", "name", "input", "title", "state", "state_type", "config", "config_type", "config_use", "init",
            "step", "variant", "vmember", "vvalue", "budget_ns", "instr_m4f", "instr_m7", "ref")
    rows = []
    for r in _rows(_macro_body(LAWS_DEF.read_text(), "AOCS_LAW_ROWS")):
        assert len(r) == len(cols), r
        d = dict(zip(cols, r))
        for k in ("name", "title", "ref"):
            d[k] = _str(d[k])
        for k in ("budget_ns", "instr_m4f", "instr_m7"):
            d[k] = _num(d[k])
        rows.append(d)
    return rows


def field_rows() -> list[dict]:
    """AOCS_LAW_FIELD_ROWS: one dict per config field in row order."""
    cols = ("name", "law", "key", "member", "type", "count", "rule", "help", "pil_id", "for", "ref")
    rows = []
    for r in _rows(_macro_body(LAWS_DEF.read_text(), "AOCS_LAW_FIELD_ROWS")):
        assert len(r) == len(cols), r
        d = dict(zip(cols, r))
        for k in ("key", "help", "ref"):
            d[k] = _str(d[k])
        for k in ("count", "pil_id"):
            d[k] = _num(d[k])
        rows.append(d)
    return rows


def _define(text: str, name: str) -> int:
    m = re.search(rf"^#define {name} (\d+)u?", text, re.M)
    assert m, name
    return int(m.group(1))


def wheel_field_rows() -> list[dict]:
    """AOCS_CONFIG_WHEEL_FIELD_ROWS of config_fields.def: one dict per per-wheel field."""
    cols = ("name", "member", "count", "rule", "index", "status", "also", "help")
    rows = []
    for r in _rows(_macro_body(CONFIG_FIELDS_DEF.read_text(), "AOCS_CONFIG_WHEEL_FIELD_ROWS")):
        d = dict(zip(cols, r))
        d["index"], d["count"], d["key"] = _num(d["index"]), _num(d["count"]), d["member"]
        rows.append(d)
    return rows


#: a general row's KIND -> (its PIL value kind, count)
_GENERAL_KIND = {"REAL": ("REAL", 1), "VEC3": ("REAL", 3), "QUAT": ("REAL", 4), "MAT3": ("REAL", 9),
                 "THR": ("REAL", 12)}


def exec_field_rows() -> list[dict]:
    """AOCS_CONFIG_FIELD_ROWS of config_fields.def (kind REAL with its count, or U64), then its per-wheel
    fields wheel by wheel (0 .. 5) as the registry lists them: WHEEL<i>_<NAME>, id AOCS_PIL_CFG_WHEEL_BASE +
    i * AOCS_PIL_WHEEL_STRIDE + index, key wheel<i>.<key>."""
    cols = ("name", "key", "member", "kind", "rule", "default", "pil_id", "status", "also", "help")
    rows = []
    for r in _rows(_macro_body(CONFIG_FIELDS_DEF.read_text(), "AOCS_CONFIG_FIELD_ROWS")):
        d = dict(zip(cols, r))
        kind, count = _GENERAL_KIND.get(d["kind"], ("U64", 1))
        rows.append({"name": d["name"], "pil_id": _num(d["pil_id"]), "kind": kind, "count": count,
                     "key": _str(d["key"])})
    text = CONFIG_REGISTRY_H.read_text()
    base, stride = _define(text, "AOCS_PIL_CFG_WHEEL_BASE"), _define(text, "AOCS_PIL_WHEEL_STRIDE")
    for i in range(6):
        for w in wheel_field_rows():
            rows.append({"name": f"WHEEL{i}_{w['name']}", "pil_id": base + i * stride + w["index"], "kind": "REAL",
                         "count": w["count"], "key": f"wheel{i}.{w['key']}"})
    return rows


def table_rows() -> list[dict]:
    """AOCS_GAIN_TABLE_ROWS of the generated gain_tables.def, in id order."""
    cols = ("id", "name", "law", "symbol")
    rows = []
    for r in _rows(_macro_body(GAIN_TABLES_DEF.read_text(), "AOCS_GAIN_TABLE_ROWS")):
        d = dict(zip(cols, r))
        d["name"] = _str(d["name"])
        rows.append(d)
    return rows


def pil_payload_rows() -> dict[str, list[dict]]:
    """AOCS_PIL_PAYLOAD_ROWS of pil_frame.h: payload name -> its rows {name, kind, member} in wire order, and
    "COUNTERS" -> the AOCS_PIL_COUNTER_ROWS; "bytes" of each payload from its AOCS_PIL_<NAME>_BYTES."""
    text = PIL_FRAME_H.read_text()
    cols = ("name", "kind", "member")
    out = {"COUNTERS": [dict(zip(cols, r)) for r in _rows(_macro_body(text, "AOCS_PIL_COUNTER_ROWS"))]}
    for name, _fn, _type, rows, _bytes in _rows(_macro_body(text, "AOCS_PIL_PAYLOAD_ROWS")):
        out[name] = [dict(zip(cols, r)) for r in _rows(_macro_body(text, rows))]
    return out
