"""The print of a plain .tsm model made by each class's own code
(:func:`spl.dsl.tsm.plain_prints.plain_fingerprint`) is the generic print
(:func:`spl.core.emf.fingerprint`): the same tuples, the same elements visited in the same
order with the same paths, the same references met in the same order. The editor compares
prints of one reading with those of the reading before (docs/performance.md, "Editor
latency"), so the two must never differ."""

from __future__ import annotations

from typing import Any

from hypothesis import given, settings
from test_tsm_reader import SHIPPED

from spl.core.diagnostics import ModelError
from spl.core.emf import fingerprint
from spl.dsl.tsm import language as tsm
from spl.dsl.tsm.declarations import FEATURES
from spl.dsl.tsm.plain_prints import plain_fingerprint

from support.hypothesis_budget import examples
from support.random_lines import line_specs, tsm_text


def both_prints(root: Any, base: int, leave_out: tuple = ()) -> tuple[tuple, tuple]:
    """(print, visits, references met) of ``root`` by the generic print and by the plain one."""
    made: dict = {}

    def record(printing: Any, *extra: Any) -> tuple:
        seen: list = []
        met: list = []
        content = printing(
            root,
            lambda target: met.append(id(target)) or ("to", len(met)),
            lambda element, path: seen.append((id(element), path)),
            base,
            leave_out,
            *extra,
        )
        return content, tuple(seen), tuple(met)

    return record(fingerprint), record(plain_fingerprint, made)


def assert_same_prints(system: Any) -> None:
    """The whole system, and each top-level declaration from its own first line."""
    generic, plain = both_prints(system, 0)
    assert plain == generic
    for feature in FEATURES:
        for root in getattr(system, feature):
            generic, plain = both_prints(root, root.srcLine or 0)
            assert plain == generic
    for container in system.containers:  # its shell: what the generic print reads
        shell = (("topics",), ("nodes",), ("stores",), ("endpoint", "interfaces"))
        generic, plain = both_prints(container, container.srcLine or 0, shell)
        assert plain == generic


def test_every_shipped_model_prints_as_the_generic_print() -> None:
    checked = 0
    for path in SHIPPED:
        try:
            system = tsm.check_file(path)
        except ModelError:
            continue  # a model kept for its errors has no plain model to print
        assert_same_prints(system)
        checked += 1
    assert checked >= 10


@settings(max_examples=examples(30), deadline=None)
@given(line_specs())
def test_generated_lines_print_as_the_generic_print(spec) -> None:
    assert_same_prints(tsm.check_text(tsm_text(spec), "generated.tsm"))


def test_a_model_that_is_not_plain_is_printed_by_the_generic_print() -> None:
    system = tsm.parse_file(SHIPPED[0])  # pyecore objects
    generic, plain = both_prints(system, 0)
    assert plain == generic
