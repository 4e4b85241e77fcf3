"""No import cycle among spl's modules, including the ones import-linter cannot see:
imports inside functions, and modules loaded by name (the bundle's TARGETS). Imports
needed only by the type checker (``if TYPE_CHECKING:``) are not run and do not count."""

from __future__ import annotations

import ast
from pathlib import Path

import networkx as nx

ROOT = Path(__file__).resolve().parents[2]
FOLDERS = {"src/spl": "spl"}


def modules() -> dict[str, Path]:
    found = {}
    for folder, package in FOLDERS.items():
        for path in (ROOT / folder).rglob("*.py"):
            parts = list(path.relative_to(ROOT / folder).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            found[".".join([package, *parts])] = path
    return found


def imports(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The spl modules ``name`` imports when it runs, wherever the import statement is,
    and those it names as strings (loaded by name)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            node.body = []
    here = name if path.name == "__init__.py" else name.rpartition(".")[0]
    targets: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level:
                base = here.split(".")[: len(here.split(".")) - (node.level - 1)]
                module = ".".join([*base, module] if module else base)
            targets += [
                f"{module}.{alias.name}" if f"{module}.{alias.name}" in known else module
                for alias in node.names
            ]
        elif isinstance(node, ast.Constant) and node.value in known:
            targets.append(node.value)
    found = set()
    for target in targets:
        while target and target not in known:
            target = target.rpartition(".")[0]
        if target and target != name:
            found.add(target)
    return found


def test_no_import_cycle():
    known = modules()
    graph = nx.DiGraph()
    for name, path in known.items():
        graph.add_edges_from((name, target) for target in imports(name, path, known))
    cycles = [sorted(c) for c in nx.strongly_connected_components(graph) if len(c) > 1]
    assert cycles == []


def test_the_check_sees_imports_inside_functions_and_by_name(tmp_path):
    """The two cycles the linter missed: the language server's requests and server
    (an import inside a function) and the bundle loading the generators by name."""
    known = {"spl.a": tmp_path / "a.py", "spl.b": tmp_path / "b.py"}
    known["spl.a"].write_text("def f():\n    from spl.b import x\n")
    known["spl.b"].write_text('TARGETS = {"a": ("spl.a",)}\n')
    assert imports("spl.a", known["spl.a"], known) == {"spl.b"}
    assert imports("spl.b", known["spl.b"], known) == {"spl.a"}
    known["spl.b"].write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import spl.a\n"
    )
    assert imports("spl.b", known["spl.b"], known) == set()
