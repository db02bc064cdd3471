"""C and Python agree on every law, field and gain table of the registry: the C runs on what
Python derives from the build's registry JSON (aocs_core.registry).

- every law: fsw_node (the C parser and aocs_exec_init) accepts the configuration made of
  the law's registry fields with their reference values, and the CONFIG payload the bridge
  makes of it (aocs_pil.config: the same parser) decodes to those values;
- every law on its reference scenario: the configuration the runner writes
  (aocs_flightcfg.fsw_config, keys derived from the registry and the scenario schema) is
  accepted by fsw_node;
- every PIL CONFIG field: encoded by the Python codec (aocs_pil.frame, ids from the
  registry), decoded by the C codec (aocs_pil_config_decode, through the test hook
  `aocs_registry_dump --pil-decode`) into the member the registry names, bit for bit;
  every gain table by name into its law's gain.
The laws are parametrised from laws.def as text (tests/registry_text.py), so a row the JSON
lost would fail here too.
"""
from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

import registry_text
from aocs_core import registry
from aocs_flightcfg import fsw_config
from aocs_pil import config as nodecfg
from aocs_pil import frame
from aocs_plant.scenario import load

LAWS = [r["name"] for r in registry_text.law_rows()]
#: general keys of a minimal valid configuration (the law's fields are added); no network
BASE = {"control_period_s": "0.1", "u_max_axis": "1 1 1", "idle_timeout_s": "0.2", "status_period_s": "0.05",
        "lcm_url": "memq://"}


@pytest.fixture(scope="module")
def dump_bin(aocs_build_dir) -> Path:
    exe = aocs_build_dir / "bin" / "aocs_registry_dump"
    if not (exe.is_file() and os.access(exe, os.X_OK)):
        pytest.fail(f"aocs_registry_dump not found at {exe}; build it first (make build-host)")
    return exe


def reference_config(law: str) -> dict[str, str]:
    cfg = {"law": law, **BASE}
    for f in registry.load().fields_of(law):
        if f.ref:
            cfg[f.key] = f.ref
    return cfg


def write(path: Path, cfg: dict[str, str]) -> Path:
    path.write_text("".join(f"{k} = {v}\n" for k, v in cfg.items()))
    return path


def run_node(fsw_node_bin, path: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(fsw_node_bin), str(path)], capture_output=True, text=True, timeout=20)


def decode(dump_bin, payload: bytes, tmp_path: Path) -> dict:
    p = tmp_path / "config.bin"
    p.write_bytes(payload)
    res = subprocess.run([str(dump_bin), "--pil-decode", str(p)], capture_output=True, text=True, timeout=20)
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout)


def numbers(text: str) -> list[float]:
    return [float(x) for x in text.replace(",", " ").split()]


@pytest.mark.parametrize("law", LAWS)
def test_fsw_node_and_the_bridge_accept_the_reference_configuration(law, fsw_node_bin, dump_bin, tmp_path):
    cfg = reference_config(law)
    path = write(tmp_path / f"{law}.cfg", cfg)
    res = run_node(fsw_node_bin, path)
    assert res.returncode == 0, res.stderr
    assert f"law {law}, period" in res.stderr
    # the bridge reads the same file (fsw_node's parser), and the image's decoder takes its CONFIG payload
    parsed = nodecfg.load(path)
    assert parsed.law == law
    out = decode(dump_bin, parsed.pil_payload(168e6), tmp_path)
    assert (out["pil_err"], out["status"]) == ("AOCS_PIL_OK", "AOCS_OK"), out
    v = out["values"]
    assert v["LAW"] == [registry.law_ids()[law]] and v["PERIOD_S"] == [0.1] and v["U_MAX_AXIS"] == [1.0] * 3
    for f in registry.load().fields_of(law):
        if not f.ref:
            continue
        if f.type == "table":
            assert any(x != 0.0 for x in v[f.name]), f.key     # the compiled table reached the gain
        elif f.type == "mat3":
            d = numbers(f.ref)
            assert v[f.name] == ([d[0], 0, 0, 0, d[1], 0, 0, 0, d[2]] if len(d) == 3 else d), f.key
        else:
            assert v[f.name] == numbers(f.ref), f.key


