"""Every "SPEC n.m" citation in the repository resolves to a section of docs/spec.md.

"SPEC n.m" anywhere in code, comments, tests or docs means section n.m of
docs/spec.md (the project's own specification). This test collects every
git-tracked text file (docs/spec.md itself excluded), finds every citation and
checks that its number is the number of a heading of docs/spec.md.

Citation forms recognised (whitespace may include a line break):
    SPEC 2.8          SPEC 4.           (trailing dot = end of sentence)
    SPEC section 1    SPEC sections 3 and 4
    SPEC 2.5, 2.6, 2.8                  SPEC 2-3 (a range: both ends checked)
    SPEC.md section 1 (the former name of the same document)
Headings of docs/spec.md: a line `#... <number>[.] <title>`, e.g.
`## 2. Control laws`, `### 2.3 quat_nlpd: nonlinear PD`.
"""
from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

HERE = Path(__file__).resolve().parent
SPEC_REL = "docs/spec.md"
SELF_REL = "tests/python/docs/test_spec_citations.py"

# A section number: 2, 2.8, 5.4 ... (a trailing sentence dot is not part of it).
_NUM = r"\d+(?:\.\d+)*"
# A further number in a list or range ("2.5, 2.6, 2.8", "3 and 4", "2-3"). Only
# numbers whose top level is one digit continue a list, so "SPEC 4, 500 s" is
# the single citation 4.
_MORE = r"\d(?:\.\d+)*(?![\d.]*\d)"
_SEP = r"(?:\s*,\s*(?:and\s+|or\s+)?|\s+(?:and|or|&)\s+|\s*/\s*|[-\u2013])"
CITATION_RE = re.compile(
    r"\bSPEC(?:\.md)?(?:\s+sections?|\s*\u00a7)?\s*(?<![A-Za-z.])"
    rf"(?P<first>{_NUM})(?P<rest>(?:{_SEP}{_MORE})*)"
)
_MORE_RE = re.compile(_MORE)
HEADING_RE = re.compile(r"^#+\s+(\d+(?:\.\d+)*)\.?(?:\s|$)")
FENCE_RE = re.compile(r"^\s*(```|~~~)")


def find_citations(text: str) -> list[tuple[int, str]]:
    """(line number, section number) of every citation in text, in order."""
    found: list[tuple[int, str]] = []
    for m in CITATION_RE.finditer(text):
        line = text.count("\n", 0, m.start()) + 1
        numbers = [m.group("first")] + _MORE_RE.findall(m.group("rest"))
        for number in numbers:
            found.append((line, number.rstrip(".")))
    return found


def spec_sections(markdown: str) -> list[str]:
    """Section numbers of the headings of a markdown text (fenced code skipped)."""
    sections: list[str] = []
    in_fence = False
    for line in markdown.splitlines():
        if FENCE_RE.match(line):
            in_fence = not in_fence
            continue
        if in_fence:
            continue
        m = HEADING_RE.match(line)
        if m:
            sections.append(m.group(1))
    return sections


def unresolved(citations: list[tuple[str, int, str]], sections: set[str]) -> list[str]:
    """`path:line: SPEC x.y` for every citation whose number is not a section."""
    return [f"{path}:{line}: SPEC {num}" for path, line, num in citations if num not in sections]


def repo_root() -> Path:
    try:
        out = subprocess.run(["git", "rev-parse", "--show-toplevel"], cwd=HERE,
                             capture_output=True, text=True, check=True).stdout.strip()
        return Path(out)
    except (OSError, subprocess.CalledProcessError):
        return HERE.parents[2]  # tests/python/docs -> repository root


def tracked_files(root: Path) -> list[str]:
    """Repository-relative paths of the git-tracked files (a plain walk without git)."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=root,
                             capture_output=True, check=True).stdout
        return sorted(p for p in out.decode("utf-8", "surrogateescape").split("\0") if p)
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", ".venv", "build", "out", "__pycache__", "node_modules"}
        paths = []
        for d, dirs, files in os.walk(root):
            dirs[:] = [x for x in dirs if x not in skip]
            paths += [os.path.relpath(os.path.join(d, f), root) for f in files]
        return sorted(paths)


def read_text(path: Path) -> str | None:
    """The file's text, or None for a binary or missing file."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", errors="replace")


