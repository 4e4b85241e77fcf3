"""A product nobody reads again goes at once, without the cyclic collector: the line
checks resolve dozens of witness products with the collector paused (spl.core.cyclic_gc),
and a 1,000-node line's copies took 700 MB until the check ended. A witness product
(released: ``Resolution.release``, then its remains collected with the youngest
generation) leaves the collector nothing that grows with their number: not the copy of
the template, nor what the resolution built around it (its flow table, trace and the
values pyecore wraps: 76,000 objects a witness product of a 10,000-node line, 3.8 GB
before its check ended)."""

from __future__ import annotations

import gc
from collections.abc import Callable
from pathlib import Path

from spl.resolver.line_checks.witnesses import witness_warnings
from spl.resolver.resolution.engine import resolve
from spl.resolver.resolution.product_line import load_product_line
from spl.resolver.resolution.product_selection import selection_from_list

ROOT = Path(__file__).resolve().parents[2]


def left_for_the_collector(work: Callable[[], None]) -> int:
    """How many objects ``work`` leaves in reference cycles, once it is done."""
    gc.collect()
    gc.disable()
    try:
        work()
        return gc.collect()
    finally:
        gc.enable()


def test_a_released_product_leaves_its_copy_to_no_collector() -> None:
    line = load_product_line(ROOT / "product_lines/mapping3d")
    products = sorted(tuple(sorted(p)) for p in line.formula.products())

    def kept_whole() -> None:
        for features in products:
            resolution = resolve(line, selection_from_list(",".join(features)))
            assert resolution.product.system.containers  # a whole model until released

    def as_witnesses(rounds: int) -> Callable[[], None]:
        return lambda: [witness_warnings(line, features) for features in products * rounds]

    # what was alive before is frozen (no collection visits it): the counts are the same,
    # and each collection passes over what the test allocated, not over everything its
    # process holds (in a worker of the whole suite, most of it)
    gc.collect()
    gc.freeze()
    try:
        kept = left_for_the_collector(kept_whole)
        released = left_for_the_collector(as_witnesses(1))
        released_thrice = left_for_the_collector(as_witnesses(3))
    finally:
        gc.unfreeze()
    assert kept > 100 * len(products), kept  # the measure sees a product's cycles
    assert released_thrice <= max(released, 10) * 1.2, (released_thrice, released)
