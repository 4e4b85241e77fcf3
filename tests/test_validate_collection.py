"""`spl validate` runs each product with the cyclic collector paused and collects once
after it: the product's models do not outlive its case, the collector is on again
afterwards, and a run makes one collection per product instead of several."""

from __future__ import annotations

import gc
from pathlib import Path

from spl.line_validation import load_lines, plan_cases, run_cases

MAPPING = Path(__file__).resolve().parents[1] / "product_lines" / "mapping3d"


def _systems(kind: type) -> int:
    return sum(1 for o in gc.get_objects() if type(o) is kind)


def test_each_product_is_collected_once_and_does_not_outlive_its_case():
    lines = load_lines([MAPPING])
    cases = plan_cases(lines, "all")[:4]
    system_class = type(lines[0].line.tsm)
    run_cases(lines, cases[:1])  # imports and caches warm
    gc.collect()
    before = _systems(system_class)
    collections = []

    def count(phase: str, info: dict) -> None:
        if phase == "start":
            collections.append(info["generation"])

    gc.callbacks.append(count)
    try:
        results = run_cases(lines, cases)
    finally:
        gc.callbacks.remove(count)
    assert [r.outcome for r in results] == ["passed"] * len(cases)
    assert gc.isenabled()
    assert collections == [0] * len(cases)  # one per product, none while it ran
    assert _systems(system_class) == before  # every resolved model already freed
