"""One class per transformation kind behind one interface
(src/spl/resolver/resolution/transformations/):
every kind of statement the .rm metamodel has is registered once, acts on products, and
the rest of the resolver asks it instead of comparing kind names."""

from __future__ import annotations

import ast
from pathlib import Path

from pyecore.ecore import EClass

from spl.metamodels import rm
from spl.resolver.resolution.transformations import KINDS, kind_of
from spl.resolver.resolution.transformations.kind import TransformationKind

ROOT = Path(__file__).resolve().parents[2]


def concrete_transformations() -> set[str]:
    """The concrete classes of rm.ecore that are transformations (.rm statements)."""
    package = rm().package
    base = package.getEClassifier("Transformation")
    return {
        c.name
        for c in package.eClassifiers
        if isinstance(c, EClass) and base in c.eAllSuperTypes() and not c.abstract
    }


def test_every_statement_kind_of_the_metamodel_has_one_class_that_applies_it():
    assert set(KINDS) == concrete_transformations()
    for name, kind in KINDS.items():
        assert isinstance(kind, TransformationKind) and kind.metaclass == name
        assert type(kind).apply is not TransformationKind.apply, name


def test_kind_of_finds_a_statement_by_its_metaclass():
    package = rm()
    migration = package.NodeMigration()
    assert kind_of(migration) is KINDS["NodeMigration"]


def test_no_module_of_the_resolver_compares_kind_names():
    """The kinds' names appear in resolver/ only as their classes' ``metaclass``."""
    names = concrete_transformations()
    found = []
    for path in sorted((ROOT / "src" / "spl" / "resolver").rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        allowed = {
            id(node.value)
            for node in ast.walk(tree)
            if isinstance(node, ast.Assign)
            and any(isinstance(t, ast.Name) and t.id == "metaclass" for t in node.targets)
        }
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and node.value in names and id(node) not in allowed:
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {node.value!r}")
    assert found == []
