"""The fast reader's class of each interface statement is made from the registry
(docs/architecture.md, "Interface kinds"): every kind's rule in ``tsm.tx`` has its class
in the reader's tree, named after the rule and with textX's attributes in textX's order,
so that a kind added to the registry and the grammar is read without a class written
for it."""

from __future__ import annotations

import pytest

from spl.dsl.tsm import language as tsm, reader as tsm_reader, tree as tsm_tree
from spl.metamodels.interface_kinds import KINDS

from support.textx_trees import assert_reads_as_textx


@pytest.mark.parametrize("kind", KINDS, ids=lambda k: k.rule)
def test_each_kind_has_the_class_of_its_rule_with_textx_attributes(kind) -> None:
    made = tsm_tree.INTERFACE_RULES[kind.rule]
    assert made.__name__ == kind.rule and made.__module__ == tsm_tree.__name__
    assert made._fields == ("position", *tsm._grammar()[kind.rule]._tx_attrs)
    assert set(tsm_tree.INTERFACE_RULES) == {k.rule for k in KINDS}


@pytest.mark.parametrize("kind", KINDS, ids=lambda k: k.rule)
def test_each_kind_statement_is_read_into_its_class_as_textx_reads_it(kind) -> None:
    """Every form of the statement: typed, bound, both, and an input's ``external``."""
    target = "T" if kind.on_topic else "M.s"
    forms = [f"{kind.keyword} x : p/T"]
    if kind.binds is None:
        forms.append(f'{kind.keyword} x : p/T name "/x"')
    else:
        forms += [f"{kind.keyword} x {kind.arrow} {target}", f"{forms[0]} {kind.arrow} {target}"]
        if not kind.provides:
            forms.append(f'{kind.keyword} x : p/T external "a driver"')
    for form in forms:
        text = f"system S\ncloud container C {{\n topic T : p/T\n node N {{\n  {form}\n }}\n}}\n"
        assert_reads_as_textx(tsm_reader.read, tsm._grammar(), text, must_read=True)
        (container,) = tsm_reader.read(text).elements
        (node,) = [m for m in container.members if type(m).__name__ == "Node"]
        assert type(node.members[0]) is tsm_tree.INTERFACE_RULES[kind.rule], form
