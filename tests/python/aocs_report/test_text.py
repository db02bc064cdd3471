"""aocs_report.text: the aligned plain-text table the command line prints, written out by hand."""
from __future__ import annotations

from aocs_report import text
from aocs_report.document import Column, Table


def test_columns_as_wide_as_their_widest_cell_two_spaces_apart_no_trailing_blanks():
    t = Table(["law", Column("settle", "s"), "x"], [["quat_pd", "20.0", ""], ["smc", "never", "1"]])
    assert text.table(t) == ("law      settle s  x\n"
                             "-------  --------  -\n"
                             "quat_pd  20.0\n"
                             "smc      never     1")


def test_a_table_without_rows_is_its_header():
    assert text.table(Table([Column("limit", "N m")], [])) == "limit N m\n---------"
