"""aocs_core.registry: the law registry Python reads from the build, against the C sources.

The build writes registry/aocs_registry.json from the X-macro rows of
firmware/include/aocs/laws.def, status.def, firmware/gains/gain_tables.def and
pil_frame.h (tools/registry/aocs_registry_dump.c). Here every law, field, table,
status code and executive PIL field of that JSON is checked against an
independent reading of those rows as text (tests/registry_text.py), and the
wire values are pinned. tests/e2e/test_registry_c_python.py runs the C side
(fsw_node, the PIL codec) on what Python derives from it.
"""
from __future__ import annotations

import re

import pytest

import registry_text
from aocs_core import paths, registry

#: the wire values (docs/wire-contract.md "Law ids"): never change
WIRE_LAWS = ("none", "crp_linear", "quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc", "lqr_quat", "hinf",
             "mrp_sat", "mrp_sat_tanh", "orbit_lqr", "quat_pid", "lqr_quat_i")


@pytest.fixture(scope="module")
def reg() -> registry.Registry:
    return registry.load()


def test_law_ids_and_names_are_the_wire_values(reg):
    # exact on purpose (docs/extending.md): a new row of laws.def must be appended here too
    assert len(reg.law_names()) == len(WIRE_LAWS), \
        f"laws.def has {len(reg.law_names())} laws (with none), WIRE_LAWS lists {len(WIRE_LAWS)}: append the new one"
    assert reg.law_names() == WIRE_LAWS
    assert reg.law_ids() == {name: i for i, name in enumerate(reg.law_names())}
    assert registry.law_ids() == reg.law_ids() and registry.law_names() == reg.law_names()
    assert registry.law_name(4) == "quat_nlpd_pos" and registry.law_name(99) == "law 99"


def test_laws_are_the_rows_of_laws_def(reg):
    rows = registry_text.law_rows()
    assert [law.name for law in reg.laws] == [r["name"] for r in rows]
    for law, row in zip(reg.laws, rows):
        assert law.id == rows.index(row) + 1
        assert law.input == row["input"].lower()
        assert law.title == row["title"] and law.reference_scenario == row["ref"]
        assert law.config == row["config"]
        assert law.variant == (row["vvalue"] if row["variant"] == "VARIANT" else None)
        assert law.budget_ns == row["budget_ns"] > 0
        assert law.budget_instructions == {"cortex-m4f": row["instr_m4f"], "cortex-m7": row["instr_m7"]}
        # a law takes the fields of its config that are for every variant or for its own, and the
        # field of another law that its FROM_FIELD column copies in (quat_pid: the inertia)
        owners = {r["id"]: r["config"] for r in rows}
        from_field = row["vvalue"] if row["variant"] == "FROM_FIELD" else None
        assert law.from_field == from_field
        want = [f["key"] for f in registry_text.field_rows()
                if (owners[f["law"]] == law.config and f["for"] in ("ALL", row["vvalue"]))
                or f["member"] == from_field]
        assert list(law.field_keys) == want
    assert reg.none.id == 0 and reg.none.budget_ns > 0


def test_fields_are_the_rows_of_laws_def(reg):
    rows = registry_text.field_rows()
    assert [f.key for f in reg.fields] == [r["key"] for r in rows]
    names = {r["id"]: r["name"] for r in registry_text.law_rows()}
    for f, r in zip(reg.fields, rows):
        assert (f.name, f.law, f.member, f.type, f.count, f.rule, f.unit, f.pil_id, f.ref) == (
            r["name"], names[r["law"]], r["member"], r["type"].lower(), r["count"], r["rule"].lower(), r["help"],
            r["pil_id"], r["ref"])
        assert f.variant == (None if r["for"] == "ALL" else r["for"])
        assert f.param == r["member"].split(".", 1)[1]
    ids = [f.pil_id for f in reg.fields] + [x.pil_id for x in reg.exec_fields]
    assert len(ids) == len(set(ids))


