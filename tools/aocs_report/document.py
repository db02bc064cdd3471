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


@dataclass(frozen=True)
class Trace:
    """One series of a Chart: y against x on panel `panel` (0 the top one). style: "lines", "markers" or
    "steps" (held until the next sample: modes, flags); dash: "solid", "dash" or "dot"; group: traces of
    one group show and hide together from the legend (a value and its 3-sigma band). ids: one integer per
    point naming what it stands for (a campaign's run index): the Chart's links[id] is shown when the point
    is clicked, and the id on hover."""
    name: str
    x: object
    y: object
    panel: int = 0
    style: str = "lines"
    dash: str = "solid"
    group: str | None = None
    color: str | None = None
    ids: object = None


@dataclass(frozen=True)
class Level:
    """A horizontal line on a panel: a limit, a requirement, a threshold, with its label."""
    value: float
    label: str


@dataclass(frozen=True)
class Panel:
    """One plot area of a Chart: its y axis (title with unit), log scale or not, its levels, and the y range first
    shown (None: every value; a renderer lets the reader zoom out to all)."""
    y_label: str
    log_y: bool = False
    levels: tuple[Level, ...] = ()
    y_range: tuple[float, float] | None = None

    def __post_init__(self):
        object.__setattr__(self, "levels", tuple(self.levels))


@dataclass(frozen=True)
class Mark:
    """An instant drawn across every panel of a Chart (an event, the settle time), with its label."""
    x: float
    label: str


@dataclass(frozen=True)
class Chart:
    """An interactive figure: panels stacked on one x axis (zoom one, all follow), its traces, its marks.
    links: the text a point's id opens (a run's repeat command), shared by every trace. A renderer that cannot
    draw it (Markdown) says where it is instead."""
    title: str
    x_label: str
    panels: tuple[Panel, ...]
    traces: tuple[Trace, ...]
    marks: tuple[Mark, ...] = ()
    links: tuple[str, ...] | None = None
    note: str = ""

    def __post_init__(self):
        object.__setattr__(self, "panels", tuple(self.panels))
        object.__setattr__(self, "traces", tuple(self.traces))
        object.__setattr__(self, "marks", tuple(self.marks))
        if self.links is not None:
            object.__setattr__(self, "links", tuple(self.links))
        for tr in self.traces:
            if not 0 <= tr.panel < len(self.panels):
                raise ValueError(f"chart {self.title!r}: trace {tr.name!r} on panel {tr.panel} of {len(self.panels)}")
            if tr.style not in ("lines", "markers", "steps"):
                raise ValueError(f"chart {self.title!r}: trace {tr.name!r}: style {tr.style!r}")


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
BLOCKS = (Paragraph, BulletList, Table, Figure, Figures, CodeBlock, Chart, Section)
