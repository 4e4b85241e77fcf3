"""Interface kinds are units (docs/architecture.md, "Interface kinds"): every interface
class of tsm.ecore has one kind in the registry, each family has one providing and one
consuming side, and outside the registry no module of spl asks an interface's class or
compares a kind's name, so that a new kind is added where the registry says and the rest
of spl handles it by what it means."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from pyecore.ecore import EClass

from spl.metamodels import tsm
from spl.metamodels.interface_kinds import FAMILIES, KINDS, kind_of, side

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ROOT / "src" / "spl"
REGISTRY = SOURCES / "metamodels" / "interface_kinds.py"
GENERATED = {SOURCES / "metamodels" / "tsm_types.py"}  # the type stubs of tsm.ecore

INTERFACE_CLASSES = {
    c.name
    for c in tsm().package.eClassifiers
    if isinstance(c, EClass)
    and c.name != "Interface"
    and tsm().Interface.eClass in c.eAllSuperTypes()
}
# what only the registry may name: the classes and the Rapyuta roles (a Rapyuta type's
# ending "Interface" is not the metamodel's class), and the classes tested
NAMES = INTERFACE_CLASSES | {k.rapyuta_role for k in KINDS if k.rapyuta_role is not None}
TESTED = NAMES | {"Interface"}
# what a kind or family is called where a name stands for it (a flow's kind, a planned
# stand-in's role)
KIND_WORDS = {f.name for f in FAMILIES} | {k.smoke_role for k in KINDS if k.smoke_role is not None}
# what names one kind wherever it stands: its statement's keyword and rule, its title
STATEMENT_WORDS = {k.keyword for k in KINDS} | {k.rule for k in KINDS} | {k.title for k in KINDS}
# the registry's families by their constants
FAMILY_NAMES = {"TOPIC", "SERVICE", "ACTION"}
# what a kind or family is asked by, compared with what names one
ASKED_BY = {"kind", "family", "keyword", "rule", "title", "eclass", "name", "smoke_role"}


def _constants(node: ast.AST) -> list[object]:
    """The constants ``node`` is, or holds (``x in ('a', 'b')``)."""
    if isinstance(node, ast.Constant):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [e.value for e in node.elts if isinstance(e, ast.Constant)]
    return []


def test_every_interface_class_of_the_metamodel_has_one_kind() -> None:
    assert {k.eclass for k in KINDS} == INTERFACE_CLASSES
    assert len({k.eclass for k in KINDS}) == len(KINDS)
    for kind in KINDS:
        made = getattr(tsm(), kind.eclass)(name="x")
        assert kind_of(made) is kind


@pytest.mark.parametrize("family", FAMILIES, ids=str)
def test_each_family_has_one_providing_and_one_consuming_side(family) -> None:
    provider, consumer = side(family, True), side(family, False)
    assert provider.provides and not consumer.provides
    assert consumer.unfed_code is not None and provider.unfed_code is None
    assert consumer.binds == ("topic" if family.on_topic else "server")
    # the zenoh-bridge-ros2dds allow lists of the two sides are the family's two
    assert {provider.zenoh_list, consumer.zenoh_list} == set(family.zenoh_lists)


def _asks_a_class(node: ast.AST) -> str | None:
    """What ``node`` does that only the registry may, in words; None when nothing."""
    if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "isinstance":
        tested = node.args[1] if len(node.args) > 1 else None
        for part in ast.walk(tested) if tested is not None else ():
            if isinstance(part, ast.Attribute) and part.attr in TESTED:
                return f"isinstance(..., {ast.unparse(tested)})"
    if isinstance(node, ast.Constant) and node.value in NAMES:
        return f"the class name {node.value!r}"
    if isinstance(node, ast.Compare):
        sides = [node.left, *node.comparators]
        asked = [s for s in sides if isinstance(s, ast.Attribute) and s.attr in ASKED_BY]
        words = {c for s in sides for c in _constants(s) if isinstance(c, str)}
        if any(isinstance(s, ast.Name) and s.id in FAMILY_NAMES for s in sides):
            return f"a family compared: {ast.unparse(node)}"
        if words & STATEMENT_WORDS or (asked and words & KIND_WORDS):
            return f"a kind compared: {ast.unparse(node)}"
    if isinstance(node, ast.Dict):  # a table of the kinds, by keyword or rule
        keys = {c for k in node.keys if k is not None for c in _constants(k)}
        if keys & STATEMENT_WORDS:
            return f"a table of kinds: {sorted(str(k) for k in keys & STATEMENT_WORDS)}"
    return None


def test_no_module_but_the_registry_asks_an_interface_its_class() -> None:
    found = []
    for path in sorted(SOURCES.rglob("*.py")):
        if path == REGISTRY or path in GENERATED:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in ast.walk(tree):
            what = _asks_a_class(node)
            if what is not None:
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {what}")  # type: ignore[attr-defined]
    assert found == []


def test_the_scan_sees_what_it_forbids() -> None:
    planted = (
        "isinstance(i, T.ServiceClient)\n"
        "isinstance(e, (T.Interface, T.Parameter))\n"
        "i.eClass.name == 'Publisher'\n"
        "flow.kind == TOPIC\n"
        "crossing.kind != 'service'\n"
        "planned.kind == 'client'\n"
        "crossing.family is ACTION\n"
        "kind.family.name in ('action', 'service')\n"
        "word == 'calls'\n"
        "rule in ('Provides', 'ProvidesAction')\n"
        "rules = {'param': p, 'publishes': q}\n"
        "token.kind == 'name'\n"  # not an interface's kind
        "decl.kind in ('node', 'store')\n"
        "rules = {'param': p, 'node': q}\n"
    )
    seen = [w for n in ast.walk(ast.parse(planted)) if (w := _asks_a_class(n)) is not None]
    assert len(seen) == 11, seen
