"""Firmware facts aocs_core.paths reads from the build and the headers.

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import json

from aocs_core import paths


def test_law_ids_follow_the_executive_enum_and_law_table():
    """The ids are the row order of the law registry (laws.def), as the build's registry JSON lists them."""
    reg = json.loads((paths.build_dir() / "registry" / "aocs_registry.json").read_text())
    names = [reg["none"]["name"]] + [law["name"] for law in reg["laws"]]
    assert [reg["none"]["id"]] + [law["id"] for law in reg["laws"]] == list(range(len(names)))
    assert names == list(paths.LAW_IDS)
    assert [paths.LAW_IDS[n] for n in names] == list(range(len(names)))


def test_budgets_and_status_names_come_from_the_headers():
    for law in paths.LAW_IDS:
        assert paths.law_budget_ns(law) > 0
    assert paths.law_budget_ns("quat_nlpd_neg") == paths.law_budget_ns("quat_nlpd_pos")
    names = paths.status_names()
    assert names[0] == "AOCS_OK"
    assert "AOCS_ERR_UNKNOWN_LAW" in names.values() and "AOCS_ERR_INPUT_NOT_FINITE" in names.values()
