"""The mutant generator of `make mutation` (scripts/mutation/mutants.py) and the equivalence list it honours.

Every entry of tests/mutation/equivalent.toml must still name exactly one mutant of the current source (a
stale entry would silently stop excusing anything, or excuse the wrong line), and the generator must never
mutate a comment, a string or a preprocessor line.
"""
from __future__ import annotations

import sys
import tomllib
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "scripts" / "mutation"))
import mutants as mut  # noqa: E402

EQUIVALENT = tomllib.loads((REPO / "tests" / "mutation" / "equivalent.toml").read_text())["mutant"]


@pytest.mark.parametrize("entry", EQUIVALENT, ids=lambda e: f"{e['file']}:{e['line'][:40]}")
def test_every_equivalent_entry_names_one_current_mutant(entry):
    assert len(entry["reason"].split()) >= 5, "say why the mutant is equivalent"
    path = entry["file"]
    lang = "c" if path.endswith(".c") else "py"
    same_text = [m for m in mut.mutants_of(path, (REPO / path).read_text(), lang)
                 if m.key()[:4] == (path, entry["line"], entry["old"], entry["new"])]
    found = [m for m in same_text if m.occurrence == int(entry.get("occurrence", 0))]
    assert len(found) == 1, f"{path}: no mutant {entry['old']!r} -> {entry['new']!r} on {entry['line']!r}"
    # the same replacement on several lines of this text: the entry must say which one it means
    assert len(same_text) == 1 or "occurrence" in entry, \
        f"{path}: {entry['line']!r} stands on lines {[m.line for m in same_text]}: give `occurrence`"


def test_c_comments_strings_and_preprocessor_lines_are_never_mutated():
    src = ('#include <stdio.h>\n'
           '#define LIM(a, b) ((a) < (b))\n'
           '/* a < b, x - 1 */ static int f(int a, int b) // a > b\n'
           '{\n'
           '    const char *s = "a < b - 0";\n'
           '    return (a < b) ? -a : s[0] == \'<\';\n'
           '}\n')
    ms = mut.mutants_of("x.c", src, "c")
    assert {(m.line, m.op, m.old, m.new) for m in ms} == {
        (6, "cmp", "<", "<="), (6, "neg", "-", ""), (6, "const", "0", "1"), (6, "eq", "==", "!=")}
    m = next(m for m in ms if m.op == "cmp")
    assert m.apply(src).splitlines()[5] == "    return (a <= b) ? -a : s[0] == '<';"


def test_python_strings_and_docstrings_are_never_mutated_and_terms_drop_whole():
    src = ('def f(x, y):\n'
           '    """x < y - 1"""\n'
           '    z = -x + y[1] * 2\n'
           '    return z - y.v, "a < b"\n')
    ms = mut.mutants_of("x.py", src, "py")
    got = {(m.line, m.op, m.old, m.new) for m in ms}
    assert all(line in (3, 4) for line, *_ in got)
    assert (3, "neg", "-", "") in got and (3, "arith", "+", "-") in got and (3, "const", "1", "0") in got
    assert not any(op == "term" and line == 3 for line, op, *_ in got)   # y[1] * 2 is not a whole term
    term = next(m for m in ms if m.op == "term")
    assert term.apply(src).splitlines()[3] == '    return z, "a < b"'


def test_a_string_operand_at_the_end_of_a_line_gives_no_term():
    """`x + "]"` then `return` on the next line: strings are no tokens, so the token after the `+` is the next
    line's; no term is cut across lines (it was a mutant that changed nothing); `x + y` still gives its term."""
    src = 'def f(x, y):\n    if x:\n        return x + "]"\n    return x + y\n'
    ms = mut.mutants_of("x.py", src, "py")
    assert [(m.line, m.old) for m in ms if m.op == "term"] == [(4, " + y")]
    assert (3, "arith") in {(m.line, m.op) for m in ms}


def test_every_mutant_of_the_sampled_areas_changes_its_file():
    """Over every file make mutation draws from (its own pool, run.all_mutants), no mutant leaves its file as
    it was."""
    import run

    for area in run.AREAS.values():
        sources: dict[str, str] = {}
        for m in run.all_mutants(area, sources):
            assert m.apply(sources[m.path]) != sources[m.path], m.ident


def test_a_mutant_applies_only_where_it_was_made():
    src = "a = b < c\n"
    m = mut.mutants_of("x.py", src, "py")[0]
    assert m.apply(src) == "a = b <= c\n"
    with pytest.raises(ValueError, match="no longer holds"):
        m.apply("a = b + c\n")
