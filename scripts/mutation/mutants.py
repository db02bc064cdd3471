"""Single-line mutants of a C or Python source file (docs/mutation.md).

Operators, each applied to one token of one line:
  cmp    flip a comparison:       <  <=  >  >=  (to its strict / non-strict twin)
  eq     ==  <->  !=
  arith  binary +  <->  -   (also +=  <->  -=)
  neg    drop a unary minus:      -x  ->  x
  term   drop a term:             a + b  ->  a   (b one simple operand: a name, member, index or number)
  const  a literal 0 <-> 1        (0, 0.0, 1, 1.0, 1u, 0.0f ...)
  bool   &&  <->  ||  (C),  and  <->  or  (Python)

Tokens come from a small C lexer (comments, strings, character literals and
preprocessor lines skipped) or Python's tokenize, so nothing in a comment or a
string is mutated. A mutant is named by file, line, column, operator and the
text it replaces; `key()` is the line-number-free identity the equivalence
list uses (file, the stripped line, the replacement, and which of the same replacements on lines of that
text it is, in file order).
"""
from __future__ import annotations

import io
import re
import tokenize
from dataclasses import dataclass

CMP_FLIP = {"<": "<=", "<=": "<", ">": ">=", ">=": ">"}
EQ_FLIP = {"==": "!=", "!=": "=="}
ARITH_FLIP = {"+": "-", "-": "+", "+=": "-=", "-=": "+="}
BOOL_FLIP_C = {"&&": "||", "||": "&&"}
BOOL_FLIP_PY = {"and": "or", "or": "and"}
ZERO = re.compile(r"^0(\.0*)?[fFuUlL]?$|^0\.0*[eE][+-]?\d+$")
ONE = re.compile(r"^1(\.0*)?[fFuUlL]?$")
C_OPS = sorted(["<<=", ">>=", "->", "++", "--", "<=", ">=", "==", "!=", "&&", "||", "+=", "-=", "*=", "/=", "<<",
                ">>", "<", ">", "+", "-", "*", "/", "%", "=", "!", "&", "|", "^", "~", "?", ":", ",", ";", "(",
                ")", "[", "]", "{", "}", "."], key=len, reverse=True)
# a token after which + or - is unary
C_UNARY_AFTER = {"(", "[", "{", ",", ";", "=", "?", ":", "return", "+=", "-=", "*=", "/=", "<", "<=", ">", ">=",
                 "==", "!=", "&&", "||", "!", "+", "-", "*", "/", "%"}
PY_UNARY_AFTER = {"(", "[", "{", ",", "=", ":", "return", "+=", "-=", "*=", "/=", "<", "<=", ">", ">=", "==", "!=",
                  "and", "or", "not", "+", "-", "*", "/", "%", "**", "if", "else", "in", "lambda", "yield", "@"}


@dataclass(frozen=True)
class Tok:
    kind: str  # "op", "name", "num"
    text: str
    line: int  # 1-based
    col: int  # 0-based, within the line


@dataclass(frozen=True)
class Mutant:
    path: str  # relative to the repository root
    line: int
    col: int
    op: str
    old: str
    new: str
    line_text: str  # the original line, stripped
    occurrence: int  # the how-manieth (from 0) mutant with the same old -> new on a line of this text in the file

    @property
    def ident(self) -> str:
        return f"{self.path}:{self.line}:{self.col}:{self.op}:{self.old!r}->{self.new!r}"

    def key(self) -> tuple[str, str, str, str, int]:
        return (self.path, self.line_text, self.old, self.new, self.occurrence)

    def apply(self, source: str) -> str:
        lines = source.splitlines(keepends=True)
        text = lines[self.line - 1]
        if text[self.col:self.col + len(self.old)] != self.old:
            raise ValueError(f"{self.ident}: the source no longer holds {self.old!r} there")
        lines[self.line - 1] = text[:self.col] + self.new + text[self.col + len(self.old):]
        return "".join(lines)

    def diff_line(self, source: str) -> str:
        return self.apply(source).splitlines()[self.line - 1].strip()


def c_tokens(source: str) -> list[Tok]:
    """Tokens of C source outside comments, strings, character literals and preprocessor lines."""
    toks: list[Tok] = []
    i, line, line_start, n = 0, 1, 0, len(source)
    at_line_start = True
    while i < n:
        ch = source[i]
        if ch == "\n":
            i, line, line_start, at_line_start = i + 1, line + 1, i + 1, True
            continue
        if ch in " \t\r\f\v":
            i += 1
            continue
        if at_line_start and ch == "#":  # a preprocessor line, with its continuations
            while i < n and source[i] != "\n":
                if source[i] == "\\" and i + 1 < n and source[i + 1] == "\n":
                    i, line, line_start = i + 2, line + 1, i + 2
                    continue
                i += 1
            continue
        at_line_start = False
        if source.startswith("/*", i):
            end = source.find("*/", i + 2)
            end = n if end < 0 else end + 2
            for k in range(i, end):
                if source[k] == "\n":
                    line, line_start = line + 1, k + 1
            i = end
            continue
        if source.startswith("//", i):
            while i < n and source[i] != "\n":
                i += 1
            continue
        if ch in "\"'":
            i += 1
            while i < n and source[i] != ch:
                i += 2 if source[i] == "\\" else 1
            i += 1
            continue
        m = re.compile(r"[A-Za-z_]\w*").match(source, i)
        if m:
            toks.append(Tok("name", m.group(), line, i - line_start))
            i = m.end()
            continue
        m = re.compile(r"(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?[fFuUlL]*").match(source, i)
        if m:
            toks.append(Tok("num", m.group(), line, i - line_start))
            i = m.end()
            continue
        for op in C_OPS:
            if source.startswith(op, i):
                toks.append(Tok("op", op, line, i - line_start))
                i += len(op)
                break
        else:
            i += 1
    return toks