def repository_citations(root: Path) -> list[tuple[str, int, str]]:
    cites: list[tuple[str, int, str]] = []
    for rel in tracked_files(root):
        if rel.replace(os.sep, "/") in (SPEC_REL, SELF_REL):
            continue  # the spec itself; this file's parser tests cite made-up sections on purpose
        text = read_text(root / rel)
        if text is None or "SPEC" not in text:
            continue
        cites += [(rel, line, num) for line, num in find_citations(text)]
    return cites


# ---- the parser itself (so a broken regex cannot make the real check vacuous) ----

def test_citation_parser_on_inline_text():
    text = ("u = -kp s qe (SPEC 2.2). See SPEC 9.9.\n"
            "plant (SPEC sections 3 and 4), tables (SPEC 2.5, 2.6, 2.8), SPEC 2-3;\n"
            "held for SPEC 4, 500 s. SPEC_IDS = [] and --event SPEC ... are not citations.\n"
            "SPEC.md\nsection 1 is the source; SPEC 4.\n")
    assert find_citations(text) == [
        (1, "2.2"), (1, "9.9"),
        (2, "3"), (2, "4"), (2, "2.5"), (2, "2.6"), (2, "2.8"), (2, "2"), (2, "3"),
        (3, "4"),
        (4, "1"), (5, "4"),
    ]
    sections = set(spec_sections("# Title\n## 2. Control laws\n### 2.2 quat_pd: PD\n"
                                 "## 3. Plant\n## 4\n```\n## 9.9 inside a code block\n```\n"))
    assert sections == {"2", "2.2", "3", "4"}
    cites = [("f.c", line, num) for line, num in find_citations(text)]
    assert unresolved(cites, sections) == ["f.c:1: SPEC 9.9", "f.c:2: SPEC 2.5", "f.c:2: SPEC 2.6",
                                           "f.c:2: SPEC 2.8", "f.c:4: SPEC 1"]


def test_heading_parser_reads_numbers_only_at_the_start():
    md = "## 1. Conventions\n### 1.10 Decisions\n## How citations work\n#### rtc_ex1a (see 2.1)\n"
    assert spec_sections(md) == ["1", "1.10"]


# ---- docs/spec.md and the repository ----

def test_spec_has_every_section_the_code_base_relies_on():
    root = repo_root()
    sections = spec_sections((root / SPEC_REL).read_text(encoding="utf-8"))
    duplicates = sorted({s for s in sections if sections.count(s) > 1})
    assert not duplicates, f"{SPEC_REL}: section numbers used twice: {duplicates}"
    required = {"1", "2", "3", "4", "5", "6"} | {f"2.{k}" for k in range(1, 9)} \
        | {f"3.{k}" for k in range(1, 6)} | {"4.1", "4.2"} | {f"5.{k}" for k in range(1, 5)}
    missing = sorted(required - set(sections))
    assert not missing, f"{SPEC_REL}: missing sections {missing}"


def test_every_spec_citation_resolves_to_a_section_of_docs_spec_md():
    root = repo_root()
    sections = set(spec_sections((root / SPEC_REL).read_text(encoding="utf-8")))
    cites = repository_citations(root)
    numbers = {num for _, _, num in cites}
    # positive control: the scan really sees the code base's citations
    assert cites, "no SPEC citation found in the repository: the scan is broken"
    assert "2.8" in numbers, f"SPEC 2.8 (orbit_lqr) is cited in the code but was not found: {sorted(numbers)}"
    bad = unresolved(cites, sections)
    assert not bad, (f"{len(bad)} of {len(cites)} SPEC citations do not resolve to a heading of "
                     f"{SPEC_REL}:\n" + "\n".join(bad))
