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

from spl.core.cyclic_gc import release
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


def test_a_witness_resolution_leaves_the_collector_as_it_found_it() -> None:
    """Resolved with the collector on (a caller that did not pause it), a witness is
    collected once, when it is dropped (``collect_young``), not also while its product is
    alive: resolve() resuming collection over the live product cost a young pass over
    all of it (a fifth of a witness resolution of a 1,000-node line)."""
    line = load_product_line(ROOT / "product_lines/mapping3d")
    witness = tuple(sorted(next(iter(line.formula.products()))))
    witness_warnings(line, witness)  # the line's own facts, read once
    passes: list[int] = []

    def counted(phase: str, info: dict[str, int]) -> None:
        if phase == "start":
            passes.append(info["generation"])

    gc.collect()
    gc.callbacks.append(counted)
    try:
        assert gc.isenabled()
        witness_warnings(line, witness)
        assert gc.isenabled()
    finally:
        gc.callbacks.remove(counted)
    assert passes == [0], passes


def test_a_released_copy_leaves_nothing_to_the_collector() -> None:
    """A copy of the template, released (what ``Resolution.release`` does), goes with
    its last reference: the copy's recursive writer held its elements in a cycle until
    the collector ran (on a 10,000-node line 60,000 objects a witness product, a tenth
    of its resolution collecting them). What is left is the writer's closure alone."""
    line = load_product_line(ROOT / "product_lines/mapping3d")
    image = line.template_image

    def copied_and_released() -> None:
        roots, copies = image.copy()
        assert roots[0].containers  # a whole model until released
        release(copies.values())
        copies.clear()

    gc.collect()
    gc.freeze()
    try:
        left = left_for_the_collector(copied_and_released)
    finally:
        gc.unfreeze()
    assert left < 10, left  # the closure, its cells and their emptied containers
