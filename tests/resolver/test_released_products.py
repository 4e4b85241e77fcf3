"""A product nobody reads again goes at once, without the cyclic collector: the line
checks resolve dozens of witness products with the collector paused (spl.core.cyclic_gc),
and a 1,000-node line's copies took 700 MB until the check ended. A released resolution
(``Resolution.release``, as the witness products are) leaves a small part of its model
for the collector (what the rewiring created), not the copy of the template."""

from __future__ import annotations

import gc
from collections.abc import Callable
from pathlib import Path

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
    products = sorted(",".join(sorted(p)) for p in line.formula.products())

    def resolved(release: bool) -> Callable[[], None]:
        def work() -> None:
            for features in products:
                resolution = resolve(line, selection_from_list(features))
                assert resolution.product.system.containers  # a whole model until released
                if release:
                    resolution.release()

        return work

    kept = left_for_the_collector(resolved(release=False))
    released = left_for_the_collector(resolved(release=True))
    assert released * 3 < kept, (released, kept)