@pytest.mark.parametrize("law", LAWS)
def test_the_runners_configuration_of_the_reference_scenario_is_accepted(law, fsw_node_bin, tmp_path):
    reg = registry.load()
    sc = load(reg.law(law).reference_scenario)
    assert law in sc.control.laws, f"{law}: its reference scenario {sc.path} does not configure it"
    cfg = fsw_config.node_config(sc, law, idle_timeout_s=0.2, lcm_url="memq://")
    for f in reg.fields_of(law):
        assert f.key in cfg or f.type == "gain", f.key            # every field the law takes is written
    path = fsw_config.write(tmp_path / f"{law}.cfg", cfg)
    res = run_node(fsw_node_bin, path)
    assert res.returncode == 0, res.stderr
    assert nodecfg.load(path).law == law


def test_every_pil_field_reaches_its_member(dump_bin, tmp_path):
    reg = registry.load()
    # every field once, in as few CONFIG payloads as fit AOCS_PIL_PAYLOAD_MAX (all of them no longer
    # fit one since the 3x9 gain of lqr_quat_i): each payload decoded on its own
    groups: list[dict] = [{}]
    for i, f in enumerate(x for x in reg.fields if x.type != "table"):
        vals = [float(10 * i + k + 1) + 0.25 for k in range(f.count)]
        trial = frame.ConfigFields(list(groups[-1].items()) + [(f.name, vals)])
        try:
            trial.encode()
        except ValueError:
            groups.append({})
        groups[-1][f.name] = vals
    assert sum(len(g) for g in groups) == sum(1 for x in reg.fields if x.type != "table")
    for n, expect in enumerate(groups):
        (tmp_path / str(n)).mkdir()
        out = decode(dump_bin, frame.ConfigFields(list(expect.items())).encode(), tmp_path / str(n))
        assert (out["pil_err"], out["status"]) == ("AOCS_PIL_OK", "AOCS_OK"), out
        for name, vals in expect.items():
            assert out["values"][name] == vals, name


@pytest.mark.parametrize("table", [r["name"] for r in registry_text.table_rows()])
def test_every_gain_table_goes_to_its_law_by_name(table, dump_bin, tmp_path):
    reg = registry.load()
    t = reg.table(table)
    tf = reg.table_field(t.law)
    out = decode(dump_bin, frame.ConfigFields([(tf.name, table)]).encode(), tmp_path)
    assert (out["pil_err"], out["status"]) == ("AOCS_PIL_OK", "AOCS_OK"), out
    assert any(x != 0.0 for x in out["values"][reg.gain_field_of(tf).name])
    # and a table of another law is refused with the field's id
    other = next((x for x in reg.fields if x.type == "table" and x.law != t.law), None)
    if other is not None:
        out = decode(dump_bin, frame.ConfigFields([(other.name, table)]).encode(), tmp_path)
        assert (out["pil_err"], out["field"], out["status"]) == (
            "AOCS_PIL_ERR_FIELD", other.pil_id, "AOCS_ERR_GAIN_TABLE_WRONG_LAW"), out


def test_an_unknown_field_id_is_refused(dump_bin, tmp_path):
    used = {v[0] for v in frame.cfg_fields().values()}
    free = next(i for i in range(1, 255) if i not in used)
    out = decode(dump_bin, bytes([free, 1]) + bytes(8), tmp_path)
    assert (out["pil_err"], out["field"]) == ("AOCS_PIL_ERR_FIELD", free)


GAIN_FIELDS = [f for f in registry.load().fields if f.type == "gain"]


@pytest.mark.parametrize("field", GAIN_FIELDS, ids=[f.key for f in GAIN_FIELDS])
def test_an_explicit_gain_of_every_size_is_taken_and_one_value_more_refused(field, fsw_node_bin, tmp_path):
    """A gain given by value (what `aocs run` writes for a K designed at run start: lqr_quat_i.k has 27
    numbers) is read whole; fsw_node once read every list into an 18-number buffer and overran its stack
    with a 3x9 gain. One number more than the field takes is a one-line refusal, never a crash."""
    cfg = {k: v for k, v in reference_config(field.law).items() if k != field.key.rsplit(".", 1)[0] + ".table"}
    cols = field.count // 3
    # a positive diagonal in every 3x3 block (each state group: integral, attitude, rate) passes the checks
    k = [(1.0 + r) if c % 3 == r else 0.0 for r in range(3) for c in range(cols)]
    cfg[field.key] = " ".join(repr(x) for x in k)
    res = run_node(fsw_node_bin, write(tmp_path / "k.cfg", cfg))
    assert res.returncode == 0, res.stderr
    cfg[field.key] += " 1.0"
    res = run_node(fsw_node_bin, write(tmp_path / "k1.cfg", cfg))
    assert res.returncode == 2 and res.returncode > 0, res.stderr
    assert field.key in res.stderr and len(res.stderr.strip().splitlines()) == 1, res.stderr