def test_exec_fields_are_the_rows_of_pil_frame_h(reg):
    rows = registry_text.exec_field_rows()
    assert [(x.name, x.pil_id, x.kind, x.count, x.key or "") for x in reg.exec_fields] == [
        (r["name"], r["pil_id"], r["kind"].lower(), r["count"], r["key"]) for r in rows]
    # the executive's own fields 1..14, the slew guidance's from 60, the wheel array's from 65, the
    # estimator's 68, the MEKF's 69 .. 80, the momentum stage's 81 .. 96, fault management's 97, 98 and
    # 160 .. 175, the MEKF's gyroless model 176 .. 178, the tracker's noise adaptation 179, then the
    # per-wheel fields 100 .. 147 (8 per wheel, pil_frame.h)
    assert [x.pil_id for x in reg.exec_fields] == (list(range(1, 15)) + list(range(60, 99))
                                                   + list(range(160, 182)) + list(range(100, 148)))
    assert reg.exec_field_of_key("wheel3.coulomb_nm").pil_id == 100 + 3 * 8 + 5


def test_gain_tables_are_the_generated_registration(reg):
    rows = registry_text.table_rows()
    assert [(t.id, t.name, t.law) for t in reg.gain_tables] == [
        (i, r["name"], names_by_id(r["law"])) for i, r in enumerate(rows)]
    for law in reg.laws:
        tf = reg.table_field(law.name)
        assert bool(reg.tables_for(law.name)) == (tf is not None)
        if tf is not None:
            assert reg.gain_field_of(tf).member == tf.member and reg.gain_field_of(tf).type == "gain"


def names_by_id(law_id: str) -> str:
    return {r["id"]: r["name"] for r in registry_text.law_rows()}[law_id]


def test_status_codes_are_the_rows_of_status_def(reg):
    text = (registry_text.REPO / "firmware/include/aocs/status.def").read_text()
    rows = re.findall(r'^\s*X\((\w+), "([^"]*)"\)', text, re.M)
    assert reg.status_names == {i: f"AOCS_{n}" for i, (n, _) in enumerate(rows)}
    assert registry.status_name(0) == "AOCS_OK" and registry.status_name(999) == "status 999"
    assert registry.status_code("AOCS_ERR_UNKNOWN_LAW") == [n for n, _ in rows].index("ERR_UNKNOWN_LAW")
    with pytest.raises(KeyError):
        registry.status_code("AOCS_ERR_NO_SUCH_THING")


def test_budgets_and_modes(reg):
    assert registry.law_budget_ns("quat_nlpd_neg") == registry.law_budget_ns("quat_nlpd_pos")
    assert registry.law_budget_ns("none") == reg.none.budget_ns
    assert registry.mode_name(paths.import_bindings().actuator_cmd_t.MODE_SAFE) == "safe" and registry.mode_name(7) == "7"


def test_pil_fields_for_the_codec(reg):
    f = reg.pil_fields()
    assert f["LAW"] == (1, "u", 1) and f["TARGET_Q"] == (3, "f", 4)
    assert f["INERTIA"] == (15, "f", 9) and f["HINF_TABLE"] == (28, "s", 0) and f["ORBIT_K"] == (36, "f", 18)


def test_a_missing_registry_says_how_to_build_it(monkeypatch, tmp_path):
    monkeypatch.setenv("AOCS_BUILD_DIR", str(tmp_path))
    with pytest.raises(paths.SetupError, match="aocs_registry.json is missing; build it first"):
        registry.load()


def test_estimators_are_the_rows_of_determination_def(reg):
    """The determination rows (their budgets, for the run's timing) are the names the key `estimator` takes,
    in the same order: two expansions of the firmware that must agree; passthrough costs nothing."""
    assert tuple(reg.estimators) == reg.config_field("estimator").names
    assert reg.estimators["passthrough"] == (0, {"cortex-m4f": 0, "cortex-m7": 0})
    for name, (ns, instr) in reg.estimators.items():
        assert ns >= 0 and set(instr) == {"cortex-m4f", "cortex-m7"}, name
