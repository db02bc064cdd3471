"""A Document as Markdown (GitHub's dialect): the form the repository's reports are committed in
(docs/results.md, docs/campaigns/*/report.md, `aocs compare`'s report.md).

Every block is followed by one blank line; the document ends with one newline. Text is inline
Markdown already (document.py), so it is written as it is.
"""
from __future__ import annotations

from .document import BulletList, Chart, CodeBlock, Document, Figure, Figures, Paragraph, Section, Table


def render(doc: Document) -> str:
    return "\n\n".join([f"# {doc.title}", *(_block(b, 2) for b in doc.blocks)]) + "\n"


def table(t: Table) -> str:
    lines = [_row(c.label for c in t.columns), "|" + "---|" * len(t.columns)]
    lines += [_row(r) for r in t.rows]
    return "\n".join(lines)


def _row(cells) -> str:
    """| a | b |, an empty cell as one blank (| | b |)."""
    return "|" + "|".join(f" {c} " if c else " " for c in cells) + "|"


def _item(text: str) -> str:
    first, *rest = text.split("\n")
    return "\n".join([f"- {first}", *(f"  {line}" for line in rest)])


def _block(b, level: int) -> str:
    if isinstance(b, Paragraph):
        return b.text
    if isinstance(b, BulletList):
        return ("\n\n" if b.loose else "\n").join(_item(i) for i in b.items)
    if isinstance(b, Table):
        return table(b)
    if isinstance(b, Figure):
        return f"![{b.alt}]({b.path})"
    if isinstance(b, Figures):
        return "\n".join(_block(f, level) for f in b.figures)
    if isinstance(b, CodeBlock):
        return f"```{b.language}\n{b.text}\n```"
    if isinstance(b, Chart):
        return f"*Interactive figure: {b.title} (in the HTML report).*"
    if isinstance(b, Section):
        return "\n\n".join(["#" * level + f" {b.title}", *(_block(x, level + 1) for x in b.blocks)])
    raise TypeError(f"not a document block: {b!r}")
