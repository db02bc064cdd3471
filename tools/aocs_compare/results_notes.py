"""The prose of docs/results.md that belongs to one scenario group or to one scenario's laws, read
from results_notes.toml: section headings with their notes, and the discussion of a scenario's
laws with the figures measured from its runs filled in.

Figures a discussion text may name (measured_fields):
    max_torque_norms   "<row> <max |u| N m>, ..." over the runs that produced metrics
"""
from __future__ import annotations

import tomllib
from functools import lru_cache
from pathlib import Path

from aocs_report.document import Paragraph, Section

NOTES = Path(__file__).with_name("results_notes.toml")


@lru_cache(maxsize=None)
def load(path: Path = NOTES) -> dict:
    with open(path, "rb") as f:
        return tomllib.load(f)


def section(key: str, path: Path = NOTES) -> Section:
    """A section of runs with its heading and, when it has one, its note."""
    entry = _entry(load(path), "sections", key, path)
    sec = Section(entry["title"])
    if entry.get("note"):
        sec.add(Paragraph(entry["note"]))
    return sec


def measured_fields(rows) -> dict[str, str]:
    """The figures a discussion may name, from the runs it is about (compare.Row)."""
    ok = [r for r in rows if r.metrics]
    return {"max_torque_norms": ", ".join(r.name + " " + format(r.metrics["max_torque_norm_nm"], ".4g") for r in ok)}


def discussion(key: str, rows, path: Path = NOTES) -> Section | None:
    """The discussion of scenario `key`'s laws, None when none of its runs produced metrics."""
    entry = _entry(load(path), "discussion", key, path)
    if not any(r.metrics for r in rows):
        return None
    try:
        text = entry["text"].format(**measured_fields(rows))
    except KeyError as exc:
        raise KeyError(f"{path}: discussion.{key} names {{{exc.args[0]}}}, which is no measured figure "
                       f"(one of {', '.join(measured_fields([]))})") from None
    return Section(entry["title"]).add(Paragraph(text))


def _entry(notes: dict, table: str, key: str, path: Path) -> dict:
    try:
        return notes[table][key]
    except KeyError:
        raise KeyError(f"{path}: no [{table}.{key}] (the results page needs it)") from None
