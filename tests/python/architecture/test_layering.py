"""The Python packages' structure (docs/architecture.md): folders named as imported, the
layering contract of pyproject.toml kept, no import cycle, and no import hidden inside a
function without its reason written beside it."""
from __future__ import annotations

import ast
import importlib
import subprocess
import sys
import tomllib
from pathlib import Path

import grimp
import pytest

REPO = Path(__file__).resolve().parents[3]
PYPROJECT = tomllib.loads((REPO / "pyproject.toml").read_text())
PACKAGES = PYPROJECT["tool"]["importlinter"]["root_packages"]


def _sources() -> list[Path]:
    return sorted(p for d in ("sil", "tools") for p in (REPO / d).glob("aocs*/**/*.py"))


def test_no_package_dir_renames_and_every_folder_is_named_as_imported():
    setuptools_cfg = PYPROJECT["tool"]["setuptools"]
    assert "package-dir" not in setuptools_cfg
    found = {p.parent.name for p in _sources() if p.name == "__init__.py" and p.parent.parent.name in ("sil", "tools")}
    assert found == set(PACKAGES), "root_packages of the layering contract must list every aocs* package"
    for name in PACKAGES:
        mod = importlib.import_module(name)
        folder = Path(mod.__file__).resolve().parent
        assert folder.name == name and folder.parent.name in ("sil", "tools"), f"{name} lives in {folder}"


def test_layering_contract_is_kept():
    """The real checker (import-linter) over the installed packages."""
    exe = Path(sys.executable).with_name("lint-imports")
    res = subprocess.run([str(exe), "--config", str(REPO / "pyproject.toml")], cwd=REPO,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "0 broken" in res.stdout


def find_cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Every elementary cycle's first discovery in a DFS (enough to report one per strongly connected knot)."""
    state, stack, cycles = {}, [], []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == 1:
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for n in sorted(edges):
        if n not in state:
            visit(n)
    return cycles


def test_cycle_finder_finds_a_cycle():
    assert find_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c", "a"]]
    assert find_cycles({"a": {"b"}, "b": set(), "c": {"a", "b"}}) == []


def test_no_import_cycle_between_modules():
    graph = grimp.build_graph(*PACKAGES)
    edges = {m: set(graph.find_modules_directly_imported_by(m)) for m in graph.modules}
    # a package's __init__ importing its own submodules is not a cycle of the code
    for m, deps in edges.items():
        edges[m] = {d for d in deps if not m.startswith(d + ".")}
    cycles = find_cycles(edges)
    assert not cycles, "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


def deferred_imports_without_reason(text: str) -> list[int]:
    """Line numbers of imports inside functions whose line has no '# deferred: <reason>' comment."""
    lines = text.splitlines()
    bad = []
    for fn in ast.walk(ast.parse(text)):
        if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for node in ast.walk(fn):
                if isinstance(node, (ast.Import, ast.ImportFrom)):
                    line = lines[node.lineno - 1]
                    if "# deferred:" not in line and "deferred:" not in line.split("#", 1)[-1]:
                        bad.append(node.lineno)
    return bad


def test_deferred_import_rule_checker():
    src = "def f():\n    import os\n\ndef g():\n    import json  # deferred: only on this path\n"
    assert deferred_imports_without_reason(src) == [2]


@pytest.mark.parametrize("path", _sources(), ids=lambda p: str(p.relative_to(REPO)))
def test_imports_inside_functions_say_why(path):
    bad = deferred_imports_without_reason(path.read_text())
    assert not bad, f"{path.relative_to(REPO)}: imports inside functions without '# deferred: why' at lines {bad}"
