"""aocs_report.document: the blocks keep what they are given and refuse a ragged table."""
from __future__ import annotations

import pytest

from aocs_report.document import BulletList, Column, Document, Figure, Figures, Paragraph, Section, Table


def test_table_columns_take_titles_or_columns_with_units():
    t = Table(["law", Column("settle", "s")], [["quat_pd", "20.0"], ("smc", "never")])
    assert t.columns == (Column("law", ""), Column("settle", "s"))
    assert t.rows == (("quat_pd", "20.0"), ("smc", "never"))


def test_a_row_with_the_wrong_number_of_cells_is_refused():
    with pytest.raises(ValueError, match="row 1 has 1 cells for 2 columns"):
        Table(["law", "settle"], [["a", "1"], ["b"]])


def test_sections_and_documents_collect_blocks_in_order():
    s = Section("Plots").add(Figure("a.png", "a"), Figures([Figure("b.png", "b")]))
    doc = Document("Report").add(Paragraph("one"), s, BulletList(["x"]))
    assert [type(b).__name__ for b in doc.blocks] == ["Paragraph", "Section", "BulletList"]
    assert s.blocks[1].figures == (Figure("b.png", "b"),)