def py_tokens(source: str) -> list[Tok]:
    """Tokens of Python source; docstrings and other strings are never mutated."""
    toks: list[Tok] = []
    for t in tokenize.generate_tokens(io.StringIO(source).readline):
        if t.type == tokenize.OP:
            toks.append(Tok("op", t.string, t.start[0], t.start[1]))
        elif t.type == tokenize.NAME:
            toks.append(Tok("name", t.string, t.start[0], t.start[1]))
        elif t.type == tokenize.NUMBER:
            toks.append(Tok("num", t.string, t.start[0], t.start[1]))
    return toks


def _simple_operand_end(toks: list[Tok], j: int, lang: str) -> int | None:
    """Index past a simple operand starting at toks[j] that is a whole term (not followed by * / % ( **), or None."""
    # the operand starts on the operator's line: a string operand is no token, so the next one may be the next line's
    if j >= len(toks) or toks[j].kind not in ("name", "num") or toks[j].line != toks[j - 1].line:
        return None
    if toks[j].kind == "name" and toks[j].text in ("and", "or", "not", "if", "else", "in", "is", "lambda", "for"):
        return None
    k = j + 1
    member = (".", "->") if lang == "c" else (".",)
    while k + 1 < len(toks) and toks[k].kind == "op" and toks[k].text in member and toks[k + 1].kind == "name" \
            and toks[k].line == toks[j].line:
        k += 2
    while k < len(toks) and toks[k].kind == "op" and toks[k].text == "[" and toks[k].line == toks[j].line:
        depth, m = 0, k
        while m < len(toks):
            if toks[m].text == "[":
                depth += 1
            elif toks[m].text == "]":
                depth -= 1
                if depth == 0:
                    break
            m += 1
        if m >= len(toks) or toks[m].line != toks[j].line:
            return None
        k = m + 1
    if k < len(toks) and toks[k].kind == "op" and toks[k].text in ("*", "/", "%", "(", "**", "@", ".", "->", "["):
        return None
    if toks[k - 1].line != toks[j].line:
        return None
    return k


def mutants_of(path: str, source: str, lang: str) -> list[Mutant]:
    """Every single-token mutant of one file, in source order."""
    toks = c_tokens(source) if lang == "c" else py_tokens(source)
    lines = source.splitlines()
    unary_after = C_UNARY_AFTER if lang == "c" else PY_UNARY_AFTER
    bool_flip = BOOL_FLIP_C if lang == "c" else BOOL_FLIP_PY
    raw: list[tuple[int, int, str, str, str]] = []  # line, col, op, old, new
    for idx, t in enumerate(toks):
        prev = toks[idx - 1] if idx > 0 else None
        unary = prev is None or (prev.kind == "op" and prev.text in unary_after) \
            or (prev.kind == "name" and prev.text in ("return", "and", "or", "not", "if", "else", "in", "yield"))
        if t.kind == "op":
            if t.text in CMP_FLIP:
                raw.append((t.line, t.col, "cmp", t.text, CMP_FLIP[t.text]))
            elif t.text in EQ_FLIP:
                raw.append((t.line, t.col, "eq", t.text, EQ_FLIP[t.text]))
            elif t.text in bool_flip:
                raw.append((t.line, t.col, "bool", t.text, bool_flip[t.text]))
            elif t.text in ("+", "-") and unary:
                if t.text == "-":
                    raw.append((t.line, t.col, "neg", "-", ""))
            elif t.text in ARITH_FLIP:
                raw.append((t.line, t.col, "arith", t.text, ARITH_FLIP[t.text]))
                end = _simple_operand_end(toks, idx + 1, lang) if t.text in ("+", "-") else None
                if end is not None:
                    line = lines[t.line - 1]
                    last = toks[end - 1]
                    stop = last.col + len(last.text) if last.text != "]" else last.col + 1
                    start = t.col
                    while start > 0 and line[start - 1] == " ":
                        start -= 1
                    raw.append((t.line, start, "term", line[start:stop], ""))
        elif t.kind == "name" and t.text in bool_flip:
            raw.append((t.line, t.col, "bool", t.text, bool_flip[t.text]))
        elif t.kind == "num":
            if ZERO.match(t.text):
                raw.append((t.line, t.col, "const", t.text, "1" + t.text[1:] if t.text[0] == "0" else "1"))
            elif ONE.match(t.text):
                raw.append((t.line, t.col, "const", t.text, "0" + t.text[1:]))
    out: list[Mutant] = []
    seen: dict[tuple[str, str, str], int] = {}
    for line, col, op, old, new in raw:
        k = (lines[line - 1].strip(), old, new)  # the same replacement on a line of the same text, in file order
        occ = seen.get(k, 0)
        seen[k] = occ + 1
        out.append(Mutant(path, line, col, op, old, new, k[0], occ))
    return out
