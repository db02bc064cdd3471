"""aocs_report.html: a self-contained page (style inline, figures embedded), text escaped, the
inline Markdown forms of the reports converted."""
from __future__ import annotations

import base64
from html.parser import HTMLParser

import pytest

from aocs_report import html
from aocs_report.document import BulletList, CodeBlock, Column, Document, Figure, Figures, Paragraph, Section, Table


class _Tags(HTMLParser):
    """Start and end tags in order, to check the page is well nested."""

    VOID = {"meta", "img", "br"}

    def __init__(self):
        super().__init__()
        self.stack, self.seen, self.errors = [], [], []

    def handle_starttag(self, tag, attrs):
        self.seen.append((tag, dict(attrs)))
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack.pop() != tag:
            self.errors.append(tag)


def _parse(page: str) -> _Tags:
    p = _Tags()
    p.feed(page)
    assert not p.errors and not p.stack, (p.errors, p.stack)
    return p


def test_inline_markdown_forms_and_escaping():
    assert html.inline("a < b & `x<y>` **bold** *em* [docs](docs/sil.md)") == (
        'a &lt; b &amp; <code>x&lt;y&gt;</code> <strong>bold</strong> <em>em</em> <a href="docs/sil.md">docs</a>')
    assert html.inline("[q](a.html?x=1&y=2)") == '<a href="a.html?x=1&amp;y=2">q</a>'   # escaped once
    assert html.inline("2 * 3 * 4") == "2 * 3 * 4"   # a lone asterisk between spaces is not emphasis
    assert html.inline("`**not bold**`") == "<code>**not bold**</code>"


def test_page_is_self_contained_and_well_nested(tmp_path):
    png = b"\x89PNG\r\n\x1a\nfake"
    (tmp_path / "a.png").write_bytes(png)
    doc = Document("Run <1>").add(
        Paragraph("line one\nline two"),
        Section("Table").add(Table(["law", Column("settle", "s")], [["smc", "never"]])),
        Section("Plots").add(Figures([Figure("a.png", "pointing"), Figure("missing.png", "gone")])),
        BulletList(["x", "y"]), CodeBlock("if a < b:", "python"))
    page = html.render(doc, base=tmp_path)
    tags = _parse(page)
    assert page.startswith("<!DOCTYPE html>") and "<style>" in page and "<title>Run &lt;1&gt;</title>" in page
    imgs = [a for t, a in tags.seen if t == "img"]
    assert imgs[0]["src"] == "data:image/png;base64," + base64.b64encode(png).decode()
    assert imgs[1]["src"] == "missing.png"      # not on disk: referred to, not embedded
    assert '<th>settle <span class="unit">s</span></th>' in page
    assert "<h2>Table</h2>" in page and "line one<br>\nline two" in page
    assert '<code class="language-python">if a &lt; b:</code>' in page
    assert [t for t, _ in tags.seen if t in ("link", "script")] == []   # nothing fetched from elsewhere


def test_an_unknown_block_is_refused():
    with pytest.raises(TypeError, match="not a document block"):
        html.render(Document("T").add(42))
