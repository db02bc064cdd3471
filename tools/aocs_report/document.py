"""The document model every report is built from (results, compare, campaign): a Document of
blocks, each block one kind of content. A report module says what the page holds; a renderer
(markdown.py, html.py) says how it looks, so the same report can be written as Markdown for the
repository and as a self-contained HTML page.

Text in Paragraph, list items, table cells and titles is inline Markdown as written (code spans,
emphasis, links): the Markdown renderer passes it through, the HTML renderer converts the few
inline forms the reports use (html.py).
"""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Paragraph:
    text: str


@dataclass(frozen=True)
class BulletList:
    """Items, each one string; a newline inside an item continues it on the next line.
    loose: a blank line between the items (each item a paragraph of its own)."""
    items: tuple[str, ...]
    loose: bool = False

    def __post_init__(self):
        object.__setattr__(self, "items", tuple(self.items))


@dataclass(frozen=True)
class Column:
    """A table column: its title and the unit of its values ("" when it has none)."""
    title: str
    unit: str = ""

    @property
    def label(self) -> str:
        """Title and unit as one header in the reports' style: "settle s", "max norm u N m"."""
        return f"{self.title} {self.unit}" if self.unit else self.title


def column(c: Column | str) -> Column:
    return c if isinstance(c, Column) else Column(c)


@dataclass(frozen=True)
class Table:
    """Columns (Column, or a plain title) and rows of cells already formatted as text."""
    columns: tuple[Column, ...]
    rows: tuple[tuple[str, ...], ...]

    def __post_init__(self):
        cols = tuple(column(c) for c in self.columns)
        rows = tuple(tuple(r) for r in self.rows)
        for i, r in enumerate(rows):
            if len(r) != len(cols):
                raise ValueError(f"table row {i} has {len(r)} cells for {len(cols)} columns: {r}")
        object.__setattr__(self, "columns", cols)
        object.__setattr__(self, "rows", rows)


@dataclass(frozen=True)
class Figure:
    """An image file, `path` as the page refers to it (relative to the page's folder)."""
    path: str
    alt: str


@dataclass(frozen=True)
class Figures:
    """Several figures shown together (one after the other, no text between)."""
    figures: tuple[Figure, ...]

    def __post_init__(self):
        object.__setattr__(self, "figures", tuple(self.figures))


@dataclass(frozen=True)
class CodeBlock:
    text: str
    language: str = ""


@dataclass
class Section:
    """A titled part of a document; sections nest (their level is their depth)."""
    title: str
    blocks: list = field(default_factory=list)

    def add(self, *blocks) -> Section:
        self.blocks.extend(blocks)
        return self


@dataclass
class Document:
    title: str
    blocks: list = field(default_factory=list)

    def add(self, *blocks) -> Document:
        self.blocks.extend(blocks)
        return self


#: every kind of block a document or a section may hold
BLOCKS = (Paragraph, BulletList, Table, Figure, Figures, CodeBlock, Section)
