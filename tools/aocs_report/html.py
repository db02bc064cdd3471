"""A Document as one self-contained HTML page: the style inline, every figure found on disk
embedded as a data URI, every Chart an interactive plotly figure with plotly.js embedded once
(plotly_chart.py), so the page can be mailed or archived as a single file and opens with no network.

Text is inline Markdown (document.py); the forms the reports use are converted: `code`,
**strong**, *emphasis* and [text](link). Everything else is escaped.
"""
from __future__ import annotations

import base64
import html
import mimetypes
import re
from pathlib import Path

from . import plotly_chart
from .document import BulletList, Chart, CodeBlock, Column, Document, Figure, Figures, Paragraph, Section, Table

STYLE = """body { font-family: sans-serif; max-width: 72em; margin: 2em auto; padding: 0 1em; line-height: 1.45; }
table { border-collapse: collapse; margin: 1em 0; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; }
th .unit { font-weight: normal; color: #555; }
figure { margin: 1em 0; } figure img { max-width: 100%; }
.figures { display: flex; flex-wrap: wrap; gap: 1em; }
pre { background: #f4f4f4; padding: 0.6em; overflow-x: auto; }
code { background: #f4f4f4; padding: 0 0.2em; }
figure.chart { margin: 1em 0; } .plot { width: 100%; min-height: 200px; }
.chart-note { color: #555; font-size: 0.85em; margin: 0.2em 0; }
pre.chart-link { font-size: 0.85em; white-space: pre-wrap; word-break: break-all; }"""

# inline Markdown, applied to escaped text in this order (code first: nothing inside it is converted)
_CODE = re.compile(r"`([^`]+)`")
_STRONG = re.compile(r"\*\*(.+?)\*\*")
_EM = re.compile(r"(?<![\w*])\*(?!\s)(.+?)(?<!\s)\*(?![\w*])")
_LINK = re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)")


def inline(text: str) -> str:
    """Escaped HTML of a line of inline Markdown."""
    parts = _CODE.split(text)
    out = []
    for i, part in enumerate(parts):
        if i % 2:
            out.append(f"<code>{html.escape(part)}</code>")
            continue
        s = html.escape(part, quote=False)
        # the text is escaped already: the link's target is unescaped once so that it is escaped once
        s = _LINK.sub(lambda m: f'<a href="{html.escape(html.unescape(m.group(2)))}">{m.group(1)}</a>', s)
        s = _STRONG.sub(r"<strong>\1</strong>", s)
        out.append(_EM.sub(r"<em>\1</em>", s))
    return "".join(out)


class _Page:
    """What the blocks of one page share: the charts' numbering and their link lists, each list written once."""

    def __init__(self, base: Path | None):
        self.base = base
        self.charts = 0
        self.links: dict[tuple, str] = {}

    def links_id(self, links) -> str | None:
        if links is None:
            return None
        return self.links.setdefault(tuple(links), f"links-{len(self.links) + 1}")


def _charts(blocks) -> bool:
    return any(isinstance(b, Chart) or (isinstance(b, Section) and _charts(b.blocks)) for b in blocks)


def render(doc: Document, base: Path | None = None) -> str:
    """The page; base: the folder figure paths are relative to (figures found there are embedded)."""
    page = _Page(base)
    body = "\n".join([f"<h1>{inline(doc.title)}</h1>", *(_block(b, 2, page) for b in doc.blocks)])
    links = "".join(f'<script type="application/json" id="{i}">{plotly_chart.links_json(k)}</script>\n'
                    for k, i in page.links.items())
    head = plotly_chart.page_head() + "\n" if _charts(doc.blocks) else ""
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{html.escape(doc.title)}</title>\n<style>\n{STYLE}\n</style>\n{head}</head>\n<body>\n"
            f"{links}{body}\n</body>\n</html>\n")


def header_cell(c: Column) -> str:
    return inline(c.title) + (f' <span class="unit">{html.escape(c.unit)}</span>' if c.unit else "")


def image_source(path: str, base: Path | None) -> str:
    """A data URI of the image when it is found under base, else the path itself (a link)."""
    f = None if base is None else Path(base) / path
    if f is None or not f.is_file():
        return html.escape(path)
    mime = mimetypes.guess_type(f.name)[0] or "application/octet-stream"
    return f"data:{mime};base64,{base64.b64encode(f.read_bytes()).decode('ascii')}"


def _figure(f: Figure, base: Path | None) -> str:
    return (f'<figure><img src="{image_source(f.path, base)}" alt="{html.escape(f.alt)}">'
            f"<figcaption>{html.escape(f.alt)}</figcaption></figure>")


def _block(b, level: int, page: _Page) -> str:
    base = page.base
    if isinstance(b, Paragraph):
        return "<p>" + "<br>\n".join(inline(line) for line in b.text.split("\n")) + "</p>"
    if isinstance(b, BulletList):
        items = ("<li>" + "<br>\n".join(inline(line) for line in i.split("\n")) + "</li>" for i in b.items)
        return "<ul>\n" + "\n".join(items) + "\n</ul>"
    if isinstance(b, Table):
        head = "<tr>" + "".join(f"<th>{header_cell(c)}</th>" for c in b.columns) + "</tr>"
        rows = ["<tr>" + "".join(f"<td>{inline(x)}</td>" for x in r) + "</tr>" for r in b.rows]
        return "<table>\n<thead>" + head + "</thead>\n<tbody>\n" + "\n".join(rows) + "\n</tbody>\n</table>"
    if isinstance(b, Figure):
        return _figure(b, base)
    if isinstance(b, Figures):
        return '<div class="figures">\n' + "\n".join(_figure(f, base) for f in b.figures) + "\n</div>"
    if isinstance(b, CodeBlock):
        cls = f' class="language-{html.escape(b.language)}"' if b.language else ""
        return f"<pre><code{cls}>{html.escape(b.text)}</code></pre>"
    if isinstance(b, Chart):
        page.charts += 1
        return plotly_chart.chart_html(b, f"chart-{page.charts}", page.links_id(b.links))
    if isinstance(b, Section):
        h = min(level, 6)
        return "\n".join([f"<section>\n<h{h}>{inline(b.title)}</h{h}>",
                          *(_block(x, level + 1, page) for x in b.blocks), "</section>"])
    raise TypeError(f"not a document block: {b!r}")
