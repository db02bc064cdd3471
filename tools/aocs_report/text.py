"""A Table as plain text in aligned columns: what the command line prints (`aocs compare`)."""
from __future__ import annotations

from .document import Table


def table(t: Table) -> str:
    """Header, a rule of dashes and the rows, each column as wide as its widest cell, two spaces apart."""
    head = [c.label for c in t.columns]
    widths = [max(len(h), *(len(r[i]) for r in t.rows)) if t.rows else len(h) for i, h in enumerate(head)]

    def line(cells) -> str:
        return "  ".join(f"{c:<{w}}" for c, w in zip(cells, widths)).rstrip()

    return "\n".join([line(head), line(["-" * w for w in widths])] + [line(r) for r in t.rows])
