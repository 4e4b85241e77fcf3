"""What ``spl validate`` says of its results on the terminal (docs/ci.md): one line per
product, its messages and warnings under it, and the summary line."""

from __future__ import annotations

from dataclasses import replace

from spl.core.diagnostics import counted
from spl.validation.line import CaseResult


def summary(results: list[CaseResult]) -> str:
    """``N passed, K of them with warnings, M failed``: K counts the products with a
    warning of their own (not one about this machine); then ``, S skipped`` when some
    bundles were unchanged (``--changed-from``, ``--since``)."""
    skipped = sum(1 for r in results if r.outcome == "skipped")
    passed = sum(1 for r in results if r.passed) - skipped
    warned = sum(1 for r in results if r.passed and r.product_warnings)
    noted = f", {warned} of them with warnings" if warned else ""
    failed = len(results) - passed - skipped
    return f"{passed} passed{noted}, {failed} failed" + (f", {skipped} skipped" if skipped else "")


def strict(results: list[CaseResult]) -> list[CaseResult]:
    """``--strict``: a product that resolves with warnings of its own (an input nothing
    feeds, SPL045, an output it cannot have, ...) fails, those warnings its failure's
    messages (docs/ci.md)."""
    return [
        replace(r, outcome="failed", messages=r.product_warnings)
        if r.passed and r.product_warnings
        else r
        for r in results
    ]


def machine_notes(results: list[CaseResult]) -> list[str]:
    """Each warning about this machine once, with how many products it concerns
    (``... (this machine, for 5 products)``): said once for the run, not under every
    product's line (docs/ci.md)."""
    products: dict[str, int] = {}
    for result in results:
        for text in dict.fromkeys(result.machine_warnings):
            products[text] = products.get(text, 0) + 1
    return [f"{text} (this machine, for {counted(n, 'product')})" for text, n in products.items()]


def describe(result: CaseResult) -> list[str]:
    """Plain-text lines for one result (CI logs): a status line, then its messages and
    the product's warnings not among them (a warning is no failure, docs/ci.md)."""
    head = {"passed": "ok  ", "failed": "FAIL", "error": "ERROR", "skipped": "skip"}[result.outcome]
    checked = f"  ({result.checked})" if result.checked else ""
    notes = tuple(w for w in result.product_warnings if w not in result.messages)
    return [
        f"{head} {result.classname} :: {result.name}{checked}",
        *(f"    {m}" for m in result.messages + notes),
    ]
