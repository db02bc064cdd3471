"""The Python packages' structure (docs/architecture.md): folders named as imported, the
layering contracts of pyproject.toml kept, no package under sil/ importing a package under
tools/, no import cycle, and no import hidden inside a function without its reason written
beside it."""
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


def package_folders(top: str) -> list[str]:
    """The packages whose folder is directly under `top` (sil or tools)."""
    return sorted(p.parent.name for p in (REPO / top).glob("aocs*/__init__.py"))


def imported_packages(text: str) -> list[tuple[int, str]]:
    """(line, top-level package) of every absolute import of a module's text, inside functions too,
    and of every importlib.import_module("...") with a literal name."""
    found = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name.split(".")[0]) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.append((node.lineno, node.module.split(".")[0]))
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "import_module"
              and node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)):
            found.append((node.lineno, node.args[0].value.split(".")[0]))
    return found


def test_imported_packages_finds_every_kind_of_import():
    src = ("import os.path\nfrom aocs_core import paths\nfrom . import sibling\n"
           "def f():\n    from aocs_compare.compare import run  # deferred: test\n"
           "    return importlib.import_module('aocs_campaign.plan')\n")
    assert imported_packages(src) == [(1, "os"), (2, "aocs_core"), (5, "aocs_compare"), (6, "aocs_campaign")]


def test_folder_contract_names_the_folders():
    """The forbidden contract's two lists are exactly the package folders under sil/ and tools/."""
    contracts = [c for c in PYPROJECT["tool"]["importlinter"]["contracts"] if c["type"] == "forbidden"]
    assert len(contracts) == 1, "one contract: no package under sil/ imports a package under tools/"
    assert sorted(contracts[0]["source_modules"]) == package_folders("sil")
    assert sorted(contracts[0]["forbidden_modules"]) == package_folders("tools")


@pytest.mark.parametrize("path", sorted((REPO / "sil").glob("aocs*/**/*.py")), ids=lambda p: str(p.relative_to(REPO)))
def test_no_sil_package_imports_a_tools_package(path):
    """Folders show the layers (issue 19 item 6): what a run needs lives in sil/, the tools build on it."""
    tools = set(package_folders("tools"))
    bad = [(line, name) for line, name in imported_packages(path.read_text()) if name in tools]
    assert not bad, (f"{path.relative_to(REPO)} imports packages under tools/ at (line, package) {bad}: "
                     "move what it needs down to sil/")


def test_layering_contract_is_kept():
    """The real checker (import-linter) over the installed packages."""
    exe = Path(sys.executable).with_name("lint-imports")
    res = subprocess.run([str(exe), "--config", str(REPO / "pyproject.toml")], cwd=REPO,
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "0 broken" in res.stdout
    assert "no package under sil/ imports a package under tools/ KEPT" in res.stdout


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
