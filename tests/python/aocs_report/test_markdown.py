"""aocs_report.markdown: each block's Markdown, written out here by hand."""
from __future__ import annotations

import pytest

from aocs_report import markdown
from aocs_report.document import BulletList, CodeBlock, Column, Document, Figure, Figures, Paragraph, Section, Table


def test_a_document_is_its_blocks_each_followed_by_a_blank_line():
    doc = Document("Title").add(Paragraph("First `code`."), Section("Part").add(
        Paragraph("Inside."), Section("Sub").add(Paragraph("Deeper."))))
    assert markdown.render(doc) == "# Title\n\nFirst `code`.\n\n## Part\n\nInside.\n\n### Sub\n\nDeeper.\n"


def test_table_header_carries_the_units_after_the_titles():
    t = Table(["law", Column("settle", "s"), Column("max norm u", "N m")], [["smc", "12.5", "3"]])
    assert markdown.table(t) == ("| law | settle s | max norm u N m |\n|---|---|---|\n| smc | 12.5 | 3 |")


def test_an_empty_cell_is_one_blank():
    assert markdown.table(Table(["", "`a`"], [["form", ""]])) == "| | `a` |\n|---|---|\n| form | |"


def test_lists_tight_loose_and_continued_items():
    assert markdown.render(Document("T").add(BulletList(["a", "b\nmore of b"]))) == "# T\n\n- a\n- b\n  more of b\n"
    assert markdown.render(Document("T").add(BulletList(["a", "b"], loose=True))) == "# T\n\n- a\n\n- b\n"


def test_figures_code_and_a_figure_gallery():
    doc = Document("T").add(Figure("x.png", "x"), Figures([Figure("a.png", "a"), Figure("b.png", "b")]),
                            CodeBlock("aocs run irassi_small"), CodeBlock("x = 1", "python"))
    assert markdown.render(doc) == ("# T\n\n![x](x.png)\n\n![a](a.png)\n![b](b.png)\n\n"
                                    "```\naocs run irassi_small\n```\n\n```python\nx = 1\n```\n")


def test_an_unknown_block_is_refused():
    with pytest.raises(TypeError, match="not a document block"):
        markdown.render(Document("T").add("plain string"))
