"""Firmware facts aocs_core.paths reads from the build and the headers.

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import re
from pathlib import Path

from aocs_core import paths

REPO = Path(__file__).resolve().parents[3]



def test_law_ids_follow_the_executive_enum_and_law_table():
    header = (REPO / "firmware/include/aocs/executive.h").read_text()
    body = header[header.index("typedef enum {"):header.index("} aocs_law_id_t;")]
    enum = re.findall(r"^\s*(AOCS_LAW_[A-Z_]+)", body, re.M)
    assert enum[-1] == "AOCS_LAW_COUNT" and len(enum) - 1 == len(paths.LAW_IDS)
    table = (REPO / "firmware/src/executive/law_table.c").read_text()
    names_block = table[table.index("law_names[AOCS_LAW_COUNT]"):]
    names = re.findall(r'"([a-z_0-9]+)"', names_block[:names_block.index("};")])
    assert names == list(paths.LAW_IDS)
    assert [paths.LAW_IDS[n] for n in names] == list(range(len(names)))


def test_budgets_and_status_names_come_from_the_headers():
    for law in paths.LAW_IDS:
        assert paths.law_budget_ns(law) > 0
    assert paths.law_budget_ns("quat_nlpd_neg") == paths.law_budget_ns("quat_nlpd_pos")
    names = paths.status_names()
    assert names[0] == "AOCS_OK"
    assert "AOCS_ERR_UNKNOWN_LAW" in names.values() and "AOCS_ERR_INPUT_NOT_FINITE" in names.values()
