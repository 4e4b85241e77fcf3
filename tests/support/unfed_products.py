"""Brute force for the line-wide dataflow check (docs/semantics.md F8): every product of
a line resolved, and the inputs each leaves unfed (SPL045) or unserved (SPL046), to be
compared with what ``spl check`` finds without enumerating products; and the publishers
some product delivers data from, none of which it may call unconsumed (SPL052)."""

from __future__ import annotations

import re

from spl.core.diagnostics import Diagnostic, Location, ModelError, location_of
from spl.resolver.architecture.flows import TOPIC
from spl.resolver.line_checks import check_product_line
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import ProductLine
from spl.resolver.resolution.product_selection import selection_from_list

CODES = ("SPL045", "SPL046")
Where = tuple[str, int, int, str]  # file, line, column, code


def where(d: Diagnostic) -> Where:
    assert d.location is not None and d.code is not None
    return (d.location.file, d.location.line, d.location.col, d.code)


def gaps(line: ProductLine, features: str) -> set[Where] | None:
    """The inputs the product ``features`` leaves unfed; None when it does not resolve."""
    try:
        product = resolve(line, selection_from_list(features)).product
    except ModelError:
        return None
    return {where(w) for w in product.warnings if w.code in CODES}


def unfed_somewhere(line: ProductLine) -> dict[Where, str]:
    """Every input some product of the line leaves unfed, with the first such product."""
    return {place: products[0] for place, products in _every_product(line)[0].items()}


def _every_product(line: ProductLine) -> tuple[dict[Where, list[str]], set[Location | None]]:
    """The inputs some product leaves unfed (with every such product, in order), and the
    publishers whose data some product delivers to a subscriber."""
    unfed: dict[Where, list[str]] = {}
    consumed: set[Location | None] = set()
    for features in sorted(",".join(sorted(p)) for p in line.formula.products()):
        try:
            product = resolve(line, selection_from_list(features)).product
        except ModelError:
            continue
        for warning in product.warnings:
            if warning.code in CODES:
                unfed.setdefault(where(warning), []).append(features)
        consumed.update(location_of(f.source) for f in product.flows if f.kind == TOPIC)
    return unfed, consumed


def witness_of(finding: Diagnostic) -> str:
    """The witness product a finding of the check names, as a feature list."""
    match = re.search(r", in the product ([^;]*)", finding.message)
    assert match, finding.message
    return match.group(1).replace(" ", "")


def assert_check_agrees(line: ProductLine) -> dict[Where, Diagnostic]:
    """The check reports exactly the inputs some product leaves unfed, and each witness
    it names resolves with that very warning and has no smaller product (by inclusion)
    that does; returns the findings by place."""
    findings = {where(d): d for d in check_product_line(line, products=False) if d.code in CODES}
    for place, finding in findings.items():
        assert place in (gaps(line, witness_of(finding)) or ()), finding
    expected, consumed = _every_product(line)
    for finding in check_product_line(line, products=False):
        if finding.code == "SPL052":  # no product consumes it: none may
            assert finding.location not in consumed, finding
    for place, finding in findings.items():  # no smaller product shows it
        witness = set(witness_of(finding).split(","))
        smaller = [p for p in expected.get(place, ()) if set(p.split(",")) < witness]
        assert not smaller, f"{finding}: also unfed in the smaller {smaller}"
    missed = {place: product for place, product in expected.items() if place not in findings}
    assert not missed, f"unfed in some product, not reported: {missed}"
    assert set(findings) == set(expected)
    return findings
